//! Textured materials on lavapipe with the validation layer on:
//! - the analytic uv derivatives (seed 002) against the hardware's finite differences;
//! - `pixel-deferred` (visibility buffer, analytic attributes) against the forward `pixel`
//!   reference;
//! - extreme texturing (one texel, strongly magnified and minified, degenerate uvs, the seam
//!   of a cylindrical projection): multirate stays within ε of `pixel` mode;
//! - an interior with its OBJ file's own MTL materials (`scenes/chapel.toml`: textures repeating
//!   far outside [0, 1]), from inside, renders in every mode, and multirate (both placements)
//!   stays within ε of `pixel` mode on the pixels that show the same triangle.

mod common;

use ash::vk;
use common::{assert_validation_clean, interior_tessellated, repo_path, validated_context};
use multirate::analysis::metrics;
use multirate::render::{Mode, Placement, Renderer, View};
use multirate::scene::Scene;
use multirate::shading::estimator::EstimatorSettings;
use multirate::vk::target::{FloatImage, RenderTarget};

fn render(renderer: &Renderer, target: &RenderTarget, view: &View) -> FloatImage {
    let image = renderer.render(target, view).expect("render");
    assert!(image.pixels.iter().flatten().all(|v| v.is_finite()), "{}: non-finite value", view.mode);
    image
}

fn sorted(mut v: Vec<f64>) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    v
}

#[test]
fn analytic_uv_derivatives_match_the_hardware_ones() {
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 320, height: 240 }).expect("target");
    for relative in ["scenes/bunny_spots.toml", "scenes/teapot_fabric.toml"] {
        let scene = Scene::load(&repo_path(relative)).expect("scene");
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        let view = View { mode: Mode::PixelDeferred, derivative_check: true, ..View::of_scene(&scene) };
        let image = render(&renderer, &target, &view);
        // Per covered pixel whose quad lies on one triangle (as the rasteriser's quads do, with
        // helper invocations): the difference relative to the derivatives' own size.
        let covered = image.pixels.iter().filter(|p| p[3] > 0.0).count();
        let relative_differences: Vec<f64> = image
            .pixels
            .iter()
            .filter(|p| p[3] > 0.0 && p[1] > 0.0 && p[2] == 0.0)
            .map(|p| f64::from(p[0]) / f64::from(p[1]))
            .collect();
        let count = relative_differences.len();
        eprintln!("{relative}: {count} of {covered} covered pixels have their quad on one triangle");
        assert!(count > 5_000, "{relative}: only {count} covered pixels");
        let mean = relative_differences.iter().sum::<f64>() / count as f64;
        // Capped at 100 %: on triangles seen nearly edge-on the depth changes across one pixel
        // by more than itself, the one-pixel difference is no derivative at all, and a few such
        // pixels would otherwise decide the mean.
        let capped = relative_differences.iter().map(|d| d.min(1.0)).sum::<f64>() / count as f64;
        let sorted = sorted(relative_differences);
        let (median, p99, max) = (sorted[count / 2], sorted[count * 99 / 100], sorted[count - 1]);
        eprintln!(
            "{relative}: analytic vs hardware uv derivatives over {count} pixels, relative difference mean {mean:.2e} (capped at 1: {capped:.2e}), median {median:.2e}, 99th percentile {p99:.2e}, max {max:.2e}"
        );
        // A one-pixel difference differs from the derivative at the pixel by the second-order
        // term, |∂²uv|/|∂uv| · ½ pixel relative: for perspective-correct uv that is about
        // |∂w/∂x|/w per pixel, the relative change of depth over a pixel, which is below 1 %
        // wherever the surface is not seen edge-on: the median pixel must be within 0.2 %.
        // Near silhouettes the depth changes fast across a pixel; with those the (capped) mean
        // must stay under 2 % (measured: 1.1 % on the bunny, see docs/estimator.md).
        assert!(median < 2e-3, "{relative}: median {median}");
        assert!(capped < 2e-2, "{relative}: mean {capped}");
    }
    assert_validation_clean(&context);
}

