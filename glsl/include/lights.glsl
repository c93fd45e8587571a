// The scene's point and directional lights: how many of each (specialization constants), in
// `lights` point lights first (bindings.glsl).
#ifndef LIGHTS_GLSL
#define LIGHTS_GLSL
#include "bindings.glsl"

layout(constant_id = 1) const int POINT_LIGHT_COUNT = 0;
layout(constant_id = 2) const int DIRECTIONAL_LIGHT_COUNT = 0;

#endif
