// The BRDF factors' jets (power_jet, ggx_d_jet, ggx_factor_jets and their net coefficients), a
// textured parameter's variation and a polygonal light's specular bound.
// Twin: `src/shading/estimator/lobe.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// The power's profile coefficient less the cosine's turning part (see `power_net_coefficient`).
P float power_net_coefficient(float s0, float s1, float c0, float c1) {
    P float p = 0.5 * (s0 - 2.0);
    P float peak = p * (s1 - 1.0) / ((p + 1.0) * s1);
    P float x = rmin(rmax(peak, c1 * c1), c0 * c0);
    P float r = s1 * est_pow(x, p) * rmax((s1 - 1.0) * (1.0 - x) - x, 0.0);
    return r;
}

// Blinn-Phong's lobe t^s, t = n.h over the angle range [h0, h1] moving at most w_nh, for a
// shininess anywhere in param = [s0, s1] (see `power_jet` in Rust).
Jet power_jet(Field n, Field h, vec2 param, float h0, float h1, float w_nh, inout Guard gd) {
    P float s0 = param.x;
    P float s1 = param.y;
    Jet c_nh = cosine(n, h, vec2(h0, h1), gd);
    P float chi = est_cos(h0);
    Jet t = jet_constant(est_pow(chi, s0));
    t.g = gc(s1 * max_cos_sin(s0 - 1.0, 1.0, h0, h1) * w_nh, gd);
    P float slope = s1 * est_pow(chi, s0 - 1.0);
    t.h = gmul(c_nh.h, slope, gd);
    P float hp = 0.0;
    P float k = 0.0;
    P float w2 = gmul(w_nh, w_nh, gd);
    if (s1 > 1.0) {
        k = s1 * (s1 - 1.0) * max_cos_sin(s0 - 2.0, 2.0, h0, h1);
        hp = gmul(k, w2, gd);
        if (booked(T_POWER, gd)) {
            t.h = gc(t.h + hp, gd);
        }
    }
    if (gd.term == T_ALL) {
        // The power's part >= 0, the cosine's turning part <= 0: the larger, plus the rest.
        Curvature curv = curvature(n, h, vec2(h0, h1), gd);
        P float turning = gmul(gmul(s1, est_pow(chi, s0), gd), curv.turn, gd);
        // The profile's part less the turning part, on the turn's share of w^2 (see Rust).
        P float net = hp;
        if (s1 > 1.0 && s0 > 2.0) {
            P float c1 = power_net_coefficient(s0, s1, chi, rmax(est_cos(h1), 0.0));
            net = gc(gmul(c1, curv.turn, gd) + gmul(k, rmax(w2 - curv.turn, 0.0), gd), gd);
        }
        P float joint = gc(gmul(slope, curv.rest, gd) + rmax(rmin(net, hp), turning), gd);
        t.h = rmin(t.h, joint);
    }
    return guard_jet(t, gd);
}

// The distribution's profile coefficient less the turning part at s2 = sin^2 psi (see
// `ggx_net_coefficient` in Rust).
P float ggx_net_at(float a2, float beta, float coef, float x) {
    P float u = a2 + beta * x;
    P float n = (2.0 * a2 + 5.0 * beta - 4.0 * beta * x) * x - a2;
    P float r = coef * rmax(n, 0.0) / ((u * u) * (u * u));
    return r;
}

P float ggx_net_coefficient(float a2, float s0, float s1) {
    P float beta = 1.0 - a2;
    P float coef = 4.0 * a2 * beta / PI;
    P float b = beta * (14.0 * a2 + 15.0 * beta);
    P float c = a2 * (2.0 * a2 + 9.0 * beta);
    P float root = 2.0 * c / rmax(b + sqrt(rmax(b * b - 32.0 * beta * beta * c, 0.0)), 1.0e-30);
    P float r = rmax(rmax(ggx_net_at(a2, beta, coef, rmin(rmax(root, s0), s1)), ggx_net_at(a2, beta, coef, s0)),
                     ggx_net_at(a2, beta, coef, s1));
    return r;
}

