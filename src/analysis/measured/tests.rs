use super::*;

fn image(width: u32, height: u32, value: impl Fn(usize) -> f32) -> FloatImage {
    let pixels = (0..(width * height) as usize).map(|i| [value(i), 0.0, 0.0, 1.0]).collect();
    FloatImage { width, height, pixels }
}

#[test]
fn measured_error_is_the_largest_interior_difference_per_triangle() {
    let (w, h) = (6u32, 4u32);
    // Left half triangle (0, 0), right half (0, 1).
    let ids: Vec<Option<(usize, usize)>> =
        (0..(w * h) as usize).map(|i| Some((0, usize::from(i % 6 >= 3)))).collect();
    let reference = image(w, h, |_| 0.5);
    // Interior pixels of the left triangle: x = 1 (x = 2 borders the right one).
    let multirate = image(w, h, |i| match i {
        7 => 0.6,   // (1, 1): interior, left
        13 => 0.3,  // (1, 2): interior, left, larger
        9 => 0.9,   // (3, 1): borders the left triangle, left out
        10 => 0.55, // (4, 1): interior, right
        _ => 0.5,
    });
    let measured = measured_errors(&multirate, &reference, &ids);
    assert!((measured[&(0, 0)].error - 0.2).abs() < 1e-6);
    assert_eq!(measured[&(0, 0)].pixels, 2);
    assert!((measured[&(0, 1)].error - 0.05).abs() < 1e-6);
}
