// Cones of directions and the angle ranges between them (cone_of, psi_range, bilinear_range,
// hull_distance, narrowed, mirror_lower_angle, ...).
// Twin: `src/shading/estimator/cone.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// Every value of a field is within `half` of `axis`; half = PI means no bound.
struct Cone {
    vec3 axis;
    float spread;
};

Cone no_cone() {
    return Cone(vec3(0.0, 0.0, 1.0), PI);
}

// The angle between a and b as (|a x b|, a.b) (see `sine_cosine` in Rust).
P vec2 sine_cosine(vec3 a, vec3 b) {
    P vec2 sc = vec2(len(cross3(a, b)), dot3(a, b));
    return sc;
}

// Angle between two vectors; 0 if one is zero.
P float angle(vec3 a, vec3 b) {
    P vec2 sc = sine_cosine(a, b);
    return est_atan2(sc.x, sc.y);
}

// A number that grows with atan2(s, c) on [0, pi] (see `pseudo_angle` in Rust).
P float pseudo_angle(vec2 sc) {
    P float t = sc.x + abs(sc.y);
    P float p = t > 0.0 ? 1.0 - sc.y / t : 0.0;
    return p;
}

// max_k angle(a, u[k]) with one arc tangent, CHOICE_PAD added (see `widest_angle` in Rust).
P float widest_angle(vec3 a, vec3 u0, vec3 u1, vec3 u2) {
    P vec2 sc = sine_cosine(a, u0);
    P float widest = pseudo_angle(sc);
    P vec2 sc1 = sine_cosine(a, u1);
    P float p1 = pseudo_angle(sc1);
    if (p1 > widest) {
        sc = sc1;
        widest = p1;
    }
    P vec2 sc2 = sine_cosine(a, u2);
    P float p2 = pseudo_angle(sc2);
    if (p2 > widest) {
        sc = sc2;
    }
    P float w = est_atan2(sc.x, sc.y) + CHOICE_PAD;
    return w;
}

P vec3 unit(vec3 v) {
    P float l2 = len2(v);
    if (l2 > 0.0 && l2 <= 3.4028235e38) {
        P vec3 u = v / sqrt(l2);
        return u;
    }
    return vec3(0.0);
}

// The smallest cone containing three directions (see `cone_of`).
Cone cone_of(vec3 w0, vec3 w1, vec3 w2) {
    P vec3 u[3] = vec3[3](unit(w0), unit(w1), unit(w2));
    if (is_zero(u[0]) || is_zero(u[1]) || is_zero(u[2])) {
        return no_cone();
    }
    P float d[3] = float[3](len2(u[0] - u[1]), len2(u[1] - u[2]), len2(u[2] - u[0]));
    int k = (d[0] >= d[1] && d[0] >= d[2]) ? 0 : (d[1] >= d[2] ? 1 : 2);
    int i = k;
    int j = (k + 1) % 3;
    P float others = d[(k + 1) % 3] + d[(k + 2) % 3];
    P vec3 axis;
    if (d[k] >= others) {
        axis = unit(u[i] + u[j]);
    } else {
        P vec3 nrm = unit(cross3(u[1] - u[0], u[2] - u[0]));
        axis = dot3(nrm, u[0] + u[1] + u[2]) < 0.0 ? -nrm : nrm;
    }
    if (is_zero(axis)) {
        return no_cone();
    }
    P float half_angle = widest_angle(axis, u[0], u[1], u[2]) + ANGLE_PAD;
    if (is_nan(half_angle) || half_angle >= MAX_HALF) {
        return no_cone();
    }
    return Cone(axis, half_angle);
}

// min |sum l_k w_k| over the simplex >= min_k w_k . axis.
P float min_length(vec3 w0, vec3 w1, vec3 w2, Cone cone) {
    if (cone.spread >= PI) {
        return 0.0;
    }
    P float r = rmin(rmin(dot3(w0, cone.axis), dot3(w1, cone.axis)), dot3(w2, cone.axis));
    return r > 0.0 ? r : 0.0;
}

// Range of the angle between a vector of cone a and one of cone b.
P vec2 psi_range(Cone a, Cone b) {
    P float t0 = angle(a.axis, b.axis);
    P vec2 r = vec2(rmax(t0 - a.spread - b.spread, 0.0), rmin(t0 + a.spread + b.spread, PI));
    return r;
}

