//! Running a distribution's cases against the oracle, and the report of what they gave.

use super::*;

#[derive(Default)]
pub(crate) struct Stats {
    pub(crate) triangles: usize,
    pub(crate) fallback_level: usize,
    pub(crate) fallback_discontinuity: usize,
    pub(crate) fallback_singular: usize,
    pub(crate) oracle_none: usize,
    pub(crate) violations: usize,
    pub(crate) rechecked: usize,
    pub(crate) closest: f64,
    pub(crate) worst_excess: f64,
    pub(crate) worst_case: String,
    pub(crate) ratios: Vec<f64>,
    pub(crate) ratios_fine: Vec<f64>,
    pub(crate) tightness: Vec<f64>,
    /// Tessellated triangles whose true error exceeds the estimator's `predicted_error`.
    pub(crate) under_predicted: usize,
    pub(crate) evals_estimator: u64,
    pub(crate) evals_oracle: u64,
    pub(crate) compared: usize,
    pub(crate) unneeded_fallbacks: usize,
    /// The estimator's fallbacks that the oracle tessellates, counted at `n_max` (the least a
    /// triangle shaded per pixel at that size costs), and the oracle's evaluations there.
    pub(crate) evals_fallback_estimator: u64,
    pub(crate) evals_fallback_oracle: u64,
    pub(crate) level_histogram: Vec<usize>,
    /// The same estimate without the product-rule cross terms (what the paper's error
    /// propagation, Eq. 31–33, keeps): triangles where that gives a lower level, and how
    /// many of those then exceed eps.
    pub(crate) no_cross_lower: usize,
    pub(crate) no_cross_violations: usize,
    pub(crate) no_cross_worst: f64,
    /// Relaxed: tessellated triangles the terminator crosses, those at `n ≥ 2`, and their
    /// largest true error / eps.
    pub(crate) terminator: usize,
    pub(crate) terminator_fine: usize,
    pub(crate) terminator_worst: f64,
}

pub(crate) fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}

