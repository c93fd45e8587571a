//! What the renderer measures and records besides the image: GPU times of the frame, the
//! pre-pass and its steps ([`Renderer::measure`], [`Measurement`]), shading evaluations by
//! stage ([`Renderer::count_evaluations`], [`EvaluationCounts`]), the analysis frame with its
//! triangle ids ([`Renderer::analyze`], [`Analysis`]) and the level records
//! ([`Renderer::record_levels`]).

use super::guard;
use super::mode::{Mode, Placement};
use super::pipelines::{Instrumentation, Variant};
use super::pre_pass::{PrePassStep, PRE_PASS_STEPS};
use super::view::View;
use super::Renderer;
use crate::error::Result;
use crate::vk::frames::FrameRing;
use crate::vk::target::{AfterPass, Attachments, FloatImage, RenderTarget};
use crate::vk::timing::{GpuInterval, GpuTimer, PipelineStatistics};
use ash::vk;

/// GPU times and counts of measured frames.
#[derive(Clone, Debug, Default)]
pub struct Measurement {
    /// When the forward pass ran in every measured frame, in submission order.
    pub frames: Vec<GpuInterval>,
    /// `Placement::Compute`: when the triangle-level pre-pass (culling, triangle levels, patch
    /// levels and lists; part of the frame) ran, in every measured frame that ran it (not those
    /// whose meshes were all drawn as `pixel` does); empty otherwise.
    pub pre_pass: Vec<GpuInterval>,
    /// `Placement::Compute`: when each of its steps ran (`PrePassStep::ALL`'s order), in every
    /// measured frame; empty otherwise.
    pub pre_pass_steps: Vec<[GpuInterval; PRE_PASS_STEPS]>,
    /// Pipeline statistics of the last frame, where the device has them.
    pub statistics: Option<PipelineStatistics>,
    /// Where the frame guard applies ([`guard::GuardKey::of`]): how many measured frames it drew
    /// as `pixel` does (`View::drawn_as_pixel`). None where it does not apply.
    pub drawn_as_pixel: Option<u32>,
    /// Frames drawn, warm-up included: where a [`CameraTurn`] goes on from.
    pub frames_drawn: u32,
}

/// The camera turning about its target while frames are measured: `degrees_per_frame` about its
/// up direction, the first frame at `first_frame` turns. A camera that stays still measures the
/// frames a still view gives, where the pre-pass reuses its levels (`render::level_ball`); a
/// turning one, what a moving view costs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CameraTurn {
    pub degrees_per_frame: f32,
    pub first_frame: u32,
}

impl CameraTurn {
    /// `view` with its camera turned as in frame `frame` (counted from `first_frame`).
    fn view_at(self, view: &View, frame: u32) -> View {
        if self.degrees_per_frame == 0.0 {
            return view.clone();
        }
        let camera = view.camera;
        let angle = (self.degrees_per_frame * (self.first_frame + frame) as f32).to_radians();
        let turn = glam::Quat::from_axis_angle(camera.up.normalize(), angle);
        let eye = camera.target + turn * (camera.eye - camera.target);
        view.seen_from(crate::scene::Camera { eye, ..camera })
    }
}

impl Measurement {
    /// Forward-pass milliseconds of every measured frame.
    pub fn gpu_ms(&self) -> Vec<f64> {
        self.frames.iter().map(GpuInterval::milliseconds).collect()
    }

    /// Pre-pass milliseconds of every measured frame (empty without a pre-pass).
    pub fn pre_pass_ms(&self) -> Vec<f64> {
        self.pre_pass.iter().map(GpuInterval::milliseconds).collect()
    }

    /// Milliseconds of pre-pass step `step` in every measured frame (empty without a pre-pass).
    pub fn pre_pass_step_ms(&self, step: PrePassStep) -> Vec<f64> {
        self.pre_pass_steps.iter().map(|steps| steps[step as usize].milliseconds()).collect()
    }
}

/// Runs of the full shading function in one frame, by where they ran (the counting variant).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
pub struct EvaluationCounts {
    /// `vertex` mode: triangle vertices shaded by the vertex shader.
    pub vertices: u64,
    /// Tessellated modes: sub-vertices shaded by the evaluation shader.
    pub sub_vertices: u64,
    /// `pixel` mode and `multirate`'s fallback: fragments shaded per pixel.
    pub fragments: u64,
    /// `multirate`: triangles culled before their estimate (outside the view frustum, or back
    /// faces of one-sided meshes). Not a shading evaluation.
    pub culled_patches: u64,
}

