#version 460
// `multirate` mode: shade the sub-vertices of tessellated triangles; for fallback triangles
// (patch_level 0) pass position and normal on for per-pixel shading instead.
#include "brdf.glsl"

layout(triangles, equal_spacing, ccw) in;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) patch in float patch_level;

layout(location = 0) out vec3 out_color;
layout(location = 1) out vec3 out_position;
layout(location = 2) out vec3 out_normal;
layout(location = 3) flat out float out_level;

// See shade.tese: no fused multiply-adds, so shared edge vertices match bit for bit.
precise gl_Position;

void main() {
    vec3 b = gl_TessCoord;
    precise vec3 position = b.x * in_position[0] + b.y * in_position[1] + b.z * in_position[2];
    vec3 normal = b.x * in_normal[0] + b.y * in_normal[1] + b.z * in_normal[2];
    out_color = vec3(0.0);
    if (patch_level > 0.0) {
        out_color = shade_point(position, normal, draw.eye.xyz, draw.material_index);
        if (COUNT_EVALUATIONS) {
            atomicAdd(counters.subvertex_evaluations, 1u);
        }
    }
    out_position = position;
    out_normal = normal;
    out_level = patch_level;
    gl_Position = draw.view_proj * vec4(position, 1.0);
}
