#version 460
// variants: textured count_evaluations
// `multirate` mode, `--estimator compute`: the compute pre-pass has written the patch levels of
// every visible triangle (patch_levels.comp) and listed it in one of the mesh's patch lists,
// whose tessellated ones are drawn through this stage (multirate_pull.vert); the control stage only reads its levels. The patch is the triangle's
// three vertices.
#include "multirate_patch.glsl"

layout(vertices = 3) out;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) in vec2 in_uv[];
layout(location = 3) in uint in_triangle[];
layout(location = 0) out vec3 out_position[];
layout(location = 1) out vec3 out_normal[];
layout(location = 2) out vec2 out_uv[];

void main() {
    out_position[gl_InvocationID] = in_position[gl_InvocationID];
    out_normal[gl_InvocationID] = in_normal[gl_InvocationID];
    out_uv[gl_InvocationID] = in_uv[gl_InvocationID];
    if (gl_InvocationID == 0) {
        patch_triangle = in_triangle[0];
        if (!drawn_by_class(in_triangle[0])) {
            // The other draw of the list shows this patch (DRAWN_SHADOW_CLASSES, bindings.glsl):
            // levels 0 cull it here, on purpose.
            gl_TessLevelOuter[0] = 0.0;
            gl_TessLevelOuter[1] = 0.0;
            gl_TessLevelOuter[2] = 0.0;
            gl_TessLevelInner[0] = 0.0;
            patch_level = 0.0;
            parameter_lod_bound = 0.0;
            return;
        }
        vec4 tess = patch_tess_levels[in_triangle[0]];
        PatchLevels levels;
        levels.inner = max(tess.x, 1.0);
        levels.outer = tess.yzw;
        levels.fallback = tess.x == 0.0;
        write_patch_levels(levels, material_lod_bound(in_uv[0], in_uv[1], in_uv[2]));
    }
}
