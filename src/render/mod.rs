//! Rendering a scene: GPU copies of the scene, the pipeline variants specialised to its
//! materials and lights, and the forward pass that draws into a render target.
//!
//! [`Renderer`] is the façade, and [`Renderer::record`] the frame: it resolves the frame's
//! configuration (`frame_config`), records the pre-pass (`pre_pass`), the draws (`draws`, or
//! `deferred`) and the emitters, in that order.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`mode`]: what a frame samples shading with ([`Mode`], [`Placement`]).
//! 2. [`draw_part`]: the parts of the forward draws a measured frame may time apart.
//! 3. [`view`]: what one frame is rendered with ([`View`]).
//! 4. [`textures`]: the scene's textures and the materials' sets.
//! 5. [`capture`]: the tessellation pattern check.
//! 6. [`output`]: image files.
//! 7. [`present`]: presentation to a swapchain image.
//! 8. [`post`]: the post chain (eye adaptation, bloom, tone mapping) after the linear frame.
//! 9. [`cost_model`]: where estimating a triangle's level pays, per device.
//! 10. [`multirate_config`]: the multirate configuration, resolved once per frame.
//! 11. [`guard`]: whether a frame is drawn the multirate way or as `pixel` draws it.
//! 12. [`level_ball`]: the ball of eyes the kept levels hold for.
//! 13. [`level_hold`]: the rule by which levels are held between the balls.
//! 14. [`frame_config`]: everything a frame is drawn with, and the per-pixel choice.
//! 15. [`scene_geometry`]: the scene gathered for upload, one draw per mesh and emitter.
//! 16. [`scene_buffers`]: the scene uploaded.
//! 17. [`descriptors`]: the forward layout, its sets, and the recorder that binds them.
//! 18. [`pipelines`]: the pipeline variants of the draws, built on first use.
//! 19. [`shadows`]: the shadow atlas and the pass that draws its maps.
//! 20. [`shadow_state`]: the maps as drawn, the directional ones fitted to the view, and the
//!     triangles' visibility classes.
//! 21. [`pre_pass`]: the triangle-level pre-pass of the compute placement.
//! 22. [`limits`]: the scene's limits against the device's.
//! 23. [`draws`]: the forward draws (and lavapipe's limits on them).
//! 24. [`deferred`]: the `pixel-deferred` passes.
//! 25. [`instrumentation`]: timings, evaluation counts and what is read back.

pub mod capture;
pub mod cost_model;
pub mod deferred;
mod descriptors;
mod draw_part;
mod draws;
mod frame_config;
pub mod guard;
mod instrumentation;
mod level_ball;
pub mod level_hold;
pub mod limits;
mod mode;
mod multirate_config;
pub mod output;
mod pipelines;
pub mod post;
mod pre_pass;
pub mod present;
mod scene_buffers;
mod scene_geometry;
mod shadow_state;
mod shadows;
pub mod textures;
mod view;

pub use draw_part::{DrawPart, DRAW_PARTS};
pub use draws::draw_splitting_note;
pub use frame_config::RecordedFrame;
pub use instrumentation::{
    Analysis, CameraTurn, EvaluationCounts, MeasureOptions, Measurement, PathFrames, GUARD_START_FRAMES,
};
pub use mode::{Mode, Placement, MAX_LEVEL};
pub use pre_pass::steps::{PrePassStep, PRE_PASS_GROUP, PRE_PASS_STEPS, REFINE_BLOCK};
pub use scene_geometry::{gpu_lights, gpu_polygon_lights, gpu_shadow_maps, ShaderLights};
pub use view::{View, EYE_BALL_SHARE};

