//! The per-triangle error estimator: the Rust twin of the tessellation control shader.
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

// `!(x > y)` is used on purpose throughout: it is also true for NaN, which must mean "no bound".
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::needless_range_loop)]

use crate::scene::{Light, MaterialKind, PolygonLight, PolygonSampling};
use crate::shading::brdf::{ggx_alpha, ggx_d, MIN_LIGHT_DISTANCE_SQUARED};
use glam::Vec3;
use std::cell::Cell;
use std::f32::consts::{FRAC_2_PI, FRAC_PI_2, FRAC_PI_4, LN_2, LOG2_E, PI, SQRT_2};

/// One patch as the TCS sees it: world-space corner positions and (not necessarily unit)
/// vertex normals, and the eye.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleInput {
    pub positions: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub eye: Vec3,
}

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
}

impl Default for EstimatorSettings {
    fn default() -> Self {
        EstimatorSettings {
            epsilon: 0.075,
            n_max: 16,
            split: Split::Heuristic,
            discontinuity: Discontinuity::Relaxed,
        }
    }
}

/// Why an estimate asks for per-pixel fallback.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reason {
    /// No fallback.
    None,
    /// The bound needs a level above `n_max` (or `ε` is not positive and the shading varies).
    Level,
    /// A clamp of the shading formula may switch inside the triangle (`n·l`, and in both
    /// modes `n·v` for GGX and `n·h` for Blinn-Phong with shininess below 2).
    Discontinuity,
    /// The shading is not smooth or not bounded on the triangle: the interpolated normal can
    /// vanish (opposite or 120°-apart normals), a point light touches the triangle (the
    /// `max(d², 10⁻⁸)` clamp), `l + v` can vanish, or a bound overflowed f32.
    Singular,
}

/// Number of error terms in [`Estimate::terms`].
pub const TERM_COUNT: usize = 13;

/// The error terms. Each second-derivative contribution is booked under the term that
/// produced it; products of two factors' first derivatives are booked under `Cross`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Term {
    /// Curvature of `n̂ = N/|N|`, the normalisation of the interpolated normal.
    Normal = 0,
    /// Curvature of `l̂ = (p − x)/|p − x|`; in a point light's diffuse part, the whole
    /// irradiance field `I = (p − x)/|p − x|³` seen by the normal (`n̂·D²I`).
    Light = 1,
    /// Curvature of `v̂ = (e − x)/|e − x|`.
    View = 2,
    /// Curvature of `ĥ = (l̂ + v̂)/|l̂ + v̂|` and of `v·h = |l̂ + v̂|/2`.
    Half = 3,
    /// The bilinear term `2 Dâ·Db̂` of a cosine `â·b̂` (the paper's Eq. 22); for a point
    /// light's diffuse part `2 Dn̂·DI`.
    Dot = 4,
    /// The second derivative of the point-light falloff `1/d²` (specular parts and polygons;
    /// a point light's diffuse part bounds it within the irradiance field, under `Light`).
    Attenuation = 5,
    /// Blinn-Phong's `t^s`: `s(s−1)t^(s−2)(Dt)²`.
    Power = 6,
    /// GGX distribution `D(n·h)`: `D''(Dt)²`.
    D = 7,
    /// Schlick Fresnel `F(v·h)`: `F''(Dt)²`.
    F = 8,
    /// Smith visibility with the cosines folded in, `(n·l)V`: `G''(Dt)²` of both halves.
    V = 9,
    /// Product-rule cross terms `2 Dfᵢ·Dfⱼ ∏ fₖ` between factors (the paper's error
    /// propagation, Eq. 31–33, leaves these out).
    Cross = 10,
    /// `Relaxed` only: the first- and zero-order terms at the terminator `n·l = 0`.
    Terminator = 11,
    /// Lights' diffuse or specular parts whose whole range `[0, sup]` bounds their error
    /// better than the interpolation bound does even at `n_max` (dim or very spiky lights, a
    /// faint lobe): a constant term.
    Range = 12,
}

/// Names of the terms, indexed like [`Estimate::terms`].
pub const TERM_NAMES: [&str; TERM_COUNT] = [
    "normal",
    "light",
    "view",
    "half",
    "dot",
    "attenuation",
    "power",
    "D",
    "F",
    "V",
    "cross",
    "terminator",
    "range",
];

/// What [`estimate`] returns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Per term (see [`Term`], [`TERM_NAMES`]): the real-valued level that term alone would
    /// need if it had the whole budget `ε` (largest channel). With `Heuristic` the
    /// second-order terms combine as `n = ⌈√(Σ nₜ²)⌉`; with `Uniform` as
    /// `n = ⌈√M · max nₜ⌉`. Finite, `≥ 0`; `f32::MAX` stands for "no level suffices".
    pub terms: [f32; TERM_COUNT],
    /// The real-valued level the triangle needs: every hardware pattern whose effective
    /// level ([`pattern_level`]) is at least this keeps the error under `ε`. `1` when the
    /// level-1 bound holds (any pattern will then do), otherwise the smallest `L` with
    /// `bound(L) ≤ ε` for sub-triangles of radius² `K/L²` (never below 1). Exactly
    /// [`FALLBACK_LEVEL`] when `fallback` is set. Never NaN. This is what the control
    /// stage computes for a triangle and each of its neighbours ([`patch_levels`]).
    pub level: f32,
    /// The uniform level (inner = outer = `n`) for this triangle alone: the smallest `n` in
    /// `1..=n_max` with `pattern_level(n, n) ≥ level`. When `fallback` is set this is 1.
    /// Shared edges may raise the outer levels; [`patch_levels`] gives what is drawn.
    pub n: u32,
    /// Per-pixel fallback: the level would exceed `n_max`, or a discontinuity or
    /// singularity was detected.
    pub fallback: bool,
    /// Why `fallback` is set (`Reason::None` when it is not).
    pub reason: Reason,
    /// The bound on the per-channel L∞ error on the uniform pattern at level `n` (at
    /// `n_max` when the level is the reason for fallback; `f32::MAX` for discontinuities and
    /// singularities).
    pub predicted_error: f32,
}

impl Estimate {
    /// `(name, level)` pairs of [`Estimate::terms`].
    pub fn named_terms(&self) -> impl Iterator<Item = (&'static str, f32)> + '_ {
        TERM_NAMES.iter().copied().zip(self.terms.iter().copied())
    }

    /// The value of one term.
    pub fn term(&self, term: Term) -> f32 {
        self.terms[term as usize]
    }
}

/// 2/√3: the largest curvature of a normalised affine vector field, `|D²ŵ| ≤ (2/√3)|Dw|²/|w|²`.
const K23: f32 = 1.154_700_5;
/// `Uniform` split: terms whose bounds stay below `ε·UNIFORM_TINY` are not counted in `M`;
/// they share a reserve of `16·ε·UNIFORM_TINY` (13 terms, the two Relaxed parts, the range),
/// so that bounds of ~10⁻³⁹, which GPUs flush to zero, cannot change `M` (and the level by
/// a factor `√((M+1)/M)`).
const UNIFORM_TINY: f32 = 1.0 / 1_048_576.0;
/// Intermediate bounds above this mean fallback (keeps products of two bounds finite).
const BIG: f32 = 1.0e18;
/// Multiplies every bound: f32 rounding in this estimator and in the shading. (The driver's
/// 16.16 fixed-point placement of the pattern vertices is in [`pattern_level`].)
const SAFETY: f32 = 1.01;
/// Relaxed: where `g = max(f, 0)` has its kink inside a sub-triangle,
/// `−E_f ≤ Lg − g ≤ E_f + TERMINATOR_KINK·(max_k f(v_k) − min_k f(v_k))` (`E_f` the
/// interpolation bound of the smooth `f`); sharp for linear `f` with corner values
/// `(1, −1, −1)`. Derived in `docs/estimator.md` §4.
const TERMINATOR_KINK: f32 = 0.25;
/// [`tilted`]: the largest `z⁵(12 − 15h²z²)` over `z ≤ 1` where `h² > 4/7` is `24/7·z*⁵`
/// (`z*² = 4/(7h²)`)...
const TILT_PEAK: f32 = 24.0 / 7.0;
/// ...and `s·max|G|` is `√7.2` for `s² ∈ [0.2, 0.8]` (rounded up).
const TILT_FLAT: f32 = 2.683_281_7;
/// Radians added to every cone half-angle (f32 rounding of the directions).
const ANGLE_PAD: f32 = 2.0e-6;
/// Relative rounding allowance of the normal's radial scale ([`Scale::g`]), per unit of
/// `max|Nₖ|·|Nδ|`.
const RADIAL_PAD: f32 = 2.0e-6;
/// Radians: the narrowest cone of `ĥ` for which [`mirror_lower_angle`] is tried. The cones'
/// bound is within twice `ĥ`'s half-angle of the true smallest angle (`n̂` covers the spherical
/// triangle of the normals), so below this no bound can raise it by more than 0.1 rad.
const MIRROR_WORTH: f32 = 0.05;
/// Radians: the narrowest cone whose spherical triangle [`mirror_lower_angle`] measures
/// (below it the cone's distance is within this of the triangle's).
const HULL_WORTH: f32 = 0.03;
/// A cone wider than this is no bound at all (a cap wider than a hemisphere is not convex).
const MAX_HALF: f32 = FRAC_PI_2 - 1.0e-4;

/// The range `[lo, hi]` a textured parameter (Blinn-Phong shininess, GGX roughness) takes
/// over a triangle's texels (seed 003 Sec. 3.5, Eq. 34–38). `lo == hi` is an untextured
/// material; Lambert ignores it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParameterRange {
    pub lo: f32,
    pub hi: f32,
}

impl ParameterRange {
    /// The material's own (untextured) parameter: shininess, roughness, or 0 for Lambert.
    pub fn of(material: &MaterialKind) -> ParameterRange {
        let value = match *material {
            MaterialKind::Lambert { .. } => 0.0,
            MaterialKind::BlinnPhong { shininess, .. } => shininess,
            MaterialKind::Ggx { roughness, .. } => roughness,
        };
        ParameterRange { lo: value, hi: value }
    }
}

/// Estimates the tessellation level of one triangle. See the module docs and
/// `docs/estimator.md`.
pub fn estimate(
    tri: &TriangleInput,
    material: &MaterialKind,
    lights: &[Light],
    settings: &EstimatorSettings,
) -> Estimate {
    estimate_textured(tri, material, ParameterRange::of(material), lights, settings)
}

/// [`estimate`] for a material whose shininess or roughness varies over the triangle within
/// `parameter` (the material's own value is then not used). The bound holds for every
/// sub-vertex and pixel value of the parameter in the range: the interpolation error is
/// bounded over the range (`sup_α* ‖f_α* − L f_α*‖`, paper Eq. 36) and the variation
/// `sup |f(α) − f(α')|` is added as an `n`-independent term (Eq. 37). See `docs/estimator.md`.
pub fn estimate_textured(
    tri: &TriangleInput,
    material: &MaterialKind,
    parameter: ParameterRange,
    lights: &[Light],
    settings: &EstimatorSettings,
) -> Estimate {
    let n_max = settings.n_max.clamp(1, 64);
    // NaN and non-positive ε become 0: only an exactly flat shading passes then.
    let eps = if settings.epsilon > 0.0 { settings.epsilon } else { 0.0 };
    let (sum, reason) = light_sums(tri, material, parameter, lights, settings, n_max, eps, false);
    let first = decide(&sum, eps, n_max, settings.split, reason);
    if first.level > REFINE_ABOVE && (!first.fallback || first.reason == Reason::Level) {
        let (sum, reason) = light_sums(tri, material, parameter, lights, settings, n_max, eps, true);
        return decide(&sum, eps, n_max, settings.split, reason);
    }
    first
}

/// A triangle whose level is above this (fallbacks for the level included) is estimated a second
/// time with each light's ranges taken over the patch's [`REFINE_CHILDREN`] children
/// ([`values_over_children`]).
const REFINE_ABOVE: f32 = 8.0;
/// The children a refined light takes its ranges over: the four of one midpoint subdivision
/// ([`midpoint_child`]). Two subdivisions (16 children) lowered the property test's evaluations
/// by another 2 % for four times the refining step's work (`docs/speedups.md` step 24).
const REFINE_CHILDREN: usize = 4;
/// ...for the lights whose diffuse or specular range exceeds this share of `ε` in a channel.
const REFINE_SHARE: f32 = 0.125;

/// Every light's bounds, summed, and the worst reason for fallback met on the way; with
/// `refine`, the ranges of the point and directional lights taken over the patch's children.
#[allow(clippy::too_many_arguments)]
fn light_sums(
    tri: &TriangleInput,
    material: &MaterialKind,
    parameter: ParameterRange,
    lights: &[Light],
    settings: &EstimatorSettings,
    n_max: u32,
    eps: f32,
    refine: bool,
) -> (Sums, Reason) {
    let frame = Frame::new(tri);
    let guard = Guard::default();
    let mut sum = Sums::default();
    let mut reason = Reason::None;
    // Point lights first, then directional ones, then polygons: the order of the GPU's light
    // buffers, so that the control stage sums the bounds in the same order (bit-identical).
    let points = lights.iter().filter(|l| matches!(l, Light::Point { .. }));
    let directionals = lights.iter().filter(|l| matches!(l, Light::Directional { .. }));
    let polygons = lights.iter().filter(|l| matches!(l, Light::Polygon(_)));
    for light in points.chain(directionals).chain(polygons) {
        let added = add_light(
            &frame,
            material,
            parameter,
            light,
            settings.discontinuity,
            settings.split,
            n_max,
            eps,
            refine,
            &mut sum,
            &guard,
        );
        if let Err(r) = added {
            reason = worse(reason, r);
        }
    }
    if guard.bad.get() {
        reason = worse(reason, Reason::Singular);
    }
    (sum, reason)
}

fn worse(a: Reason, b: Reason) -> Reason {
    let rank = |r: Reason| match r {
        Reason::None => 0,
        Reason::Level => 1,
        Reason::Discontinuity => 2,
        Reason::Singular => 3,
    };
    if rank(b) > rank(a) {
        b
    } else {
        a
    }
}

// ------------------------------------------------------------------------------------------
// Elementary functions
// ------------------------------------------------------------------------------------------
//
// The estimator's own sine, cosine, arc tangent, arc cosine, arc sine and power, built from
// IEEE-754 f32 additions, multiplications, divisions, square roots, `floor` and exact bit
// manipulation only, so that `glsl/include/estimator.glsl` (which has the same functions,
// operation for operation, all `precise`) computes bit-identical values on any Vulkan device
// whose basic f32 arithmetic is IEEE (the drivers' `sin`, `atan`, `pow`, ... differ from libm
// and from each other in the last bits, which flipped levels). Accuracy (tested in
// `elementary_functions_are_accurate`): ~1 ulp-level, far inside `ANGLE_PAD` and `SAFETY`.

/// π/2 split for Cody–Waite reduction: `P1 + P2` is exact in few bits (k·P1, k·P2 exact for
/// the small quadrant counts used here), `P3` the rest.
const PIO2_P1: f32 = 1.5703125;
const PIO2_P2: f32 = 0.0004837513;
const PIO2_P3: f32 = 7.54979e-8;
const TAN_PI_8: f32 = 0.41421357;

/// `x` reduced to `r ∈ [−π/4, π/4]` and the quadrant `x = r + n·π/2` (`n` mod 4).
fn reduce_quadrant(x: f32) -> (f32, i32) {
    let k = (x * FRAC_2_PI + 0.5).floor();
    let r = x - k * PIO2_P1 - k * PIO2_P2 - k * PIO2_P3;
    (r, (k as i32) & 3)
}

/// sin and cos on [−π/4, π/4]: Taylor polynomials (remainders below 2·10⁻⁹).
fn sin_poly(r: f32) -> f32 {
    let z = r * r;
    r + r * z * (-0.16666667 + z * (0.008333334 + z * (-0.0001984127 + z * 2.7557319e-6)))
}

fn cos_poly(r: f32) -> f32 {
    let z = r * r;
    1.0 - 0.5 * z + z * z * (0.041666668 + z * (-0.0013888889 + z * (2.4801588e-5 + z * -2.755732e-7)))
}

pub(crate) fn est_sin(x: f32) -> f32 {
    let (r, n) = reduce_quadrant(x);
    match n {
        0 => sin_poly(r),
        1 => cos_poly(r),
        2 => -sin_poly(r),
        _ => -cos_poly(r),
    }
}

pub(crate) fn est_cos(x: f32) -> f32 {
    let (r, n) = reduce_quadrant(x);
    match n {
        0 => cos_poly(r),
        1 => -sin_poly(r),
        2 => -cos_poly(r),
        _ => sin_poly(r),
    }
}

/// atan on [−tan(π/8), tan(π/8)]: Taylor series to t¹⁹ (remainder below 5·10⁻¹⁰).
fn atan_poly(t: f32) -> f32 {
    let z = t * t;
    let p = 0.06666667 + z * (-0.05882353 + z * 0.05263158);
    let p = -0.07692308 + z * p;
    let p = 0.09090909 + z * p;
    let p = -0.11111111 + z * p;
    let p = 0.14285715 + z * p;
    let p = -0.2 + z * p;
    let p = 0.33333334 + z * p;
    t - t * z * p
}

/// atan on [0, 1].
fn atan_unit(t: f32) -> f32 {
    if t > TAN_PI_8 {
        FRAC_PI_4 + atan_poly((t - 1.0) / (t + 1.0))
    } else {
        atan_poly(t)
    }
}

/// atan2 (0 for (0, 0)).
pub(crate) fn est_atan2(y: f32, x: f32) -> f32 {
    let (ax, ay) = (x.abs(), y.abs());
    if ax == 0.0 && ay == 0.0 {
        return 0.0;
    }
    let a = if ay <= ax { atan_unit(ay / ax) } else { FRAC_PI_2 - atan_unit(ax / ay) };
    let a = if x < 0.0 { PI - a } else { a };
    if y < 0.0 {
        -a
    } else {
        a
    }
}

/// acos on [−1, 1] (clamped), through atan2 of the sine `√((1 − x)(1 + x))`.
pub(crate) fn est_acos(x: f32) -> f32 {
    est_atan2(((1.0 - x) * (1.0 + x)).max(0.0).sqrt(), x)
}

/// asin on [−1, 1] (clamped).
pub(crate) fn est_asin(x: f32) -> f32 {
    est_atan2(x, ((1.0 - x) * (1.0 + x)).max(0.0).sqrt())
}

/// log₂ of a positive normal `x`: exponent and `ln m = 2 atanh((m−1)/(m+1))`, `m ∈ [√½, √2)`.
pub(crate) fn est_log2(x: f32) -> f32 {
    let bits = x.to_bits();
    let mut e = ((bits >> 23) & 0xff) as i32 - 127;
    let mut m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    if m > SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let t = (m - 1.0) / (m + 1.0);
    let z = t * t;
    let ln_m = 2.0 * t * (1.0 + z * (0.33333334 + z * (0.2 + z * (0.14285715 + z * 0.11111111))));
    e as f32 + ln_m * LOG2_E
}

/// 2^z; 0 below 2⁻¹²⁶ (no subnormals: GPUs may flush them), ∞ from 2¹²⁸ on.
fn est_exp2(z: f32) -> f32 {
    if z.is_nan() {
        return z;
    }
    if z >= 128.0 {
        return f32::INFINITY;
    }
    if !(z >= -126.0) {
        return 0.0;
    }
    let n = z.floor();
    let u = (z - n) * LN_2;
    let p = 1.0
        + u * (1.0
            + u * (0.5
                + u * (0.16666667
                    + u * (0.041666668
                        + u * (0.008333334
                            + u * (0.0013888889
                                + u * (0.0001984127 + u * (2.4801588e-5 + u * 2.7557319e-6))))))));
    p * f32::from_bits(((n as i32 + 127) as u32) << 23)
}

/// `x^y` for `x ≥ 0` (NaN for negative `x`): `x⁰ = 1`, `x¹ = x`, `0^y = 0` or ∞.
pub(crate) fn est_pow(x: f32, y: f32) -> f32 {
    if y == 0.0 {
        return 1.0;
    }
    if y == 1.0 {
        return x;
    }
    if x == 0.0 {
        return if y > 0.0 { 0.0 } else { f32::INFINITY };
    }
    if !(x > 0.0) {
        return f32::NAN;
    }
    if x == f32::INFINITY {
        return if y > 0.0 { f32::INFINITY } else { 0.0 };
    }
    if x < f32::MIN_POSITIVE {
        // Subnormal: as 0 (GPUs may flush them).
        return if y > 0.0 { 0.0 } else { f32::INFINITY };
    }
    est_exp2(y * est_log2(x))
}

// ------------------------------------------------------------------------------------------
// Jets
// ------------------------------------------------------------------------------------------

/// Bounds of one factor over the whole triangle: `m ≥ sup|f|`, `g ≥ sup|Df[δ]|` and
/// `Σₜ h[t] ≥ sup|D²f[δ,δ]|`, the derivatives taken along a domain step `δ` and evaluated
/// at the pattern scale (`|Xδ| → a`, `|Nδ| → b`, see [`Scale`]).
///
/// `t ≥ sup|D²f[δ,δ]|` is the same second-order bound carried as one number: every rule
/// that adds a part to some `h[t]` adds it to `t` too, in a fixed order, so that the GPU,
/// which carries only `t` (one pass over the jets instead of one per term), gets the same
/// value bit for bit. The levels are decided on `t`; `h` tells which term dominates
/// (`Estimate::terms`) and drives the `Uniform` split. `t ≤ Σₜ h[t]` (equal up to rounding
/// except where [`jet_max`] takes the larger of two jets).
#[derive(Clone, Copy, Debug)]
struct Jet {
    m: f32,
    g: f32,
    h: [f32; TERM_COUNT],
    t: f32,
}

const NO_H: [f32; TERM_COUNT] = [0.0; TERM_COUNT];

impl Jet {
    fn constant(m: f32) -> Jet {
        Jet { m, g: 0.0, h: NO_H, t: 0.0 }
    }
}

/// Saturates bounds at [`BIG`] and remembers that it did (which forces fallback). Also
/// catches NaN (`!(x <= BIG)`).
#[derive(Default)]
struct Guard {
    bad: Cell<bool>,
}

impl Guard {
    #[inline]
    fn c(&self, x: f32) -> f32 {
        if x <= BIG {
            x
        } else {
            self.bad.set(true);
            BIG
        }
    }

    #[inline]
    fn mul(&self, a: f32, b: f32) -> f32 {
        self.c(a * b)
    }

    fn jet(&self, j: Jet) -> Jet {
        let mut out = Jet { m: self.c(j.m), g: self.c(j.g), h: j.h, t: self.c(j.t) };
        for h in &mut out.h {
            *h = self.c(*h);
        }
        out
    }
}

/// `h · s` for every term.
fn scaled(h: &[f32; TERM_COUNT], s: f32, gd: &Guard) -> [f32; TERM_COUNT] {
    let mut out = NO_H;
    for (o, &x) in out.iter_mut().zip(h) {
        *o = gd.mul(x, s);
    }
    out
}

/// Product rule for `K` factors:
/// `D²∏f = Σᵢ D²fᵢ ∏_{j≠i} fⱼ + 2 Σ_{i<j} Dfᵢ Dfⱼ ∏_{k≠i,j} fₖ`.
fn product<const K: usize>(f: [Jet; K], gd: &Guard) -> Jet {
    let mut m = 1.0;
    for j in &f {
        m = gd.mul(m, j.m);
    }
    let mut out = Jet::constant(m);
    for i in 0..K {
        let mut others = 1.0;
        for (j, fj) in f.iter().enumerate() {
            if j != i {
                others = gd.mul(others, fj.m);
            }
        }
        let gi = gd.mul(f[i].g, others);
        out.g = gd.c(out.g + gi);
        for t in 0..TERM_COUNT {
            let hi = gd.mul(f[i].h[t], others);
            out.h[t] = gd.c(out.h[t] + hi);
        }
        let ti = gd.mul(f[i].t, others);
        out.t = gd.c(out.t + ti);
        for j in (i + 1)..K {
            let mut rest = 2.0;
            for (l, fl) in f.iter().enumerate() {
                if l != i && l != j {
                    rest = gd.mul(rest, fl.m);
                }
            }
            let gg = gd.mul(f[i].g, f[j].g);
            let cross = gd.mul(gg, rest);
            out.h[Term::Cross as usize] = gd.c(out.h[Term::Cross as usize] + cross);
            out.t = gd.c(out.t + cross);
        }
    }
    out
}

/// A unit vector field `û = m/|m|` over the triangle (its cone is kept by the caller):
/// `w ≥ |Dm|/|m|` (≥ the angular speed `|Dû|`, at the pattern scale), `radial ≥ |û·Dm|/|m|`
/// (the part of the change along the field itself, which only rescales it; at most `w`), and
/// `x ≥ |P m''|/|m|` where `m` is not affine (zero for normalised affine fields).
#[derive(Clone, Copy, Debug)]
struct Field {
    w: f32,
    radial: f32,
    x: f32,
    term: Term,
}

/// Jet of `c = â·b̂` where the angle between them stays in `[ψ₀, ψ₁]`:
/// `|Dc| ≤ sin ψ (|Dâ| + |Db̂|)` (a derivative of a unit vector is orthogonal to it),
/// `|D²c| ≤ C(â) + C(b̂) + sin ψ (xₐ + x_b) + 2 wₐ w_b` with `C` the part of `D²â` that
/// `b̂` can see (`docs/estimator.md` §2, "Normalised vector fields"):
/// `C = min(φ(ψ)·w², max|cos ψ|·w² + 2 max sin ψ·w·radial)`,
/// `φ(ψ) = |cos ψ|/2 + √(1 − ¾cos²ψ) ≤ 2/√3`.
fn cosine(a: &Field, b: &Field, psi: (f32, f32), gd: &Guard) -> Jet {
    cosine_at(a, b, &Angles::of(psi), gd)
}

/// [`cosine`] with the angle range's [`Angles`] given.
fn cosine_at(a: &Field, b: &Field, angles: &Angles, gd: &Guard) -> Jet {
    let mut h = NO_H;
    let ha = angles.seen(a, gd);
    let hb = angles.seen(b, gd);
    let hd = gd.c(2.0 * a.w * b.w);
    h[a.term as usize] += ha;
    h[b.term as usize] += hb;
    h[Term::Dot as usize] += hd;
    let g = gd.c(angles.s_max * (a.w + b.w));
    Jet { m: angles.c_max, g, h, t: ha + hb + hd }
}

/// The second derivative of a cosine `t = â·b̂` split by sign (`docs/estimator.md` §3, "A lobe
/// of a cosine"): with `u = Dâ`, `v = Db̂` and `Tₐ`, `T_b` the parts of `D²â`, `D²b̂` across
/// the fields (radial and non-affine), `D²t = −t(|u|² + |v|²) + 2u·v + Tₐ·b̂ + â·T_b`. Where
/// `t ≥ 0` the first part is `≤ 0` and at most `t·turn` in size; `rest` bounds the others.
struct Curvature {
    /// `wₐ² + w_b² ≥ |u|² + |v|²`.
    turn: f32,
    /// `2wₐw_b + sin ψ (2wₐρₐ + xₐ + 2w_bρ_b + x_b)`.
    rest: f32,
}

fn curvature(a: &Field, b: &Field, psi: (f32, f32), gd: &Guard) -> Curvature {
    let s_max = max_sin(psi.0, psi.1);
    let across_a = gd.c(2.0 * gd.mul(a.w, a.radial) + a.x);
    let across_b = gd.c(2.0 * gd.mul(b.w, b.radial) + b.x);
    Curvature {
        turn: gd.c(gd.mul(a.w, a.w) + gd.mul(b.w, b.w)),
        rest: gd.c(2.0 * a.w * b.w + s_max * gd.c(across_a + across_b)),
    }
}

/// What the jets need of an angle range `[ψ₀, ψ₁]` between two unit fields.
struct Angles {
    s_max: f32,
    c_max: f32,
    phi: f32,
}

impl Angles {
    fn of((p0, p1): (f32, f32)) -> Angles {
        Angles::with_cosines((p0, p1), (est_cos(p0), est_cos(p1)))
    }

    /// The same with the cosines of the range's ends given (`est_cos` of each).
    fn with_cosines((p0, p1): (f32, f32), (c0, c1): (f32, f32)) -> Angles {
        let (c0, c1) = (c0.abs(), c1.abs());
        Angles { s_max: max_sin(p0, p1), c_max: c0.max(c1), phi: max_phi(p0, p1, c0, c1) }
    }

    /// `≥ |D²û·b̂|` for the field `f` and a unit `b̂` at an angle in the range: with
    /// `A = Dm` and `p` its part across `û`, `D²û = −(2p(û·A) + û|p|²)/|m|²`, so
    /// `|D²û·b̂| ≤ min(φ(ψ)·w², max|cos ψ|·w² + 2 max sin ψ·w·radial)` (+ `sin ψ·x`).
    fn seen(&self, f: &Field, gd: &Guard) -> f32 {
        let w2 = gd.mul(f.w, f.w);
        let turning = gd.mul(self.phi, w2);
        let radial = gd.c(self.c_max * w2 + 2.0 * self.s_max * gd.mul(f.w, f.radial));
        gd.c(turning.min(radial) + self.s_max * f.x)
    }
}

/// `max sin ψ` over `[p0, p1] ⊂ [0, π]`.
fn max_sin(p0: f32, p1: f32) -> f32 {
    if p0 <= FRAC_PI_2 && p1 >= FRAC_PI_2 {
        1.0
    } else {
        est_sin(p0).max(est_sin(p1)).max(0.0)
    }
}

/// `max φ(ψ)` over `[p0, p1]`, `φ = c/2 + √(1 − ¾c²)` with `c = |cos ψ|`; φ rises from 1 at
/// `c = 0` to 2/√3 at `c = 1/√3` and falls back to 1 at `c = 1`. `c0`, `c1`: `|cos|` at the ends.
fn max_phi(p0: f32, p1: f32, c0: f32, c1: f32) -> f32 {
    let (lo, hi) =
        if p0 <= FRAC_PI_2 && p1 >= FRAC_PI_2 { (0.0, c0.max(c1)) } else { (c0.min(c1), c0.max(c1)) };
    let c = (1.0 / 3.0f32.sqrt()).clamp(lo, hi);
    (0.5 * c + (1.0 - 0.75 * c * c).max(0.0).sqrt()).min(K23)
}

/// `max cos^p ψ · sin^q ψ` over `[a, b] ⊂ [0, π/2]` (`q ≥ 0`): unimodal with its peak at
/// `tan²ψ = q/p` (`p > 0`); increasing when `p ≤ 0`.
fn max_cos_sin(p: f32, q: f32, a: f32, b: f32) -> f32 {
    let peak = if p > 0.0 { est_atan2((q / p).sqrt(), 1.0) } else { FRAC_PI_2 };
    let x = peak.clamp(a, b);
    let c = est_cos(x).max(0.0);
    let s = est_sin(x).max(0.0);
    let cp = if p == 0.0 { 1.0 } else { est_pow(c, p) };
    let sq = if q == 0.0 { 1.0 } else { est_pow(s, q) };
    cp * sq
}

// ------------------------------------------------------------------------------------------
// Cones
// ------------------------------------------------------------------------------------------

/// A circular cone of directions: every value of the field is within `half` of `axis`.
/// `half = π` means no bound.
#[derive(Clone, Copy, Debug)]
struct Cone {
    axis: Vec3,
    half: f32,
}

const NO_CONE: Cone = Cone { axis: Vec3::Z, half: PI };

/// Angle between two vectors, accurate for small and large angles; 0 if one is zero.
fn angle(a: Vec3, b: Vec3) -> f32 {
    est_atan2(a.cross(b).length(), a.dot(b))
}

fn unit(v: Vec3) -> Vec3 {
    let l2 = v.length_squared();
    if l2 > 0.0 && l2.is_finite() {
        v / l2.sqrt()
    } else {
        Vec3::ZERO
    }
}

/// The smallest cone containing three directions (the paper's Fig. 3b, with the obtuse
/// case handled): if the chord triangle of the unit vectors is obtuse or right (or
/// degenerate), the cone on its longest chord; otherwise the cone through all three (axis
/// normal to their plane). The half-angle is then measured, not trusted. A cone of
/// half-angle ≥ ~90° is returned as [`NO_CONE`]: positive combinations of vectors in a cap
/// stay in it only while the cap is convex.
fn cone_of(w: [Vec3; 3]) -> Cone {
    let u = w.map(unit);
    if u.contains(&Vec3::ZERO) {
        return NO_CONE;
    }
    let d = [(u[0] - u[1]).length_squared(), (u[1] - u[2]).length_squared(), (u[2] - u[0]).length_squared()];
    // Longest chord (i, j) = pair index k: 0 → (0,1), 1 → (1,2), 2 → (2,0).
    let k = if d[0] >= d[1] && d[0] >= d[2] {
        0
    } else if d[1] >= d[2] {
        1
    } else {
        2
    };
    let (i, j) = (k, (k + 1) % 3);
    let others = d[(k + 1) % 3] + d[(k + 2) % 3];
    let axis = if d[k] >= others {
        unit(u[i] + u[j])
    } else {
        let nrm = unit((u[1] - u[0]).cross(u[2] - u[0]));
        if nrm.dot(u[0] + u[1] + u[2]) < 0.0 {
            -nrm
        } else {
            nrm
        }
    };
    if axis == Vec3::ZERO {
        return NO_CONE;
    }
    let half = angle(axis, u[0]).max(angle(axis, u[1])).max(angle(axis, u[2])) + ANGLE_PAD;
    if half.is_nan() || half >= MAX_HALF {
        NO_CONE
    } else {
        Cone { axis, half }
    }
}

/// `min |Σλₖwₖ|` over the simplex is at least `min_k wₖ·axis` (project on the axis).
fn min_length(w: [Vec3; 3], cone: &Cone) -> f32 {
    if cone.half >= PI {
        return 0.0;
    }
    let r = w[0].dot(cone.axis).min(w[1].dot(cone.axis)).min(w[2].dot(cone.axis));
    if r > 0.0 {
        r
    } else {
        0.0
    }
}

/// Range of the angle between a vector of cone `a` and one of cone `b` (paper Eq. 20, 51).
fn psi_range(a: &Cone, b: &Cone) -> (f32, f32) {
    let t0 = angle(a.axis, b.axis);
    ((t0 - a.half - b.half).max(0.0), (t0 + a.half + b.half).min(PI))
}

