//! Running a benchmark: every configuration of a [`BenchConfig`] on every [`BenchScene`],
//! its images and shading evaluations against the `pixel` reference, and its GPU time measured
//! in turns with the other configurations of the same scene and resolution.

use super::renderers::OwnRenderers;
use super::row::{Row, Timing, Trade};
use super::stability::{self, StabilityRun, Walker};
use crate::analysis::metrics::{self, fallback_mask, fallback_pixels, scaled_difference, ImageError};
use crate::error::Result;
use crate::geometry::shadow_class::ShadowClasses;
use crate::render::{
    output, Analysis, CameraTurn, DrawPart, EvaluationCounts, MeasureOptions, Measurement, Mode, PathFrames,
    Placement, PrePassStep, Renderer, ShadowRefits, View,
};
use crate::scene::path::{CameraPath, PathChoice};
use crate::scene::Scene;
use crate::shading::estimator::{Discontinuity, EstimatorSettings, Split};
use crate::vk::target::{FloatImage, RenderTarget};
use crate::vk::Context;
use ash::vk;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A scene to benchmark, with the name its rows carry.
pub struct BenchScene {
    pub name: String,
    pub scene: Scene,
}

impl BenchScene {
    /// Loads a scene file; its name is the file stem.
    pub fn load(path: &Path) -> Result<BenchScene> {
        let scene = Scene::load(path)?;
        let name = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        Ok(BenchScene { name, scene })
    }
}

/// What to measure.
#[derive(Clone, Debug)]
pub struct BenchConfig {
    /// Modes besides the `pixel` reference, which is always measured.
    pub modes: Vec<Mode>,
    /// multirate's ε values (empty: the scene's own).
    pub epsilons: Vec<f32>,
    /// multirate's n_max values (empty: the scene's own).
    pub n_maxes: Vec<u32>,
    /// Width × height; empty: the scene's own.
    pub resolutions: Vec<(u32, u32)>,
    pub warmup: u32,
    pub frames: u32,
    pub split: Split,
    pub discontinuity: Discontinuity,
    /// multirate's estimator placements, each measured (empty: the default).
    pub placements: Vec<Placement>,
    /// Where to write each row's images (error ×30, heat map, fallback mask), if anywhere.
    pub images: Option<PathBuf>,
    /// multirate: images below this many pixels are shaded per pixel without an estimate,
    /// each measured; `None`: the renderer's cost model chooses (`Renderer::min_estimated_area`).
    /// Empty: the cost model.
    pub min_estimated_areas: Vec<Option<f32>>,
    /// Degrees per frame by which the camera turns about its target while frames are timed (0:
    /// it stays still; `CameraTurn`), every configuration's measured frames at the same cameras.
    pub orbit_degrees: f32,
    /// Whether each part of the draws is timed apart (`MeasureOptions::draw_parts`): the frames
    /// are then slower by the split renderings.
    pub draw_parts: bool,
    /// Whether each step of the pre-pass is timed apart (`MeasureOptions::pre_pass_steps`): the
    /// frames are then slower by the flushes of the timestamps between the steps.
    pub pre_pass_steps: bool,
    /// multirate: the radius of the ball of eyes its levels hold for and are kept in, as a share
    /// of the camera's distance to its target (`View`'s `EYE_BALL_SHARE`; 0: every frame
    /// estimates for its own eye).
    pub eye_ball_share: f32,
    /// multirate: whether the pre-pass holds its levels between the balls of eyes
    /// (`View::hold_levels`), each measured. Empty: not held (the view's default).
    pub level_holds: Vec<bool>,
    /// Along a camera path at this many frames a second instead of `frames` and
    /// `orbit_degrees`: each scene's measured frames are its path's frames.
    pub path: Option<(PathChoice, f32)>,
}

impl BenchConfig {
    /// How its configurations are timed.
    pub fn schedule(&self) -> Schedule {
        Schedule {
            warmup: self.warmup,
            frames: self.frames,
            orbit_degrees: self.orbit_degrees,
            draw_parts: self.draw_parts,
            pre_pass_steps: self.pre_pass_steps,
            path: None,
        }
    }

