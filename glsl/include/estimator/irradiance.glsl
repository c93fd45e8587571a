// The jets of one light's diffuse and specular parts (light_jets, attenuation_jet, irradiance_jet)
// and the terms a material can have (active_term).
// Twin: `src/shading/estimator/irradiance.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// The normal part of n.D^2 I with the falloff and sin(gamma) taken together along
// sin^2 = 1 - H^2/d^2 (see `along_plane` in Rust): the coefficient of |a|^2/d_min^4.
P float along_plane(LightSetup st, float nu, float c) {
    P float h2 = st.near_cos * st.near_cos;
    P float q = rmax(1.875 * h2, 1.0);
    P float rising = rmax(12.0 * q - 15.0 * h2, 0.0) / (q * q * q);
    P float k = 6.0 * st.plane_sin * nu + rmax(rising, 3.0) * c;
    return k;
}

// The light part n.D^2 I with the normal split along the plane normal and in the plane (see
// `tilted` in Rust): the coefficient of |a|^2/d_min^4.
P float tilted(LightSetup st, float nu) {
    P float h2 = st.near_cos * st.near_cos;
    P float rising;
    if (7.0 * h2 <= 4.0) {
        rising = 12.0 - 15.0 * h2;
    } else {
        P float x = 4.0 / (7.0 * h2);
        rising = rmax(TILT_PEAK * x * x * sqrt(x), 3.0);
    }
    P float s = st.plane_sin;
    P float s2 = s * s;
    P float turning;
    if (s2 < 0.2) {
        turning = s * (9.0 - 15.0 * s2);
    } else if (s2 <= 0.8) {
        turning = TILT_FLAT;
    } else {
        turning = s * (15.0 * s2 - 9.0);
    }
    P float k = st.far_cos * rising + nu * turning;
    return k;
}

// A point light's diffuse factor n.I with the irradiance field I = r/|r|^3 bounded as one
// field (see `irradiance_jet` in Rust).
Jet irradiance_jet(Frame frame, LightSetup st, Field n, float a, inout Guard gd) {
    Angles an = angles_with(st.psi_nl, st.nl_cos);
    P float sg = st.plane_sin;
    P float nu = frame.n_plane_sin;
    P float c = an.c_max;
    P float id2 = gmul(st.inv_d, st.inv_d, gd);
    P float a_id = gmul(a, st.inv_d, gd);
    P float a_id2 = gmul(a_id, a_id, gd);
    P float sg2 = sg * sg;
    P float near2 = st.near_sin * st.near_sin;
    P float speed = sqrt(1.0 + 3.0 * near2);
    P float along_normal = rmin(rmin(speed, nu + 3.0 * c * sg), 2.0 * sg * c + an.s_max);
    P float whole = sqrt(rmax(45.0 * near2 * near2 - 18.0 * near2 + 9.0, 9.0));
    P float projected = 6.0 * sg * nu + rmax(abs(15.0 * sg2 - 3.0), 3.0) * c;
    P float product_rule = rmax(8.0 * sg2 - 2.0, 2.0) * c + 4.0 * sg * an.s_max
                           + rmin(an.phi, c + 2.0 * an.s_max * sg);
    P float light_k = rmin(rmin(rmin(rmin(whole, projected), product_rule), along_plane(st, nu, c)), tilted(st, nu));
    P float cross_k = rmin(speed, 2.0 * sg * an.s_max + 1.0);
    P float hn = gmul(seen(an, n, gd), id2, gd);
    P float hd = gmul(gmul(2.0 * cross_k * n.w, a_id, gd), id2, gd);
    P float hl = gmul(light_k * a_id2, id2, gd);
    Jet j = jet_constant(gmul(c, id2, gd));
    if (booked(T_NORMAL, gd)) {
        j.h = hn;
    }
    if (booked(T_DOT, gd)) {
        j.h = j.h + hd;
    }
    if (booked(T_LIGHT, gd)) {
        j.h = j.h + hl;
    }
    j.h = gc(j.h, gd);
    j.g = gc(gmul(an.s_max * n.w, id2, gd) + gmul(along_normal * a_id, id2, gd), gd);
    return j;
}

