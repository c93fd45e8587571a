//! Where an estimate exceeds the true error: the measured supremum, Eq. 1's form over Taylor children, and the decomposition of the excess.

use super::*;

/// How many times the measured supremum the sensitivity rows of [`where_the_excess_lies`]
/// take as a bound.
pub(crate) const LOOSENESS: [f64; 4] = [1.25, 1.5, 2.0, 3.0];

/// "p25 a, median b, p75 c, p90 d" of `v`.
pub(crate) fn quartiles(v: &mut [f64]) -> String {
    if v.is_empty() {
        return "none".into();
    }
    let (p25, p50, p75) = (percentile(v, 0.25), percentile(v, 0.5), percentile(v, 0.75));
    format!("p25 {p25:.2}, median {p50:.2}, p75 {p75:.2}, p90 {:.2}", percentile(v, 0.9))
}

/// Random triangles per BRDF of [`where_the_excess_lies`].
pub(crate) const DECOMPOSITION_TRIANGLES: usize = 3_000;

/// What [`measured_supremum`] measures of a case: equation (1)'s coefficient from the sampled
/// Hessians on the patch alone (`patch`, level 1) and over every shape (`all`, levels ≥ 2),
/// and the sampled range `osc` of the shaded colour.
pub(crate) struct MeasuredSupremum {
    pub(crate) patch: f64,
    pub(crate) all: f64,
    pub(crate) osc: f64,
    /// `(patch, all)` from a second-order Taylor model on the patch's 1, 4 and 16 children:
    /// the Hessian at each child's centroid plus its radius times the measured sup of the
    /// third derivative over it. The centre is exact and the remainder measured (not
    /// bounded): what an estimator exact to second order at a point could reach at best.
    pub(crate) taylor: [(f64, f64); 3],
}

impl MeasuredSupremum {
    /// The smallest `n` whose bound, the measured one times `looseness`, or else the range,
    /// is within ε: the level a bound `looseness` times the true supremum would choose.
    pub(crate) fn level(&self, case: &Case, looseness: f64) -> Option<u32> {
        self.level_of((looseness * self.patch, looseness * self.all), case)
    }

    /// The level that the Taylor model on `4^depth` children chooses.
    pub(crate) fn taylor_level(&self, case: &Case, depth: usize) -> Option<u32> {
        self.level_of(self.taylor[depth], case)
    }

    pub(crate) fn level_of(&self, (patch, all): (f64, f64), case: &Case) -> Option<u32> {
        (1..=case.n_max).find(|&n| {
            let l = f64::from(pattern_level(n, n));
            let bound = if n == 1 { patch } else { all / (l * l) };
            bound.min(self.osc) <= f64::from(case.epsilon)
        })
    }

    /// The real-valued level the measured supremum asks for at levels ≥ 2 (no range).
    pub(crate) fn real_level(&self, case: &Case) -> f64 {
        (self.all / f64::from(case.epsilon)).sqrt()
    }
}

/// What a bound by the supremum of the true second derivative would use, measured:
/// the Hessian `H(y)` of each channel by central differences (step 0.01 of the patch) on a
/// 24-per-edge grid of points `y`, then equation (1) with `sup_y |dᵀH(y)d|` for every corner
/// offset `d` of a 6-per-edge grid of points in each pattern shape ([`SHAPES`]; `E`, and `E₁`
/// for the patch alone), and the sampled range `osc f`. No jets: a perfect bound of the
/// supremum kind ([`MeasuredSupremum::level`]).
pub(crate) fn measured_supremum(case: &Case) -> MeasuredSupremum {
    use multirate::analysis::oracle::shade_at;
    let f = |s: f64, t: f64| shade_at(&case.tri, &case.material, &case.lights, [1.0 - s - t, s, t]);
    let h = 0.01;
    // Per channel `[∂ss, ∂tt, ∂st]` at `(s, t)`, and the value there.
    let hessian = |s: f64, t: f64| {
        let c = f(s, t);
        let along = |ds: f64, dt: f64| {
            let (p, m) = (f(s + ds, t + dt), f(s - ds, t - dt));
            [0, 1, 2].map(|k| (p[k] - 2.0 * c[k] + m[k]) / (h * h))
        };
        let (ss, tt, dd) = (along(h, 0.0), along(0.0, h), along(h, h));
        ([0, 1, 2].map(|k| [ss[k], tt[k], 0.5 * (dd[k] - ss[k] - tt[k])]), c)
    };
    let grid = 24;
    let mut points: Vec<GridHessian> = Vec::new();
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for i in 0..=grid {
        for j in 0..=(grid - i) {
            let (hk, c) = hessian(i as f64 / grid as f64, j as f64 / grid as f64);
            for k in 0..3 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
            points.push(((i, j), hk));
        }
    }
    let sup = |d: (f64, f64), k: usize| points.iter().map(|(_, hk)| form(&hk[k], d)).fold(0.0, f64::max);
    let (patch, all) = equation_one(sup);
    let taylor = [0, 1, 2].map(|depth| {
        let children = taylor_children(depth, &points, grid, &hessian);
        equation_one(|d: (f64, f64), k: usize| {
            let length2 = d.0 * d.0 + d.1 * d.1;
            children
                .iter()
                .map(|c| form(&c.centre[k], d) + c.radius * c.third[k] * length2)
                .fold(0.0, f64::max)
        })
    });
    let osc = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
    MeasuredSupremum { patch, all, osc, taylor }
}

