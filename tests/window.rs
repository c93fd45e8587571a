//! The viewer opens a window (in a tessellated mode), switches modes, heat map, wireframe, ε,
//! n_max and shadows by key, renders, survives a resize (swapchain recreation) and closes cleanly with
//! the validation layer on; its title shows the GPU time, the speed against `pixel` and the
//! evaluations. Then the soak:
//! `multirate soak` runs the window for 10,000 frames through every mode, key and size,
//! minimised spells included, and its memory stays flat.
//!
//! winit allows one event loop per process: the first test runs the viewer in this process,
//! the soak runs the `multirate` binary. Both use the display in `DISPLAY` as the process
//! started with it, or an Xvfb of their own.

mod common;

use common::VirtualDisplay;
use multirate::render::{Mode, View};
use multirate::scene::path::CameraPath;
use multirate::scene::{Scene, ShadowCaster};
use multirate::vk::ContextOptions;
use multirate::window::{view, ScriptEvent, ViewScript};
use std::ffi::OsString;
use std::io::{BufRead, BufReader};
use std::process::Stdio;
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// `DISPLAY` as the process started with it: read by each test before the first one to start
/// an Xvfb sets it, so that the soak never borrows the first test's short-lived server.
fn starting_display() -> Option<OsString> {
    static DISPLAY: OnceLock<Option<OsString>> = OnceLock::new();
    DISPLAY.get_or_init(|| std::env::var_os("DISPLAY").filter(|d| !d.is_empty())).clone()
}

#[test]
fn window_opens_resizes_and_closes_cleanly() {
    starting_display();
    let _display = VirtualDisplay::ensure();
    let scene = common::repo_path("scenes/test/lambert_directional.toml");
    // Heat map, wireframe, vertex mode, then back to fixed:4 (F, then +); ε halved twice and
    // doubled once, n_max the same; the shadows and the post chain off for the last frames (the
    // renderer made again, with the wireframe still on).
    let keys = [
        (2, "h"),
        (4, "w"),
        (5, "d"),
        (6, "v"),
        (7, "["),
        (7, "["),
        (7, "<"),
        (7, "<"),
        (8, "f"),
        (9, "+"),
        (10, "]"),
        (10, ">"),
        (10, "s"),
        (10, "o"),
        (11, " "),
    ];
    let mut events: Vec<(u32, ScriptEvent)> =
        keys.iter().map(|&(at, key)| (at, ScriptEvent::Key(key))).collect();
    events.insert(2, (3, ScriptEvent::Resize(200, 150)));
    let script = ViewScript { events, close_at_frame: 12 };
    let mut scene = Scene::load(&scene).expect("scene loads");
    scene.shadow_casters.push(ShadowCaster { light: 0, resolution: 64, filter: 3 });
    // A camera path, played from the start and paused by Space for the last frame.
    scene.camera_path = Some(CameraPath::Orbit { seconds: 2.0 });
    let start = View { mode: Mode::Fixed(3), ..View::of_scene(&scene) };
    let (epsilon, n_max) = (start.estimator.epsilon, start.estimator.n_max);
    let report = view(scene, start, &ContextOptions { validate: true, device_name: None }, Some(script))
        .expect("the viewer runs");
    assert!(report.frames_presented >= 12, "{report:?}");
    assert!(report.swapchain_recreations >= 1, "the resize must recreate the swapchain: {report:?}");
    assert_eq!(report.final_extent, (200, 150), "{report:?}");
    assert_eq!(report.validation_messages, 0, "{report:?}");
    let last = report.final_view.as_ref().expect("the view at close");
    assert_eq!(last.mode, Mode::Fixed(4), "keys switch modes: {report:?}");
    assert!(last.heat_map, "H toggled the heat map on");
    assert!(last.wireframe, "W toggled the wireframe on (lavapipe has fillModeNonSolid)");
    assert_eq!(last.estimator.epsilon, epsilon * 0.5, "[ halves ε twice, ] doubles it once");
    assert_eq!(last.estimator.n_max, (n_max / 4).max(1) * 2, "< halves n_max twice, > doubles it once");
    assert!(
        report.frames_without_shadows >= 1 && report.frames_without_shadows < report.frames_presented,
        "S turned the shadows off for the last frames: {report:?}"
    );
    assert!(
        report.frames_without_post >= 1 && report.frames_without_post < report.frames_presented,
        "O turned the post chain off for the last frames: {report:?}"
    );
    assert!(
        report.frames_on_path >= 1 && report.frames_on_path < report.frames_presented,
        "the path played, then Space paused it: {report:?}"
    );
    // The title: mode, GPU time from timestamps, speed and evaluations against `pixel` (fixed:4
    // shades sub-vertices only, a fraction of the covered pixels here).
    let title = &report.final_title;
    assert!(
        title.contains("fixed:4")
            && title.contains("shadows off")
            && title.contains("post off")
            && title.contains("paused"),
        "{title}"
    );
    let number_before = |unit: &str| -> f64 {
        let head = &title[..title.find(unit).unwrap_or_else(|| panic!("no `{unit}` in {title}"))];
        head.split_whitespace().last().and_then(|w| w.parse().ok()).unwrap_or_else(|| panic!("{title}"))
    };
    assert!(number_before(" ms") > 0.0, "{title}");
    // Its speed against `pixel` mode, timed in the same window.
    assert!(number_before("× pixel's speed") > 0.0, "{title}");
    let percent = number_before(" % of pixel");
    assert!(percent > 0.0 && percent < 100.0, "{title}");
}