// GGX D(n.h) jet (see `ggx_d_jet`).
Jet ggx_d_jet(Jet c, Curvature curv, float p0, float p1, float w, float alpha, inout Guard gd) {
    P float a2 = alpha * alpha;
    P float beta = 1.0 - a2;
    P float coef = 4.0 * a2 * beta / PI;
    P float sp0 = est_sin(p0);
    P float sp1 = est_sin(p1);
    P float s0 = sp0 * sp0;
    P float s1 = sp1 * sp1;
    P float b1 = 5.0 * beta + 2.0 * a2;
    P float r1 = 2.0 * a2 / rmax(b1 + sqrt(rmax(b1 * b1 - 16.0 * a2 * beta, 0.0)), 1.0e-30);
    P float x1 = clamp(r1, s0, s1);
    P float u1 = a2 + beta * x1;
    P float d1 = sqrt(rmax(x1 * (1.0 - x1), 0.0)) / (u1 * u1 * u1);
    P float big_a = a2 + 6.0 * beta;
    P float b2 = 3.0 * big_a + 10.0 * a2;
    P float r2 = 2.0 * big_a * a2
        / rmax(beta * (b2 + sqrt(rmax(b2 * b2 - 40.0 * big_a * a2, 0.0))), 1.0e-30);
    P float x2 = clamp(r2, s0, s1);
    P float u2 = a2 + beta * x2;
    P float d2 = x2 * (big_a - 5.0 * beta * x2) / (u2 * u2 * u2 * u2);
    P float u0 = a2 + beta * s0;
    Jet o = jet_constant(a2 / (PI * u0 * u0));
    o.g = gmul(gc(coef * d1, gd), w, gd);
    P float slope = gc(coef * est_cos(p0) / (u0 * u0 * u0), gd);
    o.h = gmul(c.h, slope, gd);
    P float w2 = gmul(w, w, gd);
    P float dd = gc(coef * d2, gd);
    P float dh = gmul(dd, w2, gd);
    if (booked(T_D, gd)) {
        o.h = gc(o.h + dh, gd);
    }
    if (gd.term == T_ALL) {
        // D''(Dt)^2 >= 0 and D'(-t(|u|^2 + |v|^2)) <= 0: the larger, plus the rest; the first
        // less the second on the turn's share of w^2 (see `ggx_net_coefficient`).
        P float c0 = est_cos(p0);
        P float turning = gmul(gc(coef * c0 * c0 / (u0 * u0 * u0), gd), curv.turn, gd);
        P float net = gc(gmul(ggx_net_coefficient(a2, s0, s1), curv.turn, gd)
            + gmul(dd, rmax(w2 - curv.turn, 0.0), gd), gd);
        P float joint = gc(gmul(slope, curv.rest, gd) + rmax(rmin(net, dh), turning), gd);
        o.h = rmin(o.h, joint);
    }
    return guard_jet(o, gd);
}

// The roughness-dependent GGX factors G, V and D at one alpha (see `ggx_factor_jets`).
void ggx_factor_jets(Field n, Field l, Field v, Field h, LightSetup st, vec2 nh, float w_nh,
                     float alpha, float view_band, out Jet gjet, out Jet vjet, out Jet djet, inout Guard gd) {
    P float h0 = nh.x;
    P float h1 = nh.y;
    P float k = 0.5 * alpha;

    // G = c/(c(1-k)+k) with c = n.l >= 0.
    P vec2 nl = vec2(st.psi_nl.x, rmin(st.psi_nl.y, HALF_PI));
    Jet c_g = cosine(n, l, nl, gd);
    P float c0 = rmax(est_cos(nl.y), 0.0);
    P float c1 = est_cos(nl.x);
    P float q0 = c0 * (1.0 - k) + k;
    P float q1 = c1 * (1.0 - k) + k;
    P float g1 = k / (q0 * q0);
    P float g2 = 2.0 * k * (1.0 - k) / (q0 * q0 * q0);
    gjet = chain(c_g, c1 / q1, g1, g2, T_V, gd);

    // V_v = 1/(max(n.v, 0)(1-k)+k): constant 1/k where n.v <= 0 throughout.
    if (st.nv_sign == SIGN_NON_POSITIVE) {
        vjet = jet_constant(1.0 / k);
    } else if (st.nv_sign == SIGN_BOTH) {
        // Relaxed, the view's kink inside: the smooth parts (see `smith_v_kink_jet`).
        Jet c_v = cosine(n, v, st.psi_nv, gd);
        P float slope = (1.0 - k) / (k * k);
        P float v2 = 2.0 * (1.0 - k) * (1.0 - k) / (k * k * k);
        vjet = chain(c_v, gc(1.0 / k + gmul(slope, rmin(c_v.m, view_band), gd), gd), slope, v2, T_V, gd);
    } else {
        P vec2 nv = vec2(st.psi_nv.x, rmin(st.psi_nv.y, HALF_PI));
        Jet c_v = cosine(n, v, nv, gd);
        P float q = rmax(est_cos(nv.y), 0.0) * (1.0 - k) + k;
        P float v1 = (1.0 - k) / (q * q);
        P float v2 = 2.0 * (1.0 - k) * (1.0 - k) / (q * q * q);
        vjet = chain(c_v, 1.0 / q, v1, v2, T_V, gd);
    }

    // D(t), t = n.h.
    if (st.psi_nh.x >= HALF_PI) {
        djet = jet_constant(alpha * alpha / PI);
    } else {
        Jet c_nh = cosine(n, h, vec2(h0, h1), gd);
        Curvature curv = curvature(n, h, vec2(h0, h1), gd);
        djet = ggx_d_jet(c_nh, curv, h0, h1, w_nh, alpha, gd);
    }
}

