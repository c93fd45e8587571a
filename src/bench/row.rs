//! A benchmark's rows: one measured configuration ([`Row`]), its GPU time's median and spread
//! ([`Timing`]), the trade's bounds it took ([`Trade`]), and the CSV and JSON files of rows.

use crate::render::{DrawPart, EvaluationCounts, PrePassStep, DRAW_PARTS, PRE_PASS_STEPS};
use crate::vk::timing::PipelineStatistics;

/// Median and spread of per-frame GPU milliseconds.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Timing {
    pub median: f64,
    pub p10: f64,
    pub p90: f64,
}

impl Timing {
    /// Percentiles by linear interpolation between order statistics.
    pub fn of(samples: &[f64]) -> Timing {
        let mut sorted: Vec<f64> = samples.to_vec();
        sorted.sort_by(f64::total_cmp);
        Timing {
            median: percentile(&sorted, 0.5),
            p10: percentile(&sorted, 0.1),
            p90: percentile(&sorted, 0.9),
        }
    }
}

/// The `q` quantile of sorted samples (NaN when there are none).
pub fn percentile(sorted: &[f64], q: f64) -> f64 {
    match sorted.len() {
        0 => f64::NAN,
        n => {
            let position = q.clamp(0.0, 1.0) * (n - 1) as f64;
            let below = position.floor() as usize;
            let above = position.ceil() as usize;
            sorted[below] + (sorted[above] - sorted[below]) * (position - below as f64)
        }
    }
}

/// One measured configuration.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Row {
    pub scene: String,
    pub triangles: usize,
    pub mode: String,
    /// multirate only.
    pub epsilon: Option<f32>,
    /// multirate only.
    pub n_max: Option<u32>,
    /// multirate only: where the estimator ran (`tcs` or `compute`).
    pub estimator: Option<String>,
    /// multirate only: whether the pre-pass held its levels between the balls of eyes
    /// (`View::hold_levels`).
    pub levels_held: Option<bool>,
    pub width: u32,
    pub height: u32,
    pub frames: u32,
    pub gpu_ms: Timing,
    /// `--estimator compute`: the part of `gpu_ms` the triangle-level pre-pass took.
    pub pre_pass_ms: Option<Timing>,
    /// `--estimator compute`: the median milliseconds of each pre-pass step
    /// (`PrePassStep::ALL`'s order: cull, range, estimate, refine, patches).
    pub pre_pass_steps_ms: Option<[f64; PRE_PASS_STEPS]>,
    /// `bench --draw-parts`: the median milliseconds of each part of the draws (`DrawPart::ALL`'s
    /// order, summed over the meshes); the frame's own time is then that of a split rendering.
    pub draw_parts_ms: Option<[f64; DRAW_PARTS]>,
    /// multirate only: images below this many pixels were shaded per pixel unestimated.
    pub min_estimated_area: Option<f32>,
    /// multirate with the cost model: how many of the measured frames the frame guard drew as
    /// `pixel` does (`render::guard`; its probes, or all where multirate measured slower).
    pub frames_drawn_as_pixel: Option<u32>,
    /// `pixel` median time over this row's: the paper's speedup ratio (×100 %).
    pub speedup: f64,
    /// The trade's bounds at this scene and resolution (where `vertex` was measured).
    pub trade: Option<Trade>,
    /// The median time of an empty frame at this scene and resolution: the `pixel` pass with
    /// the camera turned around, so that every triangle is clipped (the pass's own cost and
    /// the vertices' transform).
    pub empty_ms: f64,
    pub evaluations: EvaluationCounts,
    /// Evaluations as a fraction of `pixel` mode's.
    pub evaluation_ratio: f64,
    pub l_inf: f64,
    /// L∞ over the pixels where this image and `pixel`'s show the same triangle: what ε bounds.
    pub l_inf_same_triangle: f64,
    /// Pixels where this image and `pixel`'s show different triangles (silhouettes, depth ties).
    pub other_triangle_pixels: usize,
    /// multirate only: pixels showing the same triangle as in `pixel`'s image where some
    /// channel differs from it by more than ε.
    pub pixels_over_epsilon: Option<usize>,
    pub mean_l2: f64,
    pub psnr_db: f64,
    pub flip: f64,
    /// multirate only: the fraction of covered pixels shaded by the per-pixel fallback.
    pub fallback_fraction: Option<f64>,
    /// Pipeline statistics of the last measured frame, where the device has them.
    pub statistics: Option<PipelineStatistics>,
    pub device: String,
    pub driver: String,
}

/// How much of the possible saving a row took. `vertex` shades least (once per vertex), so its
/// time is the floor any shading-rate method can approach, and `pixel`'s over it the ceiling
/// of the speedup.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Trade {
    /// `vertex` mode's median time.
    pub floor_ms: f64,
    /// `pixel` over `vertex`: the most any mode can speed up.
    pub ceiling: f64,
    /// (t_pixel − t_row) / (t_pixel − t_vertex): 1 at the floor, 0 at `pixel`'s time, below 0
    /// where the row is slower than `pixel`.
    pub saving_share: f64,
}

