//! The trade's bounds (multirate must never be slower than per-pixel shading): every scene with its floor
//! (`vertex`), its ceiling (`pixel` / `vertex`), the empty frame, and multirate with the cost
//! model against multirate estimating every triangle, at the sweep's resolution and at the
//! table's (1920×1080 and 3840×2160), each table naming the scenes where multirate was slower than
//! `pixel`; the same with the camera turning a degree a frame, beside the still camera's; and the
//! light-count sweep, the bunny lit by 1, 4, 16 and 64 point lights.

use super::setup::{config, create_results, header, load_scene, percent, write, ExperimentOptions, Plan};
use crate::bench::calibrate::lit_by;
use crate::bench::measure::{run, BenchConfig, BenchScene, Progress};
use crate::bench::row::{to_csv, Row};
use crate::bench::twin::twin_cost;
use crate::error::Result;
use crate::render::Mode;
use crate::vk::Context;
use std::fmt::Write as _;
use std::sync::Arc;

/// Degrees per frame by which the camera turns about its target in the turning tables.
pub const TURN_DEGREES: f32 = 1.0;

/// The light counts of the sweep.
pub const SWEEP_LIGHTS: [usize; 4] = [1, 4, 16, 64];

/// The scenes of the bounds table (the first one's lights are swept): the shipped ones, the
/// many-light bunnies, the dense meshes, and the spotlit bunny whose parameter map the cost
/// model cannot foresee.
pub const SCENES: [&str; 10] = [
    "bunny",
    "teapot",
    "plane_lights",
    "bunny_16",
    "bunny_64",
    "bunny_dense",
    "teapot_dense",
    "gear",
    "sculpture",
    "bunny_spots",
];

/// Runs both parts and returns the page (`docs/trade.md`), its CSVs written into
/// `options.out`.
pub fn trade_page(
    context: &Arc<Context>,
    options: &ExperimentOptions,
    progress: &mut dyn FnMut(&str, Progress<'_>),
) -> Result<String> {
    let plan = Plan::new(options.quick);
    create_results(options)?;
    let scenes = SCENES.iter().map(|name| load_scene(options, name)).collect::<Result<Vec<_>>>()?;
    let mut md = String::new();
    header(&mut md, context, options);
    trade(&mut md, context, options, &plan, &scenes, progress)?;
    Ok(md)
}

fn trade(
    md: &mut String,
    context: &Arc<Context>,
    options: &ExperimentOptions,
    plan: &Plan,
    scenes: &[BenchScene],
    progress: &mut dyn FnMut(&str, Progress<'_>),
) -> Result<()> {
    let mut model = config(options, vec![Mode::Vertex, Mode::Multirate], vec![plan.sweep, plan.table]);
    model.min_estimated_areas = vec![None];
    let rows = run_apart(context, scenes, &model, &mut |p| progress("the trade's bounds", p))?;
    write(&options.out.join("trade.csv"), &to_csv(&rows))?;
    bounds_table(md, &rows, plan.sweep, true);
    bounds_table(md, &rows, plan.table, false);
    let turning = BenchConfig { orbit_degrees: TURN_DEGREES, ..model.clone() };
    let turning_rows =
        run(context, scenes, &turning, &mut |p| progress("the trade's bounds, turning", p))?.rows;
    write(&options.out.join("trade_turning.csv"), &to_csv(&turning_rows))?;
    turning_table(md, &rows, &turning_rows, plan.sweep, true);
    turning_table(md, &rows, &turning_rows, plan.table, false);
    pre_pass_table(md, &rows, plan.sweep, scenes);

    model.resolutions = vec![plan.sweep];

    let lit: Vec<BenchScene> = SWEEP_LIGHTS
        .iter()
        .map(|&count| BenchScene {
            name: format!("{}, {count} lights", scenes[0].name),
            scene: lit_by(&scenes[0].scene, count),
        })
        .collect();
    let sweep_rows = run_apart(context, &lit, &model, &mut |p| progress("light-count sweep", p))?;
    write(&options.out.join("lights.csv"), &to_csv(&sweep_rows))?;
    light_sweep(md, &sweep_rows, plan.sweep);
    Ok(())
}

/// `model` (multirate with the cost model) and the same estimating every visible triangle, each in
/// a run of its own beside `pixel` and `vertex`, the second run's rows of those two left out. Run in
/// turns, the two would begin a ball of eyes at every turn (its key holds the resolved break-even
/// area, `level_ball`) and estimate every visible triangle each time, which no user's frames do.
fn run_apart(
    context: &Arc<Context>,
    scenes: &[BenchScene],
    model: &BenchConfig,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<Row>> {
    let every = BenchConfig { min_estimated_areas: vec![Some(0.0)], ..model.clone() };
    let mut rows = run(context, scenes, model, progress)?.rows;
    let every_rows = run(context, scenes, &every, progress)?.rows;
    rows.extend(every_rows.into_iter().filter(|r| r.mode == "multirate"));
    Ok(rows)
}

fn find<'a>(rows: &'a [Row], of: &Row, mode: &str, cost_model: Option<bool>) -> Option<&'a Row> {
    rows.iter().find(|r| {
        same_frame(r, of)
            && r.mode == mode
            && cost_model.is_none_or(|on| r.min_estimated_area.is_some_and(|a| (a > 0.0) == on))
    })
}

/// The `vertex` row and the multirate rows with the cost model and without of the scene and
/// resolution of a `pixel` row.
fn measured<'a>(rows: &'a [Row], pixel: &Row) -> Option<(&'a Row, &'a Row, &'a Row)> {
    Some((
        find(rows, pixel, "vertex", None)?,
        find(rows, pixel, "multirate", Some(true))?,
        find(rows, pixel, "multirate", Some(false))?,
    ))
}

