//! One light's bounds: the parts bounded apart at grid levels, the refined values over the
//! children, the level-1 jets scaled from the later ones, and the light jets against the
//! exact derivatives of the shading.

use super::*;

/// A glazed teapot triangle next to the lid's rim: its normals turn by 45°, so the curved
/// diffuse part and a GGX lobe whose bound is loose both ask for a high level when bounded
/// together. Bounding each part by the better of its interpolation bound and its range *at
/// each grid level* gives a lower level than the solved one, and the true error there
/// stays below ε.
#[test]
fn parts_bounded_apart_at_grid_levels_lower_the_level_and_hold() {
    use crate::analysis::oracle::{true_error_sampled, SAMPLES_PER_EDGE};
    let tri = TriangleInput {
        positions: [
            Vec3::new(-3.917371, 4.494141, 6.684522),
            Vec3::new(-1.070312, 4.494141, 7.246094),
            Vec3::new(-1.070312, 4.617188, 7.015625),
        ],
        normals: [
            Vec3::new(-0.29425466, 0.6970452, 0.65386707),
            Vec3::new(-0.024959099, 0.69927245, 0.71441936),
            Vec3::new(-0.047243647, 0.9988657, 0.005941045),
        ],
        eye: Vec3::new(12.0, 15.0, 30.0),
    };
    let glaze =
        MaterialKind::Ggx { albedo: Vec3::new(0.4, 0.14, 0.06), f0: Vec3::splat(0.06), roughness: 0.3 };
    let lights = [
        Light::Point {
            position: Vec3::new(-8.0, 32.0, 36.0),
            color: Vec3::new(1.0, 0.96, 0.9),
            intensity: 3400.0,
        },
        Light::Point {
            position: Vec3::new(40.0, 10.0, 10.0),
            color: Vec3::new(0.8, 0.9, 1.0),
            intensity: 500.0,
        },
    ];
    let settings = EstimatorSettings::default();
    let est = estimate(&tri, &glaze, &lights, &settings);
    assert!(!est.fallback, "{est:?}");
    // The level the terms alone solve for (Heuristic: n² = Σ nₜ²).
    let solved = est.terms.iter().map(|t| t * t).sum::<f32>().sqrt();
    let on_grid = GRID_LEVELS.iter().any(|&n| est.level == pattern_level(n, n));
    assert!(on_grid && est.level + 1.0 < solved, "level {} (solved {solved})", est.level);
    let pattern = triangle_pattern(est.n as f32, [est.n as f32; 3]);
    let error = true_error_sampled(&tri, &glaze, &lights, &pattern, SAMPLES_PER_EDGE, f64::INFINITY);
    let worst = error.into_iter().fold(0.0, f64::max);
    assert!(worst <= f64::from(settings.epsilon), "true error {worst} at n = {}", est.n);
    assert!(f64::from(est.predicted_error) >= worst, "{est:?}, true {worst}");
}

/// `material` with its shininess or roughness set to `value`.
fn with_value(material: &MaterialKind, value: f32) -> MaterialKind {
    match *material {
        MaterialKind::BlinnPhong { kd, ks, .. } => MaterialKind::BlinnPhong { kd, ks, shininess: value },
        MaterialKind::Ggx { albedo, f0, .. } => MaterialKind::Ggx { albedo, f0, roughness: value },
        lambert => lambert,
    }
}