    /// How the configurations of `scene` are timed: along its path where one is asked for.
    fn schedule_of(&self, scene: &Scene) -> Result<Schedule> {
        let Some((choice, fps)) = self.path else { return Ok(self.schedule()) };
        let path = CameraPath::chosen(choice, scene.camera_path.as_ref())
            .ok_or_else(|| crate::Error::NoCameraPath { scene: scene.path.clone() })?;
        let frames = path.frame_times(fps).len() as u32;
        let along = PathFrames { path: Arc::new(path), fps, start: scene.camera, bounds: scene.bounds() };
        Ok(Schedule { frames, orbit_degrees: 0.0, path: Some(along), ..self.schedule() })
    }
}

/// Everything a run produced: rows and, per row, the measured frames.
pub struct BenchResult {
    pub rows: Vec<Row>,
    /// Parallel to `rows`.
    pub measurements: Vec<Measurement>,
    /// Per scene whose lights cast shadows, in the order measured.
    pub shadows: Vec<ShadowReport>,
    /// Along a camera path: every configuration but `pixel`, its stability frame by frame.
    pub stability: Vec<StabilityRun>,
}

/// A shadowed scene's maps as the run drew them.
pub struct ShadowReport {
    /// The scene's name (`BenchScene::name`).
    pub scene: String,
    /// The GPU time every map took to draw when the renderer was made, ms.
    pub shadow_pass_ms: f64,
    /// The triangles' classes at the scene's camera and the first resolution measured (a
    /// directional map follows the view).
    pub classes: ShadowClasses,
    /// The directional maps drawn again for the views over the whole run (analysis, warm-up
    /// and measured frames of every mode), and what that took.
    pub refits: ShadowRefits,
}

/// One configuration to run, before it is measured.
struct Job {
    scene: usize,
    resolution: (u32, u32),
    mode: Mode,
    epsilon: f32,
    n_max: u32,
    placement: Placement,
    /// multirate: `None` for the cost model's area.
    min_estimated_area: Option<f32>,
    /// multirate: whether the pre-pass holds its levels (`View::hold_levels`).
    hold_levels: bool,
}

impl Job {
    /// The view of `scene` the job renders with `config`'s estimator settings.
    fn view(&self, scene: &Scene, config: &BenchConfig) -> View {
        let scene_view = View::of_scene(scene);
        View {
            mode: self.mode,
            estimator: EstimatorSettings {
                epsilon: self.epsilon,
                n_max: self.n_max,
                split: config.split,
                discontinuity: config.discontinuity,
                min_estimated_area: self.min_estimated_area.unwrap_or(0.0),
                ..scene_view.estimator
            },
            placement: self.placement,
            cost_model: self.min_estimated_area.is_none(),
            hold_levels: self.hold_levels,
            ..scene_view
        }
        .with_eye_ball(config.eye_ball_share)
    }

    fn label(&self, scenes: &[BenchScene]) -> String {
        let (width, height) = self.resolution;
        let name = &scenes[self.scene].name;
        match self.mode {
            Mode::Multirate => {
                let (epsilon, n_max, placement) = (self.epsilon, self.n_max, self.placement);
                let area = self.min_estimated_area.map_or_else(|| "auto".to_string(), |a| a.to_string());
                let held = if self.hold_levels { " levels held" } else { "" };
                format!(
                    "{name} {width}x{height} multirate ε={epsilon} n_max={n_max} estimator {placement} area {area}{held}"
                )
            }
            mode => format!("{name} {width}x{height} {mode}"),
        }
    }
}

