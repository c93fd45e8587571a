#version 460
// variants: material_kind polygon_lights textured count_evaluations
// `pixel-deferred` mode: the per-pixel reference rebuilt from the visibility buffer. The
// triangle's vertices come from the vertex and index buffers; perspective-correct barycentrics
// and their screen derivatives (seed 002, derivatives.glsl) give the position, normal, texture
// coordinates and the texture level of detail, with no help from the rasteriser. One full-screen
// pass per mesh shades that mesh's pixels.
#include "texturing.glsl"
#include "triangle_id.glsl"

// The triangles' vertices come from bindings.glsl's scene_vertices and scene_indices.
layout(set = 2, binding = 0) uniform sampler2D visibility;

layout(location = 0) out vec4 out_color;

void main() {
    vec4 id = texelFetch(visibility, ivec2(gl_FragCoord.xy), 0);
    bool mine = id.w != 0.0 && uint(id.x) == draw.mesh_index + 1u;
    // Every invocation reconstructs its own pixel's triangle (any valid id), and discards only
    // after the hardware derivatives below, which need the whole quad.
    uint triangle = id.w != 0.0 ? uint(id.y) : 0u;
    vec3 p[3];
    vec3 n[3];
    vec2 t[3];
    vec4 clip[3];
    for (int k = 0; k < 3; ++k) {
        uint vertex = scene_indices[3u * triangle + uint(k)];
        p[k] = scene_position(vertex);
        n[k] = scene_normal(vertex);
        t[k] = scene_uv(vertex);
        clip[k] = draw.view_proj * vec4(p[k], 1.0);
    }
    BarycentricDerivatives b =
        barycentric_derivatives(clip[0], clip[1], clip[2], gl_FragCoord.xy, draw.viewport_size);
    vec3 position;
    vec3 normal;
    vec2 uv;
    vec3 unused_dx;
    vec3 unused_dy;
    vec2 duv_dx;
    vec2 duv_dy;
    interpolate3(b, p[0], p[1], p[2], position, unused_dx, unused_dy);
    interpolate3(b, n[0], n[1], n[2], normal, unused_dx, unused_dy);
    interpolate2(b, t[0], t[1], t[2], uv, duv_dx, duv_dy);
    if ((draw.flags & FLAG_DERIVATIVE_CHECK) != 0u) {
        // One-pixel differences within the quad, as the rasteriser's derivatives are taken;
        // blue marks quads whose pixels lie on different triangles (the rasteriser would have
        // extrapolated one triangle there with helper invocations).
        vec2 hardware_dx = dFdxFine(uv);
        vec2 hardware_dy = dFdyFine(uv);
        bool one_triangle = dFdxFine(id.y) == 0.0 && dFdyFine(id.y) == 0.0;
        if (!mine) {
            discard;
        }
        float difference = length(duv_dx - hardware_dx) + length(duv_dy - hardware_dy);
        out_color = vec4(difference, length(duv_dx) + length(duv_dy), one_triangle ? 0.0 : 1.0, 1.0);
        return;
    }
    if (!mine) {
        discard;
    }
    GpuMaterial m = materials[draw.material_index];
    float parameter = parameter_at_grad(m, uv, duv_dx, duv_dy);
    ShadowPoint lookup = fragment_shadow_point(triangle);
    Shading s = shade_visible(position, normal, draw.eye.xyz, draw.material_index, parameter, lookup);
    if (COUNT_EVALUATIONS) {
        atomicAdd(counters.pixel_evaluations, 1u);
    }
    out_color = vec4(albedo_at_grad(m, uv, duv_dx, duv_dy) * s.diffuse + s.specular, 1.0);
#if TRIANGLE_IDS
    write_triangle_id(triangle);
#endif
}
