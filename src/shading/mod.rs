//! Rust twins of the GLSL shading functions, used by CPU tests and tools. The formula is the
//! one in the README ("What is rendered"); `glsl/include/brdf.glsl` is its GPU half.
//!
//! Files, bottom to top: each imports through `super::` only from those listed before it.
//! 1. [`brdf`]: the BRDFs' terms.
//! 2. [`derivatives`]: the analytic screen derivatives of a triangle's attributes.
//! 3. [`tonemap`]: the tone map and sRGB encoding.
//! 4. [`polygon`]: polygonal lights' geometry: clipping, closed forms and sampling.
//! 5. [`reflect`]: one point or directional light's reflection.
//! 6. [`polygon_light`]: one polygonal light's reflection.
//! 7. [`shade`]: the outgoing radiance under every light of a scene.
//! 8. [`estimator`]: the error estimator, twin of the GLSL one.

pub mod brdf;
pub mod derivatives;
pub mod estimator;
pub mod polygon;
pub mod polygon_light;
pub mod reflect;
pub mod shade;
pub mod tonemap;

pub use reflect::{light_at, reflect_one_light, reflect_split};
pub use shade::shade_point;
