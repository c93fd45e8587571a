// The per-triangle error estimator: the GLSL port of `src/shading/estimator/` (the source of
// truth; its docs and `docs/estimator.md` have the derivation). Keep the two in step, operation
// for operation: the control stage must choose exactly the levels the Rust twin
// (`analysis::report`) predicts, and a GPU test compares them triangle by triangle.
//
// Porting rules followed throughout:
// - every floating-point result is `precise` (P): no fused multiply-adds or reassociation,
//   so the level of a triangle is bit-identical in every patch that evaluates it (its own and
//   its three neighbours'), and as close as possible to the Rust f32 arithmetic;
// - the same operation order as Rust, with glam's formulas for dot, cross, length and
//   max_element written out (dot3, cross3, ...);
// - Rust's NaN behaviour where NaN can arise: `f32::max`/`min` ignore a NaN operand (rmax,
//   rmin), comparisons are false;
// - its own sin, cos, atan2, acos, asin and pow (bit-identical to the Rust ones, exact_math.glsl);
// - `acos` only ever sees arguments in [0, 1] (clamped as in Rust).
// Only the scene's material kind and light counts are compiled in (specialization constants of
// brdf.glsl), plus SPLIT and DISCONTINUITY (estimator/constants.glsl).
//
// Each file is the twin of one Rust module; the parts under estimator/ follow in dependency order
// and are included only from here:
//
// | Rust                                  | GLSL                        | test proving them equal             |
// |---------------------------------------|-----------------------------|-------------------------------------|
// | src/exact_math.rs                     | exact_math.glsl             | control_stage_levels_equal_the_twin |
// | src/shading/estimator/constants.rs    | estimator/constants.glsl    | control_stage_levels_equal_the_twin |
// | src/shading/estimator/terms.rs        | estimator/terms.glsl        | control_stage_levels_equal_the_twin |
// | src/shading/estimator/patch_levels.rs | estimator/patch_levels.glsl | control_stage_levels_equal_the_twin |
// | src/shading/estimator/pattern.rs      | estimator/pattern.glsl      | control_stage_levels_equal_the_twin |
// | src/shading/estimator/jet.rs          | estimator/jet.glsl          | control_stage_levels_equal_the_twin |
// | src/shading/estimator/cone.rs         | estimator/cone.glsl         | control_stage_levels_equal_the_twin |
// | src/shading/estimator/frame.rs        | estimator/frame.glsl        | control_stage_levels_equal_the_twin |
// | src/shading/estimator/light_setup.rs  | estimator/light_setup.glsl  | control_stage_levels_equal_the_twin |
// | src/shading/estimator/lobe.rs         | estimator/lobe.glsl         | control_stage_levels_equal_the_twin |
// | src/shading/estimator/irradiance.rs   | estimator/irradiance.glsl   | control_stage_levels_equal_the_twin |
// | src/shading/estimator/terminator.rs   | estimator/terminator.glsl   | control_stage_levels_equal_the_twin |
// | src/shading/estimator/range.rs        | estimator/range.glsl        | control_stage_levels_equal_the_twin |
// | src/shading/estimator/decide.rs       | estimator/decide.glsl       | control_stage_levels_equal_the_twin |
// | src/shading/estimator/add_light.rs    | estimator/add_light.glsl    | control_stage_levels_equal_the_twin |
// | src/shading/estimator/estimate.rs     | estimator/estimate.glsl     | control_stage_levels_equal_the_twin |
// (`control_stage_levels_equal_the_twin` is in `tests/multirate.rs`.)
#ifndef ESTIMATOR_GLSL
#define ESTIMATOR_GLSL
#include "brdf.glsl"
#include "exact_math.glsl"
#include "estimator/constants.glsl"
#include "estimator/terms.glsl"
#include "estimator/patch_levels.glsl"
#include "estimator/pattern.glsl"
#include "estimator/jet.glsl"
#include "estimator/cone.glsl"
#include "estimator/frame.glsl"
#include "estimator/light_setup.glsl"
#include "estimator/lobe.glsl"
#include "estimator/irradiance.glsl"
#include "estimator/terminator.glsl"
#include "estimator/range.glsl"
#include "estimator/decide.glsl"
#include "estimator/add_light.glsl"
#include "estimator/estimate.glsl"
#endif
