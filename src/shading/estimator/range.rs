//! The range class: a triangle whose shading provably varies by at most `ε` over it needs
//! level 1, and no estimate. The linear interpolant of values in `[m, M]` stays in `[m, M]`,
//! so its error is at most `M − m` wherever the shading itself stays there; [`range_class`]
//! bounds `M − m` from cosine cones of the normal, light and view directions and the lights'
//! distances, without trigonometry, for a small fraction of an estimate's cost.
//!
//! Every bound here holds for the shading of `brdf.glsl` at any point of the triangle, the
//! interpolated normal normalised: a direction field `w(λ) = Σ λₖ wₖ` (the normal, `L − x`,
//! `e − x`) stays within the [`Spread`] of its corners' directions, and a point light's
//! distance `|L − x(λ)|` lies between `min_k a·(L − xₖ)` (for the unit axis `a`) and
//! `max_k |L − xₖ|`. The diffuse part's range is its upper less its lower bound; a specular
//! part's is its upper bound (it is 0 where `n·l ≤ 0`). A polygonal light, or a GGX roughness
//! that varies over the triangle (a map), gives no bound: such triangles are estimated.
//!
//! GLSL twin: `glsl/include/estimator/range.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::cone::unit;
use super::constants::SPECULAR_CAP_SHARE;
use super::frame::{ball_angle, Frame};
use crate::exact_math::{est_cos, est_pow, est_sin};
use crate::scene::{Light, MaterialKind, ParameterRange};
use crate::shading::brdf::{GGX_MIN_ALPHA, MIN_LIGHT_DISTANCE_SQUARED};
use glam::Vec3;
use std::f32::consts::FRAC_PI_2;

/// Taken from every lower bound on a cosine and added to every upper bound: the f32 rounding
/// of the unit vectors and their dot products, with room to spare.
pub(super) const COS_PAD: f32 = 4.0e-6;
/// The relative rounding allowed for the shading (the renderer's and the bound's own).
pub(super) const RANGE_RELATIVE_PAD: f32 = 1.0e-4;

/// Every direction of a field is within the angle `acos(cos)` (below 90°) of `axis`; `sin` is
/// that angle's sine.
#[derive(Clone, Copy, Debug)]
pub(super) struct Spread {
    pub(super) axis: Vec3,
    pub(super) cos: f32,
    pub(super) sin: f32,
}

/// `√(1 − c²)`, 0 where rounding makes it negative.
fn sine_of(c: f32) -> f32 {
    (1.0 - c * c).max(0.0).sqrt()
}

impl Spread {
    pub(super) fn new(axis: Vec3, cos: f32) -> Spread {
        Spread { axis, cos, sin: sine_of(cos) }
    }
}

/// The spread of `Σ λₖ wₖ` over the simplex (`λ ≥ 0`): the unit corners' mean as axis, and the
/// least cosine to a corner, padded. For unit `a` and `y = Σ μₖ ŵₖ` (`|y| ≤ 1`),
/// `a·y/|y| ≥ a·y ≥ min_k a·ŵₖ`, which is the bound while it is positive. `None` where a
/// corner vanishes or the field may turn by 90° or more.
pub(super) fn spread_of(w: [Vec3; 3]) -> Option<Spread> {
    spread_of_units(w.map(unit))
}

/// [`spread_of`] the fields whose corners' directions are `u` (`unit` of each corner).
pub(super) fn spread_of_units(u: [Vec3; 3]) -> Option<Spread> {
    if u.contains(&Vec3::ZERO) {
        return None;
    }
    let axis = unit(u[0] + u[1] + u[2]);
    if axis == Vec3::ZERO {
        return None;
    }
    let cos = axis.dot(u[0]).min(axis.dot(u[1])).min(axis.dot(u[2])) - COS_PAD;
    if !(cos > 0.0) {
        return None;
    }
    Some(Spread::new(axis, cos))
}

