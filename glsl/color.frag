#version 460
// variants: textured count_evaluations
// Writes the colour interpolated from shaded vertices (alpha = coverage), the albedo map
// applied per pixel to the diffuse part; vertex and fixed:N modes (whose level is
// fixed_level()).
#include "texturing.glsl"
#include "heat.glsl"
#include "triangle_id.glsl"

layout(location = 0) in vec3 in_diffuse;
layout(location = 1) in vec3 in_specular;
layout(location = 2) in vec2 in_uv;
#if TRIANGLE_IDS
layout(location = TRIANGLE_ID_LOCATION) flat in uint in_triangle;
#endif
layout(location = 0) out vec4 out_color;

layout(early_fragment_tests) in;

void main() {
    vec2 duv_dx = dFdx(in_uv);
    vec2 duv_dy = dFdy(in_uv);
    vec3 albedo = albedo_at_grad(materials[draw.material_index], in_uv, duv_dx, duv_dy);
    vec3 color = albedo * in_diffuse + in_specular;
    out_color = vec4(heat_map_on() ? heat_color(float(fixed_level())) : color, 1.0);
#if TRIANGLE_IDS
    write_triangle_id(in_triangle);
#endif
}
