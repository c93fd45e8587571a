// One light's bounds added to the sums (add_light: light_bounds, then add_bounds_or_ranges with
// add_grid and add_to_sums), and its values over a patch's children (ChildValues,
// midpoint_child).
// Twin: `src/shading/estimator/add_light.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// The shaded diffuse part max(E' c, 0) per unit weight lies in [inf, sup] (`diffuse_values` in
// Rust): (sup, inf).
P vec2 diffuse_values(LightSetup setup, Jet diffuse) {
    P float att = setup.inv_d > 0.0 ? setup.inv_d * setup.inv_d : 1.0;
    P float inf = setup.att_inf * rmax(setup.nl_cos.y, 0.0) * (1.0 - 1.0e-5);
    P float sup = setup.area ? diffuse.m : rmin(diffuse.m, att * rmax(setup.nl_cos.x, 0.0));
    return vec2(sup, inf);
}

// Child k (0..3) of the midpoint subdivision of the triangle with corners c (`midpoint_child`).
void midpoint_child(inout vec3 c[3], int k) {
    P vec3 ab = (c[0] + c[1]) * 0.5;
    P vec3 bc = (c[1] + c[2]) * 0.5;
    P vec3 ca = (c[2] + c[0]) * 0.5;
    if (k == 0) {
        c[1] = ab;
        c[2] = ca;
    } else if (k == 1) {
        c[0] = ab;
        c[2] = bc;
    } else if (k == 2) {
        c[0] = ca;
        c[1] = bc;
    } else {
        c[0] = bc;
        c[1] = ca;
        c[2] = ab;
    }
}

vec3 rmax3(vec3 a, vec3 b) {
    return vec3(rmax(a.x, b.x), rmax(a.y, b.y), rmax(a.z, b.z));
}

// The values of a light's two parts per unit weight over the children of a patch (`ChildValues`
// in Rust), and whether every child could be bounded.
struct ChildValues {
    float diffuse_sup;
    float diffuse_inf;
    vec3 specular_sup;
    bool ok;
};

#ifdef CHILDREN_GIVEN
// Where the including stage took the children's turns itself (refine_levels.comp, the refining
// step, side by side in a workgroup): light `light`'s values over the patch's children, combined
// in the children's order as light_sums combines them, and whether a child's bound went bad.
// light_sums uses it for the first GIVEN_LIGHTS point and directional lights.
ChildValues given_child_values(int light, out bool bad);
#endif

// One light's bounds before they join the sums, its diffuse (_d) and specular (_s) part apart, at
// level 1 (1) and levels >= 2 (n): all terms in one pass, and for the Uniform split one more pass
// per term in h_d and h_s (terms that are zero for every light of this material are skipped:
// they add nothing). The locals of `add_light` in Rust.
struct LightBounds {
    vec3 h_d[2][TERM_COUNT];
    vec3 h_s[2][TERM_COUNT];
    vec3 tot_d1;
    vec3 tot_dn;
    vec3 tot_s1;
    vec3 tot_sn;
    vec3 lin1;
    vec3 linn;
    vec3 lin1_s;
    vec3 linn_s;
    vec3 range_d;
    vec3 range_s;
    vec3 spec_sup;
    vec2 later_diffuse;
    // Relaxed: how far n.l can be from 0 on a crossed sub-triangle, at level 1 and per 1/L.
    float band1;
    float bandn;
    // sup E' (1 for a directional light).
    float att;
    TerminatorBand terminator;
    // The weight of the diffuse part, and whether n.l may change sign inside the triangle.
    vec3 diff_w;
    bool straddle;
    // Whether the specular part is bounded by its cap (range_s) at every level.
    bool specular_capped;
};

