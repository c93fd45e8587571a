//! The `multirate` command line: its arguments ([`Cli`], one [`Command`] per subcommand) and one
//! file per subcommand; `main.rs` parses and dispatches.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`common`]: the GPU options, the default scene, scene loading, the progress bar, `--frames`
//!    and resolutions, arguments parsed from words.
//! 2. [`shading`]: the SHADING options `render`, `view` and `analyze` share, and their checks.
//! 3. [`path`]: `--path`, the camera path a command follows, and the frames it numbers.
//! 4. [`render`]: `render`, one frame (or a path's frames) headless into image files.
//! 5. [`view`]: `view`, the interactive window.
//! 6. [`first_run`]: no subcommand: the window, or headless the default scene and its trade.
//! 7. [`analyze`]: `analyze`, the estimator per visible triangle as CSV.
//! 8. [`bench`]: `bench`, modes timed and measured against the pixel reference.
//! 9. [`experiments`]: `experiments`, the paper's experiments as documentation pages.
//! 10. [`calibrate`]: `calibrate`, this device's costs for the cost model.
//! 11. [`soak`]: `soak`, a long run with memory sampled.
//! 12. [`demo`]: `demo`, the room along its path: timed, its stability measured, its frames.

pub mod analyze;
pub mod bench;
pub mod calibrate;
pub mod common;
pub mod demo;
pub mod experiments;
pub mod first_run;
pub mod path;
pub mod render;
pub mod shading;
pub mod soak;
pub mod view;

use analyze::AnalyzeArgs;
use bench::BenchArgs;
use calibrate::CalibrateArgs;
use clap::{Parser, Subcommand};
use common::GpuArgs;
use demo::DemoArgs;
use experiments::ExperimentArgs;
use render::RenderArgs;
use soak::SoakArgs;
use view::ViewArgs;

/// Error-bounded multirate shading on the hardware tessellator.
///
/// Without a subcommand: opens a window on the default scene in multirate mode where a display
/// exists; otherwise renders it headless in multirate mode to multirate.png, with its level map,
/// and prints the time, evaluations and error against per-pixel shading from the same run.
#[derive(Parser)]
#[command(version, about)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub gpu: GpuArgs,
}

/// The subcommands, each run by the file of its name.
#[derive(Subcommand)]
pub enum Command {
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
    Calibrate(CalibrateArgs),
    /// The paper's demo: the room with its shadows along its camera path, every mode timed
    /// frame by frame against the pixel reference, multirate's stability from frame to frame,
    /// and frames of the path; writes them with a page (OUT/README.md) into --out.
    Demo(DemoArgs),
}
