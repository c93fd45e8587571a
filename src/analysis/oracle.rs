//! The brute-force truth the estimator ([`crate::shading::estimator`]) is measured against:
//! the actual per-channel L∞ error of interpolating the sub-vertex shading over a
//! tessellation pattern, found by dense sampling.
//!
//! # What is measured
//!
//! The shading at barycentric point `λ` of the patch is
//! `f(λ) = shade_point(Σλₖpₖ, ΣλₖNₖ, eye, material, lights)`, the world position and the
//! unnormalised normal interpolated linearly in the patch's own barycentrics (what the TES
//! computes at a sub-vertex, and what perspective-correct interpolation gives at a pixel).
//! Inside a sub-triangle with corners `λ₁, λ₂, λ₃` and local barycentrics `μ`, the
//! rasteriser shows `Σ μₖ f(λₖ)`; the error there is `|f(Σμₖλₖ) − Σμₖ f(λₖ)|`, per colour
//! channel. The barycentric combinations are formed in f64 and rounded to f32 once, then
//! shaded with the f32 Rust twin of the GLSL (`shade_point`).
//!
//! # Sampling density
//!
//! Each sub-triangle is sampled on the barycentric grid `μ = (i, j, k − i − j)/k` with
//! `k` = [`SAMPLES_PER_EDGE`] = 6 (28 points, the corners included; the three edges are
//! sampled at sixths, so their midpoints are hit, and so is the centroid). Why that is
//! enough: the grid splits the sub-triangle into `k²` cells that are `±1/k` copies of it.
//! On a cell, the error `e = f − L f` has the same second derivative as `f` (L f is
//! linear), so by the same interpolation estimate the estimator uses,
//! `sup_cell e ≤ max over the cell's corners of e + ½ r_cell² sup|D²f|` with
//! `r_cell = r_sub / k`. The missed part is therefore at most `1/k² = 1/36 ≈ 2.8 %` of the
//! second-order bound `½ r_sub² sup|D²f|` of the sub-triangle, i.e. of what a tight
//! estimator predicts. The refinement study in this module's tests
//! (`sampling_density_refinement`) compares `k = 6` with `k = 24` at the level the estimator
//! picks, on smooth random cases: the miss stays under 1/36 of the predicted bound (asserted)
//! and was at most 1.2 % of the `k = 24` maximum when last run. Callers that need more
//! certainty near `ε` can re-measure with [`true_error_sampled`] (the property test does so
//! for every case above `ε/2`).

use crate::analysis::tessellator::Pattern;
use crate::scene::{Light, MaterialKind};
use crate::shading::estimator::TriangleInput;
use crate::shading::shade_point;
use glam::Vec3;

/// Samples per sub-triangle edge (see the module docs).
pub const SAMPLES_PER_EDGE: u32 = 6;

/// The shading `f(λ)` at barycentric point `b` of the patch, per channel.
pub fn shade_at(tri: &TriangleInput, material: &MaterialKind, lights: &[Light], b: [f64; 3]) -> [f64; 3] {
    shade_with(tri, *material, lights, b)
}

fn shade_with(tri: &TriangleInput, material: MaterialKind, lights: &[Light], b: [f64; 3]) -> [f64; 3] {
    let mix = |v: [Vec3; 3]| -> Vec3 {
        (v[0].as_dvec3() * b[0] + v[1].as_dvec3() * b[1] + v[2].as_dvec3() * b[2]).as_vec3()
    };
    let f = shade_point(mix(tri.positions), mix(tri.normals), tri.eye, &material, lights);
    [f64::from(f.x), f64::from(f.y), f64::from(f.z)]
}

/// Per-channel L∞ interpolation error of `pattern` (see the module docs), sampled with
/// [`SAMPLES_PER_EDGE`].
pub fn true_error(
    tri: &TriangleInput,
    material: &MaterialKind,
    lights: &[Light],
    pattern: &Pattern,
) -> [f64; 3] {
    true_error_sampled(tri, material, lights, pattern, SAMPLES_PER_EDGE, f64::INFINITY)
}

/// [`true_error`] with `k` samples per sub-triangle edge. Stops early, returning the error
/// found so far, as soon as a channel exceeds `stop_above` (pass `f64::INFINITY` for the
/// full maximum).
pub fn true_error_sampled(
    tri: &TriangleInput,
    material: &MaterialKind,
    lights: &[Light],
    pattern: &Pattern,
    k: u32,
    stop_above: f64,
) -> [f64; 3] {
    true_error_textured(tri, &|_| *material, lights, pattern, k, stop_above)
}

/// [`true_error_sampled`] for a material that varies over the patch (a textured shininess or
/// roughness): `material_at(λ)` is the material at barycentric point `λ`, used both for the
/// sub-vertices (what the evaluation shader samples there) and for the points in between
/// (what a pixel samples).
pub fn true_error_textured(
    tri: &TriangleInput,
    material_at: &dyn Fn([f64; 3]) -> MaterialKind,
    lights: &[Light],
    pattern: &Pattern,
    k: u32,
    stop_above: f64,
) -> [f64; 3] {
    let k = k.max(1);
    let shade = |b: [f64; 3]| shade_with(tri, material_at(b), lights, b);
    let corner_values: Vec<[f64; 3]> = pattern.vertices.iter().map(|&b| shade(b)).collect();
    let mut worst = [0.0f64; 3];
    let kf = f64::from(k);
    for t in &pattern.triangles {
        let corners = t.map(|i| pattern.vertices[i as usize]);
        let values = t.map(|i| corner_values[i as usize]);
        for i in 0..=k {
            for j in 0..=(k - i) {
                let l = k - i - j;
                if i == k || j == k || l == k {
                    continue; // a corner: no error by construction
                }
                let mu = [f64::from(i) / kf, f64::from(j) / kf, f64::from(l) / kf];
                let b: [f64; 3] = std::array::from_fn(|c| {
                    mu[0] * corners[0][c] + mu[1] * corners[1][c] + mu[2] * corners[2][c]
                });
                let f = shade(b);
                for c in 0..3 {
                    let lin = mu[0] * values[0][c] + mu[1] * values[1][c] + mu[2] * values[2][c];
                    let e = (f[c] - lin).abs();
                    if e > worst[c] {
                        worst[c] = e;
                    }
                }
                if worst.iter().any(|&e| e > stop_above) {
                    return worst;
                }
            }
        }
    }
    worst
}

/// The smallest level `n` in `1..=n_max` whose pattern (`pattern_of(n)`) has a true error
/// `≤ epsilon` in every channel, or `None`. Levels are tried in increasing order (the error
/// need not fall monotonically with the level, so no bisection); a level is abandoned at
/// the first sample above `epsilon`.
pub fn oracle_level(
    tri: &TriangleInput,
    material: &MaterialKind,
    lights: &[Light],
    epsilon: f64,
    n_max: u32,
    pattern_of: impl Fn(u32) -> Pattern,
) -> Option<u32> {
    (1..=n_max).find(|&n| {
        let pattern = pattern_of(n);
        let e = true_error_sampled(tri, material, lights, &pattern, SAMPLES_PER_EDGE, epsilon);
        e.iter().all(|&x| x <= epsilon)
    })
}

/// Shading evaluations (TES invocations) of one patch at level `n` (inner = outer = n):
/// `⌈3(n+1)²/4⌉`.
pub fn vertices_at_level(n: u32) -> u64 {
    let m = u64::from(n) + 1;
    (3 * m * m).div_ceil(4)
}

#[cfg(test)]
mod tests;