/// Exact range of the bilinear form `q(λ) = (Σλₖaₖ)·(Σλₖbₖ)` over the simplex (a quadratic
/// in λ): the corners, the extremum along each edge, and the interior critical point.
/// `n·l` (unnormalised) is such a form for point lights (`bₖ = p − xₖ`, linear for
/// directional ones), and so is `n·v`; its sign is the sign of the shading's cosine.
fn bilinear_range(a: [Vec3; 3], b: [Vec3; 3]) -> (f32, f32) {
    let s = |i: usize, j: usize| 0.5 * (a[i].dot(b[j]) + a[j].dot(b[i]));
    let (s00, s11, s22) = (s(0, 0), s(1, 1), s(2, 2));
    let (s01, s12, s02) = (s(0, 1), s(1, 2), s(0, 2));
    let mut lo = s00.min(s11).min(s22);
    let mut hi = s00.max(s11).max(s22);
    for (sii, sjj, sij) in [(s00, s11, s01), (s11, s22, s12), (s22, s00, s02)] {
        let curv = sii - 2.0 * sij + sjj;
        let t = (sii - sij) / curv;
        if t > 0.0 && t < 1.0 {
            let v = (1.0 - t) * (1.0 - t) * sii + 2.0 * t * (1.0 - t) * sij + t * t * sjj;
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    // λ = (1 − s − t, s, t): q = s00 + 2dᵀx + xᵀMx, critical where Mx = −d, q* = s00 + dᵀx.
    let (d1, d2) = (s01 - s00, s02 - s00);
    let (ma, mb, mc) = (s00 - 2.0 * s01 + s11, s00 - s01 - s02 + s12, s00 - 2.0 * s02 + s22);
    let det = ma * mc - mb * mb;
    let x = (-d1 * mc + d2 * mb) / det;
    let y = (-ma * d2 + mb * d1) / det;
    if x > 0.0 && y > 0.0 && x + y < 1.0 {
        let v = s00 + d1 * x + d2 * y;
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (lo, hi)
}

/// Angular distance from the unit vector `a` to the spherical triangle spanned by the unit
/// vectors `u` (which lie in an open hemisphere): 0 inside, otherwise the distance to the
/// nearest edge arc or corner. Padded to stay a lower bound under f32 rounding.
fn hull_distance(a: Vec3, u: [Vec3; 3]) -> f32 {
    let orient = u[0].dot(u[1].cross(u[2]));
    let side = [a.dot(u[0].cross(u[1])), a.dot(u[1].cross(u[2])), a.dot(u[2].cross(u[0]))];
    let tol = 1.0e-6;
    let same_half = a.dot(u[0] + u[1] + u[2]) > 0.0;
    let inside = same_half
        && ((orient >= 0.0 && side.iter().all(|&x| x >= -tol))
            || (orient <= 0.0 && side.iter().all(|&x| x <= tol)));
    if inside {
        return 0.0;
    }
    let mut best = PI;
    for (p, q) in [(u[0], u[1]), (u[1], u[2]), (u[2], u[0])] {
        let ends = angle(a, p).min(angle(a, q));
        let m = unit(p.cross(q));
        let mut d = ends;
        if m != Vec3::ZERO {
            let foot = a - m * a.dot(m);
            if p.cross(foot).dot(m) >= 0.0 && foot.cross(q).dot(m) >= 0.0 && foot != Vec3::ZERO {
                d = d.min(est_atan2(a.dot(m).abs(), foot.length()));
            }
        }
        best = best.min(d);
    }
    (best * (1.0 - 1.0e-3) - ANGLE_PAD).max(0.0)
}

/// A lower bound on the angle between n̂ and the half vector `ĥ = (â + b̂)/|â + b̂|` at the
/// same point, where `n̂·â > 0` on the whole triangle (`docs/estimator.md` §2, "Cones and
/// cosine ranges": "`n·h` at the same point"). There `n̂` is the half vector of `â` and its mirror
/// `r = 2(n̂·â)n̂ − â`, and two half vectors of a common `â` are at least half as far apart as
/// their other ends: `∠(ĥ, n̂) ≥ ∠(b̂, r)/2`. `r` stays within `2ν_n + ν_a` of the mirror `r₀`
/// of the cones' axes (a half-turn about `n̂` against one about the axis is a rotation by twice
/// their angle), and `b̂` lies in its cone and in the spherical triangle of the directions of
/// `b_vectors` (from the corners to a point light or the eye; `None` for a single direction).
/// Returns the larger of this bound and `lo`.
fn mirror_lower_angle(n: &Cone, a: &Cone, b: &Cone, b_vectors: Option<[Vec3; 3]>, lo: f32) -> f32 {
    if !(n.half < PI && a.half < PI && b.half < PI) {
        return lo;
    }
    let r0 = unit(n.axis * (2.0 * n.axis.dot(a.axis)) - a.axis);
    if r0 == Vec3::ZERO {
        return lo;
    }
    let spread = 2.0 * n.half + a.half;
    let axis_angle = angle(b.axis, r0);
    let mut apart = axis_angle - b.half;
    // The spherical triangle is within `θ_b` of the axis, so it adds at most `θ_b` to the
    // cone's distance: it is worth its cost only for a wide cone, where it could raise `lo`.
    if let Some(vectors) = b_vectors {
        if b.half > HULL_WORTH && 0.5 * (axis_angle + b.half - spread) > lo {
            apart = apart.max(hull_distance(r0, vectors.map(unit)));
        }
    }
    lo.max(0.5 * (apart - spread) - ANGLE_PAD)
}

/// `range` narrowed to the angles that unit fields `â`, `b̂` (corner values `a`, `b`) can make
/// over the patch, given `curvature ≥ sup|D²(â − b̂)|` at level 1: `|â − b̂| = 2 sin(ψ/2)` lies
/// within `½·curvature` (the level-1 interpolation bound) of the linear interpolant of the
/// corners' differences, whose norm ranges from the triangle's distance to the origin to its
/// farthest corner (`docs/estimator.md` §2, "`n·h` from the corners' differences, to second order").
/// `1.0e-5` covers the rounding of the corners; a NaN leaves `range` as it is.
fn narrowed(range: (f32, f32), a: [Vec3; 3], b: [Vec3; 3], curvature: f32) -> (f32, f32) {
    let corners = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let error = 0.5 * curvature + 1.0e-5;
    let lo = origin_distance(corners) - error;
    let hi = corners[0].length().max(corners[1].length()).max(corners[2].length()) + error;
    let lo_angle = if lo > 0.0 { 2.0 * est_asin((0.5 * lo).min(1.0)) - ANGLE_PAD } else { 0.0 };
    let hi_angle = if hi < 2.0 { 2.0 * est_asin(0.5 * hi) + ANGLE_PAD } else { PI };
    let low = range.0.max(lo_angle);
    (low, range.1.min(hi_angle).max(low))
}

/// The distance from the origin to the segment `p q` (a point where `q = p`).
fn segment_distance(p: Vec3, q: Vec3) -> f32 {
    let pq = q - p;
    let length2 = pq.length_squared();
    let t = if length2 > 0.0 { (-p.dot(pq) / length2).clamp(0.0, 1.0) } else { 0.0 };
    (p + pq * t).length()
}

/// A lower bound on the distance from the origin to the triangle with corners `c`, exact up to
/// rounding unless the triangle is a sliver: the nearest of its edges, or the distance to its
/// plane where the origin projects inside it. The plane's normal is trusted only where the
/// triangle's height over its longest edge is at least a tenth of that edge (a plane's distance
/// never exceeds the distance to a point of the plane, so the inside test may err towards it);
/// a thinner triangle lies within its height `h` of its longest edge (whose ends see the third
/// corner at acute angles), so it is at least that edge's distance less `h` away.
fn origin_distance(c: [Vec3; 3]) -> f32 {
    let edges = [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])];
    let nearest = edges.map(|(p, q)| segment_distance(p, q));
    let lengths = edges.map(|(p, q)| (q - p).length_squared());
    let edge_min = nearest[0].min(nearest[1]).min(nearest[2]);
    let longest = if lengths[0] >= lengths[1] && lengths[0] >= lengths[2] {
        0
    } else if lengths[1] >= lengths[2] {
        1
    } else {
        2
    };
    let normal = (c[1] - c[0]).cross(c[2] - c[0]);
    let area2 = normal.length_squared();
    if area2 >= 0.01 * lengths[longest] * lengths[longest] && area2 > 0.0 {
        let inside = edges.iter().all(|&(p, q)| normal.dot((q - p).cross(-p)) >= 0.0);
        if inside {
            return edge_min.min(c[0].dot(normal).abs() / area2.sqrt());
        }
        return edge_min;
    }
    let height = if lengths[longest] > 0.0 { area2.sqrt() / lengths[longest].sqrt() } else { 0.0 };
    edge_min.min(nearest[longest] - height)
}

/// Largest angle between `a` and the spherical triangle spanned by unit `u`, valid when it
/// is below π/2 (then `n̂·a` is quasi-concave on the cone and its minimum sits at a corner);
/// `π` otherwise.
fn hull_max_angle(a: Vec3, u: [Vec3; 3]) -> f32 {
    let m = angle(a, u[0]).max(angle(a, u[1])).max(angle(a, u[2])) + ANGLE_PAD;
    if m < FRAC_PI_2 {
        m
    } else {
        PI
    }
}

// ------------------------------------------------------------------------------------------
// The pattern
// ------------------------------------------------------------------------------------------

/// Evaluation point of the jets: what `|Xδ|` (length), `|Nδ|` and `|Gδ|` are replaced by,
/// where `Gδ = (N₀·Nδ, N₁·Nδ, N₂·Nδ)` bounds the normal's change along itself
/// (`|N(λ)·Nδ| ≤ |Gδ|`, see [`Field::radial`]).
#[derive(Clone, Copy, Debug, Default)]
struct Scale {
    a: f32,
    b: f32,
    g: f32,
}

/// For the images of the seven sub-triangle shapes under one attribute map: `(√K₁, √K, D₁, D)`
/// where `K₁` is the enclosing-circle radius² of the patch itself (level 1), `K` the largest
/// over all shapes (levels ≥ 2), and `D₁`, `D` the matching largest diameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatternConstants {
    pub sqrt_k1: f32,
    pub sqrt_k: f32,
    pub diam1: f32,
    pub diam: f32,
}

/// The shapes, as `{0, u, v}` with `u`, `v` in the basis `e₁ = B − A`, `e₂ = C − A` of the
/// patch `(A, B, C)`. At level `n` every sub-triangle of Vulkan's `equal_spacing` pattern
/// (inner = outer = n) is a translate of `±1/n` times one of them:
/// the patch (level 1, and the centre triangle of odd levels), and for each side with
/// direction `e` and "rung" `r` (from a point of the side to the next inner ring, ⅔ of the
/// median towards the opposite corner) the two halves of a ring quad, `{0, e, e + r}` and
/// `{0, e, r}` (both diagonals; corner triangles and the centre fan of even levels are
/// among them).
pub const SHAPES: [[(f32, f32); 2]; 7] = [
    [(1.0, 0.0), (0.0, 1.0)],
    // side AB: e = e₁, r = −e₁/3 + 2e₂/3
    [(1.0, 0.0), (2.0 / 3.0, 2.0 / 3.0)],
    [(1.0, 0.0), (-1.0 / 3.0, 2.0 / 3.0)],
    // side AC: e = e₂, r = 2e₁/3 − e₂/3
    [(0.0, 1.0), (2.0 / 3.0, 2.0 / 3.0)],
    [(0.0, 1.0), (2.0 / 3.0, -1.0 / 3.0)],
    // side BC: e = e₂ − e₁, r = −(e₁ + e₂)/3
    [(-1.0, 1.0), (-4.0 / 3.0, 2.0 / 3.0)],
    [(-1.0, 1.0), (-1.0 / 3.0, -1.0 / 3.0)],
];

/// `max_x Σμₖ|vₖ − x|²` over the triangle `{0, u, v}`: the circumradius² if the triangle
/// is acute, (longest edge / 2)² otherwise; clamped to Jung's `[d²/4, d²/3]` against
/// rounding. Returns it with the squared diameter `d²`.
fn enclosing_radius2(u: Vec3, v: Vec3) -> (f32, f32) {
    let e = [u.length_squared(), v.length_squared(), (u - v).length_squared()];
    let d2 = e[0].max(e[1]).max(e[2]);
    if !(d2 > 0.0) {
        return (0.0, 0.0);
    }
    let sum = e[0] + e[1] + e[2];
    if 2.0 * d2 >= sum {
        return (0.25 * d2, d2);
    }
    // Scale-free: R²/d² = (a²b²c²/d⁶) / (4|u×v|²/d⁴).
    let x = u.cross(v).length_squared() / (d2 * d2);
    let r = (e[0] / d2) * (e[1] / d2) * (e[2] / d2) / (4.0 * x).max(1.0e-30);
    (d2 * r.clamp(0.25, 1.0 / 3.0), d2)
}

/// The pattern constants of the attribute triangle with edge vectors `e1 = W(B) − W(A)`,
/// `e2 = W(C) − W(A)`: see [`PatternConstants`].
pub fn pattern_constants(e1: Vec3, e2: Vec3) -> PatternConstants {
    let mut out = PatternConstants::default();
    for (s, shape) in SHAPES.iter().enumerate() {
        let u = e1 * shape[0].0 + e2 * shape[0].1;
        let v = e1 * shape[1].0 + e2 * shape[1].1;
        let (k, d2) = enclosing_radius2(u, v);
        let (k, d) = (k.sqrt(), d2.sqrt());
        if s == 0 {
            out.sqrt_k1 = k;
            out.diam1 = d;
        }
        out.sqrt_k = out.sqrt_k.max(k);
        out.diam = out.diam.max(d);
    }
    out
}

/// Upper bounds `(√K₁, √K)` on [`pattern_constants`] from the longest edge `d` of the shapes
/// alone (Jung's theorem, `r² ≤ d²/3`): at most 15 % above them and cheaper, for the normal's
/// radial scale ([`Scale::g`]), which only ever enters beside a larger term.
fn jung_scales(e1: Vec3, e2: Vec3) -> (f32, f32) {
    let (mut d1, mut d) = (0.0f32, 0.0f32);
    for (s, shape) in SHAPES.iter().enumerate() {
        let u = e1 * shape[0].0 + e2 * shape[0].1;
        let v = e1 * shape[1].0 + e2 * shape[1].1;
        let d2 = u.length_squared().max(v.length_squared()).max((u - v).length_squared());
        if s == 0 {
            d1 = d2;
        }
        d = d.max(d2);
    }
    ((d1 / 3.0).sqrt(), (d / 3.0).sqrt())
}

// ------------------------------------------------------------------------------------------
// Per-triangle and per-light geometry
// ------------------------------------------------------------------------------------------

/// Scale-free quantities of the triangle.
struct Frame {
    vertices: [Vec3; 3],
    eye: Vec3,
    centroid: Vec3,
    /// `max_k |xₖ − centroid|`: how far any point is from the centroid.
    rho_x: f32,
    /// Pattern scales: level 1, levels ≥ 2, and the diameters (Relaxed terms).
    s1: Scale,
    sn: Scale,
    /// `ρ = max` over the three attributes of `s₁/sₙ` (`≤ 1`, as `s₁ ≤ sₙ`): the level-1 jets are
    /// at most `ρ` (first derivatives) and `ρ²` (second) times those at levels ≥ 2.
    rho: f32,
    d1: Scale,
    dn: Scale,
    n_cone: Cone,
    /// Lower bound on `|N(λ)|` over the triangle; 0 when the normal can vanish.
    r_n: f32,
    /// Upper bound on `|N(λ)|`.
    n_max_len: f32,
    /// The vertex normals as given, and normalised (corners of the spherical triangle n̂).
    normals: [Vec3; 3],
    unit_normals: [Vec3; 3],
    /// Unit normal of the triangle's plane (zero for a degenerate triangle).
    plane: Vec3,
    v_cone: Cone,
    /// Bound on the angle (rad) between `plane` and the true plane normal (f32 rounding).
    plane_tilt: f32,
    /// `max |sin|` of the angle between n̂ and the plane normal (see [`plane_sin`]): bounds
    /// `|n̂·Xδ|/|Xδ|`.
    n_plane_sin: f32,
    /// Lower bound on the distance from the eye to the triangle.
    e_min: f32,
    v_center: Vec3,
}

impl Frame {
    fn new(tri: &TriangleInput) -> Frame {
        let [p0, p1, p2] = tri.positions;
        let centroid = (p0 + p1 + p2) / 3.0;
        let rho_x = (p0 - centroid).length().max((p1 - centroid).length()).max((p2 - centroid).length());
        let px = pattern_constants(p1 - p0, p2 - p0);
        let [n0, n1, n2] = tri.normals;
        let pn = pattern_constants(n1 - n0, n2 - n0);
        let n_cone = cone_of(tri.normals);
        let longest = n0.length().max(n1.length()).max(n2.length());
        let along = |e: Vec3| Vec3::new(n0.dot(e), n1.dot(e), n2.dot(e));
        let pg = jung_scales(along(n1 - n0), along(n2 - n0));
        // Rounding of the dot products: a few ulps of |N|·|Nδ|, and |Nδ| ≤ 2√K at the scale.
        let g_pad = RADIAL_PAD * longest;
        let mut r_n = min_length(tri.normals, &n_cone);
        if !(r_n > 1.0e-6 * longest) {
            r_n = 0.0;
        }
        let to_eye = [tri.eye - p0, tri.eye - p1, tri.eye - p2];
        let v_cone = cone_of(to_eye);
        let e_min = min_length(to_eye, &v_cone);
        let (plane, plane_tilt) = {
            let c = (p1 - p0).cross(p2 - p0);
            let scale = (p1 - p0).length() * (p2 - p0).length();
            if c.length() > 1.0e-6 * scale {
                // Each component of the cross product is within about 4·10⁻⁷·scale.
                (unit(c), 4.0e-7 * scale / c.length() + 1.0e-6)
            } else {
                (Vec3::ZERO, 0.0)
            }
        };
        let s1 = Scale { a: px.sqrt_k1, b: pn.sqrt_k1, g: pg.0 + g_pad * pn.sqrt_k1 };
        let sn = Scale { a: px.sqrt_k, b: pn.sqrt_k, g: pg.1 + g_pad * pn.sqrt_k };
        let ratio = |one: f32, later: f32| if later > 0.0 { one / later } else { 0.0 };
        let rho = ratio(s1.a, sn.a).max(ratio(s1.b, sn.b)).max(ratio(s1.g, sn.g)).min(1.0);
        Frame {
            vertices: tri.positions,
            eye: tri.eye,
            centroid,
            rho_x,
            s1,
            sn,
            rho,
            d1: Scale { a: px.diam1, b: pn.diam1, g: 0.0 },
            dn: Scale { a: px.diam, b: pn.diam, g: 0.0 },
            n_cone,
            r_n,
            n_max_len: longest,
            normals: tri.normals,
            unit_normals: tri.normals.map(unit),
            plane,
            plane_tilt,
            n_plane_sin: plane_sin(&n_cone, plane),
            v_cone,
            e_min,
            v_center: unit(tri.eye - centroid),
        }
    }

    /// Lower and upper bounds on the height of `p` over the triangle's plane (0 without a
    /// plane): the computed one less and plus what the plane's direction and the rounding can be
    /// off by.
    fn height_of(&self, p: Vec3) -> (f32, f32) {
        if self.plane == Vec3::ZERO {
            return (0.0, 0.0);
        }
        let r = p - self.vertices[0];
        let (height, pad) = (r.dot(self.plane).abs(), r.length() * (self.plane_tilt + 1.0e-6));
        ((height - pad).max(0.0), height + pad)
    }

    /// A lower bound on the distance from `p` to the triangle: `√(H² + ρ²)` with `H ≥ height`
    /// its height from below ([`Frame::height_of`]) and `ρ` the in-plane distance from its foot
    /// to the triangle, less what the rounding can move it.
    fn distance_of(&self, p: Vec3, height: f32) -> f32 {
        if self.plane == Vec3::ZERO {
            return self.distance_along_line(p);
        }
        let foot = p - self.plane * (p - self.vertices[0]).dot(self.plane);
        // The foot's distance to the triangle: 0 inside, else to the nearest edge (at most to
        // the first corner).
        let mut inside = true;
        let mut rho = (foot - self.vertices[0]).length();
        for k in 0..3 {
            let (a, b) = (self.vertices[k], self.vertices[(k + 1) % 3]);
            let (e, f) = (b - a, foot - a);
            inside &= e.cross(f).dot(self.plane) >= 0.0;
            let t = (f.dot(e) / e.length_squared()).clamp(0.0, 1.0);
            rho = rho.min((f - e * t).length());
        }
        let reach = (p - self.vertices[0]).length() + 2.0 * self.rho_x;
        // The foot's rounding (the plane's tilt over the light's reach) and the differences'.
        let magnitude = foot.abs().max_element() + self.vertices[0].abs().max_element() + 2.0 * self.rho_x;
        let pad = 2.0 * reach * (self.plane_tilt + 1.0e-6) + 1.0e-6 * magnitude;
        let rho = if inside || !(rho > pad) { 0.0 } else { rho - pad };
        (height * height + rho * rho).sqrt()
    }

    /// For a triangle without a plane (its corners on a line, up to rounding): the distance
    /// from `p` to its longest edge, less the third corner's distance from that edge (every
    /// point of the triangle is that close to the edge) and the rounding.
    fn distance_along_line(&self, p: Vec3) -> f32 {
        let v = self.vertices;
        let lengths =
            [(v[1] - v[0]).length_squared(), (v[2] - v[1]).length_squared(), (v[0] - v[2]).length_squared()];
        let k = if lengths[0] >= lengths[1] && lengths[0] >= lengths[2] {
            0
        } else if lengths[1] >= lengths[2] {
            1
        } else {
            2
        };
        let (a, b, third) = (v[k], v[(k + 1) % 3], v[(k + 2) % 3]);
        let to_segment = |x: Vec3| {
            let (e, f) = (b - a, x - a);
            let t = if lengths[k] > 0.0 { (f.dot(e) / lengths[k]).clamp(0.0, 1.0) } else { 0.0 };
            (f - e * t).length()
        };
        let magnitude = p.abs().max_element() + a.abs().max_element() + 2.0 * self.rho_x;
        (to_segment(p) - to_segment(third) - 1.0e-6 * magnitude).max(0.0)
    }
}

/// `max |sin|` of the angle between a direction of `cone` and the unit `plane` normal, 1
/// without a plane: bounds `|ŵ·Xδ|/|Xδ|` for the directions ŵ of the cone, since position
/// steps `Xδ` lie in the plane.
fn plane_sin(cone: &Cone, plane: Vec3) -> f32 {
    if plane == Vec3::ZERO {
        return 1.0;
    }
    let (g0, g1) = psi_range(cone, &Cone { axis: plane, half: 0.0 });
    max_sin(g0, g1)
}

/// Everything about one light that does not depend on the pattern scale.
struct LightSetup {
    /// `max |sin|` of the angle between l̂ and the plane normal (1 without a plane): bounds
    /// `|l̂·Xδ|/|Xδ|`, since position steps lie in the plane.
    plane_sin: f32,
    /// `≤ plane_sin`: `|sin γ|` where the light is nearest (`√(1 − H²/d_min²)`, `H` the
    /// light's height over the plane), for bounds that fall as `d` grows along `sin²γ = 1 − H²/d²`.
    near_sin: f32,
    /// `1/d_min` for a point light, 0 for a directional one.
    inv_d: f32,
    /// Range of the angle between n̂ and l̂.
    psi_nl: (f32, f32),
    /// Whether `n·l` may change sign inside the triangle.
    straddle: bool,
    // Blinn-Phong and GGX only:
    h_cone: Cone,
    m_min: f32,
    psi_nh: (f32, f32),
    psi_nv: (f32, f32),
    nv_sign: Sign,
    /// Range of the angle between l̂ and v̂.
    psi_lv: (f32, f32),
    /// A polygonal light: the range of the emitter's angle (see [`AreaGeometry`]); its diffuse
    /// part is bounded as a continuum of point lights, its sampled specular part by its range.
    area: Option<(f32, f32)>,
    /// `≤ H/d_min` (at most 1), `H` the light's height over the plane (0 without a plane):
    /// the cosine of `γ` where the light is nearest, for bounds along `sin²γ = 1 − H²/d²`.
    near_cos: f32,
    /// `≥ H/d_min` (at most 1; 1 without a plane): `H` from above, so `cos γ ≤ far_cos` at
    /// every point.
    far_cos: f32,
    /// `≤ inf E'` over the triangle: `1/d_max²` for a point light (the farthest point is a
    /// corner), 1 for a directional one, 0 for a polygon.
    att_inf: f32,
    /// The cosines at the ends of `psi_nl`, `(cos ψ_min, cos ψ_max)`.
    nl_cos: (f32, f32),
}

impl LightSetup {
    /// A light at `1/d_min = inv_d` with the angle range `psi_nl` and nothing else known yet:
    /// every other bound at its loosest.
    fn unbounded(inv_d: f32, psi_nl: (f32, f32), straddle: bool, area: Option<(f32, f32)>) -> LightSetup {
        LightSetup {
            plane_sin: 1.0,
            near_sin: 1.0,
            inv_d,
            psi_nl,
            straddle,
            h_cone: NO_CONE,
            m_min: 0.0,
            psi_nh: (0.0, PI),
            psi_nv: (0.0, PI),
            nv_sign: Sign::Both,
            psi_lv: (0.0, PI),
            area,
            near_cos: 0.0,
            far_cos: 1.0,
            att_inf: 0.0,
            nl_cos: (1.0, -1.0),
        }
    }
}

/// Accumulated bounds, per term and channel: `½·SAFETY·Σ weight·H` at level 1 and at
/// levels ≥ 2 (to be divided by n²), and the Relaxed first-order (÷ n) and constant terms.
#[derive(Default)]
struct Sums {
    h1: [Vec3; TERM_COUNT],
    hn: [Vec3; TERM_COUNT],
    /// The second-order bound at levels ≥ 2 as one number per channel ([`Jet::t`]): what
    /// the level is decided on (the level-1 bound goes into `one`).
    tn: Vec3,
    lin1: Vec3,
    linn: Vec3,
    /// Constant (n-independent) parts at levels ≥ 2: the Relaxed specular jumps at the
    /// terminator (taken at a lower bound of the level) and the parameter variations...
    jumps: Vec3,
    /// ...the same at level 1...
    jumps1: Vec3,
    /// ...and the light parts bounded by their range, reported as [`Term::Range`].
    range: Vec3,
    /// The level-1 bound, per light and part the smaller of its interpolation bound and its
    /// range.
    one: Vec3,
    /// The same at the uniform levels of [`GRID_LEVELS`] (the effective level of each).
    grid: [Vec3; GRID_LEVELS.len()],
    /// The largest of the lights' lower bounds on the level (`low` in `add_light`): `linn` and
    /// `jumps` hold at effective levels from there on (their bands are taken there), so the
    /// bound `tn/L² + linn/L + jumps + range` does too. The level the solver returns is never
    /// below it; a grid level may be.
    low: f32,
}

/// Uniform levels at which the estimator also bounds each light's parts by the smaller of
/// their interpolation bound and their range at that very level (the rule of `add_light`
/// decides once, at `n_max`). A level found on this grid replaces the solved one where it is
/// lower; levels above `n_max` are skipped.
const GRID_LEVELS: [u32; 8] = [2, 3, 4, 6, 8, 12, 16, 32];

/// Sign of a cosine over the whole triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sign {
    Positive,
    NonPositive,
    Both,
}

/// Range of the angle between n̂ and the field `ŵ = normalize(Σλₖwₖ)` (cone `w_cone`), and
/// the sign of `n·w` over the triangle. The cones give one range (paper Eq. 20, 51); the
/// exact range `[q₋, q₊]` of the bilinear form `n·w` gives the sign and, through
/// `q₋/(max|n| max|w|) ≤ cos ≤ q₊/(min|n| min|w|)`, a second range; the tighter ends are kept.
fn cosine_range(frame: &Frame, w_cone: &Cone, w: [Vec3; 3]) -> ((f32, f32), Sign) {
    let q = bilinear_range(frame.normals, w);
    let w_max = w[0].length().max(w[1].length()).max(w[2].length());
    cosine_range_of(frame, w_cone, q, w_max, min_length(w, w_cone))
}

/// [`cosine_range`] from the range `q` of `n·w` over the triangle and bounds on `|w|`.
fn cosine_range_of(
    frame: &Frame,
    w_cone: &Cone,
    q: (f32, f32),
    w_max: f32,
    w_min: f32,
) -> ((f32, f32), Sign) {
    let (mut p0, mut p1) = psi_range(&frame.n_cone, w_cone);
    let (q_lo, q_hi) = q;
    let scale = frame.n_max_len * w_max;
    let tol = 1.0e-5 * scale;
    let sign = if q_lo > tol {
        Sign::Positive
    } else if q_hi < -tol {
        Sign::NonPositive
    } else {
        Sign::Both
    };

    if q_lo > tol && scale > 0.0 {
        p1 = p1.min(est_acos((q_lo / scale).min(1.0)) + ANGLE_PAD);
    }
    let denom = frame.r_n * w_min;
    if q_hi > 0.0 && denom > 0.0 {
        p0 = p0.max(est_acos((q_hi / denom).min(1.0)) - ANGLE_PAD);
    }
    if sign == Sign::NonPositive {
        p0 = p0.max(FRAC_PI_2);
    }
    if p0 > p1 {
        p0 = p1;
    }
    ((p0, p1), sign)
}

/// Where a polygonal light is as seen from the triangle: every direction from a point of the
/// triangle to a point of the polygon, and the emitter's cosine. See `docs/estimator.md` §13.
struct AreaGeometry {
    /// Contains every `y − x` (x in the triangle, y in the polygon): the cone around the
    /// centroid-to-centroid axis through all vertex-to-vertex differences (a cone narrower
    /// than a hemisphere is convex, so it holds their convex hull, which is the set).
    cone: Cone,
    /// `min |y − x|` ≥ the smallest projection of a vertex-to-vertex difference on the axis.
    d_min: f32,
    /// Range of `n·(y − x)` over the triangle and the polygon: per polygon vertex the exact
    /// bilinear range over the triangle, and their hull (the form is affine in y).
    q: (f32, f32),
    w_max: f32,
    /// Range of the angle between the emitter's normal and `x − y` (cosine at the emitter).
    emitter: (f32, f32),
}

/// The [`AreaGeometry`] of `light` from `frame`, `Ok(None)` when the triangle lies behind the
/// emitter (it then receives exactly nothing), `Err` when the emitter's plane cuts it.
fn area_geometry(frame: &Frame, light: &PolygonLight) -> Result<Option<AreaGeometry>, Reason> {
    let y = light.vertices();
    let side = frame.vertices.map(|x| light.normal.dot(x - y[0]));
    if side.iter().all(|&d| d <= 0.0) {
        return Ok(None);
    }
    let reach = frame.vertices.iter().map(|x| (*x - y[0]).length()).fold(0.0, f32::max);
    if !side.iter().all(|&d| d > 1.0e-5 * reach) {
        return Err(Reason::Discontinuity);
    }
    let centroid = y.iter().copied().sum::<Vec3>() / y.len() as f32;
    let axis = unit(centroid - frame.centroid);
    let (mut half, mut d_min, mut w_max) = (0.0f32, f32::MAX, 0.0f32);
    let (mut q_lo, mut q_hi) = (f32::MAX, -f32::MAX);
    for &yj in y {
        let w = frame.vertices.map(|x| yj - x);
        for wk in w {
            half = half.max(angle(axis, wk));
            d_min = d_min.min(wk.dot(axis));
            w_max = w_max.max(wk.length());
        }
        let (lo, hi) = bilinear_range(frame.normals, w);
        q_lo = q_lo.min(lo);
        q_hi = q_hi.max(hi);
    }
    half += ANGLE_PAD;
    let cone = if axis == Vec3::ZERO || !(half < MAX_HALF) { NO_CONE } else { Cone { axis, half } };
    if cone.half >= PI || !(d_min > 0.0) {
        d_min = 0.0;
    }
    let emitter = psi_range(&Cone { axis: -light.normal, half: 0.0 }, &cone);
    Ok(Some(AreaGeometry { cone, d_min, q: (q_lo, q_hi), w_max, emitter }))
}

/// Colour weights of the diffuse and specular parts.
fn weights(material: &MaterialKind, radiance: Vec3) -> (Vec3, Vec3) {
    match *material {
        MaterialKind::Lambert { kd } => (radiance * kd, Vec3::ZERO),
        MaterialKind::BlinnPhong { kd, ks, .. } => (radiance * kd, radiance * ks),
        // The specular part's colour comes from F (per channel, see `spec_jets`).
        MaterialKind::Ggx { albedo, .. } => (radiance * albedo, radiance),
    }
}

/// A light's geometry over the triangle ([`LightSetup`]) and the weights of its diffuse and
/// specular parts; `None` where it adds exactly nothing; the reason for fallback where a
/// clamp or a singularity rules out a bound.
fn plan_light(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    light: &Light,
    mode: Discontinuity,
) -> Result<Option<(LightSetup, Vec3, Vec3)>, Reason> {
    let mut area = None;
    // A point light's height over the plane, from below and from above.
    let mut heights = (0.0, 0.0);
    // A point light's vectors from the corners (their directions span the spherical triangle
    // of l̂).
    let mut l_vectors = None;
    let (radiance, l_cone, inv_d, l_center) = match *light {
        Light::Point { position, color, intensity } => {
            let radiance = color * intensity;
            if radiance == Vec3::ZERO {
                return Ok(None);
            }
            let w = frame.vertices.map(|x| position - x);
            l_vectors = Some(w);
            let cone = cone_of(w);
            let d_min = min_length(w, &cone);
            // The falloff is clamped at d² = 10⁻⁸: only smooth (and bounded) beyond it.
            if !(d_min * d_min > MIN_LIGHT_DISTANCE_SQUARED * 1.001) {
                let (diff, spec) = weights(material, radiance);
                if diff == Vec3::ZERO && spec == Vec3::ZERO {
                    return Ok(None);
                }
                return Err(Reason::Singular);
            }
            // Every point of the triangle is at least its height and in-plane distance away.
            heights = frame.height_of(position);
            let d_min = d_min.max(frame.distance_of(position, heights.0));
            (radiance, cone, 1.0 / d_min, unit(position - frame.centroid))
        }
        Light::Directional { direction, color, intensity } => {
            let radiance = color * intensity;
            if radiance == Vec3::ZERO {
                return Ok(None);
            }
            let l = unit(-direction);
            (radiance, Cone { axis: l, half: 0.0 }, 0.0, l)
        }
        Light::Polygon(ref polygon) => {
            if polygon.radiance() == Vec3::ZERO {
                return Ok(None);
            }
            let Some(geometry) = area_geometry(frame, polygon)? else {
                return Ok(None);
            };
            if !(geometry.d_min * geometry.d_min > MIN_LIGHT_DISTANCE_SQUARED * 1.001) {
                return Err(Reason::Singular);
            }
            let (cone, d_min) = (geometry.cone, geometry.d_min);
            area = Some(geometry);
            // Per unit of this weight the diffuse part is ∫ (n·l)(cos at the emitter)/d² dA / A.
            (polygon.radiance() * polygon.area, cone, 1.0 / d_min, cone.axis)
        }
    };
    let (diff_w, spec_w) = weights(material, radiance);
    if diff_w == Vec3::ZERO && spec_w == Vec3::ZERO {
        return Ok(None);
    }
    if frame.r_n <= 0.0 {
        return Err(Reason::Singular);
    }
    // Sign of n·l: exact, from the bilinear form (Σλₖ Nₖ)·(Σλₖ wₖ) over the simplex.
    let (psi_nl, sign) = match (l_vectors, &area) {
        (Some(w), _) => cosine_range(frame, &l_cone, w),
        (_, Some(a)) => cosine_range_of(frame, &l_cone, a.q, a.w_max, a.d_min),
        _ => cosine_range(frame, &l_cone, [l_cone.axis; 3]),
    };
    if sign == Sign::NonPositive {
        // n·l ≤ 0 everywhere: this light adds exactly 0.
        return Ok(None);
    }
    let straddle = sign == Sign::Both;
    if straddle && mode == Discontinuity::Conservative {
        return Err(Reason::Discontinuity);
    }
    let mut setup = LightSetup::unbounded(inv_d, psi_nl, straddle, area.as_ref().map(|a| a.emitter));
    setup.att_inf = match (l_vectors, light) {
        (Some(w), _) => {
            1.0 / (w[0].length_squared().max(w[1].length_squared()).max(w[2].length_squared())
                * (1.0 + 2.0e-5))
        }
        (None, Light::Directional { .. }) => 1.0,
        _ => 0.0,
    };
    if inv_d > 0.0 {
        setup.plane_sin = plane_sin(&l_cone, frame.plane);
        setup.near_sin = setup.plane_sin;
        if matches!(light, Light::Point { .. }) && frame.plane != Vec3::ZERO {
            let (height, height_hi) = heights;
            let q = (height * inv_d).min(1.0);
            setup.near_cos = q;
            setup.far_cos = (height_hi * inv_d).min(1.0);
            setup.near_sin = setup.plane_sin.min((1.0 - q * q).max(0.0).sqrt());
            // |n̂·l̂| ≤ H/d + ν·sin γ ≤ H/d_min + ν (n̂'s and l̂'s parts along the plane normal
            // and in the plane; H from above): a light near the plane is seen at grazing angles.
            let grazing = (height_hi * inv_d + frame.n_plane_sin) * (1.0 + 1.0e-5) + 1.0e-6;
            if grazing < 1.0 {
                let lo = (est_acos(grazing) - ANGLE_PAD).max(0.0);
                let (p0, p1) = setup.psi_nl;
                setup.psi_nl = (p0.max(lo), p1.min(PI - lo).max(p0.max(lo)));
            }
        }
    }
    setup.nl_cos = (est_cos(setup.psi_nl.0), est_cos(setup.psi_nl.1));
    let specular = !matches!(material, MaterialKind::Lambert { .. });
    if specular {
        if !(frame.e_min > 0.0) {
            return Err(Reason::Singular);
        }
        let psi_lv = psi_range(&l_cone, &frame.v_cone);
        let m_min = 2.0 * est_cos(0.5 * psi_lv.1);
        if !(psi_lv.1 < PI - 1.0e-3) || !(m_min > 0.0) {
            return Err(Reason::Singular);
        }
        // A cone for ĥ, the tighter of two: (a) ĥ turns at most (|Dl̂| + |Dv̂|)/|l̂ + v̂| per
        // unit |Xδ|, integrated from the centroid; (b) l̂ + v̂ stays within
        // δ = 2 sin(θₗ/2) + 2 sin(θᵥ/2) of m₀ = aₗ + aᵥ, so ĥ is within asin(δ/|m₀|) of m̂₀.
        let speed = (inv_d + 1.0 / frame.e_min) / m_min;
        let half_a = speed * frame.rho_x + ANGLE_PAD;
        let axis_a = unit(l_center + frame.v_center);
        let m0 = l_cone.axis + frame.v_cone.axis;
        let delta = 2.0 * est_sin(0.5 * l_cone.half) + 2.0 * est_sin(0.5 * frame.v_cone.half);
        let half_b = if delta < m0.length() { est_asin(delta / m0.length()) + ANGLE_PAD } else { PI };
        // (a) follows one light point; a polygon needs (b), which holds for all of them.
        let (h_axis, h_half) =
            if half_b < half_a || area.is_some() { (unit(m0), half_b) } else { (axis_a, half_a) };
        setup.h_cone = if h_axis == Vec3::ZERO || !(h_half < MAX_HALF) {
            NO_CONE
        } else {
            Cone { axis: h_axis, half: h_half }
        };
        setup.m_min = m_min;
        setup.psi_lv = psi_lv;
        let (c_nh0, c_nh1) = psi_range(&frame.n_cone, &setup.h_cone);
        setup.psi_nh = if setup.h_cone.half < PI {
            (
                c_nh0.max(hull_distance(setup.h_cone.axis, frame.unit_normals) - setup.h_cone.half),
                c_nh1.min(hull_max_angle(setup.h_cone.axis, frame.unit_normals) + setup.h_cone.half),
            )
        } else {
            (c_nh0, c_nh1)
        };
        let v_vectors = frame.vertices.map(|x| frame.eye - x);
        let (psi_nv, nv_sign) = cosine_range(frame, &frame.v_cone, v_vectors);
        setup.psi_nv = psi_nv;
        setup.nv_sign = nv_sign;
        // The same angle at the same point, from the mirror directions: where n·v > 0, n̂ is
        // the half vector of v̂ and its mirror, and where n·l > 0 of l̂ and its mirror.
        if area.is_none() && setup.h_cone.half > MIRROR_WORTH {
            let mut lo = setup.psi_nh.0;
            if nv_sign == Sign::Positive {
                lo = mirror_lower_angle(&frame.n_cone, &frame.v_cone, &l_cone, l_vectors, lo);
            }
            if !straddle {
                lo = mirror_lower_angle(&frame.n_cone, &l_cone, &frame.v_cone, Some(v_vectors), lo);
            }
            setup.psi_nh.0 = lo.min(setup.psi_nh.1);
        }
        // The same angle from the interpolant of n̂ − ĥ at the corners (`narrowed`), where n̂ and
        // ĥ turn together: n̂'s and ĥ's second derivatives at level 1 bound its error.
        if area.is_none() {
            let l_units = match l_vectors {
                Some(w) => w.map(unit),
                None => [l_cone.axis; 3],
            };
            let h_units: [Vec3; 3] = std::array::from_fn(|k| unit(l_units[k] + unit(v_vectors[k])));
            let n_w = frame.s1.b / frame.r_n;
            let (l_w, v_w) = (frame.s1.a * inv_d, frame.s1.a / frame.e_min);
            let h_w = (l_w + v_w) / m_min;
            let curvature = K23 * (n_w * n_w + h_w * h_w) + K23 * (l_w * l_w + v_w * v_w) / m_min;
            setup.psi_nh = narrowed(setup.psi_nh, frame.unit_normals, h_units, curvature);
        }
        // A polygon's sampled specular part is bounded by its range: kinks do not matter.
        let kinks = if area.is_some() { &MaterialKind::Lambert { kd: Vec3::ZERO } } else { material };
        match *kinks {
            MaterialKind::BlinnPhong { .. } => {
                // max(n·h, 0)^s is C^{1,1} across n·h = 0 only for s ≥ 2.
                let nh = setup.psi_nh;
                if nh.0 < FRAC_PI_2 && nh.1 >= FRAC_PI_2 && parameter.lo < 2.0 {
                    return Err(Reason::Discontinuity);
                }
            }
            MaterialKind::Ggx { .. } => {
                // max(n·v, 0) has a kink in V at n·v = 0: Relaxed bounds it like the
                // terminator's (`LightJets::view_kink`), Conservative shades it per pixel.
                if setup.nv_sign == Sign::Both && mode == Discontinuity::Conservative {
                    return Err(Reason::Discontinuity);
                }
            }
            MaterialKind::Lambert { .. } => {}
        }
    }
    Ok(Some((setup, diff_w, spec_w)))
}

