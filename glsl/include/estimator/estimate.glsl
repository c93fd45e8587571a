// The estimate of one triangle: every light's bounds summed (light_sums), the level decided
// (estimate_pass, as `estimate_textured` in Rust) and again over the children where it asks for
// it (required_level).
// Twin: `src/shading/estimator/estimate.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

int worse(int a, int b) {
    return b > a ? b : a;
}

// Every light's bounds summed over the triangle in `frame` into `sums` (`light_sums` in Rust): the
// reason to fall back (REASON_NONE if none); with `every_capped` (the range class's), each light's
// specular part bounded by its cap; with `refine`, each point or directional light's ranges over
// the patch's REFINE_CHILDREN children. The lights that reach none of the triangle by its
// visibility `classes` (shadowed_in) add nothing.
int light_sums(Frame frame, GpuMaterial material, vec2 param, float eps, uint n_max, float top, bool every_capped,
               bool refine, uint classes, out Sums sums) {
    Guard gd = FRESH_GUARD;
    if (SPLIT == 0) {
        for (int t = 0; t < TERM_COUNT; ++t) {
            sums.h1[t] = vec3(0.0);
            sums.hn[t] = vec3(0.0);
        }
    }
    sums.tn = vec3(0.0);
    sums.lin1 = vec3(0.0);
    sums.linn = vec3(0.0);
    sums.jumps = vec3(0.0);
    sums.jumps1 = vec3(0.0);
    sums.range = vec3(0.0);
    sums.one = vec3(0.0);
    sums.floor = vec3(0.0);
    if (SPLIT == 1) {
        for (int k = 0; k < GRID_LEVEL_COUNT; ++k) {
            sums.grid[k] = vec3(0.0);
        }
    }
    int reason = REASON_NONE;
    // Point lights first, then directional ones (the buffer's order, and the twin's). With
    // `refine`, each light takes REFINE_CHILDREN + 1 turns: its children first (their values
    // only, under their own guard), then the patch. One loop and one call site: a second call
    // would inline the whole estimator twice, and a loop over the children inside the loop over
    // the lights made the estimator step twice as slow on lavapipe even where `refine` is a
    // constant false (docs/notebook/speedups.md, step 20); every branch tests `refine` first, so that
    // there the children's code folds away.
    // The polygonal lights take the last turns, one each, through the same call site (-1 where
    // the variant has none, so that their code folds away).
    int turns = refine ? REFINE_CHILDREN + 1 : 1;
    int light_turns = (POINT_LIGHT_COUNT + DIRECTIONAL_LIGHT_COUNT) * turns;
    ChildValues values = ChildValues(0.0, MAX_FINITE, vec3(0.0), true);
    // Every light's specular part capped (the range class's `every_capped`): their spreads.
    SpecularCaps caps = NO_SPECULAR_CAPS;
    if (every_capped || SPECULAR_ALL_CAPPED) {
        caps = specular_caps(frame);
    }
    bool saved_bad = gd.bad;
    for (int turn = 0; turn < light_turns + POLYGON_LIGHT_COUNT; ++turn) {
        int polygon = POLYGON_LIGHT_COUNT > 0 && turn >= light_turns ? turn - light_turns : -1;
        int i = refine ? turn / (REFINE_CHILDREN + 1) : turn;
        int r = refine ? turn % (REFINE_CHILDREN + 1) : REFINE_CHILDREN;
        GpuLight light = GpuLight(vec4(0.0), vec4(0.0), ivec4(-1, 0, 0, 0));
        if (polygon < 0) {
            if (shadowed_in(i, classes)) {
                continue;
            }
            light = lights[i];
        }
        Frame at = frame;
        int mode = ADD_BOUNDS;
        if (polygon >= 0) {
            values = ChildValues(0.0, 0.0, vec3(0.0), false);
        } else if (refine && r < REFINE_CHILDREN) {
#ifdef CHILDREN_GIVEN
            if (i < GIVEN_LIGHTS) {
                continue;
            }
#endif
            if (r == 0) {
                values = ChildValues(0.0, MAX_FINITE, vec3(0.0), true);
                saved_bad = gd.bad;
                gd.bad = false;
            }
            vec3 q[3] = frame.vertices;
            midpoint_child(q, r);
            vec3 m[3] = frame.normals;
            midpoint_child(m, r);
            at = make_frame(q[0], q[1], q[2], m[0], m[1], m[2], vec4(frame.eye, frame.eye_radius));
            mode = ADD_VALUES;
        } else if (refine) {
#ifdef CHILDREN_GIVEN
            if (i < GIVEN_LIGHTS) {
                saved_bad = gd.bad;
                values = given_child_values(i, gd.bad);
            }
#endif
            values.ok = values.ok && !gd.bad;
            gd.bad = saved_bad;
            mode = ADD_REFINED;
        }
        int added = add_light(at, material, param, polygon < 0 && i < POINT_LIGHT_COUNT, light.position.xyz,
                              light.radiance.rgb, polygon, top, n_max, eps, mode, caps, values, sums, gd);
        if (mode != ADD_VALUES) {
            reason = worse(reason, added);
        } else if (added == REASON_NONE) {
            values.diffuse_inf = 0.0;
        } else if (added != VALUES_ADDED) {
            values.ok = false;
        }
    }
    if (gd.bad) {
        reason = worse(reason, REASON_SINGULAR);
    }
    return reason;
}

