//! What one frame is drawn with, resolved once before anything is recorded ([`FrameConfig`]),
//! what submitting it commits ([`RecordedFrame`]), and the choice of what is shaded per pixel,
//! at its four scales, in one place ([`PerPixelChoice`], [`back_faces_per_pixel`]):
//!
//! | scale | decided from | here |
//! | --- | --- | --- |
//! | the frame | the frame guard's times (`guard`), set on the view by `Renderer::guarded` | `View::drawn_as_pixel` → every mesh |
//! | the mesh | the cost model: most visible triangles too small for an estimate to pay | [`PerPixelChoice::meshes`] |
//! | the triangle | its image area below the resolved break-even area, or a level above `n_max` | [`PerPixelChoice::min_estimated_area`] → the shaders |
//! | the back faces | a two-sided mesh drawn from the pre-pass's lists | [`back_faces_per_pixel`] |

use super::cost_model::{self, CostModel, MeshSample};
use super::level_ball::{self, BallUse, LevelBall};
use super::mode::{Mode, Placement, MAX_LEVEL};
use super::multirate_config::MultirateConfig;
use super::view::View;
use crate::geometry::camera;
use crate::gpu_interface::flags::{
    FLAG_DERIVATIVE_CHECK, FLAG_HEAT_MAP, FLAG_HOLD_LEVELS, FLAG_REUSE_LEVELS,
};
use crate::gpu_types::DrawConstants;
use crate::scene::{Light, Scene};
use crate::shading::estimator::EstimatorSettings;
use ash::vk;
use glam::Vec2;

/// The scene's inputs to the per-pixel choice and the rules that make it.
pub(super) struct PerPixelChoice {
    /// Where estimating pays on this device (views with `cost_model` set).
    pub cost_model: CostModel,
    /// Per mesh, in scene order: the triangles that stand for it in the per-mesh choice.
    mesh_samples: Vec<MeshSample>,
    /// The scene's lights: the cost model weighs their count, and the per-mesh choice tries the
    /// range class under them.
    lights: Vec<Light>,
}

impl PerPixelChoice {
    /// The choice for `scene` on the device named `device`.
    pub(super) fn new(device: &str, scene: &Scene) -> PerPixelChoice {
        PerPixelChoice {
            cost_model: CostModel::for_device(device),
            mesh_samples: scene
                .meshes
                .iter()
                .map(|m| MeshSample::of(m, &scene.materials[m.material]))
                .collect(),
            lights: scene.lights.clone(),
        }
    }

    /// The triangle's scale: the image area (pixels) below which `view`'s multirate pass shades
    /// a triangle per pixel without an estimate: the cost model's break-even area for the
    /// scene's lights where `view.cost_model` is set, else `view.estimator.min_estimated_area`.
    /// (A triangle whose level would exceed `n_max` is shaded per pixel too, by the shaders.)
    pub(super) fn min_estimated_area(&self, view: &View) -> f32 {
        if view.cost_model {
            self.cost_model.min_estimated_area(cost_model::weighed_lights(&self.lights))
        } else {
            view.estimator.min_estimated_area
        }
    }

    /// The frame's and the mesh's scales: per mesh, whether `view`'s multirate pass draws it
    /// whole as `pixel` mode does on a target of `extent`. Every mesh where the frame guard
    /// draws the frame as `pixel` does (`View::drawn_as_pixel`); with the cost model on, the
    /// meshes most of whose visible triangles are too small for an estimate to pay
    /// ([`MeshSample::mostly_small`]). Empty outside multirate or without the cost model.
    pub(super) fn meshes(&self, view: &View, extent: vk::Extent2D) -> Vec<bool> {
        if view.mode != Mode::Multirate {
            return Vec::new();
        }
        if view.drawn_as_pixel {
            return vec![true; self.mesh_samples.len()];
        }
        if !view.cost_model {
            return Vec::new();
        }
        let view_proj = camera::view_projection(&view.camera, extent.width, extent.height);
        let viewport = Vec2::new(extent.width as f32, extent.height as f32);
        let area = self.min_estimated_area(view);
        self.mesh_samples
            .iter()
            .map(|s| {
                s.mostly_small(
                    &view_proj,
                    view.camera.eye,
                    viewport,
                    area,
                    &self.lights,
                    view.estimator.epsilon,
                )
            })
            .collect()
    }

