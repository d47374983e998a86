//! Data-sheet figures (plotters, SVG backend; the look of [`super::plot`]: its palette,
//! sans-serif text, no system fonts, byte-for-byte reproducible): axes with units, the
//! legend in a band below the plot area so that it never covers data, integer ticks on an
//! axis marked integer, optional log y. The caption is the page's (`<figcaption>`), so the
//! SVG carries none. Used by `sinedec datasheet` (`crate::datasheet::figures`).
use super::plot::{err, COLORS};
use crate::error::Result;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// How a trace is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// A line through the points.
    Line,
    /// A dashed line (limits, references).
    Dashed,
    /// A small dot per point (scatter).
    Dots,
    /// Bars of a histogram: each point is (bin centre, count); the width is the distance
    /// between the first two centres.
    Bars,
}

/// One named set of points.
#[derive(Clone, Debug)]
pub struct Trace {
    /// Legend text (empty: not in the legend, e.g. the second line of a band).
    pub label: String,
    /// Points (non-finite ones, and non-positive y on a log axis, are left out).
    pub points: Vec<(f64, f64)>,
    /// How it is drawn.
    pub kind: Kind,
    /// Index into the palette (the same quantity keeps its colour across figures).
    pub color: usize,
}

impl Trace {
    /// A trace of `kind` in palette colour `color`.
    pub fn new(
        label: impl Into<String>,
        kind: Kind,
        color: usize,
        points: Vec<(f64, f64)>,
    ) -> Self {
        Trace {
            label: label.into(),
            points,
            kind,
            color,
        }
    }
}

/// One axis.
#[derive(Clone, Debug, Default)]
pub struct Axis {
    /// Quantity and unit, `speed (rpm)`.
    pub desc: String,
    /// Fixed range; None: the data's, with a margin on y.
    pub range: Option<(f64, f64)>,
    /// Ticks on whole numbers only (counts, codes).
    pub integer: bool,
    /// Log scale (y only).
    pub log: bool,
}

impl Axis {
    /// A linear axis with the data's range.
    pub fn new(desc: impl Into<String>) -> Axis {
        Axis {
            desc: desc.into(),
            ..Default::default()
        }
    }
}

/// A figure: axes, traces and pixel size of the plot (the legend band is added below).
#[derive(Clone, Debug)]
pub struct Figure {
    /// x axis.
    pub x: Axis,
    /// y axis.
    pub y: Axis,
    /// Traces, drawn in order.
    pub traces: Vec<Trace>,
    /// Width and height of the plot part, pixels.
    pub size: (u32, u32),
}

/// Text of the tick labels and legend.
const FONT: (&str, u32) = ("sans-serif", 15);

/// The range of `v` (finite values), or None.
fn span(v: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    v.filter(|x| x.is_finite()).fold(None, |r, x| match r {
        None => Some((x, x)),
        Some((a, b)) => Some((a.min(x), b.max(x))),
    })
}

/// Tick text with as many decimals as the axis's extent needs (none on an integer axis).
fn tick_text(v: f64, extent: f64, integer: bool) -> String {
    if integer {
        return format!("{}", v.round() as i64);
    }
    let decimals = (1.0 - (extent.abs().max(1e-12) / 5.0).log10().floor()).clamp(0.0, 6.0);
    let s = format!("{v:.*}", decimals as usize);
    if s.starts_with("-") && s.trim_start_matches(['-', '0', '.']).is_empty() {
        s[1..].to_string()
    } else {
        s
    }
}

/// Legend rows: each entry's (trace index, x offset), wrapped to `width`.
fn legend_layout(f: &Figure, width: u32, measure: &dyn Fn(&str) -> u32) -> Vec<Vec<(usize, u32)>> {
    let mut rows: Vec<Vec<(usize, u32)>> = vec![vec![]];
    let mut x = 12;
    for (i, t) in f
        .traces
        .iter()
        .enumerate()
        .filter(|(_, t)| !t.label.is_empty())
    {
        let w = 34 + measure(&t.label) + 24;
        if x + w > width && x > 12 {
            rows.push(vec![]);
            x = 12;
        }
        if let Some(r) = rows.last_mut() {
            r.push((i, x));
        }
        x += w;
    }
    rows
}

