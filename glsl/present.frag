#version 460
// Tone maps the float render target into the swapchain image.
#include "tonemap.glsl"

layout(constant_id = 0) const bool ENCODE_SRGB = true;

layout(set = 0, binding = 0) uniform sampler2D hdr_image;
layout(push_constant) uniform Present { float exposure; } present;

layout(location = 0) out vec4 out_color;

void main() {
    vec3 linear = texelFetch(hdr_image, ivec2(gl_FragCoord.xy), 0).rgb;
    vec3 mapped = aces_filmic(max(linear, vec3(0.0)) * present.exposure);
    out_color = vec4(ENCODE_SRGB ? srgb_encode(mapped) : mapped, 1.0);
}