// Exact range of q(l) = (sum l_k a_k).(sum l_k b_k) over the simplex.
P vec2 bilinear_range(vec3 a[3], vec3 b[3]) {
    P float s00 = 0.5 * (dot3(a[0], b[0]) + dot3(a[0], b[0]));
    P float s11 = 0.5 * (dot3(a[1], b[1]) + dot3(a[1], b[1]));
    P float s22 = 0.5 * (dot3(a[2], b[2]) + dot3(a[2], b[2]));
    P float s01 = 0.5 * (dot3(a[0], b[1]) + dot3(a[1], b[0]));
    P float s12 = 0.5 * (dot3(a[1], b[2]) + dot3(a[2], b[1]));
    P float s02 = 0.5 * (dot3(a[0], b[2]) + dot3(a[2], b[0]));
    P float lo = rmin(rmin(s00, s11), s22);
    P float hi = rmax(rmax(s00, s11), s22);
    P vec3 edges[3] = vec3[3](vec3(s00, s11, s01), vec3(s11, s22, s12), vec3(s22, s00, s02));
    for (int e = 0; e < 3; ++e) {
        P float sii = edges[e].x;
        P float sjj = edges[e].y;
        P float sij = edges[e].z;
        P float curv = sii - 2.0 * sij + sjj;
        P float t = (sii - sij) / curv;
        if (t > 0.0 && t < 1.0) {
            P float v = (1.0 - t) * (1.0 - t) * sii + 2.0 * t * (1.0 - t) * sij + t * t * sjj;
            lo = rmin(lo, v);
            hi = rmax(hi, v);
        }
    }
    P float d1 = s01 - s00;
    P float d2 = s02 - s00;
    P float ma = s00 - 2.0 * s01 + s11;
    P float mb = s00 - s01 - s02 + s12;
    P float mc = s00 - 2.0 * s02 + s22;
    P float det = ma * mc - mb * mb;
    P float x = (-d1 * mc + d2 * mb) / det;
    P float y = (-ma * d2 + mb * d1) / det;
    if (x > 0.0 && y > 0.0 && x + y < 1.0) {
        P float v = s00 + d1 * x + d2 * y;
        lo = rmin(lo, v);
        hi = rmax(hi, v);
    }
    return vec2(lo, hi);
}

// Angular distance from unit a to the spherical triangle of the unit vectors u.
P float hull_distance(vec3 a, vec3 u[3]) {
    P float orient = dot3(u[0], cross3(u[1], u[2]));
    P float side0 = dot3(a, cross3(u[0], u[1]));
    P float side1 = dot3(a, cross3(u[1], u[2]));
    P float side2 = dot3(a, cross3(u[2], u[0]));
    const float tol = 1.0e-6;
    bool same_half = dot3(a, u[0] + u[1] + u[2]) > 0.0;
    bool inside = same_half
        && ((orient >= 0.0 && side0 >= -tol && side1 >= -tol && side2 >= -tol)
            || (orient <= 0.0 && side0 <= tol && side1 <= tol && side2 <= tol));
    if (inside) {
        return 0.0;
    }
    // The corners' angles and the feet's on the edge arcs, the nearest measured once (see
    // `nearest_angle` in Rust).
    P vec2 nearest_sc = vec2(0.0);
    P float nearest = 0.0;
    for (int e = 0; e < 3; ++e) {
        P vec3 p = u[e];
        P vec3 q = u[(e + 1) % 3];
        P vec2 corner = sine_cosine(a, p);
        P float pc = pseudo_angle(corner);
        if (e == 0 || pc < nearest) {
            nearest_sc = corner;
            nearest = pc;
        }
        P vec3 m = unit(cross3(p, q));
        if (!is_zero(m)) {
            P vec3 foot = a - m * dot3(a, m);
            if (dot3(cross3(p, foot), m) >= 0.0 && dot3(cross3(foot, q), m) >= 0.0 && !is_zero(foot)) {
                P vec2 at_foot = vec2(abs(dot3(a, m)), len(foot));
                P float pf = pseudo_angle(at_foot);
                if (pf < nearest) {
                    nearest_sc = at_foot;
                    nearest = pf;
                }
            }
        }
    }
    P float best = est_atan2(nearest_sc.x, nearest_sc.y) - CHOICE_PAD;
    P float r = rmax(best * HULL_SHRINK - ANGLE_PAD, 0.0);
    return r;
}

// The distance from the origin to the segment p q (see Rust: segment_distance).
P float segment_distance(vec3 p, vec3 q) {
    P vec3 pq = q - p;
    P float length2 = len2(pq);
    P float t = length2 > 0.0 ? rmin(rmax(-dot3(p, pq) / length2, 0.0), 1.0) : 0.0;
    return len(p + pq * t);
}

