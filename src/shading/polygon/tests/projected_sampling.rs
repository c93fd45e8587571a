//! Projected-solid-angle sampling: inside, inverting to its random numbers, its density.

use super::*;

fn is_angle_tiny(case: &Case) -> bool {
    case.name.starts_with("tiny")
}

#[test]
fn psa_samples_are_inside_with_zero_variance() {
    for case in sampling_cases() {
        let clipped = clip_to_horizon(&case.polygon);
        let sampler = prepare_projected_solid_angle(&clipped);
        assert!(!sampler.is_empty(), "{}", case.name);
        let tolerance_psa = 4e-6 * case.psa;
        assert!(
            (sampler.projected_solid_angle() as f64 - case.psa).abs() <= tolerance_psa,
            "{}: {} vs {}",
            case.name,
            sampler.projected_solid_angle(),
            case.psa
        );
        let count = 256;
        for i in 0..count {
            let u = sample_point(i, count);
            let (direction, density) = sample_projected_solid_angle(&sampler, u);
            let label = format!("{} sample {i} {u:?} -> {direction}", case.name);
            assert!(direction.is_finite() && density.is_finite(), "{label}");
            assert!((direction.length() - 1.0).abs() < 1e-5 && direction.z >= 0.0, "{label}");
            // Inside: the ray from the shading point hits the clipped polygon
            assert!(ray_hits_polygon(&case.clipped_reference, direction.as_dvec3(), 1e-6), "{label}");
            // Zero variance for diffuse irradiance: cos θ / p_ω(ω) is the projected solid angle
            let solid_angle_density = projected_to_solid_angle_density(density, direction);
            if direction.z > 1e-3 {
                let estimate = direction.z as f64 / solid_angle_density as f64;
                assert!((estimate - case.psa).abs() <= tolerance_psa, "{label}: {estimate} vs {}", case.psa);
            }
            // The density function agrees with the sampler's density
            assert_eq!(projected_solid_angle_density(&sampler, direction), density, "{label}");
        }
    }
}

/// Projected solid angle of the part of `polygon` in the wedge from xy-direction `from`
/// counterclockwise to `to` (at most 180°).
fn psa_in_wedge(polygon: &[DVec3], from: DVec3, to: DVec3) -> f64 {
    let part = clip_reference(polygon, DVec3::new(-from.y, from.x, 0.0));
    let part = dedupe(&clip_reference(&dedupe(&part), DVec3::new(to.y, -to.x, 0.0)));
    if part.is_empty() {
        0.0
    } else {
        psa_reference(&part).abs()
    }
}

/// The random numbers that map to `direction` in exact arithmetic: `u[0]` from the projected
/// solid angle swept from `start` (the first non-empty sector's boundary), `u[1]` from where the
/// direction's squared xy-radius lies between the polygon's entry and exit along its ray.
fn invert_psa_sample(polygon: &[DVec3], total: f64, start: DVec3, direction: DVec3) -> [f64; 2] {
    let det = start.x * direction.y - start.y * direction.x;
    let dot = start.x * direction.x + start.y * direction.y;
    let swept = if det >= 0.0 || (det.abs() < 1e-12 && dot > 0.0) {
        psa_in_wedge(polygon, start, direction)
    } else {
        total - psa_in_wedge(polygon, direction, start)
    };
    // Crossings of the polygon's boundary with the half-plane through the zenith and direction
    let plane = DVec3::new(-direction.y, direction.x, 0.0);
    let mut radii = Vec::new();
    let count = polygon.len();
    for j in 0..count {
        let (a, b) = (polygon[j], polygon[(j + 1) % count]);
        let (da, db) = (plane.dot(a), plane.dot(b));
        if (da <= 0.0) != (db <= 0.0) {
            let q = (a + (da / (da - db)) * (b - a)).normalize();
            if q.x * direction.x + q.y * direction.y > 0.0 {
                radii.push(q.x * q.x + q.y * q.y);
            }
        }
    }
    let outer = radii.iter().cloned().fold(0.0, f64::max);
    let inner = if radii.len() >= 2 { radii.iter().cloned().fold(f64::INFINITY, f64::min) } else { 0.0 };
    let radius = direction.x * direction.x + direction.y * direction.y;
    [swept / total, (radius - inner) / (outer - inner)]
}

#[test]
fn psa_sampling_inverts_to_its_random_numbers() {
    // The sampled direction sweeps exactly the fraction u[0] of the projected solid angle
    // (Algorithm 3's iteration converged) and sits at the fraction u[1] of the squared radius.
    for case in sampling_cases() {
        if is_angle_tiny(&case) {
            continue;
        }
        let sampler = prepare_projected_solid_angle(&clip_to_horizon(&case.polygon));
        let first = (0..sampler.count).find(|&j| sampler.sector_areas[j] > 0.0).unwrap();
        let start = sampler.sector_dirs[first].extend(0.0).as_dvec3();
        let count = 97;
        let mut worst = [0.0f64; 2];
        for i in 0..count {
            let u = sample_point(i, count);
            let (direction, _) = sample_projected_solid_angle(&sampler, u);
            let inverse = invert_psa_sample(&case.clipped_reference, case.psa, start, direction.as_dvec3());
            for k in 0..2 {
                let error = (inverse[k] - u[k] as f64).abs();
                worst[k] = worst[k].max(error);
                assert!(error < 1e-4, "{} sample {i} {u:?}: inverse {inverse:?} (u[{k}])", case.name);
            }
        }
        assert!(worst[0].is_finite() && worst[1].is_finite());
    }
}

