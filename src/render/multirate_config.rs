//! [`MultirateConfig`]: the multirate configuration of a frame, resolved once per frame. It is
//! what the frame guard's times hold for (`guard`), what the kept levels hold for
//! (`level_ball`) and what selects the multirate pipelines (`pipelines`, `pre_pass`): one
//! description of "the same configuration" for all three.

use super::mode::Placement;
use crate::shading::estimator::{Discontinuity, EstimatorSettings, Split};

/// Where the estimator runs, its settings with the image area below which a triangle is shaded
/// per pixel without an estimate resolved (`EstimatorSettings::min_estimated_area`: the cost
/// model's where the view asks for it), the target's size, and whether the pre-pass holds
/// levels (`View::hold_levels`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultirateConfig {
    pub placement: Placement,
    pub estimator: EstimatorSettings,
    pub extent: (u32, u32),
    pub hold_levels: bool,
}

impl MultirateConfig {
    /// The values of the specialization constants `SPLIT` and `DISCONTINUITY`, which select
    /// the estimator's pipelines.
    pub fn estimator_ids(&self) -> (i32, i32) {
        (split_id(self.estimator.split), discontinuity_id(self.estimator.discontinuity))
    }

    /// The configuration as the frame guard compares frames: the ball of eyes aside, since its
    /// radius follows the camera's distance, and the camera is not part of what the guard
    /// weighs.
    pub fn without_eye(&self) -> MultirateConfig {
        MultirateConfig { estimator: EstimatorSettings { eye_radius: 0.0, ..self.estimator }, ..*self }
    }
}

/// The value of `spec::SPLIT` for `split`.
fn split_id(split: Split) -> i32 {
    match split {
        Split::Uniform => 0,
        Split::Heuristic => 1,
    }
}

/// The value of `spec::DISCONTINUITY` for `discontinuity`.
fn discontinuity_id(discontinuity: Discontinuity) -> i32 {
    match discontinuity {
        Discontinuity::Conservative => 0,
        Discontinuity::Relaxed => 1,
    }
}
