//! Jet arithmetic: a factor's bounds (value, first and second derivative) as a [`Jet`], the
//! [`Guard`] that saturates them, the product and chain rules, and the jets of a cosine between
//! two unit fields ([`Field`], [`Angles`], [`Curvature`]).
//!
//! GLSL twin: `glsl/include/estimator/jet.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::constants::{BIG, K23};
use super::terms::{Term, TERM_COUNT};
use crate::exact_math::{est_atan2, est_cos, est_pow, est_sin};
use std::cell::Cell;
use std::f32::consts::FRAC_PI_2;

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
///
/// [`Scale`]: super::pattern::Scale
#[derive(Clone, Copy, Debug)]
pub(super) struct Jet {
    pub(super) m: f32,
    pub(super) g: f32,
    pub(super) h: [f32; TERM_COUNT],
    pub(super) t: f32,
}

pub(super) const NO_H: [f32; TERM_COUNT] = [0.0; TERM_COUNT];

impl Jet {
    pub(super) fn constant(m: f32) -> Jet {
        Jet { m, g: 0.0, h: NO_H, t: 0.0 }
    }
}

/// Saturates bounds at [`BIG`] and remembers that it did (which forces fallback). Also
/// catches NaN (`!(x <= BIG)`).
#[derive(Default)]
pub(super) struct Guard {
    pub(super) bad: Cell<bool>,
}

impl Guard {
    #[inline]
    pub(super) fn c(&self, x: f32) -> f32 {
        if x <= BIG {
            x
        } else {
            self.bad.set(true);
            BIG
        }
    }

    #[inline]
    pub(super) fn mul(&self, a: f32, b: f32) -> f32 {
        self.c(a * b)
    }

    pub(super) fn jet(&self, j: Jet) -> Jet {
        let mut out = Jet { m: self.c(j.m), g: self.c(j.g), h: j.h, t: self.c(j.t) };
        for h in &mut out.h {
            *h = self.c(*h);
        }
        out
    }
}

/// `h · s` for every term.
pub(super) fn scaled(h: &[f32; TERM_COUNT], s: f32, gd: &Guard) -> [f32; TERM_COUNT] {
    let mut out = NO_H;
    for (o, &x) in out.iter_mut().zip(h) {
        *o = gd.mul(x, s);
    }
    out
}

