//! `demo`: the paper's demo in one command. The room with its shadows walks along its camera
//! path: `bench --path scene` times pixel, vertex, fixed:4 and multirate on the same frames and
//! measures their stability against the per-pixel reference (`path.csv`, `path.svg`,
//! `stability.csv`, `bench.csv`: every figure of the linear frame, before any post effect); the
//! path is then rendered as a viewer draws it, one renderer for every frame, and a frame a second
//! is kept as an image through the post chain (eye adaptation, bloom, tone mapping); `README.md`
//! shows it all with the command that wrote it. `multirate demo` regenerates `docs/demo/`.

use super::bench::{run_bench, BenchArgs};
use super::common::{options, parse_resolution, parsed, shipped_scene, GpuArgs};
use super::path::{check_fps, numbered, PathChoice};
use super::render::render_path;
use super::shading::ShadingArgs;
use anyhow::{Context as _, Result};
use clap::Args;
use multirate::bench::stability::StabilityRun;
use multirate::bench::{plot, BenchResult};
use multirate::scene::Scene;
use multirate::vk::Context;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct DemoArgs {
    /// Scene file with a [[path]] (default: scenes/room_shadows.toml).
    #[arg(long)]
    pub scene: Option<PathBuf>,
    /// Resolution the path is timed and measured at, as WxH (the default keeps the run to
    /// minutes on a CPU rasteriser: a frame of `pixel` of the room takes seconds at 1280x720).
    #[arg(long, value_parser = parse_resolution, default_value = "640x360")]
    pub resolution: (u32, u32),
    /// Frames a second along the path.
    #[arg(long, default_value_t = 30.0)]
    pub fps: f32,
    /// Size of the frames kept as images, as WxH (every frame of the path is rendered; one a
    /// second is kept).
    #[arg(long, value_parser = parse_resolution, default_value = "640x360")]
    pub still_size: (u32, u32),
    /// Output folder.
    #[arg(long, default_value = "docs/demo")]
    pub out: PathBuf,
}

pub fn run_demo(args: &DemoArgs, gpu: &GpuArgs) -> Result<()> {
    check_fps(args.fps)?;
    let scene_path = args.scene.clone().unwrap_or_else(|| shipped_scene("room_shadows.toml"));
    let scene = Scene::load(&scene_path)?;
    anyhow::ensure!(
        scene.camera_path.is_some(),
        "{}: the demo follows the scene's camera path, and it has no [[path]]",
        scene_path.display()
    );
    let (width, height) = args.resolution;
    let (scene_arg, resolution) = (scene_path.display().to_string(), format!("{width}x{height}"));
    let (fps, out) = (args.fps.to_string(), args.out.display().to_string());
    let bench: BenchArgs = parsed(&[
        "--scene",
        &scene_arg,
        "--modes",
        "pixel,vertex,fixed:4,multirate",
        "--resolution",
        &resolution,
        "--path",
        "scene",
        "--fps",
        &fps,
        "--out",
        &out,
    ])?;
    let measured = run_bench(&bench, gpu)?;
    let stills = args.out.join("frames");
    std::fs::create_dir_all(&stills).with_context(|| format!("{}: cannot create", stills.display()))?;
    let context = Context::headless(&options(gpu))?;
    let view = parsed::<ShadingArgs>(&[])?.view(&scene)?;
    let every = args.fps.round().max(1.0) as usize;
    let first = stills.join("frame.png");
    let frames = render_path(
        &context,
        &scene,
        &view,
        (PathChoice::Scene, args.fps),
        args.still_size,
        (&first, true, &|index| index % every == 0),
    )?;
    let kept: Vec<usize> = (0..frames).filter(|index| index % every == 0).collect();
    let page = page(args, &scene_path, (&context, &measured), &kept)?;
    let written = args.out.join("README.md");
    std::fs::write(&written, page).with_context(|| format!("{}: cannot write", written.display()))?;
    println!("{}: the demo's page, {} frames kept of {frames}", written.display(), kept.len());
    let messages = context.validation().count();
    anyhow::ensure!(messages == 0, "the validation layer reported {messages} message(s)");
    Ok(())
}

