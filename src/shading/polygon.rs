//! Polygonal area lights seen from one shading point: clipping to the horizon, the closed-form
//! projected solid angle, projected-solid-angle sampling, solid-angle sampling of triangle fans,
//! clamped optimal MIS weights and a fixed low-discrepancy point set. This is the CPU reference of
//! the GLSL twin `glsl/include/polygon.glsl`, which follows it function for function (so
//! everything here is f32, works on fixed-size arrays with a vertex count, allocates nothing,
//! never recurses and loops only over fixed bounds); `tests/polygon_gpu.rs` checks that the two
//! agree. The twin emulates `mul_add` and `atan2`, which GLSL does not guarantee to the accuracy
//! used here.
//!
//! All directions live in the local shading frame: the shading normal is +z, and a polygon is
//! given by its vertices relative to the shading point (convex, planar, at most
//! [`MAX_POLYGON_VERTICES`] vertices, either winding; emission is treated as two-sided).
//!
//! The methods are those of C. Peters, "BRDF Importance Sampling for Polygonal Lights" (ACM TOG
//! 40(4), 2021) and its supplemental document:
//! - A.1: [`clip_to_horizon`] (a plain fixed-bound clipper instead of the generated switch; new
//!   vertices from 2×2 determinants by Kahan's algorithm, accurate also next to the shading
//!   point).
//! - A.2: great circles through the zenith (degenerate ellipses, `u.x = ∞`, zero sector area,
//!   degenerate-first tie break in the sort).
//! - A.3/A.4 and Algorithms 1–4: [`prepare_projected_solid_angle`],
//!   [`sample_projected_solid_angle`] (an odd-even transposition sort replaces the optimal
//!   bitonic sorting networks of A.6, which only exist up to eight vertices).
//! - B.3: [`clamped_optimal_mis_weights`].
//! - C and Algorithm 5: [`prepare_solid_angle`], [`sample_solid_angle`] with the Householder
//!   determinant.
//!
//! Three deliberate deviations, all for accuracy with lights that are small as seen from the
//! shading point (the tests cover polygons 10⁻⁴ wide at distance 1):
//! - [`projected_solid_angle`] evaluates Lambert's edge sum `½ Σ γⱼ n̂ⱼ·z` as "shoelace of the
//!   unit vertex directions + per-edge segment terms `(γ/sin γ − 1)(v̂ⱼ × v̂ⱼ₊₁)·z`", with the
//!   differences of unit directions formed without cancellation. The plain sum loses about
//!   `ε / size` relative accuracy. Sampling densities are normalised by this value; the per-
//!   sector areas of Algorithm 4 only select a sector.
//! - Algorithm 3 solves its homogeneous quadratics in a basis rotated onto the sector boundary
//!   (initialisation) or the current direction (iteration). In xy-coordinates the quadratic form
//!   of the initialisation is tiny (∝ size²) next to its entries (∝ 1) and thin sectors sample
//!   outside the polygon; rotated, its small coefficients are products and stay accurate.
//! - The determinant of Algorithm 5 is the Householder one of Sec. C applied to the columns
//!   `v̂ⱼ − v̂₀` (same determinant), which removes the remaining `ε / size` error of normalising;
//!   its `t' = √((1 − s²)/(1 − s₂²))` is evaluated as `√(ξ₁ (1 + s)/(1 + s₂))`.
//!
//! What remains: the per-sector areas of the ellipse representation carry a relative error of
//! about `ε / size`, so for a polygon 10⁻⁴ wide samples are uniform to about 10⁻³ (still inside);
//! and since z is rebuilt from xy, directions near the horizon are accurate to about `ε / z`. In
//! the decentral case a sector bounded by an edge whose great circle passes within rounding of the
//! zenith (|u| > 10³, A.2 up to rounding) is too thin to sample in f32 (the ray from the zenith
//! meets that great circle at a grazing angle); such sectors get no area, like the exactly
//! degenerate ones of rule 2, which leaves out a sliver of relative size of order 1/|u| (the
//! density stays normalised by the closed form, so diffuse estimates are unaffected). If rounding
//! swamps every sector area, sectors are selected by angle (see [`prepare_projected_solid_angle`]).
//! A sweep over 10⁶ random polygons (the distribution of the test `random_polygons_sample_inside`,
//! 2.6·10⁷ samples) found no sample farther outside than 2·10⁻⁶ + 4ε/z radians.

#![allow(clippy::needless_range_loop)] // index loops with fixed bounds mirror the GLSL twin

use glam::{Vec2, Vec3};

/// Most vertices a light polygon may have.
pub const MAX_POLYGON_VERTICES: usize = 8;
/// Most vertices a polygon clipped to the horizon may have.
pub const MAX_CLIPPED_VERTICES: usize = MAX_POLYGON_VERTICES + 1;
/// Most triangles in the fan of a clipped polygon.
const MAX_FAN_TRIANGLES: usize = MAX_CLIPPED_VERTICES - 2;
/// The visibility estimate `v` of clamped optimal MIS that the paper uses throughout (B.3).
pub const DEFAULT_MIS_VISIBILITY: f32 = 0.5;
/// A projected solid angle or solid angle below this fraction of the magnitude of the terms it
/// is summed from is rounding noise (e.g. the shading point in the polygon's plane): it counts
/// as zero.
const EMPTY_RELATIVE_THRESHOLD: f32 = 32.0 * f32::EPSILON;
/// Directions this close (in radians) outside an edge's great circle still count as inside, so
/// that samples rounded onto the wrong side of an edge keep their density.
const INSIDE_TOLERANCE: f32 = 4.0 * f32::EPSILON;
/// Algorithm 3 skips the iteration when the sector-relative random number is this close to 0
/// or 1: the initialisation is exact there and the iteration may be unstable.
const ITERATION_MARGIN: f32 = 1.0e-5;
/// |u|² above which an ellipse counts as nearly degenerate in the decentral case (see
/// [`prepare_projected_solid_angle`]).
const STEEP_ELLIPSE_SQUARED: f32 = 1.0e6;
/// Iterations of Algorithm 3 (the paper's choice: local cubic convergence, A.5).
const ITERATION_COUNT: usize = 2;