fn jobs(scenes: &[BenchScene], config: &BenchConfig) -> Vec<Job> {
    let mut jobs = Vec::new();
    for (index, bench_scene) in scenes.iter().enumerate() {
        let settings = &bench_scene.scene.settings;
        let resolutions = if config.resolutions.is_empty() {
            vec![(settings.width, settings.height)]
        } else {
            config.resolutions.clone()
        };
        let epsilons =
            if config.epsilons.is_empty() { vec![settings.epsilon] } else { config.epsilons.clone() };
        let n_maxes = if config.n_maxes.is_empty() { vec![settings.n_max] } else { config.n_maxes.clone() };
        let placements =
            if config.placements.is_empty() { vec![Placement::default()] } else { config.placements.clone() };
        let areas = if config.min_estimated_areas.is_empty() {
            vec![None]
        } else {
            config.min_estimated_areas.clone()
        };
        let holds = if config.level_holds.is_empty() { vec![false] } else { config.level_holds.clone() };
        for &resolution in &resolutions {
            let job = |mode, epsilon, n_max, placement, (min_estimated_area, hold_levels)| Job {
                scene: index,
                resolution,
                mode,
                epsilon,
                n_max,
                placement,
                min_estimated_area,
                hold_levels,
            };
            let default = Placement::default();
            jobs.push(job(Mode::Pixel, settings.epsilon, settings.n_max, default, (None, true)));
            for &mode in config.modes.iter().filter(|&&m| m != Mode::Pixel) {
                if mode == Mode::Multirate {
                    for &epsilon in &epsilons {
                        for &n_max in &n_maxes {
                            for &placement in &placements {
                                for &area in &areas {
                                    for &hold in &holds {
                                        jobs.push(job(mode, epsilon, n_max, placement, (area, hold)));
                                    }
                                }
                            }
                        }
                    }
                } else {
                    jobs.push(job(mode, settings.epsilon, settings.n_max, default, (None, true)));
                }
            }
        }
    }
    jobs
}

/// How far a run has got: rows done, rows in all, and the row being measured.
pub struct Progress<'a> {
    pub done: usize,
    pub total: usize,
    pub label: &'a str,
    /// Timing turns of the current scene and resolution finished (0 outside its timing):
    /// each leaves every configuration rendered once more, so that a soak samples memory
    /// after each in the same state (`multirate soak --bench`).
    pub turns_done: usize,
}

/// The `pixel` reference's time and evaluations, for one scene at one resolution.
struct Reference {
    gpu_ms: f64,
    evaluations: u64,
    /// `vertex` mode's median time, where it was measured.
    vertex_ms: Option<f64>,
    /// The empty frame's median time.
    empty_ms: f64,
}

