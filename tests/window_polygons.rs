//! The viewer on a polygon-light scene: the emitters and the polygon shading render in a window
//! in multirate and pixel mode with the validation layer on. (A binary of its own: winit allows
//! one event loop per process, and `tests/window.rs` has one.)

mod common;

use common::VirtualDisplay;
use multirate::render::{Mode, View};
use multirate::scene::Scene;
use multirate::vk::ContextOptions;
use multirate::window::{view, ScriptEvent, ViewScript};

#[test]
fn polygon_light_scene_renders_in_the_window() {
    let _display = VirtualDisplay::ensure();
    let scene = Scene::load(&common::repo_path("scenes/plane_polygons.toml")).expect("scene loads");
    let events = vec![(1, ScriptEvent::Resize(320, 180)), (2, ScriptEvent::Key("p"))];
    let script = ViewScript { events, close_at_frame: 4 };
    let start = View { mode: Mode::Multirate, ..View::of_scene(&scene) };
    let report = view(scene, start, &ContextOptions { validate: true, device_name: None }, Some(script))
        .expect("the viewer runs");
    assert!(report.frames_presented >= 4, "{report:?}");
    assert_eq!(report.validation_messages, 0, "{report:?}");
    assert_eq!(report.final_view.as_ref().expect("the view at close").mode, Mode::Pixel, "{report:?}");
}
