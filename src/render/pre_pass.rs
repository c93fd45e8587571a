//! The triangle-level pre-pass of `multirate` mode's compute placement (`Placement::Compute`):
//! its steps (culling, the estimator, refining, patch levels and lists), the barriers that
//! order them within a frame and against the frames around it, and the indirect draws of the
//! patch lists it fills.

use super::draws::{draw_constants, DrawCall};
use super::instrumentation::Timed;
use super::level_ball::{self, BallKey, BallUse};
use super::pipelines::{ListPipelines, PrePassPipelines, Variant};
use super::view::View;
use super::Renderer;
use crate::gpu_interface::flags::{FLAG_FALLBACK_PATCHES, FLAG_REUSE_LEVELS};
use crate::gpu_interface::slots::{
    CAPPED_ESTIMATE_DISPATCH, ESTIMATE_DISPATCH, FALLBACK_LIST, FULL_ESTIMATE_DISPATCH, INTERPOLATED_LIST,
    LEVEL_DISPATCHES, OPENED_DRAWS, PATCH_COUNT_WORDS, PATCH_DISPATCH, PATCH_LISTS, REFINE_DISPATCH,
};
use crate::gpu_types::DrawConstants;
use crate::vk::pipeline::Pipeline;
use ash::vk;
use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};

/// The steps of the triangle-level pre-pass, in order: list the visible triangles, give level 1
/// to those the range class settles (listing the others), estimate the others' levels (listing
/// those to refine), refine those, combine each level with its neighbours' into its patch's
/// tessellation levels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PrePassStep {
    Cull,
    Range,
    Levels,
    Refine,
    Patches,
}

impl PrePassStep {
    /// Every step, in the order they run.
    pub const ALL: [PrePassStep; PRE_PASS_STEPS] = [
        PrePassStep::Cull,
        PrePassStep::Range,
        PrePassStep::Levels,
        PrePassStep::Refine,
        PrePassStep::Patches,
    ];

    /// Its name in `bench`'s columns (`<name>_ms_median`).
    pub fn name(self) -> &'static str {
        match self {
            PrePassStep::Cull => "cull",
            PrePassStep::Range => "range",
            PrePassStep::Levels => "estimate",
            PrePassStep::Refine => "refine",
            PrePassStep::Patches => "patches",
        }
    }
}

/// How many steps the pre-pass has.
pub const PRE_PASS_STEPS: usize = 5;

/// Invocations per work group of the triangle-level pre-pass (`PRE_PASS_GROUP` in
/// glsl/include/bindings.glsl, the `local_size_x` of its compute shaders).
pub const PRE_PASS_GROUP: u32 = 64;

/// Listed triangles per block of the pre-pass's refining step (`REFINE_BLOCK` in
/// glsl/refine_levels.comp and glsl/triangle_levels.comp): a workgroup takes their children's
/// turns side by side, then estimates each of them. `tests/layout.rs` checks that the three agree.
pub const REFINE_BLOCK: u32 = 8;

/// The refining step's workgroup size on `info`'s device. A GPU runs invocations as threads:
/// `PRE_PASS_GROUP` of them share a block's children's turns (a GPU gains the most here: one
/// thread taking a triangle's turns in a row made the step 4.6 × the estimator step on an H200,
/// `docs/notebook/gpu.md`). A CPU device runs each SIMD batch through the whole estimator, idle lanes
/// or not: there the workgroup is the block alone, one batch.
pub(super) fn refine_lanes(info: &crate::vk::context::DeviceInfo) -> u32 {
    if info.cpu {
        REFINE_BLOCK
    } else {
        PRE_PASS_GROUP
    }
}

/// Bytes per dispatch in `PrePassBuffers::level_dispatches` (`uvec4 level_dispatches[]`).
const LEVEL_DISPATCH_STRIDE: vk::DeviceSize = 16;

/// The stages that read what the pre-pass writes: the indirect draws, vertex pulling and
/// control stages of the multirate draws.
const LIST_READERS: S = S::from_raw(
    S::DRAW_INDIRECT.as_raw() | S::VERTEX_SHADER.as_raw() | S::TESSELLATION_CONTROL_SHADER.as_raw(),
);

