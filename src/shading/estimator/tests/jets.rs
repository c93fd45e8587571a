//! The jets of a cosine, a power, GGX's D, the half-vector cosine, Fresnel and the Smith
//! halves against finite differences along sampled unit fields.

use super::*;

/// The falloff's jet (`attenuation_jet`) against its exact value and derivatives, by
/// central differences in f64 at points of random triangles and along random in-plane
/// directions: lights far away, closer than the triangle's size and grazing (in the
/// triangle's plane, where `D²(1/d²)` reaches `6/d⁴`).
/// A unit vector field `normalize(m₀ + t·dm)` along `t ∈ [0, 1]` (an affine `m`, as the
/// estimator's normal and light fields are), with the bounds the estimator uses:
/// `|dû/dt| ≤ |dm|/min|m|` and `|û·dm|/|m| ≤ max|m·dm|/min|m|²` (`m·dm` is affine in `t`).
struct UnitField {
    m0: DVec3,
    dm: DVec3,
}

impl UnitField {
    fn random(rng: &mut crate::test_rng::Rng, speed: f64) -> UnitField {
        let mut v = || rng.point(Vec3::splat(-1.0), Vec3::ONE).as_dvec3();
        let (m0, dm) = (v().normalize_or(DVec3::Z), v().normalize_or(DVec3::X));
        let m0 = m0 * (0.2 + 1.8 * f64::from(rng.f()));
        let dm = dm * speed * m0.length() * f64::from(rng.f());
        UnitField { m0, dm }
    }

    fn at(&self, t: f64) -> DVec3 {
        (self.m0 + self.dm * t).normalize()
    }

    fn min_length(&self) -> f64 {
        let t = (-self.m0.dot(self.dm) / self.dm.length_squared().max(1e-300)).clamp(0.0, 1.0);
        (self.m0 + self.dm * t).length()
    }

    fn field(&self, term: Term) -> Field {
        let min = self.min_length();
        let along = self.m0.dot(self.dm).abs().max((self.m0 + self.dm).dot(self.dm).abs());
        let w = (self.dm.length() / min) as f32;
        Field { w, radial: ((along / (min * min)) as f32).min(w), x: 0.0, term }
    }
}

/// The range of `angle(t)` over `t ∈ [0, 1]`, sampled densely and widened by 10⁻³.
fn angle_range(angle: &dyn Fn(f64) -> f64) -> (f32, f32) {
    let samples = (0..=4000).map(|i| angle(f64::from(i) / 4000.0));
    let (lo, hi) = samples.fold((f64::INFINITY, 0.0f64), |(lo, hi), a| (lo.min(a), hi.max(a)));
    ((lo - 1e-3).max(0.0) as f32, (hi + 1e-3).min(std::f64::consts::PI) as f32)
}

/// Checks a jet against `f` at 60 points of `[0, 1]` (away from the ends by `h`): `|f| ≤ m`
/// (or `f ≥ m` with `m_is_min`), `|f'| ≤ g`, `|f''| ≤ t`, and returns the largest `|f''|/t`
/// (the differences' rounding allowed for: 10⁻³ relative, 10⁻⁶ absolute).
fn check_jet(jet: &Jet, f: &dyn Fn(f64) -> f64, h: f64, m_is_min: bool, what: &str) -> f64 {
    let mut tightest = 0.0f64;
    for i in 0..60 {
        let t = h + (1.0 - 2.0 * h) * f64::from(i) / 59.0;
        let [value, first, second] = differences(f, t, h);
        let slack = |bound: f32| f64::from(bound) * 1.001 + 1e-6;
        if m_is_min {
            assert!(value >= f64::from(jet.m) - 1e-6, "{what}, t {t}: value {value} < {}", jet.m);
        } else {
            assert!(value.abs() <= slack(jet.m), "{what}, t {t}: value {value} > {}", jet.m);
        }
        assert!(first.abs() <= slack(jet.g), "{what}, t {t}: first {first} > {}", jet.g);
        assert!(second.abs() <= slack(jet.t), "{what}, t {t}: second {second} > {}", jet.t);
        tightest = tightest.max(second.abs() / (f64::from(jet.t) + 1e-6));
    }
    tightest
}

