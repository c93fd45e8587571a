//! `analyze`: the estimator's levels, fallback and predicted error per visible triangle (CSV),
//! with `--oracle` the brute-force truth and with `--measured` the error measured on the GPU.

use super::common::{load_scene, options, GpuArgs};
use super::shading::ShadingArgs;
use anyhow::{Context as _, Result};
use clap::Args;
use multirate::analysis::report;
use multirate::geometry::shadow_class::ShadowClasses;
use multirate::render::cost_model::CostModel;
use multirate::render::{Mode, View};
use multirate::scene::Scene;
use multirate::vk::Context;
use std::path::PathBuf;

#[derive(Args)]
pub struct AnalyzeArgs {
    /// Scene file (TOML), or an OBJ model with its MTL materials (camera and lights added).
    #[arg(long)]
    pub scene: PathBuf,
    /// Output CSV.
    #[arg(long)]
    pub out: PathBuf,
    /// Also compute the oracle's level and the true error at the chosen level (slow).
    #[arg(long)]
    pub oracle: bool,
    /// Also render multirate and the per-pixel reference on the GPU and measure each
    /// triangle's largest error over its interior pixels (visibility buffer): the
    /// `measured_error` column beside `predicted_error` (the paper's Fig. 12).
    #[arg(long)]
    pub measured: bool,
    /// With --measured: an SVG scatter of measured against predicted error.
    #[arg(long, requires = "measured")]
    pub plot: Option<PathBuf>,
    /// How a shininess or roughness map's range over a triangle is found: `pyramid` (the
    /// min/max pyramid, conservative; what the GPU does) or `sat:P` (the paper's summed-area
    /// tables with power-weighted filtering at power P; compare with --oracle).
    #[arg(long, default_value = "pyramid")]
    pub texture_bounds: report::TextureBounds,
    #[command(flatten)]
    pub shading: ShadingArgs,
}

pub fn analyze(args: &AnalyzeArgs, gpu: &GpuArgs) -> Result<()> {
    let scene = load_scene(&args.scene)?;
    let mut view = args.shading.view(&scene)?;
    if view.cost_model {
        // The CPU analysis knows no device: `auto` takes the built-in cost model's area, and
        // `--measured` renders with the same.
        view.estimator.min_estimated_area = CostModel::lavapipe().min_estimated_area_of(&scene);
        view.cost_model = false;
    }
    let settings = &view.estimator;
    let classes = shadow_classes(&scene, &view, gpu)?;
    let reports = report::analyze(
        &scene,
        settings,
        report::Triangles::Visible,
        args.oracle,
        args.texture_bounds,
        classes.as_ref(),
    );
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
    if let Some(classes) = &classes {
        report_shadow_classes(classes);
    }
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

/// The visibility classes of the scene's triangles (section 18 of docs/estimator.md), from the
/// maps the renderer draws for `view` at the scene's size and reads back; None where no light
/// casts shadows.
fn shadow_classes(scene: &Scene, view: &View, gpu: &GpuArgs) -> Result<Option<ShadowClasses>> {
    if scene.shadow_casters.is_empty() {
        return Ok(None);
    }
    let context = Context::headless(&options(gpu))?;
    let renderer = multirate::render::Renderer::new(&context, scene)?;
    let extent = ash::vk::Extent2D { width: scene.settings.width, height: scene.settings.height };
    renderer.fit_shadows(view, extent)?;
    Ok(Some(renderer.shadow_classes()))
}

/// Each shadow-casting light's share of triangles lit, shadowed and mixed.
fn report_shadow_classes(classes: &ShadowClasses) {
    for (slot, [lit, shadowed, mixed]) in classes.counts().into_iter().enumerate() {
        let share = |n: usize| 100.0 * n as f64 / (lit + shadowed + mixed).max(1) as f64;
        println!(
            "  light {} casts shadows: of the triangles, {lit} lit ({:.1} %), {shadowed} shadowed ({:.1} %), {mixed} mixed ({:.1} %)",
            classes.light(slot),
            share(lit),
            share(shadowed),
            share(mixed)
        );
    }
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
