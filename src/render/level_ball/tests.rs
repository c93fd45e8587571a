use super::{next, BallUse};
use crate::render::multirate_config::MultirateConfig;
use crate::render::Placement;
use crate::shading::estimator::EstimatorSettings;
use glam::Vec3;

fn key(eye_radius: f32) -> MultirateConfig {
    MultirateConfig {
        placement: Placement::Compute,
        estimator: EstimatorSettings { eye_radius, min_estimated_area: 20.0, ..EstimatorSettings::default() },
        extent: (640, 480),
    }
}

#[test]
fn without_a_radius_no_ball_is_kept() {
    let (using, ball) = next(None, Vec3::ZERO, key(0.0));
    assert_eq!(using, BallUse::Off);
    assert!(ball.is_none());
    assert!(!using.keeps_levels());
}

#[test]
fn a_ball_lasts_while_the_eye_stays_in_it() {
    let (first, ball) = next(None, Vec3::ZERO, key(1.0));
    assert_eq!(first, BallUse::Begin { radius: 1.0 });
    let (second, same) = next(ball, Vec3::new(0.6, 0.0, 0.0), key(1.0));
    assert_eq!(same, ball);
    let BallUse::Continue { radius } = second else { panic!("{second:?}: the eye is in the ball") };
    assert!(radius >= 1.6, "{radius}: the frame's ball must hold the first");
    let (third, moved) = next(ball, Vec3::new(0.0, 1.2, 0.0), key(1.0));
    assert_eq!(third, BallUse::Begin { radius: 1.0 }, "the eye left the ball");
    assert_ne!(moved, ball);
}

#[test]
fn other_settings_begin_a_ball() {
    let (_, ball) = next(None, Vec3::ZERO, key(1.0));
    let other = MultirateConfig {
        estimator: EstimatorSettings { min_estimated_area: 0.0, ..key(1.0).estimator },
        ..key(1.0)
    };
    assert_eq!(next(ball, Vec3::ZERO, other).0, BallUse::Begin { radius: 1.0 });
    let finer =
        MultirateConfig { estimator: EstimatorSettings { epsilon: 0.01, ..key(1.0).estimator }, ..key(1.0) };
    assert_eq!(next(ball, Vec3::ZERO, finer).0, BallUse::Begin { radius: 1.0 });
    assert_eq!(next(ball, Vec3::ZERO, key(0.0)), (BallUse::Off, None));
}

/// A continuing frame's ball holds every point of the first, the farthest ones included.
#[test]
fn a_continuing_frame_holds_the_whole_first_ball() {
    let centre = Vec3::new(3.0, -2.0, 7.5);
    let radius = 0.37;
    let (_, ball) = next(None, centre, key(radius));
    for k in 0..200 {
        let t = k as f32 * 0.731;
        let direction = Vec3::new(t.cos() * (2.0 * t).sin(), t.sin() * (2.0 * t).sin(), (2.0 * t).cos());
        let eye = centre + direction * (radius * (k as f32 / 200.0));
        let (using, _) = next(ball, eye, key(radius));
        let BallUse::Continue { radius: around } = using else { panic!("{using:?} at {eye}") };
        let farthest = centre - (eye - centre).normalize_or(Vec3::X) * radius;
        assert!(farthest.distance(eye) <= around, "{eye}: {} > {around}", farthest.distance(eye));
    }
}