    /// The multirate configuration of `view` on a target of `extent`, its area resolved.
    pub(super) fn multirate_config(&self, view: &View, extent: vk::Extent2D) -> MultirateConfig {
        MultirateConfig {
            placement: view.placement,
            estimator: EstimatorSettings {
                min_estimated_area: self.min_estimated_area(view),
                ..view.estimator
            },
            extent: (extent.width, extent.height),
            hold_levels: view.hold_levels,
        }
    }
}

/// The back faces' scale: whether a mesh's back faces are drawn as `pixel` mode draws them,
/// after its front faces: a two-sided mesh drawn from the pre-pass's patch lists, which hold its
/// front faces (and the back faces beside a tessellated edge) only.
pub(super) fn back_faces_per_pixel(placement: Placement, one_sided: bool) -> bool {
    placement == Placement::Compute && !one_sided
}

/// Whether a frame of `view` may draw a mesh with `pixel` mode's pipeline: outside `pixel` mode,
/// where the cost model may draw a mesh whole per pixel, or some mesh is two-sided
/// (`one_sided` per mesh) and its back faces are drawn per pixel.
pub(super) fn may_draw_per_pixel(view: &View, mut one_sided: impl Iterator<Item = bool>) -> bool {
    view.mode == Mode::Multirate
        && (view.cost_model || one_sided.any(|one_sided| back_faces_per_pixel(view.placement, one_sided)))
}

/// Whether a frame commits what it learns (the ball of eyes) once submitted: the frames drawn
/// for the image do (and the analysis frame drawn as the image, `Renderer::analyze_as_shown`);
/// the other analysis, counting and level-recording frames leave the renderer as it was.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Commit {
    OnSubmit,
    Never,
}

/// Everything one frame is drawn with, resolved once (`Renderer::record`): the only source of
/// the frame's push constants.
pub(super) struct FrameConfig {
    /// The view as the frame guard draws it.
    pub view: View,
    pub extent: vk::Extent2D,
    /// The multirate configuration (read in multirate mode; its resolved area is also in every
    /// mode's push constants).
    pub multirate: MultirateConfig,
    /// Per mesh: drawn whole as `pixel` mode does ([`PerPixelChoice::meshes`]; missing
    /// entries: no).
    pub meshes_per_pixel: Vec<bool>,
    /// Whether the frame runs the pre-pass: multirate on the compute placement, with some mesh
    /// not drawn whole as `pixel` does.
    pub runs_pre_pass: bool,
    /// How the pre-pass uses the ball of eyes (`level_ball`).
    pub ball: BallUse,
    /// The ball that holds once this frame is submitted, where the frame commits it.
    pub ball_after: Option<Option<LevelBall>>,
    /// Most patches one tessellated draw of the multirate mode may hold (`n_max` everywhere).
    pub patches_per_draw: u32,
}

