//! The binary's `bench` subcommand: checks its arguments, times the configurations
//! (`bench::run`), writes the rows (CSV, JSON), plots and trace, and prints the table with the
//! trade's floor and ceiling.

use super::common::{check_frames, options, parse_resolution, print_warnings, progress_bar, GpuArgs};
use super::path::{check_fps, parse_path_choice, PathChoice};
use super::shading::{check_eye_ball, parse_discontinuity, parse_split, EstimatedArea};
use anyhow::{Context as _, Result};
use clap::Args;
use multirate::bench::{self, BenchConfig, BenchScene};
use multirate::render::{DrawPart, Mode, Placement, EYE_BALL_SHARE};
use multirate::scene::settings::{check_epsilon, check_n_max};
use multirate::shading::estimator::{Discontinuity, Split};
use multirate::vk::Context;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct BenchArgs {
    /// Scene file (TOML), or an OBJ model (camera and lights added); repeat for several scenes.
    #[arg(long, required = true)]
    pub scene: Vec<PathBuf>,
    /// Modes to measure besides the pixel reference (which always runs).
    #[arg(long, value_delimiter = ',', default_value = "pixel,vertex,fixed:1,fixed:2,fixed:4,multirate")]
    pub modes: Vec<Mode>,
    /// multirate: ε values (default: the scene's).
    #[arg(long, value_delimiter = ',')]
    pub epsilon: Vec<f32>,
    /// multirate: n_max values (default: the scene's).
    #[arg(long, value_delimiter = ',')]
    pub nmax: Vec<u32>,
    /// Resolutions as WxH (default: the scene's).
    #[arg(long, value_delimiter = ',', value_parser = parse_resolution)]
    pub resolution: Vec<(u32, u32)>,
    /// Measured frames per configuration.
    #[arg(long, default_value_t = 30)]
    pub frames: u32,
    /// Frames rendered before measuring.
    #[arg(long, default_value_t = 5)]
    pub warmup: u32,
    /// Output folder (bench.csv, bench.json, time_vs_linf.svg, time_vs_flip.svg).
    #[arg(long)]
    pub out: PathBuf,
    /// Also write the measured frames' GPU intervals as a Chrome trace (Perfetto).
    #[arg(long)]
    pub capture: Option<PathBuf>,
    /// Also write each configuration's image, error ×30, level map and fallback mask into
    /// OUT/images.
    #[arg(long)]
    pub images: bool,
    /// multirate: how ε is shared between error terms.
    #[arg(long, value_parser = parse_split, default_value = "heuristic")]
    pub split: Split,
    /// multirate: relaxed (a bound valid across the terminator) or conservative (per-pixel
    /// shading wherever it may cross a triangle) handling of the terminator.
    #[arg(long, value_parser = parse_discontinuity, default_value = "relaxed")]
    pub discontinuity: Discontinuity,
    /// multirate: where the estimator runs, each measured: tcs, compute or both
    /// (tcs,compute); default: compute.
    #[arg(long = "estimator", value_name = "ESTIMATOR", value_delimiter = ',')]
    pub placements: Vec<Placement>,
    /// multirate: triangles whose image covers fewer pixels are shaded per pixel without an
    /// estimate: auto (the device's cost model, `multirate calibrate`; its frame guard draws
    /// frames as pixel does where that measured faster) or a number of pixels (0: estimate
    /// every visible triangle; unguarded).
    /// Several values, comma-separated, are each measured.
    #[arg(long, value_name = "auto|PIXELS", value_delimiter = ',', default_value = "auto")]
    pub min_estimated_area: Vec<EstimatedArea>,
    /// Degrees per frame by which the camera turns about its target while frames are timed
    /// (0: still, where multirate reuses its levels from frame to frame).
    #[arg(long, value_name = "DEGREES", default_value_t = 0.0)]
    pub orbit: f32,
    /// Times every configuration along a camera path, frame by frame, in place of --frames and
    /// --orbit: `scene` (each scene file's [[path]]) or `orbit:SECONDS` (one turn about the
    /// target); writes `path.csv` and `path.svg` (GPU time per frame) beside the tables.
    #[arg(long, value_parser = parse_path_choice, conflicts_with = "orbit")]
    pub path: Option<PathChoice>,
    /// Frames a second along --path.
    #[arg(long, default_value_t = 30.0, requires = "path")]
    pub fps: f32,
    /// Along --path, measure only the stability of every configuration (`stability.csv`), in
    /// about half the time: no images, counts, timing turns or per-frame plot.
    #[arg(long, requires = "path", conflicts_with_all = ["images", "capture", "draw_parts", "pre_pass_steps"])]
    pub stability_only: bool,
    /// Time each part of the draws apart (the whole meshes, the flat and tessellated lists, the
    /// fallback's depth and shading, the back faces, the emitters: the `draw_*_ms_median`
    /// columns). The frame's rendering is split at every part, which slows the frame itself:
    /// compare its time with a run without.
    #[arg(long)]
    pub draw_parts: bool,
    /// Also measure each scene whose lights cast shadows without its shadows, every mode
    /// against its own `pixel` (as `<scene>_without_shadows`).
    #[arg(long)]
    pub without_shadows: bool,
    /// Time each step of the pre-pass apart (culling, range, estimate, refine, patches: the
    /// `<step>_ms_median` columns). lavapipe flushes its work at each step's timestamps, which
    /// slows the pre-pass: compare its time with a run without.
    #[arg(long)]
    pub pre_pass_steps: bool,
    /// multirate: the radius of the ball of eyes its levels hold for and are reused in while
    /// the eye stays in it, as a share of the camera's distance to its target (0: every frame
    /// estimates for its own eye).
    #[arg(long, value_name = "SHARE", default_value_t = EYE_BALL_SHARE)]
    pub eye_ball: f32,
    /// multirate: whether its levels are held between the balls of eyes (after a level rose,
    /// a coarser estimate used only once coarser ones have come several times in a row): on,
    /// off, or on,off to measure both.
    #[arg(long, value_name = "on|off", value_delimiter = ',', value_parser = parse_on_off, default_value = "off")]
    pub level_hold: Vec<bool>,
}

