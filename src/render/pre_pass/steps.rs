//! The steps of the triangle-level pre-pass ([`PrePassStep`]), their workgroup sizes, the
//! barrier after each, and what a timestamp pair of a measured frame times ([`Timed`]).

use crate::render::draw_part::{DrawPart, DRAW_PARTS};
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
    Estimate,
    Refine,
    Patches,
}

impl PrePassStep {
    /// Every step, in the order they run.
    pub const ALL: [PrePassStep; PRE_PASS_STEPS] = [
        PrePassStep::Cull,
        PrePassStep::Range,
        PrePassStep::Estimate,
        PrePassStep::Refine,
        PrePassStep::Patches,
    ];

    /// Its name in `bench`'s columns (`<name>_ms_median`).
    pub fn name(self) -> &'static str {
        match self {
            PrePassStep::Cull => "cull",
            PrePassStep::Range => "range",
            PrePassStep::Estimate => "estimate",
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
pub(crate) fn refine_lanes(info: &crate::vk::context::DeviceInfo) -> u32 {
    if info.cpu {
        REFINE_BLOCK
    } else {
        PRE_PASS_GROUP
    }
}

/// Bytes per dispatch in `PrePassBuffers::level_dispatches` (`uvec4 level_dispatches[]`).
pub(crate) const LEVEL_DISPATCH_STRIDE: vk::DeviceSize = 16;

/// The stages that read what the pre-pass writes: the indirect draws, the index fetch of the
/// flat patches' draws, and the vertex pulling and control stages of the multirate draws.
pub(crate) const LIST_READERS: S = S::from_raw(
    S::DRAW_INDIRECT.as_raw()
        | S::VERTEX_INPUT.as_raw()
        | S::VERTEX_SHADER.as_raw()
        | S::TESSELLATION_CONTROL_SHADER.as_raw(),
);

/// The barrier after `step`: its writes before the reads of the next step, or after the
/// last one, of the draws.
pub(crate) fn barrier_after(step: PrePassStep) -> (S, A, S, A) {
    let storage = A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE;
    match step {
        PrePassStep::Cull | PrePassStep::Range | PrePassStep::Estimate => (
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
            A::INDIRECT_COMMAND_READ | A::INDEX_READ | A::SHADER_STORAGE_READ,
        ),
    }
}

/// What a timestamp pair of `measure` times: the whole frame, the pre-pass, one of its steps, or
/// one part of one mesh's draws.
#[derive(Clone, Copy)]
pub(crate) enum Timed {
    PrePass,
    Step(PrePassStep),
    /// A part of mesh `mesh`'s draws, timed only where the frame's draws are timed apart
    /// ([`FrameStamps::draw_parts`]).
    Draw {
        mesh: u32,
        part: DrawPart,
    },
}

impl Timed {
    /// Its pass in `measure`'s `GpuTimer` (pass 0 is the whole frame; the draws' parts follow the
    /// steps, mesh by mesh).
    pub(crate) fn pass(self) -> u32 {
        match self {
            Timed::PrePass => 1,
            Timed::Step(step) => 2 + step as u32,
            Timed::Draw { mesh, part } => FIRST_DRAW_PASS + mesh * DRAW_PARTS as u32 + part as u32,
        }
    }
}

/// The first pass of the draws' parts in `measure`'s `GpuTimer`.
pub(crate) const FIRST_DRAW_PASS: u32 = 2 + PRE_PASS_STEPS as u32;

/// What a frame stamps as it is recorded: `stamp(timed, false)` before and `(.., true)` after
/// what `timed` names, and whether the draws' parts are stamped too. Timing them apart splits
/// the frame's rendering at each part's boundaries (lavapipe takes no timestamp inside a
/// rendering), which keeps its depth between renderings and costs the frame some time of its
/// own.
pub(crate) struct FrameStamps<'a> {
    pub stamp: &'a dyn Fn(Timed, bool),
    pub draw_parts: bool,
}

fn no_stamp(_: Timed, _: bool) {}

impl FrameStamps<'static> {
    /// A frame that is not timed.
    pub(crate) const NONE: FrameStamps<'static> = FrameStamps { stamp: &no_stamp, draw_parts: false };
}
