//! The forward draws ([`ForwardDraws`]): each mesh's draw as its frame says (whole, in chunks,
//! or from the pre-pass's patch lists, with the back faces after them), the polygonal lights'
//! emissive geometry, and how a draw is split into chunks where lavapipe needs it (the lavapipe
//! workarounds at the end of this file).

use super::descriptors::Recorder;
use super::draw_part::DrawPart;
use super::frame_config::{back_faces_per_pixel, FrameConfig};
use super::mode::Mode;
use super::pipelines::{ListPipelines, MeshPipelines};
use super::pre_pass::buffers::PatchLists;
use super::pre_pass::steps::Timed;
use super::scene_geometry::{DrawCall, EmitterDraw};
use super::view::View;
use crate::analysis::tessellator::uniform_vertex_count;
use crate::gpu_interface::flags::FLAG_FALLBACK_PATCHES;
use crate::gpu_interface::slots::{
    FALLBACK_FLAT_DRAW, FALLBACK_LIST, FLAT_DRAW_WORDS, FLAT_LIST_DRAW, INTERPOLATED_LIST, OPENED_DRAWS,
    PATCH_COUNT_WORDS, PATCH_LISTS,
};
use crate::gpu_types::DrawConstants;
use crate::scene::adjacency::PATCH_SIZE;
use crate::vk::pipeline::Pipeline;
use crate::vk::target::Attachments;
use ash::vk;

/// The scene's draws: one per mesh and one per polygonal light, and the most tessellated
/// vertices one draw may emit on this device.
pub(super) struct ForwardDraws {
    /// One per mesh, in scene order.
    pub meshes: Vec<DrawCall>,
    /// The polygonal lights' emissive geometry, one fan each.
    pub emitters: Vec<EmitterDraw>,
    /// Most tessellated vertices one draw may emit, where the driver needs a limit
    /// (lavapipe: [`tessellated_vertex_budget`]).
    vertex_budget: Option<u32>,
}

/// Whether a draw draws the draw-indirect counts (`drawIndirectCount`) of the patch lists, and
/// how many commands a list has at most.
#[derive(Clone, Copy)]
pub(super) struct IndirectCounts {
    pub supported: bool,
    pub max_count: u32,
}

impl ForwardDraws {
    /// The draws of `meshes` and `emitters` on the device `info`.
    pub(super) fn new(
        meshes: Vec<DrawCall>,
        emitters: Vec<EmitterDraw>,
        info: &crate::vk::context::DeviceInfo,
    ) -> ForwardDraws {
        ForwardDraws { meshes, emitters, vertex_budget: tessellated_vertex_budget(info) }
    }

