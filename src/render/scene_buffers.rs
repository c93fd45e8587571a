//! The scene on the GPU ([`SceneBuffers`]): its geometry, lights and materials uploaded, and the
//! per-scene buffers the shaders write besides the pre-pass's (level records, counters).

use super::scene_geometry::{gpu_shadow_maps, SceneGeometry};
use crate::error::Result;
use crate::gpu_types::{GpuPolygonLight, GpuShadowMap};
use crate::vk::memory::Buffer;
use crate::vk::Context;
use ash::vk;
use std::sync::Arc;

/// The per-scene buffers. Every one is in `SceneSizes::buffers` (limits.rs), which
/// `limits::check` checks before they are created.
pub(super) struct SceneBuffers {
    /// The meshes' and the emitters' vertices; a texel buffer too (two texels a vertex): the
    /// deferred pass fetches triangles by id, the compute placement pulls its patches'
    /// vertices and its pre-pass estimates from them.
    pub vertices: Buffer,
    pub indices: Buffer,
    /// Per triangle of the meshes: its 12-index adjacency patch (`Placement::Tcs` draws).
    pub patch_indices: Buffer,
    pub lights: Buffer,
    pub materials: Buffer,
    /// The polygonal lights; a scene without any still binds one (unread) entry.
    pub polygon_lights: Buffer,
    /// The shadow atlas's tiles; a scene without shadows still binds one (unread) entry.
    pub shadow_maps: Buffer,
    /// `PATTERN_LEVELS`, the effective levels of the hardware patterns (replaced by the
    /// device's measured table where the built-in one does not hold on it).
    pub pattern_levels: Buffer,
    /// Per triangle: the level records of the level-recording variants (host-visible).
    pub level_records: Buffer,
    /// The counting variants' four counters (`EvaluationCounters` in bindings.glsl).
    pub counters: Buffer,
}

impl SceneBuffers {
    /// Uploads `geometry` and creates the buffers the shaders write.
    pub(super) fn upload(context: &Arc<Context>, geometry: &SceneGeometry) -> Result<SceneBuffers> {
        let vertices = Buffer::with_data(
            context,
            "scene vertices",
            vk::BufferUsageFlags::VERTEX_BUFFER | vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER,
            &geometry.vertices,
        )?;
        let indices = Buffer::with_data(
            context,
            "scene indices",
            vk::BufferUsageFlags::INDEX_BUFFER | vk::BufferUsageFlags::STORAGE_BUFFER,
            &geometry.indices,
        )?;
        let patch_indices = Buffer::with_data(
            context,
            "scene adjacency patches",
            vk::BufferUsageFlags::INDEX_BUFFER,
            &geometry.patch_indices,
        )?;
        let level_records = Buffer::new(
            context,
            "level records",
            (geometry.triangle_count * 16) as vk::DeviceSize,
            vk::BufferUsageFlags::STORAGE_BUFFER,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let counters = Buffer::new(
            context,
            "evaluation counters",
            16,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            gpu_allocator::MemoryLocation::GpuToCpu,
        )?;
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let lights = Buffer::with_data(context, "scene lights", storage, &geometry.lights.lights)?;
        let materials = Buffer::with_data(context, "scene materials", storage, &geometry.materials)?;
        let unread = [GpuPolygonLight::default()];
        let polygon_entries: &[GpuPolygonLight] =
            if geometry.polygon_lights.is_empty() { &unread } else { &geometry.polygon_lights };
        let polygon_lights = Buffer::with_data(context, "scene polygonal lights", storage, polygon_entries)?;
        let tiles = gpu_shadow_maps(&geometry.shadows);
        let unread = [GpuShadowMap::default()];
        let tile_entries: &[GpuShadowMap] = if tiles.is_empty() { &unread } else { &tiles };
        let texels = vk::BufferUsageFlags::UNIFORM_TEXEL_BUFFER;
        let shadow_maps = Buffer::with_data(context, "shadow maps", texels, tile_entries)?;
        let pattern_levels = Buffer::with_data(
            context,
            "pattern levels",
            storage,
            &crate::shading::estimator::PATTERN_LEVELS,
        )?;
        Ok(SceneBuffers {
            vertices,
            indices,
            patch_indices,
            lights,
            materials,
            polygon_lights,
            shadow_maps,
            pattern_levels,
            level_records,
            counters,
        })
    }
}
