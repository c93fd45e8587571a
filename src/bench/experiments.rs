//! The paper's experiments (seed 003, Sec. 5–6) as one command that writes its tables, CSVs
//! and plots into a results folder and returns `docs/results.md`:
//! - Table 1: every shipped scene, `pixel` against `multirate` (time, speedup, error,
//!   evaluations), and with the same rows Fig. 6 (evaluations per mode) and Figs. 2 / 9
//!   (fixed n = 1, 2, 4 against multirate: time and error, with the bunny's images);
//! - the scenes at the paper's scale (dense bunny and teapot, the room), every mode;
//! - Fig. 10: the bunny at 1920×1080, 2560×1440 and 3840×2160, work per shader stage;
//! - Fig. 11: the plane with three sharp lights at triangle counts from 32 to 131,072;
//! - the ε sweep: time and evaluations against error, the trade itself;
//! - the trade's bounds (`trade`, its own page `docs/trade.md`): floor, ceiling, empty frame and
//!   the share of the saving per scene, with and without the cost model, and the light sweep.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`setup`]: the options, the plan, the scenes, the results folder and the page's header.
//! 2. [`trade`]: the trade's bounds and the light sweep, `docs/trade.md`.

mod setup;
mod trade;

pub use setup::ExperimentOptions;
pub use trade::trade_page;

use setup::{config, create_results, header, load_scene, percent, write, Plan};

use super::measure::{run, BenchScene, Progress};
use super::plot;
use super::row::{to_csv, Row};
use crate::error::Result;
use crate::render::Mode;
use crate::scene::Scene;
use crate::vk::Context;
use glam::Vec3;
use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;

/// The plane of `scenes/plane_lights.toml` re-meshed as an n×n grid (2n² triangles), as
/// `scenes/tools/make_grid.py n 2` writes it.
pub fn plane_grid(plane: &Scene, n: u32) -> Scene {
    let mut scene = plane.clone();
    let mesh = &mut scene.meshes[0];
    let (size, half) = (2.0f32, 1.0f32);
    mesh.positions.clear();
    for j in 0..=n {
        for i in 0..=n {
            let x = -half + size * i as f32 / n as f32;
            let z = -half + size * j as f32 / n as f32;
            mesh.positions.push(Vec3::new(x, 0.0, z));
        }
    }
    mesh.normals = vec![Vec3::Y; mesh.positions.len()];
    mesh.indices.clear();
    let vertex = |i: u32, j: u32| j * (n + 1) + i;
    for j in 0..n {
        for i in 0..n {
            let (a, b, c, d) = (vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1), vertex(i, j + 1));
            mesh.indices.extend([a, d, c, a, c, b]);
        }
    }
    mesh.name = format!("grid_{n}");
    scene
}

fn find<'a>(rows: &'a [Row], scene: &str, mode: &str, resolution: (u32, u32)) -> Option<&'a Row> {
    rows.iter().find(|r| r.scene == scene && r.mode == mode && (r.width, r.height) == resolution)
}

fn small(value: f64) -> String {
    if value == 0.0 {
        "0".into()
    } else if value < 1e-3 {
        format!("{value:.1e}")
    } else {
        format!("{value:.4}")
    }
}

fn millions(value: u64) -> String {
    format!("{:.2} M", value as f64 * 1e-6)
}

