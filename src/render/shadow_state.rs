//! The shadows as the renderer holds them: the atlas and the pipeline that draws it, the
//! layout its maps are drawn with, and every triangle's visibility classes from the maps as
//! drawn. Point lights' maps are drawn once; a directional light's map is fitted to what the
//! camera sees (`geometry::shadow_fit`) and drawn again, its classes computed anew, when a view
//! leaves the square it was drawn for or needs a much finer one ([`Shadows::fit`]).

use super::scene_buffers::SceneBuffers;
use super::scene_geometry::{gpu_shadow_maps, with_classes, DrawCall, SceneGeometry};
use super::shadows::{shadow_pipeline, AtlasBefore, ShadowAtlas};
use crate::error::Result;
use crate::geometry::shadow_class::{ShadowClasses, ShadowDepths};
use crate::geometry::shadow_fit::{DirectionalFit, DirectionalFrame};
use crate::geometry::shadow_view::{Projection, ShadowLayout};
use crate::scene::{bounds_of, Camera, Light, Scene};
use crate::vk::memory::Buffer;
use crate::vk::pipeline::{Pipeline, PipelineLayout, ShaderModule};
use crate::vk::Context;
use ash::vk;
use glam::Vec3;
use std::sync::{Arc, Mutex};
use std::time::Instant;

/// How often directional maps were drawn again for the views since the renderer was made, and
/// what that took.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ShadowRefits {
    /// Times the maps were drawn again (all refitted maps of one view count once).
    pub count: u32,
    /// The GPU time of those draws, ms.
    pub gpu_ms: f64,
    /// The wall time of the refits: waiting for the device, the draws, reading them back, the
    /// classes and their upload, ms.
    pub wall_ms: f64,
}

/// A directional light's map that follows the view.
#[derive(Clone, Copy)]
struct FittedMap {
    /// Its index in `ShadowLayout::maps`, its light's slot and its kernel's radius in texels.
    map: usize,
    slot: usize,
    radius: u32,
    fit: DirectionalFit,
}

/// What changes as the view does.
struct Fitted {
    layout: ShadowLayout,
    directional: Vec<FittedMap>,
    classes: ShadowClasses,
    refits: ShadowRefits,
}

pub(super) struct Shadows {
    pub atlas: ShadowAtlas,
    pipeline: Option<Pipeline>,
    /// The scene's lights and the box of its meshes.
    lights: Vec<Light>,
    bounds: (Vec3, Vec3),
    /// Per triangle, its corners as `PrePassBuffers::triangle_corners` holds them (kept where a
    /// directional light casts shadows: its classes are uploaded again with each refit).
    corners: Vec<[[f32; 4]; 3]>,
    fitted: Mutex<Fitted>,
    /// The GPU time of the first draw of every map, ms (none without a map).
    pub first_pass_ms: Option<f64>,
}

impl Shadows {
    /// Draws every map of `scene` into `atlas` (directional ones fitted to the whole box until a
    /// view says otherwise) with the pipeline built from `pass`, classifies every triangle and
    /// uploads the classes into `triangle_corners`.
    pub(super) fn draw_all(
        context: &Arc<Context>,
        (scene, geometry): (&Scene, &SceneGeometry),
        atlas: ShadowAtlas,
        pass: (&PipelineLayout, &ShaderModule),
        (buffers, triangle_corners): (&SceneBuffers, &Buffer),
    ) -> Result<Shadows> {
        let layout = geometry.shadows.clone();
        let pipeline = shadow_pipeline(context, &layout, pass)?;
        let every_map: Vec<usize> = (0..layout.maps.len()).collect();
        let drawn = atlas.draw(
            context,
            (pass.0, pipeline.as_ref()),
            buffers,
            (&layout, &every_map),
            &geometry.draws,
            AtlasBefore::Nothing,
        )?;
        let bounds = bounds_of(scene.meshes.iter().flat_map(|m| m.positions.iter().copied()));
        let directional = directional_maps(scene, &layout, bounds);
        let classes = if scene.shadow_casters.is_empty() {
            ShadowClasses::default()
        } else {
            let depths = ShadowDepths::of_maps(&layout, &drawn.maps);
            let classes = ShadowClasses::of(scene, &layout, &depths);
            triangle_corners.upload(&with_classes(&geometry.triangle_corners, &classes))?;
            classes
        };
        let corners = if directional.is_empty() { Vec::new() } else { geometry.triangle_corners.clone() };
        Ok(Shadows {
            atlas,
            pipeline,
            lights: scene.lights.clone(),
            bounds,
            corners,
            fitted: Mutex::new(Fitted { layout, directional, classes, refits: ShadowRefits::default() }),
            first_pass_ms: drawn.milliseconds,
        })
    }

