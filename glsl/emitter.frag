#version 460
// variants: count_evaluations
// The emissive geometry of a polygonal light: its radiance on the emitting side, black behind
// (a one-sided emitter). `emitter_light()` names the light.
#include "triangle_id.glsl"

layout(location = 0) in vec3 in_position;

layout(location = 0) out vec4 out_color;

void main() {
    GpuPolygonLight light = polygon_lights[emitter_light()];
    bool front = dot(light.normal.xyz, draw.eye.xyz - in_position) > 0.0;
    out_color = vec4(front ? light.radiance.rgb : vec3(0.0), 1.0);
#if TRIANGLE_IDS
    out_triangle_id = EMITTER_ID_BIT | emitter_light();
#endif
}