/// The values over the children (`values_over_children`, what a triangle above
/// `REFINE_ABOVE` takes its ranges from) hold the shaded parts at 200 random points of each
/// of 3 000 random patches (sizes 0.05–1, normals spread up to 0.8 rad, point lights far,
/// closer than the patch's size and grazing, directional lights: [`random_light`]; the
/// three BRDFs, Relaxed): the diffuse part within `[inf, sup]`, the
/// specular part at most its sup, per channel. Prints how much lower than the patch's own
/// the children's sups are, and asserts that they are lower by a tenth on a tenth of the
/// patches (0.81 of the patch's there with 4 children, 0.70 with 16) and that the sampled
/// parts come within 20 % of them somewhere (neither vacuous nor never useful).
#[test]
fn values_over_children_hold_the_sampled_parts() {
    let mut rng = crate::test_rng::Rng(0x0c41_1d5e_7a1b);
    let gd = Guard::default();
    let (mut ratios, mut reached) = (Vec::new(), 0.0f64);
    let mut checked = 0;
    for case in 0..3000 {
        let brdf = case % 3;
        let size = rng.range(0.05, 1.0);
        let (centre, positions, eye_dir, eye) = random_patch(&mut rng, size);
        let base = tilt(&mut rng, eye_dir, 0.0, 1.2);
        let spread = (rng.range(-7.0, -0.2)).exp();
        let normals = [0; 3].map(|_| tilt(&mut rng, base, 0.0, spread) * (0.7 + 0.6 * rng.f()));
        let light = random_light(&mut rng, centre, base, eye_dir.any_orthonormal_vector(), size);
        let material = random_material(&mut rng, brdf);
        let tri = TriangleInput { positions, normals, eye };
        let frame = Frame::new(&tri, 0.0, true);
        let own = ParameterRange::of(&material);
        let Ok(Some((setup, diff_w, spec_w))) =
            plan_light(&frame, &material, own, &light, Discontinuity::Relaxed)
        else {
            continue;
        };
        let Some(children) = values_over_children(&frame, &material, own, &light, Discontinuity::Relaxed)
        else {
            continue;
        };
        checked += 1;
        let jets = light_jets(&frame, &material, own, &setup, frame.sn, 0.0, &gd);
        let (patch_sup, _) = diffuse_values(&setup, &jets.diffuse);
        let patch = diff_w[0] * patch_sup + spec_w[0] * jets.specular[0].m;
        let tight = diff_w[0] * patch_sup.min(children.diffuse_sup)
            + spec_w[0] * jets.specular[0].m.min(children.specular_sup[0]);
        if patch > 0.0 {
            ratios.push(f64::from(tight / patch));
        }
        let specular_only = match material {
            MaterialKind::Lambert { .. } => None,
            MaterialKind::BlinnPhong { ks, shininess, .. } => {
                Some(MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks, shininess })
            }
            MaterialKind::Ggx { f0, roughness, .. } => {
                Some(MaterialKind::Ggx { albedo: Vec3::ZERO, f0, roughness })
            }
        };
        let [p, q, r] = positions.map(|x| x.as_dvec3());
        let [np, nq, nr] = normals.map(|x| x.as_dvec3());
        for _ in 0..200 {
            let (a, b) = (f64::from(rng.f()), f64::from(rng.f()));
            let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
            let x = p + (q - p) * a + (r - p) * b;
            let nrm = np + (nq - np) * a + (nr - np) * b;
            let full = shade_f64(x, nrm, eye.as_dvec3(), &material, &light);
            let spec = specular_only.map_or([0.0; 3], |m| shade_f64(x, nrm, eye.as_dvec3(), &m, &light));
            for c in 0..3 {
                let diffuse = full[c] - spec[c];
                let (sup, inf) = (f64::from(children.diffuse_sup), f64::from(children.diffuse_inf));
                let w = f64::from(diff_w[c]);
                let slack = 1.0e-4 * w * sup + 1.0e-12;
                assert!(
                    diffuse <= w * sup + slack && diffuse >= w * inf - slack,
                    "case {case}: diffuse {diffuse} outside [{}, {}]: {tri:?} {light:?} {material:?}",
                    w * inf,
                    w * sup
                );
                let s_sup = f64::from(spec_w[c] * children.specular_sup[c]);
                assert!(
                    spec[c] <= s_sup * (1.0 + 1.0e-4) + 1.0e-12,
                    "case {case}: specular {} above {s_sup}: {tri:?} {light:?} {material:?}",
                    spec[c]
                );
                let total = w * sup + s_sup;
                if total > 0.0 {
                    reached = reached.max(full[c] / total);
                }
            }
        }
    }
    ratios.sort_by(f64::total_cmp);
    let at = |q: f64| ratios[((ratios.len() - 1) as f64 * q) as usize];
    eprintln!(
        "{checked} patches: the children's sup over the patch's: 10th percentile {:.2}, median {:.2}, 90th {:.2}; sampled parts up to {reached:.2} of the children's sups",
        at(0.1),
        at(0.5),
        at(0.9)
    );
    assert!(checked > 1500, "{checked} patches");
    assert!(at(0.1) < 0.9, "the children seldom tighten the values");
    assert!(reached > 0.8, "the children's values are never approached: {reached}");
}

