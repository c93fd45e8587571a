//! The post chain: eye adaptation, bloom and tone mapping of the linear float frame into a
//! display image, the viewer's frame (by default) and `multirate render --post`'s.
//!
//! It only reads the frame: every error `bench`, `analyze` and the tests measure is measured on
//! the linear frame before it. Its passes (GLSL `post_*`, interface in `glsl/include/post.glsl`):
//! 1. `post_downsample.frag`: a quarter-resolution image, per texel its 4×4 block's average
//!    colour and average log luminance;
//! 2. `post_luminance.comp`: the frame's average log luminance, blended into the adapted one
//!    (exponentially, [`PostSettings::adaptation_seconds`]; at once for a single image), and the
//!    exposure that maps it to [`PostSettings::key`], times the scene's exposure;
//! 3. `post_blur.frag` twice: a separable Gaussian over the part of the exposed image above
//!    [`PostSettings::bloom_threshold`] (the bloom);
//! 4. `post_composite.frag`: the frame at the adapted exposure plus the bloom, through the ACES
//!    curve and sRGB (`tonemap.glsl`) into the output image.

use super::present::{draw_fullscreen, fullscreen_pipeline};
use crate::error::Result;
use crate::gpu_interface::bindings::post::{ADAPTATION, BLOOM_IMAGE, INPUTS, LINEAR_FRAME};
use crate::gpu_interface::specialization::ENCODE_SRGB;
use crate::shaders;
use crate::vk::memory::{transition, Buffer, Image};
use crate::vk::pipeline::{
    bind_sampled_images, bind_storage_buffers, DescriptorPool, Optimization, Pipeline, PipelineLayout,
    ShaderModule, Specialization,
};
use crate::vk::target::{FloatImage, COLOR_FORMAT};
use crate::vk::texture::Sampler;
use crate::vk::Context;
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// The downsampling factor of the chain's images per axis (`POST_DOWNSAMPLE` in post.glsl).
pub const DOWNSAMPLE: u32 = 4;
/// The format of the chain's quarter-resolution images.
const BLOOM_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// What the chain does, the same for every frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PostSettings {
    /// The exposed average luminance eye adaptation aims at (middle grey).
    pub key: f32,
    /// The time constant of the adaptation, in seconds: after it, 63 % of a change is adapted.
    pub adaptation_seconds: f32,
    /// The exposed luminance above which light blooms.
    pub bloom_threshold: f32,
    /// The weight of the bloom added to the exposed frame.
    pub bloom_strength: f32,
}

impl Default for PostSettings {
    fn default() -> Self {
        PostSettings { key: 0.18, adaptation_seconds: 0.7, bloom_threshold: 1.0, bloom_strength: 0.1 }
    }
}

/// How a frame's exposure follows the adapted one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Adapt {
    /// To this frame's average alone: a single image, or the first of a sequence.
    AtOnce,
    /// Towards this frame's average over this many seconds since the last frame.
    After(f32),
}

impl Adapt {
    /// The weight of the frame's average against the adapted one.
    pub fn weight(self, settings: &PostSettings) -> f32 {
        match self {
            Adapt::AtOnce => 1.0,
            Adapt::After(seconds) => {
                let weight = 1.0 - (-seconds / settings.adaptation_seconds).exp();
                if weight.is_finite() {
                    weight.clamp(0.0, 1.0)
                } else {
                    1.0
                }
            }
        }
    }
}

/// The push constants of every stage (twin: `PostConstants` in post.glsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct PostConstants {
    pub scene_exposure: f32,
    pub adaptation_weight: f32,
    pub key: f32,
    pub bloom_threshold: f32,
    pub bloom_strength: f32,
    pub blur_x: f32,
    pub blur_y: f32,
    pub bright_pass: f32,
}

/// An image layout with the stage and access that last used it or will use it.
type Use = (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2);

/// Where the chain writes its display image.
#[derive(Clone, Copy, Debug)]
pub struct Output {
    pub image: vk::Image,
    pub view: vk::ImageView,
    /// The layout, stage and access the image is left ready for.
    pub after: Use,
}