impl FrameConfig {
    /// The frame of `view` (as the guard draws it) on a target of `extent`, with the levels kept
    /// for `kept` (the ball the last committed frame left), drawing at most `patches_per_draw`
    /// patches of level `n_max` per draw.
    pub(super) fn resolve(
        choice: &PerPixelChoice,
        view: &View,
        extent: vk::Extent2D,
        kept: Option<LevelBall>,
        commit: Commit,
        patches_per_draw: u32,
    ) -> FrameConfig {
        let multirate = choice.multirate_config(view, extent);
        let meshes_per_pixel = choice.meshes(view, extent);
        let meshes = choice.mesh_samples.len();
        // No pre-pass where every mesh is drawn as `pixel` draws it.
        let runs_pre_pass = view.mode == Mode::Multirate
            && view.placement == Placement::Compute
            && (meshes_per_pixel.len() < meshes || meshes_per_pixel.contains(&false));
        let (ball, ball_after) = if runs_pre_pass {
            let (ball, after) = level_ball::next(kept, view.camera.eye, multirate);
            match (commit, ball) {
                (Commit::OnSubmit, _) => (ball, Some(after)),
                // The levels kept for the committed ball stay as they are.
                (Commit::Never, BallUse::Begin { radius, .. }) => (BallUse::Detached { radius }, None),
                (Commit::Never, _) => (ball, None),
            }
        } else {
            (BallUse::Off, None)
        };
        FrameConfig {
            view: view.clone(),
            extent,
            multirate,
            meshes_per_pixel,
            runs_pre_pass,
            ball,
            ball_after,
            patches_per_draw,
        }
    }

    /// Whether mesh `index` is drawn whole as `pixel` mode does.
    pub(super) fn mesh_per_pixel(&self, index: usize) -> bool {
        self.meshes_per_pixel.get(index) == Some(&true)
    }

    /// Whether the frame's mode has a pre-pass (`Placement::Compute`), run or not.
    pub(super) fn has_pre_pass(&self) -> bool {
        self.view.mode == Mode::Multirate && self.view.placement == Placement::Compute
    }

    /// The push constants of the frame's draws (the per-mesh fields: `DrawCall::set_constants`).
    pub(super) fn draw_constants(&self) -> DrawConstants {
        let (view, extent) = (&self.view, self.extent);
        let estimator = &view.estimator;
        DrawConstants {
            view_proj: camera::view_projection(&view.camera, extent.width, extent.height),
            eye: view.camera.eye,
            min_estimated_area: self.multirate.estimator.min_estimated_area,
            viewport_size: Vec2::new(extent.width as f32, extent.height as f32),
            epsilon: estimator.epsilon,
            // The shaders' range (their estimator, patch levels and heat map read it in it).
            n_max: estimator.n_max.clamp(1, MAX_LEVEL),
            draw_argument: match view.mode {
                Mode::Fixed(level) => level,
                _ => 1,
            },
            flags: if view.heat_map { FLAG_HEAT_MAP } else { 0 }
                | if view.derivative_check { FLAG_DERIVATIVE_CHECK } else { 0 },
            eye_radius: estimator.eye_radius,
            ..Default::default()
        }
    }

    /// The push constants of the pre-pass: the draws', with the radius its estimates hold for
    /// and whether it reuses and keeps levels (`ball`).
    pub(super) fn pre_pass_constants(&self) -> DrawConstants {
        let mut constants = self.draw_constants();
        constants.patches_per_draw = self.patches_per_draw;
        constants.eye_radius = self.ball.radius();
        if self.ball.keeps_levels() {
            constants.flags |= FLAG_REUSE_LEVELS;
            if self.multirate.hold_levels {
                constants.flags |= FLAG_HOLD_LEVELS;
            }
        }
        constants
    }

    /// What submitting the frame commits.
    pub(super) fn recorded(&self) -> RecordedFrame {
        RecordedFrame { ball: self.ball_after, ran_pre_pass: self.runs_pre_pass }
    }
}

/// A recorded frame: what the renderer learns once it is submitted (`Renderer::submitted`).
/// Recording alone changes nothing.
#[must_use = "pass a submitted frame to Renderer::submitted"]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecordedFrame {
    /// The ball of eyes that holds after it, where the frame commits it.
    pub(super) ball: Option<Option<LevelBall>>,
    /// Whether it ran the pre-pass.
    pub ran_pre_pass: bool,
}

#[cfg(test)]
mod tests;
