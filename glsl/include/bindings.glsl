// The forward passes' resource interface: one descriptor set and the per-draw push constants.
#ifndef BINDINGS_GLSL
#define BINDINGS_GLSL
#include "types.glsl"

layout(set = 0, binding = 0, std430) readonly buffer Lights { GpuLight lights[]; };
layout(set = 0, binding = 1, std430) readonly buffer Materials { GpuMaterial materials[]; };
layout(push_constant, std430) uniform Push { DrawConstants draw; };

#endif
