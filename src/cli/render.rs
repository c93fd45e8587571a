//! `render`: one frame of a scene headless into a PNG or EXR file, and the line saying what
//! multirate's cost model chose.

use super::common::{load_scene, options, GpuArgs};
use super::shading::ShadingArgs;
use anyhow::Result;
use clap::Args;
use multirate::render::cost_model::CostModel;
use multirate::render::{output, render_headless, Mode, View};
use multirate::scene::settings::check_image_size;
use multirate::scene::Scene;
use multirate::vk::Context;
use std::path::PathBuf;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
    #[arg(long)]
    pub scene: PathBuf,
    /// Output image: .png or .exr.
    #[arg(long)]
    pub out: PathBuf,
    /// Width in pixels (default: the scene's).
    #[arg(long)]
    pub width: Option<u32>,
    /// Height in pixels (default: the scene's).
    #[arg(long)]
    pub height: Option<u32>,
    #[command(flatten)]
    pub shading: ShadingArgs,
}

pub fn render(args: &RenderArgs, gpu: &GpuArgs) -> Result<()> {
    let scene = load_scene(&args.scene)?;
    let width = args.width.unwrap_or(scene.settings.width);
    let height = args.height.unwrap_or(scene.settings.height);
    check_image_size(width, height).map_err(|e| anyhow::anyhow!("--width and --height {e}"))?;
    let context = Context::headless(&options(gpu))?;
    let view = args.shading.view(&scene)?;
    let image = render_headless(&context, &scene, &view, width, height)?;
    output::write_image(&image, &args.out, scene.settings.exposure)?;
    let non_finite = image.pixels.iter().flatten().filter(|v| !v.is_finite()).count();
    anyhow::ensure!(non_finite == 0, "the rendered image holds {non_finite} non-finite values");
    println!(
        "{}: {width}x{height}, {} triangles, mode {} on {}",
        args.out.display(),
        scene.triangle_count(),
        view.mode,
        context.info.name
    );
    if view.mode == Mode::Multirate {
        println!("{}", cost_model_line(&context, &scene, &view));
    }
    if matches!(view.mode, Mode::Fixed(_) | Mode::Multirate) {
        if let Some(note) = multirate::render::draw_splitting_note(&context.info) {
            println!("{note}");
        }
    }
    let messages = context.validation().count();
    anyhow::ensure!(messages == 0, "the validation layer reported {messages} message(s)");
    Ok(())
}

/// What multirate's pass estimated with: the cost model's break-even area for the device and the
/// scene, or the area given.
pub fn cost_model_line(context: &Context, scene: &Scene, view: &View) -> String {
    if view.cost_model {
        let model = CostModel::for_device(&context.info.name);
        format!(
            "cost model {}: images under {:.1} px are shaded per pixel without an estimate (`multirate calibrate` measures this device)",
            model.source,
            model.min_estimated_area_of(scene)
        )
    } else {
        format!(
            "images under {} px are shaded per pixel without an estimate",
            view.estimator.min_estimated_area
        )
    }
}
