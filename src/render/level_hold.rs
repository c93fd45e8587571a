//! Levels that do not flip back and forth as the eye moves: the rule by which the pre-pass holds
//! a triangle's level between the balls of eyes (`level_ball`). Twin of
//! `glsl/include/level_hold.glsl`; `tests/level_ball.rs` proves the pre-pass follows it, level
//! for level.
//!
//! Each estimate of a triangle (the frames that begin a ball estimate every visible triangle,
//! the others those that come into view) passes through [`held_level`], which compares levels by
//! the uniform pattern they ask for ([`held_pattern`]; per pixel above every pattern):
//! - an estimate of a finer pattern than the one held is used at once, since the bound needs
//!   it, and opens a hold;
//! - one of the same pattern is used at once (the image keeps its pattern), and starts the count
//!   below again;
//! - while a hold is open, a coarser one is used only once coarser estimates have come
//!   [`hold_estimates`] times in a row, and then the highest of them, which closes the hold;
//! - with no hold open, a coarser one is used at once.
//!
//! So a level that rose does not fall back at the next ball, and a level that flips between two
//! patterns stays at the finer; a level that falls steadily (the camera moving away) falls as it
//! is estimated, after its first hold, so that holding costs little shading. The wait is staggered
//! over the triangles, so those a ball found coarser do not all change in the same frame.
//!
//! Every level used is at least the estimate for the frame's ball: an estimate used as it is; a
//! held level of a finer pattern than the estimate's is a higher level (a level's pattern grows
//! with it); a fall is to the highest of estimates that include this one. The error bound falls
//! as the level rises, so every level used meets ε.

use crate::gpu_types::LevelHold;
use crate::shading::estimator::uniform_level;

/// Coarser estimates in a row before a held level falls, at the least.
pub const HOLD_ESTIMATES: u32 = 3;

/// The spread of [`hold_estimates`] over the triangles: triangle `t` waits `t % HOLD_STAGGER`
/// estimates more, so that those a ball found coarser do not all change in the same frame.
pub const HOLD_STAGGER: u32 = 3;

/// How many coarser estimates in a row triangle `triangle` waits for before its held level falls.
pub fn hold_estimates(triangle: u32) -> u32 {
    HOLD_ESTIMATES + triangle % HOLD_STAGGER
}

/// The uniform pattern `level` asks for with `n_max`: `1..=n_max`, `n_max + 1` where it is
/// shaded per pixel.
pub fn held_pattern(level: f32, n_max: u32) -> u32 {
    match uniform_level(level, n_max) {
        0 => n_max + 1,
        n => n,
    }
}

/// The level a frame with `n_max` uses for `triangle`, whose estimate for the frame's ball is
/// `estimate`, given its hold state `hold` (zeroed: nothing held), and its hold state after.
pub fn held_level(triangle: u32, estimate: f32, hold: LevelHold, n_max: u32) -> (f32, LevelHold) {
    let n_max = n_max.clamp(1, 64);
    let (now, held) = (held_pattern(estimate, n_max), held_pattern(hold.held, n_max));
    let used = |held, closed| LevelHold { held, lower: 0.0, estimates: 0, closed };
    let after = if now > held {
        used(estimate, 0)
    } else if now == held {
        used(estimate, hold.closed)
    } else if hold.closed != 0 {
        LevelHold { held: estimate, ..hold }
    } else {
        let lower = hold.lower.max(estimate);
        let estimates = hold.estimates + 1;
        if estimates >= hold_estimates(triangle) {
            used(lower, 1)
        } else {
            LevelHold { lower, estimates, ..hold }
        }
    };
    (after.held, after)
}

#[cfg(test)]
mod tests;
