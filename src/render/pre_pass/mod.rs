//! The triangle-level pre-pass of `multirate` mode's compute placement (`Placement::Compute`):
//! [`PrePass`] owns its pipelines, its buffers and the ball of eyes its kept levels hold for, and
//! records its steps (culling, the range class, the estimator, refining, the patch levels and
//! lists) with the barriers that order them within a frame and against the frames around it.
//! The draws consume what it leaves ([`PatchLists`]).
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`steps`]: the steps, their workgroup sizes and barriers, and what a timestamp times.
//! 2. [`buffers`]: the buffers the steps write and read, and the patch lists the draws read.
//! 3. [`pipelines`]: the steps' compute pipelines, built on first use.

pub mod buffers;
pub mod pipelines;
pub mod steps;

use super::descriptors::Recorder;
use super::frame_config::FrameConfig;
use super::level_ball::{BallUse, LevelBall};
use super::pipelines::Instrumentation;
use super::scene_geometry::DrawCall;
use crate::error::Result;
use crate::gpu_interface::slots::{
    CAPPED_ESTIMATE_DISPATCH, FULL_ESTIMATE_DISPATCH, LEVEL_DISPATCHES, PATCH_DISPATCH, RANGE_DISPATCH,
    REFINE_DISPATCH,
};
use crate::gpu_types::DrawConstants;
use crate::shaders::Features;
use crate::vk::pipeline::{Pipeline, PipelineLayout, Specialization};
use crate::vk::Context;
use ash::vk;
use buffers::{PatchLists, PrePassBuffers};
use pipelines::{PrePassCache, PrePassPipelines};
use std::sync::{Arc, Mutex};
use steps::{barrier_after, PrePassStep, Timed, LEVEL_DISPATCH_STRIDE, LIST_READERS, PRE_PASS_GROUP};
use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};

/// The pre-pass of one scene.
pub(crate) struct PrePass {
    pub buffers: PrePassBuffers,
    pipelines: PrePassCache,
    /// The ball of eyes the kept levels (`PrePassBuffers::estimated_levels`) hold for, as the
    /// last submitted frame that commits left it (`level_ball`).
    ball: Mutex<Option<LevelBall>>,
}

impl PrePass {
    /// The pre-pass of a scene of `geometry`'s triangles and meshes and `kinds` material kinds.
    pub(crate) fn new(
        context: &Arc<Context>,
        geometry: &super::scene_geometry::SceneGeometry,
        kinds: usize,
    ) -> Result<PrePass> {
        Ok(PrePass {
            buffers: PrePassBuffers::new(context, geometry)?,
            pipelines: PrePassCache::new(kinds),
            ball: Mutex::new(None),
        })
    }

    /// The ball the kept levels hold for now.
    pub(crate) fn kept_ball(&self) -> Option<LevelBall> {
        *self.ball.lock().expect("level ball lock")
    }

    /// A submitted frame's ball (`FrameConfig::ball_after`) holds from now on.
    pub(crate) fn commit(&self, ball: Option<LevelBall>) {
        *self.ball.lock().expect("level ball lock") = ball;
    }

    /// Builds the pipelines a frame of `frame`'s configuration needs with `instrumentation`.
    pub(crate) fn prepare(
        &self,
        context: &Arc<Context>,
        layout: &PipelineLayout,
        specializations: &[(Features, Specialization)],
        instrumentation: Instrumentation,
        frame: &super::multirate_config::MultirateConfig,
    ) -> Result<()> {
        self.pipelines.prepare(context, layout, specializations, instrumentation, frame)
    }

