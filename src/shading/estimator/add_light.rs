//! One light's bounds added to the [`Sums`]: [`add_light`] and its steps, and the refining
//! step's values over the patch's children ([`values_over_children`]).
//!
//! GLSL twin: `glsl/include/estimator/add_light.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).
//!
//! [`Sums`]: super::light_setup::Sums

use super::cone::unit;
use super::constants::{Sign, CORNER_VALUE_MARGIN, REFINE_CHILDREN, REFINE_SHARE, SAFETY, TERMINATOR_KINK};
use super::decide::level_for;
use super::frame::Frame;
use super::irradiance::light_jets;
use super::jet::{Guard, Jet};
use super::light_setup::{plan_light, plan_parts, LightSetup, Sums, GRID_LEVELS};
use super::lobe::{parameter_variation, polygon_specular_bound};
use super::patch_levels::pattern_level;
use super::range::SpecularCaps;
use super::settings::{Discontinuity, Split};
use super::terminator::{lobe_band_share, view_band, TerminatorBand};
use super::terms::{Reason, TriangleInput, TERM_COUNT};
use crate::exact_math::est_pow;
use crate::scene::{Light, MaterialKind, ParameterRange};
use crate::shading::brdf::MIN_LIGHT_DISTANCE_SQUARED;
use glam::Vec3;

