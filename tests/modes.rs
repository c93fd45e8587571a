//! The shading modes against each other on lavapipe (validation layer on): `fixed:1` shades
//! exactly what `vertex` shades; tessellated modes cover exactly the pixels `pixel` covers (no
//! cracks); the error against `pixel` shrinks as the level grows; no NaN anywhere; the
//! analysis variant draws the timed image and the triangle each pixel shows; a frame the frame
//! guard draws as `pixel` does is `pixel`'s image.

mod common;

use ash::vk;
use common::{assert_validation_clean, cracks, on_an_edge, repo_path, validated_context};
use multirate::render::{Mode, Placement, Renderer, View};
use multirate::scene::Scene;
use multirate::vk::target::{FloatImage, RenderTarget, EMITTER_ID_BIT};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

fn render_modes(relative: &str, modes: &[Mode]) -> Vec<FloatImage> {
    let scene = Scene::load(&repo_path(relative)).expect("scene loads");
    let context = validated_context();
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    let images = modes
        .iter()
        .map(|&mode| {
            let view = View { mode, ..View::of_scene(&scene) };
            let image = renderer.render(&target, &view).expect("render");
            assert!(
                image.pixels.iter().flatten().all(|v| v.is_finite()),
                "{relative} {mode}: non-finite value"
            );
            image
        })
        .collect();
    assert_validation_clean(&context);
    images
}

/// Pixels covered in one image and not the other.
fn coverage_mismatches(a: &FloatImage, b: &FloatImage) -> usize {
    a.pixels.iter().zip(&b.pixels).filter(|(p, q)| p[3] != q[3]).count()
}

/// Largest and mean per-channel difference over pixels both cover.
fn difference(a: &FloatImage, b: &FloatImage) -> (f32, f32) {
    let mut max = 0.0f32;
    let mut sum = 0.0f64;
    let mut count = 0usize;
    for (p, q) in a.pixels.iter().zip(&b.pixels) {
        if p[3] == 1.0 && q[3] == 1.0 {
            for c in 0..3 {
                let d = (p[c] - q[c]).abs();
                max = max.max(d);
                sum += d as f64;
                count += 1;
            }
        }
    }
    (max, (sum / count.max(1) as f64) as f32)
}

#[test]
fn fixed_1_shades_exactly_the_vertices() {
    for scene in ["scenes/bunny.toml", "scenes/test/ggx_point.toml"] {
        let images = render_modes(scene, &[Mode::Vertex, Mode::Fixed(1)]);
        assert_eq!(coverage_mismatches(&images[0], &images[1]), 0, "{scene}");
        let (max, _) = difference(&images[0], &images[1]);
        assert!(max < 1e-4, "{scene}: vertex and fixed:1 differ by {max}");
    }
}

#[test]
fn tessellated_modes_leave_no_cracks() {
    for scene in ["scenes/bunny.toml", "scenes/teapot.toml", "scenes/test/blinn_phong_mixed.toml"] {
        let modes = [Mode::Pixel, Mode::Vertex, Mode::Fixed(2), Mode::Fixed(5), Mode::Fixed(16)];
        let images = render_modes(scene, &modes);
        let holes: Vec<usize> = images[1..].iter().map(|image| cracks(&images[0], image)).collect();
        let silhouette: Vec<usize> =
            images[1..].iter().map(|image| coverage_mismatches(&images[0], image)).collect();
        eprintln!("{scene}: cracks {holes:?}, coverage differences {silhouette:?} for {:?}", &modes[1..]);
        assert_eq!(holes, vec![0; modes.len() - 1], "{scene}: cracks for {:?}", &modes[1..]);
    }
}

#[test]
fn error_against_pixel_shrinks_with_the_level() {
    let modes =
        [Mode::Pixel, Mode::Fixed(1), Mode::Fixed(2), Mode::Fixed(4), Mode::Fixed(8), Mode::Fixed(16)];
    let images = render_modes("scenes/plane_lights.toml", &modes);
    let errors: Vec<(f32, f32)> = images[1..].iter().map(|image| difference(&images[0], image)).collect();
    eprintln!("plane_lights, (max, mean) error against pixel for fixed 1, 2, 4, 8, 16: {errors:?}");
    for pair in errors.windows(2) {
        assert!(pair[1].1 < pair[0].1, "mean error must shrink as the level doubles: {errors:?}");
    }
    assert!(errors[0].0 > 0.05, "fixed:1 must visibly miss the sharp highlights: {errors:?}");
}

// One test per scene, so that they run side by side. The plane's polygonal lights are in
// view, so their emitters' ids are checked too.
#[test]
fn the_analysis_frame_is_the_timed_image_and_the_triangles_it_shows() {
    assert_the_analysis_frame_is_the_timed_image("scenes/teapot.toml");
}

#[test]
fn the_analysis_frame_is_the_timed_image_and_the_triangles_it_shows_emitters_included() {
    assert_the_analysis_frame_is_the_timed_image("scenes/plane_polygons.toml");
}

