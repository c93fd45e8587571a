use super::*;
use crate::scene::LightSampling;

fn with(light: PolygonLight, sampling: LightSampling) -> PolygonLight {
    PolygonLight { sampling, ..light }
}

fn quad(centre: Vec3, half: f32, intensity: f32) -> PolygonLight {
    // Facing down (-y), a square in the plane y = centre.y.
    let v = [
        centre + Vec3::new(-half, 0.0, -half),
        centre + Vec3::new(half, 0.0, -half),
        centre + Vec3::new(half, 0.0, half),
        centre + Vec3::new(-half, 0.0, half),
    ];
    let light = PolygonLight::new(&v, Vec3::ONE, intensity).unwrap();
    assert!(light.normal.y < -0.99, "{:?}", light.normal);
    light
}

#[test]
fn tangent_frame_is_orthonormal_and_right_handed() {
    for n in [Vec3::Z, -Vec3::Z, Vec3::X, Vec3::new(0.3, -0.5, 0.8).normalize(), Vec3::new(0.0, 1e-8, -1.0)] {
        let (t, b) = tangent_frame(n);
        assert!((t.length() - 1.0).abs() < 1e-6 && (b.length() - 1.0).abs() < 1e-6);
        assert!(t.dot(b).abs() < 1e-6 && t.dot(n).abs() < 1e-6 && b.dot(n).abs() < 1e-6);
        assert!((t.cross(b) - n).length() < 1e-5, "{n:?}");
    }
}

#[test]
fn diffuse_is_kd_radiance_projected_solid_angle_and_one_sided() {
    let light = quad(Vec3::new(0.0, 1.0, 0.0), 0.05, 3.0);
    let material = MaterialKind::Lambert { kd: Vec3::splat(0.5) };
    let (d, s) = shade_polygon(Vec3::ZERO, Vec3::Y, Vec3::Y, &material, &light);
    // Small, straight above: Ω⊥ ≈ area / distance².
    let expected = 0.5 * 3.0 * light.area;
    assert!((d.x - expected).abs() < 0.01 * expected, "{d} vs {expected}");
    assert_eq!(s, Vec3::ZERO);
    // Behind the emitter: nothing.
    let (d, _) = shade_polygon(Vec3::new(0.0, 2.0, 0.0), Vec3::Y, Vec3::Y, &material, &light);
    assert_eq!(d, Vec3::ZERO);
}

/// The MIS estimate converges to the integral: a brute-force quadrature over the light's
/// area (many samples) agrees with few MIS samples per technique, for both techniques.
#[test]
fn specular_estimate_matches_quadrature() {
    let light = quad(Vec3::new(0.3, 1.0, 0.1), 0.25, 2.0);
    let position = Vec3::ZERO;
    let n = Vec3::new(0.1, 1.0, 0.0).normalize();
    let eye = Vec3::new(-1.0, 1.2, -0.3);
    let v = (eye - position).normalize();
    for material in [
        MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::splat(0.5), shininess: 30.0 },
        MaterialKind::Ggx { albedo: Vec3::ZERO, f0: Vec3::splat(0.04), roughness: 0.4 },
    ] {
        // Quadrature: the integrand in area measure, f(ω) cos_y / d², on a 400² grid.
        let steps = 400;
        let mut reference = Vec3::ZERO;
        let [a, b, _, d] = [light.vertices[0], light.vertices[1], light.vertices[2], light.vertices[3]];
        let (e0, e1) = (b - a, d - a);
        let cell = light.area / (steps * steps) as f32;
        let (t, bt) = tangent_frame(n);
        let local = |w: Vec3| Vec3::new(w.dot(t), w.dot(bt), w.dot(n));
        for i in 0..steps {
            for j in 0..steps {
                let y = a + e0 * ((i as f32 + 0.5) / steps as f32) + e1 * ((j as f32 + 0.5) / steps as f32);
                let to = y - position;
                let d2 = to.length_squared();
                let l = to / d2.sqrt();
                let cos_y = light.normal.dot(-l).max(0.0);
                reference += specular(local(l), local(v), &material) * (cos_y / d2 * cell);
            }
        }
        reference *= light.radiance();
        for sampling in [PolygonSampling::ProjectedSolidAngle, PolygonSampling::SolidAngle] {
            let settings = LightSampling { samples: 4096, technique: sampling, mis_visibility: 0.5 };
            let (_, s) = shade_polygon(position, n, v, &material, &with(light, settings));
            let rel = (s - reference).abs().max_element() / reference.max_element();
            assert!(rel < 0.02, "{material:?} {sampling:?}: {s} vs {reference} ({rel})");
        }
    }
}

#[test]
fn brdf_sampling_density_matches_its_samples() {
    // The density returned with a sample equals brdf_density of that direction, and the
    // density integrates to at most 1 over the sphere (samples below the horizon are lost).
    let v = Vec3::new(0.4, 0.1, 0.9).normalize();
    for material in [
        MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::ONE, shininess: 12.0 },
        MaterialKind::Ggx { albedo: Vec3::ZERO, f0: Vec3::ONE, roughness: 0.5 },
    ] {
        for i in 0..64 {
            let u = sample_point(i, 64);
            let (l, p) = sample_brdf(u, v, &material);
            assert!((l.length() - 1.0).abs() < 1e-4);
            let q = brdf_density(l, v, &material);
            assert!((p - q).abs() <= 1e-4 * p.max(q), "{p} vs {q}");
        }
        // ∫ p dω over a fine grid of the sphere.
        let steps = 600;
        let mut total = 0.0;
        for i in 0..steps {
            let z = -1.0 + 2.0 * (i as f32 + 0.5) / steps as f32;
            for j in 0..steps {
                let phi = 2.0 * PI * (j as f32 + 0.5) / steps as f32;
                let r = (1.0 - z * z).sqrt();
                total += brdf_density(Vec3::new(r * phi.cos(), r * phi.sin(), z), v, &material);
            }
        }
        total *= 4.0 * PI / (steps * steps) as f32;
        assert!(total > 0.9 && total < 1.01, "{material:?}: {total}");
    }
}
