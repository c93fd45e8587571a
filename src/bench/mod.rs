//! Benchmarks: the speed/accuracy trade, measured. For every scene and resolution the `pixel`
//! reference is rendered first; then every mode (multirate for every ε × n_max) is
//! - timed: warm-up frames, then N measured frames with frames in flight; median, p10, p90 of
//!   the forward pass's GPU time; the configurations of one scene and resolution take turns
//!   of a few frames each, so that a slow spell of the machine slows them all alike,
//! - counted: runs of the full shading function with the counting variant (never timed),
//! - compared with the reference image: L∞, mean L2, PSNR, FLIP (`analysis::metrics`).
//!
//! The results are rows (CSV and JSON), SVG plots of time against error with the Pareto front
//! ([`plot`]), and a Chrome trace of every measured frame ([`trace`]). The estimator's Rust twin
//! is timed apart, without a frame ([`twin`]).
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`row`]: one measured configuration, its timing and trade, and the CSV and JSON files.
//! 2. [`plot`]: SVG plots of time against error, with the Pareto front.
//! 3. [`trace`]: a Chrome trace of every measured frame.
//! 4. [`renderers`]: a renderer of its own for every multirate configuration after the first.
//! 5. [`stability`]: temporal stability along a camera path, as a user sees a mode.
//! 6. [`measure`]: running every configuration: images, counts and time in turns (and, along a
//!    camera path, their stability, or that alone).
//! 7. [`per_frame`]: a run along a camera path, frame by frame (CSV and plot).
//! 8. [`twin`]: the estimator's Rust twin, timed without a frame.
//! 9. [`calibrate`]: the cost model's calibration from measured frames.
//! 10. [`experiments`]: the paper's experiments and the trade's page.

pub mod calibrate;
pub mod experiments;
mod measure;
pub mod per_frame;
pub mod plot;
pub mod renderers;
mod row;
pub mod stability;
pub mod trace;
pub mod twin;

pub use measure::{
    measure_in_turns, run, walk_paths, BenchConfig, BenchResult, BenchScene, Progress, Schedule,
    ShadowReport, FRAMES_PER_TURN,
};
pub use row::{csv_line, percentile, to_csv, to_json, Row, Timing, Trade, CSV_HEADER};
