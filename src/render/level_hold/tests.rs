use super::*;
use crate::shading::estimator::pattern_level;
use crate::test_rng::Rng;

const N_MAX: u32 = 16;

/// The effective level of the uniform pattern `n`: a level that asks for exactly that pattern.
fn of(n: u32) -> f32 {
    pattern_level(n, n)
}

/// The levels `estimates` give triangle `triangle` one after the other, held.
fn held(triangle: u32, estimates: &[f32]) -> Vec<f32> {
    let mut hold = LevelHold::default();
    estimates
        .iter()
        .map(|&estimate| {
            let (level, after) = held_level(triangle, estimate, hold, N_MAX);
            hold = after;
            level
        })
        .collect()
}

#[test]
fn patterns_grow_with_levels_and_per_pixel_is_above_them_all() {
    for n in 1..=N_MAX {
        assert_eq!(held_pattern(of(n), N_MAX), n);
    }
    assert_eq!(held_pattern(of(N_MAX) + 0.01, N_MAX), N_MAX + 1);
    assert_eq!(held_pattern(crate::shading::estimator::FALLBACK_LEVEL, N_MAX), N_MAX + 1);
}

#[test]
fn a_finer_level_is_used_at_once_and_a_coarser_one_after_it_held() {
    // Triangle 0 waits HOLD_ESTIMATES coarser estimates after a rise, then falls to the highest.
    let estimates = [of(2), of(5), of(3), of(4), of(3), of(2), of(1)];
    let expected = [of(2), of(5), of(5), of(5), of(4), of(2), of(1)];
    assert_eq!(held(0, &estimates), expected, "after the fall no hold is open: later falls at once");
    // An estimate of the held pattern starts the count again.
    let estimates = [of(2), of(5), of(3), of(5), of(3), of(3), of(3)];
    assert_eq!(held(0, &estimates), [of(2), of(5), of(5), of(5), of(5), of(5), of(3)]);
}

#[test]
fn the_wait_is_staggered_over_the_triangles() {
    let falls_after = |triangle| {
        let levels = held(triangle, &[of(1), of(8), of(1), of(1), of(1), of(1), of(1), of(1)]);
        levels.iter().skip(1).position(|&level| level == of(1)).expect("it falls")
    };
    let waits: Vec<usize> = (0..HOLD_STAGGER).map(falls_after).collect();
    assert_eq!(waits, (0..HOLD_STAGGER).map(|k| (HOLD_ESTIMATES + k) as usize).collect::<Vec<_>>());
}

#[test]
fn levels_that_alternate_stay_at_the_finer() {
    let alternating: Vec<f32> = (0..20).map(|k| if k % 2 == 0 { of(3) } else { of(2) }).collect();
    assert!(held(1, &alternating).iter().all(|&level| level == of(3)));
}

#[test]
fn every_level_used_is_at_least_its_estimate_and_changes_pattern_less_often() {
    let mut rng = Rng(0x5eed_0000_0065);
    for triangle in 0..200 {
        // A level drifting up and down, with noise that flips it between neighbouring patterns.
        let mut drift = 1.0 + 6.0 * rng.f();
        let estimates: Vec<f32> = (0..60)
            .map(|_| {
                drift = (drift + 0.6 * (rng.f() - 0.5)).clamp(1.0, 8.0);
                drift + 0.4 * rng.f()
            })
            .collect();
        let levels = held(triangle, &estimates);
        assert!(levels.iter().zip(&estimates).all(|(level, estimate)| level >= estimate));
        let changes = |values: &[f32]| {
            values.windows(2).filter(|w| held_pattern(w[0], N_MAX) != held_pattern(w[1], N_MAX)).count()
        };
        assert!(changes(&levels) <= changes(&estimates), "triangle {triangle}");
    }
}
