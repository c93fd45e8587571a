// The forward passes' resource interface: the per-draw push constants and three descriptor
// sets, declared in binding order. Each binding has a Rust twin of the same name in
// `src/gpu_interface/bindings.rs` (`forward`), which tests/layout.rs checks against the SPIR-V.
#ifndef BINDINGS_GLSL
#define BINDINGS_GLSL
#include "types.glsl"

// The variant's features, defined by build.rs for every module (0 or 1; the material kind in
// brdf.glsl). Each selects code at compile time, so a variant contains only what its scenes use.
#if !defined(VARIANT_POLYGON_LIGHTS) || !defined(VARIANT_TEXTURED) || !defined(VARIANT_COUNT_EVALUATIONS)
#error "build.rs defines the VARIANT_ macros"
#endif

layout(push_constant, std430) uniform Push { DrawConstants draw; };

// DrawConstants.draw_argument by the draw's kind (the 128 bytes of push constants every device
// offers leave no room for a field each): a fixed:N draw's tessellation level, and an emitter
// draw's polygonal light.
uint fixed_level() {
    return draw.draw_argument;
}
uint emitter_light() {
    return draw.draw_argument;
}

// The counting variant (COUNT_EVALUATIONS) adds one to EvaluationCounters for every run of the
// full shading function, by where it ran. The timed variants contain no counting.
const bool COUNT_EVALUATIONS = VARIANT_COUNT_EVALUATIONS != 0;
// The same variant also writes which triangle each pixel shows (triangle_id.glsl), for error
// metrics that compare only pixels where two images show the same triangle
// (src/analysis/metrics.rs). The stage before the fragment stage passes the triangle's scene
// index on at TRIANGLE_ID_LOCATION where it knows it (tessellated and vertex-pulled draws); an
// indexed draw of shared vertices cannot, so its vertex stage passes ID_FROM_PRIMITIVE and the
// fragment stage takes draw.patch_base + gl_PrimitiveID instead.
#define TRIANGLE_IDS (VARIANT_COUNT_EVALUATIONS != 0)
#define TRIANGLE_ID_LOCATION 6
const uint ID_FROM_PRIMITIVE = 0xffffffffu;
const uint EMITTER_ID_BIT = 0x80000000u;

// The workgroup size of the pre-pass's steps (`render::PRE_PASS_GROUP` in Rust; tests/layout.rs
// checks the compiled modules against it).
#define PRE_PASS_GROUP 64