// One light's bounds from its jets at level 1 and at levels >= 2 (the first half of `add_light`
// in Rust). `mode` ADD_VALUES: the jets' values join `values` instead, and VALUES_ADDED is
// returned; else REASON_NONE.
int light_bounds(Frame frame, GpuMaterial material, vec2 param, LightSetup setup, vec3 diff_w, vec3 spec_w,
                 int mode, inout ChildValues values, P out LightBounds bounds, inout Guard gd) {
    if (SPLIT == 0) {
        for (int t = 0; t < TERM_COUNT; ++t) {
            bounds.h_d[0][t] = vec3(0.0);
            bounds.h_d[1][t] = vec3(0.0);
            bounds.h_s[0][t] = vec3(0.0);
            bounds.h_s[1][t] = vec3(0.0);
        }
    }
    bounds.tot_d1 = vec3(0.0);
    bounds.tot_dn = vec3(0.0);
    bounds.tot_s1 = vec3(0.0);
    bounds.tot_sn = vec3(0.0);
    bounds.lin1 = vec3(0.0);
    bounds.linn = vec3(0.0);
    bounds.lin1_s = vec3(0.0);
    bounds.linn_s = vec3(0.0);
    bounds.range_d = vec3(0.0);
    bounds.range_s = vec3(0.0);
    bounds.spec_sup = vec3(0.0);
    bounds.later_diffuse = vec2(0.0);
    bounds.band1 = 0.0;
    bounds.bandn = 0.0;
    bounds.att = setup.inv_d > 0.0 ? setup.inv_d * setup.inv_d : 1.0;
    bounds.terminator = terminator_band(frame, setup, frame.dn);
    bounds.diff_w = diff_w;
    bounds.straddle = setup.straddle;
    bounds.specular_capped = false;
    if (setup.straddle) {
        bounds.band1 = gc(band_at(terminator_band(frame, setup, frame.d1), 1.0), gd);
        bounds.bandn = gc(band_per_level(bounds.terminator, 0.0), gd);
    }
    // Relaxed, GGX: the same for n.v where it may change sign (its kink in V).
    bool view_kink = MATERIAL_KIND == MATERIAL_GGX && !setup.area && setup.specular && setup.nv_sign == SIGN_BOTH;
    P float view1 = 0.0;
    P float viewn = 0.0;
    if (view_kink) {
        view1 = view_band(frame, frame.d1, gd);
        viewn = view_band(frame, frame.dn, gd);
    }
    // The jets at levels >= 2, and at level 1 those scaled by rho unless the Uniform split needs
    // each term or GGX's view kink takes another band (see Rust).
    bool derive_one = SPLIT == 1 && !view_kink;
    Jet diff_n;
    Jet spec_n[3];
    P vec3 kink_n;
    gd.term = T_ALL;
    // (A child's values take GGX's V at the band 0, where its value is 1/k, its sup.)
    light_jets(frame, material, param, setup, frame.sn, mode == ADD_VALUES ? 0.0 : rmin(view1, viewn), diff_n,
               spec_n, kink_n, gd);
    if (mode == ADD_VALUES) {
        P vec2 diffuse = diffuse_values(setup, diff_n);
        values.diffuse_sup = rmax(values.diffuse_sup, diffuse.x);
        values.diffuse_inf = rmin(values.diffuse_inf, diffuse.y);
        values.specular_sup = rmax3(values.specular_sup, vec3(spec_n[0].m, spec_n[1].m, spec_n[2].m));
        return VALUES_ADDED;
    }
    for (int level = 0; level < 2; ++level) {
        Scale s = level == 0 ? frame.s1 : frame.sn;
        P float view_at = level == 0 ? view1 : rmin(view1, viewn);
        Jet diff;
        Jet spec[3];
        P vec3 kink;
        if (SPLIT == 0) {
            for (int pass = 0; pass < active_term_count(); ++pass) {
                gd.term = active_term(pass);
                light_jets(frame, material, param, setup, s, view_at, diff, spec, kink, gd);
                P vec3 spec_h = vec3(spec[0].h, spec[1].h, spec[2].h);
                bounds.h_d[level][gd.term] = diff_w * (diff.h * (0.5 * SAFETY));
                bounds.h_s[level][gd.term] = spec_w * spec_h * (0.5 * SAFETY);
            }
        }
        gd.term = T_ALL;
        if (level == 1) {
            diff = diff_n;
            spec = spec_n;
            kink = kink_n;
        } else if (derive_one) {
            diff = scaled_jet(diff_n, frame.rho);
            spec[0] = scaled_jet(spec_n[0], frame.rho);
            spec[1] = scaled_jet(spec_n[1], frame.rho);
            spec[2] = scaled_jet(spec_n[2], frame.rho);
            kink = kink_n;
        } else {
            light_jets(frame, material, param, setup, s, view_at, diff, spec, kink, gd);
        }
        P vec3 spec_t = vec3(spec[0].h, spec[1].h, spec[2].h);
        if (level == 0) {
            bounds.tot_d1 = diff_w * (diff.h * (0.5 * SAFETY));
            bounds.tot_s1 = spec_w * spec_t * (0.5 * SAFETY);
        } else {
            bounds.tot_dn = diff_w * (diff.h * (0.5 * SAFETY));
            bounds.tot_sn = spec_w * spec_t * (0.5 * SAFETY);
        }
        // (The sups m do not depend on the pass.)
        P vec3 spec_m = vec3(spec[0].m, spec[1].m, spec[2].m);
        bounds.spec_sup = spec_m;
        // Each part lies in [inf, sup] and so does its interpolant, the shaded diffuse part in
        // [inf E' cos psi_max, sup E' max(cos psi_min, 0)] (see Rust).
        P vec2 diffuse = diffuse_values(setup, diff);
        bounds.later_diffuse = diffuse;
        bounds.range_d = diff_w * (rmax(diffuse.x - diffuse.y, 0.0) * SAFETY);
        bounds.range_s = spec_w * spec_m * SAFETY;
        if (setup.straddle && level == 1) {
            // Relaxed: the diffuse kink adds 1/4 sup E' osc(n.l) (see Rust).
            bounds.lin1 = diff_w * (TERMINATOR_KINK * SAFETY * gmul(bounds.att, bounds.band1, gd));
            bounds.linn = diff_w * (TERMINATOR_KINK * SAFETY * gmul(bounds.att, bounds.bandn, gd));
        }
        if (view_kink && level == 1) {
            // Relaxed: the view's kink adds 1/4 sup(specular without V) |V'(0)| osc(n.v).
            bounds.lin1_s = spec_w * (kink * (TERMINATOR_KINK * SAFETY * view1));
            bounds.linn_s = spec_w * (kink * (TERMINATOR_KINK * SAFETY * viewn));
        }
    }
    return REASON_NONE;
}

