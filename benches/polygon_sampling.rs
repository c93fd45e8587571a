//! Cost per sample of the polygonal-light sampling techniques of `multirate::shading::polygon` (the
//! CPU Rust twin, not the GLSL shaders), next to Table A.2 of Peters, "Supplemental Document on BRDF
//! Importance Sampling for Polygonal Lights" (ACM TOG 40(4), 2021).
//!
//! Inputs: random convex planar polygons with 6 and 7 vertices around a shading point at the origin
//! of the local frame (normal +z): points on a randomly oriented ellipse (so always convex and
//! planar) with random size, tilt and offset, some entirely above the horizon, some crossing it.
//! They are kept only if both samplers of the clipped polygon are non-empty and sorted by the case
//! of projected-solid-angle sampling ([`ProjectedSolidAngleSampler::is_central`]: the zenith lies
//! in the clipped polygon) into a central and a decentral set of [`POLYGONS_PER_SET`] each.
//!
//! Techniques (each timed on both sets):
//! - *baseline*: load (copy) the polygon and draw two random numbers per sample, nothing else;
//! - *clip*: the baseline plus [`clip_to_horizon`];
//! - *solid angle, unclipped*: [`prepare_solid_angle`] + [`sample_solid_angle`] on the raw polygon
//!   (the paper's "Solid angle, ours");
//! - *solid angle, clipped*: the same after [`clip_to_horizon`] (the paper's "Solid angle, clipped,
//!   ours"; the reference of all ratios);
//! - *projected solid angle*: [`clip_to_horizon`] + [`prepare_projected_solid_angle`] +
//!   [`sample_projected_solid_angle`] (Algorithms 1–4; "Proj., central/decentral, ours");
//! - *closed form*: [`clip_to_horizon`] + [`projected_solid_angle`] only, the accurate closed form
//!   that [`prepare_projected_solid_angle`] evaluates to normalise the density (the paper uses the
//!   sum of its sector areas instead), to show its share of the projected technique's setup.
//!
//! Modes, both with 128 samples per polygon:
//! - *128 lights*: every (polygon, sample) pair prepares its own sampler and draws one sample; the
//!   loop runs over all polygons once per sample index, like a pixel that takes each of its 128
//!   samples from a different light;
//! - *128 samples*: the sampler is prepared once per polygon and then draws 128 samples.
//!
//! Every timing is the median over [`REPETITIONS`] runs (after one warm-up run), interleaved so that
//! slow drifts of the machine affect all techniques alike. As in the paper, the baseline is
//! subtracted from every technique before ratios are formed. Output: markdown tables on stdout.
//!
//! Run: `cargo bench --bench polygon_sampling`

use std::f32::consts::TAU;
use std::hint::black_box;
use std::time::Instant;

use glam::Vec3;
use multirate::shading::polygon::{
    clip_to_horizon, prepare_projected_solid_angle, prepare_solid_angle, projected_solid_angle,
    sample_projected_solid_angle, sample_solid_angle, Polygon, ProjectedSolidAngleSampler,
};

/// Polygons per set (central or decentral, for each vertex count).
const POLYGONS_PER_SET: usize = 512;
/// Samples per polygon in both modes.
const SAMPLES_PER_POLYGON: usize = 128;
/// Timed repetitions of every measurement (a warm-up run comes on top).
const REPETITIONS: usize = 15;
/// The vertex counts of Table A.2.
const VERTEX_COUNTS: [usize; 2] = [6, 7];

/// SplitMix64: a tiny deterministic generator.
struct SplitMix(u64);

impl SplitMix {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Two uniform numbers in [0, 1) with 24 bits each, from one draw.
    fn u2(&mut self) -> [f32; 2] {
        let bits = self.next_u64();
        let scale = 1.0 / (1u32 << 24) as f32;
        [(bits >> 40) as f32 * scale, ((bits >> 8) & 0xff_ffff) as f32 * scale]
    }

    /// Uniform in [lo, hi).
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.u2()[0]
    }
}

