// Conservative range of a parameter texture (shininess, roughness) over a box of texture
// coordinates, read from its min/max pyramid: an R8G8_UNORM image whose level k texel holds the
// (min, max) of the texture's level-0 texels in the aligned 2^k x 2^k block, with the same
// mip chain sizes as the texture. Width and height are powers of two.
// Rust twin: `MinMaxPyramid::query` in `src/scene/texture/bounds.rs`. Keep the two in step, operation
// for operation (the same f32 operations in the same order), so both give the same range. Every
// product but the last two is by a power of two, so it is exact and a fused multiply-add changes
// nothing; the last two are `precise`.
#ifndef TEXTURE_BOUNDS_GLSL
#define TEXTURE_BOUNDS_GLSL
#include "bindings.glsl"

// One 8-bit UNORM step, 1/255, multiplied by (a product is correctly rounded, a quotient need not be).
const float PYRAMID_UNORM_STEP = 0.003921569;
// Half an 8-bit UNORM step (1/510), added on each side for the sampler's fixed-point weights.
const float PYRAMID_SLACK = 0.0019607844;
// How far the box is widened per level-j texel of the coarsest level read: 1/2 (every texel a
// bilinear lookup reads overlaps the lookup point +- 1/2 texel) plus 1/16 for the sampler's
// fixed-point texel coordinates.
const float PYRAMID_REACH = 0.5625;
// Texel coordinates |uv| * size from this far (2^20 texels) give the whole range: samplers address
// texels in fixed point of limited range (lavapipe in Mesa 22.3 reads texels from elsewhere beyond
// 2^23), and f32 uv no longer resolves a fraction of a texel.
const float PYRAMID_FAR_TEXELS = 1048576.0;
// 2^-20 texels of widening per unit |uv| per texel of size: covers f32 rounding of uv * size.
const float PYRAMID_MAGNITUDE_MARGIN = 9.5367431640625e-7;

bool pyramid_finite(vec2 v) {
    return !any(isnan(v)) && !any(isinf(v));
}

// (lo, hi) in [0, 1] bounding every value a REPEAT, LINEAR/LINEAR/LINEAR sampler can return from
// the texture whose pyramid is bound as `parameter_pyramid` for uv in the box [uv_min, uv_max] (corners in
// either order, any real uv) and any lod <= lod_bound (+inf: any lod). The box is widened by
// 0.5625 texels of the coarsest level read, ceil(lod_bound); 3x3 texels are read from the
// finest pyramid level whose texels are at least half the widened extent, or the top 1x1 level
// (the whole texture's range) when there is none, when a corner is 2^20 texels or more from the
// origin, or when an input is NaN or infinite.
vec2 parameter_bounds(vec2 uv_min, vec2 uv_max, float lod_bound) {
    // The chain is full, so its top level is log2 of the larger side (textureQueryLevels is not
    // used: lavapipe in Mesa 22.3 answers 1 for a combined image sampler with several levels).
    ivec2 base = textureSize(parameter_pyramid, 0);
    int top = findMSB(max(base.x, base.y));
    vec2 lo = min(uv_min, uv_max);
    vec2 hi = max(uv_min, uv_max);
    vec2 size = vec2(base);
    int level = top;
    ivec2 first = ivec2(0);
    ivec2 last = ivec2(0);
    vec2 magnitude = max(abs(lo), abs(hi)) * size;
    bool near = max(magnitude.x, magnitude.y) < PYRAMID_FAR_TEXELS;
    if (pyramid_finite(uv_min) && pyramid_finite(uv_max) && !isnan(lod_bound) && near) {
        float lod = min(max(lod_bound, 0.0), float(top));
        float reach = PYRAMID_REACH * float(1 << int(ceil(lod)));
        vec2 pad = magnitude * PYRAMID_MAGNITUDE_MARGIN + reach;
        vec2 shift = floor(lo);
        vec2 x0 = (lo - shift) * size - pad;
        vec2 x1 = (hi - shift) * size + pad;
        vec2 widths = x1 - x0;
        float extent = max(widths.x, widths.y);
        float span = 2.0;
        level = 0;
        while (level < top && extent > span) {
            span *= 2.0;
            level += 1;
        }
        if (level < top) {
            float scale = 1.0 / float(1 << level);
            first = ivec2(floor(x0 * scale));
            last = ivec2(floor(x1 * scale));
        }
    }
    // The level's size from level 0's (textureSize with a level that differs between invocations
    // gives wrong sizes on lavapipe in Mesa 22.3).
    ivec2 mask = max(base >> level, ivec2(1)) - 1;
    // The 8-bit values, recovered exactly from the UNORM conversion (whose last bit is the
    // implementation's), so that the result below is computed from integers as the twin does.
    int range_lo = 255;
    int range_hi = 0;
    for (int dy = 0; dy < 3; ++dy) {
        for (int dx = 0; dx < 3; ++dx) {
            ivec2 t = min(first + ivec2(dx, dy), last) & mask;
            ivec2 texel = ivec2(round(texelFetch(parameter_pyramid, t, level).rg * 255.0));
            range_lo = min(range_lo, texel.x);
            range_hi = max(range_hi, texel.y);
        }
    }
    precise float bound_lo = float(range_lo) * PYRAMID_UNORM_STEP - PYRAMID_SLACK;
    precise float bound_hi = float(range_hi) * PYRAMID_UNORM_STEP + PYRAMID_SLACK;
    return vec2(max(bound_lo, 0.0), min(bound_hi, 1.0));
}

#endif
