#version 460
// Tessellator capture: records gl_TessCoord of every invocation.
layout(triangles, equal_spacing, ccw) in;
layout(set = 0, binding = 0, std430) buffer Coords { uint coord_count; uint pad[3]; vec4 coords[]; };
layout(location = 0) out vec3 out_coord;

void main() {
    uint slot = atomicAdd(coord_count, 1u);
    if (slot < uint(coords.length())) {
        coords[slot] = vec4(gl_TessCoord, 0.0);
    }
    out_coord = gl_TessCoord;
    gl_Position = vec4(gl_TessCoord, 1.0);
}
