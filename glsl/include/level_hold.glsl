// Levels that do not flip back and forth between the balls of eyes (Rust twin:
// `src/render/level_hold.rs`; `tests/level_ball.rs` proves them equal). Where the pre-pass keeps
// levels and holds them (FLAG_HOLD_LEVELS), each estimate of a triangle passes through
// held_level before it is used: a level at or above the one held is used at once (the bound
// needs it); a lower one only once lower estimates have come hold_estimates(triangle) times in a
// row, and then the highest of them. Every level used is at least the triangle's estimate for
// the frame's ball, so it meets ε there (the error bound falls as the level rises).
#ifndef LEVEL_HOLD_GLSL
#define LEVEL_HOLD_GLSL
#include "bindings.glsl"

// Lower estimates in a row before a triangle's level falls: HOLD_ESTIMATES, plus the triangle's
// index modulo HOLD_STAGGER, so that the triangles a ball of eyes found coarser do not all
// change in the same frame (`HOLD_ESTIMATES`, `HOLD_STAGGER` in Rust).
const uint HOLD_ESTIMATES = 3u;
const uint HOLD_STAGGER = 3u;

uint hold_estimates(uint triangle) {
    return HOLD_ESTIMATES + triangle % HOLD_STAGGER;
}

// The level the frame uses for `triangle`, whose estimate for the frame's ball is `estimate`,
// and the triangle's hold state (level_holds) after it. Without FLAG_HOLD_LEVELS: the estimate.
float held_level(uint triangle, float estimate) {
    if ((draw.flags & FLAG_HOLD_LEVELS) == 0u) {
        return estimate;
    }
    LevelHold hold = level_holds[triangle];
    if (estimate >= hold.held) {
        hold = LevelHold(estimate, 0.0, 0u, 0u);
    } else {
        hold.lower = max(hold.lower, estimate);
        hold.estimates += 1u;
        if (hold.estimates >= hold_estimates(triangle)) {
            hold = LevelHold(hold.lower, 0.0, 0u, 0u);
        }
    }
    level_holds[triangle] = hold;
    return hold.held;
}

#endif
