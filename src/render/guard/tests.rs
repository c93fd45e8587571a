//! Tests of `render::guard`: the probe schedule, the choice of the faster way as times come
//! back late, and one guard per configuration.

use super::*;

/// Draws `frames` frames with `guard`, each drawn way timed by `cost`, the times reported
/// `lag` frames after the frame was drawn (frames in flight); returns the ways drawn.
fn run(guard: &mut PathGuard, frames: usize, lag: usize, cost: impl Fn(FramePath) -> f64) -> Vec<FramePath> {
    let mut drawn = Vec::new();
    for frame in 0..frames + lag {
        if frame < frames {
            drawn.push(guard.next_frame());
        }
        if frame >= lag {
            let path = drawn[frame - lag];
            guard.record(path, cost(path));
        }
    }
    drawn
}

fn count(drawn: &[FramePath], path: FramePath) -> usize {
    drawn.iter().filter(|&&p| p == path).count()
}

/// Whether `frames` alternate between the way other than `choice` and `choice`, the other first.
fn alternates(frames: &[FramePath], choice: FramePath) -> bool {
    frames.iter().enumerate().all(|(k, &p)| (p != choice) == (k % 2 == 0))
}

#[test]
fn a_guard_starts_the_multirate_way_then_probes_pixel_frame_by_frame() {
    let mut guard = PathGuard::default();
    let first: Vec<FramePath> = (0..3 * PROBE_FRAMES).map(|_| guard.next_frame()).collect();
    let probe = PROBE_FRAMES as usize;
    assert!(first[..probe].iter().all(|&p| p == FramePath::Multirate), "{first:?}");
    assert!(alternates(&first[probe..], FramePath::Multirate), "{first:?}");
    assert_eq!(count(&first[probe..], FramePath::Pixel), probe, "{first:?}");
    // Without times it keeps multirate.
    assert_eq!(guard.next_frame(), FramePath::Multirate);
}

/// The frames at which probes began, each checked to alternate the ways.
fn probe_starts(drawn: &[FramePath]) -> Vec<usize> {
    let probe = 2 * PROBE_FRAMES as usize;
    let mut choice = FramePath::Multirate;
    let mut starts = Vec::new();
    let mut k = 0;
    while k + probe <= drawn.len() {
        if drawn[k] == choice {
            k += 1;
            continue;
        }
        // Its last frame, the chosen way's, is drawn the way it chose where the times of its
        // other way came back before it was drawn.
        assert!(alternates(&drawn[k..k + probe - 1], choice), "the probe at {k}: {:?}", &drawn[k..k + probe]);
        starts.push(k);
        // The frames after a probe are drawn the way it chose, from the second on (with times
        // two frames late, the first is drawn before the probe's last time is back).
        k += probe + 1;
        if let Some(&after) = drawn.get(k) {
            choice = after;
        }
    }
    starts
}

#[test]
fn a_guard_keeps_the_faster_way_and_probes_ever_more_rarely_while_it_stays_faster() {
    let frames = 2 * LONGEST_GAP as usize;
    for lag in [0, 1, 2] {
        for (faster, slower) in
            [(FramePath::Multirate, FramePath::Pixel), (FramePath::Pixel, FramePath::Multirate)]
        {
            let mut guard = PathGuard::default();
            let drawn = run(&mut guard, frames, lag, |p| if p == faster { 10.0 } else { 30.0 });
            assert_eq!(guard.choice(), faster, "lag {lag}");
            let starts = probe_starts(&drawn);
            let gaps: Vec<usize> = starts.windows(2).map(|w| w[1] - w[0]).collect();
            // Gaps of 120, 240, ..., 1920 frames (plus the probe's own), then 1920.
            assert!(gaps.windows(2).all(|w| w[1] >= w[0]), "lag {lag}: {gaps:?}");
            assert!(gaps.len() >= 4 && gaps.len() <= 7, "lag {lag}: {gaps:?}");
            assert!(*gaps.last().unwrap() >= LONGEST_GAP as usize, "lag {lag}: {gaps:?}");
            // Frames drawn the slower way: PROBE_FRAMES in each probe, and where multirate is
            // the slower, its first frames, and the first probe's last frame and those after it
            // drawn before its last time came back (one frame fewer than the lag).
            let slow = count(&drawn, slower);
            let first = if slower == FramePath::Multirate { PROBE_FRAMES as usize + lag - 1 } else { 0 };
            assert_eq!(slow, first + PROBE_FRAMES as usize * starts.len(), "lag {lag}");
        }
    }
}

#[test]
fn a_close_race_is_probed_every_reprobe_gap() {
    let mut guard = PathGuard::default();
    let frames = 8 * REPROBE_EVERY as usize;
    let drawn = run(&mut guard, frames, 2, |p| if p == FramePath::Multirate { 10.0 } else { 11.0 });
    assert_eq!(guard.choice(), FramePath::Multirate);
    let probes = count(&drawn, FramePath::Pixel) / PROBE_FRAMES as usize;
    assert!((7..=9).contains(&probes), "{probes} probes in {frames} frames");
}

#[test]
fn a_guard_probes_at_once_when_the_chosen_way_slows_down() {
    let mut guard = PathGuard::default();
    run(&mut guard, 4 * REPROBE_EVERY as usize, 2, |p| if p == FramePath::Multirate { 10.0 } else { 30.0 });
    assert_eq!(guard.choice(), FramePath::Multirate);
    // The camera moved: multirate now loses, long before the next probe was due.
    let drawn =
        run(
            &mut guard,
            4 * PROBE_FRAMES as usize,
            2,
            |p| if p == FramePath::Multirate { 40.0 } else { 30.0 },
        );
    assert_eq!(guard.choice(), FramePath::Pixel, "{drawn:?}");
}

