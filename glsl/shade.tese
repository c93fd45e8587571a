#version 460
// variants: material_kind polygon_lights textured count_evaluations
// Tessellated modes: shade every sub-vertex. Position and normal are interpolated linearly over
// the patch (the triangle's own barycentrics, as per-pixel shading sees them); the rasteriser
// then interpolates the shaded colour over each sub-triangle.
#include "texturing.glsl"

// Vulkan's tessellation domain has its origin at the upper left, which mirrors the domain: `cw`
// here emits sub-triangles with the winding of the patch (anticlockwise from the front), so that
// back-face culling treats them as it treats the triangle itself.
layout(triangles, equal_spacing, cw) in;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) in vec2 in_uv[];
layout(location = 0) out vec3 out_diffuse;
layout(location = 1) out vec3 out_specular;
layout(location = 2) out vec2 out_uv;
#if TRIANGLE_IDS
layout(location = TRIANGLE_ID_LOCATION) flat out uint out_triangle;
#endif

// `precise` forbids fused multiply-adds here: a vertex on an edge shared by two patches is then
// computed bit-identically from both sides (one weight is exactly 0, and the sum of the other two
// products commutes), so neighbouring patches meet without cracks.
precise gl_Position;

void main() {
    vec3 b = gl_TessCoord;
    precise vec3 position = b.x * in_position[0] + b.y * in_position[1] + b.z * in_position[2];
    vec3 normal = b.x * in_normal[0] + b.y * in_normal[1] + b.z * in_normal[2];
    vec2 uv = b.x * in_uv[0] + b.y * in_uv[1] + b.z * in_uv[2];
    GpuMaterial m = materials[draw.material_index];
    float parameter = m.params.x;
    if (has_parameter_map(m)) {
        vec3 p[3] = vec3[3](in_position[0], in_position[1], in_position[2]);
        vec2 t[3] = vec2[3](in_uv[0], in_uv[1], in_uv[2]);
        float lod = subvertex_lod(m, p, t, position, gl_TessLevelInner[0], 1.0e30);
        parameter = parameter_at_lod(m, uv, lod);
    }
    Shading s = shade_visible(position, normal, draw.eye.xyz, draw.material_index, parameter,
                               ShadowPoint(position, safe_normalize(normal), true));
    out_diffuse = s.diffuse;
    out_specular = s.specular;
    out_uv = uv;
    if (COUNT_EVALUATIONS) {
        atomicAdd(counters.subvertex_evaluations, 1u);
    }
#if TRIANGLE_IDS
    out_triangle = draw.patch_base + uint(gl_PrimitiveID);
#endif
    gl_Position = draw.view_proj * vec4(position, 1.0);
}
