//! Tests of `window::speed`: the title's speed is the reference's time over the live one, and
//! `pixel` is timed again only when the size changes, the user asks, or the camera has moved
//! and `RETIME_EVERY` has passed.

use super::{speed_text, PixelReference, RETIME_EVERY};
use crate::render::View;
use crate::scene::Scene;
use ash::vk;
use std::path::Path;
use std::time::Instant;

#[test]
fn the_speed_is_the_reference_over_the_live_time() {
    assert_eq!(speed_text(80.0, 20.0), "4.00× pixel's speed (pixel 80.00 ms)");
    assert_eq!(speed_text(10.0, 40.0), "0.25× pixel's speed (pixel 10.00 ms)");
}

#[test]
fn pixel_is_timed_again_on_a_new_size_on_request_and_after_the_camera_moved_for_a_while() {
    let scene = Scene::load(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bunny.toml"))).unwrap();
    let view = View::of_scene(&scene);
    let extent = vk::Extent2D { width: 64, height: 48 };
    let taken = |at| PixelReference { ms: 1.0, camera: view.camera, extent, at };
    let fresh = taken(Instant::now());
    assert!(PixelReference::due(None, &view, extent, false), "no reference yet");
    assert!(!PixelReference::due(Some(&fresh), &view, extent, false), "nothing changed");
    assert!(PixelReference::due(Some(&fresh), &view, extent, true), "the user pressed T");
    let larger = vk::Extent2D { width: 128, height: 48 };
    assert!(PixelReference::due(Some(&fresh), &view, larger, false), "the window's size changed");
    let mut moved = view.clone();
    moved.camera.eye.x += 1.0;
    assert!(!PixelReference::due(Some(&fresh), &moved, extent, false), "moved, but just timed");
    let old = taken(Instant::now() - RETIME_EVERY);
    assert!(PixelReference::due(Some(&old), &moved, extent, false), "moved, and timed a while ago");
    assert!(!PixelReference::due(Some(&old), &view, extent, false), "a while ago, but not moved");
}
