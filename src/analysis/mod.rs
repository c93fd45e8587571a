//! CPU analysis tools: the model of the hardware tessellator and the brute-force oracle.

pub mod oracle;
pub mod report;
pub mod tessellator;
