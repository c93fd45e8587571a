//! `multirate` mode on lavapipe with the validation layer on:
//! - the levels the control stage chooses (recorded by its analysis variant) equal the Rust
//!   twin's (`analysis::report`), shared edges and culled triangles included, and are the same
//!   with the estimator in the control stage and in the compute pre-pass;
//! - on every shipped scene, every pixel that shows the same triangle as in `pixel` mode is
//!   within ε of it (triangle ids of the analysis render): with the default terminator rule
//!   (Relaxed) on every scene, with the Conservative rule on one scene of each material kind.
//!   The Rust twin proves the rest for the Conservative rule: on every shipped scene it
//!   chooses Relaxed's level or shades the triangle per pixel;
//! - no cracks: coverage inside the reference silhouette is complete;
//! - extreme inputs render with the coverage of `pixel` mode and no NaN;
//! - a scene at 10⁶ is recentred at load time and renders as at the origin, multirate within ε;
//! - an OBJ model of three MTL materials (one without normals) renders framed, lit, within ε.

mod common;

use ash::vk;
use common::{assert_validation_clean, cracks, on_an_edge, repo_path, validated_context};
use glam::DVec3;
use multirate::analysis::{metrics, report};
use multirate::geometry::cull::CULLED_LEVEL;
use multirate::gpu_interface::slots::{LEVEL_DISPATCHES, REFINE_DISPATCH};
use multirate::render::{Analysis, Mode, Placement, Renderer, View};
use multirate::scene::Scene;
use multirate::shading::estimator::{Discontinuity, EstimatorSettings, Reason, Split};
use multirate::vk::target::{FloatImage, RenderTarget};
use std::path::{Path, PathBuf};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