// Set 0: the scene's storage buffers.
layout(set = 0, binding = 0, std430) readonly buffer Lights { GpuLight lights[]; };
layout(set = 0, binding = 1, std430) readonly buffer Materials { GpuMaterial materials[]; };
// Written only by the level-recording pipelines (patch_levels.comp, multirate.tesc): per
// triangle, x = the level it shades at (0: per-pixel fallback), yzw = its outer levels.
layout(set = 0, binding = 2, std430) writeonly buffer LevelRecords { vec4 level_records[]; };
layout(set = 0, binding = 3, std430) buffer EvaluationCounters {
    uint vertex_evaluations;    // vertex mode: triangle vertices (vertex shader)
    uint subvertex_evaluations; // tessellated modes: sub-vertices (evaluation shader)
    uint pixel_evaluations;     // pixel mode, and multirate's per-pixel fallback
    uint culled_patches;        // multirate: triangles culled before their estimate
} counters;
layout(set = 0, binding = 4, std430) readonly buffer PolygonLights { GpuPolygonLight polygon_lights[]; };
// The multirate pass with the estimator in a compute pre-pass (triangle_levels.comp): per
// triangle of the scene its level (triangle_level.glsl) and the triangles across its edges 0,
// 1, 2 (itself where it has none), a texel (w 0) fetched at the cost of two loads where a
// storage buffer's uvec4 takes four; the pre-pass reads the scene's vertices (8 floats each:
// position, normal, uv) and indices.
layout(set = 0, binding = 5, std430) buffer TriangleLevels { float triangle_levels[]; };
layout(set = 0, binding = 6) uniform usamplerBuffer triangle_neighbours;
// The scene's vertices (src/gpu_types.rs `Vertex`: position, normal, uv; 8 floats) as two texels
// each: (position, normal.x), (normal.yz, uv) (scene_position, scene_normal, scene_uv).
layout(set = 0, binding = 7) uniform samplerBuffer scene_vertices;
layout(set = 0, binding = 8, std430) readonly buffer SceneIndices { uint scene_indices[]; };
// The pre-pass's culling step (cull_triangles.comp) lists each mesh's triangles that are not
// culled (mesh: draw.mesh_index): those to estimate from the mesh's first triangle on; from its
// last triangle down, those whose level is known without an estimate, the levels a ball of eyes
// kept and the back faces of a two-sided mesh (BACK_FACE_ENTRY set), so that the later steps'
// invocations run side by side on the triangles they classify or estimate only.
layout(set = 0, binding = 9, std430) buffer VisibleTriangles { uint visible_triangles[]; };
// Per mesh, the patch step's counts of its interpolated and fallback lists (below):
// PATCH_COUNT_WORDS words from patch_counts[PATCH_COUNT_WORDS * patch_list(false)] and
// [.. * patch_list(true)]: the patches listed (LISTED_PATCHES) and the indirect draws they open
// (OPENED_DRAWS, the count a drawIndirectCount draw reads), zeroed by the host.
layout(set = 0, binding = 10, std430) buffer PatchCounts { uint patch_counts[]; };
// The effective levels of the hardware patterns (estimator/patch_levels.glsl, `pattern_level`): Rust's
// `PATTERN_LEVELS` words. A buffer rather than a constant array: lavapipe copies a shader's
// array into every invocation's private memory before the first read.
layout(set = 0, binding = 11, std430) readonly buffer PatternLevels { uint pattern_level_words[]; };
// The pre-pass's last step (patch_levels.comp): per visible triangle the tessellation levels of
// its patch, x = the inner level (0: per-pixel fallback), yzw = the outer levels; and per mesh,
// from its first triangle on, two lists of its tessellated visible triangles, those shaded on
// sub-vertices and those shaded per pixel (counted in patch_counts). Each list is drawn by
// indirect draws of draw.patches_per_draw patches each: the k-th is the VkDrawIndirectCommand at
// entry (first triangle + k) of the list's draws, with vertexCount = 3 per patch; the host
// zeroes them before each pre-pass (instanceCount 0: nothing drawn; the patch step counts those
// it opens in patch_counts, from the first on), and multirate_pull.vert
// turns vertices back into list entries.
layout(set = 0, binding = 12, std430) buffer PatchTessLevels { vec4 patch_tess_levels[]; };
layout(set = 0, binding = 13, std430) buffer InterpolatedPatches { uint interpolated_patches[]; };
layout(set = 0, binding = 14, std430) buffer FallbackPatches { uint fallback_patches[]; };
layout(set = 0, binding = 15, std430) buffer InterpolatedDraws { uvec4 interpolated_draws[]; };
layout(set = 0, binding = 16, std430) buffer FallbackDraws { uvec4 fallback_draws[]; };
// Per mesh, a third list: the visible triangles whose patch is the triangle itself (inner and
// outer levels all 1), drawn without tessellation. Those shaded on their corners, where the
// mesh's material has a parameter map (otherwise flat_indices, below), are listed from the
// mesh's first triangle on and drawn by the mesh's FLAT_LIST_DRAW in flat_draws
// (a VkDrawIndirectCommand: vertexCount = 3 per triangle, counted as they are listed; the host
// zeroes it, and the first entry sets instanceCount to 1). Those shaded per pixel are drawn from
// fallback_indices (below) by its FALLBACK_FLAT_DRAW (a VkDrawIndexedIndirectCommand, likewise;
// the first entry also sets firstIndex). flat_draws holds FLAT_DRAW_WORDS words per mesh.
// multirate_flat.vert shades the corners as the evaluation stage would, or, in the per-pixel
// draw (FLAG_FALLBACK_PATCHES), passes them on for multirate.frag to shade.
layout(set = 0, binding = 17, std430) buffer FlatPatches { uint flat_patches[]; };
layout(set = 0, binding = 18, std430) buffer FlatDraws { uint flat_draws[]; };
// Per mesh, the pre-pass's five indirect dispatches and the lengths of their lists
// (`VkDispatchIndirectCommand` in xyz, the length in w; the host resets each to (0, 1, 1, 0)):
// level_dispatch(RANGE_DISPATCH) of the range step, one workgroup per PRE_PASS_GROUP
// triangles to estimate, w their count; level_dispatch(PATCH_DISPATCH) of the patch step, those
// workgroups first, then one per PRE_PASS_GROUP back faces, w their count; both counted by the
// culling step. level_dispatch(REFINE_DISPATCH) of the refining step over the triangles the
// estimator step lists in refine_triangles, w their count; level_dispatch(FULL_ESTIMATE_DISPATCH)
// of the estimator step over the triangles the range step lists in estimate_triangles, w their
// count; level_dispatch(CAPPED_ESTIMATE_DISPATCH) of its variant without specular code over those
// it lists from the end of the mesh's range down (every light's specular part capped). Only those
// run: on a CPU rasteriser
// every SIMD batch of a workgroup runs the estimator's whole code, returned lanes or not.
layout(set = 0, binding = 19, std430) buffer LevelDispatches { uvec4 level_dispatches[]; };
// The triangles whose estimate is refined (estimator/estimate.glsl, estimate_pass), listed per mesh from
// draw.patch_base on by the estimator step (triangle_levels.comp) for its refining step, so that
// the children's work runs side by side on those triangles only.
layout(set = 0, binding = 20, std430) buffer RefineTriangles { uint refine_triangles[]; };
// The triangles to estimate that the range class does not settle (estimator/range.glsl), listed
// per mesh from draw.patch_base on by the range step (range_levels.comp) for the estimator step;
// those whose every light's specular part is capped from draw.patch_base + draw.triangle_count - 1
// down, for its variant without specular code.
layout(set = 0, binding = 21, std430) buffer EstimateTriangles { uint estimate_triangles[]; };
// Where a mesh's material has no parameter map, its flat patches shaded on their corners are
// drawn instead by one indexed draw of the whole mesh in its own order, from this index buffer:
// three words per scene triangle, the triangle's own vertices where it is such a patch, else
// SKIPPED_VERTEX three times (a point, which the rasteriser drops). Each vertex is shaded once
// however many of those triangles share it (as far as the device reuses vertices), in the same
// order every frame. The culling step writes the culled triangles' words, the patch step the
// others'. (A parameter map makes a corner's shading depend on its triangle's level of detail:
// such a mesh keeps the flat list.)
layout(set = 0, binding = 22, std430) writeonly buffer FlatIndices { uint flat_indices[]; };
// Per triangle of the scene, the level the pre-pass found for it while the eye stays in the
// current ball (the patch step keeps each estimated triangle's), 0 where none yet: the culling
// step reuses it where draw.flags has FLAG_REUSE_LEVELS. The host zeroes it when a ball begins.
// Where levels are held (FLAG_HOLD_LEVELS), the level kept is the one held (level_hold.glsl).
layout(set = 0, binding = 23, std430) buffer EstimatedLevels { float estimated_levels[]; };
// Every mesh's flat patches shaded per pixel, compacted: the patch step appends each one's three
// vertices from the mesh's first index on, and lists the triangle in fallback_patches from the
// end of the mesh's range down (the k-th appended at draw.patch_base + draw.triangle_count - 1 -
// k, below the tessellated fallback patches listed from the start; write_triangle_id reads it).
// Both passes of the per-pixel path draw them indexed (FALLBACK_FLAT_DRAW in flat_draws), each
// vertex transformed once as far as the device reuses vertices, where pulling them from a list
// would transform it once per triangle; a draw covers only those triangles, and none where the
// mesh has none. Whatever the material: nothing is shaded on their corners.
layout(set = 0, binding = 24, std430) writeonly buffer FallbackIndices { uint fallback_indices[]; };
// Per triangle of the meshes, its corners' positions, a texel each (xyz; triangle_corner), the
// first's w its shadow classes (triangle_shadow_classes):
// the culling step reads them in 3 fetches where the indices and the vertices take 12 loads. On
// a CPU rasteriser a load of a lane's own address from a storage buffer is a loop over the
// lanes for each 32-bit word, and a texel fetch gathers four words at about the cost of two
// such loads (docs/notebook/pre_pass_loads.md): most of that step's time was its loads.
layout(set = 0, binding = 25) uniform samplerBuffer triangle_corners;
// The shadow maps (shadow.glsl), six texels each: a directional light's matrix's columns,
// GpuShadowMap.rect, GpuShadowMap.depth (types.glsl); one unread entry where no light casts
// shadows. Texels, not a storage buffer: see shadow_map_rect.
layout(set = 0, binding = 26) uniform samplerBuffer shadow_maps;
// Per triangle of the scene, the multirate pre-pass's hold state (level_hold.glsl, held_level):
// written where a frame holds levels (FLAG_HOLD_LEVELS) and estimates the triangle; the host
// zeroes it when a ball of eyes begins in another configuration than the last.
layout(set = 0, binding = 27, std430) buffer LevelHolds { LevelHold level_holds[]; };
// The index of no vertex, 2^24 - 1 (`SKIPPED_VERTEX` in Rust, Vulkan's least
// maxDrawIndexedIndexValue; render::limits refuses scenes with more vertices):
// multirate_flat.vert shades nothing for it.
const uint SKIPPED_VERTEX = 16777215u;
// Marks a back face among the visible triangles listed from the end of a mesh's range
// (`BACK_FACE_ENTRY` in Rust): the triangle's index with bit 31 set.
const uint BACK_FACE_ENTRY = 2147483648u;

