//! Deterministic counts (lavapipe, validation layer on):
//! - pipeline statistics: one triangle at `fixed:n` runs the evaluation shader once per
//!   distinct sub-vertex, ceil(3(n+1)²/4) (at least once on devices other than lavapipe, as
//!   Vulkan allows), and the timestamps around the pass are positive;
//! - the counting variant: the same sub-vertex counts, one fragment evaluation per covered
//!   pixel in `pixel` mode, three vertex evaluations in `vertex` mode, and a scene that falls
//!   back everywhere counts exactly the fragments of `pixel` mode, and the same with the
//!   estimator in the control stage (whose counter is a specialization constant);
//! - multirate draws patches whose levels are all 1 without the tessellator, and shades their
//!   corners by vertex, each vertex shared by such triangles at least once, the same count
//!   every frame;
//! - the back faces of a two-sided mesh fall back to per-pixel shading after the front faces:
//!   hidden, they shade nothing and reach the tessellator only beside a tessellated edge;
//! - the front-facing patches shaded per pixel shade each pixel they show once, and nothing
//!   else, whatever the order in which the pre-pass listed them; the back faces, drawn in the
//!   mesh's order, the same few pixels more every run.

mod common;

use ash::vk;
use common::{assert_validation_clean, repo_path, validated_context};
use multirate::analysis::tessellator::uniform_vertex_count;
use multirate::geometry::cull::CULLED_LEVEL;
use multirate::render::{EvaluationCounts, Mode, Placement, Renderer, View};
use multirate::scene::Scene;
use multirate::shading::estimator::EstimatorSettings;
use multirate::vk::target::RenderTarget;

fn one_triangle_scene() -> Scene {
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
    scene
}

#[test]
fn one_triangle_at_fixed_n_shades_the_pattern_vertices() {
    let scene = one_triangle_scene();
    let context = validated_context();
    assert!(context.features.pipeline_statistics, "lavapipe has pipelineStatisticsQuery");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: 64, height: 64 }).expect("target");
    for n in [1u32, 2, 3, 4, 8, 16] {
        let view = View { mode: Mode::Fixed(n), ..View::of_scene(&scene) };
        let measured = renderer.measure(&target, &view, 1, 3).expect("measure");
        let stats = measured.statistics.expect("statistics");
        let expected = uniform_vertex_count(n) as u64;
        assert_eq!(stats.tessellation_control_patches, 1, "n = {n}");
        // Vulkan runs the evaluation shader at least once per distinct sub-vertex; lavapipe
        // (CI's device) runs it exactly once, an NVIDIA H200 ran it 90 times at n = 8 (61).
        let invocations = stats.tessellation_evaluation_invocations;
        if context.info.is_lavapipe() {
            assert_eq!(invocations, expected, "n = {n}: evaluation shader runs per distinct sub-vertex");
        } else {
            assert!(invocations >= expected, "n = {n}: {invocations} evaluations, {expected} sub-vertices");
        }
        let gpu_ms = measured.gpu_ms();
        assert_eq!(gpu_ms.len(), 3, "n = {n}: one interval per measured frame");
        assert!(gpu_ms.iter().all(|ms| ms.is_finite() && *ms > 0.0), "{gpu_ms:?}");
        assert!(
            measured.frames.windows(2).all(|w| w[1].start_ns >= w[0].end_ns),
            "frames run in submission order: {:?}",
            measured.frames
        );

        let counted = renderer.count_evaluations(&target, &view).expect("count");
        if context.info.is_lavapipe() {
            assert_eq!(counted, EvaluationCounts { sub_vertices: expected, ..Default::default() }, "n = {n}");
        } else {
            assert!(counted.sub_vertices >= expected, "n = {n}: {counted:?}");
        }
    }
    assert_validation_clean(&context);
}

#[test]
fn pixel_and_vertex_modes_count_fragments_and_vertices() {
    let scene = one_triangle_scene();
    let context = validated_context();
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: 80, height: 60 }).expect("target");
    let pixel = View { mode: Mode::Pixel, ..View::of_scene(&scene) };
    let image = renderer.render(&target, &pixel).expect("render");
    let covered = image.pixels.iter().filter(|p| p[3] == 1.0).count() as u64;
    assert!(covered > 100, "the triangle covers part of the image ({covered} pixels)");
    let counted = renderer.count_evaluations(&target, &pixel).expect("count");
    assert_eq!(counted, EvaluationCounts { fragments: covered, ..Default::default() });
    // The deferred reference shades each covered pixel once too, in its full-screen pass.
    let deferred = View { mode: Mode::PixelDeferred, ..pixel.clone() };
    let counted = renderer.count_evaluations(&target, &deferred).expect("count deferred");
    assert_eq!(counted, EvaluationCounts { fragments: covered, ..Default::default() });

    let vertex = View { mode: Mode::Vertex, ..View::of_scene(&scene) };
    let counted = renderer.count_evaluations(&target, &vertex).expect("count");
    assert_eq!(counted, EvaluationCounts { vertices: 3, ..Default::default() });
    assert_validation_clean(&context);
}