/// A random convex planar polygon with `count` vertices: points in angular order on an ellipse
/// whose centre lies 1 to 3 units from the shading point in a direction with z in [−0.3, 1), with
/// semi-axes 0.2 to 1.2 times that distance, and whose normal is the direction back to the shading
/// point plus a random offset in [−0.7, 0.7)³.
fn random_polygon(rng: &mut SplitMix, count: usize) -> Polygon {
    let azimuth = rng.range(0.0, TAU);
    let height = rng.range(-0.3, 1.0);
    let ground = (1.0 - height * height).sqrt();
    let direction = Vec3::new(ground * azimuth.cos(), ground * azimuth.sin(), height);
    let distance = rng.range(1.0, 3.0);
    let center = direction * distance;
    let tilt = Vec3::new(rng.range(-0.7, 0.7), rng.range(-0.7, 0.7), rng.range(-0.7, 0.7));
    let normal = (tilt - direction).normalize();
    let helper = if normal.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
    let tangent = normal.cross(helper).normalize();
    let bitangent = normal.cross(tangent);
    let major = distance * rng.range(0.2, 1.2);
    let minor = major * rng.range(0.5, 1.0);
    let phase = rng.range(0.0, TAU);
    let mut vertices = [Vec3::ZERO; 8];
    for (k, vertex) in vertices.iter_mut().take(count).enumerate() {
        let angle = phase + TAU * (k as f32 + rng.range(-0.3, 0.3)) / count as f32;
        *vertex = center + major * angle.cos() * tangent + minor * angle.sin() * bitangent;
    }
    Polygon::new(&vertices[..count])
}

/// The test polygons of one vertex count, split by the case of projected-solid-angle sampling.
struct PolygonSets {
    central: Vec<Polygon>,
    decentral: Vec<Polygon>,
}

/// Draws polygons until both sets are full; polygons that either sampler cannot sample (e.g.
/// entirely below the horizon) are skipped.
fn polygon_sets(rng: &mut SplitMix, count: usize) -> PolygonSets {
    let mut sets = PolygonSets { central: Vec::new(), decentral: Vec::new() };
    while sets.central.len() < POLYGONS_PER_SET || sets.decentral.len() < POLYGONS_PER_SET {
        let polygon = random_polygon(rng, count);
        let clipped = clip_to_horizon(&polygon);
        let projected = prepare_projected_solid_angle(&clipped);
        if projected.is_empty()
            || prepare_solid_angle(&clipped).is_empty()
            || prepare_solid_angle(&polygon).is_empty()
        {
            continue;
        }
        let set = if projected.is_central() { &mut sets.central } else { &mut sets.decentral };
        if set.len() < POLYGONS_PER_SET {
            set.push(polygon);
        }
    }
    sets
}

/// Fraction of `polygons` that cross the horizon, and their mean vertex count after clipping.
fn set_statistics(polygons: &[Polygon]) -> (f64, f64) {
    let crossing = polygons.iter().filter(|p| p.as_slice().iter().any(|v| v.z < 0.0)).count();
    let clipped_vertices: usize = polygons.iter().map(|p| clip_to_horizon(p).count).sum();
    (crossing as f64 / polygons.len() as f64, clipped_vertices as f64 / polygons.len() as f64)
}

/// The two ways of spending [`SAMPLES_PER_POLYGON`] samples per polygon.
#[derive(Clone, Copy, PartialEq)]
enum Mode {
    /// Prepare the sampler for every single sample.
    Lights,
    /// Prepare once per polygon, then draw all samples.
    Samples,
}

/// Times one pass of `mode` over `polygons`: `prepare` builds the per-polygon state, `sample`
/// turns it and two random numbers into a number that is summed (so nothing is optimised away).
/// Returns nanoseconds per sample.
fn time_pass<S>(
    mode: Mode,
    polygons: &[Polygon],
    prepare: impl Fn(&Polygon) -> S,
    sample: impl Fn(&S, [f32; 2]) -> f32,
) -> f64 {
    let mut rng = SplitMix(0x5eed);
    let mut sum = 0.0f32;
    let start = Instant::now();
    match mode {
        Mode::Lights => {
            for _ in 0..SAMPLES_PER_POLYGON {
                for polygon in polygons {
                    let polygon = black_box(*polygon);
                    sum += sample(&prepare(&polygon), rng.u2());
                }
            }
        }
        Mode::Samples => {
            for polygon in polygons {
                let polygon = black_box(*polygon);
                let state = prepare(&polygon);
                for _ in 0..SAMPLES_PER_POLYGON {
                    sum += sample(&state, rng.u2());
                }
            }
        }
    }
    let elapsed = start.elapsed();
    black_box(sum);
    elapsed.as_nanos() as f64 / (polygons.len() * SAMPLES_PER_POLYGON) as f64
}

