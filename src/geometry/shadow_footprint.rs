//! What a triangle's shadow lookups read of one map square, and whether they all pass or all
//! fail there ([`Image::visibility`]): the image of the triangle (or of its part in one cube
//! face) in the square, the lookups' depth over it, and the square's min/max pyramid
//! ([`DepthSquare`]), refined down to single texels where a coarse cell cannot decide. The
//! caller, `shadow_class`, makes the images and combines their verdicts.
//!
//! Both kinds of map are handled alike: over the image of the triangle's plane in a map, a
//! directional map's depth and the reciprocal of a cube face's distance along its axis are
//! affine in the map's coordinates, so their extremes over any box of texels lie at its corners.

use super::shadow_view::{face_basis, Projection, ShadowMap};
use glam::{DVec2, DVec3, IVec2};

/// A light's visibility over the whole of a triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Visibility {
    /// Every kernel sample of every pixel passes: V = 1.
    Lit,
    /// Every kernel sample of every pixel fails: V = 0.
    Shadowed,
    /// Neither could be proven: V is looked up per pixel.
    Mixed,
}

/// The lookup's slack for the GPU's rounding: in texels across the map, and in depth (the
/// maps' depths run from 0 to 1: eight units in the last place of 1).
const TEXEL_SLACK: f64 = 0.02;
const DEPTH_SLACK: f64 = 1e-6;
/// A cube face's cone is widened by this much (relative) for the part of a triangle whose
/// pixels may look up in that face: rounding never sends a pixel farther to a neighbouring face.
const FACE_SLACK: f64 = 1e-4;
/// The pyramid level is chosen so that a footprint spans at most this many cells a side.
const CELLS_ACROSS: u32 = 16;

/// One square of depths as the shadow pass rendered it (a directional map or a cube face),
/// and above it a min/max pyramid: level `k` holds each block of `2^k × 2^k` texels' least
/// and greatest depth.
pub struct DepthSquare {
    pub(super) size: u32,
    texels: Vec<f32>,
    /// Levels 1, 2, …: side in cells and the cells' (min, max), row by row.
    pub(super) coarse: Vec<(u32, Vec<[f32; 2]>)>,
}

impl DepthSquare {
    /// The square of `size` texels a side at `origin` in an atlas `width` texels wide.
    pub fn new(atlas: &[f32], width: u32, origin: [u32; 2], size: u32) -> DepthSquare {
        let texels: Vec<f32> = (0..size)
            .flat_map(|y| {
                let row = (origin[1] + y) as usize * width as usize + origin[0] as usize;
                atlas[row..row + size as usize].iter().copied()
            })
            .collect();
        let mut coarse: Vec<(u32, Vec<[f32; 2]>)> = Vec::new();
        let mut side = size;
        while side > 1 {
            let below = |x: u32, y: u32| match coarse.last() {
                None => {
                    let d = texels[(y * size + x) as usize];
                    [d, d]
                }
                Some((s, cells)) => cells[(y * s + x) as usize],
            };
            let next = side.div_ceil(2);
            let cells = (0..next * next)
                .map(|i| {
                    let (x, y) = (2 * (i % next), 2 * (i / next));
                    let mut range = below(x, y);
                    for (dx, dy) in [(1, 0), (0, 1), (1, 1)] {
                        if x + dx < side && y + dy < side {
                            let [lo, hi] = below(x + dx, y + dy);
                            range = [range[0].min(lo), range[1].max(hi)];
                        }
                    }
                    range
                })
                .collect();
            coarse.push((next, cells));
            side = next;
        }
        DepthSquare { size, texels, coarse }
    }

    /// The least and greatest depth of cell (`x`, `y`) of level `level`.
    pub(super) fn range(&self, level: usize, x: u32, y: u32) -> [f32; 2] {
        if level == 0 {
            let d = self.texels[(y * self.size + x) as usize];
            return [d, d];
        }
        let (side, cells) = &self.coarse[level - 1];
        cells[(y * side + x) as usize]
    }
}

