//! Tests of `render::frame_config`: a frame's configuration is resolved from the renderer's
//! state without changing it, and a frame that commits nothing neither begins nor keeps a ball.

use super::*;
use crate::gpu_interface::flags::{FLAG_HOLD_LEVELS, FLAG_REUSE_LEVELS};

fn bunny() -> (PerPixelChoice, View) {
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bunny.toml"));
    let scene = Scene::load(path).expect("the bunny loads");
    let view = View { mode: Mode::Multirate, ..View::of_scene(&scene) };
    (PerPixelChoice::new("a test device", &scene), view)
}

const EXTENT: vk::Extent2D = vk::Extent2D { width: 64, height: 48 };

#[test]
fn resolving_a_frame_twice_gives_the_same_frame() {
    let (choice, view) = bunny();
    let radius = view.estimator.eye_radius;
    let first = FrameConfig::resolve(&choice, &view, EXTENT, None, Commit::OnSubmit, 1);
    let again = FrameConfig::resolve(&choice, &view, EXTENT, None, Commit::OnSubmit, 1);
    assert!(first.runs_pre_pass);
    assert_eq!(first.ball, BallUse::Begin { radius, fresh: true });
    assert_eq!(again.ball, first.ball, "nothing was submitted in between");
    let Some(Some(ball)) = first.ball_after else { panic!("a frame for the image commits its ball") };
    assert_eq!(ball.centre(), view.camera.eye);
    let next = FrameConfig::resolve(&choice, &view, EXTENT, Some(ball), Commit::OnSubmit, 1);
    assert!(matches!(next.ball, BallUse::Continue { .. }), "{:?}", next.ball);
    let flags = next.pre_pass_constants().flags;
    assert_ne!(flags & FLAG_REUSE_LEVELS, 0);
    assert_eq!(flags & FLAG_HOLD_LEVELS, 0, "levels are not held by default");
    let held = View { hold_levels: true, ..view.clone() };
    let frame = FrameConfig::resolve(&choice, &held, EXTENT, Some(ball), Commit::OnSubmit, 1);
    assert_ne!(frame.pre_pass_constants().flags & FLAG_HOLD_LEVELS, 0, "{:?}", frame.ball);
}

#[test]
fn a_frame_that_commits_nothing_keeps_no_levels_of_its_own() {
    let (choice, view) = bunny();
    let view = View { hold_levels: true, ..view };
    let radius = view.estimator.eye_radius;
    let detached = FrameConfig::resolve(&choice, &view, EXTENT, None, Commit::Never, 1);
    assert_eq!(detached.ball, BallUse::Detached { radius });
    assert_eq!(detached.ball_after, None);
    let constants = detached.pre_pass_constants();
    assert_eq!(constants.flags & FLAG_REUSE_LEVELS, 0, "it neither reads nor replaces the kept levels");
    assert_eq!(constants.flags & FLAG_HOLD_LEVELS, 0, "nor the levels held");
    assert_eq!(
        constants.eye_radius, radius,
        "its estimates hold for the ball a frame for the image would begin"
    );
    let kept = FrameConfig::resolve(&choice, &view, EXTENT, None, Commit::OnSubmit, 1).ball_after.flatten();
    let inside = FrameConfig::resolve(&choice, &view, EXTENT, kept, Commit::Never, 1);
    assert!(matches!(inside.ball, BallUse::Continue { .. }), "it reuses the kept levels: {:?}", inside.ball);
    assert_eq!(inside.ball_after, None);
}

#[test]
fn frames_without_a_pre_pass_leave_the_ball_alone() {
    let (choice, view) = bunny();
    for other in [
        View { mode: Mode::Pixel, ..view.clone() },
        View { placement: Placement::Tcs, ..view.clone() },
        View { drawn_as_pixel: true, ..view.clone() },
    ] {
        let frame = FrameConfig::resolve(&choice, &other, EXTENT, None, Commit::OnSubmit, 1);
        assert!(!frame.runs_pre_pass, "{other:?}");
        assert_eq!((frame.ball, frame.ball_after), (BallUse::Off, None), "{other:?}");
    }
}
