//! `multirate` with no subcommand: the window on the default scene where a display exists;
//! otherwise the default scene rendered headless with the trade against `pixel` printed.

use super::common::{default_scene, load_scene, options, GpuArgs};
use super::render::cost_model_line;
use super::shading::ShadingArgs;
use super::view::view;
use anyhow::{Context as _, Result};
use multirate::analysis::metrics;
use multirate::bench;
use multirate::render::cost_model::LavapipeCompiler;
use multirate::render::{output, Mode, Renderer, View};
use multirate::vk::context::DeviceInfo;
use multirate::vk::target::RenderTarget;
use multirate::vk::Context;
use std::path::PathBuf;

/// The first run: the viewer where a display exists, else [`first_run`].
pub fn run(gpu: &GpuArgs) -> Result<()> {
    if has_display() {
        view(&default_scene(), &ShadingArgs::default(), gpu)
            .context("opening the viewer (set no DISPLAY to render headless instead)")
    } else {
        first_run(gpu).context("rendering the default scene headless")
    }
}

fn has_display() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"].iter().any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

/// `multirate` with no command and no display: the default scene in multirate mode, written to
/// `multirate.png` with its level map (`multirate_levels.png`), and the trade against `pixel`
/// measured in the same run: GPU time with the camera still and turning, shading evaluations,
/// the largest error against ε.
fn first_run(gpu: &GpuArgs) -> Result<()> {
    const FRAMES: u32 = 10;
    const TURN_DEGREES: f32 = 1.0;
    let scene = load_scene(&default_scene())?;
    let (width, height) = (scene.settings.width, scene.settings.height);
    let context = Context::headless(&options(gpu))?;
    let renderer = Renderer::new(&context, &scene)?;
    let target = RenderTarget::new(&context, ash::vk::Extent2D { width, height })?;
    let multirate = View { mode: Mode::Multirate, cost_model: true, ..View::of_scene(&scene) };
    let pixel = View { mode: Mode::Pixel, ..multirate.clone() };
    // The analysis frames give the image (the timed variant's, tests/modes.rs), the triangle
    // ids the error is measured on, and the evaluation counts.
    let (pixel_frame, multirate_frame) =
        (renderer.analyze(&target, &pixel)?, renderer.analyze(&target, &multirate)?);
    let levels = renderer.render(&target, &View { heat_map: true, ..multirate.clone() })?;
    let (out, level_map) = (PathBuf::from("multirate.png"), PathBuf::from("multirate_levels.png"));
    output::write_image(&multirate_frame.image, &out, scene.settings.exposure)?;
    output::write_data_png(&levels, &level_map)?;
    // Both modes in turns, the camera still and then turning (`bench --orbit`).
    let views = [multirate.clone(), pixel.clone()];
    let mut medians = Vec::new();
    for orbit_degrees in [0.0, TURN_DEGREES] {
        let schedule = bench::Schedule {
            warmup: 2,
            frames: FRAMES,
            orbit_degrees,
            draw_parts: false,
            pre_pass_steps: false,
            path: None,
        };
        let measurements =
            bench::measure_in_turns(&[&renderer, &renderer], &target, &views, schedule, &mut |_| {})?;
        let [multirate_ms, pixel_ms] = [0, 1].map(|k| bench::Timing::of(&measurements[k].gpu_ms()).median);
        medians.push((orbit_degrees, multirate_ms, pixel_ms));
    }
    let (pixel_evaluations, multirate_evaluations) =
        (pixel_frame.evaluations.total(), multirate_frame.evaluations.total());
    let (reference, test) = (pixel_frame.frame(), multirate_frame.frame());
    let error = metrics::image_error(reference, test, scene.settings.exposure);
    let over = metrics::pixels_over(reference, test, f64::from(multirate.estimator.epsilon));
    println!(
        "{}: {}, {width}x{height}, {} triangles, multirate ε = {}, n_max = {} on {}",
        out.display(),
        scene.description,
        scene.triangle_count(),
        multirate.estimator.epsilon,
        multirate.estimator.n_max,
        context.info.name
    );
    println!("  GPU time (median of {FRAMES} frames, the modes in turns){}:", compiler_note(&context.info));
    for (orbit_degrees, multirate_ms, pixel_ms) in medians {
        let camera = if orbit_degrees == 0.0 {
            "camera still".to_string()
        } else {
            format!("turning {orbit_degrees}° a frame")
        };
        println!(
            "    {camera:<20} multirate {multirate_ms:.2} ms, pixel {pixel_ms:.2} ms: multirate {:.2}× as fast",
            pixel_ms / multirate_ms
        );
    }
    println!(
        "  shading evaluations: multirate {multirate_evaluations}, pixel {pixel_evaluations} ({:.1} %)",
        100.0 * multirate_evaluations as f64 / pixel_evaluations.max(1) as f64
    );
    println!(
        "  largest error against pixel: {:.4} where both show the same triangle (ε = {}), {over} pixels over ε; \
         {:.4} over all pixels, where {} pixels show another triangle",
        error.l_inf_same_triangle, multirate.estimator.epsilon, error.l_inf, error.other_triangle_pixels
    );
    println!("  level map (blue 1 → red n_max, magenta per-pixel): {}", level_map.display());
    println!("  {}", cost_model_line(&context, &scene, &multirate));
    let messages = context.validation().count();
    anyhow::ensure!(messages == 0, "the validation layer reported {messages} message(s)");
    Ok(())
}

/// Where the device is lavapipe run with CI's setting rather than a user's, the timing says so.
fn compiler_note(info: &DeviceInfo) -> &'static str {
    if info.is_lavapipe() && LavapipeCompiler::current() == LavapipeCompiler::Unoptimised {
        " on lavapipe with GALLIVM_PERF=nopt (CI's setting: a pixel about four times as dear as for a user)"
    } else {
        ""
    }
}
