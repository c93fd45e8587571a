//! Reflection of one point or directional light: the BRDF's diffuse and specular parts per unit
//! irradiance ([`reflect_split`]), and where a light comes from and what it delivers
//! ([`light_at`]).

use super::brdf::{ggx_alpha, ggx_d_sin2, safe_normalize, schlick_f, smith_v, MIN_LIGHT_DISTANCE_SQUARED};
use crate::scene::{Light, MaterialKind};
use glam::Vec3;

/// Reflected radiance per unit irradiance for one light, `(diffuse, specular)`; n, l, v are
/// unit vectors.
pub fn reflect_split(n: Vec3, l: Vec3, v: Vec3, material: &MaterialKind) -> (Vec3, Vec3) {
    let n_dot_l = n.dot(l);
    if n_dot_l <= 0.0 {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    let h = safe_normalize(l + v);
    let n_dot_h = n.dot(h).max(0.0);
    match *material {
        MaterialKind::Lambert { kd } => (kd * n_dot_l, Vec3::ZERO),
        MaterialKind::BlinnPhong { kd, ks, shininess } => (kd * n_dot_l, ks * n_dot_h.powf(shininess)),
        MaterialKind::Ggx { albedo, f0, roughness } => {
            let alpha = ggx_alpha(roughness);
            let k = 0.5 * alpha;
            let n_dot_v = n.dot(v).max(0.0);
            let v_dot_h = v.dot(h).clamp(0.0, 1.0);
            // sin²θ_h from the cross product, exact near the highlight (see `ggx_d_sin2`).
            let sin2_h = if n_dot_h > 0.0 { n.cross(h).length_squared().min(1.0) } else { 1.0 };
            let specular =
                ggx_d_sin2(sin2_h, alpha) * schlick_f(v_dot_h, f0) * smith_v(n_dot_l, n_dot_v, k) * 0.25;
            (albedo * n_dot_l, specular * n_dot_l)
        }
    }
}

/// Reflected radiance per unit irradiance for one light; n, l, v are unit vectors.
pub fn reflect_one_light(n: Vec3, l: Vec3, v: Vec3, material: &MaterialKind) -> Vec3 {
    let (diffuse, specular) = reflect_split(n, l, v, material);
    diffuse + specular
}

/// Direction to a point or directional light (unit) and the irradiance it delivers facing it,
/// at `position`; `None` for a polygonal light.
pub fn light_at(light: &Light, position: Vec3) -> Option<(Vec3, Vec3)> {
    match *light {
        Light::Point { position: light_position, color, intensity } => {
            let to_light = light_position - position;
            let d2 = to_light.dot(to_light).max(MIN_LIGHT_DISTANCE_SQUARED);
            Some((to_light * (1.0 / d2.sqrt()), color * intensity / d2))
        }
        Light::Directional { direction, color, intensity } => Some((-direction, color * intensity)),
        Light::Polygon(_) => None,
    }
}
