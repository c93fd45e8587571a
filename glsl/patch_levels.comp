#version 460
// variants: record_levels
// `multirate` mode, `--estimator compute`, the patch step (the last): one invocation per visible triangle of
// a mesh combines its level and its neighbours' (triangle_levels, written by
// triangle_levels.comp) into the tessellation levels of its patch (estimator/patch_levels.glsl,
// `patch_levels`), writes them to patch_tess_levels, and puts the triangle where its draw finds
// it (bindings.glsl): a flat patch (all levels 1, drawn without tessellation) in the flat
// patches' index buffers (appended to fallback_indices where it is shaded per pixel), or the
// flat list where its mesh's parameter map keeps it from flat_indices; a tessellated one in the
// interpolated or the fallback list, counting it into the indirect draw that covers its slot. A back face of a two-sided mesh goes to a list
// only where a neighbour's edge is tessellated (its outer levels must match it): the others are
// drawn by the mesh's back-face draw, as `pixel` mode draws them (`Renderer::record_mesh`). The
// control stage (multirate_levels.tesc) only reads the levels.
#include "triangle_level.glsl"

layout(local_size_x = PRE_PASS_GROUP) in;

// Whether this invocation's workgroup covers the triangles whose level the culling step knew
// (cull_triangles.comp): the workgroups of the classified triangles come first, then those of
// the kept levels and the back faces, listed from the end.
bool covers_known_levels() {
    return gl_WorkGroupID.x >= level_dispatches[level_dispatch(RANGE_DISPATCH)].x;
}

// The list entry this invocation covers (a triangle, with BACK_FACE_ENTRY for a back face); ~0u
// past its list's count.
uint listed_entry(bool known_levels) {
    if (!known_levels) {
        uint local = gl_GlobalInvocationID.x;
        uint estimated = level_dispatches[level_dispatch(RANGE_DISPATCH)].w;
        return local < estimated ? visible_triangles[draw.patch_base + local] : ~0u;
    }
    uint first = level_dispatches[level_dispatch(RANGE_DISPATCH)].x;
    uint back = (gl_WorkGroupID.x - first) * PRE_PASS_GROUP + gl_LocalInvocationID.x;
    return back < level_dispatches[level_dispatch(PATCH_DISPATCH)].w
        ? visible_triangles[draw.patch_base + draw.triangle_count - 1u - back]
        : ~0u;
}

void main() {
    bool known_level = covers_known_levels();
    uint entry = listed_entry(known_level);
    if (entry == ~0u) {
        return;
    }
    bool back_face = (entry & BACK_FACE_ENTRY) != 0u;
    uint triangle = entry & ~BACK_FACE_ENTRY;
    // The level of a triangle this frame classified or estimated holds for the whole ball of
    // eyes: kept for the frames that follow in it.
    if (!known_level && (draw.flags & FLAG_REUSE_LEVELS) != 0u) {
        estimated_levels[triangle] = triangle_levels[triangle];
    }
    uvec4 across = texelFetch(triangle_neighbours, int(triangle));
    vec3 neighbours = vec3(triangle_levels[across.x], triangle_levels[across.y], triangle_levels[across.z]);
    PatchLevels levels = patch_levels(triangle_levels[triangle], neighbours, float(draw.n_max));
    patch_tess_levels[triangle] = vec4(levels.fallback ? 0.0 : levels.inner, levels.outer);
    if (VARIANT_RECORD_LEVELS != 0) {
        level_records[triangle] = level_record(levels);
    }
    // A patch that is its own triangle needs no tessellator. Shaded per pixel, it is appended to
    // fallback_indices; shaded on its corners without a parameter map, it is drawn from
    // flat_indices in the mesh's order (every visible triangle writes its words there), otherwise
    // from the flat list. A back face's is drawn by the back-face draw.
    bool flat_patch = levels.inner <= 1.0 && all(lessThanEqual(levels.outer, vec3(1.0)));
    write_flat_corners(triangle, flat_patch && !levels.fallback);
    if (flat_patch) {
        if (back_face || (!levels.fallback && (draw.flags & FLAG_SHARED_CORNERS) != 0u)) {
            return;
        }
        if (levels.fallback) {
            append_fallback_flat(triangle);
            return;
        }
        uint command = FLAT_DRAW_WORDS * draw.mesh_index + FLAT_LIST_DRAW;
        uint entry = atomicAdd(flat_draws[command], 3u) / 3u;
        flat_patches[draw.patch_base + entry] = triangle;
        if (entry == 0u) {
            flat_draws[command + 1u] = 1u;
        }
        return;
    }
    uint counts = PATCH_COUNT_WORDS * patch_list(levels.fallback);
    uint slot = atomicAdd(patch_counts[counts + LISTED_PATCHES], 1u);
    uint per_draw = max(draw.patches_per_draw, 1u);
    uint command = draw.patch_base + slot / per_draw;
    // The first patch of a draw enables it: one instance, from its first vertex; the list's
    // draws are those opened, the first ones of its range.
    bool opens = slot % per_draw == 0u;
    if (opens) {
        atomicAdd(patch_counts[counts + OPENED_DRAWS], 1u);
    }
    if (levels.fallback) {
        fallback_patches[draw.patch_base + slot] = triangle;
        atomicAdd(fallback_draws[command].x, 3u);
        if (opens) {
            fallback_draws[command].yz = uvec2(1u, 3u * slot);
        }
    } else {
        interpolated_patches[draw.patch_base + slot] = triangle;
        atomicAdd(interpolated_draws[command].x, 3u);
        if (opens) {
            interpolated_draws[command].yz = uvec2(1u, 3u * slot);
        }
    }
}