/// Runs every experiment; returns the text of `results.md`.
pub fn run_all(
    context: &Arc<Context>,
    options: &ExperimentOptions,
    progress: &mut dyn FnMut(&str, Progress<'_>),
) -> Result<String> {
    let plan = Plan::new(options.quick);
    create_results(options)?;
    let load = |name: &str| load_scene(options, name);
    let shipped = vec![load("bunny")?, load("teapot")?, load("plane_lights")?];
    let mut md = String::new();
    header(&mut md, context, options);

    // Table 1, Fig. 6 and Figs. 2 / 9 share one run.
    let modes = vec![Mode::Vertex, Mode::Fixed(1), Mode::Fixed(2), Mode::Fixed(4), Mode::Multirate];
    let table_rows = run(context, &shipped, &config(options, modes.clone(), vec![plan.table]), &mut |p| {
        progress("Table 1, Figs. 2, 6, 9", p)
    })?
    .rows;
    write(&options.out.join("table1.csv"), &to_csv(&table_rows))?;
    table1(&mut md, &table_rows, &shipped, plan.table);
    fig6(&mut md, &table_rows, &shipped, plan.table, &options.out)?;
    fig2_9(&mut md, &table_rows, &shipped, plan.table, &options.out)?;

    // The bunny's images for Fig. 2 at a size that keeps the repository small.
    let mut images = config(options, modes, vec![plan.images]);
    images.images = Some(options.out.join("fig2"));
    images.frames = 1;
    images.warmup = 0;
    run(context, &shipped[..1], &images, &mut |p| progress("Fig. 2 images", p))?;
    fig2_images(&mut md, plan.images);

    // The scenes at the paper's scale, every mode at the sweep's resolution.
    let dense = vec![load("bunny_dense")?, load("teapot_dense")?, load("room")?];
    let modes = vec![Mode::Vertex, Mode::Fixed(1), Mode::Fixed(4), Mode::Multirate];
    let dense_rows = run(context, &dense, &config(options, modes, vec![plan.sweep]), &mut |p| {
        progress("the paper's scale", p)
    })?
    .rows;
    write(&options.out.join("paper_scale.csv"), &to_csv(&dense_rows))?;
    paper_scale(&mut md, &dense_rows, plan.sweep);

    let fig10_rows = run(
        context,
        &shipped[..1],
        &config(options, vec![Mode::Multirate], plan.resolutions.clone()),
        &mut |p| progress("Fig. 10", p),
    )?
    .rows;
    write(&options.out.join("fig10.csv"), &to_csv(&fig10_rows))?;
    fig10(&mut md, &fig10_rows, &plan.resolutions, &options.out)?;

    let plane = &shipped[2].scene;
    let grids: Vec<BenchScene> = plan
        .grids
        .iter()
        .map(|&n| BenchScene { name: format!("plane_{n}x{n}"), scene: plane_grid(plane, n) })
        .collect();
    let fig11_rows =
        run(context, &grids, &config(options, vec![Mode::Multirate], vec![plan.sweep]), &mut |p| {
            progress("Fig. 11", p)
        })?
        .rows;
    write(&options.out.join("fig11.csv"), &to_csv(&fig11_rows))?;
    fig11(&mut md, &fig11_rows, plan.sweep, &options.out)?;

    let mut sweep = config(
        options,
        vec![Mode::Vertex, Mode::Fixed(1), Mode::Fixed(2), Mode::Fixed(4), Mode::Multirate],
        vec![plan.sweep],
    );
    sweep.epsilons = plan.epsilons.clone();
    let sweep_rows = run(context, &shipped[..2], &sweep, &mut |p| progress("ε sweep", p))?.rows;
    write(&options.out.join("sweep.csv"), &to_csv(&sweep_rows))?;
    epsilon_sweep(&mut md, &sweep_rows, plan.sweep, &options.out)?;
    let trade = trade_page(context, options, progress)?;
    write(&options.out.with_file_name("trade.md"), &trade)?;
    let _ = writeln!(
        md,
        "## The trade's bounds and the light-count sweep\n\nOn their own page, [trade.md](trade.md) (`--only trade` reruns just those).\n"
    );
    steps(&mut md);
    comparison(&mut md, &table_rows, &fig11_rows, &sweep_rows);
    if context.info.is_lavapipe() {
        reading_lavapipe_times(&mut md);
    }
    Ok(md)
}

fn table1(md: &mut String, rows: &[Row], scenes: &[BenchScene], resolution: (u32, u32)) {
    let (w, h) = resolution;
    let _ = writeln!(md, "## Table 1: summary at {w}×{h}\n");
    let _ = writeln!(
        md,
        "| scene | triangles | n_max | ε | t pixel (ms) | t multirate (ms) | speedup | evaluations | L∞ | L∞ same triangle | pixels > ε | mean L2 | FLIP |"
    );
    let _ = writeln!(
        md,
        "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
    );
    for scene in scenes {
        let (Some(pixel), Some(ours)) =
            (find(rows, &scene.name, "pixel", resolution), find(rows, &scene.name, "multirate", resolution))
        else {
            continue;
        };
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.2} ({:.2}–{:.2}) | {:.2} ({:.2}–{:.2}) | {} | {} | {} | {} | {} | {} | {:.4} |",
            scene.name,
            ours.triangles,
            ours.n_max.unwrap_or_default(),
            ours.epsilon.unwrap_or_default(),
            pixel.gpu_ms.median,
            pixel.gpu_ms.p10,
            pixel.gpu_ms.p90,
            ours.gpu_ms.median,
            ours.gpu_ms.p10,
            ours.gpu_ms.p90,
            percent(ours.speedup),
            percent(ours.evaluation_ratio),
            small(ours.l_inf),
            small(ours.l_inf_same_triangle),
            ours.pixels_over_epsilon.unwrap_or_default(),
            small(ours.mean_l2),
            ours.flip,
        );
    }
    let _ = writeln!(
        md,
        "\nThe paper (Table 1, 3840×2160, NVIDIA GTX 1060 / RTX 2070 Super / RTX 3090): bunny (13,996 triangles, n_max 5, ε 0.075) speedup 227 % / 174 % / 161 %, L∞ 0.073; teapot (15,704, n_max 8, ε 0.075) 233 % / 177 % / 163 %, L∞ 0.013; average L2 < 0.001; 11–23 % of the per-pixel evaluations (Fig. 6).\n"
    );
}