pub(crate) fn percentile(v: &mut [f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[((v.len() - 1) as f64 * p).round() as usize]
}

/// Polygonal lights: wherever the estimator does not fall back, the true error at its level is
/// `≤ ε` (Conservative and Relaxed). The oracle's own level is not computed (too slow with
/// sampled shading); the figures are printed.
pub(crate) fn check_polygons(brdf: Brdf, seed: u64, count: usize) {
    let mut text = String::new();
    let mut violations = 0;
    for (name, settings_of) in
        [("Conservative", conservative as fn(f32) -> EstimatorSettings), ("Relaxed", relaxed)]
    {
        let start = Instant::now();
        let mut rng = SplitMix64(seed);
        let (mut tessellated, mut closest, mut levels) = (0usize, 0.0f64, [0usize; N_MAX as usize + 1]);
        let mut reasons = [0usize; 4];
        for index in 0..count {
            let case = random_polygon_case(&mut rng, brdf);
            let settings = settings_of(case.epsilon);
            let est = estimate(&case.tri, &case.material, &case.lights, &settings);
            assert!(est.n >= 1 && est.n <= N_MAX && est.level.is_finite());
            if est.fallback {
                reasons[match est.reason {
                    Reason::Level => 1,
                    Reason::Discontinuity => 2,
                    _ => 3,
                }] += 1;
                continue;
            }
            tessellated += 1;
            levels[est.n as usize] += 1;
            let eps = f64::from(case.epsilon);
            let pattern = hardware(est.n);
            let error = true_error(&case.tri, &case.material, &case.lights, &pattern);
            let worst = error.iter().copied().fold(0.0, f64::max);
            closest = closest.max(worst / eps);
            if worst > eps {
                violations += 1;
                let _ = writeln!(
                    text,
                    "VIOLATION #{index}: n = {}, true {worst:.4e} > ε {eps}, predicted {:.4e}, {:?}, {:?}, {:?}",
                    est.n, est.predicted_error, case.material, case.lights, case.tri
                );
            }
        }
        let _ = writeln!(
            text,
            "{brdf:?} polygons, {name}: {count} triangles in {:.1} s, {tessellated} tessellated (levels {:?}), \
             fallback level/discontinuity/singular {}/{}/{}, worst true/ε {closest:.3}",
            start.elapsed().as_secs_f64(),
            levels.iter().enumerate().filter(|(_, &c)| c > 0).collect::<Vec<_>>(),
            reasons[1],
            reasons[2],
            reasons[3]
        );
    }
    println!("{text}");
    assert_eq!(violations, 0, "{text}");
}

pub(crate) fn run(
    brdf: Brdf,
    seed: u64,
    count: usize,
    case_of: fn(&mut Rng, Brdf) -> Case,
    settings_of: impl Fn(f32) -> EstimatorSettings,
) -> Stats {
    let patterns: Vec<Pattern> =
        (0..=N_MAX_EXTENDED).map(|n| if n == 0 { Pattern::default() } else { hardware(n) }).collect();
    let pattern_of = |n: u32| patterns[n as usize].clone();
    let mut rng = SplitMix64(seed);
    let mut s = Stats::default();
    for index in 0..count {
        let case = case_of(&mut rng, brdf);
        let settings =
            EstimatorSettings { n_max: case.n_max, eye_radius: case.eye_radius, ..settings_of(case.epsilon) };
        let est = estimate(&case.tri, &case.material, &case.lights, &settings);
        // The truth from the eye it is measured from (the estimate's own, or one of its ball).
        let case = Case { tri: TriangleInput { eye: case.truth_eye, ..case.tri }, ..case };
        assert!(est.n >= 1 && est.n <= case.n_max);
        assert!(est.predicted_error.is_finite() && est.predicted_error >= 0.0);
        s.triangles += 1;
        let eps = f64::from(case.epsilon);
        let oracle = oracle_level(&case.tri, &case.material, &case.lights, eps, case.n_max, pattern_of);
        if oracle.is_none() {
            s.oracle_none += 1;
        }
        if est.fallback {
            match est.reason {
                Reason::Level => s.fallback_level += 1,
                Reason::Discontinuity => s.fallback_discontinuity += 1,
                _ => s.fallback_singular += 1,
            }
            if let Some(m) = oracle {
                s.unneeded_fallbacks += 1;
                s.evals_fallback_estimator += vertices_at_level(case.n_max);
                s.evals_fallback_oracle += vertices_at_level(m);
            }
            continue;
        }
        if s.level_histogram.len() <= est.n as usize {
            s.level_histogram.resize(est.n as usize + 1, 0);
        }
        s.level_histogram[est.n as usize] += 1;
        let pattern = &patterns[est.n as usize];
        let mut error = true_error(&case.tri, &case.material, &case.lights, pattern);
        if error.iter().any(|&e| e > 0.5 * eps) {
            // Close calls are re-measured 16 times denser (24 samples per sub-triangle edge).
            let fine =
                true_error_sampled(&case.tri, &case.material, &case.lights, pattern, 24, f64::INFINITY);
            error = std::array::from_fn(|c| error[c].max(fine[c]));
            s.rechecked += 1;
        }
        let worst = error.iter().copied().fold(0.0, f64::max);
        s.closest = s.closest.max(worst / eps);
        if est.term(Term::Terminator) > 0.0 {
            s.terminator += 1;
            s.terminator_fine += usize::from(est.n >= 2);
            s.terminator_worst = s.terminator_worst.max(worst / eps);
        }
        if worst > eps {
            s.violations += 1;
            let excess = worst / eps;
            if excess > s.worst_excess {
                s.worst_excess = excess;
                s.worst_case = format!(
                    "#{index}: n = {}, true {worst:.4e} > eps {eps}, predicted {:.4e}, material {:?}, lights {:?}, tri {:?}",
                    est.n, est.predicted_error, case.material, case.lights, case.tri
                );
            }
        }
        if worst > 1e-9 {
            s.tightness.push(f64::from(est.predicted_error) / worst);
        }
        // The prediction is the bound at `n`: the true error is never above it (1 % and 10⁻⁶ for
        // the f32 shading's rounding, which the bound on the exact function does not cover).
        if worst > f64::from(est.predicted_error) * 1.01 + 1.0e-6 {
            s.under_predicted += 1;
            s.violations += 1;
            if s.worst_case.is_empty() {
                s.worst_case = format!(
                "#{index}: n = {}, true {worst:.4e} above the predicted {:.4e}, material {:?}, lights {:?}, tri {:?}",
                est.n, est.predicted_error, case.material, case.lights, case.tri
            );
            }
        }
        // n² = Σ nₜ² over the second-order terms (Heuristic); drop the cross terms.
        if settings.split == Split::Heuristic
            && est.term(Term::Range) == 0.0
            && est.term(Term::Terminator) == 0.0
        {
            let sum: f32 = est
                .terms
                .iter()
                .enumerate()
                .filter(|(t, _)| *t != Term::Cross as usize)
                .map(|(_, v)| v * v)
                .sum();
            let n_nc = (sum.sqrt().ceil() as u32).max(1);
            if n_nc < est.n {
                s.no_cross_lower += 1;
                let e = true_error(&case.tri, &case.material, &case.lights, &patterns[n_nc as usize]);
                let w = e.iter().copied().fold(0.0, f64::max);
                if w > eps {
                    s.no_cross_violations += 1;
                    s.no_cross_worst = s.no_cross_worst.max(w / eps);
                }
            }
        }
        if let Some(m) = oracle {
            s.compared += 1;
            s.ratios.push(f64::from(est.n) / f64::from(m));
            if m >= 2 {
                s.ratios_fine.push(f64::from(est.n) / f64::from(m));
            }
            s.evals_estimator += vertices_at_level(est.n);
            s.evals_oracle += vertices_at_level(m);
        }
    }
    s
}

pub(crate) fn report(name: &str, mut s: Stats, seconds: f64) -> String {
    let fb = s.fallback_level + s.fallback_discontinuity + s.fallback_singular;
    let pct = |x: usize| 100.0 * x as f64 / s.triangles as f64;
    let mut out = String::new();
    let _ = writeln!(out, "== {name}: {} triangles, {seconds:.1} s", s.triangles);
    let _ = writeln!(
        out,
        "   violations (true error > eps at the estimator's n): {}; largest true error / eps: {:.3} ({} close calls re-measured at 24 samples/edge)",
        s.violations, s.closest, s.rechecked
    );
    if s.violations > 0 {
        let _ = writeln!(out, "   worst excess: true/eps = {:.4}  {}", s.worst_excess, s.worst_case);
    }
    let _ = writeln!(
        out,
        "   estimator fallback: {:.1} % (level > n_max {:.1} %, discontinuity {:.1} %, singular {:.1} %); oracle needs > n_max: {:.1} %; fallbacks the oracle could tessellate: {:.1} %",
        pct(fb),
        pct(s.fallback_level),
        pct(s.fallback_discontinuity),
        pct(s.fallback_singular),
        pct(s.oracle_none),
        pct(s.unneeded_fallbacks)
    );
    let med = median(&mut s.ratios);
    let p90 = percentile(&mut s.ratios, 0.9);
    let mean = s.ratios.iter().sum::<f64>() / s.ratios.len().max(1) as f64;
    let _ = writeln!(
        out,
        "   estimator n / oracle n over {} triangles: median {med:.2}, mean {mean:.2}, 90th percentile {p90:.2}",
        s.compared
    );
    let _ = writeln!(
        out,
        "   ... where the oracle needs n >= 2 ({} triangles): median {:.2}",
        s.ratios_fine.len(),
        median(&mut s.ratios_fine)
    );
    let _ = writeln!(
        out,
        "   predicted / true error: median {:.2}, 10th percentile {:.2}; true error above the prediction: {}",
        median(&mut s.tightness.clone()),
        percentile(&mut s.tightness, 0.1),
        s.under_predicted
    );
    let _ = writeln!(
        out,
        "   shading evaluations (ceil(3(n+1)^2/4) per triangle) on those: estimator {} vs oracle {} (x{:.2})",
        s.evals_estimator,
        s.evals_oracle,
        s.evals_estimator as f64 / s.evals_oracle.max(1) as f64
    );
    let (with_estimator, with_oracle) =
        (s.evals_estimator + s.evals_fallback_estimator, s.evals_oracle + s.evals_fallback_oracle);
    let _ = writeln!(
        out,
        "   ... with the fallbacks the oracle tessellates, counted at n_max: estimator {with_estimator} vs oracle {with_oracle} (x{:.2})",
        with_estimator as f64 / with_oracle.max(1) as f64
    );
    let levels = s.level_histogram.get(1..).unwrap_or_default();
    let _ = writeln!(out, "   estimator levels 1..={}: {levels:?}", levels.len());
    if s.terminator > 0 {
        let _ = writeln!(
            out,
            "   tessellated across the terminator: {} ({} at n >= 2), largest true error / eps there {:.3}",
            s.terminator, s.terminator_fine, s.terminator_worst
        );
    }
    if s.no_cross_lower > 0 {
        let _ = writeln!(
            out,
            "   without the cross terms (paper's error propagation): lower n on {} triangles, {} of them exceed eps (worst true/eps {:.2})",
            s.no_cross_lower, s.no_cross_violations, s.no_cross_worst
        );
    }
    out
}

pub(crate) fn conservative(epsilon: f32) -> EstimatorSettings {
    EstimatorSettings {
        epsilon,
        n_max: N_MAX,
        split: Split::Heuristic,
        discontinuity: Discontinuity::Conservative,
        min_estimated_area: 0.0,
        eye_radius: 0.0,
    }
}

pub(crate) fn relaxed(epsilon: f32) -> EstimatorSettings {
    EstimatorSettings { discontinuity: Discontinuity::Relaxed, ..conservative(epsilon) }
}

pub(crate) fn uniform(epsilon: f32) -> EstimatorSettings {
    EstimatorSettings { split: Split::Uniform, ..conservative(epsilon) }
}

/// Runs the three configurations on the same triangles and prints their figures; every
/// configuration must have zero violations (all three bounds are meant to be rigorous).
pub(crate) fn check(brdf: Brdf, seed: u64) {
    let mut text = String::new();
    let mut violations = 0;
    let configs: [Config; 3] = [
        ("Conservative, Heuristic", conservative),
        ("Relaxed, Heuristic", relaxed),
        ("Conservative, Uniform", uniform),
    ];
    for (name, settings_of) in configs {
        let start = Instant::now();
        let stats = run(brdf, seed, TRIANGLES, random_case, settings_of);
        violations += stats.violations;
        text += &report(&format!("{brdf:?}, {name}"), stats, start.elapsed().as_secs_f64());
    }
    println!("{text}");
    assert_eq!(violations, 0, "{text}");
}

pub(crate) fn relaxed_uniform(epsilon: f32) -> EstimatorSettings {
    EstimatorSettings { split: Split::Uniform, ..relaxed(epsilon) }
}

/// The Relaxed bound where it matters: every light at the terminator ([`terminator_case`]),
/// both splits. Zero violations, and most crossed triangles must tessellate, many at `n ≥ 2`
/// (so that the first-order term and the lobe's band are exercised, not only level 1).
pub(crate) fn check_terminator(brdf: Brdf, seed: u64) {
    let (mut text, mut violations, mut few) = (String::new(), 0, false);
    let configs: [Config; 2] = [("Relaxed, Heuristic", relaxed), ("Relaxed, Uniform", relaxed_uniform)];
    for (name, settings_of) in configs {
        let start = Instant::now();
        let stats = run(brdf, seed, TERMINATOR_TRIANGLES, terminator_case, settings_of);
        violations += stats.violations;
        few |= stats.terminator_fine < TERMINATOR_TRIANGLES / 50;
        text += &report(&format!("{brdf:?} at the terminator, {name}"), stats, start.elapsed().as_secs_f64());
    }
    println!("{text}");
    assert_eq!(violations, 0, "{text}");
    assert!(!few, "too few crossed triangles tessellated at n >= 2: {text}");
}

/// A named estimator configuration.
pub(crate) type Config = (&'static str, fn(f32) -> EstimatorSettings);

/// [`run`] on `count` cases of `case_of` for each BRDF (with its seed) and configuration: the
/// report of each, the violations summed, and the largest true error over ε.
pub(crate) fn run_all(
    brdfs: &[(Brdf, u64)],
    configs: &[Config],
    count: usize,
    case_of: fn(&mut Rng, Brdf) -> Case,
    what: &str,
) -> (String, usize, f64) {
    let (mut text, mut violations, mut closest) = (String::new(), 0, 0.0f64);
    for &(brdf, seed) in brdfs {
        for &(name, settings_of) in configs {
            let start = Instant::now();
            let stats = run(brdf, seed, count, case_of, settings_of);
            violations += stats.violations;
            closest = closest.max(stats.closest);
            text += &report(&format!("{brdf:?}, {what}, {name}"), stats, start.elapsed().as_secs_f64());
        }
    }
    (text, violations, closest)
}

/// The property test for textured shininess (Blinn-Phong) and roughness (GGX): the parameter
/// varies over the triangle within `[lo, hi]`, the estimator is given that range, and the
/// oracle shades every sub-vertex and every point in between with the parameter there.
pub(crate) fn check_textured(brdf: Brdf, seed: u64) {
    let patterns: Vec<Pattern> =
        (0..=N_MAX).map(|n| if n == 0 { Pattern::default() } else { hardware(n) }).collect();
    let mut rng = SplitMix64(seed);
    let (mut violations, mut tessellated, mut worst) = (0, 0, 0.0f64);
    let mut worst_case = String::new();
    let start = Instant::now();
    for index in 0..TEXTURED_TRIANGLES {
        let case = random_case(&mut rng, brdf);
        let (lo, hi) = match case.material {
            MaterialKind::BlinnPhong { shininess, .. } => {
                let hi = (shininess * rng.log(1.0, 8.0)).min(1.0e4);
                (shininess, if rng.chance(0.2) { shininess * 1.01 } else { hi })
            }
            MaterialKind::Ggx { roughness, .. } => {
                let hi = (roughness + rng.log(0.001, 0.5)).min(1.0);
                (roughness, hi)
            }
            MaterialKind::Lambert { .. } => unreachable!("textured parameters are specular"),
        };
        let field = parameter_field(&mut rng, lo, hi);
        let material = case.material;
        let material_at = |b: [f64; 3]| with_parameter(&material, field(b));
        let settings = conservative(case.epsilon);
        let range = ParameterRange { lo, hi };
        let est = estimate_textured(&case.tri, &case.material, range, &case.lights, &settings);
        assert!(est.level.is_finite() && est.level >= 1.0);
        if est.fallback {
            continue;
        }
        tessellated += 1;
        let eps = f64::from(case.epsilon);
        let pattern = &patterns[est.n as usize];
        let mut error = true_error_textured(&case.tri, &material_at, &case.lights, pattern, 6, f64::INFINITY);
        if error.iter().any(|&e| e > 0.5 * eps) {
            let fine = true_error_textured(&case.tri, &material_at, &case.lights, pattern, 24, f64::INFINITY);
            error = std::array::from_fn(|c| error[c].max(fine[c]));
        }
        let e = error.iter().copied().fold(0.0, f64::max) / eps;
        if e > worst {
            worst = e;
            worst_case =
                format!("#{index}: n {}, true/eps {e:.4}, range [{lo}, {hi}], {:?}", est.n, case.material);
        }
        if e > 1.0 {
            violations += 1;
        }
    }
    let text = format!(
        "== {brdf:?}, textured: {TEXTURED_TRIANGLES} triangles, {:.1} s; tessellated {tessellated}, violations {violations}, largest true error / eps {worst:.3} ({worst_case})",
        start.elapsed().as_secs_f64()
    );
    println!("{text}");
    assert!(tessellated > TEXTURED_TRIANGLES / 10, "the textured bound should not always fall back: {text}");
    assert_eq!(violations, 0, "{text}");
}
