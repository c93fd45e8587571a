//! The estimator's settings ([`EstimatorSettings`]: ε, n_max, how ε is [`Split`] between the
//! error terms, what the terminator's [`Discontinuity`] does, the smallest estimated image and
//! the ball of eyes), defaulted from the scene layer's one default per setting.

use crate::scene::settings::{DEFAULT_EPSILON, DEFAULT_N_MAX};

/// How `ε` is shared between the error terms.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Split {
    /// The paper's Sec. 3: every term that is not zero gets `ε / M` (`M` such terms); the
    /// level is the largest any term asks for.
    Uniform,
    /// The paper's Sec. 4.2: shares proportional to the terms' bounds, which for terms that
    /// all fall as `1/n²` is the same as requiring the sum of the bounds to be `≤ ε`.
    Heuristic,
}

/// What to do where `max(n·l, 0)` (the terminator) may cut through the triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Discontinuity {
    /// The paper's solution (1): fall back to per-pixel shading.
    Conservative,
    /// The default: keep tessellating, with a bound that stays valid across the kink. The
    /// diffuse `max(E'c, 0)` adds a first-order term `¼·sup E'·sup|∇c|·diam/L` (sharp), the
    /// specular lobe that `n·l > 0` switches on adds its sup over the band
    /// `0 < n·l ≤ sup|∇c|·diam/L` where the terminator-crossed sub-triangles lie. See the docs.
    Relaxed,
}

/// Settings of the estimator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EstimatorSettings {
    /// L∞ bound on the interpolation error, linear radiance, per colour channel.
    pub epsilon: f32,
    /// Largest level before per-pixel fallback (clamped to `1..=64`).
    pub n_max: u32,
    pub split: Split,
    pub discontinuity: Discontinuity,
    /// Triangles whose image covers fewer pixels than this are shaded per pixel without an
    /// estimate, where estimating costs more than it can save (`geometry::cull::small_image`;
    /// `render::cost_model` chooses it per device and scene). 0: every visible triangle is
    /// estimated.
    pub min_estimated_area: f32,
    /// The estimate holds for every eye within this distance of the triangle's eye
    /// (`TriangleInput::eye`), not only for that one (0): the renderer keeps levels while the
    /// camera stays in such a ball (`docs/estimator.md` §16).
    pub eye_radius: f32,
}

impl Default for EstimatorSettings {
    fn default() -> Self {
        EstimatorSettings {
            epsilon: DEFAULT_EPSILON,
            n_max: DEFAULT_N_MAX,
            split: Split::Heuristic,
            discontinuity: Discontinuity::Relaxed,
            min_estimated_area: 0.0,
            eye_radius: 0.0,
        }
    }
}