/// A convex planar polygon as a fixed-size vertex array plus a count (the GLSL layout). Vertices
/// are positions relative to the shading point in the shading frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polygon {
    /// The vertices; only the first `count` are meaningful.
    pub vertices: [Vec3; MAX_CLIPPED_VERTICES],
    /// The number of vertices; 0 means empty.
    pub count: usize,
}

impl Polygon {
    /// The polygon without vertices.
    pub const EMPTY: Polygon = Polygon { vertices: [Vec3::ZERO; MAX_CLIPPED_VERTICES], count: 0 };

    /// A polygon from at most [`MAX_CLIPPED_VERTICES`] vertices.
    pub fn new(vertices: &[Vec3]) -> Polygon {
        assert!(vertices.len() <= MAX_CLIPPED_VERTICES, "at most {MAX_CLIPPED_VERTICES} vertices");
        let mut polygon = Polygon::EMPTY;
        polygon.vertices[..vertices.len()].copy_from_slice(vertices);
        polygon.count = vertices.len();
        polygon
    }

    /// The meaningful vertices.
    pub fn as_slice(&self) -> &[Vec3] {
        &self.vertices[..self.count]
    }
}

/// Index of the vertex after `j` in a polygon with `count` vertices.
fn next_index(j: usize, count: usize) -> usize {
    if j + 1 == count {
        0
    } else {
        j + 1
    }
}

/// `a·b − c·d` with at most 1.5 ulps of error (Kahan's algorithm with one fma).
fn kahan(a: f32, b: f32, c: f32, d: f32) -> f32 {
    let cd = c * d;
    let error = c.mul_add(d, -cd);
    a.mul_add(b, -cd) - error
}

/// The cross product with every component evaluated by [`kahan`].
fn cross_stable(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(kahan(a.y, b.z, a.z, b.y), kahan(a.z, b.x, a.x, b.z), kahan(a.x, b.y, a.y, b.x))
}

/// `det(a, b) = a.x·b.y − a.y·b.x`; positive iff `b` is counterclockwise of `a` (within 180°).
/// Agrees bit for bit with the z-component of [`cross_stable`].
fn det2(a: Vec2, b: Vec2) -> f32 {
    kahan(a.x, b.y, a.y, b.x)
}

/// `v` rotated by 90° counterclockwise (the paper's `R v`).
fn rotate_90(v: Vec2) -> Vec2 {
    Vec2::new(-v.y, v.x)
}

/// `(1 − t)·a + t·b` with two fmas, exact at both ends.
fn mix(a: f32, b: f32, t: f32) -> f32 {
    t.mul_add(b, (-t).mul_add(a, a))
}

/// `a/|a| − b/|b|` for non-zero `a`, `b`, with a small relative error even when the two
/// directions nearly agree (normalising first leaves an absolute error of about ε, and so does
/// `(a − b)/|a| + …` when `a` and `b` differ mostly in length). With θ the angle between them:
/// `â − b̂ = b̂ × (â × b̂) − (1 − cos θ) b̂`, where `a × b` is evaluated by [`cross_stable`] and
/// `1 − cos θ = sin²θ / (1 + cos θ)` while `cos θ > 0`.
fn unit_difference(a: Vec3, b: Vec3) -> Vec3 {
    let length_b = b.length();
    let inverse_lengths = 1.0 / (a.length() * length_b);
    let normal = cross_stable(a, b);
    let sine = normal.length() * inverse_lengths;
    let cosine = a.dot(b) * inverse_lengths;
    let one_minus_cosine = if cosine > 0.0 { sine * sine / (1.0 + cosine) } else { 1.0 - cosine };
    b.cross(normal) * (inverse_lengths / length_b) - b * (one_minus_cosine / length_b)
}

/// Clips a convex polygon (3 to [`MAX_POLYGON_VERTICES`] vertices) to the closed upper half-space
/// z ≥ 0 (supplement A.1). Vertices with z ≥ 0 are kept; every edge that strictly crosses z = 0
/// gets a new vertex with z = 0 exactly, so vertices lying on the horizon are never duplicated.
/// The winding is kept. A result with fewer than three vertices is empty (count 0). A convex
/// planar input yields at most [`MAX_CLIPPED_VERTICES`] vertices; an input that would yield more
/// (only possible when it is not planar) also yields the empty polygon.
pub fn clip_to_horizon(polygon: &Polygon) -> Polygon {
    let mut clipped = Polygon::EMPTY;
    let count = polygon.count;
    if !(3..=MAX_CLIPPED_VERTICES).contains(&count) {
        return clipped;
    }
    let mut out = 0;
    let mut overflow = false;
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        let a = polygon.vertices[j];
        let b = polygon.vertices[next_index(j, count)];
        if a.z >= 0.0 {
            if out < MAX_CLIPPED_VERTICES {
                clipped.vertices[out] = a;
                out += 1;
            } else {
                overflow = true;
            }
        }
        if (a.z > 0.0 && b.z < 0.0) || (a.z < 0.0 && b.z > 0.0) {
            // (p.xy q.z − q.xy p.z) / (q.z − p.z) with p above and q below (so that both traversal
            // directions of an edge give the same point): each numerator is a 2×2 determinant, and
            // Kahan's algorithm keeps the crossing accurate to a few ulps even close to the shading
            // point (p + t (q − p) would leave an absolute error of ε|p|).
            let (p, q) = if a.z > 0.0 { (a, b) } else { (b, a) };
            let inverse_height = 1.0 / (q.z - p.z);
            let crossing = Vec3::new(
                kahan(p.x, q.z, q.x, p.z) * inverse_height,
                kahan(p.y, q.z, q.y, p.z) * inverse_height,
                0.0,
            );
            if out < MAX_CLIPPED_VERTICES {
                clipped.vertices[out] = crossing;
                out += 1;
            } else {
                overflow = true;
            }
        }
    }
    clipped.count = if out >= 3 && !overflow { out } else { 0 };
    clipped
}