/// The spread `s` of the directions from the triangle (corners `positions`) to `eye`, widened
/// to hold for every eye within `radius` of it (`s` itself where `radius` is 0): by the
/// [`ball_angle`] at a lower bound on the distance (the nearest corner's less the longest edge,
/// as every point is within it of a corner). `None` where the spread reaches 90°.
fn widened(s: Spread, positions: [Vec3; 3], (eye, radius): (Vec3, f32)) -> Option<Spread> {
    if !(radius > 0.0) {
        return Some(s);
    }
    let [p0, p1, p2] = positions;
    let nearest = (eye - p0).length().min((eye - p1).length()).min((eye - p2).length());
    let longest = (p1 - p0).length().max((p2 - p1).length()).max((p0 - p2).length());
    let turn = ball_angle(radius, nearest - longest);
    if !(turn < FRAC_PI_2) {
        return None;
    }
    let cos = s.cos * est_cos(turn) - s.sin * est_sin(turn);
    if !(cos > 0.0) {
        return None;
    }
    Some(Spread::new(s.axis, cos))
}

/// Lower and upper bounds on `x̂·ŷ` for `x̂` within spread `a` and `ŷ` within `b`: the angle
/// between them lies within `γ = ∠a + ∠b` of the axes' angle `t₀` (both below 90°, so `γ < π`).
pub(super) fn cosine_bounds(a: Spread, b: Spread) -> (f32, f32) {
    let ct = a.axis.dot(b.axis).clamp(-1.0, 1.0);
    let st = sine_of(ct);
    let (sa, sb) = (a.sin, b.sin);
    let cg = a.cos * b.cos - sa * sb;
    let sg = sa * b.cos + a.cos * sb;
    let hi = if ct >= cg { 1.0 } else { ct * cg + st * sg + COS_PAD };
    let lo = if ct <= -cg { -1.0 } else { ct * cg - st * sg - COS_PAD };
    (lo, hi)
}

/// The spread of the half vector `ĥ = (l̂ + v̂)/|l̂ + v̂|`, and a lower bound on `v̂·ĥ = |l̂ + v̂|/2`:
/// `|l̂ − a_l| ≤ √(2 − 2 cos_l)` (a chord), likewise for `v̂`, so `l̂ + v̂` is within the sum `δ`
/// of `w₀ = a_l + a_v`, and its angle from `w₀` has a sine of at most `δ/|w₀|`. `None` where
/// `δ ≥ |w₀|` (the half vector may vanish).
pub(super) fn half_spread(l: Spread, v: Spread) -> Option<(Spread, f32)> {
    let w0 = l.axis + v.axis;
    let length = w0.length();
    let chord = (2.0 - 2.0 * l.cos).max(0.0).sqrt() + (2.0 - 2.0 * v.cos).max(0.0).sqrt();
    if !(chord < length) {
        return None;
    }
    let sine = chord / length;
    let cos = (1.0 - sine * sine).sqrt() - COS_PAD;
    let axis = unit(w0);
    if !(cos > 0.0) || axis == Vec3::ZERO {
        return None;
    }
    Some((Spread::new(axis, cos), 0.5 * (length - chord)))
}

/// One light's direction spread over the triangle, and the least and largest irradiance
/// scale (`1/d²` bounds; 1 for a directional light). `None`: no bound (a point light at or
/// near the triangle, or a polygonal light).
fn light_spread(light: &Light, positions: [Vec3; 3]) -> Option<(Spread, f32, f32, Vec3)> {
    match *light {
        Light::Point { position, color, intensity } => {
            let to_light = positions.map(|p| position - p);
            let spread = spread_of(to_light)?;
            let near = spread
                .axis
                .dot(to_light[0])
                .min(spread.axis.dot(to_light[1]))
                .min(spread.axis.dot(to_light[2]));
            let far2 = to_light[0]
                .length_squared()
                .max(to_light[1].length_squared())
                .max(to_light[2].length_squared())
                * (1.0 + RANGE_RELATIVE_PAD);
            let near2 = near * near * (1.0 - RANGE_RELATIVE_PAD);
            if !(near > 0.0 && near2 >= MIN_LIGHT_DISTANCE_SQUARED && far2 <= f32::MAX) {
                return None;
            }
            Some((spread, 1.0 / far2, 1.0 / near2, color * intensity))
        }
        Light::Directional { direction, color, intensity } => {
            let axis = unit(-direction);
            if axis == Vec3::ZERO {
                return None;
            }
            Some((Spread::new(axis, 1.0 - COS_PAD), 1.0, 1.0, color * intensity))
        }
        Light::Polygon(_) => None,
    }
}

