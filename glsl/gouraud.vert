#version 460
// variants: material_kind polygon_lights textured count_evaluations
// `vertex` mode: shade the triangle's own vertices (Gouraud); the rasteriser interpolates.
#include "texturing.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;

layout(location = 0) out vec3 out_diffuse;
layout(location = 1) out vec3 out_specular;
layout(location = 2) out vec2 out_uv;
#if TRIANGLE_IDS
layout(location = TRIANGLE_ID_LOCATION) flat out uint out_triangle;
#endif

void main() {
    float parameter = parameter_at_lod(materials[draw.material_index], in_uv, 0.0);
    Shading s = shade_visible(in_position, in_normal, draw.eye.xyz, draw.material_index, parameter,
                               ShadowPoint(in_position, safe_normalize(in_normal), true));
    out_diffuse = s.diffuse;
    out_specular = s.specular;
    out_uv = in_uv;
    if (COUNT_EVALUATIONS) {
        atomicAdd(counters.vertex_evaluations, 1u);
    }
#if TRIANGLE_IDS
    // Vertices are shared between triangles: the fragment stage counts primitives.
    out_triangle = ID_FROM_PRIMITIVE;
#endif
    gl_Position = draw.view_proj * vec4(in_position, 1.0);
}
