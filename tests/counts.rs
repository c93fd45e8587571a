//! Deterministic counts from pipeline statistics (lavapipe, validation layer on): one triangle
//! at `fixed:n` runs the evaluation shader once per distinct sub-vertex, ceil(3(n+1)²/4); the
//! timestamps around the pass are positive and finite.

mod common;

use ash::vk;
use common::{assert_validation_clean, repo_path, validated_context};
use multirate::analysis::tessellator::uniform_vertex_count;
use multirate::render::{Mode, Renderer, View};
use multirate::scene::Scene;
use multirate::vk::target::RenderTarget;

#[test]
fn one_triangle_at_fixed_n_shades_the_pattern_vertices() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("counts");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("tri.obj"), "v -1 -1 0\nv 1 -1 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scene_text = std::fs::read_to_string(repo_path("scenes/test/lambert_directional.toml")).unwrap();
    let scene_path = dir.join("tri.toml");
    let mut patched = String::new();
    for line in scene_text.lines() {
        if line.trim_start().starts_with("obj =") {
            patched.push_str("obj = \"tri.obj\"\n");
        } else if ["translate", "rotate_degrees", "scale"].iter().any(|k| line.trim_start().starts_with(k)) {
            continue;
        } else {
            patched.push_str(line);
            patched.push('\n');
        }
    }
    std::fs::write(&scene_path, patched).unwrap();
    let scene = Scene::load(&scene_path).expect("one-triangle scene");
    assert_eq!(scene.triangle_count(), 1);

    let context = validated_context();
    assert!(context.features.pipeline_statistics, "lavapipe has pipelineStatisticsQuery");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: 64, height: 64 }).expect("target");
    for n in [1u32, 2, 3, 4, 8, 16] {
        let view = View { mode: Mode::Fixed(n), ..View::of_scene(&scene) };
        let measured = renderer.measure(&target, &view, 1, 2).expect("measure");
        let stats = measured.statistics.expect("statistics");
        assert_eq!(stats.tessellation_control_patches, 1, "n = {n}");
        assert_eq!(
            stats.tessellation_evaluation_invocations,
            uniform_vertex_count(n) as u64,
            "n = {n}: evaluation shader runs per distinct sub-vertex"
        );
        assert!(measured.gpu_ms.iter().all(|ms| ms.is_finite() && *ms > 0.0), "{:?}", measured.gpu_ms);
    }
    assert_validation_clean(&context);
}