/// The level-1 jets `add_light` takes from those at levels ≥ 2 (`LightJets::scaled` by
/// `Frame::rho`) are never below the jets computed at the level-1 scale itself: every jet is
/// non-decreasing in each attribute's scale and homogeneous in them. Random triangles
/// (needles and flat ones included), point lights far, close and grazing, directional
/// lights, the three BRDFs with textured ranges; and the scaled jets are not vacuous (within
/// 1.5× of the direct ones at the median).
#[test]
fn level_one_jets_scaled_from_the_later_ones_bound_the_direct_ones() {
    let mut rng = crate::test_rng::Rng(0x5ca1_ed0e_17e7_00b5);
    let mut ratios = Vec::new();
    for case in 0..3000 {
        let size = rng.range(0.01, 1.0);
        let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
        let mut positions = [0; 3].map(|_| centre + rng.point(Vec3::splat(-size), Vec3::splat(size)));
        if case % 7 == 0 {
            positions[2] = positions[0].lerp(positions[1], rng.range(0.0, 1.0)) + Vec3::splat(1e-3 * size);
        }
        let base = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or_zero();
        let spread = if case % 5 == 0 { 0.0 } else { rng.range(-7.0, 0.0).exp() };
        let normals = [0; 3]
            .map(|_| (base + rng.point(Vec3::splat(-spread), Vec3::splat(spread))) * rng.range(0.7, 1.3));
        let eye = centre
            + rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or_zero() * rng.range(0.5, 20.0);
        let light = match rng.below(4) {
            0 => Light::Point {
                position: centre + base * rng.range(2.0, 30.0),
                color: Vec3::ONE,
                intensity: 50.0,
            },
            1 => Light::Point {
                position: centre + base * size * rng.range(0.05, 1.5),
                color: Vec3::ONE,
                intensity: 1.0,
            },
            2 => Light::Point {
                position: centre + (positions[1] - positions[0]) * rng.range(1.0, 4.0),
                color: Vec3::ONE,
                intensity: 5.0,
            },
            _ => Light::Directional {
                direction: -base.lerp(Vec3::X, rng.f()),
                color: Vec3::ONE,
                intensity: 1.0,
            },
        };
        let material = random_material(&mut rng, case % 3);
        let own = ParameterRange::of(&material);
        let parameter = if case % 2 == 0 {
            own
        } else {
            ParameterRange { lo: own.lo * 0.5, hi: (own.hi * 2.0).min(own.hi.max(1.0)) }
        };
        let tri = TriangleInput { positions, normals, eye };
        let frame = Frame::new(&tri, 0.0, true);
        let Ok(Some((setup, _, _))) =
            plan_light(&frame, &material, parameter, &light, Discontinuity::Relaxed)
        else {
            continue;
        };
        // A bound that reaches BIG sets the guard, and the triangle falls back
        // (`Reason::Singular`) whatever its level-1 bound.
        let gd = Guard::default();
        let later = light_jets(&frame, &material, parameter, &setup, frame.sn, 0.0, &gd);
        if gd.bad.get() {
            continue;
        }
        let direct = light_jets(&frame, &material, parameter, &setup, frame.s1, 0.0, &gd);
        let scaled = later.scaled(frame.rho);
        let parts = [(&scaled.diffuse, &direct.diffuse)]
            .into_iter()
            .chain(scaled.specular.iter().zip(&direct.specular));
        for (from, at) in parts {
            let what = format!("case {case}: {material:?} {light:?} {tri:?}: scaled {from:?}, direct {at:?}");
            assert_eq!(from.m.to_bits(), at.m.to_bits(), "{what}");
            let slack = |x: f32| x * 1.0e-5 + 1.0e-30;
            assert!(from.g + slack(from.g) >= at.g, "{what}: first derivative");
            assert!(from.t + slack(from.t) >= at.t, "{what}: second derivative");
            for (hs, hd) in from.h.iter().zip(&at.h) {
                assert!(hs + slack(*hs) >= *hd, "{what}: a term");
            }
            if at.t > 0.0 {
                ratios.push(from.t / at.t);
            }
        }
    }
    ratios.sort_by(f32::total_cmp);
    let median = ratios[ratios.len() / 2];
    eprintln!("scaled / direct level-1 second derivative over {} parts: median {median:.3}", ratios.len());
    assert!(ratios.len() > 1500 && median < 1.5, "{} parts, median {median}", ratios.len());
}

