//! What the renderer measures and records besides the image: GPU times of the frame, the
//! pre-pass and its steps ([`measure`], [`Measurement`]), shading evaluations by stage
//! ([`EvaluationCounts`], counted by the analysis frames, [`Analysis`]), and the barriers and
//! copies that hand counters, level records and dispatches to the host.

use super::draw_part::DRAW_PARTS;
use super::frame_config::RecordedFrame;
use super::guard;
use super::mode::{Mode, Placement};
use super::pre_pass::steps::{FrameStamps, PrePassStep, Timed, FIRST_DRAW_PASS, PRE_PASS_STEPS};
use super::view::View;
use crate::error::Result;
use crate::vk::frames::FrameRing;
use crate::vk::memory::Buffer;
use crate::vk::target::{Attachments, FloatImage, RenderTarget};
use crate::vk::timing::{GpuInterval, GpuTimer, PipelineStatistics};
use ash::vk;

/// GPU times and counts of measured frames.
#[derive(Clone, Debug, Default)]
pub struct Measurement {
    /// When the forward pass ran in every measured frame, in submission order.
    pub frames: Vec<GpuInterval>,
    /// `Placement::Compute`: when the triangle-level pre-pass (its steps: culling, range,
    /// estimator, refining, patch; part of the frame) ran, in every measured frame that ran it (not those
    /// whose meshes were all drawn as `pixel` does); empty otherwise.
    pub pre_pass: Vec<GpuInterval>,
    /// `Placement::Compute` where its steps are timed ([`MeasureOptions::pre_pass_steps`]): when
    /// each of them ran (`PrePassStep::ALL`'s order), in every measured frame that ran it; empty
    /// otherwise.
    pub pre_pass_steps: Vec<[GpuInterval; PRE_PASS_STEPS]>,
    /// Where the draws' parts were timed ([`MeasureOptions::draw_parts`]): per measured frame, the
    /// milliseconds of each part (`DrawPart::ALL`'s order), summed over the meshes; empty
    /// otherwise.
    pub draw_parts_ms: Vec<[f64; DRAW_PARTS]>,
    /// Pipeline statistics of the last frame, where the device has them.
    pub statistics: Option<PipelineStatistics>,
    /// Where the frame guard applies (`guard::key_of`): how many measured frames it drew
    /// as `pixel` does (`View::drawn_as_pixel`). None where it does not apply.
    pub drawn_as_pixel: Option<u32>,
    /// Per measured frame, its pre-pass's milliseconds (0 where it ran none).
    pub frame_pre_pass_ms: Vec<f64>,
}

/// How frames are measured besides their number: the camera's turn, and whether the pre-pass's
/// steps and each part of the draws are timed apart. By default a frame is timed as a user's
/// frame runs: a timestamp at its start and end, and the pre-pass's two.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeasureOptions {
    pub turn: CameraTurn,
    /// Time each part of every mesh's draws (`DrawPart`) apart. The frame's rendering is then
    /// split at every part's start and end (lavapipe takes no timestamp inside a rendering),
    /// which makes the frame itself slower: compare its time with a run without.
    pub draw_parts: bool,
    /// Time each step of the pre-pass apart. lavapipe flushes its queued work at a timestamp of
    /// any stage after the top of the pipe, which a step's end needs: the timestamps between
    /// the steps slow the pre-pass (`docs/frame_time.md`), which a user's frame does not pay.
    pub pre_pass_steps: bool,
}

/// The camera turning about its target while frames are measured: `degrees_per_frame` about its
/// up direction, frame after frame. Measured frame `k` of a measurement shows the camera turned
/// by `first_measured + k` frames' worth, whatever warm-up came before it, so that every
/// configuration measured along the same turn sees the same cameras (a guarded view warms up
/// longer, `GUARD_START_FRAMES`); the warm-up frames lead up to the first measured one. A camera
/// that stays still measures the frames a still view gives, where the pre-pass reuses its levels
/// (`render::level_ball`); a turning one, what a moving view costs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CameraTurn {
    pub degrees_per_frame: f32,
    /// Frames measured before along this turn (by earlier measurements).
    pub first_measured: u32,
    /// Along a camera path instead of a turn: frame `k` shows the path at `k / fps` seconds
    /// (the warm-up frames its start).
    pub path: Option<PathFrames>,
}