// Scene triangle `triangle`'s words of flat_indices, where the draw's mesh is drawn from them
// (FLAG_SHARED_CORNERS): its vertices where `on_corners` (a flat patch shaded on its corners),
// SKIPPED_VERTEX elsewhere.
void write_flat_corners(uint triangle, bool on_corners) {
    if ((draw.flags & FLAG_SHARED_CORNERS) == 0u) {
        return;
    }
    for (uint corner = 0u; corner < 3u; corner++) {
        flat_indices[3u * triangle + corner] = on_corners ? scene_indices[3u * triangle + corner] : SKIPPED_VERTEX;
    }
}

// The per-mesh slots of the pre-pass's indirect buffers (`src/gpu_interface/slots.rs`).
const uint LEVEL_DISPATCHES = 5u;
// Shadow-casting lights whose unshadowed shading multirate's interpolants carry apart
// (shadow.glsl).
const uint MAX_SHADOWED_LIGHTS = 4u;
const uint SHADOWED_CLASS_BIT = 1u;
const uint MIXED_CLASS_BIT = 16u;
const uint EVERY_SHADOW_CLASS = 0u;
const uint WITHOUT_MIXED_LIGHTS = 1u;
const uint WITH_MIXED_LIGHTS = 2u;
const uint RANGE_DISPATCH = 0u;
const uint PATCH_DISPATCH = 1u;
const uint REFINE_DISPATCH = 2u;
const uint FULL_ESTIMATE_DISPATCH = 3u;
const uint CAPPED_ESTIMATE_DISPATCH = 4u;
const uint PATCH_LISTS = 2u;
const uint INTERPOLATED_LIST = 0u;
const uint FALLBACK_LIST = 1u;
const uint PATCH_COUNT_WORDS = 2u;
const uint LISTED_PATCHES = 0u;
const uint OPENED_DRAWS = 1u;

