//! The scale-free quantities of one triangle ([`Frame`]): its pattern scales, cones of normals
//! and of view directions, plane, the range of the angle between the normal and the view, and
//! the distance bounds to a light; [`plane_sin`] and the cosine ranges ([`cosine_range`]).
//!
//! GLSL twin: `glsl/include/estimator/frame.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::cone::{bilinear_range, cone_of, min_length, psi_range, unit, Cone, NO_CONE};
use super::constants::{Sign, ANGLE_PAD, BALL_SLACK_PAD, MAX_HALF, RADIAL_PAD};
use super::jet::max_sin;
use super::pattern::{jung_scales, pattern_constants, Scale};
use super::terms::TriangleInput;
use crate::exact_math::{est_acos, est_asin};
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, PI};

/// The angle by which a ball of eyes of radius `radius` widens the directions from a point at
/// least `distance` from its centre: the directions to the ball's points lie within
/// `asin(radius/distance)` of the direction to its centre (padded); π where the ball comes
/// within 1 % of the point (no bound).
pub(super) fn ball_angle(radius: f32, distance: f32) -> f32 {
    if !(radius > 0.0) {
        0.0
    } else if radius < 0.99 * distance {
        est_asin(radius / distance) + ANGLE_PAD
    } else {
        PI
    }
}

/// Scale-free quantities of the triangle.
pub(super) struct Frame {
    pub(super) vertices: [Vec3; 3],
    pub(super) eye: Vec3,
    /// The bounds below hold for every eye within this distance of `eye`
    /// ([`EstimatorSettings::eye_radius`]).
    ///
    /// [`EstimatorSettings::eye_radius`]: super::settings::EstimatorSettings::eye_radius
    pub(super) eye_radius: f32,
    pub(super) centroid: Vec3,
    /// `max_k |xₖ − centroid|`: how far any point is from the centroid.
    pub(super) rho_x: f32,
    /// Pattern scales: level 1, levels ≥ 2, and the diameters (Relaxed terms).
    pub(super) s1: Scale,
    pub(super) sn: Scale,
    /// `ρ = max` over the three attributes of `s₁/sₙ` (`≤ 1`, as `s₁ ≤ sₙ`): the level-1 jets are
    /// at most `ρ` (first derivatives) and `ρ²` (second) times those at levels ≥ 2.
    pub(super) rho: f32,
    pub(super) d1: Scale,
    pub(super) dn: Scale,
    pub(super) n_cone: Cone,
    /// Lower bound on `|N(λ)|` over the triangle; 0 when the normal can vanish.
    pub(super) r_n: f32,
    /// Upper bound on `|N(λ)|`.
    pub(super) n_max_len: f32,
    /// The vertex normals as given, and normalised (corners of the spherical triangle n̂).
    pub(super) normals: [Vec3; 3],
    pub(super) unit_normals: [Vec3; 3],
    /// Unit normal of the triangle's plane (zero for a degenerate triangle).
    pub(super) plane: Vec3,
    pub(super) v_cone: Cone,
    /// Bound on the angle (rad) between `plane` and the true plane normal (f32 rounding).
    pub(super) plane_tilt: f32,
    /// `max |sin|` of the angle between n̂ and the plane normal (see [`plane_sin`]): bounds
    /// `|n̂·Xδ|/|Xδ|`.
    pub(super) n_plane_sin: f32,
    /// Lower bound on the distance from the eye (every eye of the ball) to the triangle.
    pub(super) e_min: f32,
    pub(super) v_center: Vec3,
    /// The vectors from the corners to the eye (the ball's centre)...
    pub(super) v_vectors: [Vec3; 3],
    /// ...their directions, and the range of the angle between n̂ and v̂ with the sign of `n·v`
    /// ([`cosine_range`]): the same for every light, so taken once, and only for a specular
    /// material (`specular`); zero, `(0, π)` and `Sign::Both` otherwise.
    pub(super) v_units: [Vec3; 3],
    pub(super) psi_nv: (f32, f32),
    pub(super) nv_sign: Sign,
}