#[test]
fn control_stage_levels_equal_the_twin() {
    let context = validated_context();
    let (width, height) = (64, 48);
    let target = RenderTarget::new(&context, vk::Extent2D { width, height }).expect("target");
    let (mut compared, mut different, mut culled, mut placements_compared) = (0usize, 0usize, 0usize, 0);
    let (mut small, mut estimated_beside_small, mut lowered_in_shadow) = (0usize, 0usize, 0usize);
    for (index, relative) in [
        "scenes/bunny.toml",
        "scenes/teapot.toml",
        "scenes/plane_lights.toml",
        "scenes/test/ggx_point.toml",
        "scenes/bunny_spots.toml",
        "scenes/teapot_fabric.toml",
        "scenes/plane_polygons.toml",
        "scenes/teapot_polygons.toml",
        "scenes/shadows.toml",
    ]
    .into_iter()
    .enumerate()
    {
        let mut scene = Scene::load(&repo_path(relative)).expect("scene");
        // The twin culls with the scene's camera at the scene's size: the target's.
        (scene.settings.width, scene.settings.height) = (width, height);
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        // Every setting builds its own pipelines (a few seconds each on lavapipe): the shipped
        // untextured scenes take all three, the others the default one (Relaxed).
        let untextured = ["scenes/bunny.toml", "scenes/teapot.toml", "scenes/plane_lights.toml"];
        let settings_to_check = if untextured.contains(&relative) { 3 } else { 1 };
        // The later settings also shade small images per pixel unestimated (the cost model's
        // class, `geometry::cull::small_image`): areas of a few pixels of the 64×48 target.
        // Every other scene's first setting, and the second, estimate for a ball of eyes (2 % of
        // the camera's distance to its target).
        let ball = 0.02 * scene.camera.eye.distance(scene.camera.target);
        for (epsilon, split, discontinuity, min_estimated_area, eye_radius) in [
            (0.075, Split::Heuristic, Discontinuity::Relaxed, 0.0, if index % 2 == 1 { ball } else { 0.0 }),
            (0.3, Split::Heuristic, Discontinuity::Conservative, 2.0, ball),
            (0.02, Split::Uniform, Discontinuity::Relaxed, 0.5, 0.0),
        ]
        .into_iter()
        .take(settings_to_check)
        {
            let scene_view = View::of_scene(&scene);
            let estimator = EstimatorSettings {
                epsilon,
                split,
                discontinuity,
                min_estimated_area,
                eye_radius,
                ..scene_view.estimator
            };
            let view = View { estimator, ..scene_view };
            assert_eq!(view.placement, Placement::Compute, "the default placement");
            let gpu = renderer.record_levels(&target, &view).expect("levels");
            // Both placements run triangle_level.glsl and must record the same levels.
            let tcs = View { placement: Placement::Tcs, ..view.clone() };
            let tcs = renderer.record_levels(&target, &tcs).expect("levels");
            assert!(tcs == gpu, "{relative} ε {epsilon}: the placements differ");
            placements_compared += 1;
            let twin = twin_reports(&scene, &view, &renderer);
            assert_eq!(gpu.len(), twin.len(), "{relative}: one record per triangle");
            if !scene.shadow_casters.is_empty() {
                // The lights that reach none of a triangle are out of its estimate: lower levels.
                let settings = &view.estimator;
                let unshadowed = report::analyze(
                    &scene,
                    settings,
                    report::Triangles::All,
                    false,
                    report::TextureBounds::Pyramid,
                    None,
                );
                lowered_in_shadow += twin
                    .iter()
                    .zip(&unshadowed)
                    .filter(|(t, u)| !t.culled && t.estimate.level < u.estimate.level)
                    .count();
            }
            let small_here = twin.iter().filter(|t| t.small_image && !t.culled).count();
            small += small_here;
            if small_here > 0 {
                estimated_beside_small += twin.iter().filter(|t| !t.culled && !t.levels.fallback).count();
            }
            for (g, t) in gpu.iter().zip(&twin) {
                let level = t.patch_level as f32;
                let expected = if t.culled {
                    culled += 1;
                    [CULLED_LEVEL, 0.0, 0.0, 0.0]
                } else {
                    [level, t.outer[0] as f32, t.outer[1] as f32, t.outer[2] as f32]
                };
                compared += 1;
                if *g != expected {
                    different += 1;
                    let off_by_one = g.iter().zip(&expected).all(|(a, b)| (a - b).abs() <= 1.0);
                    assert!(
                        off_by_one,
                        "{relative} ε {epsilon}: triangle {} of mesh {}: GPU {g:?}, twin {expected:?}",
                        t.triangle, t.mesh
                    );
                }
            }
        }
    }
    eprintln!("levels: {different} of {compared} triangles differ; {culled} culled; {small} small images");
    assert!(culled > 0, "no triangle was culled: the culling goes untested");
    assert!(small > 0 && estimated_beside_small > 0, "the small-image class goes untested");
    assert_eq!(placements_compared, 15, "both placements were compared on every scene and setting");
    assert!(lowered_in_shadow > 0, "no estimate left a shadowed light out: that goes untested");
    eprintln!("{lowered_in_shadow} triangles of the shadow scene estimated lower for their shadowed lights");
    // The GLSL estimator is bit-identical to the twin (its own elementary functions, precise
    // arithmetic): every level must agree exactly.
    assert_eq!(different, 0, "{different} of {compared} triangles differ from the twin");
    assert_validation_clean(&context);
}

