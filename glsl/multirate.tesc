#version 460
// `multirate` mode: estimate, per triangle, the real-valued level that keeps the interpolation
// error under epsilon (glsl/include/estimator.glsl, the port of src/shading/estimator.rs), and
// tessellate with the levels the combination rule `patch_levels` derives from it.
//
// The patch holds 12 control points: the triangle, then for each edge k (the edge of
// gl_TessLevelOuter[k], opposite vertex k) the neighbouring triangle across it, in that
// triangle's own vertex order (src/scene/adjacency.rs). Both triangles sharing an edge compute
// both levels from identical inputs with identical (precise) code, and the edge's outer level
// is a symmetric function of the two, so shared edges get the same level and no T-junction
// cracks appear. The inner level is chosen so that the whole pattern, including the transition
// strips next to raised edges, keeps the error bound (src/shading/estimator.rs,
// `pattern_level`). A triangle that cannot be tessellated finely enough falls back to
// per-pixel shading (patch_level = 0) but keeps the edge levels its neighbours expect.
#include "estimator.glsl"

// The analysis variant also records each triangle's levels (bindings.glsl, level_records).
layout(constant_id = 5) const bool RECORD_LEVELS = false;

layout(vertices = 3) out;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 0) out vec3 out_position[];
layout(location = 1) out vec3 out_normal[];
layout(location = 2) patch out float patch_level;

void main() {
    out_position[gl_InvocationID] = in_position[gl_InvocationID];
    out_normal[gl_InvocationID] = in_normal[gl_InvocationID];
    if (gl_InvocationID == 0) {
        // The triangle itself (t = 0) and its neighbours across edges 0, 1, 2.
        float levels[4];
        for (int t = 0; t < 4; ++t) {
            int first = 3 * t;
            levels[t] = required_level(
                in_position[first], in_position[first + 1], in_position[first + 2],
                in_normal[first], in_normal[first + 1], in_normal[first + 2],
                draw.eye.xyz, draw.material_index, vec2(materials[draw.material_index].params.x),
                draw.viewport.z, draw.viewport.w);
        }
        PatchLevels levels_of_patch =
            patch_levels(levels[0], vec3(levels[1], levels[2], levels[3]), draw.viewport.w);
        gl_TessLevelOuter[0] = levels_of_patch.outer.x;
        gl_TessLevelOuter[1] = levels_of_patch.outer.y;
        gl_TessLevelOuter[2] = levels_of_patch.outer.z;
        gl_TessLevelInner[0] = levels_of_patch.inner;
        patch_level = levels_of_patch.fallback ? 0.0 : ceil(levels_of_patch.inner);
        if (RECORD_LEVELS) {
            // Note: lavapipe (Mesa 22.3) restarts gl_PrimitiveID every 85 twelve-point patches
            // within a draw, so the recording draws must not be longer than that there.
            level_records[draw.patch_base + uint(gl_PrimitiveID)] = vec4(patch_level,
                ceil(levels_of_patch.outer.x), ceil(levels_of_patch.outer.y),
                ceil(levels_of_patch.outer.z));
        }
    }
}
