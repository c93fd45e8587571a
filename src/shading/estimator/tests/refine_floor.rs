//! The refining floor (`light_floor`, `refining_futile`): where it says that refining cannot keep
//! a triangle from falling back, the estimate refined over the children does fall back, on
//! random patches and on the textured scene it was made for.

use super::super::add_light::corner_values;
use super::super::decide::decide;
use super::super::range::{range_class, range_proves};
use super::*;
use crate::scene::Scene;

/// Checks one triangle: where the floor calls refining futile, the refined estimate falls back
/// (and so does the first, which the floor bounds too). Returns whether it called it futile.
fn futile_and_falls_back(
    tri: &TriangleInput,
    material: &MaterialKind,
    parameter: ParameterRange,
    lights: &[Light],
    context: &dyn Fn() -> String,
) -> bool {
    let settings = EstimatorSettings::default();
    let (eps, n_max) = (settings.epsilon, settings.n_max);
    let class = range_class(tri.positions, tri.normals, (tri.eye, 0.0), material, parameter, lights, eps);
    if range_proves(class.bound, eps) {
        return false;
    }
    let capped = class.every_specular_capped;
    let sums = |refine| light_sums(tri, material, parameter, lights, &settings, n_max, eps, capped, refine);
    let (first_sum, first_reason) = sums(false);
    if !refining_futile(&first_sum, eps, settings.split) {
        return false;
    }
    let floor = first_sum.floor;
    for (refined, (sum, reason)) in [(false, (first_sum, first_reason)), (true, sums(true))] {
        let estimate = decide(&sum, eps, n_max, settings.split, reason);
        assert!(
            estimate.fallback,
            "{}: the floor {floor} exceeds ε {eps}, yet the estimate (refined: {refined}) gives level {}",
            context(),
            estimate.level
        );
    }
    true
}

#[test]
fn refining_falls_back_wherever_the_floor_says_it_must() {
    let mut rng = crate::test_rng::Rng(0x5eed_f100_0000_0001);
    let mut futile = 0;
    for case in 0..20000 {
        let size = 1.0e-2 * (rng.range(0.0, 4.5)).exp();
        let (centre, positions, eye_dir, eye) = random_patch(&mut rng, size);
        let base = tilt(&mut rng, eye_dir, 0.0, 1.2);
        let spread = rng.range(0.0, 0.6);
        let normals = [0; 3].map(|_| tilt(&mut rng, base, 0.0, spread) * rng.range(0.5, 2.0));
        let tangent = base.any_orthonormal_vector();
        let lights: Vec<Light> =
            (0..1 + rng.below(3)).map(|_| random_light(&mut rng, centre, base, tangent, size)).collect();
        let brdf = 1 + rng.below(2) as usize;
        let material = random_material(&mut rng, brdf);
        // Half the cases with a textured parameter: a range from the material's own value up.
        let own = ParameterRange::of(&material);
        let parameter = if rng.below(2) == 0 {
            own
        } else {
            ParameterRange { lo: own.lo, hi: own.hi * rng.range(1.0, 20.0) }
        };
        let tri = TriangleInput { positions, normals, eye };
        let context = || format!("case {case}: {material:?}, {parameter:?}, {lights:?}, {tri:?}");
        futile += usize::from(futile_and_falls_back(&tri, &material, parameter, &lights, &context));
    }
    eprintln!("random patches: the floor calls refining futile on {futile} of 20000");
    assert!(futile > 2000, "only {futile} random cases called futile: the test no longer reaches the floor");
}

#[test]
fn on_the_spotted_bunny_refining_falls_back_wherever_the_floor_says_it_must() {
    let scene =
        Scene::load(std::path::Path::new("scenes/bunny_spots.toml")).expect("the shipped scene loads");
    let mut futile = 0;
    for mesh in &scene.meshes {
        let material = &scene.materials[mesh.material];
        let map = material.maps.parameter.as_ref().expect("the spotted bunny has a shininess map");
        for (t, corners) in mesh.indices.chunks_exact(3).enumerate() {
            let tri = TriangleInput::of(mesh, corners, scene.camera.eye);
            let parameter = map.range_over([0, 1, 2].map(|k| mesh.uvs[corners[k] as usize]));
            let context = || format!("triangle {t}");
            futile +=
                usize::from(futile_and_falls_back(&tri, &material.kind, parameter, &scene.lights, &context));
        }
    }
    // Most of its triangles that fall back do so whatever their children (docs/estimator.md section 3, "Where refining cannot help").
    eprintln!("bunny_spots: the floor calls refining futile on {futile} triangles");
    assert!(futile > 500, "only {futile} triangles called futile");
}

#[test]
fn corner_values_are_the_shading_at_the_corners() {
    let material = MaterialKind::BlinnPhong { kd: Vec3::ONE, ks: Vec3::ONE, shininess: 12.0 };
    let tri = TriangleInput {
        positions: [Vec3::ZERO, Vec3::X, Vec3::Y],
        normals: [Vec3::Z, Vec3::new(0.3, 0.0, 1.0), Vec3::new(0.0, -0.4, 1.0)],
        eye: Vec3::new(0.2, 0.3, 4.0),
    };
    let light = Light::Point { position: Vec3::new(1.0, 1.0, 2.0), color: Vec3::ONE, intensity: 1.0 };
    let frame = super::super::frame::Frame::new(&tri, 0.0, true);
    let values = corner_values(&frame, &material, ParameterRange::of(&material), &light, true);
    // Per corner: (diffuse, specular, n̂·ĥ) of the first channel.
    let shaded = [0, 1, 2].map(|i| {
        let (l, irradiance) = crate::shading::light_at(&light, tri.positions[i]).expect("a point light");
        let n = tri.normals[i].normalize();
        let v = (tri.eye - tri.positions[i]).normalize();
        let (diffuse, specular) = crate::shading::reflect_split(n, l, v, &material);
        (diffuse.x * irradiance.x, specular.x * irradiance.x, n.dot((l + v).normalize()))
    });
    let close = |a: f32, b: f32| (a - b).abs() <= 1.0e-5 * b.abs().max(1.0e-3);
    let diffuse_max = shaded.iter().map(|s| s.0).fold(f32::MIN, f32::max);
    let diffuse_min = shaded.iter().map(|s| s.0).fold(f32::MAX, f32::min);
    let peak = shaded.iter().fold(shaded[0], |a, &b| if b.2 > a.2 { b } else { a });
    assert!(close(values.diffuse_max, diffuse_max), "{} against {diffuse_max}", values.diffuse_max);
    assert!(close(values.diffuse_min, diffuse_min), "{} against {diffuse_min}", values.diffuse_min);
    assert!(close(values.specular, peak.1), "{} against {}", values.specular, peak.1);
    // The peak corner's part is at most the largest.
    let specular_max = shaded.iter().map(|s| s.1).fold(f32::MIN, f32::max);
    assert!(values.specular <= specular_max);
}
