//! The polygon module's constants and plain data: [`Polygon`] and the two samplers' states,
//! [`ProjectedSolidAngleSampler`] and [`SolidAngleSampler`], with their empty values. Twin of
//! `glsl/include/polygon/types.glsl` (which also defines `MAX_POLYGON_VERTICES` and
//! `DEFAULT_MIS_VISIBILITY`; here they are the scene's, [`crate::scene`]); `tests/polygon_gpu.rs`
//! checks that the two agree.

pub use crate::scene::{DEFAULT_MIS_VISIBILITY, MAX_POLYGON_VERTICES};

use glam::{Vec2, Vec3};

/// Most vertices a polygon clipped to the horizon may have.
pub const MAX_CLIPPED_VERTICES: usize = MAX_POLYGON_VERTICES + 1;
/// Most triangles in the fan of a clipped polygon.
pub(super) const MAX_FAN_TRIANGLES: usize = MAX_CLIPPED_VERTICES - 2;
/// A projected solid angle or solid angle below this fraction of the magnitude of the terms it
/// is summed from is rounding noise (e.g. the shading point in the polygon's plane): it counts
/// as zero.
pub(super) const EMPTY_RELATIVE_THRESHOLD: f32 = 32.0 * f32::EPSILON;
/// Directions this close (in radians) outside an edge's great circle still count as inside, so
/// that samples rounded onto the wrong side of an edge keep their density.
pub(super) const INSIDE_TOLERANCE: f32 = 4.0 * f32::EPSILON;
/// Algorithm 3 skips the iteration when the sector-relative random number is this close to 0
/// or 1: the initialisation is exact there and the iteration may be unstable.
pub(super) const ITERATION_MARGIN: f32 = 1.0e-5;
/// |u|² above which an ellipse counts as nearly degenerate in the decentral case (see
/// [`prepare_projected_solid_angle`]).
///
/// [`prepare_projected_solid_angle`]: super::prepare_projected_solid_angle
pub(super) const STEEP_ELLIPSE_SQUARED: f32 = 1.0e6;
/// Iterations of Algorithm 3 (the paper's choice: local cubic convergence, A.5).
pub(super) const ITERATION_COUNT: usize = 2;

/// A convex planar polygon as a fixed-size vertex array plus a count (the GLSL layout). Vertices
/// are positions relative to the shading point in the shading frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Polygon {
    /// The vertices; only the first `count` are meaningful.
    pub vertices: [Vec3; MAX_CLIPPED_VERTICES],
    /// The number of vertices; 0 means empty.
    pub count: usize,
}

impl Polygon {
    /// The polygon without vertices.
    pub const EMPTY: Polygon = Polygon { vertices: [Vec3::ZERO; MAX_CLIPPED_VERTICES], count: 0 };

    /// A polygon from at most [`MAX_CLIPPED_VERTICES`] vertices.
    pub fn new(vertices: &[Vec3]) -> Polygon {
        assert!(vertices.len() <= MAX_CLIPPED_VERTICES, "at most {MAX_CLIPPED_VERTICES} vertices");
        let mut polygon = Polygon::EMPTY;
        polygon.vertices[..vertices.len()].copy_from_slice(vertices);
        polygon.count = vertices.len();
        polygon
    }

    /// The meaningful vertices.
    pub fn as_slice(&self) -> &[Vec3] {
        &self.vertices[..self.count]
    }
}

