//! A directional light's map fitted to what the camera sees. The light's frame
//! ([`DirectionalFrame`]) looks along the light at the scene's box; its map is a square of the
//! light's plane, and its depth always spans the whole box, so that a caster the camera does not
//! see still shadows what it sees. What the camera sees of the box ([`DirectionalFrame::seen`])
//! is the box clipped by the view frustum; [`DirectionalFit`] says when the square a map was
//! drawn for no longer serves a view (part of what it sees lies outside, or the square is much
//! wider than it needs) and which square to draw it for instead.

use super::camera::look_at;
use crate::scene::Camera;
use glam::{DVec3, Mat4, Vec2, Vec3, Vec4};

/// A square of a directional light's plane, in its frame's view space (x and y).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Square {
    pub centre: Vec2,
    pub half: f32,
}

impl Square {
    /// Whether every point of the rectangle `lo..hi` lies in the square (up to a millionth of
    /// its width, for the rounding of the fit).
    pub fn holds(&self, lo: Vec2, hi: Vec2) -> bool {
        let slack = 1e-6 * self.half;
        let (min, max) = (self.centre - self.half - slack, self.centre + self.half + slack);
        lo.cmpge(min).all() && hi.cmple(max).all()
    }
}

/// A directional light travelling along a direction, seen from its side of the scene's box:
/// the view looking along the light, the depth range holding the box, and the square holding it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalFrame {
    view: Mat4,
    near: f32,
    far: f32,
    /// The square holding the whole box (a 1 % margin around its image).
    pub whole: Square,
}

impl DirectionalFrame {
    /// The frame of a light travelling along `direction` over the box `lo`..`hi`.
    pub fn new(direction: Vec3, lo: Vec3, hi: Vec3) -> DirectionalFrame {
        let centre = 0.5 * (lo + hi);
        let radius = (0.5 * (hi - lo).length()).max(1e-6);
        let up = if direction.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
        let view = look_at(centre - 2.0 * radius * direction, centre, up);
        let (mut min, mut max) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for corner in box_corners(lo, hi) {
            let p = view.transform_point3(corner);
            (min, max) = (min.min(p), max.max(p));
        }
        let half = (0.5 * (max - min).truncate().max_element() * 1.01).max(1e-6);
        let depth = (max.z - min.z).max(1e-6);
        // The view looks along -z: the nearest point has the largest z.
        let (near, far) = (-max.z - 0.01 * depth, -min.z + 0.01 * depth);
        let whole = Square { centre: 0.5 * (min + max).truncate(), half };
        DirectionalFrame { view, near, far, whole }
    }

    /// The map of `square`: world to its clip space (depth 0 to 1 over the box), and its width
    /// in world units.
    pub fn map(&self, square: Square) -> (Mat4, f32) {
        let (near, far, half, mid) = (self.near, self.far, square.half, square.centre);
        let projection = Mat4::from_cols(
            Vec4::new(1.0 / half, 0.0, 0.0, 0.0),
            Vec4::new(0.0, 1.0 / half, 0.0, 0.0),
            Vec4::new(0.0, 0.0, -1.0 / (far - near), 0.0),
            Vec4::new(-mid.x / half, -mid.y / half, -near / (far - near), 1.0),
        );
        (projection * self.view, 2.0 * half)
    }

    /// The rectangle of the light's plane that holds what `camera` sees of the box `lo`..`hi`
    /// on a target `aspect` times as wide as high (the box clipped by the view frustum); none
    /// where the camera sees none of it.
    pub fn seen(&self, camera: &Camera, aspect: f32, lo: Vec3, hi: Vec3) -> Option<(Vec2, Vec2)> {
        let points = frustum_in_box(camera, aspect, lo, hi);
        let mut min = Vec2::splat(f32::INFINITY);
        let mut max = Vec2::splat(f32::NEG_INFINITY);
        for p in points {
            let q = self.view.transform_point3(p.as_vec3()).truncate();
            (min, max) = (min.min(q), max.max(q));
        }
        (min.cmple(max).all() && min.is_finite() && max.is_finite()).then_some((min, max))
    }
}

/// A refitted square is this much wider than the least that holds what the view sees: the
/// camera may move a little before the map is drawn again.
pub const ROOM: f32 = 1.25;
/// A square more than this many times as wide as the least that holds the view is refitted:
/// its texels are that much coarser than they need be.
pub const COARSEST: f32 = 1.6;
/// Texels kept around what the view sees beyond the filter kernel's radius, for the lookups'
/// rounding and the lift off the surface.
const KERNEL_MARGIN: u32 = 2;

/// The square a directional light's map is drawn for, in its frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionalFit {
    pub frame: DirectionalFrame,
    pub square: Square,
}

impl DirectionalFit {
    /// The whole box: what a map serves before any view.
    pub fn whole(frame: DirectionalFrame) -> DirectionalFit {
        DirectionalFit { frame, square: frame.whole }
    }

