//! Cost per triangle of the estimator's Rust twin (`multirate::shading::estimator::estimate`) on
//! every triangle of the shipped scenes, with each scene's own camera, lights and materials, ε
//! 0.075 and `n_max` 16 (`multirate::bench::twin`, which `experiments --only trade` also runs).
//! The GPU runs the same
//! operations in `glsl/include/estimator.glsl` (the compute pre-pass), so a change that makes
//! this slower makes the pre-pass slower too; this bench times it without the rest of a frame.
//!
//! Every timing is the median over [`REPETITIONS`] passes over all triangles (after one warm-up
//! pass). Output: a markdown table on stdout.
//!
//! Run: `cargo bench --bench estimator` (or `-- scenes/a.toml scenes/b.toml` for other scenes)

use std::path::Path;

use multirate::bench::twin::twin_cost;
use multirate::scene::Scene;

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
        let cost = twin_cost(&scene, REPETITIONS);
        let share = 100.0 * cost.settled as f64 / cost.triangles.max(1) as f64;
        let front_share = 100.0 * cost.front_settled as f64 / cost.front.max(1) as f64;
        println!(
            "| {path} | {} | {} | {:.2} | {:.0} | {share:.1} % | {front_share:.1} % |",
            cost.triangles,
            scene.lights.len(),
            cost.per_triangle_us,
            cost.levels
        );
    }
}
