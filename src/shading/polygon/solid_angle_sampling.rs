//! Solid-angle sampling of the polygon's triangle fan (Algorithm 5, with the Householder
//! determinant of Sec. C) and its density. Twin of
//! `glsl/include/polygon/solid_angle_sampling.glsl`, operation for operation;
//! `tests/polygon_gpu.rs` checks that the two agree.

use super::arithmetic::{det2, mix, unit_difference};
use super::projected_sampling::is_inside;
use super::types::{
    Polygon, SolidAngleSampler, EMPTY_RELATIVE_THRESHOLD, MAX_CLIPPED_VERTICES, MAX_FAN_TRIANGLES,
};

use glam::{Vec2, Vec3};

/// Prepares solid-angle sampling of a convex polygon (3 to [`MAX_CLIPPED_VERTICES`] vertices,
/// clipped or not, either winding): splits it into the fan of triangles (v̂ⱼ₊₁, v̂₀, v̂ⱼ₊₂) and
/// computes each triangle's solid angle `2 atan2(G₀, G₁ + G₂)` (van Oosterom and Strackee). `G₀`,
/// the determinant, uses the Householder reflection `H` that maps v̂₀ to ±e₀ (Sec. C): applied to
/// the columns `v̂ⱼ − v̂₀` (formed without cancellation) it leaves a 2×2 minor of small, accurate
/// numbers.
pub fn prepare_solid_angle(polygon: &Polygon) -> SolidAngleSampler {
    let mut sampler = SolidAngleSampler::EMPTY;
    let count = polygon.count;
    if !(3..=MAX_CLIPPED_VERTICES).contains(&count) {
        return sampler;
    }
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        if polygon.vertices[j] == Vec3::ZERO {
            return sampler;
        }
        sampler.directions[j] = polygon.vertices[j].normalize();
    }
    let origin = polygon.vertices[0];
    let apex = sampler.directions[0];
    // H = I − 2hhᵀ with h ∝ v̂₀ − σe₀ maps v̂₀ to σe₀. For a vector d, (Hd).yz =
    // d.yz − v̂₀.yz (v̂₀·d − σ d.x) / (|v̂₀.x| + 1).
    let sigma = if apex.x > 0.0 { -1.0 } else { 1.0 };
    let householder_yz = Vec2::new(apex.y, apex.z) / (apex.x.abs() + 1.0);
    let mut previous_offset = unit_difference(polygon.vertices[1], origin);
    let mut total = 0.0;
    let mut signed_total = 0.0;
    let mut magnitude = 0.0;
    for j in 0..MAX_FAN_TRIANGLES {
        if j + 2 >= count {
            break;
        }
        let a = sampler.directions[j + 1];
        let b = sampler.directions[j + 2];
        let offset_a = previous_offset;
        let offset_b = unit_difference(polygon.vertices[j + 2], origin);
        previous_offset = offset_b;
        // v̂₀·d = −|d|²/2 exactly for d = v̂ − v̂₀
        let reflected_a = Vec2::new(offset_a.y, offset_a.z)
            - householder_yz * (-0.5 * offset_a.length_squared() - sigma * offset_a.x);
        let reflected_b = Vec2::new(offset_b.y, offset_b.z)
            - householder_yz * (-0.5 * offset_b.length_squared() - sigma * offset_b.x);
        // det(v̂ₐ, v̂₀, v̂_b) = det(dₐ, v̂₀, d_b) = σ · det of the yz minor after H
        let signed_det = sigma * det2(reflected_a, reflected_b);
        let g_0 = signed_det.abs();
        let g_1 = a.dot(b) + apex.dot(b);
        let g_2 = 1.0 + a.dot(apex);
        let triangle_solid_angle = 2.0 * g_0.atan2(g_1 + g_2);
        sampler.triangles[j] = Vec3::new(g_0, g_1, g_2);
        total += triangle_solid_angle;
        sampler.fan_solid_angles[j] = total;
        signed_total += triangle_solid_angle.copysign(signed_det);
        magnitude += triangle_solid_angle;
    }
    if !(total > 0.0 && total.is_finite()) || signed_total.abs() <= EMPTY_RELATIVE_THRESHOLD * magnitude {
        return SolidAngleSampler::EMPTY;
    }
    // det(v̂ⱼ₊₁, v̂₀, v̂ⱼ₊₂) > 0 means (v̂ⱼ₊₁ × v̂ⱼ₊₂)·v̂₀ < 0: the edges' normals point outwards
    sampler.orientation = if signed_total > 0.0 { -1.0 } else { 1.0 };
    sampler.count = count;
    sampler.solid_angle = total;
    sampler
}