/// Two random unit fields whose angle stays within `max_angle`, with their jets' inputs.
/// Every other pair turns in one plane in opposite senses, starting across its `m`: there
/// the angle between them changes at the full `w_a + w_b` (at `t = 0`), where the bounds
/// are reached.
fn field_pair(rng: &mut crate::test_rng::Rng, max_angle: f64) -> Option<(UnitField, UnitField, (f32, f32))> {
    let speed = [0.1, 1.0, 4.0][rng.below(3) as usize];
    let (a, b) = if rng.below(2) == 0 {
        (UnitField::random(rng, speed), UnitField::random(rng, speed))
    } else {
        let planar = |angle: f64, sense: f64, rng: &mut crate::test_rng::Rng| {
            let m0 = DVec3::new(angle.cos(), angle.sin(), 0.0) * (0.2 + 1.8 * f64::from(rng.f()));
            let dm = DVec3::Z.cross(m0) * sense * speed * f64::from(rng.f());
            UnitField { m0, dm }
        };
        let start = f64::from(rng.range(0.0, max_angle.min(3.0) as f32));
        (planar(start, 1.0, rng), planar(0.0, -1.0, rng))
    };
    let psi = angle_range(&|t| a.at(t).angle_between(b.at(t)));
    (f64::from(psi.1) <= max_angle).then_some((a, b, psi))
}

/// Runs `case` on 2 000 pairs of fields (seeded) whose angle stays within `max_angle`, and
/// returns the largest of each figure it reports (how close its bounds came).
fn over_field_pairs<const N: usize>(
    seed: u64,
    max_angle: f64,
    mut case: impl FnMut(&mut crate::test_rng::Rng, usize, &UnitField, &UnitField, (f32, f32)) -> [f64; N],
) -> [f64; N] {
    let mut rng = crate::test_rng::Rng(seed);
    let (mut checked, mut tightest) = (0, [0.0f64; N]);
    while checked < 2000 {
        let Some((a, b, psi)) = field_pair(&mut rng, max_angle) else { continue };
        let figures = case(&mut rng, checked, &a, &b, psi);
        tightest = std::array::from_fn(|k| tightest[k].max(figures[k]));
        checked += 1;
    }
    tightest
}

#[test]
fn cosine_jet_bounds_the_exact_derivatives() {
    let [tightest] = over_field_pairs(0xc051_e7e7, std::f64::consts::PI, |_, case, a, b, psi| {
        let jet = cosine(&a.field(Term::Normal), &b.field(Term::Light), psi, &Guard::default());
        let what = format!("case {case}: ψ {psi:?}");
        [check_jet(&jet, &|t| a.at(t).dot(b.at(t)), 1e-4, false, &what)]
    });
    eprintln!("cosine: largest |c''| reaches {tightest:.3} of the bound");
    assert!(tightest > 0.9, "the cosine bound is never approached: {tightest}");
}

/// The lobes' net coefficients are the largest values of their functions over the range
/// (dense sampling in f64 never exceeds them, and comes within 0.1 % of them), for
/// shininess 2–10⁴ (also as textured ranges) and roughness down to 0, over random ranges.
#[test]
fn lobe_net_coefficients_are_the_maxima_over_the_range() {
    let mut rng = crate::test_rng::Rng(0x6e7_c0ef_f1c1_e475);
    // A linear grid and two dense near the range's ends (GGX's peak for small α is at
    // s₂ ≈ α², the power's for large s at x ≈ 1 − 2/s).
    let sampled_max = |f: &dyn Fn(f64) -> f64, lo: f64, hi: f64| {
        let linear = (0..=20_000).map(|i| lo + (hi - lo) * f64::from(i) / 20_000.0);
        let near = (0..=20_000).map(|i| lo + (hi - lo) * (f64::from(i) / 20_000.0).powi(4));
        let far = (0..=20_000).map(|i| hi - (hi - lo) * (f64::from(i) / 20_000.0).powi(4));
        linear.chain(near).chain(far).map(f).fold(0.0f64, f64::max)
    };
    let mut reached = [0usize; 2];
    for case in 0..2_000 {
        let (a, b) = (rng.range(0.0, 1.5), rng.range(0.0, 1.5));
        let (h0, h1) = (a.min(b), a.max(b).min(FRAC_PI_2));
        if case % 2 == 0 {
            let s0 = rng.range(2.0f32.ln(), 10_000f32.ln()).exp();
            let s1 = if case % 4 == 0 { s0 } else { s0 * rng.range(1.0, 3.0) };
            let (c0, c1) = (est_cos(h0), est_cos(h1).max(0.0));
            let got = f64::from(power_net_coefficient(s0, s1, c0, c1));
            let (p, s1d) = (0.5 * (f64::from(s0) - 2.0), f64::from(s1));
            let f = |x: f64| s1d * x.powf(p) * ((s1d - 1.0) * (1.0 - x) - x).max(0.0);
            let want = sampled_max(&f, f64::from(c1 * c1), f64::from(c0 * c0));
            assert!(want <= got * 1.0001 + 1e-30, "power s {s0}..{s1}, ψ {h0}..{h1}: {want} > {got}");
            assert!(got <= want * 1.001 + 1e-30, "power s {s0}..{s1}, ψ {h0}..{h1}: {got} ≫ {want}");
            reached[0] += usize::from(want > 0.0);
        } else {
            let alpha = if case % 10 == 1 { 1.0e-3f32 } else { rng.range(0.001, 1.0) };
            let a2 = alpha * alpha;
            let (s0, s1) = (est_sin(h0).powi(2), est_sin(h1).powi(2));
            let got = f64::from(ggx_net_coefficient(a2, s0, s1));
            let (a2d, beta) = (f64::from(a2), 1.0 - f64::from(a2));
            // D''(t)·sin²ψ − D'(t)·t in s₂ = sin²ψ, from D = α²/(πu²).
            let f = |x: f64| {
                let (u, t2) = (a2d + beta * x, 1.0 - x);
                let d1 = 4.0 * a2d * beta / (std::f64::consts::PI * u * u * u);
                let d2 = d1 * (u + 6.0 * beta * t2) / u;
                (d2 * x - d1 * t2).max(0.0)
            };
            let want = sampled_max(&f, f64::from(s0), f64::from(s1));
            assert!(want <= got * 1.0001 + 1e-30, "GGX α {alpha}, ψ {h0}..{h1}: {want} > {got}");
            assert!(got <= want * 1.001 + 1e-30, "GGX α {alpha}, ψ {h0}..{h1}: {got} ≫ {want}");
            reached[1] += usize::from(want > 0.0);
        }
    }
    assert!(reached[0] > 300 && reached[1] > 300, "{reached:?}: too few ranges with a positive net part");
}

