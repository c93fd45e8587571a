//! What one light looks like from the triangle before any jet: its geometry and angle ranges
//! ([`LightSetup`], [`plan_light`]), a polygonal light's ([`AreaGeometry`]), the cosine ranges
//! ([`cosine_range`]), the colour weights of the two parts, and the sums the lights' bounds
//! go into ([`Sums`], [`GRID_LEVELS`]).
//!
//! GLSL twin: `glsl/include/estimator/light_setup.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::cone::{
    angle, bilinear_range, cone_of, hull_distance, hull_max_angle, min_length, mirror_lower_angle, narrowed,
    psi_range, unit, Cone, NO_CONE,
};
use super::constants::{Sign, ANGLE_PAD, K23, MAX_HALF, MIRROR_WORTH};
use super::frame::{cosine_range, cosine_range_of, plane_sin, Frame};
use super::settings::Discontinuity;
use super::terms::{Reason, TERM_COUNT};
use crate::exact_math::{est_acos, est_asin, est_cos, est_sin};
use crate::scene::{Light, MaterialKind, ParameterRange, PolygonLight};
use crate::shading::brdf::MIN_LIGHT_DISTANCE_SQUARED;
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, PI};

/// Everything about one light that does not depend on the pattern scale.
pub(super) struct LightSetup {
    /// `max |sin|` of the angle between l̂ and the plane normal (1 without a plane): bounds
    /// `|l̂·Xδ|/|Xδ|`, since position steps lie in the plane.
    pub(super) plane_sin: f32,
    /// `≤ plane_sin`: `|sin γ|` where the light is nearest (`√(1 − H²/d_min²)`, `H` the
    /// light's height over the plane), for bounds that fall as `d` grows along `sin²γ = 1 − H²/d²`.
    pub(super) near_sin: f32,
    /// `1/d_min` for a point light, 0 for a directional one.
    pub(super) inv_d: f32,
    /// Range of the angle between n̂ and l̂.
    pub(super) psi_nl: (f32, f32),
    /// Whether `n·l` may change sign inside the triangle.
    pub(super) straddle: bool,
    // Blinn-Phong and GGX only:
    pub(super) h_cone: Cone,
    pub(super) m_min: f32,
    pub(super) psi_nh: (f32, f32),
    pub(super) psi_nv: (f32, f32),
    pub(super) nv_sign: Sign,
    /// Range of the angle between l̂ and v̂.
    pub(super) psi_lv: (f32, f32),
    /// A polygonal light: the range of the emitter's angle (see [`AreaGeometry`]); its diffuse
    /// part is bounded as a continuum of point lights, its sampled specular part by its range.
    pub(super) area: Option<(f32, f32)>,
    /// `≤ H/d_min` (at most 1), `H` the light's height over the plane (0 without a plane):
    /// the cosine of `γ` where the light is nearest, for bounds along `sin²γ = 1 − H²/d²`.
    pub(super) near_cos: f32,
    /// `≥ H/d_min` (at most 1; 1 without a plane): `H` from above, so `cos γ ≤ far_cos` at
    /// every point.
    pub(super) far_cos: f32,
    /// `≤ inf E'` over the triangle: `1/d_max²` for a point light (the farthest point is a
    /// corner), 1 for a directional one, 0 for a polygon.
    pub(super) att_inf: f32,
    /// The cosines at the ends of `psi_nl`, `(cos ψ_min, cos ψ_max)`.
    pub(super) nl_cos: (f32, f32),
    /// Whether the specular fields above were planned ([`plan_parts`]): the specular part is
    /// bounded by its jets; else it has none (a Lambert material) or its cap bounds it.
    pub(super) specular: bool,
}

impl LightSetup {
    /// A light at `1/d_min = inv_d` with the angle range `psi_nl` and nothing else known yet:
    /// every other bound at its loosest.
    pub(super) fn unbounded(
        inv_d: f32,
        psi_nl: (f32, f32),
        straddle: bool,
        area: Option<(f32, f32)>,
    ) -> LightSetup {
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
            specular: false,
        }
    }
}

