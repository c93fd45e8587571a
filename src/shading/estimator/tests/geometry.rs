//! Distances, cones and angle ranges: each bound against sampled points and directions.

use super::*;

/// [`Frame::distance_of`] for triangles without a plane (the third corner on the line of the
/// other two, up to rounding): below the distance to the nearest of 45 451 sample points and
/// within 1 % of it.
#[test]
fn distance_along_a_line_bounds_the_nearest_point() {
    let mut rng = crate::test_rng::Rng(0xd157_a9ce_0f11_0004);
    let mut checked = 0;
    for case in 0..600 {
        let a = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
        let b = a + rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
        let c = a.lerp(b, rng.range(-0.5, 1.5));
        let tri = TriangleInput { positions: [a, b, c], normals: [Vec3::Z; 3], eye: Vec3::splat(5.0) };
        let frame = Frame::new(&tri, 0.0, true);
        if frame.plane != Vec3::ZERO {
            continue;
        }
        let position = a.lerp(b, rng.range(-1.0, 2.0))
            + rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)) * rng.range(0.0, 1.0);
        let bound = f64::from(frame.distance_of(position, frame.height_of(position).0));
        let nearest = sampled_distance(&tri, position);
        assert!(bound <= nearest * (1.0 + 1.0e-5), "case {case}: bound {bound} > nearest {nearest}");
        assert!(bound >= 0.99 * nearest - 1.0e-5, "case {case}: bound {bound} far below nearest {nearest}");
        checked += 1;
    }
    assert!(checked > 300, "{checked} triangles without a plane");
}

/// The distance from `position` to the nearest of 45 451 points of the triangle, in f64.
fn sampled_distance(tri: &TriangleInput, position: Vec3) -> f64 {
    let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
    let light_at = position.as_dvec3();
    let steps = 300;
    let mut nearest = f64::MAX;
    for i in 0..=steps {
        for j in 0..=(steps - i) {
            let (a, b) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
            nearest = nearest.min((p + (q - p) * a + (r - p) * b - light_at).length());
        }
    }
    nearest
}

/// [`Frame::distance_of`] bounds the distance from a point to the triangle from below (at
/// 45 451 sample points of it) and is within 1 % of it, for lights above the triangle (their
/// foot inside) and beside it.
#[test]
fn distance_of_a_light_bounds_the_nearest_point() {
    let mut rng = crate::test_rng::Rng(0xd157_a9ce_0f11_0002);
    let mut seen = [0; 2];
    for case in 0..600 {
        let size = rng.range(0.05, 1.0);
        let Some((tri, position)) = irradiance_case(&mut rng, size, false, case % 3) else {
            continue;
        };
        let frame = Frame::new(&tri, 0.0, true);
        let bound = f64::from(frame.distance_of(position, frame.height_of(position).0));
        let nearest = sampled_distance(&tri, position);
        let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
        let light_at = position.as_dvec3();
        assert!(bound <= nearest * (1.0 + 1.0e-5), "case {case}: bound {bound} > nearest {nearest}");
        assert!(bound >= 0.99 * nearest, "case {case}: bound {bound} far below nearest {nearest}");
        let n = (q - p).cross(r - p).normalize();
        let foot = light_at - n * (light_at - p).dot(n);
        let inside = [(p, q), (q, r), (r, p)].iter().all(|&(a, b)| (b - a).cross(foot - a).dot(n) > 0.0);
        seen[usize::from(inside)] += 1;
    }
    assert!(seen[0] > 50 && seen[1] > 50, "lights beside and above their triangle: {seen:?}");
}

/// [`origin_distance`] against the smallest norm sampled on 5 151 points of each of 2 000
/// random triangles (general, slivers, collinear and coincident corners): never above it
/// (10⁻⁶ for rounding), and within 1 % of it on most where it is not below 10⁻³.
#[test]
fn origin_distance_is_the_triangle_nearest_point() {
    let mut rng = crate::test_rng::Rng(0x0d15_7a9c_e0f0_0001);
    let mut close = 0;
    for case in 0..2000 {
        let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)) * rng.range(0.0, 2.0);
        let size = rng.range(0.01f32.ln(), 2.0f32.ln()).exp();
        let mut c = [0; 3].map(|_| centre + rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)) * size);
        match case % 5 {
            0 => c[2] = c[0].lerp(c[1], rng.range(-0.5, 1.5)),
            1 => c[2] = c[0].lerp(c[1], rng.range(0.0, 1.0)) + Vec3::splat(1.0e-4 * size),
            2 => c[1] = c[0],
            _ => {}
        }
        let distance = origin_distance(c);
        let [a, b, d] = c.map(|x| x.as_dvec3());
        let steps = 100;
        let mut sampled = f64::MAX;
        for i in 0..=steps {
            for j in 0..=(steps - i) {
                let (u, v) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
                sampled = sampled.min((a + (b - a) * u + (d - a) * v).length());
            }
        }
        let distance = f64::from(distance);
        assert!(distance <= sampled + 1.0e-6, "case {case}: {distance} above the sampled {sampled}: {c:?}");
        if distance >= 1.0e-3 {
            close += usize::from(distance >= 0.99 * sampled);
        }
    }
    assert!(close > 1500, "{close} triangles within 1 % of their sampled distance");
}

