#version 460
// variants: count_evaluations record_levels
// `multirate` mode, `--estimator compute`, first step: one invocation per triangle of a mesh
// (draw.patch_base to draw.patch_base + draw.triangle_count - 1) gives culled triangles
// CULLED_LEVEL and lists the others for triangle_levels.comp (bindings.glsl, visible_triangles
// and visible_counts, which the host zeroes first).
#include "triangle_level.glsl"

layout(local_size_x = 64) in;

void main() {
    uint local = gl_GlobalInvocationID.x;
    if (local >= draw.triangle_count) {
        return;
    }
    uint triangle = draw.patch_base + local;
    vec3 p0 = scene_vec3(scene_indices[3u * triangle], 0u);
    vec3 p1 = scene_vec3(scene_indices[3u * triangle + 1u], 0u);
    vec3 p2 = scene_vec3(scene_indices[3u * triangle + 2u], 0u);
    if (patch_culled(p0, p1, p2)) {
        triangle_levels[triangle] = CULLED_LEVEL;
        if (COUNT_EVALUATIONS) {
            atomicAdd(counters.culled_patches, 1u);
        }
        if (VARIANT_RECORD_LEVELS != 0) {
            level_records[triangle] = CULLED_RECORD;
        }
    } else {
        uint slot = atomicAdd(visible_counts[3u * draw.mesh_index], 1u);
        visible_triangles[draw.patch_base + slot] = triangle;
    }
}
