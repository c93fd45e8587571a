//! Sampled images: uploading a texture's mip chain (from the CPU, as `scene::texture` builds
//! it) into a device-local image, and the samplers that read them. Both free themselves in
//! `Drop`.

use super::context::Context;
use super::memory::{transition, Buffer, Image};
use crate::error::{Result, VkContext};
use ash::vk;
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// One mip level's texels, tightly packed rows from the top-left corner.
pub struct LevelData<'a> {
    pub width: u32,
    pub height: u32,
    pub texels: &'a [u8],
}

/// Uploads `levels` (level 0 first, each half the size of the one before) into a new image of
/// `format`, left in `SHADER_READ_ONLY_OPTIMAL` for every shader stage.
pub fn upload_image(
    context: &Arc<Context>,
    name: &str,
    format: vk::Format,
    levels: &[LevelData<'_>],
) -> Result<Image> {
    let first = levels.first().expect("a texture has at least one level");
    let image = Image::with_levels(
        context,
        name,
        vk::Extent2D { width: first.width, height: first.height },
        levels.len() as u32,
        format,
        vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        vk::ImageAspectFlags::COLOR,
    )?;
    let mut bytes = Vec::new();
    let mut regions = Vec::with_capacity(levels.len());
    for (level, data) in levels.iter().enumerate() {
        // Buffer offsets of a copy to an image must be multiples of 4 (and of the texel size).
        bytes.resize(bytes.len().next_multiple_of(4), 0);
        regions.push(
            vk::BufferImageCopy::default()
                .buffer_offset(bytes.len() as vk::DeviceSize)
                .image_subresource(
                    vk::ImageSubresourceLayers::default()
                        .aspect_mask(vk::ImageAspectFlags::COLOR)
                        .mip_level(level as u32)
                        .layer_count(1),
                )
                .image_extent(vk::Extent3D { width: data.width, height: data.height, depth: 1 }),
        );
        bytes.extend_from_slice(data.texels);
    }
    let staging = Buffer::new(
        context,
        &format!("{name} (staging)"),
        bytes.len() as vk::DeviceSize,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
    )?;
    staging.write(&bytes);
    let device = &context.device;
    context.run_once(|cmd| {
        let aspect = vk::ImageAspectFlags::COLOR;
        transition(
            device,
            cmd,
            image.raw,
            aspect,
            (vk::ImageLayout::UNDEFINED, vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
            (
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
        );
        // SAFETY: the staging buffer holds every region, the image has every level, and
        // `run_once` waits for completion before `staging` is dropped.
        unsafe {
            device.cmd_copy_buffer_to_image(
                cmd,
                staging.raw,
                image.raw,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &regions,
            )
        };
        transition(
            device,
            cmd,
            image.raw,
            aspect,
            (
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                vk::PipelineStageFlags2::ALL_GRAPHICS,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            ),
        );
    })?;
    Ok(image)
}

/// A sampler: trilinear with REPEAT addressing for the materials' textures, or nearest with
/// edge clamping for images read with `texelFetch`; no anisotropy.
pub struct Sampler {
    context: Arc<Context>,
    pub raw: vk::Sampler,
}

impl Sampler {
    /// Trilinear filtering, REPEAT addressing, every mip level.
    /// `scene::texture::Texture::sample_parameter` is its CPU twin.
    pub fn trilinear_repeat(context: &Arc<Context>, name: &str) -> Result<Sampler> {
        let linear = (vk::Filter::LINEAR, vk::SamplerMipmapMode::LINEAR);
        Sampler::new(context, name, linear, vk::SamplerAddressMode::REPEAT, vk::LOD_CLAMP_NONE)
    }

    /// Nearest filtering, clamped to the edge, level 0 only: for images read with `texelFetch`
    /// (the shadow atlas), which a filtering sampler would need a filterable format for.
    pub fn nearest_clamp(context: &Arc<Context>, name: &str) -> Result<Sampler> {
        let nearest = (vk::Filter::NEAREST, vk::SamplerMipmapMode::NEAREST);
        Sampler::new(context, name, nearest, vk::SamplerAddressMode::CLAMP_TO_EDGE, 0.0)
    }

    /// Bilinear filtering, clamped to the edge, level 0 only: for upsampling a smaller image.
    pub fn linear_clamp(context: &Arc<Context>, name: &str) -> Result<Sampler> {
        let linear = (vk::Filter::LINEAR, vk::SamplerMipmapMode::NEAREST);
        Sampler::new(context, name, linear, vk::SamplerAddressMode::CLAMP_TO_EDGE, 0.0)
    }

    fn new(
        context: &Arc<Context>,
        name: &str,
        (filter, mipmap_mode): (vk::Filter, vk::SamplerMipmapMode),
        address: vk::SamplerAddressMode,
        max_lod: f32,
    ) -> Result<Sampler> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter)
            .min_filter(filter)
            .mipmap_mode(mipmap_mode)
            .address_mode_u(address)
            .address_mode_v(address)
            .address_mode_w(address)
            .min_lod(0.0)
            .max_lod(max_lod);
        // SAFETY: valid create info; destroyed in `Drop`.
        let raw = unsafe { context.device.create_sampler(&info, None) }.while_("creating a sampler")?;
        context.name(raw, name);
        Ok(Sampler { context: context.clone(), raw })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees no pending work uses the sampler.
        unsafe { self.context.device.destroy_sampler(self.raw, None) };
    }
}
