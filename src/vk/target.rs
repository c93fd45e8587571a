//! Offscreen render targets: a linear float colour image (alpha = coverage), a triangle-id
//! image that the analysis pipelines write beside it, and a depth image, with
//! dynamic-rendering begin/end helpers and a readback into host memory.

use super::context::Context;
use super::memory::{transition, Buffer, Image};
use crate::error::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::cell::OnceCell;
use std::sync::Arc;

pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// Colour attachment 1 of the analysis pipelines: per pixel the id of the triangle it shows
/// (`glsl/include/triangle_id.glsl`; 0: nothing).
pub const ID_FORMAT: vk::Format = vk::Format::R32_UINT;

/// The id a pixel holds where a polygonal light's emitter is drawn: this bit with the light's
/// index (scene triangles hold their scene index + 1, below it).
pub const EMITTER_ID_BIT: u32 = 0x8000_0000;

/// A float RGBA image in host memory, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct FloatImage {
    pub width: u32,
    pub height: u32,
    pub pixels: Vec<[f32; 4]>,
}

impl FloatImage {
    pub fn pixel(&self, x: u32, y: u32) -> [f32; 4] {
        self.pixels[(y * self.width + x) as usize]
    }
}

/// Begins dynamic rendering with `rendering`'s attachments over the whole of `extent` (one
/// layer) and sets the matching viewport and scissor. The attachments must be in the layouts
/// they name.
pub fn begin_rendering(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    extent: vk::Extent2D,
    rendering: vk::RenderingInfo<'_>,
) {
    let area = vk::Rect2D { offset: vk::Offset2D::default(), extent };
    let viewport = [vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: extent.width as f32,
        height: extent.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    }];
    // SAFETY: `cmd` is recording outside a render pass; the caller keeps the attachments in
    // the layouts `rendering` names.
    unsafe {
        device.cmd_begin_rendering(cmd, &rendering.render_area(area).layer_count(1));
        device.cmd_set_viewport(cmd, 0, &viewport);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// What the colour image is used for after a pass.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AfterPass {
    /// Copied to the host.
    Readback,
    /// Sampled by a later pass (for example the window's tone mapping).
    Sampled,
}

/// What becomes of the depth attachment when a rendering ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DepthAfter {
    /// Discarded: nothing reads it after the pass.
    Discarded,
    /// Stored: the rendering is paused and resumed ([`RenderTarget::pause`]).
    Kept,
}

/// Which attachments a pass draws into.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Attachments {
    /// Colour and depth: every timed pass.
    Color,
    /// Colour, triangle ids and depth: the analysis pipelines.
    ColorAndIds,
}

/// Colour, triangle-id and depth attachments of one size. The id image is created by the
/// first pass that draws ids ([`RenderTarget::prepare_ids`]): timed, viewer and
/// visibility-buffer targets never hold one.
pub struct RenderTarget {
    pub color: Image,
    ids: OnceCell<Image>,
    pub depth: Image,
}

impl RenderTarget {
    pub fn new(context: &Arc<Context>, extent: vk::Extent2D) -> Result<RenderTarget> {
        let color = Image::new(
            context,
            "render target colour",
            extent,
            COLOR_FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::SAMPLED,
            vk::ImageAspectFlags::COLOR,
        )?;
        let depth = Image::new(
            context,
            "render target depth",
            extent,
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
        )?;
        Ok(RenderTarget { color, ids: OnceCell::new(), depth })
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.color.extent
    }

    /// Creates the triangle-id image (once); `Attachments::ColorAndIds` needs it.
    pub fn prepare_ids(&self, context: &Arc<Context>) -> Result<()> {
        if self.ids.get().is_none() {
            let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
            let name = "render target triangle ids";
            let ids =
                Image::new(context, name, self.extent(), ID_FORMAT, usage, vk::ImageAspectFlags::COLOR)?;
            let _ = self.ids.set(ids);
        }
        Ok(())
    }

    /// The id image; `prepare_ids` must have run.
    fn ids(&self) -> &Image {
        self.ids.get().expect("passes that draw ids prepare the id image first")
    }

