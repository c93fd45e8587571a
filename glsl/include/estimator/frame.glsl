// What the estimator knows of one triangle (Frame, make_frame), the cosine ranges
// (cosine_range, cosine_range_of) and its distances to a point (height_of, distance_of,
// distance_along_line).
// Twin: `src/shading/estimator/frame.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// See `Frame` in Rust.
struct Frame {
    vec3 vertices[3];
    vec3 eye;
    // The bounds hold for every eye within this distance of `eye` (see Rust).
    float eye_radius;
    vec3 center;
    float rho_x;
    Scale s1;
    Scale sn;
    float rho;
    Scale d1;
    Scale dn;
    Cone n_cone;
    float r_n;
    float n_max_len;
    vec3 normals[3];
    vec3 unit_normals[3];
    vec3 plane;
    float plane_tilt;
    float n_plane_sin;
    Cone v_cone;
    float e_min;
    vec3 v_center;
    // The vectors from the corners to the eye and their directions; the range of the angle
    // between n and v and the sign of n.v, for a specular material only (see Rust).
    vec3 v_vectors[3];
    vec3 v_units[3];
    vec2 psi_nv;
    int nv_sign;
};

// The range of the angle between n and w from the range q of n.w over the triangle and bounds
// on |w| (see `cosine_range_of`); the sign of n.w goes to `sign_out`.
P vec2 cosine_range_of(Frame frame, Cone w_cone, vec2 q, float w_max, float w_min, out int sign_out) {
    P vec2 psi = psi_range(frame.n_cone, w_cone);
    P float p0 = psi.x;
    P float p1 = psi.y;
    P float q_lo = q.x;
    P float q_hi = q.y;
    P float scale = frame.n_max_len * w_max;
    P float tol = 1.0e-5 * scale;
    int sign_of = q_lo > tol ? SIGN_POSITIVE : (q_hi < -tol ? SIGN_NON_POSITIVE : SIGN_BOTH);
    sign_out = sign_of;
    if (q_lo > tol && scale > 0.0) {
        p1 = rmin(p1, est_acos(rmin(q_lo / scale, 1.0)) + ANGLE_PAD);
    }
    P float denom = frame.r_n * w_min;
    if (q_hi > 0.0 && denom > 0.0) {
        p0 = rmax(p0, est_acos(rmin(q_hi / denom, 1.0)) - ANGLE_PAD);
    }
    if (sign_of == SIGN_NON_POSITIVE) {
        p0 = rmax(p0, HALF_PI);
    }
    if (p0 > p1) {
        p0 = p1;
    }
    return vec2(p0, p1);
}

// Range of the angle between n and the field normalize(sum l_k w_k), and the sign of n.w.
// Returns the range; the sign goes to `sign_out`.
P vec2 cosine_range(Frame frame, Cone w_cone, vec3 w[3], out int sign_out) {
    P vec2 q = bilinear_range(frame.normals, w);
    P float w_max = rmax(rmax(len(w[0]), len(w[1])), len(w[2]));
    P float w_min = min_length(w[0], w[1], w[2], w_cone);
    return cosine_range_of(frame, w_cone, q, w_max, w_min, sign_out);
}

// max |sin| of the angle between a direction of the cone and the plane normal, 1 without a
// plane (see `plane_sin` in Rust).
P float plane_sin(Cone cone, vec3 plane) {
    if (is_zero(plane)) {
        return 1.0;
    }
    P vec2 g = psi_range(cone, Cone(plane, 0.0));
    return max_sin(g.x, g.y);
}

// s1/sn of one attribute, 0 where sn is (see `Frame::rho` in Rust).
P float scale_ratio(float one, float later) {
    P float r = later > 0.0 ? one / later : 0.0;
    return r;
}

// The jet at a scale rho times this one's: value kept, first derivative times rho, second
// times rho^2 (see `LightJets::scaled`).
Jet scaled_jet(Jet j, float rho) {
    P float rho2 = rho * rho;
    Jet o;
    o.m = j.m;
    o.g = j.g * rho;
    o.h = j.h * rho2;
    return o;
}

