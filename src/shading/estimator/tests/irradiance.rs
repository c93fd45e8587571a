//! The falloff and irradiance jets and their light-part bounds (`along_plane`, `tilted`)
//! against finite differences.

use super::*;

#[test]
fn attenuation_jet_bounds_the_exact_derivatives() {
    let mut rng = crate::test_rng::Rng(0x5eed_a77e);
    let mut range = |lo: f64, hi: f64| f64::from(rng.range(lo as f32, hi as f32));
    let (mut checked, mut tightest) = (0usize, 0.0f64);
    for case in 0..400 {
        let mut corner = || DVec3::new(range(-1.0, 1.0), range(-1.0, 1.0), range(-0.2, 0.2));
        let tri = [corner(), corner(), corner()];
        let normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
        if normal.length() < 1e-2 {
            continue;
        }
        let normal = normal.normalize();
        let centre = (tri[0] + tri[1] + tri[2]) / 3.0;
        let far = case % 3;
        let light = match far {
            // Grazing: in the plane, outside the triangle.
            0 => centre + (tri[0] - centre) * range(1.2, 3.0),
            // Close: less than the triangle's size above it.
            1 => centre + normal * range(0.05, 0.5) + (tri[1] - centre) * range(0.0, 0.9),
            _ => centre + DVec3::new(range(-5.0, 5.0), range(-5.0, 5.0), range(2.0, 8.0)),
        };
        // Points of the triangle on a dense barycentric grid: d_min and max sin γ over it
        // (the estimator's cones give bounds of these), a little on the safe side.
        let points: Vec<DVec3> = (0..=40)
            .flat_map(|i| (0..=40 - i).map(move |j| (i, j)))
            .map(|(i, j)| {
                let (u, v) = (f64::from(i) / 40.0, f64::from(j) / 40.0);
                tri[0] + (tri[1] - tri[0]) * u + (tri[2] - tri[0]) * v
            })
            .collect();
        let d_min = points.iter().map(|p| (light - *p).length()).fold(f64::INFINITY, f64::min) * 0.98;
        let sin_max = points
            .iter()
            .map(|p| {
                let l = (light - *p).normalize();
                (l - normal * l.dot(normal)).length()
            })
            .fold(0.0, f64::max)
            .min(1.0);
        let jet = attenuation_jet((1.0 / d_min) as f32, sin_max as f32, 1.0, &Guard::default());
        let falloff = |x: DVec3| 1.0 / (light - x).length_squared();
        for p in points.iter().step_by(7) {
            let angle = range(0.0, std::f64::consts::TAU);
            let e1 = (tri[1] - tri[0]).normalize();
            let e2 = normal.cross(e1);
            let u = e1 * angle.cos() + e2 * angle.sin();
            let [f0, first, second] = differences(&|s| falloff(*p + u * s), 0.0, 1e-4 * d_min);
            let what = format!("case {case}: light {light:?}, point {p:?}");
            assert!(f0 <= f64::from(jet.m) * 1.0001, "{what}: value {f0} > {}", jet.m);
            assert!(first.abs() <= f64::from(jet.g) * 1.0001, "{what}: first {first} > {}", jet.g);
            assert!(second.abs() <= f64::from(jet.t) * 1.001, "{what}: second {second} > {}", jet.t);
            tightest = tightest.max(second.abs() / f64::from(jet.t));
            checked += 1;
        }
    }
    assert!(checked > 5_000, "{checked} points checked");
    // The bound is reached within a few per cent (grazing lights): not just valid, tight.
    assert!(tightest > 0.85, "the largest second derivative is only {tightest} of the bound");
}

/// A random point `(u, v)` of the patch (barycentric, uniform in `u`) and a random unit
/// step direction `(du, dv)` in the same coordinates.
fn point_and_step(rng: &mut crate::test_rng::Rng) -> (f64, f64, f64, f64) {
    let (u, v) = (f64::from(rng.range(0.0, 1.0)), f64::from(rng.f()));
    let turn = f64::from(rng.range(0.0, std::f32::consts::TAU));
    (u, (1.0 - u) * v, turn.cos(), turn.sin())
}

