//! Rendering a scene: GPU copies of the scene, the pipeline variants specialised to its
//! materials and lights, and the forward pass that draws into a render target.
//!
//! [`Renderer`] is the façade; its rooms:
//! - `mode` and `view`: what a frame is rendered with ([`Mode`], [`Placement`], [`View`]);
//! - `scene_buffers`: the scene uploaded, the per-scene buffers and set 0's binding table;
//! - `descriptors`: the forward layout and its descriptor sets;
//! - `pipelines`: the pipeline variants, built on first use;
//! - `pre_pass`: the triangle-level pre-pass of `multirate` mode's compute placement;
//! - `draws`: the forward draws (and lavapipe's limits on them);
//! - `instrumentation`: timings, evaluation counts, analysis frames and level records;
//! - [`deferred`]: the `pixel-deferred` passes;
//! - [`cost_model`]: where estimating a triangle's level pays, per device;
//! - [`guard`]: whether a frame is drawn the multirate way or as `pixel` draws it, from the
//!   times of recent frames drawn each way;
//! - [`capture`], [`limits`], [`output`], [`present`], [`textures`]: the tessellation
//!   pattern check, the scene's limits, image files, presentation and the scene's textures.

pub mod capture;
pub mod cost_model;
pub mod deferred;
mod descriptors;
mod draws;
pub mod guard;
mod instrumentation;
mod level_ball;
pub mod limits;
mod mode;
pub mod output;
mod pipelines;
mod pre_pass;
pub mod present;
mod scene_buffers;
pub mod textures;
mod view;

pub use draws::draw_splitting_note;
pub use instrumentation::{Analysis, CameraTurn, EvaluationCounts, Measurement};
pub use mode::{Mode, Placement, MAX_LEVEL};
pub use pre_pass::{PrePassStep, PRE_PASS_GROUP, PRE_PASS_STEPS, REFINE_BLOCK};
pub use scene_buffers::{gpu_lights, gpu_polygon_lights};
pub use view::{View, EYE_BALL_SHARE};

use deferred::Deferred;
use descriptors::ForwardDescriptors;
use draws::{tessellated_vertex_budget, DrawCall, Draws, EmitterDraw};
use instrumentation::Timed;
use limits::SceneSizes;
use pipelines::{Instrumentation, Pipelines, Variant};
use scene_buffers::{SceneBuffers, SceneGeometry};

use crate::error::Result;
use crate::scene::{Light, Scene};
use crate::vk::context::DeviceLimits;
use crate::vk::target::{AfterPass, Attachments, FloatImage, RenderTarget};
use crate::vk::Context;
use ash::vk;
use cost_model::{CostModel, MeshSample};
use guard::{FramePath, GuardKey, Guards};
use std::cell::OnceCell;
use std::sync::{Arc, Mutex};

/// A scene uploaded to the GPU with its specialised pipelines.
pub struct Renderer {
    context: Arc<Context>,
    /// The scene's vertices, indices, lights and materials, the pre-pass's buffers and the
    /// instrumentation's records.
    buffers: SceneBuffers,
    /// The forward layout, set 0 bound to `buffers`, and the materials' textures and sets.
    descriptors: ForwardDescriptors,
    /// One per mesh, in scene order.
    draws: Vec<DrawCall>,
    /// The polygonal lights' emissive geometry, one fan each.
    emitters: Vec<EmitterDraw>,
    /// The pipeline variants (timed, wireframe, counting, level-recording) and the modules
    /// they share.
    pipelines: Pipelines,
    /// The device's own effective-level table in `SceneBuffers::pattern_levels`, where the
    /// built-in one does not hold on it (`capture::check_patterns`).
    measured_table: Mutex<Option<Arc<Vec<u32>>>>,
    /// The `pixel-deferred` passes, built on first use.
    deferred: OnceCell<Deferred>,
    clear_color: [f32; 4],
    /// Most tessellated vertices one draw may emit, where the driver needs a limit
    /// (lavapipe: `draws::tessellated_vertex_budget`).
    tessellated_vertex_budget: Option<u32>,
    /// Where estimating pays on this device (views with `cost_model` set).
    cost_model: CostModel,
    /// Per draw, the triangles that stand for its mesh in the cost model's per-mesh choice.
    mesh_samples: Vec<MeshSample>,
    /// The scene's lights: the cost model weighs their count, and the per-mesh choice tries the
    /// range class under them.
    lights: Vec<Light>,
    /// The frame guards of the configurations drawn so far (`guarded`, `report_frame_time`).
    guards: Mutex<Guards>,
    /// The ball of eyes the pre-pass's kept levels hold for (`level_ball`).
    level_ball: Mutex<Option<level_ball::LevelBall>>,
}