/// The barrier after `step`: its writes before the reads of the next step, or after the
/// last one, of the draws.
fn barrier_after(step: PrePassStep) -> (S, A, S, A) {
    let storage = A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE;
    match step {
        PrePassStep::Cull | PrePassStep::Range | PrePassStep::Levels => (
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE,
            S::COMPUTE_SHADER | S::DRAW_INDIRECT,
            storage | A::INDIRECT_COMMAND_READ,
        ),
        PrePassStep::Refine => (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE, S::COMPUTE_SHADER, storage),
        PrePassStep::Patches => (
            S::COMPUTE_SHADER,
            A::SHADER_STORAGE_WRITE,
            LIST_READERS,
            A::INDIRECT_COMMAND_READ | A::SHADER_STORAGE_READ,
        ),
    }
}

impl Renderer {
    /// `Placement::Compute`: the pre-pass that prepares the multirate draws: culling, which
    /// lists each mesh's visible triangles, the estimator over those lists, then the patch
    /// levels, which also sort the visible triangles into the flat, interpolated and fallback
    /// patch lists and fill their indirect draws; with the barriers that order it after the
    /// previous frame's reads and before this frame's. Where the view's levels hold for a ball of
    /// eyes, the levels kept while the eye stays in it are reused (`level_ball`).
    pub(super) fn record_triangle_levels(
        &self,
        variants: &[Variant],
        cmd: vk::CommandBuffer,
        view: &View,
        extent: vk::Extent2D,
        stamp: &dyn Fn(Timed, bool),
        per_pixel: &[bool],
    ) {
        // Whether this frame begins a ball of eyes or reuses the levels kept in one.
        let min_estimated_area = self.min_estimated_area(view);
        let key =
            BallKey { estimator: view.estimator, extent: (extent.width, extent.height), min_estimated_area };
        let ball_use = {
            let mut ball = self.level_ball.lock().expect("level ball lock");
            let (ball_use, next) = level_ball::next(*ball, view.camera.eye, key);
            *ball = next;
            ball_use
        };
        // Each step's timestamps come right before a barrier, which settles them: the first
        // step's start before the resets (its interval holds them), each end and the next
        // step's start before the end's barrier.
        stamp(Timed::Step(PrePassStep::ALL[0]), false);
        self.reset_pre_pass(cmd, matches!(ball_use, BallUse::Begin { .. }));
        let mut constants = draw_constants(view, extent, min_estimated_area);
        constants.patches_per_draw = self.patches_per_draw(view.estimator.n_max);
        constants.eye_radius = ball_use.radius();
        if ball_use.keeps_levels() {
            constants.flags |= FLAG_REUSE_LEVELS;
        }
        self.bind_set_at(cmd, vk::PipelineBindPoint::COMPUTE, 0, self.descriptors.set);
        for (k, step) in PrePassStep::ALL.into_iter().enumerate() {
            // A mesh drawn whole as `pixel` draws it needs no levels.
            for (index, draw) in self.draws.iter().enumerate() {
                if per_pixel.get(index) == Some(&true) {
                    continue;
                }
                let cell = variants[draw.pipeline].multirate_cell(view);
                let Some(pre_pass) = cell.get().and_then(|m| m.pre_pass.as_ref()) else {
                    debug_assert!(false, "render, measure and the viewer prepare the view first");
                    continue;
                };
                self.dispatch_step(cmd, step, pre_pass, draw, &mut constants);
            }
            stamp(Timed::Step(step), true);
            if let Some(&next) = PrePassStep::ALL.get(k + 1) {
                stamp(Timed::Step(next), false);
            }
            self.barrier(cmd, barrier_after(step));
        }
    }

