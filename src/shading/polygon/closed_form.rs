//! The closed-form projected solid angle: Lambert's edge sum, evaluated without cancellation (the
//! module documentation has why). Twin of `glsl/include/polygon/closed_form.glsl`, operation for
//! operation; `tests/polygon_gpu.rs` checks that the two agree.

use super::arithmetic::{cross_stable, kahan, next_index, unit_difference};
use super::types::{Polygon, EMPTY_RELATIVE_THRESHOLD, MAX_CLIPPED_VERTICES};

use glam::Vec3;

/// `γ/sin γ − 1` times `c.z` for an edge with `c = v̂ⱼ × v̂ⱼ₊₁` (`|c| = sin γ`) and `cos γ`. A
/// series near 0 keeps the relative accuracy of this small term; an edge between antipodal
/// directions (only when the polygon's plane contains the shading point) contributes 0.
pub(super) fn edge_segment_term(c: Vec3, cos_angle: f32) -> f32 {
    let sine = c.length();
    let angle = sine.atan2(cos_angle);
    if angle < 0.5 {
        // x/sin x − 1 = x²/6 + 7x⁴/360 + 31x⁶/15120 + 127x⁸/604800 + 73x¹⁰/3421440 + O(x¹²)
        let x2 = angle * angle;
        let series = x2
            * (1.0 / 6.0
                + x2 * (7.0 / 360.0
                    + x2 * (31.0 / 15120.0 + x2 * (127.0 / 604800.0 + x2 * (73.0 / 3421440.0)))));
        series * c.z
    } else if sine > 0.0 {
        angle * (c.z / sine) - c.z
    } else {
        0.0
    }
}

/// The signed projected solid angle (positive iff the polygon winds counterclockwise about +z)
/// of a polygon on or above the horizon, and 0 for an empty or degenerate one. See
/// [`projected_solid_angle`].
pub(super) fn signed_projected_solid_angle(polygon: &Polygon) -> f32 {
    let count = polygon.count;
    if count < 3 {
        return 0.0;
    }
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        if polygon.vertices[j] == Vec3::ZERO {
            // A vertex at the shading point: the polygon's plane contains it.
            return 0.0;
        }
    }
    let origin = polygon.vertices[0];
    let mut fan = 0.0;
    let mut segments = 0.0;
    let mut magnitude = 0.0;
    let mut previous_offset = Vec3::ZERO;
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        let a = polygon.vertices[j];
        let b = polygon.vertices[next_index(j, count)];
        // Shoelace term of the projected unit directions, relative to direction 0
        let offset = unit_difference(b, origin);
        let shoelace = kahan(previous_offset.x, offset.y, previous_offset.y, offset.x);
        previous_offset = offset;
        // Curved part of the edge: the great-circle arc bulges beyond its chord
        let edge = unit_difference(b, a);
        let c = cross_stable(a.normalize(), edge);
        let segment = edge_segment_term(c, 1.0 - 0.5 * edge.length_squared());
        fan += shoelace;
        segments += segment;
        magnitude += shoelace.abs() + segment.abs();
    }
    let total = 0.5 * (fan + segments);
    if total.abs() > 0.5 * EMPTY_RELATIVE_THRESHOLD * magnitude {
        total
    } else {
        0.0
    }
}

/// The projected solid angle `∫ cos θ dω` of a polygon clipped to the horizon (e.g. by
/// [`clip_to_horizon`]), in closed form: Lambert's sum over the edges `½ Σ γⱼ (n̂ⱼ·z)` with `γⱼ`
/// the angle the edge subtends and `n̂ⱼ` the unit normal of the plane through the shading point
/// and the edge. It equals π × the irradiance factor: a Lambertian emitter of radiance `L` lights
/// a diffuse surface whose BRDF value is `kd` (this project's convention) with outgoing radiance
/// `kd · L · projected_solid_angle`. Either winding gives the same (non-negative) value. The sum
/// is evaluated as shoelace + segment terms (see the module documentation), accurate to a few ulps
/// also for tiny polygons. Empty polygons, polygons below the horizon (after clipping), edge-on
/// polygons (the shading point in their plane) and zero-length edges give 0 or contribute 0.
///
/// [`clip_to_horizon`]: super::clip_to_horizon
pub fn projected_solid_angle(clipped: &Polygon) -> f32 {
    signed_projected_solid_angle(clipped).abs()
}

/// Converts a density with respect to projected solid angle into one with respect to solid
/// angle: multiplies by `cos θ = direction.z` (0 below the horizon). `direction` is a unit vector.
pub fn projected_to_solid_angle_density(projected_density: f32, direction: Vec3) -> f32 {
    projected_density * direction.z.max(0.0)
}
