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
        eprintln!("n = {n}: {} invocations, {vertices} distinct, {} triangles", captured.tess_coords.len(), captured.triangles.len());
        assert_eq!(vertices, expected_vertices, "distinct vertices at n = {n}");
        assert_eq!(captured.triangles.len(), expected_triangles, "triangles at n = {n}");
        for c in &captured.tess_coords {
            assert!((c[0] + c[1] + c[2] - 1.0).abs() < COORD_TOLERANCE, "barycentric {c:?}");
        }
    }
    assert_validation_clean(&context);
}