/// The upper bound, per colour channel, of one light's specular part over the triangle, given
/// the spreads of the normal, light and view and the upper bound on `n·l`.
fn specular_sup(
    material: &MaterialKind,
    parameter: ParameterRange,
    n: Spread,
    l: Spread,
    v: Option<Spread>,
    nl_hi: f32,
) -> Option<Vec3> {
    if let MaterialKind::Lambert { .. } = material {
        return Some(Vec3::ZERO);
    }
    let v = v?;
    let (h, vh_lo) = half_spread(l, v)?;
    let nh_hi = cosine_bounds(n, h).1.clamp(0.0, 1.0);
    match *material {
        MaterialKind::Lambert { .. } => Some(Vec3::ZERO),
        MaterialKind::BlinnPhong { ks, .. } => Some(ks * est_pow(nh_hi, parameter.lo)),
        MaterialKind::Ggx { f0, .. } => {
            if parameter.lo != parameter.hi {
                return None;
            }
            let alpha = (parameter.lo * parameter.lo).max(GGX_MIN_ALPHA);
            let a2 = alpha * alpha;
            let sin2 = (1.0 - nh_hi * nh_hi).max(0.0);
            let d = sin2 * (1.0 - a2) + a2;
            let distribution = a2 / (std::f32::consts::PI * d * d);
            let m = 1.0 - vh_lo.clamp(0.0, 1.0);
            let m2 = m * m;
            let fresnel = f0 + (Vec3::ONE - f0) * (m2 * m2 * m);
            let k = 0.5 * alpha;
            let nv_lo = cosine_bounds(n, v).0.max(0.0);
            let nl = nl_hi.clamp(0.0, 1.0);
            let visibility = nl / ((nl * (1.0 - k) + k) * (nv_lo * (1.0 - k) + k));
            Some(fresnel * (distribution * visibility * 0.25))
        }
    }
}

/// What the specular caps need of a triangle whose every light is capped
/// ([`RangeClass::every_specular_capped`]; `add_light`): the spreads of its normal and of its
/// view.
#[derive(Clone, Copy, Debug)]
pub(super) struct SpecularCaps {
    n: Spread,
    v: Spread,
}

/// A light's specular part's upper bound over the triangle, `radiance·sup(specular)·sup(E')`
/// (`specular_most`: the last two), padded for rounding: its cap.
fn padded_cap(radiance: Vec3, specular_most: Vec3) -> Vec3 {
    radiance * specular_most * (1.0 + RANGE_RELATIVE_PAD)
}

impl SpecularCaps {
    /// The triangle's spreads from its frame's unit normals and unit vectors to the eye; `None`
    /// for a material without a specular part, or where a spread is not below 90°.
    pub(super) fn new(frame: &Frame, material: &MaterialKind) -> Option<SpecularCaps> {
        if !material.is_specular() {
            return None;
        }
        let n = spread_of_units(frame.unit_normals)?;
        let v = widened(spread_of_units(frame.v_units)?, frame.vertices, (frame.eye, frame.eye_radius))?;
        Some(SpecularCaps { n, v })
    }

    /// The cap of `light`'s specular part over the triangle ([`padded_cap`]): the part's values
    /// and its interpolant's lie in `[0, cap]`, so `cap` bounds its error at every level.
    /// [`range_class`] computes the same from the same quantities and decides whether every
    /// light's cap is within its share of `ε`. `None` where the range class gives no bound.
    pub(super) fn cap(
        &self,
        material: &MaterialKind,
        parameter: ParameterRange,
        light: &Light,
        positions: [Vec3; 3],
    ) -> Option<Vec3> {
        let (l, _, most, radiance) = light_spread(light, positions)?;
        let nl_hi = cosine_bounds(self.n, l).1;
        if !(nl_hi > 0.0) {
            // The specular part is 0 where n·l ≤ 0.
            return Some(Vec3::ZERO);
        }
        let specular = specular_sup(material, parameter, self.n, l, Some(self.v), nl_hi)?;
        Some(padded_cap(radiance, specular * most))
    }
}

