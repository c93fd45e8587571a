//! The shading modes against each other on lavapipe (validation layer on): `fixed:1` shades
//! exactly what `vertex` shades; tessellated modes cover exactly the pixels `pixel` covers (no
//! cracks); the error against `pixel` shrinks as the level grows; no NaN anywhere.

mod common;

use ash::vk;
use common::{assert_validation_clean, cracks, repo_path, validated_context};
use multirate::render::{Mode, Renderer, View};
use multirate::scene::Scene;
use multirate::vk::target::{FloatImage, RenderTarget};

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
