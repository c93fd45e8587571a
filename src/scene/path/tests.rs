//! Tests of `scene::path`: the spline passes through its keys with a velocity that does not
//! jump, at rest at its ends; an orbit keeps its distance and comes round; frames cover the
//! path; the far plane follows an eye that leaves the scene behind.

use super::*;
use crate::scene::Camera;

fn keys() -> Vec<PathKey> {
    let key =
        |time, eye: [f32; 3], target: [f32; 3]| PathKey { time, eye: eye.into(), target: target.into() };
    vec![
        key(0.5, [0.0, 1.0, 5.0], [0.0, 0.0, 0.0]),
        key(1.0, [3.0, 1.5, 4.0], [0.5, 0.0, 0.0]),
        key(3.0, [5.0, 2.0, -1.0], [1.0, 0.5, 0.0]),
        key(3.5, [2.0, 1.0, -4.0], [0.0, 0.0, 0.0]),
    ]
}

fn start() -> (Vec3, Vec3, Vec3) {
    let camera = camera();
    (camera.eye, camera.target, camera.up)
}

fn camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 1.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_degrees: 45.0,
        near: 0.01,
        far: 10.0,
    }
}

#[test]
fn the_spline_passes_through_its_keys_at_rest_at_its_ends() {
    let keys = keys();
    let path = CameraPath::Keys(keys.clone());
    assert_eq!(path.duration(), 3.0);
    for key in &keys {
        let (eye, target) = path.eye_and_target(start(), key.time - keys[0].time);
        assert!(
            eye.distance(key.eye) < 1e-5 && target.distance(key.target) < 1e-5,
            "{key:?}: {eye} {target}"
        );
    }
    let at = |t: f32| path.eye_and_target(start(), t).0;
    let h = 1e-3;
    // At rest at both ends; before and after the path, where it begins and ends.
    assert!(at(h).distance(at(0.0)) < 1e-4 && at(3.0).distance(at(3.0 - h)) < 1e-4);
    assert_eq!(at(-1.0), at(0.0));
    assert_eq!(at(9.0), at(3.0));
    // The velocity does not jump at an inner key (uneven times on either side), and is not zero.
    for key in &keys[1..3] {
        let t = key.time - keys[0].time;
        let before = (at(t) - at(t - h)) / h;
        let after = (at(t + h) - at(t)) / h;
        assert!(before.length() > 0.5, "at rest inside the path at {t}");
        assert!((before - after).length() < 0.02 * before.length(), "{before} then {after} at {t}");
    }
}

#[test]
fn an_orbit_keeps_its_distance_and_comes_round() {
    let path = CameraPath::Orbit { seconds: 4.0 };
    let start = camera();
    let distance = start.eye.distance(start.target);
    for k in 0..=40 {
        let (eye, target) = path.eye_and_target((start.eye, start.target, start.up), k as f32 * 0.1);
        assert_eq!(target, start.target);
        assert!((eye.distance(target) - distance).abs() < 1e-4);
        assert!((eye.y - start.eye.y).abs() < 1e-5, "turned about the up direction");
    }
    let flat = |v: Vec3| Vec3::new(v.x, 0.0, v.z);
    let quarter = flat(path.eye_and_target((start.eye, start.target, start.up), 1.0).0 - start.target);
    assert!(
        quarter.dot(flat(start.eye - start.target)).abs() < 1e-4,
        "a quarter turn in a quarter of the time"
    );
    assert!(path.eye_and_target((start.eye, start.target, start.up), 4.0).0.distance(start.eye) < 1e-4);
}

#[test]
fn frames_cover_the_path() {
    let path = CameraPath::Keys(keys());
    let times = path.frame_times(30.0);
    assert_eq!(times.len(), 91);
    assert_eq!(times[0], 0.0);
    assert!((times[90] - 3.0).abs() < 1e-5);
    assert_eq!(CameraPath::Orbit { seconds: 0.0 }.frame_times(24.0), vec![0.0]);
}

#[test]
fn the_far_plane_follows_an_eye_that_leaves_the_scene_behind() {
    let bounds = (Vec3::splat(-1.0), Vec3::splat(1.0));
    let far_key = PathKey { time: 1.0, eye: Vec3::new(0.0, 0.0, 50.0), target: Vec3::ZERO };
    let path = CameraPath::Keys(vec![PathKey { time: 0.0, eye: camera().eye, target: Vec3::ZERO }, far_key]);
    let near = camera().on_path(&path, 0.0, bounds);
    assert_eq!((near.near, near.far), (0.01, 10.0), "the scene's own depth range where it reaches");
    let away = camera().on_path(&path, 1.0, bounds);
    assert!(away.far > 51.0 * 1.01 && away.far < 52.0 * 1.01, "{}", away.far);
    assert!((away.near / away.far - 0.001).abs() < 1e-6, "the same ratio");
}