/// The refining step's list on the GPU holds as many triangles as the twin refines
/// (`Estimate::refined`, culled triangles, back faces and small images left out as the GPU leaves
/// them): the refining floor skips the same ones on both. On the spotted bunny it skips most of
/// the triangles whose first estimate falls back (they would be listed without it); on the teapot
/// (GGX) it skips none, and its refining step still has triangles to refine.
#[test]
fn the_refining_step_lists_what_the_twin_refines() {
    let context = validated_context();
    let (width, height) = (160, 120);
    let target = RenderTarget::new(&context, vk::Extent2D { width, height }).expect("target");
    for relative in ["scenes/bunny_spots.toml", "scenes/teapot.toml"] {
        let mut scene = Scene::load(&repo_path(relative)).expect("scene");
        (scene.settings.width, scene.settings.height) = (width, height);
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        let scene_view = View::of_scene(&scene);
        let view = View {
            estimator: EstimatorSettings { min_estimated_area: 0.0, ..scene_view.estimator },
            ..scene_view
        };
        let dispatches = renderer.pre_pass_dispatches(&target, &view).expect("dispatches");
        let per_mesh = LEVEL_DISPATCHES as usize;
        let listed: u32 = (0..scene.meshes.len())
            .map(|mesh| dispatches[mesh * per_mesh + REFINE_DISPATCH as usize][3])
            .sum();
        let twin = twin_reports(&scene, &view, &renderer);
        let estimated: Vec<_> = twin.iter().filter(|t| !t.culled && !t.back_face && !t.small_image).collect();
        let refined = estimated.iter().filter(|t| t.estimate.refined).count();
        let fallbacks = estimated.iter().filter(|t| t.estimate.fallback).count();
        eprintln!("{relative}: {listed} listed to refine, the twin refines {refined}; {fallbacks} fall back");
        assert_eq!(
            listed as usize, refined,
            "{relative}: the GPU lists {listed} to refine, the twin refines {refined}"
        );
        if relative.contains("spots") {
            assert!(
                4 * refined < fallbacks,
                "{relative}: the floor skips too few ({refined} refined, {fallbacks} fall back)"
            );
        } else {
            assert!(refined > 0, "{relative}: nothing to refine, the step goes untested");
        }
    }
    assert_validation_clean(&context);
}

/// The twin's report on every triangle of `scene` (culled ones included, in the GPU's order) as
/// `view` estimates it, parameter maps bounded by their min/max pyramid as the GPU bounds them,
/// the lights that reach none of a triangle left out by `renderer`'s visibility classes.
fn twin_reports(scene: &Scene, view: &View, renderer: &Renderer) -> Vec<report::TriangleReport> {
    let classes = (!scene.shadow_casters.is_empty()).then(|| renderer.shadow_classes());
    report::analyze(
        scene,
        &view.estimator,
        report::Triangles::All,
        false,
        report::TextureBounds::Pyramid,
        classes.as_ref(),
    )
}

fn render(renderer: &Renderer, target: &RenderTarget, view: &View) -> FloatImage {
    let image = renderer.render(target, view).expect("render");
    assert!(image.pixels.iter().flatten().all(|v| v.is_finite()), "{:?}: non-finite value", view.mode);
    image
}

/// Every scene under `scenes/` (the shipped ones).
fn shipped_scenes() -> Vec<PathBuf> {
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(repo_path("scenes"))
        .expect("scenes folder")
        .map(|entry| entry.expect("folder entry").path())
        .filter(|path| path.extension().is_some_and(|e| e == "toml"))
        .collect();
    scenes.sort();
    scenes
}

