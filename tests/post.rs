//! The post chain on lavapipe (validation layer on): it leaves the linear frame, on which every
//! error is measured, as it was; eye adaptation brings a dim and a bright grey frame to about
//! the same display value (at once for a single image, over its time constant in a sequence);
//! bloom spreads a bright pixel into its neighbours and leaves a frame under the threshold
//! unchanged; the tone map's output is in [0, 1] and monotonic in the frame's luminance.

mod common;

use ash::vk;
use common::{assert_validation_clean, repo_path, validated_context};
use multirate::render::post::{Adapt, PostChain, PostSettings};
use multirate::render::{Renderer, View};
use multirate::scene::Scene;
use multirate::shading::tonemap::{aces_filmic, srgb_encode};
use multirate::vk::memory::Image;
use multirate::vk::target::{FloatImage, RenderTarget, COLOR_FORMAT};
use multirate::vk::texture::{upload_image, LevelData};
use multirate::vk::Context;
use std::sync::Arc;

const SIZE: u32 = 64;

/// A linear frame of `SIZE`² pixels, `radiance(x, y)` each, uploaded ready to be sampled.
fn frame(context: &Arc<Context>, radiance: impl Fn(u32, u32) -> f32) -> Image {
    let texels: Vec<[f32; 4]> =
        (0..SIZE * SIZE).map(|i| radiance(i % SIZE, i / SIZE)).map(|v| [v, v, v, 1.0]).collect();
    let level = LevelData { width: SIZE, height: SIZE, texels: bytemuck::cast_slice(&texels) };
    upload_image(context, "post test frame", COLOR_FORMAT, &[level]).expect("upload the frame")
}

fn chain(context: &Arc<Context>, settings: PostSettings) -> PostChain {
    PostChain::new(context, COLOR_FORMAT, true, settings).expect("post chain")
}

/// The chain's display image of `input`, at scene exposure 1.
fn display(chain: &mut PostChain, input: &Image, adapt: Adapt) -> FloatImage {
    chain.bind_input(input).expect("bind the frame");
    chain.read(vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL, 1.0, adapt).expect("run the chain")
}

/// The display value of a grey exposed to `exposed` with no bloom.
fn grey_display(exposed: f32) -> f32 {
    srgb_encode(aces_filmic(exposed))
}

#[test]
fn the_post_chain_leaves_the_linear_frame_as_it_was() {
    let context = validated_context();
    let scene = Scene::load(&repo_path("scenes/shadows.toml")).expect("scenes/shadows.toml loads");
    let renderer = Renderer::new(&context, &scene).expect("renderer");
    let target = RenderTarget::new(&context, vk::Extent2D { width: 96, height: 64 }).expect("target");
    let linear = renderer.render(&target, &View::of_scene(&scene)).expect("render");
    let mut chain = chain(&context, PostSettings::default());
    chain.bind_input(&target.color).expect("bind the target");
    let shown = chain
        .read(vk::ImageLayout::TRANSFER_SRC_OPTIMAL, scene.settings.exposure, Adapt::AtOnce)
        .expect("run the chain");
    // The target is back in TRANSFER_SRC_OPTIMAL: read it again without drawing.
    let again = target.render_and_read(&context, |_| {}).expect("read the target again");
    assert_eq!(linear, again, "the post chain changed the linear frame");
    assert_eq!((shown.width, shown.height), (96, 64));
    let lit = shown.pixels.iter().filter(|p| p[0] > 0.05).count();
    assert!(lit > shown.pixels.len() / 10, "the display image is dark: {lit} lit pixels");
    assert_validation_clean(&context);
}

#[test]
fn eye_adaptation_brings_dim_and_bright_frames_to_the_key() {
    let context = validated_context();
    let settings = PostSettings::default();
    let mut chain = chain(&context, settings);
    let dim = frame(&context, |_, _| 0.05);
    let bright = frame(&context, |_, _| 2.0);
    let expected = grey_display(settings.key);
    let dim_shown = display(&mut chain, &dim, Adapt::AtOnce).pixel(10, 10)[0];
    assert!((dim_shown - expected).abs() < 2e-3, "dim frame shown {dim_shown}, the key shows {expected}");
    // A moment after the change, the eye has not adapted yet: the bright frame is still
    // exposed for the dim one.
    let soon = display(&mut chain, &bright, Adapt::After(0.05)).pixel(10, 10)[0];
    assert!(soon > expected + 0.2, "adapted too fast: {soon} against {expected}");
    // After many time constants it has.
    let later = display(&mut chain, &bright, Adapt::After(30.0)).pixel(10, 10)[0];
    assert!((later - expected).abs() < 2e-3, "bright frame shown {later}, the key shows {expected}");
    assert!((later - dim_shown).abs() < 2e-3);
    assert_validation_clean(&context);
}

#[test]
fn bloom_spreads_a_bright_pixel_and_leaves_a_frame_under_the_threshold() {
    let context = validated_context();
    let bloomed = PostSettings::default();
    let plain = PostSettings { bloom_strength: 0.0, ..bloomed };
    let (mut with, mut without) = (chain(&context, bloomed), chain(&context, plain));
    let spot = frame(&context, |x, y| if (x, y) == (32, 32) { 5000.0 } else { 0.1 });
    let (a, b) = (display(&mut with, &spot, Adapt::AtOnce), display(&mut without, &spot, Adapt::AtOnce));
    for (x, y) in [(36, 32), (32, 28), (40, 40)] {
        let (glow, none) = (a.pixel(x, y)[0], b.pixel(x, y)[0]);
        assert!(glow > none + 0.01, "no bloom at ({x}, {y}): {glow} against {none}");
    }
    let (far, none) = (a.pixel(2, 60)[0], b.pixel(2, 60)[0]);
    assert!((far - none).abs() < 1e-4, "bloom reached the far corner: {far} against {none}");
    // Under the threshold (exposed at the key, everything is far below 1), bloom adds nothing.
    let gradient = frame(&context, |x, y| 0.02 + 0.01 * (x + y) as f32);
    let (a, b) =
        (display(&mut with, &gradient, Adapt::AtOnce), display(&mut without, &gradient, Adapt::AtOnce));
    assert_eq!(a, b, "bloom changed a frame under its threshold");
    assert_validation_clean(&context);
}

#[test]
fn the_tone_map_is_bounded_and_monotonic_in_luminance() {
    let context = validated_context();
    let mut chain = chain(&context, PostSettings::default());
    // Columns of growing radiance, from below zero to far beyond white.
    let ramp = |x: u32| if x == 0 { -1.0 } else { 1e-3 * 1.25f32.powi(x as i32) };
    let image = frame(&context, |x, _| ramp(x));
    let shown = display(&mut chain, &image, Adapt::AtOnce);
    for pixel in &shown.pixels {
        assert!(pixel.iter().all(|v| (0.0..=1.0).contains(v)), "out of [0, 1]: {pixel:?}");
    }
    let row = |y: u32| (0..SIZE).map(|x| shown.pixel(x, y)[0]).collect::<Vec<f32>>();
    for y in [0, 31, 63] {
        let values = row(y);
        assert!(values.windows(2).all(|w| w[1] >= w[0]), "not monotonic in row {y}: {values:?}");
        assert!(values[SIZE as usize - 1] > 0.99 && values[0] == 0.0, "row {y} spans {values:?}");
    }
    assert_validation_clean(&context);
}
