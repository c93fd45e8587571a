//! `multirate analyze`: per visible triangle, the estimator's levels (each term's, the
//! real-valued `Estimate::level` and the uniform `n`) and the levels the control stage
//! writes for its patch (`patch_levels` of its own and its three neighbours' levels: the
//! twin the GPU agreement test compares with), and optionally the oracle's truth on the
//! pattern the driver really emits for those levels (`triangle_pattern(inner, outer)`).
//! Where the scene's lights cast shadows, each triangle's estimate sums the lights its
//! visibility classes let reach it, in the shaders' order (`ShadowClasses::lights_reaching`).

use super::measured::Measured;
use super::oracle::{oracle_level, true_error_textured, vertices_at_level, SAMPLES_PER_EDGE};
use super::tessellator::triangle_pattern;
use crate::geometry::camera::view_projection;
use crate::geometry::cull::{
    back_face_per_pixel, culled, faces_away, small_per_pixel, PerPixelRule, CULLED_LEVEL,
};
use crate::geometry::shadow_class::ShadowClasses;
use crate::scene::adjacency::{adjacency_patches, neighbours, PATCH_SIZE};
use crate::scene::texture::PowerSat;
use crate::scene::{with_parameter, Light, ParameterRange, Scene};
use crate::shading::estimator::{
    estimate_textured, patch_levels, settled_by_range, Estimate, EstimatorSettings, PatchLevels,
    TriangleInput, FALLBACK_LEVEL, TERM_NAMES,
};
use glam::Vec2;
use std::borrow::Cow;
use std::collections::HashMap;
use std::fmt::Write as _;

/// One analysed triangle.
#[derive(Clone, Debug)]
pub struct TriangleReport {
    pub mesh: usize,
    pub triangle: usize,
    pub estimate: Estimate,
    /// The levels the control stage writes for this patch (`patch_levels` of its own and
    /// its three neighbours' `Estimate::level`), exactly as the GPU computes them.
    pub levels: PatchLevels,
    /// The level the patch is shaded at, as the control stage records it: 0 for per-pixel
    /// fallback, else the (rounded-up) inner level.
    pub patch_level: u32,
    /// Outer levels as the control stage sets them, rounded up as the driver does.
    pub outer: [u32; 3],
    /// Smallest uniform level whose true error is ≤ ε (None: above n_max).
    pub oracle_n: Option<u32>,
    /// True L∞ error (max over channels) on the pattern the driver really emits for
    /// `levels` (None for fallback patches).
    pub true_error: Option<f64>,
    /// Culled before its estimate (`geometry::cull`): not drawn, outer levels 0. Only
    /// `Triangles::All` reports culled triangles.
    pub culled: bool,
    /// A back face of a two-sided mesh (`geometry::cull::back_face_per_pixel`): shaded per pixel
    /// whatever its estimate, which is reported all the same.
    pub back_face: bool,
    /// Not a back face nor settled by the range class, but an image smaller than the settings'
    /// `min_estimated_area` (`geometry::cull::small_per_pixel`): shaded per pixel without an
    /// estimate on the GPU.
    pub small_image: bool,
}

/// Vertices (shading evaluations) of the pattern with these levels.
pub fn pattern_vertices(levels: &PatchLevels) -> u64 {
    triangle_pattern(levels.inner, levels.outer).vertices.len() as u64
}

/// Totals over the analysed triangles.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Summary {
    pub triangles: usize,
    /// Patches shaded per pixel (the estimator's fallbacks, the patches no inner level fits and
    /// the back faces of two-sided meshes).
    pub fallbacks: usize,
    /// Of the fallbacks, the back faces of two-sided meshes (never estimated on the GPU).
    pub back_faces: usize,
    /// Of the fallbacks, the images below `min_estimated_area` (never estimated on the GPU).
    pub small_images: usize,
    /// Tessellated vertices the control stage's levels shade (fallback patches excluded),
    /// shared-edge levels included.
    pub estimator_evaluations: u64,
    /// Tessellated vertices the oracle's levels would shade, over the same triangles.
    pub oracle_evaluations: u64,
    /// Tessellated triangles whose true error exceeds ε.
    pub violations: usize,
}