    /// The draws of every mesh of `frame` into the rendering begun on `rec`, each with the
    /// pipelines `pick` gives for the view it is drawn with (the frame's, or `pixel` mode's for a
    /// mesh drawn whole per pixel), into `attachments`; the multirate draws of the compute
    /// placement from `lists`, each part stamped (`Timed::Draw`). Returns the push constants
    /// as the last draw left them.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn record_meshes(
        &self,
        rec: &Recorder<'_>,
        frame: &FrameConfig,
        pick: &dyn Fn(&DrawCall, &View) -> Option<MeshPipelines>,
        lists: Option<PatchLists<'_>>,
        counts: IndirectCounts,
        attachments: Attachments,
        stamp: &dyn Fn(Timed, bool),
    ) -> DrawConstants {
        let mut constants = frame.draw_constants();
        // SAFETY: `cmd` is recording inside a rendering; the buffers are owned by the renderer and
        // outlive the submission.
        unsafe {
            rec.device.cmd_bind_vertex_buffers(rec.cmd, 0, &[rec.buffers.vertices.raw], &[0]);
            rec.device.cmd_bind_index_buffer(rec.cmd, rec.buffers.indices.raw, 0, vk::IndexType::UINT32);
        }
        rec.bind_set(0, rec.descriptors.set);
        let view = &frame.view;
        let pixel_view = View { mode: Mode::Pixel, ..view.clone() };
        for (index, draw) in self.meshes.iter().enumerate() {
            let mesh_view = if frame.mesh_per_pixel(index) { &pixel_view } else { view };
            draw.set_constants(&mut constants);
            let Some(pipelines) = pick(draw, mesh_view) else {
                debug_assert!(false, "render, measure and the viewer prepare the view first");
                continue;
            };
            let mesh = MeshDraw { draw, view: mesh_view, frame, attachments, stamp };
            self.record_mesh(rec, &mesh, pipelines, lists, counts, &mut constants);
        }
        constants
    }

    /// The draws of one mesh with `pipelines`: the pre-pass's patch lists where they have
    /// them, otherwise the mesh's triangles (or `Placement::Tcs` adjacency patches) in chunks
    /// of at most the patches one draw may hold.
    fn record_mesh(
        &self,
        rec: &Recorder<'_>,
        mesh: &MeshDraw<'_>,
        pipelines: MeshPipelines,
        lists: Option<PatchLists<'_>>,
        counts: IndirectCounts,
        constants: &mut DrawConstants,
    ) {
        let (device, cmd) = (rec.device, rec.cmd);
        let (draw, view, attachments) = (mesh.draw, mesh.view, mesh.attachments);
        let cull = if draw.one_sided { vk::CullModeFlags::BACK } else { vk::CullModeFlags::NONE };
        // SAFETY: `cmd` is recording inside the rendering `record_meshes` draws into.
        unsafe { device.cmd_set_cull_mode(cmd, cull) };
        rec.bind_set(1, rec.descriptors.textures.sets[draw.material_index as usize]);
        if let (Some(list_pipelines), Some(lists)) = (pipelines.lists, lists) {
            let patch_draws = PatchDraws { lists, counts, per_draw: mesh.frame.patches_per_draw };
            self.record_patch_lists(rec, mesh, &patch_draws, constants, pipelines.first, list_pipelines);
            if back_faces_per_pixel(view.placement, draw.one_sided) {
                mesh.part(DrawPart::BackFaces, || {
                    self.record_back_faces(rec, constants, draw, pipelines.back_faces);
                });
            }
            return;
        }
        // Multirate drawn here is `Placement::Tcs`: 12-point adjacency patches.
        let adjacency = view.mode == Mode::Multirate;
        let (first_index, index_count, patches, indices_per_primitive) = match view.mode {
            Mode::Pixel | Mode::Vertex | Mode::PixelDeferred => {
                (draw.first_index, draw.index_count, u32::MAX, 3)
            }
            Mode::Fixed(level) => {
                (draw.first_index, draw.index_count, self.fixed_patches_per_draw(level, attachments), 3)
            }
            Mode::Multirate => (
                draw.first_patch_index,
                draw.index_count / 3 * PATCH_SIZE as u32,
                self.multirate_patches_per_draw(mesh.frame.multirate.estimator.n_max),
                PATCH_SIZE as u32,
            ),
        };
        let chunk = patches.saturating_mul(indices_per_primitive);
        mesh.stamp_part(DrawPart::Whole, false);
        // SAFETY: as above; the index buffers have INDEX_BUFFER usage and the pipeline was
        // built with the renderer's layout.
        unsafe {
            if adjacency {
                device.cmd_bind_index_buffer(cmd, rec.buffers.patch_indices.raw, 0, vk::IndexType::UINT32);
            }
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipelines.first);
            let mut first = 0;
            while first < index_count {
                let count = chunk.min(index_count - first);
                constants.patch_base = draw.first_triangle + first / indices_per_primitive;
                rec.push(constants);
                device.cmd_draw_indexed(cmd, count, 1, first_index + first, 0, 0);
                first += count;
            }
            if adjacency {
                device.cmd_bind_index_buffer(cmd, rec.buffers.indices.raw, 0, vk::IndexType::UINT32);
            }
        }
        mesh.stamp_part(DrawPart::Whole, true);
    }

    /// `Placement::Compute`: draws the mesh's three patch lists of this frame's pre-pass, the
    /// interpolated patches with `interpolated`, the others with `lists`, each by the indirect
    /// draws the pre-pass filled (those it did not reach draw nothing).
    fn record_patch_lists(
        &self,
        rec: &Recorder<'_>,
        mesh: &MeshDraw<'_>,
        patch_draws: &PatchDraws<'_>,
        constants: &mut DrawConstants,
        interpolated: vk::Pipeline,
        lists: ListPipelines<vk::Pipeline>,
    ) {
        let (device, cmd, draw) = (rec.device, rec.cmd, mesh.draw);
        let buffers = &patch_draws.lists;
        let per_draw = patch_draws.per_draw;
        let commands = (draw.index_count / 3).div_ceil(per_draw);
        let stride = std::mem::size_of::<vk::DrawIndirectCommand>() as u32;
        constants.patch_base = draw.first_triangle;
        constants.patches_per_draw = per_draw;
        constants.triangle_count = draw.index_count / 3;
        // Every list's draws are count draws, or none is: lavapipe (Mesa 22.3) keeps a count
        // draw's count buffer for the plain indirect draws recorded after it.
        let counted = patch_draws.counts.supported && commands <= patch_draws.counts.max_count;
        let u32_size = std::mem::size_of::<u32>() as vk::DeviceSize;
        // `max_draws` indirect draws from `draws` (a buffer and offset), as many as the word at
        // `count` says where they are counted.
        let indirect = |(buffer, offset): (vk::Buffer, vk::DeviceSize), count, max_draws: u32| {
            // SAFETY: recording inside the rendering `record_meshes` draws into; the pre-pass wrote
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
            rec.bind_pipeline(vk::PipelineBindPoint::GRAPHICS, pipeline);
            rec.push(constants);
        };
        // The mesh's words in `flat_draws` (its two draws of flat patches).
        let flat_draw_word =
            |first_word: u32| vk::DeviceSize::from(FLAT_DRAW_WORDS * draw.mesh_index + first_word) * u32_size;
        // The flat list is one draw over the mesh (no tessellated-vertex limit applies), counted
        // by its own instance count (1 once the list has a triangle).
        let flat_list_draw = |constants: &mut DrawConstants, pipeline| {
            bind(constants, pipeline, 0);
            let offset = flat_draw_word(FLAT_LIST_DRAW);
            let flat_draws = buffers.flat_draws.raw;
            indirect((flat_draws, offset), (flat_draws, offset + u32_size), 1);
        };
        // The flat patches shaded on their corners, from `flat_indices`: one indexed draw of the
        // mesh in its own order, which skips the other triangles' words. The scene's index buffer
        // is bound back for the draws that follow.
        let shared_corners_draw = |constants: &mut DrawConstants, pipeline| {
            bind(constants, pipeline, 0);
            // SAFETY: as above; the pre-pass wrote every word of the mesh's range of
            // `flat_indices` (INDEX_BUFFER usage) before its last barrier.
            unsafe {
                device.cmd_bind_index_buffer(cmd, buffers.flat_indices.raw, 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0);
                device.cmd_bind_index_buffer(cmd, rec.buffers.indices.raw, 0, vk::IndexType::UINT32);
            }
        };
        // The flat patches shaded per pixel, which the pre-pass appended to `fallback_indices`:
        // one indexed draw of as many as it appended (none where it appended none), counted by
        // its own instance count like the flat list.
        let fallback_flat_draw = |constants: &mut DrawConstants, pipeline| {
            bind(constants, pipeline, FLAG_FALLBACK_PATCHES);
            let offset = flat_draw_word(FALLBACK_FLAT_DRAW);
            let flat_draws = buffers.flat_draws.raw;
            let indexed_stride = std::mem::size_of::<vk::DrawIndexedIndirectCommand>() as u32;
            // SAFETY: as above; the pre-pass wrote the command (zeroed by the host, INDIRECT_BUFFER
            // usage) and the indices it counts within the mesh's range of `fallback_indices`
            // (INDEX_BUFFER usage) before its last barrier; its count word is 0 or 1.
            unsafe {
                device.cmd_bind_index_buffer(cmd, buffers.fallback_indices.raw, 0, vk::IndexType::UINT32);
                if counted {
                    device.cmd_draw_indexed_indirect_count(
                        cmd,
                        flat_draws,
                        offset,
                        flat_draws,
                        offset + u32_size,
                        1,
                        indexed_stride,
                    );
                } else {
                    device.cmd_draw_indexed_indirect(cmd, flat_draws, offset, 1, indexed_stride);
                }
                device.cmd_bind_index_buffer(cmd, rec.buffers.indices.raw, 0, vk::IndexType::UINT32);
            }
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
        mesh.stamp_part(DrawPart::Flat, false);
        if draw.shared_corners {
            shared_corners_draw(constants, lists.flat);
        } else {
            for pipeline in std::iter::once(lists.flat).chain(lists.flat_without_mixed) {
                flat_list_draw(constants, pipeline);
            }
        }
        mesh.stamp_part(DrawPart::Flat, true);
        mesh.part(DrawPart::Tessellated, || {
            for pipeline in std::iter::once(interpolated).chain(lists.interpolated_without_mixed) {
                tessellated_draw(constants, pipeline, INTERPOLATED_LIST, 0);
            }
        });
        // The per-pixel patches' depth first, then their shading where they are the nearest
        // surface: each covered pixel is shaded once, whatever the lists' order.
        mesh.part(DrawPart::FallbackDepth, || {
            tessellated_draw(constants, lists.fallback_prime, FALLBACK_LIST, FLAG_FALLBACK_PATCHES);
            fallback_flat_draw(constants, lists.flat_fallback_prime);
        });
        mesh.part(DrawPart::FallbackShading, || {
            tessellated_draw(constants, lists.fallback, FALLBACK_LIST, FLAG_FALLBACK_PATCHES);
            fallback_flat_draw(constants, lists.flat_fallback);
        });
        constants.flags &= !FLAG_FALLBACK_PATCHES;
    }

    /// After a two-sided mesh's patch lists, its back faces as `pixel` mode draws them: one
    /// indexed draw of the mesh, front faces culled, shaded per pixel. Drawn after every front
    /// face, they shade only where no front face hides them (the early depth test), in the
    /// mesh's order, with each vertex shaded once; the pre-pass lists only those beside a
    /// tessellated edge (glsl/patch_levels.comp), whose outer levels must match it and which
    /// this draw then finds at their own depth.
    fn record_back_faces(
        &self,
        rec: &Recorder<'_>,
        constants: &mut DrawConstants,
        draw: &DrawCall,
        pipeline: Option<vk::Pipeline>,
    ) {
        let Some(pipeline) = pipeline else {
            debug_assert!(false, "prepare_variants builds pixel mode's pipeline for the back faces");
            return;
        };
        let (device, cmd) = (rec.device, rec.cmd);
        constants.patch_base = draw.first_triangle;
        // SAFETY: `cmd` is recording inside the rendering `record_draws` began, with the scene's
        // vertex and index buffers bound; the pipeline is owned by `self` and was built with the
        // renderer's layout.
        unsafe {
            device.cmd_set_cull_mode(cmd, vk::CullModeFlags::FRONT);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        }
        rec.push(constants);
        // SAFETY: as above.
        unsafe { device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0) };
    }

    /// The polygonal lights' emissive geometry with `emitter` (nothing where the scene has
    /// none), after the meshes' draws (`constants` as they left them), stamped as the first
    /// mesh's `DrawPart::Emitters`.
    pub(super) fn record_emitters(
        &self,
        rec: &Recorder<'_>,
        mut constants: DrawConstants,
        emitter: Option<&Pipeline>,
        stamp: &dyn Fn(Timed, bool),
    ) {
        let Some(emitter) = emitter else { return };
        let timed = Timed::Draw { mesh: 0, part: DrawPart::Emitters };
        stamp(timed, false);
        let (device, cmd) = (rec.device, rec.cmd);
        // SAFETY: `cmd` is recording inside the rendering the meshes were drawn into; the pipeline
        // and the buffers it reads are owned by the renderer.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, emitter.raw);
            device.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
        }
        for draw in &self.emitters {
            constants.draw_argument = draw.light_index;
            rec.push(&constants);
            // SAFETY: as above; the fan lies in the bound index buffer.
            unsafe { device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0) };
        }
        stamp(timed, true);
    }

    /// How many patches one draw may hold when every patch is tessellated at `level`.
    pub(super) fn patches_per_draw(&self, level: u32) -> u32 {
        match self.vertex_budget {
            Some(budget) => (budget / uniform_vertex_count(level) as u32).max(1),
            None => u32::MAX,
        }
    }

    /// Patches per `Placement::Tcs` multirate draw: besides the vertex budget, lavapipe
    /// (Mesa 22.3) restarts `gl_PrimitiveID` in the control stage every 1020 control points (85
    /// patches of 12), which would scramble the triangle indices; other drivers get no limit.
    /// (`Placement::Compute` draws need no `gl_PrimitiveID`.)
    fn multirate_patches_per_draw(&self, n_max: u32) -> u32 {
        let patches = self.patches_per_draw(n_max);
        if self.vertex_budget.is_some() {
            patches.min(LAVAPIPE_PRIMITIVE_ID_CONTROL_POINTS / PATCH_SIZE as u32)
        } else {
            patches
        }
    }

    /// Patches per `fixed:N` draw: besides the vertex budget, where the evaluation stage
    /// passes triangle ids on (`gl_PrimitiveID`), lavapipe's restart (see
    /// `multirate_patches_per_draw`) limits a draw to 340 patches of 3.
    fn fixed_patches_per_draw(&self, level: u32, attachments: Attachments) -> u32 {
        let patches = self.patches_per_draw(level);
        if self.vertex_budget.is_some() && attachments == Attachments::ColorAndIds {
            patches.min(LAVAPIPE_PRIMITIVE_ID_CONTROL_POINTS / 3)
        } else {
            patches
        }
    }
}

