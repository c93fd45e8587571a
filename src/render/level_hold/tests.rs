use super::*;
use crate::test_rng::Rng;

/// The levels `estimates` give triangle `triangle` one after the other, held.
fn held(triangle: u32, estimates: &[f32]) -> Vec<f32> {
    let mut hold = LevelHold::default();
    estimates
        .iter()
        .map(|&estimate| {
            let (level, after) = held_level(triangle, estimate, hold);
            hold = after;
            level
        })
        .collect()
}

#[test]
fn a_higher_estimate_is_used_at_once_and_a_lower_one_after_it_held() {
    // Triangle 0 waits HOLD_ESTIMATES lower estimates, and then falls to the highest of them.
    assert_eq!(held(0, &[2.0, 5.0, 3.0, 4.0, 3.5]), vec![2.0, 5.0, 5.0, 5.0, 4.0]);
    // A higher estimate in between starts the wait again.
    assert_eq!(held(0, &[5.0, 3.0, 3.0, 6.0, 3.0, 3.0, 3.0]), vec![5.0, 5.0, 5.0, 6.0, 6.0, 6.0, 3.0]);
    // An equal estimate is not a lower one.
    assert_eq!(held(0, &[4.0, 4.0, 3.0, 4.0, 3.0, 3.0]), vec![4.0; 6]);
}

#[test]
fn the_wait_is_staggered_over_the_triangles() {
    let falls_after = |triangle| {
        let levels = held(triangle, &[8.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0]);
        levels.iter().position(|&level| level == 1.0).expect("it falls")
    };
    let waits: Vec<usize> = (0..HOLD_STAGGER).map(falls_after).collect();
    assert_eq!(waits, (0..HOLD_STAGGER).map(|k| (HOLD_ESTIMATES + k) as usize).collect::<Vec<_>>());
}

#[test]
fn levels_that_alternate_stay_at_the_higher() {
    let alternating: Vec<f32> = (0..20).map(|k| if k % 2 == 0 { 3.0 } else { 2.0 }).collect();
    assert!(held(1, &alternating).iter().all(|&level| level == 3.0));
}

#[test]
fn every_level_used_is_at_least_its_estimate_and_changes_less_often() {
    let mut rng = Rng(0x5eed_0000_0065);
    for triangle in 0..200 {
        let estimates: Vec<f32> = (0..40).map(|_| 1.0 + 6.0 * rng.f()).collect();
        let levels = held(triangle, &estimates);
        assert!(levels.iter().zip(&estimates).all(|(level, estimate)| level >= estimate));
        let changes = |values: &[f32]| values.windows(2).filter(|w| w[0] != w[1]).count();
        assert!(changes(&levels) < changes(&estimates), "triangle {triangle}");
        // Once it fell, a level is the highest estimate since it was last held.
        for (k, pair) in levels.windows(2).enumerate() {
            if pair[1] < pair[0] {
                let wait = hold_estimates(triangle) as usize;
                let since = &estimates[k + 2 - wait..=k + 1];
                assert_eq!(pair[1], since.iter().copied().fold(f32::MIN, f32::max));
            }
        }
    }
}