/// `γ/sin γ − 1` times `c.z` for an edge with `c = v̂ⱼ × v̂ⱼ₊₁` (`|c| = sin γ`) and `cos γ`. A
/// series near 0 keeps the relative accuracy of this small term; an edge between antipodal
/// directions (only when the polygon's plane contains the shading point) contributes 0.
fn edge_segment_term(c: Vec3, cos_angle: f32) -> f32 {
    let sine = c.length();
    let angle = sine.atan2(cos_angle);
    if angle < 0.5 {
        // x/sin x − 1 = x²/6 + 7x⁴/360 + 31x⁶/15120 + 127x⁸/604800 + 73x¹⁰/3421440 + O(x¹²)
        let x2 = angle * angle;
        let series = x2
            * (1.0 / 6.0
                + x2 * (7.0 / 360.0
                    + x2 * (31.0 / 15120.0 + x2 * (127.0 / 604800.0 + x2 * (73.0 / 3421440.0)))));
        series * c.z
    } else if sine > 0.0 {
        angle * (c.z / sine) - c.z
    } else {
        0.0
    }
}

/// The signed projected solid angle (positive iff the polygon winds counterclockwise about +z)
/// of a polygon on or above the horizon, and 0 for an empty or degenerate one. See
/// [`projected_solid_angle`].
fn signed_projected_solid_angle(polygon: &Polygon) -> f32 {
    let count = polygon.count;
    if count < 3 {
        return 0.0;
    }
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        if polygon.vertices[j] == Vec3::ZERO {
            // A vertex at the shading point: the polygon's plane contains it.
            return 0.0;
        }
    }
    let origin = polygon.vertices[0];
    let mut fan = 0.0;
    let mut segments = 0.0;
    let mut magnitude = 0.0;
    let mut previous_offset = Vec3::ZERO;
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        let a = polygon.vertices[j];
        let b = polygon.vertices[next_index(j, count)];
        // Shoelace term of the projected unit directions, relative to direction 0
        let offset = unit_difference(b, origin);
        let shoelace = kahan(previous_offset.x, offset.y, previous_offset.y, offset.x);
        previous_offset = offset;
        // Curved part of the edge: the great-circle arc bulges beyond its chord
        let edge = unit_difference(b, a);
        let c = cross_stable(a.normalize(), edge);
        let segment = edge_segment_term(c, 1.0 - 0.5 * edge.length_squared());
        fan += shoelace;
        segments += segment;
        magnitude += shoelace.abs() + segment.abs();
    }
    let total = 0.5 * (fan + segments);
    if total.abs() > 0.5 * EMPTY_RELATIVE_THRESHOLD * magnitude {
        total
    } else {
        0.0
    }
}

/// The projected solid angle `∫ cos θ dω` of a polygon clipped to the horizon (e.g. by
/// [`clip_to_horizon`]), in closed form: Lambert's sum over the edges `½ Σ γⱼ (n̂ⱼ·z)` with `γⱼ`
/// the angle the edge subtends and `n̂ⱼ` the unit normal of the plane through the shading point
/// and the edge. It equals π × the irradiance factor: a Lambertian emitter of radiance `L` lights
/// a diffuse surface whose BRDF value is `kd` (this project's convention) with outgoing radiance
/// `kd · L · projected_solid_angle`. Either winding gives the same (non-negative) value. The sum
/// is evaluated as shoelace + segment terms (see the module documentation), accurate to a few ulps
/// also for tiny polygons. Empty polygons, polygons below the horizon (after clipping), edge-on
/// polygons (the shading point in their plane) and zero-length edges give 0 or contribute 0.
pub fn projected_solid_angle(clipped: &Polygon) -> f32 {
    signed_projected_solid_angle(clipped).abs()
}

/// Converts a density with respect to projected solid angle into one with respect to solid
/// angle: multiplies by `cos θ = direction.z` (0 below the horizon). `direction` is a unit vector.
pub fn projected_to_solid_angle_density(projected_density: f32, direction: Vec3) -> f32 {
    projected_density * direction.z.max(0.0)
}

/// Algorithm 1: the ellipse that the great circle through `a` and `b` projects to in the
/// xy-plane, as the vector `u` with `C = I + u uᵀ` (points p on it satisfy `pᵀ C p = 1`). With
/// `n = a × b`, `u = ±n.xy / n.z`; the sign is chosen such that the sign bit of `u.x` is the sign
/// of `n.z`: set iff the edge runs clockwise about the zenith (an inner ellipse, see
/// [`is_inner`]). Degenerate ellipses (`n.z = 0`, the great circle passes through the zenith) get
/// `u = (∞, 0)`: they count as outer ellipses (A.2, rule 1).
fn ellipse_from_edge(a: Vec3, b: Vec3) -> Vec2 {
    let normal = cross_stable(a, b);
    let scaling = 1.0f32.copysign(normal.x) / normal.z;
    if normal.z == 0.0 || !scaling.is_finite() {
        return Vec2::new(f32::INFINITY, 0.0);
    }
    Vec2::new(normal.x * scaling, normal.y * scaling)
}

