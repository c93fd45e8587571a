//! Clipping a polygon to the horizon (supplement A.1). Twin of `glsl/include/polygon/clip.glsl`,
//! operation for operation; `tests/polygon_gpu.rs` checks that the two agree.

use super::arithmetic::{kahan, next_index};
use super::types::{Polygon, MAX_CLIPPED_VERTICES};

use glam::Vec3;

/// Clips a convex polygon (3 to [`MAX_POLYGON_VERTICES`] vertices) to the closed upper half-space
/// z ≥ 0 (supplement A.1). Vertices with z ≥ 0 are kept; every edge that strictly crosses z = 0
/// gets a new vertex with z = 0 exactly, so vertices lying on the horizon are never duplicated.
/// The winding is kept. A result with fewer than three vertices is empty (count 0). A convex
/// planar input yields at most [`MAX_CLIPPED_VERTICES`] vertices; an input that would yield more
/// (only possible when it is not planar) also yields the empty polygon.
///
/// [`MAX_POLYGON_VERTICES`]: super::MAX_POLYGON_VERTICES
pub fn clip_to_horizon(polygon: &Polygon) -> Polygon {
    let mut clipped = Polygon::EMPTY;
    let count = polygon.count;
    if !(3..=MAX_CLIPPED_VERTICES).contains(&count) {
        return clipped;
    }
    let mut out = 0;
    let mut overflow = false;
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        let a = polygon.vertices[j];
        let b = polygon.vertices[next_index(j, count)];
        if a.z >= 0.0 {
            if out < MAX_CLIPPED_VERTICES {
                clipped.vertices[out] = a;
                out += 1;
            } else {
                overflow = true;
            }
        }
        if (a.z > 0.0 && b.z < 0.0) || (a.z < 0.0 && b.z > 0.0) {
            // (p.xy q.z − q.xy p.z) / (q.z − p.z) with p above and q below (so that both traversal
            // directions of an edge give the same point): each numerator is a 2×2 determinant, and
            // Kahan's algorithm keeps the crossing accurate to a few ulps even close to the shading
            // point (p + t (q − p) would leave an absolute error of ε|p|).
            let (p, q) = if a.z > 0.0 { (a, b) } else { (b, a) };
            let inverse_height = 1.0 / (q.z - p.z);
            let crossing = Vec3::new(
                kahan(p.x, q.z, q.x, p.z) * inverse_height,
                kahan(p.y, q.z, q.y, p.z) * inverse_height,
                0.0,
            );
            if out < MAX_CLIPPED_VERTICES {
                clipped.vertices[out] = crossing;
                out += 1;
            } else {
                overflow = true;
            }
        }
    }
    clipped.count = if out >= 3 && !overflow { out } else { 0 };
    clipped
}
