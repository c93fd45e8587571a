//! CPU analysis tools: the model of the hardware tessellator, the effective levels of its
//! patterns, the brute-force oracle, the per-triangle report and the image metrics.

pub mod measured;
pub mod metrics;
pub mod oracle;
pub mod pattern_level;
pub mod report;
pub mod tessellator;
