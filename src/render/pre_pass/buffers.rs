//! The buffers of the triangle-level pre-pass ([`PrePassBuffers`]) and the part of them the
//! draws read ([`PatchLists`]).

use crate::error::Result;
use crate::gpu_interface::slots::{FLAT_DRAW_WORDS, LEVEL_DISPATCHES, PATCH_COUNT_WORDS, PATCH_LISTS};
use crate::render::scene_geometry::SceneGeometry;
use crate::vk::memory::Buffer;
use crate::vk::Context;
use ash::vk;
use std::sync::Arc;

/// The buffers of the triangle-level pre-pass (`Placement::Compute`).
pub(crate) struct PrePassBuffers {
    /// Per triangle: its level.
    pub triangle_levels: Buffer,
    /// Per triangle: the level found for it in the current ball of eyes, 0 where none yet
    /// (`ESTIMATED_LEVELS`; zeroed when a ball begins, `PrePass::record`).
    pub estimated_levels: Buffer,
    /// Per triangle, its hold state (`gpu_types::LevelHold`, `LEVEL_HOLDS`; zeroed when a ball
    /// of another configuration begins, `PrePass::record`).
    pub level_holds: Buffer,
    /// Per triangle: the triangles across its edges (`uvec4`, scene indices).
    pub triangle_neighbours: Buffer,
    /// Per triangle: its corners' positions (9 floats).
    pub triangle_corners: Buffer,
    /// Per mesh: its triangles the pre-pass did not cull, those to classify and estimate from
    /// its first triangle on; from its last triangle down, those whose level the culling step
    /// knew (kept by the ball of eyes, or a back face of a two-sided mesh, marked with
    /// `BACK_FACE_ENTRY`).
    pub visible_triangles: Buffer,
    /// Per mesh: the triangles whose estimate the refining step refines, listed by the
    /// estimator step.
    pub refine_triangles: Buffer,
    /// Per mesh: the triangles to estimate that the range class does not settle, listed by the
    /// range step for the estimator step.
    pub estimate_triangles: Buffer,
    /// Per mesh: the lengths of its interpolated and fallback lists, and the indirect draws each
    /// opened (`PATCH_COUNT_WORDS` a list; zeroed before each pre-pass; the draw counts of
    /// `ForwardDraws::record_patch_lists`).
    pub patch_counts: Buffer,
    /// Per mesh: the indirect dispatches of the range, patch, refining and estimator steps over
    /// the triangles the culling, estimator and range steps listed (`VkDispatchIndirectCommand` and the
    /// list's length, 4 words each, `LEVEL_DISPATCHES` per mesh), reset from
    /// `level_dispatch_reset` before each pre-pass.
    pub level_dispatches: Buffer,
    /// `level_dispatches` before the culling step: (0, 1, 1, 0), no workgroups yet.
    pub level_dispatch_reset: Buffer,
    /// Per mesh, from its first triangle on: its visible triangles shaded on sub-vertices,
    /// those shaded per pixel, and those whose patch is the triangle itself (flat), as the
    /// last step lists them.
    pub patch_lists: [Buffer; 3],
    /// The indirect draws of the first two lists (`VkDrawIndirectCommand`, one per triangle),
    /// indexed by `INTERPOLATED_LIST` and `FALLBACK_LIST`.
    pub patch_draws: [Buffer; 2],
    /// Per mesh (`FLAT_DRAW_WORDS` words), the indirect draw of its flat list
    /// (`VkDrawIndirectCommand`: its flat patches shaded on their corners where its draws lack
    /// `DrawCall::shared_corners`) and that of its flat patches shaded per pixel
    /// (`VkDrawIndexedIndirectCommand`, over `fallback_indices`).
    pub flat_draws: Buffer,
    /// The flat patches shaded on their corners as an index buffer over the scene's vertices
    /// (`flat_indices` in glsl/include/bindings.glsl), for meshes whose draws have
    /// `DrawCall::shared_corners`.
    pub flat_indices: Buffer,
    /// Every mesh's flat patches shaded per pixel, appended from the mesh's first index on
    /// (`fallback_indices`).
    pub fallback_indices: Buffer,
    /// Per triangle: its patch's tessellation levels, written by the last step.
    pub patch_levels: Buffer,
}

