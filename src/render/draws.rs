//! The forward draws: one [`DrawCall`] per mesh and one [`EmitterDraw`] per polygonal light,
//! their push constants, and how a draw is split into chunks where lavapipe needs it (the
//! lavapipe workarounds at the end of this file).

use super::mode::{Mode, MAX_LEVEL};
use super::pipelines::MeshPipelines;
use super::view::View;
use super::Renderer;
use crate::analysis::tessellator::uniform_vertex_count;
use crate::geometry::camera;
use crate::gpu_interface::flags::{
    FLAG_DERIVATIVE_CHECK, FLAG_HEAT_MAP, FLAG_ONE_SIDED, FLAG_SHARED_CORNERS,
};
use crate::gpu_types::DrawConstants;
use crate::scene::adjacency::PATCH_SIZE;
use crate::vk::target::{AfterPass, Attachments, RenderTarget};
use ash::vk;
use glam::Vec2;

/// One mesh's draw: where its triangles lie in the scene's buffers and what it is drawn with.
pub(super) struct DrawCall {
    /// Index of the mesh's first triangle in the scene.
    pub first_triangle: u32,
    pub first_index: u32,
    pub index_count: u32,
    /// Where this mesh's 12-index adjacency patches start in the patch index buffer.
    pub first_patch_index: u32,
    /// Back faces are culled (`Mesh::two_sided` false).
    pub one_sided: bool,
    /// Its material has no parameter map, so a flat patch's corner shades the same in every
    /// triangle that shares it: the compute placement draws those patches indexed, from
    /// `PrePassBuffers::flat_indices`.
    pub shared_corners: bool,
    pub material_index: u32,
    pub mesh_index: u32,
    /// The variant of its material kind (index into the renderer's variants).
    pub pipeline: usize,
}

/// What `Renderer::record_draws` draws with.
pub(super) struct Draws<'a> {
    /// The pipelines of a mesh drawn as the given view says (None: not prepared).
    pub pick: &'a dyn Fn(&DrawCall, &View) -> Option<MeshPipelines>,
    /// Per draw, whether a multirate view draws the mesh whole as `pixel` mode does
    /// (`Renderer::meshes_drawn_per_pixel`; missing entries: no).
    pub per_pixel: &'a [bool],
    /// Whether the polygonal lights' emissive geometry is drawn too.
    pub emitters: bool,
    /// The colour the target is cleared to.
    pub clear: [f32; 4],
}

/// The emissive geometry of one polygonal light: a triangle fan in the scene's buffers.
pub(super) struct EmitterDraw {
    pub first_index: u32,
    pub index_count: u32,
    pub light_index: u32,
}

/// The push constants of `view` on a target of `extent` (per draw: material, mesh, first
/// triangle), `min_estimated_area` from the cost model or the view (`Renderer::min_estimated_area`).
pub(super) fn draw_constants(view: &View, extent: vk::Extent2D, min_estimated_area: f32) -> DrawConstants {
    let estimator = &view.estimator;
    DrawConstants {
        view_proj: camera::view_projection(&view.camera, extent.width, extent.height),
        eye: view.camera.eye,
        min_estimated_area,
        viewport_size: Vec2::new(extent.width as f32, extent.height as f32),
        epsilon: estimator.epsilon,
        // The shaders' range (their estimator, patch levels and heat map read it in it).
        n_max: estimator.n_max.clamp(1, MAX_LEVEL),
        level_or_light: match view.mode {
            Mode::Fixed(level) => level,
            _ => 1,
        },
        flags: if view.heat_map { FLAG_HEAT_MAP } else { 0 }
            | if view.derivative_check { FLAG_DERIVATIVE_CHECK } else { 0 },
        eye_radius: estimator.eye_radius,
        ..Default::default()
    }
}

impl Renderer {
    /// The per-mesh fields of the push constants.
    pub(super) fn set_draw_constants(&self, constants: &mut DrawConstants, draw: &DrawCall) {
        constants.material_index = draw.material_index;
        constants.mesh_index = draw.mesh_index;
        let mesh_flags = FLAG_ONE_SIDED | FLAG_SHARED_CORNERS;
        constants.flags = (constants.flags & !mesh_flags)
            | if draw.one_sided { FLAG_ONE_SIDED } else { 0 }
            | if draw.shared_corners { FLAG_SHARED_CORNERS } else { 0 };
    }

    /// The forward draws of every mesh with the pipelines `draws.pick` gives, into `target`'s
    /// `attachments`, and where `draws.emitters` the polygonal lights' emissive geometry.
    pub(super) fn record_draws(
        &self,
        draws: &Draws<'_>,
        cmd: vk::CommandBuffer,
        target: &RenderTarget,
        attachments: Attachments,
        view: &View,
        after: AfterPass,
    ) {
        let device = &self.context.device;
        let extent = target.extent();
        target.begin(device, cmd, draws.clear, attachments);
        let mut constants = draw_constants(view, extent, self.min_estimated_area(view));
        // SAFETY: `cmd` is recording inside the rendering begun above; every bound object is
        // owned by `self` and outlives the submission (callers wait before dropping).
        unsafe {
            device.cmd_bind_vertex_buffers(cmd, 0, &[self.buffers.vertices.raw], &[0]);
            device.cmd_bind_index_buffer(cmd, self.buffers.indices.raw, 0, vk::IndexType::UINT32);
        }
        self.bind_set(cmd, 0, self.descriptors.set);
        let pixel_view = View { mode: Mode::Pixel, ..view.clone() };
        for (index, draw) in self.draws.iter().enumerate() {
            let mesh_view = if draws.per_pixel.get(index) == Some(&true) { &pixel_view } else { view };
            self.set_draw_constants(&mut constants, draw);
            let Some(pipelines) = (draws.pick)(draw, mesh_view) else {
                debug_assert!(false, "render, measure and the viewer prepare the view first");
                continue;
            };
            self.record_mesh(cmd, draw, pipelines, &mut constants, mesh_view, attachments);
        }
        if draws.emitters {
            self.record_emitters(cmd, &mut constants, attachments);
        }
        target.end(device, cmd, after, attachments);
    }

