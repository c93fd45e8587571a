//! Tests of the polygonal-light module against independent f64 references: a Sutherland–Hodgman
//! clipper, Lambert's edge sum evaluated plainly, van Oosterom–Strackee fans, ray–plane inside
//! tests, area quadrature and Monte Carlo estimates with tolerances from their standard errors.
//! This file holds the references and the polygons; the tests are in one file per topic.

use super::arithmetic::unit_difference;
use super::closed_form::edge_segment_term;
use super::ellipse::{ellipse_from_edge, is_degenerate};
use super::*;
use glam::{DVec3, Vec3};
use std::f64::consts::PI;

mod clip;
mod closed_form;
mod mis;
mod points;
mod projected_sampling;
mod robustness;
mod solid_angle_sampling;

// ---------------------------------------------------------------------------------------------
// Deterministic pseudo-random numbers (xorshift64*)

struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }

    fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in [0, 1).
    fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    fn range(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.uniform()
    }

    /// Uniform in [0, 1)², exactly representable in f32.
    fn u2(&mut self) -> [f32; 2] {
        let scale = 1.0 / (1u32 << 24) as f32;
        [(self.next_u64() >> 40) as f32 * scale, (self.next_u64() >> 40) as f32 * scale]
    }
}

// ---------------------------------------------------------------------------------------------
// f64 references

fn to_f64(vertices: &[Vec3]) -> Vec<DVec3> {
    vertices.iter().map(|v| v.as_dvec3()).collect()
}

/// Sutherland–Hodgman against the half-space `normal·p ≥ 0`.
fn clip_reference(polygon: &[DVec3], normal: DVec3) -> Vec<DVec3> {
    let mut out = Vec::new();
    let count = polygon.len();
    for j in 0..count {
        let a = polygon[j];
        let b = polygon[(j + 1) % count];
        let (da, db) = (normal.dot(a), normal.dot(b));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            out.push(a + (da / (da - db)) * (b - a));
        }
    }
    out
}

/// Removes cyclically consecutive duplicates; fewer than three vertices make the empty polygon.
fn dedupe(polygon: &[DVec3]) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = Vec::new();
    for &p in polygon {
        if out.last().is_none_or(|q| (p - *q).length() > 1e-12 * (p.length() + q.length())) {
            out.push(p);
        }
    }
    while out.len() > 1 {
        let (first, last) = (out[0], out[out.len() - 1]);
        if (first - last).length() > 1e-12 * (first.length() + last.length()) {
            break;
        }
        out.pop();
    }
    if out.len() < 3 {
        out.clear();
    }
    out
}

fn clip_horizon_reference(polygon: &[DVec3]) -> Vec<DVec3> {
    dedupe(&clip_reference(polygon, DVec3::Z))
}

/// Lambert's edge sum `½ Σ γ n̂·z`, evaluated plainly in f64 (signed).
fn psa_reference(polygon: &[DVec3]) -> f64 {
    let count = polygon.len();
    let mut sum = 0.0;
    for j in 0..count {
        let a = polygon[j].normalize();
        let b = polygon[(j + 1) % count].normalize();
        let c = a.cross(b);
        let sine = c.length();
        if sine > 0.0 {
            sum += sine.atan2(a.dot(b)) * c.z / sine;
        }
    }
    0.5 * sum
}

/// Solid angle of a convex polygon as a van Oosterom–Strackee fan (absolute value); the
/// determinant from differences, so that tiny triangles keep their accuracy in f64 too.
fn solid_angle_reference(polygon: &[DVec3]) -> f64 {
    let v: Vec<DVec3> = polygon.iter().map(|p| p.normalize()).collect();
    let mut sum = 0.0;
    for j in 1..v.len().saturating_sub(1) {
        let (a, b, c) = (v[0], v[j], v[j + 1]);
        let det = a.dot((b - a).cross(c - a));
        sum += 2.0 * det.atan2(1.0 + a.dot(b) + b.dot(c) + c.dot(a));
    }
    sum.abs()
}

/// Newell normal (twice the vector area) of a planar polygon.
fn newell_normal(polygon: &[DVec3]) -> DVec3 {
    let count = polygon.len();
    (0..count).map(|j| polygon[j].cross(polygon[(j + 1) % count])).sum()
}

/// Whether the ray from the origin along the unit `direction` hits the planar convex polygon: it
/// meets the polygon's plane in front of the origin and on the inner side of every edge, where
/// "side" is measured as the angle to the plane through the origin and the edge, so that
/// `tolerance` is in radians (an in-plane distance would blow up for polygons seen edge-on).
fn ray_hits_polygon(polygon: &[DVec3], direction: DVec3, tolerance: f64) -> bool {
    let normal = newell_normal(polygon);
    let t = normal.dot(polygon[0]) / normal.dot(direction);
    if !(t > 0.0 && t.is_finite()) {
        return false;
    }
    let count = polygon.len();
    let centroid = polygon.iter().sum::<DVec3>() / count as f64;
    (0..count).all(|j| {
        let edge_normal = polygon[j].cross(polygon[(j + 1) % count]);
        let length = edge_normal.length();
        length == 0.0
            || edge_normal.dot(direction) * edge_normal.dot(centroid).signum() >= -tolerance * length
    })
}

