//! Per-triangle measured error (the paper's Fig. 12): from a multirate image, the per-pixel
//! reference and the visibility buffer's triangle ids, the largest difference over each
//! triangle's pixels, set beside the error the estimator predicted.

use crate::error::{Error, Result};
use crate::vk::target::FloatImage;
use plotters::prelude::*;
use std::collections::HashMap;
use std::path::Path;

/// The measured error of one triangle.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measured {
    /// max over the triangle's interior pixels and the colour channels of |multirate − reference|.
    pub error: f32,
    /// How many interior pixels it was taken over.
    pub pixels: u32,
}

/// Per `(mesh, triangle)`: the largest |image − reference| (linear, any channel) over the
/// triangle's *interior* pixels, those whose four neighbours show the same triangle. Edge
/// pixels are left out: there the two images may see different triangles (rasterisation of
/// the tessellated against the untessellated surface), which is visibility, not shading.
pub fn measured_errors(
    image: &FloatImage,
    reference: &FloatImage,
    ids: &[Option<(usize, usize)>],
) -> HashMap<(usize, usize), Measured> {
    let (w, h) = (image.width as usize, image.height as usize);
    let mut out: HashMap<(usize, usize), Measured> = HashMap::new();
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            let i = y * w + x;
            let Some(id) = ids[i] else { continue };
            if [i - 1, i + 1, i - w, i + w].iter().any(|&j| ids[j] != Some(id)) {
                continue;
            }
            let (m, r) = (image.pixels[i], reference.pixels[i]);
            let error = (0..3).map(|c| (m[c] - r[c]).abs()).fold(0.0, f32::max);
            let entry = out.entry(id).or_default();
            entry.error = entry.error.max(error);
            entry.pixels += 1;
        }
    }
    out
}

/// A log-log scatter of `(predicted, measured)` per triangle with the line measured =
/// predicted (a sound bound keeps every point below it) and the line of ε.
pub fn scatter_svg(points: &[(f64, f64)], epsilon: f64, title: &str, path: &Path) -> Result<()> {
    draw(points, epsilon, title, path).map_err(|message| Error::Output { path: path.to_path_buf(), message })
}

fn draw(points: &[(f64, f64)], epsilon: f64, title: &str, path: &Path) -> std::result::Result<(), String> {
    let floor = 1e-6;
    let shown: Vec<(f64, f64)> = points
        .iter()
        .filter(|(p, m)| p.is_finite() && m.is_finite() && *p > 0.0)
        .map(|&(p, m)| (p.max(floor).log10(), m.max(floor).log10()))
        .collect();
    if shown.is_empty() {
        return Err("nothing to plot: no tessellated triangle was measured".into());
    }
    let lo = shown.iter().flat_map(|&(a, b)| [a, b]).fold(f64::MAX, f64::min).floor();
    let hi = shown.iter().flat_map(|&(a, b)| [a, b]).fold(f64::MIN, f64::max).max(epsilon.log10()).ceil();
    let root = SVGBackend::new(path, (720, 640)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| e.to_string())?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(56)
        .build_cartesian_2d(lo..hi, lo..hi)
        .map_err(|e| e.to_string())?;
    chart
        .configure_mesh()
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(215, 215, 215))
        .x_desc("predicted error (log10, linear radiance)")
        .y_desc("measured error (log10)")
        .draw()
        .map_err(|e| e.to_string())?;
    chart
        .draw_series(LineSeries::new([(lo, lo), (hi, hi)], BLACK.stroke_width(1)))
        .map_err(|e| e.to_string())?
        .label("measured = predicted")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK));
    let e = epsilon.log10();
    let red = RGBColor(200, 30, 30);
    chart
        .draw_series(LineSeries::new([(lo, e), (hi, e)], red.stroke_width(1)))
        .map_err(|e| e.to_string())?
        .label("ε")
        .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], red));
    let blue = RGBColor(31, 119, 180);
    chart
        .draw_series(shown.iter().map(|&(x, y)| Circle::new((x, y), 2, blue.mix(0.5).filled())))
        .map_err(|e| e.to_string())?
        .label("tessellated triangle")
        .legend(move |(x, y)| Circle::new((x + 8, y), 3, blue.filled()));
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE)
        .draw()
        .map_err(|e| e.to_string())?;
    root.present().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests;