// The angle by which a ball of eyes of `radius` widens the directions from a point at least
// `distance` from its centre (see `ball_angle` in Rust).
P float ball_angle(float radius, float distance) {
    if (!(radius > 0.0)) {
        return 0.0;
    }
    if (radius < 0.99 * distance) {
        P float angle = est_asin(radius / distance) + ANGLE_PAD;
        return angle;
    }
    return PI;
}

// The frame of the triangle for every eye within eye_ball.w of eye_ball.xyz (see `Frame::new`).
Frame make_frame(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec4 eye_ball) {
    Frame f;
    f.vertices = vec3[3](p0, p1, p2);
    P vec3 eye = eye_ball.xyz;
    P float eye_radius = eye_ball.w;
    f.eye = eye;
    f.eye_radius = eye_radius;
    P vec3 center = (p0 + p1 + p2) / 3.0;
    f.center = center;
    f.rho_x = rmax(rmax(len(p0 - center), len(p1 - center)), len(p2 - center));
    PatternConstants px = pattern_constants(p1 - p0, p2 - p0);
    PatternConstants pn = pattern_constants(n1 - n0, n2 - n0);
    f.n_cone = cone_of(n0, n1, n2);
    P float longest = rmax(rmax(len(n0), len(n1)), len(n2));
    P vec3 e1 = n1 - n0;
    P vec3 e2 = n2 - n0;
    P vec2 pg = jung_scales(vec3(dot3(n0, e1), dot3(n1, e1), dot3(n2, e1)),
                            vec3(dot3(n0, e2), dot3(n1, e2), dot3(n2, e2)));
    P float g_pad = RADIAL_PAD * longest;
    P float r_n = min_length(n0, n1, n2, f.n_cone);
    if (!(r_n > 1.0e-6 * longest)) {
        r_n = 0.0;
    }
    f.r_n = r_n;
    P vec3 to_eye0 = eye - p0;
    P vec3 to_eye1 = eye - p1;
    P vec3 to_eye2 = eye - p2;
    f.v_cone = cone_of(to_eye0, to_eye1, to_eye2);
    f.e_min = min_length(to_eye0, to_eye1, to_eye2, f.v_cone);
    if (eye_radius > 0.0) {
        P float widen = ball_angle(eye_radius, f.e_min);
        f.v_cone.spread += widen;
        if (!(f.v_cone.spread < MAX_HALF)) {
            f.v_cone = no_cone();
        }
        f.e_min = widen < PI ? f.e_min - eye_radius : 0.0;
    }
    f.s1 = Scale(px.sqrt_k1, pn.sqrt_k1, pg.x + g_pad * pn.sqrt_k1);
    f.sn = Scale(px.sqrt_k, pn.sqrt_k, pg.y + g_pad * pn.sqrt_k);
    f.rho = rmin(rmax(rmax(scale_ratio(f.s1.a, f.sn.a), scale_ratio(f.s1.b, f.sn.b)), scale_ratio(f.s1.g, f.sn.g)),
                 1.0);
    f.d1 = Scale(px.diam1, pn.diam1, 0.0);
    f.dn = Scale(px.diam, pn.diam, 0.0);
    f.n_max_len = longest;
    f.normals = vec3[3](n0, n1, n2);
    f.unit_normals = vec3[3](unit(n0), unit(n1), unit(n2));
    P vec3 c = cross3(p1 - p0, p2 - p0);
    P float plane_scale = len(p1 - p0) * len(p2 - p0);
    if (len(c) > 1.0e-6 * plane_scale) {
        f.plane = unit(c);
        f.plane_tilt = 4.0e-7 * plane_scale / len(c) + 1.0e-6;
    } else {
        f.plane = vec3(0.0);
        f.plane_tilt = 0.0;
    }
    f.n_plane_sin = plane_sin(f.n_cone, f.plane);
    f.v_center = unit(eye - center);
    f.v_vectors = vec3[3](to_eye0, to_eye1, to_eye2);
    f.v_units = vec3[3](vec3(0.0), vec3(0.0), vec3(0.0));
    f.psi_nv = vec2(0.0, PI);
    f.nv_sign = SIGN_BOTH;
    if (MATERIAL_KIND != MATERIAL_LAMBERT) {
        f.v_units = vec3[3](unit(to_eye0), unit(to_eye1), unit(to_eye2));
        int nv_sign;
        if (eye_radius > 0.0) {
            P vec2 q = bilinear_range(f.normals, f.v_vectors);
            P float slack = f.n_max_len * eye_radius * (1.0 + BALL_SLACK_PAD);
            P float w_max = rmax(rmax(len(to_eye0), len(to_eye1)), len(to_eye2)) + eye_radius;
            f.psi_nv = cosine_range_of(f, f.v_cone, vec2(q.x - slack, q.y + slack), w_max, rmax(f.e_min, 0.0), nv_sign);
        } else {
            f.psi_nv = cosine_range(f, f.v_cone, f.v_vectors, nv_sign);
        }
        f.nv_sign = nv_sign;
    }
    return f;
}

