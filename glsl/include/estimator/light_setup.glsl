// One light as seen from the triangle (LightSetup, LightSource, AreaGeometry,
// light_weights, and the steps of `plan_light` in Rust: diffuse_setup, specular_setup; the steps
// that may fall back are add_light's), and the sums the lights' bounds accumulate in (Sums,
// GRID_LEVELS).
// Twin: `src/shading/estimator/light_setup.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// See `LightSetup` in Rust.
struct LightSetup {
    float plane_sin;
    float near_sin;
    float inv_d;
    vec2 psi_nl;
    bool straddle;
    Cone h_cone;
    float m_min;
    vec2 psi_nh;
    vec2 psi_nv;
    int nv_sign;
    vec2 psi_lv;
    // A polygonal light, and the range of the emitter's angle (see `LightSetup` in Rust).
    bool area;
    vec2 emitter;
    // <= H/d_min (at most 1): the cosine of gamma where the light is nearest (see Rust).
    float near_cos;
    // >= H/d_min (at most 1; 1 without a plane), and <= inf E' over the triangle (see Rust).
    float far_cos;
    float att_inf;
    // The cosines at the ends of psi_nl.
    vec2 nl_cos;
    // Whether the specular fields were planned (specular_setup): the specular part is bounded by
    // its jets; else it has none or its cap bounds it.
    bool specular;
};

// Heuristic split: the uniform levels at which each light's parts are also bounded by the smaller
// of their interpolation bound and their range there (see `GRID_LEVELS` in Rust).
const int GRID_LEVEL_COUNT = 8;
const uint GRID_LEVELS[GRID_LEVEL_COUNT] = uint[](2u, 3u, 4u, 6u, 8u, 12u, 16u, 32u);

// Accumulated bounds (`Sums` in Rust, without `low`): per term and channel, levels 1 and >= 2
// (Uniform split only); all terms at levels >= 2 (tn); the Relaxed first-order terms (lin1, linn);
// the n-independent parts at levels >= 2 and at level 1 (jumps, jumps1); the parts bounded by
// their range (range); the level-1 bound (one); the Heuristic split's bound at the uniform levels
// of GRID_LEVELS (grid); and the refining floor (floor).
struct Sums {
    vec3 h1[TERM_COUNT];
    vec3 hn[TERM_COUNT];
    vec3 tn;
    vec3 lin1;
    vec3 linn;
    vec3 jumps;
    vec3 jumps1;
    vec3 range;
    vec3 one;
    vec3 grid[GRID_LEVEL_COUNT];
    vec3 floor;
};

// Where a polygonal light is as seen from the triangle (see `AreaGeometry` in Rust).
struct AreaGeometry {
    Cone cone;
    float d_min;
    vec2 q;
    float w_max;
    vec2 emitter;
};

// `area_geometry` in Rust: 0 with the geometry, 1 when the triangle is behind the emitter (it
// receives nothing), 2 when the emitter's plane cuts the triangle (a discontinuity).
int area_geometry(Frame frame, GpuPolygonLight light, out AreaGeometry g) {
    int count = light.info.x;
    P vec3 y0 = light.vertices[0].xyz;
    P vec3 normal = light.normal.xyz;
    P float side[3] = float[3](dot3(normal, frame.vertices[0] - y0), dot3(normal, frame.vertices[1] - y0),
                               dot3(normal, frame.vertices[2] - y0));
    if (side[0] <= 0.0 && side[1] <= 0.0 && side[2] <= 0.0) {
        return 1;
    }
    P float reach = 0.0;
    for (int k = 0; k < 3; ++k) {
        reach = rmax(reach, len(frame.vertices[k] - y0));
    }
    P float tol = 1.0e-5 * reach;
    if (!(side[0] > tol && side[1] > tol && side[2] > tol)) {
        return 2;
    }
    P vec3 light_centre = vec3(0.0);
    for (int j = 0; j < 8; ++j) {
        if (j < count) {
            light_centre = light_centre + light.vertices[j].xyz;
        }
    }
    light_centre = light_centre / float(count);
    P vec3 axis = unit(light_centre - frame.center);
    P float half_angle = 0.0;
    P float d_min = 3.4028235e38;
    P float w_max = 0.0;
    P float q_lo = 3.4028235e38;
    P float q_hi = -3.4028235e38;
    for (int j = 0; j < 8; ++j) {
        if (j < count) {
            P vec3 yj = light.vertices[j].xyz;
            P vec3 w[3] = vec3[3](yj - frame.vertices[0], yj - frame.vertices[1], yj - frame.vertices[2]);
            for (int k = 0; k < 3; ++k) {
                half_angle = rmax(half_angle, angle(axis, w[k]));
                d_min = rmin(d_min, dot3(w[k], axis));
                w_max = rmax(w_max, len(w[k]));
            }
            P vec2 q = bilinear_range(frame.normals, w);
            q_lo = rmin(q_lo, q.x);
            q_hi = rmax(q_hi, q.y);
        }
    }
    half_angle = half_angle + ANGLE_PAD;
    g.cone = (is_zero(axis) || !(half_angle < MAX_HALF)) ? no_cone() : Cone(axis, half_angle);
    if (g.cone.spread >= PI || !(d_min > 0.0)) {
        d_min = 0.0;
    }
    g.d_min = d_min;
    g.q = vec2(q_lo, q_hi);
    g.w_max = w_max;
    g.emitter = psi_range(Cone(-normal, 0.0), g.cone);
    return 0;
}

