//! Tests of `analysis::temporal` on frames rendered here by ray casting: an error that stays on
//! its surface does not change as the camera moves; an error that appears is counted as jumps
//! and flicker; what a moving camera uncovers is masked, not compared.

use super::*;

const SIZE: (u32, u32) = (96, 64);

fn camera(eye: Vec3) -> Camera {
    Camera { eye, target: Vec3::new(0.0, 0.0, 0.0), up: Vec3::Y, fov_y_degrees: 40.0, near: 0.1, far: 100.0 }
}

/// A square of half width `half` in the plane z = `z`, in two triangles.
fn square(half: f32, z: f32) -> [[Vec3; 3]; 2] {
    let c = |x: f32, y: f32| Vec3::new(x * half, y * half, z);
    [[c(-1.0, -1.0), c(1.0, -1.0), c(1.0, 1.0)], [c(-1.0, -1.0), c(1.0, 1.0), c(-1.0, 1.0)]]
}

/// Möller–Trumbore: the distance along the ray to the triangle, where it meets it.
fn hit((origin, direction): (Vec3, Vec3), [a, b, c]: [Vec3; 3]) -> Option<f32> {
    let (e1, e2) = (b - a, c - a);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-9 {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = direction.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some(t)
}

/// The frame `camera` sees of `corners`: the reference shades a point `reference(X)`, the mode
/// `reference(X) + error(X)`.
fn frame(
    camera: Camera,
    corners: &[[Vec3; 3]],
    reference: impl Fn(Vec3) -> f32,
    error: impl Fn(Vec3) -> f32,
) -> (FloatImage, FloatImage, Vec<u32>) {
    let (width, height) = SIZE;
    let mut images = [Vec::new(), Vec::new()];
    let mut ids = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let ray = pixel_ray(&camera, width, height, x as f32 + 0.5, y as f32 + 0.5);
            let nearest = corners
                .iter()
                .enumerate()
                .filter_map(|(k, t)| hit(ray, *t).map(|d| (d, k)))
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let (id, value, wrong) = match nearest {
                Some((d, k)) => {
                    let point = ray.0 + ray.1 * d;
                    (k as u32 + 1, reference(point), error(point))
                }
                None => (0, 0.0, 0.0),
            };
            ids.push(id);
            images[0].push([value + wrong; 4]);
            images[1].push([value; 4]);
        }
    }
    let [test, reference] = images.map(|pixels| FloatImage { width, height, pixels });
    (test, reference, ids)
}

fn stepped(
    cameras: [Camera; 2],
    corners: &[[Vec3; 3]],
    reference: impl Fn(Vec3) -> f32 + Copy,
    errors: [&dyn Fn(Vec3) -> f32; 2],
    pattern_changed: &[bool],
) -> StepStability {
    let (t0, r0, ids0) = frame(cameras[0], corners, reference, errors[0]);
    let (t1, r1, ids1) = frame(cameras[1], corners, reference, errors[1]);
    let (previous_camera, camera) = (cameras[0], cameras[1]);
    let previous = PathFrame {
        test: &t0,
        reference: &r0,
        triangles: &ids0,
        test_triangles: &ids0,
        camera: previous_camera,
        pattern_changed: &[],
    };
    let current = PathFrame {
        test: &t1,
        reference: &r1,
        triangles: &ids1,
        test_triangles: &ids1,
        camera,
        pattern_changed,
    };
    step(&previous, &current, corners, 0.1)
}

#[test]
fn an_error_that_stays_on_its_surface_does_not_change_as_the_camera_moves() {
    let corners = square(3.0, 0.0).to_vec();
    let shading = |p: Vec3| 0.5 + 0.1 * p.x;
    let error = |p: Vec3| 0.02 * (p.y * 0.5).sin();
    let still = stepped([camera(Vec3::new(0.0, 0.0, 8.0)); 2], &corners, shading, [&error, &error], &[]);
    assert!(still.compared > 2000 && still.largest == 0.0 && still.jumps == 0, "{still:?}");
    let moved = [camera(Vec3::new(0.0, 0.0, 8.0)), camera(Vec3::new(0.3, 0.1, 8.0))];
    let step = stepped(moved, &corners, shading, [&error, &error], &[]);
    // Nearest-pixel reprojection: at most a pixel's worth of the error's and the shading's slope.
    assert!(step.compared > 2000, "{step:?}");
    assert!(step.largest < 0.002 && step.jumps == 0, "{step:?}");
    let ratio = PathStability { steps: vec![step] }.flicker_ratio();
    assert!((ratio - 1.0).abs() < 0.1, "the mode changes as the reference does: {ratio}");
}

#[test]
fn an_error_that_appears_is_counted_as_jumps_and_flicker() {
    let corners = square(3.0, 0.0).to_vec();
    let shading = |p: Vec3| 0.5 + 0.1 * p.x;
    let none = |_: Vec3| 0.0;
    let patch = |p: Vec3| if p.x.abs() < 1.0 && p.y.abs() < 1.0 { 0.08 } else { 0.0 };
    let moved = [camera(Vec3::new(0.0, 0.0, 8.0)), camera(Vec3::new(0.2, 0.0, 8.0))];
    let step = stepped(moved, &corners, shading, [&none, &patch], &[]);
    assert!((step.largest - 0.08).abs() < 1e-5, "{step:?}");
    // The patch covers about a ninth of the square: its pixels jump by 0.08 > ε/2 = 0.05.
    let share = step.jump_share();
    assert!(share > 0.05 && share < 0.2, "{share}: {step:?}");
    assert!((step.p99 - 0.08).abs() < 1e-5, "{step:?}");
    assert_eq!(step.pattern_jumps, 0, "no pattern changed: {step:?}");
    // The same step where the square's first triangle changed its pattern: its jumps, and only
    // its, are counted apart.
    let first_changed = stepped(moved, &corners, shading, [&none, &patch], &[true, false]);
    assert!(first_changed.pattern_jumps > 0 && first_changed.pattern_jumps < step.jumps, "{first_changed:?}");
    let both_changed = stepped(moved, &corners, shading, [&none, &patch], &[true, true]);
    assert_eq!(both_changed.pattern_jumps, step.jumps, "{both_changed:?}");
    let ratio = PathStability { steps: vec![step] }.flicker_ratio();
    assert!(ratio > 1.5, "flicker beyond the reference's own: {ratio}");
}

#[test]
fn what_a_moving_camera_uncovers_is_masked() {
    // A small square in front of a large one; the camera slides, uncovering part of the back.
    let mut corners = square(3.0, 0.0).to_vec();
    corners.extend(square(0.8, 2.0));
    let shading = |p: Vec3| 0.3 + 0.05 * p.z;
    let error = |p: Vec3| if p.z > 1.0 { 0.04 } else { -0.04 };
    let moved = [camera(Vec3::new(0.0, 0.0, 8.0)), camera(Vec3::new(0.6, 0.0, 8.0))];
    let step = stepped(moved, &corners, shading, [&error, &error], &[]);
    // Uncovered pixels of the back square would read the front square's error (a change of
    // 0.08) were they not masked; the front square's silhouette is masked too.
    assert!(step.masked > 20, "{step:?}");
    assert!(step.largest < 0.002, "an uncovered pixel was compared: {step:?}");
}