    /// The draws of one mesh with `pipelines`: the pre-pass's patch lists where they have
    /// them, otherwise the mesh's triangles (or `Placement::Tcs` adjacency patches) in chunks
    /// of at most the patches one draw may hold.
    fn record_mesh(
        &self,
        cmd: vk::CommandBuffer,
        draw: &DrawCall,
        pipelines: MeshPipelines,
        constants: &mut DrawConstants,
        view: &View,
        attachments: Attachments,
    ) {
        let device = &self.context.device;
        let cull = if draw.one_sided { vk::CullModeFlags::BACK } else { vk::CullModeFlags::NONE };
        // SAFETY: `cmd` is recording inside the rendering `record_draws` began.
        unsafe { device.cmd_set_cull_mode(cmd, cull) };
        self.bind_set(cmd, 1, self.descriptors.textures.sets[draw.material_index as usize]);
        if let Some(lists) = pipelines.lists {
            self.record_patch_lists(cmd, constants, draw, view, pipelines.first, lists);
            if !draw.one_sided {
                self.record_back_faces(cmd, constants, draw, pipelines.back_faces);
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
                self.multirate_patches_per_draw(view.estimator.n_max),
                PATCH_SIZE as u32,
            ),
        };
        let chunk = patches.saturating_mul(indices_per_primitive);
        // SAFETY: as above; the index buffers have INDEX_BUFFER usage and the pipeline was
        // built with the renderer's layout.
        unsafe {
            if adjacency {
                device.cmd_bind_index_buffer(cmd, self.buffers.patch_indices.raw, 0, vk::IndexType::UINT32);
            }
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipelines.first);
            let mut first = 0;
            while first < index_count {
                let count = chunk.min(index_count - first);
                constants.patch_base = draw.first_triangle + first / indices_per_primitive;
                self.push_draw_constants(cmd, constants);
                device.cmd_draw_indexed(cmd, count, 1, first_index + first, 0, 0);
                first += count;
            }
            if adjacency {
                device.cmd_bind_index_buffer(cmd, self.buffers.indices.raw, 0, vk::IndexType::UINT32);
            }
        }
    }

    /// After a two-sided mesh's patch lists, its back faces as `pixel` mode draws them: one
    /// indexed draw of the mesh, front faces culled, shaded per pixel. Drawn after every front
    /// face, they shade only where no front face hides them (the early depth test), in the
    /// mesh's order, with each vertex shaded once; the pre-pass lists only those beside a
    /// tessellated edge (glsl/patch_levels.comp), whose outer levels must match it and which
    /// this draw then finds at their own depth.
    fn record_back_faces(
        &self,
        cmd: vk::CommandBuffer,
        constants: &mut DrawConstants,
        draw: &DrawCall,
        pipeline: Option<vk::Pipeline>,
    ) {
        let Some(pipeline) = pipeline else {
            debug_assert!(false, "prepare_variants builds pixel mode's pipeline for the back faces");
            return;
        };
        let device = &self.context.device;
        constants.patch_base = draw.first_triangle;
        // SAFETY: `cmd` is recording inside the rendering `record_draws` began, with the scene's
        // vertex and index buffers bound; the pipeline is owned by `self` and was built with the
        // renderer's layout.
        unsafe {
            device.cmd_set_cull_mode(cmd, vk::CullModeFlags::FRONT);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
            self.push_draw_constants(cmd, constants);
            device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0);
        }
    }

    /// The polygonal lights' emissive geometry, with the emitter pipeline of `attachments`
    /// (nothing where the scene has none).
    fn record_emitters(
        &self,
        cmd: vk::CommandBuffer,
        constants: &mut DrawConstants,
        attachments: Attachments,
    ) {
        let device = &self.context.device;
        let emitter = match attachments {
            Attachments::Color => self.pipelines.emitter.as_ref(),
            Attachments::ColorAndIds => self.pipelines.analysis_emitter.get(),
        };
        let Some(emitter) = emitter else { return };
        // SAFETY: `cmd` is recording inside the rendering `record_draws` began; the pipeline
        // and the buffers it reads are owned by `self`.
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, emitter.raw);
            device.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
            for draw in &self.emitters {
                constants.level_or_light = draw.light_index;
                self.push_draw_constants(cmd, constants);
                device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0);
            }
        }
    }

    /// How many patches one draw may hold when every patch is tessellated at `level`.
    pub(super) fn patches_per_draw(&self, level: u32) -> u32 {
        match self.tessellated_vertex_budget {
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
        if self.tessellated_vertex_budget.is_some() {
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
        if self.tessellated_vertex_budget.is_some() && attachments == Attachments::ColorAndIds {
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
pub(super) fn tessellated_vertex_budget(info: &crate::vk::context::DeviceInfo) -> Option<u32> {
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
