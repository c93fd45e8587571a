//! Writing rendered images: PNG (exposure, ACES filmic tone map, sRGB, 8 bits), OpenEXR
//! (linear float RGB, alpha = geometric coverage) and the post chain's display images (PNG). The tone map lives in
//! [`crate::shading::tonemap`].

use crate::error::{Error, Result};
pub use crate::shading::tonemap::{aces_filmic, display_value, srgb_encode};
use crate::vk::target::FloatImage;
use std::path::Path;

/// The tone-mapped 8-bit RGBA image (alpha = coverage).
pub fn tone_mapped(image: &FloatImage, exposure: f32) -> image::RgbaImage {
    let mut out = image::RgbaImage::new(image.width, image.height);
    for (pixel, value) in out.pixels_mut().zip(&image.pixels) {
        *pixel = image::Rgba([
            display_value(value[0], exposure),
            display_value(value[1], exposure),
            display_value(value[2], exposure),
            (value[3].clamp(0.0, 1.0) * 255.0 + 0.5) as u8,
        ]);
    }
    out
}

/// Writes `image` to `path`; the extension picks the format (`.png` or `.exr`).
pub fn write_image(image: &FloatImage, path: &Path, exposure: f32) -> Result<()> {
    let fail = |message: String| Error::Output { path: path.to_path_buf(), message };
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("png") => {
            // PNG keeps opaque colour so viewers show the clear colour; coverage is in the EXR.
            let mut rgba = tone_mapped(image, exposure);
            rgba.pixels_mut().for_each(|p| p.0[3] = 255);
            rgba.save_with_format(path, image::ImageFormat::Png)
                .map_err(|e| fail(format!("cannot write PNG: {e}")))
        }
        Some("exr") => {
            let data: Vec<f32> = image.pixels.iter().flatten().copied().collect();
            let buffer = image::Rgba32FImage::from_raw(image.width, image.height, data)
                .expect("pixel count matches the size");
            buffer
                .save_with_format(path, image::ImageFormat::OpenExr)
                .map_err(|e| fail(format!("cannot write OpenEXR: {e}")))
        }
        _ => Err(fail("unknown image format: use a .png or .exr file name".into())),
    }
}

/// Writes a display image, its values already tone mapped and encoded in [0, 1] (as the post
/// chain, `render::post`, writes them), as an opaque 8-bit PNG.
pub fn write_display_png(image: &FloatImage, path: &Path) -> Result<()> {
    let mut rgb = image::RgbImage::new(image.width, image.height);
    let byte = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
    for (pixel, value) in rgb.pixels_mut().zip(&image.pixels) {
        *pixel = image::Rgb([byte(value[0]), byte(value[1]), byte(value[2])]);
    }
    rgb.save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| Error::Output { path: path.to_path_buf(), message: format!("cannot write PNG: {e}") })
}

/// Writes a data image (error, level map, mask) as an 8-bit sRGB PNG without the tone curve:
/// values are clamped to [0, 1], so the colours are exactly those computed.
pub fn write_data_png(image: &FloatImage, path: &Path) -> Result<()> {
    let mut rgb = image::RgbImage::new(image.width, image.height);
    let encode = |v: f32| (srgb_encode(v.clamp(0.0, 1.0)) * 255.0 + 0.5) as u8;
    for (pixel, value) in rgb.pixels_mut().zip(&image.pixels) {
        *pixel = image::Rgb([encode(value[0]), encode(value[1]), encode(value[2])]);
    }
    rgb.save_with_format(path, image::ImageFormat::Png)
        .map_err(|e| Error::Output { path: path.to_path_buf(), message: format!("cannot write PNG: {e}") })
}

#[cfg(test)]
mod tests;
