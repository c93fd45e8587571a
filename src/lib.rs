//! `multirate`: error-bounded multirate shading on the hardware tessellator.
//!
//! Layers, each importing only those above it in this list:
//! - [`vk`]: Vulkan plumbing (context, memory, targets, pipelines, swapchain); knows no scenes.
//! - [`scene`]: the TOML scene format and OBJ meshes; knows no Vulkan.
//! - [`shading`]: the Rust twins of the GLSL shading functions.
//! - [`render`]: passes and pipeline variants that join the three above, and image output.
//! - [`bench`]: benchmarks of the speed/accuracy trade: rows, plots, timing captures.
//! - [`window`]: the interactive viewer.

pub mod analysis;
pub mod bench;
pub mod error;
pub mod gpu_types;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod shading;
#[cfg(test)]
mod test_rng;
pub mod vk;
pub mod window;

pub use error::{Error, Result};