/// The texels a triangle's lookups may read in one square (`first` ..= `last`, clamped to the
/// square as the lookup clamps), with what [`Image::narrow`] needs beside: the lookups' depth
/// over the image, the image's bounds, and how far (in texels) a point whose kernel reads a
/// texel may lie from it.
struct Footprint<'a> {
    square: &'a DepthSquare,
    affine: &'a Affine,
    first: IVec2,
    last: IVec2,
    image_lo: DVec2,
    image_hi: DVec2,
    reach: f64,
}

/// What the cells seen so far allow: every sample passes (lit), every sample fails (shadowed).
struct Verdict {
    lit: bool,
    shadowed: bool,
}

/// What the lookups of a convex piece of a triangle's pixels read of one square: the image of
/// the piece there (`corners`, in texels, a convex polygon), the lookups' depth over it, and
/// how far a lookup may land from the image of its own surface point.
pub struct Image {
    /// The square: 0 for a directional map, the face of a cube.
    pub face: usize,
    corners: Vec<DVec2>,
    /// Per corner, the value `depth` interpolates: a directional map's depth, a cube face's
    /// reciprocal distance along its axis.
    at: Vec<f64>,
    /// Texels a lookup may land from its point's image, beside the slack for rounding.
    spread: f64,
    depth: DepthBound,
}

/// How the depths compared over a box of the map are bounded.
enum DepthBound {
    /// A directional map: the lookup's depth is affine over the image.
    Affine,
    /// A cube face: the reciprocal of the distance along the face's axis is affine over the
    /// image; the lookup lies up to `closer` nearer and `farther` farther (less than 0: at least
    /// that much nearer) along it than its point; depth is `far·(a − near) / ((far − near)·a)`
    /// of distance `a`.
    Reciprocal { closer: f64, farther: f64, near: f64, far: f64 },
}

impl Image {
    /// Whether every sample the kernel reads for any point of the image passes, or fails.
    pub fn visibility(&self, square: &DepthSquare, radius: u32) -> Visibility {
        let reach = f64::from(radius) + self.spread + TEXEL_SLACK;
        let (mut lo, mut hi) = (self.corners[0], self.corners[0]);
        for c in &self.corners[1..] {
            (lo, hi) = (lo.min(*c), hi.max(*c));
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return Visibility::Mixed;
        }
        let Some(affine) = self.affine() else {
            return Visibility::Mixed;
        };
        // The texels any lookup's kernel reads: a lookup at u reads floor(u) − r ..= floor(u) + r,
        // clamped to the square.
        let size = square.size as i32;
        let first = (lo - reach).floor().max(DVec2::ZERO).min(DVec2::splat(f64::from(size - 1))).as_ivec2();
        let last = (hi + reach).floor().max(DVec2::ZERO).min(DVec2::splat(f64::from(size - 1))).as_ivec2();
        let across = (last - first).max_element() as u32 + 1;
        let level = (across.div_ceil(CELLS_ACROSS)).next_power_of_two().trailing_zeros() as usize;
        let level = level.min(square.coarse.len());
        let footprint = Footprint { square, affine: &affine, first, last, image_lo: lo, image_hi: hi, reach };
        let mut verdict = Verdict { lit: true, shadowed: true };
        for y in (first.y >> level)..=(last.y >> level) {
            for x in (first.x >> level)..=(last.x >> level) {
                if !self.narrow(&footprint, level, IVec2::new(x, y), &mut verdict) {
                    return Visibility::Mixed;
                }
            }
        }
        if verdict.lit {
            Visibility::Lit
        } else {
            Visibility::Shadowed
        }
    }

