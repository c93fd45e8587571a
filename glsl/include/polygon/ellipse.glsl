// The ellipses of the projected edges and sampling between two of them in a sector
// (Algorithms 1 to 3).
// Part of polygon.glsl, which includes its parts in order (each uses only those before it).
// Rust twin: `src/shading/polygon/ellipse.rs`; `tests/polygon_gpu.rs` checks that the two agree.

// Algorithm 1: the ellipse u (C = I + u u^T) of the great circle through a and b; the sign bit
// of u.x is set iff the edge runs clockwise about the zenith; (inf, 0) when degenerate.
precise vec2 ellipse_from_edge(vec3 a, vec3 b) {
    precise vec3 normal = cross_stable(a, b);
    precise float scaling = polygon_copysign(1.0, normal.x) / normal.z;
    if (normal.z == 0.0 || !polygon_is_finite(scaling)) {
        return vec2(polygon_infinity(), 0.0);
    }
    return vec2(normal.x * scaling, normal.y * scaling);
}

// Whether an ellipse is an inner one (reads the sign bit).
bool is_inner(vec2 ellipse) {
    return polygon_sign_negative(ellipse.x);
}

// Whether an ellipse is degenerate (A.2).
bool is_degenerate(vec2 ellipse) {
    return ellipse.x == polygon_infinity();
}

// C p = p + u (u.p).
precise vec2 ellipse_transform(vec2 ellipse, vec2 point) {
    return point + ellipse * dot2(ellipse, point);
}

// p^T C p = |p|^2 + (u.p)^2.
precise float ellipse_quadratic_form(vec2 ellipse, vec2 point) {
    precise float along = dot2(ellipse, point);
    return fused_multiply_add(along, along, dot2(point, point));
}

// 1/sqrt(det C); 0 for degenerate ellipses.
precise float ellipse_rsqrt_det(vec2 ellipse) {
    if (is_degenerate(ellipse)) {
        return 0.0;
    }
    return 1.0 / sqrt(1.0 + dot2(ellipse, ellipse));
}

// Area of the ellipse within the sector from dir_0 counterclockwise to dir_1 (supplement Eq. (1)).
precise float ellipse_area_in_sector(vec2 ellipse, float rsqrt_det, vec2 dir_0, vec2 dir_1) {
    if (is_degenerate(ellipse)) {
        return 0.0;
    }
    precise float det_dirs = max(det2(dir_0, dir_1), 0.0);
    precise float dot_dirs = rsqrt_det * dot2(dir_0, ellipse_transform(ellipse, dir_1));
    return 0.5 * rsqrt_det * polygon_atan2(det_dirs, dot_dirs);
}

// Area between an outer and an inner ellipse within a sector; never negative.
precise float area_between_ellipses_in_sector(vec2 inner, vec2 outer, vec2 dir_0, vec2 dir_1) {
    precise float area = ellipse_area_in_sector(outer, ellipse_rsqrt_det(outer), dir_0, dir_1)
        - ellipse_area_in_sector(inner, ellipse_rsqrt_det(inner), dir_0, dir_1);
    return area > 0.0 ? area : 0.0;
}

// Algorithm 2 (Blinn): a non-zero root of w^T Q w = 0 from Q_xx, Q_xy + Q_yx and Q_yy.
precise vec2 solve_homogeneous_quadratic(float q_xx, float q_xy_plus_yx, float q_yy) {
    precise float b = 0.5 * q_xy_plus_yx;
    precise float sqrt_discriminant = sqrt(max(b * b - q_xx * q_yy, 0.0));
    precise float scaled_root = abs(b) + sqrt_discriminant;
    if (b >= 0.0) {
        return vec2(scaled_root, -q_xx);
    }
    return vec2(q_yy, scaled_root);
}

// The coefficients (Q_xx, Q_xy + Q_yx, Q_yy) of Q = a g^T - k c e^T.
precise vec3 quadratic_from_outer_products(vec2 a, vec2 g, float k, vec2 c, vec2 e) {
    return vec3(a.x * g.x - k * c.x * e.x,
                a.x * g.y + a.y * g.x - k * (c.x * e.y + c.y * e.x),
                a.y * g.y - k * c.y * e.y);
}

// `root` unless it is zero or not finite, then `fallback`.
precise vec2 usable_root(vec2 root, vec2 fallback) {
    precise float size = abs(root.x) + abs(root.y);
    return size > 0.0 && polygon_is_finite(size) ? root : fallback;
}