/// `on` or `off`.
fn parse_on_off(text: &str) -> Result<bool, String> {
    match text {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("expected on or off, got {text:?}")),
    }
}

/// Runs `bench` as `args` ask, writes its files, prints its tables, and returns what it measured.
pub fn run_bench(args: &BenchArgs, gpu: &GpuArgs) -> Result<bench::BenchResult> {
    for &epsilon in &args.epsilon {
        check_epsilon(epsilon).map_err(|e| anyhow::anyhow!("--epsilon {e}"))?;
    }
    for &n_max in &args.nmax {
        check_n_max(n_max).map_err(|e| anyhow::anyhow!("--nmax {e}"))?;
    }
    check_frames(args.frames)?;
    anyhow::ensure!(args.orbit.is_finite(), "--orbit must be a number of degrees (got {})", args.orbit);
    check_eye_ball(args.eye_ball)?;
    check_fps(args.fps)?;
    let scenes = args.scene.iter().map(|path| BenchScene::load(path)).collect::<Result<Vec<_>, _>>()?;
    let scenes = with_shadowless_twins(scenes, args.without_shadows);
    scenes.iter().for_each(|s| print_warnings(&s.scene));
    let context = Context::headless(&options(gpu))?;
    let config = BenchConfig {
        modes: args.modes.clone(),
        epsilons: args.epsilon.clone(),
        n_maxes: args.nmax.clone(),
        resolutions: args.resolution.clone(),
        warmup: args.warmup,
        frames: args.frames,
        split: args.split,
        discontinuity: args.discontinuity,
        placements: args.placements.clone(),
        images: args.images.then(|| args.out.join("images")),
        min_estimated_areas: args.min_estimated_area.iter().map(|a| a.pixels()).collect(),
        orbit_degrees: args.orbit,
        draw_parts: args.draw_parts,
        pre_pass_steps: args.pre_pass_steps,
        eye_ball_share: args.eye_ball,
        level_holds: args.level_hold.clone(),
        path: args.path.map(|choice| (choice, args.fps)),
    };
    std::fs::create_dir_all(&args.out).with_context(|| format!("{}: cannot create", args.out.display()))?;
    if args.stability_only {
        return stability_only(&context, &scenes, &config, &args.out);
    }
    let bar = progress_bar();
    let result = bench::run(&context, &scenes, &config, &mut |progress| {
        bar.set_length(progress.total as u64);
        bar.set_position(progress.done as u64);
        bar.set_message(progress.label.to_string());
    })?;
    bar.finish_and_clear();
    let write = |name: &str, text: String| {
        let path = args.out.join(name);
        std::fs::write(&path, text).with_context(|| format!("{}: cannot write", path.display()))
    };
    write("bench.csv", bench::to_csv(&result.rows))?;
    write("bench.json", bench::to_json(&result.rows))?;
    report_shadows(&result.shadows, &args.out)?;
    bench::plot::time_against_error(
        &result.rows,
        "L∞ error",
        |r| r.l_inf,
        &args.out.join("time_vs_linf.svg"),
    )?;
    bench::plot::time_against_error(
        &result.rows,
        "mean FLIP",
        |r| r.flip,
        &args.out.join("time_vs_flip.svg"),
    )?;
    if args.path.is_some() {
        write("path.csv", bench::per_frame::to_csv(&result.rows, &result.measurements, args.fps))?;
        bench::per_frame::plot(&result.rows, &result.measurements, args.fps, &args.out.join("path.svg"))?;
        write("stability.csv", bench::per_frame::stability_csv(&result.stability))?;
    }
    if let Some(path) = &args.capture {
        std::fs::write(path, bench::trace::chrome_trace(&result.rows, &result.measurements))
            .with_context(|| format!("{}: cannot write the capture", path.display()))?;
    }
    println!("{} on {} ({})", args.out.display(), context.info.name, context.info.driver);
    if let Some(note) = multirate::render::draw_splitting_note(&context.info) {
        println!("{note}");
    }
    println!(
        "{:<44} {:>10} {:>9} {:>8} {:>7} {:>10} {:>9} {:>9} {:>10} {:>8}",
        "configuration",
        "GPU ms",
        "pre-pass",
        "speedup",
        "share",
        "evals",
        "L∞ same",
        "other px",
        "mean L2",
        "FLIP"
    );
    for row in &result.rows {
        let name = format!("{} {}x{} {}", row.scene, row.width, row.height, bench::plot::row_label(row));
        let pre_pass = row.pre_pass_ms.map_or_else(|| "-".to_string(), |t| format!("{:.3}", t.median));
        let share = row.trade.map_or_else(|| "-".to_string(), |t| format!("{:.0}%", t.saving_share * 100.0));
        println!(
            "{name:<44} {:>10.3} {pre_pass:>9} {:>7.0}% {share:>7} {:>9.1}% {:>9.5} {:>9} {:>10.2e} {:>8.5}",
            row.gpu_ms.median,
            row.speedup * 100.0,
            row.evaluation_ratio * 100.0,
            row.l_inf_same_triangle,
            row.other_triangle_pixels,
            row.mean_l2,
            row.flip
        );
    }
    print_stability(&result.stability);
    print_draw_parts(&result.rows);
    for row in result.rows.iter().filter(|row| row.frames_drawn_as_pixel.is_some_and(|n| n > 0)) {
        println!(
            "frame guard: {} {}x{} {} drew {} of {} measured frames as pixel does (its probes, or all where multirate was slower)",
            row.scene,
            row.width,
            row.height,
            bench::plot::row_label(row),
            row.frames_drawn_as_pixel.unwrap_or(0),
            row.frames
        );
    }
    let mut bounds = result.rows.iter().filter(|row| row.mode == "pixel").peekable();
    if bounds.peek().is_some() {
        println!("floor (vertex), ceiling (pixel / vertex), empty frame; multirate's estimated-area floor:");
    }
    for reference in bounds {
        let same = |row: &&bench::Row| {
            row.scene == reference.scene && (row.width, row.height) == (reference.width, reference.height)
        };
        let areas: Vec<String> = result
            .rows
            .iter()
            .filter(same)
            .filter_map(|row| row.min_estimated_area.map(|a| format!("{a:.1} px")))
            .collect();
        let trade = reference.trade.map_or_else(
            || "floor -, ceiling - (add vertex to --modes)".to_string(),
            |t| format!("floor {:.3} ms, ceiling {:.2}×", t.floor_ms, t.ceiling),
        );
        println!(
            "  {} {}x{}: {trade}, empty frame {:.3} ms; estimated above {}",
            reference.scene,
            reference.width,
            reference.height,
            reference.empty_ms,
            if areas.is_empty() { "-".to_string() } else { areas.join(", ") }
        );
    }
    let messages = context.validation().count();
    anyhow::ensure!(messages == 0, "the validation layer reported {messages} message(s)");
    Ok(result)
}