/// Product rule for `K` factors:
/// `D²∏f = Σᵢ D²fᵢ ∏_{j≠i} fⱼ + 2 Σ_{i<j} Dfᵢ Dfⱼ ∏_{k≠i,j} fₖ`.
pub(super) fn product<const K: usize>(f: [Jet; K], gd: &Guard) -> Jet {
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
pub(super) struct Field {
    pub(super) w: f32,
    pub(super) radial: f32,
    pub(super) x: f32,
    pub(super) term: Term,
}

/// Jet of `c = â·b̂` where the angle between them stays in `[ψ₀, ψ₁]`:
/// `|Dc| ≤ sin ψ (|Dâ| + |Db̂|)` (a derivative of a unit vector is orthogonal to it),
/// `|D²c| ≤ C(â) + C(b̂) + sin ψ (xₐ + x_b) + 2 wₐ w_b` with `C` the part of `D²â` that
/// `b̂` can see (`docs/estimator.md` §2, "Normalised vector fields"):
/// `C = min(φ(ψ)·w², max|cos ψ|·w² + 2 max sin ψ·w·radial)`,
/// `φ(ψ) = |cos ψ|/2 + √(1 − ¾cos²ψ) ≤ 2/√3`.
pub(super) fn cosine(a: &Field, b: &Field, psi: (f32, f32), gd: &Guard) -> Jet {
    cosine_at(a, b, &Angles::of(psi), gd)
}

/// [`cosine`] with the angle range's [`Angles`] given.
pub(super) fn cosine_at(a: &Field, b: &Field, angles: &Angles, gd: &Guard) -> Jet {
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
pub(super) struct Curvature {
    /// `wₐ² + w_b² ≥ |u|² + |v|²`.
    pub(super) turn: f32,
    /// `2wₐw_b + sin ψ (2wₐρₐ + xₐ + 2w_bρ_b + x_b)`.
    pub(super) rest: f32,
}

pub(super) fn curvature(a: &Field, b: &Field, psi: (f32, f32), gd: &Guard) -> Curvature {
    let s_max = max_sin(psi.0, psi.1);
    let across_a = gd.c(2.0 * gd.mul(a.w, a.radial) + a.x);
    let across_b = gd.c(2.0 * gd.mul(b.w, b.radial) + b.x);
    Curvature {
        turn: gd.c(gd.mul(a.w, a.w) + gd.mul(b.w, b.w)),
        rest: gd.c(2.0 * a.w * b.w + s_max * gd.c(across_a + across_b)),
    }
}

/// What the jets need of an angle range `[ψ₀, ψ₁]` between two unit fields.
pub(super) struct Angles {
    pub(super) s_max: f32,
    pub(super) c_max: f32,
    pub(super) phi: f32,
}

impl Angles {
    pub(super) fn of((p0, p1): (f32, f32)) -> Angles {
        Angles::with_cosines((p0, p1), (est_cos(p0), est_cos(p1)))
    }

    /// The same with the cosines of the range's ends given (`est_cos` of each).
    pub(super) fn with_cosines((p0, p1): (f32, f32), (c0, c1): (f32, f32)) -> Angles {
        let (c0, c1) = (c0.abs(), c1.abs());
        Angles { s_max: max_sin(p0, p1), c_max: c0.max(c1), phi: max_phi(p0, p1, c0, c1) }
    }

    /// `≥ |D²û·b̂|` for the field `f` and a unit `b̂` at an angle in the range: with
    /// `A = Dm` and `p` its part across `û`, `D²û = −(2p(û·A) + û|p|²)/|m|²`, so
    /// `|D²û·b̂| ≤ min(φ(ψ)·w², max|cos ψ|·w² + 2 max sin ψ·w·radial)` (+ `sin ψ·x`).
    pub(super) fn seen(&self, f: &Field, gd: &Guard) -> f32 {
        let w2 = gd.mul(f.w, f.w);
        let turning = gd.mul(self.phi, w2);
        let radial = gd.c(self.c_max * w2 + 2.0 * self.s_max * gd.mul(f.w, f.radial));
        gd.c(turning.min(radial) + self.s_max * f.x)
    }
}

/// `max sin ψ` over `[p0, p1] ⊂ [0, π]`.
pub(super) fn max_sin(p0: f32, p1: f32) -> f32 {
    if p0 <= FRAC_PI_2 && p1 >= FRAC_PI_2 {
        1.0
    } else {
        est_sin(p0).max(est_sin(p1)).max(0.0)
    }
}

/// `max φ(ψ)` over `[p0, p1]`, `φ = c/2 + √(1 − ¾c²)` with `c = |cos ψ|`; φ rises from 1 at
/// `c = 0` to 2/√3 at `c = 1/√3` and falls back to 1 at `c = 1`. `c0`, `c1`: `|cos|` at the ends.
pub(super) fn max_phi(p0: f32, p1: f32, c0: f32, c1: f32) -> f32 {
    let (lo, hi) =
        if p0 <= FRAC_PI_2 && p1 >= FRAC_PI_2 { (0.0, c0.max(c1)) } else { (c0.min(c1), c0.max(c1)) };
    let c = (1.0 / 3.0f32.sqrt()).clamp(lo, hi);
    (0.5 * c + (1.0 - 0.75 * c * c).max(0.0).sqrt()).min(K23)
}

/// `max cos^p ψ · sin^q ψ` over `[a, b] ⊂ [0, π/2]` (`q ≥ 0`): unimodal with its peak at
/// `tan²ψ = q/p` (`p > 0`); increasing when `p ≤ 0`.
pub(super) fn max_cos_sin(p: f32, q: f32, a: f32, b: f32) -> f32 {
    let peak = if p > 0.0 { est_atan2((q / p).sqrt(), 1.0) } else { FRAC_PI_2 };
    let x = peak.clamp(a, b);
    let c = est_cos(x).max(0.0);
    let s = est_sin(x).max(0.0);
    let cp = if p == 0.0 { 1.0 } else { est_pow(c, p) };
    let sq = if q == 0.0 { 1.0 } else { est_pow(s, q) };
    cp * sq
}

/// The chain rule for `φ(u)` of a factor `u` with jet `inner`, given `value ≥ sup|φ|`,
/// `first ≥ sup|φ'|` and `second ≥ sup|φ''|` over `u`'s range: `g = first·g_u`,
/// `h = first·h_u + second·g_u²` (the last part charged to `term`).
pub(super) fn chain(inner: &Jet, value: f32, first: f32, second: f32, term: Term, gd: &Guard) -> Jet {
    let mut h = scaled(&inner.h, first, gd);
    let mut t = gd.mul(inner.t, first);
    let g2 = gd.mul(inner.g, inner.g);
    let curvature = gd.mul(second, g2);
    h[term as usize] = gd.c(h[term as usize] + curvature);
    t = gd.c(t + curvature);
    gd.jet(Jet { m: value, g: gd.mul(first, inner.g), h, t })
}

/// Elementwise larger bounds of two jets.
pub(super) fn jet_max(a: &Jet, b: &Jet) -> Jet {
    let mut h = NO_H;
    for t in 0..TERM_COUNT {
        h[t] = a.h[t].max(b.h[t]);
    }
    Jet { m: a.m.max(b.m), g: a.g.max(b.g), h, t: a.t.max(b.t) }
}
