//! The estimator's constants: the geometric ones (`K23`, `TILT_*`), the paddings that absorb
//! f32 rounding (`SAFETY`, `ANGLE_PAD`, `RADIAL_PAD`), the thresholds that decide what is worth
//! computing (`MIRROR_WORTH`, `HULL_WORTH`, `REFINE_*`, `UNIFORM_TINY`), and the sign of a cosine
//! over a triangle ([`Sign`]). The term ids and the reasons for fallback are the public
//! [`Term`] and [`Reason`].
//!
//! GLSL twin: `glsl/include/estimator/constants.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit). The GLSL side also holds the
//! specialization constants `SPLIT` and `DISCONTINUITY`, the term ids `T_*` and the reasons
//! `REASON_*`.
//!
//! [`Term`]: super::Term
//! [`Reason`]: super::Reason

use std::f32::consts::FRAC_PI_2;

/// 2/√3: the largest curvature of a normalised affine vector field, `|D²ŵ| ≤ (2/√3)|Dw|²/|w|²`.
pub(super) const K23: f32 = 1.154_700_5;
/// `Uniform` split: terms whose bounds stay below `ε·UNIFORM_TINY` are not counted in `M`;
/// they share a reserve of `16·ε·UNIFORM_TINY` (13 terms, the two Relaxed parts, the range),
/// so that bounds of ~10⁻³⁹, which GPUs flush to zero, cannot change `M` (and the level by
/// a factor `√((M+1)/M)`).
pub(super) const UNIFORM_TINY: f32 = 1.0 / 1_048_576.0;
/// Intermediate bounds above this mean fallback (keeps products of two bounds finite).
pub(super) const BIG: f32 = 1.0e18;
/// Multiplies every bound: f32 rounding in this estimator and in the shading. (The driver's
/// 16.16 fixed-point placement of the pattern vertices is in [`pattern_level`].)
///
/// [`pattern_level`]: super::patch_levels::pattern_level
pub(super) const SAFETY: f32 = 1.01;
/// Relaxed: where `g = max(f, 0)` has its kink inside a sub-triangle,
/// `−E_f ≤ Lg − g ≤ E_f + TERMINATOR_KINK·(max_k f(v_k) − min_k f(v_k))` (`E_f` the
/// interpolation bound of the smooth `f`); sharp for linear `f` with corner values
/// `(1, −1, −1)`. Derived in `docs/estimator.md` §4.
pub(super) const TERMINATOR_KINK: f32 = 0.25;
/// [`tilted`]: the largest `z⁵(12 − 15h²z²)` over `z ≤ 1` where `h² > 4/7` is `24/7·z*⁵`
/// (`z*² = 4/(7h²)`)...
///
/// [`tilted`]: super::irradiance::tilted
pub(super) const TILT_PEAK: f32 = 24.0 / 7.0;
/// ...and `s·max|G|` is `√7.2` for `s² ∈ [0.2, 0.8]` (rounded up).
pub(super) const TILT_FLAT: f32 = 2.683_281_7;
/// Radians added to every cone half-angle (f32 rounding of the directions).
pub(super) const ANGLE_PAD: f32 = 2.0e-6;
/// Radians by which the widest or nearest of several angles, chosen by their
/// [`pseudo_angle`]s, can miss the true one: the pseudo-angle grows at least ½ per radian and
/// two of them round by at most 2.4·10⁻⁷ each, so a wrong choice is under 10⁻⁶ from the right.
///
/// [`pseudo_angle`]: super::cone::pseudo_angle
pub(super) const CHOICE_PAD: f32 = 1.0e-6;
/// Relative rounding allowance of the normal's radial scale ([`Scale::g`]), per unit of
/// `max|Nₖ|·|Nδ|`.
///
/// [`Scale::g`]: super::pattern::Scale::g
pub(super) const RADIAL_PAD: f32 = 2.0e-6;
/// Radians: the narrowest cone of `ĥ` for which [`mirror_lower_angle`] is tried. The cones'
/// bound is within twice `ĥ`'s half-angle of the true smallest angle (`n̂` covers the spherical
/// triangle of the normals), so below this no bound can raise it by more than 0.1 rad.
///
/// [`mirror_lower_angle`]: super::cone::mirror_lower_angle
pub(super) const MIRROR_WORTH: f32 = 0.05;
/// Radians: the narrowest cone whose spherical triangle [`mirror_lower_angle`] measures
/// (below it the cone's distance is within this of the triangle's).
///
/// [`mirror_lower_angle`]: super::cone::mirror_lower_angle
pub(super) const HULL_WORTH: f32 = 0.03;
/// The share by which the slack a ball of eyes adds to `n·v` is grown, for its rounding
/// (`Frame::new`).
pub(super) const BALL_SLACK_PAD: f32 = 1.0e-4;
/// A cone wider than this is no bound at all (a cap wider than a hemisphere is not convex).
pub(super) const MAX_HALF: f32 = FRAC_PI_2 - 1.0e-4;

/// A triangle whose level is above this (fallbacks for the level included) is estimated a second
/// time with each light's ranges taken over the patch's [`REFINE_CHILDREN`] children
/// ([`values_over_children`]).
///
/// [`values_over_children`]: super::add_light::values_over_children
pub(super) const REFINE_ABOVE: f32 = 8.0;
/// The children a refined light takes its ranges over: the four of one midpoint subdivision
/// ([`midpoint_child`]). Two subdivisions (16 children) lowered the property test's evaluations
/// by another 2 % for four times the refining step's work (`docs/notebook/speedups.md` step 24).
///
/// [`midpoint_child`]: super::add_light::midpoint_child
pub(super) const REFINE_CHILDREN: usize = 4;
/// ...for the lights whose diffuse or specular range exceeds this share of `ε` in a channel.
pub(super) const REFINE_SHARE: f32 = 0.125;
/// Refining is skipped where the refining floor (`Sums::floor`, a lower bound on the bound at
/// every level up to the top of the estimate refined over the children) exceeds `ε` by this
/// factor: that estimate falls back as the first one did. The factor keeps the decision clear of
/// the solver's rounding.
pub(super) const REFINE_FLOOR_MARGIN: f32 = 1.01;
/// The corners' values that bound the children's values from below are shrunk by this share
/// (grown where they are subtracted), far more than their rounding.
pub(super) const CORNER_VALUE_MARGIN: f32 = 1.0e-3;

/// A light's specular part whose upper bound over the triangle (the range class's, without the
/// specular setup and jets) is within `ε·SPECULAR_CAP_SHARE / (number of lights)` is bounded by
/// that upper bound, a constant term (`add_light`): the lights' capped parts together take at
/// most this share of `ε`, so a level rises by at most `1/√(1 − share)` − 1 (1.6 %) where caps
/// reach it (`docs/notebook/speedups.md` step 35).
pub(super) const SPECULAR_CAP_SHARE: f32 = 0.03125;

/// Sign of a cosine over the whole triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Sign {
    Positive,
    NonPositive,
    Both,
}