// The falloff 1/d^2 of a point light at 1/d_min = inv_d, seen from a pattern scale `a` along a
// plane at the sine `plane_sin` (see `attenuation_jet` in Rust).
Jet attenuation_jet(float inv_d, float plane_sin, float a, inout Guard gd) {
    Jet att;
    P float id = inv_d;
    P float id2 = gmul(id, id, gd);
    P float a_id = gmul(a, id, gd);
    P float sg = plane_sin;
    att = jet_constant(id2);
    P float a_id2 = gmul(a_id, a_id, gd);
    P float k = rmax(8.0 * sg * sg - 2.0, 2.0);
    P float ha = gmul(k * a_id2, id2, gd);
    if (booked(T_ATTENUATION, gd)) {
        att.h = ha;
    }
    att.g = gmul(2.0 * sg * a_id, id2, gd);
    return att;
}

// The jets of one light's diffuse part and (per channel) specular part at pattern scale s,
// and GGX's view-kink weight (see `LightJets`); view_band bounds |n.v| where the kink crosses.
void light_jets(Frame frame, GpuMaterial material, vec2 param, LightSetup st, Scale s,
                float view_band, out Jet diffuse, out Jet spec[3], out vec3 view_kink, inout Guard gd) {
    view_kink = vec3(0.0);
    P float n_w = gc(s.b / frame.r_n, gd);
    P Field n = Field(n_w, rmin(n_w, gc(s.g / frame.r_n, gd)), 0.0, T_NORMAL);
    P float l_w = gmul(s.a, st.inv_d, gd);
    Field l = Field(l_w, gmul(l_w, st.plane_sin, gd), 0.0, T_LIGHT);
    Jet att;
    if (st.inv_d > 0.0) {
        att = attenuation_jet(st.inv_d, st.plane_sin, s.a, gd);
    } else {
        att = jet_constant(1.0);
    }
    if (st.area) {
        // Each point of the polygon: a point light with the emitter's cosine.
        Field fixed_direction = Field(0.0, 0.0, 0.0, T_LIGHT);
        att = product2(att, cosine(fixed_direction, l, st.emitter, gd), gd);
    }
    if (st.inv_d > 0.0 && !st.area) {
        diffuse = irradiance_jet(frame, st, n, s.a, gd);
    } else {
        diffuse = product2(att, cosine_at(n, l, angles_with(st.psi_nl, st.nl_cos), gd), gd);
    }
    Jet zero = jet_constant(0.0);
    spec[0] = zero;
    spec[1] = zero;
    spec[2] = zero;
    if (MATERIAL_KIND == MATERIAL_LAMBERT || st.area || !st.specular) {
        return;
    }

    P float v_w = gc(s.a / frame.e_min, gd);
    Field v = Field(v_w, v_w, 0.0, T_VIEW);
    P float h_w = gc((l.w + v.w) / st.m_min, gd);
    Field h = Field(h_w, h_w, gc(K23 * (l.w * l.w + v.w * v.w) / st.m_min, gd), T_HALF);
    P float h0 = st.psi_nh.x;
    P float h1 = rmin(st.psi_nh.y, HALF_PI);
    P float w_nh = gc(n.w + h.w, gd);

    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        if (st.psi_nh.x >= HALF_PI) {
            return;
        }
        Jet sp = product2(att, power_jet(n, h, param, h0, h1, w_nh, gd), gd);
        spec[0] = sp;
        spec[1] = sp;
        spec[2] = sp;
        return;
    }

    // GGX: D, G and V at the ends of the roughness range and where D peaks (see Rust).
    P float alpha_lo = max(param.x * param.x, GGX_MIN_ALPHA);
    P float alpha_hi = max(param.y * param.y, GGX_MIN_ALPHA);
    P float alphas[3] = float[3](alpha_lo, alpha_lo, alpha_lo);
    int alpha_count = 1;
    if (TEXTURED && alpha_hi > alpha_lo) {
        alphas[1] = alpha_hi;
        alpha_count = 2;
        if (st.psi_nh.x < HALF_PI) {
            P float sh0 = est_sin(h0);
            P float s2 = sh0 * sh0;
            alphas[2] = rmin(rmax(sqrt(s2 / (1.0 - s2)), alpha_lo), alpha_hi);
            alpha_count = 3;
        }
    }
    Jet gjet;
    Jet vjet;
    Jet djet;
    ggx_factor_jets(n, l, v, h, st, vec2(h0, h1), w_nh, alphas[0], view_band, gjet, vjet, djet, gd);
    for (int i = 1; i < alpha_count; ++i) {
        Jet g2;
        Jet v2;
        Jet d2;
        ggx_factor_jets(n, l, v, h, st, vec2(h0, h1), w_nh, alphas[i], view_band, g2, v2, d2, gd);
        gjet = jet_max(gjet, g2);
        vjet = jet_max(vjet, v2);
        djet = jet_max(djet, d2);
    }

    // v.h = |l + v|/2.
    P float t0 = clamp(est_cos(0.5 * st.psi_lv.y), 0.0, 1.0);
    P float gt = gc(0.5 * (l.w + v.w), gd);
    P float ht_light = gc(0.5 * K23 * l.w * l.w, gd);
    P float ht_view = gc(0.5 * K23 * v.w * v.w, gd);
    P float ht_half = gc(0.5 * (l.w + v.w) * (l.w + v.w) / st.m_min, gd);
    P float ht = gd.term == T_ALL ? ht_light + ht_view + ht_half
        : (gd.term == T_LIGHT ? ht_light
        : (gd.term == T_VIEW ? ht_view : (gd.term == T_HALF ? ht_half : 0.0)));
    P float om = 1.0 - t0;
    P float om2 = om * om;
    P float om3 = om * om2;
    P float om4 = om2 * om2;
    P float om5 = om * om4;
    // |V'| at the kink, largest at the smallest k.
    P float k_lo = 0.5 * alpha_lo;
    P float kink_slope = (1.0 - k_lo) / (k_lo * k_lo);
    for (int c = 0; c < 3; ++c) {
        P float f0c = material.specular[c];
        P float fm = f0c + (1.0 - f0c) * om5;
        P float f1 = 5.0 * (1.0 - f0c) * om4;
        P float f2 = 20.0 * (1.0 - f0c) * om3;
        Jet fjet = chain(Jet(0.0, gt, ht), fm, f1, f2, T_F, gd);
        Jet f[5] = Jet[5](att, djet, fjet, gjet, vjet);
        Jet p = product(f, 5, gd);
        spec[c].m = 0.25 * p.m;
        spec[c].g = 0.25 * p.g;
        spec[c].h = gmul(p.h, 0.25, gd);
        if (st.nv_sign == SIGN_BOTH) {
            P float without_v = gmul(gmul(gmul(att.m, djet.m, gd), fjet.m, gd), gjet.m, gd);
            view_kink[c] = gmul(0.25 * without_v, kink_slope, gd);
        }
    }
}

// The terms that can be non-zero for the scene's material kind, in term order.
int active_term_count() {
    return MATERIAL_KIND == MATERIAL_LAMBERT ? 5 : (MATERIAL_KIND == MATERIAL_BLINN_PHONG ? 7 : 10);
}
int active_term(int pass) {
    const int lambert[5] = int[5](T_NORMAL, T_LIGHT, T_DOT, T_ATTENUATION, T_CROSS);
    const int blinn_phong[7] = int[7](T_NORMAL, T_LIGHT, T_HALF, T_DOT, T_ATTENUATION, T_POWER, T_CROSS);
    const int ggx[10] = int[10](T_NORMAL, T_LIGHT, T_VIEW, T_HALF, T_DOT, T_ATTENUATION, T_D, T_F, T_V, T_CROSS);
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        return lambert[pass];
    }
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        return blinn_phong[pass];
    }
    return ggx[pass];
}