/// The slope of `t = n̂·ĥ` against its bound `|Dt| ≤ sin ψ·(w_n + w_h)` (what the lobes'
/// profile part squares), at the centre of tiny patches as in
/// [`jets_at_a_point_against_the_worst_direction`], over 72 directions: asserts the bound and
/// prints `max_δ (Dt)² / max_δ bound²`, for `t` and for its normal's part `Dn̂·ĥ` alone
/// (`docs/estimator.md` §11).
#[test]
fn lobe_slope_against_the_worst_direction() {
    let mut rng = crate::test_rng::Rng(0x1234_5678_9abc);
    let (mut whole, mut normal_part) = (Vec::new(), Vec::new());
    for _ in 0..2000 {
        let (tri, light, towards) = tiny_patch(&mut rng);
        let material = MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::ONE, shininess: 100.0 };
        let (positions, normals, eye) = (tri.positions, tri.normals, tri.eye);
        let frame = Frame::new(&tri, 0.0, true);
        let own = ParameterRange::of(&material);
        let Ok(Some((setup, _, _))) = plan_light(&frame, &material, own, &light, Discontinuity::Conservative)
        else {
            continue;
        };
        let [p, q, r] = positions.map(|x| x.as_dvec3());
        let [np, nq, nr] = normals.map(|x| x.as_dvec3());
        let gd = Guard::default();
        let nh = (setup.psi_nh.0, setup.psi_nh.1.min(FRAC_PI_2));
        let (mut slope, mut bound, mut slope_n, mut bound_n) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
        for k in 0..72 {
            let turn = f64::from(k) * std::f64::consts::PI / 72.0;
            let (du, dv) = (turn.cos(), turn.sin());
            // t along the step; with `normal_only` the light and view stay at the centre's.
            let t_at = |t: f64, normal_only: bool| {
                let (a, b) = (1.0 / 3.0 + t * du, 1.0 / 3.0 + t * dv);
                let x = p + (q - p) * a + (r - p) * b;
                let n = (np + (nq - np) * a + (nr - np) * b).normalize();
                let seen_from = if normal_only { (p + q + r) / 3.0 } else { x };
                let l = match light {
                    Light::Point { position, .. } => (position.as_dvec3() - seen_from).normalize(),
                    _ => towards.as_dvec3().normalize(),
                };
                let v = (eye.as_dvec3() - seen_from).normalize();
                n.dot((l + v).normalize())
            };
            let h = 1.0e-2;
            let dt = (t_at(h, false) - t_at(-h, false)) / (2.0 * h);
            let dn = (t_at(h, true) - t_at(-h, true)) / (2.0 * h);
            let scale = scale_along(&tri, du, dv);
            // The estimator's own bounds: the cosine jet's slope, and its normal's part alone.
            let (n, l) = normal_and_light_fields(&frame, &setup, scale, &gd);
            let (_, h) = view_and_half_fields(&frame, &setup, &l, scale, &gd);
            let still = Field { w: 0.0, ..h };
            let b = f64::from(cosine(&n, &h, nh, &gd).g);
            assert!(dt.abs() <= b * 1.001, "{light:?}, {tri:?}, direction {k}: |Dt| {} > {b}", dt.abs());
            slope = slope.max(dt * dt);
            bound = bound.max(b * b);
            slope_n = slope_n.max(dn * dn);
            bound_n = bound_n.max(f64::from(cosine(&n, &still, nh, &gd).g).powi(2));
        }
        whole.push(slope / bound);
        normal_part.push(slope_n / bound_n);
    }
    for (name, v) in [("(Dt)²", &mut whole), ("(Dn̂·ĥ)²", &mut normal_part)] {
        let text = percentiles(v);
        let n = v.len();
        assert!(n > 1000 && v[n - 1] > 0.9, "{name}: {n} patches, largest {}", v[n - 1]);
        eprintln!("{name} / its bound², worst direction of each of {n} patches: {text}");
    }
}