/// On `relative`, in every mode: the analysis frame is the timed image, and its triangle ids
/// are those the reference shows but on edges.
fn assert_the_analysis_frame_is_the_timed_image(relative: &str) {
    let scene = Scene::load(&repo_path(relative)).expect("scene loads");
    let context = validated_context();
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    let pixel = View { mode: Mode::Pixel, ..View::of_scene(&scene) };
    let reference = renderer.analyze(&target, &pixel).expect("analyze pixel");
    // Pixel mode's ids are the visibility buffer's (`pixel-deferred`'s first pass), which
    // draws no emitters.
    let mut first_triangle = vec![0u32];
    for mesh in &scene.meshes {
        first_triangle.push(first_triangle.last().unwrap() + (mesh.indices.len() / 3) as u32);
    }
    let visible = renderer.triangle_ids(&target, &pixel).expect("visibility buffer");
    let emitter_pixels = reference.triangles.iter().filter(|&&id| id & EMITTER_ID_BIT != 0).count();
    for (i, (&id, seen)) in reference.triangles.iter().zip(&visible).enumerate() {
        if id & EMITTER_ID_BIT == 0 {
            let expected = seen.map_or(0, |(mesh, triangle)| first_triangle[mesh] + triangle as u32 + 1);
            assert_eq!(id, expected, "{relative}: pixel {i}");
        }
    }
    let on_edge = on_an_edge(&reference.triangles, WIDTH as usize);
    let modes = [
        pixel.clone(),
        View { mode: Mode::PixelDeferred, ..pixel.clone() },
        View { mode: Mode::Vertex, ..pixel.clone() },
        View { mode: Mode::Fixed(3), ..pixel.clone() },
        View { mode: Mode::Multirate, placement: Placement::Compute, ..pixel.clone() },
        View { mode: Mode::Multirate, placement: Placement::Tcs, ..pixel.clone() },
    ];
    for view in modes {
        let what = format!("{relative} {} ({})", view.mode, view.placement);
        let timed = renderer.render(&target, &view).expect("render");
        let analysis = renderer.analyze(&target, &view).expect("analyze");
        assert_eq!(coverage_mismatches(&timed, &analysis.image), 0, "{what}");
        let (max, _) = difference(&timed, &analysis.image);
        assert!(max <= 1e-5, "{what}: the analysis image differs from the timed one by {max}");
        for (p, &id) in analysis.image.pixels.iter().zip(&analysis.triangles) {
            assert_eq!(p[3] > 0.0, id != 0, "{what}: a pixel's id and its coverage disagree");
        }
        // `pixel-deferred` draws no emitters (its full-screen passes shade mesh triangles
        // only): where the others show one, it shows what lies behind.
        let deferred = view.mode == Mode::PixelDeferred;
        let emitters = analysis.triangles.iter().filter(|&&id| id & EMITTER_ID_BIT != 0).count();
        assert_eq!(emitters, if deferred { 0 } else { emitter_pixels }, "{what}: emitter pixels");
        // Only where the reference changes triangle may another triangle be seen: the
        // modes rasterise the same triangles, up to sub-pixel rounding on their edges.
        let differing: Vec<usize> = (0..analysis.triangles.len())
            .filter(|&i| analysis.triangles[i] != reference.triangles[i])
            .filter(|&i| !(deferred && reference.triangles[i] & EMITTER_ID_BIT != 0))
            .collect();
        assert!(differing.iter().all(|&i| on_edge[i]), "{what}: another triangle inside one: {differing:?}");
        eprintln!("{what}: {} pixels show another triangle, on edges", differing.len());
    }
    if relative.contains("polygons") {
        assert!(emitter_pixels > 0, "{relative}: no emitter in view, its ids go untested");
    }
    assert_validation_clean(&context);
}

