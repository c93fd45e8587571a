//! Robustness: no NaN and no level out of range on degenerate and extreme inputs; the
//! second-order total against its terms.

use super::*;

fn sane(e: &Estimate, n_max: u32, what: &str) {
    assert!(e.n >= 1 && e.n <= n_max, "{what}: n = {}", e.n);
    assert!(
        e.predicted_error.is_finite() && e.predicted_error >= 0.0,
        "{what}: predicted {}",
        e.predicted_error
    );
    assert!(e.terms.iter().all(|t| t.is_finite() && *t >= 0.0), "{what}: terms {:?}", e.terms);
    assert_eq!(e.fallback, e.reason != Reason::None, "{what}");
    if e.fallback {
        assert_eq!(e.n, 1, "{what}");
        assert_eq!(e.level, FALLBACK_LEVEL, "{what}");
    } else {
        // The real level: at least 1, within the uniform level's reach, never NaN.
        assert!(e.level >= 1.0 && e.level <= pattern_level(n_max, n_max), "{what}: level {}", e.level);
        assert_eq!(uniform_level(e.level, n_max), e.n, "{what}");
    }
}

/// The levels are decided on the jets' one-number second-order bound (`Jet::t`), the
/// GPU's single pass; the per-term bounds are its parts. They must agree: never above the
/// parts' sum, and equal to it up to rounding where neither a lobe's joint bound
/// ([`Curvature`]) nor a textured range's larger of several jets applies (Lambert with a
/// constant parameter); a lobe's joint bound is below the sum somewhere.
#[test]
fn second_order_total_is_the_sum_of_its_terms() {
    let mut compared = 0;
    let mut textured = 0;
    let mut joint_below = 0;
    for (tname, t) in triangles() {
        for (lname, lights) in light_sets(&t) {
            for m in materials() {
                let own = ParameterRange::of(&m);
                let wide = ParameterRange { lo: own.lo * 0.5, hi: own.hi * 2.0 };
                for (parameter, exact) in [(own, true), (wide, false)] {
                    for mode in [Discontinuity::Conservative, Discontinuity::Relaxed] {
                        let settings =
                            EstimatorSettings { discontinuity: mode, ..EstimatorSettings::default() };
                        let (sum, reason) =
                            light_sums(&t, &m, parameter, &lights, &settings, 16, 0.075, false, false);
                        if reason != Reason::None {
                            continue;
                        }
                        let parts = sum.hn.iter().fold(Vec3::ZERO, |acc, h| acc + *h);
                        for c in 0..3 {
                            let (total, parts) = (sum.tn[c], parts[c]);
                            let what = format!("{tname} / {lname} / {m:?} / {parameter:?} / {mode:?}");
                            assert!(total <= parts * (1.0 + 1.0e-5), "{what}: {total} > {parts}");
                            if exact && matches!(m, MaterialKind::Lambert { .. }) {
                                assert!(total >= parts * (1.0 - 1.0e-5), "{what}: {total} < {parts}");
                            }
                            joint_below += usize::from(exact && total < parts * 0.99);
                        }
                        compared += 1;
                        textured += usize::from(!exact);
                    }
                }
            }
        }
    }
    assert!(compared > 100 && textured > 50, "{compared} compared, {textured} textured");
    assert!(joint_below > 10, "the lobes' joint bound is never below the sum ({joint_below})");
}

#[test]
fn never_nan_never_out_of_range() {
    let epsilons = [0.0, -1.0, f32::NAN, f32::INFINITY, 1.0e-30, 1.0e-6, 0.075, 1.0, 1.0e6];
    let mut count = 0;
    for (tname, t) in triangles() {
        for (lname, lights) in light_sets(&t) {
            for m in materials() {
                for &eps in &epsilons {
                    for s in all_settings(eps) {
                        let e = estimate(&t, &m, &lights, &s);
                        sane(&e, 16, &format!("{tname} / {lname} / {m:?} / {s:?}"));
                        count += 1;
                    }
                }
            }
        }
    }
    // n_max outside 1..=64 is clamped.
    for n_max in [0, 1, 64, 1000] {
        let s = EstimatorSettings { n_max, ..EstimatorSettings::default() };
        let e = estimate(&base(), &materials()[0], &light_sets(&base())[0].1, &s);
        sane(&e, n_max.clamp(1, 64), "n_max");
    }
    assert!(count > 10_000);
}

