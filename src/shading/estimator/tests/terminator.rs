//! Relaxed bounds: the terminator's band, the kink constant, and the view's kink.

use super::*;

/// [`TerminatorBand::at`] and [`TerminatorBand::guarded`] against `n̂·l̂` sampled on sub-triangles of
/// the pattern's shapes at levels 1 to 8 that the terminator crosses (both signs among the
/// samples): their largest `|n̂·l̂|` and their oscillation stay below the band at that level,
/// and below the per-`1/L` band from every level `above ≤ L`; on curved patches with lights
/// near their plane.
#[test]
fn terminator_band_holds_on_crossed_sub_triangles() {
    let mut rng = crate::test_rng::Rng(0x7e27_b0d0_0000_0003);
    let gd = Guard::default();
    let (mut crossed, mut tightest) = (0usize, 0.0f64);
    for case in 0..3000 {
        let size = rng.range(0.05, 1.0);
        let Some((tri, position, frame, setup)) = planned_irradiance_case(&mut rng, size, true, 1 + case % 2)
        else {
            continue;
        };
        if !setup.straddle {
            continue;
        }
        let [p, q, r] = tri.positions.map(|x| x.as_dvec3());
        let [np, nq, nr] = tri.normals.map(|x| x.as_dvec3());
        let light_at = position.as_dvec3();
        let cosine = |(u, v): (f64, f64)| {
            let x = p + (q - p) * u + (r - p) * v;
            let n = (np + (nq - np) * u + (nr - np) * v).normalize();
            n.dot((light_at - x).normalize())
        };
        for _ in 0..6 {
            let level = 1 + rng.below(8);
            let l = level as f32;
            let shape = SHAPES[rng.below(7) as usize];
            let scale = 1.0 / f64::from(level);
            let (u, v) = (
                (f64::from(shape[0].0) * scale, f64::from(shape[0].1) * scale),
                (f64::from(shape[1].0) * scale, f64::from(shape[1].1) * scale),
            );
            // A translate that keeps all three corners in the patch, if one is drawn.
            let origin = (0..20).find_map(|_| {
                let o = (f64::from(rng.f()), f64::from(rng.f()));
                let inside = |(a, b): (f64, f64)| a >= 0.0 && b >= 0.0 && a + b <= 1.0;
                [o, (o.0 + u.0, o.1 + u.1), (o.0 + v.0, o.1 + v.1)].iter().all(|&c| inside(c)).then_some(o)
            });
            let Some(o) = origin else {
                continue;
            };
            let (mut lo, mut hi) = (f64::MAX, f64::MIN);
            let steps = 12;
            for i in 0..=steps {
                for j in 0..=(steps - i) {
                    let (a, b) = (f64::from(i) / f64::from(steps), f64::from(j) / f64::from(steps));
                    let c = cosine((o.0 + u.0 * a + v.0 * b, o.1 + u.1 * a + v.1 * b));
                    lo = lo.min(c);
                    hi = hi.max(c);
                }
            }
            if !(lo < 0.0 && hi > 0.0) {
                continue;
            }
            crossed += 1;
            let worst = (hi - lo).max(hi).max(-lo);
            let band = TerminatorBand::new(&frame, &setup, frame.dn);
            let at = f64::from(band.at(l));
            let per_level = f64::from(band.guarded(0.0, &gd)) / f64::from(l);
            let above = 1.0 + rng.f() * (l - 1.0);
            let from_above = f64::from(band.guarded(above, &gd)) / f64::from(l);
            let what = format!("case {case}, level {level}: light {position:?}, {tri:?}");
            assert!(worst <= at * (1.0 + 1.0e-5), "{what}: {worst} > band at the level {at}");
            assert!(worst <= per_level * (1.0 + 1.0e-5), "{what}: {worst} > band per level {per_level}");
            assert!(
                worst <= from_above * (1.0 + 1.0e-5),
                "{what}: {worst} > band from {above}: {from_above}"
            );
            tightest = tightest.max(worst / at);
        }
    }
    eprintln!("terminator band: {crossed} crossed sub-triangles, largest oscillation / band {tightest:.3}");
    assert!(crossed > 1_000, "{crossed} crossed sub-triangles");
    assert!(tightest > 0.3, "the band is never approached: {tightest}");
}

/// `Lg − g` for `g = max(f, 0)` at local barycentrics `mu`, with `f` given at the corners
/// (`fc`) and at the point (`fx`).
fn kink_error(fc: [f64; 3], fx: f64, mu: [f64; 3]) -> f64 {
    let lg: f64 = (0..3).map(|k| mu[k] * fc[k].max(0.0)).sum();
    lg - fx.max(0.0)
}