/// Whether an ellipse from [`ellipse_from_edge`] is an inner one (its edge runs clockwise about
/// the zenith). Reads the sign bit, so that `u.x = −0` counts (GLSL: `floatBitsToUint`).
fn is_inner(ellipse: Vec2) -> bool {
    ellipse.x.is_sign_negative()
}

/// Whether an ellipse from [`ellipse_from_edge`] is degenerate (A.2).
fn is_degenerate(ellipse: Vec2) -> bool {
    ellipse.x == f32::INFINITY
}

/// `C p = p + u (u·p)`.
fn ellipse_transform(ellipse: Vec2, point: Vec2) -> Vec2 {
    point + ellipse * ellipse.dot(point)
}

/// `pᵀ C p = |p|² + (u·p)²`; the point on the ellipse in direction `p` is `p / √(pᵀ C p)`.
fn ellipse_quadratic_form(ellipse: Vec2, point: Vec2) -> f32 {
    let along = ellipse.dot(point);
    along.mul_add(along, point.length_squared())
}

/// `1/√det C = 1/√(1 + |u|²)`; 0 for degenerate ellipses.
fn ellipse_rsqrt_det(ellipse: Vec2) -> f32 {
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
fn ellipse_area_in_sector(ellipse: Vec2, rsqrt_det: f32, dir_0: Vec2, dir_1: Vec2) -> f32 {
    if is_degenerate(ellipse) {
        return 0.0;
    }
    let det_dirs = det2(dir_0, dir_1).max(0.0);
    let dot = rsqrt_det * dir_0.dot(ellipse_transform(ellipse, dir_1));
    0.5 * rsqrt_det * det_dirs.atan2(dot)
}

/// Area between an outer and an inner ellipse within a sector; negative or NaN results (rounding,
/// degenerate input) become 0.
fn area_between_ellipses_in_sector(inner: Vec2, outer: Vec2, dir_0: Vec2, dir_1: Vec2) -> f32 {
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
fn solve_homogeneous_quadratic(q_xx: f32, q_xy_plus_yx: f32, q_yy: f32) -> Vec2 {
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
fn quadratic_from_outer_products(a: Vec2, g: Vec2, k: f32, c: Vec2, e: Vec2) -> (f32, f32, f32) {
    (
        a.x * g.x - k * c.x * e.x,
        a.x * g.y + a.y * g.x - k * (c.x * e.y + c.y * e.x),
        a.y * g.y - k * c.y * e.y,
    )
}

/// `root` unless it is zero or not finite (a degenerate quadratic), then `fallback`.
fn usable_root(root: Vec2, fallback: Vec2) -> Vec2 {
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
fn sample_sector_between_ellipses(
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

/// Everything projected-solid-angle sampling needs from one polygon and shading point (the
/// first half of Algorithm 4): plain, fixed-size and `Copy`, like its GLSL twin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectedSolidAngleSampler {
    /// Vertex count; 0 when there is nothing to sample.
    count: usize,
    /// The clipped polygon, counterclockwise about +z (for [`projected_solid_angle_density`]).
    vertices: [Vec3; MAX_CLIPPED_VERTICES],
    /// Sector boundary directions: vertex xy in polygon order (central case) or sorted
    /// counterclockwise (decentral case).
    sector_dirs: [Vec2; MAX_CLIPPED_VERTICES],
    /// Per sector boundary the ellipse of the next edge counterclockwise (Algorithm 4).
    ellipses: [Vec2; MAX_CLIPPED_VERTICES],
    /// The inner ellipse of the first sector; not inner (`(1, 0)`) in the central case.
    inner_ellipse_0: Vec2,
    /// Projected solid angle per sector (used to select a sector).
    sector_areas: [f32; MAX_CLIPPED_VERTICES],
    /// Sum of `sector_areas`.
    sector_total: f32,
    /// Whether `sector_areas` hold sector angles instead (all areas were lost to rounding).
    proxy_sector_areas: bool,
    /// The closed-form projected solid angle (normalises the density).
    projected_solid_angle: f32,
}

impl ProjectedSolidAngleSampler {
    /// The sampler of an empty polygon.
    pub const EMPTY: ProjectedSolidAngleSampler = ProjectedSolidAngleSampler {
        count: 0,
        vertices: [Vec3::ZERO; MAX_CLIPPED_VERTICES],
        sector_dirs: [Vec2::ZERO; MAX_CLIPPED_VERTICES],
        ellipses: [Vec2::ZERO; MAX_CLIPPED_VERTICES],
        inner_ellipse_0: Vec2::X,
        sector_areas: [0.0; MAX_CLIPPED_VERTICES],
        sector_total: 0.0,
        proxy_sector_areas: false,
        projected_solid_angle: 0.0,
    };

    /// The closed-form projected solid angle of the polygon ([`projected_solid_angle`]).
    pub fn projected_solid_angle(&self) -> f32 {
        self.projected_solid_angle
    }

    /// Whether there is nothing to sample (zero projected solid angle); samples then have
    /// density 0.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// Whether the polygon contains the zenith (the central case of the paper), where each
    /// sector is bounded by a single ellipse.
    pub fn is_central(&self) -> bool {
        !is_inner(self.inner_ellipse_0)
    }
}

/// Compares sector boundaries `lhs < rhs` and swaps them (with their ellipses) when `rhs` is
/// clockwise of `lhs`; on a tie (the same direction) a degenerate ellipse goes first (A.2,
/// rule 3). [`det2`] agrees exactly with the z-component of [`cross_stable`] used for the edges,
/// so the two vertices of a degenerate edge tie exactly.
fn compare_and_swap(sampler: &mut ProjectedSolidAngleSampler, lhs: usize, rhs: usize) {
    let det = det2(sampler.sector_dirs[lhs], sampler.sector_dirs[rhs]);
    let swap = det < 0.0
        || (det == 0.0 && is_degenerate(sampler.ellipses[rhs]) && !is_degenerate(sampler.ellipses[lhs]));
    if swap {
        sampler.sector_dirs.swap(lhs, rhs);
        sampler.ellipses.swap(lhs, rhs);
    }
}

/// Prepares projected-solid-angle sampling of a polygon clipped to the horizon (the first half of
/// Algorithm 4). Either winding is accepted. Assigns to each vertex the ellipse of the next edge
/// counterclockwise about the zenith; if some edge runs clockwise the zenith is outside
/// (decentral case): the vertices are sorted counterclockwise and every sector lies between an
/// inner and an outer ellipse, else (central case) each sector is bounded by one ellipse. In the
/// decentral case, sectors bounded by a nearly degenerate ellipse get no area (module
/// documentation), and if rounding leaves no sector with area, sectors are weighted by their angle
/// and sampled without Algorithm 3's iteration (only polygons a few ε thin as seen from the
/// shading point); the density is the closed form's either way.
pub fn prepare_projected_solid_angle(clipped: &Polygon) -> ProjectedSolidAngleSampler {
    let mut sampler = ProjectedSolidAngleSampler::EMPTY;
    let count = clipped.count;
    let signed = signed_projected_solid_angle(clipped);
    if count < 3 || signed == 0.0 || !signed.is_finite() {
        return sampler;
    }
    // Counterclockwise about +z
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        sampler.vertices[j] = clipped.vertices[if signed > 0.0 { j } else { count - 1 - j }];
        sampler.sector_dirs[j] = sampler.vertices[j].truncate();
    }
    // Associate vertices with ellipses (Algorithm 4): an outer edge j starts at vertex j in
    // angular order, an inner edge j at vertex j + 1. The inner edge that ends at the clockwise
    // end of the polygon would be lost; it is the inner ellipse of the first sector.
    let ellipse_0 = ellipse_from_edge(sampler.vertices[0], sampler.vertices[1]);
    let mut previous = ellipse_0;
    for j in 1..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        let current = ellipse_from_edge(sampler.vertices[j], sampler.vertices[next_index(j, count)]);
        sampler.ellipses[j] = if is_inner(current) { previous } else { current };
        if is_inner(previous) && !is_inner(current) {
            sampler.inner_ellipse_0 = previous;
        }
        previous = current;
    }
    sampler.ellipses[0] = if is_inner(ellipse_0) { previous } else { ellipse_0 };
    if is_inner(previous) && !is_inner(ellipse_0) {
        sampler.inner_ellipse_0 = previous;
    }
    // Projected solid angle per sector
    let mut total = 0.0;
    if sampler.is_central() {
        for j in 0..MAX_CLIPPED_VERTICES {
            if j >= count {
                break;
            }
            let ellipse = sampler.ellipses[j];
            let area = ellipse_area_in_sector(
                ellipse,
                ellipse_rsqrt_det(ellipse),
                sampler.sector_dirs[j],
                sampler.sector_dirs[next_index(j, count)],
            );
            sampler.sector_areas[j] = area;
            total += area;
        }
    } else {
        // Odd-even transposition sort: `count` passes sort `count` elements. The vertices span
        // less than 180° about the zenith, so "counterclockwise of" is a strict order.
        for pass in 0..MAX_CLIPPED_VERTICES {
            if pass >= count {
                break;
            }
            for k in 0..MAX_CLIPPED_VERTICES / 2 {
                let lhs = 2 * k + (pass & 1);
                if lhs + 1 < count {
                    compare_and_swap(&mut sampler, lhs, lhs + 1);
                }
            }
        }
        let mut inner = sampler.inner_ellipse_0;
        let mut outer = sampler.ellipses[0];
        for j in 0..MAX_CLIPPED_VERTICES - 1 {
            if j + 1 >= count {
                break;
            }
            if j > 0 {
                let ellipse = sampler.ellipses[j];
                if is_inner(ellipse) {
                    inner = ellipse;
                } else {
                    outer = ellipse;
                }
            }
            // Near-degenerate ellipses (A.2 with rounding) bound sectors too thin to sample in f32
            let steep = inner.length_squared().max(outer.length_squared()) > STEEP_ELLIPSE_SQUARED;
            let area = if steep {
                0.0
            } else {
                area_between_ellipses_in_sector(
                    inner,
                    outer,
                    sampler.sector_dirs[j],
                    sampler.sector_dirs[j + 1],
                )
            };
            sampler.sector_areas[j] = area;
            total += area;
        }
    }
    if !sampler.is_central() && total <= 0.0 {
        // Rounding swamped every sector area (the xy-plane resolves a polygon near the horizon
        // only to ε/z radians): select sectors by their angle instead and sample them without the
        // area-based iteration. The density stays 1/Ω_proj: exact for the diffuse part.
        sampler.proxy_sector_areas = true;
        total = 0.0;
        for j in 0..MAX_CLIPPED_VERTICES - 1 {
            if j + 1 >= count {
                break;
            }
            let angle = det2(sampler.sector_dirs[j].normalize(), sampler.sector_dirs[j + 1].normalize());
            sampler.sector_areas[j] = angle.max(0.0);
            total += sampler.sector_areas[j];
        }
    }
    if !(total > 0.0 && total.is_finite()) {
        return ProjectedSolidAngleSampler::EMPTY;
    }
    sampler.count = count;
    sampler.sector_total = total;
    sampler.projected_solid_angle = signed.abs();
    sampler
}

/// Samples a direction uniformly with respect to projected solid angle within the polygon (the
/// second half of Algorithm 4) from `u ∈ [0, 1)²`. Returns the unit direction (z ≥ 0) and its
/// density with respect to projected solid angle, `1 / projected_solid_angle`; convert with
/// [`projected_to_solid_angle_density`]. An empty sampler returns `(+z, 0)`.
pub fn sample_projected_solid_angle(sampler: &ProjectedSolidAngleSampler, u: [f32; 2]) -> (Vec3, f32) {
    if sampler.is_empty() {
        return (Vec3::Z, 0.0);
    }
    let count = sampler.count;
    let mut target = u[0] * sampler.sector_total;
    // Select the sector; a target beyond the last non-empty sector (rounding) clamps to its end
    let mut selected_area = 0.0;
    let mut selected_target = 0.0;
    let mut dir_0 = Vec2::X;
    let mut dir_1 = Vec2::Y;
    let mut inner = sampler.inner_ellipse_0;
    let mut outer = sampler.ellipses[0];
    let mut selected_inner = inner;
    let mut selected_outer = outer;
    let central = sampler.is_central();
    let sector_count = if central { count } else { count - 1 };
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= sector_count {
            break;
        }
        let ellipse = sampler.ellipses[j];
        if central || j == 0 {
            outer = ellipse;
        } else if is_inner(ellipse) {
            inner = ellipse;
        } else {
            outer = ellipse;
        }
        let area = sampler.sector_areas[j];
        if area > 0.0 {
            selected_area = area;
            selected_target = target.min(area);
            selected_inner = inner;
            selected_outer = outer;
            dir_0 = sampler.sector_dirs[j];
            dir_1 = sampler.sector_dirs[next_index(j, count)];
        }
        if target < area {
            break;
        }
        target -= area;
    }
    let w = if central {
        // Rotate s₀ within the ellipse: with C = L Lᵀ, the angle about the origin in the space
        // mapped by Lᵀ is 2 √det C × area, and back in the plane that rotation is
        // cos φ · √det C · s₀ + sin φ · R C s₀ (up to a positive factor).
        let sqrt_det = (1.0 + selected_outer.length_squared()).sqrt();
        let angle = 2.0 * selected_target * sqrt_det;
        let direction = (angle.cos() * sqrt_det) * dir_0
            + angle.sin() * rotate_90(ellipse_transform(selected_outer, dir_0));
        // Uniform in squared radius inside the ellipse
        direction * (u[1] / ellipse_quadratic_form(selected_outer, direction)).max(0.0).sqrt()
    } else {
        let sector_u = [(selected_target / selected_area).min(1.0), u[1]];
        sample_sector_between_ellipses(
            sector_u,
            selected_target,
            selected_inner,
            selected_outer,
            dir_0,
            dir_1,
            !sampler.proxy_sector_areas,
        )
    };
    let z = (1.0 - w.length_squared()).max(0.0).sqrt();
    (w.extend(z), 1.0 / sampler.projected_solid_angle)
}

/// Whether the unit `direction` lies in the convex spherical polygon (vertices in `vertices`,
/// winding given by `orientation` = ±1), up to [`INSIDE_TOLERANCE`] radians.
fn is_inside(
    vertices: &[Vec3; MAX_CLIPPED_VERTICES],
    count: usize,
    orientation: f32,
    direction: Vec3,
) -> bool {
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        let normal = cross_stable(vertices[j], vertices[next_index(j, count)]) * orientation;
        if normal.dot(direction) < -INSIDE_TOLERANCE * normal.length() {
            return false;
        }
    }
    true
}

