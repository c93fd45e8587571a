// Levels that do not flip back and forth between the balls of eyes (Rust twin:
// `src/render/level_hold.rs`, which says why the bound holds; `tests/level_ball.rs` proves them
// equal). Where the pre-pass keeps levels and holds them (FLAG_HOLD_LEVELS), each estimate of a
// triangle passes through held_level before it is used. Levels are compared by their uniform
// pattern (per pixel above every pattern): an estimate of a finer or the same pattern is used at
// once, a finer one opening a hold; while a hold is open, a coarser estimate is used only once
// coarser ones have come hold_estimates(triangle) times in a row, and then the highest of them,
// which closes the hold; with no hold open, a coarser estimate is used at once.
#ifndef LEVEL_HOLD_GLSL
#define LEVEL_HOLD_GLSL
#include "bindings.glsl"

// Coarser estimates in a row before a held level falls: HOLD_ESTIMATES, plus the triangle's
// index modulo HOLD_STAGGER, so that the triangles a ball of eyes found coarser do not all
// change in the same frame (`HOLD_ESTIMATES`, `HOLD_STAGGER` in Rust).
const uint HOLD_ESTIMATES = 3u;
const uint HOLD_STAGGER = 3u;

uint hold_estimates(uint triangle) {
    return HOLD_ESTIMATES + triangle % HOLD_STAGGER;
}

// The uniform pattern a level asks for (`held_pattern` in Rust): 1 to n_max, n_max + 1 where it
// is shaded per pixel.
uint held_pattern(float level, uint n_max) {
    uint n = uniform_level(level, n_max);
    return n == 0u ? n_max + 1u : n;
}

// The level the frame uses for `triangle`, whose estimate for the frame's ball is `estimate`,
// and the triangle's hold state (level_holds) after it. Without FLAG_HOLD_LEVELS: the estimate.
float held_level(uint triangle, float estimate) {
    if ((draw.flags & FLAG_HOLD_LEVELS) == 0u) {
        return estimate;
    }
    uint n_max = clamp(draw.n_max, 1u, 64u);
    LevelHold hold = level_holds[triangle];
    uint now = held_pattern(estimate, n_max);
    uint held = held_pattern(hold.held, n_max);
    if (now > held) {
        hold = LevelHold(estimate, 0.0, 0u, 0u);
    } else if (now == held) {
        hold = LevelHold(estimate, 0.0, 0u, hold.closed);
    } else if (hold.closed != 0u) {
        hold.held = estimate;
    } else {
        hold.lower = max(hold.lower, estimate);
        hold.estimates += 1u;
        if (hold.estimates >= hold_estimates(triangle)) {
            hold = LevelHold(hold.lower, 0.0, 0u, 1u);
        }
    }
    level_holds[triangle] = hold;
    return hold.held;
}

#endif
