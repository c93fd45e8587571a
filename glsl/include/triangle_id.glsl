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
// ID_FROM_PRIMITIVE (an indexed draw), the id of the draw's gl_PrimitiveID-th triangle.
void write_triangle_id(uint triangle) {
    if (triangle == ID_FROM_PRIMITIVE) {
        triangle = draw.patch_base + uint(gl_PrimitiveID);
    }
    out_triangle_id = triangle + 1u;
}
#endif

#endif
