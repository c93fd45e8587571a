//! The SHADING options `render`, `view` and `analyze` share (mode, ε, n_max, split,
//! discontinuity, estimator placement, smallest estimated image, ball of eyes), their parsers and
//! checks, and the view they give of a scene.

use anyhow::Result;
use clap::Args;
use multirate::render::{Mode, Placement, View, EYE_BALL_SHARE, MAX_LEVEL};
use multirate::scene::settings::{check_epsilon, check_n_max, N_MAX_RANGE};
use multirate::scene::Scene;
use multirate::shading::estimator::{Discontinuity, Split};

// `fixed:N` is checked against the tessellator's largest level, `--nmax` against n_max's range.
const _: () = assert!(MAX_LEVEL == *N_MAX_RANGE.end());

/// How shading is sampled; unset values come from the scene.
#[derive(Args, Clone)]
pub struct ShadingArgs {
    /// multirate (the default: shaded on the sub-vertices the estimator asks for), pixel (the
    /// per-pixel reference), vertex (Gouraud) or fixed:N (tessellated at level N).
    #[arg(long, default_value = "multirate")]
    pub mode: Mode,
    /// multirate: L∞ bound on the interpolation error, in linear radiance.
    #[arg(long)]
    pub epsilon: Option<f32>,
    /// multirate: largest tessellation level before per-pixel fallback (1..=64).
    #[arg(long)]
    pub nmax: Option<u32>,
    /// multirate: how ε is shared between error terms.
    #[arg(long, value_parser = parse_split, default_value = "heuristic")]
    pub split: Split,
    /// multirate: where the terminator may cross a triangle, keep a bound valid across the
    /// kink (relaxed) or shade it per pixel (conservative, the paper's choice).
    #[arg(long, value_parser = parse_discontinuity, default_value = "relaxed")]
    pub discontinuity: Discontinuity,
    /// multirate: run the estimator in a compute pre-pass (compute, the default: faster frames)
    /// or in the tessellation control stage (tcs, as the seeds describe it); both give the
    /// same levels.
    #[arg(long = "estimator", value_name = "ESTIMATOR", default_value_t = Placement::default())]
    pub placement: Placement,
    /// multirate: triangles whose image covers fewer pixels are shaded per pixel without an
    /// estimate: auto (the device's cost model, `multirate calibrate`; where frames are timed,
    /// its frame guard draws them as pixel does where that measured faster) or a number of
    /// pixels (0: estimate every visible triangle; unguarded).
    #[arg(long, value_name = "auto|PIXELS", default_value = "auto")]
    pub min_estimated_area: EstimatedArea,
    /// multirate: the radius of the ball of eyes its levels hold for, kept while the eye stays
    /// in it, as a share of the camera's distance to its target (0: for the eye alone).
    #[arg(long, value_name = "SHARE", default_value_t = EYE_BALL_SHARE)]
    pub eye_ball: f32,
    /// multirate: hold levels between the balls of eyes (after a level rose, a coarser estimate
    /// is used only once coarser ones have come several times in a row), so that they do not
    /// flip back and forth as the eye moves; off by default (it costs a turning camera time).
    #[arg(long)]
    pub hold_levels: bool,
}

impl Default for ShadingArgs {
    fn default() -> Self {
        ShadingArgs {
            mode: Mode::Multirate,
            epsilon: None,
            nmax: None,
            split: Split::Heuristic,
            discontinuity: Discontinuity::Relaxed,
            placement: Placement::default(),
            min_estimated_area: EstimatedArea::Auto,
            eye_ball: EYE_BALL_SHARE,
            hold_levels: false,
        }
    }
}

impl ShadingArgs {
    /// The scene's view with these settings applied; rejects out-of-range values.
    pub fn view(&self, scene: &Scene) -> Result<View> {
        let mut view = View::of_scene(scene).with_eye_ball(check_eye_ball(self.eye_ball)?);
        view.mode = self.mode;
        view.estimator.split = self.split;
        view.estimator.discontinuity = self.discontinuity;
        view.placement = self.placement;
        view.hold_levels = self.hold_levels;
        view.cost_model = self.min_estimated_area.pixels().is_none();
        view.estimator.min_estimated_area = self.min_estimated_area.pixels().unwrap_or(0.0);
        if let Some(epsilon) = self.epsilon {
            view.estimator.epsilon = check_epsilon(epsilon).map_err(|e| anyhow::anyhow!("--epsilon {e}"))?;
        }
        if let Some(n_max) = self.nmax {
            view.estimator.n_max = check_n_max(n_max).map_err(|e| anyhow::anyhow!("--nmax {e}"))?;
        }
        Ok(view)
    }
}

/// `--min-estimated-area`: the cost model's choice, or a given area.
#[derive(Clone, Copy, Debug)]
pub enum EstimatedArea {
    Auto,
    Pixels(f32),
}

impl EstimatedArea {
    /// The given area; `None` for the cost model's.
    pub fn pixels(self) -> Option<f32> {
        match self {
            EstimatedArea::Auto => None,
            EstimatedArea::Pixels(pixels) => Some(pixels),
        }
    }
}

impl std::str::FromStr for EstimatedArea {
    type Err = String;
    fn from_str(text: &str) -> Result<EstimatedArea, String> {
        match (text, text.parse::<f32>()) {
            ("auto", _) => Ok(EstimatedArea::Auto),
            (_, Ok(pixels)) if pixels >= 0.0 && pixels.is_finite() => Ok(EstimatedArea::Pixels(pixels)),
            _ => Err(format!("\"{text}\": expected auto or a number of pixels >= 0")),
        }
    }
}

/// `--eye-ball`: a share in [0, 1).
pub fn check_eye_ball(share: f32) -> Result<f32> {
    anyhow::ensure!(
        share.is_finite() && (0.0..1.0).contains(&share),
        "--eye-ball must be a share in [0, 1) of the camera's distance to its target (got {share})"
    );
    Ok(share)
}

pub fn parse_split(text: &str) -> Result<Split, String> {
    match text {
        "uniform" => Ok(Split::Uniform),
        "heuristic" => Ok(Split::Heuristic),
        _ => Err("expected uniform or heuristic".into()),
    }
}

pub fn parse_discontinuity(text: &str) -> Result<Discontinuity, String> {
    match text {
        "conservative" => Ok(Discontinuity::Conservative),
        "relaxed" => Ok(Discontinuity::Relaxed),
        _ => Err("expected conservative or relaxed".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cli::common::{parsed, shipped_scene};

    #[test]
    fn hold_levels_is_off_unless_asked_for() {
        let scene = Scene::load(&shipped_scene("test/lambert_directional.toml")).expect("the test scene");
        let view =
            |words: &[&str]| parsed::<ShadingArgs>(words).expect("parsed").view(&scene).expect("a view");
        assert!(!view(&[]).hold_levels);
        assert!(view(&["--hold-levels"]).hold_levels);
        assert!(parsed::<ShadingArgs>(&["--hold-levels", "on"]).is_err(), "a flag takes no value");
    }
}
