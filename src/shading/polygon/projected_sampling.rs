//! Projected-solid-angle sampling (Algorithm 4): preparing the sectors, sampling a direction and
//! the density. Twin of `glsl/include/polygon/projected_sampling.glsl`, operation for operation;
//! `tests/polygon_gpu.rs` checks that the two agree.

use super::arithmetic::{cross_stable, det2, next_index, rotate_90};
use super::closed_form::signed_projected_solid_angle;
use super::ellipse::{
    area_between_ellipses_in_sector, ellipse_area_in_sector, ellipse_from_edge, ellipse_quadratic_form,
    ellipse_rsqrt_det, ellipse_transform, is_degenerate, is_inner, sample_sector_between_ellipses,
};
use super::types::{
    Polygon, ProjectedSolidAngleSampler, INSIDE_TOLERANCE, MAX_CLIPPED_VERTICES, STEEP_ELLIPSE_SQUARED,
};

use glam::{Vec2, Vec3};

impl ProjectedSolidAngleSampler {
    /// Whether the polygon contains the zenith (the central case of the paper), where each
    /// sector is bounded by a single ellipse.
    pub fn is_central(&self) -> bool {
        !is_inner(self.inner_ellipse_0)
    }
}

/// Compares sector boundaries `lhs < rhs` and swaps them (with their ellipses) when `rhs` is
/// clockwise of `lhs`; on a tie (the same direction) a degenerate ellipse goes first (A.2,
/// rule 3). [`det2`] agrees exactly with the z-component of [`cross_stable`] used for the edges,
/// so the two vertices of a degenerate edge tie exactly.
pub(super) fn compare_and_swap(sampler: &mut ProjectedSolidAngleSampler, lhs: usize, rhs: usize) {
    let det = det2(sampler.sector_dirs[lhs], sampler.sector_dirs[rhs]);
    let swap = det < 0.0
        || (det == 0.0 && is_degenerate(sampler.ellipses[rhs]) && !is_degenerate(sampler.ellipses[lhs]));
    if swap {
        sampler.sector_dirs.swap(lhs, rhs);
        sampler.ellipses.swap(lhs, rhs);
    }
}