impl Renderer {
    /// Uploads `scene` and prepares its pipelines, once the scene was found to fit the device
    /// and the shaders (`limits::check`).
    pub fn new(context: &Arc<Context>, scene: &Scene) -> Result<Renderer> {
        Renderer::with_limits(context, scene, &context.limits)
    }

    /// [`Renderer::new`], checking the scene against `limits` where they are lower than the
    /// device's own (the tests reach each check with a small scene that way); never against
    /// higher ones.
    pub fn with_limits(context: &Arc<Context>, scene: &Scene, limits: &DeviceLimits) -> Result<Renderer> {
        limits::check(&scene.path, &SceneSizes::of(scene), &limits.min(&context.limits))?;
        let geometry = SceneGeometry::of(scene);
        let buffers = SceneBuffers::upload(context, &geometry)?;
        let descriptors = ForwardDescriptors::new(context, scene, &buffers)?;
        let pipelines = Pipelines::new(context, scene, &descriptors.layout, &geometry)?;
        let clear = scene.settings.clear_color;
        Ok(Renderer {
            context: context.clone(),
            buffers,
            descriptors,
            draws: geometry.draws,
            emitters: geometry.emitters,
            pipelines,
            measured_table: Mutex::new(None),
            deferred: OnceCell::new(),
            clear_color: [clear.x, clear.y, clear.z, 0.0],
            tessellated_vertex_budget: tessellated_vertex_budget(&context.info),
            cost_model: CostModel::for_device(&context.info.name),
            mesh_samples: scene
                .meshes
                .iter()
                .map(|m| MeshSample::of(m, &scene.materials[m.material]))
                .collect(),
            lights: scene.lights.clone(),
            guards: Mutex::new(Guards::default()),
            level_ball: Mutex::new(None),
        })
    }

    /// The device's cost model (a stored calibration or the built-in figures).
    pub fn cost_model(&self) -> &CostModel {
        &self.cost_model
    }

    /// The image area (pixels) below which `view`'s multirate pass shades a triangle per pixel
    /// without an estimate: the cost model's break-even area for the scene's lights where
    /// `view.cost_model` is set, else `view.estimator.min_estimated_area`.
    pub fn min_estimated_area(&self, view: &View) -> f32 {
        if view.cost_model {
            self.cost_model.min_estimated_area(cost_model::weighed_lights(&self.lights))
        } else {
            view.estimator.min_estimated_area
        }
    }

    /// Per draw, whether `view`'s multirate pass draws its mesh whole as `pixel` mode does on a
    /// target of `extent`: with the cost model on, where most of the mesh's visible triangles
    /// are too small for an estimate to pay ([`MeshSample::mostly_small`]). Empty outside
    /// multirate or without the cost model; every draw where the frame guard draws the frame
    /// as `pixel` does (`View::drawn_as_pixel`).
    pub fn meshes_drawn_per_pixel(&self, view: &View, extent: vk::Extent2D) -> Vec<bool> {
        if view.mode != Mode::Multirate {
            return Vec::new();
        }
        if view.drawn_as_pixel {
            return vec![true; self.draws.len()];
        }
        if !view.cost_model {
            return Vec::new();
        }
        let view_proj = crate::geometry::camera::view_projection(&view.camera, extent.width, extent.height);
        let viewport = glam::Vec2::new(extent.width as f32, extent.height as f32);
        let area = self.min_estimated_area(view);
        self.mesh_samples
            .iter()
            .map(|s| {
                s.mostly_small(
                    &view_proj,
                    view.camera.eye,
                    viewport,
                    area,
                    &self.lights,
                    view.estimator.epsilon,
                )
            })
            .collect()
    }