// Lavapipe workarounds: the limits lavapipe's tessellation (Mesa 22.3) puts on one draw. Other
// drivers draw each mesh whole.

/// Lavapipe (Mesa 22.3) restarts `gl_PrimitiveID` in the tessellation stages every this many
/// control points within a draw: draws that read it there hold no more.
const LAVAPIPE_PRIMITIVE_ID_CONTROL_POINTS: u32 = 1020;

/// Lavapipe's draw module (Mesa 22.3) loses tessellated patches when one draw emits more than
/// about 2^16 vertices in one of its internal batches (measured: the 8192-patch plane renders
/// whole at fixed:15 and loses rows of patches from fixed:16 on). Splitting draws so that each
/// emits at most 65535 vertices avoids it; other drivers get no limit.
fn tessellated_vertex_budget(info: &crate::vk::context::DeviceInfo) -> Option<u32> {
    info.is_lavapipe().then_some(65535)
}

/// What this device's draws are split for, where that splitting exists only for lavapipe's
/// limits (None elsewhere): for the tools to print beside their timings.
pub fn draw_splitting_note(info: &crate::vk::context::DeviceInfo) -> Option<String> {
    tessellated_vertex_budget(info).map(|budget| {
        format!(
            "note: on lavapipe only, tessellated draws are split to emit at most {budget} vertices each \
             (Mesa 22.3 loses patches past about 2^16), and `--estimator tcs` multirate draws to 85 \
             patches (it restarts gl_PrimitiveID every 1020 control points); other devices draw \
             each mesh whole"
        )
    })
}

/// One mesh's draw in a frame: the view it is drawn with and the attachments.
struct MeshDraw<'a> {
    draw: &'a DrawCall,
    view: &'a View,
    frame: &'a FrameConfig,
    attachments: Attachments,
    stamp: &'a dyn Fn(Timed, bool),
}

impl MeshDraw<'_> {
    /// Stamps the start (`end == false`) or end of `part` of this mesh's draws.
    fn stamp_part(&self, part: DrawPart, end: bool) {
        (self.stamp)(Timed::Draw { mesh: self.draw.mesh_index, part }, end);
    }

    /// Records `part` of this mesh's draws with `record`, stamped before and after.
    fn part(&self, part: DrawPart, record: impl FnOnce()) {
        self.stamp_part(part, false);
        record();
        self.stamp_part(part, true);
    }
}

/// What the draws of a mesh's patch lists read: the pre-pass's lists, whether their draws are
/// counted, and the most patches one of them holds.
struct PatchDraws<'a> {
    lists: PatchLists<'a>,
    counts: IndirectCounts,
    per_draw: u32,
}