/// A patch of size 10⁻³ with unit normals spread by 5·10⁻⁵–10⁻³ rad, and one light in the
/// direction `towards` (returned) within 1.4 rad of them: a point light 0.003–10 away (a
/// third of the cases) or a directional one.
fn tiny_patch(rng: &mut crate::test_rng::Rng) -> (TriangleInput, Light, Vec3) {
    let (centre, positions, eye_dir, eye) = random_patch(rng, 1.0e-3);
    let base = tilt(rng, eye_dir, 0.0, 1.2);
    let spread = 1.0e-3 * (rng.range(-3.0, 0.0)).exp();
    let normals = [0; 3].map(|_| tilt(rng, base, 0.0, spread));
    let towards = tilt(rng, base, 0.0, 1.4);
    let light = if rng.below(3) == 0 {
        Light::Point { position: centre + towards * rng.range(0.003, 10.0), color: Vec3::ONE, intensity: 1.0 }
    } else {
        Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 }
    };
    (TriangleInput { positions, normals, eye }, light, towards)
}

/// How close the jets come, at a point, to the second derivative in its worst direction:
/// tiny patches (size 10⁻³, normal spreads 5·10⁻⁵–10⁻³ rad, point lights from 3 sizes
/// away and directional lights, the three BRDFs, and the lobes alone), 72 directions at
/// the centre. Asserts the bound in every direction (1 % for the differences' truncation)
/// and prints `max_δ|D²f[δ,δ]| / max_δ bound(δ)` (`docs/estimator.md` §11: the lobes'
/// jets are loose at a point, not only over a patch).
#[test]
fn jets_at_a_point_against_the_worst_direction() {
    let mut rng = crate::test_rng::Rng(0x005e_ed0f_7a11);
    let gd = Guard::default();
    let mut ratios: [Vec<f64>; 5] = Default::default();
    for case in 0..3000 {
        let brdf = case % 3;
        let (tri, light, _) = tiny_patch(&mut rng);
        let (positions, normals, eye) = (tri.positions, tri.normals, tri.eye);
        let full = random_material(&mut rng, brdf);
        let lobe = match full {
            MaterialKind::BlinnPhong { ks, shininess, .. } => {
                Some(MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks, shininess })
            }
            MaterialKind::Ggx { f0, roughness, .. } => {
                Some(MaterialKind::Ggx { albedo: Vec3::ZERO, f0, roughness })
            }
            MaterialKind::Lambert { .. } => None,
        };
        let frame = Frame::new(&tri, 0.0, true);
        for (material, slot) in [(Some(full), brdf), (lobe, brdf + 2)] {
            let Some(material) = material else { continue };
            let own = ParameterRange::of(&material);
            let Ok(Some((setup, diff_w, spec_w))) =
                plan_light(&frame, &material, own, &light, Discontinuity::Conservative)
            else {
                continue;
            };
            let [p, q, r] = positions.map(|x| x.as_dvec3());
            let [np, nq, nr] = normals.map(|x| x.as_dvec3());
            let (mut worst_second, mut worst_bound) = (0.0f64, 0.0f64);
            for k in 0..72 {
                let turn = f64::from(k) * std::f64::consts::PI / 72.0;
                let (du, dv) = (turn.cos(), turn.sin());
                let at = |t: f64| {
                    let (a, b) = (1.0 / 3.0 + t * du, 1.0 / 3.0 + t * dv);
                    let x = p + (q - p) * a + (r - p) * b;
                    let nrm = np + (nq - np) * a + (nr - np) * b;
                    shade_f64(x, nrm, eye.as_dvec3(), &material, &light)[0]
                };
                let scale = scale_along(&tri, du, dv);
                let jets = light_jets(&frame, &material, own, &setup, scale, 0.0, &gd);
                let bound = f64::from(diff_w[0] * jets.diffuse.t + spec_w[0] * jets.specular[0].t);
                let h = 2.0e-2;
                let second = ((at(h) - 2.0 * at(0.0) + at(-h)) / (h * h)).abs();
                assert!(
                    second <= bound * 1.01 + 1.0e-9 * at(0.0).abs() / (h * h) + 1.0e-30,
                    "case {case}: {material:?}, {light:?}, {tri:?}, direction {k}: {second} > {bound}"
                );
                worst_second = worst_second.max(second);
                worst_bound = worst_bound.max(bound);
            }
            if worst_bound > 1.0e-30 {
                ratios[slot].push(worst_second / worst_bound);
            }
        }
    }
    let names = ["Lambert", "Blinn-Phong", "GGX", "Blinn-Phong lobe alone", "GGX lobe alone"];
    for (name, v) in names.iter().zip(ratios.iter_mut()) {
        let text = percentiles(v);
        let n = v.len();
        assert!(n > 500, "{name}: {n} cases");
        eprintln!("{name}: {n} patches, max over directions of |f''| / of the bound: {text}");
        assert!(v[n - 1] > 0.5, "{name}: the bound is never approached");
    }
}

