//! The per-pixel reference on the GPU equals the Rust twin of the shading.
//!
//! Every scene is rendered at a small size with the validation layer on; at a grid of pixels
//! the test casts the pixel-centre ray on the CPU (f64), interpolates position and normal at
//! the hit and evaluates `multirate::shading::shade_point`. Only pixels whose four corners hit
//! the same mesh as the centre, at nearly the same depth, are compared: silhouettes are left
//! out, while edges between triangles of a mesh are not (position and normal are continuous
//! across them, so triangle ownership there changes nothing beyond the tolerance below).
//!
//! Tolerance, per channel: 1e-4 + 1e-3·|value| + the change of the twin over ±1/16 pixel.
//! The first two terms cover fp32 evaluation order (the GPU and the twin differ in fused
//! multiply-adds and in `pow`/`inversesqrt` implementations: a few ulp per operation, far
//! below 1e-3 relative). The last covers rasterisation: the rasteriser snaps vertices to
//! 1/256 pixel (8 sub-pixel bits on lavapipe; the Vulkan minimum is 4 bits = 1/16 pixel),
//! so the interpolated point can sit up to that far from the exact pixel centre.

mod common;

use common::{assert_validation_clean, ray_cast, repo_path, validated_context};
use glam::Vec3;
use multirate::geometry::camera::pixel_ray;
use multirate::render::{render_headless, View};
use multirate::scene::{Light, Scene};
use multirate::shading::shade_point;

const WIDTH: u32 = 128;
const HEIGHT: u32 = 96;
const STEP: u32 = 4;

/// Twin shading at framebuffer position (x, y), with the mesh and distance of the hit.
fn twin_at(scene: &Scene, x: f32, y: f32) -> Option<(usize, f64, Vec3)> {
    let (origin, direction) = pixel_ray(&scene.camera, WIDTH, HEIGHT, x, y);
    let hit = ray_cast(scene, origin, direction)?;
    let (position, normal) = hit.attributes(scene);
    let material = &scene.materials[scene.meshes[hit.mesh].material].kind;
    let value = shade_point(position.as_vec3(), normal.as_vec3(), scene.camera.eye, material, &scene.lights);
    Some((hit.mesh, hit.distance, value))
}

/// Whether the pixel ray through (x, y) meets a polygonal light's emissive geometry (such pixels
/// show the emitter, which the twin does not shade, and are left out).
fn meets_emitter(scene: &Scene, x: f32, y: f32) -> bool {
    let (origin, direction) = pixel_ray(&scene.camera, WIDTH, HEIGHT, x, y);
    let (origin, direction) = (origin.as_dvec3(), direction.as_dvec3());
    scene.lights.iter().any(|light| {
        let Light::Polygon(polygon) = light else { return false };
        let normal = polygon.normal.as_dvec3();
        let corner = polygon.vertices[0].as_dvec3();
        let t = (corner - origin).dot(normal) / direction.dot(normal);
        let ahead = t > 0.0;
        if !ahead {
            return false;
        }
        let hit = origin + direction * t;
        let v = polygon.vertices();
        (0..v.len()).all(|j| {
            let (a, b) = (v[j].as_dvec3(), v[(j + 1) % v.len()].as_dvec3());
            (b - a).cross(hit - a).dot(normal) >= 0.0
        })
    })
}

/// Whether a corner hit continues the centre's surface: same mesh, no depth discontinuity.
fn same_surface(corner: &Option<(usize, f64)>, mesh: usize, distance: f64) -> bool {
    corner.is_some_and(|(m, d)| m == mesh && (d - distance).abs() < 0.02 * distance)
}

