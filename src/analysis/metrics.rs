//! Image error against the per-pixel reference, at the same camera and resolution:
//! - L∞ and mean L2 on linear radiance (the paper's two; ε bounds the first per channel, on
//!   the pixels where both images show the same triangle),
//! - PSNR and FLIP on the tone-mapped 8-bit sRGB images a viewer sees (FLIP via `nv-flip`).
//!
//! Also the images that show where errors are: the difference scaled (×30 in the paper) and
//! the per-pixel fallback mask read off a heat-map render.

use crate::shading::tonemap::display_value;
use crate::vk::target::FloatImage;

/// An image and which triangle each of its pixels shows, as the analysis variant draws them
/// (`Renderer::analyze`: the triangle's scene index + 1, 0 where nothing is drawn).
#[derive(Clone, Copy, Debug)]
pub struct Frame<'a> {
    pub image: &'a FloatImage,
    pub triangles: &'a [u32],
}

impl Frame<'_> {
    /// Per pixel: whether `self` and `other` show the same triangle there (or both nothing).
    fn same_triangle<'b>(&'b self, other: &'b Frame<'_>) -> impl Iterator<Item = bool> + 'b {
        assert_same_size(self.image, other.image);
        let pixels = self.image.pixels.len();
        assert!(
            self.triangles.len() == pixels && other.triangles.len() == pixels,
            "one triangle id per pixel"
        );
        self.triangles.iter().zip(other.triangles).map(|(a, b)| a == b)
    }
}

/// Error of one image against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageError {
    /// Largest absolute difference of any RGB channel of any pixel (linear radiance); infinite
    /// when a value is not finite.
    pub l_inf: f64,
    /// L∞ over the pixels where both images show the same triangle: what ε bounds. It leaves
    /// out the pixels whose visible triangle differs (`other_triangle_pixels`), where two
    /// renders of the same scene may disagree without any shading error: on silhouettes a
    /// sub-triangle's rounded edge vertex can move a pixel centre to the other side of the
    /// edge, and where two surfaces meet at equal depth either may win.
    pub l_inf_same_triangle: f64,
    /// Pixels where the two images show different triangles (or only one shows any).
    pub other_triangle_pixels: usize,
    /// Mean over all pixels of the Euclidean distance of the RGB triples (linear radiance).
    pub mean_l2: f64,
    /// 10·log10(1 / MSE) of the display values in [0, 1]; infinite for identical images.
    pub psnr_db: f64,
    /// Mean FLIP error (LDR-FLIP at 67 pixels per degree) of the display images, in [0, 1].
    pub flip: f64,
}

/// All metrics of `test` against `reference` (equal sizes), tone-mapped with `exposure`.
pub fn image_error(reference: Frame<'_>, test: Frame<'_>, exposure: f32) -> ImageError {
    let reference_display = display_rgb(reference.image, exposure);
    let test_display = display_rgb(test.image, exposure);
    let (image, other) = (reference.image, test.image);
    ImageError {
        l_inf: l_inf(image, other),
        l_inf_same_triangle: l_inf_same_triangle(reference, test),
        other_triangle_pixels: reference.same_triangle(&test).filter(|same| !same).count(),
        mean_l2: mean_l2(image, other),
        psnr_db: psnr(&reference_display, &test_display),
        flip: flip(image.width, image.height, &reference_display, &test_display),
    }
}

fn assert_same_size(reference: &FloatImage, test: &FloatImage) {
    assert_eq!(
        (reference.width, reference.height),
        (test.width, test.height),
        "metrics compare images of one size"
    );
}

/// Per-channel absolute difference, infinite where either value is not finite.
fn channel_difference(a: f32, b: f32) -> f64 {
    let difference = (f64::from(a) - f64::from(b)).abs();
    if difference.is_finite() {
        difference
    } else {
        f64::INFINITY
    }
}

/// The largest RGB channel difference of two pixels.
fn pixel_difference(r: &[f32; 4], t: &[f32; 4]) -> f64 {
    (0..3).map(|c| channel_difference(r[c], t[c])).fold(0.0, f64::max)
}

/// Largest per-channel RGB difference.
pub fn l_inf(reference: &FloatImage, test: &FloatImage) -> f64 {
    assert_same_size(reference, test);
    reference.pixels.iter().zip(&test.pixels).map(|(r, t)| pixel_difference(r, t)).fold(0.0, f64::max)
}