/// Whether the unit `direction` lies in the convex spherical polygon (either winding).
fn spherical_inside(polygon: &[DVec3], direction: DVec3, tolerance: f64) -> bool {
    let count = polygon.len();
    let orientation = newell_normal(polygon).dot(polygon[0]).signum();
    (0..count).all(|j| {
        let normal = polygon[j].cross(polygon[(j + 1) % count]) * orientation;
        normal.dot(direction) >= -tolerance * normal.length()
    })
}

/// `∫ cos θ_s cos θ_l / r² dA` over a planar polygon above the horizon, by the centroid rule on
/// a regular subdivision of its fan triangles into `steps²` pieces each (second order): an
/// evaluation of the projected solid angle independent of Lambert's formula, and free of its
/// cancellation for tiny polygons. Each fan triangle uses its own normal, so that the f32
/// rounding of a tiny polygon's vertices (planar only to within ε·distance) changes nothing:
/// the result is the projected solid angle of the spherical polygon.
fn psa_quadrature(polygon: &[DVec3], steps: usize) -> f64 {
    let mut integral = 0.0;
    for j in 1..polygon.len() - 1 {
        let (a, b, c) = (polygon[0], polygon[j], polygon[j + 1]);
        let normal = (b - a).cross(c - a).normalize();
        let area = 0.5 * (b - a).cross(c - a).length() / (steps * steps) as f64;
        let mut sum = 0.0;
        for i in 0..steps {
            for k in 0..steps - i {
                // the upward sub-triangle at (i, k) and, if it exists, the downward one
                for (offset, exists) in [(1.0 / 3.0, true), (2.0 / 3.0, i + k + 1 < steps)] {
                    if exists {
                        let s = (i as f64 + offset) / steps as f64;
                        let t = (k as f64 + offset) / steps as f64;
                        let p = a + s * (b - a) + t * (c - a);
                        let r2 = p.length_squared();
                        sum += p.z * normal.dot(p).abs() / (r2 * r2);
                    }
                }
            }
        }
        integral += area * sum;
    }
    integral
}

// ---------------------------------------------------------------------------------------------
// Polygons

/// Two unit vectors completing `normal` to a right-handed frame.
fn frame(normal: DVec3) -> (DVec3, DVec3) {
    let n = normal.normalize();
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let t1 = helper.cross(n).normalize();
    (t1, n.cross(t1))
}

/// A convex planar polygon: `count` vertices on an ellipse with radii `radii` around `center` in
/// the plane with `normal`, starting at angle `rotation`, angles jittered by up to `jitter` of a
/// step (convexity is kept: the points stay in angular order on the ellipse).
fn planar_polygon(
    count: usize,
    center: DVec3,
    normal: DVec3,
    radii: (f64, f64),
    rotation: f64,
    jitter: f64,
    rng: &mut Rng,
) -> Vec<Vec3> {
    let (t1, t2) = frame(normal);
    (0..count)
        .map(|k| {
            let angle = rotation + 2.0 * PI * (k as f64 + jitter * (rng.uniform() - 0.5)) / count as f64;
            (center + radii.0 * angle.cos() * t1 + radii.1 * angle.sin() * t2).as_vec3()
        })
        .collect()
}

/// A polygon facing the shading point: centred at `center`, normal towards the origin.
fn facing_polygon(count: usize, center: DVec3, radius: f64, rng: &mut Rng) -> Vec<Vec3> {
    let rotation = rng.range(0.0, 2.0 * PI);
    planar_polygon(count, center, -center, (radius, 0.8 * radius), rotation, 0.5, rng)
}

/// A named test polygon with its f64 clipped reference and projected solid angle.
struct Case {
    name: String,
    polygon: Polygon,
    clipped_reference: Vec<DVec3>,
    psa: f64,
}

fn case(name: &str, vertices: &[Vec3]) -> Case {
    let clipped_reference = clip_horizon_reference(&to_f64(vertices));
    let psa = psa_reference(&clipped_reference).abs();
    Case { name: name.to_string(), polygon: Polygon::new(vertices), clipped_reference, psa }
}

fn v(x: f32, y: f32, z: f32) -> Vec3 {
    Vec3::new(x, y, z)
}

