//! The estimator's Rust twin timed on a scene ([`twin_cost`]): microseconds per triangle over
//! every triangle of its meshes (its camera, lights and materials, the default settings: ε 0.075,
//! `n_max` 16), the median of several passes after one warm-up, with the levels summed and the
//! share the range class settles. The GPU's pre-pass runs the same operations
//! (`glsl/include/estimator.glsl`), so this is the pre-pass's work without the rest of a frame.
//! `cargo bench --bench estimator` prints it per scene; `experiments --only trade` gives it beside
//! the pre-pass's time.

use crate::scene::{MaterialKind, ParameterRange, Scene};
use crate::shading::estimator::{estimate, settled_by_range, EstimatorSettings, TriangleInput};
use std::hint::black_box;
use std::time::Instant;

/// What [`twin_cost`] measured on one scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwinCost {
    pub triangles: usize,
    /// The median pass's time over the triangles, µs.
    pub per_triangle_us: f64,
    /// Every triangle's `Estimate::level` (at most 64) summed: equal in two builds whose
    /// levels are equal.
    pub levels: f64,
    /// Triangles the range class settles, of all and of those facing the eye (the back faces of a
    /// closed mesh are culled before any estimate).
    pub settled: usize,
    pub front: usize,
    pub front_settled: usize,
}

/// Times [`estimate`] on every triangle of `scene`: `passes` passes (at least one) after a
/// warm-up pass, the median kept.
pub fn twin_cost(scene: &Scene, passes: usize) -> TwinCost {
    let settings = EstimatorSettings::default();
    let mut work: Vec<(TriangleInput, &MaterialKind)> = Vec::new();
    for mesh in &scene.meshes {
        let material = &scene.materials[mesh.material].kind;
        for corners in mesh.indices.chunks_exact(3) {
            work.push((TriangleInput::of(mesh, corners, scene.camera.eye), material));
        }
    }
    let pass = || {
        work.iter()
            .map(|(input, material)| {
                f64::from(black_box(estimate(input, material, &scene.lights, &settings)).level.min(64.0))
            })
            .sum::<f64>()
    };
    let levels = pass();
    let (mut settled, mut front, mut front_settled) = (0, 0, 0);
    for (input, material) in &work {
        let is_settled = settled_by_range(
            input,
            material,
            ParameterRange::of(material),
            &scene.lights,
            (settings.epsilon, settings.eye_radius),
        );
        let [p0, p1, p2] = input.positions;
        let is_front = (p1 - p0).cross(p2 - p0).dot(input.eye - p0) > 0.0;
        settled += usize::from(is_settled);
        front += usize::from(is_front);
        front_settled += usize::from(is_settled && is_front);
    }
    let mut times: Vec<f64> = (0..passes.max(1))
        .map(|_| {
            let start = Instant::now();
            black_box(pass());
            start.elapsed().as_secs_f64()
        })
        .collect();
    times.sort_by(f64::total_cmp);
    let per_triangle_us = times[times.len() / 2] / work.len().max(1) as f64 * 1e6;
    TwinCost { triangles: work.len(), per_triangle_us, levels, settled, front, front_settled }
}

#[cfg(test)]
mod tests;