#[test]
fn a_scene_that_falls_back_everywhere_counts_the_fragments_of_pixel_mode() {
    // Three sharp lights close above the plane: at ε = 10⁻⁶ no triangle of it can be
    // tessellated within n_max = 2, so every one falls back to per-pixel shading.
    let scene = Scene::load(&repo_path("scenes/plane_lights.toml")).expect("scene");
    let context = validated_context();
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: 96, height: 72 }).expect("target");
    let view = View::of_scene(&scene);
    let estimator = EstimatorSettings { epsilon: 1e-6, n_max: 2, ..view.estimator };
    let multirate = View { mode: Mode::Multirate, estimator, ..view };
    let levels = renderer.record_levels(&target, &multirate).expect("levels");
    // (Triangles outside the view are culled and record CULLED_LEVEL.)
    let drawn: Vec<_> = levels.iter().filter(|l| l[0] != CULLED_LEVEL).collect();
    assert!(!drawn.is_empty() && drawn.iter().all(|l| l[0] == 0.0), "every drawn triangle falls back");

    let pixel = renderer.count_evaluations(&target, &View { mode: Mode::Pixel, ..multirate.clone() });
    let pixel = pixel.expect("count pixel");
    let fallback = renderer.count_evaluations(&target, &multirate).expect("count multirate");
    assert!(pixel.fragments > 1000, "{pixel:?}");
    // The same fragments, no sub-vertices, and the culled patches the level records show.
    let culled = (levels.len() - drawn.len()) as u64;
    assert!(culled > 0, "part of the plane is outside the view");
    assert_eq!(fallback, EvaluationCounts { culled_patches: culled, ..pixel });
    // The control stage's placement counts the same (its counter is a specialization constant).
    let in_the_control_stage = View { placement: Placement::Tcs, ..multirate.clone() };
    let counted = renderer.count_evaluations(&target, &in_the_control_stage).expect("count tcs");
    assert_eq!(counted, fallback, "the control stage's placement");

    // Pipeline statistics are no substitute here: lavapipe's fragment-invocation count
    // includes the helper lanes of every 2×2 quad. `multirate bench --scene
    // scenes/plane_lights.toml --modes pixel --resolution 96x72` shows 69,488 fragment
    // invocations (column fs_invocations) for 4,896 shaded fragments (fragment_evaluations).
    assert_validation_clean(&context);
}