#[test]
fn deferred_reference_equals_the_forward_reference() {
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 160, height: 120 }).expect("target");
    for relative in ["scenes/bunny.toml", "scenes/teapot_fabric.toml", "scenes/test/blinn_phong_mixed.toml"] {
        let scene = Scene::load(&repo_path(relative)).expect("scene");
        let renderer = Renderer::new(&context, &scene).expect("renderer");
        let forward = render(&renderer, &target, &View::of_scene(&scene));
        let deferred =
            render(&renderer, &target, &View { mode: Mode::PixelDeferred, ..View::of_scene(&scene) });
        let mut differences = Vec::new();
        for (f, d) in forward.pixels.iter().zip(&deferred.pixels) {
            assert_eq!(f[3], d[3], "{relative}: the id pass covers exactly the pixels of the forward pass");
            if f[3] > 0.0 {
                let scale = f[0].abs().max(f[1].abs()).max(f[2].abs()).max(1.0);
                differences.push((0..3).map(|c| f64::from((f[c] - d[c]).abs() / scale)).fold(0.0, f64::max));
            }
        }
        let count = differences.len();
        let mean = differences.iter().sum::<f64>() / count as f64;
        let sorted = sorted(differences);
        let (p999, max) = (sorted[count * 999 / 1000], sorted[count - 1]);
        eprintln!("{relative}: deferred vs forward over {count} pixels: mean {mean:.2e}, 99.9th percentile {p999:.2e}, max {max:.2e}");
        // Both shade the same point: the rasteriser's interpolation and the analytic
        // barycentrics differ by f32 rounding (10⁻⁶ relative), which the sharpest highlight
        // amplifies by its exponent; textures add the level of detail of quad differences
        // against analytic derivatives (a fraction of a level: blends of neighbouring mips).
        assert!(mean < 2e-3, "{relative}: mean difference {mean}");
        assert!(p999 < 5e-2, "{relative}: 99.9th percentile {p999}");
    }
    assert_validation_clean(&context);
}

#[test]
fn extreme_texturing_stays_within_epsilon() {
    let sphere = repo_path("scenes/test/icosphere.obj").display().to_string().replace('\\', "/");
    let texture =
        |name: &str| repo_path("scenes/textures").join(name).display().to_string().replace('\\', "/");
    // name, parameter map, albedo map, uv scale: one texel; the spots magnified 100× (a few
    // texels over the sphere); minified 40× (many texels per pixel); uvs collapsed to a point.
    let cases = [
        ("one_texel", "one_texel.png", None, 1.0),
        ("magnified", "spots_shininess.png", Some("spots_albedo.png"), 0.01),
        ("minified", "spots_shininess.png", None, 40.0),
        ("degenerate", "checker_8.png", None, 1.0e-7),
    ];
    let mut toml = String::from(
        "description = \"extreme texturing\"\nsource = \"written by the test\"\n\
         [camera]\neye = [0, 1.5, 9]\ntarget = [0, 0, 0]\nfov_y_degrees = 40\n\
         [[lights]]\ntype = \"point\"\nposition = [3, 4, 6]\ncolor = [1, 1, 1]\nintensity = 40\n",
    );
    for (i, (name, map, albedo, scale)) in cases.iter().enumerate() {
        let albedo = albedo.map(|a| format!("kd_map = \"{}\"\n", texture(a))).unwrap_or_default();
        toml += &format!(
            "[[materials]]\nname = \"{name}\"\ntype = \"blinn_phong\"\nkd = [0.5, 0.5, 0.5]\nks = [0.5, 0.5, 0.5]\n\
             shininess_map = \"{}\"\nshininess_range = [4.0, 300.0]\n{albedo}\
             [[meshes]]\nobj = \"{sphere}\"\nmaterial = \"{name}\"\nuv_projection = \"cylindrical\"\n\
             uv_scale = [{scale}, {scale}]\ntranslate = [{}, 0, 0]\n",
            texture(map),
            -4.5 + 3.0 * i as f32,
        );
    }
    let dir = std::env::temp_dir().join(format!("multirate-extreme-textures-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temporary folder");
    let path = dir.join("scene.toml");
    std::fs::write(&path, toml).expect("write scene");
    let scene = Scene::load(&path).expect("extreme textured scene");
    let _ = std::fs::remove_dir_all(&dir);

    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 240, height: 80 }).expect("target");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let reference = render(&renderer, &target, &View::of_scene(&scene));
    for epsilon in [0.01, 0.1] {
        let scene_view = View::of_scene(&scene);
        let estimator = EstimatorSettings { epsilon, ..scene_view.estimator };
        let view = View { mode: Mode::Multirate, estimator, ..scene_view };
        let image = render(&renderer, &target, &view);
        let heat = render(&renderer, &target, &View { heat_map: true, ..view.clone() });
        let mask = interior_tessellated(&heat);
        let (mut checked, mut worst) = (0usize, 0.0f32);
        for ((&inside, m), r) in mask.iter().zip(&image.pixels).zip(&reference.pixels) {
            assert_eq!(m[3], r[3], "ε {epsilon}: coverage differs from pixel mode");
            if inside {
                checked += 1;
                for c in 0..3 {
                    let error = (m[c] - r[c]).abs();
                    worst = worst.max(error / epsilon);
                    // As in tests/multirate.rs: ε plus 10⁻³ relative for rasterisation.
                    assert!(error <= epsilon + 1e-3 * r[c].abs().max(1.0), "ε {epsilon}: error {error}");
                }
            }
        }
        eprintln!(
            "extreme texturing, ε {epsilon}: {checked} interior tessellated pixels, worst {worst:.3} ε"
        );
        assert!(checked > 500, "ε {epsilon}: only {checked} tessellated pixels were checked");
    }
    assert_validation_clean(&context);
}

