#version 460
// The post chain's first pass: each texel of the quarter-resolution image is the average colour
// of its 4x4 block of the linear frame (rgb) and the block's average log luminance (a).
#include "post.glsl"

layout(location = 0) out vec4 out_color;

void main() {
    ivec2 size = textureSize(linear_frame, 0);
    ivec2 corner = ivec2(gl_FragCoord.xy) * POST_DOWNSAMPLE;
    vec3 colour = vec3(0.0);
    float log_sum = 0.0;
    float count = 0.0;
    for (int y = 0; y < POST_DOWNSAMPLE; y++) {
        for (int x = 0; x < POST_DOWNSAMPLE; x++) {
            ivec2 at = corner + ivec2(x, y);
            if (all(lessThan(at, size))) {
                vec3 linear = max(texelFetch(linear_frame, at, 0).rgb, vec3(0.0));
                colour += linear;
                log_sum += log_luminance(linear);
                count += 1.0;
            }
        }
    }
    out_color = vec4(colour, log_sum) / max(count, 1.0);
}
