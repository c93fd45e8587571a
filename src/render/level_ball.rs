//! Levels kept while the eye stays in a ball. Lights and meshes do not move, so a triangle's
//! level depends on the camera only through the eye, and the estimator can bound the shading
//! for every eye within `EstimatorSettings::eye_radius` of the one it is given
//! (`docs/estimator.md` §16). The frame that begins a ball estimates its visible triangles for
//! the ball around its eye and keeps their levels (`estimated_levels`); the frames whose eye is
//! still in the ball reuse them, and estimate only the triangles that come into view, for a
//! ball around their own eye wide enough to hold the first. A frame whose eye has left the ball,
//! or whose settings differ, begins a new one.

use super::multirate_config::MultirateConfig;
use glam::Vec3;

/// The ball the kept levels hold for: every eye within `key.estimator.eye_radius` of `centre`,
/// in the multirate configuration `key` (the estimator's settings, the radius among them, the
/// target's size and the resolved area below which triangles are shaded per pixel).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LevelBall {
    centre: Vec3,
    key: MultirateConfig,
}

/// How one frame's pre-pass uses the ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum BallUse {
    /// No ball (a radius of 0): every visible triangle is estimated for the frame's eye alone.
    Off,
    /// A ball begins at the frame's eye: the kept levels are cleared, and every visible triangle
    /// is estimated for the ball.
    Begin { radius: f32 },
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
            BallUse::Begin { radius } | BallUse::Continue { radius } | BallUse::Detached { radius } => radius,
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
    let radius = key.estimator.eye_radius;
    // Also no ball for NaN.
    if radius.is_nan() || radius <= 0.0 {
        return (BallUse::Off, None);
    }
    if let Some(ball) = ball {
        let off = ball.centre.distance(eye);
        if ball.key == key && off <= radius {
            // Every eye within `radius` of the centre is within `radius + off` of this one.
            return (BallUse::Continue { radius: (radius + off) * (1.0 + RADIUS_PAD) }, Some(ball));
        }
    }
    (BallUse::Begin { radius }, Some(LevelBall { centre: eye, key }))
}

#[cfg(test)]
mod tests;
