#version 460
// variants: material_kind polygon_lights textured record_levels
// `multirate` mode: estimate, per triangle, the real-valued level that keeps the interpolation
// error under epsilon (glsl/include/estimator.glsl, the port of src/shading/estimator.rs), and
// tessellate with the levels the combination rule `patch_levels` derives from it.
//
// The patch holds 12 control points: the triangle, then for each edge k (the edge of
// gl_TessLevelOuter[k], opposite vertex k) the neighbouring triangle across it, in that
// triangle's own vertex order (src/scene/adjacency.rs). Both triangles sharing an edge compute
// both levels from identical inputs with identical (precise) code, and the edge's outer level
// is a symmetric function of the two, so shared edges get the same level and no T-junction
// cracks appear. The inner level is chosen so that the whole pattern, including the transition
// strips next to raised edges, keeps the error bound (src/shading/estimator.rs,
// `pattern_level`). A triangle that cannot be tessellated finely enough falls back to
// per-pixel shading (patch_level = 0) but keeps the edge levels its neighbours expect.
#include "estimator.glsl"
#include "texture_bounds.glsl"

// The analysis variant also records each triangle's levels (bindings.glsl, level_records).
const bool RECORD_LEVELS = VARIANT_RECORD_LEVELS != 0;

layout(vertices = 3) out;

layout(location = 0) in vec3 in_position[];
layout(location = 1) in vec3 in_normal[];
layout(location = 2) in vec2 in_uv[];
layout(location = 0) out vec3 out_position[];
layout(location = 1) out vec3 out_normal[];
layout(location = 2) out vec2 out_uv[];
layout(location = 3) patch out float patch_level;
layout(location = 4) patch out float parameter_lod_bound;

// The coarsest level of detail at which the evaluation stage samples the parameter map on the
// triangle with texture coordinates a, b, c: log2 of its texel extent (at least 0). Rust twin:
// `ParameterMap::lod_bound` in src/scene/mod.rs.
float lod_bound_of(vec2 a, vec2 b, vec2 c, vec2 size) {
    P vec2 extent = (max(max(a, b), c) - min(min(a, b), c)) * size;
    return est_log2(rmax(rmax(extent.x, extent.y), 1.0));
}

// The range of the material's shininess or roughness over the triangle's texels (seed 003
// Sec. 3.5), from the min/max pyramid; the material's own value without a map.
// `bound`: the triangle's lod_bound_of.
vec2 parameter_range_of(GpuMaterial m, vec2 p, vec2 q, vec2 r, float bound) {
    if (!TEXTURED || m.maps.y < 0) {
        return vec2(m.params.x);
    }
    vec2 u = parameter_bounds(min(min(p, q), r), max(max(p, q), r), bound);
    P float lo = m.parameter_range.x;
    P float hi = m.parameter_range.y;
    P float a;
    P float b;
    if (m.maps.w == 1) {
        a = lo * est_pow(hi / lo, u.x);
        b = lo * est_pow(hi / lo, u.y);
    } else {
        a = lo + (hi - lo) * u.x;
        b = lo + (hi - lo) * u.y;
    }
    return vec2(a, b);
}

void main() {
    out_position[gl_InvocationID] = in_position[gl_InvocationID];
    out_normal[gl_InvocationID] = in_normal[gl_InvocationID];
    out_uv[gl_InvocationID] = in_uv[gl_InvocationID];
    if (gl_InvocationID == 0) {
        GpuMaterial material = materials[draw.material_index];
        bool mapped = TEXTURED && material.maps.y >= 0;
        vec2 map_size = mapped ? vec2(textureSize(parameter_map, 0)) : vec2(1.0);
        // The triangle itself (t = 0) and its neighbours across edges 0, 1, 2.
        float levels[4];
        float own_lod_bound = 0.0;
        for (int t = 0; t < 4; ++t) {
            int first = 3 * t;
            float bound = 0.0;
            if (mapped) {
                bound = lod_bound_of(in_uv[first], in_uv[first + 1], in_uv[first + 2], map_size);
            }
            if (t == 0) {
                own_lod_bound = bound;
            }
            vec2 range =
                parameter_range_of(material, in_uv[first], in_uv[first + 1], in_uv[first + 2], bound);
            levels[t] = required_level(
                in_position[first], in_position[first + 1], in_position[first + 2],
                in_normal[first], in_normal[first + 1], in_normal[first + 2],
                draw.eye.xyz, draw.material_index, range, draw.viewport.z, draw.viewport.w);
        }
        PatchLevels levels_of_patch =
            patch_levels(levels[0], vec3(levels[1], levels[2], levels[3]), draw.viewport.w);
        gl_TessLevelOuter[0] = levels_of_patch.outer.x;
        gl_TessLevelOuter[1] = levels_of_patch.outer.y;
        gl_TessLevelOuter[2] = levels_of_patch.outer.z;
        gl_TessLevelInner[0] = levels_of_patch.inner;
        patch_level = levels_of_patch.fallback ? 0.0 : ceil(levels_of_patch.inner);
        // The evaluation stage samples no coarser than this (a little finer than the bound the
        // range above covers, for the sampler's fixed-point level of detail).
        parameter_lod_bound = mapped ? own_lod_bound - 0.02 : 0.0;
        if (RECORD_LEVELS) {
            // Note: lavapipe (Mesa 22.3) restarts gl_PrimitiveID every 85 twelve-point patches
            // within a draw, so the recording draws must not be longer than that there.
            level_records[draw.patch_base + uint(gl_PrimitiveID)] = vec4(patch_level,
                ceil(levels_of_patch.outer.x), ceil(levels_of_patch.outer.y),
                ceil(levels_of_patch.outer.z));
        }
    }
}
