#version 460
// Eye adaptation: one workgroup averages the downsampled frame's log luminance (its alpha),
// blends it into the adapted average by the frame's weight and writes the exposure it gives.
#define ADAPTATION_ACCESS
#include "post.glsl"

const uint LANES = 256;
layout(local_size_x = LANES) in;

shared float partial[LANES];

void main() {
    ivec2 size = textureSize(bloom_image, 0);
    uint count = uint(size.x * size.y);
    uint lane = gl_LocalInvocationIndex;
    float sum = 0.0;
    for (uint i = lane; i < count; i += LANES) {
        sum += texelFetch(bloom_image, ivec2(i % uint(size.x), i / uint(size.x)), 0).a;
    }
    partial[lane] = sum;
    barrier();
    for (uint stride = LANES / 2; stride > 0; stride /= 2) {
        if (lane < stride) {
            partial[lane] += partial[lane + stride];
        }
        barrier();
    }
    if (lane == 0) {
        float average = partial[0] / float(max(count, 1u));
        float adapted = mix(adaptation.log_average, average, clamp(post.adaptation_weight, 0.0, 1.0));
        adaptation.log_average = adapted;
        adaptation.exposure = adapted_exposure(adapted);
    }
}