/// Runs every configuration of `config` on `scenes`, calling `progress` before each row and
/// before each timing turn. The configurations of one scene and resolution are timed in
/// turns ([`measure_in_turns`]), after their images and counts.
pub fn run(
    context: &Arc<Context>,
    scenes: &[BenchScene],
    config: &BenchConfig,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<BenchResult> {
    let jobs = jobs(scenes, config);
    let schedules = scenes.iter().map(|s| config.schedule_of(&s.scene)).collect::<Result<Vec<_>>>()?;
    let turns = |scene: usize| schedules[scene].frames.div_ceil(FRAMES_PER_TURN) as usize;
    let groups = groups(&jobs);
    let total = jobs.len() + groups.iter().map(|group| turns(group[0].scene)).sum::<usize>();
    let mut done = 0;
    let mut result = BenchResult {
        rows: Vec::new(),
        measurements: Vec::new(),
        shadows: Vec::new(),
        stability: Vec::new(),
    };
    let mut renderer: Option<(usize, Renderer)> = None;
    let mut target: Option<RenderTarget> = None;
    for group in groups {
        let bench_scene = &scenes[group[0].scene];
        let scene = &bench_scene.scene;
        if renderer.as_ref().is_none_or(|(index, _)| *index != group[0].scene) {
            drop(renderer.take()); // free the previous scene's GPU memory first
            renderer = Some((group[0].scene, Renderer::new(context, scene)?));
        }
        let (_, renderer) = renderer.as_ref().expect("created above");
        let target = target_of(context, &mut target, group[0].resolution)?;
        let extent = target.extent();
        let views: Vec<View> = group.iter().map(|job| job.view(scene, config)).collect();
        // Each configuration's frames, from its first image on, on its renderer: `OwnRenderers`.
        let own = OwnRenderers::new(context, scene, views.iter().map(|view| view.mode))?;
        // Images are compared with the reference as they come (it is the group's first), so
        // that only its image is held, whatever the number of configurations.
        assert!(group[0].mode == Mode::Pixel, "each scene and resolution starts with pixel mode");
        let mut reference_frame: Option<Analysis> = None;
        let mut untimed = Vec::with_capacity(group.len());
        for (index, (job, view)) in group.iter().zip(&views).enumerate() {
            let label = job.label(scenes);
            progress(Progress { done, total, label: &label, turns_done: 0 });
            done += 1;
            let (analysis, heat_and_mask) = analyze_with_heat(own.of(renderer, index), target, view)?;
            let reference = reference_frame.get_or_insert_with(|| analysis.clone());
            if let Some(dir) = &config.images {
                let stem = file_stem(bench_scene, job);
                write_row_images(
                    dir,
                    &stem,
                    &reference.image,
                    &analysis.image,
                    heat_and_mask.as_ref(),
                    scene,
                )?;
            }
            let (reference, test) = (reference.frame(), analysis.frame());
            untimed.push(Untimed {
                evaluations: analysis.evaluations,
                error: metrics::image_error(reference, test, scene.settings.exposure),
                pixels_over_epsilon: (job.mode == Mode::Multirate)
                    .then(|| metrics::pixels_over(reference, test, f64::from(job.epsilon))),
                fallback_fraction: heat_and_mask.as_ref().map(|(heat, mask)| {
                    let covered = heat.pixels.iter().filter(|p| p[3] > 0.0).count().max(1);
                    fallback_pixels(mask) as f64 / covered as f64
                }),
            });
        }
        drop(reference_frame);
        let name = &bench_scene.name;
        if !scene.shadow_casters.is_empty() && result.shadows.last().is_none_or(|r| &r.scene != name) {
            result.shadows.push(ShadowReport {
                scene: name.clone(),
                shadow_pass_ms: renderer.shadow_pass_ms().unwrap_or(0.0),
                classes: renderer.shadow_classes(),
                refits: ShadowRefits::default(),
            });
        }
        let label = format!("{} {}x{}: timing in turns", bench_scene.name, extent.width, extent.height);
        // The empty frame takes its turns with the others.
        let mut timed = views.clone();
        timed.push(empty_view(&views[0], scene));
        let schedule = schedules[group[0].scene].clone();
        let renderers: Vec<&Renderer> = (0..timed.len()).map(|k| own.of(renderer, k)).collect();
        let mut measurements = measure_in_turns(&renderers, target, &timed, schedule, &mut |turn| {
            progress(Progress { done: done + turn, total, label: &label, turns_done: turn })
        })?;
        drop(renderers);
        drop(own); // their memory freed before the walk makes renderers of its own
        done += turns(group[0].scene);
        if let Some(along) = &schedules[group[0].scene].path {
            let runs = walk(context, target, scenes, (group, &views), along, &mut |label| {
                progress(Progress { done, total, label, turns_done: 0 })
            })?;
            result.stability.extend(runs);
        }
        if let Some(report) = result.shadows.last_mut().filter(|r| &r.scene == name) {
            report.refits = renderer.shadow_refits();
        }
        let median = |measurement: &Measurement| Timing::of(&measurement.gpu_ms()).median;
        let empty = measurements.pop().expect("the empty frame was timed last");
        let reference = Reference {
            gpu_ms: median(&measurements[0]),
            evaluations: untimed[0].evaluations.total(),
            vertex_ms: group
                .iter()
                .position(|job| job.mode == Mode::Vertex)
                .map(|k| median(&measurements[k])),
            empty_ms: median(&empty),
        };
        for (((job, view), untimed), measurement) in group.iter().zip(&views).zip(untimed).zip(measurements) {
            let min_estimated_area = (job.mode == Mode::Multirate).then(|| renderer.min_estimated_area(view));
            result.rows.push(row(
                context,
                bench_scene,
                job,
                Timing::of(&measurement.gpu_ms()),
                &reference,
                untimed,
                &measurement,
                min_estimated_area,
            ));
            result.measurements.push(measurement);
        }
    }
    progress(Progress { done: total, total, label: "done", turns_done: 0 });
    Ok(result)
}

/// Only the stability of every configuration of `config` along its scene's camera path (none
/// where `config.path` asks for no path), without images, counts or timing turns: [`run`]'s walk
/// alone, about half its time. `progress` is told each frame before it is drawn (`done` counts frames).
pub fn walk_paths(
    context: &Arc<Context>,
    scenes: &[BenchScene],
    config: &BenchConfig,
    progress: &mut dyn FnMut(Progress<'_>),
) -> Result<Vec<StabilityRun>> {
    let jobs = jobs(scenes, config);
    let schedules = scenes.iter().map(|s| config.schedule_of(&s.scene)).collect::<Result<Vec<_>>>()?;
    let groups = groups(&jobs);
    let total = groups.iter().map(|group| schedules[group[0].scene].frames as usize).sum();
    let mut runs = Vec::new();
    let mut target: Option<RenderTarget> = None;
    let mut done = 0;
    for group in groups {
        let Some(along) = &schedules[group[0].scene].path else { continue };
        let scene = &scenes[group[0].scene].scene;
        let target = target_of(context, &mut target, group[0].resolution)?;
        let views: Vec<View> = group.iter().map(|job| job.view(scene, config)).collect();
        runs.extend(walk(context, target, scenes, (group, &views), along, &mut |label| {
            progress(Progress { done, total, label, turns_done: 0 });
            done += 1;
        })?);
    }
    progress(Progress { done: total, total, label: "done", turns_done: 0 });
    Ok(runs)
}

/// `jobs` by scene and resolution, in order: the configurations measured side by side.
fn groups(jobs: &[Job]) -> Vec<&[Job]> {
    jobs.chunk_by(|a, b| a.scene == b.scene && a.resolution == b.resolution).collect()
}

/// The render target of `resolution`: `target` where it has that size, else made anew in its
/// place (the old one freed first).
fn target_of<'a>(
    context: &Arc<Context>,
    target: &'a mut Option<RenderTarget>,
    (width, height): (u32, u32),
) -> Result<&'a RenderTarget> {
    let extent = vk::Extent2D { width, height };
    if target.as_ref().is_none_or(|t| t.extent() != extent) {
        drop(target.take());
        *target = Some(RenderTarget::new(context, extent)?);
    }
    Ok(target.as_ref().expect("made above"))
}

