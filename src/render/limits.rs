//! Limits checked before the GPU sees a scene: what the scene needs (vertices, triangles,
//! lights, textures, and the bytes of every per-scene buffer and image that [`super::Renderer`]
//! creates) against the device's limits (`vk::context::DeviceLimits`, read once per context)
//! and against what the shaders can index. [`check`] is a pure function, run once per scene
//! load before any buffer or image exists; its error names the scene file and the limit.

use super::pre_pass::steps::PRE_PASS_GROUP;
use super::textures;
use crate::error::{mib, Error, Result};
use crate::geometry::shadow_view::ShadowLayout;
use crate::gpu_interface::bindings::TexelFormat;
use crate::gpu_interface::slots::{BACK_FACE_ENTRY, LEVEL_DISPATCHES, SKIPPED_VERTEX};
use crate::gpu_types::{GpuLight, GpuMaterial, GpuPolygonLight, GpuShadowMap, Vertex};
use crate::scene::adjacency::PATCH_SIZE;
use crate::scene::{Light, Scene};
use crate::shading::estimator::PATTERN_LEVELS;
use crate::vk::context::DeviceLimits;
use crate::vk::target::EMITTER_ID_BIT;
use std::mem::size_of;
use std::path::Path;

/// Most triangles a scene may have: the analysis variant writes a triangle's scene index + 1
/// as its id, and ids with [`EMITTER_ID_BIT`] set are the polygonal lights' emitters
/// (glsl/include/triangle_id.glsl); the pre-pass's list of visible triangles marks back faces
/// with [`BACK_FACE_ENTRY`], bit 31 of a triangle's index, likewise.
pub const MAX_TRIANGLES: u64 = EMITTER_ID_BIT as u64 - 1;
const _: () = assert!(MAX_TRIANGLES < BACK_FACE_ENTRY as u64);

/// Turns of the estimator's light loop per point or directional light: its
/// `REFINE_CHILDREN` children and the patch (`turns` in `light_sums`,
/// glsl/include/estimator/estimate.glsl). A polygonal light takes one turn.
pub const TURNS_PER_LIGHT: u64 = 5;

/// Most turns of the estimator's light loop: the shaders count them, and index the lights, in
/// a GLSL `int` (`light_turns` in `light_sums`; the light counts are `int` specialization
/// constants in glsl/include/brdf.glsl). This bounds the lights of a scene:
/// `TURNS_PER_LIGHT × (point + directional) + polygonal ≤ MAX_LIGHT_TURNS`.
pub const MAX_LIGHT_TURNS: u64 = i32::MAX as u64;

/// One mesh's share of the pre-pass's dispatches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshSize {
    pub triangles: u64,
}

/// One image of the scene's textures.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureSize {
    /// As the upload names it: what it is and its file.
    pub name: String,
    pub width: u32,
    pub height: u32,
    pub levels: u32,
    /// Texel bytes of the whole mip chain.
    pub bytes: u64,
}

/// What a scene needs on the GPU, counted from its public fields without building anything.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SceneSizes {
    /// The meshes' vertices and the polygonal lights' emitter vertices (`scene vertices`).
    pub vertices: u64,
    /// The meshes' triangle indices and the emitters' fans (`scene indices`).
    pub indices: u64,
    /// The meshes, in scene order.
    pub meshes: Vec<MeshSize>,
    pub point_and_directional_lights: u64,
    pub polygon_lights: u64,
    pub materials: u64,
    /// The materials' textures, then the shadow atlas (`shadows`; 1 × 1 without shadows).
    pub textures: Vec<TextureSize>,
    /// The shadow maps (a directional light's, a point light's cube).
    pub shadow_maps: u64,
}

/// Where a buffer's memory comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Heap {
    DeviceLocal,
    HostVisible,
}

/// How the shaders read a buffer, which decides the device limit its size must fit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoundAs {
    /// A storage buffer: at most maxStorageBufferRange bytes.
    StorageBuffer,
    /// A uniform texel buffer of 16-byte texels: at most maxTexelBufferElements texels.
    TexelBuffer,
    /// Not through a descriptor (an index or indirect buffer, a copy's source).
    Nothing,
}