/// `|dᵀHd|` for `H = [∂ss, ∂tt, ∂st]`.
pub(crate) fn form(hk: &[f64; 3], d: (f64, f64)) -> f64 {
    (hk[0] * d.0 * d.0 + hk[1] * d.1 * d.1 + 2.0 * hk[2] * d.0 * d.1).abs()
}

/// Equation (1)'s coefficient from `sup(d, channel) ≥ sup_y |D²f(y)[d, d]|` (`d` in the patch's
/// `(s, t)` coordinates): on the patch alone (level 1) and over every shape (levels ≥ 2).
pub(crate) fn equation_one(sup: impl Fn((f64, f64), usize) -> f64) -> (f64, f64) {
    let (mut all, mut patch) = (0.0f64, 0.0f64);
    for (index, shape) in SHAPES.iter().enumerate() {
        let widen = |(s, t): (f32, f32)| (f64::from(s), f64::from(t));
        let corners = [(0.0, 0.0), widen(shape[0]), widen(shape[1])];
        let q = 6;
        for a in 0..=q {
            for b in 0..=(q - a) {
                let mu = [a, b, q - a - b].map(|m| f64::from(m) / f64::from(q));
                let x = (
                    (0..3).map(|k| mu[k] * corners[k].0).sum::<f64>(),
                    (0..3).map(|k| mu[k] * corners[k].1).sum::<f64>(),
                );
                for k in 0..3 {
                    let e = 0.5
                        * (0..3)
                            .map(|c| mu[c] * sup((corners[c].0 - x.0, corners[c].1 - x.1), k))
                            .sum::<f64>();
                    all = all.max(e);
                    if index == 0 {
                        patch = patch.max(e);
                    }
                }
            }
        }
    }
    (patch, all)
}

/// A point `(i, j)` of the 24-per-edge grid and, per channel, `[∂ss, ∂tt, ∂st]` there.
pub(crate) type GridHessian = ((usize, usize), [[f64; 3]; 3]);

/// One child of the patch for [`MeasuredSupremum::taylor`]: the Hessian at its centroid, its
/// radius about it, and per channel the measured `sup |D³f[e, u, u]|` over it (unit `e`, `u`).
pub(crate) struct TaylorChild {
    pub(crate) centre: [[f64; 3]; 3],
    pub(crate) radius: f64,
    pub(crate) third: [f64; 3],
}

