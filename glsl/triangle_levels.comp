#version 460
// variants: material_kind polygon_lights textured
// `multirate` mode, `--estimator compute`, the estimator step: one invocation per triangle to estimate of a
// mesh that the range class does not settle (listed by range_levels.comp) writes its level
// (triangle_level.glsl) to triangle_levels, once per frame, before the forward pass;
// patch_levels.comp then combines each patch's levels and the control stage only reads them.
// Running over the list rather than over all triangles keeps culled triangles and back faces out of
// the SIMD lanes that run the estimator.
//
// It lists the triangles whose estimate Rust refines (estimate_pass, `refine_next`) in
// refine_triangles for the refining step (refine_levels.comp), which estimates those again with
// their children's ranges and writes the level that stands. The children cost about five
// estimates per light; run here, every SIMD batch with one such triangle would pay them, and
// the estimator's code would be in this module twice (the children's turns have their own call).
#include "triangle_level.glsl"

layout(local_size_x = PRE_PASS_GROUP) in;

// Listed triangles per workgroup of the refining step (refine_levels.comp, `render::REFINE_BLOCK`),
// and its most workgroups (the least maxComputeWorkGroupCount[0] Vulkan allows).
const uint REFINE_BLOCK = 8u;
const uint REFINE_MAX_GROUPS = 65535u;

void main() {
    uint local = gl_GlobalInvocationID.x;
    // The variant without specular code (SPECULAR_ALL_CAPPED) takes the range step's second list,
    // from the end of the mesh's range down.
    uint list = SPECULAR_ALL_CAPPED ? CAPPED_ESTIMATE_DISPATCH : FULL_ESTIMATE_DISPATCH;
    if (local >= level_dispatches[level_dispatch(list)].w) {
        return;
    }
    uint at = SPECULAR_ALL_CAPPED ? draw.triangle_count - 1u - local : local;
    uint triangle = estimate_triangles[draw.patch_base + at];
    uint a = scene_indices[3u * triangle];
    uint b = scene_indices[3u * triangle + 1u];
    uint c = scene_indices[3u * triangle + 2u];
    // The culling step gave back faces shaded per pixel their level, and the range step the
    // triangles it settles; neither is listed here.
    bool again;
    float level = estimated_level_pass(scene_position(a), scene_position(b), scene_position(c), scene_normal(a),
                                       scene_normal(b), scene_normal(c), scene_uv(a), scene_uv(b), scene_uv(c),
                                       estimated_classes(triangle), SPECULAR_ALL_CAPPED, false, again);
    // A triangle to refine is held once, at the level the refining step finds for it.
    triangle_levels[triangle] = again ? level : held_level(triangle, level);
    if (again) {
        uint slot = atomicAdd(level_dispatches[level_dispatch(REFINE_DISPATCH)].w, 1u);
        refine_triangles[draw.patch_base + slot] = triangle;
        // Each REFINE_BLOCK-th triangle to refine opens one more workgroup of the refining step,
        // up to REFINE_MAX_GROUPS (which then take several blocks each).
        if (slot % REFINE_BLOCK == 0u && slot / REFINE_BLOCK < REFINE_MAX_GROUPS) {
            atomicAdd(level_dispatches[level_dispatch(REFINE_DISPATCH)].x, 1u);
        }
    }
}