/// On each scene of `scenes`, with `discontinuity`'s terminator rule and ε 0.02, 0.075 and 0.3,
/// every pixel that shows the same triangle as in `pixel` mode is within ε of it, there are no
/// cracks, and fewer than 2 % of the covered pixels show another triangle.
fn assert_same_triangle_pixels_within_epsilon(scenes: &[PathBuf], discontinuity: Discontinuity) {
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    for path in scenes {
        let name = path.file_stem().expect("file name").to_string_lossy().into_owned();
        let start = std::time::Instant::now();
        let scene = Scene::load(path).expect("scene");
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        let reference = renderer.analyze(&target, &View::of_scene(&scene)).expect("analyze pixel");
        let covered = reference.triangles.iter().filter(|&&id| id != 0).count();
        for epsilon in [0.02, 0.075, 0.3] {
            let scene_view = View::of_scene(&scene);
            let estimator = EstimatorSettings { epsilon, discontinuity, ..scene_view.estimator };
            let view = View { mode: Mode::Multirate, estimator, ..scene_view };
            let what = format!("{name} {discontinuity:?} ε {epsilon}");
            let analysis = renderer.analyze(&target, &view).expect("analyze multirate");
            assert!(analysis.image.pixels.iter().flatten().all(|v| v.is_finite()), "{what}: not finite");
            assert_eq!(cracks(&reference.image, &analysis.image), 0, "{what}: cracks");
            let (expected, image) = (reference.frame(), analysis.frame());
            let error = metrics::image_error(expected, image, scene.settings.exposure);
            let over = metrics::pixels_over(expected, image, f64::from(epsilon));
            eprintln!(
                "{what}: L∞ {:.4} ({:.2} ε) on pixels of the same triangle, {} pixels show another",
                error.l_inf_same_triangle,
                error.l_inf_same_triangle / f64::from(epsilon),
                error.other_triangle_pixels
            );
            assert_eq!(over, 0, "{what}: {over} pixels of the same triangle over ε ({error:?})");
            assert!(
                error.other_triangle_pixels * 50 < covered,
                "{what}: {} of {covered} pixels show another triangle",
                error.other_triangle_pixels
            );
        }
        eprintln!("{name}: {:.1} s", start.elapsed().as_secs_f64());
    }
    assert_validation_clean(&context);
}

/// The room's pipelines take most of the time under validation: it runs beside the others. The
/// room with shadows (its twin in geometry and materials) runs in tests/shadows.rs, at the ε of
/// its done-when in both placements.
fn is_room(path: &Path) -> bool {
    path.file_stem().is_some_and(|name| name == "room")
}

fn is_room_with_shadows(path: &Path) -> bool {
    path.file_stem().is_some_and(|name| name == "room_shadows")
}

#[test]
fn every_pixel_showing_the_same_triangle_is_within_epsilon_of_pixel_mode_without_cracks() {
    let scenes: Vec<PathBuf> =
        shipped_scenes().into_iter().filter(|path| !is_room(path) && !is_room_with_shadows(path)).collect();
    assert!(scenes.len() >= 9, "the shipped scenes: {scenes:?}");
    assert_same_triangle_pixels_within_epsilon(&scenes, Discontinuity::Relaxed);
}

#[test]
fn every_pixel_of_the_room_showing_the_same_triangle_is_within_epsilon_of_pixel_mode() {
    let room: Vec<PathBuf> = shipped_scenes().into_iter().filter(|path| is_room(path)).collect();
    assert_eq!(room.len(), 1, "scenes/room.toml");
    assert_same_triangle_pixels_within_epsilon(&room, Discontinuity::Relaxed);
}

/// The Conservative rule on the GPU, on one scene of each material kind (Blinn-Phong with
/// point and directional lights, GGX, Lambert under polygonal lights); on the other scenes
/// `the_conservative_rule_keeps_the_relaxed_level_or_shades_per_pixel` carries the Relaxed
/// rule's result over.
#[test]
fn with_the_conservative_rule_every_pixel_showing_the_same_triangle_is_within_epsilon() {
    let scenes = ["scenes/bunny.toml", "scenes/teapot.toml", "scenes/plane_polygons.toml"].map(repo_path);
    assert_same_triangle_pixels_within_epsilon(&scenes, Discontinuity::Conservative);
}