// Adds the light's bound at each uniform level of GRID_LEVELS up to n_max (the Heuristic split's
// grid, `LightBounds::add_grid` in Rust): per part and channel the smaller of its interpolation
// bound there and its range. `low`: the light's lower bound on the level; `zeron`: the
// n-independent specular parts from `low` on, `whole_lobe + other` below it.
void add_grid(LightBounds bounds, inout Sums sums, uint n_max, float low, vec3 zeron, vec3 whole_lobe, vec3 other) {
    for (int k = 0; k < GRID_LEVEL_COUNT; ++k) {
        if (GRID_LEVELS[k] > n_max) {
            break;
        }
        P float l = pattern_level(GRID_LEVELS[k], GRID_LEVELS[k]);
        // The jump at l: the one at `low` where l >= low, else the whole lobe (see Rust).
        P vec3 zero_l = l >= low ? zeron : whole_lobe + other;
        // The diffuse kink at l itself (valid below `low` too; at most att bandn, guarded).
        P vec3 kink_l = bounds.straddle
            ? bounds.diff_w * (TERMINATOR_KINK * SAFETY * (bounds.att * band_at(bounds.terminator, l)))
            : vec3(0.0);
        P vec3 part_d = rmin3(bounds.tot_dn / (l * l) + kink_l, bounds.range_d);
        P vec3 part_s = bounds.specular_capped
            ? bounds.range_s
            : rmin3(bounds.tot_sn / (l * l) + bounds.linn_s / l + zero_l, bounds.range_s);
        sums.grid[k] = sums.grid[k] + (part_d + part_s);
    }
}

