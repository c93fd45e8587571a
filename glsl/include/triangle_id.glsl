// The fragment stages' triangle-id output (bindings.glsl, TRIANGLE_IDS): at colour location 1,
// an R32_UINT attachment (src/vk/target.rs, ID_FORMAT), the analysis variant writes which
// triangle the pixel shows: its scene index + 1, or EMITTER_ID_BIT | the light index on a
// polygonal light's emitter; the clear value 0 is nothing.
#ifndef TRIANGLE_ID_GLSL
#define TRIANGLE_ID_GLSL
#include "shadow.glsl"

// The scene triangle the fragment lies on, as the stage before passed it on (`triangle`); where
// that was ID_FROM_PRIMITIVE (an indexed draw), the draw's gl_PrimitiveID-th triangle: of the
// mesh, or in the draw of the flat patches shaded per pixel (FLAG_FALLBACK_PATCHES), of those
// appended to fallback_indices (bindings.glsl).
uint fragment_triangle(uint triangle) {
    if (triangle == ID_FROM_PRIMITIVE) {
        uint primitive = uint(gl_PrimitiveID);
        triangle = (draw.flags & FLAG_FALLBACK_PATCHES) != 0u
            ? fallback_patches[draw.patch_base + draw.triangle_count - 1u - primitive]
            : draw.patch_base + primitive;
    }
    return triangle;
}

// Where the fragment on `triangle` (as `fragment_triangle` takes it) looks its shadows up
// (shadow.glsl); nothing where no light casts shadows.
ShadowPoint fragment_shadow_point(uint triangle) {
    if (!SHADOWS) {
        return ShadowPoint(vec3(0.0), vec3(0.0), false);
    }
    return shadow_point(fragment_triangle(triangle), gl_FragCoord.xy);
}

#if TRIANGLE_IDS
layout(location = 1) out uint out_triangle_id;

// Writes the id of the fragment's scene triangle (`fragment_triangle`).
void write_triangle_id(uint triangle) {
    out_triangle_id = fragment_triangle(triangle) + 1u;
}
#endif

#endif
