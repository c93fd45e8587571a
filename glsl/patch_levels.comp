#version 460
// `multirate` mode, `--estimator compute`, third step: one invocation per visible triangle of
// a mesh combines its level and its neighbours' (triangle_levels, written by
// triangle_levels.comp) into the tessellation levels of its patch (estimator.glsl,
// `patch_levels`) and writes them to patch_tess_levels, so that the control stage
// (multirate_levels.tesc), which both draws of a mesh run for every patch, only reads them.
#include "triangle_level.glsl"

layout(local_size_x = 64) in;

void main() {
    uint local = gl_GlobalInvocationID.x;
    if (local >= visible_counts[draw.mesh_index]) {
        return;
    }
    uint triangle = visible_triangles[draw.patch_base + local];
    uvec4 across = triangle_neighbours[triangle];
    vec3 neighbours = vec3(triangle_levels[across.x], triangle_levels[across.y], triangle_levels[across.z]);
    PatchLevels levels = patch_levels(triangle_levels[triangle], neighbours, draw.viewport.w);
    patch_tess_levels[triangle] = vec4(levels.fallback ? 0.0 : levels.inner, levels.outer);
}