    /// The colour images `attachments` draws into, in location order.
    fn color_images(&self, attachments: Attachments) -> ([&Image; 2], usize) {
        match attachments {
            Attachments::Color => ([&self.color; 2], 1),
            Attachments::ColorAndIds => ([&self.color, self.ids()], 2),
        }
    }

    /// Transitions the attachments (contents discarded) and begins dynamic rendering with a
    /// clear to `clear` (alpha 0 = no coverage), ids 0 and depth 1; the depth is stored where
    /// `depth` says so (a rendering [`RenderTarget::pause`]d and resumed needs it).
    pub fn begin(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        clear: [f32; 4],
        attachments: Attachments,
        depth: DepthAfter,
    ) {
        let (images, count) = self.color_images(attachments);
        let images = &images[..count];
        for image in images {
            transition(
                device,
                cmd,
                image.raw,
                vk::ImageAspectFlags::COLOR,
                (vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::ALL_COMMANDS, vk::AccessFlags2::NONE),
                (
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
            );
        }
        transition(
            device,
            cmd,
            self.depth.raw,
            vk::ImageAspectFlags::DEPTH,
            // The previous frame's depth writes must finish before these clear it again.
            (
                vk::ImageLayout::UNDEFINED,
                vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
            ),
            (
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                    | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
            ),
        );
        self.begin_rendering_into(device, cmd, attachments, Some((clear, depth)));
    }

    /// Ends the rendering `begin` began with [`DepthAfter::Kept`], keeping what it drew, so that
    /// commands outside a rendering may follow (a timestamp, which lavapipe takes only there);
    /// [`RenderTarget::resume`] goes on with it.
    pub fn pause(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        // SAFETY: rendering was begun by `begin` or `resume` on this command buffer.
        unsafe { device.cmd_end_rendering(cmd) };
    }

    /// Begins rendering again into what [`RenderTarget::pause`] left, every attachment loaded
    /// and stored, once the earlier rendering's attachment writes are done.
    pub fn resume(&self, device: &ash::Device, cmd: vk::CommandBuffer, attachments: Attachments) {
        let color = vk::AccessFlags2::COLOR_ATTACHMENT_WRITE | vk::AccessFlags2::COLOR_ATTACHMENT_READ;
        let depth = vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ;
        let tests =
            vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        let barriers = [
            vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)
                .src_access_mask(vk::AccessFlags2::COLOR_ATTACHMENT_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT)
                .dst_access_mask(color),
            vk::MemoryBarrier2::default()
                .src_stage_mask(tests)
                .src_access_mask(vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE)
                .dst_stage_mask(tests)
                .dst_access_mask(depth),
        ];
        // SAFETY: `cmd` is recording outside a rendering (`pause` ended it).
        unsafe {
            device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barriers))
        };
        self.begin_rendering_into(device, cmd, attachments, None);
    }

    /// Begins dynamic rendering into `attachments`: cleared (to `clear`'s colour, ids 0 and depth
    /// 1, the depth stored where its `DepthAfter` says so), or with `None` loaded as an earlier
    /// rendering left them and stored.
    fn begin_rendering_into(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        attachments: Attachments,
        clear: Option<([f32; 4], DepthAfter)>,
    ) {
        let (images, count) = self.color_images(attachments);
        let load = if clear.is_some() { vk::AttachmentLoadOp::CLEAR } else { vk::AttachmentLoadOp::LOAD };
        let colour = clear.map_or([0.0; 4], |(colour, _)| colour);
        let clears = [vk::ClearColorValue { float32: colour }, vk::ClearColorValue { uint32: [0; 4] }];
        let color_attachments = [0, 1].map(|k| {
            vk::RenderingAttachmentInfo::default()
                .image_view(images[..count].get(k).map_or(vk::ImageView::null(), |image| image.view))
                .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                .load_op(load)
                .store_op(vk::AttachmentStoreOp::STORE)
                .clear_value(vk::ClearValue { color: clears[k] })
        });
        let depth_store = match clear {
            Some((_, DepthAfter::Discarded)) => vk::AttachmentStoreOp::DONT_CARE,
            _ => vk::AttachmentStoreOp::STORE,
        };
        let depth_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(self.depth.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(load)
            .store_op(depth_store)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
            });
        let rendering = vk::RenderingInfo::default()
            .color_attachments(&color_attachments[..count])
            .depth_attachment(&depth_attachment);
        begin_rendering(device, cmd, self.extent(), rendering);
    }

    /// Ends dynamic rendering and makes the colour image ready for `after`; the id image, when
    /// drawn, is made ready to be copied to the host.
    pub fn end(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        after: AfterPass,
        attachments: Attachments,
    ) {
        // SAFETY: rendering was begun by `begin` on this command buffer.
        unsafe { device.cmd_end_rendering(cmd) };
        let readback = (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
        );
        let next = match after {
            AfterPass::Readback => readback,
            AfterPass::Sampled => (
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::PipelineStageFlags2::FRAGMENT_SHADER,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            ),
        };
        let written = (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        transition(device, cmd, self.color.raw, vk::ImageAspectFlags::COLOR, written, next);
        if attachments == Attachments::ColorAndIds {
            transition(device, cmd, self.ids().raw, vk::ImageAspectFlags::COLOR, written, readback);
        }
    }

    /// Records `record` (which must leave the colour image in TRANSFER_SRC_OPTIMAL, as
    /// `end(.., AfterPass::Readback, ..)` does), runs it, and copies the colour image to the host.
    pub fn render_and_read(
        &self,
        context: &Arc<Context>,
        record: impl FnOnce(vk::CommandBuffer),
    ) -> Result<FloatImage> {
        Ok(self.render_and_read_with(context, Attachments::Color, record)?.0)
    }

    /// `render_and_read`, and with `Attachments::ColorAndIds` the triangle ids too (rows top to
    /// bottom; `record` then draws them and leaves them as `end` does).
    pub fn render_and_read_with(
        &self,
        context: &Arc<Context>,
        attachments: Attachments,
        record: impl FnOnce(vk::CommandBuffer),
    ) -> Result<(FloatImage, Option<Vec<u32>>)> {
        let extent = self.extent();
        let pixel_count = extent.width as usize * extent.height as usize;
        let (images, count) = self.color_images(attachments);
        let images = &images[..count];
        let texel_bytes = [16, 4];
        let readbacks = images
            .iter()
            .zip(texel_bytes)
            .map(|(_, bytes)| {
                Buffer::new(
                    context,
                    "render target readback",
                    (pixel_count * bytes) as vk::DeviceSize,
                    vk::BufferUsageFlags::TRANSFER_DST,
                    MemoryLocation::GpuToCpu,
                )
            })
            .collect::<Result<Vec<Buffer>>>()?;
        context.run_once(|cmd| {
            record(cmd);
            let region = [vk::BufferImageCopy::default()
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(vk::ImageAspectFlags::COLOR)
                        .layer_count(1),
                )
                .image_extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })];
            for (image, readback) in images.iter().zip(&readbacks) {
                // SAFETY: the image is in TRANSFER_SRC_OPTIMAL (see above) and the buffer is
                // large enough for a tightly packed copy.
                unsafe {
                    context.device.cmd_copy_image_to_buffer(
                        cmd,
                        image.raw,
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        readback.raw,
                        &region,
                    );
                }
            }
            let barrier = [vk::MemoryBarrier2::default()
                .src_stage_mask(vk::PipelineStageFlags2::COPY)
                .src_access_mask(vk::AccessFlags2::TRANSFER_WRITE)
                .dst_stage_mask(vk::PipelineStageFlags2::HOST)
                .dst_access_mask(vk::AccessFlags2::HOST_READ)];
            let dependency = vk::DependencyInfo::default().memory_barriers(&barrier);
            // SAFETY: recording command buffer.
            unsafe { context.device.cmd_pipeline_barrier2(cmd, &dependency) };
        })?;
        let bytes = readbacks[0].mapped().expect("GpuToCpu memory is mapped");
        let pixels: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&bytes[..pixel_count * 16]);
        let ids = readbacks.get(1).map(|readback| {
            let bytes = readback.mapped().expect("GpuToCpu memory is mapped");
            bytemuck::pod_collect_to_vec::<u8, u32>(&bytes[..pixel_count * 4])
        });
        Ok((FloatImage { width: extent.width, height: extent.height, pixels }, ids))
    }
}
