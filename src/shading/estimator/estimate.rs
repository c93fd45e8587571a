//! The estimator's API and entry point: one triangle's input ([`TriangleInput`]), the result ([`Estimate`], its
//! [`Term`]s and [`Reason`]), [`estimate`] and [`estimate_textured`], and the loop over the
//! lights that sums their bounds (`light_sums`).
//!
//! GLSL twin: `glsl/include/estimator/estimate.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit). There the entry functions (`level_pass`
//! and the others) close the file.

use super::add_light::add_light;
use super::constants::{REFINE_ABOVE, REFINE_FLOOR_MARGIN};
use super::decide::decide;
use super::frame::Frame;
use super::jet::Guard;
use super::light_setup::Sums;
use super::range::{range_class, range_proves, SpecularCaps};
use super::settings::{EstimatorSettings, Split};
use crate::scene::{Light, MaterialKind, Mesh, ParameterRange};
use glam::Vec3;

/// One patch as the TCS sees it: world-space corner positions and (not necessarily unit)
/// vertex normals, and the eye.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleInput {
    pub positions: [Vec3; 3],
    pub normals: [Vec3; 3],
    pub eye: Vec3,
}

impl TriangleInput {
    /// The triangle of `mesh` with the vertex indices `corners` (three), seen from `eye`.
    pub fn of(mesh: &Mesh, corners: &[u32], eye: Vec3) -> TriangleInput {
        let at = |of: &[Vec3]| [0, 1, 2].map(|k| of[corners[k] as usize]);
        TriangleInput { positions: at(&mesh.positions), normals: at(&mesh.normals), eye }
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
    ///
    /// [`pattern_level`]: super::patch_levels::pattern_level
    /// [`FALLBACK_LEVEL`]: super::patch_levels::FALLBACK_LEVEL
    /// [`patch_levels`]: super::patch_levels::patch_levels
    pub level: f32,
    /// The uniform level (inner = outer = `n`) for this triangle alone: the smallest `n` in
    /// `1..=n_max` with `pattern_level(n, n) ≥ level`. When `fallback` is set this is 1.
    /// Shared edges may raise the outer levels; [`patch_levels`] gives what is drawn.
    ///
    /// [`patch_levels`]: super::patch_levels::patch_levels
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
    /// Whether this is the second estimate, with the point and directional lights' ranges over
    /// the children: the first asked for it and the refining floor allowed it
    /// ([`refining_futile`]). The GPU's estimator step lists exactly these triangles for its
    /// refining step.
    pub refined: bool,
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
    // The range class: where the shading's whole range over the triangle is within ε, level 1
    // holds without an estimate.
    let eye = (tri.eye, settings.eye_radius);
    let class = range_class(tri.positions, tri.normals, eye, material, parameter, lights, eps);
    let range = class.bound;
    if range_proves(range, eps) {
        let predicted_error = range.map_or(0.0, |r| r.max_element());
        return Estimate {
            terms: [0.0; TERM_COUNT],
            level: 1.0,
            n: 1,
            fallback: false,
            reason: Reason::None,
            predicted_error,
            refined: false,
        };
    }
    let capped = class.every_specular_capped;
    let (sum, reason) = light_sums(tri, material, parameter, lights, settings, n_max, eps, capped, false);
    let first = decide(&sum, eps, n_max, settings.split, reason);
    let refining_can_help = !refining_futile(&sum, eps, settings.split);
    if first.level > REFINE_ABOVE && (!first.fallback || first.reason == Reason::Level) && refining_can_help {
        let (sum, reason) = light_sums(tri, material, parameter, lights, settings, n_max, eps, capped, true);
        return Estimate { refined: true, ..decide(&sum, eps, n_max, settings.split, reason) };
    }
    first
}

/// Whether the estimate refined over the children must fall back, as its refining floor
/// ([`Sums::floor`]) exceeds `ε` at every level up to the top: then it is not computed. The
/// Heuristic split only (the Uniform split's decision is not bounded by the floor).
pub(super) fn refining_futile(sum: &Sums, eps: f32, split: Split) -> bool {
    split == Split::Heuristic && sum.floor.max_element() > eps * REFINE_FLOOR_MARGIN
}

/// Every light's bounds, summed, and the worst reason for fallback met on the way; with
/// `every_capped` ([`RangeClass::every_specular_capped`]), each light's specular part bounded by
/// its cap; with `refine`, the ranges of the point and directional lights taken over the patch's
/// children.
///
/// [`RangeClass::every_specular_capped`]: super::range::RangeClass::every_specular_capped
#[allow(clippy::too_many_arguments)]
pub(super) fn light_sums(
    tri: &TriangleInput,
    material: &MaterialKind,
    parameter: ParameterRange,
    lights: &[Light],
    settings: &EstimatorSettings,
    n_max: u32,
    eps: f32,
    every_capped: bool,
    refine: bool,
) -> (Sums, Reason) {
    let frame = Frame::new(tri, settings.eye_radius, material.is_specular());
    let caps = if every_capped { SpecularCaps::new(&frame, material) } else { None };
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
            caps.as_ref(),
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

pub(super) fn worse(a: Reason, b: Reason) -> Reason {
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