/// Accumulated bounds, per term and channel: `½·SAFETY·Σ weight·H` at level 1 and at
/// levels ≥ 2 (to be divided by n²), and the Relaxed first-order (÷ n) and constant terms.
#[derive(Default)]
pub(super) struct Sums {
    pub(super) h1: [Vec3; TERM_COUNT],
    pub(super) hn: [Vec3; TERM_COUNT],
    /// The second-order bound at levels ≥ 2 as one number per channel ([`Jet::t`]): what
    /// the level is decided on (the level-1 bound goes into `one`).
    ///
    /// [`Jet::t`]: super::jet::Jet::t
    pub(super) tn: Vec3,
    pub(super) lin1: Vec3,
    pub(super) linn: Vec3,
    /// Constant (n-independent) parts at levels ≥ 2: the Relaxed specular jumps at the
    /// terminator (taken at a lower bound of the level) and the parameter variations...
    pub(super) jumps: Vec3,
    /// ...the same at level 1...
    pub(super) jumps1: Vec3,
    /// ...and the light parts bounded by their range, reported as [`Term::Range`].
    ///
    /// [`Term::Range`]: super::terms::Term::Range
    pub(super) range: Vec3,
    /// The level-1 bound, per light and part the smaller of its interpolation bound and its
    /// range.
    pub(super) one: Vec3,
    /// The same at the uniform levels of [`GRID_LEVELS`] (the effective level of each).
    pub(super) grid: [Vec3; GRID_LEVELS.len()],
    /// The largest of the lights' lower bounds on the level (`low` in `add_light`): `linn` and
    /// `jumps` hold at effective levels from there on (their bands are taken there), so the
    /// bound `tn/L² + linn/L + jumps + range` does too. The level the solver returns is never
    /// below it; a grid level may be.
    pub(super) low: f32,
    /// The refining floor: per channel a lower bound, summed over the lights, on the bound at
    /// every level up to the top of the estimate refined over the children ([`light_floor`]).
    /// Where it exceeds `ε`, refining cannot keep the triangle from falling back.
    ///
    /// [`light_floor`]: super::add_light::light_floor
    pub(super) floor: Vec3,
}

/// Uniform levels at which the estimator also bounds each light's parts by the smaller of
/// their interpolation bound and their range at that very level (the rule of `add_light`
/// decides once, at `n_max`). A level found on this grid replaces the solved one where it is
/// lower; levels above `n_max` are skipped.
pub(super) const GRID_LEVELS: [u32; 8] = [2, 3, 4, 6, 8, 12, 16, 32];

/// Where a polygonal light is as seen from the triangle: every direction from a point of the
/// triangle to a point of the polygon, and the emitter's cosine. See `docs/estimator.md` §13.
pub(super) struct AreaGeometry {
    /// Contains every `y − x` (x in the triangle, y in the polygon): the cone around the
    /// centroid-to-centroid axis through all vertex-to-vertex differences (a cone narrower
    /// than a hemisphere is convex, so it holds their convex hull, which is the set).
    pub(super) cone: Cone,
    /// `min |y − x|` ≥ the smallest projection of a vertex-to-vertex difference on the axis.
    pub(super) d_min: f32,
    /// Range of `n·(y − x)` over the triangle and the polygon: per polygon vertex the exact
    /// bilinear range over the triangle, and their hull (the form is affine in y).
    pub(super) q: (f32, f32),
    pub(super) w_max: f32,
    /// Range of the angle between the emitter's normal and `x − y` (cosine at the emitter).
    pub(super) emitter: (f32, f32),
}

