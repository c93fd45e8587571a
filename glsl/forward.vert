#version 460
// Forward pass vertex stage: world-space vertices in, clip space out.
#include "bindings.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;

layout(location = 0) out vec3 out_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv;

// The same transform, without fused multiply-adds, as the tessellated stages: a multirate
// triangle that falls back to per-pixel shading then rasterises with bit-identical depth, so
// where two surfaces intersect both modes pick the same one.
precise gl_Position;

void main() {
    out_position = in_position;
    out_normal = in_normal;
    out_uv = in_uv;
    gl_Position = draw.view_proj * vec4(in_position, 1.0);
}
