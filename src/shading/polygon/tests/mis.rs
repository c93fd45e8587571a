//! The MIS weights and an unbiased estimate with a polygonal light.

use super::*;

#[test]
fn mis_weights_sum_to_one_and_blend_the_two_balance_heuristics() {
    let mut rng = Rng::new(14);
    for trial in 0..4000 {
        let mut densities = [rng.range(0.0, 10.0) as f32, 10f64.powf(rng.range(-6.0, 6.0)) as f32];
        match trial % 5 {
            0 => densities[0] = 0.0,
            1 => densities[1] = 0.0,
            _ => {}
        }
        let mut coefficients = [rng.range(0.0, 3.0) as f32, rng.range(0.0, 3.0) as f32];
        if trial % 7 == 0 {
            coefficients = [0.0, 0.0];
        }
        for visibility in [0.0, 0.25, DEFAULT_MIS_VISIBILITY, 1.0] {
            let weights = clamped_optimal_mis_weights(densities, coefficients, visibility);
            assert!(weights.iter().all(|w| (0.0..=1.0).contains(w)), "{weights:?}");
            assert!((weights[0] + weights[1] - 1.0).abs() < 4.0 * f32::EPSILON, "{weights:?}");
            // A technique that cannot produce the direction gets weight 0
            for j in 0..2 {
                if densities[j] == 0.0 {
                    assert_eq!(weights[j], 0.0);
                }
            }
            // v = 0: balance heuristic
            let balance = densities[0] as f64 / (densities[0] as f64 + densities[1] as f64);
            let weighted_sum =
                coefficients[0] as f64 * densities[0] as f64 + coefficients[1] as f64 * densities[1] as f64;
            let weighted = if weighted_sum > 0.0 {
                coefficients[0] as f64 * densities[0] as f64 / weighted_sum
            } else {
                balance
            };
            let expected = (1.0 - visibility as f64) * balance + visibility as f64 * weighted;
            assert!(
                (weights[0] as f64 - expected).abs() < 1e-6,
                "{densities:?} {coefficients:?} {visibility}"
            );
        }
        // v = 1 without occlusion and with an exact model f = c₀p₀ + c₁p₁: every weighted
        // contribution (f/pⱼ) wⱼ is the constant cⱼ (zero variance).
        if densities[0] > 0.0 && densities[1] > 0.0 && coefficients[0] + coefficients[1] > 0.0 {
            let f =
                coefficients[0] as f64 * densities[0] as f64 + coefficients[1] as f64 * densities[1] as f64;
            let weights = clamped_optimal_mis_weights(densities, coefficients, 1.0);
            for j in 0..2 {
                let contribution = f / densities[j] as f64 * weights[j] as f64;
                assert!((contribution - coefficients[j] as f64).abs() < 1e-5 * (1.0 + f), "{contribution}");
            }
        }
    }
    assert_eq!(clamped_optimal_mis_weights([0.0, 0.0], [1.0, 1.0], 0.5), [0.0, 0.0]);
}

#[test]
fn mis_estimate_with_a_polygonal_light_is_unbiased() {
    // f(ω) = L (kd + ks max(0, ω·r)^16) cos θ on the light. Technique 0: projected-solid-angle
    // light sampling; technique 1: cosine-weighted hemisphere ("BRDF") sampling. Each pair of
    // samples gives Σⱼ wⱼ f/pⱼ; its mean must match a converged light-sampling estimate.
    let mut rng = Rng::new(15);
    let (kd, ks, radiance) = (0.6, 4.0, 2.0);
    let r = DVec3::new(0.5, 0.3, 0.8).normalize();
    let integrand = |d: DVec3| radiance * (kd + ks * d.dot(r).max(0.0).powi(16)) * d.z.max(0.0);
    for case in sampling_cases().iter().filter(|case| {
        ["decentral pentagon", "clipped tilted quad (contains the zenith)"]
            .iter()
            .any(|n| case.name.starts_with(n))
    }) {
        let sampler = prepare_projected_solid_angle(&clip_to_horizon(&case.polygon));
        let psa = sampler.projected_solid_angle() as f64;
        // Reference: light sampling, f/p = psa (kd + ks lobe) L with a dense point set
        let reference_count = 1 << 15;
        let reference = (0..reference_count)
            .map(|i| {
                let (d, density) = sample_projected_solid_angle(&sampler, sample_point(i, reference_count));
                let d = d.as_dvec3();
                integrand(d) / (density as f64 * d.z)
            })
            .sum::<f64>()
            / reference_count as f64;
        let coefficients = [(kd * radiance * psa) as f32, (0.3 * ks * radiance) as f32];
        for visibility in [0.0, DEFAULT_MIS_VISIBILITY, 1.0] {
            let trials = 4000;
            let (mut sum, mut sum_squares) = (0.0, 0.0);
            for _ in 0..trials {
                let mut estimate = 0.0;
                // light sample
                let (d, density) = sample_projected_solid_angle(&sampler, rng.u2());
                let p_light = projected_to_solid_angle_density(density, d) as f64;
                if p_light > 0.0 {
                    let p_brdf = d.z as f64 / PI;
                    let w = clamped_optimal_mis_weights(
                        [p_light as f32, p_brdf as f32],
                        coefficients,
                        visibility,
                    );
                    estimate += w[0] as f64 * integrand(d.as_dvec3()) / p_light;
                }
                // BRDF sample
                let (radius, phi) = (rng.uniform().sqrt(), 2.0 * PI * rng.uniform());
                let d = DVec3::new(
                    radius * phi.cos(),
                    radius * phi.sin(),
                    (1.0 - radius * radius).max(0.0).sqrt(),
                );
                let p_brdf = d.z / PI;
                let p_light = projected_to_solid_angle_density(
                    projected_solid_angle_density(&sampler, d.as_vec3()),
                    d.as_vec3(),
                );
                if p_light > 0.0 && p_brdf > 0.0 {
                    let w = clamped_optimal_mis_weights([p_light, p_brdf as f32], coefficients, visibility);
                    estimate += w[1] as f64 * integrand(d) / p_brdf;
                }
                sum += estimate;
                sum_squares += estimate * estimate;
            }
            let mean = sum / trials as f64;
            let standard_error = ((sum_squares / trials as f64 - mean * mean) / trials as f64).sqrt();
            assert!(
                (mean - reference).abs() <= 4.5 * standard_error + 2e-3 * reference,
                "{} v={visibility}: {mean} ± {standard_error} vs {reference}",
                case.name
            );
        }
    }
}
