#version 460
// `multirate` mode: the interpolated vertex shading, or full per-pixel shading where the
// triangle fell back (level 0).
#include "brdf.glsl"
#include "heat.glsl"

layout(location = 0) in vec3 in_color;
layout(location = 1) in vec3 in_position;
layout(location = 2) in vec3 in_normal;
layout(location = 3) flat in float in_level;

layout(location = 0) out vec4 out_color;

void main() {
    vec3 color = in_level > 0.0
        ? in_color
        : shade_point(in_position, in_normal, draw.eye.xyz, draw.material_index);
    out_color = vec4(heat_map_on() ? heat_color(in_level) : color, 1.0);
}
