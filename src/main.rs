//! The `multirate` command line: the only place that prints or exits.

use anyhow::{Context as _, Result};
use clap::{Args, Parser, Subcommand};
use multirate::analysis::{metrics, report};
use multirate::bench;
use multirate::render::cost_model::CostModel;
use multirate::render::{output, render_headless, Mode, Placement, Renderer, View, MAX_LEVEL};
use multirate::scene::Scene;
use multirate::shading::estimator::{Discontinuity, Split};
use multirate::vk::target::RenderTarget;
use multirate::vk::{Context, ContextOptions};
use std::path::{Path, PathBuf};

#[path = "cli/bench.rs"]
mod bench_command;
#[path = "cli/calibrate.rs"]
mod calibrate;
#[path = "cli/soak.rs"]
mod soak;

/// Error-bounded multirate shading on the hardware tessellator.
///
/// Without a subcommand: opens a window on the default scene in multirate mode where a display
/// exists; otherwise renders it headless in multirate mode to multirate.png, with its level map,
/// and prints the time, evaluations and error against per-pixel shading from the same run.
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
    /// Per visible triangle: the estimator's levels, fallback and predicted error (CSV), and
    /// with --oracle the brute-force truth; prints a summary.
    Analyze(AnalyzeArgs),
    /// Measure modes against the pixel reference: GPU time (median, p10, p90), shading
    /// evaluations, L∞, mean L2, PSNR and FLIP; writes CSV, JSON and SVG plots into --out.
    Bench(BenchArgs),
    /// The paper's experiments (Table 1, Figs. 2, 6, 9, 10, 11, the ε sweep): writes
    /// DOCS/results.md and its tables, CSVs and plots into DOCS/results.
    Experiments(ExperimentArgs),
    /// A long run with the validation layer on: the window on a script that cycles through
    /// every mode, key and size, minimised spells included (--bench: a bench of one scene at
    /// one resolution instead). Prints resident and device memory after the warm-up and at
    /// the end; fails on any validation message or a growth over --max-growth.
    Soak(SoakArgs),
    /// Measure this device's costs for multirate's cost model (an estimate per triangle,
    /// per-pixel shading per fragment, at two light counts) and store them; the renderer then
    /// estimates only triangles whose image is large enough for an estimate to pay.
    Calibrate(calibrate::CalibrateArgs),
}

#[derive(Args)]
struct SoakArgs {
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
    #[arg(long, default_value_os_t = default_scene())]
    scene: PathBuf,
    /// Frames presented by the window; with --bench, measured frames per configuration.
    #[arg(long, default_value_t = 10_000)]
    frames: u32,
    /// The window's initial size, or with --bench the resolution, as WxH (default: the
    /// scene's).
    #[arg(long, value_parser = parse_resolution)]
    size: Option<(u32, u32)>,
    /// Soak `bench` (the pixel reference and --modes, timed in turns) instead of the window.
    #[arg(long)]
    bench: bool,
    /// --bench: the modes measured besides the pixel reference.
    #[arg(long, value_delimiter = ',', default_value = "pixel,vertex,fixed:1,fixed:2,fixed:4,multirate")]
    modes: Vec<Mode>,
    /// The largest growth of each memory figure from the first sample to the last, in percent.
    #[arg(long, default_value_t = 1.0)]
    max_growth: f64,
    /// Also write the figures as JSON into this file.
    #[arg(long)]
    json: Option<PathBuf>,
}

#[derive(Args)]
struct ExperimentArgs {
    /// The documentation folder: results.md goes here, everything else into its results/.
    #[arg(long, default_value = "docs")]
    docs: PathBuf,
    /// Smaller resolutions and fewer settings: minutes instead of most of an hour on lavapipe.
    #[arg(long)]
    quick: bool,
    /// Measured frames per configuration.
    #[arg(long, default_value_t = 10)]
    frames: u32,
    /// Frames rendered before measuring.
    #[arg(long, default_value_t = 2)]
    warmup: u32,
    /// Run one part only: `trade` (the trade's bounds and the light sweep, DOCS/trade.md).
    #[arg(long, value_parser = ["trade"])]
    only: Option<String>,
}

