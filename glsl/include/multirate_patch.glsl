// The control stages of the multirate pass (multirate.tesc, multirate_levels.tesc): from the
// levels of a triangle and of its three neighbours, the tessellation levels of its patch.
//
// Both triangles sharing an edge compute both levels from identical inputs with identical
// (precise) code, and the edge's outer level is a symmetric function of the two, so shared edges
// get the same level and no T-junction cracks appear. The inner level is chosen so that the whole
// pattern, including the transition strips next to raised edges, keeps the error bound
// (src/shading/estimator.rs, `pattern_level`). A triangle that cannot be tessellated finely
// enough falls back to per-pixel shading (patch_level = 0) but keeps the edge levels its
// neighbours expect; a culled triangle gets outer level 0 and is not drawn.
//
// The compute placement draws each mesh twice: once keeping the patches shaded on their
// sub-vertices (FLAG_INTERPOLATED_PATCHES), whose fragment shader then holds no shading code,
// and once keeping the fallback patches (FLAG_FALLBACK_PATCHES), shaded per pixel. Both draws
// compute the same levels; each gives the other's patches outer level 0.
#ifndef MULTIRATE_PATCH_GLSL
#define MULTIRATE_PATCH_GLSL
#include "triangle_level.glsl"

// The analysis variant records each triangle's levels (bindings.glsl, level_records).
const bool RECORD_LEVELS = VARIANT_RECORD_LEVELS != 0;

layout(location = 3) patch out float patch_level;
layout(location = 4) patch out float parameter_lod_bound;

const uint FLAG_INTERPOLATED_PATCHES = 8u;
const uint FLAG_FALLBACK_PATCHES = 16u;

// Whether this draw is the first (or only) one to see each patch: it counts and records them.
bool first_draw_of_patches() {
    return (draw.flags & FLAG_FALLBACK_PATCHES) == 0u;
}

void cull_patch() {
    gl_TessLevelOuter[0] = 0.0;
    gl_TessLevelOuter[1] = 0.0;
    gl_TessLevelOuter[2] = 0.0;
    gl_TessLevelInner[0] = 0.0;
    patch_level = 0.0;
    parameter_lod_bound = 0.0;
}

void apply_patch_levels(PatchLevels levels, float own_lod_bound, uint triangle);

// Sets the patch's levels for the triangle of scene index `triangle` with level `own`, its
// neighbours' levels across edges 0, 1, 2, and its parameter-map lod bound.
void set_patch_levels(float own, vec3 neighbours, float own_lod_bound, uint triangle) {
    if (own == CULLED_LEVEL) {
        cull_patch();
        if (RECORD_LEVELS && first_draw_of_patches()) {
            level_records[triangle] = vec4(CULLED_LEVEL, 0.0, 0.0, 0.0);
        }
        return;
    }
    apply_patch_levels(patch_levels(own, neighbours, draw.viewport.w), own_lod_bound, triangle);
}

// Sets the patch's levels `levels` (not culled) for the triangle of scene index `triangle`
// with parameter-map lod bound `own_lod_bound`.
void apply_patch_levels(PatchLevels levels, float own_lod_bound, uint triangle) {
    if (RECORD_LEVELS && first_draw_of_patches()) {
        level_records[triangle] = vec4(levels.fallback ? 0.0 : ceil(levels.inner), ceil(levels.outer.x),
                                       ceil(levels.outer.y), ceil(levels.outer.z));
    }
    if ((draw.flags & (levels.fallback ? FLAG_INTERPOLATED_PATCHES : FLAG_FALLBACK_PATCHES)) != 0u) {
        cull_patch();
        return;
    }
    gl_TessLevelOuter[0] = levels.outer.x;
    gl_TessLevelOuter[1] = levels.outer.y;
    gl_TessLevelOuter[2] = levels.outer.z;
    gl_TessLevelInner[0] = levels.inner;
    patch_level = levels.fallback ? 0.0 : ceil(levels.inner);
    // The evaluation stage samples no coarser than this (a little finer than the bound the
    // parameter range covers, for the sampler's fixed-point level of detail).
    GpuMaterial material = materials[draw.material_index];
    parameter_lod_bound = TEXTURED && material.maps.y >= 0 ? own_lod_bound - 0.02 : 0.0;
}

#endif