/// The timed techniques, in table order.
#[derive(Clone, Copy, PartialEq)]
enum Technique {
    Baseline,
    Clip,
    SolidAngleUnclipped,
    SolidAngleClipped,
    Projected,
    ClosedForm,
}

const TECHNIQUES: [Technique; 6] = [
    Technique::Baseline,
    Technique::Clip,
    Technique::SolidAngleUnclipped,
    Technique::SolidAngleClipped,
    Technique::Projected,
    Technique::ClosedForm,
];

impl Technique {
    fn label(self) -> &'static str {
        match self {
            Technique::Baseline => "baseline (polygon copy + random numbers)",
            Technique::Clip => "clip to horizon only",
            Technique::SolidAngleUnclipped => "solid angle, unclipped",
            Technique::SolidAngleClipped => "solid angle, clipped",
            Technique::Projected => "projected solid angle",
            Technique::ClosedForm => "clip + closed-form projected solid angle",
        }
    }

    /// Nanoseconds per sample of one pass.
    fn time(self, mode: Mode, polygons: &[Polygon]) -> f64 {
        let direction_sum =
            |(direction, density): (Vec3, f32)| direction.x + direction.y + direction.z + density;
        match self {
            Technique::Baseline => time_pass(mode, polygons, |p| p.vertices[0].z, |z, u| z + u[0] + u[1]),
            Technique::Clip => {
                time_pass(mode, polygons, clip_to_horizon, |c, u| c.count as f32 + u[0] + u[1])
            }
            Technique::SolidAngleUnclipped => {
                time_pass(mode, polygons, prepare_solid_angle, |s, u| direction_sum(sample_solid_angle(s, u)))
            }
            Technique::SolidAngleClipped => time_pass(
                mode,
                polygons,
                |p| prepare_solid_angle(&clip_to_horizon(p)),
                |s, u| direction_sum(sample_solid_angle(s, u)),
            ),
            Technique::Projected => time_pass(
                mode,
                polygons,
                |p| prepare_projected_solid_angle(&clip_to_horizon(p)),
                |s: &ProjectedSolidAngleSampler, u| direction_sum(sample_projected_solid_angle(s, u)),
            ),
            Technique::ClosedForm => time_pass(
                mode,
                polygons,
                |p| projected_solid_angle(&clip_to_horizon(p)),
                |omega, u| omega + u[0] + u[1],
            ),
        }
    }
}

/// Which polygon set a measurement runs on.
#[derive(Clone, Copy, PartialEq)]
enum Case {
    Central,
    Decentral,
}

/// One measurement and its per-repetition results.
struct Measurement {
    count: usize,
    case: Case,
    mode: Mode,
    technique: Technique,
    runs: Vec<f64>,
}

impl Measurement {
    fn median(&self) -> f64 {
        let mut sorted = self.runs.clone();
        sorted.sort_by(f64::total_cmp);
        sorted[sorted.len() / 2]
    }
}

/// Table A.2 (milliseconds per frame, baseline already subtracted) for the rows this bench
/// reproduces: `[mode][vertex count 6, 7]`.
struct PaperRows {
    solid_angle: [[f64; 2]; 2],
    solid_angle_clipped: [[f64; 2]; 2],
    projected_central: [[f64; 2]; 2],
    projected_decentral: [[f64; 2]; 2],
}

const PAPER: PaperRows = PaperRows {
    solid_angle: [[9.45, 11.0], [2.11, 2.37]],
    solid_angle_clipped: [[12.6, 15.5], [2.75, 3.53]],
    projected_central: [[17.4, 22.6], [3.24, 3.47]],
    projected_decentral: [[45.6, 59.4], [12.4, 12.9]],
};

/// The rows of the summary tables.
#[derive(Clone, Copy)]
enum Row {
    Baseline,
    Clip,
    SolidAngle,
    SolidAngleClipped,
    ProjectedCentral,
    ProjectedDecentral,
    ClosedForm,
}

const ROWS: [Row; 7] = [
    Row::Baseline,
    Row::Clip,
    Row::SolidAngle,
    Row::SolidAngleClipped,
    Row::ProjectedCentral,
    Row::ProjectedDecentral,
    Row::ClosedForm,
];

