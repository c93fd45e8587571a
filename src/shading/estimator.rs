//! The per-triangle error estimator: the Rust twin of the tessellation control shader.
//!
//! For one triangle, its lights and its material, [`estimate`] returns the smallest
//! tessellation level `n` (inner = outer = `n`, `equal_spacing`) at which linear
//! interpolation of the sub-vertex shading keeps the L∞ error of *every colour channel*
//! below `ε`, or asks for per-pixel fallback. The derivation, every deviation from the
//! paper (Hu et al. 2022 and its supplement) and the measured figures are in
//! `docs/estimator.md`; the brute-force truth it is tested against is
//! [`crate::analysis::oracle`].
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

use crate::scene::{Light, MaterialKind};
use crate::shading::brdf::{ggx_alpha, MIN_LIGHT_DISTANCE_SQUARED};
use glam::Vec3;
use std::cell::Cell;
use std::f32::consts::{FRAC_PI_2, PI};

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
    /// Keep tessellating, with a bound that stays valid across the kink: the diffuse
    /// `max(c, 0)` adds a first-order term `½·sup E·|∇c|·diam/n`, the specular lobe that
    /// `n·l > 0` switches on adds its maximum (an `n`-independent term). See the docs.
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
            discontinuity: Discontinuity::Conservative,
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
pub const TERM_COUNT: usize = 12;

/// The error terms. Each second-derivative contribution is booked under the term that
/// produced it; products of two factors' first derivatives are booked under `Cross`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Term {
    /// Curvature of `n̂ = N/|N|`, the normalisation of the interpolated normal.
    Normal = 0,
    /// Curvature of `l̂ = (p − x)/|p − x|` (point lights).
    Light = 1,
    /// Curvature of `v̂ = (e − x)/|e − x|`.
    View = 2,
    /// Curvature of `ĥ = (l̂ + v̂)/|l̂ + v̂|` and of `v·h = |l̂ + v̂|/2`.
    Half = 3,
    /// The bilinear term `2 Dâ·Db̂` of a cosine `â·b̂` (the paper's Eq. 22).
    Dot = 4,
    /// The second derivative of the point-light falloff `1/d²`.
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
];

/// What [`estimate`] returns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Per term (see [`Term`], [`TERM_NAMES`]): the real-valued level that term alone would
    /// need if it had the whole budget `ε` (largest channel). With `Heuristic` the
    /// second-order terms combine as `n = ⌈√(Σ nₜ²)⌉`; with `Uniform` as
    /// `n = ⌈√M · max nₜ⌉`. Finite, `≥ 0`; `f32::MAX` stands for "no level suffices".
    pub terms: [f32; TERM_COUNT],
    /// The level for inner and outer tessellation levels, in `1..=n_max`. When `fallback`
    /// is set this is 1: the patch is not subdivided and the fragment shader shades per pixel.
    pub n: u32,
    /// Per-pixel fallback: the level would exceed `n_max`, or a discontinuity or
    /// singularity was detected.
    pub fallback: bool,
    /// Why `fallback` is set (`Reason::None` when it is not).
    pub reason: Reason,
    /// The bound on the per-channel L∞ error at level `n` (at `n_max` when the level is
    /// the reason for fallback; `f32::MAX` for discontinuities and singularities).
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
/// Intermediate bounds above this mean fallback (keeps products of two bounds finite).
const BIG: f32 = 1.0e18;
/// Multiplies every bound: f32 rounding in this estimator and in the shading, and the
/// driver's 16.16 fixed-point placement of the pattern vertices (measured in the tests:
/// at most 0.2 % in `K` for `n ≤ 16`); `pattern_slack` adds the growth with `n`.
const SAFETY: f32 = 1.01;
/// Radians added to every cone half-angle (f32 rounding of the directions).
const ANGLE_PAD: f32 = 2.0e-6;
/// A cone wider than this is no bound at all (a cap wider than a hemisphere is not convex).
const MAX_HALF: f32 = FRAC_PI_2 - 1.0e-4;

