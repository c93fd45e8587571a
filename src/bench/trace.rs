//! Timing captures in the Chrome trace event format (JSON), which Perfetto and
//! chrome://tracing open: one track per benchmarked configuration, one complete ("X") event
//! per measured frame's forward pass, placed at its GPU timestamps, and one per pre-pass
//! (`--estimator compute`) nested in it.

use super::Row;
use crate::render::Measurement;
use serde_json::{json, Value};

/// The trace of `measurements` (parallel to `rows`), times relative to the earliest frame.
pub fn chrome_trace(rows: &[Row], measurements: &[Measurement]) -> String {
    let origin_ns =
        measurements.iter().flat_map(|m| m.frames.iter().map(|f| f.start_ns)).fold(f64::INFINITY, f64::min);
    let device = rows.first().map_or_else(String::new, |r| format!("{} ({})", r.device, r.driver));
    let mut events: Vec<Value> = vec![
        json!({ "name": "process_name", "ph": "M", "pid": 1, "args": { "name": format!("GPU: {device}") } }),
    ];
    for (track, (row, measurement)) in rows.iter().zip(measurements).enumerate() {
        let tid = track + 1;
        let label = match (row.epsilon, row.n_max) {
            (Some(epsilon), Some(n_max)) => {
                format!("{} {}x{} {} ε={epsilon} n_max={n_max}", row.scene, row.width, row.height, row.mode)
            }
            _ => format!("{} {}x{} {}", row.scene, row.width, row.height, row.mode),
        };
        events.push(
            json!({ "name": "thread_name", "ph": "M", "pid": 1, "tid": tid, "args": { "name": label } }),
        );
        events.push(json!({ "name": "thread_sort_index", "ph": "M", "pid": 1, "tid": tid, "args": { "sort_index": tid } }));
        for (frame, interval) in measurement.frames.iter().enumerate() {
            events.push(json!({
                "name": format!("forward pass ({})", row.mode),
                "cat": "gpu",
                "ph": "X",
                "pid": 1,
                "tid": tid,
                "ts": (interval.start_ns - origin_ns) * 1e-3,
                "dur": (interval.end_ns - interval.start_ns) * 1e-3,
                "args": { "frame": frame, "gpu_ms": interval.milliseconds() },
            }));
        }
        // `--estimator compute`: the pre-pass, nested in its frame's event.
        for (frame, interval) in measurement.pre_pass.iter().enumerate() {
            events.push(json!({
                "name": "triangle-level pre-pass",
                "cat": "gpu",
                "ph": "X",
                "pid": 1,
                "tid": tid,
                "ts": (interval.start_ns - origin_ns) * 1e-3,
                "dur": (interval.end_ns - interval.start_ns) * 1e-3,
                "args": { "frame": frame, "gpu_ms": interval.milliseconds() },
            }));
        }
    }
    serde_json::to_string(&json!({ "traceEvents": events, "displayTimeUnit": "ms" }))
        .expect("trace serialises")
}
