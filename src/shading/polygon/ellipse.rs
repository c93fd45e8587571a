//! The ellipses that the polygon's edges project to (Algorithm 1), their areas in a sector, and
//! sampling the area between two of them in a sector (Algorithms 2 and 3). Twin of
//! `glsl/include/polygon/ellipse.glsl`, operation for operation; `tests/polygon_gpu.rs` checks that
//! the two agree.

use super::arithmetic::{cross_stable, det2, mix, rotate_90};
use super::types::{ITERATION_COUNT, ITERATION_MARGIN};

use glam::{Vec2, Vec3};

/// Algorithm 1: the ellipse that the great circle through `a` and `b` projects to in the
/// xy-plane, as the vector `u` with `C = I + u uᵀ` (points p on it satisfy `pᵀ C p = 1`). With
/// `n = a × b`, `u = ±n.xy / n.z`; the sign is chosen such that the sign bit of `u.x` is the sign
/// of `n.z`: set iff the edge runs clockwise about the zenith (an inner ellipse, see
/// [`is_inner`]). Degenerate ellipses (`n.z = 0`, the great circle passes through the zenith) get
/// `u = (∞, 0)`: they count as outer ellipses (A.2, rule 1).
pub(super) fn ellipse_from_edge(a: Vec3, b: Vec3) -> Vec2 {
    let normal = cross_stable(a, b);
    let scaling = 1.0f32.copysign(normal.x) / normal.z;
    if normal.z == 0.0 || !scaling.is_finite() {
        return Vec2::new(f32::INFINITY, 0.0);
    }
    Vec2::new(normal.x * scaling, normal.y * scaling)
}

/// Whether an ellipse from [`ellipse_from_edge`] is an inner one (its edge runs clockwise about
/// the zenith). Reads the sign bit, so that `u.x = −0` counts (GLSL: `floatBitsToUint`).
pub(super) fn is_inner(ellipse: Vec2) -> bool {
    ellipse.x.is_sign_negative()
}

/// Whether an ellipse from [`ellipse_from_edge`] is degenerate (A.2).
pub(super) fn is_degenerate(ellipse: Vec2) -> bool {
    ellipse.x == f32::INFINITY
}

/// `C p = p + u (u·p)`.
pub(super) fn ellipse_transform(ellipse: Vec2, point: Vec2) -> Vec2 {
    point + ellipse * ellipse.dot(point)
}

/// `pᵀ C p = |p|² + (u·p)²`; the point on the ellipse in direction `p` is `p / √(pᵀ C p)`.
pub(super) fn ellipse_quadratic_form(ellipse: Vec2, point: Vec2) -> f32 {
    let along = ellipse.dot(point);
    along.mul_add(along, point.length_squared())
}

/// `1/√det C = 1/√(1 + |u|²)`; 0 for degenerate ellipses.
pub(super) fn ellipse_rsqrt_det(ellipse: Vec2) -> f32 {
    if is_degenerate(ellipse) {
        return 0.0;
    }
    1.0 / (1.0 + ellipse.length_squared()).sqrt()
}

/// Area of the ellipse within the sector from `dir_0` counterclockwise to `dir_1` (at most
/// 180°), for an ellipse with `rsqrt_det = 1/√det C`: with `C = L Lᵀ`, the map `Lᵀ` turns the
/// ellipse into the unit circle and scales areas by `√det C`, so the area is
/// `atan2(det(s₀, s₁), s₀ᵀ C s₁ / √det C) / (2 √det C)` (supplement Eq. (1)). Zero for degenerate
/// ellipses (A.2, rule 2). The directions need not be normalised.
pub(super) fn ellipse_area_in_sector(ellipse: Vec2, rsqrt_det: f32, dir_0: Vec2, dir_1: Vec2) -> f32 {
    if is_degenerate(ellipse) {
        return 0.0;
    }
    let det_dirs = det2(dir_0, dir_1).max(0.0);
    let dot = rsqrt_det * dir_0.dot(ellipse_transform(ellipse, dir_1));
    0.5 * rsqrt_det * det_dirs.atan2(dot)
}

/// Area between an outer and an inner ellipse within a sector; negative or NaN results (rounding,
/// degenerate input) become 0.
pub(super) fn area_between_ellipses_in_sector(inner: Vec2, outer: Vec2, dir_0: Vec2, dir_1: Vec2) -> f32 {
    let area = ellipse_area_in_sector(outer, ellipse_rsqrt_det(outer), dir_0, dir_1)
        - ellipse_area_in_sector(inner, ellipse_rsqrt_det(inner), dir_0, dir_1);
    if area > 0.0 {
        area
    } else {
        0.0
    }
}