#[derive(Args)]
struct BenchArgs {
    /// Scene file (TOML), or an OBJ model (camera and lights added); repeat for several scenes.
    #[arg(long, required = true)]
    scene: Vec<PathBuf>,
    /// Modes to measure besides the pixel reference (which always runs).
    #[arg(long, value_delimiter = ',', default_value = "pixel,vertex,fixed:1,fixed:2,fixed:4,multirate")]
    modes: Vec<Mode>,
    /// multirate: ε values (default: the scene's).
    #[arg(long, value_delimiter = ',')]
    epsilon: Vec<f32>,
    /// multirate: n_max values (default: the scene's).
    #[arg(long, value_delimiter = ',')]
    nmax: Vec<u32>,
    /// Resolutions as WxH (default: the scene's).
    #[arg(long, value_delimiter = ',', value_parser = parse_resolution)]
    resolution: Vec<(u32, u32)>,
    /// Measured frames per configuration.
    #[arg(long, default_value_t = 30)]
    frames: u32,
    /// Frames rendered before measuring.
    #[arg(long, default_value_t = 5)]
    warmup: u32,
    /// Output folder (bench.csv, bench.json, time_vs_linf.svg, time_vs_flip.svg).
    #[arg(long)]
    out: PathBuf,
    /// Also write the measured frames' GPU intervals as a Chrome trace (Perfetto).
    #[arg(long)]
    capture: Option<PathBuf>,
    /// Also write each configuration's image, error ×30, level map and fallback mask into
    /// OUT/images.
    #[arg(long)]
    images: bool,
    /// multirate: how ε is shared between error terms.
    #[arg(long, value_parser = parse_split, default_value = "heuristic")]
    split: Split,
    /// multirate: relaxed (a bound valid across the terminator) or conservative (per-pixel
    /// shading wherever it may cross a triangle) handling of the terminator.
    #[arg(long, value_parser = parse_discontinuity, default_value = "relaxed")]
    discontinuity: Discontinuity,
    /// multirate: where the estimator runs, each measured: tcs, compute or both
    /// (tcs,compute); default: compute.
    #[arg(long = "estimator", value_name = "ESTIMATOR", value_delimiter = ',')]
    placements: Vec<Placement>,
    /// multirate: triangles whose image covers fewer pixels are shaded per pixel without an
    /// estimate: auto (the device's cost model, `multirate calibrate`; its frame guard draws
    /// frames as pixel does where that measured faster) or a number of pixels (0: estimate
    /// every visible triangle; unguarded).
    /// Several values, comma-separated, are each measured.
    #[arg(long, value_name = "auto|PIXELS", value_delimiter = ',', default_value = "auto")]
    min_estimated_area: Vec<EstimatedArea>,
    /// Degrees per frame by which the camera turns about its target while frames are timed
    /// (0: still, where multirate reuses its levels from frame to frame).
    #[arg(long, value_name = "DEGREES", default_value_t = 0.0)]
    orbit: f32,
    /// multirate: the radius of the ball of eyes its levels hold for and are reused in while
    /// the eye stays in it, as a share of the camera's distance to its target (0: every frame
    /// estimates for its own eye).
    #[arg(long, value_name = "SHARE", default_value_t = multirate::render::EYE_BALL_SHARE)]
    eye_ball: f32,
}

/// `--min-estimated-area`: the cost model's choice, or a given area.
#[derive(Clone, Copy, Debug)]
enum EstimatedArea {
    Auto,
    Pixels(f32),
}

impl EstimatedArea {
    /// The given area; `None` for the cost model's.
    fn pixels(self) -> Option<f32> {
        match self {
            EstimatedArea::Auto => None,
            EstimatedArea::Pixels(pixels) => Some(pixels),
        }
    }
}

impl std::str::FromStr for EstimatedArea {
    type Err = String;
    fn from_str(text: &str) -> Result<EstimatedArea, String> {
        match (text, text.parse::<f32>()) {
            ("auto", _) => Ok(EstimatedArea::Auto),
            (_, Ok(pixels)) if pixels >= 0.0 && pixels.is_finite() => Ok(EstimatedArea::Pixels(pixels)),
            _ => Err(format!("\"{text}\": expected auto or a number of pixels >= 0")),
        }
    }
}