/// Relative growth of the pattern constant with the level, from the driver's fixed-point
/// vertex placement: `K(n) ≤ K·(1 + n²·PATTERN_SLACK)` (bounded from the measurements in
/// `pattern_constants_cover_the_hardware_pattern`).
const PATTERN_SLACK: f32 = 1.5e-5;

/// Estimates the tessellation level of one triangle. See the module docs and
/// `docs/estimator.md`.
pub fn estimate(
    tri: &TriangleInput,
    material: &MaterialKind,
    lights: &[Light],
    settings: &EstimatorSettings,
) -> Estimate {
    let n_max = settings.n_max.clamp(1, 64);
    // NaN and non-positive ε become 0: only an exactly flat shading passes then.
    let eps = if settings.epsilon > 0.0 { settings.epsilon } else { 0.0 };
    let frame = Frame::new(tri);
    let guard = Guard::default();
    let mut sum = Sums::default();
    let mut reason = Reason::None;
    for light in lights {
        if let Err(r) = add_light(&frame, material, light, settings.discontinuity, &mut sum, &guard)
        {
            reason = worse(reason, r);
        }
    }
    if guard.bad.get() {
        reason = worse(reason, Reason::Singular);
    }
    decide(&sum, eps, n_max, settings.split, reason)
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
// Jets
// ------------------------------------------------------------------------------------------

/// Bounds of one factor over the whole triangle: `m ≥ sup|f|`, `g ≥ sup|Df[δ]|` and
/// `Σₜ h[t] ≥ sup|D²f[δ,δ]|`, the derivatives taken along a domain step `δ` and evaluated
/// at the pattern scale (`|Xδ| → a`, `|Nδ| → b`, see [`Scale`]).
#[derive(Clone, Copy, Debug)]
struct Jet {
    m: f32,
    g: f32,
    h: [f32; TERM_COUNT],
}

const NO_H: [f32; TERM_COUNT] = [0.0; TERM_COUNT];

impl Jet {
    fn constant(m: f32) -> Jet {
        Jet { m, g: 0.0, h: NO_H }
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
        let mut out = Jet { m: self.c(j.m), g: self.c(j.g), h: j.h };
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
        }
    }
    out
}

/// A unit vector field over the triangle (its cone is kept by the caller): `w ≥ |Dû|`
/// (angular speed, at the pattern scale), and `x ≥ |P m''|/|m|` for a field `û = m/|m|`
/// whose `m` is not affine (zero for normalised affine fields).
#[derive(Clone, Copy, Debug)]
struct Field {
    w: f32,
    x: f32,
    term: Term,
}

/// Jet of `c = â·b̂` where the angle between them stays in `[ψ₀, ψ₁]`:
/// `|Dc| ≤ sin ψ (|Dâ| + |Db̂|)` (a derivative of a unit vector is orthogonal to it),
/// `|D²c| ≤ φ(ψ)(wₐ² + w_b²) + sin ψ (xₐ + x_b) + 2 wₐ w_b` with
/// `φ(ψ) = |cos ψ|/2 + √(1 − ¾cos²ψ) ≤ 2/√3` (the part of `D²â` that `b̂` can see).
fn cosine(a: &Field, b: &Field, psi: (f32, f32), gd: &Guard) -> Jet {
    let (p0, p1) = psi;
    let s_max = max_sin(p0, p1);
    let phi = max_phi(p0, p1);
    let mut h = NO_H;
    let ha = gd.c(phi * a.w * a.w + s_max * a.x);
    let hb = gd.c(phi * b.w * b.w + s_max * b.x);
    h[a.term as usize] += ha;
    h[b.term as usize] += hb;
    h[Term::Dot as usize] += gd.c(2.0 * a.w * b.w);
    let g = gd.c(s_max * (a.w + b.w));
    Jet {
        m: p0.cos().abs().max(p1.cos().abs()),
        g,
        h,
    }
}

/// `max sin ψ` over `[p0, p1] ⊂ [0, π]`.
fn max_sin(p0: f32, p1: f32) -> f32 {
    if p0 <= FRAC_PI_2 && p1 >= FRAC_PI_2 {
        1.0
    } else {
        p0.sin().max(p1.sin()).max(0.0)
    }
}

