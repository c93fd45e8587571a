//! The BRDF factors' jets: the Blinn-Phong power ([`power_jet`]), GGX's distribution, Smith
//! halves and Fresnel ([`ggx_factor_jets`]), the half-vector cosine, a textured parameter's
//! variation ([`parameter_variation`]), and a polygonal light's sampled specular part
//! ([`polygon_specular_bound`]).
//!
//! GLSL twin: `glsl/include/estimator/lobe.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::constants::{Sign, K23, SAFETY};
use super::jet::{chain, cosine, curvature, max_cos_sin, scaled, Curvature, Field, Guard, Jet, NO_H};
use super::light_setup::LightSetup;
use super::terms::Term;
use crate::exact_math::{est_cos, est_log2, est_pow, est_sin};
use crate::scene::{MaterialKind, ParameterRange, PolygonLight, PolygonSampling};
use crate::shading::brdf::{ggx_alpha, ggx_d};
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, LN_2, PI};

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
pub(super) fn polygon_specular_bound(
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
pub(super) fn mis_bound(light: f32, brdf: f32, visibility: f32, gd: &Guard) -> f32 {
    gd.c(gd.mul(2.0 - visibility, light) + gd.mul(visibility, brdf))
}

/// The roughness-dependent GGX factors `[G, V, D]` (the Smith halves with the cosines folded
/// in, and the distribution) at one `alpha`.
#[allow(clippy::too_many_arguments)]
pub(super) fn ggx_factor_jets(
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
pub(super) fn power_jet(
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
pub(super) fn power_net_coefficient(s0: f32, s1: f32, c0: f32, c1: f32) -> f32 {
    let p = 0.5 * (s0 - 2.0);
    let peak = p * (s1 - 1.0) / ((p + 1.0) * s1);
    let x = peak.max(c1 * c1).min(c0 * c0);
    s1 * est_pow(x, p) * ((s1 - 1.0) * (1.0 - x) - x).max(0.0)
}

/// Jet of `v·h = |l̂ + v̂|/2 = cos(∠(l,v)/2)` where the angle between `l̂` and `v̂` is at most
/// `psi_lv_max` and `|l̂ + v̂| ≥ m_min`: its `m` is the *smallest* value (what Fresnel needs),
/// `|D| ≤ (wₗ + wᵥ)/2`, `|D²| ≤ ((wₗ + wᵥ)²/|l̂+v̂| + (2/√3)(wₗ² + wᵥ²))/2`.
pub(super) fn half_cosine_jet(l: &Field, v: &Field, psi_lv_max: f32, m_min: f32, gd: &Guard) -> Jet {
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
pub(super) fn fresnel_jet(f0: f32, vh: &Jet, gd: &Guard) -> Jet {
    let om = 1.0 - vh.m;
    let fm = f0 + (1.0 - f0) * om.powi(5);
    let f1 = 5.0 * (1.0 - f0) * om.powi(4);
    let f2 = 20.0 * (1.0 - f0) * om.powi(3);
    chain(vh, fm, f1, f2, Term::F, gd)
}

/// Jet of the Smith light half with its cosine, `G = c/(c(1 − k) + k)`, of `c = n·l` with jet
/// `c_g` and angle in `nl ⊂ [0, π/2]`: `G' = k/q²`, `G'' = −2k(1 − k)/q³`, `q = c(1 − k) + k`
/// smallest at the largest angle.
pub(super) fn smith_g_jet(c_g: &Jet, nl: (f32, f32), k: f32, gd: &Guard) -> Jet {
    let (c0, c1) = (est_cos(nl.1).max(0.0), est_cos(nl.0));
    let q0 = c0 * (1.0 - k) + k;
    let q1 = c1 * (1.0 - k) + k;
    let g1 = k / (q0 * q0);
    let g2 = 2.0 * k * (1.0 - k) / (q0 * q0 * q0);
    chain(c_g, c1 / q1, g1, g2, Term::V, gd)
}

/// Jet of the Smith view half `V = 1/(c(1 − k) + k)` of `c = n·v` with jet `c_v` and angle in
/// `nv ⊂ [0, π/2]`: `V' = −(1 − k)/q²`, `V'' = 2(1 − k)²/q³`.
pub(super) fn smith_v_jet(c_v: &Jet, nv: (f32, f32), k: f32, gd: &Guard) -> Jet {
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
pub(super) fn smith_v_kink_jet(c_v: &Jet, k: f32, band: f32, gd: &Guard) -> Jet {
    let slope = (1.0 - k) / (k * k);
    let v2 = 2.0 * (1.0 - k) * (1.0 - k) / (k * k * k);
    let value = gd.c(1.0 / k + gd.mul(slope, c_v.m.min(band)));
    chain(c_v, value, slope, v2, Term::V, gd)
}

/// The variation `sup |f(α) − f(α')|` of one light's specular part (per unit weight, per
/// channel) for a parameter anywhere in `parameter` (Eq. 37). `spec_sup` is the part's sup.
/// Blinn-Phong: `att·max_t (t^s₀ − t^s₁)` over the range of `t = n·h`, whose maximum over
/// `t ∈ [0, 1]` is at `t* = (s₀/s₁)^(1/(s₁−s₀))`. GGX: `|∂D/∂α| ≤ 2D/α`, `|∂G/∂α| ≤ G/α` and
/// `|∂V/∂α| ≤ V/α` give `|∂f/∂α| ≤ 4f/α`, so the variation is at most
/// `sup f · min(1, 4 ln(α₁/α₀))`.
pub(super) fn parameter_variation(
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
pub(super) fn ggx_d_jet(c: &Jet, curv: &Curvature, p0: f32, p1: f32, w: f32, alpha: f32, gd: &Guard) -> Jet {
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
pub(super) fn ggx_net_coefficient(a2: f32, s0: f32, s1: f32) -> f32 {
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