impl EvaluationCounts {
    pub fn total(&self) -> u64 {
        self.vertices + self.sub_vertices + self.fragments
    }
}

/// Frames a measurement keeps in flight, so reading one frame's queries never stalls the next.
const FRAMES_IN_FLIGHT: usize = 2;

/// One frame drawn by the analysis variant ([`Renderer::analyze`]).
#[derive(Clone, Debug)]
pub struct Analysis {
    pub image: FloatImage,
    /// Per pixel, rows from the top: the id of the triangle it shows (glsl/include/triangle_id.glsl; 0: nothing).
    pub triangles: Vec<u32>,
    pub evaluations: EvaluationCounts,
}

impl Analysis {
    /// The image and its triangle ids, for the error metrics.
    pub fn frame(&self) -> crate::analysis::metrics::Frame<'_> {
        crate::analysis::metrics::Frame { image: &self.image, triangles: &self.triangles }
    }
}

/// The most frames `measure` adds to a guarded view's warm-up while its guard has not decided:
/// the guard's first frames each way and those in flight, twice over (a time the device did
/// not write is not counted).
pub const GUARD_START_FRAMES: u32 = 4 * (guard::PROBE_FRAMES + FRAMES_IN_FLIGHT as u32);

/// What a timestamp pair of `measure` times: the whole frame, the pre-pass, or one of its steps.
#[derive(Clone, Copy)]
pub(super) enum Timed {
    PrePass,
    Step(PrePassStep),
    /// A step of a frame without a pre-pass (every mesh drawn as `pixel` does): its interval
    /// is written back to back at the top of the pipe, without the barrier that settles a
    /// step's timestamps. On lavapipe those barriers made such frames 7–15 % slower than
    /// `pixel` mode's, and each later-stage timestamp flushes its queued work.
    SkippedStep(PrePassStep),
}

impl Timed {
    /// Its pass in `measure`'s `GpuTimer` (pass 0 is the whole frame).
    pub(super) fn pass(self) -> u32 {
        match self {
            Timed::PrePass => 1,
            Timed::Step(step) | Timed::SkippedStep(step) => 2 + step as u32,
        }
    }
}

