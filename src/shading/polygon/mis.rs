//! Clamped optimal MIS weights (supplement B.3) and the fixed low-discrepancy point set both
//! techniques draw their samples from. Twin of `glsl/include/polygon/mis.glsl`, operation for
//! operation; `tests/polygon_gpu.rs` checks that the two agree.

use super::arithmetic::mix;

/// Clamped optimal MIS weights (supplement B.3) of two techniques at one direction, e.g. a light
/// technique and a BRDF technique. `densities[j]` is technique j's density at the direction (both
/// in the same measure) and `coefficients[j] = cⱼ ≥ 0` the estimated unoccluded integral of the
/// part of the integrand that technique j's density models, i.e. the model `f ≈ V Σₖ cₖ pₖ` of
/// Eq. (B.1) (for projected-solid-angle light sampling of a diffuse surface,
/// `c = kd · L · projected_solid_angle`). `visibility` is `v` ([`DEFAULT_MIS_VISIBILITY`]).
///
/// Derivation: B.3 splits the optimal-MIS contribution of a sample ωⱼ from technique j into a
/// part for visible samples, `f(ωⱼ) (v cⱼ / Σₖ cₖ pₖ(ωⱼ) + (1 − v) / Σₖ pₖ(ωⱼ))`, and a zero-mean
/// part for occluded ones, which clamping drops. Since a weight is the contribution divided by
/// `f/pⱼ`:
///
/// `wⱼ = v · cⱼ pⱼ / Σₖ cₖ pₖ + (1 − v) · pⱼ / Σₖ pₖ`,
///
/// the blend of the weighted balance heuristic (v = 1, zero variance without occluders when the
/// model is exact: `(f/pⱼ) wⱼ = cⱼ`) and the balance heuristic (v = 0). Both weights lie in
/// [0, 1] and sum to 1 (up to rounding) wherever `Σₖ pₖ > 0`; where `Σₖ cₖ pₖ = 0` the weighted
/// part falls back to the balance heuristic. Both weights are 0 where both densities are.
///
/// [`DEFAULT_MIS_VISIBILITY`]: super::DEFAULT_MIS_VISIBILITY
pub fn clamped_optimal_mis_weights(densities: [f32; 2], coefficients: [f32; 2], visibility: f32) -> [f32; 2] {
    let density_sum = densities[0] + densities[1];
    if density_sum.is_nan() || density_sum <= 0.0 {
        return [0.0, 0.0];
    }
    let weighted_sum = coefficients[0] * densities[0] + coefficients[1] * densities[1];
    // Each weight from its own formula (not 1 − the other), so that small weights keep their
    // relative accuracy: the contribution (f/pⱼ) wⱼ multiplies them by a large f/pⱼ.
    let mut weights = [0.0; 2];
    for j in 0..2 {
        let balance = densities[j] / density_sum;
        let weighted =
            if weighted_sum > 0.0 { coefficients[j] * densities[j] / weighted_sum } else { balance };
        weights[j] = mix(balance, weighted, visibility).clamp(0.0, 1.0);
    }
    weights
}

/// Point `index` of a deterministic 2D low-discrepancy set of `count` points in [0, 1)²: the
/// Hammersley set `((i + ½)/n, φ₂(i) + ½/n mod 1)` (φ₂ the base-2 radical inverse), shifted by
/// half a stratum. For `count` a power of two (up to 2²⁴) it is a (0, m, 2)-net: every dyadic box
/// of area `1/count` holds exactly one point. `index` should be below `count`.
pub fn sample_point(index: u32, count: u32) -> [f32; 2] {
    let inverse_count = 1.0 / count.max(1) as f32;
    let u_0 = ((index as f32 + 0.5) * inverse_count).min(1.0 - f32::EPSILON / 2.0);
    let radical_inverse = (index.reverse_bits() >> 8) as f32 * (1.0 / 16_777_216.0);
    let shifted = radical_inverse + 0.5 * inverse_count;
    let u_1 = if shifted >= 1.0 { shifted - 1.0 } else { shifted };
    [u_0, u_1]
}