const uint FLAT_DRAW_WORDS = 12u;
const uint FLAT_LIST_DRAW = 0u;
const uint FALLBACK_FLAT_DRAW = 4u;

// Appends scene triangle `triangle`, a flat patch shaded per pixel, to its mesh's part of
// fallback_indices and fallback_patches, and counts it into the mesh's FALLBACK_FLAT_DRAW.
void append_fallback_flat(uint triangle) {
    uint command = FLAT_DRAW_WORDS * draw.mesh_index + FALLBACK_FLAT_DRAW;
    uint appended = atomicAdd(flat_draws[command], 3u) / 3u;
    uint first_index = 3u * draw.patch_base;
    for (uint corner = 0u; corner < 3u; corner++) {
        fallback_indices[first_index + 3u * appended + corner] = scene_indices[3u * triangle + corner];
    }
    fallback_patches[draw.patch_base + draw.triangle_count - 1u - appended] = triangle;
    if (appended == 0u) {
        // instanceCount and firstIndex; vertexOffset and firstInstance stay the host's zeros.
        flat_draws[command + 1u] = 1u;
        flat_draws[command + 2u] = first_index;
    }
}

uint level_dispatch(uint which) {
    return LEVEL_DISPATCHES * draw.mesh_index + which;
}

// The draw's slot in patch_counts: of its fallback list, or its interpolated one.
uint patch_list(bool fallback) {
    return PATCH_LISTS * draw.mesh_index + (fallback ? FALLBACK_LIST : INTERPOLATED_LIST);
}