/// Which triangles to analyse.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Triangles {
    /// Those the control stage does not cull (`geometry::cull`): in the camera's view frustum,
    /// and front-facing where the mesh is one-sided.
    Visible,
    /// All, in scene order (meshes in order): what the GPU's level records hold.
    All,
}

/// How a parameter map's range over a triangle is found (seed 003 Sec. 3.5).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TextureBounds {
    /// The min/max pyramid: exact and conservative; what the control stage does.
    Pyramid,
    /// The paper's summed-area tables with normalized power-weighted filtering at this power
    /// (not conservative: a power mean never reaches the extremes).
    PowerSat(f64),
}

impl std::str::FromStr for TextureBounds {
    type Err = String;
    fn from_str(text: &str) -> Result<TextureBounds, String> {
        if text == "pyramid" {
            return Ok(TextureBounds::Pyramid);
        }
        match text.strip_prefix("sat:").map(str::parse::<f64>) {
            Some(Ok(p)) if p > 0.0 && p.is_finite() => Ok(TextureBounds::PowerSat(p)),
            _ => Err(format!("\"{text}\": expected `pyramid` or `sat:P` with a power P > 0")),
        }
    }
}

/// Analyses the `which` triangles of `scene`; with `with_oracle` also the brute-force truth.
/// Textured parameters take their range over each triangle by `bounds`. `shadows`: the
/// visibility classes of the scene's triangles against its shadow maps (`Renderer::shadow_classes`),
/// by which each triangle's estimate leaves out the lights that reach none of it; None: every
/// light reaches every triangle.
pub fn analyze(
    scene: &Scene,
    settings: &EstimatorSettings,
    which: Triangles,
    with_oracle: bool,
    bounds: TextureBounds,
    shadows: Option<&ShadowClasses>,
) -> Vec<TriangleReport> {
    let view_proj = view_projection(&scene.camera, scene.settings.width, scene.settings.height);
    let n_max = settings.n_max.clamp(1, 64);
    let mut reports = Vec::new();
    let mut first_triangle = 0;
    for (mesh_index, mesh) in scene.meshes.iter().enumerate() {
        let mesh_first = first_triangle;
        first_triangle += mesh.indices.len() / 3;
        // The lights mesh triangle `t`'s estimate sums.
        let lights_of = |t: usize| match shadows {
            Some(classes) => Cow::Owned(classes.lights_reaching(&scene.lights, mesh_first + t)),
            None => Cow::Borrowed(&scene.lights[..]),
        };
        let across = neighbours(mesh);
        let material = &scene.materials[mesh.material].kind;
        let input = |corners: &[u32]| TriangleInput::of(mesh, corners, scene.camera.eye);
        let map = scene.materials[mesh.material].maps.parameter.as_ref();
        let sat = match (map, bounds) {
            (Some(map), TextureBounds::PowerSat(p)) => Some(PowerSat::new(&map.texture, p)),
            _ => None,
        };
        // The parameter's range over a triangle's texels, as the control stage reads it (or
        // as the paper estimates it).
        let range = |corners: &[u32]| {
            let uvs = || [0, 1, 2].map(|k| mesh.uvs[corners[k] as usize]);
            match (map, &sat) {
                (Some(map), Some(sat)) => {
                    let uvs = uvs();
                    let (lo, hi) = sat.query(uvs[0].min(uvs[1]).min(uvs[2]), uvs[0].max(uvs[1]).max(uvs[2]));
                    ParameterRange { lo: map.value(lo), hi: map.value(hi.max(lo)) }
                }
                (Some(map), None) => map.range_over(uvs()),
                (None, _) => ParameterRange::of(material),
            }
        };
        let estimate_of = |corners: &[u32], lights: &[Light]| {
            estimate_textured(&input(corners), material, range(corners), lights, settings)
        };
        let positions_of = |corners: &[u32]| [0, 1, 2].map(|k| mesh.positions[corners[k] as usize]);
        let culled_of =
            |corners: &[u32]| culled(&view_proj, scene.camera.eye, positions_of(corners), !mesh.two_sided);
        let rule = PerPixelRule {
            view_proj,
            eye: scene.camera.eye,
            viewport: Vec2::new(scene.settings.width as f32, scene.settings.height as f32),
            min_estimated_area: settings.min_estimated_area,
        };
        // As triangle_level.glsl's visible_level: a back face of a two-sided mesh falls back
        // without an estimate; then the range class settles a triangle at level 1, or an image
        // too small to pay for an estimate falls back without one.
        let settled_of = |corners: &[u32], lights: &[Light]| {
            settled_by_range(
                &input(corners),
                material,
                range(corners),
                lights,
                (settings.epsilon, settings.eye_radius),
            )
        };
        let per_pixel_of = |corners: &[u32], lights: &[Light]| {
            let positions = positions_of(corners);
            // The range bound only where the area rule would apply: estimate_of runs it again.
            back_face_per_pixel(&rule, positions, !mesh.two_sided)
                || (small_per_pixel(&rule, positions) && !settled_of(corners, lights))
        };
        let level_of = |corners: &[u32], lights: &[Light]| {
            if culled_of(corners) {
                CULLED_LEVEL
            } else if per_pixel_of(corners, lights) {
                FALLBACK_LEVEL
            } else {
                estimate_of(corners, lights).level
            }
        };
        let patches = adjacency_patches(mesh);
        for (triangle, patch) in patches.chunks_exact(PATCH_SIZE).enumerate() {
            let own_culled = culled_of(&patch[0..3]);
            if which == Triangles::Visible && own_culled {
                continue;
            }
            let own = input(&patch[0..3]);
            let lights = lights_of(triangle);
            let own_estimate = estimate_of(&patch[0..3], &lights);
            let per_pixel = per_pixel_of(&patch[0..3], &lights);
            let back_face = mesh.two_sided && faces_away(scene.camera.eye, positions_of(&patch[0..3]));
            let neighbours = [0, 1, 2].map(|edge| {
                let corners = &patch[3 + 3 * edge..6 + 3 * edge];
                level_of(corners, &lights_of(across[triangle][edge] as usize))
            });
            let own_level = if per_pixel { FALLBACK_LEVEL } else { own_estimate.level };
            let levels = patch_levels(own_level, neighbours, n_max);
            let (oracle_n, true_err) = if with_oracle {
                let oracle = oracle_level(&own, material, &lights, settings.epsilon as f64, n_max, |n| {
                    triangle_pattern(n as f32, [n as f32; 3])
                });
                let error = (!levels.fallback).then(|| {
                    let pattern = triangle_pattern(levels.inner, levels.outer);
                    // A textured parameter is sampled at the point's uv (finest level).
                    let uvs = [0, 1, 2].map(|k| mesh.uvs.get(patch[k] as usize).copied().unwrap_or_default());
                    let material_at = |b: [f64; 3]| match map {
                        Some(map) => {
                            let uv = (uvs[0].as_dvec2() * b[0]
                                + uvs[1].as_dvec2() * b[1]
                                + uvs[2].as_dvec2() * b[2])
                                .as_vec2();
                            with_parameter(material, map.value(map.texture.sample_parameter(uv, 0.0)))
                        }
                        None => *material,
                    };
                    true_error_textured(
                        &own,
                        &material_at,
                        &lights,
                        &pattern,
                        SAMPLES_PER_EDGE,
                        f64::INFINITY,
                    )
                    .into_iter()
                    .fold(0.0, f64::max)
                });
                (oracle, error)
            } else {
                (None, None)
            };
            reports.push(TriangleReport {
                mesh: mesh_index,
                triangle,
                estimate: own_estimate,
                levels,
                patch_level: if levels.fallback { 0 } else { levels.inner.ceil() as u32 },
                outer: levels.outer.map(|o| o.ceil() as u32),
                oracle_n,
                true_error: true_err,
                culled: own_culled,
                back_face,
                small_image: per_pixel && !back_face,
            });
        }
    }
    reports
}

