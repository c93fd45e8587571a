//! The range class (`range.rs`) against the sampled shading: its bound holds the shading's
//! whole range over the triangle, and it settles nothing it cannot bound.

use super::super::range::{range_class, range_proves};
use super::*;
use crate::shading::shade_point;

/// The shading's range per channel over a barycentric grid of `steps` per edge.
fn sampled_range(tri: &TriangleInput, material: &MaterialKind, lights: &[Light], steps: usize) -> Vec3 {
    let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for i in 0..=steps {
        for j in 0..=steps - i {
            let (a, b) = (i as f32 / steps as f32, j as f32 / steps as f32);
            let w = [1.0 - a - b, a, b];
            let at = |v: [Vec3; 3]| v[0] * w[0] + v[1] * w[1] + v[2] * w[2];
            let value = shade_point(at(tri.positions), at(tri.normals), tri.eye, material, lights);
            lo = lo.min(value);
            hi = hi.max(value);
        }
    }
    hi - lo
}

/// Asserts that no channel of `sampled` exceeds `bound` (by more than 1 ‰ and 10⁻⁶, the sampling's
/// own rounding); `context` names the case.
fn assert_within(sampled: Vec3, bound: Vec3, context: &dyn Fn() -> String) {
    for c in 0..3 {
        assert!(
            sampled[c] <= bound[c] * 1.001 + 1.0e-6,
            "{}: channel {c} varies by {} over the bound {}",
            context(),
            sampled[c],
            bound[c]
        );
    }
}

/// The range class's whole bound (no early stop) of `tri` under `lights`, the material's own
/// parameter.
fn whole_bound(tri: &TriangleInput, material: &MaterialKind, lights: &[Light]) -> Option<Vec3> {
    let parameter = ParameterRange::of(material);
    range_class(tri.positions, tri.normals, (tri.eye, 0.0), material, parameter, lights, f32::INFINITY).bound
}

/// A random patch of size 10⁻³ to 0.3 with normals spread by up to 0.3 rad, seen from `eye`, and
/// one to three point or directional lights around its normal.
fn random_lit_patch(rng: &mut crate::test_rng::Rng) -> (TriangleInput, Vec<Light>) {
    let size = 1.0e-3 * (rng.range(0.0, 5.7)).exp();
    let (centre, positions, eye_dir, eye) = random_patch(rng, size);
    let base = tilt(rng, eye_dir, 0.0, 1.2);
    let spread = rng.range(0.0, 0.3);
    let normals = [0; 3].map(|_| tilt(rng, base, 0.0, spread) * rng.range(0.5, 2.0));
    let lights: Vec<Light> = (0..1 + rng.below(3))
        .map(|_| {
            let towards = tilt(rng, base, 0.0, 1.6);
            if rng.below(2) == 0 {
                let position = centre + towards * rng.range(2.0 * size, 10.0);
                Light::Point { position, color: Vec3::new(1.0, 0.8, 0.6), intensity: rng.range(0.1, 8.0) }
            } else {
                Light::Directional { direction: -towards, color: Vec3::ONE, intensity: rng.range(0.1, 3.0) }
            }
        })
        .collect();
    (TriangleInput { positions, normals, eye }, lights)
}

/// Random patches ([`random_lit_patch`]), each BRDF: wherever the class gives a bound, the sampled shading
/// varies by no more (1 ‰ and 10⁻⁶ for the sampling's own rounding), and it gives one on most
/// patches. Stopped early for an ε (`limit`), the bound decides `range_proves` for that ε as the
/// whole bound does, for ε just above the bound, below it and far below it.
#[test]
fn the_range_bound_holds_the_sampled_shading() {
    let mut rng = crate::test_rng::Rng(0x7a46_e0c1_a55e_0001);
    let (mut bounded, mut cases, mut tightest) = (0, 0, 0.0f32);
    for case in 0..1_500 {
        let (tri, lights) = random_lit_patch(&mut rng);
        let TriangleInput { positions, normals, eye } = tri;
        let material = &materials()[case % materials().len()];
        cases += 1;
        let Some(bound) = whole_bound(&tri, material, &lights) else {
            continue;
        };
        bounded += 1;
        let largest = bound.max_element();
        for eps in [largest * 1.001 + 2.0e-6, 0.5 * largest, 1.0e-3 * largest] {
            let parameter = ParameterRange::of(material);
            let stopped =
                range_class(positions, normals, (eye, 0.0), material, parameter, &lights, eps).bound;
            assert_eq!(
                range_proves(stopped, eps),
                range_proves(Some(bound), eps),
                "case {case}, ε {eps}: stopped at {stopped:?}, whole {bound}"
            );
        }
        let sampled = sampled_range(&tri, material, &lights, 12);
        assert_within(sampled, bound, &|| format!("case {case}, {tri:?} {material:?} {lights:?}"));
        for c in 0..3 {
            if bound[c] > 1.0e-3 {
                tightest = tightest.max(sampled[c] / bound[c]);
            }
        }
    }
    eprintln!(
        "range class: bounds on {bounded} of {cases} patches, largest sampled range / bound {tightest:.3}"
    );
    assert!(bounded * 2 > cases, "a bound on only {bounded} of {cases} patches");
    assert!(tightest > 0.5, "the bound is never approached: {tightest}");
}

