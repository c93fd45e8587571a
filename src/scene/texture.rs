//! Textures on the CPU: PNG loading, the mip chain, a twin of Vulkan's trilinear sampling, and
//! (in `texture/bounds.rs`) the two ways of bounding a parameter texture over a region that the error
//! estimator needs.
//!
//! This module owns everything between a PNG file and the texel arrays the renderer uploads:
//!
//! - [`Texture`]: the image and its full mip chain, as albedo (sRGB colour, RGBA8) or as a
//!   parameter (one linear UNORM channel, R8) such as shininess or roughness;
//! - [`Texture::sample_parameter`] and [`Texture::sample_albedo`]: what a Vulkan sampler with
//!   REPEAT addressing and LINEAR mag, min and mipmap filtering returns, computed as the Vulkan
//!   specification writes it ("Texel Filtering", "Level-of-Detail Operation");
//! - [`MinMaxPyramid`]: per-block minima and maxima of a parameter texture, and a conservative
//!   range of every value the sampler can return over a box of texture coordinates. Its GPU
//!   half is `glsl/include/texture_bounds.glsl`, operation for operation;
//! - [`PowerSat`]: the paper's estimate of the same range (seed 003 Sec. 4.2, normalized
//!   power-weighted filtering over summed-area tables), which is not conservative.
//!
//! It knows nothing of Vulkan objects; the renderer uploads [`MipLevel`]s as they are.

//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`image`]: the texture, its mip chain and its sampling.
//! 2. [`bounds`]: a parameter texture's range over a region, conservative and the paper's.

mod bounds;
mod image;

pub use bounds::{MinMaxPyramid, PowerSat, PYRAMID_SLACK, PYRAMID_UNORM_STEP};
pub use image::{MipLevel, Texture, TextureError, TextureUsage, MAX_TEXTURE_SIZE};
