//! The binary's `bench` subcommand: checks its arguments, times the configurations
//! (`bench::run`), writes the rows (CSV, JSON), plots and trace, and prints the table with the
//! trade's floor and ceiling.

use super::{check_eye_ball, options, print_warnings, progress_bar, BenchArgs, GpuArgs};
use anyhow::{Context as _, Result};
use multirate::bench::{self, BenchConfig, BenchScene};
use multirate::render::MAX_LEVEL;
use multirate::vk::Context;

pub(super) fn run_bench(args: &BenchArgs, gpu: &GpuArgs) -> Result<()> {
    for &epsilon in &args.epsilon {
        anyhow::ensure!(
            epsilon.is_finite() && epsilon > 0.0,
            "--epsilon values must be positive (got {epsilon})"
        );
    }
    for &n_max in &args.nmax {
        anyhow::ensure!(
            (1..=MAX_LEVEL).contains(&n_max),
            "--nmax values must be in 1..={MAX_LEVEL} (got {n_max})"
        );
    }
    anyhow::ensure!(args.frames >= 1, "--frames must be at least 1");
    anyhow::ensure!(args.orbit.is_finite(), "--orbit must be a number of degrees (got {})", args.orbit);
    check_eye_ball(args.eye_ball)?;
    let scenes = args.scene.iter().map(|path| BenchScene::load(path)).collect::<Result<Vec<_>, _>>()?;
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
        eye_ball_share: args.eye_ball,
    };
    std::fs::create_dir_all(&args.out).with_context(|| format!("{}: cannot create", args.out.display()))?;
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
    Ok(())
}
