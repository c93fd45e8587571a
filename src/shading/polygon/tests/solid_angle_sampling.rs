//! Solid-angle sampling of the triangle fan: accuracy, inversion, density.

use super::*;

fn solid_angle_cases() -> Vec<Case> {
    let mut rng = Rng::new(11);
    let mut cases: Vec<Case> =
        sampling_cases().into_iter().filter(|case| !case.name.starts_with("huge")).collect();
    cases.push(case("triangle", &facing_polygon(3, DVec3::new(0.4, 0.3, 1.0), 0.7, &mut rng)));
    cases.push(case(
        "triangle across the horizon (unclipped)",
        &facing_polygon(3, DVec3::new(1.0, 0.2, 0.0), 0.6, &mut rng),
    ));
    cases.push(case("big triangle", &[v(-3.0, -2.0, 1.0), v(3.0, -2.0, 1.0), v(0.0, 3.0, 0.5)]));
    for size in [1e-4, 1e-5] {
        cases.push(case(
            &format!("tiny triangle {size}"),
            &facing_polygon(3, DVec3::new(0.3, -0.5, 0.8).normalize(), size, &mut rng),
        ));
    }
    cases
}

#[test]
fn solid_angle_matches_f64_including_tiny_triangles() {
    for case in solid_angle_cases() {
        let expected = solid_angle_reference(&to_f64(case.polygon.as_slice()));
        let sampler = prepare_solid_angle(&case.polygon);
        let relative = (sampler.solid_angle() as f64 / expected - 1.0).abs();
        assert!(relative < 4e-6, "{}: {} vs {expected}", case.name, sampler.solid_angle());
    }
    // With the Laplace expansion of normalised directions the determinant of a 1e-4 triangle would
    // be off by order ε/size² ≈ 10; the Householder form on differences stays accurate even here.
    let mut rng = Rng::new(12);
    for size in [1e-3, 1e-5, 1e-7] {
        for _ in 0..20 {
            let center = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            let vertices = facing_polygon(3, center, size * center.length(), &mut rng);
            let expected = solid_angle_reference(&to_f64(&vertices));
            let sampler = prepare_solid_angle(&Polygon::new(&vertices));
            assert!((sampler.solid_angle() as f64 / expected - 1.0).abs() < 4e-6, "size {size}");
        }
    }
}

#[test]
fn solid_angle_samples_are_inside_and_invert_to_their_random_numbers() {
    for case in solid_angle_cases() {
        let polygon = to_f64(case.polygon.as_slice());
        let sampler = prepare_solid_angle(&case.polygon);
        let total = solid_angle_reference(&polygon);
        let apex = polygon[0].normalize();
        let second = polygon[1].normalize();
        let tiny = case.name.starts_with("tiny");
        let count = 128;
        for i in 0..count {
            let u = sample_point(i, count);
            let (direction, density) = sample_solid_angle(&sampler, u);
            let label = format!("{} sample {i} {u:?} -> {direction}", case.name);
            let d = direction.as_dvec3();
            assert!(direction.is_finite() && (d.length() - 1.0).abs() < 1e-5, "{label}");
            assert!(ray_hits_polygon(&polygon, d, 1e-6), "{label}");
            assert_eq!(solid_angle_density(&sampler, direction), density, "{label}");
            assert!((density as f64 * total - 1.0).abs() < 4e-6, "{label}");
            if tiny {
                continue;
            }
            // u[0]: the fan swept from the first edge to the great circle through apex and d
            let mut plane = apex.cross(d);
            if plane.dot(second) < 0.0 {
                plane = -plane;
            }
            let part = dedupe(&clip_reference(&polygon, plane));
            let swept = if part.is_empty() { 0.0 } else { solid_angle_reference(&part) };
            assert!((swept / total - u[0] as f64).abs() < 1e-4, "{label}: swept {}", swept / total);
            // u[1]: 1 − apex·d is uniform between 0 and 1 − apex·e, e the exit point of the arc
            let side = d - apex * apex.dot(d);
            let count_vertices = polygon.len();
            let exit = (1..count_vertices - 1)
                .filter_map(|j| {
                    let (a, b) = (polygon[j], polygon[j + 1]);
                    let normal = apex.cross(d);
                    let (da, db) = (normal.dot(a), normal.dot(b));
                    ((da <= 0.0) != (db <= 0.0)).then(|| (a + (da / (da - db)) * (b - a)).normalize())
                })
                .find(|e| e.dot(side) > 0.0)
                .expect("exit point");
            let fraction = (1.0 - apex.dot(d)) / (1.0 - apex.dot(exit));
            assert!((fraction - u[1] as f64).abs() < 1e-4, "{label}: radial {fraction}");
        }
    }
}

#[test]
fn solid_angle_density_integrates_to_one() {
    // Uniform directions in a cap around the polygon (pdf 1/Ω_cap): Ω_cap p_ω(ω) has mean 1 and
    // variance Ω_cap/Ω − 1.
    let mut rng = Rng::new(13);
    let trials = 20000;
    for case in solid_angle_cases().iter().filter(|case| !case.name.starts_with("tiny")) {
        let polygon = to_f64(case.polygon.as_slice());
        let axis = polygon.iter().map(|p| p.normalize()).sum::<DVec3>().normalize();
        let cos_radius = polygon.iter().map(|p| p.normalize().dot(axis)).fold(1.0, f64::min) - 0.05;
        if cos_radius <= 0.0 {
            continue;
        }
        let cap = 2.0 * PI * (1.0 - cos_radius);
        let total = solid_angle_reference(&polygon);
        let (t1, t2) = frame(axis);
        let sampler = prepare_solid_angle(&case.polygon);
        let (mut sum, mut hits) = (0.0, 0usize);
        for _ in 0..trials {
            let z = 1.0 - rng.uniform() * (1.0 - cos_radius);
            let (r, phi) = ((1.0 - z * z).max(0.0).sqrt(), 2.0 * PI * rng.uniform());
            let direction = axis * z + t1 * (r * phi.cos()) + t2 * (r * phi.sin());
            let density = solid_angle_density(&sampler, direction.as_vec3()) as f64;
            sum += cap * density;
            hits += (density > 0.0) as usize;
            // The density is positive exactly inside the polygon (away from its edges)
            let inside = spherical_inside(&polygon, direction, -1e-5);
            let outside = !spherical_inside(&polygon, direction, 1e-5);
            assert!(!(inside && density == 0.0 || outside && density > 0.0), "{}", case.name);
        }
        let mean = sum / trials as f64;
        let expected_error = ((cap / total - 1.0) / trials as f64).sqrt();
        assert!((mean - 1.0).abs() <= 4.5 * expected_error, "{}: {mean}, {hits} hits", case.name);
    }
}
