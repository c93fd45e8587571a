//! Analytic screen-space derivatives of vertex attributes (seed 002, Chao Jia, "Vertex Attribute
//! Interpolation and Analytical Derivatives"): perspective-correct barycentrics at a pixel,
//! their derivatives per pixel step, attributes interpolated with them, and Vulkan's isotropic
//! texture LOD. The GLSL twin is `glsl/include/derivatives.glsl`, operation for operation.
//!
//! # Conventions
//!
//! Vulkan clip space `(x, y, z, w)`, NDC = `clip.xyz / w`; framebuffer pixel `(px, py)` from the
//! top-left corner with pixel centres at `+0.5`, `ndc = 2·pixel / viewport − 1` (positive
//! viewport height, so NDC y grows downwards like `py`).
//!
//! # Derivation
//!
//! With `nᵢ` the NDC of vertex i and `p` that of the pixel, the screen-space barycentrics are
//! `λⁿᵢ = cross(n_{i+1} − p, n_{i+2} − p) / D` (indices mod 3, `D = cross(n₁ − n₀, n₂ − n₀)`,
//! `cross(a, b) = a.x·b.y − b.x·a.y`), so `∂λⁿᵢ/∂xⁿ = (n_{i+1}.y − n_{i+2}.y) / D` and
//! `∂λⁿᵢ/∂yⁿ = (n_{i+2}.x − n_{i+1}.x) / D`. `1/w = Σ λⁿᵢ / wᵢ` is linear in screen space and the
//! perspective-correct barycentrics are `λᵢ = w·λⁿᵢ / wᵢ`. For any attribute `A = Σ λᵢ Aᵢ`,
//! `∂A/∂xⁿ = Σ (Aᵢ − A)·Tᵢ` with `Tᵢ = (w / wᵢ)·∂λⁿᵢ/∂xⁿ` (the blog's `T_x`); taking `Aᵢ` to be
//! the unit vectors gives `∂λᵢ/∂xⁿ = Tᵢ − λᵢ·Σₖ Tₖ`. One pixel step is `2/width` in `xⁿ` and
//! `2/height` in `yⁿ`, so `T` is scaled by those factors to give derivatives per pixel.

use glam::{Vec2, Vec3, Vec4, Vec4Swizzles};

/// The smallest texel footprint [`texture_lod`] takes the logarithm of, 2⁻¹⁰⁰: zero
/// derivatives give LOD −100 (finite) instead of −∞.
pub const MIN_FOOTPRINT: f32 = 7.888_609e-31;

/// Perspective-correct barycentrics of a pixel and their derivatives per pixel step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarycentricDerivatives {
    /// `λᵢ` with `Σ λᵢ Vᵢ` the point (in any pre-perspective space) seen at the pixel.
    pub lambda: Vec3,
    /// `∂λ/∂px`: change per pixel step to the right. Components sum to zero.
    pub ddx: Vec3,
    /// `∂λ/∂py`: change per pixel step down. Components sum to zero.
    pub ddy: Vec3,
}

impl BarycentricDerivatives {
    /// What [`barycentric_derivatives`] returns for degenerate inputs: the centroid, no change.
    pub const DEGENERATE: BarycentricDerivatives =
        BarycentricDerivatives { lambda: Vec3::splat(1.0 / 3.0), ddx: Vec3::ZERO, ddy: Vec3::ZERO };
}

fn cross2(a: Vec2, b: Vec2) -> f32 {
    a.x * b.y - b.x * a.y
}