/// `max φ(ψ)` over `[p0, p1]`, `φ = c/2 + √(1 − ¾c²)` with `c = |cos ψ|`; φ rises from 1 at
/// `c = 0` to 2/√3 at `c = 1/√3` and falls back to 1 at `c = 1`.
fn max_phi(p0: f32, p1: f32) -> f32 {
    let (c0, c1) = (p0.cos().abs(), p1.cos().abs());
    let (lo, hi) = if p0 <= FRAC_PI_2 && p1 >= FRAC_PI_2 {
        (0.0, c0.max(c1))
    } else {
        (c0.min(c1), c0.max(c1))
    };
    let c = (1.0 / 3.0f32.sqrt()).clamp(lo, hi);
    (0.5 * c + (1.0 - 0.75 * c * c).max(0.0).sqrt()).min(K23)
}

/// `max cos^p ψ · sin^q ψ` over `[a, b] ⊂ [0, π/2]` (`q ≥ 0`): unimodal with its peak at
/// `tan²ψ = q/p` (`p > 0`); increasing when `p ≤ 0`.
fn max_cos_sin(p: f32, q: f32, a: f32, b: f32) -> f32 {
    let peak = if p > 0.0 { (q / p).sqrt().atan() } else { FRAC_PI_2 };
    let x = peak.clamp(a, b);
    let c = x.cos().max(0.0);
    let s = x.sin().max(0.0);
    let cp = if p == 0.0 { 1.0 } else { c.powf(p) };
    let sq = if q == 0.0 { 1.0 } else { s.powf(q) };
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
    a.cross(b).length().atan2(a.dot(b))
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
    if u.iter().any(|v| *v == Vec3::ZERO) {
        return NO_CONE;
    }
    let d = [
        (u[0] - u[1]).length_squared(),
        (u[1] - u[2]).length_squared(),
        (u[2] - u[0]).length_squared(),
    ];
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

// ------------------------------------------------------------------------------------------
// The pattern
// ------------------------------------------------------------------------------------------

/// Evaluation point of the jets: what `|Xδ|` (length) and `|Nδ|` are replaced by.
#[derive(Clone, Copy, Debug, Default)]
struct Scale {
    a: f32,
    b: f32,
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
const SHAPES: [[(f32, f32); 2]; 7] = [
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

// ------------------------------------------------------------------------------------------
// Per-triangle and per-light geometry
// ------------------------------------------------------------------------------------------

/// Scale-free quantities of the triangle.
struct Frame {
    vertices: [Vec3; 3],
    centroid: Vec3,
    /// `max_k |xₖ − centroid|`: how far any point is from the centroid.
    rho_x: f32,
    /// Pattern scales: level 1, levels ≥ 2, and the diameters (Relaxed terms).
    s1: Scale,
    sn: Scale,
    d1: Scale,
    dn: Scale,
    n_cone: Cone,
    /// Lower bound on `|N(λ)|` over the triangle; 0 when the normal can vanish.
    r_n: f32,
    v_cone: Cone,
    /// Lower bound on the distance from the eye to the triangle.
    e_min: f32,
    v_center: Vec3,
}

impl Frame {
    fn new(tri: &TriangleInput) -> Frame {
        let [p0, p1, p2] = tri.positions;
        let centroid = (p0 + p1 + p2) / 3.0;
        let rho_x = (p0 - centroid)
            .length()
            .max((p1 - centroid).length())
            .max((p2 - centroid).length());
        let px = pattern_constants(p1 - p0, p2 - p0);
        let [n0, n1, n2] = tri.normals;
        let pn = pattern_constants(n1 - n0, n2 - n0);
        let n_cone = cone_of(tri.normals);
        let longest = n0.length().max(n1.length()).max(n2.length());
        let mut r_n = min_length(tri.normals, &n_cone);
        if !(r_n > 1.0e-6 * longest) {
            r_n = 0.0;
        }
        let to_eye = [tri.eye - p0, tri.eye - p1, tri.eye - p2];
        let v_cone = cone_of(to_eye);
        let e_min = min_length(to_eye, &v_cone);
        Frame {
            vertices: tri.positions,
            centroid,
            rho_x,
            s1: Scale { a: px.sqrt_k1, b: pn.sqrt_k1 },
            sn: Scale { a: px.sqrt_k, b: pn.sqrt_k },
            d1: Scale { a: px.diam1, b: pn.diam1 },
            dn: Scale { a: px.diam, b: pn.diam },
            n_cone,
            r_n,
            v_cone,
            e_min,
            v_center: unit(tri.eye - centroid),
        }
    }
}

/// Everything about one light that does not depend on the pattern scale.
struct LightSetup {
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
    /// Range of the angle between l̂ and v̂.
    psi_lv: (f32, f32),
}

/// Accumulated bounds, per term and channel: `½·SAFETY·Σ weight·H` at level 1 and at
/// levels ≥ 2 (to be divided by n²), and the Relaxed first-order (÷ n) and constant terms.
#[derive(Default)]
struct Sums {
    h1: [Vec3; TERM_COUNT],
    hn: [Vec3; TERM_COUNT],
    lin1: Vec3,
    linn: Vec3,
    zero: Vec3,
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

fn add_light(
    frame: &Frame,
    material: &MaterialKind,
    light: &Light,
    mode: Discontinuity,
    sum: &mut Sums,
    gd: &Guard,
) -> Result<(), Reason> {
    let (radiance, l_cone, inv_d, l_center) = match *light {
        Light::Point { position, color, intensity } => {
            let radiance = color * intensity;
            if radiance == Vec3::ZERO {
                return Ok(());
            }
            let w = frame.vertices.map(|x| position - x);
            let cone = cone_of(w);
            let d_min = min_length(w, &cone);
            // The falloff is clamped at d² = 10⁻⁸: only smooth (and bounded) beyond it.
            if !(d_min * d_min > MIN_LIGHT_DISTANCE_SQUARED * 1.001) {
                let (diff, spec) = weights(material, radiance);
                if diff == Vec3::ZERO && spec == Vec3::ZERO {
                    return Ok(());
                }
                return Err(Reason::Singular);
            }
            (radiance, cone, 1.0 / d_min, unit(position - frame.centroid))
        }
        Light::Directional { direction, color, intensity } => {
            let radiance = color * intensity;
            if radiance == Vec3::ZERO {
                return Ok(());
            }
            let l = unit(-direction);
            (radiance, Cone { axis: l, half: 0.0 }, 0.0, l)
        }
    };
    let (diff_w, spec_w) = weights(material, radiance);
    if diff_w == Vec3::ZERO && spec_w == Vec3::ZERO {
        return Ok(());
    }
    if frame.r_n <= 0.0 {
        return Err(Reason::Singular);
    }
    let psi_nl = psi_range(&frame.n_cone, &l_cone);
    if psi_nl.0 >= FRAC_PI_2 {
        // n·l ≤ 0 everywhere: this light adds exactly 0.
        return Ok(());
    }
    let straddle = psi_nl.1 >= FRAC_PI_2;
    if straddle && mode == Discontinuity::Conservative {
        return Err(Reason::Discontinuity);
    }
    let mut setup = LightSetup {
        inv_d,
        psi_nl,
        straddle,
        h_cone: NO_CONE,
        m_min: 0.0,
        psi_nh: (0.0, PI),
        psi_nv: (0.0, PI),
        psi_lv: (0.0, PI),
    };
    let specular = !matches!(material, MaterialKind::Lambert { .. });
    if specular {
        if !(frame.e_min > 0.0) {
            return Err(Reason::Singular);
        }
        let psi_lv = psi_range(&l_cone, &frame.v_cone);
        let m_min = 2.0 * (0.5 * psi_lv.1).cos();
        if !(psi_lv.1 < PI - 1.0e-3) || !(m_min > 0.0) {
            return Err(Reason::Singular);
        }
        // ĥ turns at most (|Dl̂| + |Dv̂|)/|l̂ + v̂| per unit |Xδ|; integrate from the centroid.
        let speed = (inv_d + 1.0 / frame.e_min) / m_min;
        let h_half = speed * frame.rho_x + ANGLE_PAD;
        let h_axis = unit(l_center + frame.v_center);
        setup.h_cone = if h_axis == Vec3::ZERO || !(h_half < MAX_HALF) {
            NO_CONE
        } else {
            Cone { axis: h_axis, half: h_half }
        };
        setup.m_min = m_min;
        setup.psi_lv = psi_lv;
        setup.psi_nh = psi_range(&frame.n_cone, &setup.h_cone);
        setup.psi_nv = psi_range(&frame.n_cone, &frame.v_cone);
        match *material {
            MaterialKind::BlinnPhong { shininess, .. } => {
                // max(n·h, 0)^s is C^{1,1} across n·h = 0 only for s ≥ 2.
                let nh = setup.psi_nh;
                if nh.0 < FRAC_PI_2 && nh.1 >= FRAC_PI_2 && shininess < 2.0 {
                    return Err(Reason::Discontinuity);
                }
            }
            MaterialKind::Ggx { .. } => {
                // max(n·v, 0) has a kink in V at n·v = 0.
                let nv = setup.psi_nv;
                if nv.0 < FRAC_PI_2 && nv.1 > FRAC_PI_2 {
                    return Err(Reason::Discontinuity);
                }
            }
            MaterialKind::Lambert { .. } => {}
        }
    }

    for level in 0..2 {
        let s = if level == 0 { frame.s1 } else { frame.sn };
        let (diff, spec) = light_jets(frame, material, &setup, s, gd);
        let target = if level == 0 { &mut sum.h1 } else { &mut sum.hn };
        for t in 0..TERM_COUNT {
            let spec_h = Vec3::new(spec[0].h[t], spec[1].h[t], spec[2].h[t]);
            target[t] += (diff_w * diff.h[t] + spec_w * spec_h) * (0.5 * SAFETY);
        }
        if setup.straddle && level == 1 {
            // Relaxed: on a sub-triangle the terminator crosses, |c| ≤ sup|Dc|·diam/n, so
            // the diffuse max(c,0) = (c + |c|)/2 adds ½·sup E'·sup|Dc|(diam)/n; the
            // specular lobe switched on by n·l > 0 adds at most its maximum.
            let att = if setup.inv_d > 0.0 { setup.inv_d * setup.inv_d } else { 1.0 };
            for (lin, d) in [(&mut sum.lin1, frame.d1), (&mut sum.linn, frame.dn)] {
                let gc = gd.c(d.b / frame.r_n + d.a * setup.inv_d);
                *lin += diff_w * (0.5 * SAFETY * gd.mul(att, gc));
            }
            sum.zero += spec_w * Vec3::new(spec[0].m, spec[1].m, spec[2].m) * SAFETY;
        }
    }
    Ok(())
}

/// The jets of one light's diffuse part (`E'·(n·l)`, per unit weight) and specular part
/// (per channel, per unit weight), at pattern scale `s`.
fn light_jets(
    frame: &Frame,
    material: &MaterialKind,
    st: &LightSetup,
    s: Scale,
    gd: &Guard,
) -> (Jet, [Jet; 3]) {
    let n = Field {
        w: gd.c(s.b / frame.r_n),
        x: 0.0,
        term: Term::Normal,
    };
    let l = Field {
        w: gd.mul(s.a, st.inv_d),
        x: 0.0,
        term: Term::Light,
    };
    // E' = 1/d²: |DE'| ≤ 2|Dl|/d³, |D²E'| = |6(l̂·Dl)² − 2|Dl|²|/d⁴ ≤ 6|Dl|²/d⁴.
    let att = if st.inv_d > 0.0 {
        let id = st.inv_d;
        let id2 = gd.mul(id, id);
        let a_id = gd.mul(s.a, id);
        let mut h = NO_H;
        let a_id2 = gd.mul(a_id, a_id);
        h[Term::Attenuation as usize] = gd.mul(6.0 * a_id2, id2);
        Jet { m: id2, g: gd.mul(2.0 * a_id, id2), h }
    } else {
        Jet::constant(1.0)
    };
    let c_nl = cosine(&n, &l, st.psi_nl, gd);
    let diffuse = product([att, c_nl], gd);
    let zero = Jet::constant(0.0);
    if matches!(material, MaterialKind::Lambert { .. }) {
        return (diffuse, [zero; 3]);
    }

    let v = Field {
        w: gd.c(s.a / frame.e_min),
        x: 0.0,
        term: Term::View,
    };
    let h = Field {
        w: gd.c((l.w + v.w) / st.m_min),
        x: gd.c(K23 * (l.w * l.w + v.w * v.w) / st.m_min),
        term: Term::Half,
    };
    // n·h where it is positive (both lobes vanish, with their derivatives, below 0).
    let (h0, h1) = (st.psi_nh.0, st.psi_nh.1.min(FRAC_PI_2));
    let w_nh = gd.c(n.w + h.w);

    match *material {
        MaterialKind::Lambert { .. } => unreachable!(),
        MaterialKind::BlinnPhong { shininess, .. } => {
            if st.psi_nh.0 >= FRAC_PI_2 {
                return (diffuse, [zero; 3]);
            }
            let s_ = shininess;
            let c_nh = cosine(&n, &h, (h0, h1), gd);
            // T = t^s, t = cos ψ: |DT| ≤ s cos^(s−1)ψ sin ψ·w, jointly maximised over ψ;
            // |D²T| ≤ s(s−1) cos^(s−2)ψ sin²ψ·w² + s t^(s−1)|D²t|.
            let chi = h0.cos();
            let g = gd.c(s_ * max_cos_sin(s_ - 1.0, 1.0, h0, h1) * w_nh);
            let mut hh = scaled(&c_nh.h, s_ * chi.powf(s_ - 1.0), gd);
            if s_ > 1.0 {
                let k = s_ * (s_ - 1.0) * max_cos_sin(s_ - 2.0, 2.0, h0, h1);
                let w2 = gd.mul(w_nh, w_nh);
                hh[Term::Power as usize] = gd.c(hh[Term::Power as usize] + gd.mul(k, w2));
            }
            let t = gd.jet(Jet { m: chi.powf(s_), g, h: hh });
            let spec = product([att, t], gd);
            (diffuse, [spec; 3])
        }
        MaterialKind::Ggx { f0, roughness, .. } => {
            let alpha = ggx_alpha(roughness);
            let k = 0.5 * alpha;

            // G = c/(c(1−k)+k) with c = n·l ≥ 0 (the gate keeps c ≥ 0 where G is used).
            let nl = (st.psi_nl.0, st.psi_nl.1.min(FRAC_PI_2));
            let c_g = cosine(&n, &l, nl, gd);
            let (c0, c1) = (nl.1.cos().max(0.0), nl.0.cos());
            let q0 = c0 * (1.0 - k) + k;
            let q1 = c1 * (1.0 - k) + k;
            let g1 = k / (q0 * q0);
            let g2 = 2.0 * k * (1.0 - k) / (q0 * q0 * q0);
            let mut gh = scaled(&c_g.h, g1, gd);
            let cg2 = gd.mul(c_g.g, c_g.g);
            gh[Term::V as usize] = gd.c(gh[Term::V as usize] + gd.mul(g2, cg2));
            let gjet = gd.jet(Jet { m: c1 / q1, g: gd.mul(g1, c_g.g), h: gh });

            // V_v = 1/(max(n·v, 0)(1−k)+k): constant 1/k where n·v ≤ 0 throughout.
            let vjet = if st.psi_nv.0 >= FRAC_PI_2 {
                Jet::constant(1.0 / k)
            } else {
                let nv = (st.psi_nv.0, st.psi_nv.1.min(FRAC_PI_2));
                let c_v = cosine(&n, &v, nv, gd);
                let q = nv.1.cos().max(0.0) * (1.0 - k) + k;
                let v1 = (1.0 - k) / (q * q);
                let v2 = 2.0 * (1.0 - k) * (1.0 - k) / (q * q * q);
                let mut vh = scaled(&c_v.h, v1, gd);
                let cv2 = gd.mul(c_v.g, c_v.g);
                vh[Term::V as usize] = gd.c(vh[Term::V as usize] + gd.mul(v2, cv2));
                gd.jet(Jet { m: 1.0 / q, g: gd.mul(v1, c_v.g), h: vh })
            };

            // D(t), t = n·h = cos ψ, with s2 = sin²ψ and u = α² + (1−α²)s2:
            // D = α²/(πu²), D' = 4α²β t/(πu³), D'' = 4α²β(u + 6βt²)/(πu⁴), β = 1 − α².
            let djet = if st.psi_nh.0 >= FRAC_PI_2 {
                Jet::constant(alpha * alpha / PI)
            } else {
                let c_nh = cosine(&n, &h, (h0, h1), gd);
                ggx_d_jet(&c_nh, h0, h1, w_nh, alpha, gd)
            };

            // v·h = |l̂ + v̂|/2 = cos(∠(l,v)/2): |D| ≤ (wₗ + wᵥ)/2,
            // |D²| ≤ ((wₗ + wᵥ)²/|l̂+v̂| + (2/√3)(wₗ² + wᵥ²))/2.
            let t0 = (0.5 * st.psi_lv.1).cos().clamp(0.0, 1.0);
            let gt = gd.c(0.5 * (l.w + v.w));
            let mut ht = NO_H;
            ht[Term::Light as usize] = gd.c(0.5 * K23 * l.w * l.w);
            ht[Term::View as usize] = gd.c(0.5 * K23 * v.w * v.w);
            ht[Term::Half as usize] = gd.c(0.5 * (l.w + v.w) * (l.w + v.w) / st.m_min);
            let om = 1.0 - t0;
            let mut spec = [zero; 3];
            for (c, out) in spec.iter_mut().enumerate() {
                let f0c = f0[c];
                let fm = f0c + (1.0 - f0c) * om.powi(5);
                let f1 = 5.0 * (1.0 - f0c) * om.powi(4);
                let f2 = 20.0 * (1.0 - f0c) * om.powi(3);
                let mut fh = scaled(&ht, f1, gd);
                let gt2 = gd.mul(gt, gt);
                fh[Term::F as usize] = gd.c(fh[Term::F as usize] + gd.mul(f2, gt2));
                let fjet = gd.jet(Jet { m: fm, g: gd.mul(f1, gt), h: fh });
                let p = product([att, djet, fjet, gjet, vjet], gd);
                *out = Jet { m: 0.25 * p.m, g: 0.25 * p.g, h: scaled(&p.h, 0.25, gd) };
            }
            (diffuse, spec)
        }
    }
}

/// GGX `D(n·h)` jet with the first and second derivatives maximised jointly with the
/// `sin ψ` that bounds `|D(n·h)|` (the peak of `D` sits where `n·h` is stationary).
fn ggx_d_jet(c: &Jet, p0: f32, p1: f32, w: f32, alpha: f32, gd: &Guard) -> Jet {
    let a2 = alpha * alpha;
    let beta = 1.0 - a2;
    let coef = 4.0 * a2 * beta / PI;
    let (s0, s1) = (p0.sin().powi(2), p1.sin().powi(2));
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
    let r2 = 2.0 * big_a * a2
        / (beta * (b2 + (b2 * b2 - 40.0 * big_a * a2).max(0.0).sqrt())).max(1.0e-30);
    let x2 = r2.clamp(s0, s1);
    let u2 = u(x2);
    let d2 = x2 * (big_a - 5.0 * beta * x2) / (u2 * u2 * u2 * u2);
    let u0 = u(s0);
    let m = a2 / (PI * u0 * u0);
    let g = gd.mul(gd.c(coef * d1), w);
    let slope = gd.c(coef * p0.cos() / (u0 * u0 * u0));
    let mut h = scaled(&c.h, slope, gd);
    let w2 = gd.mul(w, w);
    let dd = gd.c(coef * d2);
    h[Term::D as usize] = gd.c(h[Term::D as usize] + gd.mul(dd, w2));
    gd.jet(Jet { m, g, h })
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

fn sum_terms(h: &[Vec3; TERM_COUNT]) -> Vec3 {
    h.iter().fold(Vec3::ZERO, |acc, x| acc + *x)
}

/// Bound at level `n` for channel sums `a1` (level 1) / `an` (levels ≥ 2).
fn bound_at(sum: &Sums, a1: Vec3, an: Vec3, n: u32) -> f32 {
    let e = if n <= 1 {
        a1 + sum.lin1 + sum.zero
    } else {
        let nf = n as f32;
        an / (nf * nf) + an * PATTERN_SLACK + sum.linn / nf + sum.zero
    };
    let m = e.max_element();
    if m.is_nan() {
        f32::MAX
    } else {
        m.min(f32::MAX)
    }
}

fn decide(sum: &Sums, eps: f32, n_max: u32, split: Split, reason: Reason) -> Estimate {
    let a1 = sum_terms(&sum.h1);
    let an = sum_terms(&sum.hn);
    let finite = |x: f32| if x.is_nan() { f32::MAX } else { x.min(f32::MAX) };

    let mut terms = [0.0f32; TERM_COUNT];
    for (t, out) in terms.iter_mut().enumerate() {
        let b = sum.hn[t].max_element();
        if b > 0.0 {
            *out = finite((b / eps).sqrt());
        }
    }
    let relaxed_on = sum.linn.max_element() > 0.0 || sum.zero.max_element() > 0.0;
    if relaxed_on {
        let mut worst = 0.0f32;
        for c in 0..3 {
            worst = worst.max(level_for(0.0, sum.linn[c], sum.zero[c], eps));
        }
        terms[Term::Terminator as usize] = finite(worst);
    }

    let n_real = match split {
        Split::Heuristic => {
            let e1 = (a1 + sum.lin1 + sum.zero).max_element();
            if e1 <= eps {
                1.0
            } else {
                let mut n = 2.0f32;
                for c in 0..3 {
                    let lvl = level_for(an[c], sum.linn[c], sum.zero[c] + an[c] * PATTERN_SLACK, eps);
                    n = n.max(lvl);
                }
                n
            }
        }
        Split::Uniform => {
            let mut count = 0u32;
            for t in 0..TERM_COUNT {
                if sum.hn[t].max_element() > 0.0 || sum.h1[t].max_element() > 0.0 {
                    count += 1;
                }
            }
            if relaxed_on {
                count += 1;
            }
            let share = eps / count.max(1) as f32;
            let one_ok = (0..TERM_COUNT).all(|t| sum.h1[t].max_element() <= share)
                && (sum.lin1 + sum.zero).max_element() <= share;
            if one_ok {
                1.0
            } else {
                let mut n = 2.0f32;
                for t in 0..TERM_COUNT {
                    for c in 0..3 {
                        let b = sum.hn[t][c];
                        n = n.max(level_for(b, 0.0, b * PATTERN_SLACK, share));
                    }
                }
                if relaxed_on {
                    for c in 0..3 {
                        n = n.max(level_for(0.0, sum.linn[c], sum.zero[c], share));
                    }
                }
                n
            }
        }
    };

    let mut reason = reason;
    let n_ok = n_real <= n_max as f32; // false for NaN and ∞
    if reason == Reason::None && !n_ok {
        reason = Reason::Level;
    }
    match reason {
        Reason::None => {
            let n = (n_real.ceil() as u32).clamp(1, n_max);
            Estimate {
                terms,
                n,
                fallback: false,
                reason,
                predicted_error: bound_at(sum, a1, an, n),
            }
        }
        Reason::Level => Estimate {
            terms,
            n: 1,
            fallback: true,
            reason,
            predicted_error: bound_at(sum, a1, an, n_max),
        },
        Reason::Discontinuity | Reason::Singular => Estimate {
            terms,
            n: 1,
            fallback: true,
            reason,
            predicted_error: f32::MAX,
        },
    }
}
