#version 460
// variants: material_kind polygon_lights textured count_evaluations
// `multirate` mode: the interpolated vertex shading (its diffuse part times the albedo map), or
// full per-pixel shading where the triangle fell back (level 0).
#include "texturing.glsl"
#include "heat.glsl"
#include "triangle_id.glsl"

layout(location = 0) in vec3 in_diffuse;
layout(location = 1) in vec3 in_specular;
layout(location = 2) in vec3 in_position;
layout(location = 3) in vec3 in_normal;
layout(location = 4) in vec2 in_uv;
layout(location = 5) flat in float in_level;
#if TRIANGLE_IDS
layout(location = TRIANGLE_ID_LOCATION) flat in uint in_triangle;
#endif

layout(location = 0) out vec4 out_color;

// Depth is tested before shading, so only visible fragments fall back (and count).
layout(early_fragment_tests) in;

void main() {
    // Derivatives in uniform control flow, before the per-triangle branch.
    vec2 duv_dx = dFdx(in_uv);
    vec2 duv_dy = dFdy(in_uv);
    GpuMaterial m = materials[draw.material_index];
    Shading s = Shading(in_diffuse, in_specular);
    if (in_level <= 0.0) {
        float parameter = parameter_at_grad(m, in_uv, duv_dx, duv_dy);
        s = shade_shadowed(in_position, in_normal, draw.eye.xyz, draw.material_index, parameter);
        if (COUNT_EVALUATIONS) {
            atomicAdd(counters.pixel_evaluations, 1u);
        }
    }
    vec3 color = albedo_at_grad(m, in_uv, duv_dx, duv_dy) * s.diffuse + s.specular;
    out_color = vec4(heat_map_on() ? heat_color(in_level) : color, 1.0);
#if TRIANGLE_IDS
    write_triangle_id(in_triangle);
#endif
}
