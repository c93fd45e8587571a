#version 460
// variants: material_kind polygon_lights textured count_evaluations record_levels
// `multirate` mode, `--estimator tcs`: the control stage estimates the levels itself.
//
// The patch holds 12 control points: the triangle, then for each edge k (the edge of
// gl_TessLevelOuter[k], opposite vertex k) the neighbouring triangle across it, in that
// triangle's own vertex order (src/scene/adjacency.rs). The four estimates are spread over four
// invocations, one triangle each (triangle_level.glsl), and shared through the per-vertex output
// `neighbourhood_level` after a barrier; invocation 0 then combines them (multirate_patch.glsl).
#include "multirate_patch.glsl"

layout(vertices = 4) out;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) in vec2 in_uv[];
layout(location = 0) out vec3 out_position[];
layout(location = 1) out vec3 out_normal[];
layout(location = 2) out vec2 out_uv[];
// Per invocation t: the level of triangle t (0: the patch's own, 1 to 3: across edges 0 to 2).
layout(location = 5) out float neighbourhood_level[];

void main() {
    int t = gl_InvocationID;
    // Control points 0 to 2 are the triangle the evaluation stage tessellates; the fourth only
    // carries its invocation's estimate.
    out_position[gl_InvocationID] = in_position[t];
    out_normal[gl_InvocationID] = in_normal[t];
    out_uv[gl_InvocationID] = in_uv[t];
    int first = 3 * t;
    neighbourhood_level[gl_InvocationID] = triangle_level(in_position[first], in_position[first + 1], in_position[first + 2],
                                        in_normal[first], in_normal[first + 1], in_normal[first + 2],
                                        in_uv[first], in_uv[first + 1], in_uv[first + 2]);
    barrier();
    if (t == 0) {
        float own = neighbourhood_level[0];
        if (COUNT_EVALUATIONS && own == CULLED_LEVEL) {
            atomicAdd(counters.culled_patches, 1u);
        }
        // Note: lavapipe (Mesa 22.3) restarts gl_PrimitiveID every 1020 control points within a
        // draw, so the recording draws must not be longer than that there.
        set_patch_levels(own, vec3(neighbourhood_level[1], neighbourhood_level[2], neighbourhood_level[3]),
                         material_lod_bound(in_uv[0], in_uv[1], in_uv[2]),
                         draw.patch_base + uint(gl_PrimitiveID));
#if TRIANGLE_IDS
        patch_triangle = draw.patch_base + uint(gl_PrimitiveID);
#endif
    }
}
