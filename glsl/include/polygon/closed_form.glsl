// The closed-form projected solid angle (Lambert's edge sum, evaluated without cancellation).
// Part of polygon.glsl, which includes its parts in order (each uses only those before it).
// Rust twin: `src/shading/polygon/closed_form.rs`; `tests/polygon_gpu.rs` checks that the two agree.

// (gamma / sin gamma - 1) c.z for an edge with c = v_j x v_j+1 (|c| = sin gamma) and cos gamma.
precise float edge_segment_term(vec3 c, float cos_angle) {
    precise float sine = length3(c);
    precise float angle = polygon_atan2(sine, cos_angle);
    if (angle < 0.5) {
        // x/sin x - 1 = x^2/6 + 7x^4/360 + 31x^6/15120 + 127x^8/604800 + 73x^10/3421440 + O(x^12)
        precise float x2 = angle * angle;
        precise float series = x2
            * (1.0 / 6.0
               + x2 * (7.0 / 360.0
                       + x2 * (31.0 / 15120.0 + x2 * (127.0 / 604800.0 + x2 * (73.0 / 3421440.0)))));
        return series * c.z;
    } else if (sine > 0.0) {
        return angle * (c.z / sine) - c.z;
    }
    return 0.0;
}

// The signed projected solid angle (positive iff counterclockwise about +z) of a polygon on or
// above the horizon; 0 for an empty or degenerate one.
precise float signed_projected_solid_angle(Polygon polygon) {
    int count = polygon.count;
    if (count < 3) {
        return 0.0;
    }
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        if (all(equal(polygon.vertices[j], vec3(0.0)))) {
            return 0.0;
        }
    }
    vec3 origin = polygon.vertices[0];
    precise float fan = 0.0;
    precise float segments = 0.0;
    precise float magnitude = 0.0;
    precise vec3 previous_offset = vec3(0.0);
    for (int j = 0; j < MAX_CLIPPED_VERTICES; ++j) {
        if (j >= count) {
            break;
        }
        vec3 a = polygon.vertices[j];
        vec3 b = polygon.vertices[next_index(j, count)];
        // Shoelace term of the projected unit directions, relative to direction 0
        precise vec3 offset = unit_difference(b, origin);
        precise float shoelace = kahan(previous_offset.x, offset.y, previous_offset.y, offset.x);
        previous_offset = offset;
        // Curved part of the edge
        precise vec3 edge = unit_difference(b, a);
        precise vec3 c = cross_stable(normalize3(a), edge);
        precise float segment = edge_segment_term(c, 1.0 - 0.5 * polygon_dot3(edge, edge));
        fan += shoelace;
        segments += segment;
        magnitude += abs(shoelace) + abs(segment);
    }
    precise float total = 0.5 * (fan + segments);
    return abs(total) > 0.5 * EMPTY_RELATIVE_THRESHOLD * magnitude ? total : 0.0;
}

// The projected solid angle of a polygon clipped to the horizon, in closed form.
float projected_solid_angle(Polygon clipped) {
    return abs(signed_projected_solid_angle(clipped));
}

// A density with respect to projected solid angle as one with respect to solid angle.
precise float projected_to_solid_angle_density(float projected_density, vec3 direction) {
    return projected_density * max(direction.z, 0.0);
}
