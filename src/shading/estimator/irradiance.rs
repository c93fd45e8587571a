//! One light's jets at one pattern scale ([`LightJets`], [`light_jets`]): the unit fields
//! `n̂`, `l̂`, `v̂`, `ĥ`, the falloff ([`attenuation_jet`]) and the irradiance field of a point
//! light ([`irradiance_jet`], with [`along_plane`] and [`tilted`]).
//!
//! GLSL twin: `glsl/include/estimator/irradiance.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::constants::{Sign, K23, TILT_FLAT, TILT_PEAK};
use super::frame::Frame;
use super::jet::{cosine, cosine_at, curvature, jet_max, product, scaled, Angles, Field, Guard, Jet, NO_H};
use super::light_setup::LightSetup;
use super::lobe::{fresnel_jet, ggx_factor_jets, half_cosine_jet, power_jet};
use super::pattern::Scale;
use super::terms::Term;
use crate::exact_math::est_sin;
use crate::scene::{MaterialKind, ParameterRange};
use crate::shading::brdf::ggx_alpha;
use glam::Vec3;
use std::f32::consts::FRAC_PI_2;

/// The jet of a point light's falloff `E' = 1/d²` over the patch, for `1/d ≤ inv_d` and
/// `sin γ ≤ plane_sin` (`γ`: the angle between `l̂` and the patch's normal) at pattern scale `a`:
/// with `s = d²`, `Ds = 2l·Dl` and `D²s = 2|Dl|²` (`l` is affine), so `DE' = −2(l̂·Dl)/d³` and
/// `D²E' = (8(l̂·Dl)² − 2|Dl|²)/d⁴`; `Dl = −Xδ` lies in the plane, so `|l̂·Dl| ≤ sin γ·a`.
pub(super) fn attenuation_jet(inv_d: f32, plane_sin: f32, a: f32, gd: &Guard) -> Jet {
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
pub(super) fn irradiance_jet(frame: &Frame, st: &LightSetup, n: &Field, a: f32, gd: &Guard) -> Jet {
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
pub(super) fn along_plane(st: &LightSetup, nu: f32, c: f32) -> f32 {
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
pub(super) fn tilted(st: &LightSetup, nu: f32) -> f32 {
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
pub(super) struct LightJets {
    pub(super) diffuse: Jet,
    /// Per channel (GGX's Fresnel colours it).
    pub(super) specular: [Jet; 3],
    /// GGX where `n·v` changes sign, per channel: the sup of the specular part without its view
    /// half `V`, times `|V'|` at the kink (`docs/estimator.md` §4, "The view's kink"); else 0.
    pub(super) view_kink: Vec3,
}

impl LightJets {
    /// The jets at a scale `ρ` times this one's (`ρ ≤ 1`): values kept, first derivatives
    /// times `ρ`, second times `ρ²`.
    pub(super) fn scaled(&self, rho: f32) -> LightJets {
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
pub(super) fn normal_and_light_fields(
    frame: &Frame,
    st: &LightSetup,
    s: Scale,
    gd: &Guard,
) -> (Field, Field) {
    let n_w = gd.c(s.b / frame.r_n);
    let n = Field { w: n_w, radial: n_w.min(gd.c(s.g / frame.r_n)), x: 0.0, term: Term::Normal };
    let l_w = gd.mul(s.a, st.inv_d);
    let l = Field { w: l_w, radial: gd.mul(l_w, st.plane_sin), x: 0.0, term: Term::Light };
    (n, l)
}

/// The unit fields `v̂` and `ĥ = (l̂ + v̂)/|l̂ + v̂|` (specular lights only: `m_min > 0`).
pub(super) fn view_and_half_fields(
    frame: &Frame,
    st: &LightSetup,
    l: &Field,
    s: Scale,
    gd: &Guard,
) -> (Field, Field) {
    let v_w = gd.c(s.a / frame.e_min);
    let v = Field { w: v_w, radial: v_w, x: 0.0, term: Term::View };
    let h_w = gd.c((l.w + v.w) / st.m_min);
    let h =
        Field { w: h_w, radial: h_w, x: gd.c(K23 * (l.w * l.w + v.w * v.w) / st.m_min), term: Term::Half };
    (v, h)
}

/// The jets of one light at pattern scale `s`; `view_band` bounds `|n̂·v̂|` on the
/// sub-triangles at this scale that the view's kink crosses (used where it may).
pub(super) fn light_jets(
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
    if matches!(material, MaterialKind::Lambert { .. }) || st.area.is_some() || !st.specular {
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