// Adds the light's level-1 bound, and the parts the solver takes at its levels
// (`LightBounds::add_to_sums` in Rust): per part and channel its interpolation bound where
// `interp_d`/`interp_s` (per term for the Uniform split; `zero1`, `zeron`: the specular
// n-independent parts at level 1 and from the light's lower bound on), else its range.
void add_to_sums(LightBounds bounds, inout Sums sums, bvec3 interp_d, bvec3 interp_s, vec3 zero1, vec3 zeron) {
    const vec3 none = vec3(0.0);
    P vec3 one_s =
        bounds.specular_capped ? bounds.range_s : rmin3(bounds.tot_s1 + bounds.lin1_s + zero1, bounds.range_s);
    sums.one = sums.one + (rmin3(bounds.tot_d1 + bounds.lin1, bounds.range_d) + one_s);
    // Each part adds its interpolation bound or its range (diffuse first, as in Rust).
    sums.range = sums.range + mix(bounds.range_d, none, interp_d);
    sums.range = sums.range + mix(bounds.range_s, none, interp_s);
    sums.tn = sums.tn + mix(none, bounds.tot_dn, interp_d);
    sums.tn = sums.tn + mix(none, bounds.tot_sn, interp_s);
    sums.lin1 = sums.lin1 + mix(none, bounds.lin1, interp_d);
    sums.lin1 = sums.lin1 + mix(none, bounds.lin1_s, interp_s);
    sums.linn = sums.linn + mix(none, bounds.linn, interp_d);
    sums.linn = sums.linn + mix(none, bounds.linn_s, interp_s);
    sums.jumps1 = sums.jumps1 + mix(none, zero1, interp_s);
    sums.jumps = sums.jumps + mix(none, zeron, interp_s);
    if (SPLIT == 0) {
        for (int pass = 0; pass < active_term_count(); ++pass) {
            int t = active_term(pass);
            sums.h1[t] = sums.h1[t] + mix(none, bounds.h_d[0][t], interp_d);
            sums.h1[t] = sums.h1[t] + mix(none, bounds.h_s[0][t], interp_s);
            sums.hn[t] = sums.hn[t] + mix(none, bounds.h_d[1][t], interp_d);
            sums.hn[t] = sums.hn[t] + mix(none, bounds.h_s[1][t], interp_s);
        }
    }
}

// A point (`point`, at `position`) or directional light's parts per unit weight at the triangle's
// corners (`corner_values` in Rust): the diffuse part's largest and smallest, and the specular
// part at the corner of the largest n.h, Blinn-Phong's at the lowest shininess of the range (0 for
// GGX and Lambert, and where not `specular`).
P vec3 corner_values(Frame frame, vec2 param, bool point, vec3 position, bool specular) {
    P vec3 values = vec3(0.0, MAX_FINITE, 0.0);
    // The largest n.h of a corner the light is in front of, and its falloff.
    P float peak = -1.0;
    P float peak_falloff = 0.0;
    for (int i = 0; i < 3; ++i) {
        P vec3 l;
        P float falloff;
        if (point) {
            P vec3 to_light = position - frame.vertices[i];
            P float d2 = rmax(dot3(to_light, to_light), MIN_LIGHT_DISTANCE_SQUARED);
            l = to_light * (1.0 / sqrt(d2));
            falloff = 1.0 / d2;
        } else {
            l = unit(-position);
            falloff = 1.0;
        }
        P vec3 n = frame.unit_normals[i];
        P float n_dot_l = dot3(n, l);
        P float diffuse = falloff * rmax(n_dot_l, 0.0);
        values.x = rmax(values.x, diffuse);
        values.y = rmin(values.y, diffuse);
        if (MATERIAL_KIND == MATERIAL_BLINN_PHONG && specular && n_dot_l > 0.0) {
            P float n_dot_h = rmax(dot3(n, unit(l + frame.v_units[i])), 0.0);
            if (n_dot_h > peak) {
                peak = n_dot_h;
                peak_falloff = falloff;
            }
        }
    }
    if (MATERIAL_KIND == MATERIAL_BLINN_PHONG && specular && peak >= 0.0) {
        values.z = peak_falloff * est_pow(peak, param.x);
    }
    return values;
}

