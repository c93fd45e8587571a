//! The window's surface and swapchain: creation, recreation after resize or out-of-date,
//! image acquisition and presentation. A zero-sized (minimised) window has no swapchain images
//! until it is restored; callers skip frames meanwhile.

use super::context::Context;
use crate::error::{Result, VkContext};
use ash::vk;
use std::sync::Arc;

/// What acquiring an image gave.
pub enum Acquired {
    /// Render into image `index`, then present it. `suboptimal`: the swapchain no longer
    /// matches the surface exactly; the image is acquired all the same (its semaphore will
    /// be signalled, so it must be used), and the swapchain is best recreated after presenting.
    Image { index: u32, suboptimal: bool },
    /// The swapchain no longer matches the surface: recreate it and try again (nothing was
    /// acquired).
    OutOfDate,
}

pub struct Swapchain {
    context: Arc<Context>,
    loader: ash::khr::swapchain::Device,
    surface: vk::SurfaceKHR,
    pub raw: vk::SwapchainKHR,
    pub format: vk::SurfaceFormatKHR,
    pub extent: vk::Extent2D,
    pub images: Vec<vk::Image>,
    pub views: Vec<vk::ImageView>,
    /// One per image: signalled when rendering into that image is done, waited by present.
    pub render_finished: Vec<vk::Semaphore>,
}

impl Swapchain {
    /// Takes ownership of `surface` (destroyed with the swapchain).
    pub fn new(context: &Arc<Context>, surface: vk::SurfaceKHR, size: vk::Extent2D) -> Result<Swapchain> {
        let loader = ash::khr::swapchain::Device::new(&context.instance, &context.device);
        let surface_instance = context.surface_instance.as_ref().expect("windowed context");
        // SAFETY: plain queries on a live surface.
        let formats =
            unsafe { surface_instance.get_physical_device_surface_formats(context.physical_device, surface) }
                .while_("listing surface formats")?;
        let format = formats
            .iter()
            .copied()
            .find(|f| {
                matches!(f.format, vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB)
                    && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR
            })
            .or_else(|| formats.first().copied())
            .expect("a surface reports at least one format");
        let mut swapchain = Swapchain {
            context: context.clone(),
            loader,
            surface,
            raw: vk::SwapchainKHR::null(),
            format,
            extent: vk::Extent2D::default(),
            images: Vec::new(),
            views: Vec::new(),
            render_finished: Vec::new(),
        };
        swapchain.recreate(size)?;
        Ok(swapchain)
    }

    /// Whether the image format encodes sRGB itself (so shaders write linear values).
    pub fn is_srgb(&self) -> bool {
        matches!(self.format.format, vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB)
    }

    /// Rebuilds the swapchain for the window's current size. Returns false (and keeps no
    /// images) while the surface is zero-sized, as when the window is minimised.
    pub fn recreate(&mut self, size: vk::Extent2D) -> Result<bool> {
        let context = self.context.clone();
        context.wait_idle()?;
        let surface_instance = context.surface_instance.as_ref().expect("windowed context");
        // SAFETY: plain query on a live surface.
        let capabilities = unsafe {
            surface_instance.get_physical_device_surface_capabilities(context.physical_device, self.surface)
        }
        .while_("querying surface capabilities")?;
        let extent = if capabilities.current_extent.width != u32::MAX {
            capabilities.current_extent
        } else {
            vk::Extent2D {
                width: size
                    .width
                    .clamp(capabilities.min_image_extent.width, capabilities.max_image_extent.width),
                height: size
                    .height
                    .clamp(capabilities.min_image_extent.height, capabilities.max_image_extent.height),
            }
        };
        self.destroy_images();
        if extent.width == 0 || extent.height == 0 {
            return Ok(false);
        }
        let mut image_count = capabilities.min_image_count + 1;
        if capabilities.max_image_count > 0 {
            image_count = image_count.min(capabilities.max_image_count);
        }
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(self.surface)
            .min_image_count(image_count)
            .image_format(self.format.format)
            .image_color_space(self.format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(vk::ImageUsageFlags::COLOR_ATTACHMENT)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(capabilities.current_transform)
            .composite_alpha(vk::CompositeAlphaFlagsKHR::OPAQUE)
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(self.raw);
        // SAFETY: the surface is live; the old swapchain is retired by this call and destroyed
        // right after (the device is idle).
        let raw = unsafe { self.loader.create_swapchain(&info, None) }.while_("creating the swapchain")?;
        if self.raw != vk::SwapchainKHR::null() {
            // SAFETY: idle device; the old swapchain's images are no longer used.
            unsafe { self.loader.destroy_swapchain(self.raw, None) };
        }
        self.raw = raw;
        self.extent = extent;
        context.name(raw, "swapchain");
        // SAFETY: live swapchain.
        self.images = unsafe { self.loader.get_swapchain_images(raw) }.while_("listing swapchain images")?;
        for (index, &image) in self.images.iter().enumerate() {
            let view_info = vk::ImageViewCreateInfo::default()
                .image(image)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(self.format.format)
                .subresource_range(super::memory::subresource_range(vk::ImageAspectFlags::COLOR));
            // SAFETY: image of the live swapchain; destroyed before the swapchain.
            let view = unsafe { context.device.create_image_view(&view_info, None) }
                .while_("creating a swapchain image view")?;
            self.views.push(view);
            // SAFETY: plain semaphore creation.
            let semaphore =
                unsafe { context.device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
                    .while_("creating a semaphore")?;
            self.render_finished.push(semaphore);
            context.name(image, &format!("swapchain image {index}"));
        }
        Ok(true)
    }

    /// Acquires the next image, signalling `available` when it can be written.
    pub fn acquire(&self, available: vk::Semaphore) -> Result<Acquired> {
        // SAFETY: live swapchain and unsignalled semaphore (the caller waits for the previous
        // frame's fence before reusing it).
        match unsafe { self.loader.acquire_next_image(self.raw, u64::MAX, available, vk::Fence::null()) } {
            Ok((index, suboptimal)) => Ok(Acquired::Image { index, suboptimal }),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(Acquired::OutOfDate),
            Err(result) => Err(crate::Error::Vulkan { what: "acquiring a swapchain image", result }),
        }
    }

    /// Presents image `index`; returns true when the swapchain must be recreated.
    pub fn present(&self, index: u32) -> Result<bool> {
        let wait = [self.render_finished[index as usize]];
        let swapchains = [self.raw];
        let indices = [index];
        let info = vk::PresentInfoKHR::default()
            .wait_semaphores(&wait)
            .swapchains(&swapchains)
            .image_indices(&indices);
        match self.context.present(&self.loader, &info) {
            Ok(suboptimal) => Ok(suboptimal),
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => Ok(true),
            Err(result) => Err(crate::Error::Vulkan { what: "presenting", result }),
        }
    }

    fn destroy_images(&mut self) {
        // SAFETY: called with the device idle; the views and semaphores belong to this swapchain.
        unsafe {
            for view in self.views.drain(..) {
                self.context.device.destroy_image_view(view, None);
            }
            for semaphore in self.render_finished.drain(..) {
                self.context.device.destroy_semaphore(semaphore, None);
            }
        }
        self.images.clear();
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        let _ = self.context.wait_idle();
        self.destroy_images();
        // SAFETY: idle device; the surface outlives nothing that still uses it.
        unsafe {
            if self.raw != vk::SwapchainKHR::null() {
                self.loader.destroy_swapchain(self.raw, None);
            }
            if let Some(surface_instance) = &self.context.surface_instance {
                surface_instance.destroy_surface(self.surface, None);
            }
        }
    }
}
