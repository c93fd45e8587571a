#version 460
// Visibility buffer vertex stage: forward.vert's transform (the same precise expression, so
// the ids cover exactly the pixels the `pixel` mode shades), without the attributes.
#include "bindings.glsl"

layout(location = 0) in vec3 in_position;

precise gl_Position;

void main() {
    gl_Position = draw.view_proj * vec4(in_position, 1.0);
}
