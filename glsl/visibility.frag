#version 460
// Visibility buffer: which triangle covers the pixel. x: mesh index + 1 (0: nothing), y: the
// triangle's index in the scene, alpha: coverage. Floats hold both exactly below 2^24.
#include "bindings.glsl"

layout(location = 0) out vec4 out_id;

layout(early_fragment_tests) in;

void main() {
    out_id = vec4(float(draw.mesh_index + 1u), float(draw.patch_base + uint(gl_PrimitiveID)), 0.0, 1.0);
}