/// Adds one light's bounds to `sum`: its diffuse and specular parts bounded apart
/// ([`light_bounds`]), their ranges narrowed over the patch's children where `refine`
/// ([`values_over_children`]), the n-independent parts and the light's own lower bound on the
/// level, then the parts at the grid levels ([`LightBounds::add_grid`]) and at the solver's
/// ([`LightBounds::add_to_sums`]). Where `caps` bounds the specular part by a small constant
/// ([`SpecularCaps::cap`]), that bounds it, without its setup and jets. `Err`: the reason for
/// fallback.
#[allow(clippy::too_many_arguments)]
pub(super) fn add_light(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    light: &Light,
    mode: Discontinuity,
    split: Split,
    n_max: u32,
    eps: f32,
    refine: bool,
    caps: Option<&SpecularCaps>,
    sum: &mut Sums,
    gd: &Guard,
) -> Result<(), Reason> {
    let cap = caps.and_then(|caps| caps.cap(material, parameter, light, frame.vertices));
    let planned =
        plan_parts(frame, material, parameter, light, mode, material.is_specular() && cap.is_none());
    let Some((setup, diff_w, spec_w)) = planned? else {
        return Ok(());
    };
    let mut bounds = light_bounds(frame, material, parameter, &setup, diff_w, spec_w, split, gd);
    if let Some(cap) = cap {
        bounds.range[SPECULAR] = cap;
        bounds.specular_capped = true;
    }
    // A triangle that needs a high level: the parts' values over the children, where this
    // light's range is not small. Every child is a part of the patch, so the largest of their
    // sups and the smallest of their infs bound the parts over the patch (and so over every
    // sub-triangle of every pattern), often far below the patch's own: the factors' sups
    // (falloff, lobe, Smith, Fresnel) are taken at different points of the patch, and on a
    // child those points are close together.
    let significant =
        bounds.range[DIFFUSE].max_element().max(bounds.range[SPECULAR].max_element()) > REFINE_SHARE * eps;
    if refine && setup.area.is_none() && significant {
        if let Some(children) = values_over_children(frame, material, parameter, light, mode) {
            let diff_sup = bounds.later_diffuse_sup.min(children.diffuse_sup);
            let diff_inf = bounds.later_diffuse_inf.max(children.diffuse_inf);
            bounds.range[DIFFUSE] = diff_w * ((diff_sup - diff_inf).max(0.0) * SAFETY);
            if !bounds.specular_capped {
                bounds.spec_sup = bounds.spec_sup.min(children.specular_sup);
                bounds.range[SPECULAR] = spec_w * bounds.spec_sup * SAFETY;
            }
        }
    }
    // The n-independent parts of the specular part: a textured parameter's variation
    // sup|f(α) − f(α')| over the range (Eq. 37), or a polygon's sampled specular part, bounded
    // by its range (which also covers a textured parameter). A capped part has neither: its
    // cap bounds its values for every parameter.
    let other = match light {
        Light::Polygon(polygon) => {
            let bound = polygon_specular_bound(material, parameter, &setup, polygon, gd) * SAFETY;
            bounds.range[SPECULAR] += bound;
            bound
        }
        _ if bounds.specular_capped => Vec3::ZERO,
        _ => spec_w * parameter_variation(material, parameter, &setup, bounds.spec_sup),
    };
    let top = pattern_level(n_max, n_max);
    if !refine {
        let narrowed = setup.area.is_none() && significant;
        sum.floor +=
            light_floor(frame, material, parameter, light, &setup, &bounds, spec_w, other, top, narrowed);
    }
    // Relaxed: the specular lobe that n·l > 0 switches on jumps on the sub-triangles the
    // terminator crosses, by at most its sup over the band 0 < n·l ≤ band/L.
    let jump = |beta: f32| {
        if setup.straddle && setup.area.is_none() && setup.specular {
            spec_w * bounds.spec_sup * (lobe_band_share(material, parameter, &setup, beta) * SAFETY)
        } else {
            Vec3::ZERO
        }
    };
    let zero1 = jump(bounds.band1) + other;
    let zero_top = jump(bounds.bandn / top) + other;
    // Per part and channel: the smaller of the part's interpolation bound and its range. The
    // range wins for good if it is below the bound even at n_max (dim or spiky lights, a
    // faint specular lobe on a diffuse surface): at every level up to n_max it is then the
    // better bound. (The error of the sum is at most the sum of the parts' errors.)
    let at_top = [
        bounds.tot[DIFFUSE][1] / (top * top) + bounds.linn[DIFFUSE] / top,
        bounds.tot[SPECULAR][1] / (top * top) + bounds.linn[SPECULAR] / top + zero_top,
    ];
    let interpolated = [0, 1].map(|part| {
        let capped = part == SPECULAR && bounds.specular_capped;
        [0, 1, 2].map(|c| !capped && !(bounds.range[part][c] <= at_top[part][c]))
    });
    // The jump at levels ≥ 2 is taken at a lower bound of the final level: the level this
    // light alone needs with the jump at its infimum (the band's width 0). Every level the
    // solver returns is at least that (it adds the other lights' non-negative bounds), and
    // the band only narrows as the level grows.
    let zero_inf = jump(0.0) + other;
    // Relaxed: the same with the diffuse kink at its floor (`TerminatorBand::floor`, the band's limit
    // as the level grows), which only lowers it; at every level the solver returns (`≥ low`) the
    // band's fixed point holds from `low` on.
    let floor_kink = if setup.straddle {
        diff_w * (TERMINATOR_KINK * SAFETY * gd.mul(bounds.att, bounds.terminator.floor(gd)))
    } else {
        Vec3::ZERO
    };
    let mut low = 1.0f32;
    for c in 0..3 {
        let (d, sp) = (interpolated[DIFFUSE][c], interpolated[SPECULAR][c]);
        if d || sp {
            let a = if d { bounds.tot[DIFFUSE][1][c] } else { 0.0 }
                + if sp { bounds.tot[SPECULAR][1][c] } else { 0.0 };
            let b = if d { floor_kink[c] } else { 0.0 } + if sp { bounds.linn[SPECULAR][c] } else { 0.0 };
            let z = if sp { zero_inf[c] } else { 0.0 };
            low = low.max(level_for(a, b, z, eps));
        }
    }
    sum.low = sum.low.max(low);
    let mut bandn = bounds.bandn;
    if setup.straddle {
        bandn = bandn.min(bounds.terminator.guarded(low, gd));
        bounds.linn[DIFFUSE] = diff_w * (TERMINATOR_KINK * SAFETY * gd.mul(bounds.att, bandn));
    }
    let zeron = jump(bandn / low) + other;
    let whole_lobe = if setup.straddle && setup.area.is_none() && setup.specular {
        spec_w * bounds.spec_sup * SAFETY
    } else {
        Vec3::ZERO
    };
    bounds.add_grid(sum, n_max, low, zeron, whole_lobe, other);
    bounds.add_to_sums(sum, interpolated, zero1, zeron);
    Ok(())
}

