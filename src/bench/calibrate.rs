//! `multirate calibrate`: measures the device costs of the cost model
//! (`render::cost_model`): the pre-pass's estimate per triangle, per-pixel shading per
//! fragment, and a tessellated patch's and sub-vertex's cost, each at two light counts, from
//! which the model draws its lines.
//!
//! Per light count `L`, the scene is lit by `L` point lights around its camera's target (its own
//! lights replaced) and benchmarked in turns (`pixel`, `vertex`, `multirate` estimating every
//! visible triangle, `multirate` shading every triangle per pixel, `fixed:1` and `fixed:4`): the
//! estimate costs the estimate step's time over the triangles it estimated (those the range
//! class leaves, counted by the twins, `geometry::cull` and `shading::estimator`), a pixel costs
//! `pixel`'s time above `vertex`'s (which rasterises and tests the same depth) over its shaded
//! fragments, a tessellated patch `fixed:1`'s time above `vertex`'s over the triangles, and a
//! sub-vertex `fixed:4`'s above `fixed:1`'s over the sub-vertices it adds. Multirate's per-pixel
//! path, the fourth configuration's time above `vertex`'s, is measured at the scene's resolution
//! and at a sixteenth of its pixels: the line through both, over the fragments it shades, splits
//! it into a cost per fragment and one per visible triangle (which the resolution leaves).

use super::measure::{run, BenchConfig, BenchScene, Progress};
use super::row::Row;
use crate::error::Result;
use crate::geometry::camera::view_projection;
use crate::geometry::cull::{back_face_per_pixel, culled, PerPixelRule};
use crate::render::cost_model::{Calibration, LinearCost};
use crate::render::{Mode, PrePassStep};
use crate::scene::{Light, ParameterRange, Scene};
use crate::shading::estimator::{settled_by_range, Discontinuity, Split, TriangleInput};
use crate::vk::Context;
use glam::{Vec2, Vec3};
use std::sync::Arc;

/// An area floor above every image: multirate shades every triangle per pixel.
const EVERY_IMAGE: f32 = 1.0e9;

/// The light counts the lines are drawn through.
pub const LIGHT_COUNTS: [usize; 2] = [1, 8];

/// The per-pixel path's second resolution: the scene's width and height over this.
pub const SMALL_RESOLUTION_DIVISOR: u32 = 4;

/// One light count's measurement.
#[derive(Clone, Copy, Debug)]
pub struct CostSample {
    pub lights: usize,
    /// Nanoseconds per estimated triangle.
    pub estimate_ns: f64,
    /// Nanoseconds per fragment shaded per pixel, by `pixel` mode and by multirate's
    /// per-pixel path, and the path's nanoseconds per visible triangle.
    pub pixel_ns: f64,
    pub fallback_ns: f64,
    pub fallback_triangle_ns: f64,
    /// Nanoseconds per triangle drawn as a patch at level 1 above `vertex`'s draw, and per
    /// sub-vertex added at level 4.
    pub patch_ns: f64,
    pub sub_vertex_ns: f64,
    /// The triangles the pre-pass estimated, the fragments `pixel` shaded, those the per-pixel
    /// path shaded at both resolutions and the triangles it drew, the patches drawn and the
    /// sub-vertices `fixed:4` shaded above `fixed:1`.
    pub estimated_triangles: usize,
    pub fragments: u64,
    pub fallback_fragments: [u64; 2],
    pub visible_triangles: usize,
    pub patches: usize,
    pub added_sub_vertices: u64,
}