/// What the range class finds of a triangle ([`range_class`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct RangeClass {
    /// An upper bound, per colour channel, on `M − m` of the shading over the triangle, or
    /// `None` where this class gives none. See the module docs. The lights' parts are summed in
    /// order and the sum returned as soon as it cannot prove level 1 for `ε` ([`within`]) and
    /// a light's specular part is not capped: the lights after it only add to it (every part is
    /// `≥ 0`), so such a result is below the bound but decides [`range_proves`] as the whole
    /// bound would.
    pub(super) bound: Option<Vec3>,
    /// Whether the estimate bounds every light's specular part by its cap: a specular
    /// material, and for each light the part's upper bound within `ε·SPECULAR_CAP_SHARE / (number
    /// of lights)` ([`SpecularCaps::cap`], from the same quantities). A triangle's lights are
    /// capped all together or not at all, so that a GPU lists such triangles apart and runs an
    /// estimator without specular code on them.
    pub(super) every_specular_capped: bool,
}

/// The range class of a triangle for `ε` ([`RangeClass`]), for every eye within `eye.1` of
/// `eye.0`.
pub(super) fn range_class(
    positions: [Vec3; 3],
    normals: [Vec3; 3],
    eye: (Vec3, f32),
    material: &MaterialKind,
    parameter: ParameterRange,
    lights: &[Light],
    eps: f32,
) -> RangeClass {
    let none = RangeClass { bound: None, every_specular_capped: false };
    let Some(n) = spread_of(normals) else {
        return none;
    };
    // The view's spread matters to the specular parts only.
    let v = if material.is_specular() {
        spread_of(positions.map(|p| eye.0 - p)).and_then(|s| widened(s, positions, eye))
    } else {
        None
    };
    let kd = match *material {
        MaterialKind::Lambert { kd } | MaterialKind::BlinnPhong { kd, .. } => kd,
        MaterialKind::Ggx { albedo, .. } => albedo,
    };
    let mut capped = material.is_specular() && v.is_some();
    let (budget, count) = (eps * SPECULAR_CAP_SHARE, lights.len() as f32);
    let mut total = Vec3::ZERO;
    // The order of the GPU's light buffer: point lights, then directional ones.
    let points = lights.iter().filter(|l| matches!(l, Light::Point { .. }));
    let directionals = lights.iter().filter(|l| matches!(l, Light::Directional { .. }));
    let polygons = lights.iter().filter(|l| matches!(l, Light::Polygon(_)));
    for light in points.chain(directionals).chain(polygons) {
        let Some((l, least, most, radiance)) = light_spread(light, positions) else {
            return none;
        };
        let (nl_lo, nl_hi) = cosine_bounds(n, l);
        if !(nl_hi > 0.0) {
            continue;
        }
        let diffuse = kd * (most * nl_hi - least * nl_lo.max(0.0));
        let Some(specular) = specular_sup(material, parameter, n, l, v, nl_hi) else {
            return none;
        };
        let specular = specular * most;
        total += radiance * (diffuse + specular);
        capped = capped && padded_cap(radiance, specular).max_element() * count <= budget;
        if !within(total, eps) && !capped {
            return RangeClass { bound: Some(total), every_specular_capped: false };
        }
    }
    RangeClass { bound: Some(total), every_specular_capped: capped }
}

/// Whether every channel of `range`, padded for rounding, is at most `eps` (never for NaN or a
/// bound that overflowed).
pub(super) fn within(range: Vec3, eps: f32) -> bool {
    let fits = |c: f32| c * (1.0 + RANGE_RELATIVE_PAD) + 1.0e-6 <= eps;
    fits(range.x) && fits(range.y) && fits(range.z)
}

/// Whether [`RangeClass::bound`] proves level 1 for `ε`: a bound [`within`] it.
pub(super) fn range_proves(bound: Option<Vec3>, eps: f32) -> bool {
    bound.is_some_and(|range| within(range, eps))
}

/// Whether the range class settles the triangle (level 1 without an estimate) for every eye
/// within `eye_radius` of `tri.eye`, as [`estimate_textured`](super::estimate_textured) decides it.
pub fn settled_by_range(
    tri: &super::terms::TriangleInput,
    material: &MaterialKind,
    parameter: ParameterRange,
    lights: &[Light],
    (epsilon, eye_radius): (f32, f32),
) -> bool {
    let eps = if epsilon > 0.0 { epsilon } else { 0.0 };
    let eye = (tri.eye, eye_radius);
    range_proves(range_class(tri.positions, tri.normals, eye, material, parameter, lights, eps).bound, eps)
}