// Diffuse and specular colour weights of a light (see `weights`).
void light_weights(GpuMaterial m, vec3 radiance, out vec3 diff_w, out vec3 spec_w) {
    if (MATERIAL_KIND == MATERIAL_LAMBERT) {
        diff_w = radiance * m.diffuse.rgb;
        spec_w = vec3(0.0);
    } else if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        diff_w = radiance * m.diffuse.rgb;
        spec_w = radiance * m.specular.rgb;
    } else {
        diff_w = radiance * m.diffuse.rgb;
        spec_w = radiance;
    }
}



// Where a light is as seen from the triangle, before any bound on its shading: what add_light
// builds the LightSetup from (`LightSource` in Rust).
struct LightSource {
    // The cone of l over the triangle (a polygon's: of every direction from the triangle to it).
    Cone cone;
    // 1/d_min, 0 for a directional light.
    float inv_d;
    // l from the centre (a polygon's cone axis).
    vec3 center;
    // A point light's vectors from the corners; a directional light's direction three times.
    vec3 vectors[3];
    // A point light's height over the plane, from below and from above.
    vec2 heights;
};

// The LightSetup as far as the diffuse part needs it (`diffuse_setup` in Rust, its fallbacks
// taken by the caller): the range psi_nl of the angle between n and l, narrowed where a point
// light is near the plane, whether n.l changes sign (`straddle`), and the falloff's bounds. A
// polygonal light (`area`) sees its emitter at angles in `emitter`.
LightSetup diffuse_setup(Frame frame, bool point, bool area, vec2 emitter, LightSource source, vec2 psi_nl,
                         bool straddle) {
    Cone l_cone = source.cone;
    P float inv_d = source.inv_d;
    P vec3 l_vectors[3] = source.vectors;
    P vec2 heights = source.heights;
    P LightSetup setup;
    setup.plane_sin = 1.0;
    setup.near_sin = 1.0;
    setup.inv_d = inv_d;
    setup.psi_nl = psi_nl;
    setup.straddle = straddle;
    setup.h_cone = no_cone();
    setup.m_min = 0.0;
    setup.psi_nh = vec2(0.0, PI);
    setup.psi_nv = vec2(0.0, PI);
    setup.nv_sign = SIGN_BOTH;
    setup.psi_lv = vec2(0.0, PI);
    setup.area = area;
    setup.emitter = area ? emitter : vec2(0.0);
    setup.near_cos = 0.0;
    setup.far_cos = 1.0;
    if (area) {
        setup.att_inf = 0.0;
    } else if (point) {
        setup.att_inf = 1.0 / (rmax(rmax(len2(l_vectors[0]), len2(l_vectors[1])), len2(l_vectors[2])) * (1.0 + 2.0e-5));
    } else {
        setup.att_inf = 1.0;
    }
    if (inv_d > 0.0) {
        setup.plane_sin = plane_sin(l_cone, frame.plane);
        setup.near_sin = setup.plane_sin;
        if (point && !area && !is_zero(frame.plane)) {
            P float height = heights.x;
            P float q = rmin(height * inv_d, 1.0);
            setup.near_cos = q;
            setup.far_cos = rmin(heights.y * inv_d, 1.0);
            setup.near_sin = rmin(setup.plane_sin, sqrt(rmax(1.0 - q * q, 0.0)));
            // |n.l| <= H/d_min + nu: a light near the plane is seen at grazing angles (see Rust).
            P float grazing = (heights.y * inv_d + frame.n_plane_sin) * (1.0 + 1.0e-5) + 1.0e-6;
            if (grazing < 1.0) {
                P float lo = rmax(est_acos(grazing) - ANGLE_PAD, 0.0);
                P float p0 = rmax(setup.psi_nl.x, lo);
                setup.psi_nl = vec2(p0, rmax(rmin(setup.psi_nl.y, PI - lo), p0));
            }
        }
    }
    setup.nl_cos = vec2(est_cos(setup.psi_nl.x), est_cos(setup.psi_nl.y));
    setup.specular = false;
    return setup;
}

