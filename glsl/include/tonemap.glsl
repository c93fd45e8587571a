// Display transform: exposure, the ACES filmic curve (Narkowicz 2015 fit), then sRGB encoding.
// Rust twin: `src/shading/tonemap.rs` (used for PNG files).
#ifndef TONEMAP_GLSL
#define TONEMAP_GLSL

vec3 aces_filmic(vec3 x) {
    return clamp((x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

vec3 srgb_encode(vec3 linear) {
    vec3 low = linear * 12.92;
    vec3 high = 1.055 * pow(linear, vec3(1.0 / 2.4)) - 0.055;
    return mix(high, low, lessThanEqual(linear, vec3(0.0031308)));
}

#endif
