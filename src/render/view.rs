//! [`View`]: what one frame is rendered with — the camera, the mode, `multirate` mode's
//! estimator settings and placement, and the debug views.

use super::mode::{Mode, Placement};
use crate::scene::{Camera, Scene};
use crate::shading::estimator::{Discontinuity, EstimatorSettings, Split};

/// What a frame is rendered with.
#[derive(Clone, Debug)]
pub struct View {
    pub camera: Camera,
    pub mode: Mode,
    /// `multirate` mode's estimator: its L∞ error bound ε (linear radiance), its largest level
    /// before per-pixel fallback (n_max), its split and its discontinuity handling.
    pub estimator: EstimatorSettings,
    /// `multirate` only: where the estimator runs.
    pub placement: Placement,
    /// `multirate` only: the renderer's cost model chooses which triangles are estimated
    /// (`Renderer::min_estimated_area`), in place of `estimator.min_estimated_area`, and the
    /// frame guard may draw the frame as `pixel` does (`Renderer::guarded`).
    pub cost_model: bool,
    /// `multirate` only: draw every mesh as `pixel` mode does, without the pre-pass: the frame
    /// guard's probe or choice ([`super::guard`]), set by `Renderer::guarded`.
    pub drawn_as_pixel: bool,
    /// Colour by tessellation level (heat map) instead of shading.
    pub heat_map: bool,
    /// Draw triangle edges only (where the device has `fillModeNonSolid`).
    pub wireframe: bool,
    /// `pixel-deferred` only: instead of shading, write per pixel the analytic uv derivatives'
    /// difference from the hardware's (`‖∂uv/∂x − dFdx uv‖ + ‖∂uv/∂y − dFdy uv‖` in red, the
    /// analytic `‖∂uv/∂x‖ + ‖∂uv/∂y‖` in green, and in blue 1 where the pixel's 2×2 quad
    /// spans several triangles; seed 002's comparison).
    pub derivative_check: bool,
    /// `multirate` only: levels do not flip back and forth as the eye moves
    /// (`render::level_hold`): after a triangle's level rose, a coarser estimate is used only
    /// once coarser ones have come several times in a row. Off by default (every estimate used as
    /// it comes): held, a turning camera's frames shaded 9 % more sub-vertices and took 9–15 %
    /// longer on lavapipe for 2–5 % fewer pixels jumping by more than ε/2 (docs/temporal.md).
    pub hold_levels: bool,
}

/// The least radius of the ball of eyes that multirate's levels are estimated for, as a share of
/// the camera's distance to its target: the pre-pass reuses them while the eye stays in the ball
/// (`render::level_ball`, which widens the ball where the eye moves). 1 % raises the estimator's
/// evaluations by 0.4–2.7 % on the shipped scenes (`docs/estimator.md` §16).
pub const EYE_BALL_SHARE: f32 = 0.01;

impl View {
    /// The scene's own camera and settings, its levels holding for a ball of eyes of
    /// [`EYE_BALL_SHARE`].
    pub fn of_scene(scene: &Scene) -> View {
        let view = View {
            camera: scene.camera,
            mode: Mode::Pixel,
            estimator: EstimatorSettings {
                epsilon: scene.settings.epsilon,
                n_max: scene.settings.n_max,
                split: Split::Heuristic,
                discontinuity: Discontinuity::Relaxed,
                min_estimated_area: 0.0,
                eye_radius: 0.0,
            },
            placement: Placement::default(),
            cost_model: false,
            drawn_as_pixel: false,
            heat_map: false,
            wireframe: false,
            derivative_check: false,
            hold_levels: false,
        };
        view.with_eye_ball(EYE_BALL_SHARE)
    }

    /// This view with multirate's ball of eyes `share` of the camera's distance to its target
    /// (0: the levels hold for the eye alone).
    pub fn with_eye_ball(&self, share: f32) -> View {
        let eye_radius = share * self.camera.eye.distance(self.camera.target);
        View { estimator: EstimatorSettings { eye_radius, ..self.estimator }, ..self.clone() }
    }

    /// This view from `camera`, its ball of eyes keeping its share of the camera's distance to its
    /// target.
    pub fn seen_from(&self, camera: Camera) -> View {
        let before = self.camera.eye.distance(self.camera.target);
        let share = if before > 0.0 { self.estimator.eye_radius / before } else { 0.0 };
        View { camera, ..self.clone() }.with_eye_ball(share)
    }
}
