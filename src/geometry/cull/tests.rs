//! Tests of `geometry::cull`: frustum, back-face and degenerate-image culling of single triangles.

use super::*;
use crate::geometry::camera::view_projection;
use crate::scene::Camera;

fn camera() -> Camera {
    Camera {
        eye: Vec3::new(0.0, 0.0, 5.0),
        target: Vec3::ZERO,
        up: Vec3::Y,
        fov_y_degrees: 60.0,
        near: 0.1,
        far: 100.0,
    }
}

#[test]
fn a_facing_triangle_in_view_is_kept_and_its_back_culled_when_one_sided() {
    let cam = camera();
    let vp = view_projection(&cam, 640, 480);
    let front = [Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    let back = [front[0], front[2], front[1]];
    assert!(!culled(&vp, cam.eye, front, true));
    assert!(culled(&vp, cam.eye, back, true));
    assert!(!culled(&vp, cam.eye, back, false), "two-sided meshes keep back faces");
    let rule = PerPixelRule {
        view_proj: vp,
        eye: cam.eye,
        viewport: Vec2::new(640.0, 480.0),
        min_estimated_area: 0.0,
    };
    assert!(back_face_per_pixel(&rule, back, false), "and shade them per pixel");
    assert!(!back_face_per_pixel(&rule, front, false) && !back_face_per_pixel(&rule, back, true));
}

#[test]
fn triangles_outside_one_plane_are_culled_and_straddling_ones_kept() {
    let cam = camera();
    let vp = view_projection(&cam, 640, 480);
    let shifted = |d: Vec3| {
        [Vec3::new(-0.5, -0.5, 0.0) + d, Vec3::new(0.5, -0.5, 0.0) + d, Vec3::new(0.0, 0.5, 0.0) + d]
    };
    for d in [Vec3::X * 50.0, -Vec3::X * 50.0, Vec3::Y * 50.0, -Vec3::Y * 50.0, Vec3::Z * 10.0] {
        assert!(culled(&vp, cam.eye, shifted(d), false), "{d}");
    }
    assert!(culled(&vp, cam.eye, shifted(-Vec3::Z * 200.0), false), "beyond the far plane");
    // One corner far outside on the right, the others inside: kept.
    let straddling = [Vec3::new(-0.5, 0.0, 0.0), Vec3::new(50.0, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0)];
    assert!(!culled(&vp, cam.eye, straddling, false));
    // Corners outside different planes (left and right) span the view: kept.
    let spanning = [Vec3::new(-50.0, -0.1, 0.0), Vec3::new(50.0, -0.1, 0.0), Vec3::new(0.0, 0.1, 0.0)];
    assert!(!culled(&vp, cam.eye, spanning, false));
}

#[test]
fn nearly_edge_on_back_faces_are_left_to_the_rasteriser() {
    let cam = camera();
    let vp = view_projection(&cam, 640, 480);
    // A back face in the plane y = −h, seen from the eye at a sine of about h / 5.
    let back_face = |h: f32| [Vec3::new(-1.0, -h, 0.0), Vec3::new(0.0, -h, -1.0), Vec3::new(1.0, -h, 0.0)];
    assert!(!culled(&vp, cam.eye, back_face(5.0e-4), true), "sine 1e-4: left to the rasteriser");
    assert!(culled(&vp, cam.eye, back_face(0.05), true), "sine 1e-2: culled");
}

#[test]
fn triangles_whose_image_is_a_segment_are_culled_and_thin_ones_kept() {
    for scale in [1.0e-6f32, 1.0, 1.0e6] {
        let cam = Camera {
            eye: camera().eye * scale,
            near: camera().near * scale,
            far: camera().far * scale,
            ..camera()
        };
        let vp = view_projection(&cam, 640, 480);
        let at = |x: f32, y: f32, z: f32| Vec3::new(x, y, z) * scale;
        let kept = |p: [Vec3; 3]| !culled(&vp, cam.eye, p, false);
        let (a, b) = (at(-1.0, -0.5, 0.0), at(1.2, 0.7, 0.0));
        // Collinear corners (the third beyond the second, and between), and coincident ones.
        assert!(!kept([a, b, a + (b - a) * 1.7]), "collinear, scale {scale}");
        assert!(!kept([a, a + (b - a) * 0.3, b]), "collinear, scale {scale}");
        assert!(!kept([a, a, b]) && !kept([a, b, b]), "coincident, scale {scale}");
        // Seen edge-on: the eye lies in the triangle's plane.
        assert!(
            !kept([at(-1.0, 0.0, -1.0), at(1.0, 0.0, -1.0), at(0.0, 0.0, 1.0)]),
            "edge-on, scale {scale}"
        );
        // A needle whose image is a thousandth as wide as it is long is a triangle.
        let across = at(0.0, 0.0, 1.0e-3) + (b - a).cross(Vec3::Z).normalize() * 2.2e-3 * scale;
        assert!(kept([a, b, (a + b) * 0.5 + across]), "needle, scale {scale}");
    }
}

#[test]
fn a_corner_behind_the_eye_is_left_to_clipping() {
    let cam = camera();
    let vp = view_projection(&cam, 640, 480);
    let behind = [Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 9.0)];
    assert!(!degenerate_image(clip_of(&vp, behind[0]), clip_of(&vp, behind[1]), clip_of(&vp, behind[2])));
}

#[test]
fn small_images_are_measured_in_pixels_and_never_behind_the_eye() {
    let cam = camera();
    let (width, height) = (640, 480);
    let vp = view_projection(&cam, width, height);
    let viewport = Vec2::new(width as f32, height as f32);
    // At distance 5 with a 60° field of view, 240 pixels span tan 30° · 5 units: a right
    // triangle with legs of 0.1 units covers (0.1 · 240 / (5 tan 30°))² / 2 ≈ 34.6 pixels.
    let legs = 0.1;
    let pixels_per_unit = 240.0 / (5.0 * 30f32.to_radians().tan());
    let area = (legs * pixels_per_unit).powi(2) / 2.0;
    let p = [Vec3::ZERO, Vec3::new(legs, 0.0, 0.0), Vec3::new(0.0, legs, 0.0)];
    let [a, b, c] = p.map(|p| clip_of(&vp, p));
    assert!((area - 34.6).abs() < 0.1, "{area}");
    assert!(small_image(a, b, c, viewport, area * 1.01));
    assert!(!small_image(a, b, c, viewport, area * 0.99));
    let rule =
        |min_estimated_area| PerPixelRule { view_proj: vp, eye: cam.eye, viewport, min_estimated_area };
    assert!(small_per_pixel(&rule(40.0), p), "a small front face is shaded per pixel");
    assert!(!small_per_pixel(&rule(30.0), p) && !small_per_pixel(&rule(0.0), p));
    let back = [p[0], p[2], p[1]];
    assert!(back_face_per_pixel(&rule(0.0), back, false), "back faces of two-sided meshes still are");
    // A corner behind the eye: the image is unbounded, never small.
    let crossing = [Vec3::new(0.0, 0.0, 10.0), Vec3::new(0.01, 0.0, 0.0), Vec3::new(0.0, 0.01, 0.0)];
    let [a, b, c] = crossing.map(|p| clip_of(&vp, p));
    assert!(!small_image(a, b, c, viewport, 1.0e9));
}