fn ms(row: &Row) -> String {
    match row.pre_pass_ms {
        Some(pre_pass) => format!("{:.1} ({:.1})", row.gpu_ms.median, pre_pass.median),
        None => format!("{:.1}", row.gpu_ms.median),
    }
}

fn share(row: &Row) -> String {
    row.trade.map_or_else(|| "–".to_string(), |t| percent(t.saving_share))
}

/// The bounds table at one resolution; `explain`: the columns' explanation before it.
fn bounds_table(md: &mut String, rows: &[Row], (w, h): (u32, u32), explain: bool) {
    let title = format!("The trade's bounds: floor, ceiling and the share of the saving taken ({w}×{h})");
    let explanation = explain.then_some(
            "`vertex` shades once per vertex: its time is the floor any shading-rate method can approach, and `pixel` over it the ceiling of the speedup. The share of the possible saving a mode takes is (t_pixel − t) / (t_pixel − t_vertex): 100 % at the floor, 0 at `pixel`'s time, below 0 where it is slower. The empty frame draws nothing visible (every triangle behind the eye). multirate runs with the device's cost model (images below the break-even area, \"estimated above\", are shaded per pixel without an estimate; the frame guard draws a frame as `pixel` does where that measured faster, \"as pixel\" counting such frames among those measured: its probes, or all) and, for comparison, estimating every visible triangle, in a run of its own (in turns, the two would begin a ball of eyes at each turn). Times in ms (pre-pass in brackets, over the frames that ran it).",
    );
    let columns = [
        "scene",
        "triangles",
        "pixel",
        "vertex (floor)",
        "ceiling",
        "empty",
        "multirate",
        "speedup",
        "share",
        "estimated above",
        "as pixel",
        "every triangle estimated",
        "share",
    ];
    table_head(md, &title, explanation, &columns);
    let mut slower = Vec::new();
    for pixel in rows.iter().filter(|r| r.mode == "pixel" && (r.width, r.height) == (w, h)) {
        let Some((vertex, model, every)) = measured(rows, pixel) else {
            continue;
        };
        slower.extend(slower_than_pixel(model, pixel));
        let _ = writeln!(
            md,
            "| {} | {} | {:.1} | {:.1} | {:.2}× | {:.1} | {} | {} | {} | {:.1} px | {} of {} | {} | {} |",
            pixel.scene,
            pixel.triangles,
            pixel.gpu_ms.median,
            vertex.gpu_ms.median,
            pixel.gpu_ms.median / vertex.gpu_ms.median,
            pixel.empty_ms,
            ms(model),
            percent(model.speedup),
            share(model),
            model.min_estimated_area.unwrap_or_default(),
            model.frames_drawn_as_pixel.unwrap_or_default(),
            model.frames,
            ms(every),
            share(every),
        );
    }
    slower_verdict(md, &slower, &format!("at {w}×{h}"));
}