/// The soak: 10,000 frames on the smallest scene in a 64×48 window, validation on.
const SOAK_FRAMES: u64 = 10_000;

#[test]
fn a_soak_of_ten_thousand_frames_visits_every_mode_and_keeps_memory_flat() {
    let (_xvfb, display) = match starting_display() {
        Some(display) => (None, display),
        None => {
            let (xvfb, display) = VirtualDisplay::start();
            (Some(xvfb), OsString::from(display))
        }
    };
    let json = std::env::temp_dir().join(format!("multirate-window-soak-{}.json", std::process::id()));
    let mut child = common::multirate_command()
        .args(["soak", "--frames", &SOAK_FRAMES.to_string(), "--size", "64x48", "--json"])
        .arg(&json)
        .arg("--scene")
        .arg(common::repo_path("scenes/test/lambert_directional.toml"))
        .env("DISPLAY", &display)
        .stdout(Stdio::piped())
        .spawn()
        .expect("the multirate binary starts");
    // A hung run fails instead of holding the suite: the soak takes about a minute on
    // lavapipe, and this is far beyond any machine's.
    let deadline = Instant::now() + Duration::from_secs(1800);
    let status = loop {
        if let Some(status) = child.try_wait().expect("the soak can be waited for") {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("the soak did not finish in 30 minutes");
        }
        std::thread::sleep(Duration::from_millis(200));
    };
    let mut printed = String::new();
    if let Some(stdout) = child.stdout.take() {
        BufReader::new(stdout).lines().map_while(Result::ok).for_each(|l| printed += &(l + "\n"));
    }
    let text = std::fs::read_to_string(&json).unwrap_or_default();
    let _ = std::fs::remove_file(&json);
    assert!(status.success(), "the soak failed ({status}):\n{printed}");
    let figures: serde_json::Value = serde_json::from_str(&text).expect("the soak writes its JSON");
    let number = |path: &str| -> f64 {
        figures
            .pointer(path)
            .and_then(serde_json::Value::as_f64)
            .unwrap_or_else(|| panic!("{path}: {printed}"))
    };

    assert!(number("/frames") >= SOAK_FRAMES as f64, "{printed}");
    assert_eq!(number("/validation_messages"), 0.0, "{printed}");
    // Every mode drew frames, the multirate estimator in both places, several N and n_max.
    let modes = figures.pointer("/details/frames by mode").and_then(|m| m.as_object()).expect("modes");
    for mode in [
        "pixel",
        "pixel-deferred",
        "vertex",
        "fixed:3",
        "fixed:4",
        "fixed:5",
        "multirate (compute)",
        "multirate (tcs)",
    ] {
        assert!(
            modes.get(mode).and_then(|f| f.as_u64()).is_some_and(|f| f > 0),
            "{mode} never drawn: {printed}"
        );
    }
    assert!(number("/details/heat map frames") > 0.0, "{printed}");
    assert!(number("/details/wireframe frames") > 0.0, "{printed}");
    let n_max_values = figures.pointer("/details/n_max values").and_then(|v| v.as_array()).expect("n_max");
    assert!(n_max_values.len() >= 3, "n_max was not switched: {printed}");
    let (low, high) = (number("/details/epsilon range/0"), number("/details/epsilon range/1"));
    assert!(high >= 4.0 * low, "ε was not switched: {printed}");
    // Resized to three sizes and minimised every cycle, and recreated the swapchain each time.
    let cycles = number("/details/scripted events/minimise");
    assert!(cycles >= 50.0, "{printed}");
    assert_eq!(number("/details/scripted events/restore"), cycles, "{printed}");
    assert!(number("/details/turns minimised") >= cycles, "minimised turns draw nothing: {printed}");
    assert!(number("/details/swapchain recreations") >= 4.0 * cycles - 4.0, "{printed}");
    // Memory: the resident set, the allocator's device memory (blocks held, bytes handed out)
    // and, where the device has VK_EXT_memory_budget, its heaps: at most 1 % more at the end
    // than after the warm-up.
    let memory = figures.pointer("/memory").and_then(|m| m.as_array()).expect("memory figures");
    let names: Vec<&str> = memory.iter().filter_map(|g| g["figure"].as_str()).collect();
    for name in ["resident set", "device memory blocks (allocator)", "device memory allocated (allocator)"] {
        assert!(names.contains(&name), "{name}: {printed}");
    }
    if figures.pointer("/samples/0/device_bytes").is_some_and(|d| !d.is_null()) {
        assert!(names.iter().any(|n| n.starts_with("device heaps")), "{printed}");
    }
    for figure in memory {
        let growth = figure["growth"].as_f64().expect("growth");
        assert!(growth <= 0.01, "{} grew by {:.3} %: {printed}", figure["figure"], 100.0 * growth);
    }
}