/// The density with respect to projected solid angle with which [`sample_projected_solid_angle`]
/// produces the unit `direction`: `1 / projected_solid_angle` inside the clipped polygon, 0
/// outside, below the horizon or for an empty sampler. For MIS with other techniques.
pub fn projected_solid_angle_density(sampler: &ProjectedSolidAngleSampler, direction: Vec3) -> f32 {
    if sampler.is_empty()
        || direction.z <= 0.0
        || !is_inside(&sampler.vertices, sampler.count, 1.0, direction)
    {
        return 0.0;
    }
    1.0 / sampler.projected_solid_angle
}

/// Everything solid-angle sampling needs from one polygon and shading point: the polygon as a
/// triangle fan around vertex 0, with the per-triangle quantities of Algorithm 5. Plain,
/// fixed-size and `Copy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolidAngleSampler {
    /// Vertex count; 0 when there is nothing to sample.
    count: usize,
    /// Unit directions to the vertices.
    directions: [Vec3; MAX_CLIPPED_VERTICES],
    /// For the fan triangle j with vertices (v̂ⱼ₊₁, v̂₀, v̂ⱼ₊₂): (G₀, G₁, G₂) of Algorithm 5, i.e.
    /// |det(v̂ⱼ₊₁, v̂₀, v̂ⱼ₊₂)|, v̂ⱼ₊₁·v̂ⱼ₊₂ + v̂₀·v̂ⱼ₊₂ and 1 + v̂ⱼ₊₁·v̂₀.
    triangles: [Vec3; MAX_FAN_TRIANGLES],
    /// Solid angle of the fan up to and including triangle j.
    fan_solid_angles: [f32; MAX_FAN_TRIANGLES],
    /// Total solid angle.
    solid_angle: f32,
    /// The sign `o` (±1, from the winding) such that `o (v̂ⱼ × v̂ⱼ₊₁)·ω ≥ 0` for every edge j
    /// exactly when ω is inside.
    orientation: f32,
}