impl Frame {
    /// The frame of `tri` for every eye within `eye_radius` of `tri.eye`, with the angle between
    /// the normal and the view where `specular` (only a specular lobe reads it).
    pub(super) fn new(tri: &TriangleInput, eye_radius: f32, specular: bool) -> Frame {
        let [p0, p1, p2] = tri.positions;
        let centroid = (p0 + p1 + p2) / 3.0;
        let rho_x = (p0 - centroid).length().max((p1 - centroid).length()).max((p2 - centroid).length());
        let px = pattern_constants(p1 - p0, p2 - p0);
        let [n0, n1, n2] = tri.normals;
        let pn = pattern_constants(n1 - n0, n2 - n0);
        let n_cone = cone_of(tri.normals);
        let longest = n0.length().max(n1.length()).max(n2.length());
        let along = |e: Vec3| Vec3::new(n0.dot(e), n1.dot(e), n2.dot(e));
        let pg = jung_scales(along(n1 - n0), along(n2 - n0));
        // Rounding of the dot products: a few ulps of |N|·|Nδ|, and |Nδ| ≤ 2√K at the scale.
        let g_pad = RADIAL_PAD * longest;
        let mut r_n = min_length(tri.normals, &n_cone);
        if !(r_n > 1.0e-6 * longest) {
            r_n = 0.0;
        }
        let to_eye = [tri.eye - p0, tri.eye - p1, tri.eye - p2];
        let mut v_cone = cone_of(to_eye);
        let mut e_min = min_length(to_eye, &v_cone);
        if eye_radius > 0.0 {
            // Every eye of the ball sees each point within `ball_angle` of the centre's view of
            // it, and is at most `eye_radius` nearer; a ball that reaches the triangle leaves no
            // bound (the specular setup then falls back).
            let widen = ball_angle(eye_radius, e_min);
            v_cone.half += widen;
            if !(v_cone.half < MAX_HALF) {
                v_cone = NO_CONE;
            }
            e_min = if widen < PI { e_min - eye_radius } else { 0.0 };
        }
        let (plane, plane_tilt) = {
            let c = (p1 - p0).cross(p2 - p0);
            let scale = (p1 - p0).length() * (p2 - p0).length();
            if c.length() > 1.0e-6 * scale {
                // Each component of the cross product is within about 4·10⁻⁷·scale.
                (unit(c), 4.0e-7 * scale / c.length() + 1.0e-6)
            } else {
                (Vec3::ZERO, 0.0)
            }
        };
        let s1 = Scale { a: px.sqrt_k1, b: pn.sqrt_k1, g: pg.0 + g_pad * pn.sqrt_k1 };
        let sn = Scale { a: px.sqrt_k, b: pn.sqrt_k, g: pg.1 + g_pad * pn.sqrt_k };
        let ratio = |one: f32, later: f32| if later > 0.0 { one / later } else { 0.0 };
        let rho = ratio(s1.a, sn.a).max(ratio(s1.b, sn.b)).max(ratio(s1.g, sn.g)).min(1.0);
        let mut frame = Frame {
            vertices: tri.positions,
            eye: tri.eye,
            eye_radius,
            centroid,
            rho_x,
            s1,
            sn,
            rho,
            d1: Scale { a: px.diam1, b: pn.diam1, g: 0.0 },
            dn: Scale { a: px.diam, b: pn.diam, g: 0.0 },
            n_cone,
            r_n,
            n_max_len: longest,
            normals: tri.normals,
            unit_normals: tri.normals.map(unit),
            plane,
            plane_tilt,
            n_plane_sin: plane_sin(&n_cone, plane),
            v_cone,
            e_min,
            v_center: unit(tri.eye - centroid),
            v_vectors: to_eye,
            v_units: [Vec3::ZERO; 3],
            psi_nv: (0.0, PI),
            nv_sign: Sign::Both,
        };
        if specular {
            frame.v_units = to_eye.map(unit);
            if eye_radius > 0.0 {
                // n·(e' − x) is within |N|·|e' − e| of n·(e − x): the bilinear range widened by
                // that, with the lengths of e' − x bounded as the ball allows.
                let (q_lo, q_hi) = bilinear_range(frame.normals, to_eye);
                let slack = frame.n_max_len * eye_radius * (1.0 + BALL_SLACK_PAD);
                let w_max = to_eye[0].length().max(to_eye[1].length()).max(to_eye[2].length()) + eye_radius;
                let q = (q_lo - slack, q_hi + slack);
                (frame.psi_nv, frame.nv_sign) =
                    cosine_range_of(&frame, &frame.v_cone, q, w_max, frame.e_min.max(0.0));
            } else {
                (frame.psi_nv, frame.nv_sign) = cosine_range(&frame, &frame.v_cone, to_eye);
            }
        }
        frame
    }

    /// Lower and upper bounds on the height of `p` over the triangle's plane (0 without a
    /// plane): the computed one less and plus what the plane's direction and the rounding can be
    /// off by.
    pub(super) fn height_of(&self, p: Vec3) -> (f32, f32) {
        if self.plane == Vec3::ZERO {
            return (0.0, 0.0);
        }
        let r = p - self.vertices[0];
        let (height, pad) = (r.dot(self.plane).abs(), r.length() * (self.plane_tilt + 1.0e-6));
        ((height - pad).max(0.0), height + pad)
    }

