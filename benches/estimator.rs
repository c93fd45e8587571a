//! Cost per triangle of the estimator's Rust twin (`multirate::shading::estimator::estimate`) on
//! every triangle of the shipped scenes, with each scene's own camera, lights, materials and
//! multirate settings (ε 0.075, `n_max` 16 where the scene sets none). The GPU runs the same
//! operations in `glsl/include/estimator.glsl` (the compute pre-pass), so a change that makes
//! this slower makes the pre-pass slower too; this bench times it without the rest of a frame.
//!
//! Every timing is the median over [`REPETITIONS`] passes over all triangles (after one warm-up
//! pass). Output: a markdown table on stdout.
//!
//! Run: `cargo bench --bench estimator` (or `-- scenes/a.toml scenes/b.toml` for other scenes)

use std::hint::black_box;
use std::path::Path;
use std::time::Instant;

use multirate::scene::Scene;
use multirate::scene::{MaterialKind, ParameterRange};
use multirate::shading::estimator::{estimate, settled_by_range, EstimatorSettings, TriangleInput};

const REPETITIONS: usize = 7;
const SCENES: [&str; 3] = ["scenes/bunny.toml", "scenes/teapot.toml", "scenes/plane_lights.toml"];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).filter(|a| a.ends_with(".toml")).collect();
    let paths: Vec<String> = if args.is_empty() { SCENES.map(String::from).to_vec() } else { args };
    println!(
        "| scene | triangles | lights | µs per triangle | levels summed | settled by the range class | of those facing the eye |"
    );
    println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
    for path in paths {
        let scene = match Scene::load(Path::new(&path)) {
            Ok(scene) => scene,
            Err(error) => {
                eprintln!("{path}: {error}");
                std::process::exit(1);
            }
        };
        let settings = EstimatorSettings::default();
        let mut work = Vec::new();
        for mesh in &scene.meshes {
            let material = &scene.materials[mesh.material].kind;
            for corners in mesh.indices.chunks_exact(3) {
                let at = |k: usize| corners[k] as usize;
                let input = TriangleInput {
                    positions: [0, 1, 2].map(|k| mesh.positions[at(k)]),
                    normals: [0, 1, 2].map(|k| mesh.normals[at(k)]),
                    eye: scene.camera.eye,
                };
                work.push((input, material));
            }
        }
        let pass = || {
            let mut levels = 0.0f64;
            for (input, material) in &work {
                levels +=
                    f64::from(black_box(estimate(input, material, &scene.lights, &settings)).level.min(64.0));
            }
            levels
        };
        let levels = pass();
        // The share the range class settles, of all triangles and of those facing the eye
        // (the back faces of a closed mesh are culled before any estimate).
        let settles = |(input, material): &&(TriangleInput, &MaterialKind)| {
            settled_by_range(input, material, ParameterRange::of(material), &scene.lights, settings.epsilon)
        };
        let facing = |(input, _): &&(TriangleInput, &MaterialKind)| {
            let [p0, p1, p2] = input.positions;
            (p1 - p0).cross(p2 - p0).dot(input.eye - p0) > 0.0
        };
        let (mut settled, mut front, mut front_settled) = (0usize, 0usize, 0usize);
        for triangle in &work {
            let (is_settled, is_front) = (settles(&triangle), facing(&triangle));
            settled += usize::from(is_settled);
            front += usize::from(is_front);
            front_settled += usize::from(is_settled && is_front);
        }
        let mut times: Vec<f64> = (0..REPETITIONS)
            .map(|_| {
                let start = Instant::now();
                black_box(pass());
                start.elapsed().as_secs_f64()
            })
            .collect();
        times.sort_by(f64::total_cmp);
        let per_triangle = times[REPETITIONS / 2] / work.len() as f64 * 1e6;
        let share = 100.0 * settled as f64 / work.len() as f64;
        let front_share = 100.0 * front_settled as f64 / front.max(1) as f64;
        println!(
            "| {path} | {} | {} | {per_triangle:.2} | {levels:.0} | {share:.1} % | {front_share:.1} % |",
            work.len(),
            scene.lights.len()
        );
    }
}