/// One per-scene buffer of [`super::Renderer`], as its constructor creates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneBuffer {
    /// The buffer's name (the renderer's, shown in captures).
    pub name: &'static str,
    pub bytes: u64,
    /// How the shaders read it (its whole size in one binding).
    pub bound_as: BoundAs,
    pub heap: Heap,
    /// What its size grows with: a count and its unit ("triangles").
    pub count: u64,
    pub unit: &'static str,
}

impl SceneSizes {
    /// The sizes of `scene`.
    pub fn of(scene: &Scene) -> SceneSizes {
        let mut sizes = SceneSizes { materials: scene.materials.len() as u64, ..SceneSizes::default() };
        for mesh in &scene.meshes {
            sizes.vertices += mesh.positions.len() as u64;
            sizes.indices += mesh.indices.len() as u64;
            sizes.meshes.push(MeshSize { triangles: mesh.indices.len() as u64 / 3 });
        }
        for light in &scene.lights {
            match light {
                Light::Point { .. } | Light::Directional { .. } => sizes.point_and_directional_lights += 1,
                Light::Polygon(polygon) => {
                    sizes.polygon_lights += 1;
                    // The emitter: a fan of `count - 2` triangles.
                    sizes.vertices += polygon.count as u64;
                    sizes.indices += 3 * (polygon.count as u64).saturating_sub(2);
                }
            }
        }
        sizes.textures = textures::uploads(scene)
            .iter()
            .map(|upload| {
                let first = upload.levels.first();
                TextureSize {
                    name: upload.name.clone(),
                    width: first.map_or(0, |l| l.width),
                    height: first.map_or(0, |l| l.height),
                    levels: upload.levels.len() as u32,
                    bytes: upload.levels.iter().map(|l| l.texels.len() as u64).sum(),
                }
            })
            .collect();
        let shadows = ShadowLayout::of(scene);
        let [width, height] = shadows.extent;
        sizes.textures.push(TextureSize {
            name: "shadow atlas".to_string(),
            width,
            height,
            levels: 1,
            bytes: 4 * u64::from(width) * u64::from(height),
        });
        sizes.shadow_maps = shadows.maps.len() as u64;
        sizes
    }

    /// Triangles of the meshes (the emitters' are not estimated, listed or recorded).
    pub fn triangles(&self) -> u64 {
        self.meshes.iter().map(|m| m.triangles).sum()
    }