/// `--stability-only`: the walk along the path alone, its figures printed and written to
/// `stability.csv`.
fn stability_only(
    context: &std::sync::Arc<Context>,
    scenes: &[BenchScene],
    config: &BenchConfig,
    out: &Path,
) -> Result<bench::BenchResult> {
    let bar = progress_bar();
    let stability = bench::walk_paths(context, scenes, config, &mut |progress| {
        bar.set_length(progress.total as u64);
        bar.set_position(progress.done as u64);
        bar.set_message(progress.label.to_string());
    })?;
    bar.finish_and_clear();
    let path = out.join("stability.csv");
    std::fs::write(&path, bench::per_frame::stability_csv(&stability))
        .with_context(|| format!("{}: cannot write", path.display()))?;
    println!("{} on {} ({})", out.display(), context.info.name, context.info.driver);
    print_stability(&stability);
    let messages = context.validation().count();
    anyhow::ensure!(messages == 0, "the validation layer reported {messages} message(s)");
    Ok(bench::BenchResult { rows: Vec::new(), measurements: Vec::new(), shadows: Vec::new(), stability })
}

/// `scenes`, each whose lights cast shadows followed, where `twins`, by itself without them.
fn with_shadowless_twins(scenes: Vec<BenchScene>, twins: bool) -> Vec<BenchScene> {
    scenes
        .into_iter()
        .flat_map(|bench_scene| {
            let twin = (twins && !bench_scene.scene.shadow_casters.is_empty()).then(|| BenchScene {
                name: format!("{}_without_shadows", bench_scene.name),
                scene: bench_scene.scene.without_shadows(),
            });
            std::iter::once(bench_scene).chain(twin)
        })
        .collect()
}

