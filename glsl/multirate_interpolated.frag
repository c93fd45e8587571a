#version 460
// variants: textured count_evaluations shadows
// `multirate` mode, `--estimator compute`, the draw of the patches shaded on their sub-vertices
// (without FLAG_FALLBACK_PATCHES): the interpolated vertex shading, its diffuse part times the
// albedo map. The fallback patches are drawn by another draw with multirate.frag. Holding no
// shading code matters where a branch does not skip the code it guards: lavapipe runs both
// sides of every branch under a mask, so multirate.frag costs a per-pixel shading for every
// fragment, and a GPU keeps the registers the fallback branch needs.
#include "texturing.glsl"
#include "heat.glsl"
#include "triangle_id.glsl"

layout(location = 0) in vec3 in_diffuse;
layout(location = 1) in vec3 in_specular;
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

layout(early_fragment_tests) in;

void main() {
    vec2 duv_dx = dFdx(in_uv);
    vec2 duv_dy = dFdy(in_uv);
    vec3 albedo = albedo_at_grad(materials[draw.material_index], in_uv, duv_dx, duv_dy);
    vec3 color = albedo * in_diffuse + in_specular;
#if VARIANT_SHADOWS
    color += shadowed_lights_color(albedo, in_shadowed_diffuse, in_shadowed_specular, fragment_triangle(in_triangle),
                                   gl_FragCoord.xy);
#endif
    out_color = vec4(heat_map_on() ? heat_color(in_level) : color, 1.0);
#if TRIANGLE_IDS
    write_triangle_id(in_triangle);
#endif
}
