//! Limits checked before the GPU sees a scene: what the scene needs (vertices, triangles,
//! lights, textures, and the bytes of every per-scene buffer and image that [`super::Renderer`]
//! creates) against the device's limits (`vk::context::DeviceLimits`, read once per context)
//! and against what the shaders can index. [`check`] is a pure function, run once per scene
//! load before any buffer or image exists; its error names the scene file and the limit.

use super::textures;
use super::PRE_PASS_GROUP;
use crate::error::{mib, Error, Result};
use crate::gpu_types::{GpuLight, GpuMaterial, GpuPolygonLight, Vertex};
use crate::scene::adjacency::PATCH_SIZE;
use crate::scene::{Light, Scene};
use crate::shading::estimator::PATTERN_LEVELS;
use crate::vk::context::DeviceLimits;
use crate::vk::target::EMITTER_ID_BIT;
use std::mem::size_of;
use std::path::Path;

/// Most triangles a scene may have: the analysis variant writes a triangle's scene index + 1
/// as its id, and ids with [`EMITTER_ID_BIT`] set are the polygonal lights' emitters
/// (glsl/include/triangle_id.glsl).
pub const MAX_TRIANGLES: u64 = EMITTER_ID_BIT as u64 - 1;

/// Turns of the estimator's light loop per point or directional light: its
/// `REFINE_CHILDREN` children and the patch (`turns` in `estimate_pass`,
/// glsl/include/estimator.glsl). A polygonal light takes one turn.
pub const TURNS_PER_LIGHT: u64 = 5;

/// Most turns of the estimator's light loop: the shaders count them, and index the lights, in
/// a GLSL `int` (`light_turns` in `estimate_pass`; the light counts are `int` specialization
/// constants in glsl/include/brdf.glsl). This bounds the lights of a scene:
/// `TURNS_PER_LIGHT × (point + directional) + polygonal ≤ MAX_LIGHT_TURNS`.
pub const MAX_LIGHT_TURNS: u64 = i32::MAX as u64;

/// One mesh's share of the pre-pass's dispatches.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MeshSize {
    pub triangles: u64,
    /// Two-sided meshes' back faces open one more workgroup of the patch step.
    pub two_sided: bool,
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
    pub textures: Vec<TextureSize>,
}

/// Where a buffer's memory comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Heap {
    DeviceLocal,
    HostVisible,
}

