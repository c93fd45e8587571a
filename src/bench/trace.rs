//! Timing captures in the Chrome trace event format (JSON), which Perfetto and
//! chrome://tracing open: one track per benchmarked configuration, one complete ("X") event
//! per measured frame's forward pass, placed at its GPU timestamps, and one per pre-pass
//! (`--estimator compute`) nested in it.

use super::row::Row;
use crate::render::Measurement;
use crate::vk::timing::GpuInterval;
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
        let forward = format!("forward pass ({})", row.mode);
        events.extend(
            measurement
                .frames
                .iter()
                .enumerate()
                .map(|(frame, interval)| frame_event(&forward, tid, frame, interval, origin_ns)),
        );
        // `--estimator compute`: the pre-pass, nested in its frame's event (frames the guard
        // drew as `pixel` draws them ran none).
        events.extend(measurement.pre_pass.iter().map(|interval| {
            let frame = measurement.frames.iter().rposition(|f| f.start_ns <= interval.start_ns).unwrap_or(0);
            frame_event("triangle-level pre-pass", tid, frame, interval, origin_ns)
        }));
    }
    serde_json::to_string(&json!({ "traceEvents": events, "displayTimeUnit": "ms" }))
        .expect("trace serialises")
}

/// A complete ("X") event named `name` on track `tid`, spanning `interval` of `frame`.
fn frame_event(name: &str, tid: usize, frame: usize, interval: &GpuInterval, origin_ns: f64) -> Value {
    json!({
        "name": name,
        "cat": "gpu",
        "ph": "X",
        "pid": 1,
        "tid": tid,
        "ts": (interval.start_ns - origin_ns) * 1e-3,
        "dur": (interval.end_ns - interval.start_ns) * 1e-3,
        "args": { "frame": frame, "gpu_ms": interval.milliseconds() },
    })
}