fn check_scene(relative: &str) {
    let scene = Scene::load(&repo_path(relative)).expect("shipped scene loads");
    let context = validated_context();
    let image =
        render_headless(&context, &scene, &View::of_scene(&scene), WIDTH, HEIGHT).expect("scene renders");
    assert_validation_clean(&context);
    assert!(
        image.pixels.iter().flatten().all(|v| v.is_finite()),
        "{relative}: non-finite values in the float target"
    );

    let (mut compared, mut background, mut lit) = (0, 0, 0);
    let mut worst = (0.0f32, 0u32, 0u32);
    for y in (1..HEIGHT - 1).step_by(STEP as usize) {
        for x in (1..WIDTH - 1).step_by(STEP as usize) {
            let (cx, cy) = (x as f32 + 0.5, y as f32 + 0.5);
            let near = [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0), (0.0, 0.0)];
            if near.iter().any(|(dx, dy)| meets_emitter(&scene, cx + dx, cy + dy)) {
                continue;
            }
            let centre = twin_at(&scene, cx, cy);
            let corners: Vec<_> = [(-0.5, -0.5), (0.5, -0.5), (-0.5, 0.5), (0.5, 0.5)]
                .iter()
                .map(|(dx, dy)| twin_at(&scene, cx + dx, cy + dy).map(|(m, d, _)| (m, d)))
                .collect();
            let gpu = image.pixel(x, y);
            match centre {
                None if corners.iter().all(Option::is_none) => {
                    assert_eq!(gpu[3], 0.0, "{relative}: pixel ({x},{y}) shows no surface but has coverage");
                    background += 1;
                }
                Some((mesh, distance, expected))
                    if corners.iter().all(|c| same_surface(c, mesh, distance)) =>
                {
                    assert_eq!(
                        gpu[3], 1.0,
                        "{relative}: pixel ({x},{y}) is inside a triangle but not covered"
                    );
                    let mut spread = Vec3::ZERO;
                    for (dx, dy) in [(-1.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.0, 1.0)] {
                        let offset = twin_at(&scene, cx + dx / 16.0, cy + dy / 16.0)
                            .expect("neighbourhood of an interior pixel hits")
                            .2;
                        spread = spread.max((offset - expected).abs());
                    }
                    for channel in 0..3 {
                        let difference = (gpu[channel] - expected[channel]).abs();
                        let tolerance = 1e-4 + 1e-3 * expected[channel].abs() + spread[channel];
                        assert!(
                            difference <= tolerance,
                            "{relative}: pixel ({x},{y}) channel {channel}: GPU {} vs twin {} \
                             (difference {difference}, tolerance {tolerance})",
                            gpu[channel],
                            expected[channel]
                        );
                        if difference / tolerance > worst.0 {
                            worst = (difference / tolerance, x, y);
                        }
                    }
                    compared += 1;
                    if expected.max_element() > 1e-3 {
                        lit += 1;
                    }
                }
                _ => {}
            }
        }
    }
    eprintln!(
        "{relative}: {compared} pixels compared ({lit} lit), {background} background; \
         worst difference/tolerance {:.3} at ({}, {})",
        worst.0, worst.1, worst.2
    );
    assert!(compared >= 40, "{relative}: only {compared} interior pixels compared");
    assert!(lit >= 20, "{relative}: only {lit} lit pixels: the test would not see shading errors");
}

#[test]
fn bunny_matches_twin() {
    check_scene("scenes/bunny.toml");
}

#[test]
fn teapot_matches_twin() {
    check_scene("scenes/teapot.toml");
}

#[test]
fn plane_with_three_lights_matches_twin() {
    check_scene("scenes/plane_lights.toml");
}

#[test]
fn plane_with_polygonal_lights_matches_twin() {
    check_scene("scenes/plane_polygons.toml");
}

#[test]
fn teapot_with_polygonal_lights_matches_twin() {
    check_scene("scenes/teapot_polygons.toml");
}

#[test]
fn lambert_with_directional_light_matches_twin() {
    check_scene("scenes/test/lambert_directional.toml");
}

#[test]
fn ggx_with_point_light_matches_twin() {
    check_scene("scenes/test/ggx_point.toml");
}

#[test]
fn blinn_phong_with_mixed_lights_matches_twin() {
    check_scene("scenes/test/blinn_phong_mixed.toml");
}