fn parse_resolution(text: &str) -> Result<(u32, u32), String> {
    let parsed = text.split_once(['x', 'X']).and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)));
    match parsed {
        Some((w, h)) if (1..=16384).contains(&w) && (1..=16384).contains(&h) => Ok((w, h)),
        _ => Err(format!("\"{text}\": expected WIDTHxHEIGHT, each in 1..=16384, such as 1920x1080")),
    }
}

#[derive(Args)]
struct AnalyzeArgs {
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
    #[arg(long)]
    scene: PathBuf,
    /// Output CSV.
    #[arg(long)]
    out: PathBuf,
    /// Also compute the oracle's level and the true error at the chosen level (slow).
    #[arg(long)]
    oracle: bool,
    /// Also render multirate and the per-pixel reference on the GPU and measure each
    /// triangle's largest error over its interior pixels (visibility buffer): the
    /// `measured_error` column beside `predicted_error` (the paper's Fig. 12).
    #[arg(long)]
    measured: bool,
    /// With --measured: an SVG scatter of measured against predicted error.
    #[arg(long, requires = "measured")]
    plot: Option<PathBuf>,
    /// How a shininess or roughness map's range over a triangle is found: `pyramid` (the
    /// min/max pyramid, conservative; what the GPU does) or `sat:P` (the paper's summed-area
    /// tables with power-weighted filtering at power P; compare with --oracle).
    #[arg(long, default_value = "pyramid")]
    texture_bounds: report::TextureBounds,
    #[command(flatten)]
    shading: ShadingArgs,
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
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
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
    #[command(flatten)]
    shading: ShadingArgs,
}

/// How shading is sampled; unset values come from the scene.
#[derive(Args, Clone)]
struct ShadingArgs {
    /// multirate (the default: shaded on the sub-vertices the estimator asks for), pixel (the
    /// per-pixel reference), vertex (Gouraud) or fixed:N (tessellated at level N).
    #[arg(long, default_value = "multirate")]
    mode: Mode,
    /// multirate: L∞ bound on the interpolation error, in linear radiance.
    #[arg(long)]
    epsilon: Option<f32>,
    /// multirate: largest tessellation level before per-pixel fallback (1..=64).
    #[arg(long)]
    nmax: Option<u32>,
    /// multirate: how ε is shared between error terms.
    #[arg(long, value_parser = parse_split, default_value = "heuristic")]
    split: Split,
    /// multirate: where the terminator may cross a triangle, keep a bound valid across the
    /// kink (relaxed) or shade it per pixel (conservative, the paper's choice).
    #[arg(long, value_parser = parse_discontinuity, default_value = "relaxed")]
    discontinuity: Discontinuity,
    /// multirate: run the estimator in a compute pre-pass (compute, the default: faster frames)
    /// or in the tessellation control stage (tcs, as the seeds describe it); both give the
    /// same levels.
    #[arg(long = "estimator", value_name = "ESTIMATOR", default_value_t = Placement::default())]
    placement: Placement,
    /// multirate: triangles whose image covers fewer pixels are shaded per pixel without an
    /// estimate: auto (the device's cost model, `multirate calibrate`; where frames are timed,
    /// its frame guard draws them as pixel does where that measured faster) or a number of
    /// pixels (0: estimate every visible triangle; unguarded).
    #[arg(long, value_name = "auto|PIXELS", default_value = "auto")]
    min_estimated_area: EstimatedArea,
    /// multirate: the radius of the ball of eyes its levels hold for, kept while the eye stays
    /// in it, as a share of the camera's distance to its target (0: for the eye alone).
    #[arg(long, value_name = "SHARE", default_value_t = multirate::render::EYE_BALL_SHARE)]
    eye_ball: f32,
}