fn paper_scale(md: &mut String, rows: &[Row], resolution: (u32, u32)) {
    let (w, h) = resolution;
    let _ = writeln!(md, "## Scenes at the paper's scale: every mode at {w}×{h}\n");
    let _ = writeln!(
        md,
        "`bunny_dense` and `teapot_dense` are the shipped meshes Loop-subdivided to the paper's triangle counts; `room` composes three dense bunnies, two dense teapots and four 8,192-triangle walls with Lambert, Blinn-Phong and GGX materials (three of them textured), two point lights and a polygonal ceiling panel (`scenes/README.md`).\n"
    );
    let _ = writeln!(
        md,
        "| scene | triangles | mode | t (ms) | pre-pass (ms) | speedup | evaluations | L∞ same triangle | pixels > ε | mean L2 | FLIP |"
    );
    let _ = writeln!(md, "| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for row in rows.iter().filter(|r| (r.width, r.height) == resolution) {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2} ({:.2}–{:.2}) | {} | {} | {} | {} | {} | {} | {:.4} |",
            row.scene,
            row.triangles,
            row.mode,
            row.gpu_ms.median,
            row.gpu_ms.p10,
            row.gpu_ms.p90,
            row.pre_pass_ms.map_or_else(|| "–".to_string(), |t| format!("{:.2}", t.median)),
            percent(row.speedup),
            percent(row.evaluation_ratio),
            small(row.l_inf_same_triangle),
            row.pixels_over_epsilon.map_or_else(|| "–".to_string(), |n| n.to_string()),
            small(row.mean_l2),
            row.flip,
        );
    }
    let _ = writeln!(md);
}

fn fig6(
    md: &mut String,
    rows: &[Row],
    scenes: &[BenchScene],
    resolution: (u32, u32),
    out: &Path,
) -> Result<()> {
    let modes = ["pixel", "vertex", "fixed:1", "fixed:2", "fixed:4", "multirate"];
    let categories: Vec<String> = scenes.iter().map(|s| s.name.clone()).collect();
    let series: Vec<(String, Vec<f64>)> = modes
        .iter()
        .map(|&mode| {
            let values = scenes
                .iter()
                .map(|s| {
                    find(rows, &s.name, mode, resolution)
                        .map_or(f64::NAN, |r| r.evaluations.total() as f64 * 1e-6)
                })
                .collect();
            (mode.to_string(), values)
        })
        .collect();
    let (w, h) = resolution;
    plot::bars(
        &format!("Shading evaluations per frame at {w}×{h}"),
        "evaluations (millions)",
        &categories,
        &series,
        &out.join("fig6_evaluations.svg"),
    )?;
    let _ = writeln!(md, "## Fig. 6: shading evaluations per mode ({w}×{h})\n");
    let _ = writeln!(md, "![evaluations per mode](results/fig6_evaluations.svg)\n");
    let _ = writeln!(md, "| scene | {} |", modes.join(" | "));
    let _ = writeln!(md, "| --- |{}", " ---: |".repeat(modes.len()));
    for scene in scenes {
        let cells: Vec<String> = modes
            .iter()
            .map(|&mode| {
                find(rows, &scene.name, mode, resolution).map_or("–".into(), |r| {
                    format!("{} ({})", millions(r.evaluations.total()), percent(r.evaluation_ratio))
                })
            })
            .collect();
        let _ = writeln!(md, "| {} | {} |", scene.name, cells.join(" | "));
    }
    let _ = writeln!(
        md,
        "\nCounted by the counting variant: vertex-shader runs (`vertex`), evaluation-shader runs (tessellated modes) and fragments shaded per pixel (`pixel`, multirate's fallback). The estimator's own work (in the compute pre-pass, or the control stage) is not a shading evaluation and is not counted.\n"
    );
    Ok(())
}