    /// A lower bound on the distance from `p` to the triangle: `√(H² + ρ²)` with `H ≥ height`
    /// its height from below ([`Frame::height_of`]) and `ρ` the in-plane distance from its foot
    /// to the triangle, less what the rounding can move it.
    pub(super) fn distance_of(&self, p: Vec3, height: f32) -> f32 {
        if self.plane == Vec3::ZERO {
            return self.distance_along_line(p);
        }
        let foot = p - self.plane * (p - self.vertices[0]).dot(self.plane);
        // The foot's distance to the triangle: 0 inside, else to the nearest edge (at most to
        // the first corner).
        let mut inside = true;
        let mut rho = (foot - self.vertices[0]).length();
        for k in 0..3 {
            let (a, b) = (self.vertices[k], self.vertices[(k + 1) % 3]);
            let (e, f) = (b - a, foot - a);
            inside &= e.cross(f).dot(self.plane) >= 0.0;
            let t = (f.dot(e) / e.length_squared()).clamp(0.0, 1.0);
            rho = rho.min((f - e * t).length());
        }
        let reach = (p - self.vertices[0]).length() + 2.0 * self.rho_x;
        // The foot's rounding (the plane's tilt over the light's reach) and the differences'.
        let magnitude = foot.abs().max_element() + self.vertices[0].abs().max_element() + 2.0 * self.rho_x;
        let pad = 2.0 * reach * (self.plane_tilt + 1.0e-6) + 1.0e-6 * magnitude;
        let rho = if inside || !(rho > pad) { 0.0 } else { rho - pad };
        (height * height + rho * rho).sqrt()
    }

    /// For a triangle without a plane (its corners on a line, up to rounding): the distance
    /// from `p` to its longest edge, less the third corner's distance from that edge (every
    /// point of the triangle is that close to the edge) and the rounding.
    pub(super) fn distance_along_line(&self, p: Vec3) -> f32 {
        let v = self.vertices;
        let lengths =
            [(v[1] - v[0]).length_squared(), (v[2] - v[1]).length_squared(), (v[0] - v[2]).length_squared()];
        let k = if lengths[0] >= lengths[1] && lengths[0] >= lengths[2] {
            0
        } else if lengths[1] >= lengths[2] {
            1
        } else {
            2
        };
        let (a, b, third) = (v[k], v[(k + 1) % 3], v[(k + 2) % 3]);
        let to_segment = |x: Vec3| {
            let (e, f) = (b - a, x - a);
            let t = if lengths[k] > 0.0 { (f.dot(e) / lengths[k]).clamp(0.0, 1.0) } else { 0.0 };
            (f - e * t).length()
        };
        let magnitude = p.abs().max_element() + a.abs().max_element() + 2.0 * self.rho_x;
        (to_segment(p) - to_segment(third) - 1.0e-6 * magnitude).max(0.0)
    }
}

/// `max |sin|` of the angle between a direction of `cone` and the unit `plane` normal, 1
/// without a plane: bounds `|ŵ·Xδ|/|Xδ|` for the directions ŵ of the cone, since position
/// steps `Xδ` lie in the plane.
pub(super) fn plane_sin(cone: &Cone, plane: Vec3) -> f32 {
    if plane == Vec3::ZERO {
        return 1.0;
    }
    let (g0, g1) = psi_range(cone, &Cone { axis: plane, half: 0.0 });
    max_sin(g0, g1)
}

/// Range of the angle between n̂ and the field `ŵ = normalize(Σλₖwₖ)` (cone `w_cone`), and
/// the sign of `n·w` over the triangle. The cones give one range (paper Eq. 20, 51); the
/// exact range `[q₋, q₊]` of the bilinear form `n·w` gives the sign and, through
/// `q₋/(max|n| max|w|) ≤ cos ≤ q₊/(min|n| min|w|)`, a second range; the tighter ends are kept.
pub(super) fn cosine_range(frame: &Frame, w_cone: &Cone, w: [Vec3; 3]) -> ((f32, f32), Sign) {
    let q = bilinear_range(frame.normals, w);
    let w_max = w[0].length().max(w[1].length()).max(w[2].length());
    cosine_range_of(frame, w_cone, q, w_max, min_length(w, w_cone))
}

/// [`cosine_range`] from the range `q` of `n·w` over the triangle and bounds on `|w|`.
pub(super) fn cosine_range_of(
    frame: &Frame,
    w_cone: &Cone,
    q: (f32, f32),
    w_max: f32,
    w_min: f32,
) -> ((f32, f32), Sign) {
    let (mut p0, mut p1) = psi_range(&frame.n_cone, w_cone);
    let (q_lo, q_hi) = q;
    let scale = frame.n_max_len * w_max;
    let tol = 1.0e-5 * scale;
    let sign = if q_lo > tol {
        Sign::Positive
    } else if q_hi < -tol {
        Sign::NonPositive
    } else {
        Sign::Both
    };

    if q_lo > tol && scale > 0.0 {
        p1 = p1.min(est_acos((q_lo / scale).min(1.0)) + ANGLE_PAD);
    }
    let denom = frame.r_n * w_min;
    if q_hi > 0.0 && denom > 0.0 {
        p0 = p0.max(est_acos((q_hi / denom).min(1.0)) - ANGLE_PAD);
    }
    if sign == Sign::NonPositive {
        p0 = p0.max(FRAC_PI_2);
    }
    if p0 > p1 {
        p0 = p1;
    }
    ((p0, p1), sign)
}
