#version 460
// Tessellated modes: shade every sub-vertex. Position and normal are interpolated linearly over
// the patch (the triangle's own barycentrics, as per-pixel shading sees them); the rasteriser
// then interpolates the shaded colour over each sub-triangle.
#include "brdf.glsl"

layout(triangles, equal_spacing, ccw) in;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 0) out vec3 out_color;

// `precise` forbids fused multiply-adds here: a vertex on an edge shared by two patches is then
// computed bit-identically from both sides (one weight is exactly 0, and the sum of the other two
// products commutes), so neighbouring patches meet without cracks.
precise gl_Position;

void main() {
    vec3 b = gl_TessCoord;
    precise vec3 position = b.x * in_position[0] + b.y * in_position[1] + b.z * in_position[2];
    vec3 normal = b.x * in_normal[0] + b.y * in_normal[1] + b.z * in_normal[2];
    out_color = shade_point(position, normal, draw.eye.xyz, draw.material_index);
    if (COUNT_EVALUATIONS) {
        atomicAdd(counters.subvertex_evaluations, 1u);
    }
    gl_Position = draw.view_proj * vec4(position, 1.0);
}
