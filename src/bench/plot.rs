//! SVG charts of benchmark rows (plotters): scatter series with labelled points, optional
//! lines through each series, a logarithmic x axis, and the Pareto front (no other point is
//! both faster and more accurate) marked across all series.

use super::row::Row;
use crate::error::{Error, Result};
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// One point of a series, optionally labelled on the chart.
#[derive(Clone, Debug)]
pub struct Point {
    pub x: f64,
    pub y: f64,
    pub label: Option<String>,
}

/// Points drawn in one colour.
#[derive(Clone, Debug)]
pub struct Series {
    pub name: String,
    pub points: Vec<Point>,
    /// Join the points (in x order) with a line.
    pub line: bool,
}

/// A chart and what its axes mean.
pub struct Chart<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: Vec<Series>,
    /// Mark the points no other point beats in both x and y (both lower is better).
    pub pareto: bool,
    pub x_log: bool,
}

/// The points no other point dominates (lower or equal x and y, one strictly lower), sorted
/// by x.
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted: Vec<(f64, f64)> =
        points.iter().copied().filter(|(x, y)| x.is_finite() && y.is_finite()).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for point in sorted {
        if front.last().is_none_or(|last| point.1 < last.1) {
            front.push(point);
        }
    }
    front
}

const COLORS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(23, 190, 207),
];

/// Draws `chart` into an SVG file at `path`.
pub fn draw(chart: &Chart<'_>, path: &Path) -> Result<()> {
    draw_svg(chart, path).map_err(|message| Error::Output { path: path.to_path_buf(), message })
}

fn draw_svg(chart: &Chart<'_>, path: &Path) -> std::result::Result<(), String> {
    let map_x = |x: f64| if chart.x_log { x.max(f64::MIN_POSITIVE).log10() } else { x };
    let all: Vec<(f64, f64)> = chart
        .series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| (map_x(p.x), p.y)))
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    if all.is_empty() {
        return Err("nothing to plot: no finite points".into());
    }
    let (mut x0, mut x1, mut y0, mut y1) = all.iter().fold(
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY),
        |(a, b, c, d), &(x, y)| (a.min(x), b.max(x), c.min(y), d.max(y)),
    );
    let pad = |lo: f64, hi: f64| {
        let span = (hi - lo).max(hi.abs() * 0.1).max(1e-9);
        (lo - 0.08 * span, hi + 0.12 * span)
    };
    (x0, x1) = pad(x0, x1);
    (y0, y1) = pad(y0, y1);
    if !chart.x_log {
        x0 = x0.max(0.0).min(all.iter().map(|p| p.0).fold(f64::INFINITY, f64::min));
    }
    y0 = y0.max(0.0).min(all.iter().map(|p| p.1).fold(f64::INFINITY, f64::min));

    let root = SVGBackend::new(path, (900, 600)).into_drawing_area();
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let mut context = ChartBuilder::on(&root)
        .caption(chart.title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(e)?;
    let x_format = |v: &f64| if chart.x_log { format!("{:.0}", 10f64.powf(*v)) } else { format!("{v:.3}") };
    context
        .configure_mesh()
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(215, 215, 215))
        .x_desc(chart.x_label)
        .y_desc(chart.y_label)
        .x_label_formatter(&x_format)
        .y_label_formatter(&|v| format!("{v:.3}"))
        .draw()
        .map_err(e)?;
    for (index, series) in chart.series.iter().enumerate() {
        let color = COLORS[index % COLORS.len()];
        let mut points: Vec<(f64, f64, Option<String>)> = series
            .points
            .iter()
            .map(|p| (map_x(p.x), p.y, p.label.clone()))
            .filter(|(x, y, _)| x.is_finite() && y.is_finite())
            .collect();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        if series.line {
            context
                .draw_series(LineSeries::new(points.iter().map(|p| (p.0, p.1)), color.stroke_width(2)))
                .map_err(e)?;
        }
        context
            .draw_series(points.iter().map(|p| Circle::new((p.0, p.1), 5, color.filled())))
            .map_err(e)?
            .label(series.name.as_str())
            .legend(move |(x, y)| Circle::new((x, y), 5, color.filled()));
        context
            .draw_series(points.iter().filter_map(|p| {
                p.2.as_ref().map(|label| Text::new(label.clone(), (p.0, p.1), ("sans-serif", 13).into_font()))
            }))
            .map_err(e)?;
    }
    if chart.pareto {
        let front = pareto_front(&all);
        let red = RGBColor(214, 39, 40);
        context
            .draw_series(LineSeries::new(front.iter().copied(), red.stroke_width(1)))
            .map_err(e)?
            .label("Pareto front")
            .legend(move |(x, y)| PathElement::new(vec![(x - 8, y), (x + 8, y)], red.stroke_width(2)));
        context.draw_series(front.iter().map(|&p| Circle::new(p, 9, red.stroke_width(2)))).map_err(e)?;
    }
    finish(&mut context, &root)
}

