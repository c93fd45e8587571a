//! The tessellator model (`analysis::tessellator`) reproduces what the driver emits: the
//! distinct `gl_TessCoord` values and the triangles (with winding), for uniform levels
//! n = 1…16 and for mixed outer levels. Captured on the GPU with the validation layer on.

mod common;

use common::{assert_validation_clean, validated_context};
use multirate::render::capture::{CapturedPattern, TessellationCapture};

/// Driver coordinates are fixed point converted to float: equal within this.
const COORD_TOLERANCE: f32 = 1e-5;

fn key(c: [f32; 3]) -> [i64; 3] {
    c.map(|x| (x as f64 * 65536.0).round() as i64)
}

fn distinct(captured: &CapturedPattern) -> Vec<[i64; 3]> {
    let mut keys: Vec<_> = captured.tess_coords.iter().map(|&c| key(c)).collect();
    keys.sort();
    keys.dedup();
    keys
}

#[test]
fn uniform_levels_emit_the_ring_pattern_counts() {
    let context = validated_context();
    let capture = TessellationCapture::new(&context).expect("capture pipeline");
    for n in 1..=16u32 {
        let captured = capture.capture(n as f32, [n as f32; 3]).expect("capture");
        let vertices = distinct(&captured).len();
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

use multirate::analysis::tessellator::{triangle_pattern, Pattern};

type Corner = [i64; 3];

/// A triangle with its corners rotated so the smallest comes first (winding kept).
fn canonical(mut t: [Corner; 3]) -> [Corner; 3] {
    let first = (0..3).min_by_key(|&k| t[k]).expect("three corners");
    t.rotate_left(first);
    t
}

/// The model's triangles as the capture sees them. The model lists corners in D3D's
/// clockwise order; the capture's evaluation shader declares `ccw` with Vulkan's upper-left
/// domain origin, which emits the same triangles with the last two corners swapped.
fn model_triangles(pattern: &Pattern) -> Vec<[Corner; 3]> {
    let corner = |i: u32| pattern.vertices[i as usize].map(|x| (x * 65536.0).round() as i64);
    let mut triangles: Vec<_> =
        pattern.triangles.iter().map(|t| canonical([corner(t[0]), corner(t[2]), corner(t[1])])).collect();
    triangles.sort();
    triangles
}

fn captured_triangles(captured: &CapturedPattern) -> Vec<[Corner; 3]> {
    let mut triangles: Vec<_> = captured.triangles.iter().map(|t| canonical(t.map(key))).collect();
    triangles.sort();
    triangles
}

fn model_vertices(pattern: &Pattern) -> Vec<Corner> {
    let mut keys: Vec<_> = pattern.vertices.iter().map(|v| v.map(|x| (x * 65536.0).round() as i64)).collect();
    keys.sort();
    keys
}

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
            distinct(&captured),
            model_vertices(&pattern),
            "vertices at inner {inner}, outer {outer:?}"
        );
        assert_eq!(
            captured_triangles(&captured),
            model_triangles(&pattern),
            "triangles at inner {inner}, outer {outer:?}"
        );
    }
    assert_validation_clean(&context);
}