/// A spread of configurations with positive projected solid angle: central and decentral,
/// clipped, 3 to 8 vertices, both windings, the degenerate configurations of A.2, tiny and huge.
fn sampling_cases() -> Vec<Case> {
    let mut rng = Rng::new(7);
    let mut cases = vec![
        case("central square", &facing_polygon(4, DVec3::new(0.1, -0.2, 1.0), 0.9, &mut rng)),
        case("central triangle", &facing_polygon(3, DVec3::new(0.0, 0.1, 0.7), 1.2, &mut rng)),
        case("decentral pentagon", &facing_polygon(5, DVec3::new(2.0, 1.0, 1.0), 0.7, &mut rng)),
        case("decentral octagon", &facing_polygon(8, DVec3::new(-1.0, 1.5, 0.8), 0.9, &mut rng)),
        case("decentral triangle", &facing_polygon(3, DVec3::new(0.3, -2.0, 2.0), 0.8, &mut rng)),
        case("clipped hexagon", &facing_polygon(6, DVec3::new(3.0, 0.5, 0.3), 0.6, &mut rng)),
        case("clipped heptagon", &facing_polygon(7, DVec3::new(0.5, 0.4, 0.2), 1.5, &mut rng)),
        case(
            "clipped tilted quad (contains the zenith)",
            &planar_polygon(
                4,
                DVec3::new(0.0, 0.2, 0.5),
                DVec3::new(0.6, 0.1, 1.0),
                (3.0, 2.0),
                0.3,
                0.5,
                &mut rng,
            ),
        ),
        case(
            "vertical wall crossing the horizon",
            &planar_polygon(
                5,
                DVec3::new(1.0, 0.5, 0.1),
                DVec3::new(-1.0, -0.3, 0.0),
                (0.8, 0.6),
                0.1,
                0.5,
                &mut rng,
            ),
        ),
        // A.2: an edge through the zenith (central case, 180° sector of zero area)
        case(
            "A.2 edge through the zenith",
            &[v(-1.0, 0.0, 1.0), v(1.0, 0.0, 1.0), v(1.0, 1.0, 1.0), v(-1.0, 1.0, 1.0)],
        ),
        // A.2: a vertex at the zenith
        case("A.2 vertex at the zenith", &[v(0.0, 0.0, 1.0), v(1.0, 0.0, 1.0), v(0.5, 1.0, 1.0)]),
        // A.2: two edges on great circles through the zenith (Fig. A.1b)
        case(
            "A.2 two degenerate edges",
            &[v(1.0, 0.0, 0.5), v(1.0, 0.0, 2.0), v(1.0, 1.0, 2.0), v(1.0, 1.0, 0.5)],
        ),
        case(
            "A.2 two degenerate edges, reversed",
            &[v(1.0, 1.0, 0.5), v(1.0, 1.0, 2.0), v(1.0, 0.0, 2.0), v(1.0, 0.0, 0.5)],
        ),
        case("A.2 one degenerate edge", &[v(1.0, 0.0, 0.5), v(1.0, 0.0, 2.0), v(2.0, 1.5, 1.5)]),
        // A.2: a degenerate edge that the horizon clips
        case(
            "A.2 degenerate edge, clipped",
            &[v(0.5, 2.0, -0.5), v(0.5, 2.0, 1.5), v(0.5, 3.0, 1.0), v(0.5, 3.5, -0.3)],
        ),
        // Lying on the horizon along one edge
        case("edge on the horizon", &[v(1.0, -1.0, 0.0), v(2.0, 0.0, 0.0), v(1.5, 0.5, 1.0)]),
        case("huge square", &[v(-5e3, -5e3, 1.0), v(5e3, -5e3, 1.0), v(5e3, 5e3, 1.0), v(-5e3, 5e3, 1.0)]),
        case(
            "huge tilted quad",
            &[v(-4e3, -3e3, -2e3), v(4e3, -3e3, 1e3), v(4e3, 3e3, 1e3), v(-4e3, 3e3, -2e3)],
        ),
    ];
    // Zero-length edges: a repeated vertex changes nothing
    for (index, name) in [(0, "central square, repeated vertex"), (2, "decentral pentagon, repeated vertex")]
    {
        let mut repeated: Vec<Vec3> = cases[index].polygon.as_slice().to_vec();
        repeated.insert(2, repeated[1]);
        cases.push(case(name, &repeated));
    }
    let mut reversed: Vec<Vec3> = cases[2].polygon.as_slice().to_vec();
    reversed.reverse();
    cases.push(case("decentral pentagon, reversed", &reversed));
    // Every starting vertex of the A.2 cases: the two vertices of a degenerate edge tie in the
    // sort and must end up in the order of rule 3 whatever order they start in.
    let degenerate: Vec<(String, Vec<Vec3>)> = cases
        .iter()
        .filter(|case| case.name.starts_with("A.2"))
        .map(|case| (case.name.clone(), case.polygon.as_slice().to_vec()))
        .collect();
    for (name, vertices) in degenerate {
        for shift in 1..vertices.len() {
            let mut rotated = vertices.clone();
            rotated.rotate_left(shift);
            cases.push(case(&format!("{name}, from vertex {shift}"), &rotated));
        }
    }
    for (name, center) in [
        ("tiny at the zenith", DVec3::new(2e-5, -1e-5, 1.0)),
        ("tiny at 45°", DVec3::new(0.6, 0.3, 0.7)),
        ("tiny near the horizon", DVec3::new(0.8, -0.55, 0.05)),
    ] {
        let center = center.normalize();
        cases.push(case(name, &facing_polygon(5, center, 5e-5, &mut rng)));
    }
    cases
}
