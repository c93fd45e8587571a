//! `experiments`: the paper's experiments, written as `DOCS/results.md` (or with `--only trade`,
//! `DOCS/trade.md`) with their tables, CSVs and plots.

use super::common::{check_frames, default_scene, options, progress_bar, GpuArgs};
use anyhow::{Context as _, Result};
use clap::Args;
use multirate::bench;
use multirate::vk::Context;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct ExperimentArgs {
    /// The documentation folder: results.md goes here, everything else into its results/.
    #[arg(long, default_value = "docs")]
    pub docs: PathBuf,
    /// Smaller resolutions and fewer settings: minutes instead of most of an hour on lavapipe.
    #[arg(long)]
    pub quick: bool,
    /// Measured frames per configuration.
    #[arg(long, default_value_t = 10)]
    pub frames: u32,
    /// Frames rendered before measuring.
    #[arg(long, default_value_t = 2)]
    pub warmup: u32,
    /// Run one part only: `trade` (the trade's bounds and the light sweep, DOCS/trade.md).
    #[arg(long, value_parser = ["trade"])]
    pub only: Option<String>,
}

pub fn run_experiments(args: &ExperimentArgs, gpu: &GpuArgs) -> Result<()> {
    check_frames(args.frames)?;
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