/// Measures `scene` (at its own resolution) with each of [`LIGHT_COUNTS`] point lights, and
/// the calibration through both.
pub fn calibrate(
    context: &Arc<Context>,
    scene: &BenchScene,
    frames: u32,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<(Calibration, Vec<CostSample>)> {
    let config = BenchConfig {
        modes: vec![Mode::Pixel, Mode::Vertex, Mode::Multirate],
        epsilons: Vec::new(),
        n_maxes: Vec::new(),
        resolutions: Vec::new(),
        warmup: 2,
        frames,
        split: Split::Heuristic,
        discontinuity: Discontinuity::Relaxed,
        placements: Vec::new(),
        images: None,
        min_estimated_areas: vec![Some(0.0)],
        // What every frame costs: the camera still, each frame estimating for its own eye.
        orbit_degrees: 0.0,
        draw_parts: false,
        // The estimator step's time is the estimate's cost.
        pre_pass_steps: true,
        eye_ball_share: 0.0,
        level_holds: Vec::new(),
        path: None,
    };
    // Every triangle per pixel: ε 0, which the range class never settles, and an area floor
    // above every image; with `vertex` of the same turns; at two resolutions.
    let resolution = (scene.scene.settings.width, scene.scene.settings.height);
    let per_pixel = BenchConfig {
        modes: vec![Mode::Vertex, Mode::Multirate],
        epsilons: vec![0.0],
        min_estimated_areas: vec![Some(EVERY_IMAGE)],
        resolutions: vec![resolution, small_resolution(&scene.scene)],
        ..config.clone()
    };
    // The tessellation stages at level 1 and 4, with `vertex` of the same turns.
    let tessellated =
        BenchConfig { modes: vec![Mode::Vertex, Mode::Fixed(1), Mode::Fixed(4)], ..config.clone() };
    let mut samples = Vec::new();
    for lights in LIGHT_COUNTS {
        let lit = BenchScene {
            name: format!("{} ({lights} lights)", scene.name),
            scene: lit_by(&scene.scene, lights),
        };
        let scenes = std::slice::from_ref(&lit);
        let rows = run(context, scenes, &config, progress)?.rows;
        let per_pixel_rows = run(context, scenes, &per_pixel, progress)?.rows;
        let tessellated_rows = run(context, scenes, &tessellated, progress)?.rows;
        samples.push(sample(&lit.scene, lights, [&rows, &per_pixel_rows, &tessellated_rows]));
    }
    let line = |cost: fn(&CostSample) -> f64| {
        LinearCost::through((samples[0].lights, cost(&samples[0])), (samples[1].lights, cost(&samples[1])))
    };
    let calibration = Calibration {
        estimate: line(|s| s.estimate_ns),
        pixel: line(|s| s.pixel_ns),
        fallback: line(|s| s.fallback_ns),
        fallback_triangle: Some(line(|s| s.fallback_triangle_ns)),
        tessellated_patch: Some(line(|s| s.patch_ns)),
        sub_vertex: Some(line(|s| s.sub_vertex_ns)),
        measured_with: format!(
            "multirate calibrate --scene {} --frames {frames} on {} ({})",
            scene.scene.path.display(),
            context.info.name,
            context.info.driver
        ),
    };
    Ok((calibration, samples))
}

/// The costs one light count's rows give: those of `pixel`, `vertex` and `multirate` estimating
/// every visible triangle; of `vertex` and `multirate` shading every triangle per pixel, at the
/// scene's resolution and the small one; of `vertex`, `fixed:1` and `fixed:4`.
fn sample(scene: &Scene, lights: usize, [rows, per_pixel, tessellated]: [&[Row]; 3]) -> CostSample {
    fn find<'a>(rows: &'a [Row], mode: &str) -> &'a Row {
        rows.iter().find(|row| row.mode == mode).expect("measured")
    }
    let above = |row: &Row, base: &Row| (row.gpu_ms.median - base.gpu_ms.median).max(0.0) * 1.0e6;
    let (pixel, vertex, multirate) = (find(rows, "pixel"), find(rows, "vertex"), find(rows, "multirate"));
    // The per-pixel path above `vertex` and the fragments it shaded, at the scene's resolution,
    // then at the small one: a cost per triangle and one per fragment.
    let fallback_at = |width: u32| {
        let at: Vec<Row> = per_pixel.iter().filter(|row| row.width == width).cloned().collect();
        let (fallback, vertex) = (find(&at, "multirate"), find(&at, "vertex"));
        (above(fallback, vertex), fallback.evaluations.fragments)
    };
    let (large, small) = (fallback_at(scene.settings.width), fallback_at(small_resolution(scene).0));
    let visible_triangles = listed_triangles(scene).len().max(1);
    let fallback_ns = (large.0 - small.0).max(0.0) / large.1.saturating_sub(small.1).max(1) as f64;
    let fallback_triangle_ns = (small.0 - fallback_ns * small.1 as f64).max(0.0) / visible_triangles as f64;
    let (patch_vertex, level_1, level_4) =
        (find(tessellated, "vertex"), find(tessellated, "fixed:1"), find(tessellated, "fixed:4"));
    // The range class runs on every listed triangle before the area rule (`small_per_pixel`), so
    // what an image too small to pay would cost is the full estimate.
    let estimate_ms = multirate.pre_pass_steps_ms.map_or(0.0, |steps| steps[PrePassStep::Estimate as usize]);
    let estimated_triangles = estimated_triangles(scene).max(1);
    let fragments = pixel.evaluations.fragments.max(1);
    let patches = level_1.triangles.max(1);
    let added_sub_vertices =
        level_4.evaluations.sub_vertices.saturating_sub(level_1.evaluations.sub_vertices).max(1);
    CostSample {
        lights,
        estimate_ns: estimate_ms * 1.0e6 / estimated_triangles as f64,
        pixel_ns: above(pixel, vertex) / fragments as f64,
        fallback_ns,
        fallback_triangle_ns,
        patch_ns: above(level_1, patch_vertex) / patches as f64,
        sub_vertex_ns: above(level_4, level_1) / added_sub_vertices as f64,
        estimated_triangles,
        fragments,
        fallback_fragments: [large.1, small.1],
        visible_triangles,
        patches,
        added_sub_vertices,
    }
}

