//! Effective levels of tessellation patterns (`docs/estimator.md` §9): the largest `L` such
//! that every sub-triangle of a pattern has, under every affine attribute map `W`, enclosing
//! radius `≤ √K_W/L` and diameter `≤ D_W/L` (`K_W`, `D_W` the seven-shape constants of
//! `estimator::pattern_constants`). Computed from the triangles alone (barycentric corners),
//! so the same code gives the table `estimator::PATTERN_LEVELS` from the model of the
//! tessellator and a device's own table from patterns captured on it
//! (`render::capture::check_patterns`).

use std::sync::OnceLock;

use crate::shading::estimator::SHAPES;

/// The effective level of a pattern given by its triangles (barycentric corners), at least 1
/// (every sub-triangle lies inside the patch, whose radius `√K₁` is at most `√K`).
pub fn effective_level(triangles: impl IntoIterator<Item = [[f64; 3]; 3]>) -> f64 {
    let facets = facets();
    let worst = triangles.into_iter().map(|t| triangle_gauge(facets, t)).fold(0.0, f64::max);
    (1.0 / worst).max(1.0)
}

/// The table entry of an effective level: rounded down to a multiple of 1/256 (values within
/// 10⁻⁶/256 below a multiple count as it: f64 noise of the gauge, far inside `SAFETY`), at
/// least 1.
pub fn table_entry(level: f64) -> u32 {
    ((level * 256.0 + 1e-6).floor() as u32).clamp(256, 0xffff)
}

/// Packs table entries in the layout of `estimator::PATTERN_LEVELS`: index
/// `(inner − 1)·64 + (outer − 1)`, two 16-bit entries per word, the even index low
/// (`estimator::pattern_level_entry` reads them back).
pub fn pack(entry: impl Fn(u32, u32) -> u32) -> Vec<u32> {
    let mut words = vec![0u32; 2048];
    for inner in 1..=64u32 {
        for outer in 1..=64u32 {
            let index = ((inner - 1) * 64 + (outer - 1)) as usize;
            words[index / 2] |= (entry(inner, outer) & 0xffff) << (16 * (index % 2));
        }
    }
    words
}

/// The facets of the hull of the side-frame configurations, computed once.
fn facets() -> &'static [[f64; 3]] {
    static FACETS: OnceLock<Vec<[f64; 3]>> = OnceLock::new();
    FACETS.get_or_init(|| hull_facets(&frame_points()))
}

/// Points `(s, τ, h)` of the side-frame configurations `{0, s·e, τ·e + h·f}` (`e` the side,
/// `f` towards the opposite corner) whose enclosing radius is at most `√K_W` under every map
/// `W`: every labelling of the seven shapes that has an edge along the side, every segment
/// between two corners of a shape (`s = 0`), segments along the side that are not longer than
/// it, and all of their negatives.
fn frame_points() -> Vec<[f64; 3]> {
    // Exact thirds (SHAPES holds f32 approximations).
    let exact = |x: f32| (f64::from(x) * 3.0).round() / 3.0;
    let mut points = vec![[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]];
    for shape in SHAPES.iter() {
        let v = [[0.0, 0.0], [exact(shape[0].0), exact(shape[0].1)], [exact(shape[1].0), exact(shape[1].1)]];
        for a in 0..3 {
            for b in 0..3 {
                if a == b {
                    continue;
                }
                let c = 3 - a - b;
                let d1 = [v[b][0] - v[a][0], v[b][1] - v[a][1]];
                let d2 = [v[c][0] - v[a][0], v[c][1] - v[a][1]];
                points.push([0.0, d1[0], d1[1]]);
                if d1[1] == 0.0 {
                    points.push([d1[0], d2[0], d2[1]]);
                }
            }
        }
    }
    let mut all: Vec<[f64; 3]> = Vec::new();
    for p in points {
        for q in [p, p.map(|x| -x)] {
            if !all.iter().any(|r| (0..3).all(|k| (r[k] - q[k]).abs() < 1e-12)) {
                all.push(q);
            }
        }
    }
    all
}

/// Facets `n` (with `n·x ≤ 1` on the hull) of the convex hull of `points`, which is symmetric
/// about the origin and full-dimensional: the gauge is `max n·x`.
fn hull_facets(points: &[[f64; 3]]) -> Vec<[f64; 3]> {
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let mut facets: Vec<[f64; 3]> = Vec::new();
    let n = points.len();
    for a in 0..n {
        for b in a + 1..n {
            for c in b + 1..n {
                let m = [points[a], points[b], points[c]];
                let det = det3(m);
                if det.abs() < 1e-12 {
                    continue;
                }
                // Cramer: n solves m·n = (1, 1, 1).
                let normal: [f64; 3] = std::array::from_fn(|k| {
                    let mut mk = m;
                    for row in &mut mk {
                        row[k] = 1.0;
                    }
                    det3(mk) / det
                });
                let dot = |q: &[f64; 3]| normal[0] * q[0] + normal[1] * q[1] + normal[2] * q[2];
                if points.iter().all(|q| dot(q) <= 1.0 + 1e-9)
                    && !facets.iter().any(|f| (0..3).all(|k| (f[k] - normal[k]).abs() < 1e-9))
                {
                    facets.push(normal);
                }
            }
        }
    }
    facets
}

fn gauge(facets: &[[f64; 3]], x: [f64; 3]) -> f64 {
    facets.iter().map(|n| n[0] * x[0] + n[1] * x[1] + n[2] * x[2]).fold(0.0, f64::max)
}

/// `γ` with `r(W·T) ≤ γ·√K_W` for every map `W`, for the pattern triangle `t` (barycentric
/// corners): the smallest over the sides `k` and the choices of a base edge of
/// `gauge(s, τ, h) + |dy|`, in the frame of side `k` (`x = b[k+1]` along the side, `y = b[k]`
/// towards the opposite corner); `dy`, the base's rise in that frame (the fixed-point rings
/// are not exactly parallel to the sides, and another device's triangles need not have an
/// edge along a side at all), is charged as a segment along `f` of length `|dy|`, whose
/// radius is at most `|dy|·√K` (the radius is a seminorm of the configuration).
fn triangle_gauge(facets: &[[f64; 3]], t: [[f64; 3]; 3]) -> f64 {
    let mut best = f64::INFINITY;
    for k in 0..3 {
        let xy = t.map(|b| (b[(k + 1) % 3], b[k]));
        for a in 0..3 {
            let (b, c) = ((a + 1) % 3, (a + 2) % 3);
            let (l, r) = if xy[a].0 <= xy[b].0 { (xy[a], xy[b]) } else { (xy[b], xy[a]) };
            let g = gauge(facets, [r.0 - l.0, xy[c].0 - l.0, xy[c].1 - l.1]);
            best = best.min(g + (r.1 - l.1).abs());
        }
    }
    best
}