/// Grouped bars: for each category (x), one bar per series, `values[series][category]`.
pub fn bars(
    title: &str,
    y_label: &str,
    categories: &[String],
    series: &[(String, Vec<f64>)],
    path: &Path,
) -> Result<()> {
    bars_svg(title, y_label, categories, series, path)
        .map_err(|message| Error::Output { path: path.to_path_buf(), message })
}

fn bars_svg(
    title: &str,
    y_label: &str,
    categories: &[String],
    series: &[(String, Vec<f64>)],
    path: &Path,
) -> std::result::Result<(), String> {
    let top =
        series.iter().flat_map(|(_, v)| v.iter().copied()).filter(|v| v.is_finite()).fold(0.0, f64::max);
    let root = SVGBackend::new(path, (900, 560)).into_drawing_area();
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let mut context = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(16)
        .x_label_area_size(40)
        .y_label_area_size(72)
        .build_cartesian_2d(0.0..categories.len() as f64, 0.0..top.max(1e-9) * 1.15)
        .map_err(e)?;
    let names = categories.to_vec();
    context
        .configure_mesh()
        .disable_x_mesh()
        .light_line_style(RGBColor(240, 240, 240))
        .bold_line_style(RGBColor(215, 215, 215))
        .y_desc(y_label)
        .x_labels(categories.len() * 2 + 1)
        .x_label_formatter(&move |v| {
            let index = (v - 0.5).round();
            if (v - 0.5 - index).abs() < 1e-6 && index >= 0.0 {
                names.get(index as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .y_label_formatter(&|v| format!("{v:.2}"))
        .draw()
        .map_err(e)?;
    let width = 0.8 / series.len().max(1) as f64;
    for (index, (name, values)) in series.iter().enumerate() {
        let color = COLORS[index % COLORS.len()];
        context
            .draw_series(values.iter().enumerate().filter(|(_, v)| v.is_finite()).map(
                |(category, &value)| {
                    let x = category as f64 + 0.1 + width * index as f64;
                    Rectangle::new([(x, 0.0), (x + width * 0.9, value)], color.filled())
                },
            ))
            .map_err(e)?
            .label(name.as_str())
            .legend(move |(x, y)| Rectangle::new([(x - 5, y - 5), (x + 5, y + 5)], color.filled()));
    }
    finish(&mut context, &root)
}

type Svg<'a> = SVGBackend<'a>;
type Context2d<'a> = ChartContext<'a, Svg<'a>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Draws the legend and writes the file.
fn finish<'a>(
    context: &mut Context2d<'a>,
    root: &DrawingArea<Svg<'a>, Shift>,
) -> std::result::Result<(), String> {
    let e = |e: DrawingAreaErrorKind<_>| e.to_string();
    context
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)
}

/// Collects named points into series, in the order the names first appear.
pub fn group(points: impl IntoIterator<Item = (String, Point)>, line: bool) -> Vec<Series> {
    let mut series: Vec<Series> = Vec::new();
    for (name, point) in points {
        match series.iter_mut().find(|s| s.name == name) {
            Some(existing) => existing.points.push(point),
            None => series.push(Series { name, points: vec![point], line }),
        }
    }
    series
}

/// The label of a row on a chart: the mode, with ε and n_max for multirate (and whether its
/// levels were held, where they were: not by default).
pub fn row_label(row: &Row) -> String {
    let area = row.min_estimated_area.map_or_else(String::new, |a| format!(" a={a:.0}"));
    let area = if row.levels_held == Some(true) { format!("{area} held") } else { area };
    match (row.epsilon, row.n_max, &row.estimator) {
        (Some(epsilon), Some(n_max), Some(estimator)) => format!("ε={epsilon} n={n_max} {estimator}{area}"),
        (Some(epsilon), Some(n_max), None) => format!("ε={epsilon} n={n_max}"),
        _ => row.mode.clone(),
    }
}

/// GPU time (median) against an error metric, one series per scene and resolution, with the
/// Pareto front: the bench command's trade plots.
pub fn time_against_error(
    rows: &[Row],
    metric: &str,
    error: impl Fn(&Row) -> f64,
    path: &Path,
) -> Result<()> {
    let series = group(
        rows.iter().map(|row| {
            let name = format!("{} {}x{}", row.scene, row.width, row.height);
            (name, Point { x: error(row), y: row.gpu_ms.median, label: Some(row_label(row)) })
        }),
        false,
    );
    let title = format!("GPU time against {metric} ({})", rows.first().map_or("", |r| r.device.as_str()));
    draw(
        &Chart {
            title: &title,
            x_label: metric,
            y_label: "GPU ms per frame (median)",
            series,
            pareto: true,
            x_log: false,
        },
        path,
    )
}

#[cfg(test)]
mod tests;