/// Per scene whose lights cast shadows: the GPU time of its shadow maps' first draw (when the
/// renderer is made), each light's visibility classes at the scene's camera
/// (`docs/estimator.md` section 18), and how often the directional maps were drawn again as the
/// view moved (in the run's analysis, warm-up and measured frames; their time is not in any
/// frame's); printed and written to `shadows.csv`.
fn report_shadows(shadows: &[bench::ShadowReport], out: &Path) -> Result<()> {
    if shadows.is_empty() {
        return Ok(());
    }
    println!(
        "shadows (the maps drawn when the renderer is made; the triangles by class at the scene's camera):"
    );
    let mut csv =
        String::from("scene,light,shadow_pass_ms,lit,shadowed,mixed,refits,refit_gpu_ms,refit_wall_ms\n");
    for report in shadows {
        let (ms, refits) = (report.shadow_pass_ms, report.refits);
        let classes = &report.classes;
        for (slot, [lit, shadowed, mixed]) in classes.counts().into_iter().enumerate() {
            let light = classes.light(slot);
            csv += &format!(
                "{},{light},{ms:.3},{lit},{shadowed},{mixed},{},{:.3},{:.3}\n",
                report.scene, refits.count, refits.gpu_ms, refits.wall_ms
            );
            let share = |n: usize| 100.0 * n as f64 / (lit + shadowed + mixed).max(1) as f64;
            println!(
                "  {}: shadow pass {ms:.3} ms; light {light}: {:.1} % lit, {:.1} % shadowed, {:.1} % mixed",
                report.scene,
                share(lit),
                share(shadowed),
                share(mixed)
            );
        }
        if refits.count > 0 {
            println!(
                "  {}: directional maps drawn again {} times for the moving view: {:.3} ms GPU, {:.1} ms in all",
                report.scene, refits.count, refits.gpu_ms, refits.wall_ms
            );
        }
    }
    let path = out.join("shadows.csv");
    std::fs::write(&path, csv).with_context(|| format!("{}: cannot write", path.display()))
}

