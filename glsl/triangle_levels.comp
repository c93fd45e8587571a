#version 460
// variants: material_kind polygon_lights textured
// `multirate` mode, `--estimator compute`, second step: one invocation per triangle to estimate of
// a mesh (listed by cull_triangles.comp) writes its level (triangle_level.glsl) to
// triangle_levels, once per frame, before the forward pass; patch_levels.comp then combines
// each patch's levels and the control stage only reads them. Running over the list rather than over all
// triangles keeps culled triangles and back faces out of the SIMD lanes that run the estimator.
//
// The same module, specialised with REFINE_STEP true, is the refining step between the two: the
// estimator step lists the triangles whose estimate Rust refines (estimate_pass, `refine_next`)
// in refine_triangles, and the refining step estimates those again with their children's ranges
// and writes the level that stands. The children cost about seventeen estimates per light; run
// in the estimator step, every SIMD batch with one such triangle would pay them.
#include "triangle_level.glsl"

layout(local_size_x = PRE_PASS_GROUP) in;
layout(constant_id = 12) const bool REFINE_STEP = false;

void main() {
    uint local = gl_GlobalInvocationID.x;
    if (local >= level_dispatches[level_dispatch(REFINE_STEP ? REFINE_DISPATCH : ESTIMATE_DISPATCH)].w) {
        return;
    }
    uint triangle = REFINE_STEP ? refine_triangles[draw.patch_base + local] : visible_triangles[draw.patch_base + local];
    uint a = scene_indices[3u * triangle];
    uint b = scene_indices[3u * triangle + 1u];
    uint c = scene_indices[3u * triangle + 2u];
    // The culling step gave back faces shaded per pixel their level and did not list them here.
    bool again;
    triangle_levels[triangle] = estimated_level_pass(scene_vec3(a, 0u), scene_vec3(b, 0u), scene_vec3(c, 0u),
                                                     scene_vec3(a, 3u), scene_vec3(b, 3u), scene_vec3(c, 3u),
                                                     scene_uv(a), scene_uv(b), scene_uv(c), REFINE_STEP, again);
    if (again) {
        uint slot = atomicAdd(level_dispatches[level_dispatch(REFINE_DISPATCH)].w, 1u);
        refine_triangles[draw.patch_base + slot] = triangle;
        // Each PRE_PASS_GROUP-th triangle to refine opens one more workgroup of the refining step.
        if (slot % PRE_PASS_GROUP == 0u) {
            atomicAdd(level_dispatches[level_dispatch(REFINE_DISPATCH)].x, 1u);
        }
    }
}
