//! Effective levels of mixed patterns: the table against the model of the tessellator, the
//! patch-level rule, and the error on mixed patterns against the oracle.

use super::pattern::{constants_of, pattern_r2, random_shapes};
use super::*;
use crate::analysis::pattern_level::{effective_level, pack, table_entry};

/// The effective level `L` of the model's pattern for `inner`, `outer`.
fn pattern_level_exact(inner: u32, outer: [u32; 3]) -> f64 {
    let p = triangle_pattern(inner as f32, outer.map(|o| o as f32));
    effective_level(p.triangles.iter().map(|t| t.map(|v| p.vertices[v as usize])))
}

/// The packed table equals the levels measured on the driver's patterns (a sample of
/// inner × outer levels; the full table is the same computation for all 64 × 64).
#[test]
fn pattern_level_table_matches_the_driver_patterns() {
    let levels = [1u32, 2, 3, 4, 5, 8, 13, 16, 31, 64];
    for &inner in &levels {
        for &outer in &levels {
            let expected = table_entry(pattern_level_exact(inner, [outer; 3]));
            let table = (pattern_level(inner, outer) * 256.0).round() as u32;
            assert_eq!(table, expected, "inner {inner}, outer {outer}");
        }
    }
}

/// The whole table against the driver's patterns. Every entry is checked when
/// `MULTIRATE_PATTERN_LEVELS=print` is set, which also prints the packed words for
/// `PATTERN_LEVELS`; otherwise every 7th entry (the full table takes a
/// few seconds in a debug build).
#[test]
fn pattern_level_table_is_current() {
    let print = std::env::var("MULTIRATE_PATTERN_LEVELS").is_ok_and(|v| v == "print");
    for index in 0..4096u32 {
        if !print && index % 7 != 0 {
            continue;
        }
        let (inner, outer) = (index / 64 + 1, index % 64 + 1);
        let expected = table_entry(pattern_level_exact(inner, [outer; 3]));
        let table = (pattern_level(inner, outer) * 256.0).round() as u32;
        assert_eq!(
            table, expected,
            "inner {inner}, outer {outer}: regenerate with MULTIRATE_PATTERN_LEVELS=print"
        );
    }
    if print {
        let words = pack(|inner, outer| table_entry(pattern_level_exact(inner, [outer; 3])));
        for line in words.chunks(8) {
            let items: Vec<String> = line.iter().map(|w| format!("{w:#010x}")).collect();
            println!("    {},", items.join(", "));
        }
    }
}

/// The effective levels against sampled attribute maps: on the driver's patterns, no
/// sub-triangle of any of the test shapes exceeds `K/L²` (the gauge argument is a bound),
/// and the worst shape comes within a few per cent of it (the bound is tight).
#[test]
fn pattern_levels_bound_and_are_reached_by_sampled_shapes() {
    let mut shapes = random_shapes();
    for xi in -12..=16 {
        for y in [1e-3, 0.03, 0.1, 0.3, 0.6, 1.0, 2.0] {
            shapes.push([DVec3::ZERO, DVec3::X, DVec3::new(f64::from(xi) * 0.25, y, 0.0)]);
        }
    }
    let constants: Vec<f64> = shapes.iter().map(|c| f64::from(constants_of(*c).sqrt_k).powi(2)).collect();
    let mut loosest = 0.0f64;
    for (inner, outer) in [
        (4, 5),
        (6, 9),
        (7, 9),
        (8, 9),
        (10, 17),
        (12, 16),
        (12, 17),
        (13, 17),
        (16, 17),
        (9, 6),
        (12, 9),
        (17, 24),
        (24, 33),
        (48, 64),
        (64, 46),
    ] {
        let level = f64::from(pattern_level(inner, outer));
        let p = triangle_pattern(inner as f32, [outer as f32; 3]);
        let mut worst = 0.0f64; // max over shapes of max r² · L² / K
        for (c, &k) in shapes.iter().zip(&constants) {
            if k > 0.0 {
                worst = worst.max(pattern_r2(&p, *c) * level * level / k);
            }
        }
        assert!(worst <= 1.0 + 1e-4, "inner {inner}, outer {outer}: r²·L²/K = {worst}");
        loosest = loosest.max(1.0 - worst);
        assert!(worst > 0.9, "inner {inner}, outer {outer}: the bound is loose ({worst})");
    }
    println!("effective levels: the sampled worst shapes reach r²·L²/K ≥ {:.4}", 1.0 - loosest);
}