impl Renderer {
    /// Renders `view` in `multirate` mode with the level-recording variant and returns, per
    /// triangle of the scene (meshes in order), `[level, outer0, outer1, outer2]` as the
    /// control stage chose them (level 0: per-pixel fallback).
    pub fn record_levels(&self, target: &RenderTarget, view: &View) -> Result<Vec<[f32; 4]>> {
        let recording = self.pipelines.instrumented(Instrumentation::RecordLevels);
        let view = View { mode: Mode::Multirate, ..view.clone() };
        self.prepare_frame(&view, target)?;
        self.prepare_variants(recording, &view)?;
        target.render_and_read(&self.context, |cmd| {
            self.record_with(recording, cmd, target, &view, AfterPass::Readback);
            let barrier = [vk::MemoryBarrier2::default()
                .src_stage_mask(
                    vk::PipelineStageFlags2::COMPUTE_SHADER
                        | vk::PipelineStageFlags2::TESSELLATION_CONTROL_SHADER,
                )
                .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                .dst_access_mask(vk::AccessFlags2::HOST_READ)];
            // SAFETY: recording command buffer.
            unsafe {
                self.context
                    .device
                    .cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barrier))
            };
        })?;
        let bytes = self.buffers.level_records.mapped().expect("GpuToCpu memory is mapped");
        Ok(bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&bytes[..self.buffers.level_records.size as usize]))
    }

    /// Renders one frame of `view` (`multirate` mode, the compute placement) and returns its
    /// pre-pass's indirect dispatches as the frame left them: per mesh, `LEVEL_DISPATCHES` words
    /// `[workgroups x, y, z, listed triangles]` (`gpu_interface::slots`), so that a test can
    /// compare each step's list with the twin's.
    pub fn pre_pass_dispatches(&self, target: &RenderTarget, view: &View) -> Result<Vec<[u32; 4]>> {
        let view = View { mode: Mode::Multirate, placement: Placement::Compute, ..view.clone() };
        self.prepare(&view, target)?;
        let source = &self.buffers.pre_pass.level_dispatches;
        let readback = crate::vk::memory::Buffer::new(
            &self.context,
            "pre-pass dispatches read back",
            source.size,
            vk::BufferUsageFlags::TRANSFER_DST,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        target.render_and_read(&self.context, |cmd| {
            self.record(cmd, target, &view, AfterPass::Readback);
            let before = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
                .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::TRANSFER_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::COPY)
                .dst_access_mask(vk::AccessFlags2::TRANSFER_READ)];
            let after = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::COPY)
                .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                .dst_access_mask(vk::AccessFlags2::HOST_READ)];
            let region = [vk::BufferCopy::default().size(source.size)];
            let device = &self.context.device;
            // SAFETY: recording command buffer, outside the rendering `record` ended; both
            // buffers are live, `source` has TRANSFER_SRC and `readback` TRANSFER_DST usage, and
            // the region fits both.
            unsafe {
                device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&before));
                device.cmd_copy_buffer(cmd, source.raw, readback.raw, &region);
                device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&after));
            }
        })?;
        let bytes = readback.mapped().expect("GpuToCpu memory is mapped");
        Ok(bytemuck::pod_collect_to_vec::<u8, [u32; 4]>(&bytes[..source.size as usize]))
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
        self.measure_turning(target, view, warmup, frames, CameraTurn::default())
    }

    /// [`Renderer::measure`] with the camera turning as `turn` says, frame after frame.
    pub fn measure_turning(
        &self,
        target: &RenderTarget,
        view: &View,
        warmup: u32,
        frames: u32,
        turn: CameraTurn,
    ) -> Result<Measurement> {
        self.prepare(view, target)?;
        // Pass 0: the whole frame; pass 1: the pre-pass, within it; then its steps, where it
        // has them (every query read must have been written).
        let pre_pass = view.mode == Mode::Multirate && view.placement == Placement::Compute;
        let passes = if pre_pass { 2 + PRE_PASS_STEPS as u32 } else { 2 };
        let timer = GpuTimer::new(&self.context, passes, FRAMES_IN_FLIGHT as u32)?;
        let mut ring = FrameRing::new(&self.context, FRAMES_IN_FLIGHT)?;
        let mut measurement = Measurement::default();
        let extent = target.extent();
        if guard::GuardKey::of(view, extent).is_some() {
            measurement.drawn_as_pixel = Some(0);
        }
        // Per slot, the frame it last drew: whether it is measured, how it was drawn (the frame
        // guard's choice or probe) and whether it ran the pre-pass.
        let mut in_slot: [Option<(bool, View, bool)>; FRAMES_IN_FLIGHT] = Default::default();
        let collect = |ring: &mut FrameRing,
                       slot: usize,
                       drawn: Option<(bool, View, bool)>,
                       measurement: &mut Measurement| {
            let Some((measured, frame_view, ran_pre_pass)) = drawn else { return Ok(()) };
            if !ring.wait(slot)? {
                return Ok(());
            }
            let intervals = timer.pass_intervals(slot as u32)?;
            self.report_frame_time(&frame_view, extent, intervals[0].milliseconds());
            if measured {
                measurement.frames.push(intervals[0]);
                // The pre-pass's times are those of the frames that ran it.
                if ran_pre_pass {
                    measurement.pre_pass.push(intervals[1]);
                    let steps = PrePassStep::ALL.map(|step| intervals[Timed::Step(step).pass() as usize]);
                    measurement.pre_pass_steps.push(steps);
                }
                if let Some(count) = &mut measurement.drawn_as_pixel {
                    *count += u32::from(frame_view.drawn_as_pixel);
                }
                measurement.statistics = timer.read_statistics(slot as u32)?;
            }
            Ok::<_, crate::Error>(())
        };
        // A guarded configuration warms up until its guard has first decided (its first probe's
        // times are in): what a user sees after the first frames, not the guard's start-up.
        let longest_warmup = warmup + GUARD_START_FRAMES;
        let (mut frame, mut measured_frames) = (0u32, 0u32);
        while measured_frames < frames {
            let slot = frame as usize % FRAMES_IN_FLIGHT;
            collect(&mut ring, slot, in_slot[slot].take(), &mut measurement)?;
            let measured = frame >= warmup && (frame >= longest_warmup || self.guard_decided(view, extent));
            let frame_view = self.guarded(&turn.view_at(view, frame), extent);
            let mut ran_pre_pass = false;
            ring.submit(slot, |cmd| {
                let slot = slot as u32;
                timer.reset(cmd, slot);
                timer.timestamp(cmd, slot, 0, false);
                timer.statistics(cmd, slot, true);
                // A step starts once the one before it has finished (the barrier between them
                // holds the next dispatch, not a top-of-pipe timestamp): its timestamps are
                // written after every earlier command, each before a barrier that settles it.
                let stamp = |timed: Timed, end: bool| match timed {
                    Timed::PrePass => timer.timestamp(cmd, slot, timed.pass(), end),
                    Timed::SkippedStep(_) => timer.top_of_pipe_timestamp(cmd, slot, timed.pass(), end),
                    Timed::Step(_) => timer.settled_timestamp(cmd, slot, timed.pass(), end),
                };
                ran_pre_pass = self.record_timed(
                    &self.pipelines.variants,
                    cmd,
                    target,
                    &frame_view,
                    AfterPass::Sampled,
                    &stamp,
                );
                timer.statistics(cmd, slot, false);
                timer.timestamp(cmd, slot, 0, true);
            })?;
            in_slot[slot] = Some((measured, frame_view, ran_pre_pass));
            measured_frames += u32::from(measured);
            frame += 1;
        }
        for (slot, drawn) in in_slot.iter_mut().enumerate() {
            collect(&mut ring, slot, drawn.take(), &mut measurement)?;
        }
        measurement.frames_drawn = frame;
        Ok(measurement)
    }

    /// Renders one frame of `view` with the counting variant (never the timed one) and
    /// returns how many times the full shading function ran, by stage. Needs storage writes
    /// in the vertex pipeline and fragment stages (`vertexPipelineStoresAndAtomics`,
    /// `fragmentStoresAndAtomics`) and primitive ids in the fragment stage (`geometryShader`).
    pub fn count_evaluations(&self, target: &RenderTarget, view: &View) -> Result<EvaluationCounts> {
        let analysis = self.analysis_variants(target, view)?;
        self.context.run_once(|cmd| self.record_analysis(analysis, cmd, target, view, AfterPass::Sampled))?;
        Ok(self.read_counters())
    }

    /// One frame of `view` drawn by the analysis variant, the counting one: its image, which
    /// triangle each pixel shows, and how many times the full shading function ran. Its
    /// rasterisation and shading are the timed variant's (tests/counts.rs compares the two).
    pub fn analyze(&self, target: &RenderTarget, view: &View) -> Result<Analysis> {
        let analysis = self.analysis_variants(target, view)?;
        let (image, triangles) =
            target.render_and_read_with(&self.context, Attachments::ColorAndIds, |cmd| {
                self.record_analysis(analysis, cmd, target, view, AfterPass::Readback)
            })?;
        let triangles = triangles.expect("ColorAndIds reads the ids back");
        Ok(Analysis { image, triangles, evaluations: self.read_counters() })
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
        if !self.emitters.is_empty() {
            self.prepare_analysis_emitter()?;
        }
        self.prepare_frame(view, target)?;
        self.prepare_variants(analysis, view)?;
        Ok(analysis)
    }

    /// Records one analysis frame: the counters zeroed, the frame, the counters made visible
    /// to the host.
    fn record_analysis(
        &self,
        analysis: &[Variant],
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        after: AfterPass,
    ) {
        let device = &self.context.device;
        let to_shaders = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::CLEAR)
            .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::ALL_GRAPHICS)
            .dst_access_mask(vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE)];
        let to_host = [vk::MemoryBarrier2::default()
            .src_stage_mask(vk::PipelineStageFlags2::ALL_GRAPHICS)
            .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)];
        // SAFETY: recording outside a render pass; the counter buffer has TRANSFER_DST usage
        // and is 16 bytes long.
        unsafe {
            device.cmd_fill_buffer(cmd, self.buffers.counters.raw, 0, 16, 0);
            device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_shaders));
        }
        self.record_with(analysis, cmd, target, view, after);
        // SAFETY: recording outside a render pass.
        unsafe {
            device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host))
        };
    }

    /// The counters of the last analysis frame (after its submission has finished).
    fn read_counters(&self) -> EvaluationCounts {
        let bytes = self.buffers.counters.mapped().expect("GpuToCpu memory is mapped");
        let values: [u32; 4] = bytemuck::pod_read_unaligned(&bytes[..16]);
        EvaluationCounts {
            vertices: u64::from(values[0]),
            sub_vertices: u64::from(values[1]),
            fragments: u64::from(values[2]),
            culled_patches: u64::from(values[3]),
        }
    }
}