/// The number of `trials` a Bernoulli(p) count may deviate from `p·trials`: 4.5 standard errors.
fn binomial_tolerance(p: f64, trials: usize) -> f64 {
    4.5 * (p * (1.0 - p) / trials as f64).sqrt() + 1e-3
}

#[test]
fn psa_samples_are_distributed_proportional_to_projected_solid_angle() {
    // The fraction of samples on one side of a plane through the shading point matches the
    // projected solid angle there.
    let mut rng = Rng::new(8);
    let trials = 2000;
    for case in sampling_cases().iter().filter(|case| !is_angle_tiny(case)) {
        let sampler = prepare_projected_solid_angle(&clip_to_horizon(&case.polygon));
        let centroid: DVec3 = case.clipped_reference.iter().map(|p| p.normalize()).sum::<DVec3>().normalize();
        for _ in 0..3 {
            let offset = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            let plane = centroid.cross(offset).normalize();
            let part = dedupe(&clip_reference(&case.clipped_reference, plane));
            let expected = if part.is_empty() { 0.0 } else { psa_reference(&part).abs() / case.psa };
            let hits = (0..trials)
                .filter(|_| plane.dot(sample_projected_solid_angle(&sampler, rng.u2()).0.as_dvec3()) >= 0.0)
                .count();
            let fraction = hits as f64 / trials as f64;
            assert!(
                (fraction - expected).abs() <= binomial_tolerance(expected, trials),
                "{}: {fraction} vs {expected}",
                case.name
            );
        }
    }
}

#[test]
fn psa_density_integrates_to_one() {
    // ∫ p_ω dω over the hemisphere with cosine-weighted directions (pdf cos θ/π): the estimator
    // π p_proj(ω) has mean 1 and variance π/Ω_proj − 1.
    let mut rng = Rng::new(9);
    let trials = 20000;
    for case in sampling_cases().iter().filter(|case| !is_angle_tiny(case) && case.psa > 0.3) {
        let sampler = prepare_projected_solid_angle(&clip_to_horizon(&case.polygon));
        let (mut sum, mut sum_squares) = (0.0, 0.0);
        for _ in 0..trials {
            let (r, phi) = (rng.uniform().sqrt(), 2.0 * PI * rng.uniform());
            let direction = DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - r * r).max(0.0).sqrt());
            let estimate = PI * projected_solid_angle_density(&sampler, direction.as_vec3()) as f64;
            sum += estimate;
            sum_squares += estimate * estimate;
        }
        let mean = sum / trials as f64;
        let standard_error = ((sum_squares / trials as f64 - mean * mean) / trials as f64).sqrt();
        let expected_error = ((PI / case.psa - 1.0) / trials as f64).sqrt();
        assert!(
            (mean - 1.0).abs() <= 4.5 * expected_error.max(standard_error),
            "{}: {mean} ± {standard_error}",
            case.name
        );
    }
}

#[test]
fn psa_samples_of_tiny_polygons_stay_inside() {
    // 1e-4 wide at distance 1: inside up to 1e-6 radians (1 % of the width), checked for a dense
    // set of random numbers including the ends of the unit square. Near the horizon, where
    // z = √(1 − |xy|²) turns the absolute f32 resolution ε of xy into ε/z radians, 2ε/z more.
    let mut rng = Rng::new(10);
    for case in sampling_cases().iter().filter(|case| is_angle_tiny(case)) {
        let sampler = prepare_projected_solid_angle(&clip_to_horizon(&case.polygon));
        let edges = [0.0, 1e-6, 0.5, 1.0 - 1e-6, 1.0 - f32::EPSILON / 2.0];
        let mut points: Vec<[f32; 2]> =
            edges.iter().flat_map(|&a| edges.iter().map(move |&b| [a, b])).collect();
        points.extend((0..500).map(|_| rng.u2()));
        for u in points {
            let (direction, density) = sample_projected_solid_angle(&sampler, u);
            assert!(direction.is_finite() && density > 0.0, "{} {u:?}", case.name);
            let tolerance = 1e-6 + 2.0 * f32::EPSILON as f64 / direction.z as f64;
            assert!(
                ray_hits_polygon(&case.clipped_reference, direction.as_dvec3(), tolerance),
                "{} {u:?}",
                case.name
            );
        }
    }
}