/// On every shipped scene and ε of the GPU tests, the Rust twin's Conservative rule (the
/// control stage's bit for bit, `control_stage_levels_equal_the_twin`) gives each triangle
/// Relaxed's estimate, or shades it per pixel for a kink it does not bound: the only
/// triangles it draws differently are exact. Its images are therefore within ε wherever the
/// Relaxed rule's are, which the GPU tests check on every scene.
#[test]
fn the_conservative_rule_keeps_the_relaxed_level_or_shades_per_pixel() {
    let (mut estimated, mut shaded_per_pixel) = (0usize, 0usize);
    for path in shipped_scenes() {
        let mut scene = Scene::load(&path).expect("scene");
        (scene.settings.width, scene.settings.height) = (WIDTH, HEIGHT);
        for epsilon in [0.02, 0.075, 0.3] {
            let analyze = |discontinuity| {
                let settings =
                    EstimatorSettings { epsilon, discontinuity, ..View::of_scene(&scene).estimator };
                report::analyze(
                    &scene,
                    &settings,
                    report::Triangles::Visible,
                    false,
                    report::TextureBounds::Pyramid,
                    None,
                )
            };
            let (relaxed, conservative) =
                (analyze(Discontinuity::Relaxed), analyze(Discontinuity::Conservative));
            assert_eq!(relaxed.len(), conservative.len(), "{path:?}: the same visible triangles");
            for (r, c) in relaxed.iter().zip(&conservative) {
                assert_eq!((r.mesh, r.triangle), (c.mesh, c.triangle), "{path:?}: the same order");
                if c.estimate == r.estimate {
                    estimated += 1;
                    continue;
                }
                assert!(
                    c.estimate.fallback
                        && matches!(c.estimate.reason, Reason::Discontinuity | Reason::Singular),
                    "{path:?} ε {epsilon}: triangle {} of mesh {}: Relaxed {:?}, Conservative {:?}",
                    r.triangle,
                    r.mesh,
                    r.estimate,
                    c.estimate
                );
                shaded_per_pixel += 1;
            }
        }
    }
    eprintln!("Conservative: {shaded_per_pixel} triangles per pixel for a kink, {estimated} as Relaxed");
    assert!(shaded_per_pixel > 0 && estimated > 0, "the rules never differ on the shipped scenes");
}

/// A scene around the shipped icosphere, with `material` and `lights` and the mesh scaled
/// by `scale` (the camera scales along). A camera inside the (closed, so by default one-sided)
/// sphere sees its inner faces: the mesh is then two-sided.
fn extreme_scene(name: &str, scale: f32, material: &str, lights: &str, eye: [f32; 3]) -> PathBuf {
    let inside = eye.iter().map(|c| c * c).sum::<f32>() < 1.0;
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("extremes");
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let mesh = repo_path("scenes/test/icosphere.obj");
    let toml = format!(
        r#"
description = "extreme case {name}"
source = "icosphere from scenes/tools/make_icosphere.py"
[camera]
eye = [{}, {}, {}]
target = [0.0, 0.0, 0.0]
fov_y_degrees = 50.0
[[materials]]
name = "m"
{material}
[[meshes]]
obj = "{}"
material = "m"
scale = {scale}
two_sided = {inside}
{lights}
"#,
        eye[0] * scale,
        eye[1] * scale,
        eye[2] * scale,
        mesh.display()
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, toml).expect("write scene");
    path
}

