//! Camera and culling math in world, view and clip space: the projection Vulkan's clip space
//! expects, the viewer's orbit, and which triangles the multirate pre-pass culls before their
//! estimate. Knows no Vulkan; imports only [`crate::scene`].
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`camera`]: camera matrices for Vulkan's clip space and the viewer's orbit.
//! 2. [`cull`]: which triangles are culled, or shaded per pixel, before their estimate.
//! 3. [`shadow_fit`]: a directional light's map fitted to what the camera sees.
//! 4. [`shadow_view`]: the shadow maps' matrices and their tiles in the atlas.
//! 5. [`shadow_lookup`]: a light's visibility at a point, read from the maps (shadow.glsl's twin).
//! 6. [`shadow_footprint`]: what a triangle's lookups read of one map square, and whether all
//!    pass or all fail there.
//! 7. [`shadow_class`]: whether a light reaches all, none or part of a triangle.

pub mod camera;
pub mod cull;
pub mod shadow_class;
pub mod shadow_fit;
pub mod shadow_footprint;
pub mod shadow_lookup;
pub mod shadow_view;
