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
//! fragments, a pixel of multirate's per-pixel path the fourth configuration's time above
//! `vertex`'s over the same fragments, a tessellated patch `fixed:1`'s time above `vertex`'s over
//! the triangles, and a sub-vertex `fixed:4`'s above `fixed:1`'s over the sub-vertices it adds.

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

/// One light count's measurement.
#[derive(Clone, Copy, Debug)]
pub struct CostSample {
    pub lights: usize,
    /// Nanoseconds per estimated triangle.
    pub estimate_ns: f64,
    /// Nanoseconds per fragment shaded per pixel, by `pixel` mode and by multirate's
    /// per-pixel path.
    pub pixel_ns: f64,
    pub fallback_ns: f64,
    /// Nanoseconds per triangle drawn as a patch at level 1 above `vertex`'s draw, and per
    /// sub-vertex added at level 4.
    pub patch_ns: f64,
    pub sub_vertex_ns: f64,
    /// The triangles the pre-pass estimated, the fragments `pixel` shaded, the patches drawn
    /// and the sub-vertices `fixed:4` shaded above `fixed:1`.
    pub estimated_triangles: usize,
    pub fragments: u64,
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
        eye_ball_share: 0.0,
    };
    // Every triangle per pixel: ε 0, which the range class never settles, and an area floor
    // above every image; with `vertex` of the same turns.
    let per_pixel = BenchConfig {
        modes: vec![Mode::Vertex, Mode::Multirate],
        epsilons: vec![0.0],
        min_estimated_areas: vec![Some(EVERY_IMAGE)],
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
/// every visible triangle; of `vertex` and `multirate` shading every triangle per pixel; of
/// `vertex`, `fixed:1` and `fixed:4`.
fn sample(scene: &Scene, lights: usize, [rows, per_pixel, tessellated]: [&[Row]; 3]) -> CostSample {
    fn find<'a>(rows: &'a [Row], mode: &str) -> &'a Row {
        rows.iter().find(|row| row.mode == mode).expect("measured")
    }
    let above = |row: &Row, base: &Row| (row.gpu_ms.median - base.gpu_ms.median).max(0.0) * 1.0e6;
    let (pixel, vertex, multirate) = (find(rows, "pixel"), find(rows, "vertex"), find(rows, "multirate"));
    let (fallback_vertex, fallback) = (find(per_pixel, "vertex"), find(per_pixel, "multirate"));
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
        fallback_ns: above(fallback, fallback_vertex) / fragments as f64,
        patch_ns: above(level_1, patch_vertex) / patches as f64,
        sub_vertex_ns: above(level_4, level_1) / added_sub_vertices as f64,
        estimated_triangles,
        fragments,
        patches,
        added_sub_vertices,
    }
}

/// The triangles the pre-pass estimates with the scene's camera at its size and ε: neither
/// culled, nor back faces shaded per pixel, nor settled by the range class (with no area
/// floor; a parameter map's range is taken as the material's own value).
pub fn estimated_triangles(scene: &Scene) -> usize {
    let (width, height) = (scene.settings.width, scene.settings.height);
    let view_proj = view_projection(&scene.camera, width, height);
    let rule = PerPixelRule {
        view_proj,
        eye: scene.camera.eye,
        viewport: Vec2::new(width as f32, height as f32),
        min_estimated_area: 0.0,
    };
    let mut count = 0;
    for mesh in &scene.meshes {
        let material = &scene.materials[mesh.material].kind;
        for corners in mesh.indices.chunks_exact(3) {
            let input = TriangleInput::of(mesh, corners, scene.camera.eye);
            let (p, one_sided) = (input.positions, !mesh.two_sided);
            if culled(&view_proj, scene.camera.eye, p, one_sided) || back_face_per_pixel(&rule, p, one_sided)
            {
                continue;
            }
            let parameter = ParameterRange::of(material);
            if !settled_by_range(&input, material, parameter, &scene.lights, (scene.settings.epsilon, 0.0)) {
                count += 1;
            }
        }
    }
    count
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
