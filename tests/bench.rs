//! `multirate bench` end to end on a small scene (lavapipe, validation layer on): every CSV
//! field filled and consistent, the JSON rows, the plots, the images and a Chrome trace with
//! one event per measured frame; multirate both estimating every triangle and with the cost
//! model, whose frame guard decides in the warm-up. `multirate calibrate` end to end: every
//! cost measured, stored under the device's key and read back.

mod common;

use common::repo_path;
use std::collections::HashMap;
use std::path::Path;

const FRAMES: usize = 3;

/// Runs `multirate --validate <args>` without a display and checks that it succeeds without a
/// validation message; returns what it printed.
fn run_validated(args: &[&str]) -> String {
    let output = common::multirate_command()
        .arg("--validate")
        .args(args)
        .env_remove("DISPLAY")
        .output()
        .expect("run multirate");
    let (stdout, stderr) = (String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "multirate {args:?} failed:\n{stdout}\n{stderr}");
    assert!(!stderr.contains("vulkan:"), "validation messages:\n{stderr}");
    stdout.into_owned()
}

#[test]
fn bench_writes_complete_rows_plots_images_and_a_capture() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench");
    let _ = std::fs::remove_dir_all(&out);
    let capture = out.join("capture.json");
    let scene = repo_path("scenes/test/lambert_directional.toml");
    let frames = FRAMES.to_string();
    let stdout = run_validated(
        &[
            &["bench", "--scene", scene.to_str().unwrap()][..],
            &["--modes", "pixel,vertex,fixed:2,multirate", "--epsilon", "0.05,0.2", "--nmax", "8"],
            &["--min-estimated-area", "0,auto"],
            &["--resolution", "256x192", "--frames", &frames, "--warmup", "1", "--images"],
            &["--out", out.to_str().unwrap(), "--capture", capture.to_str().unwrap(), "--draw-parts"],
            &["--pre-pass-steps"],
        ]
        .concat(),
    );
    assert!(stdout.contains("the frame's parts"), "{stdout}");

    // CSV: pixel, vertex, fixed:2 and multirate at two ε: five rows, every field filled.
    let csv = std::fs::read_to_string(out.join("bench.csv")).expect("bench.csv");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let rows: Vec<HashMap<&str, &str>> = lines
        .map(|line| {
            // Device strings may be quoted and hold commas; they come last, as one field here.
            let fields: Vec<&str> = line.splitn(header.len() - 1, ',').collect();
            header.iter().copied().zip(fields).collect()
        })
        .collect();
    // pixel, vertex, fixed:2, then per ε multirate estimating every triangle and with the model.
    assert_eq!(rows.len(), 7, "{csv}");
    for row in &rows {
        assert_eq!(row.len(), header.len() - 1, "{row:?}");
        for (key, value) in row {
            assert!(!value.is_empty(), "{key} is empty in {row:?}");
        }
    }
    let number = |row: &HashMap<&str, &str>, key: &str| -> f64 {
        row[key].parse().unwrap_or_else(|_| panic!("{key} = {:?} is not a number", row[key]))
    };
    let modes: Vec<&str> = rows.iter().map(|r| r["mode"]).collect();
    assert_eq!(modes, ["pixel", "vertex", "fixed:2", "multirate", "multirate", "multirate", "multirate"]);
    let pixel = &rows[0];
    assert_eq!(pixel["epsilon"], "NA");
    assert_eq!(number(pixel, "l_inf"), 0.0);
    assert_eq!(number(pixel, "evaluation_ratio"), 1.0);
    assert_eq!(number(pixel, "evaluations"), number(pixel, "fragment_evaluations"));
    for row in &rows {
        for key in ["gpu_ms_median", "gpu_ms_p10", "gpu_ms_p90", "speedup"] {
            assert!(number(row, key) > 0.0 && number(row, key).is_finite(), "{key} in {row:?}");
        }
        assert!(number(row, "gpu_ms_p10") <= number(row, "gpu_ms_median"));
        assert!(number(row, "gpu_ms_median") <= number(row, "gpu_ms_p90"));
        let parts = ["vertex_evaluations", "subvertex_evaluations", "fragment_evaluations"];
        let sum: f64 = parts.iter().map(|k| number(row, k)).sum();
        assert_eq!(sum, number(row, "evaluations"), "{row:?}");
        assert!(number(row, "fs_invocations") > 0.0, "{row:?}");
    }
    // `--draw-parts`: every part timed where a frame draws it, within the frame. The modes
    // without a pre-pass draw their mesh whole; multirate without the frame guard (estimating
    // every triangle) draws the pre-pass's lists and nothing whole.
    let parts = multirate::render::DrawPart::ALL.map(|part| format!("draw_{}_ms_median", part.name()));
    let lists = ["draw_flat_ms_median", "draw_tessellated_ms_median"];
    for row in &rows {
        let sum: f64 = parts.iter().map(|part| number(row, part)).sum();
        assert!(parts.iter().all(|part| number(row, part) >= 0.0), "{row:?}");
        assert!(sum <= number(row, "gpu_ms_p90"), "the parts lie within the frame: {row:?}");
        let listed: f64 = lists.iter().map(|list| number(row, list)).sum();
        if row["mode"] != "multirate" {
            assert!(number(row, "draw_whole_ms_median") > 0.0 && listed == 0.0, "{row:?}");
        } else if row["frames_drawn_as_pixel"] == "NA" {
            assert!(number(row, "draw_whole_ms_median") == 0.0 && listed > 0.0, "{row:?}");
        }
    }
    assert!(number(&rows[1], "vertex_evaluations") > 0.0);
    assert!(number(&rows[2], "subvertex_evaluations") > 0.0);
    let steps = multirate::render::PrePassStep::ALL.map(|step| format!("{}_ms_median", step.name()));
    for row in &rows[..3] {
        assert_eq!(row["frames_drawn_as_pixel"], "NA", "{row:?}");
        assert_eq!(row["pre_pass_ms_median"], "NA", "{row:?}");
        for step in &steps {
            assert_eq!(row[step.as_str()], "NA", "{row:?}");
        }
    }
    let mut pre_passes_expected = 0;
    // Per ε, estimating every triangle (area 0), then with the cost model, whose area may be 0
    // too where an estimate costs less than the per-pixel path's triangle.
    for (k, row) in rows[3..].iter().enumerate() {
        let modelled = k % 2 == 1;
        assert!(number(row, "epsilon") == 0.05 || number(row, "epsilon") == 0.2, "{row:?}");
        assert_eq!(row["estimator"], "compute", "the default placement");
        assert_eq!(number(row, "n_max"), 8.0);
        let fraction = number(row, "fallback_fraction");
        assert!((0.0..=1.0).contains(&fraction), "{row:?}");
        assert!(number(row, "l_inf").is_finite() && number(row, "flip") >= 0.0, "{row:?}");
        // At this size the triangles are large enough to estimate: no mesh is drawn whole as
        // `pixel` draws it, so a frame the guard draws the multirate way runs the pre-pass.
        assert!(fraction < 1.0, "{row:?}");
        if modelled {
            // The cost model's frame guard decides in the warm-up (its first frames each way);
            // frames drawn the multirate way time a pre-pass, the others none.
            let as_pixel = number(row, "frames_drawn_as_pixel");
            assert!((0.0..=FRAMES as f64).contains(&as_pixel), "{row:?}");
            assert_eq!(row["pre_pass_ms_median"] == "NA", as_pixel == FRAMES as f64, "{row:?}");
            pre_passes_expected += FRAMES - as_pixel as usize;
            continue;
        }
        assert_eq!(number(row, "min_estimated_area"), 0.0, "{row:?}");
        assert_eq!(row["frames_drawn_as_pixel"], "NA", "{row:?}");
        pre_passes_expected += FRAMES;
        let pre_pass = number(row, "pre_pass_ms_median");
        assert!(pre_pass > 0.0 && pre_pass <= number(row, "gpu_ms_p90"), "{row:?}");
        // The steps run back to back within the pre-pass: their medians add up to about its.
        let step_sum: f64 = steps.iter().map(|step| number(row, step)).sum();
        assert!(steps.iter().all(|step| number(row, step) >= 0.0), "{row:?}");
        assert!(step_sum <= 1.5 * pre_pass && number(row, "estimate_ms_median") > 0.0, "{row:?}");
    }

    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("bench.json")).expect("bench.json"))
            .expect("JSON");
    assert_eq!(json.as_array().map(Vec::len), Some(7));

    for plot in ["time_vs_linf.svg", "time_vs_flip.svg"] {
        let svg = std::fs::read_to_string(out.join(plot)).expect("plot");
        assert!(svg.starts_with("<svg") && svg.contains("Pareto front"), "{plot}");
    }
    let images = out.join("images");
    for name in ["lambert_directional_256x192_pixel.png", "lambert_directional_256x192_fixed2_error_x30.png"]
    {
        assert!(images.join(name).is_file(), "{name}");
    }
    // The rows estimating every triangle have images of their own.
    for area in ["", "_area0"] {
        for suffix in ["", "_error_x30", "_levels", "_fallback"] {
            let name = format!("lambert_directional_256x192_multirate_eps0.05_nmax8{area}{suffix}.png");
            assert!(images.join(&name).is_file(), "{name}");
        }
    }

    assert_capture(&capture, rows.len(), pre_passes_expected);
}