    /// Every triangle's visibility class per shadow-casting light, from the maps as drawn now.
    pub(super) fn classes(&self) -> ShadowClasses {
        self.fitted.lock().expect("shadow lock").classes.clone()
    }

    /// The maps' layout as drawn now.
    pub(super) fn layout(&self) -> ShadowLayout {
        self.fitted.lock().expect("shadow lock").layout.clone()
    }

    /// The refits so far.
    pub(super) fn refits(&self) -> ShadowRefits {
        self.fitted.lock().expect("shadow lock").refits
    }

    /// Fits the directional lights' maps to what `camera` sees on a target of `extent`: where a
    /// map no longer serves it, waits for the device, draws those maps again with `pass`'s
    /// layout into their squares, classifies every triangle against them anew and uploads the
    /// maps' records and the classes (`buffers.shadow_maps`, `triangle_corners`). Returns
    /// whether it did: the levels kept for a ball of eyes hold for the classes before.
    pub(super) fn fit(
        &self,
        context: &Arc<Context>,
        (camera, extent): (&Camera, vk::Extent2D),
        pipeline_layout: &PipelineLayout,
        (buffers, triangle_corners): (&SceneBuffers, &Buffer),
        draws: &[DrawCall],
    ) -> Result<bool> {
        let mut fitted = self.fitted.lock().expect("shadow lock");
        if fitted.directional.is_empty() {
            return Ok(false);
        }
        let aspect = extent.width as f32 / extent.height.max(1) as f32;
        let (lo, hi) = self.bounds;
        let mut changed = Vec::new();
        for (k, fitted_map) in fitted.directional.iter().enumerate() {
            let size = fitted.layout.maps[fitted_map.map].size;
            let seen = fitted_map.fit.frame.seen(camera, aspect, lo, hi);
            if let Some(square) = fitted_map.fit.refit_for(seen, size, fitted_map.radius) {
                changed.push((k, square));
            }
        }
        if changed.is_empty() {
            return Ok(false);
        }
        let start = Instant::now();
        context.wait_idle()?;
        let Fitted { layout, directional, classes, refits } = &mut *fitted;
        for &(k, square) in &changed {
            let fitted_map = &mut directional[k];
            fitted_map.fit.square = square;
            let (view_proj, width) = fitted_map.fit.frame.map(square);
            let record = &mut layout.maps[fitted_map.map];
            record.projection = Projection::Orthographic(view_proj);
            record.texel_width = width / record.size as f32;
        }
        let maps: Vec<usize> = changed.iter().map(|&(k, _)| directional[k].map).collect();
        let slots: Vec<usize> = changed.iter().map(|&(k, _)| directional[k].slot).collect();
        let drawn = self.atlas.draw(
            context,
            (pipeline_layout, self.pipeline.as_ref()),
            buffers,
            (layout, &maps),
            draws,
            AtlasBefore::Maps,
        )?;
        let depths = ShadowDepths::of_maps(layout, &drawn.maps);
        let triangles = self.corners.iter().map(|c| c.map(|t| Vec3::new(t[0], t[1], t[2])));
        classes.reclassify(&self.lights, layout, &depths, triangles, &slots);
        buffers.shadow_maps.upload(&gpu_shadow_maps(layout))?;
        triangle_corners.upload(&with_classes(&self.corners, classes))?;
        refits.count += 1;
        refits.gpu_ms += drawn.milliseconds.unwrap_or(0.0);
        refits.wall_ms += start.elapsed().as_secs_f64() * 1e3;
        Ok(true)
    }
}

/// The directional lights' maps of `layout`, each fitted to the whole box `bounds` of `scene`.
fn directional_maps(scene: &Scene, layout: &ShadowLayout, (lo, hi): (Vec3, Vec3)) -> Vec<FittedMap> {
    layout
        .by_slot
        .iter()
        .enumerate()
        .filter_map(|(slot, &light)| match scene.lights[light] {
            Light::Directional { direction, .. } => {
                let shadow = layout.lights[light].expect("a slot's light has a map");
                let frame = DirectionalFrame::new(direction, lo, hi);
                Some(FittedMap {
                    map: shadow.map as usize,
                    slot,
                    radius: shadow.radius,
                    fit: DirectionalFit::whole(frame),
                })
            }
            _ => None,
        })
        .collect()
}
