//! The estimator's vocabulary: one triangle's input ([`TriangleInput`]), the result ([`Estimate`]),
//! the bound's terms ([`Term`], [`TERM_COUNT`], [`TERM_NAMES`]) and why an estimate asks for
//! per-pixel fallback ([`Reason`]).
//!
//! GLSL twin: `glsl/include/estimator/terms.glsl` (the term ids and the reasons; the input and
//! the result are `estimate_pass`'s arguments and level). Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin`.

use crate::scene::Mesh;
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
