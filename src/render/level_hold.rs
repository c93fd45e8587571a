//! Levels that do not flip back and forth as the eye moves: the rule by which the pre-pass holds
//! a triangle's level between the balls of eyes (`level_ball`). Twin of
//! `glsl/include/level_hold.glsl`; `tests/level_ball.rs` proves the pre-pass follows it, level
//! for level, and `docs/estimator.md` §16 says why it keeps the bound.
//!
//! Each estimate of a triangle (the frames that begin a ball estimate every visible triangle,
//! the others those that come into view) passes through [`held_level`]: a level at or above the
//! one held is used at once, since the bound needs it; a lower one only once lower estimates have
//! come [`hold_estimates`] times in a row, and then the highest of them. A triangle's level thus
//! never falls in the frame after it rose, and the triangles a ball found coarser fall over a few
//! balls rather than all in one frame. Every level used is at least the estimate for the frame's
//! ball, and the error bound falls as the level rises, so every level used meets ε.

use crate::gpu_types::LevelHold;

/// Lower estimates in a row before a triangle's level falls, at the least.
pub const HOLD_ESTIMATES: u32 = 3;

/// The spread of [`hold_estimates`] over the triangles: triangle `t` waits `t % HOLD_STAGGER`
/// estimates more, so that those a ball found coarser do not all change in the same frame.
pub const HOLD_STAGGER: u32 = 3;

/// How many lower estimates in a row triangle `triangle` waits for before its level falls.
pub fn hold_estimates(triangle: u32) -> u32 {
    HOLD_ESTIMATES + triangle % HOLD_STAGGER
}

/// The level a frame uses for `triangle`, whose estimate for the frame's ball is `estimate`,
/// given its hold state `hold` (zeroed: nothing held), and its hold state after the frame.
pub fn held_level(triangle: u32, estimate: f32, hold: LevelHold) -> (f32, LevelHold) {
    let after = if estimate >= hold.held {
        LevelHold { held: estimate, ..LevelHold::default() }
    } else {
        let lower = hold.lower.max(estimate);
        let estimates = hold.estimates + 1;
        if estimates >= hold_estimates(triangle) {
            LevelHold { held: lower, ..LevelHold::default() }
        } else {
            LevelHold { lower, estimates, ..hold }
        }
    };
    (after.held, after)
}

#[cfg(test)]
mod tests;