/// The f32 shading near a sharp GGX highlight interpolates like the exact function: its
/// interpolation error at levels 8, 16 and 32 falls as `1/n²` with the f64 shading's. With
/// `1 − (n·h)²` formed as `(n·h)²(α² − 1) + 1` it cancelled to about `α²` in f32, and the
/// peak `1/(πα²)` made the rounding an error floor of about 4.5·10⁻³ here, above the
/// estimator's bound at `n = 14` (`brdf::ggx_d_sin2`; a case of the property test's).
#[test]
fn ggx_shading_has_no_rounding_floor_near_the_highlight() {
    let tri = TriangleInput {
        positions: [
            Vec3::new(7.4046254, -6.955778, -8.476829),
            Vec3::new(7.478987, -6.9212723, -8.439407),
            Vec3::new(7.4802165, -6.900775, -8.455878),
        ],
        normals: [
            Vec3::new(-0.5664613, 0.5346247, 0.6271348),
            Vec3::new(-0.5668246, 0.54001987, 0.6221643),
            Vec3::new(-0.56884605, 0.5319315, 0.62726635),
        ],
        eye: Vec3::ZERO,
    };
    let material = MaterialKind::Ggx {
        albedo: Vec3::new(0.3454659, 0.119069576, 0.78844523),
        f0: Vec3::new(0.73252666, 0.60075366, 0.53019875),
        roughness: 0.24354774,
    };
    let light = Light::Point {
        position: Vec3::new(-0.40450287, 1.3913608, 0.71938324),
        color: Vec3::new(0.2702486, 0.22998543, 0.6092827),
        intensity: 496.99304,
    };
    let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
    let [np, nq, nr] = tri.normals.map(|x| x.as_dvec3());
    let exact = |b: [f64; 3]| {
        let x = p * b[0] + q * b[1] + r * b[2];
        shade_f64(x, np * b[0] + nq * b[1] + nr * b[2], DVec3::ZERO, &material, &light)
    };
    let k = 12;
    for n in [8u32, 16, 32] {
        let pattern = triangle_pattern(n as f32, [n as f32; 3]);
        let shaded = crate::analysis::oracle::true_error_sampled(
            &tri,
            &material,
            std::slice::from_ref(&light),
            &pattern,
            k,
            f64::INFINITY,
        );
        let mut worst = [0.0f64; 3];
        for t in &pattern.triangles {
            let corners = t.map(|i| pattern.vertices[i as usize]);
            let values = corners.map(exact);
            for i in 0..=k {
                for j in 0..=(k - i) {
                    let mu = [i, j, k - i - j].map(|m| f64::from(m) / f64::from(k));
                    let b: [f64; 3] = std::array::from_fn(|c| (0..3).map(|v| mu[v] * corners[v][c]).sum());
                    let f = exact(b);
                    for c in 0..3 {
                        let linear: f64 = (0..3).map(|v| mu[v] * values[v][c]).sum();
                        worst[c] = worst[c].max((f[c] - linear).abs());
                    }
                }
            }
        }
        let text = |e: [f64; 3]| e.map(|x| format!("{x:.2e}")).join(", ");
        eprintln!("n = {n}: f32 shading {}, exact {}", text(shaded), text(worst));
        for c in 0..3 {
            assert!(
                shaded[c] <= 1.25 * worst[c] + 1.0e-5,
                "n = {n}, channel {c}: f32 {} against exact {}",
                shaded[c],
                worst[c]
            );
        }
    }
}

