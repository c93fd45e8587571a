//! Clipping to the horizon against the Sutherland–Hodgman reference.

use super::*;

/// Whether `a` (f32 clip) and `b` (f64 reference) are the same cyclic vertex sequence up to
/// `tolerance` relative to `scale`.
fn same_cycle(a: &[DVec3], b: &[DVec3], tolerance: f64, scale: f64) -> bool {
    if a.len() != b.len() {
        return false;
    }
    if a.is_empty() {
        return true;
    }
    (0..a.len())
        .any(|shift| (0..a.len()).all(|j| (a[(j + shift) % a.len()] - b[j]).length() <= tolerance * scale))
}

/// Compares `clip_to_horizon` with the f64 reference for one polygon; returns the reference
/// vertex count (after dropping duplicates).
fn check_clip(vertices: &[Vec3], label: &str) -> usize {
    let reference = clip_horizon_reference(&to_f64(vertices));
    let clipped = clip_to_horizon(&Polygon::new(vertices));
    let scale = vertices.iter().map(|p| p.length() as f64).fold(0.0, f64::max);
    if reference.len() > MAX_CLIPPED_VERTICES {
        assert_eq!(clipped.count, 0, "{label}: overflowing clip must be empty");
        return reference.len();
    }
    let mine = dedupe(&to_f64(clipped.as_slice()));
    assert_eq!(mine.len(), clipped.count, "{label}: clip produced duplicate vertices");
    assert_eq!(clipped.count, reference.len(), "{label}: vertex count");
    assert!(clipped.as_slice().iter().all(|p| p.z >= 0.0), "{label}: vertex below the horizon");
    assert!(same_cycle(&mine, &reference, 1e-6, scale), "{label}: vertices {mine:?} vs {reference:?}");
    let psa = projected_solid_angle(&clipped) as f64;
    let expected = psa_reference(&reference).abs();
    assert!((psa - expected).abs() <= 2e-6 + 1e-5 * expected, "{label}: psa {psa} vs {expected}");
    reference.len()
}

#[test]
fn clip_matches_reference_for_every_sign_pattern() {
    // Regular-ish convex polygons (in their xy-projection) whose vertex heights take every
    // above/below pattern; a non-contiguous pattern makes the polygon non-planar, which the
    // clipper handles edge by edge as long as the result fits.
    let mut rng = Rng::new(1);
    let mut overflowing = 0;
    for count in 3..=MAX_POLYGON_VERTICES {
        for pattern in 0u32..1 << count {
            let center = DVec3::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), 0.0);
            let rotation = rng.range(0.0, 2.0 * PI);
            let vertices: Vec<Vec3> = (0..count)
                .map(|k| {
                    let angle = rotation + 2.0 * PI * (k as f64 + 0.6 * (rng.uniform() - 0.5)) / count as f64;
                    let height = rng.range(0.2, 1.0) * if pattern >> k & 1 == 1 { 1.0 } else { -1.0 };
                    (center + DVec3::new(angle.cos(), angle.sin(), height)).as_vec3()
                })
                .collect();
            let expected = check_clip(&vertices, &format!("{count} vertices, pattern {pattern:b}"));
            if pattern == 0 {
                assert_eq!(expected, 0);
            }
            if pattern == (1 << count) - 1 {
                assert_eq!(expected, count);
            }
            overflowing += (expected > MAX_CLIPPED_VERTICES) as usize;
        }
    }
    // Alternating patterns of non-planar polygons do overflow; the test saw that path too.
    assert!(overflowing > 0);
}