/// The frame the chain reads and its two quarter-resolution images.
struct Images {
    input: vk::Image,
    extent: vk::Extent2D,
    /// The downsampled frame, then the bloom (bound in set 0).
    first: Image,
    /// The bloom's horizontal pass (bound in set 1).
    second: Image,
}

/// The chain's pipelines and state. Bind a frame with [`PostChain::bind_input`] first.
pub struct PostChain {
    context: Arc<Context>,
    settings: PostSettings,
    format: vk::Format,
    nearest: Sampler,
    linear: Sampler,
    layout: PipelineLayout,
    _pool: DescriptorPool,
    /// Both with the frame and the adaptation; set 0 with the first image, set 1 the second.
    sets: [vk::DescriptorSet; 2],
    _adaptation: Buffer,
    downsample: Pipeline,
    luminance: Pipeline,
    blur: Pipeline,
    composite: Pipeline,
    images: Option<Images>,
}

impl PostChain {
    /// A chain writing `format` images; `encode_srgb` when the format does not encode itself.
    pub fn new(
        context: &Arc<Context>,
        format: vk::Format,
        encode_srgb: bool,
        settings: PostSettings,
    ) -> Result<PostChain> {
        let stages = vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
        let bindings = INPUTS.map(|b| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(b.binding)
                .descriptor_type(b.kind.descriptor_type())
                .descriptor_count(1)
                .stage_flags(stages)
        });
        let push_size = std::mem::size_of::<PostConstants>() as u32;
        let push = [vk::PushConstantRange::default().stage_flags(stages).size(push_size)];
        let layout = PipelineLayout::new(context, "post layout", &[&bindings], &push)?;
        let pool = DescriptorPool::new(
            context,
            "post descriptors",
            2,
            &[
                vk::DescriptorPoolSize { ty: LINEAR_FRAME.kind.descriptor_type(), descriptor_count: 4 },
                vk::DescriptorPoolSize { ty: ADAPTATION.kind.descriptor_type(), descriptor_count: 2 },
            ],
        )?;
        let sets = [pool.allocate(layout.set_layouts[0])?, pool.allocate(layout.set_layouts[0])?];
        let adaptation = Buffer::with_data(
            context,
            "post adaptation",
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &[0.0f32, 1.0],
        )?;
        for set in sets {
            bind_storage_buffers(context, set, ADAPTATION.binding, &[adaptation.raw]);
        }
        let vertex = ShaderModule::new(context, "fullscreen.vert", shaders::single("fullscreen.vert"))?;
        let encode = Specialization::default().boolean(ENCODE_SRGB.id, encode_srgb);
        let fragment = |name: &'static str, format: vk::Format, spec: Option<&Specialization>| {
            let module = ShaderModule::new(context, name, shaders::single(name))?;
            fullscreen_pipeline(context, name, &layout, (&vertex, &module), format, spec)
        };
        let downsample = fragment("post_downsample.frag", BLOOM_FORMAT, None)?;
        let blur = fragment("post_blur.frag", BLOOM_FORMAT, None)?;
        let composite = fragment("post_composite.frag", format, Some(&encode))?;
        let module =
            ShaderModule::new(context, "post_luminance.comp", shaders::single("post_luminance.comp"))?;
        let luminance =
            Pipeline::compute(context, "post luminance", &layout, &module, None, Optimization::Optimized)?;
        Ok(PostChain {
            context: context.clone(),
            settings,
            format,
            nearest: Sampler::nearest_clamp(context, "post frame sampler")?,
            linear: Sampler::linear_clamp(context, "post bloom sampler")?,
            layout,
            _pool: pool,
            sets,
            _adaptation: adaptation,
            downsample,
            luminance,
            blur,
            composite,
            images: None,
        })
    }

    pub fn settings(&self) -> &PostSettings {
        &self.settings
    }

    /// Points the chain at `input`, a linear frame (the render target's colour image) that is
    /// in `SHADER_READ_ONLY_OPTIMAL` whenever the chain is recorded, and makes its images of the
    /// frame's size. Call again after the frame is recreated; no pending work may use the chain.
    pub fn bind_input(&mut self, input: &Image) -> Result<()> {
        let extent = input.extent;
        let reduced = vk::Extent2D {
            width: extent.width.div_ceil(DOWNSAMPLE).max(1),
            height: extent.height.div_ceil(DOWNSAMPLE).max(1),
        };
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
        let color = vk::ImageAspectFlags::COLOR;
        let first = Image::new(&self.context, "post image 1", reduced, BLOOM_FORMAT, usage, color)?;
        let second = Image::new(&self.context, "post image 2", reduced, BLOOM_FORMAT, usage, color)?;
        // Both start ready to be read, as every pass leaves them.
        self.context.run_once(|cmd| {
            for image in [&first, &second] {
                transition(&self.context.device, cmd, image.raw, color, UNUSED, SAMPLED);
            }
        })?;
        for (set, bloom) in self.sets.iter().zip([&first, &second]) {
            bind_sampled_images(&self.context, *set, LINEAR_FRAME.binding, self.nearest.raw, &[input.view]);
            bind_sampled_images(&self.context, *set, BLOOM_IMAGE.binding, self.linear.raw, &[bloom.view]);
        }
        self.images = Some(Images { input: input.raw, extent, first, second });
        Ok(())
    }

    /// Records the chain: the bound frame, at `scene_exposure` times the adapted exposure, into
    /// `output` (of the chain's format and the frame's size). Nothing is recorded before
    /// [`PostChain::bind_input`].
    pub fn record(&self, cmd: vk::CommandBuffer, output: Output, scene_exposure: f32, adapt: Adapt) {
        let Some(images) = &self.images else { return };
        let device = &self.context.device;
        let settings = &self.settings;
        let constants = PostConstants {
            scene_exposure,
            adaptation_weight: adapt.weight(settings),
            key: settings.key,
            bloom_threshold: settings.bloom_threshold,
            bloom_strength: settings.bloom_strength,
            ..PostConstants::default()
        };
        let reduced = images.first.extent;
        let (first, second) = (&images.first, &images.second);
        self.pass(cmd, &self.downsample, (first.raw, first.view, reduced), self.sets[1], constants);
        // The last frame's passes read the adaptation the luminance pass writes.
        let to_compute = (vk::PipelineStageFlags2::FRAGMENT_SHADER, vk::AccessFlags2::SHADER_STORAGE_READ);
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let storage = vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
        memory_barrier(device, cmd, to_compute, (compute, storage));
        // SAFETY: `cmd` is recording outside rendering; the set's images are in the layouts it
        // names (the first image was left sampled by the pass above).
        unsafe {
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.luminance.raw);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout.raw,
                0,
                &[self.sets[0]],
                &[],
            );
            let stages = vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
            device.cmd_push_constants(cmd, self.layout.raw, stages, 0, bytemuck::bytes_of(&constants));
            device.cmd_dispatch(cmd, 1, 1, 1);
        }
        let fragment = (vk::PipelineStageFlags2::FRAGMENT_SHADER, vk::AccessFlags2::SHADER_STORAGE_READ);
        memory_barrier(device, cmd, (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE), fragment);
        let horizontal = PostConstants { blur_x: 1.0, bright_pass: 1.0, ..constants };
        self.pass(cmd, &self.blur, (second.raw, second.view, reduced), self.sets[0], horizontal);
        let vertical = PostConstants { blur_y: 1.0, ..constants };
        self.pass(cmd, &self.blur, (first.raw, first.view, reduced), self.sets[1], vertical);
        let target = (output.image, output.view, images.extent);
        self.draw(cmd, &self.composite, target, self.sets[0], constants, (UNUSED, output.after));
    }

    /// One pass into a quarter-resolution image, left sampled.
    fn pass(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        target: (vk::Image, vk::ImageView, vk::Extent2D),
        set: vk::DescriptorSet,
        constants: PostConstants,
    ) {
        self.draw(cmd, pipeline, target, set, constants, (SAMPLED, SAMPLED));
    }

    /// A fullscreen draw of `pipeline` into `target` (whose contents it replaces), taken from
    /// its last use `before` and left for `after`.
    fn draw(
        &self,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        (image, view, extent): (vk::Image, vk::ImageView, vk::Extent2D),
        set: vk::DescriptorSet,
        constants: PostConstants,
        (before, after): (Use, Use),
    ) {
        let device = &self.context.device;
        let color = vk::ImageAspectFlags::COLOR;
        let before = (vk::ImageLayout::UNDEFINED, before.1, vk::AccessFlags2::NONE);
        transition(device, cmd, image, color, before, ATTACHMENT);
        let stages = vk::ShaderStageFlags::FRAGMENT | vk::ShaderStageFlags::COMPUTE;
        let bound = (pipeline, &self.layout, set);
        draw_fullscreen(device, cmd, (view, extent), bound, (stages, bytemuck::bytes_of(&constants)));
        transition(device, cmd, image, color, ATTACHMENT, after);
    }

    /// Runs the chain on the bound frame and reads its display image back (sRGB-encoded values
    /// in [0, 1], alpha 1). `input_layout` is the frame's layout (`TRANSFER_SRC_OPTIMAL` after
    /// [`crate::render::Renderer::render`], `SHADER_READ_ONLY_OPTIMAL` otherwise); the frame is
    /// left in it. The chain must have been made for [`COLOR_FORMAT`].
    pub fn read(
        &self,
        input_layout: vk::ImageLayout,
        scene_exposure: f32,
        adapt: Adapt,
    ) -> Result<FloatImage> {
        assert_eq!(self.format, COLOR_FORMAT, "only a chain writing float images is read back");
        let Some(images) = &self.images else {
            return Ok(FloatImage { width: 0, height: 0, pixels: Vec::new() });
        };
        let extent = images.extent;
        let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
        let output = Image::new(
            &self.context,
            "post output",
            extent,
            COLOR_FORMAT,
            usage,
            vk::ImageAspectFlags::COLOR,
        )?;
        let pixel_count = extent.width as usize * extent.height as usize;
        let readback = Buffer::new(
            &self.context,
            "post readback",
            (pixel_count * 16) as vk::DeviceSize,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let device = &self.context.device;
        let color = vk::ImageAspectFlags::COLOR;
        let copied = (
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
        );
        self.context.run_once(|cmd| {
            let before =
                (input_layout, vk::PipelineStageFlags2::ALL_COMMANDS, vk::AccessFlags2::MEMORY_WRITE);
            let back = (input_layout, vk::PipelineStageFlags2::ALL_COMMANDS, vk::AccessFlags2::MEMORY_READ);
            if input_layout != vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL {
                transition(device, cmd, images.input, color, before, SAMPLED);
            }
            let target = Output { image: output.raw, view: output.view, after: copied };
            self.record(cmd, target, scene_exposure, adapt);
            if input_layout != vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL {
                transition(device, cmd, images.input, color, SAMPLED, back);
            }
            let region = [vk::BufferImageCopy::default()
                .image_subresource(vk::ImageSubresourceLayers::default().aspect_mask(color).layer_count(1))
                .image_extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })];
            // SAFETY: the output image is in TRANSFER_SRC_OPTIMAL (the chain left it so) and the
            // buffer holds a tightly packed copy.
            unsafe {
                device.cmd_copy_image_to_buffer(
                    cmd,
                    output.raw,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    readback.raw,
                    &region,
                )
            };
            let to_host = (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ);
            memory_barrier(
                device,
                cmd,
                (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_WRITE),
                to_host,
            );
        })?;
        let bytes = readback.mapped().expect("GpuToCpu memory is mapped");
        let pixels = bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&bytes[..pixel_count * 16]);
        Ok(FloatImage { width: extent.width, height: extent.height, pixels })
    }
}

/// An image whose contents are discarded, last written as an attachment (a swapchain image
/// after its acquire semaphore's wait).
const UNUSED: Use =
    (vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT, vk::AccessFlags2::NONE);
/// An image the chain reads (in a fragment or compute stage).
const SAMPLED: Use = (
    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::FRAGMENT_SHADER.as_raw() | vk::PipelineStageFlags2::COMPUTE_SHADER.as_raw(),
    ),
    vk::AccessFlags2::SHADER_SAMPLED_READ,
);
/// An image being drawn into.
const ATTACHMENT: Use = (
    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
);

/// A global memory barrier from `(stage, access)` to `(stage, access)`.
fn memory_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)];
    // SAFETY: `cmd` is recording outside rendering.
    unsafe { device.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().memory_barriers(&barrier)) };
}

#[cfg(test)]
mod tests;
