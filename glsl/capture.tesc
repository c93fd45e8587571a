#version 460
// Tessellator capture: levels from push constants.
layout(vertices = 3) out;
layout(push_constant) uniform Levels { vec4 outer; float inner; } levels;

void main() {
    if (gl_InvocationID == 0) {
        gl_TessLevelInner[0] = levels.inner;
        gl_TessLevelOuter[0] = levels.outer.x;
        gl_TessLevelOuter[1] = levels.outer.y;
        gl_TessLevelOuter[2] = levels.outer.z;
    }
}