// Whether the estimate refined over the children must fall back, as its refining floor
// (sums.floor) exceeds eps at every level up to the top (`refining_futile` in Rust). The
// Heuristic split only.
bool refining_futile(Sums sums, float eps) {
    return SPLIT == 1 && max_el(sums.floor) > eps * REFINE_FLOOR_MARGIN;
}

// One estimate of the triangle (p0, p1, p2) with vertex normals n0, n1, n2 seen from `eye`:
// >= 1, or FALLBACK_LEVEL when it must be shaded per pixel; never NaN. With `refine`, each light's
// ranges are taken over the triangle's children. `refine_next`: whether this estimate (without
// `refine`) is one that Rust estimates again with it: its `Estimate::level` (FALLBACK_LEVEL above
// n_max) exceeds REFINE_ABOVE (`!(<=)`: true for NaN, as Rust's fallback level). `every_capped`:
// the range class's (settled_by_range). The level holds for every eye within eye_ball.w of
// eye_ball.xyz. `classes`: the triangle's visibility classes (estimated_classes).
float estimate_pass(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec4 eye_ball, uint material_index,
                    vec2 param, float epsilon, float n_max_value, bool every_capped, bool refine, uint classes,
                    out bool refine_next) {
    uint n_max = uint(clamp(n_max_value, 1.0, 64.0));
    P float eps = epsilon > 0.0 ? epsilon : 0.0;
    P float top = pattern_level(n_max, n_max);
    GpuMaterial material = materials[material_index];
    Frame frame = make_frame(p0, p1, p2, n0, n1, n2, eye_ball);
    Sums sums;
    int reason = light_sums(frame, material, param, eps, n_max, top, every_capped, refine, classes, sums);
    P float level = reason == REASON_NONE ? decide(sums, eps, n_max) : FALLBACK_LEVEL;
    // Not where refining cannot keep the triangle from falling back.
    bool futile = refining_futile(sums, eps);
    refine_next = !refine && reason == REASON_NONE && (!(level <= REFINE_ABOVE) || !(level <= top)) && !futile;
    // false for NaN and infinity
    if (reason != REASON_NONE || !(level <= top)) {
        return FALLBACK_LEVEL;
    }
    return level;
}

// Estimate::level of the triangle: estimate_pass, and again with `refine` where it asks for it.
// One call site in a loop: a second one would inline the whole estimator twice.
float required_level(vec3 p0, vec3 p1, vec3 p2, vec3 n0, vec3 n1, vec3 n2, vec4 eye_ball,
                     uint material_index, vec2 param, float epsilon, float n_max_value, bool every_capped,
                     uint classes) {
    P float level = 0.0;
    bool again = false;
    for (int pass = 0; pass < 2; ++pass) {
        level = estimate_pass(p0, p1, p2, n0, n1, n2, eye_ball, material_index, param, epsilon, n_max_value,
                              every_capped, pass == 1, classes, again);
        if (!again) {
            break;
        }
    }
    return level;
}
