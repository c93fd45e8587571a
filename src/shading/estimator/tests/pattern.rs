//! The pattern constants `K_W`, `D_W` against the model's hardware patterns.

use super::*;

/// Exact `max_x Σμₖ|vₖ − x|²` of a triangle in f64.
fn enclosing_r2(p: [DVec3; 3]) -> f64 {
    let e = [(p[1] - p[0]).length_squared(), (p[2] - p[1]).length_squared(), (p[0] - p[2]).length_squared()];
    let d2 = e[0].max(e[1]).max(e[2]);
    if 2.0 * d2 >= e[0] + e[1] + e[2] {
        return 0.25 * d2;
    }
    let x = (p[1] - p[0]).cross(p[2] - p[0]).length_squared();
    e[0] * e[1] * e[2] / (4.0 * x)
}

pub(super) fn pattern_r2(p: &Pattern, corners: [DVec3; 3]) -> f64 {
    let place = |b: [f64; 3]| corners[0] * b[0] + corners[1] * b[1] + corners[2] * b[2];
    p.triangles.iter().map(|t| enclosing_r2(t.map(|i| place(p.vertices[i as usize])))).fold(0.0, f64::max)
}

pub(super) fn random_shapes() -> Vec<[DVec3; 3]> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut shapes = vec![
        [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 0.75f64.sqrt(), 0.0)],
        [DVec3::ZERO, DVec3::X, DVec3::Y],
        [DVec3::ZERO, DVec3::X, DVec3::new(0.0, 0.001, 0.0)],
        [DVec3::ZERO, DVec3::X, DVec3::new(0.5, 0.001, 0.0)],
        [DVec3::ZERO, DVec3::X, DVec3::new(3.0, 0.01, 0.0)],
    ];
    for _ in 0..40 {
        let mut c = [DVec3::ZERO; 3];
        for p in &mut c {
            *p = DVec3::new(rng.f(), rng.f(), rng.f());
        }
        if rng.f() < 0.3 {
            c[2] = c[0].lerp(c[1], 2.0 * rng.f() - 0.5) + DVec3::new(rng.f(), rng.f(), rng.f()) * 1e-3;
        }
        shapes.push(c);
    }
    shapes
}

pub(super) fn constants_of(c: [DVec3; 3]) -> PatternConstants {
    pattern_constants((c[1] - c[0]).as_vec3(), (c[2] - c[0]).as_vec3())
}

/// Relative growth of the uniform pattern's constant with the level from the driver's
/// fixed-point placement, `K(n) ≤ K·(1 + n²·PATTERN_SLACK)` (the estimator now reads
/// it, with the mixed patterns, from [`pattern_level`]).
const PATTERN_SLACK: f32 = 2.0e-5;

/// The pattern constants against the hardware pattern (Vulkan `equal_spacing`, inner =
/// outer = n, lavapipe's fixed point): `max over sub-triangles of r² · n² ≤ K (1 + n²·s)`.
#[test]
fn pattern_constants_cover_the_hardware_pattern() {
    let shapes = random_shapes();
    let mut worst_slack = 0.0f64; // max over n of (ratio − 1)/n²
    let mut worst_ratio_16 = 0.0f64;
    let mut worst_ratio_64 = 0.0f64;
    for n in 1..=64u32 {
        let p = triangle_pattern(n as f32, [n as f32; 3]);
        for c in &shapes {
            let k = constants_of(*c);
            let bound = if n == 1 { k.sqrt_k1 } else { k.sqrt_k };
            let bound = f64::from(bound).powi(2);
            let real = pattern_r2(&p, *c) * f64::from(n * n);
            if bound == 0.0 {
                assert!(real < 1e-12);
                continue;
            }
            let ratio = real / bound;
            if n <= 16 {
                worst_ratio_16 = worst_ratio_16.max(ratio);
            }
            worst_ratio_64 = worst_ratio_64.max(ratio);
            worst_slack = worst_slack.max((ratio - 1.0) / f64::from(n * n));
            assert!(
                ratio <= 1.0 + f64::from(n * n) * f64::from(PATTERN_SLACK) + 1e-4,
                "n = {n}, ratio {ratio}, shape {c:?}"
            );
        }
    }
    println!(
        "pattern constants: real/predicted r² at most {worst_ratio_16:.5} (n ≤ 16), {worst_ratio_64:.5} (n ≤ 64); (ratio − 1)/n² at most {worst_slack:.2e}"
    );
}

/// Measures (does not assert) how far mixed levels (outer ≥ inner, as a crack-free TCS
/// that raises shared edges to the neighbour's level produces) exceed the uniform
/// constants.
#[test]
fn pattern_constants_with_raised_outer_levels() {
    let shapes = random_shapes();
    let mut worst = (0.0f64, 0u32, [0u32; 3]);
    for n in 1..=12u32 {
        for m0 in [n, n + 1, n + 3, 16] {
            for m1 in [n, n + 2, 16] {
                for m2 in [n, n + 5] {
                    let outer = [m0, m1, m2];
                    let p = triangle_pattern(n as f32, outer.map(|m| m as f32));
                    for c in &shapes {
                        let k = constants_of(*c);
                        let bound = f64::from(if n == 1 { k.sqrt_k1 } else { k.sqrt_k }).powi(2);
                        if bound == 0.0 {
                            continue;
                        }
                        let ratio = pattern_r2(&p, *c) * f64::from(n * n) / bound;
                        if ratio > worst.0 {
                            worst = (ratio, n, outer);
                        }
                    }
                }
            }
        }
    }
    println!(
        "raised outer levels: real/predicted r² up to {:.4} (inner {}, outer {:?})",
        worst.0, worst.1, worst.2
    );
}
