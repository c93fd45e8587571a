//! Temporal stability along a camera path. A mode's error at a frame is `e_t = T_t − R_t`, its
//! image minus the per-pixel reference's (linear radiance, before any post effect). Each pixel
//! of frame `t` is carried back to frame `t − 1` through the surface it shows: the ray through
//! its centre meets its triangle's plane at `X`, and `X` seen by the camera before falls in a
//! pixel `q`. The pixel is compared there unless `q` lies outside the frame, shows nothing, lies
//! next to the background (a silhouette), or shows another surface (a disocclusion: the point
//! `q` shows lies farther from `X` than two of its pixels' widths, allowing for a slanted
//! surface). Only pixels of the same triangle in the mode's frame and the reference's, in both
//! frames, are compared: the bound holds for those (`docs/estimator.md` section 14), and a
//! pixel where the mode's rasteriser shows another triangle is an edge, not an error of the
//! shading. [`step`] measures one frame against the one before: the largest and the 99th
//! percentile `|e_t − e_{t−1}|` (the largest channel), the pixels that jump by more than ε/2,
//! and `Σ|T_t − T_{t−1}|` against `Σ|R_t − R_{t−1}|`, whose ratio over a path is the flicker
//! ratio (1: no flicker beyond the reference's own). Of the jumps, those on a triangle whose
//! tessellation pattern changed since the frame before are counted apart: the ones a level
//! change made. [`PathStability`] gathers the steps.

use crate::geometry::camera::{pixel_ray, view_projection};
use crate::scene::Camera;
use crate::vk::target::FloatImage;
use glam::Vec3;

/// One frame of a path: the mode's image, the reference's, which triangle each pixel of the
/// reference shows (`Analysis::triangles`: scene triangle + 1, 0 for nothing) and of the
/// mode's, and the camera.
pub struct PathFrame<'a> {
    pub test: &'a FloatImage,
    pub reference: &'a FloatImage,
    pub triangles: &'a [u32],
    pub test_triangles: &'a [u32],
    pub camera: Camera,
    /// Per scene triangle (id − 1), whether its tessellation pattern (level or outer levels)
    /// changed since the frame before; empty where that is not known (modes other than
    /// multirate, a path's first frame).
    pub pattern_changed: &'a [bool],
}

/// One frame against the one before.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepStability {
    /// Pixels carried back and compared, those masked (out of the frame, disoccluded, beside a
    /// silhouette), and those where the mode shows another triangle than the reference in
    /// either frame.
    pub compared: usize,
    pub masked: usize,
    pub other_triangle: usize,
    /// The largest and the 99th-percentile `|e_t − e_{t−1}|` over the compared pixels.
    pub largest: f32,
    pub p99: f32,
    /// Compared pixels whose error changed by more than ε/2.
    pub jumps: usize,
    /// Of those, the pixels of a triangle whose pattern changed (`PathFrame::pattern_changed`).
    pub pattern_jumps: usize,
    /// `Σ|T_t − T_{t−1}|` and `Σ|R_t − R_{t−1}|` over the compared pixels and channels.
    pub test_change: f64,
    pub reference_change: f64,
}

impl StepStability {
    /// The share of compared pixels that jumped by more than ε/2.
    pub fn jump_share(&self) -> f64 {
        self.jumps as f64 / self.compared.max(1) as f64
    }
}

/// Every step of a path, and the figures over the whole of it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PathStability {
    pub steps: Vec<StepStability>,
}

impl PathStability {
    /// The largest `|e_t − e_{t−1}|` of any step.
    pub fn largest(&self) -> f32 {
        self.steps.iter().map(|s| s.largest).fold(0.0, f32::max)
    }

    /// The largest 99th percentile of any step.
    pub fn worst_p99(&self) -> f32 {
        self.steps.iter().map(|s| s.p99).fold(0.0, f32::max)
    }

    /// Over the path: the compared pixels that jumped by more than ε/2, as a share.
    pub fn jump_share(&self) -> f64 {
        self.jumps() as f64 / self.compared().max(1) as f64
    }

    /// Over the path: the pixels compared, those that jumped by more than ε/2, and those of the
    /// jumps on a triangle whose pattern changed.
    pub fn compared(&self) -> usize {
        self.steps.iter().map(|s| s.compared).sum()
    }
    pub fn jumps(&self) -> usize {
        self.steps.iter().map(|s| s.jumps).sum()
    }
    pub fn pattern_jumps(&self) -> usize {
        self.steps.iter().map(|s| s.pattern_jumps).sum()
    }

    /// `Σ|T_t − T_{t−1}| / Σ|R_t − R_{t−1}|` over the path (1 where the reference never changes).
    pub fn flicker_ratio(&self) -> f64 {
        let test: f64 = self.steps.iter().map(|s| s.test_change).sum();
        let reference: f64 = self.steps.iter().map(|s| s.reference_change).sum();
        if reference > 0.0 {
            test / reference
        } else {
            1.0
        }
    }
}

