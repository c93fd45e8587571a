//! Shading with a polygonal area light at one point: the exact diffuse part and the Monte Carlo
//! specular part. The Rust twin of `glsl/include/polygon_light.glsl` (same steps, same sample
//! set); `src/shading/polygon/` supplies clipping, the closed forms and the samplers.
//!
//! For a one-sided Lambertian emitter of radiance `L` and a shading point `x` in front of it:
//! - **diffuse** `kd · L · Ω⊥(x)`, with `Ω⊥` the closed-form projected solid angle of the polygon
//!   clipped to the horizon: exact, no samples, no noise.
//! - **specular** `∫ f(ω) dω` with `f = L · ρₛ(ω)` (Blinn-Phong `ks (n·h)^s`, GGX `D F V (n·l)/4`,
//!   the integrands whose point-light versions are in [`super::reflect::reflect_split`]) estimated with
//!   `N` light samples (projected solid angle, Algorithms 1–4, or solid angle, Algorithm 5) and
//!   `N` BRDF samples, combined by clamped optimal MIS (B.3) with visibility estimate `v`:
//!   `S = 1/N Σᵢ [w_l f/p_l (ωᵢ) + w_b f/p_b (ω'ᵢ)]`.
//!
//! The sample set is the same at every shading point ([`super::polygon::sample_point`] of `N`;
//! the BRDF samples use the point with its coordinates swapped), so images do not flicker and
//! the per-pixel reference and the sub-vertices evaluate the same function. The MIS coefficients
//! (the model `f ≈ c_l p_l + c_b p_b` of B.1) are each technique's one-sample estimate at its
//! most likely direction: `c_l = f̃/p_l` towards the clipped polygon's mean vertex direction and
//! `c_b = f̃/p_b` at the mirror direction, where `f̃` ignores the light's extent.

use super::brdf::{ggx_alpha, ggx_d, safe_normalize};
use super::polygon::{
    clip_to_horizon, prepare_projected_solid_angle, prepare_solid_angle, projected_solid_angle,
    projected_solid_angle_density, projected_to_solid_angle_density, sample_point,
    sample_projected_solid_angle, sample_solid_angle, solid_angle_density, Polygon,
    ProjectedSolidAngleSampler, SolidAngleSampler,
};
use super::reflect::reflect_split;
use crate::scene::{MaterialKind, PolygonLight, PolygonSampling};
use glam::Vec3;
use std::f32::consts::PI;

/// An orthonormal basis `(t, b)` completing the unit `n` (Duff et al. 2017, branch-free up to
/// the sign): `(t, b, n)` is right-handed.
pub fn tangent_frame(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// The light sampler of either technique for one clipped polygon.
enum LightSampler {
    Projected(ProjectedSolidAngleSampler),
    Solid(SolidAngleSampler),
}

impl LightSampler {
    /// A sampled direction and its density with respect to solid angle.
    fn sample(&self, u: [f32; 2]) -> (Vec3, f32) {
        match self {
            LightSampler::Projected(s) => {
                let (w, density) = sample_projected_solid_angle(s, u);
                (w, projected_to_solid_angle_density(density, w))
            }
            LightSampler::Solid(s) => sample_solid_angle(s, u),
        }
    }

    /// The density with respect to solid angle of producing `w`.
    fn density(&self, w: Vec3) -> f32 {
        match self {
            LightSampler::Projected(s) => {
                projected_to_solid_angle_density(projected_solid_angle_density(s, w), w)
            }
            LightSampler::Solid(s) => solid_angle_density(s, w),
        }
    }
}

/// The specular integrand per unit radiance in the local frame (`n = +z`): `ρₛ` of
/// [`reflect_split`], zero below the horizon.
fn specular(l: Vec3, v: Vec3, material: &MaterialKind) -> Vec3 {
    reflect_split(Vec3::Z, l, v, material).1
}

/// The BRDF technique: a direction from `u` and its density with respect to solid angle, in the
/// local frame. Blinn-Phong samples `h ∝ (n·h)^s`, GGX samples `h ∝ D(h)(n·h)`; `l` is `v`
/// reflected about `h`, `p(l) = p(h) / (4 v·h)`. Lambert has no specular lobe (density 0).
pub fn sample_brdf(u: [f32; 2], v: Vec3, material: &MaterialKind) -> (Vec3, f32) {
    let cos_theta = match *material {
        MaterialKind::Lambert { .. } => return (Vec3::Z, 0.0),
        MaterialKind::BlinnPhong { shininess, .. } => u[0].powf(1.0 / (shininess + 1.0)),
        MaterialKind::Ggx { roughness, .. } => {
            let a2 = ggx_alpha(roughness) * ggx_alpha(roughness);
            ((1.0 - u[0]) / (1.0 + (a2 - 1.0) * u[0])).max(0.0).sqrt()
        }
    };
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let phi = 2.0 * PI * u[1];
    let h = Vec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta);
    let l = h * (2.0 * v.dot(h)) - v;
    (l, brdf_density(l, v, material))
}

