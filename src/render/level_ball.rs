//! Levels kept while the eye stays in a ball. Lights and meshes do not move, so a triangle's
//! level depends on the camera only through the eye, and the estimator can bound the shading
//! for every eye within `EstimatorSettings::eye_radius` of the one it is given
//! (`docs/estimator.md` §16). The frame that begins a ball estimates its visible triangles for
//! the ball around its eye and keeps their levels (`estimated_levels`); the frames whose eye is
//! still in the ball reuse them, and estimate only the triangles that come into view, for a
//! ball around their own eye wide enough to hold the first. A frame whose eye has left the ball,
//! or whose settings differ, begins a new one.
//!
//! The configured radius is the least: a ball that begins while the eye moves is wide enough to
//! hold the eye's next [`FRAMES_AHEAD`] steps of the size of its latest one (at most
//! [`MOST_WIDENED`] times the configured radius), so that a moving camera estimates once every
//! few frames rather than every frame. An eye that stays still for [`STILL_FRAMES`] frames in a
//! widened ball begins a ball of the configured radius, whose levels are lower.

use super::multirate_config::MultirateConfig;
use glam::Vec3;

/// The ball the kept levels hold for: every eye within `radius` of `centre`, in the multirate
/// configuration `key` (the estimator's settings, the target's size and the resolved area below
/// which triangles are shaded per pixel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LevelBall {
    centre: Vec3,
    radius: f32,
    /// The eye of the latest frame in the ball, and how many frames before it had the same eye.
    latest_eye: Vec3,
    still_frames: u32,
    key: MultirateConfig,
}

/// How many steps of the eye, each as long as its latest, a ball that begins holds.
pub const FRAMES_AHEAD: f32 = 3.0;

/// How many frames in a row at the eye of the one before a widened ball lets pass before it
/// narrows to the configured radius: one such frame may be a repeat (a redraw, a frame measured
/// again), a second is a camera that stopped.
pub const STILL_FRAMES: u32 = 2;

/// The widest ball, as a multiple of the configured radius (`EstimatorSettings::eye_radius`):
/// the levels of a wider ball are higher (docs/estimator.md §16).
pub const MOST_WIDENED: f32 = 6.0;

/// How one frame's pre-pass uses the ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum BallUse {
    /// No ball (a radius of 0): every visible triangle is estimated for the frame's eye alone.
    Off,
    /// A ball begins at the frame's eye: the kept levels are cleared, and every visible triangle
    /// is estimated for the ball. `fresh`: no ball of the same configuration came before (the
    /// first ball, or the settings changed), so the levels held (`level_hold`) are cleared too.
    Begin { radius: f32, fresh: bool },
    /// The eye is still in the ball: the kept levels are reused, and the triangles without one
    /// are estimated for every eye within `radius` of the frame's, which holds the whole ball.
    Continue { radius: f32 },
    /// A frame that commits nothing (analysis, counting, level records) where a ball would
    /// begin: every visible triangle is estimated for the ball around its eye, and the levels
    /// kept for the committed ball are neither cleared, read nor replaced.
    Detached { radius: f32 },
}

impl LevelBall {
    /// The eye the ball is centred on.
    pub(super) fn centre(&self) -> Vec3 {
        self.centre
    }
}

impl BallUse {
    /// The radius the frame's estimates hold for around its eye.
    pub(super) fn radius(self) -> f32 {
        match self {
            BallUse::Off => 0.0,
            BallUse::Begin { radius, .. } | BallUse::Continue { radius } | BallUse::Detached { radius } => {
                radius
            }
        }
    }

    /// Whether the frame reuses and keeps levels.
    pub(super) fn keeps_levels(self) -> bool {
        matches!(self, BallUse::Begin { .. } | BallUse::Continue { .. })
    }
}

/// Relative growth of a continuing frame's radius, far above its rounding, so that its ball
/// holds the first one.
const RADIUS_PAD: f32 = 1.0e-5;

/// How a frame with `eye` and `key` uses `ball` (the one the kept levels hold for, if any), and
/// the ball that holds after it.
pub(super) fn next(ball: Option<LevelBall>, eye: Vec3, key: MultirateConfig) -> (BallUse, Option<LevelBall>) {
    let least = key.estimator.eye_radius;
    // Also no ball for NaN.
    if least.is_nan() || least <= 0.0 {
        return (BallUse::Off, None);
    }
    // The configured radius is left out of the comparison: the camera's distance to its target,
    // which it is a share of, moves by a rounding error as the camera turns about the target. A
    // ball narrower than it, though, does not serve.
    let same_settings = ball.filter(|ball| ball.key.without_eye() == key.without_eye());
    let fresh = same_settings.is_none();
    let ball = same_settings.filter(|ball| ball.radius >= least);
    // The eye's latest step (0 where it begins the configuration's first ball).
    let step = ball.map_or(0.0, |ball| ball.latest_eye.distance(eye));
    if let Some(ball) = ball {
        let off = ball.centre.distance(eye);
        let still_frames = if step == 0.0 { ball.still_frames + 1 } else { 0 };
        let stopped_in_widened = still_frames >= STILL_FRAMES && ball.radius > least;
        if off <= ball.radius && !stopped_in_widened {
            // Every eye within `ball.radius` of the centre is within `ball.radius + off` of this one.
            let radius = (ball.radius + off) * (1.0 + RADIUS_PAD);
            return (BallUse::Continue { radius }, Some(LevelBall { latest_eye: eye, still_frames, ..ball }));
        }
    }
    let ahead = FRAMES_AHEAD * step;
    let radius = if ahead.is_finite() { ahead.clamp(least, MOST_WIDENED * least) } else { least };
    (
        BallUse::Begin { radius, fresh },
        Some(LevelBall { centre: eye, radius, latest_eye: eye, still_frames: 0, key }),
    )
}

#[cfg(test)]
mod tests;