#[test]
fn a_guard_decides_once_the_probe_is_in_by_the_fastest_recent_frames() {
    let mut guard = PathGuard::default();
    for ms in [50.0, 12.0, 12.0] {
        guard.record(FramePath::Multirate, ms);
    }
    guard.record(FramePath::Pixel, 11.0);
    guard.record(FramePath::Pixel, 13.0);
    assert_eq!(guard.choice(), FramePath::Multirate, "the probe is not in yet");
    assert!(!guard.decided());
    guard.record(FramePath::Pixel, 14.0);
    assert_eq!(guard.choice(), FramePath::Pixel, "pixel's fastest, 11 ms, beats multirate's 12 ms");
    assert!(guard.decided());
    // Pixel's own frames then slow down: no switch without a probe of multirate.
    for ms in [20.0, 20.0, 20.0] {
        guard.record(FramePath::Pixel, ms);
    }
    assert_eq!(guard.choice(), FramePath::Pixel);
    for ms in [20.0, 20.0, 20.0] {
        guard.record(FramePath::Multirate, ms);
    }
    assert_eq!(guard.choice(), FramePath::Multirate, "20 ms each way: a tie keeps multirate");
}

#[test]
fn a_guard_ignores_unwritten_times() {
    let mut guard = PathGuard::default();
    for _ in 0..PROBE_FRAMES {
        guard.record(FramePath::Multirate, 20.0);
        guard.record(FramePath::Pixel, f64::NAN);
        guard.record(FramePath::Pixel, 0.0);
        guard.record(FramePath::Pixel, -1.0);
        guard.record(FramePath::Pixel, f64::INFINITY);
    }
    assert_eq!(guard.choice(), FramePath::Multirate);
}

#[test]
fn guards_are_kept_per_configuration_and_not_per_camera() {
    use crate::render::Mode;
    let path = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/bunny.toml"));
    let scene = crate::scene::Scene::load(path).expect("the bunny loads");
    let view = View { mode: Mode::Multirate, cost_model: true, ..View::of_scene(&scene) };
    let config = |view: &View, width| MultirateConfig {
        placement: view.placement,
        estimator: view.estimator,
        extent: (width, 48),
        hold_levels: view.hold_levels,
    };
    let key = key_of(&view, &config(&view, 64)).expect("a multirate view with the cost model is guarded");
    let mut moved = view.clone();
    moved.camera.eye += glam::Vec3::X;
    assert_eq!(key_of(&moved, &config(&moved, 64)), Some(key));
    let nearer = view.with_eye_ball(0.5 * crate::render::EYE_BALL_SHARE);
    assert_eq!(key_of(&nearer, &config(&nearer, 64)), Some(key), "the ball of eyes follows the camera");
    let mut finer = view.clone();
    finer.estimator.epsilon *= 0.5;
    assert_ne!(key_of(&finer, &config(&finer, 64)), Some(key));
    assert_ne!(key_of(&view, &config(&view, 65)), Some(key));
    for unguarded in [
        View { cost_model: false, ..view.clone() },
        View { heat_map: true, ..view.clone() },
        View { wireframe: true, ..view.clone() },
        View { mode: Mode::Pixel, ..view.clone() },
    ] {
        assert_eq!(key_of(&unguarded, &config(&unguarded, 64)), None, "{unguarded:?}");
    }
    let mut guards = Guards::default();
    for _ in 0..PROBE_FRAMES {
        guards.of(key).record(FramePath::Multirate, 30.0);
        guards.of(key).record(FramePath::Pixel, 10.0);
    }
    assert_eq!(guards.of(key).choice(), FramePath::Pixel);
    let other = key_of(&finer, &config(&finer, 64)).expect("guarded");
    assert_eq!(guards.of(other).choice(), FramePath::Multirate, "a new configuration starts afresh");
    assert_eq!(guards.of(key).choice(), FramePath::Pixel, "the first keeps its choice");
}

#[test]
fn only_a_lasting_change_that_may_flip_the_choice_sets_off_a_probe() {
    let mut guard = PathGuard::default();
    run(&mut guard, REPROBE_EVERY as usize, 0, |p| if p == FramePath::Multirate { 10.0 } else { 30.0 });
    assert_eq!(guard.choice(), FramePath::Multirate);
    let mut frames = |times: &[f64]| -> Vec<FramePath> {
        times
            .iter()
            .map(|&ms| {
                let path = guard.next_frame();
                guard.record(path, ms);
                path
            })
            .collect()
    };
    // A frame much faster (it reused its levels) or much slower (the machine was busy) than the
    // rest, each among frames as before: no probe.
    let odd = frames(&[10.0, 4.0, 10.0, 10.0, 40.0, 10.0, 10.0, 10.0]);
    assert!(odd.iter().all(|&p| p == FramePath::Multirate), "{odd:?}");
    // Slower by more than the factor, but faster than pixel was when multirate won: no probe.
    let slower = frames(&[25.0; 2 * PROBE_FRAMES as usize]);
    assert!(slower.iter().all(|&p| p == FramePath::Multirate), "{slower:?}");
    frames(&[10.0; PROBE_FRAMES as usize]);
    // Every frame of the latest three faster by more than the factor: the next frame probes.
    let lasting = frames(&[10.0 / (MOVED + 0.5); PROBE_FRAMES as usize]);
    assert!(lasting.iter().all(|&p| p == FramePath::Multirate), "{lasting:?}");
    assert_eq!(guard.next_frame(), FramePath::Pixel, "a lasting change probes at once");
}