    /// Narrows `verdict` by cell `cell` of pyramid level `level`: where the cell's depth range
    /// cannot decide what is still possible, by its four cells a level finer, down to single
    /// texels. Whether lit or shadowed is still possible after it.
    fn narrow(&self, footprint: &Footprint, level: usize, cell: IVec2, verdict: &mut Verdict) -> bool {
        // The cell's texels that some lookup's kernel may read.
        let first = (cell << level as i32).max(footprint.first);
        let last = (((cell + 1) << level as i32) - 1).min(footprint.last);
        if first.cmpgt(last).any() {
            return verdict.lit || verdict.shadowed;
        }
        // The points whose kernel can read one of them: within r texels (and the spread) of
        // their texels, the texel's own width included; at the square's edge, every point
        // beyond it too (the lookup clamps).
        let mut box_lo = first.as_dvec2() - footprint.reach;
        let mut box_hi = (last + 1).as_dvec2() + footprint.reach;
        let edge = footprint.square.size as i32 - 1;
        let beyond_lo = footprint.image_lo - footprint.reach;
        let beyond_hi = footprint.image_hi + footprint.reach;
        box_lo = DVec2::select(first.cmpeq(IVec2::ZERO), box_lo.min(beyond_lo), box_lo);
        box_hi = DVec2::select(last.cmpeq(IVec2::splat(edge)), box_hi.max(beyond_hi), box_hi);
        if !self.touches(box_lo - TEXEL_SLACK, box_hi + TEXEL_SLACK) {
            return verdict.lit || verdict.shadowed;
        }
        let [stored_lo, stored_hi] = footprint.square.range(level, cell.x as u32, cell.y as u32);
        let [depth_lo, depth_hi] = self.depth_over(footprint.affine, box_lo, box_hi);
        let cell_lit = f64::from(stored_lo) >= depth_hi + DEPTH_SLACK;
        let cell_shadowed = f64::from(stored_hi) < depth_lo - DEPTH_SLACK;
        let settled = (cell_lit || !verdict.lit) && (cell_shadowed || !verdict.shadowed);
        if settled || level == 0 {
            verdict.lit &= cell_lit;
            verdict.shadowed &= cell_shadowed;
            return verdict.lit || verdict.shadowed;
        }
        [(0, 0), (1, 0), (0, 1), (1, 1)]
            .into_iter()
            .all(|(dx, dy)| self.narrow(footprint, level - 1, 2 * cell + IVec2::new(dx, dy), verdict))
    }

    /// Whether the image meets the box `lo`..`hi` (separating axes: the box's and the image's
    /// edges' normals).
    fn touches(&self, lo: DVec2, hi: DVec2) -> bool {
        let c = &self.corners;
        let (mut image_lo, mut image_hi) = (c[0], c[0]);
        for p in &c[1..] {
            (image_lo, image_hi) = (image_lo.min(*p), image_hi.max(*p));
        }
        if image_lo.cmpgt(hi).any() || image_hi.cmplt(lo).any() {
            return false;
        }
        let orientation = signed_area(c).signum();
        let box_corners = [lo, DVec2::new(hi.x, lo.y), DVec2::new(lo.x, hi.y), hi];
        (0..c.len()).all(|k| {
            let (a, edge) = (c[k], c[(k + 1) % c.len()] - c[k]);
            box_corners.iter().any(|p| orientation * edge.perp_dot(*p - a) >= 0.0)
        })
    }

    /// The lookups' depth (or reciprocal distance) as an affine function over the image,
    /// through its best-conditioned three corners; None where the image is a line.
    fn affine(&self) -> Option<Affine> {
        let n = self.corners.len();
        let mut best: Option<(f64, [usize; 3])> = None;
        for i in 0..n {
            for j in i + 1..n {
                for k in j + 1..n {
                    let c = &self.corners;
                    let area = (c[j] - c[i]).perp_dot(c[k] - c[i]).abs();
                    if best.is_none_or(|(b, _)| area > b) {
                        best = Some((area, [i, j, k]));
                    }
                }
            }
        }
        let [i, j, k] = best?.1;
        Affine::through(
            [self.corners[i], self.corners[j], self.corners[k]],
            [self.at[i], self.at[j], self.at[k]],
        )
    }

