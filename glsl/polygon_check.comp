#version 460
// Runs the polygonal-light functions of polygon.glsl on test cases, for `tests/polygon_gpu.rs`,
// which runs the same cases through the Rust twin `src/shading/polygon/` and compares.
#include "polygon.glsl"

layout(local_size_x = 64) in;

// One case: a polygon in the shading frame, random numbers and a probe direction.
struct PolygonCase {
    vec4 vertices[MAX_POLYGON_VERTICES]; // xyz: vertex relative to the shading point
    vec4 u;                              // xy: projected-solid-angle sample, zw: solid-angle sample
    vec4 probe;                          // xyz: unit direction at which the densities are evaluated
    uvec4 counts;                        // x: vertex count, y: point index, z: point count
};

// What the GPU computed for one case.
struct PolygonResult {
    vec4 projected_sample;   // xyz: sample_projected_solid_angle direction, w: its density
    vec4 solid_angle_sample; // xyz: sample_solid_angle direction, w: its density
    vec4 values;             // x: projected solid angle, y: solid angle, zw: MIS weights at the
                             // projected-solid-angle sample
    vec4 densities;          // x, y: projected-solid-angle and solid-angle density at the probe,
                             // z: the projected sample's density per solid angle, w: 0
    vec4 point;              // xy: sample_point(counts.y, counts.z), zw: 0
    uvec4 counts;            // x: clipped vertex count, y: projected sampler count (0 if empty),
                             // z: 1 if central, w: solid-angle sampler count
};

layout(set = 0, binding = 0, std430) readonly buffer Cases { PolygonCase cases[]; };
layout(set = 0, binding = 1, std430) writeonly buffer Results { PolygonResult results[]; };

void main() {
    uint index = gl_GlobalInvocationID.x;
    if (index >= uint(cases.length())) {
        return;
    }
    PolygonCase test_case = cases[index];
    Polygon polygon = polygon_empty();
    for (int j = 0; j < MAX_POLYGON_VERTICES; ++j) {
        polygon.vertices[j] = test_case.vertices[j].xyz;
    }
    polygon.count = int(test_case.counts.x);

    Polygon clipped = clip_to_horizon(polygon);
    ProjectedSolidAngleSampler projected = prepare_projected_solid_angle(clipped);
    SolidAngleSampler solid = prepare_solid_angle(clipped);
    vec4 projected_sample = sample_projected_solid_angle(projected, test_case.u.xy);
    vec4 solid_angle_sample = sample_solid_angle(solid, test_case.u.zw);
    float projected_in_solid_angle = projected_to_solid_angle_density(projected_sample.w, projected_sample.xyz);
    vec2 weights = clamped_optimal_mis_weights(vec2(projected_in_solid_angle, solid_angle_sample.w),
                                               vec2(projected.projected_solid_angle, solid.solid_angle),
                                               DEFAULT_MIS_VISIBILITY);

    PolygonResult result;
    result.projected_sample = projected_sample;
    result.solid_angle_sample = solid_angle_sample;
    result.values = vec4(projected_solid_angle(clipped), solid.solid_angle, weights);
    result.densities = vec4(projected_solid_angle_density(projected, test_case.probe.xyz),
                            solid_angle_density(solid, test_case.probe.xyz), projected_in_solid_angle, 0.0);
    result.point = vec4(sample_point(test_case.counts.y, test_case.counts.z), 0.0, 0.0);
    result.counts = uvec4(uint(clipped.count), uint(projected.count), is_central(projected) ? 1u : 0u,
                          uint(solid.count));
    results[index] = result;
}