/// `--eye-ball`: a share in [0, 1).
fn check_eye_ball(share: f32) -> Result<f32> {
    anyhow::ensure!(
        share.is_finite() && (0.0..1.0).contains(&share),
        "--eye-ball must be a share in [0, 1) of the camera's distance to its target (got {share})"
    );
    Ok(share)
}

fn parse_split(text: &str) -> Result<Split, String> {
    match text {
        "uniform" => Ok(Split::Uniform),
        "heuristic" => Ok(Split::Heuristic),
        _ => Err("expected uniform or heuristic".into()),
    }
}

fn parse_discontinuity(text: &str) -> Result<Discontinuity, String> {
    match text {
        "conservative" => Ok(Discontinuity::Conservative),
        "relaxed" => Ok(Discontinuity::Relaxed),
        _ => Err("expected conservative or relaxed".into()),
    }
}

impl ShadingArgs {
    /// The scene's view with these settings applied; rejects out-of-range values.
    fn view(&self, scene: &Scene) -> Result<View> {
        let mut view = View::of_scene(scene).with_eye_ball(check_eye_ball(self.eye_ball)?);
        view.mode = self.mode;
        view.estimator.split = self.split;
        view.estimator.discontinuity = self.discontinuity;
        view.placement = self.placement;
        view.cost_model = self.min_estimated_area.pixels().is_none();
        view.estimator.min_estimated_area = self.min_estimated_area.pixels().unwrap_or(0.0);
        if let Some(epsilon) = self.epsilon {
            anyhow::ensure!(
                epsilon.is_finite() && epsilon > 0.0,
                "--epsilon must be a positive number (got {epsilon})"
            );
            view.estimator.epsilon = epsilon;
        }
        if let Some(n_max) = self.nmax {
            anyhow::ensure!(
                (1..=MAX_LEVEL).contains(&n_max),
                "--nmax must be in 1..={MAX_LEVEL} (got {n_max})"
            );
            view.estimator.n_max = n_max;
        }
        Ok(view)
    }
}

