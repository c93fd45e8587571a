//! The `multirate` command line: the only place that prints or exits.

use anyhow::{Context as _, Result};
use clap::{Args, Parser, Subcommand};
use multirate::render::{output, render_headless, Mode, View};
use multirate::scene::Scene;
use multirate::vk::{Context, ContextOptions};
use std::path::{Path, PathBuf};

/// Error-bounded multirate shading on the hardware tessellator.
///
/// Without a subcommand: opens a window on the default scene where a display exists,
/// otherwise renders it headless to a PNG and prints where.
#[derive(Parser)]
#[command(version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    #[command(flatten)]
    gpu: GpuArgs,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene headless into a PNG (tone-mapped) or EXR (linear float) file.
    Render(RenderArgs),
    /// Open a window on a scene (drag to orbit, wheel to zoom, Esc to quit).
    View(ViewArgs),
}

#[derive(Args, Clone)]
struct GpuArgs {
    /// Enable the Khronos validation layer; its messages are printed to stderr.
    #[arg(long, global = true)]
    validate: bool,
    /// Use the first Vulkan device whose name contains this text.
    #[arg(long, global = true)]
    device: Option<String>,
}

#[derive(Args)]
struct RenderArgs {
    /// Scene file (TOML).
    #[arg(long)]
    scene: PathBuf,
    /// Output image: .png or .exr.
    #[arg(long)]
    out: PathBuf,
    /// Width in pixels (default: the scene's).
    #[arg(long)]
    width: Option<u32>,
    /// Height in pixels (default: the scene's).
    #[arg(long)]
    height: Option<u32>,
    /// Shading mode: pixel (reference), vertex (Gouraud) or fixed:N (tessellated at level N).
    #[arg(long, default_value = "pixel")]
    mode: Mode,
}

#[derive(Args)]
struct ViewArgs {
    /// Scene file (TOML).
    #[arg(long, default_value_os_t = default_scene())]
    scene: PathBuf,
    /// Initial shading mode (keys P, V, F, + and - change it in the window).
    #[arg(long, default_value = "pixel")]
    mode: Mode,
}

/// `scenes/bunny.toml` from the working directory, or from the source tree.
fn default_scene() -> PathBuf {
    let relative = Path::new("scenes").join("bunny.toml");
    if relative.exists() {
        relative
    } else {
        Path::new(env!("CARGO_MANIFEST_DIR")).join(relative)
    }
}

fn options(gpu: &GpuArgs) -> ContextOptions {
    ContextOptions { validate: gpu.validate, device_name: gpu.device.clone() }
}

fn render(args: &RenderArgs, gpu: &GpuArgs) -> Result<()> {
    let scene = Scene::load(&args.scene)?;
    let width = args.width.unwrap_or(scene.settings.width);
    let height = args.height.unwrap_or(scene.settings.height);
    anyhow::ensure!(
        (1..=16384).contains(&width) && (1..=16384).contains(&height),
        "--width and --height must be between 1 and 16384 (got {width}x{height})"
    );
    let context = Context::headless(&options(gpu))?;
    let mut view = View::of_scene(&scene);
    view.mode = args.mode;
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
    let messages = context.validation().count();
    anyhow::ensure!(messages == 0, "the validation layer reported {messages} message(s)");
    Ok(())
}

fn has_display() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"].iter().any(|v| std::env::var_os(v).is_some_and(|s| !s.is_empty()))
}

fn main() -> Result<()> {
    let cli = Cli::parse();
    match &cli.command {
        Some(Command::Render(args)) => render(args, &cli.gpu),
        Some(Command::View(args)) => {
            multirate::window::view(&args.scene, args.mode, &options(&cli.gpu), None).map(|_| ())
                .with_context(|| format!("viewing {}", args.scene.display()))
        }
        None if has_display() => multirate::window::view(&default_scene(), Mode::Pixel, &options(&cli.gpu), None)
            .map(|_| ())
            .context("opening the viewer (set no DISPLAY to render headless instead)"),
        None => {
            let out = PathBuf::from("multirate.png");
            let args = RenderArgs { scene: default_scene(), out, width: None, height: None, mode: Mode::Pixel };
            render(&args, &cli.gpu)
        }
    }
}
