//! Random and nearly degenerate polygons: samples stay inside.

use super::*;

#[test]
fn random_polygons_sample_inside() {
    // Random convex polygons from 10⁻⁴ to 10 wide, anywhere around the shading point (clipped,
    // crossing the horizon, edge-on): the closed forms match f64 within their conditioning, and
    // every sample of both techniques is finite, inside and has a positive density.
    let mut rng = Rng::new(16);
    let polygons = 300;
    for trial in 0..polygons {
        let count = 3 + trial % 6;
        let size = 10f64.powf(rng.range(-4.0, 1.0));
        let center = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-0.3, 1.0));
        let center = center.normalize() * rng.range(0.5, 3.0);
        let normal = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let radii = (size * rng.range(0.3, 1.0), size * rng.range(0.3, 1.0));
        let vertices = planar_polygon(count, center, normal, radii, rng.range(0.0, 7.0), 0.8, &mut rng);
        let label = format!("trial {trial}: {vertices:?}");
        let clipped_reference = clip_horizon_reference(&to_f64(&vertices));
        let clipped = clip_to_horizon(&Polygon::new(&vertices));
        let sampler = prepare_projected_solid_angle(&clipped);
        let psa = if clipped_reference.is_empty() { 0.0 } else { psa_reference(&clipped_reference).abs() };
        // f32 directions carry an error of about ε, which moves the projected solid angle by about
        // ε·Ω (ill-conditioned near the horizon, where it is Ω·z) and areas of slivers (tiny area,
        // large extent) by about ε·extent²
        let directions: Vec<DVec3> = to_f64(&vertices).iter().map(|p| p.normalize()).collect();
        let extent = directions
            .iter()
            .flat_map(|a| directions.iter().map(move |b| (*a - *b).length()))
            .fold(0.0, f64::max);
        let epsilon = f32::EPSILON as f64;
        let clipped_solid_angle =
            if clipped_reference.is_empty() { 0.0 } else { solid_angle_reference(&clipped_reference) };
        let tolerance = 1e-5 * psa + 8.0 * epsilon * (clipped_solid_angle + extent * extent);
        assert!((sampler.projected_solid_angle() as f64 - psa).abs() <= tolerance, "{label}");
        if !sampler.is_empty() {
            for i in 0..32 {
                let u = if i < 16 { sample_point(i, 16) } else { rng.u2() };
                let (direction, density) = sample_projected_solid_angle(&sampler, u);
                let tolerance = 2e-6 + 4.0 * f32::EPSILON as f64 / direction.z as f64;
                assert!(direction.is_finite() && density > 0.0, "{label} {u:?}");
                assert!(
                    ray_hits_polygon(&clipped_reference, direction.as_dvec3(), tolerance),
                    "{label} {u:?}"
                );
            }
        }
        let polygon = to_f64(&vertices);
        let solid_sampler = prepare_solid_angle(&Polygon::new(&vertices));
        let solid_angle = solid_angle_reference(&polygon);
        // Rounding to f32 can make a sliver seen edge-on non-convex as seen from the origin; its
        // fan then has triangles of both orientations, whose areas Algorithm 5 adds (|det|)
        let dets: Vec<f64> = (1..count - 1)
            .map(|j| {
                let (a, b, c) = (directions[0], directions[j], directions[j + 1]);
                a.dot((b - a).cross(c - a))
            })
            .collect();
        let convex = dets.iter().all(|&d| d >= 0.0) || dets.iter().all(|&d| d <= 0.0);
        // and a plane passing close to the shading point (large polygons seen edge-on) makes the
        // solid angle sensitive in proportion to 1/cos of the viewing angle
        let cos_view = newell_normal(&polygon).normalize().dot(directions[0]).abs();
        let tolerance = 1e-5 * solid_angle + 8.0 * epsilon * extent * extent * (1.0 + 1.0 / cos_view);
        let error = (solid_sampler.solid_angle() as f64 - solid_angle).abs();
        assert!(!convex || error <= tolerance, "{label}");
        for i in 0..32 {
            let u = if i < 16 { sample_point(i, 16) } else { rng.u2() };
            let (direction, density) = sample_solid_angle(&solid_sampler, u);
            assert!(direction.is_finite() && density > 0.0, "{label} {u:?}");
            assert!(ray_hits_polygon(&polygon, direction.as_dvec3(), 2e-6), "{label} {u:?}");
        }
    }
}

#[test]
fn psa_samples_next_to_nearly_degenerate_edges_stay_inside() {
    // Edges whose great circle passes within rounding of the zenith (A.2 up to rounding: u large
    // but finite) bound sectors too thin to sample in f32; such sectors get no area. Regression
    // cases from a sweep over 10⁶ random polygons, and a wall whose vertical edges are tilted by
    // 1e-6 radians.
    let mut cases: Vec<Vec<Vec3>> = vec![
        vec![
            v(-1.6188718, 1.2629286, 0.12937988),
            v(-1.6179032, 1.2643913, 0.12944831),
            v(-1.6196359, 1.2635242, 0.12859035),
        ],
        vec![
            v(0.9815383, -1.248498, 1.7982978),
            v(0.9815635, -1.2485181, 1.7983328),
            v(0.9815565, -1.248497, 1.7984123),
            v(0.98147327, -1.2484076, 1.7984283),
            v(0.9814235, -1.2483646, 1.798378),
            v(0.98141545, -1.2483633, 1.7983373),
            v(0.981461, -1.2484212, 1.7982767),
        ],
        vec![
            v(0.6175854, 1.7902154, 0.01642938),
            v(0.6175492, 1.790245, 0.016348274),
            v(0.617577, 1.7902547, 0.016267372),
            v(0.6176296, 1.7902465, 0.016231593),
            v(0.61768395, 1.7902294, 0.016232207),
            v(0.6177418, 1.7901989, 0.01628755),
            v(0.61773425, 1.790177, 0.016394772),
            v(0.617671, 1.7901847, 0.016447011),
        ],
    ];
    let tilt = glam::DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 1e-6);
    let wall = [
        DVec3::new(2.0, -0.5, -0.3),
        DVec3::new(2.0, 0.5, -0.3),
        DVec3::new(2.0, 0.5, 1.0),
        DVec3::new(2.0, -0.5, 1.0),
    ];
    cases.push(wall.iter().map(|p| (tilt * *p).as_vec3()).collect());
    let mut rng = Rng::new(17);
    for vertices in cases {
        let reference = clip_horizon_reference(&to_f64(&vertices));
        let sampler = prepare_projected_solid_angle(&clip_to_horizon(&Polygon::new(&vertices)));
        let psa = psa_reference(&reference).abs();
        assert!((sampler.projected_solid_angle() as f64 / psa - 1.0).abs() < 1e-5, "{vertices:?}");
        let mut points: Vec<[f32; 2]> = (0..256).map(|i| sample_point(i, 256)).collect();
        points.extend((0..2000).map(|_| rng.u2()));
        points.extend([[0.9999827, 0.25480324], [0.0006492138, 0.8283782], [5.7280064e-5, 0.15021533]]);
        for u in points {
            let (direction, density) = sample_projected_solid_angle(&sampler, u);
            let tolerance = 2e-6 + 4.0 * f32::EPSILON as f64 / direction.z as f64;
            assert!(
                density > 0.0 && ray_hits_polygon(&reference, direction.as_dvec3(), tolerance),
                "{vertices:?} {u:?}"
            );
        }
    }
}
