//! `render`: one frame of a scene headless into a PNG or EXR file (or, along a camera path, a
//! numbered sequence of them), and the line saying what multirate's cost model chose. With
//! `--post` a PNG goes through the viewer's post chain (eye adaptation, bloom, tone mapping),
//! read back from the GPU; the linear frame is rendered and checked first, as without.

use super::common::{load_scene, options, GpuArgs};
use super::path::{camera_path, check_fps, numbered, parse_path_choice, PathChoice};
use super::shading::ShadingArgs;
use anyhow::{Context as _, Result};
use clap::Args;
use multirate::render::cost_model::CostModel;
use multirate::render::post::{Adapt, PostChain, PostSettings};
use multirate::render::{output, render_headless, Mode, Renderer, View};
use multirate::scene::settings::check_image_size;
use multirate::scene::Scene;
use multirate::vk::target::{FloatImage, RenderTarget, COLOR_FORMAT};
use multirate::vk::Context;
use std::path::PathBuf;
use std::sync::Arc;

#[derive(Args)]
pub struct RenderArgs {
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
    #[arg(long)]
    pub scene: PathBuf,
    /// Output image: .png or .exr (with --path, the frames' name: shot.png → shot_0000.png, …);
    /// a missing folder is made.
    #[arg(long)]
    pub out: PathBuf,
    /// Renders a camera path's frames, in order, with one renderer (as a viewer would): `scene`
    /// (the scene file's [[path]]) or `orbit:SECONDS` (one turn about the target).
    #[arg(long, value_parser = parse_path_choice)]
    pub path: Option<PathChoice>,
    /// Frames a second along --path.
    #[arg(long, default_value_t = 30.0, requires = "path")]
    pub fps: f32,
    /// Width in pixels (default: the scene's).
    #[arg(long)]
    pub width: Option<u32>,
    /// Height in pixels (default: the scene's).
    #[arg(long)]
    pub height: Option<u32>,
    /// Writes the PNG(s) through the viewer's post chain (eye adaptation, bloom, tone mapping;
    /// along --path adapting from frame to frame at --fps) instead of the plain tone map at the
    /// scene's exposure. Only the display image changes: the rendered frame is the same.
    #[arg(long)]
    pub post: bool,
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
    if args.post {
        let png =
            args.out.extension().and_then(|e| e.to_str()).is_some_and(|e| e.eq_ignore_ascii_case("png"));
        anyhow::ensure!(png, "{}: --post writes PNG images: use a .png file name", args.out.display());
    }
    if let Some(folder) = args.out.parent().filter(|folder| !folder.as_os_str().is_empty()) {
        std::fs::create_dir_all(folder).with_context(|| format!("{}: cannot create", folder.display()))?;
    }
    let written = match args.path {
        None if args.post => {
            let renderer = Renderer::new(&context, &scene)?;
            let target = RenderTarget::new(&context, ash::vk::Extent2D { width, height })?;
            let image = renderer.render(&target, &view)?;
            let chain = post_chain(&context, &target)?;
            write_frame(&image, &args.out, scene.settings.exposure, Some((&chain, Adapt::AtOnce)))?;
            args.out.display().to_string()
        }
        None => {
            let image = render_headless(&context, &scene, &view, width, height)?;
            write_frame(&image, &args.out, scene.settings.exposure, None)?;
            args.out.display().to_string()
        }
        Some(choice) => {
            check_fps(args.fps)?;
            let size = (width, height);
            let frames = render_path(
                &context,
                &scene,
                &view,
                (choice, args.fps),
                size,
                (&args.out, args.post, &|_| true),
            )?;
            format!(
                "{} to {} ({frames} frames)",
                numbered(&args.out, 0).display(),
                numbered(&args.out, frames - 1).display()
            )
        }
    };
    println!(
        "{written}: {width}x{height}, {} triangles, mode {} on {}",
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

/// The post chain of PNG output, reading `target`'s colour image.
fn post_chain(context: &Arc<Context>, target: &RenderTarget) -> Result<PostChain> {
    let mut chain = PostChain::new(context, COLOR_FORMAT, true, PostSettings::default())?;
    chain.bind_input(&target.color)?;
    Ok(chain)
}

/// Writes `image` to `out` once it holds only finite values: through `post` (a chain bound to
/// the target `image` was just read from, and how it adapts) where given, else tone mapped at
/// `exposure` or as linear EXR.
fn write_frame(
    image: &FloatImage,
    out: &std::path::Path,
    exposure: f32,
    post: Option<(&PostChain, Adapt)>,
) -> Result<()> {
    let non_finite = image.pixels.iter().flatten().filter(|v| !v.is_finite()).count();
    anyhow::ensure!(
        non_finite == 0,
        "{}: the rendered image holds {non_finite} non-finite values",
        out.display()
    );
    match post {
        None => Ok(output::write_image(image, out, exposure)?),
        Some((chain, adapt)) => {
            let layout = ash::vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            let shown = chain.read(layout, exposure, adapt)?;
            Ok(output::write_display_png(&shown, out)?)
        }
    }
}

/// Renders `scene`'s frames along the path `choice` asks for at `fps`, one renderer for all (its
/// ball of eyes and its shadow maps carried from frame to frame, as in the viewer), each frame
/// `kept` says into `out` numbered (through the post chain when `post`, its eye adapting over
/// the time since the frame written before); returns how many were rendered.
pub fn render_path(
    context: &Arc<Context>,
    scene: &Scene,
    view: &View,
    (choice, fps): (PathChoice, f32),
    (width, height): (u32, u32),
    (out, post, kept): (&std::path::Path, bool, &dyn Fn(usize) -> bool),
) -> Result<usize> {
    let path = camera_path(choice, scene)?;
    let renderer = Renderer::new(context, scene)?;
    let target = RenderTarget::new(context, ash::vk::Extent2D { width, height })?;
    let chain = if post { Some(post_chain(context, &target)?) } else { None };
    let times = path.frame_times(fps);
    let mut written_at = None;
    for (index, &time) in times.iter().enumerate() {
        let camera = scene.camera.on_path(&path, time, scene.bounds());
        let image = renderer.render(&target, &view.seen_from(camera))?;
        if !kept(index) {
            continue;
        }
        let adapt = match written_at {
            None => Adapt::AtOnce,
            Some(before) => Adapt::After(time - before),
        };
        written_at = Some(time);
        let post = chain.as_ref().map(|chain| (chain, adapt));
        write_frame(&image, &numbered(out, index), scene.settings.exposure, post)?;
    }
    Ok(times.len())
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