/// Prepares projected-solid-angle sampling of a polygon clipped to the horizon (the first half of
/// Algorithm 4). Either winding is accepted. Assigns to each vertex the ellipse of the next edge
/// counterclockwise about the zenith; if some edge runs clockwise the zenith is outside
/// (decentral case): the vertices are sorted counterclockwise and every sector lies between an
/// inner and an outer ellipse, else (central case) each sector is bounded by one ellipse. In the
/// decentral case, sectors bounded by a nearly degenerate ellipse get no area (module
/// documentation), and if rounding leaves no sector with area, sectors are weighted by their angle
/// and sampled without Algorithm 3's iteration (only polygons a few ε thin as seen from the
/// shading point); the density is the closed form's either way.
pub fn prepare_projected_solid_angle(clipped: &Polygon) -> ProjectedSolidAngleSampler {
    let mut sampler = ProjectedSolidAngleSampler::EMPTY;
    let count = clipped.count;
    let signed = signed_projected_solid_angle(clipped);
    if count < 3 || signed == 0.0 || !signed.is_finite() {
        return sampler;
    }
    // Counterclockwise about +z
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        sampler.vertices[j] = clipped.vertices[if signed > 0.0 { j } else { count - 1 - j }];
        sampler.sector_dirs[j] = sampler.vertices[j].truncate();
    }
    // Associate vertices with ellipses (Algorithm 4): an outer edge j starts at vertex j in
    // angular order, an inner edge j at vertex j + 1. The inner edge that ends at the clockwise
    // end of the polygon would be lost; it is the inner ellipse of the first sector.
    let ellipse_0 = ellipse_from_edge(sampler.vertices[0], sampler.vertices[1]);
    let mut previous = ellipse_0;
    for j in 1..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        let current = ellipse_from_edge(sampler.vertices[j], sampler.vertices[next_index(j, count)]);
        sampler.ellipses[j] = if is_inner(current) { previous } else { current };
        if is_inner(previous) && !is_inner(current) {
            sampler.inner_ellipse_0 = previous;
        }
        previous = current;
    }
    sampler.ellipses[0] = if is_inner(ellipse_0) { previous } else { ellipse_0 };
    if is_inner(previous) && !is_inner(ellipse_0) {
        sampler.inner_ellipse_0 = previous;
    }
    // Projected solid angle per sector
    let mut total = 0.0;
    if sampler.is_central() {
        for j in 0..MAX_CLIPPED_VERTICES {
            if j >= count {
                break;
            }
            let ellipse = sampler.ellipses[j];
            let area = ellipse_area_in_sector(
                ellipse,
                ellipse_rsqrt_det(ellipse),
                sampler.sector_dirs[j],
                sampler.sector_dirs[next_index(j, count)],
            );
            sampler.sector_areas[j] = area;
            total += area;
        }
    } else {
        // Odd-even transposition sort: `count` passes sort `count` elements. The vertices span
        // less than 180° about the zenith, so "counterclockwise of" is a strict order.
        for pass in 0..MAX_CLIPPED_VERTICES {
            if pass >= count {
                break;
            }
            for k in 0..MAX_CLIPPED_VERTICES / 2 {
                let lhs = 2 * k + (pass & 1);
                if lhs + 1 < count {
                    compare_and_swap(&mut sampler, lhs, lhs + 1);
                }
            }
        }
        let mut inner = sampler.inner_ellipse_0;
        let mut outer = sampler.ellipses[0];
        for j in 0..MAX_CLIPPED_VERTICES - 1 {
            if j + 1 >= count {
                break;
            }
            if j > 0 {
                let ellipse = sampler.ellipses[j];
                if is_inner(ellipse) {
                    inner = ellipse;
                } else {
                    outer = ellipse;
                }
            }
            // Near-degenerate ellipses (A.2 with rounding) bound sectors too thin to sample in f32
            let steep = inner.length_squared().max(outer.length_squared()) > STEEP_ELLIPSE_SQUARED;
            let area = if steep {
                0.0
            } else {
                area_between_ellipses_in_sector(
                    inner,
                    outer,
                    sampler.sector_dirs[j],
                    sampler.sector_dirs[j + 1],
                )
            };
            sampler.sector_areas[j] = area;
            total += area;
        }
    }
    if !sampler.is_central() && total <= 0.0 {
        // Rounding swamped every sector area (the xy-plane resolves a polygon near the horizon
        // only to ε/z radians): select sectors by their angle instead and sample them without the
        // area-based iteration. The density stays 1/Ω_proj: exact for the diffuse part.
        sampler.proxy_sector_areas = true;
        total = 0.0;
        for j in 0..MAX_CLIPPED_VERTICES - 1 {
            if j + 1 >= count {
                break;
            }
            let angle = det2(sampler.sector_dirs[j].normalize(), sampler.sector_dirs[j + 1].normalize());
            sampler.sector_areas[j] = angle.max(0.0);
            total += sampler.sector_areas[j];
        }
    }
    if !(total > 0.0 && total.is_finite()) {
        return ProjectedSolidAngleSampler::EMPTY;
    }
    sampler.count = count;
    sampler.sector_total = total;
    sampler.projected_solid_angle = signed.abs();
    sampler
}