// Lower and upper bounds on the height of p over the triangle's plane (see `Frame::height_of`).
P vec2 height_of(Frame frame, vec3 p) {
    if (is_zero(frame.plane)) {
        return vec2(0.0);
    }
    P vec3 r = p - frame.vertices[0];
    P float height = abs(dot3(r, frame.plane));
    P float pad = len(r) * (frame.plane_tilt + 1.0e-6);
    P vec2 range = vec2(rmax(height - pad, 0.0), height + pad);
    return range;
}

// The distance from p to the longest edge of a triangle without a plane, less the third
// corner's distance from it and the rounding (see `Frame::distance_along_line`).
P float distance_to_segment(vec3 a, vec3 b, float length2, vec3 x) {
    P vec3 e = b - a;
    P vec3 f = x - a;
    P float t = length2 > 0.0 ? clamp(dot3(f, e) / length2, 0.0, 1.0) : 0.0;
    P float d = len(f - e * t);
    return d;
}
P float distance_along_line(Frame frame, vec3 p) {
    P vec3 v[3] = frame.vertices;
    P float lengths[3] = float[](len2(v[1] - v[0]), len2(v[2] - v[1]), len2(v[0] - v[2]));
    int k = (lengths[0] >= lengths[1] && lengths[0] >= lengths[2]) ? 0 : (lengths[1] >= lengths[2] ? 1 : 2);
    P vec3 a = v[k];
    P vec3 b = v[(k + 1) % 3];
    P float magnitude = max_el(abs(p)) + max_el(abs(a)) + 2.0 * frame.rho_x;
    P float d = rmax(distance_to_segment(a, b, lengths[k], p) - distance_to_segment(a, b, lengths[k], v[(k + 2) % 3])
                     - 1.0e-6 * magnitude, 0.0);
    return d;
}

// A lower bound on the distance from p to the triangle, its height from below given (see
// `Frame::distance_of`).
P float distance_of(Frame frame, vec3 p, float height) {
    if (is_zero(frame.plane)) {
        return distance_along_line(frame, p);
    }
    P vec3 foot = p - frame.plane * dot3(p - frame.vertices[0], frame.plane);
    // The foot's distance to the triangle: 0 inside, else to the nearest edge.
    bool inside = true;
    P float rho = len(foot - frame.vertices[0]);
    for (int k = 0; k < 3; ++k) {
        P vec3 a = frame.vertices[k];
        P vec3 e = frame.vertices[(k + 1) % 3] - a;
        P vec3 f = foot - a;
        inside = inside && dot3(cross3(e, f), frame.plane) >= 0.0;
        P float t = clamp(dot3(f, e) / len2(e), 0.0, 1.0);
        rho = rmin(rho, len(f - e * t));
    }
    P float reach = len(p - frame.vertices[0]) + 2.0 * frame.rho_x;
    P float magnitude = max_el(abs(foot)) + max_el(abs(frame.vertices[0])) + 2.0 * frame.rho_x;
    P float pad = 2.0 * reach * (frame.plane_tilt + 1.0e-6) + 1.0e-6 * magnitude;
    P float rho_out = (inside || !(rho > pad)) ? 0.0 : rho - pad;
    P float d = sqrt(height * height + rho_out * rho_out);
    return d;
}
