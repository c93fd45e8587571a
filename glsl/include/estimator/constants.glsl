// The estimator's constants: the f32 values of the Rust constants, signs and add_light's modes,
// and the specialization constants SPLIT and DISCONTINUITY.
// Twin: `src/shading/estimator/constants.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

// Split of epsilon between the terms: 0 Uniform, 1 Heuristic.
layout(constant_id = 3) const int SPLIT = 1;
// Terminator handling: 0 Conservative (fallback), 1 Relaxed.
layout(constant_id = 4) const int DISCONTINUITY = 0;
// The estimator step's variant over the triangles whose every light's specular part is capped
// (range_levels.comp lists them apart, estimator/range.glsl every_specular_capped): no specular
// setup or jets are compiled in.
layout(constant_id = 16) const bool SPECULAR_ALL_CAPPED = false;

// The f32 values of the Rust constants (shortest decimals that round to them).
const float K23 = 1.1547005;
const float BIG = 1.0e18;
const float UNIFORM_TINY = 9.536743e-7;   // 1.0 / 1048576.0
const float SAFETY = 1.01;
const float ANGLE_PAD = 2.0e-6;
// How far the widest or nearest of several angles chosen by pseudo_angle can miss (see
// `CHOICE_PAD` in Rust).
const float CHOICE_PAD = 1.0e-6;
// Relative rounding allowance of the normal's radial scale (see `RADIAL_PAD` in Rust).
const float RADIAL_PAD = 2.0e-6;
// Relaxed: Lg - g <= E_f + TERMINATOR_KINK osc(f) where g = max(f, 0) has its kink (see Rust).
const float TERMINATOR_KINK = 0.25;
// The light part's peaks along the plane (see `TILT_PEAK` and `TILT_FLAT` in Rust).
const float TILT_PEAK = 3.42857146;       // 24.0 / 7.0 in f32
const float TILT_FLAT = 2.6832817;        // sqrt(7.2), rounded up

// The share by which the slack a ball of eyes adds to n.v is grown (see `BALL_SLACK_PAD` in Rust).
const float BALL_SLACK_PAD = 1.0e-4;
const float MAX_HALF = 1.5706964;         // FRAC_PI_2 - 1.0e-4 in f32
const float INV_SQRT3 = 0.57735026;       // 1.0 / 3.0f32.sqrt()
const float THIRD = 0.33333334;           // 1.0 / 3.0
const float TWO_THIRDS = 0.6666667;       // 2.0 / 3.0
const float FOUR_THIRDS = 1.3333334;      // 4.0 / 3.0
const float MIRROR_WORTH = 0.05;          // radians (see Rust)
const float HULL_WORTH = 0.03;            // radians (see Rust)
const float HULL_SHRINK = 0.999;          // 1.0 - 1.0e-3 in f32
const float PI_MINUS_MILLI = 3.1405928;   // PI - 1.0e-3 in f32
const float MIN_D2_SAFE = 1.0010001e-8;   // MIN_LIGHT_DISTANCE_SQUARED * 1.001 in f32
const float INF = 1.0 / 0.0;

const int SIGN_POSITIVE = 0;
const int SIGN_NON_POSITIVE = 1;
const int SIGN_BOTH = 2;

// add_light on a child (ADD_VALUES): its values were taken.
const int VALUES_ADDED = -1;
const float MAX_FINITE = 3.4028235e38;
// A triangle above this level is estimated again with each light's ranges over REFINE_CHILDREN
// children (one midpoint subdivision), for the lights whose range exceeds this share of eps
// (`REFINE_ABOVE`, `REFINE_CHILDREN`, `REFINE_SHARE` in Rust).
const float REFINE_ABOVE = 8.0;
const int REFINE_CHILDREN = 4;
const float REFINE_SHARE = 0.125;
// Refining is skipped where the refining floor exceeds eps by REFINE_FLOOR_MARGIN; the corners'
// values that bound it are shrunk by CORNER_VALUE_MARGIN (the constants of the same names in Rust).
const float REFINE_FLOOR_MARGIN = 1.01;
const float CORNER_VALUE_MARGIN = 1.0e-3;
// A light's specular part within eps * SPECULAR_CAP_SHARE / (number of lights) over the triangle is
// bounded by that cap (`SPECULAR_CAP_SHARE` in Rust).
const float SPECULAR_CAP_SHARE = 0.03125;
// add_light's modes: a patch's bounds; a child's values only; a patch's bounds with its ranges
// from its children's values.
const int ADD_BOUNDS = 0;
const int ADD_VALUES = 1;
const int ADD_REFINED = 2;