// The rest of the LightSetup for a specular material (`specular_setup` in Rust, the singular
// view and half vector ruled out by the caller): the cone of h and the ranges of the angles
// between n and h, n and v, l and v, from psi_lv and m_min (<= |l + v|). Returns
// REASON_DISCONTINUITY where a kink of the lobe cannot be bounded, else REASON_NONE.
int specular_setup(Frame frame, vec2 param, bool point, LightSource source, vec2 psi_lv, float m_min,
                   P inout LightSetup setup) {
    bool area = setup.area;
    bool straddle = setup.straddle;
    Cone l_cone = source.cone;
    P float inv_d = source.inv_d;
    P vec3 l_center = source.center;
    P vec3 l_vectors[3] = source.vectors;
    // A cone for h, the tighter of two (see Rust).
    P float speed = (inv_d + 1.0 / frame.e_min) / m_min;
    P float half_a = speed * frame.rho_x + ANGLE_PAD;
    P vec3 axis_a = unit(l_center + frame.v_center);
    P vec3 m0 = l_cone.axis + frame.v_cone.axis;
    P float delta = 2.0 * est_sin(0.5 * l_cone.spread) + 2.0 * est_sin(0.5 * frame.v_cone.spread);
    P float half_b = delta < len(m0) ? est_asin(delta / len(m0)) + ANGLE_PAD : PI;
    P vec3 h_axis;
    P float h_half;
    // (a) follows one light point and one eye; a polygon or a ball of eyes needs (b), which holds
    // for all of them.
    bool one_eye = frame.eye_radius <= 0.0;
    if (half_b < half_a || area || !one_eye) {
        h_axis = unit(m0);
        h_half = half_b;
    } else {
        h_axis = axis_a;
        h_half = half_a;
    }
    setup.h_cone = (is_zero(h_axis) || !(h_half < MAX_HALF)) ? no_cone() : Cone(h_axis, h_half);
    setup.specular = true;
    setup.m_min = m_min;
    setup.psi_lv = psi_lv;
    P vec2 c_nh = psi_range(frame.n_cone, setup.h_cone);
    if (setup.h_cone.spread < PI) {
        setup.psi_nh = vec2(
            rmax(c_nh.x, hull_distance(setup.h_cone.axis, frame.unit_normals) - setup.h_cone.spread),
            rmin(c_nh.y, hull_max_angle(setup.h_cone.axis, frame.unit_normals) + setup.h_cone.spread));
    } else {
        setup.psi_nh = c_nh;
    }
    P vec3 v_vectors[3] = frame.v_vectors;
    int nv_sign = frame.nv_sign;
    setup.psi_nv = frame.psi_nv;
    setup.nv_sign = nv_sign;
    // The same angle at the same point, from the mirror directions, where h's cone is wide
    // enough for it to matter (see Rust).
    if (!area && setup.h_cone.spread > MIRROR_WORTH) {
        P float lo = setup.psi_nh.x;
        if (nv_sign == SIGN_POSITIVE) {
            lo = mirror_lower_angle(frame.n_cone, frame.v_cone, l_cone, point, l_vectors, lo);
        }
        if (!straddle) {
            // The corners' vectors to the eye span v's directions for one eye only.
            lo = mirror_lower_angle(frame.n_cone, l_cone, frame.v_cone, one_eye, v_vectors, lo);
        }
        setup.psi_nh.x = rmin(lo, setup.psi_nh.y);
    }
    // The same angle from the interpolant of n - h at the corners (see Rust: narrowed), one eye's.
    if (!area && one_eye) {
        P vec3 h_units[3];
        for (int k = 0; k < 3; ++k) {
            P vec3 l_unit = point ? unit(l_vectors[k]) : l_vectors[k];
            h_units[k] = unit(l_unit + frame.v_units[k]);
        }
        P float n_w = frame.s1.b / frame.r_n;
        P float l_w = frame.s1.a * inv_d;
        P float v_w = frame.s1.a / frame.e_min;
        P float h_w = (l_w + v_w) / m_min;
        P float curvature = K23 * (n_w * n_w + h_w * h_w) + K23 * (l_w * l_w + v_w * v_w) / m_min;
        setup.psi_nh = narrowed(setup.psi_nh, frame.unit_normals, h_units, curvature);
    }
    // A polygon's sampled specular part is bounded by its range: kinks do not matter.
    if (area) {
    } else if (MATERIAL_KIND == MATERIAL_BLINN_PHONG) {
        // max(n.h, 0)^s is C^{1,1} across n.h = 0 only for s >= 2.
        if (setup.psi_nh.x < HALF_PI && setup.psi_nh.y >= HALF_PI && param.x < 2.0) {
            return REASON_DISCONTINUITY;
        }
    } else {
        // max(n.v, 0) has a kink in V at n.v = 0: bounded in Relaxed (see Rust).
        if (setup.nv_sign == SIGN_BOTH && DISCONTINUITY == 0) {
            return REASON_DISCONTINUITY;
        }
    }
    return REASON_NONE;
}
