//! Tests of `geometry::camera`: the projection against Vulkan's depth range and y axis, and pixel rays.

use super::*;

fn camera() -> Camera {
    Camera {
        eye: Vec3::new(1.0, 2.0, 5.0),
        target: Vec3::new(0.0, 0.5, 0.0),
        up: Vec3::Y,
        fov_y_degrees: 50.0,
        near: 0.1,
        far: 20.0,
    }
}

#[test]
fn near_and_far_planes_map_to_vulkan_depth_range() {
    let c = camera();
    let view_proj = view_projection(&c, 200, 100);
    let forward = (c.target - c.eye).normalize();
    let near = view_proj.project_point3(c.eye + forward * c.near);
    let far = view_proj.project_point3(c.eye + forward * c.far);
    assert!(near.z.abs() < 1e-5, "near plane at depth {}", near.z);
    assert!((far.z - 1.0).abs() < 1e-5, "far plane at depth {}", far.z);
    assert!(near.x.abs() < 1e-5 && near.y.abs() < 1e-5, "the target projects to the centre");
}

#[test]
fn up_is_towards_the_top_row() {
    let c = camera();
    let clip = view_projection(&c, 100, 100).project_point3(c.target + Vec3::Y * 0.1);
    assert!(clip.y < 0.0, "Vulkan's y points down: a point above the target has y < 0");
}

#[test]
fn pixel_rays_hit_what_the_projection_puts_there() {
    let c = camera();
    let (origin, direction) = pixel_ray(&c, 320, 240, 40.5, 200.5);
    let point = origin + direction * 3.0;
    let ndc = view_projection(&c, 320, 240).project_point3(point);
    let pixel = ((ndc.x + 1.0) * 0.5 * 320.0, (ndc.y + 1.0) * 0.5 * 240.0);
    assert!((pixel.0 - 40.5).abs() < 1e-3 && (pixel.1 - 200.5).abs() < 1e-3, "{pixel:?}");
}
