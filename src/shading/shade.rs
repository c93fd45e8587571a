//! [`shade_point`]: the outgoing radiance at a surface point under every light of a scene, the
//! reference every mode's shading is measured against.

use super::brdf::safe_normalize;
use super::polygon_light::shade_polygon;
use super::reflect::{light_at, reflect_one_light};
use crate::scene::{Light, MaterialKind};
use glam::Vec3;

/// Outgoing radiance at a surface point, summed over `lights`. `normal` need not be unit.
pub fn shade_point(
    position: Vec3,
    normal: Vec3,
    eye: Vec3,
    material: &MaterialKind,
    lights: &[Light],
) -> Vec3 {
    let n = safe_normalize(normal);
    let v = safe_normalize(eye - position);
    lights
        .iter()
        .map(|light| match (light, light_at(light, position)) {
            (Light::Polygon(polygon), _) => {
                let (diffuse, specular) = shade_polygon(position, n, v, material, polygon);
                diffuse + specular
            }
            (_, Some((l, irradiance))) => reflect_one_light(n, l, v, material) * irradiance,
            (_, None) => Vec3::ZERO,
        })
        .sum()
}