/// Samples a direction uniformly with respect to projected solid angle within the polygon (the
/// second half of Algorithm 4) from `u ∈ [0, 1)²`. Returns the unit direction (z ≥ 0) and its
/// density with respect to projected solid angle, `1 / projected_solid_angle`; convert with
/// [`projected_to_solid_angle_density`]. An empty sampler returns `(+z, 0)`.
///
/// [`projected_to_solid_angle_density`]: super::projected_to_solid_angle_density
pub fn sample_projected_solid_angle(sampler: &ProjectedSolidAngleSampler, u: [f32; 2]) -> (Vec3, f32) {
    if sampler.is_empty() {
        return (Vec3::Z, 0.0);
    }
    let count = sampler.count;
    let mut target = u[0] * sampler.sector_total;
    // Select the sector; a target beyond the last non-empty sector (rounding) clamps to its end
    let mut selected_area = 0.0;
    let mut selected_target = 0.0;
    let mut dir_0 = Vec2::X;
    let mut dir_1 = Vec2::Y;
    let mut inner = sampler.inner_ellipse_0;
    let mut outer = sampler.ellipses[0];
    let mut selected_inner = inner;
    let mut selected_outer = outer;
    let central = sampler.is_central();
    let sector_count = if central { count } else { count - 1 };
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= sector_count {
            break;
        }
        let ellipse = sampler.ellipses[j];
        if central || j == 0 {
            outer = ellipse;
        } else if is_inner(ellipse) {
            inner = ellipse;
        } else {
            outer = ellipse;
        }
        let area = sampler.sector_areas[j];
        if area > 0.0 {
            selected_area = area;
            selected_target = target.min(area);
            selected_inner = inner;
            selected_outer = outer;
            dir_0 = sampler.sector_dirs[j];
            dir_1 = sampler.sector_dirs[next_index(j, count)];
        }
        if target < area {
            break;
        }
        target -= area;
    }
    let w = if central {
        // Rotate s₀ within the ellipse: with C = L Lᵀ, the angle about the origin in the space
        // mapped by Lᵀ is 2 √det C × area, and back in the plane that rotation is
        // cos φ · √det C · s₀ + sin φ · R C s₀ (up to a positive factor).
        let sqrt_det = (1.0 + selected_outer.length_squared()).sqrt();
        let angle = 2.0 * selected_target * sqrt_det;
        let direction = (angle.cos() * sqrt_det) * dir_0
            + angle.sin() * rotate_90(ellipse_transform(selected_outer, dir_0));
        // Uniform in squared radius inside the ellipse
        direction * (u[1] / ellipse_quadratic_form(selected_outer, direction)).max(0.0).sqrt()
    } else {
        let sector_u = [(selected_target / selected_area).min(1.0), u[1]];
        sample_sector_between_ellipses(
            sector_u,
            selected_target,
            selected_inner,
            selected_outer,
            dir_0,
            dir_1,
            !sampler.proxy_sector_areas,
        )
    };
    let z = (1.0 - w.length_squared()).max(0.0).sqrt();
    (w.extend(z), 1.0 / sampler.projected_solid_angle)
}

/// Whether the unit `direction` lies in the convex spherical polygon (vertices in `vertices`,
/// winding given by `orientation` = ±1), up to [`INSIDE_TOLERANCE`] radians.
pub(super) fn is_inside(
    vertices: &[Vec3; MAX_CLIPPED_VERTICES],
    count: usize,
    orientation: f32,
    direction: Vec3,
) -> bool {
    for j in 0..MAX_CLIPPED_VERTICES {
        if j >= count {
            break;
        }
        let normal = cross_stable(vertices[j], vertices[next_index(j, count)]) * orientation;
        if normal.dot(direction) < -INSIDE_TOLERANCE * normal.length() {
            return false;
        }
    }
    true
}

/// The density with respect to projected solid angle with which [`sample_projected_solid_angle`]
/// produces the unit `direction`: `1 / projected_solid_angle` inside the clipped polygon, 0
/// outside, below the horizon or for an empty sampler. For MIS with other techniques.
pub fn projected_solid_angle_density(sampler: &ProjectedSolidAngleSampler, direction: Vec3) -> f32 {
    if sampler.is_empty()
        || direction.z <= 0.0
        || !is_inside(&sampler.vertices, sampler.count, 1.0, direction)
    {
        return 0.0;
    }
    1.0 / sampler.projected_solid_angle
}