    /// The least and greatest depth a lookup compares whose point's image lies in the box
    /// `lo`..`hi` and in the image (within the slack), `affine` being [`Image::affine`].
    fn depth_over(&self, affine: &Affine, lo: DVec2, hi: DVec2) -> [f64; 2] {
        let [box_lo, box_hi] = affine.over(lo, hi);
        // Over the image the function lies between its corners' values, give or take the
        // slack by which a pixel's point may stray outside.
        let stray = affine.gradient.abs().element_sum() * TEXEL_SLACK;
        let least = self.at.iter().copied().fold(f64::INFINITY, f64::min);
        let greatest = self.at.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let value_lo = box_lo.max(least - stray);
        let value_hi = box_hi.min(greatest + stray);
        match self.depth {
            DepthBound::Affine => [value_lo, value_hi],
            DepthBound::Reciprocal { closer, farther, near, far } => {
                // The point's distance along the axis runs from 1/value_hi to 1/value_lo.
                let depth = |a: f64| far * (a - near) / ((far - near) * a);
                let nearest = (1.0 / value_hi - closer).max(0.5 * near);
                let farthest = 1.0 / value_lo + farther;
                [depth(nearest), depth(farthest)]
            }
        }
    }
}

/// Twice the signed area of the polygon `corners` (positive: anticlockwise).
fn signed_area(corners: &[DVec2]) -> f64 {
    (0..corners.len()).map(|k| corners[k].perp_dot(corners[(k + 1) % corners.len()])).sum()
}

/// The affine function of the map's coordinates that takes given values at a triangle's
/// corners.
struct Affine {
    origin: DVec2,
    value: f64,
    gradient: DVec2,
}

impl Affine {
    /// The function taking `at[k]` at `corners[k]`; None where the corners lie on a line.
    fn through(corners: [DVec2; 3], at: [f64; 3]) -> Option<Affine> {
        let (e1, e2) = (corners[1] - corners[0], corners[2] - corners[0]);
        let det = e1.perp_dot(e2);
        if det.abs().partial_cmp(&(1e-9 * e1.length() * e2.length())) != Some(std::cmp::Ordering::Greater) {
            return None;
        }
        let (d1, d2) = (at[1] - at[0], at[2] - at[0]);
        // The gradient solves g·e1 = d1, g·e2 = d2.
        let gradient = DVec2::new(d1 * e2.y - d2 * e1.y, d2 * e1.x - d1 * e2.x) / det;
        Some(Affine { origin: corners[0], value: at[0], gradient })
    }

    /// Its least and greatest value over the box `lo`..`hi` (at two of its corners).
    fn over(&self, lo: DVec2, hi: DVec2) -> [f64; 2] {
        let corner = |up: bool| {
            DVec2::new(
                if (self.gradient.x > 0.0) == up { hi.x } else { lo.x },
                if (self.gradient.y > 0.0) == up { hi.y } else { lo.y },
            )
        };
        let value = |p: DVec2| self.value + self.gradient.dot(p - self.origin);
        [value(corner(false)), value(corner(true))]
    }
}

/// In texels, where a point at clip-space x, y (−1..1) lies in a square of `size` texels.
fn texel_of(ndc: DVec2, size: u32) -> DVec2 {
    (ndc * 0.5 + 0.5) * f64::from(size)
}