fn fig2_9(
    md: &mut String,
    rows: &[Row],
    scenes: &[BenchScene],
    resolution: (u32, u32),
    out: &Path,
) -> Result<()> {
    let (w, h) = resolution;
    let _ = writeln!(md, "## Figs. 2 and 9: fixed levels against multirate ({w}×{h})\n");
    let _ = writeln!(
        md,
        "| scene | mode | GPU ms | speedup | evaluations | L∞ | L∞ same triangle | mean L2 | FLIP |"
    );
    let _ = writeln!(md, "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for scene in scenes {
        for mode in ["vertex", "fixed:1", "fixed:2", "fixed:4", "multirate"] {
            if let Some(r) = find(rows, &scene.name, mode, resolution) {
                let _ = writeln!(
                    md,
                    "| {} | {} | {:.2} | {} | {} | {} | {} | {} | {:.4} |",
                    scene.name,
                    plot::row_label(r).replace("ε=", "multirate ε="),
                    r.gpu_ms.median,
                    percent(r.speedup),
                    percent(r.evaluation_ratio),
                    small(r.l_inf),
                    small(r.l_inf_same_triangle),
                    small(r.mean_l2),
                    r.flip
                );
            }
        }
    }
    let bunny: Vec<Row> = rows.iter().filter(|r| r.scene == scenes[0].name).cloned().collect();
    plot::time_against_error(
        &bunny,
        "L∞ same triangle error",
        |r| r.l_inf_same_triangle,
        &out.join("fig9_time_vs_linf.svg"),
    )?;
    plot::time_against_error(&bunny, "mean FLIP", |r| r.flip, &out.join("fig9_time_vs_flip.svg"))?;
    let _ = writeln!(md, "\n![time against L∞](results/fig9_time_vs_linf.svg)\n");
    let _ = writeln!(md, "![time against FLIP](results/fig9_time_vs_flip.svg)\n");
    Ok(())
}

fn fig2_images(md: &mut String, resolution: (u32, u32)) {
    let (w, h) = resolution;
    let stem = |mode: &str| format!("results/fig2/bunny_{w}x{h}_{mode}");
    let _ = writeln!(md, "Fig. 2 images (bunny, {w}×{h}; error ×30, linear radiance, white = 1/30):\n");
    let _ = writeln!(md, "| | render | error ×30 |\n| --- | --- | --- |");
    for (label, mode) in
        [("pixel", "pixel"), ("fixed:1", "fixed1"), ("fixed:2", "fixed2"), ("fixed:4", "fixed4")]
    {
        let _ = writeln!(md, "| {label} | ![]({}.png) | ![]({}_error_x30.png) |", stem(mode), stem(mode));
    }
    let multirate = stem("multirate_eps0.075_nmax16");
    let _ = writeln!(md, "| multirate | ![]({multirate}.png) | ![]({multirate}_error_x30.png) |");
    let _ = writeln!(
        md,
        "\nmultirate's tessellation levels (blue 1 → red n_max, magenta per-pixel fallback) and the fallback mask:\n\n![]({multirate}_levels.png) ![]({multirate}_fallback.png)\n"
    );
}

