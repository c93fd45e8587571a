//! The shadow atlas: every shadow map of the scene in one depth image (`geometry::shadow_view`
//! lays the maps out), drawn when the renderer is made (lights and meshes do not move) and a
//! directional light's map again where the view it is fitted to changes (`shadow_state`); read
//! by `glsl/include/shadow.glsl` through set 1, and the drawn maps' depths read back for the
//! triangles' visibility classes (`geometry::shadow_class`).

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

/// What [`ShadowAtlas::draw`] gives back: per map it drew, its index in the layout and its
/// texels read back (its footprint in the atlas, row by row), and the GPU time the maps took.
pub(super) struct ShadowPass {
    pub maps: Vec<(usize, Vec<f32>)>,
    pub milliseconds: Option<f64>,
}

/// What the atlas held before a draw.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum AtlasBefore {
    /// Nothing yet: the whole atlas is cleared.
    Nothing,
    /// Maps the shaders read: only the squares drawn again are cleared, the others kept.
    Maps,
}

/// The atlas image, in `SHADER_READ_ONLY_OPTIMAL` once [`ShadowAtlas::draw`] ran, and the
/// sampler set 1 reads it with.
pub(super) struct ShadowAtlas {
    pub image: Image,
    pub sampler: Sampler,
}

/// The depth-only pipeline that draws every mesh into a map with `vertex` (`forward.vert`), both
/// faces; none where `layout` has no map.
pub(super) fn shadow_pipeline(
    context: &Arc<Context>,
    layout: &ShadowLayout,
    (pipeline_layout, vertex): (&PipelineLayout, &ShaderModule),
) -> Result<Option<Pipeline>> {
    if layout.maps.is_empty() {
        return Ok(None);
    }
    let stages = vec![Stage { stage: vk::ShaderStageFlags::VERTEX, module: vertex, specialization: None }];
    let mut desc = scene_pipeline("shadow map", stages, pipeline_layout, Instrumentation::None);
    desc.color_formats = &[];
    desc.depth_use = DepthUse::Prime;
    desc.dynamic_cull_mode = false;
    desc.cull_mode = vk::CullModeFlags::NONE;
    desc.optimization = Optimization::Optimized;
    Ok(Some(Pipeline::graphics(context, &desc)?))
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

    /// Draws every mesh of `draws` with `pipeline` ([`shadow_pipeline`]) into each square of
    /// the maps `drawn` (indices into `layout.maps`), cleared to the far plane first (the whole atlas where it held
    /// `AtlasBefore::Nothing`); leaves the atlas ready for the shaders to read and returns the
    /// drawn maps' depths and the time they took. Without a map it only clears and returns
    /// neither. The caller makes sure no submitted work reads the atlas.
    pub(super) fn draw(
        &self,
        context: &Arc<Context>,
        (pipeline_layout, pipeline): (&PipelineLayout, Option<&Pipeline>),
        buffers: &SceneBuffers,
        (layout, drawn): (&ShadowLayout, &[usize]),
        draws: &[DrawCall],
        before: AtlasBefore,
    ) -> Result<ShadowPass> {
        let device = &context.device;
        let atlas = self.image.raw;
        let pipeline = pipeline.filter(|_| !drawn.is_empty());
        let footprints: Vec<(usize, [u32; 2])> =
            drawn.iter().map(|&m| (m, layout.maps[m].footprint())).collect();
        let texels: usize = footprints.iter().map(|(_, [w, h])| *w as usize * *h as usize).sum();
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
        let timer = pipeline.map(|_| GpuTimer::new(context, 1, 1)).transpose()?;
        let sampled = (
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::PipelineStageFlags2::ALL_GRAPHICS | vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
        );
        context.run_once(|cmd| {
            let depth = vk::ImageAspectFlags::DEPTH;
            if let Some(timer) = &timer {
                timer.reset(cmd, 0);
                timer.timestamp(cmd, 0, 0, false);
            }
            let (from, load) = match before {
                AtlasBefore::Nothing => (
                    (vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                    vk::AttachmentLoadOp::CLEAR,
                ),
                AtlasBefore::Maps => (sampled, vk::AttachmentLoadOp::LOAD),
            };
            transition(
                device,
                cmd,
                atlas,
                depth,
                from,
                (
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                    vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                        | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
                ),
            );
            let far = vk::ClearValue { depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 } };
            let attachment = vk::RenderingAttachmentInfo::default()
                .image_view(self.image.view)
                .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                .load_op(load)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(far);
            begin_rendering(
                device,
                cmd,
                self.image.extent,
                vk::RenderingInfo::default().depth_attachment(&attachment),
            );
            if let Some(pipeline) = pipeline {
                let clear = (before == AtlasBefore::Maps).then_some(far);
                record_squares(
                    device,
                    cmd,
                    (pipeline_layout, pipeline),
                    buffers,
                    (layout, drawn),
                    draws,
                    clear,
                );
            }
            // SAFETY: `cmd` is recording inside the rendering begun above.
            unsafe { device.cmd_end_rendering(cmd) };
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
                copy_to_host(device, cmd, atlas, layout, drawn, readback);
                copied
            } else {
                attachment_written
            };
            transition(device, cmd, atlas, depth, before_shaders, sampled);
        })?;
        let milliseconds = timer.map(|t| t.pass_intervals(0, 1).map(|i| i[0].milliseconds())).transpose()?;
        let mut maps = Vec::new();
        if let Some(readback) = readback {
            let bytes = readback.mapped().expect("GpuToCpu memory is mapped");
            let mut at = 0;
            for (m, [w, h]) in footprints {
                let count = w as usize * h as usize;
                maps.push((m, bytemuck::pod_collect_to_vec::<u8, f32>(&bytes[4 * at..4 * (at + count)])));
                at += count;
            }
        }
        Ok(ShadowPass { maps, milliseconds })
    }
}

