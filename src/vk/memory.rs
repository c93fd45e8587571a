//! Buffers and images backed by gpu-allocator. Each owns its memory and frees it in `Drop`;
//! each holds an `Arc<Context>` so the device outlives it.

use super::context::Context;
use crate::error::{mib, Error, Result, VkContext};
use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;
use std::sync::Arc;

/// A buffer and its memory.
pub struct Buffer {
    context: Arc<Context>,
    pub raw: vk::Buffer,
    pub size: vk::DeviceSize,
    allocation: Option<Allocation>,
}

impl Buffer {
    /// An uninitialised buffer of `size` bytes in `location`, named `name` for captures.
    pub fn new(
        context: &Arc<Context>,
        name: &str,
        size: vk::DeviceSize,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Buffer> {
        let device = &context.device;
        let bytes = size.max(4);
        check_heap(context, name, bytes, location)?;
        let most = context.limits.max_buffer_size;
        if bytes > most {
            let reason = format!("more than the device's maxBufferSize ({} MiB)", mib(most));
            return Err(memory_error(context, name, bytes, location, reason));
        }
        let info =
            vk::BufferCreateInfo::default().size(bytes).usage(usage).sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create info (its size checked above); the buffer is destroyed in `Drop`.
        let raw = unsafe { device.create_buffer(&info, None) }.while_("creating a buffer")?;
        // SAFETY: `raw` is a live buffer of this device.
        let requirements = unsafe { device.get_buffer_memory_requirements(raw) };
        let allocation = allocate(context, name, requirements, location, true);
        let allocation = match allocation {
            Ok(allocation) => allocation,
            Err(error) => {
                // SAFETY: the buffer was never bound or used.
                unsafe { device.destroy_buffer(raw, None) };
                return Err(error);
            }
        };
        let buffer = Buffer { context: context.clone(), raw, size, allocation: Some(allocation) };
        let allocation = buffer.allocation.as_ref().expect("just set");
        // SAFETY: the memory was allocated for this buffer's requirements.
        unsafe { device.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) }
            .while_("binding buffer memory")?;
        context.name(raw, name);
        Ok(buffer)
    }

    /// A device-local buffer holding `data`, uploaded through a staging buffer.
    pub fn with_data<T: bytemuck::Pod>(
        context: &Arc<Context>,
        name: &str,
        usage: vk::BufferUsageFlags,
        data: &[T],
    ) -> Result<Buffer> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let size = bytes.len().max(4) as vk::DeviceSize;
        let buffer = Buffer::new(
            context,
            name,
            size,
            usage | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
        )?;
        buffer.upload(data)?;
        Ok(buffer)
    }

    /// Copies `data` to the start of a buffer made by [`Buffer::with_data`] through a staging
    /// buffer, and waits for the copy. The caller makes sure no submitted work uses it.
    pub fn upload<T: bytemuck::Pod>(&self, data: &[T]) -> Result<()> {
        let bytes: &[u8] = bytemuck::cast_slice(data);
        let size = bytes.len().max(4) as vk::DeviceSize;
        assert!(size <= self.size, "upload past the end of the buffer");
        let staging = Buffer::new(
            &self.context,
            "staging",
            size,
            vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::CpuToGpu,
        )?;
        staging.write(bytes);
        let context = &self.context;
        context.run_once(|cmd| {
            let region = [vk::BufferCopy::default().size(size)];
            // SAFETY: both buffers are live and large enough; `run_once` waits for completion.
            unsafe { context.device.cmd_copy_buffer(cmd, staging.raw, self.raw, &region) };
        })
    }

    /// Host-visible bytes of the buffer (None for device-only memory).
    pub fn mapped(&self) -> Option<&[u8]> {
        let allocation = self.allocation.as_ref()?;
        allocation.mapped_slice()
    }

    /// Copies `bytes` to the start of a host-visible buffer.
    pub fn write(&self, bytes: &[u8]) {
        let allocation = self.allocation.as_ref().expect("buffer has memory");
        let ptr = allocation.mapped_ptr().expect("write() needs a host-visible buffer");
        assert!(bytes.len() as u64 <= self.size, "write past the end of the buffer");
        // SAFETY: the mapping is at least `size` bytes long and not aliased by any reference.
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), ptr.as_ptr().cast::<u8>(), bytes.len()) };
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if let Some(allocation) = self.allocation.take() {
            let _ = self.context.allocator.lock().map(|mut a| a.free(allocation));
        }
        // SAFETY: the owner guarantees the GPU no longer uses the buffer.
        unsafe { self.context.device.destroy_buffer(self.raw, None) };
    }
}