// Vertex `vertex`'s position, normal and uv, from its two texels of scene_vertices (a caller
// that reads all three asks for each texel twice; the driver's compiler, which inlines these,
// can merge the equal fetches).
vec3 scene_position(uint vertex) {
    return texelFetch(scene_vertices, int(2u * vertex)).xyz;
}

vec3 scene_normal(uint vertex) {
    return vec3(texelFetch(scene_vertices, int(2u * vertex)).w, texelFetch(scene_vertices, int(2u * vertex + 1u)).xy);
}

// Corner `corner` (0, 1, 2) of scene triangle `triangle`'s position, from triangle_corners.
vec3 triangle_corner(uint triangle, uint corner) {
    return texelFetch(triangle_corners, int(3u * triangle + corner)).xyz;
}

// Scene triangle `triangle`'s visibility classes (src/geometry/shadow_class.rs), a bit each per
// shadow-casting light's slot s: SHADOWED_CLASS_BIT << s where the light reaches none of the
// triangle, MIXED_CLASS_BIT << s where it may reach part; neither: all of it. Kept as a float
// (exact: fewer than 2^24) in the w of the triangle's first texel of triangle_corners.
uint triangle_shadow_classes(uint triangle) {
    return uint(texelFetch(triangle_corners, int(3u * triangle)).w);
}

// Which patches of a list a draw shows by their visibility classes (EVERY_SHADOW_CLASS,
// WITHOUT_MIXED_LIGHTS, WITH_MIXED_LIGHTS): where some light casts shadows, the flat and the
// tessellated lists are each drawn twice, the patches no light reaches only in part by a
// pipeline whose fragment stage looks nothing up (SHADOW_LOOKUPS false, shadow.glsl), the others
// by one that does. llvmpipe runs both sides of every branch, so only a pipeline without the
// lookups' code skips their cost.
layout(constant_id = 19) const uint DRAWN_SHADOW_CLASSES = EVERY_SHADOW_CLASS;

// Whether the draw shows scene triangle `triangle` (DRAWN_SHADOW_CLASSES).
bool drawn_by_class(uint triangle) {
    return DRAWN_SHADOW_CLASSES == EVERY_SHADOW_CLASS
        || (triangle_shadow_classes(triangle) >= MIXED_CLASS_BIT) == (DRAWN_SHADOW_CLASSES == WITH_MIXED_LIGHTS);
}

vec2 scene_uv(uint vertex) {
    return texelFetch(scene_vertices, int(2u * vertex + 1u)).zw;
}

// Set 1: the textures of the draw's material (bound per draw); a white 1x1 texture where the
// material has none. GpuMaterial.maps says which are real.
layout(set = 1, binding = 0) uniform sampler2D albedo_map;
layout(set = 1, binding = 1) uniform sampler2D parameter_map;
// The parameter map's min/max pyramid: per mip level, each texel's (min, max) over its block
// of level-0 texels.
layout(set = 1, binding = 2) uniform sampler2D parameter_pyramid;
// Every shadow map, one depth image (the same in every material's set; shadow.glsl reads it
// with texelFetch).
layout(set = 1, binding = 3) uniform sampler2D shadow_atlas;
// Whether any material of the scene has a texture: without, no texture code is compiled in.
const bool TEXTURED = VARIANT_TEXTURED != 0;

// Set 2, the deferred pass's visibility buffer, is declared by its only reader, deferred.frag.

#endif