// Algorithm 3: a point uniform in area between the inner and outer ellipse within the sector
// from dir_0 to dir_1 (see the Rust twin for the rotated bases).
precise vec2 sample_sector_between_ellipses(vec2 u, float target_area, vec2 inner, vec2 outer, vec2 dir_0,
                                            vec2 dir_1, bool iterate) {
    precise vec2 s_0 = normalize2(dir_0);
    precise vec2 s_1_full = normalize2(dir_1);
    precise vec2 s_h = s_0 + s_1_full;
    precise float inner_0 = 1.0 / sqrt(ellipse_quadratic_form(inner, s_0));
    precise float inner_h = 1.0 / sqrt(ellipse_quadratic_form(inner, s_h));
    precise float inner_1_full = 1.0 / sqrt(ellipse_quadratic_form(inner, s_1_full));
    precise float outer_0 = 1.0 / sqrt(ellipse_quadratic_form(outer, s_0));
    precise float outer_h = 1.0 / sqrt(ellipse_quadratic_form(outer, s_h));
    precise float outer_1_full = 1.0 / sqrt(ellipse_quadratic_form(outer, s_1_full));
    // Areas of the two quads, up to a common factor
    precise float quad_0 = outer_0 * outer_h - inner_0 * inner_h;
    precise float quad_1 = outer_h * outer_1_full - inner_h * inner_1_full;
    // Pick a quad; its outer boundary direction goes to index 1
    precise float quad_target = mix_exact(-quad_0, quad_1, u.x);
    bool first_quad = quad_target <= 0.0;
    precise vec2 s_1 = first_quad ? s_0 : s_1_full;
    precise float inner_1 = first_quad ? inner_0 : inner_1_full;
    precise float outer_1 = first_quad ? outer_0 : outer_1_full;
    quad_target += first_quad ? quad_0 : -quad_1;
    // Twice the signed target area
    quad_target *= abs(det2(s_h, s_1));
    // Lines through the quad's inner and outer edge
    precise vec2 inner_normal = ellipse_transform(inner, inner_h * s_h + inner_1 * s_1);
    precise vec2 outer_normal = ellipse_transform(outer, outer_h * s_h + outer_1 * s_1);
    precise float inner_offset = inner_h * dot2(inner_normal, s_h);
    precise float outer_offset = outer_h * dot2(outer_normal, s_h);
    // Q in the basis (s_1, R s_1)
    precise vec2 e_1 = rotate_90(s_1);
    precise vec2 g = (outer_1 * outer_offset) * inner_normal - (inner_1 * inner_offset) * outer_normal;
    precise vec3 q = quadratic_from_outer_products(vec2(0.0, 1.0), vec2(dot2(g, s_1), dot2(g, e_1)), quad_target,
                                                   vec2(dot2(inner_normal, s_1), dot2(inner_normal, e_1)),
                                                   vec2(dot2(outer_normal, s_1), dot2(outer_normal, e_1)));
    precise vec2 root = usable_root(solve_homogeneous_quadratic(q.x, q.y, q.z), vec2(1.0, 0.0));
    precise vec2 w = root.x * s_1 + root.y * e_1;
    // Refine, unless at the ends of the sector where the initialisation is exact
    int iterations = iterate && u.x >= ITERATION_MARGIN && u.x <= 1.0 - ITERATION_MARGIN ? ITERATION_COUNT : 0;
    precise float inner_rsqrt_det = ellipse_rsqrt_det(inner);
    precise float outer_rsqrt_det = ellipse_rsqrt_det(outer);
    for (int iteration = 0; iteration < ITERATION_COUNT; ++iteration) {
        if (iteration >= iterations) {
            break;
        }
        // Keep w away from under- and overflow, on the side of the sector
        w *= 1.0 / (abs(w.x) + abs(w.y));
        if (dot2(w, s_h) < 0.0) {
            w = -w;
        }
        precise vec2 inner_w = ellipse_transform(inner, w);
        precise vec2 outer_w = ellipse_transform(outer, w);
        precise float det_dirs = max(det2(s_0, w), 0.0);
        precise float area = 0.5
            * (outer_rsqrt_det * polygon_atan2(det_dirs, outer_rsqrt_det * dot2(s_0, outer_w))
               - inner_rsqrt_det * polygon_atan2(det_dirs, inner_rsqrt_det * dot2(s_0, inner_w)));
        precise float residual = target_area - area;
        // T in the basis (w, R w)
        precise vec2 w_perp = rotate_90(w);
        precise float inner_along = dot2(inner, w);
        precise float outer_along = dot2(outer, w);
        precise float difference_along = (inner_along - outer_along) * (inner_along + outer_along);
        precise vec3 t = quadratic_from_outer_products(vec2(0.0, dot2(w, w)),
                                                       vec2(difference_along, dot2(inner_w - outer_w, w_perp)),
                                                       2.0 * residual, vec2(dot2(inner_w, w), dot2(inner_w, w_perp)),
                                                       vec2(dot2(outer_w, w), dot2(outer_w, w_perp)));
        precise vec2 refined = usable_root(solve_homogeneous_quadratic(t.x, t.y, t.z), vec2(1.0, 0.0));
        w = refined.x * w + refined.y * w_perp;
    }
    // The half sectors span at most 90 degrees: the root on the side of s_h is the right one
    if (dot2(w, s_h) < 0.0) {
        w = -w;
    }
    // Stay in the sector even when rounding dominates the areas
    if (det2(s_0, w) < 0.0) {
        w = s_0;
    } else if (det2(w, s_1_full) < 0.0) {
        w = s_1_full;
    }
    // Uniform in squared radius between the two ellipses
    precise float inner_squared_radius = 1.0 / ellipse_quadratic_form(inner, w);
    precise float outer_squared_radius = 1.0 / ellipse_quadratic_form(outer, w);
    return w * sqrt(max(mix_exact(inner_squared_radius, outer_squared_radius, u.y), 0.0));
}
