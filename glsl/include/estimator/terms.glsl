// The estimator's vocabulary: the bound's terms (TERM_COUNT and the term ids, `Term` in Rust) and
// why an estimate asks for per-pixel fallback (the reasons, `Reason` in Rust). The input and the
// result (`TriangleInput`, `Estimate`) are the arguments and the level of estimate_pass.
// Twin: `src/shading/estimator/terms.rs`; proven equal with the rest of the estimator by
// `tests/multirate.rs` (`control_stage_levels_equal_the_twin`).
// A part of estimator.glsl, which includes the parts in dependency order: include that
// header, not this file.

const int TERM_COUNT = 13;
const int T_NORMAL = 0;
const int T_LIGHT = 1;
const int T_VIEW = 2;
const int T_HALF = 3;
const int T_DOT = 4;
const int T_ATTENUATION = 5;
const int T_POWER = 6;
const int T_D = 7;
const int T_F = 8;
const int T_V = 9;
const int T_CROSS = 10;
const int T_TERMINATOR = 11;
const int T_RANGE = 12;
// Not a term: the jets carry the sum of all terms (`Jet::t` in Rust).
const int T_ALL = 13;

// Why an estimate falls back (`Reason` in Rust).
const int REASON_NONE = 0;
const int REASON_LEVEL = 1;
const int REASON_DISCONTINUITY = 2;
const int REASON_SINGULAR = 3;