#[test]
fn level_one_patches_skip_the_tessellator_and_shade_their_corners() {
    // The bunny at its own ε: most visible triangles are patches of level 1 with every edge at
    // level 1 (the flat list, drawn without tessellation stages); the rest are tessellated or
    // fall back.
    let scene = Scene::load(&repo_path("scenes/bunny.toml")).expect("scene");
    let context = validated_context();
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: 320, height: 240 }).expect("target");
    let view = View { mode: Mode::Multirate, ..View::of_scene(&scene) };
    let levels = renderer.record_levels(&target, &view).expect("levels");
    let visible: Vec<_> = levels.iter().filter(|l| l[0] != CULLED_LEVEL).collect();
    let flat = visible.iter().filter(|l| **l == &[1.0; 4]).count() as u64;
    let tessellated = visible.len() as u64 - flat;
    assert!(flat > 0 && tessellated > 0, "both kinds of patch: {flat} flat, {tessellated} others");

    let measured = renderer.measure(&target, &view, 0, 1).expect("measure");
    let stats = measured.statistics.expect("statistics");
    assert_eq!(stats.tessellation_control_patches, tessellated, "only the other patches are tessellated");
    // Timed as a user's frame runs: the pre-pass whole, its steps only where asked
    // (`MeasureOptions::pre_pass_steps`: their timestamps flush lavapipe's work).
    assert_eq!(measured.pre_pass.len(), 1, "the frame ran its pre-pass");
    assert!(measured.pre_pass_steps.is_empty(), "{:?}", measured.pre_pass_steps);
    let counted = renderer.count_evaluations(&target, &view).expect("count");
    let flat_only = View { estimator: EstimatorSettings { epsilon: 1e3, ..view.estimator }, ..view.clone() };
    let all_flat = renderer.record_levels(&target, &flat_only).expect("levels at a large ε");
    let all_visible = all_flat.iter().filter(|l| l[0] != CULLED_LEVEL).count() as u64;
    assert!(
        all_flat.iter().all(|l| l[0] == CULLED_LEVEL || *l == [1.0; 4]),
        "a large ε puts every patch at level 1"
    );
    let stats = renderer.measure(&target, &flat_only, 0, 1).expect("measure").statistics.expect("statistics");
    assert_eq!(stats.tessellation_control_patches, 0, "no patch reaches the tessellator");
    // Nor is any shaded per pixel: the per-pixel path draws only the flat patches the pre-pass
    // appended for it, none here, so the frame's one draw is the flat patches' over the mesh.
    let mesh_triangles = (scene.meshes[0].indices.len() / 3) as u64;
    assert_eq!(stats.input_assembly_primitives, mesh_triangles, "{stats:?}");
    // The bunny has no parameter map: its flat patches are one indexed draw of the mesh, so a
    // vertex that visible triangles share is shaded once or a few times (the device reuses
    // vertices within a batch), never less than once, and the same number every frame.
    let indices = &scene.meshes[0].indices;
    let visible_vertices: std::collections::BTreeSet<u32> = (0..indices.len() / 3)
        .filter(|&t| all_flat[t][0] != CULLED_LEVEL)
        .flat_map(|t| indices[3 * t..3 * t + 3].iter().copied())
        .collect();
    let counted_flat = renderer.count_evaluations(&target, &flat_only).expect("count");
    let shaded = counted_flat.sub_vertices;
    assert!(shaded >= visible_vertices.len() as u64, "{shaded} of {} vertices", visible_vertices.len());
    assert!(shaded < 2 * all_visible, "{shaded} corners shaded for {all_visible} triangles");
    assert!(shaded <= stats.vertex_shader_invocations, "{shaded} of {stats:?}");
    let again = renderer.count_evaluations(&target, &flat_only).expect("count");
    assert_eq!(again, counted_flat, "the same count every frame");
    assert!(counted.sub_vertices > shaded, "{counted:?}");
    assert_validation_clean(&context);
}

#[test]
fn back_faces_of_a_two_sided_mesh_fall_back_and_shade_only_where_seen() {
    // The icosphere is closed, so it is one-sided by default and its back faces are culled.
    // Marked two-sided, its back faces are drawn, but shaded per pixel in the fallback draw
    // after the front faces: the early depth test rejects every fragment the front faces hide,
    // so the hidden half costs no shading, where interpolation would shade its sub-vertices.
    let one_sided = Scene::load(&repo_path("scenes/test/ggx_point.toml")).expect("scene");
    let sphere = one_sided.meshes.iter().position(|m| m.name == "sphere").expect("sphere mesh");
    assert!(!one_sided.meshes[sphere].two_sided, "a closed mesh is one-sided by default");
    let mut two_sided = one_sided.clone();
    two_sided.meshes[sphere].two_sided = true;
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 160, height: 120 }).expect("target");
    let view = View { mode: Mode::Multirate, ..View::of_scene(&one_sided) };

    let culling = Renderer::new(&context, &one_sided).expect("renderer");
    let culled_levels = culling.record_levels(&target, &view).expect("levels");
    let culled_counts = culling.count_evaluations(&target, &view).expect("count");
    let culled_image = culling.render(&target, &view).expect("render");
    let keeping = Renderer::new(&context, &two_sided).expect("renderer");
    let kept_levels = keeping.record_levels(&target, &view).expect("levels");
    let kept_counts = keeping.count_evaluations(&target, &view).expect("count");
    let kept_image = keeping.render(&target, &view).expect("render");

    // Every back face the one-sided mesh culls inside the view falls back instead; nothing else
    // changes, neighbours' edge levels included (a fallback asks as little as a culled face).
    let first: usize = two_sided.meshes[..sphere].iter().map(|m| m.indices.len() / 3).sum();
    let count = two_sided.meshes[sphere].indices.len() / 3;
    let mut back_faces = 0u64;
    for (triangle, (culled, kept)) in culled_levels.iter().zip(&kept_levels).enumerate() {
        if (first..first + count).contains(&triangle) && culled[0] == CULLED_LEVEL && kept[0] != CULLED_LEVEL
        {
            assert_eq!(kept[0], 0.0, "triangle {triangle}: a kept back face falls back");
            back_faces += 1;
        } else {
            assert_eq!(culled, kept, "triangle {triangle}");
        }
    }
    assert!(back_faces > count as u64 / 4, "{back_faces} of the sphere's {count} triangles are back faces");
    assert_eq!(kept_counts.culled_patches + back_faces, culled_counts.culled_patches);
    assert_eq!(kept_counts.sub_vertices, culled_counts.sub_vertices, "back faces shade no sub-vertex");
    assert_eq!(kept_counts.fragments, culled_counts.fragments, "nor a fragment: the front faces hide them");
    assert_eq!(kept_image.pixels, culled_image.pixels, "the same image");
    // Only the back faces beside a tessellated edge reach the tessellator (their outer levels
    // must match it), twice: their depth, then their shading; the others are drawn as they
    // are, like the flat patches.
    let patches = |renderer: &Renderer| {
        let measured = renderer.measure(&target, &view, 0, 1).expect("measure");
        measured.statistics.expect("statistics").tessellation_control_patches
    };
    let beside_tessellated = kept_levels.iter().zip(&culled_levels).filter(|(kept, culled)| {
        culled[0] == CULLED_LEVEL && kept[0] == 0.0 && kept[1..].iter().any(|&outer| outer > 1.0)
    });
    let beside_tessellated = beside_tessellated.count() as u64;
    assert!(beside_tessellated < back_faces, "{beside_tessellated} of {back_faces}");
    assert_eq!(patches(&keeping), patches(&culling) + 2 * beside_tessellated);
    assert_validation_clean(&context);
}