/// One per-scene buffer of [`super::Renderer`], as its constructor creates it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SceneBuffer {
    /// The buffer's name (the renderer's, shown in captures).
    pub name: &'static str,
    pub bytes: u64,
    /// Bound as a storage buffer (its whole size in one binding).
    pub storage: bool,
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
            sizes
                .meshes
                .push(MeshSize { triangles: mesh.indices.len() as u64 / 3, two_sided: mesh.two_sided });
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
        sizes
    }

    /// Triangles of the meshes (the emitters' are not estimated, listed or recorded).
    pub fn triangles(&self) -> u64 {
        self.meshes.iter().map(|m| m.triangles).sum()
    }

    /// Every per-scene buffer `Renderer::new` creates, with its size. A buffer added there
    /// belongs here too: tests/cli.rs checks a renderer's allocations against this list.
    pub fn buffers(&self) -> Vec<SceneBuffer> {
        let triangles = self.triangles();
        let meshes = self.meshes.len() as u64;
        let lights = self.point_and_directional_lights;
        // `device_words`: at least one word; `Buffer::with_data`: at least 4 bytes.
        let words = |count: u64| 4 * count.max(1);
        let data = |count: u64, size: usize| (count * size as u64).max(4);
        let buffer = |name, bytes, storage, count, unit| SceneBuffer {
            name,
            bytes,
            storage,
            heap: Heap::DeviceLocal,
            count,
            unit,
        };
        let per_triangle =
            |name, words_each: u64| buffer(name, words(words_each * triangles), true, triangles, "triangles");
        let per_mesh = |name, bytes_each: u64, storage| {
            buffer(name, (bytes_each * meshes).max(4), storage, meshes, "meshes")
        };
        let pattern_levels = std::mem::size_of_val(&PATTERN_LEVELS) as u64;
        vec![
            buffer(
                "scene vertices",
                data(self.vertices, size_of::<Vertex>()),
                true,
                self.vertices,
                "vertices",
            ),
            buffer("scene indices", data(self.indices, size_of::<u32>()), true, self.indices, "indices"),
            buffer(
                "scene adjacency patches",
                data(PATCH_SIZE as u64 * triangles, size_of::<u32>()),
                false,
                triangles,
                "triangles",
            ),
            per_triangle("triangle levels", 1),
            buffer(
                "triangle neighbours",
                data(triangles.max(1), size_of::<[u32; 4]>()),
                true,
                triangles,
                "triangles",
            ),
            per_triangle("visible triangles", 1),
            per_triangle("triangles to refine", 1),
            per_mesh("interpolated and fallback patch counts", 2 * 4, true),
            per_mesh("pre-pass dispatches", 4 * 3 * 4, true),
            buffer("pre-pass dispatch reset", 3 * 16 * meshes.max(1), false, meshes, "meshes"),
            per_triangle("interpolated patches", 1),
            per_triangle("fallback patches", 1),
            per_triangle("flat patches", 1),
            per_triangle("interpolated patch draws", 4),
            per_triangle("fallback patch draws", 4),
            per_mesh("flat patch draws", 2 * 4 * 4, true),
            SceneBuffer {
                heap: Heap::HostVisible,
                ..buffer("level records", (16 * triangles).max(4), true, triangles, "triangles")
            },
            buffer(
                "scene lights",
                data(lights, size_of::<GpuLight>()),
                true,
                lights,
                "point and directional lights",
            ),
            buffer(
                "scene materials",
                data(self.materials, size_of::<GpuMaterial>()),
                true,
                self.materials,
                "materials",
            ),
            buffer(
                "scene polygonal lights",
                data(self.polygon_lights.max(1), size_of::<GpuPolygonLight>()),
                true,
                self.polygon_lights,
                "polygonal lights",
            ),
            per_triangle("patch tessellation levels", 4),
            buffer("pattern levels", pattern_levels, true, PATTERN_LEVELS.len() as u64, "words"),
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
    for (index, mesh) in sizes.meshes.iter().enumerate() {
        let groups = mesh.triangles.div_ceil(u64::from(PRE_PASS_GROUP)) + u64::from(mesh.two_sided);
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
        let exceeded = [
            (buffer.storage, "maxStorageBufferRange", limits.max_storage_buffer_range),
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
mod tests {
    use super::*;

    const MIB: u64 = 1 << 20;

    fn scene() -> &'static Path {
        Path::new("scenes/test.toml")
    }

    /// Roomy limits, lowered one at a time by the tests.
    fn limits() -> DeviceLimits {
        DeviceLimits {
            max_storage_buffer_range: 1 << 30,
            max_buffer_size: 1 << 32,
            max_memory_allocation_size: 1 << 32,
            max_draw_indexed_index_value: u64::from(u32::MAX),
            max_compute_work_group_count_x: 65535,
            max_image_dimension_2d: 4096,
            device_local_heap: 8 << 30,
            host_visible_heap: 8 << 30,
        }
    }

    /// One one-sided mesh of `triangles` triangles on `2 × triangles` vertices, one light.
    fn sizes(triangles: u64) -> SceneSizes {
        SceneSizes {
            vertices: 2 * triangles,
            indices: 3 * triangles,
            meshes: vec![MeshSize { triangles, two_sided: false }],
            point_and_directional_lights: 1,
            polygon_lights: 0,
            materials: 1,
            textures: vec![TextureSize {
                name: "albedo map textures/spots.png".into(),
                width: 256,
                height: 128,
                levels: 9,
                bytes: 4 * 256 * 128 * 4 / 3,
            }],
        }
    }

    /// The message of `check`'s error, which must name the scene and `limit`.
    fn refused(sizes: &SceneSizes, limits: &DeviceLimits, limit: &str) -> String {
        let message = check(scene(), sizes, limits).expect_err("over a limit").to_string();
        assert!(message.starts_with("scenes/test.toml: "), "{message}");
        assert!(message.contains(limit), "{limit} missing from: {message}");
        message
    }

    #[test]
    fn a_scene_within_every_limit_passes() {
        check(scene(), &sizes(1000), &limits()).expect("fits");
    }

    #[test]
    fn triangles_beyond_the_shaders_ids_are_refused() {
        let message = refused(&sizes(MAX_TRIANGLES + 1), &limits(), "31-bit triangle ids");
        assert!(message.contains(&format!("{} triangles", MAX_TRIANGLES + 1)), "{message}");
        // Exactly at the limit, the ids fit (what fails then is the pre-pass's dispatch).
        let message = refused(&sizes(MAX_TRIANGLES), &limits(), "maxComputeWorkGroupCount[0]");
        assert!(!message.contains("triangle ids"), "{message}");
    }

    #[test]
    fn lights_beyond_the_shaders_index_are_refused() {
        let mut at_limit = sizes(10);
        at_limit.point_and_directional_lights = MAX_LIGHT_TURNS / TURNS_PER_LIGHT;
        at_limit.polygon_lights = MAX_LIGHT_TURNS % TURNS_PER_LIGHT;
        let message = refused(&at_limit, &limits(), "\"scene lights\"");
        assert!(!message.contains("light index"), "{message}");
        let mut over = at_limit.clone();
        over.polygon_lights += 1;
        let message = refused(&over, &limits(), "32-bit signed light index");
        assert!(message.contains(&format!("{} turns", MAX_LIGHT_TURNS + 1)), "{message}");
    }

    #[test]
    fn vertices_beyond_the_largest_index_are_refused() {
        let limits = DeviceLimits { max_draw_indexed_index_value: 1999, ..limits() };
        check(scene(), &sizes(1000), &limits).expect("2000 vertices: indices up to 1999");
        let message = refused(&sizes(1001), &limits, "maxDrawIndexedIndexValue (1999");
        assert!(message.contains("its 2002 vertices"), "{message}");
    }

    #[test]
    fn meshes_beyond_the_pre_pass_workgroups_are_refused() {
        let limits = DeviceLimits { max_compute_work_group_count_x: 10, ..limits() };
        check(scene(), &sizes(640), &limits).expect("10 workgroups");
        refused(&sizes(641), &limits, "maxComputeWorkGroupCount[0] (10)");
        let mut two_sided = sizes(640);
        two_sided.meshes[0].two_sided = true;
        refused(&two_sided, &limits, "maxComputeWorkGroupCount[0] (10)");
    }

    #[test]
    fn textures_beyond_the_image_dimension_are_refused() {
        let limits = DeviceLimits { max_image_dimension_2d: 255, ..limits() };
        let message = refused(&sizes(10), &limits, "maxImageDimension2D (255)");
        assert!(message.contains("albedo map textures/spots.png (256×128 texels)"), "{message}");
    }

    #[test]
    fn textures_with_more_mip_levels_than_their_size_allows_are_refused() {
        let mut sizes = sizes(10);
        sizes.textures[0].levels = 10;
        refused(&sizes, &limits(), "a 256×128 image's full mip chain (9 levels)");
    }

    #[test]
    fn buffers_beyond_the_storage_range_are_refused_naming_the_buffer() {
        // 1 MiB holds 65536 neighbour entries of 16 bytes; the vertices (32 bytes) overflow first.
        let limits = DeviceLimits { max_storage_buffer_range: MIB, ..limits() };
        check(scene(), &sizes(16384), &limits).expect("32768 vertices: exactly 1 MiB");
        let message = refused(&sizes(16385), &limits, "maxStorageBufferRange (1.0 MiB)");
        assert!(message.contains("\"scene vertices\" of its 32770 vertices (1.0 MiB)"), "{message}");
    }

    #[test]
    fn buffers_beyond_the_buffer_and_allocation_sizes_are_refused() {
        // The adjacency patches (48 bytes a triangle) are bound as no storage buffer.
        let storage = DeviceLimits { max_storage_buffer_range: 1 << 40, ..limits() };
        let mut few_vertices = sizes(30000);
        few_vertices.vertices = 100;
        let buffer = DeviceLimits { max_buffer_size: MIB, ..storage };
        let message = refused(&few_vertices, &buffer, "maxBufferSize (1.0 MiB)");
        assert!(message.contains("\"scene adjacency patches\" of its 30000 triangles"), "{message}");
        let allocation = DeviceLimits { max_memory_allocation_size: MIB, ..storage };
        refused(&few_vertices, &allocation, "maxMemoryAllocationSize (1.0 MiB)");
    }

    #[test]
    fn scenes_beyond_the_heaps_are_refused() {
        let sizes = sizes(1000);
        let total = sizes.device_local_bytes();
        let fits = DeviceLimits { device_local_heap: total, ..limits() };
        check(scene(), &sizes, &fits).expect("exactly the heap");
        let over = DeviceLimits { device_local_heap: total - 1, ..limits() };
        let message = refused(&sizes, &over, "device-local heap");
        assert!(message.contains("buffers and textures"), "{message}");
        // The level records are read back from host-visible memory.
        let host = DeviceLimits { host_visible_heap: 15_999, ..limits() };
        let message = refused(&sizes, &host, "host-visible heap");
        assert!(message.contains("\"level records\" of its 1000 triangles"), "{message}");
    }

    #[test]
    fn the_light_limit_is_the_glsl_light_loop() {
        let estimator = include_str!("../../glsl/include/estimator.glsl");
        let children = TURNS_PER_LIGHT - 1;
        assert!(estimator.contains(&format!("const int REFINE_CHILDREN = {children};")));
        assert!(estimator.contains("int turns = refine ? REFINE_CHILDREN + 1 : 1;"));
        assert!(
            estimator.contains("int light_turns = (POINT_LIGHT_COUNT + DIRECTIONAL_LIGHT_COUNT) * turns;")
        );
        assert!(estimator.contains("for (int turn = 0; turn < light_turns + POLYGON_LIGHT_COUNT; ++turn)"));
        let brdf = include_str!("../../glsl/include/brdf.glsl");
        for count in ["POINT_LIGHT_COUNT", "DIRECTIONAL_LIGHT_COUNT", "POLYGON_LIGHT_COUNT"] {
            assert!(brdf.contains(&format!("const int {count} = 0;")), "{count} is no int");
        }
        let bindings = include_str!("../../glsl/include/bindings.glsl");
        assert!(bindings.contains(&format!("const uint EMITTER_ID_BIT = {EMITTER_ID_BIT:#x}u;")));
    }

    #[test]
    fn the_buffer_list_follows_the_scene() {
        let one = sizes(1000);
        let buffers = one.buffers();
        let find = |name: &str| buffers.iter().find(|b| b.name == name).expect(name).bytes;
        assert_eq!(find("scene vertices"), 2000 * 32);
        assert_eq!(find("scene indices"), 3000 * 4);
        assert_eq!(find("scene adjacency patches"), 1000 * 48);
        assert_eq!(find("triangle neighbours"), 1000 * 16);
        assert_eq!(find("patch tessellation levels"), 1000 * 16);
        assert_eq!(find("scene polygonal lights"), size_of::<GpuPolygonLight>() as u64);
        let names: std::collections::HashSet<_> = buffers.iter().map(|b| b.name).collect();
        assert_eq!(names.len(), buffers.len(), "one entry per buffer");
    }
}
