// Polygonal area lights seen from one shading point (C. Peters, "BRDF Importance Sampling for
// Polygonal Lights", ACM TOG 40(4), 2021): clipping to the horizon, the closed-form projected
// solid angle, projected-solid-angle sampling, solid-angle sampling of triangle fans, clamped
// optimal MIS weights and a fixed low-discrepancy point set.
// The parts live in `polygon/` and are included below in order; each has a Rust twin of the same
// name in `src/shading/polygon/`, whose `mod.rs` documents the methods and the deviations from
// the paper. Keep the two in step, function for function and operation for operation:
// `tests/polygon_gpu.rs` runs `polygon_check.comp` and compares with the twin.
//
// Directions live in the local shading frame (shading normal +z); a polygon is given by its
// vertices relative to the shading point (convex, planar, either winding).
//
// Rounding: Rust rounds every operation separately and fuses only where it calls `mul_add`, here
// `fused_multiply_add` (GLSL's fma() need not fuse). Every function that does arithmetic is
// `precise`, so that the compiler neither contracts a * b + c into an fma nor reassociates;
// vector lengths and dot products are spelled out in glam's order. Vulkan allows polygon_atan2() an error
// of 4096 ulps, far too much for small polygons (whose solid angles are atan2 of small ratios),
// so `polygon_atan2` is a polynomial accurate to a few ulps.
#ifndef POLYGON_GLSL
#define POLYGON_GLSL

#include "polygon/types.glsl"
#include "polygon/arithmetic.glsl"
#include "polygon/clip.glsl"
#include "polygon/closed_form.glsl"
#include "polygon/ellipse.glsl"
#include "polygon/projected_sampling.glsl"
#include "polygon/solid_angle_sampling.glsl"
#include "polygon/mis.glsl"

#endif