/// Renders `f` as an SVG document.
pub fn render(f: &Figure) -> Result<String> {
    let what = f.y.desc.as_str();
    let (w, h) = f.size;
    let probe = |s: &str| (s.chars().count() as u32) * 8;
    let rows = legend_layout(f, w, &probe);
    let legend_h = 10 + 24 * rows.len() as u32;
    let keep = |p: &(f64, f64)| p.0.is_finite() && p.1.is_finite() && (!f.y.log || p.1 > 0.0);
    let pts = || {
        f.traces
            .iter()
            .flat_map(|t| t.points.iter())
            .filter(|p| keep(p))
    };
    let (x0, x1) =
        f.x.range
            .or_else(|| span(pts().map(|p| p.0)))
            .unwrap_or((0.0, 1.0));
    let x1 = if x1 > x0 { x1 } else { x0 + 1.0 };
    let bars = f.traces.iter().any(|t| t.kind == Kind::Bars);
    let (y0, y1) = f.y.range.unwrap_or_else(|| {
        let (a, b) = span(pts().map(|p| p.1)).unwrap_or((0.0, 1.0));
        if f.y.log {
            (
                10f64.powf(a.max(1e-12).log10().floor()),
                10f64.powf(b.max(a * 10.0).log10().ceil()),
            )
        } else {
            let (a, b) = if bars { (a.min(0.0), b) } else { (a, b) };
            let m = ((b - a) * 0.06).max(if f.y.integer { 1.0 } else { 1e-9 });
            (if bars && a >= 0.0 { 0.0 } else { a - m }, b + m)
        }
    });
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (w, h + legend_h)).into_drawing_area();
        root.fill(&WHITE).map_err(err(what))?;
        let (plot, legend) = root.split_vertically(h);
        let mut b = ChartBuilder::on(&plot);
        b.margin(14).x_label_area_size(52).y_label_area_size(78);
        let labels = |a: &Axis, lo: f64, hi: f64| {
            if a.integer {
                ((hi - lo).floor() as usize + 1).clamp(2, 10)
            } else {
                10
            }
        };
        let (xl, yl) = (labels(&f.x, x0, x1), labels(&f.y, y0, y1));
        let fx = |v: &f64| tick_text(*v, x1 - x0, f.x.integer);
        let fy = |v: &f64| tick_text(*v, y1 - y0, f.y.integer);
        let fy_log = |v: &f64| {
            let s = format!("{v}");
            if s.len() > 8 {
                format!("{v:.0e}")
            } else {
                s
            }
        };
        macro_rules! draw {
            ($chart:expr, $yfmt:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(f.x.desc.as_str())
                    .y_desc(f.y.desc.as_str())
                    .x_labels(xl)
                    .y_labels(yl)
                    .x_label_formatter(&fx)
                    .y_label_formatter($yfmt)
                    .label_style(FONT)
                    .axis_desc_style(("sans-serif", 16))
                    .light_line_style(RGBColor(0xee, 0xee, 0xee))
                    .bold_line_style(RGBColor(0xcc, 0xcc, 0xcc))
                    .draw()
                    .map_err(err(what))?;
                for t in &f.traces {
                    let c = COLORS[t.color % COLORS.len()];
                    let p: Vec<(f64, f64)> = t.points.iter().copied().filter(|p| keep(p)).collect();
                    match t.kind {
                        Kind::Line => {
                            chart
                                .draw_series(LineSeries::new(p, c.stroke_width(2)))
                                .map_err(err(what))?;
                        }
                        Kind::Dashed => {
                            chart
                                .draw_series(DashedLineSeries::new(p, 8, 5, c.stroke_width(2)))
                                .map_err(err(what))?;
                        }
                        Kind::Dots => {
                            chart
                                .draw_series(p.iter().map(|&q| Circle::new(q, 2, c.filled())))
                                .map_err(err(what))?;
                        }
                        Kind::Bars => {
                            let bw = match p.as_slice() {
                                [a, b, ..] => (b.0 - a.0).abs(),
                                _ => 1.0,
                            };
                            chart
                                .draw_series(p.iter().map(|&(x, y)| {
                                    Rectangle::new(
                                        [(x - bw * 0.45, y0.max(0.0)), (x + bw * 0.45, y)],
                                        c.mix(0.75).filled(),
                                    )
                                }))
                                .map_err(err(what))?;
                        }
                    }
                }
            }};
        }
        if f.y.log {
            draw!(
                b.build_cartesian_2d(x0..x1, (y0..y1).log_scale())
                    .map_err(err(what))?,
                &fy_log
            );
        } else {
            let chart: ChartContext<'_, _, Cartesian2d<RangedCoordf64, RangedCoordf64>> =
                b.build_cartesian_2d(x0..x1, y0..y1).map_err(err(what))?;
            draw!(chart, &fy);
        }
        // The legend band: one sample of each trace's mark and its label, in rows.
        for (r, row) in rows.iter().enumerate() {
            let y = 12 + 24 * r as i32;
            for &(i, x) in row {
                let t = &f.traces[i];
                let c = COLORS[t.color % COLORS.len()];
                let x = x as i32 + 60;
                match t.kind {
                    Kind::Line | Kind::Dashed => legend
                        .draw(&PathElement::new(
                            vec![(x, y), (x + 26, y)],
                            c.stroke_width(2),
                        ))
                        .map_err(err(what))?,
                    Kind::Dots => legend
                        .draw(&Circle::new((x + 13, y), 4, c.filled()))
                        .map_err(err(what))?,
                    Kind::Bars => legend
                        .draw(&Rectangle::new(
                            [(x + 4, y - 6), (x + 22, y + 6)],
                            c.mix(0.75).filled(),
                        ))
                        .map_err(err(what))?,
                }
                legend
                    .draw(&Text::new(t.label.clone(), (x + 34, y - 8), FONT))
                    .map_err(err(what))?;
            }
        }
        root.present().map_err(err(what))?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_have_the_decimals_the_extent_needs() {
        assert_eq!(tick_text(2.0, 10.0, true), "2");
        assert_eq!(tick_text(2.5, 10.0, false), "2.5");
        assert_eq!(tick_text(12000.0, 20000.0, false), "12000");
        assert_eq!(tick_text(-0.0001, 1.0, false), "0.00");
    }
}