/// A patch's effective level is the smallest of its edges' table entries: checked on
/// patterns with three different outer levels.
#[test]
fn mixed_patterns_take_the_smallest_edge_level() {
    let mut rng = Rng(0x005e_ed1e_7e15);
    for _ in 0..150 {
        let pick = |rng: &mut Rng| 1 + (rng.f() * 24.0) as u32;
        let inner = pick(&mut rng);
        let outer = [pick(&mut rng), pick(&mut rng), pick(&mut rng)];
        let exact = pattern_level_exact(inner, outer);
        let table = outer.iter().map(|&o| pattern_level(inner, o)).fold(f32::MAX, f32::min);
        assert!(
            f64::from(table) <= exact + 1e-9,
            "inner {inner}, outer {outer:?}: table {table} > exact {exact}"
        );
        assert!(f64::from(table) >= exact.max(1.0) - 1.0 / 256.0 - 1e-9, "inner {inner}, outer {outer:?}");
    }
}

/// The combination rule: shared edges agree, fallback triangles ask for nothing, the
/// chosen pattern is fine enough and the smallest inner level that is.
#[test]
fn patch_levels_rule() {
    let mut rng = Rng(0x0ab5_0c1a_7e00);
    let level = |rng: &mut Rng| match (rng.f() * 6.0) as u32 {
        0 => FALLBACK_LEVEL,
        1 => 1.0,
        2 => f32::NAN,
        _ => 1.0 + (rng.f() * 20.0) as f32,
    };
    for _ in 0..20_000 {
        let n_max = [1u32, 4, 16, 64][(rng.f() * 4.0) as usize];
        let own = level(&mut rng);
        let nb = [level(&mut rng), level(&mut rng), level(&mut rng)];
        let p = patch_levels(own, nb, n_max);
        let own_n = uniform_level(own, n_max);
        for k in 0..3 {
            // Symmetric: the neighbour computes the same level for the shared edge.
            let theirs = patch_levels(nb[k], [own, own, own], n_max);
            assert_eq!(p.outer[k], theirs.outer[0], "own {own}, neighbour {}", nb[k]);
            assert!(p.outer[k] >= 1.0 && p.outer[k] <= n_max as f32 && p.outer[k].fract() == 0.0);
            assert!(p.outer[k] as u32 >= own_n);
        }
        assert!(p.inner >= 1.0 && p.inner <= n_max as f32 && p.inner.fract() == 0.0);
        if own_n == 0 {
            assert!(p.fallback && p.inner == 1.0, "{own} {p:?}");
        }
        let l = |i: u32| p.outer.iter().map(|&o| pattern_level(i, o as u32)).fold(f32::MAX, f32::min);
        if !p.fallback {
            let i = p.inner as u32;
            assert!(l(i) >= own, "{own} {p:?}");
            assert!((1..i).all(|j| l(j) < own), "not the smallest inner level: {own} {p:?}");
        } else if own_n > 0 {
            assert!((1..=n_max).all(|j| l(j) < own), "{own} {p:?}");
        }
        // All equal: the uniform pattern.
        if nb.iter().all(|&x| x == own) && own_n > 0 {
            assert_eq!(p.outer, [own_n as f32; 3]);
            assert!(!p.fallback && p.inner as u32 <= own_n);
        }
    }
}