#[allow(clippy::too_many_arguments)]
fn add_light(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    light: &Light,
    mode: Discontinuity,
    split: Split,
    n_max: u32,
    eps: f32,
    refine: bool,
    sum: &mut Sums,
    gd: &Guard,
) -> Result<(), Reason> {
    let Some((setup, diff_w, spec_w)) = plan_light(frame, material, parameter, light, mode)? else {
        return Ok(());
    };

    // This light's bounds, for its diffuse and its specular part apart: second order per
    // term at level 1 and at levels ≥ 2, the Relaxed diffuse first-order parts, and the range
    // of each part's contribution.
    let mut h = [[[Vec3::ZERO; TERM_COUNT]; 2]; 2];
    let mut tot = [[Vec3::ZERO; 2]; 2];
    let (mut lin1, mut linn) = ([Vec3::ZERO; 2], [Vec3::ZERO; 2]);
    let mut range = [Vec3::ZERO; 2];
    let mut spec_sup = Vec3::ZERO;
    let (mut later_diffuse_sup, mut later_diffuse_inf) = (0.0, 0.0);
    // sup E' (1 for a directional light).
    let att = if setup.inv_d > 0.0 { setup.inv_d * setup.inv_d } else { 1.0 };
    // Relaxed: how far n·l can be from 0 on a sub-triangle the terminator crosses, at level 1
    // (the patch's diameters) and per 1/L at levels L ≥ 2 (see [`TerminatorBand`]).
    let terminator = TerminatorBand::new(frame, &setup, frame.dn);
    let (band1, bandn) = if setup.straddle {
        (gd.c(TerminatorBand::new(frame, &setup, frame.d1).at(1.0)), terminator.guarded(0.0, gd))
    } else {
        (0.0, 0.0)
    };
    // Relaxed, GGX: the same for n·v where it may change sign (its kink in V).
    let view_kink =
        matches!(material, MaterialKind::Ggx { .. }) && setup.area.is_none() && setup.nv_sign == Sign::Both;
    let (view1, viewn) =
        if view_kink { (view_band(frame, frame.d1, gd), view_band(frame, frame.dn, gd)) } else { (0.0, 0.0) };
    // The kink's band on a sub-triangle: at most the patch's, and `viewn/L ≤ viewn` at the
    // effective levels `L ≥ 1` the solver may return.
    let later = light_jets(frame, material, parameter, &setup, frame.sn, view1.min(viewn), gd);
    // Every jet is non-decreasing in each attribute's scale and homogeneous in them (first
    // derivatives of degree 1, second of degree 2), and `s₁ ≤ ρ·sₙ`: so the level-1 jets are
    // those at levels ≥ 2 times `ρ` and `ρ²` (docs/estimator.md §2), unless the Uniform split
    // needs each term at level 1 as the GPU computes it, or GGX's view kink takes another band.
    let first = if split == Split::Heuristic && !view_kink {
        later.scaled(frame.rho)
    } else {
        light_jets(frame, material, parameter, &setup, frame.s1, view1, gd)
    };
    for (level, jets) in [&first, &later].into_iter().enumerate() {
        let (diff, spec) = (jets.diffuse, jets.specular);
        for t in 0..TERM_COUNT {
            let spec_h = Vec3::new(spec[0].h[t], spec[1].h[t], spec[2].h[t]);
            h[DIFFUSE][level][t] = diff_w * (diff.h[t] * (0.5 * SAFETY));
            h[SPECULAR][level][t] = spec_w * spec_h * (0.5 * SAFETY);
        }
        let spec_t = Vec3::new(spec[0].t, spec[1].t, spec[2].t);
        tot[DIFFUSE][level] = diff_w * (diff.t * (0.5 * SAFETY));
        tot[SPECULAR][level] = spec_w * spec_t * (0.5 * SAFETY);
        let spec_m = Vec3::new(spec[0].m, spec[1].m, spec[2].m);
        spec_sup = spec_m;
        // Each part lies in [inf, sup] and so does its interpolant; the diffuse part `E'·c` is
        // at least `inf E'·cos ψ_max` where it does not change sign. As shaded, `max(E'·c, 0)`,
        // it is at most `sup E'·max(cos ψ_min, 0)`: below the jet's `m` (`sup E'·max|cos ψ|`)
        // where the light may be behind the surface.
        let (diff_sup, diff_inf) = diffuse_values(&setup, &diff);
        (later_diffuse_sup, later_diffuse_inf) = (diff_sup, diff_inf);
        range = [diff_w * ((diff_sup - diff_inf).max(0.0) * SAFETY), spec_w * spec_m * SAFETY];
        if setup.straddle && level == 1 {
            // Relaxed: with f = E'·c and g = max(f, 0), Lg − g ≤ E_f + ¼·sup E'·osc(c) on a
            // sub-triangle the terminator crosses (docs/estimator.md §4), and
            // osc(c) ≤ sup|Dc|·diam ≤ band/L.
            lin1[DIFFUSE] = diff_w * (TERMINATOR_KINK * SAFETY * gd.mul(att, band1));
            linn[DIFFUSE] = diff_w * (TERMINATOR_KINK * SAFETY * gd.mul(att, bandn));
        }
        if view_kink && level == 1 {
            // Relaxed: the view's kink adds ¼·sup(specular without V)·|V'(0)|·osc(n̂·v̂).
            lin1[SPECULAR] = spec_w * (jets.view_kink * (TERMINATOR_KINK * SAFETY * view1));
            linn[SPECULAR] = spec_w * (jets.view_kink * (TERMINATOR_KINK * SAFETY * viewn));
        }
    }
    // A triangle that needs a high level: the parts' values over the children, where this
    // light's range is not small. Every child is a part of the patch, so the largest of their
    // sups and the smallest of their infs bound the parts over the patch (and so over every
    // sub-triangle of every pattern), often far below the patch's own: the factors' sups
    // (falloff, lobe, Smith, Fresnel) are taken at different points of the patch, and on a
    // child those points are close together.
    let significant = range[DIFFUSE].max_element().max(range[SPECULAR].max_element()) > REFINE_SHARE * eps;
    if refine && setup.area.is_none() && significant {
        if let Some(children) = values_over_children(frame, material, parameter, light, mode) {
            let diff_sup = later_diffuse_sup.min(children.diffuse_sup);
            let diff_inf = later_diffuse_inf.max(children.diffuse_inf);
            range[DIFFUSE] = diff_w * ((diff_sup - diff_inf).max(0.0) * SAFETY);
            spec_sup = spec_sup.min(children.specular_sup);
            range[SPECULAR] = spec_w * spec_sup * SAFETY;
        }
    }
    // The n-independent parts of the specular part: a textured parameter's variation
    // sup|f(α) − f(α')| over the range (Eq. 37), or a polygon's sampled specular part, bounded
    // by its range (which also covers a textured parameter).
    let other = match light {
        Light::Polygon(polygon) => {
            let bound = polygon_specular_bound(material, parameter, &setup, polygon, gd) * SAFETY;
            range[SPECULAR] += bound;
            bound
        }
        _ => spec_w * parameter_variation(material, parameter, &setup, spec_sup),
    };
    // Relaxed: the specular lobe that n·l > 0 switches on jumps on the sub-triangles the
    // terminator crosses, by at most its sup over the band 0 < n·l ≤ band/L.
    let jump = |beta: f32| {
        if setup.straddle && setup.area.is_none() {
            spec_w * spec_sup * (lobe_band_share(material, parameter, &setup, beta) * SAFETY)
        } else {
            Vec3::ZERO
        }
    };
    let top = pattern_level(n_max, n_max);
    let zero1 = jump(band1) + other;
    let zero_top = jump(bandn / top) + other;
    // Per part and channel: the smaller of the part's interpolation bound and its range. The
    // range wins for good if it is below the bound even at n_max (dim or spiky lights, a
    // faint specular lobe on a diffuse surface): at every level up to n_max it is then the
    // better bound. (The error of the sum is at most the sum of the parts' errors.)
    let at_top = [
        tot[DIFFUSE][1] / (top * top) + linn[DIFFUSE] / top,
        tot[SPECULAR][1] / (top * top) + linn[SPECULAR] / top + zero_top,
    ];
    let interpolated = [0, 1].map(|part| [0, 1, 2].map(|c| !(range[part][c] <= at_top[part][c])));
    // The jump at levels ≥ 2 is taken at a lower bound of the final level: the level this
    // light alone needs with the jump at its infimum (the band's width 0). Every level the
    // solver returns is at least that (it adds the other lights' non-negative bounds), and
    // the band only narrows as the level grows.
    let zero_inf = jump(0.0) + other;
    // Relaxed: the same with the diffuse kink at its floor (`TerminatorBand::floor`, the band's limit
    // as the level grows), which only lowers it; at every level the solver returns (`≥ low`) the
    // band's fixed point holds from `low` on.
    let floor_kink = if setup.straddle {
        diff_w * (TERMINATOR_KINK * SAFETY * gd.mul(att, terminator.floor(gd)))
    } else {
        Vec3::ZERO
    };
    let mut low = 1.0f32;
    for c in 0..3 {
        let (d, sp) = (interpolated[DIFFUSE][c], interpolated[SPECULAR][c]);
        if d || sp {
            let a = if d { tot[DIFFUSE][1][c] } else { 0.0 } + if sp { tot[SPECULAR][1][c] } else { 0.0 };
            let b = if d { floor_kink[c] } else { 0.0 } + if sp { linn[SPECULAR][c] } else { 0.0 };
            let z = if sp { zero_inf[c] } else { 0.0 };
            low = low.max(level_for(a, b, z, eps));
        }
    }
    sum.low = sum.low.max(low);
    let mut bandn = bandn;
    if setup.straddle {
        bandn = bandn.min(terminator.guarded(low, gd));
        linn[DIFFUSE] = diff_w * (TERMINATOR_KINK * SAFETY * gd.mul(att, bandn));
    }
    let zeron = jump(bandn / low) + other;
    let whole_lobe =
        if setup.straddle && setup.area.is_none() { spec_w * spec_sup * SAFETY } else { Vec3::ZERO };
    for (k, &n) in GRID_LEVELS.iter().enumerate() {
        if n > n_max {
            break;
        }
        let l = pattern_level(n, n);
        // The jump at `l`: at or above `low` the one taken there bounds it (the band only
        // narrows), below it the whole lobe does (cheap, and then the range is no larger).
        let zero_l = if l >= low { zeron } else { whole_lobe + other };
        // The diffuse kink at `l` itself (valid below `low` too; at most `att·bandn`, which
        // passed the guard).
        let kink_l = if setup.straddle {
            diff_w * (TERMINATOR_KINK * SAFETY * (att * terminator.at(l)))
        } else {
            Vec3::ZERO
        };
        for c in 0..3 {
            let d = (tot[DIFFUSE][1][c] / (l * l) + kink_l[c]).min(range[DIFFUSE][c]);
            let sp =
                (tot[SPECULAR][1][c] / (l * l) + linn[SPECULAR][c] / l + zero_l[c]).min(range[SPECULAR][c]);
            sum.grid[k][c] += d + sp;
        }
    }
    for c in 0..3 {
        let one_d = (tot[DIFFUSE][0][c] + lin1[DIFFUSE][c]).min(range[DIFFUSE][c]);
        let one_s = (tot[SPECULAR][0][c] + lin1[SPECULAR][c] + zero1[c]).min(range[SPECULAR][c]);
        sum.one[c] += one_d + one_s;
        for part in [DIFFUSE, SPECULAR] {
            if !interpolated[part][c] {
                sum.range[c] += range[part][c];
                continue;
            }
            for t in 0..TERM_COUNT {
                sum.h1[t][c] += h[part][0][t][c];
                sum.hn[t][c] += h[part][1][t][c];
            }
            sum.tn[c] += tot[part][1][c];
            sum.lin1[c] += lin1[part][c];
            sum.linn[c] += linn[part][c];
            if part == SPECULAR {
                sum.jumps1[c] += zero1[c];
                sum.jumps[c] += zeron[c];
            }
        }
    }
    Ok(())
}

/// The shaded diffuse part `max(E'·c, 0)` per unit weight lies in `[inf, sup]`: at least
/// `inf E'·cos ψ_max` where it does not change sign, and at most `sup E'·max(cos ψ_min, 0)`
/// (below the jet's `m`, `sup E'·max|cos ψ|`, where the light may be behind the surface).
fn diffuse_values(setup: &LightSetup, diffuse: &Jet) -> (f32, f32) {
    let att = if setup.inv_d > 0.0 { setup.inv_d * setup.inv_d } else { 1.0 };
    let inf = setup.att_inf * setup.nl_cos.1.max(0.0) * (1.0 - 1.0e-5);
    let sup = if setup.area.is_none() { diffuse.m.min(att * setup.nl_cos.0.max(0.0)) } else { diffuse.m };
    (sup, inf)
}

/// The values of a light's two parts (per unit weight) over a set of sub-triangles.
struct ChildValues {
    diffuse_sup: f32,
    diffuse_inf: f32,
    specular_sup: Vec3,
}

/// Child `k` (`0..4`) of the midpoint subdivision of the triangle with corners `c` (positions
/// or normals, each affine over the patch as the interpolated attributes are).
fn midpoint_child(c: [Vec3; 3], k: usize) -> [Vec3; 3] {
    let ab = (c[0] + c[1]) * 0.5;
    let bc = (c[1] + c[2]) * 0.5;
    let ca = (c[2] + c[0]) * 0.5;
    match k {
        0 => [c[0], ab, ca],
        1 => [ab, c[1], bc],
        2 => [ca, bc, c[2]],
        _ => [bc, ca, ab],
    }
}

/// The parts' values of a point or directional light over the [`REFINE_CHILDREN`] children of
/// the patch (its midpoint subdivision), each child planned and its jets' sups taken as for a
/// patch of its own: the largest sups and the smallest inf. `None` where a child cannot be
/// bounded (a singularity, a kink its own cones cannot exclude, or a bound that saturates): the
/// patch's own values stand then.
fn values_over_children(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    light: &Light,
    mode: Discontinuity,
) -> Option<ChildValues> {
    let gd = Guard::default();
    let mut values = ChildValues { diffuse_sup: 0.0, diffuse_inf: f32::MAX, specular_sup: Vec3::ZERO };
    for k in 0..REFINE_CHILDREN {
        let positions = midpoint_child(frame.vertices, k);
        let normals = midpoint_child(frame.normals, k);
        let child = Frame::new(&TriangleInput { positions, normals, eye: frame.eye });
        match plan_light(&child, material, parameter, light, mode) {
            Err(_) => return None,
            // The light adds exactly 0 on this child.
            Ok(None) => values.diffuse_inf = 0.0,
            Ok(Some((setup, _, _))) => {
                // GGX's `V` where `n·v` changes sign: its value at the band 0 is `1/k`, its sup.
                let jets = light_jets(&child, material, parameter, &setup, child.sn, 0.0, &gd);
                let (sup, inf) = diffuse_values(&setup, &jets.diffuse);
                values.diffuse_sup = values.diffuse_sup.max(sup);
                values.diffuse_inf = values.diffuse_inf.min(inf);
                let specular = Vec3::new(jets.specular[0].m, jets.specular[1].m, jets.specular[2].m);
                values.specular_sup = values.specular_sup.max(specular);
            }
        }
    }
    (!gd.bad.get()).then_some(values)
}

/// The two parts of a light's contribution, bounded apart: index of the diffuse part...
const DIFFUSE: usize = 0;
/// ...and of the specular part.
const SPECULAR: usize = 1;

/// Relaxed: a bound on `|n̂·l̂|` (and on its oscillation) over the sub-triangles that the
/// terminator crosses, of diameters (positions, normals) `d/L` at the effective level `L`. It
/// has a zero of `c = n̂·l̂`, so every point is within `sup|Dc|·diam` of 0, and
/// `Dc = Dn̂·l̂ + n̂·Dl̂` with `|Dn̂| ≤ |Nδ|/min|N|` and `n̂·Dl̂ = (n̂·Xδ − c·(l̂·Xδ))/d`, at most
/// `(ν + σ·|c|)|Xδ|/d` (`ν`, `σ`: the normals' and the light's sines to the plane normal;
/// position steps lie in the plane). `|c| ≤ c_max` (the angle range), and on the sub-triangle
/// `c* = sup|c| ≤ b_N + (ν + σc*)·b_X` (`b = d/L` over `min|N|` and `d_min`), so
/// `c* ≤ (b_N + ν b_X)/(1 − σ b_X)`.
///
/// The scalars that do not depend on the level are taken once per light, so that the grid
/// levels pay a division and a few minima each.
struct TerminatorBand {
    /// `b_N·L = d_b/min|N|`.
    normal: f32,
    /// `b_X·L = d_a/d_min`.
    light: f32,
    /// `ν`, the normals' sine to the plane normal.
    nu: f32,
    /// `σ`, the light's.
    sigma: f32,
    /// `c_max = max|cos|` over the angle range.
    c_max: f32,
    /// `(b_N + ν b_X)·L`, the fixed point's numerator.
    fixed: f32,
    /// `σ b_X·L`, subtracted from `L` in the fixed point's denominator.
    held: f32,
    /// `cos ψ_min − cos ψ_max`, the oscillation of `n̂·l̂` over the whole triangle.
    oscillation: f32,
}

impl TerminatorBand {
    fn new(frame: &Frame, st: &LightSetup, d: Scale) -> TerminatorBand {
        let (normal, light) = (d.b / frame.r_n, d.a * st.inv_d);
        TerminatorBand {
            normal,
            light,
            nu: frame.n_plane_sin,
            sigma: st.plane_sin,
            c_max: st.nl_cos.0.abs().max(st.nl_cos.1.abs()),
            fixed: normal + frame.n_plane_sin * light,
            held: st.plane_sin * light,
            oscillation: st.nl_cos.0 - st.nl_cos.1,
        }
    }

    /// The band per `1/L` at every effective level `L ≥ above`, with `c*` taken at `above`
    /// (0: the angle range alone), which only grows as `L` falls to `above`; unguarded.
    fn per_level(&self, above: f32) -> f32 {
        let mut c_star = self.c_max;
        let room = above - self.held;
        if room > 0.0 {
            c_star = c_star.min(self.fixed / room);
        }
        let across = (self.nu + self.sigma * c_star).min(1.0);
        self.normal + self.light * across
    }

    /// [`TerminatorBand::per_level`] with the guard.
    fn guarded(&self, above: f32, gd: &Guard) -> f32 {
        gd.c(self.per_level(above))
    }

    /// The band at one effective level `l`, and at most the oscillation of `n̂·l̂` over the
    /// whole triangle, which does not fall with the level (unguarded: at most
    /// `guarded(0)/l`).
    fn at(&self, l: f32) -> f32 {
        (self.per_level(l) / l).min(self.oscillation)
    }

    /// The band's floor as the level grows (`c* → 0`): `b_N + ν·b_X` per `1/L`.
    fn floor(&self, gd: &Guard) -> f32 {
        gd.c(self.normal + self.light * self.nu.min(1.0))
    }
}

/// Relaxed, GGX: the same for the view's kink, `|n̂·v̂|` on a sub-triangle of diameters `d`
/// that `n·v = 0` crosses: `|D(n̂·v̂)| ≤ |Nδ|/min|N| + |Xδ|/e_min`.
fn view_band(frame: &Frame, d: Scale, gd: &Guard) -> f32 {
    gd.c(d.b / frame.r_n + d.a / frame.e_min)
}

/// Relaxed: the factor `≤ 1` by which the specular lobe's sup over the band `0 < n̂·l̂ ≤ β`
/// is below its sup over the triangle (the latter is what the jets' `m` bound).
/// - Blinn-Phong, `(n·h)^s`: ĥ bisects l̂ and v̂, so `∠(n, h) ≥ ∠(n, l) − ∠(l, v)/2`, and
///   `∠(n, l) ≥ acos β` on the band: `(n·h)^s ≤ cos^s(max(ψ_nh,min, acos β − ψ_lv,max/2))`.
/// - GGX: the specular part carries `G(c) = c/(c(1−k)+k)`, increasing in `c` and decreasing
///   in `k`: on the band it is at most `G(β)` at the smallest `k`, against `G(c_max)` in the
///   jets.
fn lobe_band_share(material: &MaterialKind, parameter: ParameterRange, st: &LightSetup, beta: f32) -> f32 {
    match *material {
        MaterialKind::Lambert { .. } => 0.0,
        MaterialKind::BlinnPhong { .. } => {
            let h0 = st.psi_nh.0;
            let edge = est_acos(beta.min(1.0)) - ANGLE_PAD - 0.5 * st.psi_lv.1;
            if !(edge > h0) {
                return 1.0;
            }
            let (ce, ch) = (est_cos(edge), est_cos(h0));
            if !(ch > 0.0) || !(ce < ch) {
                1.0
            } else if !(ce > 0.0) {
                0.0
            } else {
                est_pow(ce / ch, parameter.lo)
            }
        }
        MaterialKind::Ggx { .. } => {
            let k = 0.5 * ggx_alpha(parameter.lo);
            let c1 = st.nl_cos.0;
            if !(beta < c1) {
                1.0
            } else {
                (beta * (c1 * (1.0 - k) + k)) / (c1 * (beta * (1.0 - k) + k))
            }
        }
    }
}

/// An upper bound, per channel, of a polygonal light's sampled specular part anywhere on the
/// triangle (`f` the specular integrand, [`crate::shading::polygon_light`]). A light sample adds
/// `w_l f/p_l ≤ f/p_l` (`w ∈ [0, 1]`); a BRDF sample adds `f (v c_b/Σcₖpₖ + (1 − v)/Σpₖ)`
/// (clamped optimal MIS, B.3) `≤ v f/p_b + (1 − v) f/p_l`. So the estimate is at most
/// `(2 − v) sup f/p_l + v sup f/p_b` over the directions to the polygon, with:
/// - Blinn-Phong, `f = L ks (n·h)^s`: `f/p_light ≤ L ks cos^s(ψ_nh,min) Ω_max` (solid angle),
///   times `max n·l / min n·l` for projected solid angle (`p = n·l/Ω⊥`, `Ω⊥ ≤ Ω max n·l`);
///   `f/p_brdf = L ks 8π (v·h)/(s + 1) ≤ 8π L ks/(s + 1)`.
/// - GGX, `f = L D F V (n·l)/4`: `f/p_light ≤ L D_max F_max V_max max(n·l) Ω_max / 4` for either
///   technique; `f/p_brdf = L F (n·l) V (v·h)/(n·h) ≤ L F_max min(1/((min n·v (1−k) + k) min n·h),
///   2 V_max)` (since `(n·l)/((n·l)(1−k) + k) ≤ 1`, and `n·h ≥ (n·l + n·v)/2`).
///
/// `Ω_max = min(2π, A cos_max/d_min²)`. Shininess and roughness take their worst ends of the
/// range (and D its peak over α). A bound that cannot be formed (`min n·l` or `min n·h` zero)
/// saturates the guard, which means per-pixel shading.
fn polygon_specular_bound(
    material: &MaterialKind,
    parameter: ParameterRange,
    st: &LightSetup,
    polygon: &PolygonLight,
    gd: &Guard,
) -> Vec3 {
    let Some(emitter) = st.area else {
        return Vec3::ZERO;
    };
    let radiance = polygon.radiance();
    let cos_l_min = st.nl_cos.1.max(0.0);
    let cos_l_max = st.nl_cos.0.min(1.0);
    let cos_y_max = est_cos(emitter.0).min(1.0);
    let omega = gd.c(gd.mul(polygon.area * cos_y_max, gd.mul(st.inv_d, st.inv_d)).min(2.0 * PI));
    let (h0, h1) = st.psi_nh;
    let projected = polygon.sampling.technique == PolygonSampling::ProjectedSolidAngle;
    match *material {
        MaterialKind::Lambert { .. } => Vec3::ZERO,
        MaterialKind::BlinnPhong { ks, .. } => {
            let s0 = parameter.lo;
            let peak = if h0 < FRAC_PI_2 { est_pow(est_cos(h0), s0) } else { 0.0 };
            let mut light = gd.mul(peak, omega);
            if projected && light > 0.0 {
                light = gd.c(light * cos_l_max / cos_l_min);
            }
            let brdf = 8.0 * PI / (s0 + 1.0);
            radiance * ks * mis_bound(light, brdf, polygon.sampling.mis_visibility, gd)
        }
        MaterialKind::Ggx { f0, .. } => {
            let (alpha_lo, alpha_hi) = (ggx_alpha(parameter.lo), ggx_alpha(parameter.hi));
            let k = 0.5 * alpha_lo;
            let cos_h = if h0 < FRAC_PI_2 { est_cos(h0) } else { 0.0 };
            let mut d_max = ggx_d(cos_h, alpha_lo).max(ggx_d(cos_h, alpha_hi));
            if alpha_hi > alpha_lo && cos_h > 0.0 {
                // D(c, α) peaks over α at α² = (1 − c²)/c².
                let s2 = (1.0 - cos_h * cos_h).max(0.0);
                let peak = (s2 / (cos_h * cos_h)).sqrt().max(alpha_lo).min(alpha_hi);
                d_max = d_max.max(ggx_d(cos_h, peak));
            }
            let cos_v_min = est_cos(st.psi_nv.1).max(0.0);
            let v_side = cos_v_min * (1.0 - k) + k;
            let v_max = 1.0 / ((cos_l_min * (1.0 - k) + k) * v_side);
            let light =
                if h0 < FRAC_PI_2 { gd.mul(gd.mul(0.25 * d_max, v_max), omega * cos_l_max) } else { 0.0 };
            // (v·h)/(n·h) ≤ 1/min n·h, and also ≤ 2/(n·l + n·v) (n·h = (n·l + n·v)/|l + v|),
            // which with (n·l)/(n·l + n·v) ≤ 1 leaves 2 V: finite where the h cone is wide.
            let cos_h_min = est_cos(h1.min(FRAC_PI_2)).max(0.0);
            let brdf =
                if v_side * cos_h_min > 0.5 / v_max { 1.0 / (v_side * cos_h_min) } else { 2.0 * v_max };
            let om = 1.0 - est_cos(0.5 * st.psi_lv.1).clamp(0.0, 1.0);
            let f_max = f0 + (Vec3::ONE - f0) * om.powi(5);
            radiance * f_max * mis_bound(light, brdf, polygon.sampling.mis_visibility, gd)
        }
    }
}

/// `(2 − v) sup f/p_l + v sup f/p_b` (see [`polygon_specular_bound`]).
fn mis_bound(light: f32, brdf: f32, visibility: f32, gd: &Guard) -> f32 {
    gd.c(gd.mul(2.0 - visibility, light) + gd.mul(visibility, brdf))
}

/// The jets of one light's diffuse part (`E'·(n·l)`, per unit weight) and specular part
/// (per channel, per unit weight), at pattern scale `s`.
/// The jet of a point light's falloff `E' = 1/d²` over the patch, for `1/d ≤ inv_d` and
/// `sin γ ≤ plane_sin` (`γ`: the angle between `l̂` and the patch's normal) at pattern scale `a`:
/// with `s = d²`, `Ds = 2l·Dl` and `D²s = 2|Dl|²` (`l` is affine), so `DE' = −2(l̂·Dl)/d³` and
/// `D²E' = (8(l̂·Dl)² − 2|Dl|²)/d⁴`; `Dl = −Xδ` lies in the plane, so `|l̂·Dl| ≤ sin γ·a`.
fn attenuation_jet(inv_d: f32, plane_sin: f32, a: f32, gd: &Guard) -> Jet {
    let id2 = gd.mul(inv_d, inv_d);
    let a_id = gd.mul(a, inv_d);
    let sg = plane_sin;
    let mut h = NO_H;
    let a_id2 = gd.mul(a_id, a_id);
    let k = (8.0 * sg * sg - 2.0).max(2.0);
    let t = gd.mul(k * a_id2, id2);
    h[Term::Attenuation as usize] = t;
    Jet { m: id2, g: gd.mul(2.0 * sg * a_id, id2), h, t }
}

/// The jet of a point light's diffuse factor `n̂·I` with the irradiance field
/// `I = r/|r|³`, `r = p − x`, bounded as one field (`docs/estimator.md` §2, "The irradiance
/// field"): with `a = Xδ` in the plane, `c = r̂·â` (`|c| ≤ σ = sin γ`), `d = |r|`,
/// `DI = (−a + 3r̂(r̂·a))/d³`, `|DI| = |a|√(1 + 3c²)/d³`, and
/// `D²I = (−6c|a|a + (15c² − 3)|a|²r̂)/d⁴`, `|D²I| = √(45c⁴ − 18c² + 9)·|a|²/d⁴`; the normal
/// sees `n̂·D²I ≤ (6σν + max(3, |15σ² − 3|)·max|cos ψ|)·|a|²/d⁴` (`ν`: the normals' sine to
/// the plane normal). Each part also keeps the product rule's bound of `E'·(n̂·l̂)`, the
/// smaller is taken.
fn irradiance_jet(frame: &Frame, st: &LightSetup, n: &Field, a: f32, gd: &Guard) -> Jet {
    let angles = Angles::with_cosines(st.psi_nl, st.nl_cos);
    let (sg, nu, c) = (st.plane_sin, frame.n_plane_sin, angles.c_max);
    let id2 = gd.mul(st.inv_d, st.inv_d);
    let a_id = gd.mul(a, st.inv_d);
    let a_id2 = gd.mul(a_id, a_id);
    let sg2 = sg * sg;
    // Along sin²γ = 1 − H²/d² the whole-vector bounds below times d⁻³ and d⁻⁴ fall as d grows:
    // they are taken where the light is nearest (`near_sin`, `d_min`).
    let near2 = st.near_sin * st.near_sin;
    // |DI|·d³/|a|, and its normal part |n̂·DI|·d³/|a| (with the product rule's 2σ cos + sin).
    let speed = (1.0 + 3.0 * near2).sqrt();
    let along_normal = speed.min(nu + 3.0 * c * sg).min(2.0 * sg * c + angles.s_max);
    // |n̂·D²I|·d⁴/|a|²: the whole vector, its normal part, and the product rule's
    // E''·cos + 2E'·(cos)' + E'·(l̂ part of cos'').
    let whole = (45.0 * near2 * near2 - 18.0 * near2 + 9.0).max(9.0).sqrt();
    let projected = 6.0 * sg * nu + (15.0 * sg2 - 3.0).abs().max(3.0) * c;
    let product_rule = (8.0 * sg2 - 2.0).max(2.0) * c
        + 4.0 * sg * angles.s_max
        + angles.phi.min(c + 2.0 * angles.s_max * sg);
    let light_k = whole.min(projected).min(product_rule).min(along_plane(st, nu, c)).min(tilted(st, nu));
    // Dn̂·DI: |Dn̂| ≤ w, and |DI|, or the product rule's 2E'·2σ·sin·w + E'·2w·|Dl̂|.
    let cross_k = speed.min(2.0 * sg * angles.s_max + 1.0);
    let mut h = NO_H;
    let hn = gd.mul(angles.seen(n, gd), id2);
    let hd = gd.mul(gd.mul(2.0 * cross_k * n.w, a_id), id2);
    let hl = gd.mul(light_k * a_id2, id2);
    h[Term::Normal as usize] = hn;
    h[Term::Dot as usize] = hd;
    h[Term::Light as usize] = hl;
    let g = gd.c(gd.mul(angles.s_max * n.w, id2) + gd.mul(along_normal * a_id, id2));
    Jet { m: gd.mul(c, id2), g, h, t: gd.c(hn + hd + hl) }
}

/// The normal part of `n̂·D²I` once more, `≤ 6σν + c·max(|15s² − 3|)` times `|a|²/d⁴`, with the
/// falloff and `s = sin γ` taken together along `sin²γ = 1 − H²/d²`: `|15s² − 3|/d⁴ =
/// |12d² − 15H²|/d⁶`. In units of `1/d_min⁴`, with `q = d²/d_min² ≥ 1` and `h = H/d_min`
/// (`near_cos`, `H` from below), its positive part peaks at `q = 1.875h²` and its negative part
/// is at most 3 (`q ≥ h²`). Returns the coefficient of `|a|²/d_min⁴`.
fn along_plane(st: &LightSetup, nu: f32, c: f32) -> f32 {
    let h2 = st.near_cos * st.near_cos;
    let q = (1.875 * h2).max(1.0);
    let rising = (12.0 * q - 15.0 * h2).max(0.0) / (q * q * q);
    6.0 * st.plane_sin * nu + rising.max(3.0) * c
}

/// The light part `n̂·D²I[a, a]` with the normal split along the plane normal and in the
/// plane, `n̂ = cos ν·n̂ₚ + sin ν·t̂`, and `r̂ = k·n̂ₚ + s·ρ̂` (`k = H/d`, `s = sin γ`): with `α`, `β`
/// the angles of `â` and `t̂` from `ρ̂`, `n̂·D²I·d⁴/|a|² = cos ν·k·(15s²cos²α − 3) +
/// sin ν·s·G`, `G = cos β·((15s² − 6)cos²α − 3) − 3 sin 2α·sin β`. The first part is at most
/// `k·max(3, |12 − 15k²|)`, which with `k = hz` (`h = H/d_min`, `z = d_min/d ≤ 1`) and the
/// falloff `z⁴` is at most `h·max(24/7, 12 − 15h²)` (`h` from above outside, from below
/// inside); `s·max|G|` is `s|15s² − 9|` for `s² ∉ [0.2, 0.8]` and `√7.2` inside, non-decreasing
/// in `s`, so at most its value at `σ`. Returns the coefficient of `|a|²/d_min⁴`.
fn tilted(st: &LightSetup, nu: f32) -> f32 {
    let h2 = st.near_cos * st.near_cos;
    let rising = if 7.0 * h2 <= 4.0 {
        12.0 - 15.0 * h2
    } else {
        let x = 4.0 / (7.0 * h2);
        (TILT_PEAK * x * x * x.sqrt()).max(3.0)
    };
    let s = st.plane_sin;
    let s2 = s * s;
    let turning = if s2 < 0.2 {
        s * (9.0 - 15.0 * s2)
    } else if s2 <= 0.8 {
        TILT_FLAT
    } else {
        s * (15.0 * s2 - 9.0)
    };
    st.far_cos * rising + nu * turning
}

/// One light's jets at one pattern scale.
struct LightJets {
    diffuse: Jet,
    /// Per channel (GGX's Fresnel colours it).
    specular: [Jet; 3],
    /// GGX where `n·v` changes sign, per channel: the sup of the specular part without its view
    /// half `V`, times `|V'|` at the kink (`docs/estimator.md` §4, "The view's kink"); else 0.
    view_kink: Vec3,
}

impl LightJets {
    /// The jets at a scale `ρ` times this one's (`ρ ≤ 1`): values kept, first derivatives
    /// times `ρ`, second times `ρ²`.
    fn scaled(&self, rho: f32) -> LightJets {
        let rho2 = rho * rho;
        let at = |j: &Jet| Jet { m: j.m, g: j.g * rho, h: j.h.map(|h| h * rho2), t: j.t * rho2 };
        LightJets {
            diffuse: at(&self.diffuse),
            specular: self.specular.each_ref().map(at),
            view_kink: self.view_kink,
        }
    }
}

/// The unit fields `n̂` and `l̂` of one light at pattern scale `s`.
fn normal_and_light_fields(frame: &Frame, st: &LightSetup, s: Scale, gd: &Guard) -> (Field, Field) {
    let n_w = gd.c(s.b / frame.r_n);
    let n = Field { w: n_w, radial: n_w.min(gd.c(s.g / frame.r_n)), x: 0.0, term: Term::Normal };
    let l_w = gd.mul(s.a, st.inv_d);
    let l = Field { w: l_w, radial: gd.mul(l_w, st.plane_sin), x: 0.0, term: Term::Light };
    (n, l)
}

/// The unit fields `v̂` and `ĥ = (l̂ + v̂)/|l̂ + v̂|` (specular lights only: `m_min > 0`).
fn view_and_half_fields(frame: &Frame, st: &LightSetup, l: &Field, s: Scale, gd: &Guard) -> (Field, Field) {
    let v_w = gd.c(s.a / frame.e_min);
    let v = Field { w: v_w, radial: v_w, x: 0.0, term: Term::View };
    let h_w = gd.c((l.w + v.w) / st.m_min);
    let h =
        Field { w: h_w, radial: h_w, x: gd.c(K23 * (l.w * l.w + v.w * v.w) / st.m_min), term: Term::Half };
    (v, h)
}

/// The jets of one light at pattern scale `s`; `view_band` bounds `|n̂·v̂|` on the
/// sub-triangles at this scale that the view's kink crosses (used where it may).
fn light_jets(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    st: &LightSetup,
    s: Scale,
    view_band: f32,
    gd: &Guard,
) -> LightJets {
    let (n, l) = normal_and_light_fields(frame, st, s, gd);
    let att =
        if st.inv_d > 0.0 { attenuation_jet(st.inv_d, st.plane_sin, s.a, gd) } else { Jet::constant(1.0) };
    // A polygon: each of its points is a point light whose intensity has the emitter's cosine
    // `(−n_e)·l̂`, a cosine between a constant direction and l̂.
    let att = match st.area {
        Some(emitter) => {
            let fixed = Field { w: 0.0, radial: 0.0, x: 0.0, term: Term::Light };
            product([att, cosine(&fixed, &l, emitter, gd)], gd)
        }
        None => att,
    };
    let diffuse = if st.inv_d > 0.0 && st.area.is_none() {
        irradiance_jet(frame, st, &n, s.a, gd)
    } else {
        product([att, cosine_at(&n, &l, &Angles::with_cosines(st.psi_nl, st.nl_cos), gd)], gd)
    };
    let zero = Jet::constant(0.0);
    let only_diffuse = LightJets { diffuse, specular: [zero; 3], view_kink: Vec3::ZERO };
    if matches!(material, MaterialKind::Lambert { .. }) || st.area.is_some() {
        return only_diffuse;
    }

    let (v, h) = view_and_half_fields(frame, st, &l, s, gd);
    // n·h where it is positive (both lobes vanish, with their derivatives, below 0).
    let (h0, h1) = (st.psi_nh.0, st.psi_nh.1.min(FRAC_PI_2));
    let w_nh = gd.c(n.w + h.w);

    match *material {
        MaterialKind::Lambert { .. } => unreachable!(),
        MaterialKind::BlinnPhong { .. } => {
            if st.psi_nh.0 >= FRAC_PI_2 {
                return only_diffuse;
            }
            // A shininess anywhere in [s₀, s₁] (s₀ ≥ 1): every factor s, s − 1 grows with s
            // and every power of t = cos ψ ≤ 1 shrinks, so s₁ and s₀ bound them separately.
            let c_nh = cosine(&n, &h, (h0, h1), gd);
            let curv = curvature(&n, &h, (h0, h1), gd);
            let t = power_jet(&c_nh, &curv, (parameter.lo, parameter.hi), (h0, h1), w_nh, gd);
            let spec = product([att, t], gd);
            LightJets { specular: [spec; 3], ..only_diffuse }
        }
        MaterialKind::Ggx { f0, .. } => {
            // The roughness-dependent factors D, G and V at the ends of the roughness range
            // and where D(n·h at its smallest angle) peaks over α (α² = sin²/cos²), combined
            // by their largest bounds (paper Eq. 36).
            let (alpha_lo, alpha_hi) = (ggx_alpha(parameter.lo), ggx_alpha(parameter.hi));
            let mut alphas = [alpha_lo; 3];
            let mut count = 1;
            if alpha_hi > alpha_lo {
                alphas[1] = alpha_hi;
                count = 2;
                if st.psi_nh.0 < FRAC_PI_2 {
                    let s2 = est_sin(h0) * est_sin(h0);
                    alphas[2] = (s2 / (1.0 - s2)).sqrt().max(alpha_lo).min(alpha_hi);
                    count = 3;
                }
            }
            let mut factors = ggx_factor_jets(&n, &l, &v, &h, st, (h0, h1), w_nh, alphas[0], view_band, gd);
            for &alpha in &alphas[1..count] {
                let more = ggx_factor_jets(&n, &l, &v, &h, st, (h0, h1), w_nh, alpha, view_band, gd);
                factors = [0, 1, 2].map(|f| jet_max(&factors[f], &more[f]));
            }
            let [gjet, vjet, djet] = factors;

            let vh = half_cosine_jet(&l, &v, st.psi_lv.1, st.m_min, gd);
            // |V'| at the kink, largest at the smallest k.
            let k = 0.5 * alpha_lo;
            let kink_slope = (1.0 - k) / (k * k);
            let mut spec = [zero; 3];
            let mut view_kink = Vec3::ZERO;
            for (c, out) in spec.iter_mut().enumerate() {
                let fjet = fresnel_jet(f0[c], &vh, gd);
                let p = product([att, djet, fjet, gjet, vjet], gd);
                *out = Jet { m: 0.25 * p.m, g: 0.25 * p.g, h: scaled(&p.h, 0.25, gd), t: gd.mul(p.t, 0.25) };
                if st.nv_sign == Sign::Both {
                    let without_v = gd.mul(gd.mul(gd.mul(att.m, djet.m), fjet.m), gjet.m);
                    view_kink[c] = gd.mul(0.25 * without_v, kink_slope);
                }
            }
            LightJets { specular: spec, view_kink, ..only_diffuse }
        }
    }
}