/// Every fixture triangle, light set and material: no bound where the shading is singular or
/// a polygonal light shines (those are estimated), and every bound given is finite and not
/// negative, so that nothing NaN or infinite settles a triangle.
#[test]
fn the_range_class_settles_nothing_it_cannot_bound() {
    let polygon = crate::scene::PolygonLight::new(
        &[Vec3::new(-1.0, -1.0, 3.0), Vec3::new(1.0, -1.0, 3.0), Vec3::new(0.0, 1.0, 3.0)],
        Vec3::ONE,
        1.0,
    )
    .expect("a valid polygon");
    assert!(!range_proves(Some(Vec3::new(0.0, f32::NAN, 0.0)), 1.0), "NaN settles");
    assert!(!range_proves(Some(Vec3::splat(f32::INFINITY)), 1.0), "infinity settles");
    for (name, tri) in triangles() {
        for (set, mut lights) in light_sets(&tri) {
            for material in materials() {
                let bound = whole_bound(&tri, &material, &lights);
                if let Some(range) = bound {
                    assert!(range.is_finite() && range.min_element() >= 0.0, "{name}, {set}: {range}");
                }
                let singular = ["light at a vertex", "light on the surface"].contains(&set)
                    || ["opposite normals", "120 degrees in a plane", "a zero normal"].contains(&name);
                if singular {
                    assert!(bound.is_none(), "{name}, {set}, {material:?}: a bound {bound:?}");
                }
                lights.push(Light::Polygon(polygon));
                assert!(
                    whole_bound(&tri, &material, &lights).is_none(),
                    "{name}, {set}: a bound with a polygonal light"
                );
                lights.pop();
            }
        }
    }
}

/// Random patches ([`random_lit_patch`]) with a specular material, at an ε the caps fit and at 0.075: where
/// the range class caps every light's specular part, each light's cap holds its sampled
/// specular part (the material without its diffuse part, that light alone), and the level the
/// estimate then chooses keeps the sampled interpolation error of the whole shading under ε
/// (a sampled error is at most the true one). Some patches at each ε are capped.
#[test]
fn specular_caps_bound_the_specular_parts() {
    use super::super::frame::Frame;
    use super::super::range::{range_class, SpecularCaps};
    use crate::analysis::oracle::{true_error_sampled, SAMPLES_PER_EDGE};
    use crate::analysis::tessellator::triangle_pattern;
    let mut rng = crate::test_rng::Rng(0x5bec_ca95_0000_0001);
    let specular: Vec<MaterialKind> = materials().into_iter().filter(MaterialKind::is_specular).collect();
    let (mut capped, mut measured) = ([0usize; 2], 0);
    for case in 0..1_200 {
        let (tri, lights) = random_lit_patch(&mut rng);
        let TriangleInput { positions, normals, eye } = tri;
        let material = specular[case % specular.len()];
        let parameter = ParameterRange::of(&material);
        for (k, eps) in [0.075f32, 2.0].into_iter().enumerate() {
            let class = range_class(positions, normals, (eye, 0.0), &material, parameter, &lights, eps);
            if !class.every_specular_capped {
                continue;
            }
            capped[k] += 1;
            let frame = Frame::new(&tri, 0.0, true);
            let caps = SpecularCaps::new(&frame, &material).expect("the class's spreads");
            let lobe_only = match material {
                MaterialKind::BlinnPhong { ks, shininess, .. } => {
                    MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks, shininess }
                }
                MaterialKind::Ggx { f0, roughness, .. } => {
                    MaterialKind::Ggx { albedo: Vec3::ZERO, f0, roughness }
                }
                MaterialKind::Lambert { .. } => unreachable!("a specular material"),
            };
            for light in &lights {
                let cap = caps.cap(&material, parameter, light, positions).expect("a bound");
                let share = eps * SPECULAR_CAP_SHARE / lights.len() as f32;
                assert!(
                    cap.max_element() <= share * 1.000_001,
                    "case {case}, ε {eps}: cap {cap} over {share}"
                );
                let sampled = sampled_range(&tri, &lobe_only, std::slice::from_ref(light), 12);
                assert_within(sampled, cap, &|| format!("case {case}, ε {eps}, the lobe of {light:?}"));
            }
            let settings = EstimatorSettings { epsilon: eps, ..EstimatorSettings::default() };
            let estimate = estimate(&tri, &material, &lights, &settings);
            if estimate.fallback || estimate.level <= 1.0 {
                continue;
            }
            measured += 1;
            let n = estimate.n as f32;
            let error = true_error_sampled(
                &tri,
                &material,
                &lights,
                &triangle_pattern(n, [n; 3]),
                SAMPLES_PER_EDGE,
                f64::INFINITY,
            );
            assert!(
                error.iter().all(|&e| e <= f64::from(eps)),
                "case {case}, ε {eps}: level {} errs by {error:?}",
                estimate.n
            );
        }
    }
    eprintln!(
        "specular caps: every light capped on {} patches at ε 0.075, {} at ε 2; {measured} levels above 1 measured",
        capped[0], capped[1]
    );
    assert!(capped.iter().all(|&k| k >= 20), "too few capped patches to test: {capped:?}");
    assert!(measured >= 20, "too few levels above 1 to measure: {measured}");
}