/// A directional light's map: every pixel's lookup is its point moved by the same offset (the
/// plane's normal and the light's direction are the triangle's), so the lookups' image is the
/// triangle's image moved, and their depth is affine over it.
pub fn directional_image(
    record: &ShadowMap,
    radius: u32,
    to_light: DVec3,
    normal: DVec3,
    corners: [DVec3; 3],
) -> Option<Image> {
    let Projection::Orthographic(view_proj) = record.projection else { return None };
    let view_proj = view_proj.as_dmat4();
    let texel = f64::from(record.texel_width);
    let cos_theta = normal.dot(to_light).clamp(-1.0, 1.0);
    let n = if cos_theta < 0.0 { -normal } else { normal };
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    let lift = (f64::from(radius) + 1.5) * texel;
    let offset = n * (lift * sin_theta) + to_light * (0.5 * texel);
    let ndc = corners.map(|c| view_proj.project_point3(c + offset));
    Some(Image {
        face: 0,
        corners: ndc.iter().map(|p| texel_of(p.truncate(), record.size)).collect(),
        at: ndc.iter().map(|p| p.z).collect(),
        spread: 0.0,
        depth: DepthBound::Affine,
    })
}

/// A point light's cube: the images of the triangle's parts in the faces its pixels may look
/// up in, one per face (the triangle clipped to the face's cone, widened by the slack), or None
/// where the light lies in the triangle's plane, or nearly (the side a pixel lifts to may flip).
pub fn cube_images(record: &ShadowMap, radius: u32, light: DVec3, corners: [DVec3; 3]) -> Option<Vec<Image>> {
    let normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]).normalize();
    let towards = -normal.dot(corners[0] - light);
    if towards.abs().partial_cmp(&(FACE_SLACK * (corners[0] - light).length()))
        != Some(std::cmp::Ordering::Greater)
    {
        return None;
    }
    let n = if towards > 0.0 { normal } else { -normal };
    let d_min = distance_to_triangle(light, corners, normal).max(towards.abs());
    (0..6)
        .filter_map(|face| {
            let piece = clipped_to_face(corners.map(|c| c - light), face);
            (!piece.is_empty()).then(|| face_image(record, radius, face, &piece, n, towards.abs(), d_min))
        })
        .collect()
}

/// The part of the triangle `d` (corners from the light) whose points may be looked up in cube
/// face `face`: inside the face's cone widened by `FACE_SLACK` (Sutherland–Hodgman against its
/// four planes); empty where none is.
fn clipped_to_face(d: [DVec3; 3], face: usize) -> Vec<DVec3> {
    let [axis, side, up] = face_basis(face).map(|v| v.as_dvec3());
    let widened = 1.0 + FACE_SLACK;
    let planes = [widened * axis - side, widened * axis + side, widened * axis - up, widened * axis + up];
    let mut polygon = d.to_vec();
    for plane in planes {
        let mut clipped = Vec::with_capacity(polygon.len() + 1);
        for k in 0..polygon.len() {
            let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
            let (fa, fb) = (plane.dot(a), plane.dot(b));
            if fa >= 0.0 {
                clipped.push(a);
            }
            if (fa >= 0.0) != (fb >= 0.0) {
                clipped.push(a + (b - a) * (fa / (fa - fb)));
            }
        }
        polygon = clipped;
        if polygon.is_empty() {
            break;
        }
    }
    polygon
}