/// `current` against `previous` at a bound of `epsilon`, the scene's triangles given by their
/// corners (`corners[id − 1]`).
pub fn step(
    previous: &PathFrame<'_>,
    current: &PathFrame<'_>,
    corners: &[[Vec3; 3]],
    epsilon: f32,
) -> StepStability {
    let (width, height) = (current.test.width, current.test.height);
    let before = view_projection(&previous.camera, width, height);
    let footprint = 2.0 * (0.5 * previous.camera.fov_y_degrees.to_radians()).tan() / height as f32;
    let mut out = StepStability::default();
    let mut changes = Vec::with_capacity(current.triangles.len());
    for y in 0..height {
        for x in 0..width {
            let at = (y * width + x) as usize;
            let id = current.triangles[at];
            if id == 0 {
                continue;
            }
            let Some(q) = carried_back(previous, current, corners, (x, y), (before, footprint)) else {
                out.masked += 1;
                continue;
            };
            if current.test_triangles[at] != id || previous.test_triangles[q] != previous.triangles[q] {
                out.other_triangle += 1;
                continue;
            }
            let error = |frame: &PathFrame<'_>, at: usize| {
                let (t, r) = (frame.test.pixels[at], frame.reference.pixels[at]);
                [t[0] - r[0], t[1] - r[1], t[2] - r[2]]
            };
            let (now, then) = (error(current, at), error(previous, q));
            let change = (0..3).map(|c| (now[c] - then[c]).abs()).fold(0.0f32, f32::max);
            changes.push(change);
            let jump = change > 0.5 * epsilon;
            out.jumps += usize::from(jump);
            let pattern_changed = current.pattern_changed.get(id as usize - 1) == Some(&true);
            out.pattern_jumps += usize::from(jump && pattern_changed);
            let (t, t0) = (current.test.pixels[at], previous.test.pixels[q]);
            let (r, r0) = (current.reference.pixels[at], previous.reference.pixels[q]);
            out.test_change += (0..3).map(|c| f64::from((t[c] - t0[c]).abs())).sum::<f64>();
            out.reference_change += (0..3).map(|c| f64::from((r[c] - r0[c]).abs())).sum::<f64>();
        }
    }
    out.compared = changes.len();
    if !changes.is_empty() {
        changes.sort_by(f32::total_cmp);
        out.largest = *changes.last().expect("not empty");
        out.p99 = changes[((changes.len() - 1) as f64 * 0.99).round() as usize];
    }
    out
}

/// The pixel of `previous` that shows the surface point pixel `(x, y)` of `current` shows, or
/// none where it is masked; `before` is `previous`'s view-projection and `footprint` its
/// pixel's width per unit of distance.
fn carried_back(
    previous: &PathFrame<'_>,
    current: &PathFrame<'_>,
    corners: &[[Vec3; 3]],
    (x, y): (u32, u32),
    (before, footprint): (glam::Mat4, f32),
) -> Option<usize> {
    let (width, height) = (current.test.width, current.test.height);
    let triangle = corners.get(current.triangles[(y * width + x) as usize] as usize - 1)?;
    let ray = pixel_ray(&current.camera, width, height, x as f32 + 0.5, y as f32 + 0.5);
    let point = on_plane(ray, triangle)?;
    let clip = before * point.extend(1.0);
    if clip.w <= 0.0 {
        return None;
    }
    let ndc = clip.truncate() / clip.w;
    let (qx, qy) = ((ndc.x * 0.5 + 0.5) * width as f32, (ndc.y * 0.5 + 0.5) * height as f32);
    if !(qx >= 0.0 && qy >= 0.0 && qx < width as f32 && qy < height as f32) {
        return None;
    }
    let (qx, qy) = (qx as u32, qy as u32);
    let shown = |x: i64, y: i64| {
        let inside = x >= 0 && y >= 0 && x < i64::from(width) && y < i64::from(height);
        if inside {
            previous.triangles[(y as u32 * width + x as u32) as usize]
        } else {
            0
        }
    };
    let (sx, sy) = (i64::from(qx), i64::from(qy));
    let id = shown(sx, sy);
    if id == 0 || [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|(dx, dy)| shown(sx + dx, sy + dy) == 0) {
        return None;
    }
    let other = corners.get(id as usize - 1)?;
    let back = pixel_ray(&previous.camera, width, height, qx as f32 + 0.5, qy as f32 + 0.5);
    let seen = on_plane(back, other)?;
    let normal = (other[1] - other[0]).cross(other[2] - other[0]).normalize_or_zero();
    let slant = normal.dot(back.1).abs().max(0.2);
    let reach = 2.0 * footprint * previous.camera.eye.distance(seen) / slant;
    (seen.distance(point) <= reach).then_some((qy * width + qx) as usize)
}

/// Where the ray `(origin, direction)` meets the plane of `triangle` (none where it runs along
/// it or the triangle has no plane).
fn on_plane((origin, direction): (Vec3, Vec3), triangle: &[Vec3; 3]) -> Option<Vec3> {
    let normal = (triangle[1] - triangle[0]).cross(triangle[2] - triangle[0]);
    let facing = normal.dot(direction);
    if facing.abs() <= 1e-12 * normal.length() {
        return None;
    }
    let t = normal.dot(triangle[0] - origin) / facing;
    let point = origin + direction * t;
    point.is_finite().then_some(point)
}

#[cfg(test)]
mod tests;