/// The `4^depth` midpoint children of the patch in `(s, t)`, with the third derivative measured
/// from the differences of the grid's Hessians between neighbours in (or on) each child.
pub(crate) fn taylor_children(
    depth: u32,
    points: &[GridHessian],
    grid: usize,
    hessian: &impl Fn(f64, f64) -> ([[f64; 3]; 3], [f64; 3]),
) -> Vec<TaylorChild> {
    let mut children = vec![[(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)]];
    for _ in 0..depth {
        children = children
            .iter()
            .flat_map(|&[a, b, c]: &[(f64, f64); 3]| {
                let mid = |p: (f64, f64), q: (f64, f64)| ((p.0 + q.0) / 2.0, (p.1 + q.1) / 2.0);
                let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [bc, ca, ab]]
            })
            .collect();
    }
    let at = |(i, j): (usize, usize)| (i as f64 / grid as f64, j as f64 / grid as f64);
    let index: std::collections::HashMap<(usize, usize), usize> =
        points.iter().enumerate().map(|(n, (ij, _))| (*ij, n)).collect();
    let directions: Vec<(f64, f64)> = (0..12)
        .map(|m| (std::f64::consts::PI * f64::from(m) / 12.0).sin_cos())
        .map(|(y, x)| (x, y))
        .collect();
    children
        .iter()
        .map(|&[a, b, c]| {
            let inside = |p: (f64, f64)| {
                let cross =
                    |o: (f64, f64), q: (f64, f64)| (q.0 - o.0) * (p.1 - o.1) - (q.1 - o.1) * (p.0 - o.0);
                let signs = [cross(a, b), cross(b, c), cross(c, a)];
                signs.iter().all(|&x| x >= -1e-9) || signs.iter().all(|&x| x <= 1e-9)
            };
            let centroid = ((a.0 + b.0 + c.0) / 3.0, (a.1 + b.1 + c.1) / 3.0);
            let radius = [a, b, c]
                .iter()
                .map(|p| ((p.0 - centroid.0).powi(2) + (p.1 - centroid.1).powi(2)).sqrt())
                .fold(0.0, f64::max);
            let mut third = [0.0f64; 3];
            for ((i, j), h1) in points {
                if !inside(at((*i, *j))) {
                    continue;
                }
                for (di, dj) in [(1, 0), (0, 1), (1, 1)] {
                    let Some(&n) = index.get(&(i + di, j + dj)) else { continue };
                    let (other, h2) = &points[n];
                    if !inside(at(*other)) {
                        continue;
                    }
                    let step = (((di * di + dj * dj) as f64).sqrt()) / grid as f64;
                    for k in 0..3 {
                        for &u in &directions {
                            let diff = [h1[k][0] - h2[k][0], h1[k][1] - h2[k][1], h1[k][2] - h2[k][2]];
                            third[k] = third[k].max(form(&diff, u) / step);
                        }
                    }
                }
            }
            TaylorChild { centre: hessian(centroid.0, centroid.1).0, radius, third }
        })
        .collect()
}

