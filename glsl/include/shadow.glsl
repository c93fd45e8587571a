// Shadow-map visibility V_k(x) in [0, 1] of one light at a surface point: the share of the
// filter kernel's texels around the point's image whose stored depth is not nearer to the light
// than the point (percentage-closer filtering; one texel: a hard shadow). The maps are tiles of
// shadow_atlas (a directional light's orthographic map, a point light's six cube faces), laid
// out and rendered once by the host (src/geometry/shadow_view.rs, src/render/shadows.rs).
//
// The bound does not see V: every stage that applies it multiplies a light's exact or
// interpolated unshadowed shading by it per pixel (docs/estimator.md, "Shadows").
#ifndef SHADOW_GLSL
#define SHADOW_GLSL
#include "bindings.glsl"

// Whether any light casts shadows: without, no shadow code is compiled in.
layout(constant_id = 17) const bool SHADOWS = false;

// The kernel's texels reach this far (in texels) beyond the point's own texel, plus rounding;
// the lookup point is pushed off the surface by as much, times the sine of the angle between
// the normal and the light, so that a plane never shadows itself (acne), while the offset
// stays within a few texels (no visible gap between a caster and its shadow).
const float SHADOW_TEXEL_SLACK = 1.5;

// Light `light`'s visibility at `position`, on a surface of unit normal `n`; `l` is the unit
// direction towards the light. 1 where the light casts no shadow.
float shadow_visibility(GpuLight light, vec3 position, vec3 n, vec3 l) {
    int first = light.shadow.x;
    if (!SHADOWS || first < 0) {
        return 1.0;
    }
    int radius = light.shadow.y;
    int tile = first;
    float distance_scale = 1.0;
    if (light.position.w != 0.0) {
        // A point light: the cube face of the largest component of the light-to-point vector.
        vec3 d = position - light.position.xyz;
        vec3 a = abs(d);
        int axis = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
        tile += 2 * axis + (d[axis] < 0.0 ? 1 : 0);
        distance_scale = a[axis];
    }
    GpuShadowTile t = shadow_tiles[tile];
    float texel = t.rect.w * distance_scale;
    float cos_theta = clamp(dot(n, l), -1.0, 1.0);
    float sin_theta = sqrt(max(1.0 - cos_theta * cos_theta, 0.0));
    float lift = (float(radius) + SHADOW_TEXEL_SLACK) * texel;
    vec3 lookup = position + n * (lift * sin_theta) + l * (0.5 * texel);
    vec4 clip = t.view_proj * vec4(lookup, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    int size = int(t.rect.z);
    ivec2 origin = ivec2(t.rect.xy);
    ivec2 centre = ivec2(floor((ndc.xy * 0.5 + 0.5) * t.rect.z));
    float depth = ndc.z;
    int lit = 0;
    for (int y = -radius; y <= radius; ++y) {
        for (int x = -radius; x <= radius; ++x) {
            ivec2 texel_at = clamp(centre + ivec2(x, y), ivec2(0), ivec2(size - 1));
            float stored = texelFetch(shadow_atlas, origin + texel_at, 0).r;
            lit += depth <= stored ? 1 : 0;
        }
    }
    int side = 2 * radius + 1;
    return float(lit) / float(side * side);
}

#endif