impl Row {
    fn label(self) -> &'static str {
        match self {
            Row::Baseline => "Baseline: polygon copy + 2 random numbers (not subtracted)",
            Row::Clip => "Clip to horizon only",
            Row::SolidAngle => "Solid angle, unclipped",
            Row::SolidAngleClipped => "Solid angle, clipped (reference)",
            Row::ProjectedCentral => "Proj., central",
            Row::ProjectedDecentral => "Proj., decentral",
            Row::ClosedForm => "Clip + closed-form Ω⊥ only (part of Proj.)",
        }
    }

    /// The paper's ratio to "Solid angle, clipped, ours"; for the clip row the paper's difference
    /// "Solid angle, clipped" − "Solid angle" stands in for the cost of clipping.
    fn paper_ratio(self, mode: usize, count: usize) -> Option<f64> {
        let reference = PAPER.solid_angle_clipped[mode][count];
        match self {
            Row::Baseline | Row::ClosedForm => None,
            Row::Clip => Some((reference - PAPER.solid_angle[mode][count]) / reference),
            Row::SolidAngle => Some(PAPER.solid_angle[mode][count] / reference),
            Row::SolidAngleClipped => Some(1.0),
            Row::ProjectedCentral => Some(PAPER.projected_central[mode][count] / reference),
            Row::ProjectedDecentral => Some(PAPER.projected_decentral[mode][count] / reference),
        }
    }
}

/// Median results, looked up by measurement.
struct Results<'a>(&'a [Measurement]);

impl Results<'_> {
    fn median(&self, count: usize, case: Case, mode: Mode, technique: Technique) -> f64 {
        self.0
            .iter()
            .find(|m| m.count == count && m.case == case && m.mode == mode && m.technique == technique)
            .map(Measurement::median)
            .expect("every combination is measured")
    }

    /// Median minus the baseline on the same set, or the plain baseline.
    fn net(&self, count: usize, case: Case, mode: Mode, technique: Technique) -> f64 {
        let raw = self.median(count, case, mode, technique);
        if technique == Technique::Baseline {
            raw
        } else {
            raw - self.median(count, case, mode, Technique::Baseline)
        }
    }

    /// A technique averaged over both sets (they are equally large: the cost over their union).
    fn net_both(&self, count: usize, mode: Mode, technique: Technique) -> f64 {
        0.5 * (self.net(count, Case::Central, mode, technique)
            + self.net(count, Case::Decentral, mode, technique))
    }

    /// Net nanoseconds per sample of a summary row.
    fn row(&self, row: Row, count: usize, mode: Mode) -> f64 {
        match row {
            Row::Baseline => self.net_both(count, mode, Technique::Baseline),
            Row::Clip => self.net_both(count, mode, Technique::Clip),
            Row::SolidAngle => self.net_both(count, mode, Technique::SolidAngleUnclipped),
            Row::SolidAngleClipped => self.net_both(count, mode, Technique::SolidAngleClipped),
            Row::ProjectedCentral => self.net(count, Case::Central, mode, Technique::Projected),
            Row::ProjectedDecentral => self.net(count, Case::Decentral, mode, Technique::Projected),
            Row::ClosedForm => self.net_both(count, mode, Technique::ClosedForm),
        }
    }
}

fn mode_title(mode: Mode) -> &'static str {
    match mode {
        Mode::Lights => "128 lights (prepare + 1 sample per polygon and sample)",
        Mode::Samples => "128 samples (prepare once, then 128 samples per polygon)",
    }
}

fn case_label(case: Case) -> &'static str {
    match case {
        Case::Central => "central",
        Case::Decentral => "decentral",
    }
}