/// `--without-shadows` on the shadow scene: both twins measured against their own `pixel`, and
/// `shadows.csv` with the shadow pass's time and every triangle in one class per light.
#[test]
fn bench_measures_a_shadowed_scene_with_and_without_its_shadows() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench_shadows");
    let _ = std::fs::remove_dir_all(&out);
    let scene = repo_path("scenes/shadows.toml");
    let stdout = run_validated(
        &[
            &["bench", "--scene", scene.to_str().unwrap(), "--without-shadows"][..],
            &["--modes", "multirate", "--resolution", "160x120", "--frames", "1", "--warmup", "0"],
            &["--out", out.to_str().unwrap()],
        ]
        .concat(),
    );
    let csv = std::fs::read_to_string(out.join("bench.csv")).expect("bench.csv");
    let configurations: Vec<(&str, &str)> = csv
        .lines()
        .skip(1)
        .map(|line| {
            let fields: Vec<&str> = line.split(',').collect();
            (fields[0], fields[2])
        })
        .collect();
    assert_eq!(
        configurations,
        [
            ("shadows", "pixel"),
            ("shadows", "multirate"),
            ("shadows_without_shadows", "pixel"),
            ("shadows_without_shadows", "multirate")
        ],
        "{csv}"
    );
    let shadows = std::fs::read_to_string(out.join("shadows.csv")).expect("shadows.csv");
    let rows: Vec<Vec<&str>> = shadows.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2, "one row per shadow-casting light:\n{shadows}");
    for row in &rows {
        assert_eq!(row[0], "shadows", "{row:?}");
        let ms: f64 = row[2].parse().expect("the shadow pass's milliseconds");
        assert!(ms > 0.0 && ms.is_finite(), "{row:?}");
        let classes: usize = row[3..6].iter().map(|n| n.parse::<usize>().expect("a count")).sum();
        // The bunny's 3,674 triangles and the ground's 8,192, each in one class.
        assert_eq!(classes, 3674 + 8192, "{row:?}");
    }
    assert!(stdout.contains("shadow pass"), "{stdout}");
}