// A lower bound on the distance from the origin to the triangle c0 c1 c2: its nearest edge, its
// plane's distance where the origin projects inside, a sliver's longest edge less its height
// (see Rust: origin_distance).
P float origin_distance(vec3 c0, vec3 c1, vec3 c2) {
    P float nearest[3] = float[3](segment_distance(c0, c1), segment_distance(c1, c2), segment_distance(c2, c0));
    P float lengths[3] = float[3](len2(c1 - c0), len2(c2 - c1), len2(c0 - c2));
    P float edge_min = rmin(rmin(nearest[0], nearest[1]), nearest[2]);
    int longest = (lengths[0] >= lengths[1] && lengths[0] >= lengths[2]) ? 0 : (lengths[1] >= lengths[2] ? 1 : 2);
    P vec3 normal = cross3(c1 - c0, c2 - c0);
    P float area2 = len2(normal);
    if (area2 >= 0.01 * lengths[longest] * lengths[longest] && area2 > 0.0) {
        bool inside = dot3(normal, cross3(c1 - c0, -c0)) >= 0.0 && dot3(normal, cross3(c2 - c1, -c1)) >= 0.0
            && dot3(normal, cross3(c0 - c2, -c2)) >= 0.0;
        if (inside) {
            return rmin(edge_min, abs(dot3(c0, normal)) / sqrt(area2));
        }
        return edge_min;
    }
    P float height = lengths[longest] > 0.0 ? sqrt(area2) / sqrt(lengths[longest]) : 0.0;
    return rmin(edge_min, nearest[longest] - height);
}

// The angle range of unit fields a, b narrowed by the interpolant of a - b at the corners, whose
// level-1 error is at most curvature/2 (see Rust: narrowed).
P vec2 narrowed(vec2 range, vec3 a[3], vec3 b[3], float curvature) {
    P vec3 c0 = a[0] - b[0];
    P vec3 c1 = a[1] - b[1];
    P vec3 c2 = a[2] - b[2];
    P float error = 0.5 * curvature + 1.0e-5;
    P float lo = origin_distance(c0, c1, c2) - error;
    P float hi = rmax(rmax(len(c0), len(c1)), len(c2)) + error;
    P float lo_angle = lo > 0.0 ? 2.0 * est_asin(rmin(0.5 * lo, 1.0)) - ANGLE_PAD : 0.0;
    P float hi_angle = hi < 2.0 ? 2.0 * est_asin(0.5 * hi) + ANGLE_PAD : PI;
    P float low = rmax(range.x, lo_angle);
    return vec2(low, rmax(rmin(range.y, hi_angle), low));
}

// Largest angle between a and the spherical triangle u when below pi/2, else PI.
P float hull_max_angle(vec3 a, vec3 u[3]) {
    P float m = widest_angle(a, u[0], u[1], u[2]) + ANGLE_PAD;
    return m < HALF_PI ? m : PI;
}

// A lower bound on the angle between n and the half vector of a and b at the same point, where
// n.a > 0 on the whole triangle: n is the half vector of a and its mirror r, and
// angle(h, n) >= angle(b, r)/2; r is within 2 nu_n + nu_a of the axes' mirror r0, and b lies in
// its cone and (when has_vectors) in the spherical triangle of the directions of b_vectors.
// Returns the larger of this and lo (see Rust: mirror_lower_angle).
P float mirror_lower_angle(Cone n, Cone a, Cone b, bool has_vectors, vec3 b_vectors[3], float lo) {
    if (!(n.spread < PI && a.spread < PI && b.spread < PI)) {
        return lo;
    }
    P vec3 r0 = unit(n.axis * (2.0 * dot3(n.axis, a.axis)) - a.axis);
    if (is_zero(r0)) {
        return lo;
    }
    P float spread = 2.0 * n.spread + a.spread;
    P float axis_angle = angle(b.axis, r0);
    P float apart = axis_angle - b.spread;
    if (has_vectors && b.spread > HULL_WORTH && 0.5 * (axis_angle + b.spread - spread) > lo) {
        P vec3 units[3] = vec3[3](unit(b_vectors[0]), unit(b_vectors[1]), unit(b_vectors[2]));
        apart = rmax(apart, hull_distance(r0, units));
    }
    return rmax(lo, 0.5 * (apart - spread) - ANGLE_PAD);
}