#[test]
fn clip_planar_polygons_in_every_realizable_configuration() {
    // A plane meets a convex planar polygon in a line, so the vertices above the horizon form a
    // cyclic run. Realise every such pattern (with and without vertices exactly on the horizon)
    // by tilting a regular polygon, in both windings.
    let mut rng = Rng::new(2);
    for count in 3..=MAX_POLYGON_VERTICES {
        let mut realizable = 0;
        for pattern in 0u32..1 << count {
            let above: Vec<bool> = (0..count).map(|k| pattern >> k & 1 == 1).collect();
            let run = above.iter().filter(|&&a| a).count();
            let starts: Vec<usize> =
                (0..count).filter(|&k| above[k] && !above[(k + count - 1) % count]).collect();
            let start = match (run, starts.len()) {
                (0, _) => 0,
                (r, _) if r == count => 0,
                (_, 1) => starts[0],
                _ => continue, // not a cyclic run: no planar polygon has this pattern
            };
            realizable += 1;
            for on_horizon in [false, true] {
                let radius = rng.range(0.5, 2.0);
                let rotation = rng.range(0.0, 2.0 * PI);
                let slope = rng.range(0.3, 2.0);
                let offset = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0);
                let step = 2.0 * PI / count as f64;
                let middle = rotation + step * (start as f64 + 0.5 * (run as f64 - 1.0));
                let threshold = match run {
                    0 => 1.5,
                    r if r == count => -1.5,
                    r if on_horizon => (0.5 * step * (r as f64 - 1.0)).cos(),
                    r => (0.5 * step * r as f64).cos(),
                };
                let mut vertices: Vec<Vec3> = (0..count)
                    .map(|k| {
                        let angle = rotation + step * k as f64;
                        let mut height = slope * radius * ((angle - middle).cos() - threshold);
                        if height.abs() < 1e-9 {
                            height = 0.0;
                        }
                        (offset + DVec3::new(radius * angle.cos(), radius * angle.sin(), height)).as_vec3()
                    })
                    .collect();
                let realized: Vec<bool> = vertices.iter().map(|p| p.z > 0.0).collect();
                if !on_horizon || run == 0 || run == count {
                    assert_eq!(realized, above, "pattern {pattern:b} not realised");
                }
                for winding in 0..2 {
                    if winding == 1 {
                        vertices.reverse();
                    }
                    let label = format!(
                        "{count} vertices, run {pattern:b}, on horizon {on_horizon}, winding {winding}"
                    );
                    let clipped_count = check_clip(&vertices, &label);
                    let expected = match run {
                        0 => 0,
                        r if r == count => count,
                        // the run's end vertices lie on the horizon: one or two make no area
                        r if on_horizon => {
                            if r >= 3 {
                                r
                            } else {
                                0
                            }
                        }
                        r => r + 2,
                    };
                    assert_eq!(clipped_count, expected, "{label}");
                }
            }
        }
        assert_eq!(realizable, count * (count - 1) + 2, "{count} vertices");
    }
}

#[test]
fn clip_degenerate_inputs() {
    let below = [v(0.0, 0.0, -1.0), v(1.0, 0.0, -1.0), v(0.0, 1.0, -2.0)];
    assert_eq!(clip_to_horizon(&Polygon::new(&below)).count, 0);
    let touching = [v(0.0, 0.0, 0.0), v(1.0, 0.0, -1.0), v(0.0, 1.0, -2.0)];
    assert_eq!(clip_to_horizon(&Polygon::new(&touching)).count, 0);
    let edge_touching = [v(1.0, 0.0, 0.0), v(0.0, 1.0, 0.0), v(0.0, 1.0, -2.0)];
    assert_eq!(clip_to_horizon(&Polygon::new(&edge_touching)).count, 0);
    let in_horizon = [v(1.0, 0.0, 0.0), v(2.0, 0.0, 0.0), v(2.0, 1.0, 0.0), v(1.0, 1.0, 0.0)];
    let clipped = clip_to_horizon(&Polygon::new(&in_horizon));
    assert_eq!(clipped.count, 4);
    assert_eq!(projected_solid_angle(&clipped), 0.0);
    assert_eq!(clip_to_horizon(&Polygon::new(&below[..2])).count, 0);
}

#[test]
fn clip_crossings_are_accurate_near_the_shading_point() {
    // An edge between vertices at distance ~1 that crosses the horizon close to the shading point:
    // the new vertex is accurate relative to its own (small) distance, not only to ε·|vertex|.
    let mut rng = Rng::new(21);
    for _ in 0..500 {
        let distance = 10f64.powf(rng.range(-5.0, -2.0));
        let crossing = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.0).normalize() * distance;
        let along = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.3, 1.0)).normalize();
        let above = (crossing + along * rng.range(0.5, 2.0)).as_vec3();
        let below = (crossing - along * rng.range(0.5, 2.0)).as_vec3();
        let third = v(rng.range(-3.0, 3.0) as f32, rng.range(-3.0, 3.0) as f32, 1.0);
        let clipped = clip_to_horizon(&Polygon::new(&[above, below, third]));
        let reference = clip_horizon_reference(&to_f64(&[above, below, third]));
        assert_eq!(clipped.count, reference.len());
        let (mine, expected) = (clipped.vertices[1].as_dvec3(), reference[1]);
        assert!(
            (mine - expected).length() <= 4.0 * f32::EPSILON as f64 * expected.length(),
            "{mine} vs {expected}"
        );
    }
}