/// Largest per-channel RGB difference over the pixels where both show the same triangle.
pub fn l_inf_same_triangle(reference: Frame<'_>, test: Frame<'_>) -> f64 {
    reference
        .same_triangle(&test)
        .zip(reference.image.pixels.iter().zip(&test.image.pixels))
        .filter(|(same, _)| *same)
        .map(|(_, (r, t))| pixel_difference(r, t))
        .fold(0.0, f64::max)
}

/// Pixels showing the same triangle in both where some RGB channel differs by more than
/// `bound`.
pub fn pixels_over(reference: Frame<'_>, test: Frame<'_>, bound: f64) -> usize {
    reference
        .same_triangle(&test)
        .zip(reference.image.pixels.iter().zip(&test.image.pixels))
        .filter(|(same, (r, t))| *same && pixel_difference(r, t) > bound)
        .count()
}

/// Mean RGB Euclidean distance per pixel.
pub fn mean_l2(reference: &FloatImage, test: &FloatImage) -> f64 {
    assert_same_size(reference, test);
    let total: f64 = reference
        .pixels
        .iter()
        .zip(&test.pixels)
        .map(|(r, t)| (0..3).map(|c| channel_difference(r[c], t[c]).powi(2)).sum::<f64>().sqrt())
        .sum();
    total / reference.pixels.len().max(1) as f64
}

/// The tone-mapped 8-bit sRGB triples of `image`, row by row.
pub fn display_rgb(image: &FloatImage, exposure: f32) -> Vec<u8> {
    image.pixels.iter().flat_map(|p| (0..3).map(move |c| display_value(p[c], exposure))).collect()
}

/// PSNR of two 8-bit images with the peak 255: 10·log10(255² / MSE).
pub fn psnr(reference: &[u8], test: &[u8]) -> f64 {
    assert_eq!(reference.len(), test.len(), "PSNR compares images of one size");
    let squared: f64 = reference.iter().zip(test).map(|(&r, &t)| (f64::from(r) - f64::from(t)).powi(2)).sum();
    let mse = squared / reference.len().max(1) as f64;
    if mse == 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64.powi(2) / mse).log10()
    }
}

/// Mean FLIP error of two 8-bit sRGB images of `width`×`height`.
pub fn flip(width: u32, height: u32, reference: &[u8], test: &[u8]) -> f64 {
    let reference = nv_flip::FlipImageRgb8::with_data(width, height, reference);
    let test = nv_flip::FlipImageRgb8::with_data(width, height, test);
    let map = nv_flip::flip(reference, test, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    f64::from(nv_flip::FlipPool::from_image(&map).mean())
}

/// |reference − test| × `scale` per RGB channel, alpha 1 (the paper shows errors ×30).
pub fn scaled_difference(reference: &FloatImage, test: &FloatImage, scale: f32) -> FloatImage {
    assert_same_size(reference, test);
    let pixels = reference
        .pixels
        .iter()
        .zip(&test.pixels)
        .map(|(r, t)| {
            let d = |c: usize| (r[c] - t[c]).abs() * scale;
            [d(0), d(1), d(2), 1.0]
        })
        .collect();
    FloatImage { width: reference.width, height: reference.height, pixels }
}

/// The colour the heat map gives per-pixel shading (`glsl/include/heat.glsl`); no level's
/// colour equals it.
pub const FALLBACK_HEAT_COLOR: [f32; 3] = [1.0, 0.0, 1.0];

/// White where a heat-map render shows per-pixel shading, black elsewhere (alpha 1).
pub fn fallback_mask(heat_map: &FloatImage) -> FloatImage {
    let pixels = heat_map
        .pixels
        .iter()
        .map(|p| {
            let fallback = p[3] > 0.0 && p[..3] == FALLBACK_HEAT_COLOR;
            let v = if fallback { 1.0 } else { 0.0 };
            [v, v, v, 1.0]
        })
        .collect();
    FloatImage { width: heat_map.width, height: heat_map.height, pixels }
}

/// Pixels of a fallback mask that are set.
pub fn fallback_pixels(mask: &FloatImage) -> usize {
    mask.pixels.iter().filter(|p| p[0] > 0.5).count()
}

#[cfg(test)]
mod tests;
