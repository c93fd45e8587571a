//! The viewer opens a window (in a tessellated mode), switches modes, heat map and wireframe
//! by key, renders, survives a resize (swapchain recreation) and closes
//! cleanly with the validation layer on; its title shows the GPU time and the evaluations.
//! Uses the display in `DISPLAY`, or starts Xvfb.

mod common;

use common::VirtualDisplay;
use multirate::render::{Mode, View};
use multirate::scene::Scene;
use multirate::vk::ContextOptions;
use multirate::window::{view, ViewScript};

#[test]
fn window_opens_resizes_and_closes_cleanly() {
    let _display = VirtualDisplay::ensure();
    let scene = common::repo_path("scenes/test/lambert_directional.toml");
    // Heat map, wireframe, vertex mode, then back to fixed:4 (F, then +); ε halved twice and
    // doubled once.
    let keys =
        vec![(2, "h"), (4, "w"), (5, "d"), (6, "v"), (7, "["), (7, "["), (8, "f"), (9, "+"), (10, "]")];
    let script = ViewScript { keys, resize_at_frame: 3, resize_to: (200, 150), close_at_frame: 12 };
    let scene = Scene::load(&scene).expect("scene loads");
    let start = View { mode: Mode::Fixed(3), ..View::of_scene(&scene) };
    let epsilon = start.epsilon;
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
    assert_eq!(last.epsilon, epsilon * 0.5, "[ halves ε twice, ] doubles it once");
    // The title: mode, GPU time from timestamps, evaluations against `pixel` (fixed:4 shades
    // sub-vertices only, a fraction of the covered pixels here).
    let title = &report.final_title;
    assert!(title.contains("fixed:4"), "{title}");
    let number_before = |unit: &str| -> f64 {
        let head = &title[..title.find(unit).unwrap_or_else(|| panic!("no `{unit}` in {title}"))];
        head.split_whitespace().last().and_then(|w| w.parse().ok()).unwrap_or_else(|| panic!("{title}"))
    };
    assert!(number_before(" ms") > 0.0, "{title}");
    let percent = number_before(" % of pixel");
    assert!(percent > 0.0 && percent < 100.0, "{title}");
}