fn main() {
    let mut rng = SplitMix(2021);
    let sets: Vec<(usize, PolygonSets)> =
        VERTEX_COUNTS.iter().map(|&count| (count, polygon_sets(&mut rng, count))).collect();

    let mut measurements = Vec::new();
    for &(count, _) in &sets {
        for case in [Case::Central, Case::Decentral] {
            for mode in [Mode::Lights, Mode::Samples] {
                for technique in TECHNIQUES {
                    measurements.push(Measurement { count, case, mode, technique, runs: Vec::new() });
                }
            }
        }
    }
    let start = Instant::now();
    for repetition in 0..=REPETITIONS {
        for measurement in &mut measurements {
            let set = &sets.iter().find(|(count, _)| *count == measurement.count).expect("measured count").1;
            let polygons = match measurement.case {
                Case::Central => &set.central,
                Case::Decentral => &set.decentral,
            };
            let nanoseconds = measurement.technique.time(measurement.mode, polygons);
            if repetition > 0 {
                measurement.runs.push(nanoseconds);
            }
        }
    }
    let seconds = start.elapsed().as_secs_f64();
    let results = Results(&measurements);

    println!("# Polygonal-light sampling: cost per sample (CPU, Rust twin)\n");
    println!(
        "{POLYGONS_PER_SET} polygons per set and vertex count, {SAMPLES_PER_POLYGON} samples per polygon, \
         median of {REPETITIONS} repetitions ({seconds:.1} s of timing).\n"
    );
    println!("| vertices | set | crossing the horizon | mean vertices after clipping |");
    println!("| --- | --- | --- | --- |");
    for (count, set) in &sets {
        for (case, polygons) in [(Case::Central, &set.central), (Case::Decentral, &set.decentral)] {
            let (crossing, clipped) = set_statistics(polygons);
            println!("| {count} | {} | {:.0} % | {clipped:.2} |", case_label(case), 100.0 * crossing);
        }
    }

    for (mode_index, mode) in [Mode::Lights, Mode::Samples].into_iter().enumerate() {
        println!("\n## {}\n", mode_title(mode));
        println!(
            "ns/sample with the baseline subtracted; ratios to \"solid angle, clipped\"; paper ratios from \
             Table A.2 (the clip row's paper value is \"Solid angle, clipped\" − \"Solid angle\").\n"
        );
        println!("| technique | ns, 6 | ns, 7 | ratio, 6 | ratio, 7 | paper ratio, 6 | paper ratio, 7 |");
        println!("| --- | ---: | ---: | ---: | ---: | ---: | ---: |");
        for row in ROWS {
            let ns: Vec<f64> = VERTEX_COUNTS.iter().map(|&count| results.row(row, count, mode)).collect();
            let mut line = format!("| {} | {:.1} | {:.1} |", row.label(), ns[0], ns[1]);
            for (index, &count) in VERTEX_COUNTS.iter().enumerate() {
                line += &match row {
                    Row::Baseline => " – |".to_string(),
                    _ => format!(" {:.2} |", ns[index] / results.row(Row::SolidAngleClipped, count, mode)),
                };
            }
            for index in 0..VERTEX_COUNTS.len() {
                line += &match row.paper_ratio(mode_index, index) {
                    Some(ratio) => format!(" {ratio:.2} |"),
                    None => " – |".to_string(),
                };
            }
            println!("{line}");
        }
    }

    println!("\n## Per set: projected over solid angle (both clipped) on the same polygons\n");
    println!(
        "\"Proj. − closed form\" subtracts the closed-form projected solid angle (net of clipping), which \
         this implementation evaluates in addition to the sector areas that the paper normalises by.\n"
    );
    println!(
        "| mode | vertices | set | solid angle, clipped (ns) | proj. (ns) | ratio | proj. − closed form (ns) | ratio |"
    );
    println!("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: |");
    for mode in [Mode::Lights, Mode::Samples] {
        for count in VERTEX_COUNTS {
            for case in [Case::Central, Case::Decentral] {
                let solid = results.net(count, case, mode, Technique::SolidAngleClipped);
                let projected = results.net(count, case, mode, Technique::Projected);
                let closed_form = results.net(count, case, mode, Technique::ClosedForm)
                    - results.net(count, case, mode, Technique::Clip);
                let without = projected - closed_form;
                println!(
                    "| {} | {count} | {} | {solid:.1} | {projected:.1} | {:.2} | {without:.1} | {:.2} |",
                    if mode == Mode::Lights { "128 lights" } else { "128 samples" },
                    case_label(case),
                    projected / solid,
                    without / solid
                );
            }
        }
    }

    println!("\n## Raw timings (ns/sample, baseline not subtracted)\n");
    println!("| mode | vertices | set | technique | median | min | max |");
    println!("| --- | ---: | --- | --- | ---: | ---: | ---: |");
    for measurement in &measurements {
        let min = measurement.runs.iter().copied().fold(f64::INFINITY, f64::min);
        let max = measurement.runs.iter().copied().fold(0.0, f64::max);
        println!(
            "| {} | {} | {} | {} | {:.1} | {min:.1} | {max:.1} |",
            if measurement.mode == Mode::Lights { "128 lights" } else { "128 samples" },
            measurement.count,
            case_label(measurement.case),
            measurement.technique.label(),
            measurement.median()
        );
    }
}