/// Share of the pixels of `image` that are covered and not black, and how many distinct colours
/// (at 6 bits a channel of the displayed value) they have.
fn lit_share_and_colours(image: &FloatImage) -> (f64, usize) {
    let lit: Vec<&[f32; 4]> =
        image.pixels.iter().filter(|p| p[3] > 0.0 && (p[0] + p[1] + p[2]) > 0.03).collect();
    let mut colours: Vec<[u8; 3]> =
        lit.iter().map(|p| [0, 1, 2].map(|c| (p[c].clamp(0.0, 1.0).sqrt() * 63.0) as u8)).collect();
    colours.sort_unstable();
    colours.dedup();
    (lit.len() as f64 / image.pixels.len() as f64, colours.len())
}

#[test]
fn an_interior_with_its_own_materials_renders_in_every_mode() {
    let relative = "scenes/chapel.toml";
    let scene = Scene::load(&repo_path(relative)).expect("scene");
    assert!(scene.materials.len() >= 3 && scene.materials.iter().any(|m| m.maps.albedo.is_some()));
    let context = validated_context();
    let target = RenderTarget::new(&context, vk::Extent2D { width: 160, height: 120 }).expect("target");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let path = scene.camera_path.as_ref().expect("the chapel has a path");
    let middle = scene.camera.on_path(path, 0.5 * path.duration(), scene.bounds());
    let multirate = |placement| View { mode: Mode::Multirate, placement, ..View::of_scene(&scene) };
    let modes = [
        View::of_scene(&scene),
        View { mode: Mode::PixelDeferred, ..View::of_scene(&scene) },
        View { mode: Mode::Vertex, ..View::of_scene(&scene) },
        View { mode: Mode::Fixed(4), ..View::of_scene(&scene) },
        multirate(Placement::Compute),
        multirate(Placement::Tcs),
    ];
    for camera in [scene.camera, middle] {
        for view in modes.iter().map(|v| v.seen_from(camera)) {
            let image = render(&renderer, &target, &view);
            let (lit, colours) = lit_share_and_colours(&image);
            eprintln!(
                "{relative} {} ({}): {:.1} % lit, {colours} colours",
                view.mode,
                view.placement,
                100.0 * lit
            );
            // Inside the hall every pixel shows a wall, the floor, the vault or what stands in it.
            assert!(lit > 0.95, "{relative} {}: only {:.1} % of the pixels are lit", view.mode, 100.0 * lit);
            assert!(colours > 100, "{relative} {}: only {colours} colours", view.mode);
        }
        let reference = renderer.analyze(&target, &modes[0].seen_from(camera)).expect("pixel");
        for placement in [Placement::Compute, Placement::Tcs] {
            let analysis =
                renderer.analyze(&target, &multirate(placement).seen_from(camera)).expect("multirate");
            let epsilon = f64::from(scene.settings.epsilon);
            let same =
                reference.triangles.iter().zip(&analysis.triangles).filter(|(a, b)| a == b && **a != 0);
            let same = same.count();
            assert!(
                10 * same > 9 * reference.triangles.len(),
                "{relative} ({placement}): {same} same-triangle pixels"
            );
            let over = metrics::pixels_over(reference.frame(), analysis.frame(), epsilon);
            assert_eq!(
                over, 0,
                "{relative} ({placement}): {over} of {same} pixels of the same triangle over ε"
            );
        }
    }
    assert_validation_clean(&context);
}
