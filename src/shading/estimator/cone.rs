//! Cones of directions and the angle ranges they give: [`Cone`], [`cone_of`], the range of the
//! angle between two cones ([`psi_range`]), the exact range of a bilinear form over the
//! triangle ([`bilinear_range`]), and the spherical-triangle and distance bounds that narrow
//! them.
//!
//! GLSL twin: `glsl/include/estimator/cone.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use super::constants::{ANGLE_PAD, CHOICE_PAD, HULL_WORTH, MAX_HALF};
use crate::exact_math::{est_asin, est_atan2};
use glam::Vec3;
use std::f32::consts::{FRAC_PI_2, PI};

/// A circular cone of directions: every value of the field is within `half` of `axis`.
/// `half = π` means no bound.
#[derive(Clone, Copy, Debug)]
pub(super) struct Cone {
    pub(super) axis: Vec3,
    pub(super) half: f32,
}

pub(super) const NO_CONE: Cone = Cone { axis: Vec3::Z, half: PI };

/// Angle between two vectors, accurate for small and large angles; 0 if one is zero.
pub(super) fn angle(a: Vec3, b: Vec3) -> f32 {
    let (s, c) = sine_cosine(a, b);
    est_atan2(s, c)
}

/// The angle between `a` and `b` as `(|a × b|, a·b)`: its sine and cosine, both times
/// `|a|·|b|`, which [`angle`] measures and [`pseudo_angle`] orders without trigonometry.
pub(super) fn sine_cosine(a: Vec3, b: Vec3) -> (f32, f32) {
    (a.cross(b).length(), a.dot(b))
}

/// A number that grows with the angle `atan2(s, c)` on `[0, π]` (`s ≥ 0`): `1 − c/(s + |c|)`,
/// from 0 at 0 through 1 at π/2 to 2 at π, never less steep than ½ per radian; 0 for `(0, 0)`,
/// whose angle is 0. Its rounding (a few 10⁻⁷) can order two angles less than [`CHOICE_PAD`]
/// apart wrongly; [`widest_angle`] and [`nearest_angle`] pad by that.
pub(super) fn pseudo_angle(s: f32, c: f32) -> f32 {
    let t = s + c.abs();
    if t > 0.0 {
        1.0 - c / t
    } else {
        0.0
    }
}

/// `max_k angle(a, u[k])` (up to [`CHOICE_PAD`], added), with one arc tangent: the widest of
/// the three chosen by [`pseudo_angle`].
pub(super) fn widest_angle(a: Vec3, u: [Vec3; 3]) -> f32 {
    let (mut s, mut c) = sine_cosine(a, u[0]);
    let mut widest = pseudo_angle(s, c);
    for &w in &u[1..] {
        let (sk, ck) = sine_cosine(a, w);
        let pk = pseudo_angle(sk, ck);
        if pk > widest {
            (s, c, widest) = (sk, ck, pk);
        }
    }
    est_atan2(s, c) + CHOICE_PAD
}

/// The smallest angle of a non-empty list of `(sine, cosine)` pairs ([`sine_cosine`]), up to
/// [`CHOICE_PAD`] (subtracted), with one arc tangent: the nearest chosen by [`pseudo_angle`].
pub(super) fn nearest_angle(pairs: &[(f32, f32)]) -> f32 {
    let (mut s, mut c) = pairs[0];
    let mut nearest = pseudo_angle(s, c);
    for &(sk, ck) in &pairs[1..] {
        let pk = pseudo_angle(sk, ck);
        if pk < nearest {
            (s, c, nearest) = (sk, ck, pk);
        }
    }
    est_atan2(s, c) - CHOICE_PAD
}