#[test]
fn terminator_kink_constant_is_sharp() {
    // Linear f with corner values (1, −1, −1): E_f = 0, the corner oscillation is 2, and on
    // the zero line (the midpoints of the edges from the first corner) Lg − g = ½ exactly:
    // ¼·2, so no smaller constant bounds it.
    let fc = [1.0, -1.0, -1.0];
    let linear = |mu: [f64; 3]| mu[0] * fc[0] + mu[1] * fc[1] + mu[2] * fc[2];
    let bound = f64::from(TERMINATOR_KINK) * (1.0 - -1.0);
    let k = 64;
    let mut worst = f64::MIN;
    for i in 0..=k {
        for j in 0..=k - i {
            let mu = [i as f64 / k as f64, j as f64 / k as f64, (k - i - j) as f64 / k as f64];
            let e = kink_error(fc, linear(mu), mu);
            assert!(e >= 0.0 && e <= bound + 1e-12, "{mu:?}: {e}");
            worst = worst.max(e);
        }
    }
    assert_eq!(worst, 0.5);
    assert_eq!(bound, 0.5);
    assert_eq!(kink_error(fc, 0.0, [0.5, 0.5, 0.0]), 0.5);

    // Any smooth f: pointwise −max(f − Lf, 0) ≤ Lg − g ≤ max(Lf − f, 0) + ¼·osc of the
    // corner values (random quadratics on the reference triangle).
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut rnd = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    for _ in 0..2000 {
        let c: [f64; 6] = std::array::from_fn(|_| rnd());
        let curve = 3.0 * rnd().abs();
        let f = |mu: [f64; 3]| {
            let (x, y) = (mu[1], mu[2]);
            c[0] + c[1] * x + c[2] * y + curve * (c[3] * x * x + c[4] * x * y + c[5] * y * y)
        };
        let corners = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]].map(f);
        let osc = corners.iter().copied().fold(f64::MIN, f64::max)
            - corners.iter().copied().fold(f64::MAX, f64::min);
        for _ in 0..50 {
            let (a, b) = (rnd().abs(), rnd().abs());
            let (a, b) = if a + b > 1.0 { (1.0 - a, 1.0 - b) } else { (a, b) };
            let mu = [1.0 - a - b, a, b];
            let lf: f64 = (0..3).map(|k| mu[k] * corners[k]).sum();
            let e = kink_error(corners, f(mu), mu);
            let tol = 1e-12;
            assert!(e <= (lf - f(mu)).max(0.0) + f64::from(TERMINATOR_KINK) * osc + tol);
            assert!(e >= -(f(mu) - lf).max(0.0) - tol);
        }
    }
}

/// The view kink's split (`smith_v_kink_jet`): `V(max(u, 0)) = 1/k − max(ρ(u), 0)` with
/// `ρ` the tangent-continued `1/k − V`; the jet of `u` itself (slope 1, no curvature)
/// must bound `ρ`'s slope and curvature on both sides of the kink, and `1/k − ρ(u)` on
/// `|u| ≤ band`.
#[test]
fn view_kink_split_is_exact_and_its_jet_bounds_it() {
    for k in [5.0e-4f64, 0.01, 0.045, 0.2, 0.5] {
        let v = |c: f64| 1.0 / (c * (1.0 - k) + k);
        let rho = |u: f64| if u >= 0.0 { 1.0 / k - v(u) } else { (1.0 - k) / (k * k) * u };
        for band in [0.01f64, 0.1, 1.0] {
            let identity = Jet { m: band as f32, g: 1.0, h: NO_H, t: 0.0 };
            let gd = Guard::default();
            let jet = smith_v_kink_jet(&identity, k as f32, band as f32, &gd);
            let (m, g, t) = (f64::from(jet.m), f64::from(jet.g), f64::from(jet.t));
            let steps = 2000;
            // Differences with a step well inside V's scale k, at points clear of the
            // kink by two steps (one of them right next to it).
            let h = 1e-3 * k.min(band);
            let grid = (-steps..=steps).map(|i| band * i as f64 / steps as f64);
            let (mut slope, mut curve) = (0.0f64, 0.0f64);
            for u in grid.chain([2.0 * h, -2.0 * h]) {
                let split = 1.0 / k - rho(u).max(0.0);
                assert!((split - v(u.max(0.0))).abs() <= 1e-12 * v(0.0), "k {k}, u {u}");
                assert!((1.0 / k - rho(u)).abs() <= m * (1.0 + 1e-6), "k {k}, u {u}: value over {m}");
                if u.abs() >= 2.0 * h && u.abs() <= band - h {
                    let first = (rho(u + h) - rho(u - h)) / (2.0 * h);
                    let second = (rho(u + h) - 2.0 * rho(u) + rho(u - h)) / (h * h);
                    slope = slope.max(first.abs());
                    curve = curve.max(second.abs());
                }
            }
            assert!(slope <= g * (1.0 + 1e-5), "k {k}: slope {slope} > {g}");
            assert!(curve <= t * (1.0 + 1e-3), "k {k}: curvature {curve} > {t}");
            // Both are reached next to the kink (the bounds are ρ's at u = 0⁺).
            assert!(slope >= 0.99 * g && curve >= 0.99 * t, "k {k}: {slope}/{g}, {curve}/{t}");
        }
    }
}