    /// `view` as the frame guard of its configuration draws the next frame on a target of
    /// `extent` (`View::drawn_as_pixel` set where it draws as `pixel` does); `view` itself
    /// where no guard applies ([`GuardKey::of`]). Callers that time their frames report each
    /// one's time with [`Renderer::report_frame_time`].
    pub fn guarded(&self, view: &View, extent: vk::Extent2D) -> View {
        let mut guarded = view.clone();
        if let Some(key) = GuardKey::of(view, extent) {
            let path = self.guards.lock().expect("guards lock").of(key).next_frame();
            guarded.drawn_as_pixel = path == FramePath::Pixel;
        }
        guarded
    }

    /// Whether the frame guard of `view`'s configuration on a target of `extent` has decided
    /// which way to draw (true where no guard applies).
    pub fn guard_decided(&self, view: &View, extent: vk::Extent2D) -> bool {
        GuardKey::of(view, extent)
            .is_none_or(|key| self.guards.lock().expect("guards lock").of(key).decided())
    }

    /// A frame of `view` (as [`Renderer::guarded`] returned it) on a target of `extent` took
    /// `gpu_ms` on the GPU; its configuration's guard weighs it.
    pub fn report_frame_time(&self, view: &View, extent: vk::Extent2D, gpu_ms: f64) {
        if let Some(key) = GuardKey::of(view, extent) {
            let path = if view.drawn_as_pixel { FramePath::Pixel } else { FramePath::Multirate };
            self.guards.lock().expect("guards lock").of(key).record(path, gpu_ms);
        }
    }

    /// Renders one frame into `target` and reads the float image back.
    pub fn render(&self, target: &RenderTarget, view: &View) -> Result<FloatImage> {
        self.prepare(view, target)?;
        target.render_and_read(&self.context, |cmd| self.record(cmd, target, view, AfterPass::Readback))
    }

    /// Records the forward pass into `target`, leaving the colour image ready for `after`.
    pub fn record(&self, cmd: vk::CommandBuffer, target: &RenderTarget, view: &View, after: AfterPass) {
        let pipelines = &self.pipelines;
        let variants = match (&pipelines.wireframe_variants, view.wireframe) {
            (Some(lines), true) => lines,
            _ => &pipelines.variants,
        };
        self.record_with(variants, cmd, target, view, after);
    }

    /// Builds what `view` needs that is built on first use (the multirate pipelines, the
    /// deferred passes) and sizes the deferred id target for `target`.
    pub fn prepare(&self, view: &View, target: &RenderTarget) -> Result<()> {
        self.prepare_frame(view, target)?;
        let pipelines = &self.pipelines;
        let wireframe = pipelines.wireframe_variants.as_ref().filter(|_| view.wireframe);
        for variants in std::iter::once(&pipelines.variants).chain(wireframe) {
            self.prepare_variants(variants, view)?;
        }
        Ok(())
    }

    /// Builds the wireframe pipelines (once); false when the device cannot draw lines
    /// (`fillModeNonSolid`), in which case `View::wireframe` is ignored.
    pub fn enable_wireframe(&mut self) -> Result<bool> {
        if !self.context.features.fill_mode_non_solid {
            return Ok(false);
        }
        if self.pipelines.wireframe_variants.is_none() {
            let lines = self.pipelines.new_variants(Instrumentation::None, vk::PolygonMode::LINE);
            self.pipelines.wireframe_variants = Some(lines);
        }
        Ok(true)
    }

