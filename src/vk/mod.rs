//! Vulkan plumbing, one module per concern. Knows nothing of scenes or shading.

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