    /// The square a map of `size` texels a side with a kernel of `radius` texels is to be
    /// drawn for, where a view sees `seen` of the box (none: nothing), or none where the
    /// current square serves the view: it holds what the view sees and the kernel's texels
    /// around it (within the whole box's square), and is at most [`COARSEST`] times as wide
    /// as it needs be. A new square is [`ROOM`] times the least, kept within the whole box's
    /// square, and never wider than that.
    pub fn refit_for(&self, seen: Option<(Vec2, Vec2)>, size: u32, radius: u32) -> Option<Square> {
        let (lo, hi) = seen?;
        let whole = self.frame.whole;
        // The kernel's texels at each side, as a share of the map's width.
        let pad_share = (radius + KERNEL_MARGIN) as f32 / size as f32;
        let needed = |square: &Square| {
            let pad = 2.0 * square.half * pad_share;
            let (wlo, whi) = (whole.centre - whole.half, whole.centre + whole.half);
            ((lo - pad).max(wlo), (hi + pad).min(whi))
        };
        // The least half width whose square holds `seen` with its own kernel's texels.
        let seen_half = 0.5 * (hi - lo).max_element();
        let least = if pad_share < 0.25 { seen_half / (1.0 - 2.0 * pad_share) } else { whole.half };
        let (need_lo, need_hi) = needed(&self.square);
        if self.square.holds(need_lo, need_hi) && self.square.half <= COARSEST * least.max(1e-6 * whole.half)
        {
            return None;
        }
        let half = ROOM * least;
        let target = if half >= whole.half {
            whole
        } else {
            let centre = 0.5 * (lo + hi);
            let reach = Vec2::splat(whole.half - half);
            Square { centre: centre.clamp(whole.centre - reach, whole.centre + reach), half }
        };
        (target != self.square).then_some(target)
    }
}

/// The box's eight corners: bit 0 of the index picks x from `lo` or `hi`, bit 1 y, bit 2 z.
pub fn box_corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The corners of the part of the box `lo`..`hi` (widened by a millionth of its diagonal, so
/// that a flat box has a volume) inside `camera`'s frustum: the corners of an intersection of
/// two convex solids lie on the faces of one clipped by the other.
fn frustum_in_box(camera: &Camera, aspect: f32, lo: Vec3, hi: Vec3) -> Vec<DVec3> {
    let (lo, hi) = (lo.as_dvec3(), hi.as_dvec3());
    let widen = DVec3::splat(1e-6 * (hi - lo).length() + 1e-9);
    let (lo, hi) = (lo - widen, hi + widen);
    let scene_box: [DVec3; 8] = std::array::from_fn(|i| {
        DVec3::new(
            if i & 1 == 0 { lo.x } else { hi.x },
            if i & 2 == 0 { lo.y } else { hi.y },
            if i & 4 == 0 { lo.z } else { hi.z },
        )
    });
    let eye = camera.eye.as_dvec3();
    let forward = (camera.target.as_dvec3() - eye).normalize();
    let side = forward.cross(camera.up.as_dvec3()).normalize();
    let up = side.cross(forward);
    let tan_y = (0.5 * f64::from(camera.fov_y_degrees)).to_radians().tan();
    let tan_x = tan_y * f64::from(aspect);
    let frustum: [DVec3; 8] = std::array::from_fn(|i| {
        let sx = if i & 1 == 0 { -1.0 } else { 1.0 };
        let sy = if i & 2 == 0 { -1.0 } else { 1.0 };
        let d = f64::from(if i & 4 == 0 { camera.near } else { camera.far });
        eye + d * (forward + sx * tan_x * side + sy * tan_y * up)
    });
    let mut points = Vec::new();
    for (solid, other) in [(&scene_box, &frustum), (&frustum, &scene_box)] {
        let planes = hexahedron_planes(other);
        for face in hexahedron_faces(solid) {
            let clipped = planes.iter().fold(face.to_vec(), |polygon, plane| clip(&polygon, *plane));
            points.extend(clipped);
        }
    }
    points
}

/// The four corners of each face of a hexahedron whose corners are indexed as
/// [`box_corners`]'s, in order around the face.
fn hexahedron_faces(corners: &[DVec3; 8]) -> [[DVec3; 4]; 6] {
    std::array::from_fn(|f| {
        let (axis, high) = (f / 2, f % 2);
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let index = |i: usize, j: usize| (high << axis) | (i << a) | (j << b);
        [index(0, 0), index(1, 0), index(1, 1), index(0, 1)].map(|k| corners[k])
    })
}

/// The planes of a convex hexahedron's faces as (normal, offset), a point `p` inside where
/// `normal · p + offset ≥ 0`.
fn hexahedron_planes(corners: &[DVec3; 8]) -> Vec<(DVec3, f64)> {
    let centroid = corners.iter().copied().sum::<DVec3>() / 8.0;
    hexahedron_faces(corners)
        .iter()
        .map(|face| {
            let normal = (face[2] - face[0]).cross(face[3] - face[1]);
            let offset = -normal.dot(face[0]);
            if normal.dot(centroid) + offset < 0.0 {
                (-normal, -offset)
            } else {
                (normal, offset)
            }
        })
        .collect()
}

/// The convex `polygon`'s part on the inner side of `plane` (Sutherland–Hodgman).
fn clip(polygon: &[DVec3], (normal, offset): (DVec3, f64)) -> Vec<DVec3> {
    let side = |p: DVec3| normal.dot(p) + offset;
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (k, &p) in polygon.iter().enumerate() {
        let q = polygon[(k + 1) % polygon.len()];
        let (sp, sq) = (side(p), side(q));
        if sp >= 0.0 {
            out.push(p);
        }
        if (sp >= 0.0) != (sq >= 0.0) {
            out.push(p + (q - p) * (sp / (sp - sq)));
        }
    }
    out
}

#[cfg(test)]
mod tests;
