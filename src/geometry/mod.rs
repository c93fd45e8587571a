//! Camera and culling math in world, view and clip space: the projection Vulkan's clip space
//! expects, the viewer's orbit, and which triangles the multirate pre-pass culls before their
//! estimate. Knows no Vulkan; imports only [`crate::scene`].

pub mod camera;
pub mod cull;
