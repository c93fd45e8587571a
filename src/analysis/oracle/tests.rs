use super::*;
use crate::analysis::tessellator::triangle_pattern;

/// The uniform "three-directional" grid: n² sub-triangles, each a ±1/n copy of the patch.
fn uniform_grid(n: u32) -> Pattern {
    let n = n.max(1);
    let nf = f64::from(n);
    let mut vertices = Vec::new();
    let mut index = vec![vec![0u32; (n + 1) as usize]; (n + 1) as usize];
    for i in 0..=n {
        for j in 0..=(n - i) {
            index[i as usize][j as usize] = vertices.len() as u32;
            vertices.push([f64::from(i) / nf, f64::from(j) / nf, f64::from(n - i - j) / nf]);
        }
    }
    let mut triangles = Vec::new();
    for i in 0..n {
        for j in 0..(n - i) {
            let (i, j) = (i as usize, j as usize);
            triangles.push([index[i][j], index[i + 1][j], index[i][j + 1]]);
            if i + j + 2 <= n as usize {
                triangles.push([index[i + 1][j], index[i + 1][j + 1], index[i][j + 1]]);
            }
        }
    }
    Pattern { vertices, triangles }
}

fn hardware(n: u32) -> Pattern {
    triangle_pattern(n as f32, [n as f32; 3])
}

fn lambert() -> MaterialKind {
    MaterialKind::Lambert { kd: Vec3::new(0.8, 0.6, 0.4) }
}

fn curved(spread: f32) -> TriangleInput {
    TriangleInput {
        positions: [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(0.3, 0.9, 0.0)],
        normals: [
            Vec3::new(-spread, -spread, 1.0).normalize(),
            Vec3::new(spread, -0.5 * spread, 1.0).normalize(),
            Vec3::new(0.0, spread, 1.0).normalize(),
        ],
        eye: Vec3::new(0.4, 0.3, 3.0),
    }
}

#[test]
fn uniform_grid_counts() {
    for n in 1..=8 {
        let p = uniform_grid(n);
        assert_eq!(p.triangles.len() as u32, n * n);
        assert_eq!(p.vertices.len() as u32, (n + 1) * (n + 2) / 2);
    }
    assert_eq!(vertices_at_level(1), 3);
    assert_eq!(vertices_at_level(2), 7);
    for n in 1..=16 {
        assert_eq!(vertices_at_level(n) as usize, hardware(n).vertices.len());
    }
}

#[test]
fn flat_shading_has_no_error() {
    let tri = curved(0.0);
    let lights = [Light::Directional {
        direction: Vec3::new(0.1, 0.2, -1.0).normalize(),
        color: Vec3::ONE,
        intensity: 2.0,
    }];
    for n in [1, 2, 5] {
        let e = true_error(&tri, &lambert(), &lights, &hardware(n));
        assert!(e.iter().all(|&x| x < 1e-6), "{e:?}");
    }
    assert_eq!(oracle_level(&tri, &lambert(), &lights, 1e-4, 16, hardware), Some(1));
}

#[test]
fn corners_only_sampling_is_exact() {
    let tri = curved(0.5);
    let lights = [Light::Point { position: Vec3::new(0.2, 0.1, 0.7), color: Vec3::ONE, intensity: 1.0 }];
    let e = true_error_sampled(&tri, &lambert(), &lights, &hardware(3), 1, f64::INFINITY);
    assert_eq!(e, [0.0; 3]);
}

#[test]
fn error_falls_with_the_level_on_both_patterns() {
    let tri = curved(0.6);
    let lights = [Light::Point { position: Vec3::new(0.5, 0.2, 1.5), color: Vec3::ONE, intensity: 3.0 }];
    let m = MaterialKind::BlinnPhong { kd: Vec3::splat(0.5), ks: Vec3::splat(0.5), shininess: 40.0 };
    let e = |p: &Pattern| true_error(&tri, &m, &lights, p)[0];
    let (h1, h8) = (e(&hardware(1)), e(&hardware(8)));
    let (u1, u8) = (e(&uniform_grid(1)), e(&uniform_grid(8)));
    assert!((h1 - u1).abs() < 1e-12, "level 1 is the patch itself in both");
    assert!(h8 < 0.25 * h1 && u8 < 0.25 * u1, "{h1} {h8} {u1} {u8}");
    let level = oracle_level(&tri, &m, &lights, 0.5 * h8 + 0.5 * h1, 16, hardware).unwrap();
    assert!(level > 1 && level <= 8);
    assert_eq!(oracle_level(&tri, &m, &lights, 0.0, 4, hardware), None);
}

/// Refinement study for the sampling density: k = 6 against k = 24 (16× the points), at
/// the level the estimator picks (smooth cases: the estimator did not fall back). The
/// module docs bound the miss by 1/36 of the second-order bound, i.e. of the predicted
/// error at that level.
#[test]
fn sampling_density_refinement() {
    use crate::shading::estimator::{estimate, EstimatorSettings};
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f32 / (1u64 << 53) as f32
    };
    let (mut worst_rel, mut worst_of_bound, mut cases) = (0.0f64, 0.0f64, 0);
    for case in 0..400 {
        if cases >= 60 {
            break;
        }
        let tri = curved(0.02 + 0.5 * rnd());
        let light = Light::Point {
            position: Vec3::new(rnd(), rnd(), 0.5 + 3.0 * rnd()),
            color: Vec3::ONE,
            intensity: 4.0,
        };
        let m = match case % 3 {
            0 => lambert(),
            1 => MaterialKind::BlinnPhong {
                kd: Vec3::splat(0.3),
                ks: Vec3::splat(0.7),
                shininess: 1.0 + 300.0 * rnd(),
            },
            _ => MaterialKind::Ggx {
                albedo: Vec3::splat(0.3),
                f0: Vec3::splat(0.04),
                roughness: 0.1 + 0.9 * rnd(),
            },
        };
        let settings = EstimatorSettings { epsilon: 0.02, n_max: 12, ..EstimatorSettings::default() };
        let est = estimate(&tri, &m, &[light], &settings);
        if est.fallback {
            continue;
        }
        cases += 1;
        let p = hardware(est.n);
        let coarse = true_error_sampled(&tri, &m, &[light], &p, SAMPLES_PER_EDGE, f64::INFINITY);
        let fine = true_error_sampled(&tri, &m, &[light], &p, 24, f64::INFINITY);
        for c in 0..3 {
            let missed = (fine[c] - coarse[c]).max(0.0);
            worst_of_bound = worst_of_bound.max(missed / f64::from(est.predicted_error));
            if fine[c] > 1e-3 {
                worst_rel = worst_rel.max(missed / fine[c]);
            }
        }
    }
    println!(
        "oracle sampling over {cases} cases: k = 6 misses at most {:.2} % of the k = 24 maximum, {:.3} % of the predicted bound",
        100.0 * worst_rel,
        100.0 * worst_of_bound
    );
    assert!(cases >= 30);
    assert!(worst_of_bound <= 1.0 / 36.0, "{worst_of_bound}");
}