/// Property test of the mixed patterns the rule draws: random triangles and lights (as in
/// `tests/estimator_property.rs`, smaller), random neighbour levels (fallback, equal,
/// higher, much higher), the pattern `triangle_pattern(inner, outer)` of `patch_levels`:
/// its true error (oracle, close calls re-measured 16 times denser) must stay under ε.
#[test]
fn mixed_patterns_keep_the_error_under_epsilon() {
    use crate::analysis::oracle::{true_error_sampled, SAMPLES_PER_EDGE};
    let mut rng = Rng(0x0000_ddba_11c0_ffee);
    let (mut checked, mut mixed, mut worst) = (0usize, 0usize, 0.0f64);
    for case in 0..3000 {
        let brdf = case % 3;
        let f = |rng: &mut Rng| rng.f() as f32;
        let unit = |rng: &mut Rng| Vec3::new(f(rng) - 0.5, f(rng) - 0.5, f(rng) - 0.5).normalize_or(Vec3::Z);
        let dist = 0.5 + 10.0 * f(&mut rng);
        let dir = unit(&mut rng);
        let centre = dir * dist;
        let base = (-dir + unit(&mut rng) * 0.8).normalize_or(-dir);
        let (t1, t2) = base.any_orthonormal_pair();
        let size = dist * (0.005 + 0.2 * f(&mut rng));
        let corners: [Vec3; 3] =
            std::array::from_fn(|_| centre + (t1 * (f(&mut rng) - 0.5) + t2 * (f(&mut rng) - 0.5)) * size);
        let spread = 0.6 * f(&mut rng) * f(&mut rng);
        let normals: [Vec3; 3] = std::array::from_fn(|_| (base + unit(&mut rng) * spread).normalize_or(base));
        let tri = TriangleInput { positions: corners, normals, eye: Vec3::ZERO };
        let mut lights = Vec::new();
        for _ in 0..1 + (f(&mut rng) * 2.0) as usize {
            let l = (base + unit(&mut rng) * 1.2).normalize_or(base);
            if f(&mut rng) < 0.6 {
                let d = size * (0.5 + 30.0 * f(&mut rng));
                lights.push(Light::Point {
                    position: centre + l * d,
                    color: Vec3::new(1.0, 0.8, 0.6),
                    intensity: d * d * (0.5 + 2.0 * f(&mut rng)),
                });
            } else {
                lights.push(Light::Directional {
                    direction: -l,
                    color: Vec3::ONE,
                    intensity: 0.5 + f(&mut rng),
                });
            }
        }
        let material = match brdf {
            0 => MaterialKind::Lambert { kd: Vec3::new(0.9, 0.5, 0.2) },
            1 => MaterialKind::BlinnPhong {
                kd: Vec3::splat(0.4),
                ks: Vec3::splat(0.6),
                shininess: 2.0 + 200.0 * f(&mut rng),
            },
            _ => MaterialKind::Ggx {
                albedo: Vec3::splat(0.4),
                f0: Vec3::new(0.04, 0.5, 0.9),
                roughness: 0.2 + 0.8 * f(&mut rng),
            },
        };
        let epsilon = [0.01f32, 0.03, 0.1][(f(&mut rng) * 3.0) as usize];
        let settings = EstimatorSettings { epsilon, n_max: 16, ..EstimatorSettings::default() };
        let own = estimate(&tri, &material, &lights, &settings);
        if own.fallback {
            continue;
        }
        let neighbours: [f32; 3] = std::array::from_fn(|_| match (f(&mut rng) * 4.0) as u32 {
            0 => FALLBACK_LEVEL,
            1 => own.level,
            2 => own.level * (1.0 + 2.0 * f(&mut rng)),
            _ => 1.0 + 16.0 * f(&mut rng),
        });
        let p = patch_levels(own.level, neighbours, 16);
        if p.fallback {
            continue;
        }
        checked += 1;
        if p.outer.iter().any(|&o| o != p.inner) {
            mixed += 1;
        }
        let pattern = triangle_pattern(p.inner, p.outer);
        let eps = f64::from(epsilon);
        let mut error =
            true_error_sampled(&tri, &material, &lights, &pattern, SAMPLES_PER_EDGE, f64::INFINITY);
        if error.iter().any(|&e| e > 0.5 * eps) {
            let fine = true_error_sampled(&tri, &material, &lights, &pattern, 24, f64::INFINITY);
            error = std::array::from_fn(|c| error[c].max(fine[c]));
        }
        let e = error.iter().copied().fold(0.0, f64::max);
        worst = worst.max(e / eps);
        assert!(
            e <= eps,
            "case {case}: true error {e} > ε {eps} on {p:?} (level {}), {material:?}, {lights:?}, {tri:?}",
            own.level
        );
    }
    println!("mixed patterns: {checked} patches checked, {mixed} with raised or lowered edges; largest true error / ε: {worst:.3}");
    assert!(mixed > 1000, "too few mixed patterns: {mixed}");
}