/// Every configuration of `group` but `pixel` (each at its view of `views`) walked along `along`
/// beside the per-pixel reference (`stability::along_path`); `progress` is given each frame's
/// label before it is drawn.
fn walk(
    context: &Arc<Context>,
    target: &RenderTarget,
    scenes: &[BenchScene],
    (group, views): (&[Job], &[View]),
    along: &PathFrames,
    progress: &mut dyn FnMut(&str),
) -> Result<Vec<StabilityRun>> {
    let bench_scene = &scenes[group[0].scene];
    let corners: Vec<_> = bench_scene.scene.triangles().collect();
    let walkers: Vec<Walker> = group
        .iter()
        .zip(views)
        .filter(|(job, _)| job.mode != Mode::Pixel)
        .map(|(job, view)| Walker { view: view.clone(), label: job.label(scenes) })
        .collect();
    stability::along_path(
        context,
        target,
        (&bench_scene.scene, &corners),
        &walkers,
        along,
        &mut |frame, frames| {
            progress(&format!("{}: stability, frame {} of {frames}", bench_scene.name, frame + 1))
        },
    )
}

/// The empty frame of `view`'s `scene`: `pixel` mode from an eye moved away from the scene,
/// beyond all of it, looking farther away, so that every triangle lies behind the eye and is
/// clipped.
fn empty_view(view: &View, scene: &Scene) -> View {
    let mut camera = view.camera;
    let away = (camera.eye - camera.target).normalize_or(glam::Vec3::Z);
    // Beyond the scene's bounds, whatever their corner nearest the eye's new place.
    let (low, high) = scene.bounds();
    let reach = camera.eye.distance(low) + (high - low).length();
    camera.eye += away * (reach + 1.0);
    camera.target = camera.eye + away;
    View { mode: Mode::Pixel, camera, ..view.clone() }
}

/// Measured frames per configuration and turn in [`measure_in_turns`].
pub const FRAMES_PER_TURN: u32 = 2;

/// What a configuration gives besides its time, measured against the reference image.
struct Untimed {
    evaluations: EvaluationCounts,
    error: ImageError,
    /// multirate only.
    pixels_over_epsilon: Option<usize>,
    /// multirate only.
    fallback_fraction: Option<f64>,
}

