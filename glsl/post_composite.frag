#version 460
// The post chain's last pass: the linear frame at the adapted exposure, the bloom added, tone
// mapped (tonemap.glsl) into the output image.
#include "post.glsl"
#include "tonemap.glsl"

layout(constant_id = 0) const bool ENCODE_SRGB = true;

layout(location = 0) out vec4 out_color;

void main() {
    vec3 linear = max(texelFetch(linear_frame, ivec2(gl_FragCoord.xy), 0).rgb, vec3(0.0));
    vec2 bloom_at = gl_FragCoord.xy / vec2(textureSize(bloom_image, 0) * POST_DOWNSAMPLE);
    vec3 bloom = textureLod(bloom_image, bloom_at, 0.0).rgb;
    vec3 mapped = aces_filmic(linear * adaptation.exposure + post.bloom_strength * bloom);
    out_color = vec4(ENCODE_SRGB ? srgb_encode(mapped) : mapped, 1.0);
}
