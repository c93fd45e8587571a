// Relaxed: the bands where n.l or n.v crosses 0 (TerminatorBand, view_band) and the specular
// lobe's jump there (terminator_jump).
// Twin: `src/shading/estimator/terminator.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// Relaxed: a bound on |n.l| over the sub-triangles the terminator crosses, of diameters d/L,
// with the scalars that do not depend on the level taken once per light (`TerminatorBand`).
struct TerminatorBand {
    float normal;
    float light;
    float nu;
    float sigma;
    float c_max;
    float fixed_point;
    float held;
    float oscillation;
};

TerminatorBand terminator_band(Frame frame, LightSetup st, Scale d) {
    P float normal = d.b / frame.r_n;
    P float light = d.a * st.inv_d;
    P float fixed_point = normal + frame.n_plane_sin * light;
    P float held = st.plane_sin * light;
    P float oscillation = st.nl_cos.x - st.nl_cos.y;
    P float c_max = rmax(abs(st.nl_cos.x), abs(st.nl_cos.y));
    return TerminatorBand(normal, light, frame.n_plane_sin, st.plane_sin, c_max, fixed_point, held, oscillation);
}

// The band per 1/L at the levels L >= above (`TerminatorBand::per_level`), unguarded.
P float band_per_level(TerminatorBand t, float above) {
    P float c_star = t.c_max;
    P float room = above - t.held;
    if (room > 0.0) {
        c_star = rmin(c_star, t.fixed_point / room);
    }
    P float across = rmin(t.nu + t.sigma * c_star, 1.0);
    P float band = t.normal + t.light * across;
    return band;
}

// The same at one effective level l, at most the oscillation of n.l over the triangle.
P float band_at(TerminatorBand t, float l) {
    P float band = rmin(band_per_level(t, l) / l, t.oscillation);
    return band;
}

// The band's floor as the level grows (`TerminatorBand::floor`).
P float band_floor(TerminatorBand t, inout Guard gd) {
    P float band = t.normal + t.light * rmin(t.nu, 1.0);
    return gc(band, gd);
}

// Relaxed, GGX: |n.v| on a sub-triangle of diameters d that n.v = 0 crosses (`view_band`).
P float view_band(Frame frame, Scale d, inout Guard gd) {
    return gc(d.b / frame.r_n + d.a / frame.e_min, gd);
}

// Relaxed: the factor <= 1 by which the specular lobe's sup over the band 0 < n.l <= beta is
// below its sup over the triangle (see `lobe_band_share`).
P float lobe_band_share(vec2 param, LightSetup st, float beta) {
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return 0.0;
    }
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        // The angle from n to h is at least the angle from n to l (>= acos beta) minus half
        // the angle between l and v.
        P float h0 = st.psi_nh.x;
        P float edge = est_acos(rmin(beta, 1.0)) - ANGLE_PAD - 0.5 * st.psi_lv.y;
        if (!(edge > h0)) {
            return 1.0;
        }
        P float ce = est_cos(edge);
        P float ch = est_cos(h0);
        if (!(ch > 0.0) || !(ce < ch)) {
            return 1.0;
        }
        if (!(ce > 0.0)) {
            return 0.0;
        }
        return est_pow(ce / ch, param.x);
    }
    // GGX: G(c) = c/(c(1-k)+k) on the band, at the smallest k, against G(c_max).
    P float k = 0.5 * max(param.x * param.x, GGX_MIN_ALPHA);
    P float c1 = st.nl_cos.x;
    if (!(beta < c1)) {
        return 1.0;
    }
    return (beta * (c1 * (1.0 - k) + k)) / (c1 * (beta * (1.0 - k) + k));
}

// Relaxed: the jump of the specular lobe that n.l > 0 switches on, on the band of width beta.
P vec3 terminator_jump(vec3 spec_w, vec3 spec_sup, vec2 param, LightSetup st, float beta) {
    if (!st.straddle || st.area || !st.specular) {
        return vec3(0.0);
    }
    return spec_w * spec_sup * (lobe_band_share(param, st, beta) * SAFETY);
}
