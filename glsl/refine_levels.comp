#version 460
// variants: material_kind polygon_lights textured
// `multirate` mode, `--estimator compute`, the refining step between the estimator step
// (triangle_levels.comp) and the patch step: the estimator step lists the triangles whose
// estimate Rust refines (estimate_pass, `refine_next`) in refine_triangles, and this step
// estimates those again with each light's ranges over their REFINE_CHILDREN children and writes
// the level that stands. A workgroup takes the listed triangles REFINE_BLOCK at a time: first its
// invocations take the block's children's turns side by side (one turn per triangle, light and
// child, for the first GIVEN_LIGHTS point and directional lights), then REFINE_BLOCK of them
// estimate one triangle each with those values (estimator/add_light.glsl, given_child_values). One
// invocation taking all its triangle's turns in a row made the step 4.6 times as long as the
// estimator step on an NVIDIA H200 (docs/notebook/gpu.md).
#define CHILDREN_GIVEN
#define GIVEN_LIGHTS 8
#include "triangle_level.glsl"

// The workgroup's size: PRE_PASS_GROUP on a GPU; REFINE_BLOCK on a CPU device, so that the
// block's estimates fill one SIMD batch and no batch runs the estimator with every lane idle (a
// CPU rasteriser runs each batch through the whole code; `render::refine_lanes`).
layout(local_size_x_id = 13) in;
layout(local_size_x = PRE_PASS_GROUP) in;

// Listed triangles per block (`render::REFINE_BLOCK`, a CPU device's workgroup size; the loop
// below covers every block whatever workgroups triangle_levels.comp's count opened).
const uint REFINE_BLOCK = 8u;

// The children's turns of one block: add_light's answer, whether the child's bound went bad,
// and the child's values (ChildValues from its initial values), at child_turn(t, i, r).
const uint BLOCK_TURNS = REFINE_BLOCK * uint(GIVEN_LIGHTS * REFINE_CHILDREN);
shared int turn_added[BLOCK_TURNS];
shared bool turn_bad[BLOCK_TURNS];
shared vec2 turn_diffuse[BLOCK_TURNS];
shared vec3 turn_specular[BLOCK_TURNS];
uint child_turn(uint slot, int light, int child) {
    return (slot * uint(GIVEN_LIGHTS) + uint(light)) * uint(REFINE_CHILDREN) + uint(child);
}

// The children's values of `light` for the block's triangle this invocation estimates (its slot
// is its invocation's index, main).
ChildValues given_child_values(int light, out bool bad) {
    ChildValues values = ChildValues(0.0, MAX_FINITE, vec3(0.0), true);
    bad = false;
    for (int r = 0; r < REFINE_CHILDREN; ++r) {
        uint k = child_turn(gl_LocalInvocationID.x, light, r);
        int added = turn_added[k];
        if (added == VALUES_ADDED) {
            values.diffuse_sup = rmax(values.diffuse_sup, turn_diffuse[k].x);
            values.diffuse_inf = rmin(values.diffuse_inf, turn_diffuse[k].y);
            values.specular_sup = rmax3(values.specular_sup, turn_specular[k]);
        } else if (added == REASON_NONE) {
            values.diffuse_inf = 0.0;
        } else {
            values.ok = false;
        }
        bad = bad || turn_bad[k];
    }
    return values;
}

// The children's turns of the block of listed triangles from `block` on, spread over the
// workgroup's invocations; as estimate_pass takes them (estimate_pass's frame, eps, n_max and top).
void take_children_turns(uint block, uint count) {
    int given = min(POINT_LIGHT_COUNT + DIRECTIONAL_LIGHT_COUNT, GIVEN_LIGHTS);
    uint per_triangle = uint(given * REFINE_CHILDREN);
    uint n_max = draw.n_max;
    P float eps = draw.epsilon > 0.0 ? draw.epsilon : 0.0;
    P float top = pattern_level(n_max, n_max);
    GpuMaterial material = materials[draw.material_index];
    for (uint k = gl_LocalInvocationID.x; k < REFINE_BLOCK * per_triangle; k += gl_WorkGroupSize.x) {
        uint t = k / per_triangle;
        int i = int(k % per_triangle) / REFINE_CHILDREN;
        int r = int(k % per_triangle) % REFINE_CHILDREN;
        if (block + t >= count) {
            break;
        }
        uint triangle = refine_triangles[draw.patch_base + block + t];
        uint a = scene_indices[3u * triangle];
        uint b = scene_indices[3u * triangle + 1u];
        uint c = scene_indices[3u * triangle + 2u];
        vec3 q[3] = vec3[3](scene_position(a), scene_position(b), scene_position(c));
        vec3 m[3] = vec3[3](scene_normal(a), scene_normal(b), scene_normal(c));
        midpoint_child(q, r);
        midpoint_child(m, r);
        Frame child = make_frame(q[0], q[1], q[2], m[0], m[1], m[2], estimator_eye());
        GpuLight light = lights[i];
        ChildValues values = ChildValues(0.0, MAX_FINITE, vec3(0.0), true);
        Guard gd = FRESH_GUARD;
        Sums unused;
        int added = add_light(child, material, draw_parameter_range(scene_uv(a), scene_uv(b), scene_uv(c)),
                              i < POINT_LIGHT_COUNT, light.position.xyz, light.radiance.rgb, -1, top, n_max, eps,
                              ADD_VALUES, NO_SPECULAR_CAPS, values, unused, gd);
        uint at = child_turn(t, i, r);
        turn_added[at] = added;
        turn_bad[at] = gd.bad;
        turn_diffuse[at] = vec2(values.diffuse_sup, values.diffuse_inf);
        turn_specular[at] = values.specular_sup;
    }
}

void main() {
    uint count = level_dispatches[level_dispatch(REFINE_DISPATCH)].w;
    uint slot = gl_LocalInvocationID.x;
    for (uint block = gl_WorkGroupID.x * REFINE_BLOCK; block < count; block += gl_NumWorkGroups.x * REFINE_BLOCK) {
        memoryBarrierShared();
        barrier();
        take_children_turns(block, count);
        memoryBarrierShared();
        barrier();
        if (slot < REFINE_BLOCK && block + slot < count) {
            uint triangle = refine_triangles[draw.patch_base + block + slot];
            uint a = scene_indices[3u * triangle];
            uint b = scene_indices[3u * triangle + 1u];
            uint c = scene_indices[3u * triangle + 2u];
            vec3 p0 = scene_position(a);
            vec3 p1 = scene_position(b);
            vec3 p2 = scene_position(c);
            vec3 n0 = scene_normal(a);
            vec3 n1 = scene_normal(b);
            vec3 n2 = scene_normal(c);
            // The range class again, for whether every light's specular part is capped (it did not
            // settle the triangle, which the estimator step listed here).
            bool capped;
            uint classes = estimated_classes(triangle);
            settled_triangle(p0, p1, p2, n0, n1, n2, scene_uv(a), scene_uv(b), scene_uv(c), classes, capped);
            bool again;
            float level = estimated_level_pass(p0, p1, p2, n0, n1, n2, scene_uv(a), scene_uv(b), scene_uv(c),
                                               classes, capped, true, again);
            triangle_levels[triangle] = held_level(triangle, level);
        }
    }
}