#[test]
fn the_cost_model_shades_small_images_per_pixel_and_small_meshes_as_pixel_does() {
    let context = validated_context();
    // The dense bunny at a small size: nearly every triangle covers a pixel or two, so the
    // whole mesh is drawn as `pixel` draws it, and the image is `pixel`'s exactly.
    let scene = Scene::load(&repo_path("scenes/bunny_dense.toml")).expect("scene loads");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: WIDTH, height: HEIGHT }).expect("target");
    let extent = vk::Extent2D { width: WIDTH, height: HEIGHT };
    let pixel = View { mode: Mode::Pixel, ..View::of_scene(&scene) };
    let modelled = View { mode: Mode::Multirate, cost_model: true, ..pixel.clone() };
    assert_eq!(renderer.meshes_drawn_per_pixel(&modelled, extent), vec![true]);
    let reference = renderer.render(&target, &pixel).expect("render pixel");
    let image = renderer.render(&target, &modelled).expect("render multirate");
    assert_eq!(coverage_mismatches(&reference, &image), 0);
    assert_eq!(difference(&reference, &image).0, 0.0, "drawn as pixel mode draws it");
    // Without the cost model the same view estimates the bunny, and shades differently.
    let estimated = View { cost_model: false, ..modelled.clone() };
    assert!(renderer.meshes_drawn_per_pixel(&estimated, extent).is_empty());
    assert!(difference(&reference, &renderer.render(&target, &estimated).expect("render")).0 > 0.0);

    // The coarse teapot: its triangles are large, so it is estimated, and those below an area
    // floor between them shade per pixel without an estimate, within ε of `pixel` and with
    // no cracks, in both placements.
    let scene = Scene::load(&repo_path("scenes/teapot.toml")).expect("scene loads");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let (width, height) = (640, 360);
    let extent = vk::Extent2D { width, height };
    let target = RenderTarget::new(&context, extent).expect("target");
    let pixel = View { mode: Mode::Pixel, ..View::of_scene(&scene) };
    assert_eq!(
        renderer.meshes_drawn_per_pixel(
            &View { mode: Mode::Multirate, cost_model: true, ..pixel.clone() },
            extent
        ),
        vec![false]
    );
    let reference = renderer.render(&target, &pixel).expect("render pixel");
    let mut per_placement = Vec::new();
    for placement in [Placement::Compute, Placement::Tcs] {
        let mut view = View { mode: Mode::Multirate, placement, ..pixel.clone() };
        view.estimator.min_estimated_area = 40.0;
        let image = renderer.render(&target, &view).expect("render multirate");
        assert_eq!(cracks(&reference, &image), 0, "{placement}");
        per_placement.push(image);
    }
    // The placements draw the same levels by different paths (flat draws, the tessellator; the
    // compute placement draws most back faces as `pixel` does, untessellated, so a pixel on an
    // edge between a back face and a tessellated front face may show the other surface): the
    // same image but for a few such pixels, where the compute placement shows what `pixel` shows.
    let (compute, tcs) = (&per_placement[0], &per_placement[1]);
    let close = |p: &[f32; 4], q: &[f32; 4], within: f32| (0..3).all(|c| (p[c] - q[c]).abs() < within);
    let apart: Vec<usize> =
        (0..compute.pixels.len()).filter(|&i| !close(&compute.pixels[i], &tcs.pixels[i], 1.0e-3)).collect();
    assert!(apart.len() <= 4, "the placements differ at {} pixels", apart.len());
    let epsilon = pixel.estimator.epsilon;
    for &i in &apart {
        assert!(close(&compute.pixels[i], &reference.pixels[i], epsilon), "pixel {i}: not what pixel shows");
    }
    let report = multirate::analysis::report::analyze(
        &Scene {
            settings: multirate::scene::RenderSettings { width, height, ..scene.settings },
            ..scene.clone()
        },
        &View {
            estimator: multirate::shading::estimator::EstimatorSettings {
                min_estimated_area: 40.0,
                ..pixel.estimator
            },
            ..pixel.clone()
        }
        .estimator,
        multirate::analysis::report::Triangles::Visible,
        false,
        multirate::analysis::report::TextureBounds::Pyramid,
        None,
    );
    let small = report.iter().filter(|t| t.small_image).count();
    assert!(small > 0 && small < report.len(), "{small} of {} visible triangles are small", report.len());
    assert_validation_clean(&context);
}

#[test]
fn a_frame_the_guard_draws_as_pixel_is_pixels_image_in_both_placements() {
    use multirate::render::guard::PROBE_FRAMES;
    let context = validated_context();
    let scene = Scene::load(&repo_path("scenes/teapot.toml")).expect("scene loads");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let extent = vk::Extent2D { width: WIDTH, height: HEIGHT };
    let target = RenderTarget::new(&context, extent).expect("target");
    let pixel = View { mode: Mode::Pixel, ..View::of_scene(&scene) };
    let reference = renderer.render(&target, &pixel).expect("render pixel");
    for placement in [Placement::Compute, Placement::Tcs] {
        let guarded = View { mode: Mode::Multirate, cost_model: true, placement, ..pixel.clone() };
        // A new configuration: the multirate way first, then the probe, `pixel`'s way frame
        // by frame with the multirate way.
        let frames: Vec<View> = (0..3 * PROBE_FRAMES).map(|_| renderer.guarded(&guarded, extent)).collect();
        let (own, probe) = frames.split_at(PROBE_FRAMES as usize);
        assert!(
            own.iter().all(|v| !v.drawn_as_pixel)
                && probe.iter().enumerate().all(|(k, v)| v.drawn_as_pixel == (k % 2 == 0)),
            "{placement}"
        );
        assert_eq!(renderer.meshes_drawn_per_pixel(&probe[0], extent), vec![true], "{placement}");
        let image = renderer.render(&target, &probe[0]).expect("render the probe");
        assert_eq!(coverage_mismatches(&reference, &image), 0, "{placement}");
        assert_eq!(difference(&reference, &image).0, 0.0, "{placement}: drawn as pixel mode draws it");
        // Unguarded views are drawn as they are.
        let fixed_area = View { cost_model: false, ..guarded.clone() };
        assert!(!renderer.guarded(&fixed_area, extent).drawn_as_pixel, "{placement}");
    }
    assert_validation_clean(&context);
}
