#version 460
// Writes the colour interpolated from shaded vertices (alpha = coverage); vertex and fixed:N
// modes (whose level is draw.fixed_level).
#include "heat.glsl"

layout(location = 0) in vec3 in_color;
layout(location = 0) out vec4 out_color;

layout(early_fragment_tests) in;

void main() {
    out_color = vec4(heat_map_on() ? heat_color(float(draw.fixed_level)) : in_color, 1.0);
}