/// The image in cube face `face` of `piece` (a convex polygon of the triangle's plane, corners
/// from the light, inside the face's widened cone), `n` the plane's normal on the light's side,
/// `plane_distance` the light's distance to the plane and `d_min` to the triangle. A lookup is its
/// point moved by `n·H(p)` (the lift along the plane's normal on the light's side, `H = (r +
/// 1.5)·w·sin θ` with `w` the texel width at the point's distance `a` along the face's axis) and
/// by half a texel towards the light, which runs along the ray through the light: it moves the
/// image not at all and `a` nearer by `w/2·a/|d|`. `H` varies over the piece within `H̄ ± e`
/// (`a` between the corners', `cos θ = D/|d|` with `D` the plane's distance and `|d|` between
/// the least and greatest distance to the light), so the lookups lie within `e` along `n` of the
/// piece moved by `n·H̄`: its image and `1/a` are exact (a plane's), and `e` moves the image by at
/// most `size/2 · e·(max(|side·n|, |up·n|) + |axis·n|) / (a_min − e)` texels and `a` by at most
/// `e·|axis·n|` either way (and the half texel a little more, below).
fn face_image(
    record: &ShadowMap,
    radius: u32,
    face: usize,
    piece: &[DVec3],
    n: DVec3,
    plane_distance: f64,
    d_min: f64,
) -> Option<Image> {
    let Projection::Cube { near, far, .. } = record.projection else { return None };
    let [axis, side, up] = face_basis(face).map(|v| v.as_dvec3());
    let along: Vec<f64> = piece.iter().map(|v| axis.dot(*v)).collect();
    let a_min = along.iter().copied().fold(f64::INFINITY, f64::min);
    let a_max = along.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if a_min.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let d_max = piece.iter().map(|v| v.length()).fold(0.0, f64::max);
    let sine = |distance: f64| (1.0 - (plane_distance / distance).min(1.0).powi(2)).sqrt();
    let texel_width = f64::from(record.texel_width);
    let lift = (f64::from(radius) + 1.5) * texel_width;
    let (h_lo, h_hi) = (lift * a_min * sine(d_min), lift * a_max * sine(d_max));
    let (h_mid, e) = (0.5 * (h_lo + h_hi), 0.5 * (h_hi - h_lo) + 1e-9 * a_max);
    let moved: Vec<DVec3> = piece.iter().map(|v| *v + n * h_mid).collect();
    let moved_along: Vec<f64> = moved.iter().map(|v| axis.dot(*v)).collect();
    let moved_min = moved_along.iter().copied().fold(f64::INFINITY, f64::min);
    let half_texel = 0.5 * texel_width * a_max;
    if moved_min.partial_cmp(&(2.0 * (e + half_texel))) != Some(std::cmp::Ordering::Greater) {
        return None;
    }
    let corners = moved
        .iter()
        .zip(&moved_along)
        .map(|(v, a)| texel_of(DVec2::new(side.dot(*v), -up.dot(*v)) / *a, record.size))
        .collect();
    let across = side.dot(n).abs().max(up.dot(n).abs()) + axis.dot(n).abs();
    let nearer = 0.5 * texel_width * a_min * a_min / d_max;
    // Half a texel towards the light runs along the ray through the point, not through the
    // lifted point: off that ray by at most half_texel·H/(|d| − H), which moves the image by at
    // most twice that over the distance along the axis.
    let off_ray = half_texel * h_hi / (d_min - h_hi).max(f64::MIN_POSITIVE);
    let shift = (e * across + 2.0 * off_ray) / (moved_min - e - half_texel);
    Some(Image {
        face,
        corners,
        at: moved_along.iter().map(|a| 1.0 / a).collect(),
        spread: 0.5 * f64::from(record.size) * shift,
        depth: DepthBound::Reciprocal {
            closer: e * axis.dot(n).abs() + half_texel,
            farther: e * axis.dot(n).abs() - nearer,
            near: f64::from(near),
            far: f64::from(far),
        },
    })
}

/// The least distance from `point` to the triangle `corners` of unit normal `normal`: to the
/// point of its plane below `point` where that lies inside it, else to the nearest edge.
fn distance_to_triangle(point: DVec3, corners: [DVec3; 3], normal: DVec3) -> f64 {
    let foot = point - normal * normal.dot(point - corners[0]);
    let inside = (0..3).all(|k| {
        let (a, b) = (corners[k], corners[(k + 1) % 3]);
        (b - a).cross(foot - a).dot(normal) >= 0.0
    });
    if inside {
        return (point - foot).length();
    }
    (0..3)
        .map(|k| {
            let (a, b) = (corners[k], corners[(k + 1) % 3]);
            let t = ((point - a).dot(b - a) / (b - a).length_squared()).clamp(0.0, 1.0);
            (point - (a + (b - a) * t)).length()
        })
        .fold(f64::INFINITY, f64::min)
}