// One light's share of the refining floor (`light_floor` in Rust): per channel a lower bound on
// what it adds to the bound at every level up to `top` in the estimate refined over the children;
// `narrowed`: whether refining narrows its ranges, which its values at the corners then bound.
P vec3 light_floor(Frame frame, vec2 param, bool point, vec3 position, LightSetup setup, LightBounds bounds,
                   vec3 spec_w, vec3 other, float top, bool narrowed) {
    P vec3 range_d = bounds.range_d;
    P vec3 range_s = bounds.range_s;
    if (narrowed) {
        // (A capped specular part keeps its cap: SPECULAR_ALL_CAPPED folds its corners' values away.)
        P vec3 corners = corner_values(frame, param, point, position, !bounds.specular_capped);
        P float spread =
            rmax(corners.x * (1.0 - CORNER_VALUE_MARGIN) - corners.y * (1.0 + CORNER_VALUE_MARGIN), 0.0);
        range_d = rmin3(range_d, bounds.diff_w * (spread * SAFETY));
        if (!bounds.specular_capped) {
            P vec3 spec_sup = rmin3(bounds.spec_sup, vec3(corners.z * (1.0 - CORNER_VALUE_MARGIN)));
            range_s = rmin3(range_s, spec_w * spec_sup * SAFETY);
            other = spec_w * parameter_variation(param, setup, spec_sup);
        }
    }
    P vec3 second_d = rmin3(bounds.tot_d1, bounds.tot_dn / (top * top));
    P vec3 second_s = rmin3(bounds.tot_s1, bounds.tot_sn / (top * top));
    P vec3 part_s = bounds.specular_capped ? range_s : rmin3(range_s, second_s + other);
    return rmin3(range_d, second_d) + part_s;
}

// The light's parts added to the sums, from its bounds (the end of `add_light` in Rust): per
// part and channel the smaller of its interpolation bound and its range, the jumps of the specular
// lobe where n.l changes sign (Relaxed), the light's own lower bound `low` on the level, then the
// parts at the grid levels (add_grid) and at the solver's (add_to_sums). `other`: the specular
// part's n-independent term.
void add_bounds_or_ranges(P inout LightBounds bounds, LightSetup setup, vec2 param, vec3 diff_w, vec3 spec_w,
                          vec3 other, float top, uint n_max, float eps, inout Sums sums, inout Guard gd) {
    P vec3 spec_sup = bounds.spec_sup;
    P vec3 zero1 = terminator_jump(spec_w, spec_sup, param, setup, bounds.band1) + other;
    P vec3 zero_top = terminator_jump(spec_w, spec_sup, param, setup, bounds.bandn / top) + other;
    // Per part and channel: the smaller of the part's interpolation bound and its range
    // (`!(range <= bound)`, true for NaN, as in Rust).
    bvec3 interp_d = not(lessThanEqual(bounds.range_d, bounds.tot_dn / (top * top) + bounds.linn / top));
    bvec3 interp_s =
        not(lessThanEqual(bounds.range_s, bounds.tot_sn / (top * top) + bounds.linn_s / top + zero_top));
    if (bounds.specular_capped) {
        interp_s = bvec3(false);
    }
    // The jump at levels >= 2 at a lower bound of the final level (see Rust).
    P vec3 zero_inf = terminator_jump(spec_w, spec_sup, param, setup, 0.0) + other;
    const vec3 none = vec3(0.0);
    P vec3 a = mix(none, bounds.tot_dn, interp_d) + mix(none, bounds.tot_sn, interp_s);
    P vec3 z = mix(none, zero_inf, interp_s);
    // Relaxed: the same with the diffuse kink at its floor; the band's fixed point holds from
    // `low` on (see Rust).
    P vec3 floor_kink = setup.straddle
        ? diff_w * (TERMINATOR_KINK * SAFETY * gmul(bounds.att, band_floor(bounds.terminator, gd), gd))
        : vec3(0.0);
    P vec3 b = mix(none, floor_kink, interp_d) + mix(none, bounds.linn_s, interp_s);
    P float low = 1.0;
    for (int c = 0; c < 3; ++c) {
        if (interp_d[c] || interp_s[c]) {
            low = rmax(low, level_for(a[c], b[c], z[c], eps));
        }
    }
    if (setup.straddle) {
        bounds.bandn = rmin(bounds.bandn, gc(band_per_level(bounds.terminator, low), gd));
        bounds.linn = diff_w * (TERMINATOR_KINK * SAFETY * gmul(bounds.att, bounds.bandn, gd));
    }
    P vec3 zeron = terminator_jump(spec_w, spec_sup, param, setup, bounds.bandn / low) + other;
    if (SPLIT == 1) {
        P vec3 whole_lobe = setup.straddle && !setup.area && setup.specular ? spec_w * spec_sup * SAFETY : vec3(0.0);
        add_grid(bounds, sums, n_max, low, zeron, whole_lobe, other);
    }
    add_to_sums(bounds, sums, interp_d, interp_s, zero1, zeron);
}

