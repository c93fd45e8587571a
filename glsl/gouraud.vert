#version 460
// `vertex` mode: shade the triangle's own vertices (Gouraud); the rasteriser interpolates.
#include "brdf.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 out_color;

void main() {
    out_color = shade_point(in_position, in_normal, draw.eye.xyz, draw.material_index);
    if (COUNT_EVALUATIONS) {
        atomicAdd(counters.vertex_evaluations, 1u);
    }
    gl_Position = draw.view_proj * vec4(in_position, 1.0);
}
