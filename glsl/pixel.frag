#version 460
// variants: material_kind polygon_lights textured count_evaluations
// Per-pixel reference shading: the full shading function at every fragment.
// Alpha is geometric coverage (the clear value is 0).
#include "texturing.glsl"
#include "heat.glsl"
#include "triangle_id.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;

layout(location = 0) out vec4 out_color;

// Depth is tested before shading, so only visible fragments shade (and count).
layout(early_fragment_tests) in;

void main() {
    vec2 duv_dx = dFdx(in_uv);
    vec2 duv_dy = dFdy(in_uv);
    vec3 color = heat_color(0.0);
    if (!heat_map_on()) {
        GpuMaterial m = materials[draw.material_index];
        float parameter = parameter_at_grad(m, in_uv, duv_dx, duv_dy);
        ShadowPoint lookup = fragment_shadow_point(ID_FROM_PRIMITIVE);
        Shading s = shade_visible(in_position, in_normal, draw.eye.xyz, draw.material_index, parameter, lookup);
        color = albedo_at_grad(m, in_uv, duv_dx, duv_dy) * s.diffuse + s.specular;
        if (COUNT_EVALUATIONS) {
            atomicAdd(counters.pixel_evaluations, 1u);
        }
    }
    out_color = vec4(color, 1.0);
#if TRIANGLE_IDS
    write_triangle_id(ID_FROM_PRIMITIVE);
#endif
}