/// The density with respect to solid angle with which [`sample_brdf`] produces `l`.
pub fn brdf_density(l: Vec3, v: Vec3, material: &MaterialKind) -> f32 {
    let h = safe_normalize(l + v);
    let (n_dot_h, v_dot_h) = (h.z, v.dot(h));
    if n_dot_h <= 0.0 || v_dot_h <= 0.0 {
        return 0.0;
    }
    let half_density = match *material {
        MaterialKind::Lambert { .. } => 0.0,
        MaterialKind::BlinnPhong { shininess, .. } => {
            (shininess + 1.0) / (2.0 * PI) * n_dot_h.powf(shininess)
        }
        MaterialKind::Ggx { roughness, .. } => ggx_d(n_dot_h, ggx_alpha(roughness)) * n_dot_h,
    };
    half_density / (4.0 * v_dot_h)
}

/// `f/p` where `p > 0`, else 0.
fn ratio(f: Vec3, p: f32) -> Vec3 {
    if p > 0.0 {
        f / p
    } else {
        Vec3::ZERO
    }
}

/// The light's contribution at `position` (unit normal `n`, unit direction to the eye `v`):
/// `(diffuse, specular)`, the diffuse part as `kd · L · Ω⊥` (an albedo map multiplies it later).
/// The light's [`PolygonLight::sampling`] says how its specular part is sampled.
pub fn shade_polygon(
    position: Vec3,
    n: Vec3,
    v: Vec3,
    material: &MaterialKind,
    light: &PolygonLight,
) -> (Vec3, Vec3) {
    let settings = &light.sampling;
    let radiance = light.radiance();
    // One-sided: only points in front of the emitter's plane see it.
    if light.normal.dot(position - light.vertices[0]) <= 0.0 {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    let (t, b) = tangent_frame(n);
    let local = |w: Vec3| Vec3::new(w.dot(t), w.dot(b), w.dot(n));
    let mut polygon = Polygon::EMPTY;
    for j in 0..light.count {
        polygon.vertices[j] = local(light.vertices[j] - position);
    }
    polygon.count = light.count;
    let clipped = clip_to_horizon(&polygon);
    let (kd, has_specular) = match *material {
        MaterialKind::Lambert { kd } => (kd, false),
        MaterialKind::BlinnPhong { kd, .. } => (kd, true),
        MaterialKind::Ggx { albedo, .. } => (albedo, true),
    };
    let sampler = match settings.technique {
        PolygonSampling::ProjectedSolidAngle => {
            LightSampler::Projected(prepare_projected_solid_angle(&clipped))
        }
        PolygonSampling::SolidAngle => LightSampler::Solid(prepare_solid_angle(&clipped)),
    };
    let projected = match &sampler {
        LightSampler::Projected(s) => s.projected_solid_angle(),
        LightSampler::Solid(_) => projected_solid_angle(&clipped),
    };
    let diffuse = kd * radiance * projected;
    let lit = projected > 0.0;
    if !has_specular || !lit {
        return (diffuse, Vec3::ZERO);
    }

    let v_local = local(v);
    // The MIS coefficients: each technique's one-sample estimate at its most likely direction.
    let centre = safe_normalize(clipped.as_slice().iter().map(|w| safe_normalize(*w)).sum());
    let c_light = ratio(specular(centre, v_local, material), sampler.density(centre)).max_element();
    let mirror = Vec3::new(-v_local.x, -v_local.y, v_local.z);
    let c_brdf =
        ratio(specular(mirror, v_local, material), brdf_density(mirror, v_local, material)).max_element();
    let coefficients = [c_light, c_brdf];
    let visibility = settings.mis_visibility;

    let mut sum = Vec3::ZERO;
    let count = settings.samples.max(1);
    for i in 0..count {
        let u = sample_point(i, count);
        let (l, p_light) = sampler.sample(u);
        if p_light > 0.0 && l.z > 0.0 {
            let p_brdf = brdf_density(l, v_local, material);
            let w = super::polygon::clamped_optimal_mis_weights([p_light, p_brdf], coefficients, visibility);
            sum += specular(l, v_local, material) * (w[0] / p_light);
        }
        let (l, p_brdf) = sample_brdf([u[1], u[0]], v_local, material);
        if p_brdf > 0.0 && l.z > 0.0 {
            let p_light = sampler.density(l);
            if p_light > 0.0 {
                let w =
                    super::polygon::clamped_optimal_mis_weights([p_light, p_brdf], coefficients, visibility);
                sum += specular(l, v_local, material) * (w[1] / p_brdf);
            }
        }
    }
    (diffuse, sum * radiance * (1.0 / count as f32))
}

#[cfg(test)]
mod tests;