// Adds one light's bounds to the sums; returns a fallback reason (REASON_NONE if none), as
// `add_light` in Rust. `polygon` >= 0: the polygonal light of that index (`position` and
// `radiance` unused); else `point`: a point light at `position`, or a directional light whose
// travel direction is `position`.
//
// `caps`: the triangle's spreads for the specular caps (`SpecularCaps` in Rust), ok only where
// every light's specular part is within its cap (range_bound): then each point or directional
// light's is bounded by its cap, without specular_setup.
//
// `mode` ADD_VALUES: `frame` is a child of a patch (`values_over_children` in Rust); its values
// join `values` and VALUES_ADDED is returned, or REASON_NONE where the light adds 0 on it, or the
// reason it cannot be bounded. ADD_REFINED: the patch's ranges take `values` where they hold.
//
// The steps that may fall back stay here, between the calls (where the light is: `light_source`
// in Rust; the checks of `diffuse_setup` and `specular_setup`): a helper that returned early would
// leave its outputs undefined on that path, and the optimiser would no longer fold them.
int add_light(Frame frame, GpuMaterial material, vec2 param, bool point, vec3 position,
              vec3 radiance, int polygon, float top, uint n_max, float eps, int mode, SpecularCaps caps,
              inout ChildValues values, inout Sums sums, inout Guard gd) {
    bool area = polygon >= 0;
    AreaGeometry geometry;
    GpuPolygonLight light;
    if (area) {
        light = polygon_lights[polygon];
        if (is_zero(light.radiance.rgb)) {
            return REASON_NONE;
        }
        int where_is = area_geometry(frame, light, geometry);
        if (where_is == 1) {
            return REASON_NONE;
        }
        if (where_is == 2) {
            return REASON_DISCONTINUITY;
        }
        if (!(geometry.d_min * geometry.d_min > MIN_D2_SAFE)) {
            return REASON_SINGULAR;
        }
        radiance = light.radiance.rgb * light.normal.w;
    }
    if (is_zero(radiance)) {
        return REASON_NONE;
    }
    vec3 diff_w;
    vec3 spec_w;
    light_weights(material, radiance, diff_w, spec_w);
    Cone l_cone;
    P float inv_d;
    P vec3 l_center;
    P vec3 l_vectors[3];
    // A point light's height over the plane, from below and from above.
    P vec2 heights = vec2(0.0);
    if (area) {
        l_cone = geometry.cone;
        inv_d = 1.0 / geometry.d_min;
        l_center = l_cone.axis;
    } else if (point) {
        l_vectors[0] = position - frame.vertices[0];
        l_vectors[1] = position - frame.vertices[1];
        l_vectors[2] = position - frame.vertices[2];
        l_cone = cone_of(l_vectors[0], l_vectors[1], l_vectors[2]);
        P float d_min = min_length(l_vectors[0], l_vectors[1], l_vectors[2], l_cone);
        // The falloff is clamped at d^2 = 1e-8: only smooth (and bounded) beyond it.
        if (!(d_min * d_min > MIN_D2_SAFE)) {
            if (is_zero(diff_w) && is_zero(spec_w)) {
                return REASON_NONE;
            }
            return REASON_SINGULAR;
        }
        // Every point of the triangle is at least its height and in-plane distance away.
        heights = height_of(frame, position);
        inv_d = 1.0 / rmax(d_min, distance_of(frame, position, heights.x));
        l_center = unit(position - frame.center);
    } else {
        P vec3 l = unit(-position);
        l_cone = Cone(l, 0.0);
        inv_d = 0.0;
        l_center = l;
        l_vectors = vec3[3](l, l, l);
    }
    if (is_zero(diff_w) && is_zero(spec_w)) {
        return REASON_NONE;
    }
    if (frame.r_n <= 0.0) {
        return REASON_SINGULAR;
    }
    int l_sign;
    P vec2 psi_nl = area ? cosine_range_of(frame, l_cone, geometry.q, geometry.w_max, geometry.d_min, l_sign)
                         : cosine_range(frame, l_cone, l_vectors, l_sign);
    if (l_sign == SIGN_NON_POSITIVE) {
        return REASON_NONE;
    }
    bool straddle = l_sign == SIGN_BOTH;
    if (straddle && DISCONTINUITY == 0) {
        return REASON_DISCONTINUITY;
    }
    LightSource source = LightSource(l_cone, inv_d, l_center, l_vectors, heights);
    LightSetup setup = diffuse_setup(frame, point, area, geometry.emitter, source, psi_nl, straddle);
    // caps.ok only where the range class found every light capped; SPECULAR_ALL_CAPPED makes it a
    // constant, so that the specular code folds away.
    bool capped = MATERIAL_KIND != MATERIAL_LAMBERT && (SPECULAR_ALL_CAPPED || caps.ok) && mode != ADD_VALUES && !area;
    P vec3 cap = vec3(0.0);
    if (capped) {
        bool bounded;
        cap = specular_cap(caps, material, param, point, position, radiance, frame.vertices[0], frame.vertices[1],
                           frame.vertices[2], bounded);
    }
    if (MATERIAL_KIND != MATERIAL_LAMBERT && !capped) {
        if (!(frame.e_min > 0.0)) {
            return REASON_SINGULAR;
        }
        P vec2 psi_lv = psi_range(l_cone, frame.v_cone);
        P float m_min = 2.0 * est_cos(0.5 * psi_lv.y);
        if (!(psi_lv.y < PI_MINUS_MILLI) || !(m_min > 0.0)) {
            return REASON_SINGULAR;
        }
        int kink = specular_setup(frame, param, point, source, psi_lv, m_min, setup);
        if (kink != REASON_NONE) {
            return kink;
        }
    }
    P LightBounds bounds;
    if (light_bounds(frame, material, param, setup, diff_w, spec_w, mode, values, bounds, gd) == VALUES_ADDED) {
        return VALUES_ADDED;
    }
    if (capped) {
        bounds.range_s = cap;
        bounds.specular_capped = true;
    }
    // A triangle that needs a high level: the parts' values over the children, where this
    // light's range is not small (see Rust).
    bool significant = rmax(max_el(bounds.range_d), max_el(bounds.range_s)) > REFINE_SHARE * eps;
    if (mode == ADD_REFINED && values.ok && !setup.area && significant) {
        P float diff_sup = rmin(bounds.later_diffuse.x, values.diffuse_sup);
        P float diff_inf = rmax(bounds.later_diffuse.y, values.diffuse_inf);
        bounds.range_d = diff_w * (rmax(diff_sup - diff_inf, 0.0) * SAFETY);
        if (!bounds.specular_capped) {
            bounds.spec_sup = rmin3(bounds.spec_sup, values.specular_sup);
            bounds.range_s = spec_w * bounds.spec_sup * SAFETY;
        }
    }
    P vec3 other;
    if (area) {
        // The sampled specular part: no interpolation bound, its range.
        other = polygon_specular_bound(material, param, setup, light, gd) * SAFETY;
        bounds.range_s = bounds.range_s + other;
    } else if (capped) {
        // The cap bounds the part for every parameter.
        other = vec3(0.0);
    } else {
        // A textured parameter: its variation over the range, an n-independent term.
        other = spec_w * parameter_variation(param, setup, bounds.spec_sup);
    }
    if (mode == ADD_BOUNDS) {
        sums.floor = sums.floor
            + light_floor(frame, param, point, position, setup, bounds, spec_w, other, top, !area && significant);
    }
    add_bounds_or_ranges(bounds, setup, param, diff_w, spec_w, other, top, n_max, eps, sums, gd);
    return REASON_NONE;
}
