use super::*;

fn constant(width: u32, height: u32, value: [f32; 4]) -> FloatImage {
    FloatImage { width, height, pixels: vec![value; (width * height) as usize] }
}

/// `image` showing triangle 1 on its covered pixels.
fn ids(image: &FloatImage) -> Vec<u32> {
    image.pixels.iter().map(|p| u32::from(p[3] > 0.0)).collect()
}

fn frame<'a>(image: &'a FloatImage, triangles: &'a [u32]) -> Frame<'a> {
    Frame { image, triangles }
}

#[test]
fn identical_images_have_no_error() {
    let mut image = constant(32, 24, [0.2, 0.5, 0.8, 1.0]);
    image.pixels[100] = [3.0, 0.0, 0.01, 1.0];
    let triangles = ids(&image);
    let error = image_error(frame(&image, &triangles), frame(&image, &triangles), 1.0);
    assert_eq!(error.l_inf, 0.0);
    assert_eq!(error.l_inf_same_triangle, 0.0);
    assert_eq!(error.other_triangle_pixels, 0);
    assert_eq!(error.mean_l2, 0.0);
    assert_eq!(error.psnr_db, f64::INFINITY);
    assert_eq!(error.flip, 0.0);
}

#[test]
fn one_differing_pixel() {
    let (width, height) = (40u32, 30u32);
    let reference = constant(width, height, [0.25, 0.25, 0.25, 1.0]);
    let mut test = reference.clone();
    test.pixels[7 * width as usize + 11] = [0.25, 0.75, 0.25, 1.0];
    let triangles = ids(&reference);
    let (reference, test) = (frame(&reference, &triangles), frame(&test, &triangles));
    let error = image_error(reference, test, 1.0);
    let count = f64::from(width * height);
    assert!((error.l_inf - 0.5).abs() < 1e-7, "{error:?}");
    assert_eq!(error.l_inf_same_triangle, error.l_inf, "the pixel shows the same triangle in both");
    assert_eq!(pixels_over(reference, test, 0.49), 1);
    assert_eq!(pixels_over(reference, test, 0.5), 0);
    assert!((error.mean_l2 - 0.5 / count).abs() < 1e-9, "{error:?}");
    let step = f64::from(display_value(0.75, 1.0)) - f64::from(display_value(0.25, 1.0));
    let expected_psnr = 10.0 * (255.0f64.powi(2) * 3.0 * count / step.powi(2)).log10();
    assert!((error.psnr_db - expected_psnr).abs() < 1e-9, "{error:?} vs {expected_psnr}");
    // FLIP spreads one pixel's error over its neighbourhood, but most pixels stay clean.
    assert!(error.flip > 0.0 && error.flip < 0.01, "{error:?}");
}

#[test]
fn constant_offset() {
    let reference = constant(16, 16, [0.1, 0.2, 0.3, 1.0]);
    let offset = 0.05;
    let test = constant(16, 16, [0.1 + offset, 0.2 + offset, 0.3 + offset, 1.0]);
    let triangles = ids(&reference);
    let error = image_error(frame(&reference, &triangles), frame(&test, &triangles), 1.0);
    assert!((error.l_inf - f64::from(offset)).abs() < 1e-6, "{error:?}");
    assert!((error.mean_l2 - f64::from(offset) * 3f64.sqrt()).abs() < 1e-6, "{error:?}");
    let mse: f64 = [0.1f32, 0.2, 0.3]
        .iter()
        .map(|&v| (f64::from(display_value(v + offset, 1.0)) - f64::from(display_value(v, 1.0))).powi(2))
        .sum::<f64>()
        / 3.0;
    assert!((error.psnr_db - 10.0 * (255.0f64.powi(2) / mse).log10()).abs() < 1e-9, "{error:?}");
    assert!(error.flip > 0.0, "{error:?}");
}

#[test]
fn only_pixels_showing_the_same_triangle_are_compared() {
    // Triangle 1 covers a 6×6 square on an empty background, triangle 2 its right half in
    // the test image only. The test image differs by 0.9 on a pixel of the square's border
    // that it leaves uncovered, by 0.7 on a pixel of the right half, by 0.1 inside.
    let mut reference = constant(10, 10, [0.0, 0.0, 0.0, 0.0]);
    let mut reference_ids = vec![0u32; 100];
    for y in 2..8 {
        for x in 2..8 {
            reference.pixels[y * 10 + x] = [0.5, 0.5, 0.5, 1.0];
            reference_ids[y * 10 + x] = 1;
        }
    }
    let (mut test, mut test_ids) = (reference.clone(), reference_ids.clone());
    test.pixels[2 * 10 + 4] = [1.4, 0.5, 0.5, 0.0];
    test_ids[2 * 10 + 4] = 0;
    for y in 2..8 {
        for x in 5..8 {
            test_ids[y * 10 + x] = 2;
        }
    }
    test.pixels[6 * 10 + 6][1] = 1.2;
    test.pixels[4 * 10 + 3][0] = 0.6;
    let (reference, test) = (frame(&reference, &reference_ids), frame(&test, &test_ids));
    let error = image_error(reference, test, 1.0);
    assert!((error.l_inf - 0.9).abs() < 1e-6, "{error:?}");
    assert!((error.l_inf_same_triangle - 0.1).abs() < 1e-6, "{error:?}");
    assert_eq!(error.other_triangle_pixels, 1 + 18, "{error:?}");
    assert_eq!(pixels_over(reference, test, 0.05), 1, "only the pixel inside counts");
}

#[test]
fn non_finite_values_are_infinite_error() {
    let reference = constant(4, 4, [0.5, 0.5, 0.5, 1.0]);
    let mut test = reference.clone();
    test.pixels[3][1] = f32::NAN;
    assert_eq!(l_inf(&reference, &test), f64::INFINITY);
    assert_eq!(mean_l2(&reference, &test), f64::INFINITY);
}

#[test]
fn scaled_difference_and_fallback_mask() {
    let reference = constant(2, 1, [0.5, 0.5, 0.5, 1.0]);
    let mut test = reference.clone();
    test.pixels[1] = [0.5, 0.4, 0.5, 1.0];
    let difference = scaled_difference(&reference, &test, 30.0);
    assert_eq!(difference.pixels[0], [0.0, 0.0, 0.0, 1.0]);
    assert!((difference.pixels[1][1] - 3.0).abs() < 1e-5);

    let heat = FloatImage {
        width: 3,
        height: 1,
        pixels: vec![[1.0, 0.0, 1.0, 1.0], [0.0, 0.2, 1.0, 1.0], [1.0, 0.0, 1.0, 0.0]],
    };
    let mask = fallback_mask(&heat);
    assert_eq!(fallback_pixels(&mask), 1, "only the covered magenta pixel");
    assert_eq!(mask.pixels[0][0], 1.0);
}