/// The roughness-dependent GGX factors `[G, V, D]` (the Smith halves with the cosines folded
/// in, and the distribution) at one `alpha`.
#[allow(clippy::too_many_arguments)]
fn ggx_factor_jets(
    n: &Field,
    l: &Field,
    v: &Field,
    h: &Field,
    st: &LightSetup,
    nh: (f32, f32),
    w_nh: f32,
    alpha: f32,
    view_band: f32,
    gd: &Guard,
) -> [Jet; 3] {
    let (n, l, v, h) = (*n, *l, *v, *h);
    let (h0, h1) = nh;
    let k = 0.5 * alpha;

    // G = c/(c(1−k)+k) with c = n·l ≥ 0 (the gate keeps c ≥ 0 where G is used).
    let nl = (st.psi_nl.0, st.psi_nl.1.min(FRAC_PI_2));
    let c_g = cosine(&n, &l, nl, gd);
    let gjet = smith_g_jet(&c_g, nl, k, gd);

    // V_v = 1/(max(n·v, 0)(1−k)+k): constant 1/k where n·v ≤ 0 throughout.
    let vjet = match st.nv_sign {
        Sign::NonPositive => Jet::constant(1.0 / k),
        Sign::Positive => {
            let nv = (st.psi_nv.0, st.psi_nv.1.min(FRAC_PI_2));
            let c_v = cosine(&n, &v, nv, gd);
            smith_v_jet(&c_v, nv, k, gd)
        }
        Sign::Both => smith_v_kink_jet(&cosine(&n, &v, st.psi_nv, gd), k, view_band, gd),
    };

    // D(t), t = n·h = cos ψ, with s2 = sin²ψ and u = α² + (1−α²)s2:
    // D = α²/(πu²), D' = 4α²β t/(πu³), D'' = 4α²β(u + 6βt²)/(πu⁴), β = 1 − α².
    let djet = if st.psi_nh.0 >= FRAC_PI_2 {
        Jet::constant(alpha * alpha / PI)
    } else {
        let c_nh = cosine(&n, &h, (h0, h1), gd);
        let curv = curvature(&n, &h, (h0, h1), gd);
        ggx_d_jet(&c_nh, &curv, h0, h1, w_nh, alpha, gd)
    };
    [gjet, vjet, djet]
}

/// Jet of the Blinn-Phong lobe `T = t^s`, `t = cos ψ = n·h` with jet `c` and angle in
/// `[ψ₀, ψ₁] ⊂ [0, π/2]` moving at most `w` (`|Dn̂| + |Dĥ|`), for any shininess `s` in
/// `[s₀, s₁]` (`s₀ ≥ 1`): `|DT| ≤ s cos^(s−1)ψ sin ψ·w`, jointly maximised over ψ;
/// `|D²T| ≤ s(s−1) cos^(s−2)ψ sin²ψ·w² + s t^(s−1)|D²t|`. Every factor `s`, `s − 1` grows
/// with `s` and every power of `t ≤ 1` shrinks, so `s₁` and `s₀` bound them separately.
fn power_jet(
    c: &Jet,
    curv: &Curvature,
    (s0, s1): (f32, f32),
    (h0, h1): (f32, f32),
    w: f32,
    gd: &Guard,
) -> Jet {
    let chi = est_cos(h0);
    let peak = est_pow(chi, s0);
    let g = gd.c(s1 * max_cos_sin(s0 - 1.0, 1.0, h0, h1) * w);
    let slope = s1 * est_pow(chi, s0 - 1.0);
    let mut hh = scaled(&c.h, slope, gd);
    let mut ht = gd.mul(c.t, slope);
    let mut hp = 0.0;
    let mut net = 0.0;
    if s1 > 1.0 {
        let k = s1 * (s1 - 1.0) * max_cos_sin(s0 - 2.0, 2.0, h0, h1);
        let w2 = gd.mul(w, w);
        hp = gd.mul(k, w2);
        hh[Term::Power as usize] = gd.c(hh[Term::Power as usize] + hp);
        ht = gd.c(ht + hp);
        // The profile's part less the turning part, on the turn's share of w² (below).
        net = if s0 > 2.0 {
            let c1 = power_net_coefficient(s0, s1, chi, est_cos(h1).max(0.0));
            gd.c(gd.mul(c1, curv.turn) + gd.mul(k, (w2 - curv.turn).max(0.0)))
        } else {
            hp
        };
    }
    // D²T = s·t^(s−2)·[(s−1)(Dt)² + t·D²t]: the power's part is ≥ 0 and the cosine's turning
    // part ≤ 0, so the larger of the two (plus the rest) bounds it, not their sum.
    let turning = gd.mul(gd.mul(s1, peak), curv.turn);
    let joint = gd.c(gd.mul(slope, curv.rest) + net.min(hp).max(turning));
    gd.jet(Jet { m: peak, g, h: hh, t: ht.min(joint) })
}

/// `C = s₁·max x^p·((s₁ − 1)(1 − x) − x)⁺` over `x = cos²ψ ∈ [c₁², c₀²]`, `p = (s₀ − 2)/2`:
/// the coefficient of `|u|² + |v|²` in the power's profile part less the cosine's turning part
/// (`docs/estimator.md` §3, "A lobe of a cosine"). With `u = Dn̂`, `v = Dĥ`,
/// `(Dt)² ≤ sin²ψ(|u| + |v|)²`, so `(s−1)(Dt)² − t²(|u|² + |v|²) ≤
/// ((s−1)sin²ψ − cos²ψ)⁺(|u|² + |v|²) + 2(s−1)sin²ψ|u||v|`, a form with non-negative
/// coefficients (so it survives the sum over the corners of equation (1)). `x^p((s₁−1)(1−x) − x)`
/// is unimodal with its peak at `x* = p(s₁ − 1)/((p + 1)s₁)`.
fn power_net_coefficient(s0: f32, s1: f32, c0: f32, c1: f32) -> f32 {
    let p = 0.5 * (s0 - 2.0);
    let peak = p * (s1 - 1.0) / ((p + 1.0) * s1);
    let x = peak.max(c1 * c1).min(c0 * c0);
    s1 * est_pow(x, p) * ((s1 - 1.0) * (1.0 - x) - x).max(0.0)
}

/// Jet of `v·h = |l̂ + v̂|/2 = cos(∠(l,v)/2)` where the angle between `l̂` and `v̂` is at most
/// `psi_lv_max` and `|l̂ + v̂| ≥ m_min`: its `m` is the *smallest* value (what Fresnel needs),
/// `|D| ≤ (wₗ + wᵥ)/2`, `|D²| ≤ ((wₗ + wᵥ)²/|l̂+v̂| + (2/√3)(wₗ² + wᵥ²))/2`.
fn half_cosine_jet(l: &Field, v: &Field, psi_lv_max: f32, m_min: f32, gd: &Guard) -> Jet {
    let t0 = est_cos(0.5 * psi_lv_max).clamp(0.0, 1.0);
    let gt = gd.c(0.5 * (l.w + v.w));
    let mut ht = NO_H;
    ht[Term::Light as usize] = gd.c(0.5 * K23 * l.w * l.w);
    ht[Term::View as usize] = gd.c(0.5 * K23 * v.w * v.w);
    ht[Term::Half as usize] = gd.c(0.5 * (l.w + v.w) * (l.w + v.w) / m_min);
    let ht_total = ht[Term::Light as usize] + ht[Term::View as usize] + ht[Term::Half as usize];
    Jet { m: t0, g: gt, h: ht, t: ht_total }
}

/// Jet of Schlick's Fresnel `F = f₀ + (1 − f₀)(1 − u)⁵` of `u = v·h` with jet `vh` (its `m`
/// the smallest `u`, in `[0, 1]`): `|F'| ≤ 5(1 − f₀)(1 − u₀)⁴`, `|F''| ≤ 20(1 − f₀)(1 − u₀)³`.
fn fresnel_jet(f0: f32, vh: &Jet, gd: &Guard) -> Jet {
    let om = 1.0 - vh.m;
    let fm = f0 + (1.0 - f0) * om.powi(5);
    let f1 = 5.0 * (1.0 - f0) * om.powi(4);
    let f2 = 20.0 * (1.0 - f0) * om.powi(3);
    chain(vh, fm, f1, f2, Term::F, gd)
}

/// The chain rule for `φ(u)` of a factor `u` with jet `inner`, given `value ≥ sup|φ|`,
/// `first ≥ sup|φ'|` and `second ≥ sup|φ''|` over `u`'s range: `g = first·g_u`,
/// `h = first·h_u + second·g_u²` (the last part charged to `term`).
fn chain(inner: &Jet, value: f32, first: f32, second: f32, term: Term, gd: &Guard) -> Jet {
    let mut h = scaled(&inner.h, first, gd);
    let mut t = gd.mul(inner.t, first);
    let g2 = gd.mul(inner.g, inner.g);
    let curvature = gd.mul(second, g2);
    h[term as usize] = gd.c(h[term as usize] + curvature);
    t = gd.c(t + curvature);
    gd.jet(Jet { m: value, g: gd.mul(first, inner.g), h, t })
}

/// Jet of the Smith light half with its cosine, `G = c/(c(1 − k) + k)`, of `c = n·l` with jet
/// `c_g` and angle in `nl ⊂ [0, π/2]`: `G' = k/q²`, `G'' = −2k(1 − k)/q³`, `q = c(1 − k) + k`
/// smallest at the largest angle.
fn smith_g_jet(c_g: &Jet, nl: (f32, f32), k: f32, gd: &Guard) -> Jet {
    let (c0, c1) = (est_cos(nl.1).max(0.0), est_cos(nl.0));
    let q0 = c0 * (1.0 - k) + k;
    let q1 = c1 * (1.0 - k) + k;
    let g1 = k / (q0 * q0);
    let g2 = 2.0 * k * (1.0 - k) / (q0 * q0 * q0);
    chain(c_g, c1 / q1, g1, g2, Term::V, gd)
}

/// Jet of the Smith view half `V = 1/(c(1 − k) + k)` of `c = n·v` with jet `c_v` and angle in
/// `nv ⊂ [0, π/2]`: `V' = −(1 − k)/q²`, `V'' = 2(1 − k)²/q³`.
fn smith_v_jet(c_v: &Jet, nv: (f32, f32), k: f32, gd: &Guard) -> Jet {
    let q = est_cos(nv.1).max(0.0) * (1.0 - k) + k;
    let v1 = (1.0 - k) / (q * q);
    let v2 = 2.0 * (1.0 - k) * (1.0 - k) / (q * q * q);
    chain(c_v, 1.0 / q, v1, v2, Term::V, gd)
}

/// Relaxed, where `n·v` changes sign (`docs/estimator.md` §4, "The view's kink"): with
/// `u = n̂·v̂`, `V(max(u, 0)) = 1/k − max(ρ(u), 0)`, `ρ` the smooth function that is
/// `1/k − V(u)` for `u ≥ 0` and continues with its slope `(1 − k)/k²` below 0. The smooth
/// parts' bounds are this jet: `c_v` the cosine's jet over the whole angle range (both sides),
/// `|ρ'| ≤ (1 − k)/k²`, `|ρ''| ≤ 2(1 − k)²/k³`, and the value `1/k + sup|ρ(u)|`, where
/// `|u| ≤ band` on a sub-triangle the kink crosses (the others need only `1/k`). The kink
/// itself adds a first-order part (`LightJets::view_kink`).
fn smith_v_kink_jet(c_v: &Jet, k: f32, band: f32, gd: &Guard) -> Jet {
    let slope = (1.0 - k) / (k * k);
    let v2 = 2.0 * (1.0 - k) * (1.0 - k) / (k * k * k);
    let value = gd.c(1.0 / k + gd.mul(slope, c_v.m.min(band)));
    chain(c_v, value, slope, v2, Term::V, gd)
}

/// Elementwise larger bounds of two jets.
fn jet_max(a: &Jet, b: &Jet) -> Jet {
    let mut h = NO_H;
    for t in 0..TERM_COUNT {
        h[t] = a.h[t].max(b.h[t]);
    }
    Jet { m: a.m.max(b.m), g: a.g.max(b.g), h, t: a.t.max(b.t) }
}

/// The variation `sup |f(α) − f(α')|` of one light's specular part (per unit weight, per
/// channel) for a parameter anywhere in `parameter` (Eq. 37). `spec_sup` is the part's sup.
/// Blinn-Phong: `att·max_t (t^s₀ − t^s₁)` over the range of `t = n·h`, whose maximum over
/// `t ∈ [0, 1]` is at `t* = (s₀/s₁)^(1/(s₁−s₀))`. GGX: `|∂D/∂α| ≤ 2D/α`, `|∂G/∂α| ≤ G/α` and
/// `|∂V/∂α| ≤ V/α` give `|∂f/∂α| ≤ 4f/α`, so the variation is at most
/// `sup f · min(1, 4 ln(α₁/α₀))`.
fn parameter_variation(
    material: &MaterialKind,
    parameter: ParameterRange,
    st: &LightSetup,
    spec_sup: Vec3,
) -> Vec3 {
    match *material {
        MaterialKind::Lambert { .. } => Vec3::ZERO,
        MaterialKind::BlinnPhong { .. } => {
            let (s0, s1) = (parameter.lo, parameter.hi);
            if !(s1 > s0) || st.psi_nh.0 >= FRAC_PI_2 {
                return Vec3::ZERO;
            }
            let t_lo = est_cos(st.psi_nh.1.min(FRAC_PI_2)).max(0.0);
            let t_hi = est_cos(st.psi_nh.0);
            let t = est_pow(s0 / s1, 1.0 / (s1 - s0)).max(t_lo).min(t_hi);
            let upper = est_pow(t, s0);
            let att = if st.inv_d > 0.0 { st.inv_d * st.inv_d } else { 1.0 };
            let variation = ((upper - est_pow(t, s1)) * SAFETY + 1.0e-6 * upper) * att;
            Vec3::splat(variation.max(0.0))
        }
        MaterialKind::Ggx { .. } => {
            let (alpha_lo, alpha_hi) = (ggx_alpha(parameter.lo), ggx_alpha(parameter.hi));
            if !(alpha_hi > alpha_lo) {
                return Vec3::ZERO;
            }
            let share = (4.0 * LN_2 * est_log2(alpha_hi / alpha_lo)).min(1.0);
            spec_sup * (share * SAFETY)
        }
    }
}

/// GGX `D(n·h)` jet with the first and second derivatives maximised jointly with the
/// `sin ψ` that bounds `|D(n·h)|` (the peak of `D` sits where `n·h` is stationary).
fn ggx_d_jet(c: &Jet, curv: &Curvature, p0: f32, p1: f32, w: f32, alpha: f32, gd: &Guard) -> Jet {
    let a2 = alpha * alpha;
    let beta = 1.0 - a2;
    let coef = 4.0 * a2 * beta / PI;
    let (s0, s1) = (est_sin(p0).powi(2), est_sin(p1).powi(2));
    let u = |s2: f32| a2 + beta * s2;
    // √(s2(1−s2))/u³ peaks at the smaller root of 4βs² − (5β + 2α²)s + α² = 0.
    let b1 = 5.0 * beta + 2.0 * a2;
    let r1 = 2.0 * a2 / (b1 + (b1 * b1 - 16.0 * a2 * beta).max(0.0).sqrt()).max(1.0e-30);
    let x1 = r1.clamp(s0, s1);
    let u1 = u(x1);
    let d1 = (x1 * (1.0 - x1)).max(0.0).sqrt() / (u1 * u1 * u1);
    // s2(α² + 6β − 5βs2)/u⁴ peaks at the smaller root of
    // 10β²s² − β(3A + 10α²)s + Aα² = 0, A = α² + 6β (increasing on [0,1] when β → 0).
    let big_a = a2 + 6.0 * beta;
    let b2 = 3.0 * big_a + 10.0 * a2;
    let r2 = 2.0 * big_a * a2 / (beta * (b2 + (b2 * b2 - 40.0 * big_a * a2).max(0.0).sqrt())).max(1.0e-30);
    let x2 = r2.clamp(s0, s1);
    let u2 = u(x2);
    let d2 = x2 * (big_a - 5.0 * beta * x2) / (u2 * u2 * u2 * u2);
    let u0 = u(s0);
    let m = a2 / (PI * u0 * u0);
    let g = gd.mul(gd.c(coef * d1), w);
    let slope = gd.c(coef * est_cos(p0) / (u0 * u0 * u0));
    let mut h = scaled(&c.h, slope, gd);
    let mut t = gd.mul(c.t, slope);
    let w2 = gd.mul(w, w);
    let dd = gd.c(coef * d2);
    let hd = gd.mul(dd, w2);
    h[Term::D as usize] = gd.c(h[Term::D as usize] + hd);
    t = gd.c(t + hd);
    // D''(Dt)² ≥ 0 and D'·(−t(|u|² + |v|²)) ≤ 0 (as for the power): the larger, plus the rest;
    // the first less the second on the turn's share of w² (see `ggx_net_coefficient`).
    let c0 = est_cos(p0);
    let turning = gd.mul(gd.c(coef * c0 * c0 / (u0 * u0 * u0)), curv.turn);
    let net =
        gd.c(gd.mul(ggx_net_coefficient(a2, s0, s1), curv.turn) + gd.mul(dd, (w2 - curv.turn).max(0.0)));
    let joint = gd.c(gd.mul(slope, curv.rest) + net.min(hd).max(turning));
    gd.jet(Jet { m, g, h, t: t.min(joint) })
}

/// `C = max (D''(t)·sin²ψ − D'(t)·t)⁺` over `s₂ = sin²ψ ∈ [s₀, s₁]`: the coefficient of
/// `|u|² + |v|²` in the distribution's profile part less the cosine's turning part (as
/// [`power_net_coefficient`]). With `u = α² + βs₂` it is `(4α²β/π)·N(s₂)/u⁴`,
/// `N = −4βs₂² + (2α² + 5β)s₂ − α²`, whose critical points on `[0, 1]` are the roots of
/// `8β²s² − β(14α² + 15β)s + α²(2α² + 9β)`: the smaller one a maximum, the larger a minimum,
/// so the largest value on the range is at the smaller root (clamped) or at an end.
fn ggx_net_coefficient(a2: f32, s0: f32, s1: f32) -> f32 {
    let beta = 1.0 - a2;
    let coef = 4.0 * a2 * beta / PI;
    let at = |x: f32| {
        let u = a2 + beta * x;
        let n = (2.0 * a2 + 5.0 * beta - 4.0 * beta * x) * x - a2;
        coef * n.max(0.0) / ((u * u) * (u * u))
    };
    let b = beta * (14.0 * a2 + 15.0 * beta);
    let c = a2 * (2.0 * a2 + 9.0 * beta);
    let root = 2.0 * c / (b + (b * b - 32.0 * beta * beta * c).max(0.0).sqrt()).max(1.0e-30);
    at(root.max(s0).min(s1)).max(at(s0)).max(at(s1))
}

/// Smallest real `n > 0` with `a/n² + b/n + c ≤ eps` (`∞` if none).
fn level_for(a: f32, b: f32, c: f32, eps: f32) -> f32 {
    if a <= 0.0 && b <= 0.0 {
        return if c <= eps { 0.0 } else { f32::INFINITY };
    }
    let room = eps - c;
    if !(room > 0.0) {
        return f32::INFINITY;
    }
    let n = (b + (b * b + 4.0 * a * room).sqrt()) / (2.0 * room);
    if n.is_nan() {
        f32::INFINITY
    } else {
        n
    }
}

/// The bound on the uniform pattern at level `n`: per channel the smallest that holds there of
/// the level-1 bound (`n = 1`), the grid's bound (`n` on [`GRID_LEVELS`]) and the bound for
/// sub-triangles of radius² `K/L²`, `L = pattern_level(n, n)` (from [`Sums::low`] on);
/// `f32::MAX` if none does.
fn bound_at(sum: &Sums, an: Vec3, n: u32) -> f32 {
    let l = pattern_level(n, n);
    let mut e = if l >= sum.low {
        an / (l * l) + sum.linn / l + sum.jumps + sum.range
    } else {
        Vec3::splat(f32::INFINITY)
    };
    if n <= 1 {
        e = e.min(sum.one);
    }
    if let Some(k) = GRID_LEVELS.iter().position(|&g| g == n) {
        e = e.min(sum.grid[k]);
    }
    let m = e.max_element();
    if m.is_nan() {
        f32::MAX
    } else {
        m.min(f32::MAX)
    }
}

fn decide(sum: &Sums, eps: f32, n_max: u32, split: Split, reason: Reason) -> Estimate {
    let an = sum.tn;
    let finite = |x: f32| {
        if x.is_nan() {
            f32::MAX
        } else {
            x.min(f32::MAX)
        }
    };

    let mut terms = [0.0f32; TERM_COUNT];
    for (t, out) in terms.iter_mut().enumerate() {
        let b = sum.hn[t].max_element();
        if b > 0.0 {
            *out = finite((b / eps).sqrt());
        }
    }
    let jumps = sum.jumps;
    let zero = sum.jumps + sum.range;
    let relaxed_on = sum.linn.max_element() > 0.0 || jumps.max_element() > 0.0;
    if relaxed_on {
        let mut worst = 0.0f32;
        for c in 0..3 {
            worst = worst.max(level_for(0.0, sum.linn[c], jumps[c], eps));
        }
        terms[Term::Terminator as usize] = finite(worst);
    }
    let range_on = sum.range.max_element() > 0.0;
    if range_on {
        terms[Term::Range as usize] = if sum.range.max_element() <= eps { 0.0 } else { f32::MAX };
    }

    // `one_ok`: the level-1 bound holds, and then it holds for every pattern (each of
    // whose sub-triangles lies inside the patch). `need`: the smallest effective level `L`
    // at which the bound for sub-triangles of radius² `K/L²` and diameter `D/L` holds.
    let (one_ok, need) = match split {
        Split::Heuristic => {
            let mut n = 0.0f32;
            for c in 0..3 {
                n = n.max(level_for(an[c], sum.linn[c], zero[c], eps));
            }
            (sum.one.max_element() <= eps, n)
        }
        Split::Uniform => {
            // M counts the terms above ε·UNIFORM_TINY; the others share a reserve.
            let tiny = eps * UNIFORM_TINY;
            let mut count = 0u32;
            for t in 0..TERM_COUNT {
                if sum.hn[t].max_element() > tiny || sum.h1[t].max_element() > tiny {
                    count += 1;
                }
            }
            if sum.linn.max_element() > tiny || jumps.max_element() > tiny || sum.jumps1.max_element() > tiny
            {
                count += 1;
            }
            if sum.range.max_element() > tiny {
                count += 1;
            }
            let share = eps * (1.0 - 16.0 * UNIFORM_TINY) / count.max(1) as f32;
            let one_ok = (0..TERM_COUNT).all(|t| sum.h1[t].max_element() <= share)
                && (sum.lin1 + sum.jumps1).max_element() <= share
                && sum.range.max_element() <= share;
            let mut n = 0.0f32;
            for t in 0..TERM_COUNT {
                for c in 0..3 {
                    n = n.max(level_for(sum.hn[t][c], 0.0, 0.0, share));
                }
            }
            if relaxed_on {
                for c in 0..3 {
                    n = n.max(level_for(0.0, sum.linn[c], jumps[c], share));
                }
            }
            if sum.range.max_element() > share {
                n = f32::INFINITY;
            }
            (one_ok, n)
        }
    };
    let mut level = if one_ok { 1.0 } else { need.max(1.0) };
    // Heuristic: the lowest grid level whose bound, each part at its better bound there,
    // holds (it holds at every higher effective level too: both bounds only fall).
    if split == Split::Heuristic && !one_ok {
        for (k, &n) in GRID_LEVELS.iter().enumerate() {
            if n > n_max {
                break;
            }
            if sum.grid[k].max_element() <= eps {
                level = level.min(pattern_level(n, n));
                break;
            }
        }
    }

    let mut reason = reason;
    // false for NaN and ∞
    if reason == Reason::None && !(level <= pattern_level(n_max, n_max)) {
        reason = Reason::Level;
    }
    match reason {
        Reason::None => {
            let n = uniform_level(level, n_max);
            Estimate { terms, level, n, fallback: false, reason, predicted_error: bound_at(sum, an, n) }
        }
        Reason::Level => Estimate {
            terms,
            level: FALLBACK_LEVEL,
            n: 1,
            fallback: true,
            reason,
            predicted_error: bound_at(sum, an, n_max),
        },
        Reason::Discontinuity | Reason::Singular => {
            Estimate { terms, level: FALLBACK_LEVEL, n: 1, fallback: true, reason, predicted_error: f32::MAX }
        }
    }
}

// ------------------------------------------------------------------------------------------
// Shared edges and mixed patterns
// ------------------------------------------------------------------------------------------

/// [`Estimate::level`] of a triangle that falls back to per-pixel shading: above every
/// effective level, so it raises the shared edges to `n_max`.
pub const FALLBACK_LEVEL: f32 = 1.0e6;

/// Levels of one patch as the control stage writes them (whole numbers; the driver rounds
/// real values up anyway).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchLevels {
    /// `gl_TessLevelInner[0]`; 1 for a fallback patch.
    pub inner: f32,
    /// `gl_TessLevelOuter[k]`, the edge opposite vertex `k`: the same on both sides.
    pub outer: [f32; 3],
    /// Per-pixel shading (the control stage's `patch_level` 0).
    pub fallback: bool,
}

/// The effective level of the hardware pattern (lavapipe's, which is the D3D11 reference
/// tessellator's) with inner level `inner` and outer level `outer` on an edge: every
/// sub-triangle of the patch's interior and of that edge's transition strip has enclosing
/// radius² `≤ K_W/L²` and diameter `≤ D_W/L` under every attribute map `W` (`K_W`, `D_W`:
/// the seven shapes' constants, [`pattern_constants`]). A patch's level is the smallest
/// over its three edges. Levels are clamped to `1..=64`. See `docs/estimator.md`.
pub fn pattern_level(inner: u32, outer: u32) -> f32 {
    crate::analysis::pattern_level::entry(&PATTERN_LEVELS, inner, outer) as f32 * (1.0 / 256.0)
}

/// The smallest `n` in `1..=n_max` whose uniform pattern has effective level `≥ level`;
/// 0 when there is none (NaN included).
pub fn uniform_level(level: f32, n_max: u32) -> u32 {
    for n in 1..=n_max.clamp(1, 64) {
        if pattern_level(n, n) >= level {
            return n;
        }
    }
    0
}

/// The level-combination rule: what the control stage sets for a triangle with real level
/// `own` ([`Estimate::level`]) whose neighbour across edge `k` has level `neighbours[k]`.
///
/// Edge `k` gets the larger of the two triangles' uniform levels ([`uniform_level`]), a
/// triangle that falls back (no uniform level up to `n_max`, or NaN) asking for nothing (1
/// if both do): both sides compute the same value, so no T-junctions. The inner level is
/// the smallest in `1..=n_max` for which the *whole* pattern, transition strips included,
/// has effective level `≥ own` ([`pattern_level`] of each edge); if there is none, or the
/// triangle itself falls back, the patch is shaded per pixel (inner 1) and keeps its outer
/// levels.
pub fn patch_levels(own: f32, neighbours: [f32; 3], n_max: u32) -> PatchLevels {
    let n_max = n_max.clamp(1, 64);
    let own_n = uniform_level(own, n_max);
    let outer = neighbours.map(|neighbour| own_n.max(uniform_level(neighbour, n_max)).max(1));
    let mut inner = 0;
    if own_n > 0 {
        for i in 1..=n_max {
            let l =
                pattern_level(i, outer[0]).min(pattern_level(i, outer[1])).min(pattern_level(i, outer[2]));
            if l >= own {
                inner = i;
                break;
            }
        }
    }
    PatchLevels { inner: inner.max(1) as f32, outer: outer.map(|o| o as f32), fallback: inner == 0 }
}

