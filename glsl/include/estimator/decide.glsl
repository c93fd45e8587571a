// The level the sums ask for (decide, level_for).
// Twin: `src/shading/estimator/decide.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// Smallest real n > 0 with a/n^2 + b/n + c <= eps (infinity if none).
P float level_for(float a, float b, float c, float eps) {
    if (a <= 0.0 && b <= 0.0) {
        return c <= eps ? 0.0 : infinity();
    }
    P float room = eps - c;
    if (!(room > 0.0)) {
        return infinity();
    }
    P float n = (b + sqrt(b * b + 4.0 * a * room)) / (2.0 * room);
    return is_nan(n) ? infinity() : n;
}

// The level the sums ask for (`decide` in Rust, the fallback reasons already taken): one_ok (the
// level-1 bound holds) and need (the smallest effective level), and with the Heuristic split the
// lowest grid level whose bound holds.
float decide(Sums sums, float eps, uint n_max) {
    P vec3 an = sums.tn;
    P vec3 zero = sums.jumps + sums.range;
    bool relaxed_on = max_el(sums.linn) > 0.0 || max_el(sums.jumps) > 0.0;
    bool one_ok;
    P float need = 0.0;
    if (SPLIT == 1) {
        for (int c = 0; c < 3; ++c) {
            need = rmax(need, level_for(an[c], sums.linn[c], zero[c], eps));
        }
        one_ok = max_el(sums.one) <= eps;
    } else {
        // M counts the terms above eps * UNIFORM_TINY; the others share a reserve.
        P float tiny = eps * UNIFORM_TINY;
        uint count = 0u;
        for (int t = 0; t < TERM_COUNT; ++t) {
            if (max_el(sums.hn[t]) > tiny || max_el(sums.h1[t]) > tiny) {
                count += 1u;
            }
        }
        if (max_el(sums.linn) > tiny || max_el(sums.jumps) > tiny || max_el(sums.jumps1) > tiny) {
            count += 1u;
        }
        if (max_el(sums.range) > tiny) {
            count += 1u;
        }
        P float share = eps * (1.0 - 16.0 * UNIFORM_TINY) / float(max(count, 1u));
        one_ok = max_el(sums.lin1 + sums.jumps1) <= share && max_el(sums.range) <= share;
        for (int t = 0; t < TERM_COUNT; ++t) {
            one_ok = one_ok && max_el(sums.h1[t]) <= share;
            for (int c = 0; c < 3; ++c) {
                need = rmax(need, level_for(sums.hn[t][c], 0.0, 0.0, share));
            }
        }
        if (relaxed_on) {
            for (int c = 0; c < 3; ++c) {
                need = rmax(need, level_for(0.0, sums.linn[c], sums.jumps[c], share));
            }
        }
        if (max_el(sums.range) > share) {
            need = infinity();
        }
    }
    P float level = one_ok ? 1.0 : rmax(need, 1.0);
    // Heuristic: the lowest grid level whose bound holds (see `decide` in Rust).
    if (SPLIT == 1 && !one_ok) {
        for (int k = 0; k < GRID_LEVEL_COUNT; ++k) {
            uint n = GRID_LEVELS[k];
            if (n > n_max) {
                break;
            }
            if (max_el(sums.grid[k]) <= eps) {
                level = rmin(level, pattern_level(n, n));
                break;
            }
        }
    }
    return level;
}