/// Algorithm 2 (Blinn): a non-zero root `w` of the homogeneous quadratic `wᵀ Q w = 0`, given by
/// `Q_xx`, `Q_xy + Q_yx` and `Q_yy`. The root depends continuously on `Q` (Lemma 1).
pub(super) fn solve_homogeneous_quadratic(q_xx: f32, q_xy_plus_yx: f32, q_yy: f32) -> Vec2 {
    let b = 0.5 * q_xy_plus_yx;
    let sqrt_discriminant = (b * b - q_xx * q_yy).max(0.0).sqrt();
    let scaled_root = b.abs() + sqrt_discriminant;
    if b >= 0.0 {
        Vec2::new(scaled_root, -q_xx)
    } else {
        Vec2::new(q_yy, scaled_root)
    }
}

/// The coefficients `(Q_xx, Q_xy + Q_yx, Q_yy)` of `Q = a gᵀ − k · c eᵀ`.
pub(super) fn quadratic_from_outer_products(a: Vec2, g: Vec2, k: f32, c: Vec2, e: Vec2) -> (f32, f32, f32) {
    (
        a.x * g.x - k * c.x * e.x,
        a.x * g.y + a.y * g.x - k * (c.x * e.y + c.y * e.x),
        a.y * g.y - k * c.y * e.y,
    )
}

/// `root` unless it is zero or not finite (a degenerate quadratic), then `fallback`.
pub(super) fn usable_root(root: Vec2, fallback: Vec2) -> Vec2 {
    let size = root.x.abs() + root.y.abs();
    if size > 0.0 && size.is_finite() {
        root
    } else {
        fallback
    }
}