/// A configuration's analysis frame (image, triangle ids, shading evaluations) and, in
/// multirate, its level heat map and fallback mask.
fn analyze_with_heat(
    renderer: &Renderer,
    target: &RenderTarget,
    view: &View,
) -> Result<(Analysis, Option<(FloatImage, FloatImage)>)> {
    let analysis = renderer.analyze(target, view)?;
    let heat_and_mask = if view.mode == Mode::Multirate {
        let heat = renderer.render(target, &View { heat_map: true, ..view.clone() })?;
        let mask = fallback_mask(&heat);
        Some((heat, mask))
    } else {
        None
    };
    Ok((analysis, heat_and_mask))
}

/// How configurations are timed in turns ([`measure_in_turns`]).
#[derive(Clone, Debug)]
pub struct Schedule {
    /// Warm-up frames of the first turn.
    pub warmup: u32,
    /// Measured frames of each configuration.
    pub frames: u32,
    /// Degrees per frame by which the camera turns about its target (0: still; `CameraTurn`).
    pub orbit_degrees: f32,
    /// Whether each part of the draws is timed apart (`MeasureOptions::draw_parts`).
    pub draw_parts: bool,
    /// Whether each step of the pre-pass is timed apart (`MeasureOptions::pre_pass_steps`).
    pub pre_pass_steps: bool,
    /// Along a camera path instead of `orbit_degrees` (`CameraTurn::path`).
    pub path: Option<PathFrames>,
}

/// Times `views` (one scene at one resolution), each with its renderer of `renderers` (a
/// multirate configuration after the first on one of its own: `OwnRenderers`), in turns: each
/// configuration in order renders
/// its warm-up frames and [`FRAMES_PER_TURN`] measured frames, then the next; turns repeat
/// until each has `schedule.frames` measured frames. A slow spell of the machine (lavapipe
/// shares the CPU with everything else on it) then slows every configuration alike instead
/// of one whole row, so ratios within a run hold up. The first turn warms up for
/// `schedule.warmup` frames, later turns for one (at most `schedule.warmup`): the pipelines and
/// buffers stay ready between turns, only caches have cooled. `turn_done(k)` is called after
/// turn `k + 1`.
pub fn measure_in_turns(
    renderers: &[&Renderer],
    target: &RenderTarget,
    views: &[View],
    schedule: Schedule,
    turn_done: &mut dyn FnMut(usize),
) -> Result<Vec<Measurement>> {
    let mut measurements: Vec<Measurement> = views.iter().map(|_| Measurement::default()).collect();
    // Each configuration's camera goes on turning from where its last turn left it, its measured
    // frames at the same cameras as every other's (`CameraTurn`).
    let mut measured = 0;
    let mut turn = 0;
    while measured < schedule.frames {
        let frames = FRAMES_PER_TURN.min(schedule.frames - measured);
        let warmup = if turn == 0 { schedule.warmup } else { schedule.warmup.min(1) };
        for ((view, measurement), renderer) in views.iter().zip(&mut measurements).zip(renderers) {
            let turn = CameraTurn {
                degrees_per_frame: schedule.orbit_degrees,
                first_measured: measured,
                path: schedule.path.clone(),
            };
            let options = MeasureOptions {
                turn,
                draw_parts: schedule.draw_parts,
                pre_pass_steps: schedule.pre_pass_steps,
            };
            let part = renderer.measure_with(target, view, warmup, frames, options)?;
            measurement.frames.extend(part.frames);
            measurement.pre_pass.extend(part.pre_pass);
            measurement.pre_pass_steps.extend(part.pre_pass_steps);
            measurement.draw_parts_ms.extend(part.draw_parts_ms);
            measurement.frame_pre_pass_ms.extend(part.frame_pre_pass_ms);
            measurement.statistics = part.statistics.or(measurement.statistics);
            measurement.drawn_as_pixel = match (measurement.drawn_as_pixel, part.drawn_as_pixel) {
                (Some(sum), Some(part)) => Some(sum + part),
                (sum, part) => sum.or(part),
            };
        }
        measured += frames;
        turn += 1;
        turn_done(turn);
    }
    Ok(measurements)
}

