//! Tests of `render::limits`: every limit check refuses an oversized scene with the resource and the limit named, and the buffer list.

use super::*;

const MIB: u64 = 1 << 20;

fn scene() -> &'static Path {
    Path::new("scenes/test.toml")
}

/// Roomy limits, lowered one at a time by the tests.
fn limits() -> DeviceLimits {
    DeviceLimits {
        max_storage_buffer_range: 1 << 30,
        max_texel_buffer_elements: 1 << 27,
        max_buffer_size: 1 << 32,
        max_memory_allocation_size: 1 << 32,
        max_draw_indexed_index_value: u64::from(u32::MAX),
        max_compute_work_group_count_x: 65535,
        max_draw_indirect_count: u32::MAX,
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
        meshes: vec![MeshSize { triangles }],
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
        shadow_maps: 0,
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
    // Exactly at the limit, the ids fit (what fails then, with vertices that fit too, is the
    // pre-pass's dispatch).
    let at_limit = SceneSizes { vertices: 3, ..sizes(MAX_TRIANGLES) };
    let message = refused(&at_limit, &limits(), "maxComputeWorkGroupCount[0]");
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
fn vertices_beyond_the_skipped_vertex_index_are_refused() {
    let mut at_limit = sizes(1000);
    at_limit.vertices = u64::from(SKIPPED_VERTEX);
    check(scene(), &at_limit, &limits()).expect("indices up to SKIPPED_VERTEX - 1");
    let over = SceneSizes { vertices: at_limit.vertices + 1, ..at_limit };
    let message = refused(&over, &limits(), "skipped-vertex index (16777215");
    assert!(message.contains("its 16777216 vertices"), "{message}");
}

#[test]
fn meshes_beyond_the_pre_pass_workgroups_are_refused() {
    // 576 triangles: 9 workgroups, and one for the triangles whose level the culling step knew.
    let limits = DeviceLimits { max_compute_work_group_count_x: 10, ..limits() };
    check(scene(), &sizes(576), &limits).expect("10 workgroups");
    refused(&sizes(577), &limits, "maxComputeWorkGroupCount[0] (10)");
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
    // 1 MiB holds 65536 entries of 16 bytes a triangle, which overflow first (the vertices,
    // the neighbours and the corners are texel buffers).
    let limits = DeviceLimits { max_storage_buffer_range: MIB, ..limits() };
    check(scene(), &sizes(65536), &limits).expect("65536 triangles: exactly 1 MiB");
    let message = refused(&sizes(65537), &limits, "maxStorageBufferRange (1.0 MiB)");
    assert!(message.contains("\"levels held\" of its 65537 triangles"), "{message}");
}

#[test]
fn texel_buffers_beyond_the_texel_count_are_refused_naming_the_buffer() {
    // The corners take three texels a triangle, the neighbours one, a vertex two.
    let limits = DeviceLimits { max_texel_buffer_elements: 3000, ..limits() };
    let few_vertices = |triangles| SceneSizes { vertices: 100, ..sizes(triangles) };
    check(scene(), &few_vertices(1000), &limits).expect("3000 corner texels: exactly the limit");
    let message = refused(&few_vertices(1001), &limits, "maxTexelBufferElements (3000)");
    assert!(message.contains("\"triangle corners\" of its 1001 triangles (3003 texels)"), "{message}");
    let message = refused(&SceneSizes { vertices: 1501, ..sizes(10) }, &limits, "maxTexelBufferElements");
    assert!(message.contains("\"scene vertices\" of its 1501 vertices (3002 texels)"), "{message}");
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
    let constants = include_str!("../../../glsl/include/estimator/constants.glsl");
    let estimator = include_str!("../../../glsl/include/estimator/estimate.glsl");
    let children = TURNS_PER_LIGHT - 1;
    assert!(constants.contains(&format!("const int REFINE_CHILDREN = {children};")));
    assert!(estimator.contains("int turns = refine ? REFINE_CHILDREN + 1 : 1;"));
    assert!(estimator.contains("int light_turns = (POINT_LIGHT_COUNT + DIRECTIONAL_LIGHT_COUNT) * turns;"));
    assert!(estimator.contains("for (int turn = 0; turn < light_turns + POLYGON_LIGHT_COUNT; ++turn)"));
    let brdf = include_str!("../../../glsl/include/brdf.glsl");
    let lights = include_str!("../../../glsl/include/lights.glsl");
    for count in ["POINT_LIGHT_COUNT", "DIRECTIONAL_LIGHT_COUNT", "POLYGON_LIGHT_COUNT"] {
        let declaration = format!("const int {count} = 0;");
        assert!(brdf.contains(&declaration) || lights.contains(&declaration), "{count} is no int");
    }
    let bindings = include_str!("../../../glsl/include/bindings.glsl");
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

#[test]
fn a_shadow_atlas_wider_than_the_device_allows_is_refused_by_name() {
    let mut over = sizes(10);
    over.shadow_maps = 6;
    over.textures.push(TextureSize {
        name: "shadow atlas".into(),
        width: 2 * limits().max_image_dimension_2d,
        height: 64,
        levels: 1,
        bytes: 4 * 64 * 2 * u64::from(limits().max_image_dimension_2d),
    });
    let message = refused(&over, &limits(), "maxImageDimension2D");
    assert!(message.contains("shadow atlas"), "{message}");
}
