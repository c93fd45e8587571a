//! CPU analysis tools: the model of the hardware tessellator, the brute-force oracle, the
//! per-triangle report and the image metrics.

pub mod measured;
pub mod metrics;
pub mod oracle;
pub mod report;
pub mod tessellator;
