//! The per-triangle error estimator: the Rust twin of the tessellation control shader.
//!
//! | Rust file | GLSL file | test proving them equal |
//! |-----------|-----------|-------------------------|
//! | `src/exact_math.rs` | `exact_math.glsl` | `control_stage_levels_equal_the_twin` |
//! | `mod.rs` | `estimator.glsl` | `control_stage_levels_equal_the_twin` |
//! | `constants.rs` | `estimator/constants.glsl` | `control_stage_levels_equal_the_twin` |
//! | `terms.rs` | `estimator/terms.glsl` | `control_stage_levels_equal_the_twin` |
//! | `estimate.rs` | `estimator/estimate.glsl` | `control_stage_levels_equal_the_twin` |
//! | `jet.rs` | `estimator/jet.glsl` | `control_stage_levels_equal_the_twin` |
//! | `cone.rs` | `estimator/cone.glsl` | `control_stage_levels_equal_the_twin` |
//! | `pattern.rs` | `estimator/pattern.glsl` | `control_stage_levels_equal_the_twin` |
//! | `frame.rs` | `estimator/frame.glsl` | `control_stage_levels_equal_the_twin` |
//! | `irradiance.rs` | `estimator/irradiance.glsl` | `control_stage_levels_equal_the_twin` |
//! | `lobe.rs` | `estimator/lobe.glsl` | `control_stage_levels_equal_the_twin` |
//! | `terminator.rs` | `estimator/terminator.glsl` | `control_stage_levels_equal_the_twin` |
//! | `light_setup.rs` | `estimator/light_setup.glsl` | `control_stage_levels_equal_the_twin` |
//! | `add_light.rs` | `estimator/add_light.glsl` | `control_stage_levels_equal_the_twin` |
//! | `decide.rs` | `estimator/decide.glsl` | `control_stage_levels_equal_the_twin` |
//! | `patch_levels.rs` | `estimator/patch_levels.glsl` | `control_stage_levels_equal_the_twin` |
//! | `range.rs` | `estimator/range.glsl` | `control_stage_levels_equal_the_twin` |
//! | `pattern_table.rs` | uploaded as `pattern_level_words` (`bindings.glsl`) | `pattern_level_table_is_current` |
//! | `tests/` | — | (the Rust side's own unit tests, one file per topic) |
//!
//! Rust files are under `src/shading/estimator/` unless named otherwise, GLSL files under
//! `glsl/include/`. `control_stage_levels_equal_the_twin` is in `tests/multirate.rs`: on every
//! triangle of the shipped scenes, the levels the GPU's control stage and compute pre-pass
//! record equal this twin's, bit for bit. `estimator.glsl` includes the GLSL files in
//! dependency order.
//!
//! For one triangle, its lights and its material, [`estimate`] returns the real-valued
//! level [`Estimate::level`] the triangle needs: every hardware tessellation pattern whose
//! effective level ([`pattern_level`]) is at least that keeps the L∞ error of linearly
//! interpolated sub-vertex shading below `ε` in *every colour channel*; also the smallest
//! uniform level `n` (inner = outer = `n`, `equal_spacing`) that does, or a request for
//! per-pixel fallback. [`patch_levels`] is the rule that turns a triangle's and its three
//! neighbours' levels into the crack-free levels the control stage writes. The derivation,
//! every deviation from the paper (Hu et al. 2022 and its supplement) and the measured figures
//! are in `docs/estimator.md`; the brute-force truth it is tested against is
//! [`crate::analysis::oracle`]. `glsl/include/estimator.glsl` is the GPU port, operation for
//! operation (bit-identical results, tested on lavapipe).
//!
//! # The bound in one paragraph
//!
//! Write the shading as `f(λ)` over the triangle's barycentric domain. Inside a
//! sub-triangle with corners `vₖ` and local barycentrics `μ`, Taylor's theorem with the
//! integral remainder gives `|f(x) − Σμₖ f(vₖ)| ≤ ½ Σ μₖ |D²f[vₖ − x]|`. Every second
//! derivative this module bounds has the form `P(|Xδ|, |Nδ|)`, a quadratic polynomial with
//! non-negative coefficients in the lengths of the position and normal displacements that
//! a domain step `δ` causes (`X`, `N`: the 3×2 maps from the domain to positions and to
//! interpolated normals). By Cauchy–Schwarz, `Σμₖ P(|Xδₖ|, |Nδₖ|) ≤ P(√Q_X, √Q_N)` with
//! `Q_W = max_x Σμₖ|W(vₖ − x)|²`, the squared radius of the smallest enclosing circle of the
//! sub-triangle's image under `W`. For the hardware pattern at level `n` every sub-triangle
//! is a translate of `±1/n` times one of seven fixed shapes (the ring quads and corners of
//! `equal_spacing`, and the patch itself), so `Q_W = K_W / n²` with `K_W` computed here
//! from the triangle ([`pattern_constants`]). So the whole estimator is "jet arithmetic":
//! every factor of the shading carries (sup |value|, bound on the first derivative, bound
//! on the second derivative), all evaluated at the pattern scale `(√K_X, √K_N)`, combined
//! with the product and chain rules, and the error at level `n` is `½ H / n²`.
//!
//! The per-triangle path does not allocate and has no data-dependent loops besides the
//! one over lights; it is written in f32 with saturating guards so that no input produces
//! NaN or an infinite level (an overflowing bound means fallback, never a smaller `n`).
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`settings`]: the estimator's settings.
//! 2. [`constants`]: the constants: geometric ones, paddings, thresholds.
//! 3. [`terms`]: one triangle's input, the estimate, its terms and fallback reasons.
//! 4. [`pattern_table`]: the effective level of every hardware pattern, generated.
//! 5. [`patch_levels`]: shared edges and mixed patterns: a patch's crack-free levels.
//! 6. [`pattern`]: the hardware pattern's sub-triangle shapes and their constants.
//! 7. [`jet`]: jet arithmetic: a factor's value and derivative bounds.
//! 8. [`cone`]: cones of directions and the angle ranges they give.
//! 9. [`frame`]: the scale-free quantities of one triangle.
//! 10. [`light_setup`]: what one light looks like from the triangle, and the sums of the bounds.
//! 11. [`lobe`]: the BRDF factors' jets.
//! 12. [`irradiance`]: one light's jets at one pattern scale.
//! 13. [`terminator`]: relaxed discontinuity bounds across the terminator.
//! 14. [`range`]: the range class: triangles whose shading provably varies by at most ε.
//! 15. [`decide`]: from the summed bounds to the level, or per-pixel fallback.
//! 16. [`add_light`]: one light's bounds added to the sums.
//! 17. [`estimate`]: the entry points and the loop over the lights.

// `!(x > y)` is used on purpose throughout: it is also true for NaN, which must mean "no bound".
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

mod add_light;
mod cone;
mod constants;
mod decide;
mod estimate;
mod frame;
mod irradiance;
mod jet;
mod light_setup;
mod lobe;
mod patch_levels;
mod pattern;
mod pattern_table;
mod range;
mod settings;
mod terminator;
mod terms;

pub use estimate::{estimate, estimate_textured};
pub use patch_levels::{
    patch_levels, pattern_level, pattern_level_entry, uniform_level, PatchLevels, FALLBACK_LEVEL,
};
pub use pattern::{pattern_constants, PatternConstants, SHAPES};
pub use pattern_table::PATTERN_LEVELS;
pub use range::settled_by_range;
pub use settings::{Discontinuity, EstimatorSettings, Split};
pub use terms::{Estimate, Reason, Term, TriangleInput, TERM_COUNT, TERM_NAMES};

#[cfg(test)]
mod tests;
