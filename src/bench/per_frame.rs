//! A run along a camera path, frame by frame (the paper's Fig. 5, last column): every row's GPU
//! time and pre-pass time per frame as CSV, the GPU time per frame as an SVG plot, one line per
//! configuration, and every configuration's temporal stability per frame as CSV. The rows' measured frames are the path's frames in order
//! (`measure::measure_in_turns` takes them in turns along the same cameras).

use super::plot::{self, Chart, Point, Series};
use super::row::Row;
use super::stability::StabilityRun;
use crate::error::Result;
use crate::render::Measurement;
use std::path::Path;

/// Per frame of every row: `scene,configuration,frame,time_s,gpu_ms,pre_pass_ms`.
pub fn to_csv(rows: &[Row], measurements: &[Measurement], fps: f32) -> String {
    let mut csv = String::from("scene,configuration,frame,time_s,gpu_ms,pre_pass_ms\n");
    for (row, measurement) in rows.iter().zip(measurements) {
        let label = format!("{} {}x{}", plot::row_label(row), row.width, row.height);
        let pre_pass = measurement.frame_pre_pass_ms.iter().copied().chain(std::iter::repeat(0.0));
        for (frame, (ms, pre_pass_ms)) in measurement.gpu_ms().into_iter().zip(pre_pass).enumerate() {
            let time = frame as f32 / fps;
            csv += &format!("{},{label},{frame},{time:.4},{ms:.4},{pre_pass_ms:.4}\n", row.scene);
        }
    }
    csv
}

/// The GPU time of every frame along the path, one line per row, into an SVG file at `path`.
pub fn plot(rows: &[Row], measurements: &[Measurement], fps: f32, path: &Path) -> Result<()> {
    let series = rows
        .iter()
        .zip(measurements)
        .map(|(row, measurement)| Series {
            name: format!("{} {}", row.scene, plot::row_label(row)),
            points: measurement
                .gpu_ms()
                .into_iter()
                .enumerate()
                .map(|(frame, ms)| Point { x: f64::from(frame as f32 / fps), y: ms, label: None })
                .collect(),
            line: true,
        })
        .collect();
    let chart = Chart {
        title: "GPU time per frame along the camera path",
        x_label: "time along the path (s)",
        y_label: "GPU ms",
        series,
        pareto: false,
        x_log: false,
    };
    plot::draw(&chart, path)
}

/// Per step of every configuration's stability run: `configuration,frame,compared,masked,
/// other_triangle,largest,p99,jump_share,jumps,pattern_jumps,test_change,reference_change,
/// level_change_share,pixels_over_epsilon` (frame `k` against frame `k − 1`; `pattern_jumps`:
/// the jumps on a triangle whose pattern changed; the level share and the pixels over ε, of
/// frame `k`, empty but for multirate).
pub fn stability_csv(runs: &[StabilityRun]) -> String {
    let mut csv = String::from(
        "configuration,frame,compared,masked,other_triangle,largest,p99,jump_share,jumps,pattern_jumps,test_change,reference_change,level_change_share,pixels_over_epsilon\n",
    );
    for run in runs {
        for (k, step) in run.steps.steps.iter().enumerate() {
            let levels = run.level_changes.get(k).map_or_else(String::new, |share| format!("{share:.6}"));
            let over = run.pixels_over_epsilon.get(k + 1).map_or_else(String::new, usize::to_string);
            csv += &format!(
                "{},{},{},{},{},{:.6},{:.6},{:.6},{},{},{:.4},{:.4},{levels},{over}\n",
                run.label,
                k + 1,
                step.compared,
                step.masked,
                step.other_triangle,
                step.largest,
                step.p99,
                step.jump_share(),
                step.jumps,
                step.pattern_jumps,
                step.test_change,
                step.reference_change
            );
        }
    }
    csv
}