#[allow(clippy::too_many_arguments)]
fn row(
    context: &Context,
    bench_scene: &BenchScene,
    job: &Job,
    gpu_ms: Timing,
    reference: &Reference,
    untimed: Untimed,
    measurement: &Measurement,
    min_estimated_area: Option<f32>,
) -> Row {
    let multirate = job.mode == Mode::Multirate;
    let Untimed { evaluations, error, pixels_over_epsilon, fallback_fraction } = untimed;
    Row {
        scene: bench_scene.name.clone(),
        triangles: bench_scene.scene.triangle_count(),
        mode: job.mode.to_string(),
        epsilon: multirate.then_some(job.epsilon),
        n_max: multirate.then_some(job.n_max),
        estimator: multirate.then(|| job.placement.to_string()),
        levels_held: multirate.then_some(job.hold_levels),
        width: job.resolution.0,
        height: job.resolution.1,
        frames: measurement.frames.len() as u32,
        gpu_ms,
        pre_pass_ms: (!measurement.pre_pass.is_empty()).then(|| Timing::of(&measurement.pre_pass_ms())),
        pre_pass_steps_ms: (!measurement.pre_pass_steps.is_empty())
            .then(|| PrePassStep::ALL.map(|step| Timing::of(&measurement.pre_pass_step_ms(step)).median)),
        draw_parts_ms: (!measurement.draw_parts_ms.is_empty()).then(|| {
            DrawPart::ALL.map(|part| {
                let ms: Vec<f64> =
                    measurement.draw_parts_ms.iter().map(|parts| parts[part as usize]).collect();
                Timing::of(&ms).median
            })
        }),
        min_estimated_area,
        frames_drawn_as_pixel: measurement.drawn_as_pixel,
        speedup: reference.gpu_ms / gpu_ms.median,
        trade: reference.vertex_ms.map(|vertex_ms| Trade::of(gpu_ms.median, reference.gpu_ms, vertex_ms)),
        empty_ms: reference.empty_ms,
        evaluations,
        evaluation_ratio: evaluations.total() as f64 / reference.evaluations.max(1) as f64,
        l_inf: error.l_inf,
        l_inf_same_triangle: error.l_inf_same_triangle,
        other_triangle_pixels: error.other_triangle_pixels,
        pixels_over_epsilon,
        mean_l2: error.mean_l2,
        psnr_db: error.psnr_db,
        flip: error.flip,
        fallback_fraction,
        statistics: measurement.statistics,
        device: context.info.name.clone(),
        driver: context.info.driver.clone(),
    }
}

fn file_stem(bench_scene: &BenchScene, job: &Job) -> String {
    let (width, height) = job.resolution;
    let mode = job.mode.to_string().replace(':', "");
    match job.mode {
        Mode::Multirate => {
            let mut stem =
                format!("{}_{width}x{height}_{mode}_eps{}_nmax{}", bench_scene.name, job.epsilon, job.n_max);
            // What else sets rows apart, where it is not the default: else their images would
            // overwrite each other's.
            if job.placement != Placement::default() {
                stem.push_str(&format!("_{}", job.placement));
            }
            if let Some(area) = job.min_estimated_area {
                stem.push_str(&format!("_area{area}"));
            }
            if job.hold_levels {
                stem.push_str("_held");
            }
            stem
        }
        _ => format!("{}_{width}x{height}_{mode}", bench_scene.name),
    }
}

fn write_row_images(
    dir: &Path,
    stem: &str,
    reference: &FloatImage,
    image: &FloatImage,
    heat_and_mask: Option<&(FloatImage, FloatImage)>,
    scene: &Scene,
) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| crate::Error::Output {
        path: dir.to_path_buf(),
        message: format!("cannot create: {e}"),
    })?;
    let exposure = scene.settings.exposure;
    output::write_image(image, &dir.join(format!("{stem}.png")), exposure)?;
    // The data images skip the tone curve: an error of 1/30 in linear radiance is white.
    let error = scaled_difference(reference, image, 30.0);
    output::write_data_png(&error, &dir.join(format!("{stem}_error_x30.png")))?;
    if let Some((heat, mask)) = heat_and_mask {
        output::write_data_png(heat, &dir.join(format!("{stem}_levels.png")))?;
        output::write_data_png(mask, &dir.join(format!("{stem}_fallback.png")))?;
    }
    Ok(())
}