/// Samples a direction uniformly with respect to solid angle within the polygon from
/// `u ∈ [0, 1)²` (Algorithm 5 on the fan triangle that `u[0]` selects). Returns the unit direction
/// and its density with respect to solid angle, `1 / solid_angle`. The direction may lie below the
/// horizon if the polygon was not clipped. An empty sampler returns `(+z, 0)`.
pub fn sample_solid_angle(sampler: &SolidAngleSampler, u: [f32; 2]) -> (Vec3, f32) {
    if sampler.is_empty() {
        return (Vec3::Z, 0.0);
    }
    let count = sampler.count;
    let target = u[0] * sampler.solid_angle;
    // Select the triangle; a target beyond the last non-empty triangle (rounding) clamps to its end
    let mut selected = 0;
    let mut sub_solid_angle = 0.0;
    let mut previous_fan = 0.0;
    for j in 0..MAX_FAN_TRIANGLES {
        if j + 2 >= count {
            break;
        }
        let fan = sampler.fan_solid_angles[j];
        if fan > previous_fan {
            selected = j;
            sub_solid_angle = (target - previous_fan).min(fan - previous_fan);
        }
        if target < fan {
            break;
        }
        previous_fan = fan;
    }
    let [g_0, g_1, g_2] = sampler.triangles[selected].to_array();
    let a = sampler.directions[selected + 1];
    let apex = sampler.directions[0];
    let b = sampler.directions[selected + 2];
    // The point on the arc from a to b that cuts off a triangle (a, apex, b') of the wanted
    // solid angle: b' = −a + 2 (a·r)/|r|² r with
    // r = (G₀ cos(A/2) − G₁ sin(A/2)) a + G₂ sin(A/2) b
    let half = 0.5 * sub_solid_angle;
    let (sin_half, cos_half) = half.sin_cos();
    let r = (g_0 * cos_half - g_1 * sin_half) * a + (g_2 * sin_half) * b;
    let new_b = (2.0 * a.dot(r) / r.length_squared()) * r - a;
    // Uniform in cos of the distance from the apex along the arc from apex to b'. The paper's
    // t' = √((1 − s²)/(1 − s₂²)) with 1 − s = ξ₁(1 − s₂) is t' = √(ξ₁ (1 + s)/(1 + s₂)), which
    // does not cancel for small triangles.
    let s_2 = apex.dot(new_b);
    let s = mix(1.0, s_2, u[1]);
    let t = (u[1] * (1.0 + s) / (1.0 + s_2).max(f32::MIN_POSITIVE)).max(0.0).sqrt();
    let direction = (s - t * s_2) * apex + t * new_b;
    (direction, 1.0 / sampler.solid_angle)
}

/// The density with respect to solid angle with which [`sample_solid_angle`] produces the unit
/// `direction`: `1 / solid_angle` inside the polygon, 0 outside or for an empty sampler.
pub fn solid_angle_density(sampler: &SolidAngleSampler, direction: Vec3) -> f32 {
    if sampler.is_empty() || !is_inside(&sampler.directions, sampler.count, sampler.orientation, direction) {
        return 0.0;
    }
    1.0 / sampler.solid_angle
}
