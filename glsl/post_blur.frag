#version 460
// Bloom: one direction of a separable Gaussian over the quarter-resolution image. The first
// pass (`bright_pass`) blurs the part of the exposed frame above the threshold; the second
// blurs the first's output as it is.
#include "post.glsl"

layout(location = 0) out vec4 out_color;

const int RADIUS = 6;
const float SIGMA = 3.0;

void main() {
    ivec2 size = textureSize(bloom_image, 0);
    ivec2 centre = ivec2(gl_FragCoord.xy);
    ivec2 direction = ivec2(post.blur_x, post.blur_y);
    bool bright_pass = post.bright_pass != 0.0;
    vec3 sum = vec3(0.0);
    float weights = 0.0;
    for (int i = -RADIUS; i <= RADIUS; i++) {
        ivec2 at = clamp(centre + i * direction, ivec2(0), size - 1);
        vec3 value = texelFetch(bloom_image, at, 0).rgb;
        value = bright_pass ? bright_part(value * adaptation.exposure) : value;
        float weight = exp(-float(i * i) / (2.0 * SIGMA * SIGMA));
        sum += weight * value;
        weights += weight;
    }
    out_color = vec4(sum / weights, 1.0);
}
