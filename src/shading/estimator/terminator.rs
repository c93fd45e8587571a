//! Relaxed discontinuity bounds: the band of `n̂·l̂` on the sub-triangles the terminator crosses
//! ([`TerminatorBand`]), the same for the view's kink ([`view_band`]), and the share of the
//! specular lobe on the band ([`lobe_band_share`]).
//!
//! GLSL twin: `glsl/include/estimator/terminator.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::constants::ANGLE_PAD;
use super::frame::Frame;
use super::jet::Guard;
use super::light_setup::LightSetup;
use super::pattern::Scale;
use crate::exact_math::{est_acos, est_cos, est_pow};
use crate::scene::{MaterialKind, ParameterRange};
use crate::shading::brdf::ggx_alpha;

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
pub(super) struct TerminatorBand {
    /// `b_N·L = d_b/min|N|`.
    pub(super) normal: f32,
    /// `b_X·L = d_a/d_min`.
    pub(super) light: f32,
    /// `ν`, the normals' sine to the plane normal.
    pub(super) nu: f32,
    /// `σ`, the light's.
    pub(super) sigma: f32,
    /// `c_max = max|cos|` over the angle range.
    pub(super) c_max: f32,
    /// `(b_N + ν b_X)·L`, the fixed point's numerator.
    pub(super) fixed: f32,
    /// `σ b_X·L`, subtracted from `L` in the fixed point's denominator.
    pub(super) held: f32,
    /// `cos ψ_min − cos ψ_max`, the oscillation of `n̂·l̂` over the whole triangle.
    pub(super) oscillation: f32,
}

impl TerminatorBand {
    pub(super) fn new(frame: &Frame, st: &LightSetup, d: Scale) -> TerminatorBand {
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
    pub(super) fn per_level(&self, above: f32) -> f32 {
        let mut c_star = self.c_max;
        let room = above - self.held;
        if room > 0.0 {
            c_star = c_star.min(self.fixed / room);
        }
        let across = (self.nu + self.sigma * c_star).min(1.0);
        self.normal + self.light * across
    }

    /// [`TerminatorBand::per_level`] with the guard.
    pub(super) fn guarded(&self, above: f32, gd: &Guard) -> f32 {
        gd.c(self.per_level(above))
    }

    /// The band at one effective level `l`, and at most the oscillation of `n̂·l̂` over the
    /// whole triangle, which does not fall with the level (unguarded: at most
    /// `guarded(0)/l`).
    pub(super) fn at(&self, l: f32) -> f32 {
        (self.per_level(l) / l).min(self.oscillation)
    }

    /// The band's floor as the level grows (`c* → 0`): `b_N + ν·b_X` per `1/L`.
    pub(super) fn floor(&self, gd: &Guard) -> f32 {
        gd.c(self.normal + self.light * self.nu.min(1.0))
    }
}

/// Relaxed, GGX: the same for the view's kink, `|n̂·v̂|` on a sub-triangle of diameters `d`
/// that `n·v = 0` crosses: `|D(n̂·v̂)| ≤ |Nδ|/min|N| + |Xδ|/e_min`.
pub(super) fn view_band(frame: &Frame, d: Scale, gd: &Guard) -> f32 {
    gd.c(d.b / frame.r_n + d.a / frame.e_min)
}

/// Relaxed: the factor `≤ 1` by which the specular lobe's sup over the band `0 < n̂·l̂ ≤ β`
/// is below its sup over the triangle (the latter is what the jets' `m` bound).
/// - Blinn-Phong, `(n·h)^s`: ĥ bisects l̂ and v̂, so `∠(n, h) ≥ ∠(n, l) − ∠(l, v)/2`, and
///   `∠(n, l) ≥ acos β` on the band: `(n·h)^s ≤ cos^s(max(ψ_nh,min, acos β − ψ_lv,max/2))`.
/// - GGX: the specular part carries `G(c) = c/(c(1−k)+k)`, increasing in `c` and decreasing
///   in `k`: on the band it is at most `G(β)` at the smallest `k`, against `G(c_max)` in the
///   jets.
pub(super) fn lobe_band_share(
    material: &MaterialKind,
    parameter: ParameterRange,
    st: &LightSetup,
    beta: f32,
) -> f32 {
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
