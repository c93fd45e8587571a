//! Temporal stability along a camera path (`analysis::temporal`), measured the way a user sees
//! a mode: its frames drawn in order with one renderer (multirate keeps its levels for a ball of
//! eyes from frame to frame), by the analysis variant for the triangle each pixel shows
//! (`Renderer::analyze_as_shown`, which commits the ball as the frame a user sees does), beside
//! the per-pixel reference of the same camera; for multirate also the share of visible
//! triangles whose level changed since the frame before. Every configuration walks the path at
//! once, frame by frame, so that each frame's reference is drawn once for all of them (a
//! multirate configuration after the first on a renderer of its own: `renderers`).

use super::renderers::OwnRenderers;
use crate::analysis::metrics::pixels_over;
use crate::analysis::temporal::{step, PathFrame, PathStability};
use crate::error::Result;
use crate::render::{Analysis, Mode, PathFrames, Renderer, View};
use crate::scene::{Camera, Scene};
use crate::vk::target::RenderTarget;
use crate::vk::Context;
use glam::Vec3;
use std::collections::HashSet;
use std::rc::Rc;
use std::sync::Arc;

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

/// One configuration to walk the path with: its view (of the path's first camera) and label.
pub struct Walker {
    pub view: View,
    pub label: String,
}

/// Every configuration of `walkers` (of `scene`, whose triangles' corners are `corners`)
/// rendered frame by frame along `along` into `target`, beside one per-pixel reference a frame,
/// each at a bound of its `view.estimator.epsilon`. The walk draws with renderers of its own,
/// made for it, so that it begins as a user's first frame does whatever ran before it (the
/// reference and the configurations see the same cameras from the same start: the same fitted
/// shadow maps). `progress` is told each frame before it is drawn.
pub fn along_path(
    context: &Arc<Context>,
    target: &RenderTarget,
    (scene, corners): (&Scene, &[[Vec3; 3]]),
    walkers: &[Walker],
    along: &PathFrames,
    progress: &mut dyn FnMut(usize, usize),
) -> Result<Vec<StabilityRun>> {
    let Some(first) = walkers.first() else { return Ok(Vec::new()) };
    let shared = Renderer::new(context, scene)?;
    let own = OwnRenderers::new(context, scene, walkers.iter().map(|walker| walker.view.mode))?;
    let mut walks: Vec<Walk> = walkers
        .iter()
        .map(|walker| Walk {
            walker,
            run: StabilityRun { label: walker.label.clone(), ..StabilityRun::default() },
            previous: None,
        })
        .collect();
    let frames = along.path.frame_times(along.fps).len();
    for frame in 0..frames {
        progress(frame, frames);
        let camera = scene.camera.on_path(&along.path, frame as f32 / along.fps, along.bounds);
        let reference_view = View { mode: Mode::Pixel, ..first.view.seen_from(camera) };
        let reference = Rc::new(shared.analyze(target, &reference_view)?);
        for (index, walk) in walks.iter_mut().enumerate() {
            walk.frame(own.of(&shared, index), target, corners, camera, &reference)?;
        }
    }
    Ok(walks.into_iter().map(|walk| walk.run).collect())
}

/// One configuration's walk so far.
struct Walk<'a> {
    walker: &'a Walker,
    run: StabilityRun,
    previous: Option<Shown>,
}

impl Walk<'_> {
    /// The frame seen from `camera`, against the frame before.
    fn frame(
        &mut self,
        renderer: &Renderer,
        target: &RenderTarget,
        corners: &[[Vec3; 3]],
        camera: Camera,
        reference: &Rc<Analysis>,
    ) -> Result<()> {
        let view = &self.walker.view;
        let frame_view = view.seen_from(camera);
        let multirate = view.mode == Mode::Multirate;
        // The frame a user sees, drawn by the analysis variant for the triangle ids: multirate's
        // commits its ball of eyes as the viewer's frame would, and the level record after it
        // draws the same levels. The other modes keep nothing from frame to frame.
        let test = if multirate {
            renderer.analyze_as_shown(target, &frame_view)?
        } else {
            renderer.analyze(target, &frame_view)?
        };
        let levels = if multirate { Some(renderer.record_levels(target, &frame_view)?) } else { None };
        let pattern_changed =
            match (self.previous.as_ref().and_then(|before| before.levels.as_ref()), &levels) {
                (Some(then), Some(now)) => then.iter().zip(now).map(|(a, b)| a != b).collect(),
                _ => Vec::new(),
            };
        let shown = Shown { camera, test, reference: Rc::clone(reference), levels, pattern_changed };
        let epsilon = view.estimator.epsilon;
        if multirate {
            let over = pixels_over(shown.reference.frame(), shown.test.frame(), f64::from(epsilon));
            self.run.pixels_over_epsilon.push(over);
        }
        if let Some(before) = &self.previous {
            self.run.steps.steps.push(step(&before.frame(), &shown.frame(), corners, epsilon));
            if let (Some(then), Some(now)) = (&before.levels, &shown.levels) {
                let (ids_then, ids_now) = (&before.reference.triangles, &shown.reference.triangles);
                self.run.level_changes.push(level_change_share((ids_then, then), (ids_now, now)));
            }
        }
        self.previous = Some(shown);
        Ok(())
    }
}

/// One frame of the path as the mode and the reference showed it.
struct Shown {
    camera: Camera,
    test: Analysis,
    /// The frame's reference, shared by every configuration.
    reference: Rc<Analysis>,
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
