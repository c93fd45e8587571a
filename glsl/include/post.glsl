// The post chain's interface and formulas, shared by its stages (`post_*.comp`, `post_*.frag`;
// host side: `src/render/post.rs`). It runs on the linear float frame and never writes it.
#ifndef POST_GLSL
#define POST_GLSL

// The compute stage writes the adaptation state; the fragment stages only read it.
#ifndef ADAPTATION_ACCESS
#define ADAPTATION_ACCESS readonly
#endif

// The linear frame (read only).
layout(set = 0, binding = 0) uniform sampler2D linear_frame;
// A quarter-resolution image of the chain: the downsampled frame, then the bloom.
layout(set = 0, binding = 1) uniform sampler2D bloom_image;
// The adapted average log luminance and the exposure it gives.
layout(set = 0, binding = 2) ADAPTATION_ACCESS buffer Adaptation {
    float log_average;
    float exposure;
} adaptation;

// Rust twin: `render::post::PostConstants`.
layout(push_constant) uniform PostConstants {
    float scene_exposure; // the scene's exposure, a compensation on top of the adapted one
    float adaptation_weight; // the weight of this frame's average (1: adapted at once)
    float key; // the exposed average luminance aimed at
    float bloom_threshold; // exposed luminance above which light blooms
    float bloom_strength; // the bloom's weight where it is added back
    float blur_x; // the blur's direction, in texels
    float blur_y;
    float bright_pass; // 1: the blur takes the bright part of what it reads (its first pass)
} post;

// The downsampling factor of the quarter-resolution images, per axis.
const int POST_DOWNSAMPLE = 4;
// Luminance below this counts as this in the log average (black would be minus infinity).
const float MIN_LUMINANCE = 1e-4;
const float MAX_LUMINANCE = 1e8;
// The range of the adapted exposure, before the scene's compensation.
const float MIN_ADAPTED_EXPOSURE = 1.0 / 64.0;
const float MAX_ADAPTED_EXPOSURE = 64.0;

float luminance(vec3 linear) {
    return dot(linear, vec3(0.2126, 0.7152, 0.0722));
}

// A pixel's log luminance, finite for every input.
float log_luminance(vec3 linear) {
    float l = luminance(linear);
    return log(isnan(l) ? MIN_LUMINANCE : clamp(l, MIN_LUMINANCE, MAX_LUMINANCE));
}

// The exposure that maps the average luminance exp(log_average) to the key.
float adapted_exposure(float log_average) {
    float adapted = clamp(post.key / exp(log_average), MIN_ADAPTED_EXPOSURE, MAX_ADAPTED_EXPOSURE);
    return adapted * post.scene_exposure;
}

// The part of an exposed colour above the bloom threshold (in luminance), its hue kept.
vec3 bright_part(vec3 exposed) {
    float l = luminance(exposed);
    return exposed * (max(l - post.bloom_threshold, 0.0) / max(l, 1e-6));
}

#endif