// The variation sup|f(a) - f(a')| of one light's specular part for a parameter anywhere in
// `param` (see `parameter_variation`).
P vec3 parameter_variation(vec2 param, LightSetup st, vec3 spec_sup) {
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return vec3(0.0);
    }
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        P float s0 = param.x;
        P float s1 = param.y;
        if (!(s1 > s0) || st.psi_nh.x >= HALF_PI) {
            return vec3(0.0);
        }
        P float t_lo = rmax(est_cos(rmin(st.psi_nh.y, HALF_PI)), 0.0);
        P float t_hi = est_cos(st.psi_nh.x);
        P float t = rmin(rmax(est_pow(s0 / s1, 1.0 / (s1 - s0)), t_lo), t_hi);
        P float upper = est_pow(t, s0);
        P float att = st.inv_d > 0.0 ? st.inv_d * st.inv_d : 1.0;
        P float variation = ((upper - est_pow(t, s1)) * SAFETY + 1.0e-6 * upper) * att;
        return vec3(rmax(variation, 0.0));
    }
    P float alpha_lo = max(param.x * param.x, GGX_MIN_ALPHA);
    P float alpha_hi = max(param.y * param.y, GGX_MIN_ALPHA);
    if (!(alpha_hi > alpha_lo)) {
        return vec3(0.0);
    }
    P float share = rmin(4.0 * LN_2 * est_log2(alpha_hi / alpha_lo), 1.0);
    return spec_sup * (share * SAFETY);
}

// The GGX distribution at n.h = c: brdf.glsl's ggx_d, `precise` (no contraction, as in Rust).
P float ggx_d_value(float c, float alpha) {
    P float a2 = alpha * alpha;
    P float d = c * c * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// (2 - v) sup f/p_light + v sup f/p_brdf (see `mis_bound` in Rust).
P float mis_bound(float light_part, float brdf_part, inout Guard gd) {
    return gc(gmul(2.0 - MIS_VISIBILITY, light_part, gd) + gmul(MIS_VISIBILITY, brdf_part, gd), gd);
}

// An upper bound of a polygonal light's sampled specular part on the triangle, per channel
// (see `polygon_specular_bound` in Rust for the derivation).
P vec3 polygon_specular_bound(GpuMaterial material, vec2 param, LightSetup st, GpuPolygonLight light, inout Guard gd) {
    if (MATERIAL_KIND == MATERIAL_LAMBERT || !st.area) {
        return vec3(0.0);
    }
    P vec3 radiance = light.radiance.rgb;
    P float cos_l_min = rmax(st.nl_cos.y, 0.0);
    P float cos_l_max = rmin(st.nl_cos.x, 1.0);
    P float cos_y_max = rmin(est_cos(st.emitter.x), 1.0);
    P float omega = gc(rmin(gmul(light.normal.w * cos_y_max, gmul(st.inv_d, st.inv_d, gd), gd), 2.0 * PI), gd);
    P float h0 = st.psi_nh.x;
    P float h1 = st.psi_nh.y;
    bool projected = POLYGON_TECHNIQUE == 0;
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        P float s0 = param.x;
        P float peak = h0 < HALF_PI ? est_pow(est_cos(h0), s0) : 0.0;
        P float light_part = gmul(peak, omega, gd);
        if (projected && light_part > 0.0) {
            light_part = gc(light_part * cos_l_max / cos_l_min, gd);
        }
        P float brdf_part = 8.0 * PI / (s0 + 1.0);
        P vec3 b = radiance * material.specular.rgb * mis_bound(light_part, brdf_part, gd);
        return b;
    }
    P float alpha_lo = max(param.x * param.x, GGX_MIN_ALPHA);
    P float alpha_hi = max(param.y * param.y, GGX_MIN_ALPHA);
    P float k = 0.5 * alpha_lo;
    P float cos_h = h0 < HALF_PI ? est_cos(h0) : 0.0;
    P float d_max = rmax(ggx_d_value(cos_h, alpha_lo), ggx_d_value(cos_h, alpha_hi));
    if (alpha_hi > alpha_lo && cos_h > 0.0) {
        P float s2 = rmax(1.0 - cos_h * cos_h, 0.0);
        P float peak = rmin(rmax(sqrt(s2 / (cos_h * cos_h)), alpha_lo), alpha_hi);
        d_max = rmax(d_max, ggx_d_value(cos_h, peak));
    }
    P float cos_v_min = rmax(est_cos(st.psi_nv.y), 0.0);
    P float v_side = cos_v_min * (1.0 - k) + k;
    P float v_max = 1.0 / ((cos_l_min * (1.0 - k) + k) * v_side);
    P float light_part = h0 < HALF_PI ? gmul(gmul(0.25 * d_max, v_max, gd), omega * cos_l_max, gd) : 0.0;
    P float cos_h_min = rmax(est_cos(rmin(h1, HALF_PI)), 0.0);
    P float brdf_part = v_side * cos_h_min > 0.5 / v_max ? 1.0 / (v_side * cos_h_min) : 2.0 * v_max;
    P float om = 1.0 - clamp(est_cos(0.5 * st.psi_lv.y), 0.0, 1.0);
    P float om2 = om * om;
    P float om4 = om2 * om2;
    P float om5 = om * om4;
    P vec3 f_max = material.specular.rgb + (vec3(1.0) - material.specular.rgb) * om5;
    P vec3 b = radiance * f_max * mis_bound(light_part, brdf_part, gd);
    return b;
}
