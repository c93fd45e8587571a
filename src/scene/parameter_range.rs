//! [`ParameterRange`]: the range a textured material parameter (Blinn-Phong shininess, GGX
//! roughness) takes over a triangle. The texture code computes it, the error estimator
//! (`shading::estimator::estimate_textured`) bounds the shading over it.
//!
//! GLSL twin: the `vec2` (lo, hi) that `parameter_range_of` in `glsl/include/triangle_level.glsl`
//! returns. Proof that the twins are equal: `tests/multirate.rs`
//! `control_stage_levels_equal_the_twin` (its textured scenes' levels hang on the range).

use crate::scene::MaterialKind;

/// The range `[lo, hi]` a textured parameter (Blinn-Phong shininess, GGX roughness) takes
/// over a triangle's texels (seed 003 Sec. 3.5, Eq. 34–38). `lo == hi` is an untextured
/// material; Lambert ignores it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParameterRange {
    pub lo: f32,
    pub hi: f32,
}

impl ParameterRange {
    /// The material's own (untextured) parameter: shininess, roughness, or 0 for Lambert.
    pub fn of(material: &MaterialKind) -> ParameterRange {
        let value = match *material {
            MaterialKind::Lambert { .. } => 0.0,
            MaterialKind::BlinnPhong { shininess, .. } => shininess,
            MaterialKind::Ggx { roughness, .. } => roughness,
        };
        ParameterRange { lo: value, hi: value }
    }
}