fn fig10(md: &mut String, rows: &[Row], resolutions: &[(u32, u32)], out: &Path) -> Result<()> {
    let _ = writeln!(md, "## Fig. 10: resolution (bunny)\n");
    let _ = writeln!(
        md,
        "| resolution | mode | GPU ms | speedup | VS invocations | TCS patches | TES invocations | FS invocations | evaluations |"
    );
    let _ = writeln!(md, "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    let mut series = vec![
        plot::Series { name: "pixel".into(), points: Vec::new(), line: true },
        plot::Series { name: "multirate".into(), points: Vec::new(), line: true },
    ];
    for &(w, h) in resolutions {
        for (index, mode) in ["pixel", "multirate"].iter().enumerate() {
            let Some(r) = find(rows, "bunny", mode, (w, h)) else { continue };
            let stat = |f: fn(&crate::vk::timing::PipelineStatistics) -> u64| {
                r.statistics.as_ref().map_or("NA".into(), |s| f(s).to_string())
            };
            let _ = writeln!(
                md,
                "| {w}×{h} | {mode} | {:.2} | {} | {} | {} | {} | {} | {} |",
                r.gpu_ms.median,
                percent(r.speedup),
                stat(|s| s.vertex_shader_invocations),
                stat(|s| s.tessellation_control_patches),
                stat(|s| s.tessellation_evaluation_invocations),
                stat(|s| s.fragment_shader_invocations),
                r.evaluations.total()
            );
            series[index].points.push(plot::Point {
                x: f64::from(w * h) * 1e-6,
                y: r.gpu_ms.median,
                label: Some(format!("{w}×{h}")),
            });
        }
    }
    plot::draw(
        &plot::Chart {
            title: "Bunny: GPU time against resolution",
            x_label: "megapixels",
            y_label: "GPU ms per frame (median)",
            series,
            pareto: false,
            x_log: false,
        },
        &out.join("fig10_resolution.svg"),
    )?;
    let _ = writeln!(md, "\n![time against resolution](results/fig10_resolution.svg)\n");
    let _ = writeln!(
        md,
        "The paper breaks the frame into shader-stage cycles with Nsight; timestamps cannot split one pass by stage, so the table gives each stage's invocations (pipeline statistics; lavapipe counts fragment invocations per 2×2 quad, helpers included) beside the pass time. The vertex and control-stage work does not change with resolution; only the fallback fragments do.\n"
    );
    Ok(())
}

fn fig11(md: &mut String, rows: &[Row], resolution: (u32, u32), out: &Path) -> Result<()> {
    let (w, h) = resolution;
    let _ = writeln!(md, "## Fig. 11: triangle count (plane, three sharp lights, {w}×{h})\n");
    let _ = writeln!(md, "| grid | triangles | t pixel (ms) | t multirate (ms) | speedup | evaluations | fallback pixels | L∞ same triangle |");
    let _ = writeln!(md, "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    let mut points = Vec::new();
    for ours in rows.iter().filter(|r| r.mode == "multirate") {
        let Some(pixel) = find(rows, &ours.scene, "pixel", (ours.width, ours.height)) else { continue };
        let _ = writeln!(
            md,
            "| {} | {} | {:.2} | {:.2} | {} | {} | {} | {} |",
            ours.scene,
            ours.triangles,
            pixel.gpu_ms.median,
            ours.gpu_ms.median,
            percent(ours.speedup),
            percent(ours.evaluation_ratio),
            ours.fallback_fraction.map_or("NA".into(), percent),
            small(ours.l_inf_same_triangle)
        );
        points.push(plot::Point {
            x: ours.triangles as f64,
            y: ours.speedup * 100.0,
            label: Some(ours.triangles.to_string()),
        });
    }
    plot::draw(
        &plot::Chart {
            title: "Plane with three sharp lights: speedup against triangle count",
            x_label: "triangles (log scale)",
            y_label: "speedup over pixel (%)",
            series: vec![plot::Series { name: "multirate".into(), points, line: true }],
            pareto: false,
            x_log: true,
        },
        &out.join("fig11_triangles.svg"),
    )?;
    let _ = writeln!(md, "\n![speedup against triangle count](results/fig11_triangles.svg)\n");
    Ok(())
}

fn epsilon_sweep(md: &mut String, rows: &[Row], resolution: (u32, u32), out: &Path) -> Result<()> {
    let (w, h) = resolution;
    let _ = writeln!(md, "## The trade: ε sweep ({w}×{h})\n");
    plot::time_against_error(
        rows,
        "L∞ same triangle error",
        |r| r.l_inf_same_triangle,
        &out.join("sweep_time_vs_linf.svg"),
    )?;
    plot::time_against_error(rows, "mean FLIP", |r| r.flip, &out.join("sweep_time_vs_flip.svg"))?;
    let series = plot::group(
        rows.iter().filter(|r| r.mode == "multirate").map(|r| {
            let label = r.epsilon.map(|e| format!("ε={e}"));
            (r.scene.clone(), plot::Point { x: r.l_inf_same_triangle, y: r.evaluation_ratio * 100.0, label })
        }),
        true,
    );
    plot::draw(
        &plot::Chart {
            title: "multirate: shading evaluations against error",
            x_label: "L∞ same triangle error",
            y_label: "evaluations (% of pixel)",
            series,
            pareto: false,
            x_log: false,
        },
        &out.join("sweep_evaluations_vs_linf.svg"),
    )?;
    let _ = writeln!(md, "![time against L∞](results/sweep_time_vs_linf.svg)\n");
    let _ = writeln!(md, "![evaluations against L∞](results/sweep_evaluations_vs_linf.svg)\n");
    let _ = writeln!(md, "![time against FLIP](results/sweep_time_vs_flip.svg)\n");
    let _ = writeln!(md, "| scene | mode | ε | GPU ms | speedup | evaluations | fallback pixels | L∞ same triangle | pixels > ε | mean L2 | FLIP |");
    let _ = writeln!(md, "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2} | {} | {} | {} | {} | {} | {} | {:.4} |",
            r.scene,
            r.mode,
            r.epsilon.map_or("–".into(), |e| e.to_string()),
            r.gpu_ms.median,
            percent(r.speedup),
            percent(r.evaluation_ratio),
            r.fallback_fraction.map_or("–".into(), percent),
            small(r.l_inf_same_triangle),
            r.pixels_over_epsilon.map_or("–".into(), |p| p.to_string()),
            small(r.mean_l2),
            r.flip
        );
    }
    let _ = writeln!(md);
    Ok(())
}