/// Totals of `reports` for threshold `epsilon`.
pub fn summarize(reports: &[TriangleReport], epsilon: f32) -> Summary {
    let mut summary = Summary { triangles: reports.len(), ..Summary::default() };
    for report in reports {
        if report.levels.fallback {
            summary.fallbacks += 1;
            summary.back_faces += usize::from(report.back_face);
            summary.small_images += usize::from(report.small_image);
            continue;
        }
        summary.estimator_evaluations += pattern_vertices(&report.levels);
        if let Some(n) = report.oracle_n {
            summary.oracle_evaluations += vertices_at_level(n);
        }
        if report.true_error.is_some_and(|e| e > epsilon as f64) {
            summary.violations += 1;
        }
    }
    summary
}

/// The CSV of `reports`: one row per triangle, one column per estimator term, then the real
/// level, the uniform `n`, the patch's level and outer levels as the control stage writes them
/// (`patch_level` 0: per-pixel fallback, `reason` `BackFace` for a back face of a two-sided
/// mesh, `SmallImage` for an image below `min_estimated_area`, `Mixed` when only the mixed
/// pattern is why).
/// `measured`: per `(mesh, triangle)` the GPU-measured error (`analyze --measured`), written
/// as `measured_error,measured_pixels` (empty for triangles without interior pixels).
pub fn to_csv(
    reports: &[TriangleReport],
    with_oracle: bool,
    measured: Option<&HashMap<(usize, usize), Measured>>,
) -> String {
    let mut csv = String::from("mesh,triangle");
    for name in TERM_NAMES {
        let _ = write!(csv, ",n_{name}");
    }
    csv.push_str(",level,n,patch_level,outer0,outer1,outer2,fallback,reason,predicted_error");
    if with_oracle {
        csv.push_str(",oracle_n,true_error");
    }
    if measured.is_some() {
        csv.push_str(",measured_error,measured_pixels");
    }
    csv.push('\n');
    for r in reports {
        let _ = write!(csv, "{},{}", r.mesh, r.triangle);
        for value in r.estimate.terms {
            let _ = write!(csv, ",{value}");
        }
        // `reason` is the estimator's; `BackFace` marks a back face of a two-sided mesh,
        // `SmallImage` an image below `min_estimated_area`, and `Mixed` a patch that falls back
        // only because no inner level makes its transition strips fine enough.
        let reason = if r.back_face {
            "BackFace".to_string()
        } else if r.small_image {
            "SmallImage".to_string()
        } else if r.levels.fallback && !r.estimate.fallback {
            "Mixed".to_string()
        } else {
            format!("{:?}", r.estimate.reason)
        };
        let _ = write!(
            csv,
            ",{},{},{},{},{},{},{},{},{}",
            r.estimate.level,
            r.estimate.n,
            r.patch_level,
            r.outer[0],
            r.outer[1],
            r.outer[2],
            r.levels.fallback,
            reason,
            r.estimate.predicted_error
        );
        if with_oracle {
            let oracle = r.oracle_n.map_or("above_n_max".to_string(), |n| n.to_string());
            let error = r.true_error.map_or(String::new(), |e| e.to_string());
            let _ = write!(csv, ",{oracle},{error}");
        }
        if let Some(measured) = measured {
            match measured.get(&(r.mesh, r.triangle)) {
                Some(m) => {
                    let _ = write!(csv, ",{},{}", m.error, m.pixels);
                }
                None => csv.push_str(",,0"),
            }
        }
        csv.push('\n');
    }
    csv
}