/// One light's bounds, for its diffuse and its specular part apart (indices [`DIFFUSE`] and
/// [`SPECULAR`]), per channel.
pub(super) struct LightBounds {
    /// Second order per term, at level 1 and at levels ≥ 2: `h[part][level][term]`...
    h: [[[Vec3; TERM_COUNT]; 2]; 2],
    /// ...and as one number ([`Jet::t`]): `tot[part][level]`.
    tot: [[Vec3; 2]; 2],
    /// Relaxed: the first-order parts of the kinks (÷ L), at level 1 and at levels ≥ 2.
    lin1: [Vec3; 2],
    linn: [Vec3; 2],
    /// The range of each part's contribution.
    range: [Vec3; 2],
    /// The specular part's sup per unit weight.
    spec_sup: Vec3,
    /// The shaded diffuse part's sup and inf per unit weight ([`diffuse_values`]).
    later_diffuse_sup: f32,
    later_diffuse_inf: f32,
    /// `sup E'` (1 for a directional light).
    att: f32,
    /// Relaxed: the terminator's band at the diameters of levels ≥ 2...
    terminator: TerminatorBand,
    /// ...how far `n·l` can be from 0 on a sub-triangle it crosses at level 1, and per `1/L` at
    /// levels `L ≥ 2`.
    band1: f32,
    bandn: f32,
    /// The weight of the diffuse part.
    diff_w: Vec3,
    /// Whether `n·l` may change sign inside the triangle.
    straddle: bool,
    /// Whether the specular part is bounded by its cap (`range[SPECULAR]`) at every level.
    specular_capped: bool,
}

/// This light's bounds ([`LightBounds`]): second order per term at level 1 and at levels ≥ 2,
/// the Relaxed first-order parts, and the range of each part's contribution.
#[allow(clippy::too_many_arguments)]
fn light_bounds(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    setup: &LightSetup,
    diff_w: Vec3,
    spec_w: Vec3,
    split: Split,
    gd: &Guard,
) -> LightBounds {
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
    let terminator = TerminatorBand::new(frame, setup, frame.dn);
    let (band1, bandn) = if setup.straddle {
        (gd.c(TerminatorBand::new(frame, setup, frame.d1).at(1.0)), terminator.guarded(0.0, gd))
    } else {
        (0.0, 0.0)
    };
    // Relaxed, GGX: the same for n·v where it may change sign (its kink in V).
    let view_kink = matches!(material, MaterialKind::Ggx { .. })
        && setup.area.is_none()
        && setup.specular
        && setup.nv_sign == Sign::Both;
    let (view1, viewn) =
        if view_kink { (view_band(frame, frame.d1, gd), view_band(frame, frame.dn, gd)) } else { (0.0, 0.0) };
    // The kink's band on a sub-triangle: at most the patch's, and `viewn/L ≤ viewn` at the
    // effective levels `L ≥ 1` the solver may return.
    let later = light_jets(frame, material, parameter, setup, frame.sn, view1.min(viewn), gd);
    // Every jet is non-decreasing in each attribute's scale and homogeneous in them (first
    // derivatives of degree 1, second of degree 2), and `s₁ ≤ ρ·sₙ`: so the level-1 jets are
    // those at levels ≥ 2 times `ρ` and `ρ²` (docs/estimator.md §2), unless the Uniform split
    // needs each term at level 1 as the GPU computes it, or GGX's view kink takes another band.
    let first = if split == Split::Heuristic && !view_kink {
        later.scaled(frame.rho)
    } else {
        light_jets(frame, material, parameter, setup, frame.s1, view1, gd)
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
        let (diff_sup, diff_inf) = diffuse_values(setup, &diff);
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
    LightBounds {
        h,
        tot,
        lin1,
        linn,
        range,
        spec_sup,
        later_diffuse_sup,
        later_diffuse_inf,
        att,
        terminator,
        band1,
        bandn,
        diff_w,
        straddle: setup.straddle,
        specular_capped: false,
    }
}

impl LightBounds {
    /// Adds the bound at each uniform level of [`GRID_LEVELS`] up to `n_max`: per part and
    /// channel the smaller of its interpolation bound there and its range. `low`: the light's
    /// lower bound on the level; `zeron`: the n-independent specular parts from `low` on,
    /// `whole_lobe + other` below it.
    fn add_grid(&self, sum: &mut Sums, n_max: u32, low: f32, zeron: Vec3, whole_lobe: Vec3, other: Vec3) {
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
            let kink_l = if self.straddle {
                self.diff_w * (TERMINATOR_KINK * SAFETY * (self.att * self.terminator.at(l)))
            } else {
                Vec3::ZERO
            };
            for c in 0..3 {
                let d = (self.tot[DIFFUSE][1][c] / (l * l) + kink_l[c]).min(self.range[DIFFUSE][c]);
                let sp = if self.specular_capped {
                    self.range[SPECULAR][c]
                } else {
                    (self.tot[SPECULAR][1][c] / (l * l) + self.linn[SPECULAR][c] / l + zero_l[c])
                        .min(self.range[SPECULAR][c])
                };
                sum.grid[k][c] += d + sp;
            }
        }
    }

    /// Adds the level-1 bound, and the parts the solver takes at its levels: the interpolated
    /// parts' bounds per term (`zero1`, `zeron`: the specular n-independent parts at level 1
    /// and from the light's lower bound on), the others' ranges.
    fn add_to_sums(&self, sum: &mut Sums, interpolated: [[bool; 3]; 2], zero1: Vec3, zeron: Vec3) {
        for c in 0..3 {
            let one_d = (self.tot[DIFFUSE][0][c] + self.lin1[DIFFUSE][c]).min(self.range[DIFFUSE][c]);
            let one_s = if self.specular_capped {
                self.range[SPECULAR][c]
            } else {
                (self.tot[SPECULAR][0][c] + self.lin1[SPECULAR][c] + zero1[c]).min(self.range[SPECULAR][c])
            };
            sum.one[c] += one_d + one_s;
            for part in [DIFFUSE, SPECULAR] {
                if !interpolated[part][c] {
                    sum.range[c] += self.range[part][c];
                    continue;
                }
                for t in 0..TERM_COUNT {
                    sum.h1[t][c] += self.h[part][0][t][c];
                    sum.hn[t][c] += self.h[part][1][t][c];
                }
                sum.tn[c] += self.tot[part][1][c];
                sum.lin1[c] += self.lin1[part][c];
                sum.linn[c] += self.linn[part][c];
                if part == SPECULAR {
                    sum.jumps1[c] += zero1[c];
                    sum.jumps[c] += zeron[c];
                }
            }
        }
    }
}