/// `bench --path`: every configuration timed along the scene's camera path, frame by frame: the
/// rows hold the path's frames, `path.csv` each frame's time and pre-pass time (the estimator
/// runs in every multirate frame: the eye leaves its ball each time), `path.svg` the plot, and
/// `stability.csv` multirate's error from frame to frame; `--stability-only` the same walk alone.
#[test]
fn bench_times_every_configuration_along_a_camera_path() {
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("bench_path");
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).expect("the output folder");
    // The test sphere with a path of a quarter of a second: the eye swings 0.3 to the side.
    let sphere = repo_path("scenes/test/lambert_directional.toml");
    let icosphere = repo_path("scenes/test/icosphere.obj").display().to_string().replace('\\', "/");
    let text = std::fs::read_to_string(&sphere)
        .expect("the test scene")
        .replace("obj = \"icosphere.obj\"", &format!("obj = {icosphere:?}"))
        + "[[path]]\ntime = 0\neye = [0.0, 0.5, 4.0]\ntarget = [0, 0, 0]\n"
        + "[[path]]\ntime = 0.25\neye = [0.3, 0.55, 3.9]\ntarget = [0, 0, 0]\n";
    let scene = out.join("sphere_path.toml");
    std::fs::write(&scene, text).expect("the scene with a path");
    let stdout = run_validated(
        &[
            &["bench", "--scene", scene.to_str().unwrap(), "--modes", "pixel,multirate"][..],
            &["--min-estimated-area", "0", "--resolution", "96x64", "--warmup", "1"],
            &["--path", "scene", "--fps", "12", "--out", out.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(stdout.contains("sphere_path"), "{stdout}");
    let csv = std::fs::read_to_string(out.join("path.csv")).expect("path.csv");
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    // A quarter of a second at 12 frames a second: frames at 0, 1/12, 2/12 and 3/12 s.
    assert_eq!(rows.len(), 2 * 4, "four frames of pixel and of multirate:\n{csv}");
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row[2], (k % 4).to_string(), "{row:?}");
        let time: f32 = row[3].parse().expect("seconds");
        assert!((time - (k % 4) as f32 / 12.0).abs() < 1e-3, "{row:?}");
        let (gpu_ms, pre_pass_ms): (f64, f64) = (row[4].parse().expect("ms"), row[5].parse().expect("ms"));
        assert!(gpu_ms > 0.0 && gpu_ms.is_finite(), "{row:?}");
        let multirate = row[1].starts_with("multirate") || row[1].contains("ε");
        assert_eq!(pre_pass_ms > 0.0, multirate, "the pre-pass runs in multirate frames only: {row:?}");
    }
    let svg = std::fs::read_to_string(out.join("path.svg")).expect("path.svg");
    assert!(svg.contains("<svg") && svg.contains("GPU time per frame"), "the plot");
    let bench = std::fs::read_to_string(out.join("bench.csv")).expect("bench.csv");
    let header: Vec<&str> = bench.lines().next().expect("header").split(',').collect();
    let frames = header.iter().position(|&c| c == "frames").expect("a frames column");
    for line in bench.lines().skip(1) {
        assert_eq!(line.split(',').nth(frames), Some("4"), "{line}");
    }
    // Multirate's stability, frame against frame: three steps, each comparing pixels carried
    // back through their surface, with the share of visible triangles whose level changed.
    assert!(stdout.contains("temporal stability along the path"), "{stdout}");
    let stability = std::fs::read_to_string(out.join("stability.csv")).expect("stability.csv");
    let steps: Vec<Vec<&str>> = stability.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(steps.len(), 3, "{stability}");
    for (k, step) in steps.iter().enumerate() {
        assert!(step[0].contains("multirate"), "{step:?}");
        assert_eq!(step[1], (k + 1).to_string(), "{step:?}");
        let compared: usize = step[2].parse().expect("a count");
        assert!(compared > 100, "pixels carried back: {step:?}");
        let (largest, p99): (f32, f32) = (step[5].parse().expect("largest"), step[6].parse().expect("p99"));
        assert!(largest.is_finite() && p99 <= largest, "{step:?}");
        let (jumps, pattern_jumps): (usize, usize) =
            (step[8].parse().expect("jumps"), step[9].parse().expect("ditto"));
        assert!(pattern_jumps <= jumps, "{step:?}");
        let levels: f64 = step[12].parse().expect("multirate's level changes");
        // Every pixel compared is of the same triangle in both frames, within ε of the
        // reference in each: it cannot change by more than 2ε.
        assert!(largest <= 2.0 * 0.075, "{step:?}");
        assert_eq!(step[13], "0", "multirate's pixels of the same triangle over ε: {step:?}");
        assert!((0.0..=1.0).contains(&levels), "{step:?}");
    }
    // `--stability-only`: the same walk, to the bit, without the images, counts and timing.
    let alone = out.join("stability_only");
    let stdout = run_validated(
        &[
            &["bench", "--scene", scene.to_str().unwrap(), "--modes", "pixel,multirate"][..],
            &["--min-estimated-area", "0", "--resolution", "96x64", "--stability-only"],
            &["--path", "scene", "--fps", "12", "--out", alone.to_str().unwrap()],
        ]
        .concat(),
    );
    assert!(stdout.contains("temporal stability along the path"), "{stdout}");
    let walked_alone = std::fs::read_to_string(alone.join("stability.csv")).expect("stability.csv alone");
    assert_eq!(walked_alone, stability, "the walk alone and after the timing");
    for timed in ["bench.csv", "path.csv", "path.svg"] {
        assert!(!alone.join(timed).exists(), "{timed} written without timing");
    }
}