/// The demo's page: the command, the device, the timing and stability tables, the plot and the
/// frames kept (`kept`, by index).
fn page(
    args: &DemoArgs,
    scene: &Path,
    (context, measured): (&Context, &BenchResult),
    kept: &[usize],
) -> Result<String> {
    let (width, height) = args.resolution;
    let mut page = String::new();
    writeln!(page, "# The demo: {} along its camera path\n", scene.display())?;
    let (still_width, still_height) = args.still_size;
    writeln!(
        page,
        "Written by `multirate demo --scene {} --resolution {width}x{height} --fps {} --still-size \
         {still_width}x{still_height} --out {}` on {} ({}), `GALLIVM_PERF` {}. Every mode is timed on the same \
         frames of the path, the modes taking turns; every error is of the linear frame against the per-pixel \
         reference of the same camera, before the post chain (docs/temporal.md says how each figure is \
         measured). The frames below went through the post chain (eye adaptation, bloom, tone mapping).\n",
        scene.display(),
        args.fps,
        args.out.display(),
        context.info.name,
        context.info.driver,
        std::env::var("GALLIVM_PERF").map_or_else(|_| "unset".to_string(), |v| format!("`{v}`"))
    )?;
    writeln!(page, "## GPU time per frame\n\n![GPU time per frame along the path](path.svg)\n")?;
    writeln!(
        page,
        "| configuration | frames | median ms | p10 | p90 | pre-pass median ms | speedup over pixel |"
    )?;
    writeln!(page, "| --- | ---: | ---: | ---: | ---: | ---: | ---: |")?;
    for row in &measured.rows {
        let pre_pass = row.pre_pass_ms.map_or_else(|| "–".to_string(), |t| format!("{:.2}", t.median));
        writeln!(
            page,
            "| {} | {} | {:.2} | {:.2} | {:.2} | {pre_pass} | {:.2}× |",
            if row.mode == "multirate" {
                format!("multirate {}", plot::row_label(row))
            } else {
                row.mode.clone()
            },
            row.frames,
            row.gpu_ms.median,
            row.gpu_ms.p10,
            row.gpu_ms.p90,
            row.speedup
        )?;
    }
    writeln!(page, "\n## Stability from frame to frame\n")?;
    writeln!(
        page,
        "| configuration | largest \\|e_t − e_t−1\\| | worst p99 | jumps over ε/2 | of them, pattern changes | flicker | levels changed a frame | most pixels over ε in a frame |"
    )?;
    writeln!(page, "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")?;
    for run in &measured.stability {
        writeln!(page, "{}", stability_row(run))?;
    }
    writeln!(page, "\n## Frames\n")?;
    for &index in kept {
        let file = numbered(Path::new("frame.png"), index);
        let seconds = index as f32 / args.fps;
        writeln!(page, "![{seconds:.1} s](frames/{})", file.display())?;
    }
    Ok(page)
}

/// One configuration's line of the stability table.
fn stability_row(run: &StabilityRun) -> String {
    let steps = &run.steps;
    let (levels, patterns, over) = if run.level_changes.is_empty() {
        ("–".to_string(), "–".to_string(), "–".to_string())
    } else {
        let mean = run.level_changes.iter().sum::<f64>() / run.level_changes.len() as f64;
        let most = run.pixels_over_epsilon.iter().max().copied().unwrap_or(0);
        (format!("{:.2} %", 100.0 * mean), steps.pattern_jumps().to_string(), most.to_string())
    };
    format!(
        "| {} | {:.4} | {:.4} | {} of {} | {patterns} | {:.3} | {levels} | {over} |",
        run.label,
        steps.largest(),
        steps.worst_p99(),
        steps.jumps(),
        steps.compared(),
        steps.flicker_ratio()
    )
}
