#version 460
// variants: material_kind polygon_lights textured
// `multirate` mode, `--estimator compute`, second step: one invocation per triangle to estimate of
// a mesh (listed by cull_triangles.comp) writes its level (triangle_level.glsl) to
// triangle_levels, once per frame, before the forward pass; patch_levels.comp then combines
// each patch's levels and the control stage only reads them. Running over the list rather than over all
// triangles keeps culled triangles and back faces out of the SIMD lanes that run the estimator.
#include "triangle_level.glsl"

layout(local_size_x = PRE_PASS_GROUP) in;

void main() {
    uint local = gl_GlobalInvocationID.x;
    if (local >= level_dispatches[2u * draw.mesh_index].w) {
        return;
    }
    uint triangle = visible_triangles[draw.patch_base + local];
    uint a = scene_indices[3u * triangle];
    uint b = scene_indices[3u * triangle + 1u];
    uint c = scene_indices[3u * triangle + 2u];
    // The culling step gave back faces shaded per pixel their level and did not list them here.
    triangle_levels[triangle] = estimated_level(scene_vec3(a, 0u), scene_vec3(b, 0u), scene_vec3(c, 0u),
                                                scene_vec3(a, 3u), scene_vec3(b, 3u), scene_vec3(c, 3u),
                                                scene_uv(a), scene_uv(b), scene_uv(c));
}
