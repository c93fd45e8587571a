//! What every experiment starts from: the options ([`ExperimentOptions`]), the plan of a
//! quick or full run ([`Plan`]), the bench configuration, the scenes, the results folder, and the
//! page's header.

use crate::bench::measure::{BenchConfig, BenchScene};
use crate::error::{Error, Result};
use crate::render::{Mode, EYE_BALL_SHARE};
use crate::shading::estimator::{Discontinuity, Split};
use crate::vk::Context;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Where and how thoroughly to run.
pub struct ExperimentOptions {
    /// Results folder (`docs/results`); `results.md` is written by the caller.
    pub out: PathBuf,
    /// The folder holding the shipped scenes.
    pub scenes: PathBuf,
    /// Smaller resolutions and fewer settings (minutes instead of an hour on lavapipe).
    pub quick: bool,
    pub frames: u32,
    pub warmup: u32,
    /// The command line, quoted in the results.
    pub command: String,
}

/// One experiment's scale: resolutions and settings.
pub(super) struct Plan {
    pub table: (u32, u32),
    pub resolutions: Vec<(u32, u32)>,
    pub sweep: (u32, u32),
    pub grids: Vec<u32>,
    pub epsilons: Vec<f32>,
    pub images: (u32, u32),
}

impl Plan {
    pub(super) fn new(quick: bool) -> Plan {
        if quick {
            Plan {
                table: (960, 540),
                resolutions: vec![(480, 270), (640, 360), (960, 540)],
                sweep: (640, 360),
                grids: vec![4, 16, 64],
                epsilons: vec![0.02, 0.075, 0.3],
                images: (480, 270),
            }
        } else {
            Plan {
                table: (3840, 2160),
                resolutions: vec![(1920, 1080), (2560, 1440), (3840, 2160)],
                sweep: (1920, 1080),
                grids: vec![4, 8, 16, 32, 64, 128, 256],
                epsilons: vec![0.01, 0.02, 0.05, 0.075, 0.1, 0.2, 0.4],
                images: (960, 540),
            }
        }
    }
}

pub(super) fn config(
    options: &ExperimentOptions,
    modes: Vec<Mode>,
    resolutions: Vec<(u32, u32)>,
) -> BenchConfig {
    BenchConfig {
        modes,
        epsilons: Vec::new(),
        n_maxes: Vec::new(),
        resolutions,
        warmup: options.warmup,
        frames: options.frames,
        split: Split::Heuristic,
        // The renderer's default (the paper shades every triangle the terminator may cross per
        // pixel, which `--discontinuity conservative` reproduces).
        discontinuity: Discontinuity::Relaxed,
        placements: Vec::new(),
        images: None,
        min_estimated_areas: Vec::new(),
        orbit_degrees: 0.0,
        draw_parts: false,
        pre_pass_steps: false,
        eye_ball_share: EYE_BALL_SHARE,
        level_holds: Vec::new(),
        path: None,
    }
}

/// Creates the results folder.
pub(super) fn create_results(options: &ExperimentOptions) -> Result<()> {
    std::fs::create_dir_all(&options.out)
        .map_err(|e| Error::Output { path: options.out.clone(), message: format!("cannot create: {e}") })
}

/// The shipped scene `name` (`scenes/<name>.toml`).
pub(super) fn load_scene(options: &ExperimentOptions, name: &str) -> Result<BenchScene> {
    BenchScene::load(&options.scenes.join(format!("{name}.toml")))
}

pub(super) fn write(path: &Path, text: &str) -> Result<()> {
    std::fs::write(path, text)
        .map_err(|e| Error::Output { path: path.to_path_buf(), message: format!("cannot write: {e}") })
}

pub(super) fn percent(value: f64) -> String {
    format!("{:.0} %", value * 100.0)
}

pub(super) fn header(md: &mut String, context: &Context, options: &ExperimentOptions) {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let threads =
        std::env::var("LP_NUM_THREADS").map(|v| format!("LP_NUM_THREADS={v}")).unwrap_or_else(|_| {
            format!("LP_NUM_THREADS unset (llvmpipe then uses one thread per core: {cores})")
        });
    // lavapipe's shader compiler: `nopt` leaves out LLVM's optimisation passes (CI's setting).
    let compiler = match std::env::var("GALLIVM_PERF") {
        _ if !context.info.is_lavapipe() => String::new(),
        Ok(value) => format!("; GALLIVM_PERF={value}"),
        Err(_) => "; GALLIVM_PERF unset (LLVM's optimisation passes on)".into(),
    };
    let _ = writeln!(md, "# Results\n");
    let _ = writeln!(
        md,
        "Regenerate everything on this page (tables, CSVs and plots in `docs/results/`) with\n\n```sh\n{}\n```\n",
        options.command
    );
    let _ = writeln!(md, "| | |\n| --- | --- |");
    let _ = writeln!(md, "| device | {} |", context.info.name);
    let _ = writeln!(md, "| driver | {} |", context.info.driver);
    let _ = writeln!(md, "| CPU | {cpu}, {cores} cores available |");
    let _ = writeln!(md, "| threads | {threads}{compiler} |");
    let _ = writeln!(
        md,
        "| timing | GPU timestamps around the forward pass, median (p10–p90) of {} frames after {} warm-up frames, two frames in flight, the configurations of a scene and resolution taking turns of two frames |",
        options.frames, options.warmup
    );
    let _ = writeln!(
        md,
        "| camera | the scene's, still: multirate keeps each level while the eye stays in a ball of {} % of the camera's distance to its target (`docs/estimator.md` §16), so after a ball's first frame it estimates only what comes into view (`bench --orbit` times a turning camera) |",
        100.0 * EYE_BALL_SHARE
    );
    let _ = writeln!(
        md,
        "| metrics | L∞ and mean L2 on linear radiance; \"L∞ same triangle\" and \"pixels > ε\" count only pixels where both images show the same triangle (triangle ids of the analysis render), the others are counted apart; FLIP (mean, LDR) on the tone-mapped images |\n"
    );
    let _ = writeln!(
        md,
        "All rows are in the CSV files next to this page; the columns are those of `multirate bench` (README).\n"
    );
}
