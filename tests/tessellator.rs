//! The tessellator model (`analysis::tessellator`) reproduces what the driver emits: the
//! distinct `gl_TessCoord` values and the triangles (with winding), for uniform levels
//! n = 1…16 and for mixed outer levels; the check the renderer runs before multirate's first
//! draw (`check_patterns`) passes here and tells patterns apart. Captured on the GPU with the
//! validation layer on.

mod common;

use common::{assert_validation_clean, validated_context};
use multirate::render::capture::TessellationCapture;

/// Driver coordinates are fixed point converted to float: equal within this.
const COORD_TOLERANCE: f32 = 1e-5;

#[test]
fn uniform_levels_emit_the_ring_pattern_counts() {
    let context = validated_context();
    let capture = TessellationCapture::new(&context).expect("capture pipeline");
    for n in 1..=16u32 {
        let captured = capture.capture(n as f32, [n as f32; 3]).expect("capture");
        let vertices = captured.distinct_vertices().len();
        let expected_vertices = (3 * (n as usize + 1).pow(2)).div_ceil(4);
        let expected_triangles = if n == 1 { 1 } else { 3 * (n as usize).pow(2) / 2 };
        eprintln!(
            "n = {n}: {} invocations, {vertices} distinct, {} triangles",
            captured.tess_coords.len(),
            captured.triangles.len()
        );
        assert_eq!(vertices, expected_vertices, "distinct vertices at n = {n}");
        assert_eq!(captured.triangles.len(), expected_triangles, "triangles at n = {n}");
        for c in &captured.tess_coords {
            assert!((c[0] + c[1] + c[2] - 1.0).abs() < COORD_TOLERANCE, "barycentric {c:?}");
        }
    }
    assert_validation_clean(&context);
}

use multirate::analysis::tessellator::triangle_pattern;
use multirate::render::capture::{check_patterns, measured_table, pattern_check_levels, PatternTable};
use multirate::shading::estimator::{pattern_level, pattern_level_entry as entry};

#[test]
fn model_reproduces_the_driver() {
    let context = validated_context();
    let capture = TessellationCapture::new(&context).expect("capture pipeline");
    let mut cases: Vec<(f32, [f32; 3])> = (1..=16).map(|n| (n as f32, [n as f32; 3])).collect();
    let levels = [1.0, 2.0, 3.0, 4.0, 7.0, 16.0];
    for &inner in &[1.0, 2.0, 5.0, 8.0] {
        for &a in &levels {
            for &b in &[1.0, 4.0, 16.0] {
                cases.push((inner, [a, b, 3.0]));
            }
        }
    }
    cases.extend([
        (2.3, [1.5, 3.01, 7.9]),
        (0.0, [2.0, 2.0, 2.0]),
        (4.0, [0.0, 3.0, 3.0]),
        (64.0, [64.0, 1.0, 33.0]),
    ]);
    for (inner, outer) in cases {
        let captured = capture.capture(inner, outer).expect("capture");
        let pattern = triangle_pattern(inner, outer);
        assert_eq!(
            captured.distinct_vertices().len(),
            pattern.vertices.len(),
            "vertices at inner {inner}, outer {outer:?}"
        );
        assert!(captured.is(&pattern), "vertices or triangles differ at inner {inner}, outer {outer:?}");
    }
    assert_validation_clean(&context);
}

#[test]
fn the_pattern_check_passes_here_and_sees_a_different_pattern() {
    let context = validated_context();
    let capture = TessellationCapture::new(&context).expect("capture pipeline");
    // A pattern is not another's: one outer level apart, or the winding reversed.
    let captured = capture.capture(3.0, [3.0, 2.0, 3.0]).expect("capture");
    assert!(captured.is(&triangle_pattern(3.0, [3.0, 2.0, 3.0])));
    assert!(!captured.is(&triangle_pattern(3.0, [3.0, 3.0, 3.0])), "one outer level apart");
    let mut mirrored = triangle_pattern(3.0, [3.0, 2.0, 3.0]);
    mirrored.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    assert!(!captured.is(&mirrored), "winding reversed");
    // Every level up to 16 (what the renderer checks before multirate's first draw).
    let levels = pattern_check_levels(16);
    assert_eq!(levels.len(), 16 * 16 + 16 * 3);
    let table = check_patterns(&context, 16).expect("lavapipe tessellates as the model");
    assert_eq!(table, PatternTable::Model, "lavapipe uses the built-in table");
    assert_validation_clean(&context);
}

/// The table a device that tessellated otherwise would get, measured here on lavapipe's own
/// captures: the built-in table's entries up to `n_max` (the measurement and the model agree).
#[test]
fn the_table_measured_on_this_device_is_the_built_in_one() {
    let context = validated_context();
    let capture = TessellationCapture::new(&context).expect("capture pipeline");
    let n_max = 8;
    let levels = pattern_check_levels(n_max);
    let captured: Vec<_> =
        levels.iter().map(|&(inner, outer)| capture.capture(inner, outer).expect("capture")).collect();
    let words = measured_table(&context.info.name, &levels, &captured, n_max).expect("the table holds");
    for inner in 1..=n_max {
        for outer in 1..=n_max {
            let measured = entry(&words, inner, outer);
            let built_in = (pattern_level(inner, outer) * 256.0).round() as u32;
            assert_eq!(measured, built_in, "inner {inner}, outer {outer}");
        }
    }
    assert_validation_clean(&context);
}
