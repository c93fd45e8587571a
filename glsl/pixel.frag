#version 460
// Per-pixel reference shading: the full shading function at every fragment.
// Alpha is geometric coverage (the clear value is 0).
#include "brdf.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(shade_point(in_position, in_normal, draw.eye.xyz, draw.material_index), 1.0);
}
