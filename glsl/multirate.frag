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

// Depth is tested before shading, so only visible fragments fall back (and count).
layout(early_fragment_tests) in;

void main() {
    vec3 color = in_color;
    if (in_level <= 0.0) {
        color = shade_point(in_position, in_normal, draw.eye.xyz, draw.material_index);
        if (COUNT_EVALUATIONS) {
            atomicAdd(counters.pixel_evaluations, 1u);
        }
    }
    out_color = vec4(heat_map_on() ? heat_color(in_level) : color, 1.0);
}