#[derive(Args)]
struct ViewArgs {
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
    #[arg(long, default_value_os_t = default_scene())]
    scene: PathBuf,
    /// Initial shading (keys P, V, F, M, + and - change the mode in the window).
    #[command(flatten)]
    shading: ShadingArgs,
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

/// [`Scene::load`], with what loading stood in for printed as warnings.
fn load_scene(path: &Path) -> Result<Scene> {
    let scene = Scene::load(path)?;
    print_warnings(&scene);
    Ok(scene)
}

fn print_warnings(scene: &Scene) {
    for warning in &scene.warnings {
        eprintln!("warning: {warning}");
    }
}

fn options(gpu: &GpuArgs) -> ContextOptions {
    ContextOptions { validate: gpu.validate, device_name: gpu.device.clone() }
}

fn render(args: &RenderArgs, gpu: &GpuArgs) -> Result<()> {
    let scene = load_scene(&args.scene)?;
    let width = args.width.unwrap_or(scene.settings.width);
    let height = args.height.unwrap_or(scene.settings.height);
    anyhow::ensure!(
        (1..=16384).contains(&width) && (1..=16384).contains(&height),
        "--width and --height must be between 1 and 16384 (got {width}x{height})"
    );
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
fn cost_model_line(context: &Context, scene: &Scene, view: &View) -> String {
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

/// `multirate` with no command and no display: the default scene in multirate mode, written to
/// `multirate.png` with its level map (`multirate_levels.png`), and the trade against `pixel`
/// measured in the same run: GPU time, shading evaluations, the largest error against ε.
fn first_run(gpu: &GpuArgs) -> Result<()> {
    const FRAMES: u32 = 10;
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
    let median_ms = |view: &View| -> Result<f64> {
        let measurement = renderer.measure(&target, view, 2, FRAMES)?;
        Ok(bench::Timing::of(&measurement.gpu_ms()).median)
    };
    let (pixel_ms, multirate_ms) = (median_ms(&pixel)?, median_ms(&multirate)?);
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
    println!(
        "  GPU time (median of {FRAMES} frames): multirate {multirate_ms:.2} ms, pixel {pixel_ms:.2} ms ({:.0} %)",
        100.0 * pixel_ms / multirate_ms
    );
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

fn view(scene: &Path, shading: &ShadingArgs, gpu: &GpuArgs) -> Result<()> {
    let loaded = load_scene(scene)?;
    let view = shading.view(&loaded)?;
    multirate::window::view(loaded, view, &options(gpu), None)?;
    Ok(())
}

impl Default for ShadingArgs {
    fn default() -> Self {
        ShadingArgs {
            mode: Mode::Multirate,
            epsilon: None,
            nmax: None,
            split: Split::Heuristic,
            discontinuity: Discontinuity::Relaxed,
            placement: Placement::default(),
            min_estimated_area: EstimatedArea::Auto,
            eye_ball: multirate::render::EYE_BALL_SHARE,
        }
    }
}

fn analyze(args: &AnalyzeArgs, gpu: &GpuArgs) -> Result<()> {
    let scene = load_scene(&args.scene)?;
    let mut view = args.shading.view(&scene)?;
    if view.cost_model {
        // The CPU analysis knows no device: `auto` takes the built-in cost model's area, and
        // `--measured` renders with the same.
        view.estimator.min_estimated_area = CostModel::lavapipe().min_estimated_area_of(&scene);
        view.cost_model = false;
    }
    let settings = &view.estimator;
    let reports =
        report::analyze(&scene, settings, report::Triangles::Visible, args.oracle, args.texture_bounds);
    let measured = if args.measured { Some(measure_triangles(&scene, &view, gpu)?) } else { None };
    std::fs::write(&args.out, report::to_csv(&reports, args.oracle, measured.as_ref()))
        .with_context(|| format!("{}: cannot write the CSV", args.out.display()))?;
    let summary = report::summarize(&reports, settings.epsilon);
    println!(
        "{}: {} visible triangles, ε = {}, n_max = {}",
        args.out.display(),
        summary.triangles,
        settings.epsilon,
        settings.n_max
    );
    println!(
        "  fallback to per-pixel shading: {} ({} back faces of two-sided meshes, {} images below {} pixels)",
        summary.fallbacks, summary.back_faces, summary.small_images, settings.min_estimated_area
    );
    println!("  shading evaluations (tessellated vertices), estimator: {}", summary.estimator_evaluations);
    if args.oracle {
        println!("  shading evaluations (tessellated vertices), oracle:    {}", summary.oracle_evaluations);
        println!("  tessellated triangles whose true error exceeds ε: {}", summary.violations);
    }
    if let Some(measured) = &measured {
        let points: Vec<(f64, f64)> = reports
            .iter()
            .filter(|r| !r.levels.fallback)
            .filter_map(|r| measured.get(&(r.mesh, r.triangle)).map(|m| (r, m)))
            .map(|(r, m)| (f64::from(r.estimate.predicted_error), f64::from(m.error)))
            .collect();
        let above = points.iter().filter(|(p, m)| m > p).count();
        let over_epsilon = points.iter().filter(|(_, m)| *m > f64::from(settings.epsilon)).count();
        let worst = points.iter().map(|(p, m)| m / p.max(1e-30)).fold(0.0, f64::max);
        println!(
            "  measured (interior pixels, GPU): {} tessellated triangles; measured > predicted: {above}; measured > ε: {over_epsilon}; largest measured / predicted: {worst:.3}",
            points.len()
        );
        if let Some(plot) = &args.plot {
            let title = format!(
                "{}: measured against predicted error, ε = {}",
                scene_name(&args.scene),
                settings.epsilon
            );
            multirate::analysis::measured::scatter_svg(&points, f64::from(settings.epsilon), &title, plot)?;
            println!("  scatter plot: {}", plot.display());
        }
    }
    Ok(())
}

fn scene_name(path: &std::path::Path) -> String {
    path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default()
}

/// Renders `view` (multirate) and the per-pixel reference at the scene's size, and measures
/// each triangle's error through the visibility buffer.
fn measure_triangles(
    scene: &Scene,
    view: &View,
    gpu: &GpuArgs,
) -> Result<std::collections::HashMap<(usize, usize), multirate::analysis::measured::Measured>> {
    let context = Context::headless(&options(gpu))?;
    let renderer = multirate::render::Renderer::new(&context, scene)?;
    let extent = ash::vk::Extent2D { width: scene.settings.width, height: scene.settings.height };
    let target = multirate::vk::target::RenderTarget::new(&context, extent)?;
    let reference = renderer.render(&target, &View { mode: Mode::Pixel, ..view.clone() })?;
    let image = renderer.render(&target, &View { mode: Mode::Multirate, ..view.clone() })?;
    let ids = renderer.triangle_ids(&target, &View { mode: Mode::Pixel, ..view.clone() })?;
    let messages = context.validation().count();
    anyhow::ensure!(messages == 0, "the validation layer reported {messages} message(s)");
    Ok(multirate::analysis::measured::measured_errors(&image, &reference, &ids))
}

/// The progress bar of `bench` and `experiments` (hidden when stderr is not a terminal).
fn progress_bar() -> indicatif::ProgressBar {
    let style =
        indicatif::ProgressStyle::with_template("{prefix} {bar:30} {pos}/{len} [{elapsed} / ~{eta}] {msg}")
            .expect("valid template");
    indicatif::ProgressBar::new(0).with_style(style)
}

fn run_experiments(args: &ExperimentArgs, gpu: &GpuArgs) -> Result<()> {
    anyhow::ensure!(args.frames >= 1, "--frames must be at least 1");
    let context = Context::headless(&options(gpu))?;
    let mut command = format!("cargo run --release -- experiments --docs {}", args.docs.display());
    if args.quick {
        command.push_str(" --quick");
    }
    if let Some(only) = &args.only {
        command.push_str(&format!(" --only {only}"));
    }
    command.push_str(&format!(" --frames {} --warmup {}", args.frames, args.warmup));
    if let Some(device) = &gpu.device {
        command.push_str(&format!(" --device \"{device}\""));
    }
    let options = bench::experiments::ExperimentOptions {
        out: args.docs.join("results"),
        scenes: default_scene().parent().map(Path::to_path_buf).unwrap_or_default(),
        quick: args.quick,
        frames: args.frames,
        warmup: args.warmup,
        command,
    };
    let bar = progress_bar();
    let started = std::time::Instant::now();
    let mut show = |experiment: &str, progress: bench::Progress<'_>| {
        bar.set_prefix(experiment.to_string());
        bar.set_length(progress.total as u64);
        bar.set_position(progress.done as u64);
        bar.set_message(progress.label.to_string());
    };
    let (markdown, page) = match args.only.as_deref() {
        Some(_) => (bench::experiments::trade_page(&context, &options, &mut show)?, "trade.md"),
        None => (bench::experiments::run_all(&context, &options, &mut show)?, "results.md"),
    };
    bar.finish_and_clear();
    let path = args.docs.join(page);
    std::fs::write(&path, markdown).with_context(|| format!("{}: cannot write", path.display()))?;
    println!(
        "{} and {}/ written in {:.0} s",
        path.display(),
        options.out.display(),
        started.elapsed().as_secs_f64()
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
        Some(Command::Analyze(args)) => analyze(args, &cli.gpu),
        Some(Command::Bench(args)) => bench_command::run_bench(args, &cli.gpu),
        Some(Command::Experiments(args)) => run_experiments(args, &cli.gpu),
        Some(Command::Soak(args)) => {
            soak::soak(args, &cli.gpu).with_context(|| format!("soaking {}", args.scene.display()))
        }
        Some(Command::Calibrate(args)) => calibrate::calibrate(args, &cli.gpu)
            .with_context(|| format!("calibrating with {}", args.scene.display())),
        Some(Command::View(args)) => view(&args.scene, &args.shading, &cli.gpu)
            .with_context(|| format!("viewing {}", args.scene.display())),
        None if has_display() => view(&default_scene(), &ShadingArgs::default(), &cli.gpu)
            .context("opening the viewer (set no DISPLAY to render headless instead)"),
        None => first_run(&cli.gpu).context("rendering the default scene headless"),
    }
}