#[test]
fn power_jet_bounds_the_exact_derivatives() {
    let [tightest] = over_field_pairs(0x90e7_b10b, std::f64::consts::FRAC_PI_2, |rng, case, n, h, psi| {
        let gd = Guard::default();
        let (fn_, fh) = (n.field(Term::Normal), h.field(Term::Half));
        let c = cosine(&fn_, &fh, psi, &gd);
        let curv = curvature(&fn_, &fh, psi, &gd);
        // Shininess log-uniform in [1, 10⁴], a single value or a textured range.
        let s0 = 10f32.powf(4.0 * rng.f());
        let s1 = if rng.below(2) == 0 { s0 } else { (s0 * 10f32.powf(rng.f())).min(1.0e4) };
        let jet = power_jet(&c, &curv, (s0, s1), psi, fn_.w + fh.w, &gd);
        assert!(!gd.bad.get(), "saturated");
        let tightness = [s0, (s0 * s1).sqrt(), s1].map(|s| {
            let what = format!("case {case}: ψ {psi:?}, s {s} in [{s0}, {s1}]");
            let step = 1e-4 / f64::from(s).sqrt();
            let lobe = |t: f64| n.at(t).dot(h.at(t)).max(0.0).powf(f64::from(s));
            check_jet(&jet, &lobe, step, false, &what)
        });
        [tightness.into_iter().fold(0.0, f64::max)]
    });
    eprintln!("power: largest |T''| reaches {tightest:.3} of the bound");
    assert!(tightest > 0.9, "the power bound is never approached: {tightest}");
}

#[test]
fn ggx_d_jet_bounds_the_exact_derivatives() {
    let [tightest] = over_field_pairs(0xd15_7d15, std::f64::consts::FRAC_PI_2, |rng, case, n, h, psi| {
        let gd = Guard::default();
        let (fn_, fh) = (n.field(Term::Normal), h.field(Term::Half));
        let c = cosine(&fn_, &fh, psi, &gd);
        let curv = curvature(&fn_, &fh, psi, &gd);
        // Roughness 0 (α at its floor) up to 1.
        let roughness = if case % 10 == 0 { 0.0 } else { rng.range(0.05, 1.0) };
        let alpha = crate::shading::brdf::ggx_alpha(roughness);
        let jet = ggx_d_jet(&c, &curv, psi.0, psi.1, fn_.w + fh.w, alpha, &gd);
        assert!(!gd.bad.get(), "saturated");
        let a2 = f64::from(alpha).powi(2);
        let d = |t: f64| {
            let c = n.at(t).dot(h.at(t));
            a2 / (std::f64::consts::PI * (c * c * (a2 - 1.0) + 1.0).powi(2))
        };
        let what = format!("case {case}: ψ {psi:?}, α {alpha}");
        // The step follows D's width in t: about max(α, sin ψ) in angle, over the speed.
        let width = f64::from(alpha).max(f64::from(psi.0).sin()) / f64::from(fn_.w + fh.w).max(1.0);
        [check_jet(&jet, &d, 1e-3 * width.min(0.1), false, &what)]
    });
    eprintln!("GGX D: largest |D''| reaches {tightest:.3} of the bound");
    assert!(tightest > 0.9, "the D bound is never approached: {tightest}");
}