/// The range of the angle between `n̂` and `ĥ` (`LightSetup::psi_nh`, from the cones of
/// `n̂` and `ĥ`) against its minimum and maximum sampled at 496 points of each of 3 000
/// random triangles (normals spread by up to 1 rad, point lights 0.3–300 sizes away and
/// directional ones, eyes 0.3–30 away): never narrower than the samples, and it prints how
/// far below the smallest angle its lower end lies (`docs/estimator.md` §11: a circular
/// cone for `ĥ` is loose where the light or the eye is close, which a narrow lobe pays for).
#[test]
fn half_vector_angle_range_holds_the_sampled_angles() {
    let mut rng = crate::test_rng::Rng(0x0a11_0f0e_a1f0_0003);
    let mut ratios = Vec::new();
    for _ in 0..3000 {
        let centre = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0));
        let view_dir = rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).normalize_or_zero();
        let view_dist = rng.range(0.3f32.ln(), 30f32.ln()).exp();
        let eye = centre + view_dir * view_dist;
        let (t1, t2) = view_dir.any_orthonormal_pair();
        let size = view_dist * rng.range(0.002f32.ln(), 0.5f32.ln()).exp();
        let positions =
            [0; 3].map(|_| centre + (t1 * rng.range(-1.0, 1.0) + t2 * rng.range(-1.0, 1.0)) * size);
        let spread = rng.range(1.0e-4f32.ln(), 0.0).exp();
        let normals = [0; 3].map(|_| tilt(&mut rng, view_dir, 0.0, spread));
        let towards = tilt(&mut rng, view_dir, 0.0, 1.5);
        let light = if rng.below(2) == 0 {
            let distance = size * rng.range(0.3f32.ln(), 300f32.ln()).exp();
            Light::Point { position: centre + towards * distance, color: Vec3::ONE, intensity: 1.0 }
        } else {
            Light::Directional { direction: -towards, color: Vec3::ONE, intensity: 1.0 }
        };
        let tri = TriangleInput { positions, normals, eye };
        let material = MaterialKind::BlinnPhong { kd: Vec3::ZERO, ks: Vec3::ONE, shininess: 100.0 };
        let frame = Frame::new(&tri, 0.0, true);
        let Ok(Some((setup, _, _))) =
            plan_light(&frame, &material, ParameterRange::of(&material), &light, Discontinuity::Relaxed)
        else {
            continue;
        };
        let (mut low, mut high) = (f64::MAX, 0.0f64);
        let steps = 30;
        for i in 0..=steps {
            for j in 0..=(steps - i) {
                let (a, b) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
                let [p, q, r] = positions.map(|x| x.as_dvec3());
                let [np, nq, nr] = normals.map(|x| x.as_dvec3());
                let x = p + (q - p) * a + (r - p) * b;
                let n = (np + (nq - np) * a + (nr - np) * b).normalize();
                let l = match light {
                    Light::Point { position, .. } => (position.as_dvec3() - x).normalize(),
                    _ => towards.as_dvec3(),
                };
                let h = (l + (eye.as_dvec3() - x).normalize()).normalize();
                let angle = n.dot(h).clamp(-1.0, 1.0).acos();
                (low, high) = (low.min(angle), high.max(angle));
            }
        }
        let (p0, p1) = (f64::from(setup.psi_nh.0), f64::from(setup.psi_nh.1));
        assert!(
            p0 <= low + 1.0e-5 && p1 >= high - 1.0e-5,
            "{tri:?}, {light:?}: [{p0}, {p1}] vs [{low}, {high}]"
        );
        if low > 0.05 {
            ratios.push(p0 / low);
        }
    }
    let n = ratios.len();
    assert!(n > 1000, "{n} triangles off the highlight");
    eprintln!(
        "lower end of the n̂-ĥ angle over its sampled minimum, {n} triangles off the highlight: {}",
        percentiles(&mut ratios)
    );
}