/// A table's heading, its explanation (or a pointer to the table above) and its header rows: the
/// first column left-aligned, the others right-aligned.
pub(super) fn table_head(md: &mut String, title: &str, explanation: Option<&str>, columns: &[&str]) {
    let _ = writeln!(md, "## {title}\n");
    let _ = writeln!(md, "{}\n", explanation.unwrap_or("The columns are those of the table above."));
    let _ = writeln!(md, "| {} |", columns.join(" | "));
    let alignment: Vec<&str> = (0..columns.len()).map(|k| if k == 0 { "---" } else { "---:" }).collect();
    let _ = writeln!(md, "| {} |", alignment.join(" | "));
}

/// `model`'s scene, with both times, where it took longer than `pixel`.
fn slower_than_pixel(model: &Row, pixel: &Row) -> Option<String> {
    let (model_ms, pixel_ms) = (model.gpu_ms.median, pixel.gpu_ms.median);
    (model_ms > pixel_ms).then(|| format!("{} ({model_ms:.1} against {pixel_ms:.1} ms)", pixel.scene))
}

/// The line naming the scenes where multirate with the cost model was slower than `pixel`, `when`.
fn slower_verdict(md: &mut String, slower: &[String], when: &str) {
    let verdict = if slower.is_empty() { "none".to_string() } else { slower.join(", ") };
    let _ = writeln!(
        md,
        "\nScenes where multirate (with the cost model) took longer than `pixel` {when}: {verdict}.\n"
    );
}

/// The camera still and turning [`TURN_DEGREES`] a frame side by side at one resolution, multirate
/// with the cost model; `explain`: the columns' explanation before it.
pub(super) fn turning_table(
    md: &mut String,
    still: &[Row],
    turning: &[Row],
    (w, h): (u32, u32),
    explain: bool,
) {
    let title = format!("The camera still and turning {TURN_DEGREES}° a frame ({w}×{h})");
    let explanation = format!(
            "The camera turns about its target by {TURN_DEGREES}° a frame while the frames are timed (`bench --orbit {TURN_DEGREES}`), every configuration's measured frames at the same cameras. The eye leaves a ball of eyes of the configured radius in one frame; the ball that begins then is widened to hold the eye's next few steps, so the pre-pass estimates the visible triangles once every few frames, as it does for a user who moves the camera. multirate with the cost model; times in ms (pre-pass in brackets); \"as pixel\" counts the turning frames the frame guard drew as `pixel` does."
    );
    let columns = [
        "scene",
        "pixel, still",
        "multirate, still",
        "share, still",
        "pixel, turning",
        "vertex, turning",
        "multirate, turning",
        "speedup, turning",
        "share, turning",
        "as pixel",
    ];
    table_head(md, &title, explain.then_some(explanation.as_str()), &columns);
    let mut slower = Vec::new();
    for pixel in turning.iter().filter(|r| r.mode == "pixel" && (r.width, r.height) == (w, h)) {
        // The turning run measures multirate with the cost model only.
        let (Some(vertex), Some(model), Some(still_pixel)) = (
            find(turning, pixel, "vertex", None),
            find(turning, pixel, "multirate", Some(true)),
            find(still, pixel, "pixel", None),
        ) else {
            continue;
        };
        let still_model = find(still, still_pixel, "multirate", Some(true));
        slower.extend(slower_than_pixel(model, pixel));
        let _ = writeln!(
            md,
            "| {} | {:.1} | {} | {} | {:.1} | {:.1} | {} | {} | {} | {} of {} |",
            pixel.scene,
            still_pixel.gpu_ms.median,
            still_model.map_or_else(|| "–".to_string(), ms),
            still_model.map_or_else(|| "–".to_string(), share),
            pixel.gpu_ms.median,
            vertex.gpu_ms.median,
            ms(model),
            percent(model.speedup),
            share(model),
            model.frames_drawn_as_pixel.unwrap_or_default(),
            model.frames,
        );
    }
    slower_verdict(md, &slower, &format!("at {w}×{h} with the camera turning"));
}