#[test]
fn half_cosine_and_fresnel_jets_bound_the_exact_derivatives() {
    let [tightest_vh, tightest_f] = over_field_pairs(0xf7e5_11e1, 3.0, |_, case, l, v, psi| {
        let gd = Guard::default();
        let m_min = (0..=4000)
            .map(|i| (l.at(f64::from(i) / 4000.0) + v.at(f64::from(i) / 4000.0)).length())
            .fold(f64::INFINITY, f64::min)
            * 0.99;
        let vh = half_cosine_jet(&l.field(Term::Light), &v.field(Term::View), psi.1, m_min as f32, &gd);
        let u = |t: f64| 0.5 * (l.at(t) + v.at(t)).length();
        let what = format!("case {case}: ∠(l, v) {psi:?}");
        let tight_vh = check_jet(&vh, &u, 1e-4, true, &what);
        // Fresnel's own rule, on the exact range and derivatives of u (a little widened),
        // so that the looser v·h jet does not hide a loose Fresnel bound; and on the v·h
        // jet as the estimator feeds it.
        let samples: Vec<[f64; 3]> =
            (0..=2000).map(|i| differences(&u, 1e-4 + 0.9998 * f64::from(i) / 2000.0, 1e-4)).collect();
        let sup = |k: usize| samples.iter().map(|d| d[k].abs()).fold(0.0, f64::max) as f32 * 1.002 + 1e-6;
        let u_min = samples.iter().map(|d| d[0]).fold(f64::INFINITY, f64::min) as f32 - 1e-6;
        let exact = Jet { m: u_min, g: sup(1), h: NO_H, t: sup(2) };
        let f0 = [0.02, 0.04, 0.5, 0.95][case % 4];
        let f = |t: f64| f64::from(f0) + (1.0 - f64::from(f0)) * (1.0 - u(t)).powi(5);
        check_jet(&fresnel_jet(f0, &vh, &gd), &f, 1e-4, false, &format!("{what}, f₀ {f0}, v·h jet"));
        let tight_f = check_jet(&fresnel_jet(f0, &exact, &gd), &f, 1e-4, false, &format!("{what}, f₀ {f0}"));
        [tight_vh, tight_f]
    });
    eprintln!("v·h: largest second derivative {tightest_vh:.3} of the bound; Fresnel {tightest_f:.3}");
    assert!(tightest_vh > 0.75 && tightest_f > 0.9, "never approached: {tightest_vh}, {tightest_f}");
}

#[test]
fn smith_jets_bound_the_exact_derivatives() {
    let [tightest_g, tightest_v] =
        over_field_pairs(0x5317_4a1f, std::f64::consts::FRAC_PI_2, |rng, case, n, l, psi| {
            let gd = Guard::default();
            let c = cosine(&n.field(Term::Normal), &l.field(Term::Light), psi, &gd);
            let roughness = if case % 10 == 0 { 0.0 } else { rng.range(0.05, 1.0) };
            let k = 0.5 * crate::shading::brdf::ggx_alpha(roughness);
            let (kk, cos) = (f64::from(k), |t: f64| n.at(t).dot(l.at(t)).max(0.0));
            let what = format!("case {case}: ψ {psi:?}, k {k}");
            let g_exact = |t: f64| cos(t) / (cos(t) * (1.0 - kk) + kk);
            let v_exact = |t: f64| 1.0 / (cos(t) * (1.0 - kk) + kk);
            [
                check_jet(&smith_g_jet(&c, psi, k, &gd), &g_exact, 1e-4, false, &what),
                check_jet(&smith_v_jet(&c, psi, k, &gd), &v_exact, 1e-4, false, &what),
            ]
        });
    eprintln!("Smith: largest second derivative G {tightest_g:.3}, V {tightest_v:.3} of the bound");
    assert!(tightest_g > 0.9 && tightest_v > 0.9, "never approached: {tightest_g}, {tightest_v}");
}
