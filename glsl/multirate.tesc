#version 460
// variants: material_kind polygon_lights textured count_evaluations
// `multirate` mode, `--estimator tcs`: the control stage estimates the levels itself.
//
// The patch holds 12 control points: the triangle, then for each edge k (the edge of
// gl_TessLevelOuter[k], opposite vertex k) the neighbouring triangle across it, in that
// triangle's own vertex order (src/scene/adjacency.rs). The four estimates are spread over four
// invocations, one triangle each (triangle_level.glsl), and shared through the per-vertex output
// `neighbourhood_level` after a barrier; invocation 0 then combines them (multirate_patch.glsl).
//
// Its analysis pipelines share one instrumented module (the `count_evaluations` variant, which
// also passes each triangle's index on): whether it records the levels or counts the culled
// patches is a specialization constant. Both are a store or an atomic beside the estimator,
// the whole of this stage; as separate variants they made three copies of the build's largest
// stage. The timed module keeps neither: lavapipe ran the code specialised off (a quarter
// slower on the bunny).
#include "multirate_patch.glsl"

#if TRIANGLE_IDS
// The level-recording pipeline writes each triangle's levels (bindings.glsl, level_records).
layout(constant_id = 14) const bool RECORD_LEVELS = false;
// The counting pipeline counts the patches culled before their estimate.
layout(constant_id = 15) const bool COUNT_CULLED_PATCHES = false;
#else
const bool RECORD_LEVELS = false;
const bool COUNT_CULLED_PATCHES = false;
#endif

layout(vertices = 4) out;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) in vec2 in_uv[];
layout(location = 0) out vec3 out_position[];
layout(location = 1) out vec3 out_normal[];
layout(location = 2) out vec2 out_uv[];
// Per invocation t: the level of triangle t (0: the patch's own, 1 to 3: across edges 0 to 2).
layout(location = 5) out float neighbourhood_level[];

// Sets the patch's levels for the triangle of scene index `triangle` with level `own`, its
// neighbours' levels across edges 0, 1, 2, and its parameter-map lod bound.
void set_patch_levels(float own, vec3 neighbours, float own_lod_bound, uint triangle) {
    if (own == CULLED_LEVEL) {
        gl_TessLevelOuter[0] = 0.0;
        gl_TessLevelOuter[1] = 0.0;
        gl_TessLevelOuter[2] = 0.0;
        gl_TessLevelInner[0] = 0.0;
        patch_level = 0.0;
        parameter_lod_bound = 0.0;
        if (RECORD_LEVELS) {
            level_records[triangle] = CULLED_RECORD;
        }
        return;
    }
    PatchLevels levels = patch_levels(own, neighbours, float(draw.n_max));
    write_patch_levels(levels, own_lod_bound);
    if (RECORD_LEVELS) {
        level_records[triangle] = level_record(levels);
    }
}

void main() {
    int t = gl_InvocationID;
    // Control points 0 to 2 are the triangle the evaluation stage tessellates; the fourth only
    // carries its invocation's estimate.
    out_position[gl_InvocationID] = in_position[t];
    out_normal[gl_InvocationID] = in_normal[t];
    out_uv[gl_InvocationID] = in_uv[t];
    int first = 3 * t;
    uint triangle = draw.patch_base + uint(gl_PrimitiveID);
    // The estimate of a neighbour leaves out the lights that reach none of the neighbour, as the
    // neighbour's own patch does: both sides of a shared edge then take the same level.
    if (SHADOWS && t > 0) {
        triangle = texelFetch(triangle_neighbours, int(triangle))[t - 1];
    }
    neighbourhood_level[gl_InvocationID] = triangle_level(in_position[first], in_position[first + 1], in_position[first + 2],
                                        in_normal[first], in_normal[first + 1], in_normal[first + 2],
                                        in_uv[first], in_uv[first + 1], in_uv[first + 2],
                                        estimated_classes(triangle));
    barrier();
    if (t == 0) {
        float own = neighbourhood_level[0];
        if (COUNT_CULLED_PATCHES && own == CULLED_LEVEL) {
            atomicAdd(counters.culled_patches, 1u);
        }
        // Note: lavapipe (Mesa 22.3) restarts gl_PrimitiveID every 1020 control points within a
        // draw, so the recording draws must not be longer than that there.
        set_patch_levels(own, vec3(neighbourhood_level[1], neighbourhood_level[2], neighbourhood_level[3]),
                         material_lod_bound(in_uv[0], in_uv[1], in_uv[2]),
                         draw.patch_base + uint(gl_PrimitiveID));
        patch_triangle = draw.patch_base + uint(gl_PrimitiveID);
    }
}