#[test]
fn calibrate_stores_every_cost_under_the_device_and_its_compiler_setting() {
    use multirate::render::cost_model::{calibration_key, CostModel, LavapipeCompiler};
    let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("calibrate");
    let _ = std::fs::remove_dir_all(&out);
    let store = out.join("cost_model.toml");
    let scene = repo_path("scenes/test/lambert_directional.toml");
    let stdout = run_validated(
        &[
            &["calibrate", "--scene", scene.to_str().unwrap(), "--frames", "1"][..],
            &["--store", store.to_str().unwrap()],
        ]
        .concat(),
    );
    // The key it stored under: the device's name, and on lavapipe with `nopt` that setting.
    let key = stdout
        .lines()
        .find_map(|line| line.strip_prefix("stored for \"")?.split('"').next())
        .unwrap_or_else(|| panic!("no store line:\n{stdout}"));
    let device = key.strip_suffix(", GALLIVM_PERF=nopt").unwrap_or(key);
    assert_eq!(calibration_key(device, LavapipeCompiler::current()), key);
    let printed = [
        "1 lights: estimate",
        "8 lights: estimate",
        "per visible triangle",
        "a sub-vertex",
        "tessellating pays",
    ];
    for printed in printed {
        assert!(stdout.contains(printed), "{printed:?} not printed:\n{stdout}");
    }
    let text = std::fs::read_to_string(&store).expect("the store is written");
    assert!(text.contains(&format!("[devices.\"{key}\"]")), "{key} not in\n{text}");
    let model = CostModel::from_store(Some(&store), device, LavapipeCompiler::current());
    assert!(model.source.starts_with("calibrated"), "{}", model.source);
    let c = &model.calibration;
    let costs = [
        Some(c.estimate),
        Some(c.pixel),
        Some(c.fallback),
        c.fallback_triangle,
        c.tessellated_patch,
        c.sub_vertex,
    ];
    for (k, cost) in costs.iter().enumerate() {
        let cost = cost.unwrap_or_else(|| panic!("cost {k} not stored:\n{text}"));
        assert!(cost.fixed_ns.is_finite() && cost.per_light_ns.is_finite(), "cost {k}: {cost:?}");
    }
    let area = model.tessellation_break_even(4, 1).expect("tessellation costs");
    assert!(area.is_finite() && area >= 0.0, "{area}");
}

