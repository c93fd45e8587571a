//! The shadow atlas: every shadow map of the scene in one depth image (`geometry::shadow_view`
//! lays the maps out), rendered once when the renderer is made, as
//! lights and meshes do not move, and read by `glsl/include/shadow.glsl` through set 1; its
//! depths read back for the triangles' visibility classes (`geometry::shadow_class`).

use super::descriptors::PUSH_STAGES;
use super::pipelines::{scene_pipeline, Instrumentation};
use super::scene_buffers::SceneBuffers;
use super::scene_geometry::DrawCall;
use crate::error::Result;
use crate::geometry::shadow_view::ShadowLayout;
use crate::gpu_types::DrawConstants;
use crate::vk::memory::{transition, Buffer, Image};
use crate::vk::pipeline::{DepthUse, Optimization, Pipeline, PipelineLayout, ShaderModule, Stage};
use crate::vk::target::{begin_rendering, DEPTH_FORMAT};
use crate::vk::texture::Sampler;
use crate::vk::timing::GpuTimer;
use crate::vk::Context;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// What [`ShadowAtlas::render`] gives back: the atlas's depths, read back row by row, and the
/// GPU time its maps took to draw (both none without a map).
pub(super) struct ShadowPass {
    pub depths: Vec<f32>,
    pub milliseconds: Option<f64>,
}

/// The atlas image, in `SHADER_READ_ONLY_OPTIMAL` once [`ShadowAtlas::render`] ran, and the
/// sampler set 1 reads it with.
pub(super) struct ShadowAtlas {
    pub image: Image,
    pub sampler: Sampler,
}

impl ShadowAtlas {
    /// The atlas of `layout` (1 × 1 where no light casts shadows: set 1 binds it all the same).
    pub(super) fn new(context: &Arc<Context>, layout: &ShadowLayout) -> Result<ShadowAtlas> {
        let [width, height] = layout.extent;
        let image = Image::new(
            context,
            "shadow atlas",
            vk::Extent2D { width, height },
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::DEPTH,
        )?;
        let sampler = Sampler::nearest_clamp(context, "shadow atlas sampler")?;
        Ok(ShadowAtlas { image, sampler })
    }

