#version 460
// variants: count_evaluations record_levels
// `multirate` mode, `--estimator compute`, first step: one invocation per triangle of a mesh
// (draw.patch_base to draw.patch_base + draw.triangle_count - 1) gives culled triangles
// CULLED_LEVEL, and lists the others (bindings.glsl, visible_triangles): those to classify and
// estimate from the mesh's first triangle on, for range_levels.comp; from its last triangle down,
// those whose level is known without: where the host reuses levels (FLAG_REUSE_LEVELS), a
// triangle with one from earlier frames of the current ball of eyes (estimated_levels) takes it
// here, and the back faces of a two-sided mesh (triangle_level.glsl, back_face_per_pixel), shaded
// per pixel without an estimate, take FALLBACK_LEVEL (listed with BACK_FACE_ENTRY). Only the
// patch step covers those. It counts both lists and the workgroups of the later steps that
// cover them in level_dispatches, which the host resets first. A culled triangle's words of the
// flat patches' index buffers skip it.
#include "triangle_level.glsl"

layout(local_size_x = PRE_PASS_GROUP) in;

// Lists a visible triangle whose level is known (`entry`: its index, with BACK_FACE_ENTRY for a
// back face) from the end of the mesh's range down, for the patch step only.
void list_known(uint entry) {
    uint known = atomicAdd(level_dispatches[level_dispatch(PATCH_DISPATCH)].w, 1u);
    visible_triangles[draw.patch_base + draw.triangle_count - 1u - known] = entry;
    // Each PRE_PASS_GROUP-th of them opens one more workgroup of the patch step.
    if (known % PRE_PASS_GROUP == 0u) {
        atomicAdd(level_dispatches[level_dispatch(PATCH_DISPATCH)].x, 1u);
    }
}

void main() {
    uint local = gl_GlobalInvocationID.x;
    if (local >= draw.triangle_count) {
        return;
    }
    uint triangle = draw.patch_base + local;
    vec3 p0 = triangle_corner(triangle, 0u);
    vec3 p1 = triangle_corner(triangle, 1u);
    vec3 p2 = triangle_corner(triangle, 2u);
    if (patch_culled(p0, p1, p2)) {
        triangle_levels[triangle] = CULLED_LEVEL;
        write_flat_corners(triangle, false);
        if (COUNT_EVALUATIONS) {
            atomicAdd(counters.culled_patches, 1u);
        }
        if (VARIANT_RECORD_LEVELS != 0) {
            level_records[triangle] = CULLED_RECORD;
        }
    } else if (back_face_per_pixel(p0, p1, p2)) {
        triangle_levels[triangle] = FALLBACK_LEVEL;
        list_known(triangle | BACK_FACE_ENTRY);
    } else if ((draw.flags & FLAG_REUSE_LEVELS) != 0u && estimated_levels[triangle] > 0.0) {
        // A level found earlier in the current ball of eyes holds for this frame's eye.
        triangle_levels[triangle] = estimated_levels[triangle];
        list_known(triangle);
    } else {
        uint slot = atomicAdd(level_dispatches[level_dispatch(RANGE_DISPATCH)].w, 1u);
        visible_triangles[draw.patch_base + slot] = triangle;
        // Each PRE_PASS_GROUP-th triangle to classify opens one more workgroup of both steps.
        if (slot % PRE_PASS_GROUP == 0u) {
            atomicAdd(level_dispatches[level_dispatch(RANGE_DISPATCH)].x, 1u);
            atomicAdd(level_dispatches[level_dispatch(PATCH_DISPATCH)].x, 1u);
        }
    }
}