/// A view of a whole buffer as texels of one format, what a uniform texel buffer descriptor
/// points at. It does not keep the buffer alive: its owner drops it first.
pub struct BufferView {
    context: Arc<Context>,
    pub raw: vk::BufferView,
}

impl BufferView {
    /// A view of all of `buffer` as `format` texels, named `name` for captures. The buffer has
    /// the UNIFORM_TEXEL_BUFFER usage, a whole number of texels and at most the device's
    /// maxTexelBufferElements of them (`render::limits` checks each scene's).
    pub fn new(
        context: &Arc<Context>,
        name: &str,
        buffer: &Buffer,
        format: vk::Format,
    ) -> Result<BufferView> {
        let info =
            vk::BufferViewCreateInfo::default().buffer(buffer.raw).format(format).range(vk::WHOLE_SIZE);
        // SAFETY: valid create info on a live buffer; the view is destroyed in `Drop`.
        let raw =
            unsafe { context.device.create_buffer_view(&info, None) }.while_("creating a buffer view")?;
        context.name(raw, name);
        Ok(BufferView { context: context.clone(), raw })
    }
}

impl Drop for BufferView {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees no pending work uses the view.
        unsafe { self.context.device.destroy_buffer_view(self.raw, None) };
    }
}

/// A 2D image, its memory and one view of all of it.
pub struct Image {
    context: Arc<Context>,
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
    allocation: Option<Allocation>,
}

