//! Offscreen render targets: a linear float colour image (alpha = coverage) and a depth image,
//! with dynamic-rendering begin/end helpers and a readback into host memory.

use super::context::Context;
use super::memory::{transition, Buffer, Image};
use crate::error::Result;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

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

/// Colour and depth attachments of one size.
pub struct RenderTarget {
    pub color: Image,
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
        Ok(RenderTarget { color, depth })
    }

    pub fn extent(&self) -> vk::Extent2D {
        self.color.extent
    }

    /// Transitions both attachments (contents discarded) and begins dynamic rendering with a
    /// clear to `clear` (alpha 0 = no coverage) and depth 1.
    pub fn begin(&self, device: &ash::Device, cmd: vk::CommandBuffer, clear: [f32; 4]) {
        transition(
            device,
            cmd,
            self.color.raw,
            vk::ImageAspectFlags::COLOR,
            (vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::ALL_COMMANDS, vk::AccessFlags2::NONE),
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
        );
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
        let color_attachment = [vk::RenderingAttachmentInfo::default()
            .image_view(self.color.view)
            .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: clear } })];
        let depth_attachment = vk::RenderingAttachmentInfo::default()
            .image_view(self.depth.view)
            .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::DONT_CARE)
            .clear_value(vk::ClearValue {
                depth_stencil: vk::ClearDepthStencilValue { depth: 1.0, stencil: 0 },
            });
        let rendering = vk::RenderingInfo::default()
            .color_attachments(&color_attachment)
            .depth_attachment(&depth_attachment);
        begin_rendering(device, cmd, self.extent(), rendering);
    }

    /// Ends dynamic rendering and makes the colour image ready for `after`.
    pub fn end(&self, device: &ash::Device, cmd: vk::CommandBuffer, after: AfterPass) {
        // SAFETY: rendering was begun by `begin` on this command buffer.
        unsafe { device.cmd_end_rendering(cmd) };
        let next = match after {
            AfterPass::Readback => (
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_READ,
            ),
            AfterPass::Sampled => (
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::PipelineStageFlags2::FRAGMENT_SHADER,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            ),
        };
        transition(
            device,
            cmd,
            self.color.raw,
            vk::ImageAspectFlags::COLOR,
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
            next,
        );
    }

    /// Records `record` (which must leave the colour image in TRANSFER_SRC_OPTIMAL, as
    /// `end(.., AfterPass::Readback)` does), runs it, and copies the colour image to the host.
    pub fn render_and_read(
        &self,
        context: &Arc<Context>,
        record: impl FnOnce(vk::CommandBuffer),
    ) -> Result<FloatImage> {
        let extent = self.extent();
        let pixel_count = extent.width as usize * extent.height as usize;
        let readback = Buffer::new(
            context,
            "render target readback",
            (pixel_count * 16) as vk::DeviceSize,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        context.run_once(|cmd| {
            record(cmd);
            let region = [vk::BufferImageCopy::default()
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(vk::ImageAspectFlags::COLOR)
                        .layer_count(1),
                )
                .image_extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })];
            // SAFETY: the image is in TRANSFER_SRC_OPTIMAL (see above) and the buffer is large
            // enough for a tightly packed copy.
            unsafe {
                context.device.cmd_copy_image_to_buffer(
                    cmd,
                    self.color.raw,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    readback.raw,
                    &region,
                );
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
        let bytes = readback.mapped().expect("GpuToCpu memory is mapped");
        let pixels: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&bytes[..pixel_count * 16]);
        Ok(FloatImage { width: extent.width, height: extent.height, pixels })
    }
}