/// One light's share of the refining floor ([`Sums::floor`]): per channel a lower bound on what
/// it adds to the bound at every level up to `top` (the level-1 bound, the grid's, the solver's)
/// in the estimate refined over the children. There each part adds the smaller of its range and
/// its interpolation bound, whose second-order part (`tot`) and, but for GGX, n-independent part
/// (`other`) refining leaves as they are; where it narrows the light's ranges (`narrowed`), the
/// children's values still hold the light's values at the corners ([`corner_values`]), and so
/// does the narrowed range. `docs/estimator.md` section 3, "Where refining cannot help".
#[allow(clippy::too_many_arguments)]
pub(super) fn light_floor(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    light: &Light,
    setup: &LightSetup,
    bounds: &LightBounds,
    spec_w: Vec3,
    other: Vec3,
    top: f32,
    narrowed: bool,
) -> Vec3 {
    let (mut range_d, mut range_s, mut other) = (bounds.range[DIFFUSE], bounds.range[SPECULAR], other);
    if narrowed {
        let corners = corner_values(frame, material, parameter, light, !bounds.specular_capped);
        let spread = (corners.diffuse_max * (1.0 - CORNER_VALUE_MARGIN)
            - corners.diffuse_min * (1.0 + CORNER_VALUE_MARGIN))
            .max(0.0);
        range_d = range_d.min(bounds.diff_w * (spread * SAFETY));
        if !bounds.specular_capped {
            let spec_sup = bounds.spec_sup.min(Vec3::splat(corners.specular * (1.0 - CORNER_VALUE_MARGIN)));
            range_s = range_s.min(spec_w * spec_sup * SAFETY);
            other = spec_w * parameter_variation(material, parameter, setup, spec_sup);
        }
    }
    let second_order = |part: usize| bounds.tot[part][0].min(bounds.tot[part][1] / (top * top));
    let part_s = if bounds.specular_capped { range_s } else { range_s.min(second_order(SPECULAR) + other) };
    range_d.min(second_order(DIFFUSE)) + part_s
}