/// The capture: a track per row, named, one complete event per measured frame, and
/// `pre_passes_expected` pre-pass events, each within a frame of its row; the rows take turns.
fn assert_capture(capture: &Path, rows: usize, pre_passes_expected: usize) {
    let trace: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(capture).expect("capture")).expect("capture is JSON");
    let events = trace["traceEvents"].as_array().expect("traceEvents");
    let (frames, pre_passes): (Vec<&serde_json::Value>, Vec<&serde_json::Value>) = events
        .iter()
        .filter(|e| e["ph"] == "X")
        .partition(|e| e["name"].as_str().unwrap().starts_with("forward pass ("));
    assert_eq!(frames.len(), rows * FRAMES);
    for event in frames.iter().chain(&pre_passes) {
        assert!(event["dur"].as_f64().unwrap() > 0.0 && event["ts"].as_f64().unwrap() >= 0.0, "{event}");
    }
    // The multirate rows (the compute pre-pass, the default): a pre-pass per frame drawn the
    // multirate way, within its frame.
    assert_eq!(pre_passes.len(), pre_passes_expected);
    for event in &pre_passes {
        assert_eq!(event["name"], "triangle-level pre-pass", "{event}");
        let (start, end) =
            (event["ts"].as_f64().unwrap(), event["ts"].as_f64().unwrap() + event["dur"].as_f64().unwrap());
        let within = frames.iter().any(|f| {
            let ts = f["ts"].as_f64().unwrap();
            f["tid"] == event["tid"] && ts <= start && end <= ts + f["dur"].as_f64().unwrap()
        });
        assert!(within, "{event} lies within no frame of its row");
    }
    let tracks = events.iter().filter(|e| e["ph"] == "M" && e["name"] == "thread_name").count();
    assert_eq!(tracks, rows);
    // The rows take turns (FRAMES = 3 makes two turns): every row's first frame starts before
    // every row's last frame, so a slow spell of the machine cannot fall on one row alone.
    let starts = |tid: usize| -> Vec<f64> {
        frames.iter().filter(|f| f["tid"] == tid).map(|f| f["ts"].as_f64().unwrap()).collect()
    };
    let firsts = (1..=rows).map(|tid| starts(tid).into_iter().fold(f64::INFINITY, f64::min));
    let lasts = (1..=rows).map(|tid| starts(tid).into_iter().fold(f64::NEG_INFINITY, f64::max));
    let latest_first = firsts.fold(f64::NEG_INFINITY, f64::max);
    let earliest_last = lasts.fold(f64::INFINITY, f64::min);
    assert!(latest_first < earliest_last, "rows measured one after another, not in turns");
}
