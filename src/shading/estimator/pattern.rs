//! The hardware pattern's seven sub-triangle shapes ([`SHAPES`]) and the constants `K_W`, `D_W`
//! of a triangle under an attribute map ([`PatternConstants`], [`pattern_constants`]), with the
//! pattern scale the jets are evaluated at ([`Scale`]).
//!
//! GLSL twin: `glsl/include/estimator/pattern.glsl`. Proof that the twins are equal:
//! `tests/multirate.rs` `control_stage_levels_equal_the_twin` (the GPU's levels equal this twin's
//! on every triangle of the shipped scenes, bit for bit).

use glam::Vec3;

/// Evaluation point of the jets: what `|Xδ|` (length), `|Nδ|` and `|Gδ|` are replaced by,
/// where `Gδ = (N₀·Nδ, N₁·Nδ, N₂·Nδ)` bounds the normal's change along itself
/// (`|N(λ)·Nδ| ≤ |Gδ|`, see [`Field::radial`]).
///
/// [`Field::radial`]: super::jet::Field::radial
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Scale {
    pub(super) a: f32,
    pub(super) b: f32,
    pub(super) g: f32,
}

/// For the images of the seven sub-triangle shapes under one attribute map: `(√K₁, √K, D₁, D)`
/// where `K₁` is the enclosing-circle radius² of the patch itself (level 1), `K` the largest
/// over all shapes (levels ≥ 2), and `D₁`, `D` the matching largest diameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PatternConstants {
    pub sqrt_k1: f32,
    pub sqrt_k: f32,
    pub diam1: f32,
    pub diam: f32,
}

/// The shapes, as `{0, u, v}` with `u`, `v` in the basis `e₁ = B − A`, `e₂ = C − A` of the
/// patch `(A, B, C)`. At level `n` every sub-triangle of Vulkan's `equal_spacing` pattern
/// (inner = outer = n) is a translate of `±1/n` times one of them:
/// the patch (level 1, and the centre triangle of odd levels), and for each side with
/// direction `e` and "rung" `r` (from a point of the side to the next inner ring, ⅔ of the
/// median towards the opposite corner) the two halves of a ring quad, `{0, e, e + r}` and
/// `{0, e, r}` (both diagonals; corner triangles and the centre fan of even levels are
/// among them).
pub const SHAPES: [[(f32, f32); 2]; 7] = [
    [(1.0, 0.0), (0.0, 1.0)],
    // side AB: e = e₁, r = −e₁/3 + 2e₂/3
    [(1.0, 0.0), (2.0 / 3.0, 2.0 / 3.0)],
    [(1.0, 0.0), (-1.0 / 3.0, 2.0 / 3.0)],
    // side AC: e = e₂, r = 2e₁/3 − e₂/3
    [(0.0, 1.0), (2.0 / 3.0, 2.0 / 3.0)],
    [(0.0, 1.0), (2.0 / 3.0, -1.0 / 3.0)],
    // side BC: e = e₂ − e₁, r = −(e₁ + e₂)/3
    [(-1.0, 1.0), (-4.0 / 3.0, 2.0 / 3.0)],
    [(-1.0, 1.0), (-1.0 / 3.0, -1.0 / 3.0)],
];

/// `max_x Σμₖ|vₖ − x|²` over the triangle `{0, u, v}`: the circumradius² if the triangle
/// is acute, (longest edge / 2)² otherwise; clamped to Jung's `[d²/4, d²/3]` against
/// rounding. Returns it with the squared diameter `d²`.
pub(super) fn enclosing_radius2(u: Vec3, v: Vec3) -> (f32, f32) {
    let e = [u.length_squared(), v.length_squared(), (u - v).length_squared()];
    let d2 = e[0].max(e[1]).max(e[2]);
    if !(d2 > 0.0) {
        return (0.0, 0.0);
    }
    let sum = e[0] + e[1] + e[2];
    if 2.0 * d2 >= sum {
        return (0.25 * d2, d2);
    }
    // Scale-free: R²/d² = (a²b²c²/d⁶) / (4|u×v|²/d⁴).
    let x = u.cross(v).length_squared() / (d2 * d2);
    let r = (e[0] / d2) * (e[1] / d2) * (e[2] / d2) / (4.0 * x).max(1.0e-30);
    (d2 * r.clamp(0.25, 1.0 / 3.0), d2)
}

/// The pattern constants of the attribute triangle with edge vectors `e1 = W(B) − W(A)`,
/// `e2 = W(C) − W(A)`: see [`PatternConstants`]. The largest squares are found first and their
/// roots taken once (a correctly rounded square root is monotone, so this is the largest root).
pub fn pattern_constants(e1: Vec3, e2: Vec3) -> PatternConstants {
    let (mut first, mut largest) = ((0.0f32, 0.0f32), (0.0f32, 0.0f32));
    for (s, shape) in SHAPES.iter().enumerate() {
        let u = e1 * shape[0].0 + e2 * shape[0].1;
        let v = e1 * shape[1].0 + e2 * shape[1].1;
        let (k2, d2) = enclosing_radius2(u, v);
        if s == 0 {
            first = (k2, d2);
        }
        largest = (largest.0.max(k2), largest.1.max(d2));
    }
    PatternConstants {
        sqrt_k1: first.0.sqrt(),
        sqrt_k: largest.0.sqrt(),
        diam1: first.1.sqrt(),
        diam: largest.1.sqrt(),
    }
}

/// Upper bounds `(√K₁, √K)` on [`pattern_constants`] from the longest edge `d` of the shapes
/// alone (Jung's theorem, `r² ≤ d²/3`): at most 15 % above them and cheaper, for the normal's
/// radial scale ([`Scale::g`]), which only ever enters beside a larger term.
pub(super) fn jung_scales(e1: Vec3, e2: Vec3) -> (f32, f32) {
    let (mut d1, mut d) = (0.0f32, 0.0f32);
    for (s, shape) in SHAPES.iter().enumerate() {
        let u = e1 * shape[0].0 + e2 * shape[0].1;
        let v = e1 * shape[1].0 + e2 * shape[1].1;
        let d2 = u.length_squared().max(v.length_squared()).max((u - v).length_squared());
        if s == 0 {
            d1 = d2;
        }
        d = d.max(d2);
    }
    ((d1 / 3.0).sqrt(), (d / 3.0).sqrt())
}