    /// Every per-scene buffer `Renderer::new` creates, with its size. A buffer added there
    /// belongs here too: tests/cli.rs checks a renderer's allocations against this list.
    pub fn buffers(&self) -> Vec<SceneBuffer> {
        use BoundAs::{Nothing, StorageBuffer, TexelBuffer};
        let triangles = self.triangles();
        let meshes = self.meshes.len() as u64;
        let lights = self.point_and_directional_lights;
        // `device_words`: at least one word; `Buffer::with_data`: at least 4 bytes.
        let words = |count: u64| 4 * count.max(1);
        let data = |count: u64, size: usize| (count * size as u64).max(4);
        let buffer = |name, bytes, bound_as, count, unit| SceneBuffer {
            name,
            bytes,
            bound_as,
            heap: Heap::DeviceLocal,
            count,
            unit,
        };
        let per_triangle = |name, words_each: u64| {
            buffer(name, words(words_each * triangles), StorageBuffer, triangles, "triangles")
        };
        let dispatches = u64::from(LEVEL_DISPATCHES);
        let per_mesh = |name, bytes_each: u64, bound_as| {
            buffer(name, (bytes_each * meshes).max(4), bound_as, meshes, "meshes")
        };
        let pattern_levels = std::mem::size_of_val(&PATTERN_LEVELS) as u64;
        vec![
            buffer(
                "scene vertices",
                data(self.vertices, size_of::<Vertex>()),
                TexelBuffer,
                self.vertices,
                "vertices",
            ),
            buffer(
                "scene indices",
                data(self.indices, size_of::<u32>()),
                StorageBuffer,
                self.indices,
                "indices",
            ),
            buffer(
                "scene adjacency patches",
                data(PATCH_SIZE as u64 * triangles, size_of::<u32>()),
                Nothing,
                triangles,
                "triangles",
            ),
            per_triangle("triangle levels", 1),
            per_triangle("levels of the ball of eyes", 1),
            per_triangle("levels held", 4),
            buffer(
                "triangle neighbours",
                data(triangles.max(1), size_of::<[u32; 4]>()),
                TexelBuffer,
                triangles,
                "triangles",
            ),
            buffer(
                "triangle corners",
                data(triangles, size_of::<[[f32; 4]; 3]>()),
                TexelBuffer,
                triangles,
                "triangles",
            ),
            per_triangle("visible triangles", 1),
            per_triangle("triangles to refine", 1),
            per_triangle("triangles to estimate in full", 1),
            per_mesh("interpolated and fallback patch counts", 2 * 4, StorageBuffer),
            per_mesh("pre-pass dispatches", 16 * dispatches, StorageBuffer),
            buffer("pre-pass dispatch reset", 16 * dispatches * meshes.max(1), Nothing, meshes, "meshes"),
            per_triangle("interpolated patches", 1),
            per_triangle("fallback patches", 1),
            per_triangle("flat patches", 1),
            per_triangle("interpolated patch draws", 4),
            per_triangle("fallback patch draws", 4),
            per_mesh("flat patch draws", 4 * 4, StorageBuffer),
            per_triangle("flat patch indices", 3),
            per_triangle("per-pixel flat patch indices", 3),
            SceneBuffer {
                heap: Heap::HostVisible,
                ..buffer("level records", (16 * triangles).max(4), StorageBuffer, triangles, "triangles")
            },
            buffer(
                "scene lights",
                data(lights, size_of::<GpuLight>()),
                StorageBuffer,
                lights,
                "point and directional lights",
            ),
            buffer(
                "scene materials",
                data(self.materials, size_of::<GpuMaterial>()),
                StorageBuffer,
                self.materials,
                "materials",
            ),
            buffer(
                "scene polygonal lights",
                data(self.polygon_lights.max(1), size_of::<GpuPolygonLight>()),
                StorageBuffer,
                self.polygon_lights,
                "polygonal lights",
            ),
            buffer(
                "shadow maps",
                data(self.shadow_maps.max(1), size_of::<GpuShadowMap>()),
                TexelBuffer,
                self.shadow_maps,
                "shadow maps",
            ),
            per_triangle("patch tessellation levels", 4),
            buffer("pattern levels", pattern_levels, StorageBuffer, PATTERN_LEVELS.len() as u64, "words"),
        ]
    }

    /// Bytes of device-local memory the scene's buffers and textures take at the least.
    pub fn device_local_bytes(&self) -> u64 {
        let buffers =
            self.buffers().iter().filter(|b| b.heap == Heap::DeviceLocal).map(|b| b.bytes).sum::<u64>();
        buffers + self.textures.iter().map(|t| t.bytes).sum::<u64>()
    }
}

/// `bytes` for a message: in MiB from 1 MiB on, in bytes below.
fn amount(bytes: u64) -> String {
    if bytes < 1 << 20 {
        format!("{bytes} bytes")
    } else {
        format!("{} MiB", mib(bytes))
    }
}

