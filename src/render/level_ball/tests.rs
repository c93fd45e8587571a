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
        hold_levels: true,
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
    assert_eq!(first, BallUse::Begin { radius: 1.0, fresh: true });
    let (second, same) = next(ball, Vec3::new(0.6, 0.0, 0.0), key(1.0));
    assert_eq!(same.map(|b| b.centre()), ball.map(|b| b.centre()));
    let BallUse::Continue { radius } = second else { panic!("{second:?}: the eye is in the ball") };
    assert!(radius >= 1.6, "{radius}: the frame's ball must hold the first");
    // From the first eye, a step of 1.2 leaves the ball: the new one is wide enough for three
    // more such steps.
    let (third, moved) = next(ball, Vec3::new(0.0, 1.2, 0.0), key(1.0));
    assert_eq!(third, BallUse::Begin { radius: 3.0 * 1.2, fresh: false }, "the eye left the ball");
    assert_ne!(moved, ball);
}

#[test]
fn a_moving_eye_begins_a_wider_ball_and_a_still_one_the_configured_one() {
    let step = Vec3::new(0.0, 0.0, 1.5);
    let (first, mut ball) = next(None, Vec3::ZERO, key(1.0));
    assert_eq!(first, BallUse::Begin { radius: 1.0, fresh: true }, "no step seen yet");
    // Steps of 1.5 each frame: each ball that begins holds three of them, so the eye moves on
    // within it for three frames and begins the next one at the fourth.
    let mut uses = Vec::new();
    for k in 1..=7 {
        let (using, after) = next(ball, step * k as f32, key(1.0));
        uses.push(using);
        ball = after;
    }
    let begins: Vec<usize> = uses
        .iter()
        .enumerate()
        .filter(|(_, u)| matches!(u, BallUse::Begin { .. }))
        .map(|(k, _)| k + 1)
        .collect();
    assert_eq!(begins, [1, 5], "{uses:?}");
    assert!(uses.iter().all(|u| u.radius() <= 2.0 * 3.0 * 1.5 * 1.001), "{uses:?}");
    assert_eq!(uses[4], BallUse::Begin { radius: 4.5, fresh: false });
    // One frame again at the same eye keeps the widened ball; a second begins one of the
    // configured radius, which then lasts.
    let stopped = step * 7.0;
    let (repeat, ball) = next(ball, stopped, key(1.0));
    assert!(matches!(repeat, BallUse::Continue { .. }), "{repeat:?}");
    let (halt, after) = next(ball, stopped, key(1.0));
    assert_eq!(halt, BallUse::Begin { radius: 1.0, fresh: false });
    for _ in 0..3 {
        assert!(matches!(next(after, stopped, key(1.0)).0, BallUse::Continue { .. }));
    }
    // A jump widens it at most MOST_WIDENED times; a NaN eye gives the configured radius.
    let (jump, _) = next(after, stopped + Vec3::splat(1.0e6), key(1.0));
    assert_eq!(jump, BallUse::Begin { radius: super::MOST_WIDENED, fresh: false });
    let (nan, _) = next(after, Vec3::NAN, key(1.0));
    assert_eq!(nan, BallUse::Begin { radius: 1.0, fresh: false });
}

#[test]
fn other_settings_begin_a_ball() {
    let (_, ball) = next(None, Vec3::ZERO, key(1.0));
    let other = MultirateConfig {
        estimator: EstimatorSettings { min_estimated_area: 0.0, ..key(1.0).estimator },
        ..key(1.0)
    };
    // The levels held for other settings say nothing of these: they are cleared.
    assert_eq!(next(ball, Vec3::ZERO, other).0, BallUse::Begin { radius: 1.0, fresh: true });
    let finer =
        MultirateConfig { estimator: EstimatorSettings { epsilon: 0.01, ..key(1.0).estimator }, ..key(1.0) };
    assert_eq!(next(ball, Vec3::ZERO, finer).0, BallUse::Begin { radius: 1.0, fresh: true });
    let unheld = MultirateConfig { hold_levels: false, ..key(1.0) };
    assert_eq!(next(ball, Vec3::ZERO, unheld).0, BallUse::Begin { radius: 1.0, fresh: true });
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

#[test]
fn the_configured_radius_may_round_but_not_outgrow_the_ball() {
    let (_, ball) = next(None, Vec3::ZERO, key(1.0));
    // A camera turning about its target sees its distance, and the radius that is a share of
    // it, move by a rounding error: the ball lasts.
    let rounded = key(f32::from_bits(1.0f32.to_bits() - 1));
    assert!(matches!(next(ball, Vec3::new(0.5, 0.0, 0.0), rounded).0, BallUse::Continue { .. }));
    // A configured radius wider than the ball's begins a ball of its own.
    // Its levels are still held: the settings are the same.
    assert_eq!(
        next(ball, Vec3::new(0.5, 0.0, 0.0), key(2.0)).0,
        BallUse::Begin { radius: 2.0, fresh: false }
    );
}
