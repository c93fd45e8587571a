#version 460
// variants: textured count_evaluations record_levels
// `multirate` mode, `--estimator compute`: the compute pre-pass (triangle_levels.comp) has
// written every triangle's level; the control stage only reads its own and its neighbours'
// (bindings.glsl, triangle_levels and triangle_neighbours) and combines them
// (multirate_patch.glsl). The patch is the triangle's three vertices. Each mesh is drawn twice,
// interpolated patches then fallback patches (multirate_patch.glsl).
#include "multirate_patch.glsl"

layout(vertices = 3) out;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) in vec2 in_uv[];
layout(location = 0) out vec3 out_position[];
layout(location = 1) out vec3 out_normal[];
layout(location = 2) out vec2 out_uv[];

void main() {
    out_position[gl_InvocationID] = in_position[gl_InvocationID];
    out_normal[gl_InvocationID] = in_normal[gl_InvocationID];
    out_uv[gl_InvocationID] = in_uv[gl_InvocationID];
    if (gl_InvocationID == 0) {
        // Note: lavapipe (Mesa 22.3) restarts gl_PrimitiveID every 1020 control points within a
        // draw, so draws there are no longer than that.
        uint triangle = draw.patch_base + uint(gl_PrimitiveID);
        if (COUNT_EVALUATIONS && triangle_levels[triangle] == CULLED_LEVEL && first_draw_of_patches()) {
            atomicAdd(counters.culled_patches, 1u);
        }
        uvec4 across = triangle_neighbours[triangle];
        vec3 neighbours = vec3(triangle_levels[across.x], triangle_levels[across.y], triangle_levels[across.z]);
        set_patch_levels(triangle_levels[triangle], neighbours,
                         material_lod_bound(in_uv[0], in_uv[1], in_uv[2]), triangle);
    }
}