use crate::error::Result;
use crate::geometry::shadow_class::ShadowClasses;
use crate::geometry::shadow_view::ShadowLayout;
use crate::gpu_interface::bindings::in_binding_order;
use crate::gpu_interface::slots::{FALLBACK_LIST, INTERPOLATED_LIST};
use crate::scene::Scene;
use crate::vk::context::DeviceLimits;
use crate::vk::memory::Buffer;
use crate::vk::target::{AfterPass, Attachments, DepthAfter, FloatImage, RenderTarget};
use crate::vk::Context;
use ash::vk;
use cost_model::CostModel;
use deferred::Deferred;
use descriptors::{ForwardDescriptors, Recorder, SCENE_BINDINGS};
use draws::{ForwardDraws, IndirectCounts};
use frame_config::{Commit, FrameConfig, PerPixelChoice};
use guard::{FramePath, Guards};
use instrumentation::TimedFrames;
use limits::SceneSizes;
use pipelines::{Instrumentation, Pipelines, Variant};
use pre_pass::buffers::PrePassBuffers;
use pre_pass::steps::{FrameStamps, Timed};
use pre_pass::PrePass;
use scene_buffers::SceneBuffers;
use scene_geometry::SceneGeometry;
pub use shadow_state::ShadowRefits;
use shadow_state::Shadows;
use shadows::ShadowAtlas;
use std::cell::OnceCell;
use std::sync::{Arc, Mutex};