impl Trade {
    /// The bounds for a row of `row_ms` with `pixel_ms` and `vertex_ms` measured alike.
    pub fn of(row_ms: f64, pixel_ms: f64, vertex_ms: f64) -> Trade {
        Trade {
            floor_ms: vertex_ms,
            ceiling: pixel_ms / vertex_ms,
            saving_share: (pixel_ms - row_ms) / (pixel_ms - vertex_ms),
        }
    }
}

/// The CSV header; `csv_line` writes the fields in this order.
pub const CSV_HEADER: &str = "scene,triangles,mode,epsilon,n_max,estimator,levels_held,width,height,frames,\
gpu_ms_median,gpu_ms_p10,gpu_ms_p90,pre_pass_ms_median,cull_ms_median,range_ms_median,estimate_ms_median,refine_ms_median,\
patches_ms_median,draw_whole_ms_median,draw_flat_ms_median,draw_tessellated_ms_median,draw_fallback_depth_ms_median,\
draw_fallback_shading_ms_median,draw_back_faces_ms_median,draw_emitters_ms_median,min_estimated_area,frames_drawn_as_pixel,speedup,floor_ms,ceiling,saving_share,empty_ms,evaluations,vertex_evaluations,subvertex_evaluations,\
fragment_evaluations,culled_patches,evaluation_ratio,l_inf,l_inf_same_triangle,other_triangle_pixels,pixels_over_epsilon,mean_l2,psnr_db,flip,fallback_fraction,\
vs_invocations,tcs_patches,tes_invocations,clipping_primitives,fs_invocations,device,driver";

/// "NA" marks a value that does not apply to the row (ε of `pixel` mode, statistics on a
/// device without them), so that every field is filled.
const NOT_APPLICABLE: &str = "NA";

fn optional<T: ToString>(value: Option<T>) -> String {
    value.map_or_else(|| NOT_APPLICABLE.to_string(), |v| v.to_string())
}

fn quoted(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// One CSV line (no newline) for `row`.
pub fn csv_line(row: &Row) -> String {
    let statistics = row.statistics.as_ref();
    [
        quoted(&row.scene),
        row.triangles.to_string(),
        row.mode.clone(),
        optional(row.epsilon),
        optional(row.n_max),
        optional(row.estimator.as_ref()),
        optional(row.levels_held),
        row.width.to_string(),
        row.height.to_string(),
        row.frames.to_string(),
        format!("{:.4}", row.gpu_ms.median),
        format!("{:.4}", row.gpu_ms.p10),
        format!("{:.4}", row.gpu_ms.p90),
        optional(row.pre_pass_ms.map(|t| format!("{:.4}", t.median))),
        PrePassStep::ALL
            .map(|step| optional(row.pre_pass_steps_ms.map(|ms| format!("{:.4}", ms[step as usize]))))
            .join(","),
        DrawPart::ALL
            .map(|part| optional(row.draw_parts_ms.map(|ms| format!("{:.4}", ms[part as usize]))))
            .join(","),
        optional(row.min_estimated_area.map(|a| format!("{a:.2}"))),
        optional(row.frames_drawn_as_pixel),
        format!("{:.4}", row.speedup),
        optional(row.trade.map(|t| format!("{:.4}", t.floor_ms))),
        optional(row.trade.map(|t| format!("{:.4}", t.ceiling))),
        optional(row.trade.map(|t| format!("{:.4}", t.saving_share))),
        format!("{:.4}", row.empty_ms),
        row.evaluations.total().to_string(),
        row.evaluations.vertices.to_string(),
        row.evaluations.sub_vertices.to_string(),
        row.evaluations.fragments.to_string(),
        optional((row.mode == "multirate").then_some(row.evaluations.culled_patches)),
        format!("{:.5}", row.evaluation_ratio),
        format!("{:.6}", row.l_inf),
        format!("{:.6}", row.l_inf_same_triangle),
        row.other_triangle_pixels.to_string(),
        optional(row.pixels_over_epsilon),
        format!("{:.3e}", row.mean_l2),
        format!("{:.3}", row.psnr_db),
        format!("{:.5}", row.flip),
        optional(row.fallback_fraction.map(|f| format!("{f:.5}"))),
        optional(statistics.map(|s| s.vertex_shader_invocations)),
        optional(statistics.map(|s| s.tessellation_control_patches)),
        optional(statistics.map(|s| s.tessellation_evaluation_invocations)),
        optional(statistics.map(|s| s.clipping_primitives)),
        optional(statistics.map(|s| s.fragment_shader_invocations)),
        quoted(&row.device),
        quoted(&row.driver),
    ]
    .join(",")
}

/// The CSV file: header and one line per row.
pub fn to_csv(rows: &[Row]) -> String {
    let mut text = String::from(CSV_HEADER);
    text.push('\n');
    for row in rows {
        text.push_str(&csv_line(row));
        text.push('\n');
    }
    text
}

/// The JSON file: an array of rows (non-finite numbers, such as the PSNR of identical
/// images, become null).
pub fn to_json(rows: &[Row]) -> String {
    serde_json::to_string_pretty(rows).expect("rows serialise")
}

#[cfg(test)]
mod tests;