fn comparison(md: &mut String, table: &[Row], grids: &[Row], sweep: &[Row]) {
    let multirate =
        |rows: &'_ [Row]| rows.iter().filter(|r| r.mode == "multirate").cloned().collect::<Vec<Row>>();
    let speedups: Vec<String> =
        multirate(table).iter().map(|r| format!("{} {}", r.scene, percent(r.speedup))).collect();
    let all: Vec<Row> = [multirate(table), multirate(grids), multirate(sweep)].concat();
    let fastest = all.iter().map(|r| r.speedup).fold(0.0, f64::max);
    let best_grid = multirate(grids)
        .iter()
        .max_by(|a, b| a.speedup.total_cmp(&b.speedup))
        .map_or("–".into(), |r| format!("{} triangles ({})", r.triangles, percent(r.speedup)));
    let within =
        all.iter().filter(|r| r.l_inf_same_triangle <= f64::from(r.epsilon.unwrap_or_default())).count();
    let over: usize = all.iter().filter_map(|r| r.pixels_over_epsilon).sum();
    let other: usize = all.iter().map(|r| r.other_triangle_pixels).sum();
    let pixels: u64 = all.iter().map(|r| u64::from(r.width) * u64::from(r.height)).sum();
    let _ = writeln!(md, "## Compared with the paper\n");
    let verdict = if fastest < 1.0 {
        format!(
            "multirate is slower than per-pixel shading in every configuration measured here (best: {})",
            percent(fastest)
        )
    } else {
        format!("the best multirate configuration reaches a speedup of {}", percent(fastest))
    };
    let _ = writeln!(
        md,
        "- Time: {verdict}; Table 1 speedups: {}. The paper's 134–283 % are measured on GPUs, where the estimator runs on shader cores in parallel with the rest of the pipeline and is small next to the per-pixel shading it saves. A CPU rasteriser such as lavapipe runs every stage on the same two cores and runs its vertex and tessellation stages (sub-vertex shading included) on one of them, while fragments and compute use both; it also runs both sides of every branch under a mask. The estimator pre-pass (once per visible triangle) and the sub-vertex shading cost per triangle and per sub-vertex, the per-pixel shading they save per pixel, so multirate gains as the resolution grows (Fig. 10) and loses on meshes of many small triangles (Fig. 11). What each optimisation gained, step by step, and what it taught about lavapipe, is in [notebook/speedups.md](notebook/speedups.md).",
        speedups.join(", ")
    );
    let _ = writeln!(
        md,
        "- Evaluations: counts do not depend on the device and compare directly with Fig. 6 (11–23 % in the paper). Our meshes are coarser than the paper's (bunny 3,674 against 13,996 triangles, teapot 992 against 15,704), so triangles need higher levels, which raises the fraction. The terminator is crossed by a bound (Relaxed, the default) instead of per-pixel shading, which the paper's handling (`--discontinuity conservative`) needs on every triangle the terminator may cross."
    );
    let _ = writeln!(md, "- Fig. 11: the best speedup on the plane is at {best_grid}; the paper finds its optimum near 1,800 triangles on a GPU.");
    let _ = writeln!(
        md,
        "- Error: the L∞ over pixels that show the same triangle as in `pixel` mode is ≤ ε in {within} of {} multirate rows; over all of them, {over} such pixels exceed ε. {other} of {pixels} pixels show another triangle than in `pixel` mode and are counted apart: they lie on silhouettes, where a sub-triangle's rounded edge vertex moves a pixel centre across the edge, and on curves where two surfaces meet (the teapot's spout and body), where a tessellated triangle's interpolated depth breaks a depth tie otherwise. The mean L2 is of the paper's order (< 0.001).\n",
        all.len()
    );
}