/// The [`AreaGeometry`] of `light` from `frame`, `Ok(None)` when the triangle lies behind the
/// emitter (it then receives exactly nothing), `Err` when the emitter's plane cuts it.
pub(super) fn area_geometry(frame: &Frame, light: &PolygonLight) -> Result<Option<AreaGeometry>, Reason> {
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
pub(super) fn weights(material: &MaterialKind, radiance: Vec3) -> (Vec3, Vec3) {
    match *material {
        MaterialKind::Lambert { kd } => (radiance * kd, Vec3::ZERO),
        MaterialKind::BlinnPhong { kd, ks, .. } => (radiance * kd, radiance * ks),
        // The specular part's colour comes from F (per channel, see `spec_jets`).
        MaterialKind::Ggx { albedo, .. } => (radiance * albedo, radiance),
    }
}

/// Where a light is as seen from the triangle, before any bound on its shading: what
/// [`plan_light`] builds the [`LightSetup`] from.
struct LightSource {
    radiance: Vec3,
    /// The cone of `l̂` over the triangle (a polygon's: of every direction from the triangle to it).
    cone: Cone,
    /// `1/d_min`, 0 for a directional light.
    inv_d: f32,
    /// `l̂` from the centroid (a polygon's cone axis).
    center: Vec3,
    /// A polygonal light's geometry.
    area: Option<AreaGeometry>,
    /// A point light's height over the plane, from below and from above.
    heights: (f32, f32),
    /// A point light's vectors from the corners (their directions span the spherical triangle
    /// of l̂).
    vectors: Option<[Vec3; 3]>,
}

/// A light's geometry over the triangle ([`LightSetup`]) and the weights of its diffuse and
/// specular parts; `None` where it adds exactly nothing; the reason for fallback where a
/// clamp or a singularity rules out a bound.
pub(super) fn plan_light(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    light: &Light,
    mode: Discontinuity,
) -> Result<Option<(LightSetup, Vec3, Vec3)>, Reason> {
    plan_parts(frame, material, parameter, light, mode, material.is_specular())
}

/// [`plan_light`], with the specular setup only where `specular` (false: the specular part is
/// bounded without it, by its cap).
pub(super) fn plan_parts(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    light: &Light,
    mode: Discontinuity,
    specular: bool,
) -> Result<Option<(LightSetup, Vec3, Vec3)>, Reason> {
    let Some(source) = light_source(frame, material, light)? else {
        return Ok(None);
    };
    let (diff_w, spec_w) = weights(material, source.radiance);
    if diff_w == Vec3::ZERO && spec_w == Vec3::ZERO {
        return Ok(None);
    }
    if frame.r_n <= 0.0 {
        return Err(Reason::Singular);
    }
    let Some(mut setup) = diffuse_setup(frame, light, &source, mode)? else {
        return Ok(None);
    };
    if specular {
        specular_setup(frame, material, parameter, mode, &source, &mut setup)?;
    }
    Ok(Some((setup, diff_w, spec_w)))
}

/// Where `light` is as seen from the triangle ([`LightSource`]); `None` where it adds exactly
/// nothing (no radiance, or a polygon the triangle lies behind); the reason for fallback where
/// the light is too close to the triangle for a bound.
fn light_source(
    frame: &Frame,
    material: &MaterialKind,
    light: &Light,
) -> Result<Option<LightSource>, Reason> {
    let mut area = None;
    let mut heights = (0.0, 0.0);
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
    Ok(Some(LightSource {
        radiance,
        cone: l_cone,
        inv_d,
        center: l_center,
        area,
        heights,
        vectors: l_vectors,
    }))
}

/// The [`LightSetup`] as far as the diffuse part needs it: the range of the angle between n̂ and
/// l̂ (narrowed where the light is near the plane), whether `n·l` changes sign, and the falloff's
/// bounds; `None` where `n·l ≤ 0` everywhere; the reason for fallback where the terminator
/// crosses the triangle in Conservative mode.
fn diffuse_setup(
    frame: &Frame,
    light: &Light,
    source: &LightSource,
    mode: Discontinuity,
) -> Result<Option<LightSetup>, Reason> {
    let (l_cone, inv_d, l_vectors) = (source.cone, source.inv_d, source.vectors);
    // Sign of n·l: exact, from the bilinear form (Σλₖ Nₖ)·(Σλₖ wₖ) over the simplex.
    let (psi_nl, sign) = match (l_vectors, &source.area) {
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
    let mut setup = LightSetup::unbounded(inv_d, psi_nl, straddle, source.area.as_ref().map(|a| a.emitter));
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
            let (height, height_hi) = source.heights;
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
    Ok(Some(setup))
}

/// The rest of the [`LightSetup`] for a specular material: the cone of ĥ and the ranges of the
/// angles between n̂ and ĥ, n̂ and v̂, l̂ and v̂; the reason for fallback where the view or the half
/// vector is singular, or where a kink of the lobe cannot be bounded in `mode`.
fn specular_setup(
    frame: &Frame,
    material: &MaterialKind,
    parameter: ParameterRange,
    mode: Discontinuity,
    source: &LightSource,
    setup: &mut LightSetup,
) -> Result<(), Reason> {
    let (l_cone, inv_d, l_center, l_vectors) = (source.cone, source.inv_d, source.center, source.vectors);
    let (area, straddle) = (&source.area, setup.straddle);
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
    // (a) follows one light point and one eye; a polygon or a ball of eyes needs (b), which holds
    // for all of them.
    let one_eye = frame.eye_radius <= 0.0;
    let (h_axis, h_half) =
        if half_b < half_a || area.is_some() || !one_eye { (unit(m0), half_b) } else { (axis_a, half_a) };
    setup.h_cone = if h_axis == Vec3::ZERO || !(h_half < MAX_HALF) {
        NO_CONE
    } else {
        Cone { axis: h_axis, half: h_half }
    };
    setup.specular = true;
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
    let v_vectors = frame.v_vectors;
    let nv_sign = frame.nv_sign;
    setup.psi_nv = frame.psi_nv;
    setup.nv_sign = nv_sign;
    // The same angle at the same point, from the mirror directions: where n·v > 0, n̂ is
    // the half vector of v̂ and its mirror, and where n·l > 0 of l̂ and its mirror.
    if area.is_none() && setup.h_cone.half > MIRROR_WORTH {
        let mut lo = setup.psi_nh.0;
        if nv_sign == Sign::Positive {
            lo = mirror_lower_angle(&frame.n_cone, &frame.v_cone, &l_cone, l_vectors, lo);
        }
        if !straddle {
            // The corners' vectors to the eye span v̂'s directions for one eye only.
            let v_corners = if one_eye { Some(v_vectors) } else { None };
            lo = mirror_lower_angle(&frame.n_cone, &l_cone, &frame.v_cone, v_corners, lo);
        }
        setup.psi_nh.0 = lo.min(setup.psi_nh.1);
    }
    // The same angle from the interpolant of n̂ − ĥ at the corners (`narrowed`), where n̂ and
    // ĥ turn together: n̂'s and ĥ's second derivatives at level 1 bound its error. The corners'
    // ĥ are one eye's.
    if area.is_none() && one_eye {
        let l_units = match l_vectors {
            Some(w) => w.map(unit),
            None => [l_cone.axis; 3],
        };
        let h_units: [Vec3; 3] = std::array::from_fn(|k| unit(l_units[k] + frame.v_units[k]));
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
    Ok(())
}
