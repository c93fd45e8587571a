// Solid-angle sampling of the triangle fan (Algorithm 5) and its density.
// Part of polygon.glsl, which includes its parts in order (each uses only those before it).
// Rust twin: `src/shading/polygon/solid_angle_sampling.rs`; `tests/polygon_gpu.rs` checks that the two agree.

// Prepares solid-angle sampling of a convex polygon (3 to MAX_CLIPPED_VERTICES vertices, clipped
// or not, either winding): the fan of triangles (v_j+1, v_0, v_j+2) with the Householder
// determinant of Sec. C.
precise SolidAngleSampler prepare_solid_angle(Polygon polygon) {
    SolidAngleSampler state = solid_angle_sampler_empty();
    int count = polygon.count;
    if (count < 3 || count > MAX_CLIPPED_VERTICES) {
        return state;
    }
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        if (all(equal(polygon.vertices[j], vec3(0.0)))) {
            return state;
        }
        state.directions[j] = normalize3(polygon.vertices[j]);
    }
    vec3 origin = polygon.vertices[0];
    vec3 apex = state.directions[0];
    // H = I - 2hh^T maps v_0 to sigma e_0
    float sigma = apex.x > 0.0 ? -1.0 : 1.0;
    precise vec2 householder_yz = vec2(apex.y, apex.z) / (abs(apex.x) + 1.0);
    precise vec3 previous_offset = unit_difference(polygon.vertices[1], origin);
    precise float total = 0.0;
    precise float signed_total = 0.0;
    precise float magnitude = 0.0;
    for (int j = 0; j < MAX_FAN_TRIANGLES; ++j) {
        if (j + 2 >= count) {
            break;
        }
        vec3 a = state.directions[j + 1];
        vec3 b = state.directions[j + 2];
        precise vec3 offset_a = previous_offset;
        precise vec3 offset_b = unit_difference(polygon.vertices[j + 2], origin);
        previous_offset = offset_b;
        // v_0.d = -|d|^2/2 exactly for d = v - v_0
        precise vec2 reflected_a =
            vec2(offset_a.y, offset_a.z) - householder_yz * (-0.5 * polygon_dot3(offset_a, offset_a) - sigma * offset_a.x);
        precise vec2 reflected_b =
            vec2(offset_b.y, offset_b.z) - householder_yz * (-0.5 * polygon_dot3(offset_b, offset_b) - sigma * offset_b.x);
        precise float signed_det = sigma * det2(reflected_a, reflected_b);
        precise float g_0 = abs(signed_det);
        precise float g_1 = polygon_dot3(a, b) + polygon_dot3(apex, b);
        precise float g_2 = 1.0 + polygon_dot3(a, apex);
        precise float triangle_solid_angle = 2.0 * polygon_atan2(g_0, g_1 + g_2);
        state.triangles[j] = vec3(g_0, g_1, g_2);
        total += triangle_solid_angle;
        state.fan_solid_angles[j] = total;
        signed_total += polygon_copysign(triangle_solid_angle, signed_det);
        magnitude += triangle_solid_angle;
    }
    if (!(total > 0.0 && polygon_is_finite(total)) || abs(signed_total) <= EMPTY_RELATIVE_THRESHOLD * magnitude) {
        return solid_angle_sampler_empty();
    }
    state.orientation = signed_total > 0.0 ? -1.0 : 1.0;
    state.count = count;
    state.solid_angle = total;
    return state;
}

// Samples a direction uniformly with respect to solid angle within the polygon from u in [0, 1)^2
// (Algorithm 5). Returns the unit direction in xyz and its density with respect to solid angle in
// w; an empty state returns (+z, 0).
precise vec4 sample_solid_angle(SolidAngleSampler state, vec2 u) {
    if (state.count == 0) {
        return vec4(0.0, 0.0, 1.0, 0.0);
    }
    int count = state.count;
    precise float target = u.x * state.solid_angle;
    // Select the triangle; a target beyond the last non-empty triangle clamps to its end
    int selected = 0;
    precise float sub_solid_angle = 0.0;
    precise float previous_fan = 0.0;
    for (int j = 0; j < MAX_FAN_TRIANGLES; ++j) {
        if (j + 2 >= count) {
            break;
        }
        float fan = state.fan_solid_angles[j];
        if (fan > previous_fan) {
            selected = j;
            sub_solid_angle = min(target - previous_fan, fan - previous_fan);
        }
        if (target < fan) {
            break;
        }
        previous_fan = fan;
    }
    vec3 g = state.triangles[selected];
    vec3 a = state.directions[selected + 1];
    vec3 apex = state.directions[0];
    vec3 b = state.directions[selected + 2];
    // The point on the arc from a to b that cuts off a triangle (a, apex, b') of the wanted solid
    // angle: b' = -a + 2 (a.r)/|r|^2 r with r = (G0 cos(A/2) - G1 sin(A/2)) a + G2 sin(A/2) b
    precise float half_angle = 0.5 * sub_solid_angle;
    precise float sin_half = sin(half_angle);
    precise float cos_half = cos(half_angle);
    precise vec3 r = (g.x * cos_half - g.y * sin_half) * a + (g.z * sin_half) * b;
    precise vec3 new_b = (2.0 * polygon_dot3(a, r) / polygon_dot3(r, r)) * r - a;
    // Uniform in cos of the distance from the apex along the arc from apex to b'
    precise float s_2 = polygon_dot3(apex, new_b);
    precise float s = mix_exact(1.0, s_2, u.y);
    precise float t = sqrt(max(u.y * (1.0 + s) / max(1.0 + s_2, POLYGON_MIN_POSITIVE), 0.0));
    precise vec3 direction = (s - t * s_2) * apex + t * new_b;
    return vec4(direction, 1.0 / state.solid_angle);
}

// The density with respect to solid angle of sample_solid_angle at the unit direction.
precise float solid_angle_density(SolidAngleSampler state, vec3 direction) {
    if (state.count == 0 || !is_inside(state.directions, state.count, state.orientation, direction)) {
        return 0.0;
    }
    return 1.0 / state.solid_angle;
}
