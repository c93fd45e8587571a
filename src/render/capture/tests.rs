//! Tests of `render::capture`: the effective-level table checked against captured patterns, built-in and measured.

use super::*;
use crate::shading::estimator::{pattern_level, pattern_level_entry as entry, PATTERN_LEVELS};

/// What a device that tessellates as `model` would capture.
fn as_captured(model: &Pattern) -> CapturedPattern {
    let at = |i: u32| model.vertices[i as usize].map(|x| x as f32);
    CapturedPattern {
        tess_coords: model.vertices.iter().map(|v| v.map(|x| x as f32)).collect(),
        triangles: model.triangles.iter().map(|t| [at(t[0]), at(t[2]), at(t[1])]).collect(),
    }
}

#[test]
fn the_model_captured_measures_the_built_in_table() {
    let n_max = 6;
    let levels = pattern_check_levels(n_max);
    let captured: Vec<_> =
        levels.iter().map(|&(inner, outer)| as_captured(&triangle_pattern(inner, outer))).collect();
    assert!(captured.iter().zip(&levels).all(|(c, &(i, o))| c.is(&triangle_pattern(i, o))));
    let words = measured_table("model", &levels, &captured, n_max).expect("the model's table holds");
    for inner in 1..=64 {
        for outer in 1..=64 {
            let built_in = entry(&PATTERN_LEVELS, inner, outer);
            assert_eq!((pattern_level(inner, outer) * 256.0) as u32, built_in);
            let expected = if inner <= n_max && outer <= n_max { built_in } else { 0 };
            assert_eq!(entry(&words, inner, outer), expected, "inner {inner}, outer {outer}");
        }
    }
}

#[test]
fn other_patterns_get_their_own_levels_or_are_refused() {
    // A device whose inner level 4 with outer 4 looks like the model's inner level 2.
    let n_max = 6;
    let levels = pattern_check_levels(n_max);
    let captured: Vec<_> = levels
        .iter()
        .map(|&(inner, outer)| {
            let inner = if inner == 4.0 && outer == [4.0; 3] { 2.0 } else { inner };
            as_captured(&triangle_pattern(inner, outer))
        })
        .collect();
    let words = measured_table("coarse", &levels, &captured, n_max).expect("a coarser table holds");
    assert_eq!(entry(&words, 4, 4), entry(&PATTERN_LEVELS, 2, 4));
    assert!(entry(&words, 4, 4) < entry(&PATTERN_LEVELS, 4, 4));
    assert_eq!(entry(&words, 5, 5), entry(&PATTERN_LEVELS, 5, 5));

    // A mixed pattern coarser than its edges' entries promise: refused, and named.
    let levels = vec![(2.0, [2.0; 3]), (2.0, [3.0; 3]), (2.0, [2.0, 2.0, 3.0])];
    let mut captured: Vec<_> =
        levels.iter().map(|&(inner, outer)| as_captured(&triangle_pattern(inner, outer))).collect();
    assert!(measured_table("model", &levels, &captured, 3).is_ok());
    captured[2] = as_captured(&triangle_pattern(1.0, [1.0; 3]));
    match measured_table("odd", &levels, &captured, 3) {
        Err(Error::Patterns { device, inner, outer }) => {
            assert_eq!((device.as_str(), inner, outer), ("odd", 2.0, [2.0, 2.0, 3.0]));
        }
        other => panic!("expected a refusal, got {other:?}"),
    }
}
