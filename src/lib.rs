//! `multirate`: error-bounded multirate shading on the hardware tessellator.
//!
//! Layers, bottom to top. A module imports only from the layers listed before its own; unit tests
//! (in sibling `tests.rs` files) may import anything. `tests/layers.rs` checks every `crate::`
//! path against this list, so it stays true and no import cycle between modules can form.
//! 1. [`exact_math`]: the estimator's bit-exact elementary functions (twin: `exact_math.glsl`).
//! 2. [`scene`]: the TOML scene format, OBJ meshes and textures; knows no Vulkan.
//! 3. [`error`]: the crate's error type (keeps each `vk::Result` with what was being done).
//! 4. [`gpu_types`]: the `#[repr(C)]` twins of the GLSL structs.
//! 5. [`gpu_interface`]: descriptor bindings, specialization ids, flags and dispatch slots, named
//!    once (the SPIR-V is checked against them by `tests/layout.rs`).
//! 6. [`shaders`]: the embedded SPIR-V modules and their feature variants.
//! 7. [`vk`]: Vulkan plumbing (context, memory, targets, pipelines, swapchain); knows no scenes.
//! 8. [`geometry`]: camera matrices and the culling before the estimate; knows no Vulkan.
//! 9. [`shading`]: the Rust twins of the GLSL shading functions and the error estimator.
//! 10. [`analysis`]: CPU models and tools: the tessellator, the oracle, reports, image metrics.
//! 11. [`render`]: passes and pipeline variants that draw a scene into a render target.
//! 12. [`bench`]: benchmarks of the speed/accuracy trade: rows, plots, timing captures.
//! 13. [`window`]: the interactive viewer.

pub mod analysis;
pub mod bench;
pub mod error;
pub mod exact_math;
pub mod geometry;
pub mod gpu_interface;
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
