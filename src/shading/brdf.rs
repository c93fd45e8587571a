//! Rust twin of `glsl/include/brdf.glsl`: the BRDF building blocks, operation for operation.

use glam::Vec3;

pub const GGX_MIN_ALPHA: f32 = 1.0e-3;
pub const MIN_LIGHT_DISTANCE_SQUARED: f32 = 1.0e-8;

/// v / |v|, and the zero vector for the zero vector (never NaN).
pub fn safe_normalize(v: Vec3) -> Vec3 {
    v * (1.0 / v.dot(v).max(1.0e-30).sqrt())
}

/// GGX / Trowbridge-Reitz normal distribution.
pub fn ggx_d(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    a2 / (std::f32::consts::PI * d * d)
}

/// The same of `s = sin²θ_h = 1 − (n·h)²` (`n·h ≥ 0`), which the shading takes as `|n × h|²`:
/// near the highlight `(n·h)²(α² − 1) + 1` cancels in f32 to about `α²`, and the lobe's peak
/// `1/(πα²)` amplifies the rounding of `n·h` into an error that does not fall with the
/// tessellation level (`docs/estimator.md` §6). [`ggx_d`] keeps the `n·h` form for the
/// estimator, whose GLSL twin repeats it operation for operation.
pub fn ggx_d_sin2(sin2: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let d = sin2 * (1.0 - a2) + a2;
    a2 / (std::f32::consts::PI * d * d)
}

/// Schlick's Fresnel approximation.
pub fn schlick_f(v_dot_h: f32, f0: Vec3) -> Vec3 {
    let m = 1.0 - v_dot_h;
    let m2 = m * m;
    f0 + (Vec3::ONE - f0) * (m2 * m2 * m)
}

/// Smith / Schlick-GGX visibility with the microfacet cosines folded in.
pub fn smith_v(n_dot_l: f32, n_dot_v: f32, k: f32) -> f32 {
    1.0 / ((n_dot_l * (1.0 - k) + k) * (n_dot_v * (1.0 - k) + k))
}

/// GGX alpha from the scene's roughness.
pub fn ggx_alpha(roughness: f32) -> f32 {
    (roughness * roughness).max(GGX_MIN_ALPHA)
}
