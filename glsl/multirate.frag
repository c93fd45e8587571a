#version 460
// variants: material_kind polygon_lights textured count_evaluations shadows
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
#if TRIANGLE_IDS || VARIANT_SHADOWS
layout(location = TRIANGLE_ID_LOCATION) flat in uint in_triangle;
#endif
#if VARIANT_SHADOWS
// Each shadow-casting light's interpolated unshadowed shading, by slot (shadow.glsl).
layout(location = SHADOWED_DIFFUSE_LOCATION) in vec3 in_shadowed_diffuse[MAX_SHADOWED_LIGHTS];
layout(location = SHADOWED_SPECULAR_LOCATION) in vec3 in_shadowed_specular[MAX_SHADOWED_LIGHTS];
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
    bool per_pixel = in_level <= 0.0;
    if (per_pixel) {
#if VARIANT_SHADOWS
        ShadowPoint lookup = fragment_shadow_point(in_triangle);
#else
        ShadowPoint lookup = ShadowPoint(vec3(0.0), vec3(0.0), false);
#endif
        float parameter = parameter_at_grad(m, in_uv, duv_dx, duv_dy);
        s = shade_visible(in_position, in_normal, draw.eye.xyz, draw.material_index, parameter, lookup);
        if (COUNT_EVALUATIONS) {
            atomicAdd(counters.pixel_evaluations, 1u);
        }
    }
    vec3 albedo = albedo_at_grad(m, in_uv, duv_dx, duv_dy);
    vec3 color = albedo * s.diffuse + s.specular;
#if VARIANT_SHADOWS
    if (!per_pixel) {
        color += shadowed_lights_color(albedo, in_shadowed_diffuse, in_shadowed_specular,
                                       fragment_triangle(in_triangle), gl_FragCoord.xy);
    }
#endif
    out_color = vec4(heat_map_on() ? heat_color(in_level) : color, 1.0);
#if TRIANGLE_IDS
    write_triangle_id(in_triangle);
#endif
}