impl Image {
    /// A device-local 2D image with one mip level.
    pub fn new(
        context: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Image> {
        Image::with_levels(context, name, extent, 1, format, usage, aspect)
    }

    /// A device-local 2D image with `mip_levels` levels; the view covers all of them.
    pub fn with_levels(
        context: &Arc<Context>,
        name: &str,
        extent: vk::Extent2D,
        mip_levels: u32,
        format: vk::Format,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Result<Image> {
        let device = &context.device;
        let max = context.limits.max_image_dimension_2d;
        if extent.width > max || extent.height > max {
            let (width, height) = (extent.width, extent.height);
            return Err(Error::ImageTooLarge { what: name.to_string(), width, height, max });
        }
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(format)
            .extent(vk::Extent3D { width: extent.width, height: extent.height, depth: 1 })
            .mip_levels(mip_levels)
            .array_layers(1)
            .samples(vk::SampleCountFlags::TYPE_1)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create info; destroyed in `Drop`.
        let raw = unsafe { device.create_image(&info, None) }.while_("creating an image")?;
        // SAFETY: `raw` is a live image of this device.
        let requirements = unsafe { device.get_image_memory_requirements(raw) };
        let allocation = check_heap(context, name, requirements.size, MemoryLocation::GpuOnly)
            .and_then(|()| allocate(context, name, requirements, MemoryLocation::GpuOnly, false));
        let allocation = match allocation {
            Ok(allocation) => allocation,
            Err(error) => {
                // SAFETY: the image was never bound or used.
                unsafe { device.destroy_image(raw, None) };
                return Err(error);
            }
        };
        let mut image = Image {
            context: context.clone(),
            raw,
            view: vk::ImageView::null(),
            format,
            extent,
            allocation: Some(allocation),
        };
        let allocation = image.allocation.as_ref().expect("just set");
        // SAFETY: memory allocated for this image's requirements.
        unsafe { device.bind_image_memory(raw, allocation.memory(), allocation.offset()) }
            .while_("binding image memory")?;
        let view_info = vk::ImageViewCreateInfo::default()
            .image(raw)
            .view_type(vk::ImageViewType::TYPE_2D)
            .format(format)
            .subresource_range(subresource_range(aspect));
        // SAFETY: the image is bound; the view is destroyed in `Drop` before the image.
        image.view =
            unsafe { device.create_image_view(&view_info, None) }.while_("creating an image view")?;
        context.name(raw, name);
        context.name(image.view, &format!("{name} view"));
        Ok(image)
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees the GPU no longer uses the image.
        unsafe {
            if self.view != vk::ImageView::null() {
                self.context.device.destroy_image_view(self.view, None);
            }
            self.context.device.destroy_image(self.raw, None);
        }
        if let Some(allocation) = self.allocation.take() {
            let _ = self.context.allocator.lock().map(|mut a| a.free(allocation));
        }
    }
}

/// Which heap memory of `location` comes from, and its size.
fn heap_of(context: &Context, location: MemoryLocation) -> (&'static str, u64) {
    match location {
        MemoryLocation::GpuOnly => ("device-local", context.limits.device_local_heap),
        _ => ("host-visible", context.limits.host_visible_heap),
    }
}

/// The error of `size` bytes of `location` for `name` that cannot be had, and why.
fn memory_error(context: &Context, name: &str, size: u64, location: MemoryLocation, reason: String) -> Error {
    let (heap, heap_size) = heap_of(context, location);
    Error::ResourceMemory { what: name.to_string(), size, heap, heap_size, reason }
}

/// Refuses `size` bytes that no single allocation of `location` can hold: more than the heap,
/// or than `maxMemoryAllocationSize`. Asking Vulkan for them would be invalid usage rather
/// than a failure.
fn check_heap(context: &Context, name: &str, size: u64, location: MemoryLocation) -> Result<()> {
    let (_, heap_size) = heap_of(context, location);
    let largest = context.limits.max_memory_allocation_size;
    let reason = if size > heap_size {
        "more than the heap holds".to_string()
    } else if size > largest {
        format!("more than the device's maxMemoryAllocationSize ({} MiB)", mib(largest))
    } else {
        return Ok(());
    };
    Err(memory_error(context, name, size, location, reason))
}

/// Memory of `requirements` from the allocator, for the resource `name`.
fn allocate(
    context: &Context,
    name: &str,
    requirements: vk::MemoryRequirements,
    location: MemoryLocation,
    linear: bool,
) -> Result<Allocation> {
    let mut allocator = context.allocator.lock().expect("allocator lock is never poisoned");
    let scheme = AllocationScheme::GpuAllocatorManaged;
    let description =
        AllocationCreateDesc { name, requirements, location, linear, allocation_scheme: scheme };
    allocator
        .allocate(&description)
        .map_err(|source| memory_error(context, name, requirements.size, location, source.to_string()))
}

/// All mips and layers of one aspect.
pub fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange::default()
        .aspect_mask(aspect)
        .level_count(vk::REMAINING_MIP_LEVELS)
        .layer_count(vk::REMAINING_ARRAY_LAYERS)
}

/// Records one image layout transition with synchronization2.
#[allow(clippy::too_many_arguments)]
pub fn transition(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    aspect: vk::ImageAspectFlags,
    (old_layout, src_stage, src_access): (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
    (new_layout, dst_stage, dst_access): (vk::ImageLayout, vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let barrier = [vk::ImageMemoryBarrier2::default()
        .image(image)
        .subresource_range(subresource_range(aspect))
        .old_layout(old_layout)
        .new_layout(new_layout)
        .src_stage_mask(src_stage)
        .src_access_mask(src_access)
        .dst_stage_mask(dst_stage)
        .dst_access_mask(dst_access)];
    let dependency = vk::DependencyInfo::default().image_memory_barriers(&barrier);
    // SAFETY: `cmd` is recording and `image` is live.
    unsafe { device.cmd_pipeline_barrier2(cmd, &dependency) };
}