#[test]
fn irradiance_jet_bounds_the_exact_derivatives() {
    let mut rng = crate::test_rng::Rng(0x1aad_1a9c_e5e1_d000);
    let (mut checked, mut tightest) = (0usize, [0.0f64; 2]);
    let gd = Guard::default();
    for case in 0..1500 {
        let size = rng.range(0.05, 1.0);
        let curved = case % 2 == 1;
        let Some((tri, position, frame, setup)) = planned_irradiance_case(&mut rng, size, curved, case % 3)
        else {
            continue;
        };
        let (positions, normals) = (tri.positions, tri.normals);
        let [p, q, r] = positions.map(|x| x.as_dvec3());
        let [np, nq, nr] = normals.map(|x| x.as_dvec3());
        let light_at = position.as_dvec3();
        for _ in 0..8 {
            let (u, v, du, dv) = point_and_step(&mut rng);
            let diffuse = |t: f64| {
                let (a, b) = (u + t * du, v + t * dv);
                let x = p + (q - p) * a + (r - p) * b;
                let n = (np + (nq - np) * a + (nr - np) * b).normalize();
                let d = light_at - x;
                n.dot(d) / d.length().powi(3)
            };
            let scale = scale_along(&tri, du, dv);
            let (n_field, _) = normal_and_light_fields(&frame, &setup, scale, &gd);
            let jet = irradiance_jet(&frame, &setup, &n_field, scale.a, &gd);
            // A step well inside the light's distance; the differences' rounding is about
            // 10⁻¹⁶·|f|/h per order.
            let h = 1.0e-3 * f64::from(size.min(1.0 / setup.inv_d));
            let [value, first, second] = differences(&diffuse, 0.0, h);
            let slack = 1.0e-14 * value.abs() / (h * h);
            let what =
                format!("case {case}: light {position:?}, triangle {positions:?}, normals {normals:?}");
            assert!(value.abs() <= f64::from(jet.m) * 1.0001, "{what}: value {value} > {}", jet.m);
            assert!(first.abs() <= f64::from(jet.g) * 1.001, "{what}: first {first} > {}", jet.g);
            assert!(second.abs() <= f64::from(jet.t) * 1.001 + slack, "{what}: second {second} > {}", jet.t);
            if slack < 1.0e-3 * second.abs() {
                let k = usize::from(curved);
                tightest[k] = tightest[k].max(second.abs() / f64::from(jet.t));
            }
            checked += 1;
        }
    }
    eprintln!(
        "irradiance: {checked} points; largest |f''| / bound, flat {:.3}, curved {:.3}",
        tightest[0], tightest[1]
    );
    assert!(checked > 5_000, "{checked} points checked");
    assert!(tightest[0] > 0.9, "flat normals: the bound is never approached: {tightest:?}");
    assert!(tightest[1] > 0.5, "curved normals: the bound is never approached: {tightest:?}");
}

/// One candidate bound of the light part, `k·|a|²/d_min⁴` with `k = candidate(frame, setup)`,
/// against `n̂·D²I[a, a]` (the normal held at the point's) by f64 central differences at 8
/// random points and steps of each of 1 500 triangles of [`irradiance_case`]: never above it.
/// Returns the points checked, the triangles where it is below 0.9 of `others(frame, setup)`,
/// and its largest `|f''|/bound`.
fn check_light_part_bound(
    seed: u64,
    candidate: impl Fn(&Frame, &LightSetup) -> f32,
    others: impl Fn(&Frame, &LightSetup) -> f32,
) -> (usize, usize, f64) {
    let mut rng = crate::test_rng::Rng(seed);
    let (mut checked, mut deciding, mut tightest) = (0usize, 0usize, 0.0f64);
    for case in 0..1500 {
        let size = rng.range(0.05, 1.0);
        let Some((tri, position, frame, setup)) =
            planned_irradiance_case(&mut rng, size, case % 2 == 1, case % 3)
        else {
            continue;
        };
        let k = f64::from(candidate(&frame, &setup));
        deciding += usize::from(k < 0.9 * f64::from(others(&frame, &setup)));
        let inv_d4 = f64::from(setup.inv_d).powi(4);
        let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
        let [np, nq, nr] = tri.normals.map(|x| x.as_dvec3());
        let light_at = position.as_dvec3();
        for _ in 0..8 {
            let (u, v, du, dv) = point_and_step(&mut rng);
            let n = (np + (nq - np) * u + (nr - np) * v).normalize();
            let light_part = |t: f64| {
                let x = p + (q - p) * (u + t * du) + (r - p) * (v + t * dv);
                let d = light_at - x;
                n.dot(d) / d.length().powi(3)
            };
            let bound = k * ((q - p) * du + (r - p) * dv).length_squared() * inv_d4;
            let h = 1.0e-3 * f64::from(size.min(1.0 / setup.inv_d));
            let [value, _, second] = differences(&light_part, 0.0, h);
            let slack = 1.0e-14 * value.abs() / (h * h);
            assert!(
                second.abs() <= bound * 1.001 + slack,
                "case {case}: light {position:?}, {tri:?}: second {second} > {bound}"
            );
            if slack < 1.0e-3 * second.abs() {
                tightest = tightest.max(second.abs() / bound);
            }
            checked += 1;
        }
    }
    (checked, deciding, tightest)
}