#[test]
fn extremes_keep_coverage_and_stay_finite() {
    let point = |s: f32, p: [f32; 3]| {
        format!(
            "[[lights]]\ntype = \"point\"\nposition = [{}, {}, {}]\ncolor = [1.0, 1.0, 1.0]\nintensity = {}\n",
            p[0] * s,
            p[1] * s,
            p[2] * s,
            4.0 * s * s
        )
    };
    let grazing = "[[lights]]\ntype = \"directional\"\ndirection = [1.0, -1e-4, 0.0]\ncolor = [1.0, 1.0, 1.0]\nintensity = 2.0\n";
    let ggx =
        |r: f32| format!("type = \"ggx\"\nalbedo = [0.2, 0.2, 0.2]\nf0 = [0.9, 0.9, 0.9]\nroughness = {r}");
    let phong = |s: f32| {
        format!("type = \"blinn_phong\"\nkd = [0.3, 0.3, 0.3]\nks = [0.7, 0.7, 0.7]\nshininess = {s}")
    };
    let eye = [0.0, 0.5, 3.0];
    let cases: Vec<(PathBuf, &[f32])> = vec![
        (extreme_scene("huge", 1.0e6, &phong(64.0), &point(1.0e6, [1.0, 2.0, 2.0]), eye), &[0.075]),
        (extreme_scene("tiny", 1.0e-6, &phong(64.0), &point(1.0e-6, [1.0, 2.0, 2.0]), eye), &[0.075]),
        (extreme_scene("shininess_1", 1.0, &phong(1.0), &point(1.0, [1.0, 2.0, 2.0]), eye), &[0.075]),
        (extreme_scene("shininess_1e4", 1.0, &phong(1.0e4), &point(1.0, [1.0, 2.0, 2.0]), eye), &[0.075]),
        (extreme_scene("roughness_0", 1.0, &ggx(0.0), &point(1.0, [1.0, 2.0, 2.0]), eye), &[0.075]),
        (extreme_scene("roughness_1", 1.0, &ggx(1.0), &point(1.0, [1.0, 2.0, 2.0]), eye), &[0.075]),
        (extreme_scene("grazing_light", 1.0, &ggx(0.3), grazing, eye), &[0.075]),
        (extreme_scene("light_on_surface", 1.0, &phong(32.0), &point(1.0, [0.0, 1.0, 0.0]), eye), &[0.075]),
        (
            extreme_scene("camera_inside", 1.0, &ggx(0.5), &point(1.0, [0.2, 0.1, 0.0]), [0.0, 0.0, 0.1]),
            &[0.075],
        ),
        (
            extreme_scene("epsilon_range", 1.0, &phong(64.0), &point(1.0, [1.0, 2.0, 2.0]), eye),
            &[1e-6, 1.0, 50.0],
        ),
    ];
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 96, height: 72 }).expect("target");
    for (path, epsilons) in cases {
        let scene = Scene::load(&path).expect("extreme scene loads");
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        let reference = render(&renderer, &target, &View::of_scene(&scene));
        for &epsilon in epsilons {
            let scene_view = View::of_scene(&scene);
            let estimator = EstimatorSettings { epsilon, ..scene_view.estimator };
            let view = View { mode: Mode::Multirate, estimator, ..scene_view };
            let image = render(&renderer, &target, &view);
            let mismatched = reference.pixels.iter().zip(&image.pixels).filter(|(a, b)| a[3] != b[3]).count();
            let covered = reference.pixels.iter().filter(|p| p[3] == 1.0).count();
            assert!(covered > 0, "{}: the reference shows the mesh", path.display());
            assert!(
                mismatched * 100 <= covered,
                "{} ε {epsilon}: {mismatched} of {covered} pixels change coverage (holes?)",
                path.display()
            );
            assert_eq!(cracks(&reference, &image), 0, "{} ε {epsilon}: cracks", path.display());
            let levels = renderer.record_levels(&target, &view).expect("levels");
            for record in levels.into_iter().filter(|r| *r != [CULLED_LEVEL, 0.0, 0.0, 0.0]) {
                assert!(record.iter().all(|v| v.is_finite()), "{}: level {record:?}", path.display());
                assert!(
                    record[0] == 0.0 || (1.0..=view.estimator.n_max as f32).contains(&record[0]),
                    "{record:?}"
                );
                assert!(
                    record[1..].iter().all(|o| (1.0..=view.estimator.n_max as f32).contains(o)),
                    "{record:?}"
                );
            }
        }
    }
    assert_validation_clean(&context);
}