impl SolidAngleSampler {
    /// The sampler of an empty polygon.
    pub const EMPTY: SolidAngleSampler = SolidAngleSampler {
        count: 0,
        directions: [Vec3::ZERO; MAX_CLIPPED_VERTICES],
        triangles: [Vec3::ZERO; MAX_FAN_TRIANGLES],
        fan_solid_angles: [0.0; MAX_FAN_TRIANGLES],
        solid_angle: 0.0,
        orientation: 1.0,
    };

    /// The solid angle of the polygon.
    pub fn solid_angle(&self) -> f32 {
        self.solid_angle
    }

    /// Whether there is nothing to sample (zero solid angle); samples then have density 0.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }
}

/// Prepares solid-angle sampling of a convex polygon (3 to [`MAX_CLIPPED_VERTICES`] vertices,
/// clipped or not, either winding): splits it into the fan of triangles (v̂ⱼ₊₁, v̂₀, v̂ⱼ₊₂) and
/// computes each triangle's solid angle `2 atan2(G₀, G₁ + G₂)` (van Oosterom and Strackee). `G₀`,
/// the determinant, uses the Householder reflection `H` that maps v̂₀ to ±e₀ (Sec. C): applied to
/// the columns `v̂ⱼ − v̂₀` (formed without cancellation) it leaves a 2×2 minor of small, accurate
/// numbers.
pub fn prepare_solid_angle(polygon: &Polygon) -> SolidAngleSampler {
    let mut sampler = SolidAngleSampler::EMPTY;
    let count = polygon.count;
    if !(3..=MAX_CLIPPED_VERTICES).contains(&count) {
        return sampler;
    }
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        if polygon.vertices[j] == Vec3::ZERO {
            return sampler;
        }
        sampler.directions[j] = polygon.vertices[j].normalize();
    }
    let origin = polygon.vertices[0];
    let apex = sampler.directions[0];
    // H = I − 2hhᵀ with h ∝ v̂₀ − σe₀ maps v̂₀ to σe₀. For a vector d, (Hd).yz =
    // d.yz − v̂₀.yz (v̂₀·d − σ d.x) / (|v̂₀.x| + 1).
    let sigma = if apex.x > 0.0 { -1.0 } else { 1.0 };
    let householder_yz = Vec2::new(apex.y, apex.z) / (apex.x.abs() + 1.0);
    let mut previous_offset = unit_difference(polygon.vertices[1], origin);
    let mut total = 0.0;
    let mut signed_total = 0.0;
    let mut magnitude = 0.0;
    for j in 0..MAX_FAN_TRIANGLES {
        if j + 2 >= count {
            break;
        }
        let a = sampler.directions[j + 1];
        let b = sampler.directions[j + 2];
        let offset_a = previous_offset;
        let offset_b = unit_difference(polygon.vertices[j + 2], origin);
        previous_offset = offset_b;
        // v̂₀·d = −|d|²/2 exactly for d = v̂ − v̂₀
        let reflected_a = Vec2::new(offset_a.y, offset_a.z)
            - householder_yz * (-0.5 * offset_a.length_squared() - sigma * offset_a.x);
        let reflected_b = Vec2::new(offset_b.y, offset_b.z)
            - householder_yz * (-0.5 * offset_b.length_squared() - sigma * offset_b.x);
        // det(v̂ₐ, v̂₀, v̂_b) = det(dₐ, v̂₀, d_b) = σ · det of the yz minor after H
        let signed_det = sigma * det2(reflected_a, reflected_b);
        let g_0 = signed_det.abs();
        let g_1 = a.dot(b) + apex.dot(b);
        let g_2 = 1.0 + a.dot(apex);
        let triangle_solid_angle = 2.0 * g_0.atan2(g_1 + g_2);
        sampler.triangles[j] = Vec3::new(g_0, g_1, g_2);
        total += triangle_solid_angle;
        sampler.fan_solid_angles[j] = total;
        signed_total += triangle_solid_angle.copysign(signed_det);
        magnitude += triangle_solid_angle;
    }
    if !(total > 0.0 && total.is_finite()) || signed_total.abs() <= EMPTY_RELATIVE_THRESHOLD * magnitude {
        return SolidAngleSampler::EMPTY;
    }
    // det(v̂ⱼ₊₁, v̂₀, v̂ⱼ₊₂) > 0 means (v̂ⱼ₊₁ × v̂ⱼ₊₂)·v̂₀ < 0: the edges' normals point outwards
    sampler.orientation = if signed_total > 0.0 { -1.0 } else { 1.0 };
    sampler.count = count;
    sampler.solid_angle = total;
    sampler
}

