// The tessellation-level heat map of the viewer: blue (level 1) through green to red (n_max);
// magenta marks per-pixel shading (the fallback, and every pixel of `pixel` mode).
#ifndef HEAT_GLSL
#define HEAT_GLSL
#include "bindings.glsl"

bool heat_map_on() {
    return (draw.flags & FLAG_HEAT_MAP) != 0u;
}

// `level` 0 means per-pixel shading.
vec3 heat_color(float level) {
    if (level <= 0.0) {
        return vec3(1.0, 0.0, 1.0);
    }
    float t = clamp((level - 1.0) / max(float(draw.n_max) - 1.0, 1.0), 0.0, 1.0);
    return t < 0.5 ? mix(vec3(0.0, 0.2, 1.0), vec3(0.0, 1.0, 0.2), 2.0 * t)
                   : mix(vec3(0.0, 1.0, 0.2), vec3(1.0, 0.1, 0.0), 2.0 * t - 1.0);
}
#endif
