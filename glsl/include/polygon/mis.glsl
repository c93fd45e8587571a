// Clamped optimal MIS weights (supplement B.3) and the fixed low-discrepancy point set.
// Part of polygon.glsl, which includes its parts in order (each uses only those before it).
// Rust twin: `src/shading/polygon/mis.rs`; `tests/polygon_gpu.rs` checks that the two agree.

// Clamped optimal MIS weights (supplement B.3) of two techniques at one direction: densities,
// coefficients c_j (the estimated unoccluded integral each technique models) and visibility v.
precise vec2 clamped_optimal_mis_weights(vec2 densities, vec2 coefficients, float visibility) {
    precise float density_sum = densities.x + densities.y;
    if (isnan(density_sum) || density_sum <= 0.0) {
        return vec2(0.0);
    }
    precise float weighted_sum = coefficients.x * densities.x + coefficients.y * densities.y;
    precise vec2 weights = vec2(0.0);
    for (int j = 0; j < 2; ++j) {
        precise float balance = densities[j] / density_sum;
        precise float weighted = weighted_sum > 0.0 ? coefficients[j] * densities[j] / weighted_sum : balance;
        weights[j] = clamp(mix_exact(balance, weighted, visibility), 0.0, 1.0);
    }
    return weights;
}

// Point `index` of the shifted Hammersley set of `count` points in [0, 1)^2.
precise vec2 sample_point(uint index, uint count) {
    precise float inverse_count = 1.0 / float(max(count, 1u));
    precise float u_0 = min((float(index) + 0.5) * inverse_count, 1.0 - POLYGON_EPSILON / 2.0);
    precise float radical_inverse = float(bitfieldReverse(index) >> 8) * (1.0 / 16777216.0);
    precise float shifted = radical_inverse + 0.5 * inverse_count;
    precise float u_1 = shifted >= 1.0 ? shifted - 1.0 : shifted;
    return vec2(u_0, u_1);
}