    /// Clears the atlas to the far plane and draws every mesh of `draws` into each square of
    /// `layout`'s maps with `vertex` (`forward.vert`), depth only, both faces; leaves the atlas
    /// ready for the shaders to read and returns its depths row by row and the time the maps
    /// took. Without a map it only clears (no pipeline is built) and returns neither.
    pub(super) fn render(
        &self,
        context: &Arc<Context>,
        (pipeline_layout, vertex): (&PipelineLayout, &ShaderModule),
        buffers: &SceneBuffers,
        layout: &ShadowLayout,
        draws: &[DrawCall],
    ) -> Result<ShadowPass> {
        let pipeline = if layout.maps.is_empty() {
            None
        } else {
            let stages =
                vec![Stage { stage: vk::ShaderStageFlags::VERTEX, module: vertex, specialization: None }];
            let mut desc = scene_pipeline("shadow map", stages, pipeline_layout, Instrumentation::None);
            desc.color_formats = &[];
            desc.depth_use = DepthUse::Prime;
            desc.dynamic_cull_mode = false;
            desc.cull_mode = vk::CullModeFlags::NONE;
            desc.optimization = Optimization::Optimized;
            Some(Pipeline::graphics(context, &desc)?)
        };
        let device = &context.device;
        let atlas = self.image.raw;
        let extent = self.image.extent;
        let texels = extent.width as usize * extent.height as usize;
        let readback = match pipeline {
            Some(_) => Some(Buffer::new(
                context,
                "shadow atlas readback",
                4 * texels as vk::DeviceSize,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?),
            None => None,
        };
        let timer = pipeline.as_ref().map(|_| GpuTimer::new(context, 1, 1)).transpose()?;
        context.run_once(|cmd| {
            let depth = vk::ImageAspectFlags::DEPTH;
            if let Some(timer) = &timer {
                timer.reset(cmd, 0);
                timer.timestamp(cmd, 0, 0, false);
            }
            transition(
                device,
                cmd,
                atlas,
                depth,
                (vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                (
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                    vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                        | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
                ),
            );
            let attachment = vk::RenderingAttachmentInfo::default()
                .image_view(self.image.view)
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(vk::AttachmentLoadOp::CLEAR)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue {
                    depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
                });
            begin_rendering(
                device,
                cmd,
                self.image.extent,
                vk::RenderingInfo::default().depth_attachment(&attachment),
            );
            // SAFETY: `cmd` is recording inside the rendering begun above; the pipeline, the
            // buffers and the layout outlive the wait `run_once` ends with.
            unsafe {
                if let Some(pipeline) = &pipeline {
                    device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
                    device.cmd_bind_vertex_buffers(cmd, 0, &[buffers.vertices.raw], &[0]);
                    device.cmd_bind_index_buffer(cmd, buffers.indices.raw, 0, vk::IndexType::UINT32);
                    for (view_proj, [x, y], size) in
                        layout.maps.iter().flat_map(|m| m.views().into_iter().map(|(v, at)| (v, at, m.size)))
                    {
                        let area = vk::Rect2D {
                            offset: vk::Offset2D { x: x as i32, y: y as i32 },
                            extent: vk::Extent2D { width: size, height: size },
                        };
                        let viewport = vk::Viewport {
                            x: x as f32,
                            y: y as f32,
                            width: size as f32,
                            height: size as f32,
                            min_depth: 0.0,
                            max_depth: 1.0,
                        };
                        device.cmd_set_viewport(cmd, 0, &[viewport]);
                        device.cmd_set_scissor(cmd, 0, &[area]);
                        let constants = DrawConstants { view_proj, ..Default::default() };
                        device.cmd_push_constants(
                            cmd,
                            pipeline_layout.raw,
                            PUSH_STAGES,
                            0,
                            bytemuck::bytes_of(&constants),
                        );
                        for draw in draws {
                            device.cmd_draw_indexed(cmd, draw.index_count, 1, draw.first_index, 0, 0);
                        }
                    }
                }
                device.cmd_end_rendering(cmd);
            }
            if let Some(timer) = &timer {
                timer.timestamp(cmd, 0, 0, true);
            }
            let attachment_written = (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            );
            let copied = (
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_READ,
            );
            let before_shaders = if let Some(readback) = &readback {
                transition(device, cmd, atlas, depth, attachment_written, copied);
                copy_to_host(device, cmd, atlas, extent, readback);
                copied
            } else {
                attachment_written
            };
            transition(
                device,
                cmd,
                atlas,
                depth,
                before_shaders,
                (
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    vk::PipelineStageFlags2::ALL_GRAPHICS | vk::PipelineStageFlags2::COMPUTE_SHADER,
                    vk::AccessFlags2::SHADER_SAMPLED_READ,
                ),
            );
        })?;
        let milliseconds = timer.map(|t| t.pass_intervals(0, 1).map(|i| i[0].milliseconds())).transpose()?;
        let depths = readback.map_or_else(Vec::new, |readback| {
            let bytes = readback.mapped().expect("GpuToCpu memory is mapped");
            bytemuck::pod_collect_to_vec::<u8, f32>(&bytes[..4 * texels])
        });
        Ok(ShadowPass { depths, milliseconds })
    }
}

/// Records the copy of the depth image `atlas` of `extent` (in TRANSFER_SRC_OPTIMAL) into
/// `readback`, tightly packed, and makes it visible to the host.
fn copy_to_host(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    atlas: vk::Image,
    extent: vk::Extent2D,
    readback: &Buffer,
) {
    let region = [vk::BufferImageCopy::default()
        .image_subresource(
            vk::ImageSubresourceLayers::default().aspect_mask(vk::ImageAspectFlags::DEPTH).layer_count(1),
        )
        .image_extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })];
    let to_host = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::COPY)
        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)];
    // SAFETY: `cmd` is recording; the atlas is in TRANSFER_SRC_OPTIMAL and the buffer holds its
    // texels tightly packed, 4 bytes each (D32); the caller waits for the copy before reading.
    unsafe {
        device.cmd_copy_image_to_buffer(
            cmd,
            atlas,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            readback.raw,
            &region,
        );
        device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host));
    }
}