/// A point or directional light's parts per unit weight at the triangle's corners: the
/// diffuse part's largest and smallest, and the specular part at the corner nearest the lobe's
/// peak (the largest `n̂·ĥ`; one power instead of three, and at most the largest), Blinn-Phong's
/// at the lowest shininess of the range (0 for GGX, which takes no specular value here, and
/// Lambert, and where not asked for).
pub(super) struct CornerValues {
    pub(super) diffuse_max: f32,
    pub(super) diffuse_min: f32,
    pub(super) specular: f32,
}

/// [`CornerValues`] of `light` on the triangle in `frame`, shaded as the evaluation stage
/// shades a corner (`reflect_split`, `light_at`), the specular part only where `specular`; all
/// 0 for a polygonal light.
pub(super) fn corner_values(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    light: &Light,
    specular: bool,
) -> CornerValues {
    let mut values = CornerValues { diffuse_max: 0.0, diffuse_min: f32::MAX, specular: 0.0 };
    let specular = specular && matches!(material, MaterialKind::BlinnPhong { .. });
    // The largest n̂·ĥ of a corner the light is in front of, and its falloff.
    let (mut peak, mut peak_falloff) = (-1.0f32, 0.0f32);
    for i in 0..3 {
        let x = frame.vertices[i];
        let (l, falloff) = match *light {
            Light::Point { position, .. } => {
                let to_light = position - x;
                let d2 = to_light.dot(to_light).max(MIN_LIGHT_DISTANCE_SQUARED);
                (to_light * (1.0 / d2.sqrt()), 1.0 / d2)
            }
            Light::Directional { direction, .. } => (unit(-direction), 1.0),
            Light::Polygon(_) => return CornerValues { diffuse_max: 0.0, diffuse_min: 0.0, specular: 0.0 },
        };
        let n = frame.unit_normals[i];
        let n_dot_l = n.dot(l);
        let diffuse = falloff * n_dot_l.max(0.0);
        values.diffuse_max = values.diffuse_max.max(diffuse);
        values.diffuse_min = values.diffuse_min.min(diffuse);
        if specular && n_dot_l > 0.0 {
            let n_dot_h = n.dot(unit(l + frame.v_units[i])).max(0.0);
            if n_dot_h > peak {
                (peak, peak_falloff) = (n_dot_h, falloff);
            }
        }
    }
    if specular && peak >= 0.0 {
        values.specular = peak_falloff * est_pow(peak, parameter.lo);
    }
    values
}

/// The shaded diffuse part `max(E'·c, 0)` per unit weight lies in `[inf, sup]`: at least
/// `inf E'·cos ψ_max` where it does not change sign, and at most `sup E'·max(cos ψ_min, 0)`
/// (below the jet's `m`, `sup E'·max|cos ψ|`, where the light may be behind the surface).
pub(super) fn diffuse_values(setup: &LightSetup, diffuse: &Jet) -> (f32, f32) {
    let att = if setup.inv_d > 0.0 { setup.inv_d * setup.inv_d } else { 1.0 };
    let inf = setup.att_inf * setup.nl_cos.1.max(0.0) * (1.0 - 1.0e-5);
    let sup = if setup.area.is_none() { diffuse.m.min(att * setup.nl_cos.0.max(0.0)) } else { diffuse.m };
    (sup, inf)
}

/// The values of a light's two parts (per unit weight) over a set of sub-triangles.
pub(super) struct ChildValues {
    pub(super) diffuse_sup: f32,
    pub(super) diffuse_inf: f32,
    pub(super) specular_sup: Vec3,
}

/// Child `k` (`0..4`) of the midpoint subdivision of the triangle with corners `c` (positions
/// or normals, each affine over the patch as the interpolated attributes are).
pub(super) fn midpoint_child(c: [Vec3; 3], k: usize) -> [Vec3; 3] {
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
pub(super) fn values_over_children(
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
        let tri = TriangleInput { positions, normals, eye: frame.eye };
        let child = Frame::new(&tri, frame.eye_radius, material.is_specular());
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
pub(super) const DIFFUSE: usize = 0;
/// ...and of the specular part.
pub(super) const SPECULAR: usize = 1;