/// The shipped icosphere (Blinn-Phong, one point light) with everything moved by `offset` along
/// each axis.
fn offset_sphere_scene(name: &str, offset: f64) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("offsets");
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let at = |p: [f64; 3]| format!("[{:.3}, {:.3}, {:.3}]", p[0] + offset, p[1] + offset, p[2] + offset);
    let toml = format!(
        r#"
description = "the icosphere moved by {offset} along each axis"
[camera]
eye = {}
target = {}
fov_y_degrees = 50.0
[[materials]]
name = "m"
type = "blinn_phong"
kd = [0.3, 0.3, 0.3]
ks = [0.7, 0.7, 0.7]
shininess = 64.0
[[meshes]]
obj = "{}"
material = "m"
translate = {}
[[lights]]
type = "point"
position = {}
color = [1.0, 1.0, 1.0]
intensity = 4.0
"#,
        at([0.0, 0.5, 3.0]),
        at([0.0, 0.0, 0.0]),
        repo_path("scenes/test/icosphere.obj").display(),
        at([0.0, 0.0, 0.0]),
        at([1.0, 2.0, 2.0]),
    );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, toml).expect("write scene");
    path
}

#[test]
fn a_scene_far_from_the_origin_renders_as_at_the_origin() {
    // At 10⁶ f32 world positions are 0.0625 apart: the loader recentres the scene in f64, so
    // it renders as the same scene at the origin, and multirate stays within ε of `pixel`.
    let near = Scene::load(&offset_sphere_scene("near", 0.0)).expect("scene at the origin");
    let far = Scene::load(&offset_sphere_scene("far", 1.0e6)).expect("scene at 10⁶");
    assert_eq!(near.origin, DVec3::ZERO, "a scene around the origin stays where it is");
    assert!((far.origin - DVec3::splat(1.0e6)).length() < 1e-3, "recentred on its mesh: {}", far.origin);
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 160, height: 120 }).expect("target");
    let near_image =
        render(&Renderer::new(&context, &near).expect("renderer"), &target, &View::of_scene(&near));
    let renderer = Renderer::new(&context, &far).expect("renderer");
    let reference = renderer.analyze(&target, &View::of_scene(&far)).expect("analyze pixel");
    let covered = reference.image.pixels.iter().filter(|p| p[3] == 1.0).count();
    assert!(covered > 1000, "the sphere is in view ({covered} pixels)");
    let worst = near_image
        .pixels
        .iter()
        .zip(&reference.image.pixels)
        .map(|(a, b)| (0..4).map(|c| (a[c] - b[c]).abs()).fold(0.0f32, f32::max))
        .fold(0.0f32, f32::max);
    assert!(worst < 1e-3, "pixel mode at 10⁶ differs from the origin by {worst}");

    let far_view = View::of_scene(&far);
    let estimator = EstimatorSettings { epsilon: 0.075, ..far_view.estimator };
    let view = View { mode: Mode::Multirate, estimator, ..far_view };
    assert_multirate_matches(&renderer, &target, &view, &reference, 0);
    assert_validation_clean(&context);
}

/// Multirate `view` covers the pixels of `reference` (pixel mode) but for at most
/// `silhouette_flips` pixels on its silhouettes, without cracks, and every pixel that shows
/// the same triangle as in `reference` is within ε.
///
/// A silhouette pixel may flip: the tessellator's vertices along an edge are snapped to the
/// rasteriser's sub-pixel grid (1/256 pixel on lavapipe) on either side of the straight edge
/// that `pixel` mode rasterises, so a pixel centre within about 1/512 pixel of the edge can land
/// on the other side. Inside the silhouette both sides of every edge snap alike: no cracks.
fn assert_multirate_matches(
    renderer: &Renderer,
    target: &RenderTarget,
    view: &View,
    reference: &Analysis,
    silhouette_flips: usize,
) {
    let analysis = renderer.analyze(target, view).expect("analyze multirate");
    let (expected, image) = (&reference.image, &analysis.image);
    let coverage: Vec<f32> = expected.pixels.iter().map(|p| p[3]).collect();
    let on_silhouette = on_an_edge(&coverage, expected.width as usize);
    let flips: Vec<usize> =
        (0..expected.pixels.len()).filter(|&i| expected.pixels[i][3] != image.pixels[i][3]).collect();
    assert!(
        flips.iter().all(|&i| on_silhouette[i]),
        "multirate covers other pixels than pixel mode: {flips:?}"
    );
    assert!(flips.len() <= silhouette_flips, "{} silhouette pixels flip: {flips:?}", flips.len());
    assert_eq!(cracks(expected, image), 0, "cracks");
    let compared =
        reference.triangles.iter().zip(&analysis.triangles).filter(|(a, b)| a == b && **a != 0).count();
    assert!(compared > 100, "{compared} pixels of the same triangle compared");
    let over = metrics::pixels_over(reference.frame(), analysis.frame(), f64::from(view.estimator.epsilon));
    assert_eq!(over, 0, "{over} pixels of the same triangle over ε");
}