impl PrePassBuffers {
    /// The pre-pass's buffers for `geometry`'s triangles and meshes.
    pub(crate) fn new(context: &Arc<Context>, geometry: &SceneGeometry) -> Result<PrePassBuffers> {
        let (triangle_count, meshes) = (geometry.triangle_count, geometry.draws.len());
        let per_triangle = |name| device_words(context, name, triangle_count, vk::BufferUsageFlags::empty());
        // TRANSFER_SRC: `Renderer::pre_pass_levels` reads it back.
        let triangle_levels =
            device_words(context, "triangle levels", triangle_count, vk::BufferUsageFlags::TRANSFER_SRC)?;
        let estimated_levels = device_words(
            context,
            "levels of the ball of eyes",
            triangle_count,
            vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        let level_holds =
            device_words(context, "levels held", 4 * triangle_count, vk::BufferUsageFlags::TRANSFER_DST)?;
        let no_neighbours = [[0; 4]];
        let neighbours: &[[u32; 4]] = if geometry.triangle_neighbours.is_empty() {
            &no_neighbours
        } else {
            &geometry.triangle_neighbours
        };
        let triangle_neighbours = Buffer::with_data(
            context,
            "triangle neighbours",
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            neighbours,
        )?;
        let triangle_corners = Buffer::with_data(
            context,
            "triangle corners",
            vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            &geometry.triangle_corners,
        )?;
        let visible_triangles = per_triangle("visible triangles")?;
        let refine_triangles = per_triangle("triangles to refine")?;
        let estimate_triangles = per_triangle("triangles to estimate in full")?;
        let patch_counts = device_words(
            context,
            "interpolated and fallback patch counts",
            PATCH_COUNT_WORDS as usize * PATCH_LISTS as usize * meshes,
            vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
        )?;
        let level_dispatches = device_words(
            context,
            "pre-pass dispatches",
            4 * LEVEL_DISPATCHES as usize * meshes,
            // TRANSFER_SRC: `Renderer::pre_pass_dispatches` reads it back.
            vk::BufferUsageFlags::INDIRECT_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
        )?;
        let level_dispatch_reset = Buffer::with_data(
            context,
            "pre-pass dispatch reset",
            vk::BufferUsageFlags::TRANSFER_SRC,
            &vec![[0u32, 1, 1, 0]; LEVEL_DISPATCHES as usize * meshes.max(1)],
        )?;
        let patch_lists = [
            per_triangle("interpolated patches")?,
            per_triangle("fallback patches")?,
            per_triangle("flat patches")?,
        ];
        let indirect = vk::BufferUsageFlags::INDIRECT_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
        let patch_draws = [
            device_words(context, "interpolated patch draws", 4 * triangle_count, indirect)?,
            device_words(context, "fallback patch draws", 4 * triangle_count, indirect)?,
        ];
        let flat_draws =
            device_words(context, "flat patch draws", FLAT_DRAW_WORDS as usize * meshes, indirect)?;
        let index_buffer =
            |name| device_words(context, name, 3 * triangle_count, vk::BufferUsageFlags::INDEX_BUFFER);
        let flat_indices = index_buffer("flat patch indices")?;
        let fallback_indices = index_buffer("per-pixel flat patch indices")?;
        let patch_levels = device_words(
            context,
            "patch tessellation levels",
            4 * triangle_count,
            vk::BufferUsageFlags::empty(),
        )?;
        Ok(PrePassBuffers {
            triangle_levels,
            estimated_levels,
            level_holds,
            triangle_neighbours,
            triangle_corners,
            visible_triangles,
            refine_triangles,
            estimate_triangles,
            patch_counts,
            level_dispatches,
            level_dispatch_reset,
            patch_lists,
            patch_draws,
            flat_draws,
            flat_indices,
            fallback_indices,
            patch_levels,
        })
    }
}

/// A device-local storage buffer of `count` 32-bit words (at least one), written and read only
/// by shaders (and by the usages in `extra`).
fn device_words(
    context: &Arc<Context>,
    name: &str,
    count: usize,
    extra: vk::BufferUsageFlags,
) -> Result<Buffer> {
    let size = (count.max(1) * std::mem::size_of::<u32>()) as vk::DeviceSize;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | extra;
    Buffer::new(context, name, size, usage, gpu_allocator::MemoryLocation::GpuOnly)
}

/// What the multirate draws read of a frame's pre-pass: the indirect draws of its patch lists and
/// their counts, and the flat patches' indices.
#[derive(Clone, Copy)]
pub(crate) struct PatchLists<'a> {
    /// Per mesh, the indirect draws of its flat patches.
    pub flat_draws: &'a Buffer,
    /// Per mesh and list, `PATCH_COUNT_WORDS` words: the list's length and the draws it opened.
    pub patch_counts: &'a Buffer,
    /// The interpolated and the fallback lists' indirect draws, one per triangle.
    pub patch_draws: &'a [Buffer; 2],
    /// The flat patches shaded on their corners, and those shaded per pixel, as index buffers
    /// (the first in each mesh's order, the second appended).
    pub flat_indices: &'a Buffer,
    pub fallback_indices: &'a Buffer,
}

impl PatchLists<'_> {
    /// The lists of `buffers`.
    pub(crate) fn of(buffers: &PrePassBuffers) -> PatchLists<'_> {
        PatchLists {
            flat_draws: &buffers.flat_draws,
            patch_counts: &buffers.patch_counts,
            patch_draws: &buffers.patch_draws,
            flat_indices: &buffers.flat_indices,
            fallback_indices: &buffers.fallback_indices,
        }
    }
}
