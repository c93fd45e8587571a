//! Temporal stability along a camera path (`analysis::temporal`), measured the way a user sees
//! a mode: its frames rendered in order with one renderer (multirate keeps its levels for a ball
//! of eyes from frame to frame), each then drawn again by the analysis variant for the triangle
//! each pixel shows (the ball just committed, so the same levels), beside the per-pixel
//! reference of the same camera; for multirate also the share of visible triangles whose level
//! changed since the frame before.

use crate::analysis::metrics::pixels_over;
use crate::analysis::temporal::{step, PathFrame, PathStability};
use crate::error::Result;
use crate::render::{Analysis, Mode, PathFrames, Renderer, View};
use crate::scene::{Camera, Scene};
use crate::vk::target::RenderTarget;
use glam::Vec3;
use std::collections::HashSet;

/// One configuration along a path.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StabilityRun {
    /// The configuration (`Job::label`).
    pub label: String,
    pub steps: PathStability,
    /// multirate: per step, the share of triangles visible in both frames whose level changed.
    pub level_changes: Vec<f64>,
    /// multirate: per frame, its pixels of the same triangle as the reference's farther than ε
    /// from it (`metrics::pixels_over`; the bound says 0).
    pub pixels_over_epsilon: Vec<usize>,
}

/// `view` (of `scene`) rendered frame by frame along `along` into `target` beside `pixel`'s
/// reference, at a bound of `view.estimator.epsilon`.
pub fn along_path(
    renderer: &Renderer,
    target: &RenderTarget,
    (scene, corners): (&Scene, &[[Vec3; 3]]),
    view: &View,
    along: &PathFrames,
    label: String,
) -> Result<StabilityRun> {
    let frames = along.path.frame_times(along.fps).len();
    let mut run = StabilityRun { label, ..StabilityRun::default() };
    let mut previous: Option<Shown> = None;
    for frame in 0..frames {
        let camera = scene.camera.on_path(&along.path, frame as f32 / along.fps, along.bounds);
        let frame_view = view.seen_from(camera);
        // The frame a user sees commits its ball of eyes; the analysis frame after it draws the
        // same levels and gives the triangle ids.
        renderer.render(target, &frame_view)?;
        let levels = match view.mode {
            Mode::Multirate => Some(renderer.record_levels(target, &frame_view)?),
            _ => None,
        };
        let pattern_changed = match (previous.as_ref().and_then(|before| before.levels.as_ref()), &levels) {
            (Some(then), Some(now)) => then.iter().zip(now).map(|(a, b)| a != b).collect(),
            _ => Vec::new(),
        };
        let shown = Shown {
            camera,
            test: renderer.analyze(target, &frame_view)?,
            reference: renderer.analyze(target, &View { mode: Mode::Pixel, ..frame_view.clone() })?,
            levels,
            pattern_changed,
        };
        if view.mode == Mode::Multirate {
            let over =
                pixels_over(shown.reference.frame(), shown.test.frame(), f64::from(view.estimator.epsilon));
            run.pixels_over_epsilon.push(over);
        }
        if let Some(before) = &previous {
            run.steps.steps.push(step(&before.frame(), &shown.frame(), corners, view.estimator.epsilon));
            if let (Some(then), Some(now)) = (&before.levels, &shown.levels) {
                let (ids_then, ids_now) = (&before.reference.triangles, &shown.reference.triangles);
                run.level_changes.push(level_change_share((ids_then, then), (ids_now, now)));
            }
        }
        previous = Some(shown);
    }
    Ok(run)
}

/// One frame of the path as the mode and the reference showed it.
struct Shown {
    camera: Camera,
    test: Analysis,
    reference: Analysis,
    /// multirate: every triangle's recorded level.
    levels: Option<Vec<[f32; 4]>>,
    /// multirate: per triangle, whether its recorded level or outer levels differ from the
    /// frame before's (empty for the first frame and other modes).
    pattern_changed: Vec<bool>,
}

impl Shown {
    fn frame(&self) -> PathFrame<'_> {
        PathFrame {
            test: &self.test.image,
            reference: &self.reference.image,
            triangles: &self.reference.triangles,
            test_triangles: &self.test.triangles,
            camera: self.camera,
            pattern_changed: &self.pattern_changed,
        }
    }
}

/// Of the triangles visible in both frames (`ids`: per pixel, triangle + 1), the share whose
/// recorded level (`[level, ..]` per triangle) differs.
fn level_change_share((ids_then, then): (&[u32], &[[f32; 4]]), (ids_now, now): (&[u32], &[[f32; 4]])) -> f64 {
    let visible = |ids: &[u32]| -> HashSet<u32> { ids.iter().copied().filter(|&id| id > 0).collect() };
    let both: Vec<u32> = visible(ids_then).intersection(&visible(ids_now)).copied().collect();
    let level = |levels: &[[f32; 4]], id: u32| levels.get(id as usize - 1).map(|l| l[0]);
    let changed = both.iter().filter(|&&id| level(then, id) != level(now, id)).count();
    changed as f64 / both.len().max(1) as f64
}
