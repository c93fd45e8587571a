// The fragment stages' triangle-id output (bindings.glsl, TRIANGLE_IDS): at colour location 1,
// an R32_UINT attachment (src/vk/target.rs, ID_FORMAT), the analysis variant writes which
// triangle the pixel shows: its scene index + 1, or EMITTER_ID_BIT | the light index on a
// polygonal light's emitter; the clear value 0 is nothing.
#ifndef TRIANGLE_ID_GLSL
#define TRIANGLE_ID_GLSL
#include "bindings.glsl"

#if TRIANGLE_IDS
layout(location = 1) out uint out_triangle_id;

// Writes the id of scene triangle `triangle`, as the stage before passed it on; where that was
// ID_FROM_PRIMITIVE (an indexed draw), the id of the draw's gl_PrimitiveID-th triangle: of the
// mesh, or in the draw of the flat patches shaded per pixel (FLAG_FALLBACK_PATCHES), of those
// appended to fallback_indices (bindings.glsl).
void write_triangle_id(uint triangle) {
    if (triangle == ID_FROM_PRIMITIVE) {
        uint primitive = uint(gl_PrimitiveID);
        triangle = (draw.flags & FLAG_FALLBACK_PATCHES) != 0u
            ? fallback_patches[draw.patch_base + draw.triangle_count - 1u - primitive]
            : draw.patch_base + primitive;
    }
    out_triangle_id = triangle + 1u;
}
#endif

#endif