/// Samples a direction uniformly with respect to solid angle within the polygon from
/// `u ∈ [0, 1)²` (Algorithm 5 on the fan triangle that `u[0]` selects). Returns the unit direction
/// and its density with respect to solid angle, `1 / solid_angle`. The direction may lie below the
/// horizon if the polygon was not clipped. An empty sampler returns `(+z, 0)`.
pub fn sample_solid_angle(sampler: &SolidAngleSampler, u: [f32; 2]) -> (Vec3, f32) {
    if sampler.is_empty() {
        return (Vec3::Z, 0.0);
    }
    let count = sampler.count;
    let target = u[0] * sampler.solid_angle;
    // Select the triangle; a target beyond the last non-empty triangle (rounding) clamps to its end
    let mut selected = 0;
    let mut sub_solid_angle = 0.0;
    let mut previous_fan = 0.0;
    for j in 0..MAX_FAN_TRIANGLES {
        if j + 2 >= count {
            break;
        }
        let fan = sampler.fan_solid_angles[j];
        if fan > previous_fan {
            selected = j;
            sub_solid_angle = (target - previous_fan).min(fan - previous_fan);
        }
        if target < fan {
            break;
        }
        previous_fan = fan;
    }
    let [g_0, g_1, g_2] = sampler.triangles[selected].to_array();
    let a = sampler.directions[selected + 1];
    let apex = sampler.directions[0];
    let b = sampler.directions[selected + 2];
    // The point on the arc from a to b that cuts off a triangle (a, apex, b') of the wanted
    // solid angle: b' = −a + 2 (a·r)/|r|² r with
    // r = (G₀ cos(A/2) − G₁ sin(A/2)) a + G₂ sin(A/2) b
    let half = 0.5 * sub_solid_angle;
    let (sin_half, cos_half) = half.sin_cos();
    let r = (g_0 * cos_half - g_1 * sin_half) * a + (g_2 * sin_half) * b;
    let new_b = (2.0 * a.dot(r) / r.length_squared()) * r - a;
    // Uniform in cos of the distance from the apex along the arc from apex to b'. The paper's
    // t' = √((1 − s²)/(1 − s₂²)) with 1 − s = ξ₁(1 − s₂) is t' = √(ξ₁ (1 + s)/(1 + s₂)), which
    // does not cancel for small triangles.
    let s_2 = apex.dot(new_b);
    let s = mix(1.0, s_2, u[1]);
    let t = (u[1] * (1.0 + s) / (1.0 + s_2).max(f32::MIN_POSITIVE)).max(0.0).sqrt();
    let direction = (s - t * s_2) * apex + t * new_b;
    (direction, 1.0 / sampler.solid_angle)
}

