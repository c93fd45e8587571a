//! The closed-form projected solid angle against the f64 references and quadrature.

use super::*;

#[test]
fn unit_difference_and_segment_series_are_accurate() {
    let mut rng = Rng::new(3);
    for trial in 0..3000 {
        let a = DVec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
        let scale = 10f64.powf(rng.range(-6.0, 0.0));
        let mut b = a + scale * DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        match trial % 3 {
            // mostly a difference in length, also far from a
            1 => {
                b = a * rng.range(0.1, 10.0)
                    + scale * DVec3::new(rng.range(-1.0, 1.0), 0.0, rng.range(-1.0, 1.0))
            }
            // large angles, up to nearly antipodal
            2 => b = DVec3::new(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0), rng.range(-2.0, 2.0)),
            _ => {}
        }
        let (a32, b32) = (a.as_vec3(), b.as_vec3());
        let exact = a32.as_dvec3().normalize() - b32.as_dvec3().normalize();
        let mine = unit_difference(a32, b32).as_dvec3();
        assert!((mine - exact).length() <= 6e-7 * exact.length(), "{a32} {b32}: {mine} vs {exact}");
    }
    // γ/sin γ − 1 on both sides of the series threshold
    for k in 1..400 {
        let angle = k as f64 * PI / 400.0;
        let c = DVec3::new(0.3, -0.2, 1.0).normalize() * angle.sin();
        let exact = (angle / angle.sin() - 1.0) * c.z;
        let mine = edge_segment_term(c.as_vec3(), angle.cos() as f32) as f64;
        assert!((mine - exact).abs() <= 4e-6 * exact.abs() + 1e-9, "angle {angle}: {mine} vs {exact}");
    }
}

#[test]
fn psa_matches_f64_reference_for_random_polygons() {
    let mut rng = Rng::new(4);
    for trial in 0..400 {
        let count = 3 + trial % 6;
        let center = DVec3::new(rng.range(-3.0, 3.0), rng.range(-3.0, 3.0), rng.range(-1.0, 3.0));
        let normal = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let radii = (rng.range(0.1, 2.0), rng.range(0.1, 2.0));
        let rotation = rng.range(0.0, 2.0 * PI);
        let vertices = planar_polygon(count, center, normal, radii, rotation, 0.8, &mut rng);
        let reference = clip_horizon_reference(&to_f64(&vertices));
        let expected = psa_reference(&reference).abs();
        let psa = projected_solid_angle(&clip_to_horizon(&Polygon::new(&vertices))) as f64;
        assert!((psa - expected).abs() <= 1e-6 + 1e-5 * expected, "trial {trial}: {psa} vs {expected}");
    }
}

#[test]
fn psa_of_tiny_and_huge_polygons_has_no_cancellation_noise() {
    let mut rng = Rng::new(5);
    for size in [1e-2, 1e-4, 1e-6] {
        for direction in [
            DVec3::new(1e-3, 2e-3, 1.0),
            DVec3::new(0.5, -0.4, 0.75),
            DVec3::new(-0.7, 0.7, 0.1),
            DVec3::new(0.99, 0.1, 0.01),
        ] {
            for count in [3, 4, 8] {
                let center = direction.normalize() * rng.range(0.5, 2.0);
                let vertices = facing_polygon(count, center, size * center.length(), &mut rng);
                // Lambert's sum in f64 loses ε₆₄/size² here; the quadrature has error ~(size/32)²
                let expected = psa_quadrature(&to_f64(&vertices), 32);
                let psa = projected_solid_angle(&clip_to_horizon(&Polygon::new(&vertices))) as f64;
                assert!(expected > 0.0);
                assert!((psa / expected - 1.0).abs() < 4e-6, "size {size}, {direction}: {psa} vs {expected}");
            }
        }
    }
    for half_width in [1e2f32, 1e4] {
        for height in [1.0f32, 0.01] {
            let square = [
                v(-half_width, -half_width, height),
                v(half_width, -half_width, height),
                v(half_width, half_width, height),
                v(-half_width, half_width, height),
            ];
            let expected = psa_reference(&to_f64(&square));
            let psa = projected_solid_angle(&clip_to_horizon(&Polygon::new(&square))) as f64;
            assert!((psa / expected - 1.0).abs() < 2e-6, "{half_width} {height}: {psa} vs {expected}");
            assert!(expected < PI && expected > 0.9 * PI);
        }
    }
}

#[test]
fn psa_matches_area_quadrature() {
    // Independent of Lambert's formula: the area integral of the irradiance kernel.
    let mut rng = Rng::new(6);
    for trial in 0..6 {
        let center = DVec3::new(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5), rng.range(0.8, 2.0));
        let vertices = facing_polygon(3 + trial, center, 0.6, &mut rng);
        let polygon = to_f64(&vertices);
        assert!(polygon.iter().all(|p| p.z > 0.0));
        let integral = psa_quadrature(&polygon, 96);
        let psa = projected_solid_angle(&clip_to_horizon(&Polygon::new(&vertices))) as f64;
        assert!((psa / integral - 1.0).abs() < 2e-4, "trial {trial}: {psa} vs {integral}");
    }
}

#[test]
fn psa_degenerate_configurations_are_zero() {
    let in_plane = [v(1.0, -0.5, 1.0), v(2.0, -0.5, 2.0), v(2.0, 0.5, 2.0), v(1.0, 0.5, 1.0)];
    let vertical_through_zenith = [v(1.0, 0.0, 1.0), v(2.0, 0.0, 1.0), v(2.0, 0.0, 2.0), v(1.0, 0.0, 2.0)];
    let in_horizon = [v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(2.0, 1.0, 0.0)];
    let below = [v(1.0, 0.0, -0.1), v(2.0, 0.0, -0.2), v(2.0, 1.0, -0.1)];
    let vertex_at_shading_point = [v(0.0, 0.0, 0.0), v(1.0, 0.0, 1.0), v(0.0, 1.0, 1.0)];
    for (name, vertices) in [
        ("shading point in the plane", &in_plane[..]),
        ("plane through the zenith", &vertical_through_zenith[..]),
        ("in the horizon", &in_horizon[..]),
        ("below the horizon", &below[..]),
        ("vertex at the shading point", &vertex_at_shading_point[..]),
    ] {
        let clipped = clip_to_horizon(&Polygon::new(vertices));
        assert_eq!(projected_solid_angle(&clipped), 0.0, "{name}");
        let sampler = prepare_projected_solid_angle(&clipped);
        assert!(sampler.is_empty(), "{name}");
        let (direction, density) = sample_projected_solid_angle(&sampler, [0.3, 0.6]);
        assert!(direction.is_finite() && density == 0.0, "{name}");
        assert_eq!(projected_solid_angle_density(&sampler, v(0.5, 0.0, 0.5).normalize()), 0.0, "{name}");
    }
    // The ellipse of an edge through the zenith is degenerate, and every edge of a polygon in a
    // vertical plane through the shading point is.
    assert!(is_degenerate(ellipse_from_edge(v(-1.0, 0.0, 1.0), v(1.0, 0.0, 1.0))));
    assert!(is_degenerate(ellipse_from_edge(v(1.0, 0.0, 0.5), v(1.0, 0.0, 2.0))));
    assert!(!is_degenerate(ellipse_from_edge(v(1.0, 0.0, 0.5), v(1.0, 0.1, 2.0))));
}