/// The five steps that made multirate faster than per-pixel shading, each as measured against
/// the build before it when it landed (docs/notebook/speedups.md holds the commands and all later steps).
fn steps(md: &mut String) {
    let intro = "Measured when each step landed, its build against the one before it in one run on this machine kind (lavapipe, bunny at 1920×1080, ε 0.075, ms; not re-measured by the command above). [notebook/speedups.md](notebook/speedups.md) has the commands, the other scenes and the later steps, each against the one before.";
    text_section(md, "What each step gained", Some(intro), &STEPS, "");
}

/// A section of fixed text: its heading, an optional paragraph, and one line per item, each
/// after `marker`.
fn text_section(md: &mut String, heading: &str, intro: Option<&str>, items: &[&str], marker: &str) {
    let _ = writeln!(md, "## {heading}\n");
    if let Some(intro) = intro {
        let _ = writeln!(md, "{intro}\n");
    }
    for item in items {
        let _ = writeln!(md, "{marker}{item}");
    }
    let _ = writeln!(md);
}

const STEPS: [&str; 5] = [
    "1. **One shader variant per feature set** (the scene's material kind, polygon lights, textures and counting compiled in or out, not switched off by specialization constants): `pixel` 431.0 → 24.9 ms, `multirate` 938.1 → 285.5 ms.",
    "2. **Each triangle's level computed once**: the control stage's four estimates spread over four invocations (`--estimator tcs`) 285.5 → 106.0 ms; a compute pre-pass estimating each triangle once (`--estimator compute`, the default) 48.4 ms.",
    "3. **Culling before the estimate** (frustum, and back faces of one-sided meshes; `pixel` culls the same): `pixel` 37.7 → 19.1 ms, `multirate` 48.4 → 52.5 ms, 2,139 of 3,674 patches culled.",
    "4. **The ¼ terminator rule, Relaxed by default**: evaluations 33.8 % → 2.9 % of `pixel`'s, time 45.3 → 46.0 ms (Conservative against Relaxed).",
    "5. **Level-1 triangles drawn without tessellation**: the plane's forward part 24.3 → 17.1 ms, the bunny's at ε 1000 (every patch flat) 11.5 → 10.1 ms; at ε 0.075 the bunny moved within the noise (16.1 → 17.3 ms).",
];

/// What a reader should and should not conclude from times measured on lavapipe.
fn reading_lavapipe_times(md: &mut String) {
    text_section(md, "Reading times measured on lavapipe", None, &READING_LAVAPIPE_TIMES, "- ");
}

const READING_LAVAPIPE_TIMES: [&str; 4] = [
    "What holds on any device: shading evaluations (counted, deterministic), culled patches, and the image errors (L∞, pixels over ε, mean L2, FLIP). A GPU rasterises with other sub-pixel precision and breaks depth ties otherwise, so silhouette and tie pixels may differ slightly; nothing else in these columns depends on the device.",
    "What does not transfer: milliseconds, and the ratios between modes. Lavapipe runs every stage on the 2 CPU cores of this machine, its vertex and tessellation stages (the fixed-function tessellator included) on one of them, both sides of every branch under a mask, and pays a fixed cost per frame for clearing and resolving the float targets (what an empty frame costs), which every row here includes. On a GPU the tessellator is hardware, shading is what costs, and the speedup of multirate tracks its share of evaluations far more closely than here.",
    "What can be read from them: a comparison within one run (an optimisation against the step before it, side by side, as in notebook/speedups.md), how a mode scales with resolution and triangle count, and whether a feature slows scenes that do not use it. Differences under about 30 % between runs are lavapipe's noise on two shared cores, not findings.",
    "What cannot: that multirate is faster or slower than per-pixel shading on a GPU, or by how much. That needs `experiments` and `bench` run on a GPU, with the device named beside every figure.",
];

#[cfg(test)]
mod tests;