/// The midpoint subdivision of a patch: four children, the attributes affine as in the patch.
pub(crate) fn children(t: &TriangleInput) -> [TriangleInput; 4] {
    let [a, b, c] = t.positions;
    let [na, nb, nc] = t.normals;
    let (ab, bc, ca) = ((a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0);
    let (nab, nbc, nca) = ((na + nb) / 2.0, (nb + nc) / 2.0, (nc + na) / 2.0);
    let child = |positions, normals| TriangleInput { positions, normals, eye: t.eye };
    [
        child([a, ab, ca], [na, nab, nca]),
        child([ab, b, bc], [nab, nb, nbc]),
        child([ca, bc, c], [nca, nbc, nc]),
        child([bc, ca, ab], [nbc, nca, nab]),
    ]
}

/// The largest level the estimator asks for on `tris` with `case`'s material and lights
/// (infinite where one falls back).
pub(crate) fn worst_level(tris: &[TriangleInput], case: &Case, settings: &EstimatorSettings) -> f32 {
    tris.iter()
        .map(|t| {
            let c = estimate(t, &case.material, &case.lights, settings);
            if c.fallback {
                f32::INFINITY
            } else {
                c.level
            }
        })
        .fold(0.0, f32::max)
}

/// What [`where_the_excess_lies`] counts for one BRDF: shading evaluations, fallbacks counted
/// at `n_max`.
#[derive(Default)]
pub(crate) struct Excess {
    /// Every triangle the oracle tessellates: the oracle, the estimator, and the least with the
    /// fallbacks a discontinuity or singularity forces...
    pub(crate) oracle_all: u64,
    pub(crate) estimator_all: u64,
    pub(crate) forced: u64,
    /// ...the same for Relaxed, and Relaxed's excess in levels above `n_max`.
    pub(crate) relaxed_all: u64,
    pub(crate) relaxed_forced: u64,
    pub(crate) relaxed_level: u64,
    /// The smooth triangles: the oracle, the measured supremum, 16 children, 4 children, the
    /// estimator.
    pub(crate) smooth: [u64; 5],
    /// Relaxed, the estimator on 4, 16 and 64 children.
    pub(crate) relaxed_children: [u64; 3],
    /// Triangles where the measured supremum's level exceeds `ε`.
    pub(crate) sup_violations: usize,
    /// Bounds [`LOOSENESS`] times the measured supremum.
    pub(crate) loose: [u64; LOOSENESS.len()],
    /// Taylor models on 1, 4 and 16 children.
    pub(crate) taylor: [u64; 3],
    /// The estimator's level ratio squared over the measured supremum's.
    pub(crate) looseness: Vec<f64>,
    /// The Relaxed excess by the term that needs the highest level.
    pub(crate) deciding: std::collections::BTreeMap<&'static str, u64>,
    /// The Relaxed excess by the oracle's level (up to 1, 4, 8, n_max) and by whether the
    /// estimator tessellates or falls back.
    pub(crate) by_level: [[u64; 2]; 4],
}

impl Excess {
    /// Counts one random triangle.
    pub(crate) fn add(&mut self, case: &Case, patterns: &[Pattern]) {
        let settings = conservative(case.epsilon);
        let est = estimate(&case.tri, &case.material, &case.lights, &settings);
        let eps = f64::from(case.epsilon);
        let Some(m) = oracle_level(&case.tri, &case.material, &case.lights, eps, case.n_max, |n| {
            patterns[n as usize].clone()
        }) else {
            return;
        };
        let count = |n: Option<u32>| n.map_or(vertices_at_level(case.n_max), vertices_at_level);
        let chosen = (!est.fallback).then_some(est.n);
        self.oracle_all += vertices_at_level(m);
        self.estimator_all += count(chosen);
        let relaxed_settings = relaxed(case.epsilon);
        let relaxed = estimate(&case.tri, &case.material, &case.lights, &relaxed_settings);
        let relaxed_count = count((!relaxed.fallback).then_some(relaxed.n));
        self.relaxed_all += relaxed_count;
        // The children of every triangle above level 2, those it sends per pixel for their
        // level included (the forced fallbacks stay).
        let forced_here = relaxed.fallback && relaxed.reason != Reason::Level;
        let mut best = if relaxed.fallback { f32::INFINITY } else { relaxed.level };
        let mut tris = vec![case.tri];
        for (depth, out) in self.relaxed_children.iter_mut().enumerate() {
            if !forced_here && best > 2.0 {
                tris = tris.iter().flat_map(children).collect();
                best = best.min(worst_level(&tris, case, &relaxed_settings) * (2u32 << depth) as f32);
            }
            let level_max = pattern_level(case.n_max, case.n_max);
            *out +=
                count((!forced_here && best <= level_max).then(|| uniform_level(best, case.n_max).max(1)));
        }
        if relaxed.fallback && relaxed.reason == Reason::Level {
            self.relaxed_level += vertices_at_level(case.n_max) - vertices_at_level(m);
        }
        // The Relaxed excess by the term that needs the highest level (forced fallbacks
        // by their reason; "range" where the parts' ranges alone exceed eps).
        let excess = relaxed_count.saturating_sub(vertices_at_level(m));
        self.by_level[[1, 4, 8].iter().take_while(|&&top| m > top).count()][usize::from(relaxed.fallback)] +=
            excess;
        if excess > 0 {
            let name = match relaxed.reason {
                Reason::Discontinuity => "discontinuity",
                Reason::Singular => "singular",
                _ => relaxed.named_terms().fold(("none", 0.0f32), |a, b| if b.1 > a.1 { b } else { a }).0,
            };
            *self.deciding.entry(name).or_insert(0) += excess;
        }
        self.relaxed_forced += if relaxed.fallback && relaxed.reason != Reason::Level {
            vertices_at_level(case.n_max)
        } else {
            vertices_at_level(m)
        };
        if est.fallback && est.reason != Reason::Level {
            self.forced += vertices_at_level(case.n_max);
            return;
        }
        self.forced += vertices_at_level(m);
        let measured = measured_supremum(case);
        let sup_level = measured.level(case, 1.0);
        for (out, &k) in self.loose.iter_mut().zip(&LOOSENESS) {
            *out += count(measured.level(case, k));
        }
        for (depth, out) in self.taylor.iter_mut().enumerate() {
            *out += count(measured.taylor_level(case, depth));
        }
        // The estimator's second-order bound against the measured supremum, where both
        // ask for a level above 1 from the interpolation bound (not the range).
        let real = measured.real_level(case);
        if !est.fallback && est.level > 1.0 && real > 1.0 && sup_level.is_some_and(|n| n > 1) {
            self.looseness.push(f64::from(est.level * est.level) / (real * real));
        }
        if let Some(n) = sup_level {
            let error = true_error(&case.tri, &case.material, &case.lights, &patterns[n as usize]);
            self.sup_violations += usize::from(error.iter().any(|&e| e > eps));
        }
        let level_max = pattern_level(case.n_max, case.n_max);
        let mut split = [est.level; 2];
        let mut tris = vec![case.tri];
        for (depth, out) in split.iter_mut().enumerate() {
            if est.fallback || est.level <= 2.0 {
                break;
            }
            tris = tris.iter().flat_map(children).collect();
            *out = est.level.min(worst_level(&tris, case, &settings) * (2u32 << depth) as f32);
        }
        let split_level =
            |l: f32| (!est.fallback && l <= level_max).then(|| uniform_level(l, case.n_max).max(1));
        self.smooth[0] += vertices_at_level(m);
        self.smooth[1] += count(sup_level);
        self.smooth[2] += count(split_level(split[1]));
        self.smooth[3] += count(split_level(split[0]));
        self.smooth[4] += count(chosen);
    }

    /// The figures, as lines of `text`.
    pub(crate) fn report(&mut self, brdf: Brdf, text: &mut String) {
        let x = |a: u64, b: u64| a as f64 / b.max(1) as f64;
        let _ = writeln!(
            text,
            "{brdf:?}: all the oracle tessellates: estimator x{:.2}, least with the forced fallbacks x{:.2} (Relaxed: x{:.2}, x{:.2}, {:.0} % of its excess in levels above n_max); smooth: oracle {}, supremum of |D2f| x{:.2} ({sup_violations} over eps), 16 children x{:.2}, 4 children x{:.2}, estimator x{:.2}",
            x(self.estimator_all, self.oracle_all),
            x(self.forced, self.oracle_all),
            x(self.relaxed_all, self.oracle_all),
            x(self.relaxed_forced, self.oracle_all),
            100.0 * x(self.relaxed_level, self.relaxed_all.saturating_sub(self.oracle_all)),
            self.smooth[0],
            x(self.smooth[1], self.smooth[0]),
            x(self.smooth[2], self.smooth[0]),
            x(self.smooth[3], self.smooth[0]),
            x(self.smooth[4], self.smooth[0]),
            sup_violations = self.sup_violations,
        );
        let _ = writeln!(
            text,
            "   Relaxed, the estimator on the 4, 16 and 64 children of every triangle above level 2, fallbacks for the level included (prototype, not a bound): x{:.2}, x{:.2}, x{:.2}",
            x(self.relaxed_children[0], self.oracle_all),
            x(self.relaxed_children[1], self.oracle_all),
            x(self.relaxed_children[2], self.oracle_all),
        );
        let scaled: Vec<String> = LOOSENESS
            .iter()
            .zip(&self.loose)
            .map(|(k, &e)| format!("x{k}: x{:.2}", x(e, self.smooth[0])))
            .collect();
        let _ = writeln!(
            text,
            "   smooth: a bound k times the measured supremum, {}; a Taylor model on 1, 4, 16 children with a measured remainder: x{:.2}, x{:.2}, x{:.2}; the estimator's bound over the measured supremum (level ratio squared, {} triangles): {}",
            scaled.join(", "),
            x(self.taylor[0], self.smooth[0]),
            x(self.taylor[1], self.smooth[0]),
            x(self.taylor[2], self.smooth[0]),
            self.looseness.len(),
            quartiles(&mut self.looseness),
        );
        let mut shares: Vec<(&str, u64)> = std::mem::take(&mut self.deciding).into_iter().collect();
        shares.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        let total: u64 = shares.iter().map(|s| s.1).sum();
        let listed: Vec<String> =
            shares.iter().take(6).map(|(name, e)| format!("{name} {:.0} %", 100.0 * x(*e, total))).collect();
        let _ = writeln!(
            text,
            "   Relaxed excess by the term that needs the highest level: {}",
            listed.join(", ")
        );
        let by_level_total: u64 = self.by_level.iter().flatten().sum();
        let rows: Vec<String> = ["1", "2-4", "5-8", "9-n_max"]
            .iter()
            .zip(&self.by_level)
            .map(|(m, [kept, fell])| {
                format!(
                    "{m}: {:.0} % tessellated, {:.0} % per pixel",
                    100.0 * x(*kept, by_level_total),
                    100.0 * x(*fell, by_level_total)
                )
            })
            .collect();
        let _ = writeln!(text, "   Relaxed excess by the oracle's level: {}", rows.join("; "));
    }
}
