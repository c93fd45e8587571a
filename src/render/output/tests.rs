//! Tests of `render::output`: tone mapping and sRGB encoding.

use super::*;

#[test]
fn tone_map_is_monotonic_and_bounded() {
    let mut previous = 0u8;
    for i in 0..1000 {
        let v = display_value(i as f32 * 0.01, 1.0);
        assert!(v >= previous, "not monotonic at {i}");
        previous = v;
    }
    assert_eq!(display_value(0.0, 1.0), 0);
    assert_eq!(display_value(-5.0, 1.0), 0);
    assert_eq!(display_value(1.0e6, 1.0), 255);
    assert_eq!(display_value(f32::NAN, 1.0), 0, "NaN must not reach the file as garbage");
}

#[test]
fn srgb_matches_reference_points() {
    assert!((srgb_encode(0.5) - 0.735_356_6).abs() < 1e-6);
    assert!((srgb_encode(0.001) - 0.012_92).abs() < 1e-7);
}