/// `--draw-parts`: per row, the median milliseconds of each part of the draws and of the
/// pre-pass, against the frame's (whose rendering the parts split).
fn print_draw_parts(rows: &[bench::Row]) {
    let timed: Vec<&bench::Row> = rows.iter().filter(|row| row.draw_parts_ms.is_some()).collect();
    if timed.is_empty() {
        return;
    }
    println!("the frame's parts (median GPU ms; the rendering split at every part):");
    let names: Vec<&str> = DrawPart::ALL.iter().map(|part| part.name()).collect();
    println!("{:<44} {:>9} {:>9} {}", "configuration", "frame", "pre-pass", names.join(" "));
    for row in timed {
        let name = format!("{} {}x{} {}", row.scene, row.width, row.height, bench::plot::row_label(row));
        let pre_pass = row.pre_pass_ms.map_or_else(|| "-".to_string(), |t| format!("{:.3}", t.median));
        let parts = row.draw_parts_ms.unwrap_or_default();
        let parts: Vec<String> = DrawPart::ALL
            .iter()
            .zip(&names)
            .map(|(part, name)| format!("{:>w$.3}", parts[*part as usize], w = name.len()))
            .collect();
        println!("{name:<44} {:>9.3} {pre_pass:>9} {}", row.gpu_ms.median, parts.join(" "));
    }
}

/// `--path`: per configuration, how its error moved from frame to frame along the path.
fn print_stability(runs: &[bench::stability::StabilityRun]) {
    if runs.is_empty() {
        return;
    }
    println!("temporal stability along the path (|e_t − e_t−1| at the same surface point; jumps over ε/2; flicker Σ|ΔT| / Σ|ΔR|):");
    for run in runs {
        let steps = &run.steps;
        let levels = if run.level_changes.is_empty() {
            String::new()
        } else {
            let mean = run.level_changes.iter().sum::<f64>() / run.level_changes.len() as f64;
            let over = run.pixels_over_epsilon.iter().max().copied().unwrap_or(0);
            format!(
                ", levels changed {:.2} % of visible triangles a frame, at most {over} pixels of the same triangle over ε in a frame",
                100.0 * mean
            )
        };
        let patterns = if run.level_changes.is_empty() {
            String::new()
        } else {
            format!(", {} of them where the triangle's pattern changed", steps.pattern_jumps())
        };
        println!(
            "  {}: largest {:.4}, worst p99 {:.4}, jumps {} of {} compared pixels ({:.2} per million){patterns}, flicker {:.3}{levels}",
            run.label,
            steps.largest(),
            steps.worst_p99(),
            steps.jumps(),
            steps.compared(),
            1e6 * steps.jump_share(),
            steps.flicker_ratio()
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::common::parsed;

    const SCENE: [&str; 4] = ["--scene", "s.toml", "--out", "o"];

    #[test]
    fn stability_only_needs_a_path_and_takes_no_timing_or_image_option() {
        let args = |more: &[&str]| parsed::<BenchArgs>(&[&SCENE[..], more].concat());
        let walk = args(&["--path", "scene", "--stability-only"]).expect("a walk alone");
        assert!(walk.stability_only && walk.path.is_some());
        assert!(!args(&["--path", "scene"]).expect("a path run").stability_only);
        assert!(args(&["--stability-only"]).is_err(), "without --path");
        for timing in [&["--images"][..], &["--capture", "c.json"], &["--draw-parts"], &["--pre-pass-steps"]]
        {
            let words = [&["--path", "scene", "--stability-only"][..], timing].concat();
            assert!(args(&words).is_err(), "{timing:?} beside --stability-only");
        }
    }

    #[test]
    fn level_hold_takes_on_off_or_both() {
        let holds = |value: &str| parsed::<BenchArgs>(&[&SCENE[..], &["--level-hold", value]].concat());
        assert_eq!(parsed::<BenchArgs>(&SCENE).expect("the default").level_hold, [false]);
        assert_eq!(holds("on,off").expect("both").level_hold, [true, false]);
        assert!(holds("yes").is_err());
    }
}
