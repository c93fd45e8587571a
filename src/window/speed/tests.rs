//! Tests of `window::speed`: the title's speed is the reference's time over the live one.

use super::speed_text;

#[test]
fn the_speed_is_the_reference_over_the_live_time() {
    assert_eq!(speed_text(80.0, 20.0), "4.00× pixel's speed (pixel 80.00 ms)");
    assert_eq!(speed_text(10.0, 40.0), "0.25× pixel's speed (pixel 10.00 ms)");
}
