//! SVG plots of the report (plotters, SVG backend; text is laid out with plotters' built-in
//! estimate, no system fonts, so the files are byte-for-byte reproducible).
use crate::error::{Error, Result};
use plotters::prelude::*;

pub(crate) fn err<E: std::fmt::Display>(what: &str) -> impl Fn(E) -> Error + '_ {
    move |e| Error::Plot {
        what: what.to_string(),
        message: e.to_string(),
    }
}

/// A named series of (x, y) points.
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Drawn as markers only (no line).
    pub markers_only: bool,
}

pub(crate) const COLORS: [RGBColor; 8] = [
    RGBColor(0x1f, 0x77, 0xb4),
    RGBColor(0xd6, 0x27, 0x28),
    RGBColor(0x2c, 0xa0, 0x2c),
    RGBColor(0xff, 0x7f, 0x0e),
    RGBColor(0x94, 0x67, 0xbd),
    RGBColor(0x8c, 0x56, 0x4b),
    RGBColor(0x7f, 0x7f, 0x7f),
    RGBColor(0x17, 0xbe, 0xcf),
];

/// An x-y chart; `log_y` plots y on a log scale (non-positive values are left out).
pub fn chart(
    title: &str,
    x_desc: &str,
    y_desc: &str,
    series: &[Series],
    log_y: bool,
    symmetric_y: bool,
    legend_middle: bool,
) -> Result<String> {
    let pts = || {
        series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| p.0.is_finite() && p.1.is_finite() && (!log_y || p.1 > 0.0))
    };
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY);
    for &(x, y) in pts() {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.1, 1.0);
    }
    if x1 <= x0 {
        x1 = x0 + 1.0;
    }
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (960, 600)).into_drawing_area();
        root.fill(&WHITE).map_err(err(title))?;
        let mut b = ChartBuilder::on(&root);
        b.caption(title, ("sans-serif", 22))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(80);
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(x_desc)
                    .y_desc(y_desc)
                    .draw()
                    .map_err(err(title))?;
                for (i, s) in series.iter().enumerate() {
                    let c = COLORS[i % COLORS.len()];
                    let p: Vec<(f64, f64)> = s
                        .points
                        .iter()
                        .copied()
                        .filter(|p| p.0.is_finite() && p.1.is_finite() && (!log_y || p.1 > 0.0))
                        .collect();
                    if s.markers_only {
                        chart
                            .draw_series(p.iter().map(|&q| Circle::new(q, 4, c.filled())))
                            .map_err(err(title))?
                            .label(s.label.as_str())
                            .legend(move |(x, y)| Circle::new((x + 10, y), 4, c.filled()));
                    } else {
                        chart
                            .draw_series(LineSeries::new(p, c.stroke_width(2)))
                            .map_err(err(title))?
                            .label(s.label.as_str())
                            .legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 20, y)], c.stroke_width(2))
                            });
                    }
                }
                chart
                    .configure_series_labels()
                    .position(if legend_middle {
                        SeriesLabelPosition::MiddleRight
                    } else {
                        SeriesLabelPosition::UpperRight
                    })
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .draw()
                    .map_err(err(title))?;
            }};
        }
        if log_y {
            let lo = 10f64.powf((y0.max(1e-12)).log10().floor());
            let hi = 10f64.powf(y1.max(lo * 10.0).log10().ceil());
            draw!(b
                .build_cartesian_2d(x0..x1, (lo..hi).log_scale())
                .map_err(err(title))?);
        } else if symmetric_y {
            let m = y0.abs().max(y1.abs()).max(1e-9) * 1.1;
            draw!(b.build_cartesian_2d(x0..x1, -m..m).map_err(err(title))?);
        } else {
            let hi = if y1 > 0.0 { y1 * 1.08 } else { 1.0 };
            let lo = y0.min(0.0);
            draw!(b.build_cartesian_2d(x0..x1, lo..hi).map_err(err(title))?);
        }
        root.present().map_err(err(title))?;
    }
    Ok(svg)
}