/// Perspective-correct barycentrics at framebuffer position `pixel` (in pixels, see the module
/// conventions) of the triangle with clip-space vertices `clip`, on a `viewport` of
/// width×height pixels, and their derivatives per pixel step.
///
/// The pixel may lie outside the triangle (the barycentrics then extrapolate). Degenerate input
/// gives [`BarycentricDerivatives::DEGENERATE`] (never NaN): a vertex with `w ≤ 0` (or NaN), a
/// projected triangle of zero area, a pixel on or beyond the triangle's horizon (`1/w ≤ 0`
/// there), or any other input that makes a result non-finite.
pub fn barycentric_derivatives(clip: [Vec4; 3], pixel: Vec2, viewport: Vec2) -> BarycentricDerivatives {
    let [c0, c1, c2] = clip;
    if !(c0.w > 0.0 && c1.w > 0.0 && c2.w > 0.0) {
        return BarycentricDerivatives::DEGENERATE;
    }
    let inv_w = Vec3::new(1.0 / c0.w, 1.0 / c1.w, 1.0 / c2.w);
    let n0 = c0.xy() * inv_w.x;
    let n1 = c1.xy() * inv_w.y;
    let n2 = c2.xy() * inv_w.z;
    let p = 2.0 * pixel / viewport - 1.0;
    let inv_area = 1.0 / cross2(n1 - n0, n2 - n0);
    let (a0, a1, a2) = (n0 - p, n1 - p, n2 - p);
    let lambda_n = Vec3::new(cross2(a1, a2), cross2(a2, a0), cross2(a0, a1)) * inv_area;
    let dndx = Vec3::new(n1.y - n2.y, n2.y - n0.y, n0.y - n1.y) * inv_area;
    let dndy = Vec3::new(n2.x - n1.x, n0.x - n2.x, n1.x - n0.x) * inv_area;
    let q = lambda_n * inv_w;
    let inv_w_pixel = q.x + q.y + q.z;
    let w = 1.0 / inv_w_pixel;
    let lambda = q * w;
    let step = 2.0 / viewport;
    let tx = dndx * inv_w * (w * step.x);
    let ty = dndy * inv_w * (w * step.y);
    let ddx = tx - lambda * (tx.x + tx.y + tx.z);
    let ddy = ty - lambda * (ty.x + ty.y + ty.z);
    if !(inv_w_pixel > 0.0 && lambda.is_finite() && ddx.is_finite() && ddy.is_finite()) {
        return BarycentricDerivatives::DEGENERATE;
    }
    BarycentricDerivatives { lambda, ddx, ddy }
}

/// A 2-vector vertex attribute (such as uv) at the pixel: `(value, ∂/∂px, ∂/∂py)`.
pub fn interpolate2(b: &BarycentricDerivatives, a: [Vec2; 3]) -> (Vec2, Vec2, Vec2) {
    let value = a[0] * b.lambda.x + a[1] * b.lambda.y + a[2] * b.lambda.z;
    let ddx = a[0] * b.ddx.x + a[1] * b.ddx.y + a[2] * b.ddx.z;
    let ddy = a[0] * b.ddy.x + a[1] * b.ddy.y + a[2] * b.ddy.z;
    (value, ddx, ddy)
}

/// A 3-vector vertex attribute (position, normal) at the pixel: `(value, ∂/∂px, ∂/∂py)`.
pub fn interpolate3(b: &BarycentricDerivatives, a: [Vec3; 3]) -> (Vec3, Vec3, Vec3) {
    let value = a[0] * b.lambda.x + a[1] * b.lambda.y + a[2] * b.lambda.z;
    let ddx = a[0] * b.ddx.x + a[1] * b.ddx.y + a[2] * b.ddx.z;
    let ddy = a[0] * b.ddy.x + a[1] * b.ddy.y + a[2] * b.ddy.z;
    (value, ddx, ddy)
}

/// Vulkan's isotropic level of detail for texture coordinates with these derivatives per pixel
/// on a texture of `texture_size` texels: `log2(max(|∂uv/∂x·size|, |∂uv/∂y·size|))`. The
/// footprint is taken to be at least [`MIN_FOOTPRINT`], so zero derivatives give −100, not −∞.
pub fn texture_lod(duv_dx: Vec2, duv_dy: Vec2, texture_size: Vec2) -> f32 {
    let rho_x = (duv_dx * texture_size).length();
    let rho_y = (duv_dy * texture_size).length();
    rho_x.max(rho_y).max(MIN_FOOTPRINT).log2()
}

#[cfg(test)]
mod tests;