/// Records, inside a rendering of the atlas, the clear of the footprints of `layout`'s maps
/// `drawn` to `clear` (where given) and every mesh of `draws` drawn with `pipeline` into each of
/// their squares.
fn record_squares(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    (pipeline_layout, pipeline): (&PipelineLayout, &Pipeline),
    buffers: &SceneBuffers,
    (layout, drawn): (&ShadowLayout, &[usize]),
    draws: &[DrawCall],
    clear: Option<vk::ClearValue>,
) {
    // SAFETY: `cmd` is recording inside a rendering of the atlas; the pipeline, the buffers and
    // the layout outlive the wait the caller's `run_once` ends with.
    unsafe {
        if let Some(far) = clear {
            let rects: Vec<vk::ClearRect> = drawn
                .iter()
                .map(|&m| vk::ClearRect {
                    rect: footprint_rect(layout, m),
                    base_array_layer: 0,
                    layer_count: 1,
                })
                .collect();
            let clear = [vk::ClearAttachment {
                aspect_mask: vk::ImageAspectFlags::DEPTH,
                color_attachment: 0,
                clear_value: far,
            }];
            device.cmd_clear_attachments(cmd, &clear, &rects);
        }
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
        device.cmd_bind_vertex_buffers(cmd, 0, &[buffers.vertices.raw], &[0]);
        device.cmd_bind_index_buffer(cmd, buffers.indices.raw, 0, vk::IndexType::UINT32);
        let squares = drawn.iter().map(|&m| &layout.maps[m]);
        for (view_proj, [x, y], size) in
            squares.flat_map(|m| m.views().into_iter().map(|(v, at)| (v, at, m.size)))
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
}

/// Map `map`'s footprint in the atlas.
fn footprint_rect(layout: &ShadowLayout, map: usize) -> vk::Rect2D {
    let record = &layout.maps[map];
    let [width, height] = record.footprint();
    vk::Rect2D {
        offset: vk::Offset2D { x: record.offset[0] as i32, y: record.offset[1] as i32 },
        extent: vk::Extent2D { width, height },
    }
}

/// Records the copy of the footprints of `layout`'s maps `drawn` in the depth image `atlas` (in
/// TRANSFER_SRC_OPTIMAL) into `readback`, one after the other, each tightly packed, and makes
/// them visible to the host.
fn copy_to_host(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    atlas: vk::Image,
    layout: &ShadowLayout,
    drawn: &[usize],
    readback: &Buffer,
) {
    let mut offset = 0;
    let regions: Vec<vk::BufferImageCopy> = drawn
        .iter()
        .map(|&m| {
            let rect = footprint_rect(layout, m);
            let region = vk::BufferImageCopy::default()
                .buffer_offset(offset)
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(vk::ImageAspectFlags::DEPTH)
                        .layer_count(1),
                )
                .image_offset(vk::Offset3D { x: rect.offset.x, y: rect.offset.y, z: 0 })
                .image_extent(vk::Extent3D {
                    width: rect.extent.width,
                    height: rect.extent.height,
                    depth: 1,
                });
            offset += 4 * u64::from(rect.extent.width) * u64::from(rect.extent.height);
            region
        })
        .collect();
    let to_host = [vk::MemoryBarrier2::default()
        .src_stage_mask(vk::PipelineStageFlags2::COPY)
        .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
        .dst_stage_mask(vk::PipelineStageFlags2::HOST)
        .dst_access_mask(vk::AccessFlags2::HOST_READ)];
    // SAFETY: `cmd` is recording; the atlas is in TRANSFER_SRC_OPTIMAL and the buffer holds the
    // footprints' texels tightly packed, 4 bytes each (D32); the caller waits for the copy
    // before reading.
    unsafe {
        device.cmd_copy_image_to_buffer(
            cmd,
            atlas,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            readback.raw,
            &regions,
        );
        device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&to_host));
    }
}
