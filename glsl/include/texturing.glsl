// Textured materials (seed 003 Sec. 3.5): the albedo map multiplies the diffuse part per pixel,
// the parameter map gives the shininess or roughness. Fragment shaders sample with derivatives
// taken in uniform control flow; the evaluation shaders, which have none, with the level of
// detail of the sub-vertex (`subvertex_lod`, analytic derivatives of seed 002).
#ifndef TEXTURING_GLSL
#define TEXTURING_GLSL
#include "brdf.glsl"
#include "derivatives.glsl"

bool has_albedo_map(GpuMaterial m) {
    return TEXTURED && m.maps.x >= 0;
}

bool has_parameter_map(GpuMaterial m) {
    return TEXTURED && m.maps.y >= 0;
}

// The parameter a texel value u in [0, 1] stands for (ParameterMap::value in Rust).
float map_parameter(GpuMaterial m, float u) {
    float lo = m.parameter_range.x;
    float hi = m.parameter_range.y;
    return m.maps.w == 1 ? lo * pow(hi / lo, u) : lo + (hi - lo) * u;
}

// The reads below are compiled into textured variants only (`#if VARIANT_TEXTURED`), not left
// to the optimiser: build.rs compiles the estimator's stages and the analysis variants without
// it, and an untextured variant's module then holds no texture read at all.

// The parameter map's size in texels ((1, 1) in an untextured variant, which has none).
vec2 parameter_map_size() {
#if VARIANT_TEXTURED
    return vec2(textureSize(parameter_map, 0));
#else
    return vec2(1.0);
#endif
}

float parameter_at_lod(GpuMaterial m, vec2 uv, float lod) {
#if VARIANT_TEXTURED
    if (has_parameter_map(m)) {
        return map_parameter(m, textureLod(parameter_map, uv, lod).r);
    }
#endif
    return m.params.x;
}

float parameter_at_grad(GpuMaterial m, vec2 uv, vec2 duv_dx, vec2 duv_dy) {
#if VARIANT_TEXTURED
    if (has_parameter_map(m)) {
        return map_parameter(m, textureGrad(parameter_map, uv, duv_dx, duv_dy).r);
    }
#endif
    return m.params.x;
}

vec3 albedo_at_grad(GpuMaterial m, vec2 uv, vec2 duv_dx, vec2 duv_dy) {
#if VARIANT_TEXTURED
    if (has_albedo_map(m)) {
        return textureGrad(albedo_map, uv, duv_dx, duv_dy).rgb;
    }
#endif
    return vec3(1.0);
}

// The level of detail of the parameter map at a sub-vertex of the patch with world corners p
// and texture coordinates uv, tessellated at `level`: the larger of the pixel footprint there
// (analytic derivatives) and the sub-triangle's footprint (the patch's uv edges / level), so
// that one sample stands for the whole sub-triangle; at most `lod_bound` (the control stage's
// bound for the patch, which its texel range covers).
float subvertex_lod(GpuMaterial m, vec3 p[3], vec2 uv[3], vec3 position, float level, float lod_bound) {
    vec2 size = parameter_map_size();
    vec4 clip = draw.view_proj * vec4(position, 1.0);
    vec2 pixel = (clip.xy / clip.w * 0.5 + 0.5) * draw.viewport_size;
    BarycentricDerivatives b = barycentric_derivatives(draw.view_proj * vec4(p[0], 1.0),
        draw.view_proj * vec4(p[1], 1.0), draw.view_proj * vec4(p[2], 1.0), pixel, draw.viewport_size);
    vec2 at_subvertex;
    vec2 duv_dx;
    vec2 duv_dy;
    interpolate2(b, uv[0], uv[1], uv[2], at_subvertex, duv_dx, duv_dy);
    float pixel_lod = texture_lod(duv_dx, duv_dy, size);
    float edge = max(max(length((uv[1] - uv[0]) * size), length((uv[2] - uv[1]) * size)),
                     length((uv[0] - uv[2]) * size));
    float sub_lod = log2(max(edge / max(level, 1.0), 1.0e-30));
    return min(max(pixel_lod, sub_lod), lod_bound);
}

#endif
