#version 460
// `multirate` mode, `--estimator compute`: the vertices of one of a mesh's patch lists (the
// pre-pass's interpolated or fallback patches, bindings.glsl), pulled from the scene's buffers:
// vertex 3k + c is corner c of the list's k-th triangle. The triangle's scene index goes to the
// control stage, which reads its levels by it (no gl_PrimitiveID, so draws need no splitting).
#include "bindings.glsl"

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv;
layout(location = 3) flat out uint out_triangle;

void main() {
    uint entry = draw.patch_base + uint(gl_VertexIndex) / 3u;
    bool fallback = (draw.flags & FLAG_FALLBACK_PATCHES) != 0u;
    uint triangle = fallback ? fallback_patches[entry] : interpolated_patches[entry];
    uint vertex = scene_indices[3u * triangle + uint(gl_VertexIndex) % 3u];
    out_position = scene_position(vertex);
    out_normal = scene_normal(vertex);
    out_uv = scene_uv(vertex);
    out_triangle = triangle;
}
