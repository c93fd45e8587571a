//! Tests of `bench::twin`: the twin's cost covers every triangle of the scene, and its counts agree
//! with the estimator's own answers.

use super::*;
use std::path::Path;

/// On a test scene: one entry per triangle, every level at least 1, the settled counts within
/// their totals and equal to the range class's own answers, a finite positive time.
#[test]
fn the_twin_cost_covers_every_triangle_and_counts_what_the_range_class_settles() {
    let scene = Scene::load(Path::new("scenes/test/blinn_phong_mixed.toml")).expect("the test scene loads");
    let triangles: usize = scene.meshes.iter().map(|mesh| mesh.indices.len() / 3).sum();
    let cost = twin_cost(&scene, 1);
    assert_eq!(cost.triangles, triangles);
    assert!(cost.levels >= triangles as f64, "levels summed {} below 1 per triangle", cost.levels);
    assert!(cost.per_triangle_us.is_finite() && cost.per_triangle_us > 0.0, "{cost:?}");
    assert!(cost.front <= triangles && cost.front_settled <= cost.front.min(cost.settled), "{cost:?}");
    let settings = EstimatorSettings::default();
    let mut settled = 0;
    for mesh in &scene.meshes {
        let material = &scene.materials[mesh.material].kind;
        for corners in mesh.indices.chunks_exact(3) {
            let input = TriangleInput::of(mesh, corners, scene.camera.eye);
            let parameter = ParameterRange::of(material);
            settled += usize::from(settled_by_range(
                &input,
                material,
                parameter,
                &scene.lights,
                (settings.epsilon, settings.eye_radius),
            ));
        }
    }
    assert_eq!(cost.settled, settled);
}