/// The two facts [`mirror_lower_angle`] rests on, in f64 over random directions (some
/// nearly coplanar, some close together): the half vectors of a common `v̂` and two others
/// are at least half as far apart as those two, with equality for coplanar ones; and a
/// half-turn about `n̂` moves `v̂` at most twice `∠(n̂, n̂₀)` plus `∠(v̂, v̂₀)` from where the
/// half-turn about `n̂₀` moves `v̂₀`.
#[test]
fn half_vectors_of_a_common_direction_are_at_least_half_as_far_apart() {
    let mut rng = crate::test_rng::Rng(0x0a11_0f0e_a1f0_0004);
    let random_unit = |rng: &mut crate::test_rng::Rng| {
        rng.point(Vec3::splat(-1.0), Vec3::splat(1.0)).as_dvec3().normalize_or(DVec3::X)
    };
    let angle = |a: DVec3, b: DVec3| a.cross(b).length().atan2(a.dot(b));
    let half_turn = |axis: DVec3, v: DVec3| axis * (2.0 * axis.dot(v)) - v;
    let (mut tightest, mut checked) = (f64::MAX, 0);
    for k in 0..200_000 {
        let v = random_unit(&mut rng);
        let l = random_unit(&mut rng);
        let r = match k % 3 {
            0 => random_unit(&mut rng),
            1 => (l + random_unit(&mut rng) * 0.01).normalize(),
            // In the plane of v and l.
            _ => (v * rng.range(-1.0, 1.0) as f64 + l * rng.range(-1.0, 1.0) as f64).normalize_or(l),
        };
        if v.dot(l) < -0.999 || v.dot(r) < -0.999 || angle(l, r) < 1.0e-6 {
            continue;
        }
        let apart = angle((v + l).normalize(), (v + r).normalize());
        let ratio = apart / (0.5 * angle(l, r));
        assert!(ratio >= 1.0 - 1.0e-9, "{v} {l} {r}: {ratio}");
        tightest = tightest.min(ratio);
        checked += 1;

        let (n, n0, v0) = (random_unit(&mut rng), random_unit(&mut rng), random_unit(&mut rng));
        let moved = angle(half_turn(n, v), half_turn(n0, v0));
        assert!(moved <= 2.0 * angle(n, n0) + angle(v, v0) + 1.0e-9, "{n} {n0} {v} {v0}");
    }
    assert!(checked > 150_000 && tightest < 1.0 + 1.0e-6, "{checked} checked, tightest {tightest}");
}

#[test]
fn bilinear_range_is_exact() {
    // q(λ) = (Σλa)·(Σλb) sampled densely against the closed form.
    let mut rng = Rng(12345);
    for _ in 0..200 {
        let mut v = || Vec3::new(rng.f() as f32 - 0.5, rng.f() as f32 - 0.5, rng.f() as f32 - 0.5);
        let a = [v(), v(), v()];
        let b = [v(), v(), v()];
        let (lo, hi) = bilinear_range(a, b);
        let (mut slo, mut shi) = (f32::MAX, f32::MIN);
        for i in 0..=60 {
            for j in 0..=(60 - i) {
                let l = [i as f32 / 60.0, j as f32 / 60.0, (60 - i - j) as f32 / 60.0];
                let q =
                    (a[0] * l[0] + a[1] * l[1] + a[2] * l[2]).dot(b[0] * l[0] + b[1] * l[1] + b[2] * l[2]);
                slo = slo.min(q);
                shi = shi.max(q);
            }
        }
        assert!(lo <= slo + 1e-5 && hi >= shi - 1e-5, "{lo} {slo} {hi} {shi}");
        assert!(slo - lo < 2e-3 && hi - shi < 2e-3, "not tight: {lo} {slo} {hi} {shi}");
    }
}

#[test]
fn cones_contain_their_vectors() {
    let mut rng = Rng(777);
    for _ in 0..500 {
        let spread = rng.f() as f32;
        let base =
            Vec3::new(rng.f() as f32 - 0.5, rng.f() as f32 - 0.5, rng.f() as f32 - 0.5).normalize_or(Vec3::Z);
        let w: [Vec3; 3] = std::array::from_fn(|_| {
            (base + Vec3::new(rng.f() as f32 - 0.5, rng.f() as f32 - 0.5, rng.f() as f32 - 0.5) * spread)
                * (0.5 + rng.f() as f32)
        });
        let cone = cone_of(w);
        if cone.half >= PI {
            continue;
        }
        let r = min_length(w, &cone);
        for i in 0..=20 {
            for j in 0..=(20 - i) {
                let l = [i as f32 / 20.0, j as f32 / 20.0, (20 - i - j) as f32 / 20.0];
                let x = w[0] * l[0] + w[1] * l[1] + w[2] * l[2];
                assert!(angle(x, cone.axis) <= cone.half, "outside the cone");
                assert!(x.length() >= r * (1.0 - 1e-5), "shorter than the bound");
                let d = hull_distance(cone.axis, w.map(unit));
                assert!(d <= angle(x, cone.axis) + 1e-6);
            }
        }
    }
}