#[test]
fn extremes_behave() {
    let lam = materials()[0];
    let b = base();
    let c = (b.positions[0] + b.positions[1] + b.positions[2]) / 3.0;
    // A light behind the surface everywhere adds nothing.
    let e = est(&b, &lam, &[sun(Vec3::new(0.0, 0.2, 1.0))], 1e-9);
    assert!(!e.fallback && e.n == 1 && e.predicted_error == 0.0, "{e:?}");
    // A light touching the triangle, zero or opposite normals: singular.
    for lights in [vec![point(b.positions[1])], vec![point(c)]] {
        assert_eq!(est(&b, &lam, &lights, 0.1).reason, Reason::Singular);
    }
    let tris = triangles();
    for name in ["opposite normals", "120 degrees in a plane", "a zero normal"] {
        let t = tris.iter().find(|(n, _)| *n == name).unwrap().1;
        assert_eq!(est(&t, &lam, &[point(c + Vec3::Z)], 0.1).reason, Reason::Singular, "{name}");
    }
    // ...unless the light is dark.
    let dark = [Light::Point { position: b.positions[0], color: Vec3::ONE, intensity: 0.0 }];
    assert_eq!(est(&b, &lam, &dark, 0.0).n, 1);
    // Flat shading: exactly n = 1 even for ε = 0.
    let mut flat = b;
    flat.normals = [Vec3::Z; 3];
    let e = est(&flat, &lam, &[sun(-Vec3::Z)], 0.0);
    assert!(!e.fallback && e.n == 1 && e.predicted_error == 0.0, "{e:?}");
    // ε = 0 with varying shading: no level suffices.
    assert_eq!(est(&b, &lam, &[point(c + Vec3::Z)], 0.0).reason, Reason::Level);
    // Huge ε: level 1.
    for m in materials() {
        let e = est(&b, &m, &[point(c + Vec3::new(0.2, 0.1, 2.0))], 1.0e6);
        assert!(!e.fallback && e.n == 1, "{m:?} {e:?}");
    }
    // A terminator through the triangle: Conservative falls back, Relaxed need not.
    let mut curved = b;
    curved.normals = [Vec3::new(0.7, 0.0, 0.7).normalize(), Vec3::new(-0.7, 0.0, 0.7).normalize(), Vec3::Z];
    let grazing = [sun(Vec3::new(-1.0, 0.0, -0.1))];
    let conservative = EstimatorSettings {
        epsilon: 0.5,
        discontinuity: Discontinuity::Conservative,
        ..EstimatorSettings::default()
    };
    assert_eq!(estimate(&curved, &lam, &grazing, &conservative).reason, Reason::Discontinuity);
    let e = est(&curved, &lam, &grazing, 0.5);
    assert!(!e.fallback, "{e:?}");
    assert!(e.term(Term::Terminator) > 0.0);
    // The sharpest lobes over a curved triangle at the highlight need more than n_max.
    let bp = MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::ONE, shininess: 1.0e4 };
    let ggx = MaterialKind::Ggx { albedo: Vec3::ZERO, f0: Vec3::ONE, roughness: 0.0 };
    let over = [point(Vec3::new(0.4, 1.0, 3.0))];
    assert!(est(&curved, &bp, &over, 0.075).fallback);
    assert!(est(&curved, &ggx, &over, 0.075).fallback);
    // Uniform never asks for less than Heuristic; smaller ε never for less.
    for m in materials() {
        let l = [point(c + Vec3::new(0.3, 0.2, 1.5))];
        let h = est(&b, &m, &l, 0.02);
        let u = estimate(
            &b,
            &m,
            &l,
            &EstimatorSettings { epsilon: 0.02, split: Split::Uniform, ..EstimatorSettings::default() },
        );
        if !h.fallback && !u.fallback {
            assert!(u.n >= h.n, "{m:?}");
        }
        let mut last = 0;
        for eps in [1.0, 0.3, 0.1, 0.03, 0.01, 0.003] {
            let e = est(&b, &m, &l, eps);
            let n = if e.fallback { 99 } else { e.n };
            assert!(n >= last, "{m:?} eps {eps}");
            last = n;
        }
    }
}
