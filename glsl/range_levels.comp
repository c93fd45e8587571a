#version 460
// variants: material_kind polygon_lights textured
// `multirate` mode, `--estimator compute`, second step: one invocation per triangle to estimate of
// a mesh (listed by cull_triangles.comp) tries the range class (estimator/range.glsl): a triangle
// whose shading provably varies by at most ε over it takes level 1 here; of the others, an image
// too small to pay for an estimate (triangle_level.glsl, small_per_pixel) is shaded per pixel, and
// the rest are listed in estimate_triangles for the estimator step (triangle_levels.comp), which
// then runs the full estimator side by side on those only. The range bound costs a small part of an
// estimate, and on a CPU rasteriser every SIMD batch with one triangle to estimate would pay the
// whole estimator. Those whose every light's specular part the estimate bounds by its cap
// (estimator/range.glsl, range_bound's every_capped) are listed apart, from the end of the mesh's range
// of estimate_triangles down, for the estimator step's variant without specular setup or jets: a
// CPU rasteriser runs both sides of every branch, so only a list of their own spares them that code.
// A triangle whose level the current ball of eyes kept is not listed here: the culling step gave
// it that level.
#include "triangle_level.glsl"

layout(local_size_x = PRE_PASS_GROUP) in;

void main() {
    uint local = gl_GlobalInvocationID.x;
    if (local >= level_dispatches[level_dispatch(RANGE_DISPATCH)].w) {
        return;
    }
    uint triangle = visible_triangles[draw.patch_base + local];
    uint a = scene_indices[3u * triangle];
    uint b = scene_indices[3u * triangle + 1u];
    uint c = scene_indices[3u * triangle + 2u];
    vec3 p0 = scene_position(a);
    vec3 p1 = scene_position(b);
    vec3 p2 = scene_position(c);
    bool capped;
    if (settled_triangle(p0, p1, p2, scene_normal(a), scene_normal(b), scene_normal(c), scene_uv(a),
                         scene_uv(b), scene_uv(c), estimated_classes(triangle), capped)) {
        triangle_levels[triangle] = held_level(triangle, 1.0);
        return;
    }
    // An image too small to pay for the estimate: shaded per pixel. It stays in the culling
    // step's list, which the patch step covers.
    if (small_per_pixel(p0, p1, p2)) {
        triangle_levels[triangle] = held_level(triangle, FALLBACK_LEVEL);
        return;
    }
    uint list = capped ? CAPPED_ESTIMATE_DISPATCH : FULL_ESTIMATE_DISPATCH;
    uint slot = atomicAdd(level_dispatches[level_dispatch(list)].w, 1u);
    estimate_triangles[draw.patch_base + (capped ? draw.triangle_count - 1u - slot : slot)] = triangle;
    // Each PRE_PASS_GROUP-th triangle of a list opens one more workgroup of its estimator step.
    if (slot % PRE_PASS_GROUP == 0u) {
        atomicAdd(level_dispatches[level_dispatch(list)].x, 1u);
    }
}