    /// What the draws read of the pre-pass.
    pub(crate) fn patch_lists(&self) -> PatchLists<'_> {
        PatchLists::of(&self.buffers)
    }

    /// Records the pre-pass of `frame` over `draws` (those drawn whole as `pixel` does aside) with
    /// the pipelines of `instrumentation`: culling, which lists each mesh's visible triangles, the
    /// estimator over those lists, then the patch levels, which also sort the visible triangles
    /// into the flat, interpolated and fallback patch lists and fill their indirect draws; with
    /// the barriers that order it after the previous frame's reads and before this frame's.
    /// Where the frame's levels hold for a ball of eyes, those kept while the eye stays in it are
    /// reused (`level_ball`). Calls `stamp(Timed::Step(step), false)` before and `(.., true)`
    /// after each step.
    pub(crate) fn record(
        &self,
        rec: &Recorder<'_>,
        frame: &FrameConfig,
        draws: &[DrawCall],
        instrumentation: Instrumentation,
        stamp: &dyn Fn(Timed, bool),
    ) {
        // Each step's timestamps come right before a barrier, which settles them: the first
        // step's start before the resets (its interval holds them), each end and the next
        // step's start before the end's barrier.
        stamp(Timed::Step(PrePassStep::ALL[0]), false);
        self.reset(rec, frame.ball);
        let mut constants = frame.pre_pass_constants();
        rec.bind_set_at(vk::PipelineBindPoint::COMPUTE, 0, rec.descriptors.set);
        for (k, step) in PrePassStep::ALL.into_iter().enumerate() {
            for (index, draw) in draws.iter().enumerate() {
                // A mesh drawn whole as `pixel` draws it needs no levels.
                if frame.mesh_per_pixel(index) {
                    continue;
                }
                let Some(pipelines) = self.pipelines.get(instrumentation, draw.pipeline, &frame.multirate)
                else {
                    debug_assert!(false, "render, measure and the viewer prepare the view first");
                    continue;
                };
                self.dispatch_step(rec, step, pipelines, draw, &mut constants);
            }
            stamp(Timed::Step(step), true);
            if let Some(&next) = PrePassStep::ALL.get(k + 1) {
                stamp(Timed::Step(next), false);
            }
            rec.barrier(barrier_after(step));
        }
    }

    /// Once the previous frame has read the lists and levels: zeroes the list lengths and
    /// indirect draws and resets the indirect dispatches, before the first step; where a ball of
    /// eyes begins, also the levels kept for the last one, and the levels held where the ball is
    /// the first of its configuration.
    fn reset(&self, rec: &Recorder<'_>, ball: BallUse) {
        let (device, cmd) = (rec.device, rec.cmd);
        let buffers = &self.buffers;
        let storage = A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE;
        // The earlier frames' draws read the lists; their patch steps wrote the kept levels, which
        // this frame's steps read, or a clear begins again.
        rec.barrier((
            LIST_READERS | S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE,
            S::COMPUTE_SHADER | S::CLEAR | S::COPY,
            storage | A::TRANSFER_WRITE,
        ));
        if let BallUse::Begin { fresh, .. } = ball {
            // SAFETY: recording outside a render pass; the buffer has TRANSFER_DST usage.
            unsafe { device.cmd_fill_buffer(cmd, buffers.estimated_levels.raw, 0, vk::WHOLE_SIZE, 0) };
            if fresh {
                // SAFETY: as above.
                unsafe { device.cmd_fill_buffer(cmd, buffers.level_holds.raw, 0, vk::WHOLE_SIZE, 0) };
            }
        }
        for buffer in [&buffers.patch_counts, &buffers.flat_draws].into_iter().chain(&buffers.patch_draws) {
            // SAFETY: recording outside a render pass; the buffers have TRANSFER_DST usage.
            unsafe { device.cmd_fill_buffer(cmd, buffer.raw, 0, vk::WHOLE_SIZE, 0) };
        }
        let reset = [vk::BufferCopy::default().size(buffers.level_dispatches.size)];
        // SAFETY: recording outside a render pass; both buffers have the same size and the
        // TRANSFER_SRC / TRANSFER_DST usages.
        unsafe {
            device.cmd_copy_buffer(
                cmd,
                buffers.level_dispatch_reset.raw,
                buffers.level_dispatches.raw,
                &reset,
            )
        };
        rec.barrier((S::CLEAR | S::COPY, A::TRANSFER_WRITE, S::COMPUTE_SHADER, storage));
    }

    /// Records `step` of the pre-pass over `draw`'s mesh.
    fn dispatch_step(
        &self,
        rec: &Recorder<'_>,
        step: PrePassStep,
        pipelines: &PrePassPipelines,
        draw: &DrawCall,
        constants: &mut DrawConstants,
    ) {
        draw.set_constants(constants);
        constants.patch_base = draw.first_triangle;
        constants.triangle_count = draw.index_count / 3;
        rec.bind_material(vk::PipelineBindPoint::COMPUTE, draw.material_index);
        // The later steps cover the triangles the culling step (for the estimator step, the range
        // step, in two lists; for the refining step, the estimator step) listed, in the workgroups
        // it counted.
        let dispatch = |pipeline, slot| self.dispatch(rec, pipeline, slot, draw, constants);
        match step {
            PrePassStep::Cull => dispatch(&pipelines.cull, None),
            PrePassStep::Range => dispatch(&pipelines.range, Some(RANGE_DISPATCH)),
            PrePassStep::Estimate => {
                dispatch(&pipelines.estimate, Some(FULL_ESTIMATE_DISPATCH));
                if let Some(capped) = &pipelines.capped_estimate {
                    dispatch(capped, Some(CAPPED_ESTIMATE_DISPATCH));
                }
            }
            PrePassStep::Refine => dispatch(&pipelines.refine, Some(REFINE_DISPATCH)),
            PrePassStep::Patches => dispatch(&pipelines.patches, Some(PATCH_DISPATCH)),
        }
    }

    /// Binds `pipeline` and dispatches it over `draw`'s mesh: one invocation per triangle, or with
    /// the workgroups counted in the mesh's indirect dispatch `slot`.
    fn dispatch(
        &self,
        rec: &Recorder<'_>,
        pipeline: &Pipeline,
        slot: Option<u32>,
        draw: &DrawCall,
        constants: &DrawConstants,
    ) {
        rec.bind_pipeline(vk::PipelineBindPoint::COMPUTE, pipeline.raw);
        rec.push(constants);
        // SAFETY: recording outside a render pass; the dispatch buffer has INDIRECT_BUFFER usage.
        unsafe {
            match slot {
                None => {
                    rec.device.cmd_dispatch(rec.cmd, constants.triangle_count.div_ceil(PRE_PASS_GROUP), 1, 1)
                }
                Some(slot) => {
                    let mesh_dispatches =
                        vk::DeviceSize::from(LEVEL_DISPATCHES) * vk::DeviceSize::from(draw.mesh_index);
                    rec.device.cmd_dispatch_indirect(
                        rec.cmd,
                        self.buffers.level_dispatches.raw,
                        LEVEL_DISPATCH_STRIDE * (mesh_dispatches + vk::DeviceSize::from(slot)),
                    )
                }
            }
        }
    }
}