/// A camera path that measured frames follow, at `fps` frames a second, from the camera
/// `start` (an orbit turns from it) in a scene of box `bounds` (`Camera::on_path`). Views
/// from another camera (the empty frame's) stay where they are.
#[derive(Clone, Debug, PartialEq)]
pub struct PathFrames {
    pub path: std::sync::Arc<crate::scene::path::CameraPath>,
    pub fps: f32,
    pub start: crate::scene::Camera,
    pub bounds: (glam::Vec3, glam::Vec3),
}

impl CameraTurn {
    /// `view` with its camera turned by `frames` frames' worth from where the turn starts
    /// (negative: before it).
    fn view_at(&self, view: &View, frames: i64) -> View {
        if let Some(along) = self.path.as_ref().filter(|along| along.start == view.camera) {
            let frame = (i64::from(self.first_measured) + frames).max(0);
            return view.seen_from(along.start.on_path(&along.path, frame as f32 / along.fps, along.bounds));
        }
        if self.degrees_per_frame == 0.0 {
            return view.clone();
        }
        let camera = view.camera;
        let angle = (self.degrees_per_frame * (i64::from(self.first_measured) + frames) as f32).to_radians();
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

/// What [`measure`] needs of the renderer: its device, its frame guard and its timed frames.
pub(super) trait TimedFrames {
    fn context(&self) -> &std::sync::Arc<crate::vk::Context>;
    /// Whether the frame guard applies to `view` on a target of `extent`.
    fn guard_applies(&self, view: &View, extent: vk::Extent2D) -> bool;
    /// Whether the guard of `view`'s configuration has decided (true where none applies).
    fn guard_decided(&self, view: &View, extent: vk::Extent2D) -> bool;
    /// `view` as its guard draws the next frame.
    fn guarded(&self, view: &View, extent: vk::Extent2D) -> View;
    /// A frame drawn as `view` took `gpu_ms`.
    fn report_frame_time(&self, view: &View, extent: vk::Extent2D, gpu_ms: f64);
    /// Fits the directional lights' shadow maps to `view` (`Renderer::fit_shadows`).
    fn fit_shadows(&self, view: &View, extent: vk::Extent2D) -> Result<()>;
    /// Records a timed frame of `view`, calling `stamp` around the pre-pass and its steps.
    fn record_timed(
        &self,
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        view: &View,
        stamps: &FrameStamps<'_>,
    ) -> RecordedFrame;
    /// How many meshes a frame draws.
    fn mesh_count(&self) -> usize;
    /// A recorded frame was submitted.
    fn submitted(&self, frame: RecordedFrame);
}

/// `Renderer::measure_with`: renders `warmup` frames (more for a guarded view whose guard has
/// not decided yet: at most [`GUARD_START_FRAMES`] more), then `frames` measured ones of `view`
/// as `options` say, with up to two frames in flight, through `renderer`.
pub(super) fn measure(
    renderer: &impl TimedFrames,
    target: &RenderTarget,
    view: &View,
    (warmup, frames): (u32, u32),
    options: MeasureOptions,
) -> Result<Measurement> {
    let turn = &options.turn;
    // Pass 0: the whole frame; pass 1: the pre-pass, within it; then its steps, where it
    // has them, and the draws' parts, where they are timed (every query read must have been
    // written).
    let pre_pass = view.mode == Mode::Multirate && view.placement == Placement::Compute;
    let draw_passes = (renderer.mesh_count() * DRAW_PARTS) as u32;
    let passes = match (options.draw_parts, pre_pass && options.pre_pass_steps) {
        (true, _) => FIRST_DRAW_PASS + draw_passes,
        (false, true) => 2 + PRE_PASS_STEPS as u32,
        (false, false) => 2,
    };
    let timer = GpuTimer::new(renderer.context(), passes, FRAMES_IN_FLIGHT as u32)?;
    let mut ring = FrameRing::new(renderer.context(), FRAMES_IN_FLIGHT)?;
    let mut measurement = Measurement::default();
    let extent = target.extent();
    if renderer.guard_applies(view, extent) {
        measurement.drawn_as_pixel = Some(0);
    }
    // Per slot, the frame it last drew.
    let mut in_slot: [Option<SlotFrame>; FRAMES_IN_FLIGHT] = Default::default();
    let collect = |ring: &mut FrameRing,
                   slot: usize,
                   drawn: Option<SlotFrame>,
                   measurement: &mut Measurement| {
        let Some(SlotFrame { measured, view: frame_view, ran_pre_pass, stamped }) = drawn else {
            return Ok(());
        };
        if !ring.wait(slot)? {
            return Ok(());
        }
        let read = if ran_pre_pass || options.draw_parts { passes } else { 2 };
        let intervals = timer.pass_intervals(slot as u32, read)?;
        renderer.report_frame_time(&frame_view, extent, intervals[0].milliseconds());
        if measured {
            measurement.frames.push(intervals[0]);
            // The pre-pass's times are those of the frames that ran it.
            measurement.frame_pre_pass_ms.push(if ran_pre_pass { intervals[1].milliseconds() } else { 0.0 });
            if ran_pre_pass {
                measurement.pre_pass.push(intervals[1]);
                if options.pre_pass_steps {
                    let steps = PrePassStep::ALL.map(|step| intervals[Timed::Step(step).pass() as usize]);
                    measurement.pre_pass_steps.push(steps);
                }
            }
            if options.draw_parts {
                let mut parts = [0.0; DRAW_PARTS];
                // A part the frame did not draw took no time: its empty interval is left out
                // (two timestamps back to back may read a tenth of a microsecond apart).
                let drawn_parts = intervals.iter().zip(&stamped).skip(FIRST_DRAW_PASS as usize);
                for (k, (interval, _)) in drawn_parts.enumerate().filter(|(_, (_, stamped))| **stamped) {
                    parts[k % DRAW_PARTS] += interval.milliseconds();
                }
                measurement.draw_parts_ms.push(parts);
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
    // The warm-up's turn leads up to the first measured frame as if the warm-up took as long as
    // it may; where the guard decides sooner, the camera skips ahead to it.
    let planned_warmup = if renderer.guard_decided(view, extent) { warmup } else { longest_warmup };
    let (mut frame, mut measured_frames) = (0u32, 0u32);
    while measured_frames < frames {
        let slot = frame as usize % FRAMES_IN_FLIGHT;
        collect(&mut ring, slot, in_slot[slot].take(), &mut measurement)?;
        let measured = frame >= warmup && (frame >= longest_warmup || renderer.guard_decided(view, extent));
        let turned =
            if measured { i64::from(measured_frames) } else { i64::from(frame) - i64::from(planned_warmup) };
        let frame_view = renderer.guarded(&turn.view_at(view, turned), extent);
        renderer.fit_shadows(&frame_view, extent)?;
        let mut recorded = None;
        let mut stamped_passes = Vec::new();
        ring.submit(slot, |cmd| {
            let slot = slot as u32;
            timer.reset(cmd, slot);
            timer.timestamp(cmd, slot, 0, false);
            timer.statistics(cmd, slot, true);
            // A step starts once the one before it has finished (the barrier between them
            // holds the next dispatch, not a top-of-pipe timestamp): its timestamps are
            // written after every earlier command, each before a barrier that settles it.
            // The draws' parts are timed outside the rendering, which each of their stamps
            // pauses. Where they are, what a frame does not stamp (the steps of a frame without
            // a pre-pass, the parts it does not draw) is written empty after it; otherwise a
            // frame that ran no pre-pass has only its first two passes read, and costs what a
            // frame of a mode without one costs (no timestamps of steps it did not run, which
            // lavapipe records as work of their own).
            let tracked = if options.draw_parts { passes as usize } else { 0 };
            let stamped = std::cell::RefCell::new(vec![false; tracked]);
            let stamp = |timed: Timed, end: bool| {
                let pass = timed.pass();
                match timed {
                    Timed::PrePass => timer.timestamp(cmd, slot, pass, end),
                    Timed::Step(_) if options.pre_pass_steps => timer.settled_timestamp(cmd, slot, pass, end),
                    Timed::Step(_) => return,
                    Timed::Draw { .. } if options.draw_parts => {
                        let device = &renderer.context().device;
                        target.pause(device, cmd);
                        timer.settled_timestamp(cmd, slot, pass, end);
                        target.resume(device, cmd, Attachments::Color);
                    }
                    Timed::Draw { .. } => return,
                }
                if let Some(stamped) = stamped.borrow_mut().get_mut(pass as usize) {
                    *stamped = true;
                }
            };
            let stamps = FrameStamps { stamp: &stamp, draw_parts: options.draw_parts };
            recorded = Some(renderer.record_timed(cmd, target, &frame_view, &stamps));
            for (pass, _) in stamped.borrow().iter().enumerate().skip(1).filter(|(_, stamped)| !**stamped) {
                for end in [false, true] {
                    timer.top_of_pipe_timestamp(cmd, slot, pass as u32, end);
                }
            }
            stamped_passes = stamped.into_inner();
            timer.statistics(cmd, slot, false);
            timer.timestamp(cmd, slot, 0, true);
        })?;
        let recorded = recorded.expect("the frame was recorded");
        let ran_pre_pass = recorded.ran_pre_pass;
        renderer.submitted(recorded);
        in_slot[slot] = Some(SlotFrame { measured, view: frame_view, ran_pre_pass, stamped: stamped_passes });
        measured_frames += u32::from(measured);
        frame += 1;
    }
    for (slot, drawn) in in_slot.iter_mut().enumerate() {
        collect(&mut ring, slot, drawn.take(), &mut measurement)?;
    }
    Ok(measurement)
}

/// A frame submitted in a slot of `measure`'s ring, until its times are read.
struct SlotFrame {
    /// Whether its times count.
    measured: bool,
    /// How it was drawn (the frame guard's choice or probe).
    view: View,
    /// Whether it ran the pre-pass.
    ran_pre_pass: bool,
    /// Per timed pass, where the draws' parts are timed, whether the frame stamped it.
    stamped: Vec<bool>,
}

/// A barrier that makes the writes of `stages` to storage buffers visible to the host.
pub(super) fn storage_to_host(device: &ash::Device, cmd: vk::CommandBuffer, stages: vk::PipelineStageFlags2) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(stages)
        .src_access_mask(vk::AccessFlags2::SHADER_STORAGE_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)];
    // SAFETY: `cmd` is recording outside a rendering.
    unsafe { device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barrier)) };
}

/// Copies `source` into `readback` once every earlier command has written it, and makes the copy
/// visible to the host.
pub(super) fn copy_for_host(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    source: &Buffer,
    readback: &Buffer,
) {
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
    // SAFETY: recording outside a rendering; both buffers are live, `source` has TRANSFER_SRC
    // and `readback` TRANSFER_DST usage, and the region fits both.
    unsafe {
        device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&before));
        device.cmd_copy_buffer(cmd, source.raw, readback.raw, &region);
        device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&after));
    }
}

/// Zeroes the evaluation `counters` before an analysis frame's shaders add to them.
pub(super) fn zero_counters(device: &ash::Device, cmd: vk::CommandBuffer, counters: &Buffer) {
    let to_shaders = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::CLEAR)
        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::ALL_GRAPHICS)
        .dst_access_mask(vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE)];
    // SAFETY: recording outside a rendering; the counter buffer has TRANSFER_DST usage and is 16
    // bytes long.
    unsafe {
        device.cmd_fill_buffer(cmd, counters.raw, 0, 16, 0);
        device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_shaders));
    }
}

/// The counters of the last analysis frame (after its submission has finished).
pub(super) fn read_counters(counters: &Buffer) -> EvaluationCounts {
    let bytes = counters.mapped().expect("GpuToCpu memory is mapped");
    let values: [u32; 4] = bytemuck::pod_read_unaligned(&bytes[..16]);
    EvaluationCounts {
        vertices: u64::from(values[0]),
        sub_vertices: u64::from(values[1]),
        fragments: u64::from(values[2]),
        culled_patches: u64::from(values[3]),
    }
}
