//! The display pass: tone maps the float render target into a swapchain image with the same
//! transform as PNG output (exposure, ACES filmic, sRGB).

use crate::error::{Result, VkContext as _};
use crate::gpu_interface::bindings::present::HDR_IMAGE;
use crate::gpu_interface::specialization::ENCODE_SRGB;
use crate::shaders;
use crate::vk::memory::transition;
use crate::vk::pipeline::{
    DepthUse, DescriptorPool, GraphicsPipelineDesc, Optimization, Pipeline, PipelineLayout, ShaderModule,
    Specialization, Stage,
};
use crate::vk::target::{begin_rendering, RenderTarget};
use crate::vk::Context;
use ash::vk;
use std::sync::Arc;

pub struct PresentPass {
    context: Arc<Context>,
    sampler: vk::Sampler,
    layout: PipelineLayout,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    pipeline: Pipeline,
}

impl PresentPass {
    /// A pass writing `format` images; `encode_srgb` when the format does not encode itself.
    pub fn new(context: &Arc<Context>, format: vk::Format, encode_srgb: bool) -> Result<PresentPass> {
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::NEAREST)
            .min_filter(vk::Filter::NEAREST)
            .max_lod(0.0);
        // SAFETY: valid create info; destroyed in `Drop`.
        let sampler = unsafe { context.device.create_sampler(&sampler_info, None) }
            .while_("creating the present sampler")?;
        let binding = [vk::DescriptorSetLayoutBinding::default()
            .binding(HDR_IMAGE.binding)
            .descriptor_type(HDR_IMAGE.kind.descriptor_type())
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::FRAGMENT)];
        let push = [vk::PushConstantRange::default().stage_flags(vk::ShaderStageFlags::FRAGMENT).size(4)];
        let layout = PipelineLayout::new(context, "present layout", &[&binding], &push)?;
        let pool = DescriptorPool::new(
            context,
            "present descriptors",
            1,
            &[vk::DescriptorPoolSize { ty: HDR_IMAGE.kind.descriptor_type(), descriptor_count: 1 }],
        )?;
        let set = pool.allocate(layout.set_layouts[0])?;
        let vertex = ShaderModule::new(context, "fullscreen.vert", shaders::single("fullscreen.vert"))?;
        let fragment = ShaderModule::new(context, "present.frag", shaders::single("present.frag"))?;
        let specialization = Specialization::default().boolean(ENCODE_SRGB.id, encode_srgb);
        let modules = (&vertex, &fragment);
        let pipeline =
            fullscreen_pipeline(context, "present", &layout, modules, format, Some(&specialization))?;
        // SAFETY: live sampler handle.
        context.name(sampler, "present sampler");
        Ok(PresentPass { context: context.clone(), sampler, layout, _pool: pool, set, pipeline })
    }

    /// Points the pass at `target` (call again after the target is recreated, device idle).
    pub fn bind_target(&self, target: &RenderTarget) {
        let image_info = [vk::DescriptorImageInfo {
            sampler: self.sampler,
            image_view: target.color.view,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }];
        let write = [vk::WriteDescriptorSet::default()
            .dst_set(self.set)
            .dst_binding(HDR_IMAGE.binding)
            .descriptor_type(HDR_IMAGE.kind.descriptor_type())
            .image_info(&image_info)];
        // SAFETY: the set is not in use by any pending command buffer (caller waited).
        unsafe { self.context.device.update_descriptor_sets(&write, &[]) };
    }

    /// Records the tone-mapping draw into a swapchain image and leaves it ready to present.
    pub fn record(
        &self,
        cmd: vk::CommandBuffer,
        image: vk::Image,
        view: vk::ImageView,
        extent: vk::Extent2D,
        exposure: f32,
    ) {
        let device = &self.context.device;
        transition(
            device,
            cmd,
            image,
            vk::ImageAspectFlags::COLOR,
            (
                vk::ImageLayout::UNDEFINED,
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::NONE,
            ),
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
        );
        // The render target was left in SHADER_READ_ONLY_OPTIMAL by the forward pass.
        let push = exposure.to_ne_bytes();
        let bound = (&self.pipeline, &self.layout, self.set);
        draw_fullscreen(device, cmd, (view, extent), bound, (vk::ShaderStageFlags::FRAGMENT, &push));
        transition(
            device,
            cmd,
            image,
            vk::ImageAspectFlags::COLOR,
            (
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
            (vk::ImageLayout::PRESENT_SRC_KHR, vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
        );
    }
}

impl Drop for PresentPass {
    fn drop(&mut self) {
        // SAFETY: the owner waits for the device before dropping the pass.
        unsafe { self.context.device.destroy_sampler(self.sampler, None) };
    }
}

/// A pipeline drawing `fullscreen.vert`'s triangle with `modules.1` into `format` images: the
/// display pass's, and each pass of the post chain's (`post`).
pub(super) fn fullscreen_pipeline(
    context: &Arc<Context>,
    name: &'static str,
    layout: &PipelineLayout,
    (vertex, fragment): (&ShaderModule, &ShaderModule),
    format: vk::Format,
    specialization: Option<&Specialization>,
) -> Result<Pipeline> {
    Pipeline::graphics(
        context,
        &GraphicsPipelineDesc {
            name,
            stages: vec![
                Stage { stage: vk::ShaderStageFlags::VERTEX, module: vertex, specialization: None },
                Stage { stage: vk::ShaderStageFlags::FRAGMENT, module: fragment, specialization },
            ],
            layout,
            vertex_bindings: &[],
            vertex_attributes: &[],
            topology: vk::PrimitiveTopology::TRIANGLE_LIST,
            patch_control_points: None,
            polygon_mode: vk::PolygonMode::FILL,
            cull_mode: vk::CullModeFlags::NONE,
            front_face: vk::FrontFace::COUNTER_CLOCKWISE,
            color_formats: &[format],
            depth_format: None,
            depth_use: DepthUse::Nearest,
            rasterizer_discard: false,
            dynamic_cull_mode: false,
            optimization: Optimization::Optimized,
        },
    )
}

/// Draws `fullscreen.vert`'s triangle into `view` (its contents before not kept) with `pipeline`,
/// `layout`'s set 0 bound to `set` and `push` pushed to `stages`: the display pass's, and each
/// pass of the post chain's (`post`). The image must be in COLOR_ATTACHMENT_OPTIMAL, and the
/// set's images in the layouts it names.
pub(super) fn draw_fullscreen(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    (view, extent): (vk::ImageView, vk::Extent2D),
    (pipeline, layout, set): (&Pipeline, &PipelineLayout, vk::DescriptorSet),
    (stages, push): (vk::ShaderStageFlags, &[u8]),
) {
    let attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(view)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::DONT_CARE)
        .store_op(vk::AttachmentStoreOp::STORE)];
    begin_rendering(device, cmd, extent, vk::RenderingInfo::default().color_attachments(&attachment));
    // SAFETY: `cmd` is recording inside the rendering begun above; the caller keeps the view, the
    // pipeline and the set alive until the commands ran, with the set's images in its layouts.
    unsafe {
        device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline.raw);
        device.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, layout.raw, 0, &[set], &[]);
        device.cmd_push_constants(cmd, layout.raw, stages, 0, push);
        device.cmd_draw(cmd, 3, 1, 0, 0);
        device.cmd_end_rendering(cmd);
    }
}
