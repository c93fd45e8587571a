//! The cancellation-free helpers the polygon module computes with: [`kahan`]'s `a·b − c·d`,
//! [`cross_stable`], [`det2`], [`rotate_90`], [`mix`] and [`unit_difference`]. Twin of
//! `glsl/include/polygon/arithmetic.glsl` (which also spells out Rust's float semantics, glam's dot
//! products and lengths, `mul_add` and `atan2`); `tests/polygon_gpu.rs` checks that the two agree.

use glam::{Vec2, Vec3};

/// Index of the vertex after `j` in a polygon with `count` vertices.
pub(super) fn next_index(j: usize, count: usize) -> usize {
    if j + 1 == count {
        0
    } else {
        j + 1
    }
}

/// `a·b − c·d` with at most 1.5 ulps of error (Kahan's algorithm with one fma).
pub(super) fn kahan(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let error = c.mul_add(d, -cd);
    a.mul_add(b, -cd) - error
}

/// The cross product with every component evaluated by [`kahan`].
pub(super) fn cross_stable(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(kahan(a.y, b.z, a.z, b.y), kahan(a.z, b.x, a.x, b.z), kahan(a.x, b.y, a.y, b.x))
}

/// `det(a, b) = a.x·b.y − a.y·b.x`; positive iff `b` is counterclockwise of `a` (within 180°).
/// Agrees bit for bit with the z-component of [`cross_stable`].
pub(super) fn det2(a: Vec2, b: Vec2) -> f32 {
    kahan(a.x, b.y, a.y, b.x)
}

/// `v` rotated by 90° counterclockwise (the paper's `R v`).
pub(super) fn rotate_90(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

/// `(1 − t)·a + t·b` with two fmas, exact at both ends.
pub(super) fn mix(a: f32, b: f32, t: f32) -> f32 {
    t.mul_add(b, (-t).mul_add(a, a))
}

/// `a/|a| − b/|b|` for non-zero `a`, `b`, with a small relative error even when the two
/// directions nearly agree (normalising first leaves an absolute error of about ε, and so does
/// `(a − b)/|a| + …` when `a` and `b` differ mostly in length). With θ the angle between them:
/// `â − b̂ = b̂ × (â × b̂) − (1 − cos θ) b̂`, where `a × b` is evaluated by [`cross_stable`] and
/// `1 − cos θ = sin²θ / (1 + cos θ)` while `cos θ > 0`.
pub(super) fn unit_difference(a: Vec3, b: Vec3) -> Vec3 {
    let length_b = b.length();
    let inverse_lengths = 1.0 / (a.length() * length_b);
    let normal = cross_stable(a, b);
    let sine = normal.length() * inverse_lengths;
    let cosine = a.dot(b) * inverse_lengths;
    let one_minus_cosine = if cosine > 0.0 { sine * sine / (1.0 + cosine) } else { 1.0 - cosine };
    b.cross(normal) * (inverse_lengths / length_b) - b * (one_minus_cosine / length_b)
}