/// [`pattern_level`] of every `(inner, outer)` in `1..=64`, index `(inner − 1)·64 +
/// (outer − 1)`, in 1/256 (rounded down), two 16-bit entries per word (low half first).
/// Generated and checked by the tests (`print_pattern_level_table`,
/// `pattern_level_table_is_current`). The renderer uploads the same words for the shaders
/// (`pattern_level_words` in `glsl/include/bindings.glsl`).
#[rustfmt::skip]
pub const PATTERN_LEVELS: [u32; 2048] = [
    0x01ff0100, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff,
    0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff,
    0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff,
    0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff,
    0x01ff0100, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff,
    0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff,
    0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff,
    0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff, 0x01ff01ff,
    0x02000100, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff,
    0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff,
    0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff,
    0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff, 0x02ff02ff,
    0x02000100, 0x03ff02ff, 0x03ff0355, 0x03ff03ff, 0x03ff0399, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff,
    0x03ff03c7, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff,
    0x03ff03e1, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff,
    0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff, 0x03ff03ff,
    0x02000100, 0x040002ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff,
    0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff,
    0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff,
    0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff, 0x04ff04ff,
    0x02000100, 0x040002ff, 0x05ff0355, 0x040004aa, 0x05000399, 0x05ff0466, 0x04aa0533, 0x04000449,
    0x048003c7, 0x05000438, 0x058004aa, 0x05ff051c, 0x0533058d, 0x04aa04e8, 0x04490476, 0x04000422,
    0x044003e1, 0x047f041d, 0x04c0045a, 0x04ff0496, 0x053f04d2, 0x057f050e, 0x05c0054a, 0x05ff0586,
    0x058e05c2, 0x0532055e, 0x04e9050c, 0x04aa04c8, 0x0476048f, 0x0448045f, 0x04220434, 0x04000410,
    0x02000100, 0x040002ff, 0x05ff0460, 0x059906ff, 0x06ff04d8, 0x06ff066a, 0x06ff06ff, 0x0599062d,
    0x06a1052c, 0x06ff060b, 0x06ff06ff, 0x06ff06ff, 0x06ff06ff, 0x06ff06ff, 0x062d068c, 0x059905dd,
    0x061a055f, 0x06a005d4, 0x06ff0650, 0x06ff06d2, 0x06ff06ff, 0x06ff06ff, 0x06ff06ff, 0x06ff06ff,
    0x06ff06ff, 0x06ff06ff, 0x06ff06ff, 0x06ff06ff, 0x068c06c4, 0x062c065b, 0x05dd0602, 0x059905b9,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x07ff06ff, 0x07ff0600, 0x07ff0755, 0x07ff07ff, 0x07ff07ff,
    0x07ff06cc, 0x07ff0799, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff,
    0x07ff0755, 0x07ff07c5, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff,
    0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff, 0x07ff07ff,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff,
    0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff,
    0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff,
    0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff, 0x08ff08ff,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x05b6065c, 0x09ff054b, 0x077f0755, 0x065c06d7, 0x05b605ff,
    0x077f057b, 0x09ff0709, 0x08750866, 0x077f07ed, 0x06d70723, 0x065d0695, 0x0600062b, 0x05b605d9,
    0x06890597, 0x077f065c, 0x08a30740, 0x09fd084b, 0x091f091a, 0x087408c5, 0x07ee082d, 0x077f07b3,
    0x0724074f, 0x06d606fc, 0x069606b5, 0x065c0678, 0x062b0643, 0x05ff0615, 0x05d905eb, 0x05b605c7,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x06c406ff, 0x09ff062f, 0x096d0aff, 0x07b30869, 0x06c4072c,
    0x096d0672, 0x0aff08b4, 0x0aff0aff, 0x096d0a1d, 0x086908de, 0x07b30806, 0x072c076b, 0x06c406f5,
    0x07f50699, 0x096c07b2, 0x0aff090a, 0x0aff0ab8, 0x0aff0aff, 0x0afe0aff, 0x0a1f0a86, 0x096c09bf,
    0x08df0921, 0x086808a1, 0x08070836, 0x07b207dc, 0x076b078e, 0x072b074b, 0x06f5070f, 0x06c406dc,
    0x02000100, 0x040002ff, 0x05ff049d, 0x060006ff, 0x08920524, 0x0bfd06f2, 0x07a308aa, 0x060006aa,
    0x07330583, 0x08920683, 0x0a2807a3, 0x0bfd08e6, 0x092e09fe, 0x07a3084e, 0x06ab071a, 0x0600064e,
    0x069505bd, 0x07320644, 0x07dd06d4, 0x0891076c, 0x0954080f, 0x0a2508be, 0x0b0c0977, 0x0bfb0a3f,
    0x0a5a0ade, 0x092b09b7, 0x085008b8, 0x07a207f5, 0x071a075b, 0x06aa06e0, 0x064e0679, 0x06000625,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x076d06ff, 0x09ff0628, 0x0bff08f0, 0x0a1c0cfd, 0x076d087a,
    0x095c06b2, 0x0bd2083b, 0x0cfd0a1d, 0x0cfd0c74, 0x0cfd0cfd, 0x0a1e0b51, 0x087b0932, 0x076d07e6,
    0x08580708, 0x095a07d7, 0x0a8408be, 0x0bcf09be, 0x0cfd0ade, 0x0cfd0c26, 0x0cfd0cfd, 0x0cfd0cfd,
    0x0cfd0cfd, 0x0cfd0cfd, 0x0b550c1b, 0x0a1a0aaf, 0x093209a1, 0x087908d2, 0x07e6082b, 0x076d07a6,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x07ff06ff, 0x09ff0600, 0x0bfe0755, 0x0dfe08aa, 0x07ff09ff,
    0x090006cc, 0x0a000799, 0x0b000866, 0x0c010931, 0x0d0209fe, 0x0dfe0acb, 0x0a010b9a, 0x07ff08db,
    0x08810755, 0x08fd07c5, 0x09810837, 0x09fd08a8, 0x0a7c091a, 0x0afb098d, 0x0b8209fd, 0x0bfb0a6e,
    0x0c830ade, 0x0cfb0b54, 0x0d850bcc, 0x0dfa0c3e, 0x0b9a0cae, 0x09fd0abc, 0x08db095f, 0x07ff0864,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09ff0780, 0x0bff09b4, 0x0dff0c2f, 0x0ae80efd,
    0x0cdb08ca, 0x0efd0a2c, 0x0dbf0bab, 0x0efc0d42, 0x0efd0efc, 0x0efd0efd, 0x0efd0efd, 0x0ae80c90,
    0x0bdf09b4, 0x0cd70a7d, 0x0deb0b51, 0x0efa0c2c, 0x0efd0d11, 0x0dc30e04, 0x0efd0efa, 0x0efd0efd,
    0x0efd0efd, 0x0efd0efd, 0x0efd0efd, 0x0efd0efd, 0x0efd0efd, 0x0efa0efd, 0x0c900da1, 0x0ae80ba7,
    0x02000100, 0x040002ff, 0x055504ff, 0x080006ff, 0x08e308ff, 0x099a0aff, 0x0dff0cfe, 0x0ffe0eff,
    0x0ffe0b54, 0x0d540ca9, 0x0bbb0e01, 0x0bfe0da2, 0x0dda0e4b, 0x0ffe0ffe, 0x0ffe0ffe, 0x0ffe0ffe,
    0x0ffe0d33, 0x0ffe0dfa, 0x0ffe0ec9, 0x0d570f92, 0x0d730e45, 0x0bbe0ea3, 0x0d210ca4, 0x0c020e7a,
    0x0e450d15, 0x0de20fb1, 0x0ffe0f61, 0x0ffe0ffe, 0x0ffe0ffe, 0x0ffe0ffe, 0x0ffe0ffe, 0x0ffe0ffe,
    0x02000100, 0x040002ff, 0x04db04ff, 0x080006ff, 0x081808ff, 0x08290a63, 0x0b550b0d, 0x10000eff,
    0x10fe10fe, 0x0c2410fe, 0x0a630dba, 0x0a320bda, 0x0b0a0bd0, 0x0d350d1e, 0x10fe106c, 0x10fe10fe,
    0x10fe10fe, 0x10fe10fe, 0x0f0310fe, 0x0c26102e, 0x0bb60cea, 0x0a650c9b, 0x0b010b18, 0x0a350bef,
    0x0ba10af9, 0x0b0f0cc0, 0x0d180bfd, 0x0d3d0e5b, 0x106c0ea9, 0x10fe10fe, 0x10fe10fe, 0x10fe10fe,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09ff08ff, 0x0bff0aff, 0x0a7f0b24, 0x099909ff,
    0x11fd0945, 0x0eff0ca9, 0x0d320dff, 0x0bff0c8a, 0x0b240b88, 0x0a800acc, 0x0a000a3c, 0x099909c9,
    0x0cc0096d, 0x11f60c59, 0x10490ec9, 0x0efd0f92, 0x0dfe0e76, 0x0d310d93, 0x0c8b0cd9, 0x0bfe0c41,
    0x0b890bc1, 0x0b230b54, 0x0acd0af7, 0x0a7f0aa5, 0x0a3c0a5d, 0x09ff0a1d, 0x09c909e3, 0x099909b0,
    0x02000100, 0x040002ff, 0x056d04ff, 0x080006ff, 0x09ff08ff, 0x09e90aff, 0x0b900c59, 0x0a7b0af6,
    0x11ff0a18, 0x114612f8, 0x0eee0ff6, 0x0d6a0e18, 0x0c5a0cd6, 0x0b910bee, 0x0af60b3e, 0x0a7b0ab5,
    0x0e5c0a47, 0x12f80dd9, 0x12f812f8, 0x11441211, 0x0ff41091, 0x0eec0f6a, 0x0e190e7c, 0x0d680dbc,
    0x0cd70d1b, 0x0c590c95, 0x0bef0c23, 0x0b900bbe, 0x0b3e0b67, 0x0af50b19, 0x0ab50ad4, 0x0a7b0a97,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x07ff06ff, 0x09ff0732, 0x0bfe0aff, 0x09540a65, 0x07ff0891,
    0x0bff078d, 0x13fb0ada, 0x0ea90e01, 0x0bff0d22, 0x0a660b1a, 0x095509d0, 0x089208ec, 0x07ff0843,
    0x09b707c3, 0x0bfd0954, 0x0f340b60, 0x13f20e2b, 0x10c7105d, 0x0ea60fa0, 0x0d250dd5, 0x0bfd0c85,
    0x0b1c0b84, 0x0a640abb, 0x09d20a19, 0x09540991, 0x08ec091e, 0x089108bd, 0x08430868, 0x07ff0820,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09ff07df, 0x0bff0aff, 0x0a7f0bdd, 0x08d7098a,
    0x0dfe084c, 0x13ff0c76, 0x11c314fb, 0x0dff0f91, 0x0bde0ccb, 0x0a800b1c, 0x098b09fb, 0x08d7092a,
    0x0afc088d, 0x0dfc0a7e, 0x12900d29, 0x14fb110a, 0x14f714fb, 0x11be1332, 0x0f95108f, 0x0dfc0eb7,
    0x0cce0d59, 0x0bdc0c4e, 0x0b1e0b7a, 0x0a7e0acc, 0x09fb0a3b, 0x098a09c1, 0x092a0958, 0x08d708fe,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09ff0712, 0x0bff0aff, 0x099f0b6f, 0x07a60875,
    0x0a6b070e, 0x0eaa0949, 0x15ff0c7c, 0x0eab0f51, 0x0b710cc8, 0x09a00a6a, 0x087608fc, 0x07a60805,
    0x08e80755, 0x0a6a0875, 0x0c4c09cd, 0x0ea60b6e, 0x11be0d72, 0x15ee1007, 0x117611f7, 0x0ea60fe3,
    0x0ccc0da0, 0x0b6e0c10, 0x0a6d0ae8, 0x099e0a01, 0x08fc094a, 0x087508b6, 0x0805083a, 0x07a607d3,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09ff07f6, 0x0bff0aff, 0x0b1b0cfe, 0x088f0996,
    0x0c2e07d2, 0x126a0aa9, 0x15ff0f1b, 0x126c16ea, 0x0d9a0f8a, 0x0b1c0c2d, 0x09970a44, 0x088f0907,
    0x0a2a0829, 0x0c2c0994, 0x0ed50b58, 0x12640d96, 0x16ea1088, 0x16ea149c, 0x16ea16ea, 0x12641461,
    0x0f8f10ce, 0x0d960e7c, 0x0c310cd9, 0x0b190b9e, 0x0a440aaa, 0x099409e9, 0x09070949, 0x088f08c7,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x07ff06ff, 0x09ff068b, 0x0bff09c6, 0x0b310cfe, 0x07ff0939,
    0x0a470727, 0x0d5308ef, 0x11960b32, 0x17f90e22, 0x0edb10a4, 0x0b330cb1, 0x093b0a15, 0x07ff088c,
    0x0911078a, 0x0a450879, 0x0bb1098a, 0x0d4f0abe, 0x0f3e0c20, 0x118d0dbf, 0x14730f9e, 0x17e711dc,
    0x122f1389, 0x0ed4104d, 0x0cb60db0, 0x0b2f0be6, 0x0a150a9a, 0x093809a1, 0x088c08dc, 0x07ff0841,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09fe0742, 0x0bff0aff, 0x0d780cfe, 0x09180ab8,
    0x0c2b0805, 0x10af0a54, 0x15ff0d79, 0x17ff11f8, 0x132718e5, 0x0d7b0fb3, 0x0aba0be5, 0x091809d0,
    0x0a810882, 0x0c2809b8, 0x0e330b25, 0x10a90cd3, 0x13cd0ed9, 0x17e31159, 0x18e51471, 0x18e51875,
    0x18e518e5, 0x131c15a1, 0x0fbb1141, 0x0d750e81, 0x0be50ca0, 0x0ab60b45, 0x09d00a3b, 0x0918096e,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x094907cb, 0x0bff0a35, 0x0dff0cfb, 0x09090b22,
    0x0b2207bf, 0x0dac094f, 0x10ce0b23, 0x14c90d44, 0x19f80fd2, 0x0f2a11fb, 0x0b240cc5, 0x090909f1,
    0x0a0b0853, 0x0b1f092d, 0x0c590a1d, 0x0da70b1f, 0x0f210c3a, 0x10c50d73, 0x12b00ec6, 0x14ba103f,
    0x173811e1, 0x19e013c2, 0x12fc1546, 0x0f2110d7, 0x0cc50dd9, 0x0b1f0be4, 0x09f10a7b, 0x09090974,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x08b408ff, 0x0bff0aff, 0x0dff0cfe, 0x0a8a0d81,
    0x0d8208d4, 0x0f6b0aea, 0x10f50d83, 0x17f410c8, 0x19fe1516, 0x13f01aec, 0x0d850fff, 0x0a8a0bcb,
    0x0bf00995, 0x0d7e0abc, 0x0f570c09, 0x11680d7e, 0x12e90f27, 0x13d21114, 0x16221345, 0x1aec15da,
    0x1aec18e8, 0x1aec1aec, 0x1aec1aec, 0x13e016f0, 0x0fff11ba, 0x0d7e0ea3, 0x0bcb0c8f, 0x0a8a0b1d,
    0x02000100, 0x040002ff, 0x059a04ff, 0x080006ff, 0x083c07a1, 0x0a8209ed, 0x0dff0c88, 0x0b300eff,
    0x0d3f08f9, 0x0e000a6b, 0x0eac0bfd, 0x12ab0dac, 0x18400f84, 0x1bf7118a, 0x0f8d1357, 0x0b300cf0,
    0x0c3409ed, 0x0d3a0abf, 0x0e600b9e, 0x0f820c85, 0x10bf0d78, 0x11250e7b, 0x12640f82, 0x14ea109a,
    0x169411be, 0x18261301, 0x1a18145b, 0x1bd815b7, 0x13c716d8, 0x0f821162, 0x0cf00e12, 0x0b300bf9,
    0x02000100, 0x040002ff, 0x054504ff, 0x080006ff, 0x07d608b2, 0x096809f7, 0x0dff0cfe, 0x0da30eff,
    0x0fd10a7c, 0x0ce30c83, 0x0d050eda, 0x0f750fe4, 0x16d2142b, 0x1bfe186b, 0x14bc1cf7, 0x0da31055,
    0x0f2e0bcf, 0x10cd0cfd, 0x125a0e49, 0x101f0fad, 0x0f3d1130, 0x0f3510a1, 0x0fdd10c0, 0x116d11ba,
    0x141c13c8, 0x1933177c, 0x1cf71cf7, 0x1cf71cf7, 0x1cf71cf7, 0x14a81820, 0x1055122e, 0x0da30ed3,
    0x02000100, 0x040002ff, 0x050004ff, 0x080006ff, 0x078008ff, 0x0893096e, 0x0dff0bd4, 0x0fff0eff,
    0x0f000b54, 0x0c000ca9, 0x0bca0e00, 0x0d550e19, 0x11ba10a4, 0x1bfe11fb, 0x1df51357, 0x0fff14a8,
    0x11070d33, 0x11f60dfa, 0x11440ec9, 0x0f040f92, 0x0e041034, 0x0dc50f2f, 0x0e130f05, 0x0f070f86,
    0x10a910c0, 0x138f12e9, 0x18831546, 0x1be71613, 0x1d0416d8, 0x1dcf17a5, 0x14a8184d, 0x0fff11f6,
    0x02000100, 0x040002ff, 0x04c404ff, 0x080006ff, 0x073508ff, 0x07ea08f8, 0x0c650a9a, 0x10000eff,
    0x0e4d0dde, 0x0b440fe9, 0x0ad20d03, 0x0bcd0cbc, 0x0ea30e5c, 0x16341308, 0x1dfe1c1e, 0x15911ef6,
    0x177c10c6, 0x1578120d, 0x1059136b, 0x0e191187, 0x0d070f23, 0x0ca40e08, 0x0cb80daf, 0x0d4c0de3,
    0x0e550ea0, 0x10230ff7, 0x12f81233, 0x1829160f, 0x1ef61d5a, 0x1ef61ef6, 0x1ef61ef6, 0x1591194c,
    0x02000100, 0x040002ff, 0x049204ff, 0x080006c9, 0x06f408ff, 0x07620895, 0x0aaa09ac, 0x10000eff,
    0x0db610fe, 0x0aaa0f97, 0x0a0e0c36, 0x0aa90baf, 0x0c980cb4, 0x11340fb7, 0x1dfe17c6, 0x1ff81ef8,
    0x1ff81600, 0x14941744, 0x0f9415ed, 0x0d5710a5, 0x0c390e45, 0x0bbe0d1b, 0x0bac0ca4, 0x0c020ca6,
    0x0caf0d15, 0x0de20df2, 0x0fad0f61, 0x12b311ba, 0x17c615ab, 0x1ff81cf7, 0x1ff81ff8, 0x1ff81ff8,
    0x02000100, 0x040002ff, 0x046604ff, 0x0800066a, 0x06bb08ff, 0x06f2083f, 0x096d08f0, 0x10000dc0,
    0x0d3310fe, 0x0a270eee, 0x096d0b8c, 0x09c60ad9, 0x0b220b77, 0x0e330d82, 0x16011266, 0x20001ef8,
    0x20ff20ff, 0x13cf20ff, 0x0eeb150f, 0x0cb30fe6, 0x0b8e0d8a, 0x0b020c57, 0x0ad60bcb, 0x0b020bac,
    0x0b730be8, 0x0c450c78, 0x0d7a0d6d, 0x0f6d0ef8, 0x12661164, 0x17a4155c, 0x20ff1ce5, 0x20ff20ff,
    0x02000100, 0x040002ff, 0x04db04ff, 0x080006ff, 0x081808ff, 0x082a0a64, 0x0b580b0f, 0x10000eff,
    0x11ff10f6, 0x0d9a12f9, 0x0c12103b, 0x0c5d0e80, 0x0e420f35, 0x13081266, 0x12341298, 0x118a11da,
    0x21f41140, 0x1e8f1744, 0x18d6189f, 0x12ea19eb, 0x104014d7, 0x0efc11d8, 0x0e7a107b, 0x0e991003,
    0x0f2c1038, 0x106a1105, 0x1258128d, 0x13061345, 0x129812ce, 0x12331265, 0x11da1205, 0x118a11b0,
    0x02000100, 0x040002ff, 0x04aa04ff, 0x080006ff, 0x07c608ff, 0x07a209dd, 0x09fd0a1b, 0x10000efa,
    0x11ff10fe, 0x0cb712f9, 0x0b260efc, 0x0b2f0d31, 0x0c710d75, 0x0f820f7b, 0x13191387, 0x125e12b6,
    0x21fd120d, 0x212a22b6, 0x16e61f99, 0x11811948, 0x0f001323, 0x0dc11059, 0x0d2c0f00, 0x0d200e6f,
    0x0d6f0e6c, 0x0e380edc, 0x0f710fcc, 0x1181116e, 0x138713c3, 0x1318134f, 0x12b612e5, 0x125e1288,
    0x02000100, 0x040002ff, 0x052404ff, 0x080006ff, 0x097708ff, 0x08fe0aff, 0x0bfb0ca3, 0x0d180dd9,
    0x11ff0c7e, 0x11fa12f9, 0x0ea614ff, 0x0e5f1264, 0x101810fc, 0x0ed50f6e, 0x0dda0e4e, 0x0d180d73,
    0x13c20cc7, 0x23cf12ce, 0x1dc8189f, 0x19b719eb, 0x16e91832, 0x13ce15d0, 0x125a1400, 0x12001298,
    0x10fe1176, 0x1023108c, 0x0f700fc8, 0x0ed30f20, 0x0e4e0e8f, 0x0dd90e12, 0x0d730da3, 0x0d180d43,
    0x02000100, 0x040002ff, 0x04ee04ff, 0x080006ff, 0x090508ff, 0x08600aff, 0x0a900b72, 0x0dc40e9b,
    0x11ff0d1b, 0x106e12f9, 0x0d55146c, 0x0cda105d, 0x0deb0ff3, 0x0fb31060, 0x0e9c0f1d, 0x0dc40e29,
    0x15560d6b, 0x23d9143a, 0x218324ce, 0x1a711eb0, 0x14751a9a, 0x11b5170c, 0x105613d5, 0x0fdd1251,
    0x0fea11cb, 0x109911a3, 0x106210c5, 0x0fb21008, 0x0f1d0f66, 0x0e9a0edb, 0x0e290e5f, 0x0dc40df5,
    0x02000100, 0x040002ff, 0x056e04ff, 0x080006ff, 0x09ff08ff, 0x09ec0aff, 0x0cae0cfe, 0x0baf0cf2,
    0x11ff0ac2, 0x13ff12f3, 0x123014ff, 0x10e11293, 0x0e860f8f, 0x0cf80dab, 0x0bdf0c60, 0x0b0c0b6e,
    0x0f050ab6, 0x16070e49, 0x25fd145a, 0x1d2a19ec, 0x18231a59, 0x14dd165c, 0x129713a0, 0x10de11a8,
    0x0f92102b, 0x0e830f03, 0x0dad0e15, 0x0cf60d4f, 0x0c600ca9, 0x0bdd0c1d, 0x0b6e0ba3, 0x0b0c0b3b,
    0x02000100, 0x040002ff, 0x053204ff, 0x080006ff, 0x09ff08ff, 0x092c0aff, 0x0b210cfd, 0x0c7c0df0,
    0x11ff0b6f, 0x13ff12f9, 0x102b14ff, 0x0ed41465, 0x0f9010d1, 0x0dd50ea1, 0x0c970d28, 0x0bab0c18,
    0x10300b4b, 0x18a30f57, 0x25fd168f, 0x21eb26a4, 0x1b4e1e2c, 0x1730190d, 0x146a15ac, 0x125b134c,
    0x10d41188, 0x0f9a102e, 0x0ea40f1b, 0x0dd30e38, 0x0d280d7c, 0x0c950cdd, 0x0c180c53, 0x0bab0bdf,
    0x02000100, 0x040002ff, 0x05b604ff, 0x080006ff, 0x09ff08c8, 0x0ae70aff, 0x0c2e0cfe, 0x0a010aea,
    0x11290951, 0x13ff0ee9, 0x15ff14ff, 0x112a1396, 0x0e110f64, 0x0c2f0d04, 0x0aeb0b7e, 0x0a010a6c,
    0x0cd809a3, 0x11250c2d, 0x18920fec, 0x27cd15fa, 0x1cf81b3d, 0x172819b3, 0x139c152e, 0x11251241,
    0x0f671032, 0x0e0e0eb0, 0x0d070d86, 0x0c2d0c96, 0x0b7e0bd3, 0x0ae90b31, 0x0a6c0aa8, 0x0a010a34,
    0x02000100, 0x040002ff, 0x057604ff, 0x080006ff, 0x09ff08ff, 0x0a080aff, 0x0bb20cfe, 0x0a960b9c,
    0x11ff09d2, 0x13ff103d, 0x140214ff, 0x113815f1, 0x0f3f10cf, 0x0d0f0e05, 0x0b9d0c44, 0x0a960b0e,
    0x0dd10a2d, 0x12ed0d0c, 0x1c661172, 0x27d018fd, 0x22722881, 0x1a871deb, 0x15f917f7, 0x12ed1449,
    0x10d311c6, 0x0f3b0ff9, 0x0e080e9b, 0x0d0c0d85, 0x0c440ca5, 0x0b9b0bed, 0x0b0e0b51, 0x0a960acf,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09ff08ff, 0x0bfd0aff, 0x0dfa0cfe, 0x0a300bac,
    0x0fc40928, 0x13ff0d4f, 0x15ff14ff, 0x12b2167b, 0x0e631029, 0x0c030d0a, 0x0a820b2f, 0x097809f1,
    0x0bb80910, 0x0ed30b0e, 0x13810dc2, 0x1b1a119e, 0x29c81797, 0x1cde1ca4, 0x16851934, 0x12ab145a,
    0x102e114a, 0x0e5f0f34, 0x0d0e0dae, 0x0c000c81, 0x0b2f0b94, 0x0a800ad5, 0x09f10a35, 0x097809b1,
    0x02000100, 0x040002ff, 0x05bb04ff, 0x080006ff, 0x09ff08ff, 0x0afa0aff, 0x0c480cfe, 0x0aec0ca6,
    0x119909bf, 0x13ff0e96, 0x15ff14ff, 0x143516ee, 0x0fc111e9, 0x0cf40e28, 0x0b390bfe, 0x0a0b0a94,
    0x0c9c0996, 0x10490bd8, 0x161c0f01, 0x206913b7, 0x29cb1b83, 0x22f82ae3, 0x1a111dbc, 0x150b1734,
    0x11ef134f, 0x0fbd10be, 0x0e2c0eea, 0x0cf10d87, 0x0bfe0c73, 0x0b360b97, 0x0a940ae1, 0x0a0b0a4c,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09ff086e, 0x0bff0aff, 0x0c540cfe, 0x09450a7c,
    0x0dab0868, 0x13ff0bc8, 0x15ff1176, 0x160e16ee, 0x0f7c120b, 0x0c560daa, 0x0a7d0b4d, 0x094509d2,
    0x0b2e08ce, 0x0da90a7a, 0x11190ca0, 0x16020f77, 0x1dd21367, 0x2bb41944, 0x1d071de4, 0x160218ec,
    0x121313c7, 0x0f7710a4, 0x0dae0e85, 0x0c530cf7, 0x0b4d0bca, 0x0a7a0ae0, 0x09d20a21, 0x09450987,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09fe08ff, 0x0bfd0aff, 0x0cd60cfe, 0x09de0b41,
    0x0f0408e6, 0x13f80cc4, 0x15ff13b8, 0x17ec16ee, 0x113c1476, 0x0d6c0f02, 0x0b430c35, 0x09de0a7e,
    0x0c100958, 0x0f000b40, 0x13410dc4, 0x19b71135, 0x250e163a, 0x2bb81e47, 0x23d72c76, 0x19b71dc8,
    0x148016b8, 0x113512ad, 0x0f07100b, 0x0d670e2b, 0x0c350cc7, 0x0b400bb5, 0x0a7e0ad9, 0x09de0a29,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x099507f5, 0x0bff0aff, 0x0dff0cfe, 0x0a360c18,
    0x0e4308e1, 0x12680bcc, 0x15ff1016, 0x17ff16ea, 0x119415a4, 0x0d230ef1, 0x0ac70bcc, 0x094f09f6,
    0x0b0308c5, 0x0d1e0a3d, 0x0fe30c0e, 0x13850e53, 0x18af1142, 0x2079153a, 0x2dfd1ac8, 0x1cef1f35,
    0x15b118aa, 0x118b135c, 0x0ef71027, 0x0d1e0dfb, 0x0bcc0c6c, 0x0ac40b42, 0x09f60a56, 0x094f099d,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x09350877, 0x0bff0aff, 0x0d670cfe, 0x0b110d11,
    0x0ffc0984, 0x11110cf3, 0x15ff1250, 0x17ff16ee, 0x141418e6, 0x0e7c10b6, 0x0bab0cdf, 0x09f70ab8,
    0x0bf10959, 0x0e770b0b, 0x11e70d2e, 0x16a80ff1, 0x1deb13aa, 0x2a2f18fd, 0x2dfd210e, 0x24662e59,
    0x19a21de4, 0x14091670, 0x10bd123e, 0x0e770f85, 0x0cdf0d9f, 0x0ba70c3c, 0x0ab80b27, 0x09f70a51,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x08e20795, 0x0bff0aff, 0x0dff0cfe, 0x099b0b70,
    0x0d1b086b, 0x0ffc0afe, 0x15160ea1, 0x17ff1417, 0x159418e6, 0x0ea3114b, 0x0b720cc9, 0x099b0a6a,
    0x0b3208f4, 0x0d180a4f, 0x0f7e0bed, 0x12770dde, 0x16671044, 0x1bc81350, 0x23cf173b, 0x2fb61c8e,
    0x1d66207d, 0x158518c6, 0x11551333, 0x0e9c0fdb, 0x0cc90da3, 0x0b6e0c12, 0x0a6a0ae2, 0x099b09fb,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x08960806, 0x0bff0aff, 0x0df80cfe, 0x0a530c79,
    0x0e7c08f7, 0x0f0e0bf3, 0x12df105e, 0x17ff16ee, 0x199518e6, 0x106013c7, 0x0c7b0e18, 0x0a530b43,
    0x0c2f0994, 0x0e770b24, 0x11740d0e, 0x15520f6c, 0x1ab61271, 0x21281676, 0x2dfd1bf0, 0x2fbb2404,
    0x255f302b, 0x19811e35, 0x13d3164f, 0x105811eb, 0x0e180f23, 0x0c770d3a, 0x0b430bd1, 0x0a530ac3,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x0855087c, 0x0bff0ac9, 0x0dff0cfe, 0x0b1a0d9f,
    0x0efb096f, 0x0e4a0bdc, 0x11330efc, 0x17ff131e, 0x19fe18e3, 0x11111560, 0x0c7f0e57, 0x0a1e0b23,
    0x0ba40950, 0x0d670a96, 0x0f920c12, 0x12210dcc, 0x155a0fd9, 0x19751257, 0x1f13155a, 0x26751928,
    0x31fd1e0f, 0x1d6621fd, 0x157018cb, 0x110612fa, 0x0e570f92, 0x0c790d58, 0x0b230bc0, 0x0a1e0a96,
    0x02000100, 0x040002ff, 0x05ff04ff, 0x080006ff, 0x081708ff, 0x0bff0a63, 0x0dff0cfe, 0x0bff0eff,
    0x0e910a33, 0x0d980d17, 0x0fcc1038, 0x17f7143c, 0x19fe18e6, 0x13951979, 0x0dcb1014, 0x0af30c28,
    0x0cc20a04, 0x0ee80b81, 0x11a30d47, 0x14a00f66, 0x15a911ff, 0x18b51548, 0x1f331972, 0x2fbb1f09,
    0x31fd26db, 0x25c332e1, 0x19901e7d, 0x13871624, 0x101411a3, 0x0dc40ed5, 0x0c280ce4, 0x0af30b81,
    0x02000100, 0x040002ff, 0x05c604ff, 0x080006ff, 0x07e008ff, 0x0b220a07, 0x0dff0cfe, 0x0af50e33,
    0x0e2d091f, 0x0cfd0b5d, 0x0ea60e34, 0x14be11dd, 0x19fe16d3, 0x157c1aec, 0x0e3710fa, 0x0af50c51,
    0x0c7a09ee, 0x0e2f0b2b, 0x103d0c95, 0x12930e2f, 0x13dc1008, 0x16031234, 0x1a7a14b6, 0x22ac17ba,
    0x2a411b60, 0x33aa200c, 0x1e0f238f, 0x156a1903, 0x10fa12f0, 0x0e2f0f74, 0x0c510d28, 0x0af50b94,
    0x02000100, 0x040002ff, 0x059504ff, 0x080006ff, 0x07ae08ff, 0x0a7109b8, 0x0dff0cfe, 0x0beb0eff,
    0x0dd409c7, 0x0c7a0c67, 0x0dbb0ea7, 0x127510f7, 0x19fe18e6, 0x19861aec, 0x0fe01367, 0x0beb0d8c,
    0x0dbd0ab6, 0x0fd60c2b, 0x12720dde, 0x12280fd6, 0x1271122d, 0x140014c1, 0x173c1703, 0x1e1c1bd2,
    0x2e982248, 0x33af29f1, 0x269b34df, 0x196d1ea8, 0x13671602, 0x0fd61170, 0x0d8c0e92, 0x0beb0ca8,
    0x02000100, 0x040002ff, 0x056704ff, 0x080006ff, 0x078008fd, 0x09d4096e, 0x0dff0cfe, 0x0d110eff,
    0x0d800a89, 0x0c010d1f, 0x0cec0e01, 0x10a00fbf, 0x19fe1634, 0x1bfe1ada, 0x10db1566, 0x0c260e09,
    0x0db10ac8, 0x0f600c01, 0x115f0d60, 0x112b0ee2, 0x11371094, 0x12541285, 0x14b414ab, 0x19861727,
    0x238c1a02, 0x2ccf1d7c, 0x35e521af, 0x1e0724e3, 0x156618fd, 0x10cf12d4, 0x0e090f42, 0x0c260cff,
    0x02000100, 0x040002ff, 0x053d04ff, 0x080006ff, 0x075508ff, 0x094e092b, 0x0dff0cfe, 0x0e650eff,
    0x0d340b61, 0x0b950ead, 0x0c3b0d6f, 0x0f2f0ebc, 0x184613b5, 0x1bfe1aec, 0x136119a2, 0x0d670fbe,
    0x0f4f0bc3, 0x11720d3b, 0x11900eea, 0x105310d1, 0x103011ee, 0x10f811f1, 0x12bf1317, 0x164715a0,
    0x1cfa1a94, 0x2de02514, 0x35fb2d86, 0x271736dd, 0x19a21ef6, 0x13511608, 0x0fbe114c, 0x0d670e72,
    0x02000100, 0x040002ff, 0x051604ff, 0x080006ff, 0x072d08d9, 0x08d608ec, 0x0dff0c54, 0x0e050eff,
    0x0ceb0ab5, 0x0b310cd5, 0x0b9d0ce9, 0x0df90dd8, 0x14bb11b7, 0x1bfe19ab, 0x15a11cff, 0x0e0510e1,
    0x0fa70c18, 0x11620d56, 0x10de0eb5, 0x0f8f102e, 0x0f461103, 0x0fcd10d4, 0x112211a0, 0x13c51381,
    0x18761715, 0x22ac1cef, 0x31592030, 0x379c23bb, 0x1ec42625, 0x158b1957, 0x10e112dd, 0x0e050f46,
    0x02000100, 0x040002ff, 0x04f504ff, 0x080006ff, 0x070908ff, 0x087308b5, 0x0dff0b96, 0x0fb20eff,
    0x0caa0ba9, 0x0adb0e39, 0x0b190c78, 0x0d070d1f, 0x124c1039, 0x1bfe19b9, 0x19e61cff, 0x0fb21360,
    0x11c60d53, 0x138f0ed8, 0x10471090, 0x0eeb11a9, 0x0e871040, 0x0ede0fed, 0x0fe21078, 0x11ed11e7,
    0x156b149c, 0x1c5d198b, 0x2c8123dc, 0x37a2311b, 0x283138dd, 0x19c61f68, 0x13601608, 0x0fb2114a,
    0x02000100, 0x040002ff, 0x04d504ff, 0x080006ff, 0x06e708ff, 0x08180881, 0x0dff0aee, 0x10000eff,
    0x0c6d0ccc, 0x0a8b0df3, 0x0aa20c0e, 0x0c340c79, 0x10600ef6, 0x1bfe1615, 0x1dfe1cfd, 0x10dc15a3,
    0x12a00df7, 0x12fe0f3b, 0x0fbb109c, 0x0e551105, 0x0dda0f8e, 0x0e0a0f1e, 0x0ecf0f76, 0x1067108c,
    0x130d129e, 0x1800163f, 0x21e91d28, 0x33fd2272, 0x39e42539, 0x1eef2777, 0x15a31956, 0x10dc12e2,
    0x02000100, 0x040002ff, 0x04b804ff, 0x080006ff, 0x06c808ff, 0x07c80852, 0x0d1f0a5f, 0x10000eff,
    0x0c350e1b, 0x0a420dac, 0x0a390bb0, 0x0b830bea, 0x0ee40def, 0x18a61377, 0x1dfe1cff, 0x136d1a0d,
    0x15ce0fae, 0x127b114b, 0x0f3f1317, 0x0dd01073, 0x0d440ef3, 0x0d550e6c, 0x0de90e9c, 0x0f2c0f6f,
    0x113e110e, 0x14f013d2, 0x1ba818c3, 0x2c6a232b, 0x39ff3488, 0x28d13adb, 0x1a0d1f9b, 0x136d1628,
    0x02000100, 0x040002ff, 0x049d04ff, 0x080006e1, 0x06aa08ff, 0x077f0825, 0x0bfc09de, 0x10000eff,
    0x0bff0dfe, 0x09fe0d69, 0x09d80b58, 0x0ae50b67, 0x0da70d0a, 0x14eb1168, 0x1dfe1ca4, 0x15df1ef8,
    0x17d910f5, 0x12011243, 0x0eca134d, 0x0d560fec, 0x0cba0e64, 0x0cb20dca, 0x0d1e0dd9, 0x0e1f0e77,
    0x0fc00fbc, 0x129311df, 0x175b1585, 0x219b1c7e, 0x38982511, 0x3b8d2738, 0x1fa12867, 0x15df19b8,
    0x02000100, 0x040002ff, 0x048404ff, 0x080006ab, 0x068e08ff, 0x073e07fc, 0x0b12096f, 0x10000eff,
    0x0bcd0fc0, 0x09c00d2a, 0x09820b08, 0x0a5e0af5, 0x0ca80c4b, 0x124a0fd1, 0x1dfe19e7, 0x1a7d1ef8,
    0x1994139c, 0x11911560, 0x0e6112ce, 0x0ce90f73, 0x0c420de5, 0x0c250d3d, 0x0c720d32, 0x0d3f0da7,
    0x0e8d0ea8, 0x10c71058, 0x145a1325, 0x1b4e1825, 0x2b58227e, 0x3b943909, 0x2a483bcb, 0x1a7d2058,
    0x02000100, 0x040002ff, 0x046d04ff, 0x0800067a, 0x067508ff, 0x070407d6, 0x0a54090e, 0x10000eff,
    0x0b9f10fe, 0x09890cf2, 0x09360ac1, 0x09e90a90, 0x0bd70ba9, 0x10590e8f, 0x1dfe162c, 0x1ffe1ef8,
    0x19131600, 0x112d1744, 0x0e03125a, 0x0c880f06, 0x0bd70d75, 0x0bab0cc1, 0x0bdf0ca2, 0x0c830cf6,
    0x0d940dc4, 0x0f5f0f20, 0x12251155, 0x1731151a, 0x213d1c2e, 0x3b8d2777, 0x3ddb2864, 0x1ffe29c8,
    0x02000100, 0x040002ff, 0x045704ff, 0x0800064c, 0x065c08ff, 0x06ce07b2, 0x09ae08b5, 0x10000e4c,
    0x0b7310fe, 0x09540cbb, 0x08ef0a7e, 0x097f0a33, 0x0b1f0b17, 0x0ec80d7d, 0x191f1362, 0x20001ef8,
    0x18981abe, 0x10cd1a40, 0x0daa11ed, 0x0c2c0ea0, 0x0b740d0c, 0x0b3a0c4e, 0x0b580c1e, 0x0bdc0c57,
    0x0cba0cfa, 0x0e2f0e13, 0x105f0fd6, 0x142912be, 0x1af617d3, 0x2b71222d, 0x3df13bcb, 0x2b1a3df1,
    0x02000100, 0x040002ff, 0x044404ff, 0x08000623, 0x064608ff, 0x069f0791, 0x09240867, 0x10000d26,
    0x0b4a10fe, 0x09240c89, 0x08b00a41, 0x092309e1, 0x0a860a9a, 0x0d8f0c9e, 0x15541155, 0x20001ef8,
    0x182920ff, 0x107619c1, 0x0d5a118b, 0x0bdb0e45, 0x0b1d0caf, 0x0ad70bea, 0x0ae40bab, 0x0b4d0bce,
    0x0c040c50, 0x0d380d36, 0x0efe0ea6, 0x11f310f5, 0x16e514cd, 0x21391be4, 0x3df12d2e, 0x3fd83e0f,
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::pattern_level::{effective_level, pack, table_entry};
    use crate::analysis::tessellator::{triangle_pattern, Pattern};
    use glam::DVec3;

    /// Exact `max_x Σμₖ|vₖ − x|²` of a triangle in f64.
    fn enclosing_r2(p: [DVec3; 3]) -> f64 {
        let e =
            [(p[1] - p[0]).length_squared(), (p[2] - p[1]).length_squared(), (p[0] - p[2]).length_squared()];
        let d2 = e[0].max(e[1]).max(e[2]);
        if 2.0 * d2 >= e[0] + e[1] + e[2] {
            return 0.25 * d2;
        }
        let x = (p[1] - p[0]).cross(p[2] - p[0]).length_squared();
        e[0] * e[1] * e[2] / (4.0 * x)
    }

    fn pattern_r2(p: &Pattern, corners: [DVec3; 3]) -> f64 {
        let place = |b: [f64; 3]| corners[0] * b[0] + corners[1] * b[1] + corners[2] * b[2];
        p.triangles.iter().map(|t| enclosing_r2(t.map(|i| place(p.vertices[i as usize])))).fold(0.0, f64::max)
    }

    struct Rng(u64);
    impl Rng {
        fn f(&mut self) -> f64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    fn random_shapes() -> Vec<[DVec3; 3]> {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut shapes = vec![
            [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 0.75f64.sqrt(), 0.0)],
            [DVec3::ZERO, DVec3::X, DVec3::Y],
            [DVec3::ZERO, DVec3::X, DVec3::new(0.0, 0.001, 0.0)],
            [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 0.001, 0.0)],
            [DVec3::ZERO, DVec3::X, DVec3::new(3.0, 0.01, 0.0)],
        ];
        for _ in 0..40 {
            let mut c = [DVec3::ZERO; 3];
            for p in &mut c {
                *p = DVec3::new(rng.f(), rng.f(), rng.f());
            }
            if rng.f() < 0.3 {
                c[2] = c[0].lerp(c[1], 2.0 * rng.f() - 0.5) + DVec3::new(rng.f(), rng.f(), rng.f()) * 1e-3;
            }
            shapes.push(c);
        }
        shapes
    }

    fn constants_of(c: [DVec3; 3]) -> PatternConstants {
        pattern_constants((c[1] - c[0]).as_vec3(), (c[2] - c[0]).as_vec3())
    }

    /// Relative growth of the uniform pattern's constant with the level from the driver's
    /// fixed-point placement, `K(n) ≤ K·(1 + n²·PATTERN_SLACK)` (the estimator now reads
    /// it, with the mixed patterns, from [`pattern_level`]).
    const PATTERN_SLACK: f32 = 2.0e-5;

    /// The pattern constants against the hardware pattern (Vulkan `equal_spacing`, inner =
    /// outer = n, lavapipe's fixed point): `max over sub-triangles of r² · n² ≤ K (1 + n²·s)`.
    #[test]
    fn pattern_constants_cover_the_hardware_pattern() {
        let shapes = random_shapes();
        let mut worst_slack = 0.0f64; // max over n of (ratio − 1)/n²
        let mut worst_ratio_16 = 0.0f64;
        let mut worst_ratio_64 = 0.0f64;
        for n in 1..=64u32 {
            let p = triangle_pattern(n as f32, [n as f32; 3]);
            for c in &shapes {
                let k = constants_of(*c);
                let bound = if n == 1 { k.sqrt_k1 } else { k.sqrt_k };
                let bound = f64::from(bound).powi(2);
                let real = pattern_r2(&p, *c) * f64::from(n * n);
                if bound == 0.0 {
                    assert!(real < 1e-12);
                    continue;
                }
                let ratio = real / bound;
                if n <= 16 {
                    worst_ratio_16 = worst_ratio_16.max(ratio);
                }
                worst_ratio_64 = worst_ratio_64.max(ratio);
                worst_slack = worst_slack.max((ratio - 1.0) / f64::from(n * n));
                assert!(
                    ratio <= 1.0 + f64::from(n * n) * f64::from(PATTERN_SLACK) + 1e-4,
                    "n = {n}, ratio {ratio}, shape {c:?}"
                );
            }
        }
        println!(
            "pattern constants: real/predicted r² at most {worst_ratio_16:.5} (n ≤ 16), {worst_ratio_64:.5} (n ≤ 64); (ratio − 1)/n² at most {worst_slack:.2e}"
        );
    }

    /// Measures (does not assert) how far mixed levels (outer ≥ inner, as a crack-free TCS
    /// that raises shared edges to the neighbour's level produces) exceed the uniform
    /// constants.
    #[test]
    fn pattern_constants_with_raised_outer_levels() {
        let shapes = random_shapes();
        let mut worst = (0.0f64, 0u32, [0u32; 3]);
        for n in 1..=12u32 {
            for m0 in [n, n + 1, n + 3, 16] {
                for m1 in [n, n + 2, 16] {
                    for m2 in [n, n + 5] {
                        let outer = [m0, m1, m2];
                        let p = triangle_pattern(n as f32, outer.map(|m| m as f32));
                        for c in &shapes {
                            let k = constants_of(*c);
                            let bound = f64::from(if n == 1 { k.sqrt_k1 } else { k.sqrt_k }).powi(2);
                            if bound == 0.0 {
                                continue;
                            }
                            let ratio = pattern_r2(&p, *c) * f64::from(n * n) / bound;
                            if ratio > worst.0 {
                                worst = (ratio, n, outer);
                            }
                        }
                    }
                }
            }
        }
        println!(
            "raised outer levels: real/predicted r² up to {:.4} (inner {}, outer {:?})",
            worst.0, worst.1, worst.2
        );
    }

    // ----- effective levels of the hardware patterns (mixed inner and outer levels) -----

    /// The effective level `L` of the model's pattern for `inner`, `outer`.
    fn pattern_level_exact(inner: u32, outer: [u32; 3]) -> f64 {
        let p = triangle_pattern(inner as f32, outer.map(|o| o as f32));
        effective_level(p.triangles.iter().map(|t| t.map(|v| p.vertices[v as usize])))
    }

    /// The packed table equals the levels measured on the driver's patterns (a sample of
    /// inner × outer levels; the full table is the same computation for all 64 × 64).
    #[test]
    fn pattern_level_table_matches_the_driver_patterns() {
        let levels = [1u32, 2, 3, 4, 5, 8, 13, 16, 31, 64];
        for &inner in &levels {
            for &outer in &levels {
                let expected = table_entry(pattern_level_exact(inner, [outer; 3]));
                let table = (pattern_level(inner, outer) * 256.0).round() as u32;
                assert_eq!(table, expected, "inner {inner}, outer {outer}");
            }
        }
    }

    /// The whole table against the driver's patterns. Every entry is checked when
    /// `MULTIRATE_PATTERN_LEVELS=print` is set, which also prints the packed words for
    /// `PATTERN_LEVELS`; otherwise every 7th entry (the full table takes a
    /// few seconds in a debug build).
    #[test]
    fn pattern_level_table_is_current() {
        let print = std::env::var("MULTIRATE_PATTERN_LEVELS").is_ok_and(|v| v == "print");
        for index in 0..4096u32 {
            if !print && index % 7 != 0 {
                continue;
            }
            let (inner, outer) = (index / 64 + 1, index % 64 + 1);
            let expected = table_entry(pattern_level_exact(inner, [outer; 3]));
            let table = (pattern_level(inner, outer) * 256.0).round() as u32;
            assert_eq!(
                table, expected,
                "inner {inner}, outer {outer}: regenerate with MULTIRATE_PATTERN_LEVELS=print"
            );
        }
        if print {
            let words = pack(|inner, outer| table_entry(pattern_level_exact(inner, [outer; 3])));
            for line in words.chunks(8) {
                let items: Vec<String> = line.iter().map(|w| format!("{w:#010x}")).collect();
                println!("    {},", items.join(", "));
            }
        }
    }

    /// The effective levels against sampled attribute maps: on the driver's patterns, no
    /// sub-triangle of any of the test shapes exceeds `K/L²` (the gauge argument is a bound),
    /// and the worst shape comes within a few per cent of it (the bound is tight).
    #[test]
    fn pattern_levels_bound_and_are_reached_by_sampled_shapes() {
        let mut shapes = random_shapes();
        for xi in -12..=16 {
            for y in [1e-3, 0.03, 0.1, 0.3, 0.6, 1.0, 2.0] {
                shapes.push([DVec3::ZERO, DVec3::X, DVec3::new(f64::from(xi) * 0.25, y, 0.0)]);
            }
        }
        let constants: Vec<f64> = shapes.iter().map(|c| f64::from(constants_of(*c).sqrt_k).powi(2)).collect();
        let mut loosest = 0.0f64;
        for (inner, outer) in [
            (4, 5),
            (6, 9),
            (7, 9),
            (8, 9),
            (10, 17),
            (12, 16),
            (12, 17),
            (13, 17),
            (16, 17),
            (9, 6),
            (12, 9),
            (17, 24),
            (24, 33),
            (48, 64),
            (64, 46),
        ] {
            let level = f64::from(pattern_level(inner, outer));
            let p = triangle_pattern(inner as f32, [outer as f32; 3]);
            let mut worst = 0.0f64; // max over shapes of max r² · L² / K
            for (c, &k) in shapes.iter().zip(&constants) {
                if k > 0.0 {
                    worst = worst.max(pattern_r2(&p, *c) * level * level / k);
                }
            }
            assert!(worst <= 1.0 + 1e-4, "inner {inner}, outer {outer}: r²·L²/K = {worst}");
            loosest = loosest.max(1.0 - worst);
            assert!(worst > 0.9, "inner {inner}, outer {outer}: the bound is loose ({worst})");
        }
        println!("effective levels: the sampled worst shapes reach r²·L²/K ≥ {:.4}", 1.0 - loosest);
    }

    /// A patch's effective level is the smallest of its edges' table entries: checked on
    /// patterns with three different outer levels.
    #[test]
    fn mixed_patterns_take_the_smallest_edge_level() {
        let mut rng = Rng(0x005e_ed1e_7e15);
        for _ in 0..150 {
            let pick = |rng: &mut Rng| 1 + (rng.f() * 24.0) as u32;
            let inner = pick(&mut rng);
            let outer = [pick(&mut rng), pick(&mut rng), pick(&mut rng)];
            let exact = pattern_level_exact(inner, outer);
            let table = outer.iter().map(|&o| pattern_level(inner, o)).fold(f32::MAX, f32::min);
            assert!(
                f64::from(table) <= exact + 1e-9,
                "inner {inner}, outer {outer:?}: table {table} > exact {exact}"
            );
            assert!(
                f64::from(table) >= exact.max(1.0) - 1.0 / 256.0 - 1e-9,
                "inner {inner}, outer {outer:?}"
            );
        }
    }

    /// The combination rule: shared edges agree, fallback triangles ask for nothing, the
    /// chosen pattern is fine enough and the smallest inner level that is.
    #[test]
    fn patch_levels_rule() {
        let mut rng = Rng(0x0ab5_0c1a_7e00);
        let level = |rng: &mut Rng| match (rng.f() * 6.0) as u32 {
            0 => FALLBACK_LEVEL,
            1 => 1.0,
            2 => f32::NAN,
            _ => 1.0 + (rng.f() * 20.0) as f32,
        };
        for _ in 0..20_000 {
            let n_max = [1u32, 4, 16, 64][(rng.f() * 4.0) as usize];
            let own = level(&mut rng);
            let nb = [level(&mut rng), level(&mut rng), level(&mut rng)];
            let p = patch_levels(own, nb, n_max);
            let own_n = uniform_level(own, n_max);
            for k in 0..3 {
                // Symmetric: the neighbour computes the same level for the shared edge.
                let theirs = patch_levels(nb[k], [own, own, own], n_max);
                assert_eq!(p.outer[k], theirs.outer[0], "own {own}, neighbour {}", nb[k]);
                assert!(p.outer[k] >= 1.0 && p.outer[k] <= n_max as f32 && p.outer[k].fract() == 0.0);
                assert!(p.outer[k] as u32 >= own_n);
            }
            assert!(p.inner >= 1.0 && p.inner <= n_max as f32 && p.inner.fract() == 0.0);
            if own_n == 0 {
                assert!(p.fallback && p.inner == 1.0, "{own} {p:?}");
            }
            let l = |i: u32| p.outer.iter().map(|&o| pattern_level(i, o as u32)).fold(f32::MAX, f32::min);
            if !p.fallback {
                let i = p.inner as u32;
                assert!(l(i) >= own, "{own} {p:?}");
                assert!((1..i).all(|j| l(j) < own), "not the smallest inner level: {own} {p:?}");
            } else if own_n > 0 {
                assert!((1..=n_max).all(|j| l(j) < own), "{own} {p:?}");
            }
            // All equal: the uniform pattern.
            if nb.iter().all(|&x| x == own) && own_n > 0 {
                assert_eq!(p.outer, [own_n as f32; 3]);
                assert!(!p.fallback && p.inner as u32 <= own_n);
            }
        }
    }

    /// Property test of the mixed patterns the rule draws: random triangles and lights (as in
    /// `tests/estimator_property.rs`, smaller), random neighbour levels (fallback, equal,
    /// higher, much higher), the pattern `triangle_pattern(inner, outer)` of `patch_levels`:
    /// its true error (oracle, close calls re-measured 16 times denser) must stay under ε.
    #[test]
    fn mixed_patterns_keep_the_error_under_epsilon() {
        use crate::analysis::oracle::{true_error_sampled, SAMPLES_PER_EDGE};
        let mut rng = Rng(0x0000_ddba_11c0_ffee);
        let (mut checked, mut mixed, mut worst) = (0usize, 0usize, 0.0f64);
        for case in 0..3000 {
            let brdf = case % 3;
            let f = |rng: &mut Rng| rng.f() as f32;
            let unit =
                |rng: &mut Rng| Vec3::new(f(rng) - 0.5, f(rng) - 0.5, f(rng) - 0.5).normalize_or(Vec3::Z);
            let dist = 0.5 + 10.0 * f(&mut rng);
            let dir = unit(&mut rng);
            let centre = dir * dist;
            let base = (-dir + unit(&mut rng) * 0.8).normalize_or(-dir);
            let (t1, t2) = base.any_orthonormal_pair();
            let size = dist * (0.005 + 0.2 * f(&mut rng));
            let corners: [Vec3; 3] = std::array::from_fn(|_| {
                centre + (t1 * (f(&mut rng) - 0.5) + t2 * (f(&mut rng) - 0.5)) * size
            });
            let spread = 0.6 * f(&mut rng) * f(&mut rng);
            let normals: [Vec3; 3] =
                std::array::from_fn(|_| (base + unit(&mut rng) * spread).normalize_or(base));
            let tri = TriangleInput { positions: corners, normals, eye: Vec3::ZERO };
            let mut lights = Vec::new();
            for _ in 0..1 + (f(&mut rng) * 2.0) as usize {
                let l = (base + unit(&mut rng) * 1.2).normalize_or(base);
                if f(&mut rng) < 0.6 {
                    let d = size * (0.5 + 30.0 * f(&mut rng));
                    lights.push(Light::Point {
                        position: centre + l * d,
                        color: Vec3::new(1.0, 0.8, 0.6),
                        intensity: d * d * (0.5 + 2.0 * f(&mut rng)),
                    });
                } else {
                    lights.push(Light::Directional {
                        direction: -l,
                        color: Vec3::ONE,
                        intensity: 0.5 + f(&mut rng),
                    });
                }
            }
            let material = match brdf {
                0 => MaterialKind::Lambert { kd: Vec3::new(0.9, 0.5, 0.2) },
                1 => MaterialKind::BlinnPhong {
                    kd: Vec3::splat(0.4),
                    ks: Vec3::splat(0.6),
                    shininess: 2.0 + 200.0 * f(&mut rng),
                },
                _ => MaterialKind::Ggx {
                    albedo: Vec3::splat(0.4),
                    f0: Vec3::new(0.04, 0.5, 0.9),
                    roughness: 0.2 + 0.8 * f(&mut rng),
                },
            };
            let epsilon = [0.01f32, 0.03, 0.1][(f(&mut rng) * 3.0) as usize];
            let settings = EstimatorSettings { epsilon, n_max: 16, ..EstimatorSettings::default() };
            let own = estimate(&tri, &material, &lights, &settings);
            if own.fallback {
                continue;
            }
            let neighbours: [f32; 3] = std::array::from_fn(|_| match (f(&mut rng) * 4.0) as u32 {
                0 => FALLBACK_LEVEL,
                1 => own.level,
                2 => own.level * (1.0 + 2.0 * f(&mut rng)),
                _ => 1.0 + 16.0 * f(&mut rng),
            });
            let p = patch_levels(own.level, neighbours, 16);
            if p.fallback {
                continue;
            }
            checked += 1;
            if p.outer.iter().any(|&o| o != p.inner) {
                mixed += 1;
            }
            let pattern = triangle_pattern(p.inner, p.outer);
            let eps = f64::from(epsilon);
            let mut error =
                true_error_sampled(&tri, &material, &lights, &pattern, SAMPLES_PER_EDGE, f64::INFINITY);
            if error.iter().any(|&e| e > 0.5 * eps) {
                let fine = true_error_sampled(&tri, &material, &lights, &pattern, 24, f64::INFINITY);
                error = std::array::from_fn(|c| error[c].max(fine[c]));
            }
            let e = error.iter().copied().fold(0.0, f64::max);
            worst = worst.max(e / eps);
            assert!(e <= eps, "case {case}: true error {e} > ε {eps} on {p:?} (level {}), {material:?}, {lights:?}, {tri:?}", own.level);
        }
        println!("mixed patterns: {checked} patches checked, {mixed} with raised or lowered edges; largest true error / ε: {worst:.3}");
        assert!(mixed > 1000, "too few mixed patterns: {mixed}");
    }

    /// The estimator's own elementary functions against f64 libm.
    #[test]
    fn elementary_functions_are_accurate() {
        let mut worst = [0.0f64; 6];
        for i in 0..=200_000 {
            let x = -1.0 + 8.5 * f64::from(i) / 200_000.0; // [−1, 7.5] rad
            let xf = x as f32;
            let xd = f64::from(xf);
            worst[0] = worst[0].max((f64::from(est_sin(xf)) - xd.sin()).abs());
            worst[1] = worst[1].max((f64::from(est_cos(xf)) - xd.cos()).abs());
            let t = (-3.0 + 6.0 * f64::from(i) / 200_000.0) as f32; // [−3, 3]
            let (y, z) = (t.abs(), 1.0 - 0.5 * t);
            let exact = f64::from(y).atan2(f64::from(z));
            worst[2] = worst[2].max((f64::from(est_atan2(y, z)) - exact).abs());
            let c = (f64::from(i) / 200_000.0) as f32; // [0, 1]
            worst[3] = worst[3].max((f64::from(est_acos(c)) - f64::from(c).acos()).abs());
            worst[4] = worst[4]
                .max((f64::from(est_asin(c.min(0.999_999))) - f64::from(c.min(0.999_999)).asin()).abs());
            if c > 0.0 {
                for e in [0.5f32, 2.0, 63.0, 1.0e4] {
                    let exact = f64::from(c).powf(f64::from(e));
                    if exact > 1.0e-30 {
                        // Relative error, in units of the exponent (the error of log2 is amplified by e).
                        let rel = (f64::from(est_pow(c, e)) / exact - 1.0).abs() / f64::from(e).max(1.0);
                        worst[5] = worst[5].max(rel);
                    }
                }
            }
        }
        println!("max errors: sin {:.2e}, cos {:.2e}, atan2 {:.2e}, acos {:.2e}, asin {:.2e} (rad); pow relative / exponent {:.2e}", worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]);
        assert!(worst[..5].iter().all(|&w| w < 5.0e-7), "{worst:?}");
        assert!(worst[5] < 1.0e-6, "{worst:?}");
        assert_eq!(est_pow(0.3, 0.0), 1.0);
        assert_eq!(est_pow(0.3, 1.0), 0.3);
        assert_eq!(est_pow(0.0, 2.0), 0.0);
        assert_eq!(est_atan2(0.0, 0.0), 0.0);
        assert_eq!(est_atan2(0.0, -1.0), PI);
        assert_eq!(est_acos(1.0), 0.0);
    }

    // ----- robustness -----

    fn sane(e: &Estimate, n_max: u32, what: &str) {
        assert!(e.n >= 1 && e.n <= n_max, "{what}: n = {}", e.n);
        assert!(
            e.predicted_error.is_finite() && e.predicted_error >= 0.0,
            "{what}: predicted {}",
            e.predicted_error
        );
        assert!(e.terms.iter().all(|t| t.is_finite() && *t >= 0.0), "{what}: terms {:?}", e.terms);
        assert_eq!(e.fallback, e.reason != Reason::None, "{what}");
        if e.fallback {
            assert_eq!(e.n, 1, "{what}");
            assert_eq!(e.level, FALLBACK_LEVEL, "{what}");
        } else {
            // The real level: at least 1, within the uniform level's reach, never NaN.
            assert!(e.level >= 1.0 && e.level <= pattern_level(n_max, n_max), "{what}: level {}", e.level);
            assert_eq!(uniform_level(e.level, n_max), e.n, "{what}");
        }
    }

    fn base() -> TriangleInput {
        TriangleInput {
            positions: [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.3, 0.8, 0.0)],
            normals: [
                Vec3::new(-0.1, -0.05, 1.0).normalize(),
                Vec3::new(0.1, -0.05, 1.0).normalize(),
                Vec3::new(0.0, 0.1, 1.0).normalize(),
            ],
            eye: Vec3::new(0.4, -1.0, 3.0),
        }
    }

    fn materials() -> Vec<MaterialKind> {
        vec![
            MaterialKind::Lambert { kd: Vec3::new(0.8, 0.5, 0.2) },
            MaterialKind::BlinnPhong { kd: Vec3::splat(0.4), ks: Vec3::splat(0.6), shininess: 1.0 },
            MaterialKind::BlinnPhong { kd: Vec3::splat(0.4), ks: Vec3::splat(0.6), shininess: 60.0 },
            MaterialKind::BlinnPhong { kd: Vec3::splat(0.4), ks: Vec3::splat(0.6), shininess: 1.0e4 },
            MaterialKind::Ggx { albedo: Vec3::splat(0.5), f0: Vec3::new(0.04, 0.5, 1.0), roughness: 0.0 },
            MaterialKind::Ggx { albedo: Vec3::splat(0.5), f0: Vec3::splat(0.04), roughness: 0.5 },
            MaterialKind::Ggx { albedo: Vec3::splat(0.5), f0: Vec3::splat(0.9), roughness: 1.0 },
        ]
    }

    fn point(p: Vec3) -> Light {
        Light::Point { position: p, color: Vec3::new(1.0, 0.9, 0.8), intensity: 4.0 }
    }

    fn sun(d: Vec3) -> Light {
        Light::Directional { direction: d.normalize(), color: Vec3::ONE, intensity: 2.0 }
    }

    fn light_sets(t: &TriangleInput) -> Vec<(&'static str, Vec<Light>)> {
        let c = (t.positions[0] + t.positions[1] + t.positions[2]) / 3.0;
        let size = (t.positions[1] - t.positions[0]).length().max(1e-30);
        vec![
            ("point above", vec![point(c + Vec3::new(0.1, 0.2, 1.0) * size)]),
            ("sun", vec![sun(Vec3::new(0.2, 0.3, -1.0))]),
            ("grazing sun", vec![sun(Vec3::new(1.0, 0.0, -0.02))]),
            ("sun in the plane", vec![sun(Vec3::new(1.0, 0.3, 0.0))]),
            ("back-facing sun", vec![sun(Vec3::new(0.0, 0.2, 1.0))]),
            ("light at a vertex", vec![point(t.positions[1])]),
            ("light on the surface", vec![point(c)]),
            ("light just above", vec![point(c + Vec3::Z * 1e-3 * size)]),
            ("far point", vec![point(c + Vec3::new(3.0, 1.0, 1e4) * size)]),
            (
                "dark light at a vertex",
                vec![Light::Point { position: t.positions[0], color: Vec3::ONE, intensity: 0.0 }],
            ),
            (
                "three lights",
                vec![
                    point(c + Vec3::new(-1.0, 0.0, 2.0) * size),
                    sun(Vec3::new(0.0, 0.0, -1.0)),
                    sun(Vec3::new(0.0, 1.0, 0.3)),
                ],
            ),
        ]
    }

    fn triangles() -> Vec<(&'static str, TriangleInput)> {
        let b = base();
        let mut out = vec![("base", b)];
        let mut t = b;
        t.positions[2] = t.positions[0].lerp(t.positions[1], 0.3);
        out.push(("zero area", t));
        let mut t = b;
        t.positions = [Vec3::new(0.2, 0.1, 0.0); 3];
        out.push(("a point", t));
        let mut t = b;
        t.positions[2] = Vec3::new(0.5, 1e-5, 0.0);
        out.push(("needle", t));
        let mut t = b;
        t.normals = [Vec3::Z; 3];
        out.push(("identical normals", t));
        let mut t = b;
        t.normals = [Vec3::Z, -Vec3::Z, Vec3::X];
        out.push(("opposite normals", t));
        let mut t = b;
        let r = |a: f32| Vec3::new(a.cos(), a.sin(), 0.0);
        t.normals = [r(0.0), r(2.094_395), r(4.188_79)];
        out.push(("120 degrees in a plane", t));
        let mut t = b;
        t.normals = [Vec3::ZERO, Vec3::Z, Vec3::Z];
        out.push(("a zero normal", t));
        let mut t = b;
        t.normals = [b.normals[0] * 3.0, b.normals[1] * 0.2, b.normals[2]];
        out.push(("unnormalised normals", t));
        let mut t = b;
        t.normals = [
            Vec3::new(0.7, 0.0, 0.7).normalize(),
            Vec3::new(-0.7, 0.0, 0.7).normalize(),
            Vec3::new(0.0, 0.7, 0.7).normalize(),
        ];
        out.push(("strongly curved", t));
        let mut t = b;
        t.eye = (b.positions[0] + b.positions[1] + b.positions[2]) / 3.0;
        out.push(("eye on the surface", t));
        let mut t = b;
        t.eye = b.positions[0] + Vec3::new(5.0, 0.0, 0.0);
        out.push(("eye in the plane", t));
        for (name, scale, offset) in [
            ("at 1e6", 1.0, 1.0e6),
            ("size 1e6", 1.0e6, 0.0),
            ("size 1e-6", 1.0e-6, 0.0),
            ("1e-6 at 1e3", 1.0e-6, 1.0e3),
        ] {
            let mut t = b;
            t.positions = b.positions.map(|p| p * scale + Vec3::splat(offset));
            t.eye = b.eye * scale + Vec3::splat(offset);
            out.push((name, t));
        }
        out
    }

    fn all_settings(eps: f32) -> Vec<EstimatorSettings> {
        let mut v = Vec::new();
        for split in [Split::Uniform, Split::Heuristic] {
            for discontinuity in [Discontinuity::Conservative, Discontinuity::Relaxed] {
                v.push(EstimatorSettings { epsilon: eps, n_max: 16, split, discontinuity });
            }
        }
        v
    }

    /// The falloff's jet (`attenuation_jet`) against its exact value and derivatives, by
    /// central differences in f64 at points of random triangles and along random in-plane
    /// directions: lights far away, closer than the triangle's size and grazing (in the
    /// triangle's plane, where `D²(1/d²)` reaches `6/d⁴`).
    /// A unit vector field `normalize(m₀ + t·dm)` along `t ∈ [0, 1]` (an affine `m`, as the
    /// estimator's normal and light fields are), with the bounds the estimator uses:
    /// `|dû/dt| ≤ |dm|/min|m|` and `|û·dm|/|m| ≤ max|m·dm|/min|m|²` (`m·dm` is affine in `t`).
    struct UnitField {
        m0: DVec3,
        dm: DVec3,
    }

    impl UnitField {
        fn random(rng: &mut crate::test_rng::Rng, speed: f64) -> UnitField {
            let mut v = || rng.point(Vec3::splat(-1.0), Vec3::ONE).as_dvec3();
            let (m0, dm) = (v().normalize_or(DVec3::Z), v().normalize_or(DVec3::X));
            let m0 = m0 * (0.2 + 1.8 * f64::from(rng.f()));
            let dm = dm * speed * m0.length() * f64::from(rng.f());
            UnitField { m0, dm }
        }

        fn at(&self, t: f64) -> DVec3 {
            (self.m0 + self.dm * t).normalize()
        }

        fn min_length(&self) -> f64 {
            let t = (-self.m0.dot(self.dm) / self.dm.length_squared().max(1e-300)).clamp(0.0, 1.0);
            (self.m0 + self.dm * t).length()
        }

        fn field(&self, term: Term) -> Field {
            let min = self.min_length();
            let along = self.m0.dot(self.dm).abs().max((self.m0 + self.dm).dot(self.dm).abs());
            let w = (self.dm.length() / min) as f32;
            Field { w, radial: ((along / (min * min)) as f32).min(w), x: 0.0, term }
        }
    }

    /// `f`, `f'` and `f''` at `t` by central differences of step `h`.
    fn differences(f: &dyn Fn(f64) -> f64, t: f64, h: f64) -> [f64; 3] {
        let (fm, f0, fp) = (f(t - h), f(t), f(t + h));
        [f0, (fp - fm) / (2.0 * h), (fp - 2.0 * f0 + fm) / (h * h)]
    }

    /// The range of `angle(t)` over `t ∈ [0, 1]`, sampled densely and widened by 10⁻³.
    fn angle_range(angle: &dyn Fn(f64) -> f64) -> (f32, f32) {
        let samples = (0..=4000).map(|i| angle(f64::from(i) / 4000.0));
        let (lo, hi) = samples.fold((f64::INFINITY, 0.0f64), |(lo, hi), a| (lo.min(a), hi.max(a)));
        ((lo - 1e-3).max(0.0) as f32, (hi + 1e-3).min(std::f64::consts::PI) as f32)
    }

    /// Checks a jet against `f` at 60 points of `[0, 1]` (away from the ends by `h`): `|f| ≤ m`
    /// (or `f ≥ m` with `m_is_min`), `|f'| ≤ g`, `|f''| ≤ t`, and returns the largest `|f''|/t`
    /// (the differences' rounding allowed for: 10⁻³ relative, 10⁻⁶ absolute).
    fn check_jet(jet: &Jet, f: &dyn Fn(f64) -> f64, h: f64, m_is_min: bool, what: &str) -> f64 {
        let mut tightest = 0.0f64;
        for i in 0..60 {
            let t = h + (1.0 - 2.0 * h) * f64::from(i) / 59.0;
            let [value, first, second] = differences(f, t, h);
            let slack = |bound: f32| f64::from(bound) * 1.001 + 1e-6;
            if m_is_min {
                assert!(value >= f64::from(jet.m) - 1e-6, "{what}, t {t}: value {value} < {}", jet.m);
            } else {
                assert!(value.abs() <= slack(jet.m), "{what}, t {t}: value {value} > {}", jet.m);
            }
            assert!(first.abs() <= slack(jet.g), "{what}, t {t}: first {first} > {}", jet.g);
            assert!(second.abs() <= slack(jet.t), "{what}, t {t}: second {second} > {}", jet.t);
            tightest = tightest.max(second.abs() / (f64::from(jet.t) + 1e-6));
        }
        tightest
    }

    /// Two random unit fields whose angle stays within `max_angle`, with their jets' inputs.
    /// Every other pair turns in one plane in opposite senses, starting across its `m`: there
    /// the angle between them changes at the full `w_a + w_b` (at `t = 0`), where the bounds
    /// are reached.
    fn field_pair(
        rng: &mut crate::test_rng::Rng,
        max_angle: f64,
    ) -> Option<(UnitField, UnitField, (f32, f32))> {
        let speed = [0.1, 1.0, 4.0][rng.below(3) as usize];
        let (a, b) = if rng.below(2) == 0 {
            (UnitField::random(rng, speed), UnitField::random(rng, speed))
        } else {
            let planar = |angle: f64, sense: f64, rng: &mut crate::test_rng::Rng| {
                let m0 = DVec3::new(angle.cos(), angle.sin(), 0.0) * (0.2 + 1.8 * f64::from(rng.f()));
                let dm = DVec3::Z.cross(m0) * sense * speed * f64::from(rng.f());
                UnitField { m0, dm }
            };
            let start = f64::from(rng.range(0.0, max_angle.min(3.0) as f32));
            (planar(start, 1.0, rng), planar(0.0, -1.0, rng))
        };
        let psi = angle_range(&|t| a.at(t).angle_between(b.at(t)));
        (f64::from(psi.1) <= max_angle).then_some((a, b, psi))
    }

    /// Runs `case` on 2 000 pairs of fields (seeded) whose angle stays within `max_angle`, and
    /// returns the largest of each figure it reports (how close its bounds came).
    fn over_field_pairs<const N: usize>(
        seed: u64,
        max_angle: f64,
        mut case: impl FnMut(&mut crate::test_rng::Rng, usize, &UnitField, &UnitField, (f32, f32)) -> [f64; N],
    ) -> [f64; N] {
        let mut rng = crate::test_rng::Rng(seed);
        let (mut checked, mut tightest) = (0, [0.0f64; N]);
        while checked < 2000 {
            let Some((a, b, psi)) = field_pair(&mut rng, max_angle) else { continue };
            let figures = case(&mut rng, checked, &a, &b, psi);
            tightest = std::array::from_fn(|k| tightest[k].max(figures[k]));
            checked += 1;
        }
        tightest
    }

    #[test]
    fn cosine_jet_bounds_the_exact_derivatives() {
        let [tightest] = over_field_pairs(0xc051_e7e7, std::f64::consts::PI, |_, case, a, b, psi| {
            let jet = cosine(&a.field(Term::Normal), &b.field(Term::Light), psi, &Guard::default());
            let what = format!("case {case}: ψ {psi:?}");
            [check_jet(&jet, &|t| a.at(t).dot(b.at(t)), 1e-4, false, &what)]
        });
        eprintln!("cosine: largest |c''| reaches {tightest:.3} of the bound");
        assert!(tightest > 0.9, "the cosine bound is never approached: {tightest}");
    }

    /// The lobes' net coefficients are the largest values of their functions over the range
    /// (dense sampling in f64 never exceeds them, and comes within 0.1 % of them), for
    /// shininess 2–10⁴ (also as textured ranges) and roughness down to 0, over random ranges.
    #[test]
    fn lobe_net_coefficients_are_the_maxima_over_the_range() {
        let mut rng = crate::test_rng::Rng(0x6e7_c0ef_f1c1_e475);
        // A linear grid and two dense near the range's ends (GGX's peak for small α is at
        // s₂ ≈ α², the power's for large s at x ≈ 1 − 2/s).
        let sampled_max = |f: &dyn Fn(f64) -> f64, lo: f64, hi: f64| {
            let linear = (0..=20_000).map(|i| lo + (hi - lo) * f64::from(i) / 20_000.0);
            let near = (0..=20_000).map(|i| lo + (hi - lo) * (f64::from(i) / 20_000.0).powi(4));
            let far = (0..=20_000).map(|i| hi - (hi - lo) * (f64::from(i) / 20_000.0).powi(4));
            linear.chain(near).chain(far).map(f).fold(0.0f64, f64::max)
        };
        let mut reached = [0usize; 2];
        for case in 0..2_000 {
            let (a, b) = (rng.range(0.0, 1.5), rng.range(0.0, 1.5));
            let (h0, h1) = (a.min(b), a.max(b).min(FRAC_PI_2));
            if case % 2 == 0 {
                let s0 = rng.range(2.0f32.ln(), 10_000f32.ln()).exp();
                let s1 = if case % 4 == 0 { s0 } else { s0 * rng.range(1.0, 3.0) };
                let (c0, c1) = (est_cos(h0), est_cos(h1).max(0.0));
                let got = f64::from(power_net_coefficient(s0, s1, c0, c1));
                let (p, s1d) = (0.5 * (f64::from(s0) - 2.0), f64::from(s1));
                let f = |x: f64| s1d * x.powf(p) * ((s1d - 1.0) * (1.0 - x) - x).max(0.0);
                let want = sampled_max(&f, f64::from(c1 * c1), f64::from(c0 * c0));
                assert!(want <= got * 1.0001 + 1e-30, "power s {s0}..{s1}, ψ {h0}..{h1}: {want} > {got}");
                assert!(got <= want * 1.001 + 1e-30, "power s {s0}..{s1}, ψ {h0}..{h1}: {got} ≫ {want}");
                reached[0] += usize::from(want > 0.0);
            } else {
                let alpha = if case % 10 == 1 { 1.0e-3f32 } else { rng.range(0.001, 1.0) };
                let a2 = alpha * alpha;
                let (s0, s1) = (est_sin(h0).powi(2), est_sin(h1).powi(2));
                let got = f64::from(ggx_net_coefficient(a2, s0, s1));
                let (a2d, beta) = (f64::from(a2), 1.0 - f64::from(a2));
                // D''(t)·sin²ψ − D'(t)·t in s₂ = sin²ψ, from D = α²/(πu²).
                let f = |x: f64| {
                    let (u, t2) = (a2d + beta * x, 1.0 - x);
                    let d1 = 4.0 * a2d * beta / (std::f64::consts::PI * u * u * u);
                    let d2 = d1 * (u + 6.0 * beta * t2) / u;
                    (d2 * x - d1 * t2).max(0.0)
                };
                let want = sampled_max(&f, f64::from(s0), f64::from(s1));
                assert!(want <= got * 1.0001 + 1e-30, "GGX α {alpha}, ψ {h0}..{h1}: {want} > {got}");
                assert!(got <= want * 1.001 + 1e-30, "GGX α {alpha}, ψ {h0}..{h1}: {got} ≫ {want}");
                reached[1] += usize::from(want > 0.0);
            }
        }
        assert!(reached[0] > 300 && reached[1] > 300, "{reached:?}: too few ranges with a positive net part");
    }

    #[test]
    fn power_jet_bounds_the_exact_derivatives() {
        let [tightest] =
            over_field_pairs(0x90e7_b10b, std::f64::consts::FRAC_PI_2, |rng, case, n, h, psi| {
                let gd = Guard::default();
                let (fn_, fh) = (n.field(Term::Normal), h.field(Term::Half));
                let c = cosine(&fn_, &fh, psi, &gd);
                let curv = curvature(&fn_, &fh, psi, &gd);
                // Shininess log-uniform in [1, 10⁴], a single value or a textured range.
                let s0 = 10f32.powf(4.0 * rng.f());
                let s1 = if rng.below(2) == 0 { s0 } else { (s0 * 10f32.powf(rng.f())).min(1.0e4) };
                let jet = power_jet(&c, &curv, (s0, s1), psi, fn_.w + fh.w, &gd);
                assert!(!gd.bad.get(), "saturated");
                let tightness = [s0, (s0 * s1).sqrt(), s1].map(|s| {
                    let what = format!("case {case}: ψ {psi:?}, s {s} in [{s0}, {s1}]");
                    let step = 1e-4 / f64::from(s).sqrt();
                    let lobe = |t: f64| n.at(t).dot(h.at(t)).max(0.0).powf(f64::from(s));
                    check_jet(&jet, &lobe, step, false, &what)
                });
                [tightness.into_iter().fold(0.0, f64::max)]
            });
        eprintln!("power: largest |T''| reaches {tightest:.3} of the bound");
        assert!(tightest > 0.9, "the power bound is never approached: {tightest}");
    }

    #[test]
    fn ggx_d_jet_bounds_the_exact_derivatives() {
        let [tightest] = over_field_pairs(0xd15_7d15, std::f64::consts::FRAC_PI_2, |rng, case, n, h, psi| {
            let gd = Guard::default();
            let (fn_, fh) = (n.field(Term::Normal), h.field(Term::Half));
            let c = cosine(&fn_, &fh, psi, &gd);
            let curv = curvature(&fn_, &fh, psi, &gd);
            // Roughness 0 (α at its floor) up to 1.
            let roughness = if case % 10 == 0 { 0.0 } else { rng.range(0.05, 1.0) };
            let alpha = crate::shading::brdf::ggx_alpha(roughness);
            let jet = ggx_d_jet(&c, &curv, psi.0, psi.1, fn_.w + fh.w, alpha, &gd);
            assert!(!gd.bad.get(), "saturated");
            let a2 = f64::from(alpha).powi(2);
            let d = |t: f64| {
                let c = n.at(t).dot(h.at(t));
                a2 / (std::f64::consts::PI * (c * c * (a2 - 1.0) + 1.0).powi(2))
            };
            let what = format!("case {case}: ψ {psi:?}, α {alpha}");
            // The step follows D's width in t: about max(α, sin ψ) in angle, over the speed.
            let width = f64::from(alpha).max(f64::from(psi.0).sin()) / f64::from(fn_.w + fh.w).max(1.0);
            [check_jet(&jet, &d, 1e-3 * width.min(0.1), false, &what)]
        });
        eprintln!("GGX D: largest |D''| reaches {tightest:.3} of the bound");
        assert!(tightest > 0.9, "the D bound is never approached: {tightest}");
    }

    #[test]
    fn half_cosine_and_fresnel_jets_bound_the_exact_derivatives() {
        let [tightest_vh, tightest_f] = over_field_pairs(0xf7e5_11e1, 3.0, |_, case, l, v, psi| {
            let gd = Guard::default();
            let m_min = (0..=4000)
                .map(|i| (l.at(f64::from(i) / 4000.0) + v.at(f64::from(i) / 4000.0)).length())
                .fold(f64::INFINITY, f64::min)
                * 0.99;
            let vh = half_cosine_jet(&l.field(Term::Light), &v.field(Term::View), psi.1, m_min as f32, &gd);
            let u = |t: f64| 0.5 * (l.at(t) + v.at(t)).length();
            let what = format!("case {case}: ∠(l, v) {psi:?}");
            let tight_vh = check_jet(&vh, &u, 1e-4, true, &what);
            // Fresnel's own rule, on the exact range and derivatives of u (a little widened),
            // so that the looser v·h jet does not hide a loose Fresnel bound; and on the v·h
            // jet as the estimator feeds it.
            let samples: Vec<[f64; 3]> =
                (0..=2000).map(|i| differences(&u, 1e-4 + 0.9998 * f64::from(i) / 2000.0, 1e-4)).collect();
            let sup = |k: usize| samples.iter().map(|d| d[k].abs()).fold(0.0, f64::max) as f32 * 1.002 + 1e-6;
            let u_min = samples.iter().map(|d| d[0]).fold(f64::INFINITY, f64::min) as f32 - 1e-6;
            let exact = Jet { m: u_min, g: sup(1), h: NO_H, t: sup(2) };
            let f0 = [0.02, 0.04, 0.5, 0.95][case % 4];
            let f = |t: f64| f64::from(f0) + (1.0 - f64::from(f0)) * (1.0 - u(t)).powi(5);
            check_jet(&fresnel_jet(f0, &vh, &gd), &f, 1e-4, false, &format!("{what}, f₀ {f0}, v·h jet"));
            let tight_f =
                check_jet(&fresnel_jet(f0, &exact, &gd), &f, 1e-4, false, &format!("{what}, f₀ {f0}"));
            [tight_vh, tight_f]
        });
        eprintln!("v·h: largest second derivative {tightest_vh:.3} of the bound; Fresnel {tightest_f:.3}");
        assert!(tightest_vh > 0.75 && tightest_f > 0.9, "never approached: {tightest_vh}, {tightest_f}");
    }

    #[test]
    fn smith_jets_bound_the_exact_derivatives() {
        let [tightest_g, tightest_v] =
            over_field_pairs(0x5317_4a1f, std::f64::consts::FRAC_PI_2, |rng, case, n, l, psi| {
                let gd = Guard::default();
                let c = cosine(&n.field(Term::Normal), &l.field(Term::Light), psi, &gd);
                let roughness = if case % 10 == 0 { 0.0 } else { rng.range(0.05, 1.0) };
                let k = 0.5 * crate::shading::brdf::ggx_alpha(roughness);
                let (kk, cos) = (f64::from(k), |t: f64| n.at(t).dot(l.at(t)).max(0.0));
                let what = format!("case {case}: ψ {psi:?}, k {k}");
                let g_exact = |t: f64| cos(t) / (cos(t) * (1.0 - kk) + kk);
                let v_exact = |t: f64| 1.0 / (cos(t) * (1.0 - kk) + kk);
                [
                    check_jet(&smith_g_jet(&c, psi, k, &gd), &g_exact, 1e-4, false, &what),
                    check_jet(&smith_v_jet(&c, psi, k, &gd), &v_exact, 1e-4, false, &what),
                ]
            });
        eprintln!("Smith: largest second derivative G {tightest_g:.3}, V {tightest_v:.3} of the bound");
        assert!(tightest_g > 0.9 && tightest_v > 0.9, "never approached: {tightest_g}, {tightest_v}");
    }

    #[test]
    fn attenuation_jet_bounds_the_exact_derivatives() {
        let mut rng = crate::test_rng::Rng(0x5eed_a77e);
        let mut range = |lo: f64, hi: f64| f64::from(rng.range(lo as f32, hi as f32));
        let (mut checked, mut tightest) = (0usize, 0.0f64);
        for case in 0..400 {
            let mut corner = || DVec3::new(range(-1.0, 1.0), range(-1.0, 1.0), range(-0.2, 0.2));
            let tri = [corner(), corner(), corner()];
            let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
            if normal.length() < 1e-2 {
                continue;
            }
            let normal = normal.normalize();
            let centre = (tri[0] + tri[1] + tri[2]) / 3.0;
            let far = case % 3;
            let light = match far {
                // Grazing: in the plane, outside the triangle.
                0 => centre + (tri[0] - centre) * range(1.2, 3.0),
                // Close: less than the triangle's size above it.
                1 => centre + normal * range(0.05, 0.5) + (tri[1] - centre) * range(0.0, 0.9),
                _ => centre + DVec3::new(range(-5.0, 5.0), range(-5.0, 5.0), range(2.0, 8.0)),
            };
            // Points of the triangle on a dense barycentric grid: d_min and max sin γ over it
            // (the estimator's cones give bounds of these), a little on the safe side.
            let points: Vec<DVec3> = (0..=40)
                .flat_map(|i| (0..=40 - i).map(move |j| (i, j)))
                .map(|(i, j)| {
                    let (u, v) = (f64::from(i) / 40.0, f64::from(j) / 40.0);
                    tri[0] + (tri[1] - tri[0]) * u + (tri[2] - tri[0]) * v
                })
                .collect();
            let d_min = points.iter().map(|p| (light - *p).length()).fold(f64::INFINITY, f64::min) * 0.98;
            let sin_max = points
                .iter()
                .map(|p| {
                    let l = (light - *p).normalize();
                    (l - normal * l.dot(normal)).length()
                })
                .fold(0.0, f64::max)
                .min(1.0);
            let jet = attenuation_jet((1.0 / d_min) as f32, sin_max as f32, 1.0, &Guard::default());
            let falloff = |x: DVec3| 1.0 / (light - x).length_squared();
            for p in points.iter().step_by(7) {
                let angle = range(0.0, std::f64::consts::TAU);
                let e1 = (tri[1] - tri[0]).normalize();
                let e2 = normal.cross(e1);
                let u = e1 * angle.cos() + e2 * angle.sin();
                let [f0, first, second] = differences(&|s| falloff(*p + u * s), 0.0, 1e-4 * d_min);
                let what = format!("case {case}: light {light:?}, point {p:?}");
                assert!(f0 <= f64::from(jet.m) * 1.0001, "{what}: value {f0} > {}", jet.m);
                assert!(first.abs() <= f64::from(jet.g) * 1.0001, "{what}: first {first} > {}", jet.g);
                assert!(second.abs() <= f64::from(jet.t) * 1.001, "{what}: second {second} > {}", jet.t);
                tightest = tightest.max(second.abs() / f64::from(jet.t));
                checked += 1;
            }
        }
        assert!(checked > 5_000, "{checked} points checked");
        // The bound is reached within a few per cent (grazing lights): not just valid, tight.
        assert!(tightest > 0.85, "the largest second derivative is only {tightest} of the bound");
    }

    /// The irradiance jet (`n̂·I`, `I = (p − x)/|p − x|³`, as the estimator sets it up) against
    /// f64 central differences along random steps at points of random triangles: lights far,
    /// close above the triangle (nearer than its size) and grazing (near its plane, outside it);
    /// flat normals (the light part alone: `projected` and `whole` reach their bound) and
    /// curved ones (the normal and cross parts too).
    /// A random triangle of size `size` with flat or (`curved`) bent normals, and a point
    /// light far (`kind` 0), close above it (nearer than its size, 1) or grazing (near its
    /// plane, outside it, 2). `None` for a near-degenerate triangle.
    fn irradiance_case(
        rng: &mut crate::test_rng::Rng,
        size: f32,
        curved: bool,
        kind: usize,
    ) -> Option<(TriangleInput, Vec3)> {
        let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
        let positions = [0; 3].map(|_| centre + rng.point(Vec3::splat(-size), Vec3::splat(size)));
        let plane = (positions[1] - positions[0]).cross(positions[2] - positions[0]);
        if plane.length() < 0.05 * size * size {
            return None;
        }
        let plane = plane.normalize();
        let normals = positions.map(|x| {
            let bend = if curved { (x - centre) * rng.range(0.0, 1.5) / size } else { Vec3::ZERO };
            (plane + bend).normalize() * if curved { 0.8 + 0.4 * rng.f() } else { 1.0 }
        });
        let toward = |k: usize| positions[k] - centre;
        let position = match kind {
            0 => {
                centre + (plane + rng.point(Vec3::splat(-1.0), Vec3::ONE)).normalize() * rng.range(3.0, 30.0)
            }
            1 => {
                centre
                    + plane * size * rng.range(0.05, 1.0)
                    + toward(rng.below(3) as usize) * rng.range(0.0, 0.9)
            }
            _ => {
                centre
                    + toward(rng.below(3) as usize) * rng.range(1.3, 3.0)
                    + plane * size * rng.range(0.0, 0.1)
            }
        };
        Some((TriangleInput { positions, normals, eye: centre + plane * 5.0 }, position))
    }

    /// The jets' scale along the domain step `(du, dv)` of a patch, in f64: `|Xδ|`, `|Nδ|` and
    /// `|Gδ|` (see [`Scale`]).
    fn scale_along(tri: &TriangleInput, du: f64, dv: f64) -> Scale {
        let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
        let [np, nq, nr] = tri.normals.map(|x| x.as_dvec3());
        let n_step = (nq - np) * du + (nr - np) * dv;
        Scale {
            a: ((q - p) * du + (r - p) * dv).length() as f32,
            b: n_step.length() as f32,
            g: DVec3::new(np.dot(n_step), nq.dot(n_step), nr.dot(n_step)).length() as f32,
        }
    }

    /// A random point `(u, v)` of the patch (barycentric, uniform in `u`) and a random unit
    /// step direction `(du, dv)` in the same coordinates.
    fn point_and_step(rng: &mut crate::test_rng::Rng) -> (f64, f64, f64, f64) {
        let (u, v) = (f64::from(rng.range(0.0, 1.0)), f64::from(rng.f()));
        let turn = f64::from(rng.range(0.0, std::f32::consts::TAU));
        (u, (1.0 - u) * v, turn.cos(), turn.sin())
    }

    /// [`irradiance_case`] with its light planned for a white Lambert material (Relaxed):
    /// `None` also where the light adds nothing.
    fn planned_irradiance_case(
        rng: &mut crate::test_rng::Rng,
        size: f32,
        curved: bool,
        kind: usize,
    ) -> Option<(TriangleInput, Vec3, Frame, LightSetup)> {
        let (tri, position) = irradiance_case(rng, size, curved, kind)?;
        let light = Light::Point { position, color: Vec3::ONE, intensity: 1.0 };
        let frame = Frame::new(&tri);
        let material = MaterialKind::Lambert { kd: Vec3::ONE };
        let own = ParameterRange::of(&material);
        let (setup, _, _) = plan_light(&frame, &material, own, &light, Discontinuity::Relaxed).ok()??;
        Some((tri, position, frame, setup))
    }

    #[test]
    fn irradiance_jet_bounds_the_exact_derivatives() {
        let mut rng = crate::test_rng::Rng(0x1aad_1a9c_e5e1_d000);
        let (mut checked, mut tightest) = (0usize, [0.0f64; 2]);
        let gd = Guard::default();
        for case in 0..1500 {
            let size = rng.range(0.05, 1.0);
            let curved = case % 2 == 1;
            let Some((tri, position, frame, setup)) =
                planned_irradiance_case(&mut rng, size, curved, case % 3)
            else {
                continue;
            };
            let (positions, normals) = (tri.positions, tri.normals);
            let [p, q, r] = positions.map(|x| x.as_dvec3());
            let [np, nq, nr] = normals.map(|x| x.as_dvec3());
            let light_at = position.as_dvec3();
            for _ in 0..8 {
                let (u, v, du, dv) = point_and_step(&mut rng);
                let diffuse = |t: f64| {
                    let (a, b) = (u + t * du, v + t * dv);
                    let x = p + (q - p) * a + (r - p) * b;
                    let n = (np + (nq - np) * a + (nr - np) * b).normalize();
                    let d = light_at - x;
                    n.dot(d) / d.length().powi(3)
                };
                let scale = scale_along(&tri, du, dv);
                let (n_field, _) = normal_and_light_fields(&frame, &setup, scale, &gd);
                let jet = irradiance_jet(&frame, &setup, &n_field, scale.a, &gd);
                // A step well inside the light's distance; the differences' rounding is about
                // 10⁻¹⁶·|f|/h per order.
                let h = 1.0e-3 * f64::from(size.min(1.0 / setup.inv_d));
                let [value, first, second] = differences(&diffuse, 0.0, h);
                let slack = 1.0e-14 * value.abs() / (h * h);
                let what =
                    format!("case {case}: light {position:?}, triangle {positions:?}, normals {normals:?}");
                assert!(value.abs() <= f64::from(jet.m) * 1.0001, "{what}: value {value} > {}", jet.m);
                assert!(first.abs() <= f64::from(jet.g) * 1.001, "{what}: first {first} > {}", jet.g);
                assert!(
                    second.abs() <= f64::from(jet.t) * 1.001 + slack,
                    "{what}: second {second} > {}",
                    jet.t
                );
                if slack < 1.0e-3 * second.abs() {
                    let k = usize::from(curved);
                    tightest[k] = tightest[k].max(second.abs() / f64::from(jet.t));
                }
                checked += 1;
            }
        }
        eprintln!(
            "irradiance: {checked} points; largest |f''| / bound, flat {:.3}, curved {:.3}",
            tightest[0], tightest[1]
        );
        assert!(checked > 5_000, "{checked} points checked");
        assert!(tightest[0] > 0.9, "flat normals: the bound is never approached: {tightest:?}");
        assert!(tightest[1] > 0.5, "curved normals: the bound is never approached: {tightest:?}");
    }

    /// One candidate bound of the light part, `k·|a|²/d_min⁴` with `k = candidate(frame, setup)`,
    /// against `n̂·D²I[a, a]` (the normal held at the point's) by f64 central differences at 8
    /// random points and steps of each of 1 500 triangles of [`irradiance_case`]: never above it.
    /// Returns the points checked, the triangles where it is below 0.9 of `others(frame, setup)`,
    /// and its largest `|f''|/bound`.
    fn check_light_part_bound(
        seed: u64,
        candidate: impl Fn(&Frame, &LightSetup) -> f32,
        others: impl Fn(&Frame, &LightSetup) -> f32,
    ) -> (usize, usize, f64) {
        let mut rng = crate::test_rng::Rng(seed);
        let (mut checked, mut deciding, mut tightest) = (0usize, 0usize, 0.0f64);
        for case in 0..1500 {
            let size = rng.range(0.05, 1.0);
            let Some((tri, position, frame, setup)) =
                planned_irradiance_case(&mut rng, size, case % 2 == 1, case % 3)
            else {
                continue;
            };
            let k = f64::from(candidate(&frame, &setup));
            deciding += usize::from(k < 0.9 * f64::from(others(&frame, &setup)));
            let inv_d4 = f64::from(setup.inv_d).powi(4);
            let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
            let [np, nq, nr] = tri.normals.map(|x| x.as_dvec3());
            let light_at = position.as_dvec3();
            for _ in 0..8 {
                let (u, v, du, dv) = point_and_step(&mut rng);
                let n = (np + (nq - np) * u + (nr - np) * v).normalize();
                let light_part = |t: f64| {
                    let x = p + (q - p) * (u + t * du) + (r - p) * (v + t * dv);
                    let d = light_at - x;
                    n.dot(d) / d.length().powi(3)
                };
                let bound = k * ((q - p) * du + (r - p) * dv).length_squared() * inv_d4;
                let h = 1.0e-3 * f64::from(size.min(1.0 / setup.inv_d));
                let [value, _, second] = differences(&light_part, 0.0, h);
                let slack = 1.0e-14 * value.abs() / (h * h);
                assert!(
                    second.abs() <= bound * 1.001 + slack,
                    "case {case}: light {position:?}, {tri:?}: second {second} > {bound}"
                );
                if slack < 1.0e-3 * second.abs() {
                    tightest = tightest.max(second.abs() / bound);
                }
                checked += 1;
            }
        }
        (checked, deciding, tightest)
    }

    /// `projected`, the light part's candidate [`along_plane`] improves on.
    fn projected(frame: &Frame, setup: &LightSetup) -> f32 {
        let (sg, c) = (setup.plane_sin, Angles::of(setup.psi_nl).c_max);
        6.0 * sg * frame.n_plane_sin + (15.0 * sg * sg - 3.0).abs().max(3.0) * c
    }

    /// [`along_plane`] alone against the light part: never above it, within a few per cent of
    /// it somewhere, and below `projected` on many triangles.
    #[test]
    fn along_plane_bounds_the_light_part() {
        let (checked, deciding, tightest) = check_light_part_bound(
            0x0f0e_d1ec_7a1a_0001,
            |frame, setup| along_plane(setup, frame.n_plane_sin, Angles::of(setup.psi_nl).c_max),
            projected,
        );
        eprintln!("along the plane: {checked} points, below 0.9 of `projected` on {deciding} triangles, largest |f''| / bound {tightest:.3}");
        assert!(checked > 5_000 && deciding > 100, "{checked} points, {deciding} deciding");
        assert!(tightest > 0.9, "the bound is never approached: {tightest}");
    }

    /// [`tilted`] alone against the light part, the same way: never above it, reached somewhere,
    /// and below 0.9 of the other candidates on triangles with curved normals and lights near
    /// their plane.
    #[test]
    fn tilted_bounds_the_light_part() {
        let (checked, deciding, tightest) = check_light_part_bound(
            0x7117_ed00_1a9c_0002,
            |frame, setup| tilted(setup, frame.n_plane_sin),
            |frame, setup| {
                let near2 = setup.near_sin * setup.near_sin;
                let whole = (45.0 * near2 * near2 - 18.0 * near2 + 9.0).max(9.0).sqrt();
                let c = Angles::of(setup.psi_nl).c_max;
                whole.min(projected(frame, setup)).min(along_plane(setup, frame.n_plane_sin, c))
            },
        );
        eprintln!("tilted: {checked} points, below 0.9 of the others on {deciding} triangles, largest |f''| / bound {tightest:.3}");
        assert!(checked > 5_000 && deciding > 25, "{checked} points, {deciding} deciding");
        assert!(tightest > 0.9, "the bound is never approached: {tightest}");
    }

    /// The two suprema [`tilted`] takes in closed form, against a dense search in f64: the
    /// first part's `z⁵·max(3, |12 − 15h²z²|)` over `z ≤ 1`, and `s·max|G|` over the angles,
    /// which must also not decrease with `s` (the bound takes it at the largest `s`).
    #[test]
    fn tilted_suprema_are_the_maxima() {
        let setup_with = |near_cos: f32, plane_sin: f32| LightSetup {
            plane_sin,
            near_cos,
            ..LightSetup::unbounded(1.0, (0.0, PI), false, None)
        };
        for i in 0..=200 {
            let h = f64::from(i) / 200.0;
            let rising = f64::from(tilted(&setup_with(h as f32, 0.0), 0.0));
            let searched = (1..=4000)
                .map(|j| {
                    let z = f64::from(j) / 4000.0;
                    z.powi(5) * (12.0 - 15.0 * h * h * z * z).abs().max(3.0)
                })
                .fold(0.0, f64::max);
            assert!(searched <= rising * (1.0 + 1.0e-6), "h {h}: searched {searched} > {rising}");
            assert!(searched >= rising * 0.999, "h {h}: searched {searched} far below {rising}");
        }
        let mut last = 0.0f64;
        for i in 0..=200 {
            let s = f64::from(i) / 200.0;
            let turning = f64::from(tilted(&setup_with(0.0, s as f32), 1.0)) - 12.0;
            let mut searched = 0.0f64;
            for a in 0..=180 {
                let alpha = f64::from(a) * std::f64::consts::PI / 180.0;
                for b in 0..=360 {
                    let beta = f64::from(b) * std::f64::consts::PI / 180.0;
                    let g = beta.cos() * ((15.0 * s * s - 6.0) * alpha.cos().powi(2) - 3.0)
                        - 3.0 * (2.0 * alpha).sin() * beta.sin();
                    searched = searched.max(s * g.abs());
                }
            }
            assert!(searched <= turning + 1.0e-5, "s {s}: searched {searched} > {turning}");
            assert!(searched >= turning - 2.0e-3, "s {s}: searched {searched} far below {turning}");
            assert!(turning >= last - 1.0e-6, "s {s}: {turning} below {last} at a smaller s");
            last = turning;
        }
    }

    /// [`TerminatorBand::at`] and [`TerminatorBand::guarded`] against `n̂·l̂` sampled on sub-triangles of
    /// the pattern's shapes at levels 1 to 8 that the terminator crosses (both signs among the
    /// samples): their largest `|n̂·l̂|` and their oscillation stay below the band at that level,
    /// and below the per-`1/L` band from every level `above ≤ L`; on curved patches with lights
    /// near their plane.
    #[test]
    fn terminator_band_holds_on_crossed_sub_triangles() {
        let mut rng = crate::test_rng::Rng(0x7e27_b0d0_0000_0003);
        let gd = Guard::default();
        let (mut crossed, mut tightest) = (0usize, 0.0f64);
        for case in 0..3000 {
            let size = rng.range(0.05, 1.0);
            let Some((tri, position, frame, setup)) =
                planned_irradiance_case(&mut rng, size, true, 1 + case % 2)
            else {
                continue;
            };
            if !setup.straddle {
                continue;
            }
            let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
            let [np, nq, nr] = tri.normals.map(|x| x.as_dvec3());
            let light_at = position.as_dvec3();
            let cosine = |(u, v): (f64, f64)| {
                let x = p + (q - p) * u + (r - p) * v;
                let n = (np + (nq - np) * u + (nr - np) * v).normalize();
                n.dot((light_at - x).normalize())
            };
            for _ in 0..6 {
                let level = 1 + rng.below(8);
                let l = level as f32;
                let shape = SHAPES[rng.below(7) as usize];
                let scale = 1.0 / f64::from(level);
                let (u, v) = (
                    (f64::from(shape[0].0) * scale, f64::from(shape[0].1) * scale),
                    (f64::from(shape[1].0) * scale, f64::from(shape[1].1) * scale),
                );
                // A translate that keeps all three corners in the patch, if one is drawn.
                let origin = (0..20).find_map(|_| {
                    let o = (f64::from(rng.f()), f64::from(rng.f()));
                    let inside = |(a, b): (f64, f64)| a >= 0.0 && b >= 0.0 && a + b <= 1.0;
                    [o, (o.0 + u.0, o.1 + u.1), (o.0 + v.0, o.1 + v.1)]
                        .iter()
                        .all(|&c| inside(c))
                        .then_some(o)
                });
                let Some(o) = origin else {
                    continue;
                };
                let (mut lo, mut hi) = (f64::MAX, f64::MIN);
                let steps = 12;
                for i in 0..=steps {
                    for j in 0..=(steps - i) {
                        let (a, b) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
                        let c = cosine((o.0 + u.0 * a + v.0 * b, o.1 + u.1 * a + v.1 * b));
                        lo = lo.min(c);
                        hi = hi.max(c);
                    }
                }
                if !(lo < 0.0 && hi > 0.0) {
                    continue;
                }
                crossed += 1;
                let worst = (hi - lo).max(hi).max(-lo);
                let band = TerminatorBand::new(&frame, &setup, frame.dn);
                let at = f64::from(band.at(l));
                let per_level = f64::from(band.guarded(0.0, &gd)) / f64::from(l);
                let above = 1.0 + rng.f() * (l - 1.0);
                let from_above = f64::from(band.guarded(above, &gd)) / f64::from(l);
                let what = format!("case {case}, level {level}: light {position:?}, {tri:?}");
                assert!(worst <= at * (1.0 + 1.0e-5), "{what}: {worst} > band at the level {at}");
                assert!(worst <= per_level * (1.0 + 1.0e-5), "{what}: {worst} > band per level {per_level}");
                assert!(
                    worst <= from_above * (1.0 + 1.0e-5),
                    "{what}: {worst} > band from {above}: {from_above}"
                );
                tightest = tightest.max(worst / at);
            }
        }
        eprintln!(
            "terminator band: {crossed} crossed sub-triangles, largest oscillation / band {tightest:.3}"
        );
        assert!(crossed > 1_000, "{crossed} crossed sub-triangles");
        assert!(tightest > 0.3, "the band is never approached: {tightest}");
    }

    /// [`Frame::distance_of`] for triangles without a plane (the third corner on the line of the
    /// other two, up to rounding): below the distance to the nearest of 45 451 sample points and
    /// within 1 % of it.
    #[test]
    fn distance_along_a_line_bounds_the_nearest_point() {
        let mut rng = crate::test_rng::Rng(0xd157_a9ce_0f11_0004);
        let mut checked = 0;
        for case in 0..600 {
            let a = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
            let b = a + rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
            let c = a.lerp(b, rng.range(-0.5, 1.5));
            let tri = TriangleInput { positions: [a, b, c], normals: [Vec3::Z; 3], eye: Vec3::splat(5.0) };
            let frame = Frame::new(&tri);
            if frame.plane != Vec3::ZERO {
                continue;
            }
            let position = a.lerp(b, rng.range(-1.0, 2.0))
                + rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)) * rng.range(0.0, 1.0);
            let bound = f64::from(frame.distance_of(position, frame.height_of(position).0));
            let nearest = sampled_distance(&tri, position);
            assert!(bound <= nearest * (1.0 + 1.0e-5), "case {case}: bound {bound} > nearest {nearest}");
            assert!(
                bound >= 0.99 * nearest - 1.0e-5,
                "case {case}: bound {bound} far below nearest {nearest}"
            );
            checked += 1;
        }
        assert!(checked > 300, "{checked} triangles without a plane");
    }

    /// The distance from `position` to the nearest of 45 451 points of the triangle, in f64.
    fn sampled_distance(tri: &TriangleInput, position: Vec3) -> f64 {
        let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
        let light_at = position.as_dvec3();
        let steps = 300;
        let mut nearest = f64::MAX;
        for i in 0..=steps {
            for j in 0..=(steps - i) {
                let (a, b) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
                nearest = nearest.min((p + (q - p) * a + (r - p) * b - light_at).length());
            }
        }
        nearest
    }

    /// [`Frame::distance_of`] bounds the distance from a point to the triangle from below (at
    /// 45 451 sample points of it) and is within 1 % of it, for lights above the triangle (their
    /// foot inside) and beside it.
    #[test]
    fn distance_of_a_light_bounds_the_nearest_point() {
        let mut rng = crate::test_rng::Rng(0xd157_a9ce_0f11_0002);
        let mut seen = [0; 2];
        for case in 0..600 {
            let size = rng.range(0.05, 1.0);
            let Some((tri, position)) = irradiance_case(&mut rng, size, false, case % 3) else {
                continue;
            };
            let frame = Frame::new(&tri);
            let bound = f64::from(frame.distance_of(position, frame.height_of(position).0));
            let nearest = sampled_distance(&tri, position);
            let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
            let light_at = position.as_dvec3();
            assert!(bound <= nearest * (1.0 + 1.0e-5), "case {case}: bound {bound} > nearest {nearest}");
            assert!(bound >= 0.99 * nearest, "case {case}: bound {bound} far below nearest {nearest}");
            let n = (q - p).cross(r - p).normalize();
            let foot = light_at - n * (light_at - p).dot(n);
            let inside = [(p, q), (q, r), (r, p)].iter().all(|&(a, b)| (b - a).cross(foot - a).dot(n) > 0.0);
            seen[usize::from(inside)] += 1;
        }
        assert!(seen[0] > 50 && seen[1] > 50, "lights beside and above their triangle: {seen:?}");
    }

    /// [`origin_distance`] against the smallest norm sampled on 5 151 points of each of 2 000
    /// random triangles (general, slivers, collinear and coincident corners): never above it
    /// (10⁻⁶ for rounding), and within 1 % of it on most where it is not below 10⁻³.
    #[test]
    fn origin_distance_is_the_triangle_nearest_point() {
        let mut rng = crate::test_rng::Rng(0x0d15_7a9c_e0f0_0001);
        let mut close = 0;
        for case in 0..2000 {
            let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)) * rng.range(0.0, 2.0);
            let size = rng.range(0.01f32.ln(), 2.0f32.ln()).exp();
            let mut c = [0; 3].map(|_| centre + rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)) * size);
            match case % 5 {
                0 => c[2] = c[0].lerp(c[1], rng.range(-0.5, 1.5)),
                1 => c[2] = c[0].lerp(c[1], rng.range(0.0, 1.0)) + Vec3::splat(1.0e-4 * size),
                2 => c[1] = c[0],
                _ => {}
            }
            let distance = origin_distance(c);
            let [a, b, d] = c.map(|x| x.as_dvec3());
            let steps = 100;
            let mut sampled = f64::MAX;
            for i in 0..=steps {
                for j in 0..=(steps - i) {
                    let (u, v) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
                    sampled = sampled.min((a + (b - a) * u + (d - a) * v).length());
                }
            }
            let distance = f64::from(distance);
            assert!(
                distance <= sampled + 1.0e-6,
                "case {case}: {distance} above the sampled {sampled}: {c:?}"
            );
            if distance >= 1.0e-3 {
                close += usize::from(distance >= 0.99 * sampled);
            }
        }
        assert!(close > 1500, "{close} triangles within 1 % of their sampled distance");
    }

    /// The range of the angle between `n̂` and `ĥ` (`LightSetup::psi_nh`, from the cones of
    /// `n̂` and `ĥ`) against its minimum and maximum sampled at 496 points of each of 3 000
    /// random triangles (normals spread by up to 1 rad, point lights 0.3–300 sizes away and
    /// directional ones, eyes 0.3–30 away): never narrower than the samples, and it prints how
    /// far below the smallest angle its lower end lies (`docs/estimator.md` §11: a circular
    /// cone for `ĥ` is loose where the light or the eye is close, which a narrow lobe pays for).
    #[test]
    fn half_vector_angle_range_holds_the_sampled_angles() {
        let mut rng = crate::test_rng::Rng(0x0a11_0f0e_a1f0_0003);
        let mut ratios = Vec::new();
        for _ in 0..3000 {
            let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
            let view_dir = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or_zero();
            let view_dist = rng.range(0.3f32.ln(), 30f32.ln()).exp();
            let eye = centre + view_dir * view_dist;
            let (t1, t2) = view_dir.any_orthonormal_pair();
            let size = view_dist * rng.range(0.002f32.ln(), 0.5f32.ln()).exp();
            let positions =
                [0; 3].map(|_| centre + (t1 * rng.range(-1.0, 1.0) + t2 * rng.range(-1.0, 1.0)) * size);
            let spread = rng.range(1.0e-4f32.ln(), 0.0).exp();
            let normals = [0; 3].map(|_| tilt(&mut rng, view_dir, 0.0, spread));
            let towards = tilt(&mut rng, view_dir, 0.0, 1.5);
            let light = if rng.below(2) == 0 {
                let distance = size * rng.range(0.3f32.ln(), 300f32.ln()).exp();
                Light::Point { position: centre + towards * distance, color: Vec3::ONE, intensity: 1.0 }
            } else {
                Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 }
            };
            let tri = TriangleInput { positions, normals, eye };
            let material = MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::ONE, shininess: 100.0 };
            let frame = Frame::new(&tri);
            let Ok(Some((setup, _, _))) =
                plan_light(&frame, &material, ParameterRange::of(&material), &light, Discontinuity::Relaxed)
            else {
                continue;
            };
            let (mut low, mut high) = (f64::MAX, 0.0f64);
            let steps = 30;
            for i in 0..=steps {
                for j in 0..=(steps - i) {
                    let (a, b) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
                    let [p, q, r] = positions.map(|x| x.as_dvec3());
                    let [np, nq, nr] = normals.map(|x| x.as_dvec3());
                    let x = p + (q - p) * a + (r - p) * b;
                    let n = (np + (nq - np) * a + (nr - np) * b).normalize();
                    let l = match light {
                        Light::Point { position, .. } => (position.as_dvec3() - x).normalize(),
                        _ => towards.as_dvec3(),
                    };
                    let h = (l + (eye.as_dvec3() - x).normalize()).normalize();
                    let angle = n.dot(h).clamp(-1.0, 1.0).acos();
                    (low, high) = (low.min(angle), high.max(angle));
                }
            }
            let (p0, p1) = (f64::from(setup.psi_nh.0), f64::from(setup.psi_nh.1));
            assert!(
                p0 <= low + 1.0e-5 && p1 >= high - 1.0e-5,
                "{tri:?}, {light:?}: [{p0}, {p1}] vs [{low}, {high}]"
            );
            if low > 0.05 {
                ratios.push(p0 / low);
            }
        }
        let n = ratios.len();
        assert!(n > 1000, "{n} triangles off the highlight");
        eprintln!(
            "lower end of the n̂-ĥ angle over its sampled minimum, {n} triangles off the highlight: {}",
            percentiles(&mut ratios)
        );
    }

    /// The two facts [`mirror_lower_angle`] rests on, in f64 over random directions (some
    /// nearly coplanar, some close together): the half vectors of a common `v̂` and two others
    /// are at least half as far apart as those two, with equality for coplanar ones; and a
    /// half-turn about `n̂` moves `v̂` at most twice `∠(n̂, n̂₀)` plus `∠(v̂, v̂₀)` from where the
    /// half-turn about `n̂₀` moves `v̂₀`.
    #[test]
    fn half_vectors_of_a_common_direction_are_at_least_half_as_far_apart() {
        let mut rng = crate::test_rng::Rng(0x0a11_0f0e_a1f0_0004);
        let random_unit = |rng: &mut crate::test_rng::Rng| {
            rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).as_dvec3().normalize_or(DVec3::X)
        };
        let angle = |a: DVec3, b: DVec3| a.cross(b).length().atan2(a.dot(b));
        let half_turn = |axis: DVec3, v: DVec3| axis * (2.0 * axis.dot(v)) - v;
        let (mut tightest, mut checked) = (f64::MAX, 0);
        for k in 0..200_000 {
            let v = random_unit(&mut rng);
            let l = random_unit(&mut rng);
            let r = match k % 3 {
                0 => random_unit(&mut rng),
                1 => (l + random_unit(&mut rng) * 0.01).normalize(),
                // In the plane of v and l.
                _ => (v * rng.range(-1.0, 1.0) as f64 + l * rng.range(-1.0, 1.0) as f64).normalize_or(l),
            };
            if v.dot(l) < -0.999 || v.dot(r) < -0.999 || angle(l, r) < 1.0e-6 {
                continue;
            }
            let apart = angle((v + l).normalize(), (v + r).normalize());
            let ratio = apart / (0.5 * angle(l, r));
            assert!(ratio >= 1.0 - 1.0e-9, "{v} {l} {r}: {ratio}");
            tightest = tightest.min(ratio);
            checked += 1;

            let (n, n0, v0) = (random_unit(&mut rng), random_unit(&mut rng), random_unit(&mut rng));
            let moved = angle(half_turn(n, v), half_turn(n0, v0));
            assert!(moved <= 2.0 * angle(n, n0) + angle(v, v0) + 1.0e-9, "{n} {n0} {v} {v0}");
        }
        assert!(checked > 150_000 && tightest < 1.0 + 1.0e-6, "{checked} checked, tightest {tightest}");
    }

    /// Sorts `v` and names its 10th percentile, median and 90th percentile.
    fn percentiles(v: &mut [f64]) -> String {
        v.sort_by(|a, b| a.total_cmp(b));
        let n = v.len();
        format!("10th percentile {:.2}, median {:.2}, 90th {:.2}", v[n / 10], v[n / 2], v[9 * n / 10])
    }

    /// The levels are decided on the jets' one-number second-order bound (`Jet::t`), the
    /// GPU's single pass; the per-term bounds are its parts. They must agree: never above the
    /// parts' sum, and equal to it up to rounding where neither a lobe's joint bound
    /// ([`Curvature`]) nor a textured range's larger of several jets applies (Lambert with a
    /// constant parameter); a lobe's joint bound is below the sum somewhere.
    #[test]
    fn second_order_total_is_the_sum_of_its_terms() {
        let mut compared = 0;
        let mut textured = 0;
        let mut joint_below = 0;
        for (tname, t) in triangles() {
            for (lname, lights) in light_sets(&t) {
                for m in materials() {
                    let own = ParameterRange::of(&m);
                    let wide = ParameterRange { lo: own.lo * 0.5, hi: own.hi * 2.0 };
                    for (parameter, exact) in [(own, true), (wide, false)] {
                        for mode in [Discontinuity::Conservative, Discontinuity::Relaxed] {
                            let settings =
                                EstimatorSettings { discontinuity: mode, ..EstimatorSettings::default() };
                            let (sum, reason) =
                                light_sums(&t, &m, parameter, &lights, &settings, 16, 0.075, false);
                            if reason != Reason::None {
                                continue;
                            }
                            let parts = sum.hn.iter().fold(Vec3::ZERO, |acc, h| acc + *h);
                            for c in 0..3 {
                                let (total, parts) = (sum.tn[c], parts[c]);
                                let what = format!("{tname} / {lname} / {m:?} / {parameter:?} / {mode:?}");
                                assert!(total <= parts * (1.0 + 1.0e-5), "{what}: {total} > {parts}");
                                if exact && matches!(m, MaterialKind::Lambert { .. }) {
                                    assert!(total >= parts * (1.0 - 1.0e-5), "{what}: {total} < {parts}");
                                }
                                joint_below += usize::from(exact && total < parts * 0.99);
                            }
                            compared += 1;
                            textured += usize::from(!exact);
                        }
                    }
                }
            }
        }
        assert!(compared > 100 && textured > 50, "{compared} compared, {textured} textured");
        assert!(joint_below > 10, "the lobes' joint bound is never below the sum ({joint_below})");
    }

    #[test]
    fn never_nan_never_out_of_range() {
        let epsilons = [0.0, -1.0, f32::NAN, f32::INFINITY, 1.0e-30, 1.0e-6, 0.075, 1.0, 1.0e6];
        let mut count = 0;
        for (tname, t) in triangles() {
            for (lname, lights) in light_sets(&t) {
                for m in materials() {
                    for &eps in &epsilons {
                        for s in all_settings(eps) {
                            let e = estimate(&t, &m, &lights, &s);
                            sane(&e, 16, &format!("{tname} / {lname} / {m:?} / {s:?}"));
                            count += 1;
                        }
                    }
                }
            }
        }
        // n_max outside 1..=64 is clamped.
        for n_max in [0, 1, 64, 1000] {
            let s = EstimatorSettings { n_max, ..EstimatorSettings::default() };
            let e = estimate(&base(), &materials()[0], &light_sets(&base())[0].1, &s);
            sane(&e, n_max.clamp(1, 64), "n_max");
        }
        assert!(count > 10_000);
    }

    fn est(t: &TriangleInput, m: &MaterialKind, lights: &[Light], eps: f32) -> Estimate {
        estimate(t, m, lights, &EstimatorSettings { epsilon: eps, ..EstimatorSettings::default() })
    }

    /// `Lg − g` for `g = max(f, 0)` at local barycentrics `mu`, with `f` given at the corners
    /// (`fc`) and at the point (`fx`).
    fn kink_error(fc: [f64; 3], fx: f64, mu: [f64; 3]) -> f64 {
        let lg: f64 = (0..3).map(|k| mu[k] * fc[k].max(0.0)).sum();
        lg - fx.max(0.0)
    }

    #[test]
    fn terminator_kink_constant_is_sharp() {
        // Linear f with corner values (1, −1, −1): E_f = 0, the corner oscillation is 2, and on
        // the zero line (the midpoints of the edges from the first corner) Lg − g = ½ exactly:
        // ¼·2, so no smaller constant bounds it.
        let fc = [1.0, -1.0, -1.0];
        let linear = |mu: [f64; 3]| mu[0] * fc[0] + mu[1] * fc[1] + mu[2] * fc[2];
        let bound = f64::from(TERMINATOR_KINK) * (1.0 - -1.0);
        let k = 64;
        let mut worst = f64::MIN;
        for i in 0..=k {
            for j in 0..=k - i {
                let mu = [i as f64 / k as f64, j as f64 / k as f64, (k - i - j) as f64 / k as f64];
                let e = kink_error(fc, linear(mu), mu);
                assert!(e >= 0.0 && e <= bound + 1e-12, "{mu:?}: {e}");
                worst = worst.max(e);
            }
        }
        assert_eq!(worst, 0.5);
        assert_eq!(bound, 0.5);
        assert_eq!(kink_error(fc, 0.0, [0.5, 0.5, 0.0]), 0.5);

        // Any smooth f: pointwise −max(f − Lf, 0) ≤ Lg − g ≤ max(Lf − f, 0) + ¼·osc of the
        // corner values (random quadratics on the reference triangle).
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..2000 {
            let c: [f64; 6] = std::array::from_fn(|_| rnd());
            let curve = 3.0 * rnd().abs();
            let f = |mu: [f64; 3]| {
                let (x, y) = (mu[1], mu[2]);
                c[0] + c[1] * x + c[2] * y + curve * (c[3] * x * x + c[4] * x * y + c[5] * y * y)
            };
            let corners = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(f);
            let osc = corners.iter().copied().fold(f64::MIN, f64::max)
                - corners.iter().copied().fold(f64::MAX, f64::min);
            for _ in 0..50 {
                let (a, b) = (rnd().abs(), rnd().abs());
                let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
                let mu = [1.0 - a - b, a, b];
                let lf: f64 = (0..3).map(|k| mu[k] * corners[k]).sum();
                let e = kink_error(corners, f(mu), mu);
                let tol = 1e-12;
                assert!(e <= (lf - f(mu)).max(0.0) + f64::from(TERMINATOR_KINK) * osc + tol);
                assert!(e >= -(f(mu) - lf).max(0.0) - tol);
            }
        }
    }

    /// The view kink's split (`smith_v_kink_jet`): `V(max(u, 0)) = 1/k − max(ρ(u), 0)` with
    /// `ρ` the tangent-continued `1/k − V`; the jet of `u` itself (slope 1, no curvature)
    /// must bound `ρ`'s slope and curvature on both sides of the kink, and `1/k − ρ(u)` on
    /// `|u| ≤ band`.
    #[test]
    fn view_kink_split_is_exact_and_its_jet_bounds_it() {
        for k in [5.0e-4f64, 0.01, 0.045, 0.2, 0.5] {
            let v = |c: f64| 1.0 / (c * (1.0 - k) + k);
            let rho = |u: f64| if u >= 0.0 { 1.0 / k - v(u) } else { (1.0 - k) / (k * k) * u };
            for band in [0.01f64, 0.1, 1.0] {
                let identity = Jet { m: band as f32, g: 1.0, h: NO_H, t: 0.0 };
                let gd = Guard::default();
                let jet = smith_v_kink_jet(&identity, k as f32, band as f32, &gd);
                let (m, g, t) = (f64::from(jet.m), f64::from(jet.g), f64::from(jet.t));
                let steps = 2000;
                // Differences with a step well inside V's scale k, at points clear of the
                // kink by two steps (one of them right next to it).
                let h = 1e-3 * k.min(band);
                let grid = (-steps..=steps).map(|i| band * i as f64 / steps as f64);
                let (mut slope, mut curve) = (0.0f64, 0.0f64);
                for u in grid.chain([2.0 * h, -2.0 * h]) {
                    let split = 1.0 / k - rho(u).max(0.0);
                    assert!((split - v(u.max(0.0))).abs() <= 1e-12 * v(0.0), "k {k}, u {u}");
                    assert!((1.0 / k - rho(u)).abs() <= m * (1.0 + 1e-6), "k {k}, u {u}: value over {m}");
                    if u.abs() >= 2.0 * h && u.abs() <= band - h {
                        let first = (rho(u + h) - rho(u - h)) / (2.0 * h);
                        let second = (rho(u + h) - 2.0 * rho(u) + rho(u - h)) / (h * h);
                        slope = slope.max(first.abs());
                        curve = curve.max(second.abs());
                    }
                }
                assert!(slope <= g * (1.0 + 1e-5), "k {k}: slope {slope} > {g}");
                assert!(curve <= t * (1.0 + 1e-3), "k {k}: curvature {curve} > {t}");
                // Both are reached next to the kink (the bounds are ρ's at u = 0⁺).
                assert!(slope >= 0.99 * g && curve >= 0.99 * t, "k {k}: {slope}/{g}, {curve}/{t}");
            }
        }
    }

    #[test]
    fn extremes_behave() {
        let lam = materials()[0];
        let b = base();
        let c = (b.positions[0] + b.positions[1] + b.positions[2]) / 3.0;
        // A light behind the surface everywhere adds nothing.
        let e = est(&b, &lam, &[sun(Vec3::new(0.0, 0.2, 1.0))], 1e-9);
        assert!(!e.fallback && e.n == 1 && e.predicted_error == 0.0, "{e:?}");
        // A light touching the triangle, zero or opposite normals: singular.
        for lights in [vec![point(b.positions[1])], vec![point(c)]] {
            assert_eq!(est(&b, &lam, &lights, 0.1).reason, Reason::Singular);
        }
        let tris = triangles();
        for name in ["opposite normals", "120 degrees in a plane", "a zero normal"] {
            let t = tris.iter().find(|(n, _)| *n == name).unwrap().1;
            assert_eq!(est(&t, &lam, &[point(c + Vec3::Z)], 0.1).reason, Reason::Singular, "{name}");
        }
        // ...unless the light is dark.
        let dark = [Light::Point { position: b.positions[0], color: Vec3::ONE, intensity: 0.0 }];
        assert_eq!(est(&b, &lam, &dark, 0.0).n, 1);
        // Flat shading: exactly n = 1 even for ε = 0.
        let mut flat = b;
        flat.normals = [Vec3::Z; 3];
        let e = est(&flat, &lam, &[sun(-Vec3::Z)], 0.0);
        assert!(!e.fallback && e.n == 1 && e.predicted_error == 0.0, "{e:?}");
        // ε = 0 with varying shading: no level suffices.
        assert_eq!(est(&b, &lam, &[point(c + Vec3::Z)], 0.0).reason, Reason::Level);
        // Huge ε: level 1.
        for m in materials() {
            let e = est(&b, &m, &[point(c + Vec3::new(0.2, 0.1, 2.0))], 1.0e6);
            assert!(!e.fallback && e.n == 1, "{m:?} {e:?}");
        }
        // A terminator through the triangle: Conservative falls back, Relaxed need not.
        let mut curved = b;
        curved.normals =
            [Vec3::new(0.7, 0.0, 0.7).normalize(), Vec3::new(-0.7, 0.0, 0.7).normalize(), Vec3::Z];
        let grazing = [sun(Vec3::new(-1.0, 0.0, -0.1))];
        let conservative = EstimatorSettings {
            epsilon: 0.5,
            discontinuity: Discontinuity::Conservative,
            ..EstimatorSettings::default()
        };
        assert_eq!(estimate(&curved, &lam, &grazing, &conservative).reason, Reason::Discontinuity);
        let e = est(&curved, &lam, &grazing, 0.5);
        assert!(!e.fallback, "{e:?}");
        assert!(e.term(Term::Terminator) > 0.0);
        // The sharpest lobes over a curved triangle at the highlight need more than n_max.
        let bp = MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::ONE, shininess: 1.0e4 };
        let ggx = MaterialKind::Ggx { albedo: Vec3::ZERO, f0: Vec3::ONE, roughness: 0.0 };
        let over = [point(Vec3::new(0.4, 1.0, 3.0))];
        assert!(est(&curved, &bp, &over, 0.075).fallback);
        assert!(est(&curved, &ggx, &over, 0.075).fallback);
        // Uniform never asks for less than Heuristic; smaller ε never for less.
        for m in materials() {
            let l = [point(c + Vec3::new(0.3, 0.2, 1.5))];
            let h = est(&b, &m, &l, 0.02);
            let u = estimate(
                &b,
                &m,
                &l,
                &EstimatorSettings { epsilon: 0.02, split: Split::Uniform, ..EstimatorSettings::default() },
            );
            if !h.fallback && !u.fallback {
                assert!(u.n >= h.n, "{m:?}");
            }
            let mut last = 0;
            for eps in [1.0, 0.3, 0.1, 0.03, 0.01, 0.003] {
                let e = est(&b, &m, &l, eps);
                let n = if e.fallback { 99 } else { e.n };
                assert!(n >= last, "{m:?} eps {eps}");
                last = n;
            }
        }
    }

    #[test]
    fn bilinear_range_is_exact() {
        // q(λ) = (Σλa)·(Σλb) sampled densely against the closed form.
        let mut rng = Rng(12345);
        for _ in 0..200 {
            let mut v = || Vec3::new(rng.f() as f32 - 0.5, rng.f() as f32 - 0.5, rng.f() as f32 - 0.5);
            let a = [v(), v(), v()];
            let b = [v(), v(), v()];
            let (lo, hi) = bilinear_range(a, b);
            let (mut slo, mut shi) = (f32::MAX, f32::MIN);
            for i in 0..=60 {
                for j in 0..=(60 - i) {
                    let l = [i as f32 / 60.0, j as f32 / 60.0, (60 - i - j) as f32 / 60.0];
                    let q = (a[0] * l[0] + a[1] * l[1] + a[2] * l[2])
                        .dot(b[0] * l[0] + b[1] * l[1] + b[2] * l[2]);
                    slo = slo.min(q);
                    shi = shi.max(q);
                }
            }
            assert!(lo <= slo + 1e-5 && hi >= shi - 1e-5, "{lo} {slo} {hi} {shi}");
            assert!(slo - lo < 2e-3 && hi - shi < 2e-3, "not tight: {lo} {slo} {hi} {shi}");
        }
    }

    #[test]
    fn cones_contain_their_vectors() {
        let mut rng = Rng(777);
        for _ in 0..500 {
            let spread = rng.f() as f32;
            let base = Vec3::new(rng.f() as f32 - 0.5, rng.f() as f32 - 0.5, rng.f() as f32 - 0.5)
                .normalize_or(Vec3::Z);
            let w: [Vec3; 3] = std::array::from_fn(|_| {
                (base + Vec3::new(rng.f() as f32 - 0.5, rng.f() as f32 - 0.5, rng.f() as f32 - 0.5) * spread)
                    * (0.5 + rng.f() as f32)
            });
            let cone = cone_of(w);
            if cone.half >= PI {
                continue;
            }
            let r = min_length(w, &cone);
            for i in 0..=20 {
                for j in 0..=(20 - i) {
                    let l = [i as f32 / 20.0, j as f32 / 20.0, (20 - i - j) as f32 / 20.0];
                    let x = w[0] * l[0] + w[1] * l[1] + w[2] * l[2];
                    assert!(angle(x, cone.axis) <= cone.half, "outside the cone");
                    assert!(x.length() >= r * (1.0 - 1e-5), "shorter than the bound");
                    let d = hull_distance(cone.axis, w.map(unit));
                    assert!(d <= angle(x, cone.axis) + 1e-6);
                }
            }
        }
    }

    /// A glazed teapot triangle next to the lid's rim: its normals turn by 45°, so the curved
    /// diffuse part and a GGX lobe whose bound is loose both ask for a high level when bounded
    /// together. Bounding each part by the better of its interpolation bound and its range *at
    /// each grid level* gives a lower level than the solved one, and the true error there
    /// stays below ε.
    #[test]
    fn parts_bounded_apart_at_grid_levels_lower_the_level_and_hold() {
        use crate::analysis::oracle::{true_error_sampled, SAMPLES_PER_EDGE};
        let tri = TriangleInput {
            positions: [
                Vec3::new(-3.917371, 4.494141, 6.684522),
                Vec3::new(-1.070312, 4.494141, 7.246094),
                Vec3::new(-1.070312, 4.617188, 7.015625),
            ],
            normals: [
                Vec3::new(-0.29425466, 0.6970452, 0.65386707),
                Vec3::new(-0.024959099, 0.69927245, 0.71441936),
                Vec3::new(-0.047243647, 0.9988657, 0.005941045),
            ],
            eye: Vec3::new(12.0, 15.0, 30.0),
        };
        let glaze =
            MaterialKind::Ggx { albedo: Vec3::new(0.4, 0.14, 0.06), f0: Vec3::splat(0.06), roughness: 0.3 };
        let lights = [
            Light::Point {
                position: Vec3::new(-8.0, 32.0, 36.0),
                color: Vec3::new(1.0, 0.96, 0.9),
                intensity: 3400.0,
            },
            Light::Point {
                position: Vec3::new(40.0, 10.0, 10.0),
                color: Vec3::new(0.8, 0.9, 1.0),
                intensity: 500.0,
            },
        ];
        let settings = EstimatorSettings::default();
        let est = estimate(&tri, &glaze, &lights, &settings);
        assert!(!est.fallback, "{est:?}");
        // The level the terms alone solve for (Heuristic: n² = Σ nₜ²).
        let solved = est.terms.iter().map(|t| t * t).sum::<f32>().sqrt();
        let on_grid = GRID_LEVELS.iter().any(|&n| est.level == pattern_level(n, n));
        assert!(on_grid && est.level + 1.0 < solved, "level {} (solved {solved})", est.level);
        let pattern = triangle_pattern(est.n as f32, [est.n as f32; 3]);
        let error = true_error_sampled(&tri, &glaze, &lights, &pattern, SAMPLES_PER_EDGE, f64::INFINITY);
        let worst = error.into_iter().fold(0.0, f64::max);
        assert!(worst <= f64::from(settings.epsilon), "true error {worst} at n = {}", est.n);
        assert!(f64::from(est.predicted_error) >= worst, "{est:?}, true {worst}");
    }

    /// `material` with its shininess or roughness set to `value`.
    fn with_value(material: &MaterialKind, value: f32) -> MaterialKind {
        match *material {
            MaterialKind::BlinnPhong { kd, ks, .. } => MaterialKind::BlinnPhong { kd, ks, shininess: value },
            MaterialKind::Ggx { albedo, f0, .. } => MaterialKind::Ggx { albedo, f0, roughness: value },
            lambert => lambert,
        }
    }

    /// One light's contribution in f64, as `reflect_split` × irradiance shades it (per
    /// channel): the exact function whose derivatives the light's jets bound.
    fn shade_f64(x: DVec3, normal: DVec3, eye: DVec3, material: &MaterialKind, light: &Light) -> [f64; 3] {
        let n = normal.normalize();
        let v = (eye - x).normalize();
        let (l, irradiance) = match *light {
            Light::Point { position, color, intensity } => {
                let to = position.as_dvec3() - x;
                (to.normalize(), color.as_dvec3() * f64::from(intensity) / to.length_squared())
            }
            Light::Directional { direction, color, intensity } => {
                (-direction.as_dvec3().normalize(), color.as_dvec3() * f64::from(intensity))
            }
            Light::Polygon(_) => unreachable!("point and directional lights only"),
        };
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            return [0.0; 3];
        }
        let h = (l + v).normalize();
        let n_dot_h = n.dot(h).max(0.0);
        let radiance = match *material {
            MaterialKind::Lambert { kd } => kd.as_dvec3() * n_dot_l,
            MaterialKind::BlinnPhong { kd, ks, shininess } => {
                kd.as_dvec3() * n_dot_l + ks.as_dvec3() * n_dot_h.powf(f64::from(shininess))
            }
            MaterialKind::Ggx { albedo, f0, roughness } => {
                let alpha = f64::from(ggx_alpha(roughness));
                let k = 0.5 * alpha;
                let n_dot_v = n.dot(v).max(0.0);
                let v_dot_h = v.dot(h).clamp(0.0, 1.0);
                let a2 = alpha * alpha;
                let q = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
                let d = a2 / (std::f64::consts::PI * q * q);
                let f = f0.as_dvec3() + (DVec3::ONE - f0.as_dvec3()) * (1.0 - v_dot_h).powi(5);
                let visibility = 1.0 / ((n_dot_l * (1.0 - k) + k) * (n_dot_v * (1.0 - k) + k));
                albedo.as_dvec3() * n_dot_l + f * (d * visibility * 0.25 * n_dot_l)
            }
        };
        (radiance * irradiance).to_array()
    }

    /// A light for a patch of `size` at `centre` with mean normal `base`: a point light 3–30
    /// away, one closer than the patch's size (`tangent` spreads it along the patch), one near
    /// grazing, or a directional light.
    fn random_light(
        rng: &mut crate::test_rng::Rng,
        centre: Vec3,
        base: Vec3,
        tangent: Vec3,
        size: f32,
    ) -> Light {
        match rng.below(4) {
            0 => Light::Point {
                position: centre + tilt(rng, base, 0.0, 1.4) * (3.0 + 27.0 * rng.f()),
                color: Vec3::ONE,
                intensity: rng.range(5.0, 500.0),
            },
            1 => Light::Point {
                position: centre + base * size * rng.range(0.3, 1.5) + tangent * size * rng.range(-1.0, 1.0),
                color: Vec3::ONE,
                intensity: rng.range(0.01, 1.0),
            },
            2 => Light::Point {
                position: centre + tilt(rng, base, 1.35, 1.55) * (1.0 + 4.0 * rng.f()),
                color: Vec3::ONE,
                intensity: rng.range(1.0, 20.0),
            },
            _ => Light::Directional {
                direction: -tilt(rng, base, 0.0, 1.5),
                color: Vec3::ONE,
                intensity: rng.range(0.3, 3.0),
            },
        }
    }

    /// A random material of kind `brdf` (0 Lambert, 1 Blinn-Phong, 2 GGX): colours 0.05–1,
    /// shininess log-uniform 1–10⁴, roughness 0.02–1 and one in eight exactly 0.
    fn random_material(rng: &mut crate::test_rng::Rng, brdf: usize) -> MaterialKind {
        let colour = |rng: &mut crate::test_rng::Rng| rng.point(Vec3::splat(0.05), Vec3::ONE);
        match brdf {
            0 => MaterialKind::Lambert { kd: colour(rng) },
            1 => MaterialKind::BlinnPhong {
                kd: colour(rng),
                ks: colour(rng),
                shininess: rng.range(0.0, 10_000f32.ln()).exp(),
            },
            _ => MaterialKind::Ggx {
                albedo: colour(rng),
                f0: colour(rng) * 0.5,
                roughness: if rng.below(8) == 0 { 0.0 } else { rng.range(0.02, 1.0) },
            },
        }
    }

    /// The values over the children (`values_over_children`, what a triangle above
    /// `REFINE_ABOVE` takes its ranges from) hold the shaded parts at 200 random points of each
    /// of 3 000 random patches (sizes 0.05–1, normals spread up to 0.8 rad, point lights far,
    /// closer than the patch's size and grazing, directional lights: [`random_light`]; the
    /// three BRDFs, Relaxed): the diffuse part within `[inf, sup]`, the
    /// specular part at most its sup, per channel. Prints how much lower than the patch's own
    /// the children's sups are, and asserts that they are lower by a tenth on a tenth of the
    /// patches (0.81 of the patch's there with 4 children, 0.70 with 16) and that the sampled
    /// parts come within 20 % of them somewhere (neither vacuous nor never useful).
    #[test]
    fn values_over_children_hold_the_sampled_parts() {
        let mut rng = crate::test_rng::Rng(0x0c41_1d5e_7a1b);
        let gd = Guard::default();
        let (mut ratios, mut reached) = (Vec::new(), 0.0f64);
        let mut checked = 0;
        for case in 0..3000 {
            let brdf = case % 3;
            let size = rng.range(0.05, 1.0);
            let (centre, positions, eye_dir, eye) = random_patch(&mut rng, size);
            let base = tilt(&mut rng, eye_dir, 0.0, 1.2);
            let spread = (rng.range(-7.0, -0.2)).exp();
            let normals = [0; 3].map(|_| tilt(&mut rng, base, 0.0, spread) * (0.7 + 0.6 * rng.f()));
            let light = random_light(&mut rng, centre, base, eye_dir.any_orthonormal_vector(), size);
            let material = random_material(&mut rng, brdf);
            let tri = TriangleInput { positions, normals, eye };
            let frame = Frame::new(&tri);
            let own = ParameterRange::of(&material);
            let Ok(Some((setup, diff_w, spec_w))) =
                plan_light(&frame, &material, own, &light, Discontinuity::Relaxed)
            else {
                continue;
            };
            let Some(children) = values_over_children(&frame, &material, own, &light, Discontinuity::Relaxed)
            else {
                continue;
            };
            checked += 1;
            let jets = light_jets(&frame, &material, own, &setup, frame.sn, 0.0, &gd);
            let (patch_sup, _) = diffuse_values(&setup, &jets.diffuse);
            let patch = diff_w[0] * patch_sup + spec_w[0] * jets.specular[0].m;
            let tight = diff_w[0] * patch_sup.min(children.diffuse_sup)
                + spec_w[0] * jets.specular[0].m.min(children.specular_sup[0]);
            if patch > 0.0 {
                ratios.push(f64::from(tight / patch));
            }
            let specular_only = match material {
                MaterialKind::Lambert { .. } => None,
                MaterialKind::BlinnPhong { ks, shininess, .. } => {
                    Some(MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks, shininess })
                }
                MaterialKind::Ggx { f0, roughness, .. } => {
                    Some(MaterialKind::Ggx { albedo: Vec3::ZERO, f0, roughness })
                }
            };
            let [p, q, r] = positions.map(|x| x.as_dvec3());
            let [np, nq, nr] = normals.map(|x| x.as_dvec3());
            for _ in 0..200 {
                let (a, b) = (f64::from(rng.f()), f64::from(rng.f()));
                let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
                let x = p + (q - p) * a + (r - p) * b;
                let nrm = np + (nq - np) * a + (nr - np) * b;
                let full = shade_f64(x, nrm, eye.as_dvec3(), &material, &light);
                let spec = specular_only.map_or([0.0; 3], |m| shade_f64(x, nrm, eye.as_dvec3(), &m, &light));
                for c in 0..3 {
                    let diffuse = full[c] - spec[c];
                    let (sup, inf) = (f64::from(children.diffuse_sup), f64::from(children.diffuse_inf));
                    let w = f64::from(diff_w[c]);
                    let slack = 1.0e-4 * w * sup + 1.0e-12;
                    assert!(
                        diffuse <= w * sup + slack && diffuse >= w * inf - slack,
                        "case {case}: diffuse {diffuse} outside [{}, {}]: {tri:?} {light:?} {material:?}",
                        w * inf,
                        w * sup
                    );
                    let s_sup = f64::from(spec_w[c] * children.specular_sup[c]);
                    assert!(
                        spec[c] <= s_sup * (1.0 + 1.0e-4) + 1.0e-12,
                        "case {case}: specular {} above {s_sup}: {tri:?} {light:?} {material:?}",
                        spec[c]
                    );
                    let total = w * sup + s_sup;
                    if total > 0.0 {
                        reached = reached.max(full[c] / total);
                    }
                }
            }
        }
        ratios.sort_by(f64::total_cmp);
        let at = |q: f64| ratios[((ratios.len() - 1) as f64 * q) as usize];
        eprintln!(
            "{checked} patches: the children's sup over the patch's: 10th percentile {:.2}, median {:.2}, 90th {:.2}; sampled parts up to {reached:.2} of the children's sups",
            at(0.1),
            at(0.5),
            at(0.9)
        );
        assert!(checked > 1500, "{checked} patches");
        assert!(at(0.1) < 0.9, "the children seldom tighten the values");
        assert!(reached > 0.8, "the children's values are never approached: {reached}");
    }

    /// The level-1 jets `add_light` takes from those at levels ≥ 2 (`LightJets::scaled` by
    /// `Frame::rho`) are never below the jets computed at the level-1 scale itself: every jet is
    /// non-decreasing in each attribute's scale and homogeneous in them. Random triangles
    /// (needles and flat ones included), point lights far, close and grazing, directional
    /// lights, the three BRDFs with textured ranges; and the scaled jets are not vacuous (within
    /// 1.5× of the direct ones at the median).
    #[test]
    fn level_one_jets_scaled_from_the_later_ones_bound_the_direct_ones() {
        let mut rng = crate::test_rng::Rng(0x5ca1_ed0e_17e7_00b5);
        let mut ratios = Vec::new();
        for case in 0..3000 {
            let size = rng.range(0.01, 1.0);
            let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
            let mut positions = [0; 3].map(|_| centre + rng.point(Vec3::splat(-size), Vec3::splat(size)));
            if case % 7 == 0 {
                positions[2] =
                    positions[0].lerp(positions[1], rng.range(0.0, 1.0)) + Vec3::splat(1e-3 * size);
            }
            let base = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or_zero();
            let spread = if case % 5 == 0 { 0.0 } else { rng.range(-7.0, 0.0).exp() };
            let normals = [0; 3]
                .map(|_| (base + rng.point(Vec3::splat(-spread), Vec3::splat(spread))) * rng.range(0.7, 1.3));
            let eye = centre
                + rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or_zero() * rng.range(0.5, 20.0);
            let light = match rng.below(4) {
                0 => Light::Point {
                    position: centre + base * rng.range(2.0, 30.0),
                    color: Vec3::ONE,
                    intensity: 50.0,
                },
                1 => Light::Point {
                    position: centre + base * size * rng.range(0.05, 1.5),
                    color: Vec3::ONE,
                    intensity: 1.0,
                },
                2 => Light::Point {
                    position: centre + (positions[1] - positions[0]) * rng.range(1.0, 4.0),
                    color: Vec3::ONE,
                    intensity: 5.0,
                },
                _ => Light::Directional {
                    direction: -base.lerp(Vec3::X, rng.f()),
                    color: Vec3::ONE,
                    intensity: 1.0,
                },
            };
            let material = random_material(&mut rng, case % 3);
            let own = ParameterRange::of(&material);
            let parameter = if case % 2 == 0 {
                own
            } else {
                ParameterRange { lo: own.lo * 0.5, hi: (own.hi * 2.0).min(own.hi.max(1.0)) }
            };
            let tri = TriangleInput { positions, normals, eye };
            let frame = Frame::new(&tri);
            let Ok(Some((setup, _, _))) =
                plan_light(&frame, &material, parameter, &light, Discontinuity::Relaxed)
            else {
                continue;
            };
            // A bound that reaches BIG sets the guard, and the triangle falls back
            // (`Reason::Singular`) whatever its level-1 bound.
            let gd = Guard::default();
            let later = light_jets(&frame, &material, parameter, &setup, frame.sn, 0.0, &gd);
            if gd.bad.get() {
                continue;
            }
            let direct = light_jets(&frame, &material, parameter, &setup, frame.s1, 0.0, &gd);
            let scaled = later.scaled(frame.rho);
            let parts = [(&scaled.diffuse, &direct.diffuse)]
                .into_iter()
                .chain(scaled.specular.iter().zip(&direct.specular));
            for (from, at) in parts {
                let what =
                    format!("case {case}: {material:?} {light:?} {tri:?}: scaled {from:?}, direct {at:?}");
                assert_eq!(from.m.to_bits(), at.m.to_bits(), "{what}");
                let slack = |x: f32| x * 1.0e-5 + 1.0e-30;
                assert!(from.g + slack(from.g) >= at.g, "{what}: first derivative");
                assert!(from.t + slack(from.t) >= at.t, "{what}: second derivative");
                for (hs, hd) in from.h.iter().zip(&at.h) {
                    assert!(hs + slack(*hs) >= *hd, "{what}: a term");
                }
                if at.t > 0.0 {
                    ratios.push(from.t / at.t);
                }
            }
        }
        ratios.sort_by(f32::total_cmp);
        let median = ratios[ratios.len() / 2];
        eprintln!(
            "scaled / direct level-1 second derivative over {} parts: median {median:.3}",
            ratios.len()
        );
        assert!(ratios.len() > 1500 && median < 1.5, "{} parts, median {median}", ratios.len());
    }

    /// Every factor's jet, composed into a light's diffuse and specular jets, against the exact
    /// derivatives of that light's shading (f64 central differences along random domain steps
    /// `δ`, the jets evaluated at the step's scale `(|Xδ|, |Nδ|)`): value, first and second
    /// derivative bounds hold at every sampled point of random triangles, with lights far,
    /// closer than the triangle's size and grazing, directional lights, Blinn-Phong
    /// shininess up to 10⁴, GGX roughness down to 0, and textured parameter ranges (the jets
    /// over a range, the shading at one value of it). Conservative handling, so that the
    /// clamps (`n·l`, `n·h` below shininess 2, `n·v`) are inactive wherever the jets apply.
    /// `axis` turned by an angle in `[lo, hi)` towards a random side.
    fn tilt(rng: &mut crate::test_rng::Rng, axis: Vec3, lo: f32, hi: f32) -> Vec3 {
        let angle = rng.range(lo, hi);
        let side = axis.any_orthonormal_pair();
        let turn = rng.range(0.0, std::f32::consts::TAU);
        let across = side.0 * turn.cos() + side.1 * turn.sin();
        (axis * angle.cos() + across * angle.sin()).normalize()
    }

    /// A random patch of corner offsets up to `size` around a centre in `[−1, 1]³`, and an eye
    /// 2–10 away: `(centre, positions, direction to the eye, eye)`.
    fn random_patch(rng: &mut crate::test_rng::Rng, size: f32) -> (Vec3, [Vec3; 3], Vec3, Vec3) {
        let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
        let positions = [0; 3].map(|_| centre + rng.point(Vec3::splat(-size), Vec3::splat(size)));
        let eye_dir = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or_zero();
        (centre, positions, eye_dir, centre + eye_dir * rng.range(2.0, 10.0))
    }

    /// The slope of `t = n̂·ĥ` against its bound `|Dt| ≤ sin ψ·(w_n + w_h)` (what the lobes'
    /// profile part squares), at the centre of tiny patches as in
    /// [`jets_at_a_point_against_the_worst_direction`], over 72 directions: asserts the bound and
    /// prints `max_δ (Dt)² / max_δ bound²`, for `t` and for its normal's part `Dn̂·ĥ` alone
    /// (`docs/estimator.md` §11).
    #[test]
    fn lobe_slope_against_the_worst_direction() {
        let mut rng = crate::test_rng::Rng(0x1234_5678_9abc);
        let (mut whole, mut normal_part) = (Vec::new(), Vec::new());
        for _ in 0..2000 {
            let (tri, light, towards) = tiny_patch(&mut rng);
            let material = MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::ONE, shininess: 100.0 };
            let (positions, normals, eye) = (tri.positions, tri.normals, tri.eye);
            let frame = Frame::new(&tri);
            let own = ParameterRange::of(&material);
            let Ok(Some((setup, _, _))) =
                plan_light(&frame, &material, own, &light, Discontinuity::Conservative)
            else {
                continue;
            };
            let [p, q, r] = positions.map(|x| x.as_dvec3());
            let [np, nq, nr] = normals.map(|x| x.as_dvec3());
            let gd = Guard::default();
            let nh = (setup.psi_nh.0, setup.psi_nh.1.min(FRAC_PI_2));
            let (mut slope, mut bound, mut slope_n, mut bound_n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for k in 0..72 {
                let turn = f64::from(k) * std::f64::consts::PI / 72.0;
                let (du, dv) = (turn.cos(), turn.sin());
                // t along the step; with `normal_only` the light and view stay at the centre's.
                let t_at = |t: f64, normal_only: bool| {
                    let (a, b) = (1.0 / 3.0 + t * du, 1.0 / 3.0 + t * dv);
                    let x = p + (q - p) * a + (r - p) * b;
                    let n = (np + (nq - np) * a + (nr - np) * b).normalize();
                    let seen_from = if normal_only { (p + q + r) / 3.0 } else { x };
                    let l = match light {
                        Light::Point { position, .. } => (position.as_dvec3() - seen_from).normalize(),
                        _ => towards.as_dvec3().normalize(),
                    };
                    let v = (eye.as_dvec3() - seen_from).normalize();
                    n.dot((l + v).normalize())
                };
                let h = 1.0e-2;
                let dt = (t_at(h, false) - t_at(-h, false)) / (2.0 * h);
                let dn = (t_at(h, true) - t_at(-h, true)) / (2.0 * h);
                let scale = scale_along(&tri, du, dv);
                // The estimator's own bounds: the cosine jet's slope, and its normal's part alone.
                let (n, l) = normal_and_light_fields(&frame, &setup, scale, &gd);
                let (_, h) = view_and_half_fields(&frame, &setup, &l, scale, &gd);
                let still = Field { w: 0.0, ..h };
                let b = f64::from(cosine(&n, &h, nh, &gd).g);
                assert!(dt.abs() <= b * 1.001, "{light:?}, {tri:?}, direction {k}: |Dt| {} > {b}", dt.abs());
                slope = slope.max(dt * dt);
                bound = bound.max(b * b);
                slope_n = slope_n.max(dn * dn);
                bound_n = bound_n.max(f64::from(cosine(&n, &still, nh, &gd).g).powi(2));
            }
            whole.push(slope / bound);
            normal_part.push(slope_n / bound_n);
        }
        for (name, v) in [("(Dt)²", &mut whole), ("(Dn̂·ĥ)²", &mut normal_part)] {
            let text = percentiles(v);
            let n = v.len();
            assert!(n > 1000 && v[n - 1] > 0.9, "{name}: {n} patches, largest {}", v[n - 1]);
            eprintln!("{name} / its bound², worst direction of each of {n} patches: {text}");
        }
    }

    /// A patch of size 10⁻³ with unit normals spread by 5·10⁻⁵–10⁻³ rad, and one light in the
    /// direction `towards` (returned) within 1.4 rad of them: a point light 0.003–10 away (a
    /// third of the cases) or a directional one.
    fn tiny_patch(rng: &mut crate::test_rng::Rng) -> (TriangleInput, Light, Vec3) {
        let (centre, positions, eye_dir, eye) = random_patch(rng, 1.0e-3);
        let base = tilt(rng, eye_dir, 0.0, 1.2);
        let spread = 1.0e-3 * (rng.range(-3.0, 0.0)).exp();
        let normals = [0; 3].map(|_| tilt(rng, base, 0.0, spread));
        let towards = tilt(rng, base, 0.0, 1.4);
        let light = if rng.below(3) == 0 {
            Light::Point {
                position: centre + towards * rng.range(0.003, 10.0),
                color: Vec3::ONE,
                intensity: 1.0,
            }
        } else {
            Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 }
        };
        (TriangleInput { positions, normals, eye }, light, towards)
    }

    /// How close the jets come, at a point, to the second derivative in its worst direction:
    /// tiny patches (size 10⁻³, normal spreads 5·10⁻⁵–10⁻³ rad, point lights from 3 sizes
    /// away and directional lights, the three BRDFs, and the lobes alone), 72 directions at
    /// the centre. Asserts the bound in every direction (1 % for the differences' truncation)
    /// and prints `max_δ|D²f[δ,δ]| / max_δ bound(δ)` (`docs/estimator.md` §11: the lobes'
    /// jets are loose at a point, not only over a patch).
    #[test]
    fn jets_at_a_point_against_the_worst_direction() {
        let mut rng = crate::test_rng::Rng(0x005e_ed0f_7a11);
        let gd = Guard::default();
        let mut ratios: [Vec<f64>; 5] = Default::default();
        for case in 0..3000 {
            let brdf = case % 3;
            let (tri, light, _) = tiny_patch(&mut rng);
            let (positions, normals, eye) = (tri.positions, tri.normals, tri.eye);
            let full = random_material(&mut rng, brdf);
            let lobe = match full {
                MaterialKind::BlinnPhong { ks, shininess, .. } => {
                    Some(MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks, shininess })
                }
                MaterialKind::Ggx { f0, roughness, .. } => {
                    Some(MaterialKind::Ggx { albedo: Vec3::ZERO, f0, roughness })
                }
                MaterialKind::Lambert { .. } => None,
            };
            let frame = Frame::new(&tri);
            for (material, slot) in [(Some(full), brdf), (lobe, brdf + 2)] {
                let Some(material) = material else { continue };
                let own = ParameterRange::of(&material);
                let Ok(Some((setup, diff_w, spec_w))) =
                    plan_light(&frame, &material, own, &light, Discontinuity::Conservative)
                else {
                    continue;
                };
                let [p, q, r] = positions.map(|x| x.as_dvec3());
                let [np, nq, nr] = normals.map(|x| x.as_dvec3());
                let (mut worst_second, mut worst_bound) = (0.0f64, 0.0f64);
                for k in 0..72 {
                    let turn = f64::from(k) * std::f64::consts::PI / 72.0;
                    let (du, dv) = (turn.cos(), turn.sin());
                    let at = |t: f64| {
                        let (a, b) = (1.0 / 3.0 + t * du, 1.0 / 3.0 + t * dv);
                        let x = p + (q - p) * a + (r - p) * b;
                        let nrm = np + (nq - np) * a + (nr - np) * b;
                        shade_f64(x, nrm, eye.as_dvec3(), &material, &light)[0]
                    };
                    let scale = scale_along(&tri, du, dv);
                    let jets = light_jets(&frame, &material, own, &setup, scale, 0.0, &gd);
                    let bound = f64::from(diff_w[0] * jets.diffuse.t + spec_w[0] * jets.specular[0].t);
                    let h = 2.0e-2;
                    let second = ((at(h) - 2.0 * at(0.0) + at(-h)) / (h * h)).abs();
                    assert!(
                        second <= bound * 1.01 + 1.0e-9 * at(0.0).abs() / (h * h) + 1.0e-30,
                        "case {case}: {material:?}, {light:?}, {tri:?}, direction {k}: {second} > {bound}"
                    );
                    worst_second = worst_second.max(second);
                    worst_bound = worst_bound.max(bound);
                }
                if worst_bound > 1.0e-30 {
                    ratios[slot].push(worst_second / worst_bound);
                }
            }
        }
        let names = ["Lambert", "Blinn-Phong", "GGX", "Blinn-Phong lobe alone", "GGX lobe alone"];
        for (name, v) in names.iter().zip(ratios.iter_mut()) {
            let text = percentiles(v);
            let n = v.len();
            assert!(n > 500, "{name}: {n} cases");
            eprintln!("{name}: {n} patches, max over directions of |f''| / of the bound: {text}");
            assert!(v[n - 1] > 0.5, "{name}: the bound is never approached");
        }
    }

    /// The f32 shading near a sharp GGX highlight interpolates like the exact function: its
    /// interpolation error at levels 8, 16 and 32 falls as `1/n²` with the f64 shading's. With
    /// `1 − (n·h)²` formed as `(n·h)²(α² − 1) + 1` it cancelled to about `α²` in f32, and the
    /// peak `1/(πα²)` made the rounding an error floor of about 4.5·10⁻³ here, above the
    /// estimator's bound at `n = 14` (`brdf::ggx_d_sin2`; a case of the property test's).
    #[test]
    fn ggx_shading_has_no_rounding_floor_near_the_highlight() {
        let tri = TriangleInput {
            positions: [
                Vec3::new(7.4046254, -6.955778, -8.476829),
                Vec3::new(7.478987, -6.9212723, -8.439407),
                Vec3::new(7.4802165, -6.900775, -8.455878),
            ],
            normals: [
                Vec3::new(-0.5664613, 0.5346247, 0.6271348),
                Vec3::new(-0.5668246, 0.54001987, 0.6221643),
                Vec3::new(-0.56884605, 0.5319315, 0.62726635),
            ],
            eye: Vec3::ZERO,
        };
        let material = MaterialKind::Ggx {
            albedo: Vec3::new(0.3454659, 0.119069576, 0.78844523),
            f0: Vec3::new(0.73252666, 0.60075366, 0.53019875),
            roughness: 0.24354774,
        };
        let light = Light::Point {
            position: Vec3::new(-0.40450287, 1.3913608, 0.71938324),
            color: Vec3::new(0.2702486, 0.22998543, 0.6092827),
            intensity: 496.99304,
        };
        let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
        let [np, nq, nr] = tri.normals.map(|x| x.as_dvec3());
        let exact = |b: [f64; 3]| {
            let x = p * b[0] + q * b[1] + r * b[2];
            shade_f64(x, np * b[0] + nq * b[1] + nr * b[2], DVec3::ZERO, &material, &light)
        };
        let k = 12;
        for n in [8u32, 16, 32] {
            let pattern = triangle_pattern(n as f32, [n as f32; 3]);
            let shaded = crate::analysis::oracle::true_error_sampled(
                &tri,
                &material,
                std::slice::from_ref(&light),
                &pattern,
                k,
                f64::INFINITY,
            );
            let mut worst = [0.0f64; 3];
            for t in &pattern.triangles {
                let corners = t.map(|i| pattern.vertices[i as usize]);
                let values = corners.map(exact);
                for i in 0..=k {
                    for j in 0..=(k - i) {
                        let mu = [i, j, k - i - j].map(|m| f64::from(m) / f64::from(k));
                        let b: [f64; 3] =
                            std::array::from_fn(|c| (0..3).map(|v| mu[v] * corners[v][c]).sum());
                        let f = exact(b);
                        for c in 0..3 {
                            let linear: f64 = (0..3).map(|v| mu[v] * values[v][c]).sum();
                            worst[c] = worst[c].max((f[c] - linear).abs());
                        }
                    }
                }
            }
            let text = |e: [f64; 3]| e.map(|x| format!("{x:.2e}")).join(", ");
            eprintln!("n = {n}: f32 shading {}, exact {}", text(shaded), text(worst));
            for c in 0..3 {
                assert!(
                    shaded[c] <= 1.25 * worst[c] + 1.0e-5,
                    "n = {n}, channel {c}: f32 {} against exact {}",
                    shaded[c],
                    worst[c]
                );
            }
        }
    }

    #[test]
    fn light_jets_bound_the_exact_derivatives() {
        let mut rng = crate::test_rng::Rng(0x1e7_b0d5_2c4f_9a31);
        let mut checked = [0usize; 3];
        let mut tightest = [0.0f64; 3];
        let gd = Guard::default();
        for case in 0..3000 {
            let brdf = case % 3;
            let size = rng.range(0.05, 1.0);
            let (centre, positions, eye_dir, eye) = random_patch(&mut rng, size);
            let tangent = eye_dir.any_orthonormal_vector();
            let base = tilt(&mut rng, eye_dir, 0.0, 1.2);
            let spread = (rng.range(-7.0, -0.2)).exp();
            let normals = [0; 3].map(|_| tilt(&mut rng, base, 0.0, spread) * (0.7 + 0.6 * rng.f()));
            let light = random_light(&mut rng, centre, base, tangent, size);
            let material = random_material(&mut rng, brdf);
            let tri = TriangleInput { positions, normals, eye };
            let frame = Frame::new(&tri);
            // Half the cases: a textured parameter, whose range the jets bound over; the
            // shading then takes one value of the range.
            let own = ParameterRange::of(&material);
            let (parameter, shaded) = if case % 2 == 0 || brdf == 0 {
                (own, material)
            } else {
                let (lo, hi) = match material {
                    MaterialKind::BlinnPhong { .. } => {
                        ((own.lo * rng.range(0.3, 1.0)).max(1.0), own.hi * rng.range(1.0, 3.0))
                    }
                    _ => (own.lo * rng.range(0.0, 1.0), (own.hi * rng.range(1.0, 3.0)).min(1.0)),
                };
                let value = rng.range(lo, hi);
                (ParameterRange { lo, hi }, with_value(&material, value))
            };
            let Ok(Some((setup, diff_w, spec_w))) =
                plan_light(&frame, &material, parameter, &light, Discontinuity::Conservative)
            else {
                continue;
            };
            let [p, q, r] = positions.map(|x| x.as_dvec3());
            let [np, nq, nr] = normals.map(|x| x.as_dvec3());
            for _ in 0..6 {
                let (u, v) = (f64::from(rng.range(0.01, 0.98)), f64::from(rng.f()));
                let (u, v) = (u, (1.0 - u - 0.01) * v + 0.005);
                let turn = f64::from(rng.range(0.0, std::f32::consts::TAU));
                // A domain step (barycentric, summing to 0) and the point moving along it.
                let (du, dv) = (turn.cos(), turn.sin());
                let at = |t: f64| {
                    let (a, b) = (u + t * du, v + t * dv);
                    let x = p + (q - p) * a + (r - p) * b;
                    let nrm = np + (nq - np) * a + (nr - np) * b;
                    shade_f64(x, nrm, eye.as_dvec3(), &shaded, &light)
                };
                let scale = scale_along(&tri, du, dv);
                let jets = light_jets(&frame, &material, parameter, &setup, scale, 0.0, &gd);
                let (diff, spec) = (jets.diffuse, jets.specular);
                let h = 2.0e-5;
                let (f0, fp, fm) = (at(0.0), at(h), at(-h));
                for c in 0..3 {
                    let bound = |d: f32, s: f32| f64::from(diff_w[c] * d + spec_w[c] * s);
                    let (m, g, t) =
                        (bound(diff.m, spec[c].m), bound(diff.g, spec[c].g), bound(diff.t, spec[c].t));
                    let first = (fp[c] - fm[c]) / (2.0 * h);
                    let second = (fp[c] - 2.0 * f0[c] + fm[c]) / (h * h);
                    // Rounding of the differences: about 10⁻¹⁶·|f|/h per order.
                    let slack = 1.0e-15 * f0[c].abs().max(1.0e-30);
                    let what = format!(
                        "case {case}: {shaded:?} of {parameter:?}, {light:?}, {tri:?}, point ({u}, {v}), step ({du}, {dv}), channel {c}"
                    );
                    assert!(f0[c] <= m * 1.0001 + slack, "{what}: value {} > {m}", f0[c]);
                    assert!(first.abs() <= g * 1.001 + slack / h, "{what}: first {first} > {g}");
                    assert!(
                        second.abs() <= t * 1.001 + 1.0e3 * slack / (h * h),
                        "{what}: second {second} > {t}"
                    );
                    if t > 0.0 && f0[c] > 0.0 {
                        tightest[brdf] = tightest[brdf].max(second.abs() / t);
                    }
                }
                checked[brdf] += 1;
            }
        }
        eprintln!("points checked per BRDF {checked:?}; largest second derivative / bound {tightest:?}");
        for brdf in 0..3 {
            assert!(checked[brdf] > 1_500, "{checked:?}: too few points where the jets apply");
            // Valid and not vacuous: somewhere the bound is within a factor of four.
            assert!(tightest[brdf] > 0.25, "{tightest:?}: the jets are nowhere near the derivatives");
        }
    }
}
