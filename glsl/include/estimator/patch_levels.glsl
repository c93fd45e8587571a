// Shared edges and mixed patterns: the effective levels of the hardware patterns (pattern_level,
// uniform_level) and the level-combination rule (patch_levels).
// Twin: `src/shading/estimator/patch_levels.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// Estimate::level of a triangle that falls back to per-pixel shading.
const float FALLBACK_LEVEL = 1.0e6;

// The effective level of the hardware pattern with inner level `inner` and outer level
// `outer` on an edge: pattern_level_words (bindings.glsl), uploaded from Rust's
// `PATTERN_LEVELS`, in 1/256, two 16-bit entries per word, index (inner-1)*64 + (outer-1).

float pattern_level(uint inner, uint outer) {
    uint index = (clamp(inner, 1u, 64u) - 1u) * 64u + (clamp(outer, 1u, 64u) - 1u);
    uint word = pattern_level_words[index / 2u];
    uint q = (word >> (16u * (index % 2u))) & 0xffffu;
    return float(q) * (1.0 / 256.0);
}

// Above every effective level the table holds (16-bit entries in 1/256).
const float ABOVE_EVERY_PATTERN = 256.0;

// The smallest n in 1..n_max whose uniform pattern has effective level >= level; 0 if none. A
// level above ABOVE_EVERY_PATTERN (FALLBACK_LEVEL) gives 0 without searching.
uint uniform_level(float level, uint n_max) {
    if (level > ABOVE_EVERY_PATTERN) {
        return 0u;
    }
    uint top = clamp(n_max, 1u, 64u);
    for (uint n = 1u; n <= top; ++n) {
        if (pattern_level(n, n) >= level) {
            return n;
        }
    }
    return 0u;
}

struct PatchLevels {
    float inner;     // gl_TessLevelInner[0] (1 for fallback)
    vec3 outer;      // gl_TessLevelOuter[0..2]
    bool fallback;   // per-pixel shading (patch_level 0)
};

// What the level-recording variants write per triangle (bindings.glsl, level_records): the
// level it shades at (0: per-pixel fallback) and its outer levels; CULLED_RECORD if culled.
vec4 level_record(PatchLevels levels) {
    return vec4(levels.fallback ? 0.0 : ceil(levels.inner), ceil(levels.outer.x), ceil(levels.outer.y),
                ceil(levels.outer.z));
}

// The level-combination rule (`patch_levels` in Rust): edge k gets the larger of the two
// triangles' uniform levels (a fallback triangle asks for nothing; 1 if both fall back); the
// inner level is the smallest whose whole pattern, transition strips included, has
// effective level >= own; none, or own itself falls back: per-pixel shading, inner 1.
PatchLevels patch_levels(float own, vec3 neighbours, float n_max_value) {
    uint n_max = uint(clamp(n_max_value, 1.0, 64.0));
    uint own_n = uniform_level(own, n_max);
    uvec3 outer = uvec3(max(max(own_n, uniform_level(neighbours.x, n_max)), 1u),
                        max(max(own_n, uniform_level(neighbours.y, n_max)), 1u),
                        max(max(own_n, uniform_level(neighbours.z, n_max)), 1u));
    uint inner = 0u;
    if (own_n > 0u) {
        for (uint i = 1u; i <= n_max; ++i) {
            float l = min(min(pattern_level(i, outer.x), pattern_level(i, outer.y)),
                          pattern_level(i, outer.z));
            if (l >= own) {
                inner = i;
                break;
            }
        }
    }
    PatchLevels result;
    result.inner = float(max(inner, 1u));
    result.outer = vec3(outer);
    result.fallback = inner == 0u;
    return result;
}