pub(super) fn unit(v: Vec3) -> Vec3 {
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
pub(super) fn cone_of(w: [Vec3; 3]) -> Cone {
    let u = w.map(unit);
    if u.contains(&Vec3::ZERO) {
        return NO_CONE;
    }
    let d = [(u[0] - u[1]).length_squared(), (u[1] - u[2]).length_squared(), (u[2] - u[0]).length_squared()];
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
    let half = widest_angle(axis, u) + ANGLE_PAD;
    if half.is_nan() || half >= MAX_HALF {
        NO_CONE
    } else {
        Cone { axis, half }
    }
}

/// `min |Σλₖwₖ|` over the simplex is at least `min_k wₖ·axis` (project on the axis).
pub(super) fn min_length(w: [Vec3; 3], cone: &Cone) -> f32 {
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
pub(super) fn psi_range(a: &Cone, b: &Cone) -> (f32, f32) {
    let t0 = angle(a.axis, b.axis);
    ((t0 - a.half - b.half).max(0.0), (t0 + a.half + b.half).min(PI))
}

/// Exact range of the bilinear form `q(λ) = (Σλₖaₖ)·(Σλₖbₖ)` over the simplex (a quadratic
/// in λ): the corners, the extremum along each edge, and the interior critical point.
/// `n·l` (unnormalised) is such a form for point lights (`bₖ = p − xₖ`, linear for
/// directional ones), and so is `n·v`; its sign is the sign of the shading's cosine.
pub(super) fn bilinear_range(a: [Vec3; 3], b: [Vec3; 3]) -> (f32, f32) {
    let s = |i: usize, j: usize| 0.5 * (a[i].dot(b[j]) + a[j].dot(b[i]));
    let (s00, s11, s22) = (s(0, 0), s(1, 1), s(2, 2));
    let (s01, s12, s02) = (s(0, 1), s(1, 2), s(0, 2));
    let mut lo = s00.min(s11).min(s22);
    let mut hi = s00.max(s11).max(s22);
    for (sii, sjj, sij) in [(s00, s11, s01), (s11, s22, s12), (s22, s00, s02)] {
        let curv = sii - 2.0 * sij + sjj;
        let t = (sii - sij) / curv;
        if t > 0.0 && t < 1.0 {
            let v = (1.0 - t) * (1.0 - t) * sii + 2.0 * t * (1.0 - t) * sij + t * t * sjj;
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    // λ = (1 − s − t, s, t): q = s00 + 2dᵀx + xᵀMx, critical where Mx = −d, q* = s00 + dᵀx.
    let (d1, d2) = (s01 - s00, s02 - s00);
    let (ma, mb, mc) = (s00 - 2.0 * s01 + s11, s00 - s01 - s02 + s12, s00 - 2.0 * s02 + s22);
    let det = ma * mc - mb * mb;
    let x = (-d1 * mc + d2 * mb) / det;
    let y = (-ma * d2 + mb * d1) / det;
    if x > 0.0 && y > 0.0 && x + y < 1.0 {
        let v = s00 + d1 * x + d2 * y;
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (lo, hi)
}

/// Angular distance from the unit vector `a` to the spherical triangle spanned by the unit
/// vectors `u` (which lie in an open hemisphere): 0 inside, otherwise the distance to the
/// nearest edge arc or corner. Padded to stay a lower bound under f32 rounding.
pub(super) fn hull_distance(a: Vec3, u: [Vec3; 3]) -> f32 {
    let orient = u[0].dot(u[1].cross(u[2]));
    let side = [a.dot(u[0].cross(u[1])), a.dot(u[1].cross(u[2])), a.dot(u[2].cross(u[0]))];
    let tol = 1.0e-6;
    let same_half = a.dot(u[0] + u[1] + u[2]) > 0.0;
    let inside = same_half
        && ((orient >= 0.0 && side.iter().all(|&x| x >= -tol))
            || (orient <= 0.0 && side.iter().all(|&x| x <= tol)));
    if inside {
        return 0.0;
    }
    // The corners' angles and the feet's on the edge arcs, the nearest measured once.
    let mut pairs = [(0.0, 0.0); 6];
    let mut count = 0;
    for (k, (p, q)) in [(u[0], u[1]), (u[1], u[2]), (u[2], u[0])].into_iter().enumerate() {
        pairs[count] = sine_cosine(a, u[k]);
        count += 1;
        let m = unit(p.cross(q));
        if m != Vec3::ZERO {
            let foot = a - m * a.dot(m);
            if p.cross(foot).dot(m) >= 0.0 && foot.cross(q).dot(m) >= 0.0 && foot != Vec3::ZERO {
                pairs[count] = (a.dot(m).abs(), foot.length());
                count += 1;
            }
        }
    }
    let best = nearest_angle(&pairs[..count]);
    (best * (1.0 - 1.0e-3) - ANGLE_PAD).max(0.0)
}

/// A lower bound on the angle between n̂ and the half vector `ĥ = (â + b̂)/|â + b̂|` at the
/// same point, where `n̂·â > 0` on the whole triangle (`docs/estimator.md` §2, "Cones and
/// cosine ranges": "`n·h` at the same point"). There `n̂` is the half vector of `â` and its mirror
/// `r = 2(n̂·â)n̂ − â`, and two half vectors of a common `â` are at least half as far apart as
/// their other ends: `∠(ĥ, n̂) ≥ ∠(b̂, r)/2`. `r` stays within `2ν_n + ν_a` of the mirror `r₀`
/// of the cones' axes (a half-turn about `n̂` against one about the axis is a rotation by twice
/// their angle), and `b̂` lies in its cone and in the spherical triangle of the directions of
/// `b_vectors` (from the corners to a point light or the eye; `None` for a single direction).
/// Returns the larger of this bound and `lo`.
pub(super) fn mirror_lower_angle(n: &Cone, a: &Cone, b: &Cone, b_vectors: Option<[Vec3; 3]>, lo: f32) -> f32 {
    if !(n.half < PI && a.half < PI && b.half < PI) {
        return lo;
    }
    let r0 = unit(n.axis * (2.0 * n.axis.dot(a.axis)) - a.axis);
    if r0 == Vec3::ZERO {
        return lo;
    }
    let spread = 2.0 * n.half + a.half;
    let axis_angle = angle(b.axis, r0);
    let mut apart = axis_angle - b.half;
    // The spherical triangle is within `θ_b` of the axis, so it adds at most `θ_b` to the
    // cone's distance: it is worth its cost only for a wide cone, where it could raise `lo`.
    if let Some(vectors) = b_vectors {
        if b.half > HULL_WORTH && 0.5 * (axis_angle + b.half - spread) > lo {
            apart = apart.max(hull_distance(r0, vectors.map(unit)));
        }
    }
    lo.max(0.5 * (apart - spread) - ANGLE_PAD)
}

/// `range` narrowed to the angles that unit fields `â`, `b̂` (corner values `a`, `b`) can make
/// over the patch, given `curvature ≥ sup|D²(â − b̂)|` at level 1: `|â − b̂| = 2 sin(ψ/2)` lies
/// within `½·curvature` (the level-1 interpolation bound) of the linear interpolant of the
/// corners' differences, whose norm ranges from the triangle's distance to the origin to its
/// farthest corner (`docs/estimator.md` §2, "`n·h` from the corners' differences, to second order").
/// `1.0e-5` covers the rounding of the corners; a NaN leaves `range` as it is.
pub(super) fn narrowed(range: (f32, f32), a: [Vec3; 3], b: [Vec3; 3], curvature: f32) -> (f32, f32) {
    let corners = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let error = 0.5 * curvature + 1.0e-5;
    let lo = origin_distance(corners) - error;
    let hi = corners[0].length().max(corners[1].length()).max(corners[2].length()) + error;
    let lo_angle = if lo > 0.0 { 2.0 * est_asin((0.5 * lo).min(1.0)) - ANGLE_PAD } else { 0.0 };
    let hi_angle = if hi < 2.0 { 2.0 * est_asin(0.5 * hi) + ANGLE_PAD } else { PI };
    let low = range.0.max(lo_angle);
    (low, range.1.min(hi_angle).max(low))
}

/// The distance from the origin to the segment `p q` (a point where `q = p`).
pub(super) fn segment_distance(p: Vec3, q: Vec3) -> f32 {
    let pq = q - p;
    let length2 = pq.length_squared();
    let t = if length2 > 0.0 { (-p.dot(pq) / length2).clamp(0.0, 1.0) } else { 0.0 };
    (p + pq * t).length()
}

/// A lower bound on the distance from the origin to the triangle with corners `c`, exact up to
/// rounding unless the triangle is a sliver: the nearest of its edges, or the distance to its
/// plane where the origin projects inside it. The plane's normal is trusted only where the
/// triangle's height over its longest edge is at least a tenth of that edge (a plane's distance
/// never exceeds the distance to a point of the plane, so the inside test may err towards it);
/// a thinner triangle lies within its height `h` of its longest edge (whose ends see the third
/// corner at acute angles), so it is at least that edge's distance less `h` away.
pub(super) fn origin_distance(c: [Vec3; 3]) -> f32 {
    let edges = [(c[0], c[1]), (c[1], c[2]), (c[2], c[0])];
    let nearest = edges.map(|(p, q)| segment_distance(p, q));
    let lengths = edges.map(|(p, q)| (q - p).length_squared());
    let edge_min = nearest[0].min(nearest[1]).min(nearest[2]);
    let longest = if lengths[0] >= lengths[1] && lengths[0] >= lengths[2] {
        0
    } else if lengths[1] >= lengths[2] {
        1
    } else {
        2
    };
    let normal = (c[1] - c[0]).cross(c[2] - c[0]);
    let area2 = normal.length_squared();
    if area2 >= 0.01 * lengths[longest] * lengths[longest] && area2 > 0.0 {
        let inside = edges.iter().all(|&(p, q)| normal.dot((q - p).cross(-p)) >= 0.0);
        if inside {
            return edge_min.min(c[0].dot(normal).abs() / area2.sqrt());
        }
        return edge_min;
    }
    let height = if lengths[longest] > 0.0 { area2.sqrt() / lengths[longest].sqrt() } else { 0.0 };
    edge_min.min(nearest[longest] - height)
}

/// Largest angle between `a` and the spherical triangle spanned by unit `u`, valid when it
/// is below π/2 (then `n̂·a` is quasi-concave on the cone and its minimum sits at a corner);
/// `π` otherwise.
pub(super) fn hull_max_angle(a: Vec3, u: [Vec3; 3]) -> f32 {
    let m = widest_angle(a, u) + ANGLE_PAD;
    if m < FRAC_PI_2 {
        m
    } else {
        PI
    }
}
