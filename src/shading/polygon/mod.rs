//! Polygonal area lights seen from one shading point: clipping to the horizon, the closed-form
//! projected solid angle, projected-solid-angle sampling, solid-angle sampling of triangle fans,
//! clamped optimal MIS weights and a fixed low-discrepancy point set. This is the CPU reference of
//! the GLSL twin `glsl/include/polygon.glsl`, which follows it file for file and function for
//! function (so everything here is f32, works on fixed-size arrays with a vertex count, allocates
//! nothing, never recurses and loops only over fixed bounds); `tests/polygon_gpu.rs` checks that
//! the two agree. The twin emulates `mul_add` and `atan2`, which GLSL does not guarantee to the
//! accuracy used here.
//!
//! # Parts
//!
//! Each file here has a twin of the same name in `glsl/include/polygon/`, which `polygon.glsl`
//! includes in this order:
//!
//! | file | holds |
//! |------|-------|
//! | `types.rs` | the constants, [`Polygon`], [`ProjectedSolidAngleSampler`], [`SolidAngleSampler`] |
//! | `arithmetic.rs` | Kahan's `a·b − c·d`, a stable cross product, `det2`, `mix`, `unit_difference` |
//! | `clip.rs` | [`clip_to_horizon`] |
//! | `closed_form.rs` | [`projected_solid_angle`], [`projected_to_solid_angle_density`] |
//! | `ellipse.rs` | Algorithms 1–3: the edges' ellipses and sampling between two of them |
//! | `projected_sampling.rs` | Algorithm 4: [`prepare_projected_solid_angle`] and its sampling |
//! | `solid_angle_sampling.rs` | Algorithm 5: [`prepare_solid_angle`], [`sample_solid_angle`] |
//! | `mis.rs` | [`clamped_optimal_mis_weights`], [`sample_point`] |
//!
//! All directions live in the local shading frame: the shading normal is +z, and a polygon is
//! given by its vertices relative to the shading point (convex, planar, at most
//! [`MAX_POLYGON_VERTICES`] vertices, either winding; emission is treated as two-sided).
//!
//! The methods are those of C. Peters, "BRDF Importance Sampling for Polygonal Lights" (ACM TOG
//! 40(4), 2021) and its supplemental document:
//! - A.1: [`clip_to_horizon`] (a plain fixed-bound clipper instead of the generated switch; new
//!   vertices from 2×2 determinants by Kahan's algorithm, accurate also next to the shading
//!   point).
//! - A.2: great circles through the zenith (degenerate ellipses, `u.x = ∞`, zero sector area,
//!   degenerate-first tie break in the sort).
//! - A.3/A.4 and Algorithms 1–4: [`prepare_projected_solid_angle`],
//!   [`sample_projected_solid_angle`] (an odd-even transposition sort replaces the optimal
//!   bitonic sorting networks of A.6, which only exist up to eight vertices).
//! - B.3: [`clamped_optimal_mis_weights`].
//! - C and Algorithm 5: [`prepare_solid_angle`], [`sample_solid_angle`] with the Householder
//!   determinant.
//!
//! Three deliberate deviations, all for accuracy with lights that are small as seen from the
//! shading point (the tests cover polygons 10⁻⁴ wide at distance 1):
//! - [`projected_solid_angle`] evaluates Lambert's edge sum `½ Σ γⱼ n̂ⱼ·z` as "shoelace of the
//!   unit vertex directions + per-edge segment terms `(γ/sin γ − 1)(v̂ⱼ × v̂ⱼ₊₁)·z`", with the
//!   differences of unit directions formed without cancellation. The plain sum loses about
//!   `ε / size` relative accuracy. Sampling densities are normalised by this value; the per-
//!   sector areas of Algorithm 4 only select a sector.
//! - Algorithm 3 solves its homogeneous quadratics in a basis rotated onto the sector boundary
//!   (initialisation) or the current direction (iteration). In xy-coordinates the quadratic form
//!   of the initialisation is tiny (∝ size²) next to its entries (∝ 1) and thin sectors sample
//!   outside the polygon; rotated, its small coefficients are products and stay accurate.
//! - The determinant of Algorithm 5 is the Householder one of Sec. C applied to the columns
//!   `v̂ⱼ − v̂₀` (same determinant), which removes the remaining `ε / size` error of normalising;
//!   its `t' = √((1 − s²)/(1 − s₂²))` is evaluated as `√(ξ₁ (1 + s)/(1 + s₂))`.
//!
//! What remains: the per-sector areas of the ellipse representation carry a relative error of
//! about `ε / size`, so for a polygon 10⁻⁴ wide samples are uniform to about 10⁻³ (still inside);
//! and since z is rebuilt from xy, directions near the horizon are accurate to about `ε / z`. In
//! the decentral case a sector bounded by an edge whose great circle passes within rounding of the
//! zenith (|u| > 10³, A.2 up to rounding) is too thin to sample in f32 (the ray from the zenith
//! meets that great circle at a grazing angle); such sectors get no area, like the exactly
//! degenerate ones of rule 2, which leaves out a sliver of relative size of order 1/|u| (the
//! density stays normalised by the closed form, so diffuse estimates are unaffected). If rounding
//! swamps every sector area, sectors are selected by angle (see [`prepare_projected_solid_angle`]).
//! A sweep over 10⁶ random polygons (the distribution of the test `random_polygons_sample_inside`,
//! 2.6·10⁷ samples) found no sample farther outside than 2·10⁻⁶ + 4ε/z radians.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`arithmetic`]: cancellation-free arithmetic helpers.
//! 2. [`types`]: the module's constants and plain data.
//! 3. [`clip`]: clipping a polygon to the horizon.
//! 4. [`closed_form`]: the closed-form projected solid angle.
//! 5. [`ellipse`]: the ellipses the edges project to, and their sector areas.
//! 6. [`mis`]: clamped optimal MIS weights and the fixed point set.
//! 7. [`projected_sampling`]: projected-solid-angle sampling.
//! 8. [`solid_angle_sampling`]: solid-angle sampling of the triangle fan.

#![allow(clippy::needless_range_loop)] // index loops with fixed bounds mirror the GLSL twin

mod arithmetic;
mod clip;
mod closed_form;
mod ellipse;
mod mis;
mod projected_sampling;
mod solid_angle_sampling;
mod types;

pub use clip::clip_to_horizon;
pub use closed_form::{projected_solid_angle, projected_to_solid_angle_density};
pub use mis::{clamped_optimal_mis_weights, sample_point};
pub use projected_sampling::{
    prepare_projected_solid_angle, projected_solid_angle_density, sample_projected_solid_angle,
};
pub use solid_angle_sampling::{prepare_solid_angle, sample_solid_angle, solid_angle_density};
pub use types::{
    Polygon, ProjectedSolidAngleSampler, SolidAngleSampler, DEFAULT_MIS_VISIBILITY, MAX_CLIPPED_VERTICES,
    MAX_POLYGON_VERTICES,
};

#[cfg(test)]
mod tests;