/// Every factor's jet, composed into a light's diffuse and specular jets, against the exact
/// derivatives of that light's shading (f64 central differences along random domain steps
/// `δ`, the jets evaluated at the step's scale `(|Xδ|, |Nδ|)`): value, first and second
/// derivative bounds hold at every sampled point of random triangles, with lights far,
/// closer than the triangle's size and grazing, directional lights, Blinn-Phong
/// shininess up to 10⁴, GGX roughness down to 0, and textured parameter ranges (the jets
/// over a range, the shading at one value of it). Conservative handling, so that the
/// clamps (`n·l`, `n·h` below shininess 2, `n·v`) are inactive wherever the jets apply.
#[test]
fn light_jets_bound_the_exact_derivatives() {
    let mut rng = crate::test_rng::Rng(0x1e7_b0d5_2c4f_9a31);
    let mut checked = [0usize; 3];
    let mut tightest = [0.0f64; 3];
    let gd = Guard::default();
    for case in 0..3000 {
        let brdf = case % 3;
        let size = rng.range(0.05, 1.0);
        let (centre, positions, eye_dir, eye) = random_patch(&mut rng, size);
        let tangent = eye_dir.any_orthonormal_vector();
        let base = tilt(&mut rng, eye_dir, 0.0, 1.2);
        let spread = (rng.range(-7.0, -0.2)).exp();
        let normals = [0; 3].map(|_| tilt(&mut rng, base, 0.0, spread) * (0.7 + 0.6 * rng.f()));
        let light = random_light(&mut rng, centre, base, tangent, size);
        let material = random_material(&mut rng, brdf);
        let tri = TriangleInput { positions, normals, eye };
        let frame = Frame::new(&tri, 0.0, true);
        // Half the cases: a textured parameter, whose range the jets bound over; the
        // shading then takes one value of the range.
        let own = ParameterRange::of(&material);
        let (parameter, shaded) = if case % 2 == 0 || brdf == 0 {
            (own, material)
        } else {
            let (lo, hi) = match material {
                MaterialKind::BlinnPhong { .. } => {
                    ((own.lo * rng.range(0.3, 1.0)).max(1.0), own.hi * rng.range(1.0, 3.0))
                }
                _ => (own.lo * rng.range(0.0, 1.0), (own.hi * rng.range(1.0, 3.0)).min(1.0)),
            };
            let value = rng.range(lo, hi);
            (ParameterRange { lo, hi }, with_value(&material, value))
        };
        let Ok(Some((setup, diff_w, spec_w))) =
            plan_light(&frame, &material, parameter, &light, Discontinuity::Conservative)
        else {
            continue;
        };
        let [p, q, r] = positions.map(|x| x.as_dvec3());
        let [np, nq, nr] = normals.map(|x| x.as_dvec3());
        for _ in 0..6 {
            let (u, v) = (f64::from(rng.range(0.01, 0.98)), f64::from(rng.f()));
            let (u, v) = (u, (1.0 - u - 0.01) * v + 0.005);
            let turn = f64::from(rng.range(0.0, std::f32::consts::TAU));
            // A domain step (barycentric, summing to 0) and the point moving along it.
            let (du, dv) = (turn.cos(), turn.sin());
            let at = |t: f64| {
                let (a, b) = (u + t * du, v + t * dv);
                let x = p + (q - p) * a + (r - p) * b;
                let nrm = np + (nq - np) * a + (nr - np) * b;
                shade_f64(x, nrm, eye.as_dvec3(), &shaded, &light)
            };
            let scale = scale_along(&tri, du, dv);
            let jets = light_jets(&frame, &material, parameter, &setup, scale, 0.0, &gd);
            let (diff, spec) = (jets.diffuse, jets.specular);
            let h = 2.0e-5;
            let (f0, fp, fm) = (at(0.0), at(h), at(-h));
            for c in 0..3 {
                let bound = |d: f32, s: f32| f64::from(diff_w[c] * d + spec_w[c] * s);
                let (m, g, t) =
                    (bound(diff.m, spec[c].m), bound(diff.g, spec[c].g), bound(diff.t, spec[c].t));
                let first = (fp[c] - fm[c]) / (2.0 * h);
                let second = (fp[c] - 2.0 * f0[c] + fm[c]) / (h * h);
                // Rounding of the differences: about 10⁻¹⁶·|f|/h per order.
                let slack = 1.0e-15 * f0[c].abs().max(1.0e-30);
                let what = format!(
                    "case {case}: {shaded:?} of {parameter:?}, {light:?}, {tri:?}, point ({u}, {v}), step ({du}, {dv}), channel {c}"
                );
                assert!(f0[c] <= m * 1.0001 + slack, "{what}: value {} > {m}", f0[c]);
                assert!(first.abs() <= g * 1.001 + slack / h, "{what}: first {first} > {g}");
                assert!(second.abs() <= t * 1.001 + 1.0e3 * slack / (h * h), "{what}: second {second} > {t}");
                if t > 0.0 && f0[c] > 0.0 {
                    tightest[brdf] = tightest[brdf].max(second.abs() / t);
                }
            }
            checked[brdf] += 1;
        }
    }
    eprintln!("points checked per BRDF {checked:?}; largest second derivative / bound {tightest:?}");
    for brdf in 0..3 {
        assert!(checked[brdf] > 1_500, "{checked:?}: too few points where the jets apply");
        // Valid and not vacuous: somewhere the bound is within a factor of four.
        assert!(tightest[brdf] > 0.25, "{tightest:?}: the jets are nowhere near the derivatives");
    }
}