/// Checks that the scene of `sizes`, loaded from `scene`, fits `limits` and the shaders:
/// the first limit it exceeds is the error.
pub fn check(scene: &Path, sizes: &SceneSizes, limits: &DeviceLimits) -> Result<()> {
    let fail =
        |what: String, limit: String| Err(Error::SceneLimit { scene: scene.to_path_buf(), what, limit });
    let triangles = sizes.triangles();
    if triangles > MAX_TRIANGLES {
        return fail(
            format!("its {triangles} triangles"),
            format!("the shaders' 31-bit triangle ids ({MAX_TRIANGLES} triangles)"),
        );
    }
    let turns = TURNS_PER_LIGHT * sizes.point_and_directional_lights + sizes.polygon_lights;
    if turns > MAX_LIGHT_TURNS {
        return fail(
            format!(
                "its {} point and directional and {} polygonal lights ({turns} turns of the estimator's light loop)",
                sizes.point_and_directional_lights, sizes.polygon_lights
            ),
            format!("the shaders' 32-bit signed light index ({MAX_LIGHT_TURNS} turns)"),
        );
    }
    if sizes.vertices > limits.max_draw_indexed_index_value.saturating_add(1) {
        return fail(
            format!("its {} vertices", sizes.vertices),
            format!(
                "the device's maxDrawIndexedIndexValue ({}, the largest vertex index a draw may use)",
                limits.max_draw_indexed_index_value
            ),
        );
    }
    if sizes.vertices > u64::from(SKIPPED_VERTEX) {
        return fail(
            format!("its {} vertices", sizes.vertices),
            format!("multirate's skipped-vertex index ({SKIPPED_VERTEX}, which no vertex may have)"),
        );
    }
    for (index, mesh) in sizes.meshes.iter().enumerate() {
        // The patch step covers the triangles to classify and, in workgroups of their own, those
        // whose level the culling step knew (kept levels, back faces): one more at most.
        let groups = mesh.triangles.div_ceil(u64::from(PRE_PASS_GROUP)) + 1;
        if groups > limits.max_compute_work_group_count_x {
            return fail(
                format!(
                    "mesh {index}'s {} triangles ({groups} workgroups of the pre-pass, {PRE_PASS_GROUP} triangles each)",
                    mesh.triangles
                ),
                format!("the device's maxComputeWorkGroupCount[0] ({})", limits.max_compute_work_group_count_x),
            );
        }
    }
    for texture in &sizes.textures {
        let (width, height, max) = (texture.width, texture.height, limits.max_image_dimension_2d);
        if width > max || height > max {
            return fail(
                format!("the {} ({width}×{height} texels)", texture.name),
                format!("the device's maxImageDimension2D ({max})"),
            );
        }
        let most_levels = 32 - width.max(height).max(1).leading_zeros();
        if texture.levels > most_levels {
            return fail(
                format!("the {} ({} mip levels of {width}×{height} texels)", texture.name, texture.levels),
                format!("a {width}×{height} image's full mip chain ({most_levels} levels)"),
            );
        }
    }
    for buffer in sizes.buffers() {
        let what = || {
            format!(
                "the buffer \"{}\" of its {} {} ({})",
                buffer.name,
                buffer.count,
                buffer.unit,
                amount(buffer.bytes)
            )
        };
        let heap = match buffer.heap {
            Heap::DeviceLocal => ("device-local heap", limits.device_local_heap),
            Heap::HostVisible => ("host-visible heap", limits.host_visible_heap),
        };
        let texels = buffer.bytes / TexelFormat::BYTES;
        if buffer.bound_as == BoundAs::TexelBuffer && texels > limits.max_texel_buffer_elements {
            return fail(
                format!(
                    "the buffer \"{}\" of its {} {} ({texels} texels)",
                    buffer.name, buffer.count, buffer.unit
                ),
                format!("the device's maxTexelBufferElements ({})", limits.max_texel_buffer_elements),
            );
        }
        let exceeded = [
            (
                buffer.bound_as == BoundAs::StorageBuffer,
                "maxStorageBufferRange",
                limits.max_storage_buffer_range,
            ),
            (true, "maxBufferSize", limits.max_buffer_size),
            (true, "maxMemoryAllocationSize", limits.max_memory_allocation_size),
            (true, heap.0, heap.1),
        ];
        if let Some((_, name, value)) =
            exceeded.iter().find(|(applies, _, value)| *applies && buffer.bytes > *value)
        {
            return fail(what(), format!("the device's {name} ({})", amount(*value)));
        }
    }
    let total = sizes.device_local_bytes();
    if total > limits.device_local_heap {
        return fail(
            format!("its buffers and textures ({} of device-local memory in all)", amount(total)),
            format!("the device's device-local heap ({})", amount(limits.device_local_heap)),
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests;
