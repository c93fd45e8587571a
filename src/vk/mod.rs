//! Vulkan plumbing, one module per concern. Knows nothing of scenes or shading.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`context`]: the instance, device, queue, allocator and validation messenger.
//! 2. [`budget`]: memory in use, as the driver and the allocator count it.
//! 3. [`memory`]: buffers and images that own their memory, and their transitions.
//! 4. [`frames`]: frames in flight for offscreen loops: a command buffer and a fence per slot.
//! 5. [`pipeline`]: shader modules, specialization constants, layouts, graphics and compute pipelines.
//! 6. [`swapchain`]: the window's surface and swapchain.
//! 7. [`target`]: offscreen render targets (float colour, triangle ids, depth) and their readback.
//! 8. [`texture`]: sampled images: a texture's mip chain on the device, and samplers.
//! 9. [`timing`]: GPU timing: timestamp queries and pipeline statistics.

pub mod budget;
pub mod context;
pub mod frames;
pub mod memory;
pub mod pipeline;
pub mod swapchain;
pub mod target;
pub mod texture;
pub mod timing;

pub use context::{Context, ContextOptions};