/// A UV sphere of radius 1 in three bands of 12 × 4 quads, each band its own MTL material:
/// Blinn-Phong at the top, GGX (PBR `Pr`/`Pm`) around the middle, Lambert below; the middle band's
/// faces give no normals.
fn banded_sphere_model() -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("banded_sphere");
    std::fs::create_dir_all(&dir).expect("scratch folder");
    let (around, down) = (12, 12);
    let mut obj = String::from("mtllib bands.mtl\n");
    for i in 0..=down {
        let theta = std::f64::consts::PI * i as f64 / down as f64;
        for j in 0..around {
            let phi = std::f64::consts::TAU * j as f64 / around as f64;
            let p = [theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin()];
            obj += &format!("v {} {} {}\nvn {} {} {}\n", p[0], p[1], p[2], p[0], p[1], p[2]);
        }
    }
    let vertex = |i: usize, j: usize| 1 + i * around + j % around;
    for (band, material) in ["glossy", "metal", "matte"].iter().enumerate() {
        obj += &format!("usemtl {material}\n");
        for i in 4 * band..4 * band + 4 {
            for j in 0..around {
                let quad = [vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1)];
                let corners: Vec<String> = quad
                    .iter()
                    .map(|&v| if band == 1 { format!("{v}") } else { format!("{v}//{v}") })
                    .collect();
                obj += &format!("f {}\n", corners.join(" "));
            }
        }
    }
    let mtl = "newmtl glossy\nKd 0.3 0.3 0.6\nKs 0.5 0.5 0.5\nNs 40\n\
               newmtl metal\nKd 0.9 0.7 0.3\nPr 0.4\nPm 0.8\n\
               newmtl matte\nKd 0.7 0.6 0.5\n";
    std::fs::write(dir.join("bands.mtl"), mtl).expect("write MTL");
    let path = dir.join("banded_sphere.obj");
    std::fs::write(&path, obj).expect("write OBJ");
    path
}

#[test]
fn an_obj_model_of_three_materials_renders_within_epsilon() {
    let scene = Scene::load(&banded_sphere_model()).expect("OBJ scene");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    assert_eq!(scene.meshes.len(), 3);
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let reference = renderer.analyze(&target, &View::of_scene(&scene)).expect("analyze pixel");
    let covered = reference.image.pixels.iter().filter(|p| p[3] == 1.0).count();
    assert!(covered > 3000, "the model fills the view ({covered} pixels)");
    // Each band is lit: the framing and the default lights show every material.
    for band in 0..3 {
        let rows = HEIGHT as usize * (2 * band + 1) / 6;
        let lit = reference.image.pixels[rows * WIDTH as usize..(rows + 1) * WIDTH as usize]
            .iter()
            .filter(|p| p[3] == 1.0 && p[0] + p[1] + p[2] > 0.05)
            .count();
        assert!(lit > 10, "band {band}: {lit} lit pixels in row {rows}");
    }
    let view = View { mode: Mode::Multirate, ..View::of_scene(&scene) };
    assert_multirate_matches(&renderer, &target, &view, &reference, 3);
    assert_validation_clean(&context);
}