    /// What a frame of `view` needs whichever variants draw it: the deferred passes, sized for
    /// `target`, and in multirate mode the device's tessellation patterns checked against the
    /// effective-level table. The analysis and recording frames prepare only their own
    /// variants' multirate pipelines: the timed ones are as slow to build and would go unused.
    fn prepare_frame(&self, view: &View, target: &RenderTarget) -> Result<()> {
        if view.mode == Mode::PixelDeferred {
            self.prepare_deferred(target.extent())?;
        }
        if view.mode == Mode::Multirate {
            // The effective-level table holds only for the tessellator it was computed from.
            if let capture::PatternTable::Measured(words) =
                capture::check_patterns(&self.context, view.estimator.n_max)?
            {
                self.use_measured_table(&words)?;
            }
        }
        Ok(())
    }

    /// Replaces the effective-level table the shaders read by the device's measured one (once
    /// per table); waits for the device first, since submitted frames read the buffer.
    fn use_measured_table(&self, words: &Arc<Vec<u32>>) -> Result<()> {
        let mut current = self.measured_table.lock().expect("measured table lock");
        if current.as_ref().is_some_and(|table| Arc::ptr_eq(table, words)) {
            return Ok(());
        }
        self.context.wait_idle()?;
        self.buffers.pattern_levels.upload(words.as_slice())?;
        *current = Some(Arc::clone(words));
        Ok(())
    }

    fn record_with(
        &self,
        variants: &[Variant],
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        after: AfterPass,
    ) {
        self.record_timed(variants, cmd, target, view, after, &|_, _| {});
    }

    /// `record_with`, calling `stamp(Timed::PrePass, false)` before and `stamp(Timed::PrePass,
    /// true)` after the pre-pass (both back to back where there is none), and the same around
    /// each of its steps (`Timed::SkippedStep` where it does not run). Returns whether the
    /// pre-pass ran.
    fn record_timed(
        &self,
        variants: &[Variant],
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        after: AfterPass,
        stamp: &dyn Fn(Timed, bool),
    ) -> bool {
        let per_pixel = self.meshes_drawn_per_pixel(view, target.extent());
        stamp(Timed::PrePass, false);
        // No pre-pass where every mesh is drawn as `pixel` draws it.
        let estimates = per_pixel.len() < self.draws.len() || per_pixel.contains(&false);
        let compute = view.mode == Mode::Multirate && view.placement == Placement::Compute;
        let pre_pass = compute && estimates;
        if pre_pass {
            self.record_triangle_levels(variants, cmd, view, target.extent(), stamp, &per_pixel);
        } else if compute {
            // Every step's interval is still written (empty), as the timing reads them.
            for step in PrePassStep::ALL {
                stamp(Timed::SkippedStep(step), false);
                stamp(Timed::SkippedStep(step), true);
            }
        }
        stamp(Timed::PrePass, true);
        if view.mode == Mode::PixelDeferred {
            let instrumentation = variants.first().map_or(Instrumentation::None, |v| v.instrumentation);
            self.record_deferred(instrumentation, cmd, target, view, after);
            return false;
        }
        let pick = |draw: &DrawCall, mesh_view: &View| variants[draw.pipeline].for_view(mesh_view);
        let attachments = variants.first().map_or(Attachments::Color, |v| v.instrumentation.attachments());
        let draws = Draws { pick: &pick, per_pixel: &per_pixel, emitters: true, clear: self.clear_color };
        self.record_draws(&draws, cmd, target, attachments, view, after);
        pre_pass
    }
}

/// Renders `scene` headless at `width`×`height` with `view`.
pub fn render_headless(
    context: &Arc<Context>,
    scene: &Scene,
    view: &View,
    width: u32,
    height: u32,
) -> Result<FloatImage> {
    let renderer = Renderer::new(context, scene)?;
    let target = RenderTarget::new(context, vk::Extent2D { width, height })?;
    renderer.render(&target, view)
}
