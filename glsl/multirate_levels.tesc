#version 460
// variants: textured count_evaluations record_levels
// `multirate` mode, `--estimator compute`: the compute pre-pass has culled the triangles
// (triangle_levels = CULLED_LEVEL) and written the patch levels of the others
// (patch_levels.comp); the control stage only reads them (bindings.glsl). The patch is the
// triangle's three vertices. Each mesh is drawn twice, interpolated patches then fallback
// patches (multirate_patch.glsl).
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
        if (triangle_levels[triangle] == CULLED_LEVEL) {
            if (COUNT_EVALUATIONS && first_draw_of_patches()) {
                atomicAdd(counters.culled_patches, 1u);
            }
            set_patch_levels(CULLED_LEVEL, vec3(CULLED_LEVEL), 0.0, triangle);
            return;
        }
        vec4 tess = patch_tess_levels[triangle];
        PatchLevels levels;
        levels.inner = max(tess.x, 1.0);
        levels.outer = tess.yzw;
        levels.fallback = tess.x == 0.0;
        apply_patch_levels(levels, material_lod_bound(in_uv[0], in_uv[1], in_uv[2]), triangle);
    }
}
