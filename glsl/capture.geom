#version 460
// Tessellator capture: records every emitted triangle as its three gl_TessCoord values, in the
// order the primitive arrives (its winding).
layout(triangles) in;
layout(points, max_vertices = 1) out;
layout(set = 0, binding = 1, std430) buffer Triangles { uint triangle_count; uint pad[3]; vec4 corners[]; };
layout(location = 0) in vec3 in_coord[];

void main() {
    uint slot = atomicAdd(triangle_count, 1u);
    if (3u * slot + 2u < uint(corners.length())) {
        for (int k = 0; k < 3; ++k) {
            corners[3u * slot + uint(k)] = vec4(in_coord[k], 0.0);
        }
    }
}