/// The triangles the pre-pass estimates with the scene's camera at its size and ε: those it
/// lists ([`listed_triangles`]) that the range class does not settle (with no area floor; a
/// parameter map's range is taken as the material's own value).
pub fn estimated_triangles(scene: &Scene) -> usize {
    let settled = |(mesh, input): &(usize, TriangleInput)| {
        let material = &scene.materials[scene.meshes[*mesh].material].kind;
        let parameter = ParameterRange::of(material);
        settled_by_range(input, material, parameter, &scene.lights, (scene.settings.epsilon, 0.0))
    };
    listed_triangles(scene).iter().filter(|triangle| !settled(triangle)).count()
}

/// The triangles the pre-pass lists with the scene's camera at its size, each with its mesh's
/// index: neither culled nor back faces shaded per pixel (which the back-face draw draws).
pub fn listed_triangles(scene: &Scene) -> Vec<(usize, TriangleInput)> {
    let (width, height) = (scene.settings.width, scene.settings.height);
    let view_proj = view_projection(&scene.camera, width, height);
    let rule = PerPixelRule {
        view_proj,
        eye: scene.camera.eye,
        viewport: Vec2::new(width as f32, height as f32),
        min_estimated_area: 0.0,
    };
    let mut listed = Vec::new();
    for (index, mesh) in scene.meshes.iter().enumerate() {
        for corners in mesh.indices.chunks_exact(3) {
            let input = TriangleInput::of(mesh, corners, scene.camera.eye);
            let (p, one_sided) = (input.positions, !mesh.two_sided);
            if !culled(&view_proj, scene.camera.eye, p, one_sided)
                && !back_face_per_pixel(&rule, p, one_sided)
            {
                listed.push((index, input));
            }
        }
    }
    listed
}

/// The per-pixel path's second, small resolution for `scene`.
pub fn small_resolution(scene: &Scene) -> (u32, u32) {
    let (width, height) = (scene.settings.width, scene.settings.height);
    ((width / SMALL_RESOLUTION_DIVISOR).max(1), (height / SMALL_RESOLUTION_DIVISOR).max(1))
}

/// `scene` with its lights replaced by `count` white point lights on a golden-angle spiral
/// around the camera's target, at the distance of its first point light (or of the camera),
/// each of the same intensity.
pub fn lit_by(scene: &Scene, count: usize) -> Scene {
    let target = scene.camera.target;
    let (distance, intensity) = scene
        .lights
        .iter()
        .find_map(|light| match light {
            Light::Point { position, intensity, .. } => Some((position.distance(target), *intensity)),
            _ => None,
        })
        .unwrap_or((scene.camera.eye.distance(target), 100.0));
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let lights = (0..count)
        .map(|k| {
            // Heights from near the top down to the horizon, so that every light reaches the
            // side the camera sees from above.
            let y = 1.0 - (k as f32 + 0.5) / count as f32;
            let radius = (1.0 - y * y).sqrt();
            let angle = golden * k as f32;
            let direction = Vec3::new(radius * angle.cos(), y, radius * angle.sin());
            Light::Point {
                position: target + direction * distance,
                color: Vec3::ONE,
                intensity: intensity / count as f32,
            }
        })
        .collect();
    Scene { lights, ..scene.clone() }
}
