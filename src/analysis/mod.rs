//! CPU analysis tools: the model of the hardware tessellator, the effective levels of its
//! patterns, the brute-force oracle, the per-triangle report and the image metrics.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`tessellator`]: the fixed-function tessellator's model: the pattern it emits for given levels.
//! 2. [`oracle`]: the brute-force truth: the actual error of interpolating over a pattern.
//! 3. [`pattern_level`]: the effective levels of tessellation patterns (`docs/estimator.md` §9).
//! 4. [`measured`]: per-triangle measured error beside the error the estimator predicted.
//! 5. [`metrics`]: image error against the per-pixel reference (L∞, mean L2, FLIP, fallback masks).
//! 6. [`report`]: `multirate analyze`: per visible triangle, the estimator's levels against the oracle's.
//! 7. [`temporal`]: temporal stability along a camera path: each frame's error against the one
//!    before at the same surface point.

pub mod measured;
pub mod metrics;
pub mod oracle;
pub mod pattern_level;
pub mod report;
pub mod temporal;
pub mod tessellator;