/// A scene uploaded to the GPU with its specialised pipelines.
pub struct Renderer {
    context: Arc<Context>,
    /// The scene's vertices, indices, lights and materials and the instrumentation's records.
    buffers: SceneBuffers,
    /// The forward layout, set 0 bound to `buffers` and the pre-pass's, and the materials'
    /// textures and sets.
    descriptors: ForwardDescriptors,
    /// One draw per mesh and per polygonal light.
    draws: ForwardDraws,
    /// The pipeline variants of the draws (timed, wireframe, counting, level-recording) and the
    /// modules they share.
    pipelines: Pipelines,
    /// The compute placement's pre-pass: its pipelines, its buffers and its ball of eyes.
    pre_pass: PrePass,
    /// Every shadow map, read through the materials' sets, the directional ones fitted to the
    /// view; every triangle's visibility classes (in `triangle_corners` for the shaders).
    shadows: Shadows,
    /// What is shaded per pixel, at the scales the frame does not decide itself.
    per_pixel: PerPixelChoice,
    /// The frame guards of the configurations drawn so far (`guarded`, `report_frame_time`).
    guards: Mutex<Guards>,
    /// The device's own effective-level table in `SceneBuffers::pattern_levels`, where the
    /// built-in one does not hold on it (`capture::check_patterns`).
    measured_table: Mutex<Option<Arc<Vec<u32>>>>,
    /// The `pixel-deferred` passes, built on first use.
    deferred: OnceCell<Deferred>,
    clear_color: [f32; 4],
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
        let pre_pass = PrePass::new(context, &geometry, geometry.kinds.len())?;
        let shadow_atlas = ShadowAtlas::new(context, &geometry.shadows)?;
        let descriptors = ForwardDescriptors::new(
            context,
            scene,
            &binding_table(&buffers, &pre_pass.buffers),
            (shadow_atlas.image.view, shadow_atlas.sampler.raw),
        )?;
        let pipelines = Pipelines::new(context, scene, &descriptors.layout, &geometry)?;
        let shadows = Shadows::draw_all(
            context,
            (scene, &geometry),
            shadow_atlas,
            (&descriptors.layout, pipelines.forward_vert()),
            (&buffers, &pre_pass.buffers.triangle_corners),
        )?;
        let clear = scene.settings.clear_color;
        Ok(Renderer {
            context: context.clone(),
            buffers,
            descriptors,
            draws: ForwardDraws::new(geometry.draws, geometry.emitters, &context.info),
            pipelines,
            pre_pass,
            shadows,
            per_pixel: PerPixelChoice::new(&context.info.name, scene),
            guards: Mutex::new(Guards::default()),
            measured_table: Mutex::new(None),
            deferred: OnceCell::new(),
            clear_color: [clear.x, clear.y, clear.z, 0.0],
        })
    }

    /// Every triangle's visibility class per shadow-casting light (none where no light casts
    /// shadows), from the maps as the last frame prepared left them: a directional light's map
    /// follows the view.
    pub fn shadow_classes(&self) -> ShadowClasses {
        self.shadows.classes()
    }

    /// Where each shadow map lies in the atlas and looks from, as the last frame prepared left
    /// them (a directional light's map follows the view).
    pub fn shadow_layout(&self) -> ShadowLayout {
        self.shadows.layout()
    }

    /// The GPU time every shadow map took to draw when the renderer was made (none where no
    /// light casts shadows).
    pub fn shadow_pass_ms(&self) -> Option<f64> {
        self.shadows.first_pass_ms
    }

    /// How often the directional lights' maps were drawn again for the views, and what it took.
    pub fn shadow_refits(&self) -> ShadowRefits {
        self.shadows.refits()
    }

    /// Fits the directional lights' maps to `view`'s camera on a target of `extent` (drawn
    /// again where they no longer serve it); a refit begins a new ball of eyes, since the kept
    /// levels hold for the classes they were estimated with.
    pub fn fit_shadows(&self, view: &View, extent: vk::Extent2D) -> Result<()> {
        let corners = &self.pre_pass.buffers.triangle_corners;
        let refitted = self.shadows.fit(
            &self.context,
            (&view.camera, extent),
            &self.descriptors.layout,
            (&self.buffers, corners),
            &self.draws.meshes,
        )?;
        if refitted {
            self.pre_pass.commit(None);
        }
        Ok(())
    }

    /// The device's cost model (a stored calibration or the built-in figures).
    pub fn cost_model(&self) -> &CostModel {
        &self.per_pixel.cost_model
    }

    /// The image area (pixels) below which `view`'s multirate pass shades a triangle per pixel
    /// without an estimate (`frame_config::PerPixelChoice::min_estimated_area`).
    pub fn min_estimated_area(&self, view: &View) -> f32 {
        self.per_pixel.min_estimated_area(view)
    }

    /// Per draw, whether `view`'s multirate pass draws its mesh whole as `pixel` mode does on a
    /// target of `extent` (`frame_config::PerPixelChoice::meshes`).
    pub fn meshes_drawn_per_pixel(&self, view: &View, extent: vk::Extent2D) -> Vec<bool> {
        self.per_pixel.meshes(view, extent)
    }

    /// The centre of the ball of eyes the pre-pass's kept levels hold for, if any: where the
    /// last submitted frame that commits it left it.
    pub fn level_ball_centre(&self) -> Option<glam::Vec3> {
        self.pre_pass.kept_ball().map(|ball| ball.centre())
    }

    /// `view` as the frame guard of its configuration draws the next frame on a target of
    /// `extent` (`View::drawn_as_pixel` set where it draws as `pixel` does); `view` itself
    /// where no guard applies (`guard::key_of`). Callers that time their frames report each
    /// one's time with [`Renderer::report_frame_time`].
    pub fn guarded(&self, view: &View, extent: vk::Extent2D) -> View {
        let mut guarded = view.clone();
        if let Some(key) = self.guard_key(view, extent) {
            let path = self.guards.lock().expect("guards lock").of(key).next_frame();
            guarded.drawn_as_pixel = path == FramePath::Pixel;
        }
        guarded
    }

    /// Whether the frame guard of `view`'s configuration on a target of `extent` has decided
    /// which way to draw (true where no guard applies).
    pub fn guard_decided(&self, view: &View, extent: vk::Extent2D) -> bool {
        self.guard_key(view, extent)
            .is_none_or(|key| self.guards.lock().expect("guards lock").of(key).decided())
    }

    /// A frame of `view` (as [`Renderer::guarded`] returned it) on a target of `extent` took
    /// `gpu_ms` on the GPU; its configuration's guard weighs it.
    pub fn report_frame_time(&self, view: &View, extent: vk::Extent2D, gpu_ms: f64) {
        if let Some(key) = self.guard_key(view, extent) {
            let path = if view.drawn_as_pixel { FramePath::Pixel } else { FramePath::Multirate };
            self.guards.lock().expect("guards lock").of(key).record(path, gpu_ms);
        }
    }

    /// The key of `view`'s frame guard on a target of `extent` (None where none applies).
    fn guard_key(&self, view: &View, extent: vk::Extent2D) -> Option<multirate_config::MultirateConfig> {
        guard::key_of(view, &self.per_pixel.multirate_config(view, extent))
    }

    /// Renders one frame into `target` and reads the float image back.
    pub fn render(&self, target: &RenderTarget, view: &View) -> Result<FloatImage> {
        self.prepare(view, target)?;
        let mut recorded = None;
        let image = target.render_and_read(&self.context, |cmd| {
            recorded = Some(self.record(cmd, target, view, AfterPass::Readback))
        })?;
        self.submitted(recorded.expect("the frame was recorded"));
        Ok(image)
    }

    /// Records the forward pass of `view` into `target`, leaving the colour image ready for
    /// `after`. Changes nothing in the renderer: pass the frame to [`Renderer::submitted`] once
    /// it is submitted.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        after: AfterPass,
    ) -> RecordedFrame {
        let variants = match (&self.pipelines.wireframe_variants, view.wireframe) {
            (Some(lines), true) => lines,
            _ => &self.pipelines.variants,
        };
        let frame = self.frame_config(view, target.extent(), Commit::OnSubmit);
        self.record_frame(variants, Instrumentation::None, cmd, target, &frame, after, &FrameStamps::NONE)
    }

    /// A frame [`Renderer::record`] recorded was submitted: what it learnt holds from now on
    /// (the ball of eyes its levels were kept for).
    pub fn submitted(&self, frame: RecordedFrame) {
        if let Some(ball) = frame.ball {
            self.pre_pass.commit(ball);
        }
    }

    /// The configuration of a frame of `view` on a target of `extent`, resolved once.
    fn frame_config(&self, view: &View, extent: vk::Extent2D, commit: Commit) -> FrameConfig {
        let patches_per_draw = self.draws.patches_per_draw(view.estimator.n_max);
        FrameConfig::resolve(
            &self.per_pixel,
            view,
            extent,
            self.pre_pass.kept_ball(),
            commit,
            patches_per_draw,
        )
    }

    /// One frame, top to bottom: the pre-pass of `frame`, then its draws with `variants` (of
    /// `instrumentation`), then the polygonal lights' emissive geometry, into `target`, leaving
    /// it ready for `after`. Stamps (`stamps.stamp`) `Timed::PrePass` before and after the
    /// pre-pass (back to back where there is none), the same around each of its steps where it
    /// runs, and, where `stamps.draw_parts`, each part of each mesh's draws.
    #[allow(clippy::too_many_arguments)]
    fn record_frame(
        &self,
        variants: &[Variant],
        instrumentation: Instrumentation,
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        frame: &FrameConfig,
        after: AfterPass,
        stamps: &FrameStamps<'_>,
    ) -> RecordedFrame {
        let rec = Recorder {
            device: &self.context.device,
            cmd,
            buffers: &self.buffers,
            descriptors: &self.descriptors,
        };
        let stamp = stamps.stamp;
        // The pre-pass.
        stamp(Timed::PrePass, false);
        if frame.runs_pre_pass {
            self.pre_pass.record(&rec, frame, &self.draws.meshes, instrumentation, stamp);
        }
        stamp(Timed::PrePass, true);
        // The draws.
        if frame.view.mode == Mode::PixelDeferred {
            let Some(deferred) = self.deferred.get() else {
                debug_assert!(false, "render, measure and the viewer prepare the view first");
                return frame.recorded();
            };
            deferred.record(&rec, &self.draws, frame, instrumentation, target, (self.clear_color, after));
            return frame.recorded();
        }
        let attachments = instrumentation.attachments();
        let depth = if stamps.draw_parts { DepthAfter::Kept } else { DepthAfter::Discarded };
        target.begin(rec.device, cmd, self.clear_color, attachments, depth);
        let pick = |draw: &scene_geometry::DrawCall, mesh_view: &View| {
            variants[draw.pipeline].for_view(mesh_view, &frame.multirate)
        };
        let lists = frame.has_pre_pass().then(|| self.pre_pass.patch_lists());
        let counts = IndirectCounts {
            supported: self.context.features.draw_indirect_count,
            max_count: self.context.limits.max_draw_indirect_count,
        };
        let constants = self.draws.record_meshes(&rec, frame, &pick, lists, counts, attachments, stamp);
        // The emitters.
        let emitter = self.pipelines.emitter_for(attachments);
        self.draws.record_emitters(&rec, constants, emitter, stamp);
        target.end(rec.device, cmd, after, attachments);
        frame.recorded()
    }

    /// Builds what `view` needs that is built on first use (the multirate pipelines, the
    /// deferred passes) and sizes the deferred id target for `target`.
    pub fn prepare(&self, view: &View, target: &RenderTarget) -> Result<()> {
        self.prepare_frame(view, target)?;
        let wireframe = self.pipelines.wireframe_variants.as_ref().filter(|_| view.wireframe);
        for variants in std::iter::once(&self.pipelines.variants).chain(wireframe) {
            self.prepare_variants(variants, Instrumentation::None, view, target.extent())?;
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

    /// Builds the pipelines of `view`'s mode in each of `variants` (of `instrumentation`) that it
    /// lacks, and in multirate mode on the compute placement the pre-pass's.
    fn prepare_variants(
        &self,
        variants: &[Variant],
        instrumentation: Instrumentation,
        view: &View,
        extent: vk::Extent2D,
    ) -> Result<()> {
        let (context, layout) = (&self.context, &self.descriptors.layout);
        let config = self.per_pixel.multirate_config(view, extent);
        let one_sided = self.draws.meshes.iter().map(|draw| draw.one_sided);
        self.pipelines.prepare(context, layout, variants, view, &config, one_sided)?;
        if view.mode == Mode::Multirate && view.placement == Placement::Compute {
            let specializations = &self.pipelines.specializations;
            self.pre_pass.prepare(context, layout, specializations, instrumentation, &config)?;
        }
        Ok(())
    }

    /// What a frame of `view` needs whichever variants draw it: the deferred passes, sized for
    /// `target`, and in multirate mode the device's tessellation patterns checked against the
    /// effective-level table. The analysis and recording frames prepare only their own
    /// variants' multirate pipelines: the timed ones are as slow to build and would go unused.
    fn prepare_frame(&self, view: &View, target: &RenderTarget) -> Result<()> {
        self.fit_shadows(view, target.extent())?;
        if view.mode == Mode::PixelDeferred {
            self.deferred()?.prepare(target.extent())?;
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

    /// The deferred passes, built on first use.
    fn deferred(&self) -> Result<&Deferred> {
        if let Some(deferred) = self.deferred.get() {
            return Ok(deferred);
        }
        let deferred =
            Deferred::new(&self.context, &self.descriptors.layout, &self.pipelines.specializations)?;
        Ok(self.deferred.get_or_init(|| deferred))
    }

    /// Renders `view` in `multirate` mode with the level-recording variant and returns, per
    /// triangle of the scene (meshes in order), `[level, outer0, outer1, outer2]` as the
    /// control stage chose them (level 0: per-pixel fallback).
    pub fn record_levels(&self, target: &RenderTarget, view: &View) -> Result<Vec<[f32; 4]>> {
        let recording = self.pipelines.instrumented(Instrumentation::RecordLevels);
        let view = View { mode: Mode::Multirate, ..view.clone() };
        self.prepare_frame(&view, target)?;
        self.prepare_variants(recording, Instrumentation::RecordLevels, &view, target.extent())?;
        let frame = self.frame_config(&view, target.extent(), Commit::Never);
        target.render_and_read(&self.context, |cmd| {
            let _ = self.record_frame(
                recording,
                Instrumentation::RecordLevels,
                cmd,
                target,
                &frame,
                AfterPass::Readback,
                &FrameStamps::NONE,
            );
            let writers = vk::PipelineStageFlags2::COMPUTE_SHADER
                | vk::PipelineStageFlags2::TESSELLATION_CONTROL_SHADER;
            instrumentation::storage_to_host(&self.context.device, cmd, writers);
        })?;
        let bytes = self.buffers.level_records.mapped().expect("GpuToCpu memory is mapped");
        Ok(bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&bytes[..self.buffers.level_records.size as usize]))
    }

    /// Renders one frame of `view` (`multirate` mode, the compute placement) and returns its
    /// pre-pass's indirect dispatches as the frame left them: per mesh, `LEVEL_DISPATCHES` words
    /// `[workgroups x, y, z, listed triangles]` (`gpu_interface::slots`), so that a test can
    /// compare each step's list with the twin's. The frame is drawn as `render` draws it, and
    /// commits what it learns as `render` does.
    pub fn pre_pass_dispatches(&self, target: &RenderTarget, view: &View) -> Result<Vec<[u32; 4]>> {
        let bytes = self.pre_pass_read_back(target, view, &self.pre_pass.buffers.level_dispatches)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// As [`Renderer::pre_pass_dispatches`], the level of every triangle of the scene (meshes in
    /// order) as the frame's pre-pass left it for the patch step: estimated, kept or held
    /// (`level_hold`); -1 where culled, 10⁶ where shaded per pixel.
    pub fn pre_pass_levels(&self, target: &RenderTarget, view: &View) -> Result<Vec<f32>> {
        let bytes = self.pre_pass_read_back(target, view, &self.pre_pass.buffers.triangle_levels)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }

    /// Renders and commits one frame of `view` as `pre_pass_dispatches` says, and reads `source`
    /// back after it.
    fn pre_pass_read_back(&self, target: &RenderTarget, view: &View, source: &Buffer) -> Result<Vec<u8>> {
        let view = View { mode: Mode::Multirate, placement: Placement::Compute, ..view.clone() };
        self.prepare(&view, target)?;
        let readback = Buffer::new(
            &self.context,
            "pre-pass buffer read back",
            source.size,
            vk::BufferUsageFlags::TRANSFER_DST,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let mut recorded = None;
        target.render_and_read(&self.context, |cmd| {
            recorded = Some(self.record(cmd, target, &view, AfterPass::Readback));
            instrumentation::copy_for_host(&self.context.device, cmd, source, &readback);
        })?;
        self.submitted(recorded.expect("the frame was recorded"));
        let bytes = readback.mapped().expect("GpuToCpu memory is mapped");
        Ok(bytes[..source.size as usize].to_vec())
    }

    /// Renders `warmup` frames (more for a guarded view whose guard has not decided yet: at most
    /// [`GUARD_START_FRAMES`] more), then `frames` measured ones, with up to two frames in flight:
    /// when the forward pass of each measured frame ran on the GPU (timestamps outside the
    /// pass), when its pre-pass did, and the pipeline statistics of the last one. A frame's
    /// queries are read only once its slot comes round again, so reading never stalls the
    /// frame being recorded. Every frame, warm-up included, is drawn as the frame guard of its
    /// configuration says ([`Renderer::guarded`]) and reported to it.
    pub fn measure(
        &self,
        target: &RenderTarget,
        view: &View,
        warmup: u32,
        frames: u32,
    ) -> Result<Measurement> {
        self.measure_with(target, view, warmup, frames, MeasureOptions::default())
    }

    /// [`Renderer::measure`] as `options` say: the camera turning frame after frame, the draws'
    /// parts timed apart.
    pub fn measure_with(
        &self,
        target: &RenderTarget,
        view: &View,
        warmup: u32,
        frames: u32,
        options: MeasureOptions,
    ) -> Result<Measurement> {
        self.prepare(view, target)?;
        instrumentation::measure(self, target, view, (warmup, frames), options)
    }

    /// Renders one frame of `view` with the counting variant (never the timed one) and
    /// returns how many times the full shading function ran, by stage. Needs storage writes
    /// in the vertex pipeline and fragment stages (`vertexPipelineStoresAndAtomics`,
    /// `fragmentStoresAndAtomics`) and primitive ids in the fragment stage (`geometryShader`).
    pub fn count_evaluations(&self, target: &RenderTarget, view: &View) -> Result<EvaluationCounts> {
        let analysis = self.analysis_variants(target, view)?;
        self.context.run_once(|cmd| {
            let _ = self.record_analysis(analysis, cmd, target, view, (AfterPass::Sampled, Commit::Never));
        })?;
        Ok(instrumentation::read_counters(&self.buffers.counters))
    }

    /// One frame of `view` drawn by the analysis variant, the counting one: its image, which
    /// triangle each pixel shows, and how many times the full shading function ran. Its
    /// rasterisation and shading are the timed variant's (tests/counts.rs compares the two).
    pub fn analyze(&self, target: &RenderTarget, view: &View) -> Result<Analysis> {
        self.analyze_committing(target, view, Commit::Never)
    }

    /// [`Renderer::analyze`] for the frame a user sees: like [`Renderer::render`], it commits
    /// what it learnt (the ball of eyes its levels were kept for), so that a walk along a path
    /// draws each frame once rather than rendering it and then analysing it.
    pub fn analyze_as_shown(&self, target: &RenderTarget, view: &View) -> Result<Analysis> {
        self.analyze_committing(target, view, Commit::OnSubmit)
    }

    fn analyze_committing(&self, target: &RenderTarget, view: &View, commit: Commit) -> Result<Analysis> {
        let analysis = self.analysis_variants(target, view)?;
        let mut recorded = None;
        let (image, triangles) =
            target.render_and_read_with(&self.context, Attachments::ColorAndIds, |cmd| {
                recorded =
                    Some(self.record_analysis(analysis, cmd, target, view, (AfterPass::Readback, commit)))
            })?;
        self.submitted(recorded.expect("the frame was recorded"));
        let triangles = triangles.expect("ColorAndIds reads the ids back");
        Ok(Analysis { image, triangles, evaluations: instrumentation::read_counters(&self.buffers.counters) })
    }

    /// The analysis variants, built on first use and prepared for `view`.
    fn analysis_variants(&self, target: &RenderTarget, view: &View) -> Result<&[Variant]> {
        let features = &self.context.features;
        if !(features.vertex_pipeline_stores && features.fragment_stores && features.geometry_shader) {
            return Err(crate::Error::Unsupported {
                device: self.context.info.name.clone(),
                what: "count shading evaluations and read triangle ids",
                missing: "vertexPipelineStoresAndAtomics, fragmentStoresAndAtomics and geometryShader",
            });
        }
        let analysis = self.pipelines.instrumented(Instrumentation::CountEvaluations);
        target.prepare_ids(&self.context)?;
        if !self.draws.emitters.is_empty() {
            self.pipelines.prepare_analysis_emitter(&self.context, &self.descriptors.layout)?;
        }
        self.prepare_frame(view, target)?;
        self.prepare_variants(analysis, Instrumentation::CountEvaluations, view, target.extent())?;
        Ok(analysis)
    }

    /// Records one analysis frame, which commits what it learnt only where `commit` says so
    /// (`analyze_as_shown`): the counters zeroed, the frame, the counters made visible to the host.
    fn record_analysis(
        &self,
        analysis: &[Variant],
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        (after, commit): (AfterPass, Commit),
    ) -> RecordedFrame {
        let device = &self.context.device;
        instrumentation::zero_counters(device, cmd, &self.buffers.counters);
        let frame = self.frame_config(view, target.extent(), commit);
        let counting = Instrumentation::CountEvaluations;
        let recorded = self.record_frame(analysis, counting, cmd, target, &frame, after, &FrameStamps::NONE);
        instrumentation::storage_to_host(device, cmd, vk::PipelineStageFlags2::ALL_GRAPHICS);
        recorded
    }

    /// The visibility buffer of `view` at `target`'s size: per pixel (rows from the top),
    /// `Some((mesh, triangle))` with the triangle's index in its mesh, or `None`.
    pub fn triangle_ids(&self, target: &RenderTarget, view: &View) -> Result<Vec<Option<(usize, usize)>>> {
        let deferred = self.deferred()?;
        let mut frame = self.frame_config(view, target.extent(), Commit::Never);
        // The id pass draws every mesh whole.
        frame.meshes_per_pixel.clear();
        let image: FloatImage = target.render_and_read(&self.context, |cmd| {
            let rec = Recorder {
                device: &self.context.device,
                cmd,
                buffers: &self.buffers,
                descriptors: &self.descriptors,
            };
            deferred.record_ids(&rec, &self.draws, &frame, target, AfterPass::Readback)
        })?;
        Ok(image
            .pixels
            .iter()
            .map(|p| {
                (p[3] > 0.0 && p[0] >= 1.0).then(|| {
                    let mesh = p[0] as usize - 1;
                    let first = self.draws.meshes[mesh].first_triangle as usize;
                    (mesh, p[1] as usize - first)
                })
            })
            .collect())
    }
}

impl TimedFrames for Renderer {
    fn context(&self) -> &Arc<Context> {
        &self.context
    }

    fn guard_applies(&self, view: &View, extent: vk::Extent2D) -> bool {
        self.guard_key(view, extent).is_some()
    }

    fn guard_decided(&self, view: &View, extent: vk::Extent2D) -> bool {
        Renderer::guard_decided(self, view, extent)
    }

    fn guarded(&self, view: &View, extent: vk::Extent2D) -> View {
        Renderer::guarded(self, view, extent)
    }

    fn fit_shadows(&self, view: &View, extent: vk::Extent2D) -> Result<()> {
        Renderer::fit_shadows(self, view, extent)
    }

    fn report_frame_time(&self, view: &View, extent: vk::Extent2D, gpu_ms: f64) {
        Renderer::report_frame_time(self, view, extent, gpu_ms)
    }

    fn record_timed(
        &self,
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        stamps: &FrameStamps<'_>,
    ) -> RecordedFrame {
        let frame = self.frame_config(view, target.extent(), Commit::OnSubmit);
        let variants = &self.pipelines.variants;
        self.record_frame(variants, Instrumentation::None, cmd, target, &frame, AfterPass::Sampled, stamps)
    }

    fn submitted(&self, frame: RecordedFrame) {
        Renderer::submitted(self, frame)
    }

    fn mesh_count(&self) -> usize {
        self.draws.meshes.len()
    }
}

/// Set 0 of the forward layout: the buffer each binding holds, in binding order
/// (`gpu_interface::bindings::forward`, twin of `glsl/include/bindings.glsl`); the one place that
/// says so.
fn binding_table<'a>(scene: &'a SceneBuffers, pre_pass: &'a PrePassBuffers) -> [&'a Buffer; SCENE_BINDINGS] {
    use crate::gpu_interface::bindings::forward as set_0;
    in_binding_order(
        &set_0::SCENE_BUFFERS,
        [
            (set_0::LIGHTS, &scene.lights),
            (set_0::MATERIALS, &scene.materials),
            (set_0::LEVEL_RECORDS, &scene.level_records),
            (set_0::EVALUATION_COUNTERS, &scene.counters),
            (set_0::POLYGON_LIGHTS, &scene.polygon_lights),
            (set_0::TRIANGLE_LEVELS, &pre_pass.triangle_levels),
            (set_0::TRIANGLE_NEIGHBOURS, &pre_pass.triangle_neighbours),
            (set_0::SCENE_VERTICES, &scene.vertices),
            (set_0::SCENE_INDICES, &scene.indices),
            (set_0::VISIBLE_TRIANGLES, &pre_pass.visible_triangles),
            (set_0::PATCH_COUNTS, &pre_pass.patch_counts),
            (set_0::PATTERN_LEVELS, &scene.pattern_levels),
            (set_0::PATCH_TESS_LEVELS, &pre_pass.patch_levels),
            (set_0::INTERPOLATED_PATCHES, &pre_pass.patch_lists[0]),
            (set_0::FALLBACK_PATCHES, &pre_pass.patch_lists[1]),
            (set_0::INTERPOLATED_DRAWS, &pre_pass.patch_draws[INTERPOLATED_LIST as usize]),
            (set_0::FALLBACK_DRAWS, &pre_pass.patch_draws[FALLBACK_LIST as usize]),
            (set_0::FLAT_PATCHES, &pre_pass.patch_lists[2]),
            (set_0::FLAT_DRAWS, &pre_pass.flat_draws),
            (set_0::LEVEL_DISPATCHES, &pre_pass.level_dispatches),
            (set_0::REFINE_TRIANGLES, &pre_pass.refine_triangles),
            (set_0::ESTIMATE_TRIANGLES, &pre_pass.estimate_triangles),
            (set_0::FLAT_INDICES, &pre_pass.flat_indices),
            (set_0::ESTIMATED_LEVELS, &pre_pass.estimated_levels),
            (set_0::LEVEL_HOLDS, &pre_pass.level_holds),
            (set_0::FALLBACK_INDICES, &pre_pass.fallback_indices),
            (set_0::SHADOW_MAPS, &scene.shadow_maps),
            (set_0::TRIANGLE_CORNERS, &pre_pass.triangle_corners),
        ],
    )
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