#[test]
fn patches_shaded_per_pixel_shade_exactly_the_pixels_they_show() {
    // The teapot at its own ε: front faces whose level exceeds n_max or whose image is too small
    // to estimate are shaded per pixel, drawn from lists that the pre-pass fills by atomics in no
    // fixed order. Their depth goes first, so a fragment is shaded only where its patch is the
    // nearest surface: drawn one-sided, the count is the number of pixels that show such a patch,
    // in any order (with the early depth test alone it was that plus the overlaps drawn far to
    // near, and varied between runs). Drawn two-sided, the back faces follow, as `pixel` mode
    // draws them (in the mesh's order, without a depth prime of their own): a back face drawn
    // before a nearer one, or a front face shaded per pixel behind a back face, shades too, the
    // same few pixels every run.
    let two_sided = Scene::load(&repo_path("scenes/teapot.toml")).expect("scene");
    assert!(two_sided.meshes.iter().any(|m| m.two_sided), "the teapot is drawn two-sided");
    let mut one_sided = two_sided.clone();
    one_sided.meshes.iter_mut().for_each(|m| m.two_sided = false);
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 320, height: 240 }).expect("target");
    let view = View { mode: Mode::Multirate, ..View::of_scene(&two_sided) };
    let one_sided_renderer = Renderer::new(&context, &one_sided).expect("renderer");
    let one_sided_levels = one_sided_renderer.record_levels(&target, &view).expect("levels");
    drop(one_sided_renderer);
    // Two runs' fragments shaded per pixel, pixels showing a front face shaded per pixel, and
    // pixels showing a back face.
    let shaded = |scene: &Scene| {
        let renderer = Renderer::new(&context, scene).expect("renderer");
        let levels = renderer.record_levels(&target, &view).expect("levels");
        let back_face = |t: usize| one_sided_levels[t][0] == CULLED_LEVEL && levels[t][0] != CULLED_LEVEL;
        (0..2)
            .map(|_| {
                let analysis = renderer.analyze(&target, &view).expect("analyze");
                let (mut front, mut back) = (0u64, 0u64);
                for &id in analysis.triangles.iter().filter(|&&id| id != 0) {
                    let triangle = id as usize - 1;
                    if levels[triangle][0] == 0.0 {
                        *(if back_face(triangle) { &mut back } else { &mut front }) += 1;
                    }
                }
                (analysis.evaluations.fragments, front, back)
            })
            .collect::<Vec<_>>()
    };
    let runs = shaded(&one_sided);
    for (run, &(fragments, front, back)) in runs.iter().enumerate() {
        assert!(front > 500, "run {run}: {front} pixels show a patch shaded per pixel");
        assert_eq!(back, 0, "run {run}: a one-sided mesh shows no back face");
        assert_eq!(fragments, front, "run {run}, one-sided");
    }
    let runs = shaded(&two_sided);
    let (fragments, front, back) = runs[0];
    assert!(back > 100, "{back} pixels show a back face");
    let overlaps = fragments.checked_sub(front + back).expect("every pixel shown is shaded");
    assert!(overlaps <= back / 20, "{overlaps} back-face fragments shaded and hidden, {back} shown");
    assert_eq!(runs[1], runs[0], "the same count every run");
    assert_validation_clean(&context);
}