/// `projected`, the light part's candidate [`along_plane`] improves on.
fn projected(frame: &Frame, setup: &LightSetup) -> f32 {
    let (sg, c) = (setup.plane_sin, Angles::of(setup.psi_nl).c_max);
    6.0 * sg * frame.n_plane_sin + (15.0 * sg * sg - 3.0).abs().max(3.0) * c
}

/// [`along_plane`] alone against the light part: never above it, within a few per cent of
/// it somewhere, and below `projected` on many triangles.
#[test]
fn along_plane_bounds_the_light_part() {
    let (checked, deciding, tightest) = check_light_part_bound(
        0x0f0e_d1ec_7a1a_0001,
        |frame, setup| along_plane(setup, frame.n_plane_sin, Angles::of(setup.psi_nl).c_max),
        projected,
    );
    eprintln!("along the plane: {checked} points, below 0.9 of `projected` on {deciding} triangles, largest |f''| / bound {tightest:.3}");
    assert!(checked > 5_000 && deciding > 100, "{checked} points, {deciding} deciding");
    assert!(tightest > 0.9, "the bound is never approached: {tightest}");
}

/// [`tilted`] alone against the light part, the same way: never above it, reached somewhere,
/// and below 0.9 of the other candidates on triangles with curved normals and lights near
/// their plane.
#[test]
fn tilted_bounds_the_light_part() {
    let (checked, deciding, tightest) = check_light_part_bound(
        0x7117_ed00_1a9c_0002,
        |frame, setup| tilted(setup, frame.n_plane_sin),
        |frame, setup| {
            let near2 = setup.near_sin * setup.near_sin;
            let whole = (45.0 * near2 * near2 - 18.0 * near2 + 9.0).max(9.0).sqrt();
            let c = Angles::of(setup.psi_nl).c_max;
            whole.min(projected(frame, setup)).min(along_plane(setup, frame.n_plane_sin, c))
        },
    );
    eprintln!("tilted: {checked} points, below 0.9 of the others on {deciding} triangles, largest |f''| / bound {tightest:.3}");
    assert!(checked > 5_000 && deciding > 25, "{checked} points, {deciding} deciding");
    assert!(tightest > 0.9, "the bound is never approached: {tightest}");
}

/// The two suprema [`tilted`] takes in closed form, against a dense search in f64: the
/// first part's `z⁵·max(3, |12 − 15h²z²|)` over `z ≤ 1`, and `s·max|G|` over the angles,
/// which must also not decrease with `s` (the bound takes it at the largest `s`).
#[test]
fn tilted_suprema_are_the_maxima() {
    let setup_with = |near_cos: f32, plane_sin: f32| LightSetup {
        plane_sin,
        near_cos,
        ..LightSetup::unbounded(1.0, (0.0, PI), false, None)
    };
    for i in 0..=200 {
        let h = f64::from(i) / 200.0;
        let rising = f64::from(tilted(&setup_with(h as f32, 0.0), 0.0));
        let searched = (1..=4000)
            .map(|j| {
                let z = f64::from(j) / 4000.0;
                z.powi(5) * (12.0 - 15.0 * h * h * z * z).abs().max(3.0)
            })
            .fold(0.0, f64::max);
        assert!(searched <= rising * (1.0 + 1.0e-6), "h {h}: searched {searched} > {rising}");
        assert!(searched >= rising * 0.999, "h {h}: searched {searched} far below {rising}");
    }
    let mut last = 0.0f64;
    for i in 0..=200 {
        let s = f64::from(i) / 200.0;
        let turning = f64::from(tilted(&setup_with(0.0, s as f32), 1.0)) - 12.0;
        let mut searched = 0.0f64;
        for a in 0..=180 {
            let alpha = f64::from(a) * std::f64::consts::PI / 180.0;
            for b in 0..=360 {
                let beta = f64::from(b) * std::f64::consts::PI / 180.0;
                let g = beta.cos() * ((15.0 * s * s - 6.0) * alpha.cos().powi(2) - 3.0)
                    - 3.0 * (2.0 * alpha).sin() * beta.sin();
                searched = searched.max(s * g.abs());
            }
        }
        assert!(searched <= turning + 1.0e-5, "s {s}: searched {searched} > {turning}");
        assert!(searched >= turning - 2.0e-3, "s {s}: searched {searched} far below {turning}");
        assert!(turning >= last - 1.0e-6, "s {s}: {turning} below {last} at a smaller s");
        last = turning;
    }
}
