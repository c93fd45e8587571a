#version 460
// variants: material_kind polygon_lights textured count_evaluations shadows
// `multirate` mode: shade the sub-vertices of tessellated triangles; for fallback triangles
// (patch_level 0) pass position, normal and texture coordinates on for per-pixel shading.
#include "texturing.glsl"

// Vulkan's tessellation domain has its origin at the upper left, which mirrors the domain: `cw`
// here emits sub-triangles with the winding of the patch (anticlockwise from the front), so that
// back-face culling treats them as it treats the triangle itself.
layout(triangles, equal_spacing, cw) in;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) in vec2 in_uv[];
layout(location = 3) patch in float patch_level;
layout(location = 4) patch in float parameter_lod_bound;
#if TRIANGLE_IDS || VARIANT_SHADOWS
layout(location = 6) patch in uint patch_triangle;
#endif

layout(location = 0) out vec3 out_diffuse;
layout(location = 1) out vec3 out_specular;
layout(location = 2) out vec3 out_position;
layout(location = 3) out vec3 out_normal;
layout(location = 4) out vec2 out_uv;
layout(location = 5) flat out float out_level;
#if TRIANGLE_IDS || VARIANT_SHADOWS
layout(location = TRIANGLE_ID_LOCATION) flat out uint out_triangle;
#endif
#if VARIANT_SHADOWS
// Each shadow-casting light's unshadowed shading, by slot (shadow.glsl).
layout(location = SHADOWED_DIFFUSE_LOCATION) out vec3 out_shadowed_diffuse[MAX_SHADOWED_LIGHTS];
layout(location = SHADOWED_SPECULAR_LOCATION) out vec3 out_shadowed_specular[MAX_SHADOWED_LIGHTS];
#endif

// See shade.tese: no fused multiply-adds, so shared edge vertices match bit for bit.
precise gl_Position;

void main() {
    vec3 b = gl_TessCoord;
    precise vec3 position = b.x * in_position[0] + b.y * in_position[1] + b.z * in_position[2];
    vec3 normal = b.x * in_normal[0] + b.y * in_normal[1] + b.z * in_normal[2];
    vec2 uv = b.x * in_uv[0] + b.y * in_uv[1] + b.z * in_uv[2];
    out_diffuse = vec3(0.0);
    out_specular = vec3(0.0);
    Shading apart[MAX_SHADOWED_LIGHTS] = no_shading_apart();
    if (patch_level > 0.0) {
        GpuMaterial m = materials[draw.material_index];
        float parameter = m.params.x;
        if (has_parameter_map(m)) {
            vec3 p[3] = vec3[3](in_position[0], in_position[1], in_position[2]);
            vec2 t[3] = vec2[3](in_uv[0], in_uv[1], in_uv[2]);
            float lod = subvertex_lod(m, p, t, position, gl_TessLevelInner[0], parameter_lod_bound);
            parameter = parameter_at_lod(m, uv, lod);
        }
#if VARIANT_SHADOWS
        uint classes = triangle_shadow_classes(patch_triangle);
        Shading s = shade_split(position, normal, draw.eye.xyz, draw.material_index, parameter, classes, apart);
#else
        Shading s = shade(position, normal, draw.eye.xyz, draw.material_index, parameter);
#endif
        out_diffuse = s.diffuse;
        out_specular = s.specular;
        if (COUNT_EVALUATIONS) {
            atomicAdd(counters.subvertex_evaluations, 1u);
        }
    }
    out_position = position;
    out_normal = normal;
    out_uv = uv;
    out_level = patch_level;
#if TRIANGLE_IDS || VARIANT_SHADOWS
    out_triangle = patch_triangle;
#endif
#if VARIANT_SHADOWS
    for (uint k = 0u; k < MAX_SHADOWED_LIGHTS; ++k) {
        out_shadowed_diffuse[k] = apart[k].diffuse;
        out_shadowed_specular[k] = apart[k].specular;
    }
#endif
    gl_Position = draw.view_proj * vec4(position, 1.0);
}