/// The density with respect to solid angle with which [`sample_solid_angle`] produces the unit
/// `direction`: `1 / solid_angle` inside the polygon, 0 outside or for an empty sampler.
pub fn solid_angle_density(sampler: &SolidAngleSampler, direction: Vec3) -> f32 {
    if sampler.is_empty() || !is_inside(&sampler.directions, sampler.count, sampler.orientation, direction) {
        return 0.0;
    }
    1.0 / sampler.solid_angle
}

/// Clamped optimal MIS weights (supplement B.3) of two techniques at one direction, e.g. a light
/// technique and a BRDF technique. `densities[j]` is technique j's density at the direction (both
/// in the same measure) and `coefficients[j] = cⱼ ≥ 0` the estimated unoccluded integral of the
/// part of the integrand that technique j's density models, i.e. the model `f ≈ V Σₖ cₖ pₖ` of
/// Eq. (B.1) (for projected-solid-angle light sampling of a diffuse surface,
/// `c = kd · L · projected_solid_angle`). `visibility` is `v` ([`DEFAULT_MIS_VISIBILITY`]).
///
/// Derivation: B.3 splits the optimal-MIS contribution of a sample ωⱼ from technique j into a
/// part for visible samples, `f(ωⱼ) (v cⱼ / Σₖ cₖ pₖ(ωⱼ) + (1 − v) / Σₖ pₖ(ωⱼ))`, and a zero-mean
/// part for occluded ones, which clamping drops. Since a weight is the contribution divided by
/// `f/pⱼ`:
///
/// `wⱼ = v · cⱼ pⱼ / Σₖ cₖ pₖ + (1 − v) · pⱼ / Σₖ pₖ`,
///
/// the blend of the weighted balance heuristic (v = 1, zero variance without occluders when the
/// model is exact: `(f/pⱼ) wⱼ = cⱼ`) and the balance heuristic (v = 0). Both weights lie in
/// [0, 1] and sum to 1 (up to rounding) wherever `Σₖ pₖ > 0`; where `Σₖ cₖ pₖ = 0` the weighted
/// part falls back to the balance heuristic. Both weights are 0 where both densities are.
pub fn clamped_optimal_mis_weights(densities: [f32; 2], coefficients: [f32; 2], visibility: f32) -> [f32; 2] {
    let density_sum = densities[0] + densities[1];
    if density_sum.is_nan() || density_sum <= 0.0 {
        return [0.0, 0.0];
    }
    let weighted_sum = coefficients[0] * densities[0] + coefficients[1] * densities[1];
    // Each weight from its own formula (not 1 − the other), so that small weights keep their
    // relative accuracy: the contribution (f/pⱼ) wⱼ multiplies them by a large f/pⱼ.
    let mut weights = [0.0; 2];
    for j in 0..2 {
        let balance = densities[j] / density_sum;
        let weighted =
            if weighted_sum > 0.0 { coefficients[j] * densities[j] / weighted_sum } else { balance };
        weights[j] = mix(balance, weighted, visibility).clamp(0.0, 1.0);
    }
    weights
}

/// Point `index` of a deterministic 2D low-discrepancy set of `count` points in [0, 1)²: the
/// Hammersley set `((i + ½)/n, φ₂(i) + ½/n mod 1)` (φ₂ the base-2 radical inverse), shifted by
/// half a stratum. For `count` a power of two (up to 2²⁴) it is a (0, m, 2)-net: every dyadic box
/// of area `1/count` holds exactly one point. `index` should be below `count`.
pub fn sample_point(index: u32, count: u32) -> [f32; 2] {
    let inverse_count = 1.0 / count.max(1) as f32;
    let u_0 = ((index as f32 + 0.5) * inverse_count).min(1.0 - f32::EPSILON / 2.0);
    let radical_inverse = (index.reverse_bits() >> 8) as f32 * (1.0 / 16_777_216.0);
    let shifted = radical_inverse + 0.5 * inverse_count;
    let u_1 = if shifted >= 1.0 { shifted - 1.0 } else { shifted };
    [u_0, u_1]
}

#[cfg(test)]
mod tests;