/// Whether two rows are of the same scene and resolution.
fn same_frame(a: &Row, b: &Row) -> bool {
    a.scene == b.scene && (a.width, a.height) == (b.width, b.height)
}

/// Passes over a scene's triangles of which the Rust twin's time is the median.
const TWIN_PASSES: usize = 3;

/// The pre-pass's time per visible triangle (not culled, as the counting frame found them), with
/// the cost model and estimating every triangle; and the Rust twin's time per triangle on the
/// same scene.
fn pre_pass_table(md: &mut String, rows: &[Row], (w, h): (u32, u32), scenes: &[BenchScene]) {
    let _ = writeln!(md, "## The pre-pass per visible triangle ({w}×{h})\n");
    let _ = writeln!(
        md,
        "The pre-pass's median time over the triangles it finds visible (not culled: in view, not facing away on a one-sided mesh), in µs; \"–\" where no frame ran it (the mesh was drawn as `pixel` draws it). The last column is the estimator's Rust twin on the CPU, over every triangle of the scene, back faces included (`multirate::bench::twin`, the median of {TWIN_PASSES} passes; `cargo bench --bench estimator` runs the same).\n"
    );
    let _ = writeln!(md, "| scene | triangles | visible | multirate | per visible triangle | every triangle estimated | per visible triangle | Rust twin per triangle |");
    let _ = writeln!(md, "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    let per_triangle = |row: &Row, visible: u64| match row.pre_pass_ms {
        Some(pre_pass) if visible > 0 => {
            (format!("{:.2}", pre_pass.median), format!("{:.2}", 1000.0 * pre_pass.median / visible as f64))
        }
        _ => ("–".to_string(), "–".to_string()),
    };
    for pixel in rows.iter().filter(|r| r.mode == "pixel" && (r.width, r.height) == (w, h)) {
        let Some((_, model, every)) = measured(rows, pixel) else {
            continue;
        };
        let visible = (pixel.triangles as u64).saturating_sub(every.evaluations.culled_patches);
        let (model_ms, model_us) = per_triangle(model, visible);
        let (every_ms, every_us) = per_triangle(every, visible);
        let twin = scenes.iter().find(|s| s.name == pixel.scene).map_or_else(
            || "–".to_string(),
            |s| format!("{:.2}", twin_cost(&s.scene, TWIN_PASSES).per_triangle_us),
        );
        let _ = writeln!(
            md,
            "| {} | {} | {visible} | {model_ms} | {model_us} | {every_ms} | {every_us} | {twin} |",
            pixel.scene, pixel.triangles
        );
    }
    let _ = writeln!(md);
}

fn light_sweep(md: &mut String, rows: &[Row], (w, h): (u32, u32)) {
    let _ = writeln!(md, "## Light-count sweep: the bunny lit by 1 to 64 point lights ({w}×{h})\n");
    let _ = writeln!(
        md,
        "The bunny's lights replaced by N white point lights around it (`bench::calibrate::lit_by`, the total intensity kept). Shading costs grow with N both per pixel and in the estimate; this is where a device's break-even lies.\n"
    );
    let _ = writeln!(
        md,
        "| lights | pixel | vertex | multirate | speedup | share | estimated above | every triangle estimated | speedup | share |"
    );
    let _ = writeln!(md, "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for (pixel, count) in rows.iter().filter(|r| r.mode == "pixel").zip(SWEEP_LIGHTS) {
        let Some((vertex, model, every)) = measured(rows, pixel) else {
            continue;
        };
        let _ = writeln!(
            md,
            "| {count} | {:.1} | {:.1} | {} | {} | {} | {:.1} px | {} | {} | {} |",
            pixel.gpu_ms.median,
            vertex.gpu_ms.median,
            ms(model),
            percent(model.speedup),
            share(model),
            model.min_estimated_area.unwrap_or_default(),
            ms(every),
            percent(every.speedup),
            share(every),
        );
    }
    let _ = writeln!(md);
}