    /// Once the previous frame has read the lists and levels: zeroes the list lengths and
    /// indirect draws and resets the indirect dispatches, before the first step; where a ball of
    /// eyes begins (`begin_ball`), also the levels kept for the last one.
    fn reset_pre_pass(&self, cmd: vk::CommandBuffer, begin_ball: bool) {
        let device = &self.context.device;
        let buffers = &self.buffers.pre_pass;
        let storage = A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE;
        // The earlier frames' draws read the lists; their patch steps wrote the kept levels, which
        // this frame's steps read, or a clear begins again.
        self.barrier(
            cmd,
            (
                LIST_READERS | S::COMPUTE_SHADER,
                A::SHADER_STORAGE_WRITE,
                S::COMPUTE_SHADER | S::CLEAR | S::COPY,
                storage | A::TRANSFER_WRITE,
            ),
        );
        if begin_ball {
            // SAFETY: recording outside a render pass; the buffer has TRANSFER_DST usage.
            unsafe { device.cmd_fill_buffer(cmd, buffers.estimated_levels.raw, 0, vk::WHOLE_SIZE, 0) };
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
        self.barrier(cmd, (S::CLEAR | S::COPY, A::TRANSFER_WRITE, S::COMPUTE_SHADER, storage));
    }

    /// Records `step` of the pre-pass over `draw`'s mesh.
    fn dispatch_step(
        &self,
        cmd: vk::CommandBuffer,
        step: PrePassStep,
        pre_pass: &PrePassPipelines,
        draw: &DrawCall,
        constants: &mut DrawConstants,
    ) {
        self.set_draw_constants(constants, draw);
        constants.patch_base = draw.first_triangle;
        constants.triangle_count = draw.index_count / 3;
        let material_set = self.descriptors.textures.sets[draw.material_index as usize];
        self.bind_set_at(cmd, vk::PipelineBindPoint::COMPUTE, 1, material_set);
        // The later steps cover the triangles the culling step (for the estimator step, the range
        // step, in two lists; for the refining step, the estimator step) listed, in the workgroups
        // it counted.
        match step {
            PrePassStep::Cull => self.dispatch(cmd, &pre_pass.cull, None, draw, constants),
            PrePassStep::Range => {
                self.dispatch(cmd, &pre_pass.range, Some(ESTIMATE_DISPATCH), draw, constants)
            }
            PrePassStep::Levels => {
                self.dispatch(cmd, &pre_pass.levels, Some(FULL_ESTIMATE_DISPATCH), draw, constants);
                if let Some(capped) = &pre_pass.capped_levels {
                    self.dispatch(cmd, capped, Some(CAPPED_ESTIMATE_DISPATCH), draw, constants);
                }
            }
            PrePassStep::Refine => {
                self.dispatch(cmd, &pre_pass.refine, Some(REFINE_DISPATCH), draw, constants)
            }
            PrePassStep::Patches => {
                self.dispatch(cmd, &pre_pass.patches, Some(PATCH_DISPATCH), draw, constants)
            }
        }
    }

    /// Binds `pipeline` and dispatches it over `draw`'s mesh: one invocation per triangle, or with
    /// the workgroups counted in the mesh's indirect dispatch `slot`.
    fn dispatch(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        slot: Option<u32>,
        draw: &DrawCall,
        constants: &DrawConstants,
    ) {
        let device = &self.context.device;
        // SAFETY: recording outside a render pass; the pipeline is owned by `self` and outlives
        // the submission.
        unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw) };
        self.push_draw_constants(cmd, constants);
        // SAFETY: as above; the dispatch buffer has INDIRECT_BUFFER usage.
        unsafe {
            match slot {
                None => device.cmd_dispatch(cmd, constants.triangle_count.div_ceil(PRE_PASS_GROUP), 1, 1),
                Some(slot) => {
                    let mesh_dispatches =
                        vk::DeviceSize::from(LEVEL_DISPATCHES) * vk::DeviceSize::from(draw.mesh_index);
                    device.cmd_dispatch_indirect(
                        cmd,
                        self.buffers.pre_pass.level_dispatches.raw,
                        LEVEL_DISPATCH_STRIDE * (mesh_dispatches + vk::DeviceSize::from(slot)),
                    )
                }
            }
        }
    }

    /// A global memory barrier from `(source stages, source accesses)` to `(destination
    /// stages, destination accesses)`.
    fn barrier(&self, cmd: vk::CommandBuffer, (src, src_access, dst, dst_access): (S, A, S, A)) {
        let barriers = [vk::MemoryBarrier2::default()
            .src_stage_mask(src)
            .src_access_mask(src_access)
            .dst_stage_mask(dst)
            .dst_access_mask(dst_access)];
        // SAFETY: `cmd` is recording outside a render pass.
        unsafe {
            self.context
                .device
                .cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barriers))
        };
    }

    /// `Placement::Compute`: draws the mesh's three patch lists of this frame's pre-pass, the
    /// interpolated patches with `interpolated`, the others with `lists`, each by the indirect
    /// draws the pre-pass filled (those it did not reach draw nothing).
    pub(super) fn record_patch_lists(
        &self,
        cmd: vk::CommandBuffer,
        constants: &mut DrawConstants,
        draw: &DrawCall,
        view: &View,
        interpolated: vk::Pipeline,
        lists: ListPipelines<vk::Pipeline>,
    ) {
        let device = &self.context.device;
        let buffers = &self.buffers.pre_pass;
        let per_draw = self.patches_per_draw(view.estimator.n_max);
        let commands = (draw.index_count / 3).div_ceil(per_draw);
        let stride = std::mem::size_of::<vk::DrawIndirectCommand>() as u32;
        constants.patch_base = draw.first_triangle;
        constants.patches_per_draw = per_draw;
        constants.triangle_count = draw.index_count / 3;
        // Every list's draws are count draws, or none is: lavapipe (Mesa 22.3) keeps a count
        // draw's count buffer for the plain indirect draws recorded after it.
        let counted = self.context.features.draw_indirect_count
            && commands <= self.context.limits.max_draw_indirect_count;
        let u32_size = std::mem::size_of::<u32>() as vk::DeviceSize;
        // `max_draws` indirect draws from `draws` (a buffer and offset), as many as the word at
        // `count` says where they are counted.
        let indirect = |(buffer, offset): (vk::Buffer, vk::DeviceSize), count, max_draws: u32| {
            // SAFETY: recording inside the rendering begun by `record_draws`; the pre-pass wrote
            // the commands and counts before the barrier it ends with; both buffers have
            // INDIRECT_BUFFER usage; a count is at most `max_draws`, whose commands lie within
            // the mesh's entries.
            unsafe {
                if counted {
                    let (count_buffer, count_offset) = count;
                    device.cmd_draw_indirect_count(
                        cmd,
                        buffer,
                        offset,
                        count_buffer,
                        count_offset,
                        max_draws,
                        stride,
                    );
                } else {
                    for k in 0..vk::DeviceSize::from(max_draws) {
                        device.cmd_draw_indirect(
                            cmd,
                            buffer,
                            offset + k * vk::DeviceSize::from(stride),
                            1,
                            stride,
                        );
                    }
                }
            }
        };
        let bind = |constants: &mut DrawConstants, pipeline, flag| {
            constants.flags = (constants.flags & !FLAG_FALLBACK_PATCHES) | flag;
            // SAFETY: as above; the pipeline is owned by `self`.
            unsafe { device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline) };
            self.push_draw_constants(cmd, constants);
        };
        // A flat list is one draw over the mesh (no tessellated-vertex limit applies), counted
        // by its own instance count (1 once the list has a triangle).
        let flat_draw = |constants: &mut DrawConstants, pipeline, list: u32, flag| {
            bind(constants, pipeline, flag);
            let offset = vk::DeviceSize::from((PATCH_LISTS * draw.mesh_index + list) * stride);
            let flat_draws = buffers.flat_draws.raw;
            indirect((flat_draws, offset), (flat_draws, offset + u32_size), 1);
        };
        // A tessellated list: the draws its patches opened, the first of its `commands` (all of
        // them, mostly empty, where they are not counted).
        let tessellated_draw = |constants: &mut DrawConstants, pipeline, list: u32, flag| {
            bind(constants, pipeline, flag);
            let first = vk::DeviceSize::from(draw.first_triangle * stride);
            let count_word = PATCH_COUNT_WORDS * (PATCH_LISTS * draw.mesh_index + list) + OPENED_DRAWS;
            let count = (buffers.patch_counts.raw, vk::DeviceSize::from(count_word) * u32_size);
            indirect((buffers.patch_draws[list as usize].raw, first), count, commands);
        };
        // The flat patches first and the per-pixel ones last, so that the early depth test
        // spares the per-pixel shading wherever the other lists cover it. Where their corners
        // are shared, the flat patches shaded on them are one indexed draw of the mesh.
        if draw.shared_corners {
            bind(constants, lists.flat, 0);
            // SAFETY: as above; the pre-pass wrote every word of the mesh's range of
            // `flat_indices` (INDEX_BUFFER usage) before its last barrier; the scene's index
            // buffer is bound back for the draws that follow.
            unsafe {
                device.cmd_bind_index_buffer(cmd, buffers.flat_indices.raw, 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0);
                device.cmd_bind_index_buffer(cmd, self.buffers.indices.raw, 0, vk::IndexType::UINT32);
            }
        } else {
            flat_draw(constants, lists.flat, INTERPOLATED_LIST, 0);
        }
        tessellated_draw(constants, interpolated, INTERPOLATED_LIST, 0);
        // The per-pixel patches' depth first, then their shading where they are the nearest
        // surface: each covered pixel is shaded once, whatever the lists' order.
        tessellated_draw(constants, lists.fallback_prime, FALLBACK_LIST, FLAG_FALLBACK_PATCHES);
        flat_draw(constants, lists.flat_fallback_prime, FALLBACK_LIST, FLAG_FALLBACK_PATCHES);
        tessellated_draw(constants, lists.fallback, FALLBACK_LIST, FLAG_FALLBACK_PATCHES);
        flat_draw(constants, lists.flat_fallback, FALLBACK_LIST, FLAG_FALLBACK_PATCHES);
        constants.flags &= !FLAG_FALLBACK_PATCHES;
    }
}