/// Everything projected-solid-angle sampling needs from one polygon and shading point (the
/// first half of Algorithm 4): plain, fixed-size and `Copy`, like its GLSL twin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectedSolidAngleSampler {
    /// Vertex count; 0 when there is nothing to sample.
    pub(super) count: usize,
    /// The clipped polygon, counterclockwise about +z (for [`projected_solid_angle_density`]).
    ///
    /// [`projected_solid_angle_density`]: super::projected_solid_angle_density
    pub(super) vertices: [Vec3; MAX_CLIPPED_VERTICES],
    /// Sector boundary directions: vertex xy in polygon order (central case) or sorted
    /// counterclockwise (decentral case).
    pub(super) sector_dirs: [Vec2; MAX_CLIPPED_VERTICES],
    /// Per sector boundary the ellipse of the next edge counterclockwise (Algorithm 4).
    pub(super) ellipses: [Vec2; MAX_CLIPPED_VERTICES],
    /// The inner ellipse of the first sector; not inner (`(1, 0)`) in the central case.
    pub(super) inner_ellipse_0: Vec2,
    /// Projected solid angle per sector (used to select a sector).
    pub(super) sector_areas: [f32; MAX_CLIPPED_VERTICES],
    /// Sum of `sector_areas`.
    pub(super) sector_total: f32,
    /// Whether `sector_areas` hold sector angles instead (all areas were lost to rounding).
    pub(super) proxy_sector_areas: bool,
    /// The closed-form projected solid angle (normalises the density).
    pub(super) projected_solid_angle: f32,
}

impl ProjectedSolidAngleSampler {
    /// The sampler of an empty polygon.
    pub const EMPTY: ProjectedSolidAngleSampler = ProjectedSolidAngleSampler {
        count: 0,
        vertices: [Vec3::ZERO; MAX_CLIPPED_VERTICES],
        sector_dirs: [Vec2::ZERO; MAX_CLIPPED_VERTICES],
        ellipses: [Vec2::ZERO; MAX_CLIPPED_VERTICES],
        inner_ellipse_0: Vec2::X,
        sector_areas: [0.0; MAX_CLIPPED_VERTICES],
        sector_total: 0.0,
        proxy_sector_areas: false,
        projected_solid_angle: 0.0,
    };

    /// The closed-form projected solid angle of the polygon ([`projected_solid_angle`]).
    ///
    /// [`projected_solid_angle`]: super::projected_solid_angle
    pub fn projected_solid_angle(&self) -> f32 {
        self.projected_solid_angle
    }

    /// Whether there is nothing to sample (zero projected solid angle); samples then have
    /// density 0.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }
}

/// Everything solid-angle sampling needs from one polygon and shading point: the polygon as a
/// triangle fan around vertex 0, with the per-triangle quantities of Algorithm 5. Plain,
/// fixed-size and `Copy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolidAngleSampler {
    /// Vertex count; 0 when there is nothing to sample.
    pub(super) count: usize,
    /// Unit directions to the vertices.
    pub(super) directions: [Vec3; MAX_CLIPPED_VERTICES],
    /// For the fan triangle j with vertices (v̂ⱼ₊₁, v̂₀, v̂ⱼ₊₂): (G₀, G₁, G₂) of Algorithm 5, i.e.
    /// |det(v̂ⱼ₊₁, v̂₀, v̂ⱼ₊₂)|, v̂ⱼ₊₁·v̂ⱼ₊₂ + v̂₀·v̂ⱼ₊₂ and 1 + v̂ⱼ₊₁·v̂₀.
    pub(super) triangles: [Vec3; MAX_FAN_TRIANGLES],
    /// Solid angle of the fan up to and including triangle j.
    pub(super) fan_solid_angles: [f32; MAX_FAN_TRIANGLES],
    /// Total solid angle.
    pub(super) solid_angle: f32,
    /// The sign `o` (±1, from the winding) such that `o (v̂ⱼ × v̂ⱼ₊₁)·ω ≥ 0` for every edge j
    /// exactly when ω is inside.
    pub(super) orientation: f32,
}

impl SolidAngleSampler {
    /// The sampler of an empty polygon.
    pub const EMPTY: SolidAngleSampler = SolidAngleSampler {
        count: 0,
        directions: [Vec3::ZERO; MAX_CLIPPED_VERTICES],
        triangles: [Vec3::ZERO; MAX_FAN_TRIANGLES],
        fan_solid_angles: [0.0; MAX_FAN_TRIANGLES],
        solid_angle: 0.0,
        orientation: 1.0,
    };

    /// The solid angle of the polygon.
    pub fn solid_angle(&self) -> f32 {
        self.solid_angle
    }

    /// Whether there is nothing to sample (zero solid angle); samples then have density 0.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }
}