/// Algorithm 3: a point of the xy-plane, uniform in area between the `inner` and `outer` ellipse
/// within the sector from `dir_0` to `dir_1`, where `target_area` (= `u[0]` × the sector's area)
/// is the area between the ellipses from `dir_0` to the sampled direction and `u[1]` places the
/// point between the ellipses (uniform in squared radius). The initialisation splits the sector in
/// half and replaces the ellipse arcs by chords (A.4, exact for the quads); then
/// [`ITERATION_COUNT`] steps replace the arcs by their tangents at the current direction (A.3):
/// with `wᵢ = Cᵢ w`, `wₒ = Cₒ w` and the residual `A_δ`, the next direction solves
/// `xᵀ (R w (wᵢ − wₒ)ᵀ − 2 A_δ wᵢ wₒᵀ) x = 0`. Both homogeneous quadratics are solved in a basis
/// rotated onto the current boundary or direction (see the comments), which keeps thin sectors
/// (polygons that are small as seen from the shading point) accurate. Without `iterate` only the
/// initialisation runs (for sectors whose area is unknown). The result is clamped to the sector.
pub(super) fn sample_sector_between_ellipses(
    u: [f32; 2],
    target_area: f32,
    inner: Vec2,
    outer: Vec2,
    dir_0: Vec2,
    dir_1: Vec2,
    iterate: bool,
) -> Vec2 {
    let s_0 = dir_0.normalize();
    let s_1_full = dir_1.normalize();
    let s_h = s_0 + s_1_full;
    // λ s lies on the ellipse
    let inner_0 = 1.0 / ellipse_quadratic_form(inner, s_0).sqrt();
    let inner_h = 1.0 / ellipse_quadratic_form(inner, s_h).sqrt();
    let inner_1_full = 1.0 / ellipse_quadratic_form(inner, s_1_full).sqrt();
    let outer_0 = 1.0 / ellipse_quadratic_form(outer, s_0).sqrt();
    let outer_h = 1.0 / ellipse_quadratic_form(outer, s_h).sqrt();
    let outer_1_full = 1.0 / ellipse_quadratic_form(outer, s_1_full).sqrt();
    // Areas of the two quads, up to the common factor |det(s_h, s_0)|/2 = |det(s_h, s_1)|/2
    let quad_0 = outer_0 * outer_h - inner_0 * inner_h;
    let quad_1 = outer_h * outer_1_full - inner_h * inner_1_full;
    // Pick a quad; its outer boundary direction goes to index 1. The signed target is measured
    // from that boundary: counterclockwise from s_0 (≥ 0) or clockwise from s_1 (≤ 0).
    let mut quad_target = mix(-quad_0, quad_1, u[0]);
    let first_quad = quad_target <= 0.0;
    let s_1 = if first_quad { s_0 } else { s_1_full };
    let inner_1 = if first_quad { inner_0 } else { inner_1_full };
    let outer_1 = if first_quad { outer_0 } else { outer_1_full };
    quad_target += if first_quad { quad_0 } else { -quad_1 };
    // Twice the signed target area (the ½ cancels against the 2 of the quadratic)
    quad_target *= det2(s_h, s_1).abs();
    // Lines through the quad's inner and outer edge: rₗ·q = Dₗ
    let inner_normal = ellipse_transform(inner, inner_h * s_h + inner_1 * s_1);
    let outer_normal = ellipse_transform(outer, outer_h * s_h + outer_1 * s_1);
    let inner_offset = inner_h * inner_normal.dot(s_h);
    let outer_offset = outer_h * outer_normal.dot(s_h);
    // Q = λₒ₁ Dₒ R s₁ rᵢᵀ − (λᵢ₁ Dᵢ R s₁ + 2 A_q rᵢ) rₒᵀ = R s₁ gᵀ − 2 A_q rᵢ rₒᵀ, written in the
    // basis (s₁, R s₁): there R s₁ = (0, 1) and the form's value at s₁ is the product
    // −2 A_q (rᵢ·s₁)(rₒ·s₁), while in xy-coordinates it would cancel down from entries of order 1
    // (fatal for thin sectors). Lemma 1 and Proposition 3 hold in any rotated basis.
    let e_1 = rotate_90(s_1);
    let g = (outer_1 * outer_offset) * inner_normal - (inner_1 * inner_offset) * outer_normal;
    let (q_xx, q_xy_plus_yx, q_yy) = quadratic_from_outer_products(
        Vec2::Y,
        Vec2::new(g.dot(s_1), g.dot(e_1)),
        quad_target,
        Vec2::new(inner_normal.dot(s_1), inner_normal.dot(e_1)),
        Vec2::new(outer_normal.dot(s_1), outer_normal.dot(e_1)),
    );
    let root = usable_root(solve_homogeneous_quadratic(q_xx, q_xy_plus_yx, q_yy), Vec2::X);
    let mut w = root.x * s_1 + root.y * e_1;
    // Refine, unless at the ends of the sector where the initialisation is exact
    let iterations = if iterate && (ITERATION_MARGIN..=1.0 - ITERATION_MARGIN).contains(&u[0]) {
        ITERATION_COUNT
    } else {
        0
    };
    let inner_rsqrt_det = ellipse_rsqrt_det(inner);
    let outer_rsqrt_det = ellipse_rsqrt_det(outer);
    for iteration in 0..ITERATION_COUNT {
        if iteration >= iterations {
            break;
        }
        // Keep w away from under- and overflow, on the side of the sector
        w *= 1.0 / (w.x.abs() + w.y.abs());
        if w.dot(s_h) < 0.0 {
            w = -w;
        }
        let inner_w = ellipse_transform(inner, w);
        let outer_w = ellipse_transform(outer, w);
        let det_dirs = det2(s_0, w).max(0.0);
        let area = 0.5
            * (outer_rsqrt_det * det_dirs.atan2(outer_rsqrt_det * s_0.dot(outer_w))
                - inner_rsqrt_det * det_dirs.atan2(inner_rsqrt_det * s_0.dot(inner_w)));
        let residual = target_area - area;
        // T = R w (wᵢ − wₒ)ᵀ − 2 A_δ wᵢ wₒᵀ in the basis (w, R w), for the same reason as Q:
        // wᵀ T w = −2 A_δ (wᵀCᵢw)(wᵀCₒw), and wᵀ(Cᵢ − Cₒ)w = (uᵢ·w)² − (uₒ·w)² is factored.
        let w_perp = rotate_90(w);
        let (inner_along, outer_along) = (inner.dot(w), outer.dot(w));
        let difference_along = (inner_along - outer_along) * (inner_along + outer_along);
        let (t_xx, t_xy_plus_yx, t_yy) = quadratic_from_outer_products(
            Vec2::new(0.0, w.length_squared()),
            Vec2::new(difference_along, (inner_w - outer_w).dot(w_perp)),
            2.0 * residual,
            Vec2::new(inner_w.dot(w), inner_w.dot(w_perp)),
            Vec2::new(outer_w.dot(w), outer_w.dot(w_perp)),
        );
        let root = usable_root(solve_homogeneous_quadratic(t_xx, t_xy_plus_yx, t_yy), Vec2::X);
        w = root.x * w + root.y * w_perp;
    }
    // The half sectors span at most 90°, so the root on the side of s_h is the right one
    if w.dot(s_h) < 0.0 {
        w = -w;
    }
    // Stay in the sector even when rounding dominates the areas (slivers a few ε wide)
    if det2(s_0, w) < 0.0 {
        w = s_0;
    } else if det2(w, s_1_full) < 0.0 {
        w = s_1_full;
    }
    // Uniform in squared radius between the two ellipses
    let inner_squared_radius = 1.0 / ellipse_quadratic_form(inner, w);
    let outer_squared_radius = 1.0 / ellipse_quadratic_form(outer, w);
    w * mix(inner_squared_radius, outer_squared_radius, u[1]).max(0.0).sqrt()
}
