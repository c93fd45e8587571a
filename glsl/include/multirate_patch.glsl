// The control stages of the multirate pass (multirate.tesc, multirate_levels.tesc): the
// tessellation levels of a triangle's patch.
//
// Both triangles sharing an edge compute both levels from identical inputs with identical
// (precise) code, and the edge's outer level is a symmetric function of the two, so shared edges
// get the same level and no T-junction cracks appear. The inner level is chosen so that the whole
// pattern, including the transition strips next to raised edges, keeps the error bound
// (src/shading/estimator/patch_levels.rs, `pattern_level`). A triangle that cannot be tessellated finely
// enough falls back to per-pixel shading (patch_level = 0) but keeps the edge levels its
// neighbours expect; a culled triangle gets outer level 0 and is not drawn.
#ifndef MULTIRATE_PATCH_GLSL
#define MULTIRATE_PATCH_GLSL
#include "triangle_level.glsl"

layout(location = 3) patch out float patch_level;
layout(location = 4) patch out float parameter_lod_bound;
// The triangle's scene index, for the fragment stage's triangle (triangle_id.glsl): its id in
// the analysis variant, its shadow point (shadow.glsl).
layout(location = 6) patch out uint patch_triangle;

// Writes `levels` (not culled) to the patch, with the triangle's parameter-map lod bound.
void write_patch_levels(PatchLevels levels, float own_lod_bound) {
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
