#version 460
// variants: material_kind polygon_lights textured count_evaluations
// `multirate` mode, `--estimator compute`: one invocation per triangle of a mesh writes its
// level (triangle_level.glsl) to triangle_levels, once per frame, before the forward pass; the
// control stage (multirate_levels.tesc) then only combines levels. The dispatch covers the draw's
// triangles draw.patch_base to draw.patch_base + draw.triangle_count - 1.
#include "triangle_level.glsl"

layout(local_size_x = 64) in;

// One Vertex (src/gpu_types.rs): position, normal, uv.
const uint VERTEX_FLOATS = 8u;

vec3 scene_vec3(uint vertex, uint offset) {
    uint base = vertex * VERTEX_FLOATS + offset;
    return vec3(scene_vertices[base], scene_vertices[base + 1u], scene_vertices[base + 2u]);
}

vec2 scene_uv(uint vertex) {
    uint base = vertex * VERTEX_FLOATS + 6u;
    return vec2(scene_vertices[base], scene_vertices[base + 1u]);
}

void main() {
    uint local = gl_GlobalInvocationID.x;
    if (local >= draw.triangle_count) {
        return;
    }
    uint triangle = draw.patch_base + local;
    uint a = scene_indices[3u * triangle];
    uint b = scene_indices[3u * triangle + 1u];
    uint c = scene_indices[3u * triangle + 2u];
    float level = triangle_level(scene_vec3(a, 0u), scene_vec3(b, 0u), scene_vec3(c, 0u),
                                 scene_vec3(a, 3u), scene_vec3(b, 3u), scene_vec3(c, 3u),
                                 scene_uv(a), scene_uv(b), scene_uv(c));
    triangle_levels[triangle] = level;
    if (COUNT_EVALUATIONS && level == CULLED_LEVEL) {
        atomicAdd(counters.culled_patches, 1u);
    }
}
