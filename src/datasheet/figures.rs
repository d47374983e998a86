//! The data sheet's figures, all drawn by [`crate::report::figure`] (one look): palette
//! colour 0 is always the decoder's output (after correction), 1 the raw codes (before), 2
//! the ideal encoder, 3 the encoder's true speed, 6 limits.
use super::grid::Plan;
use super::tables::Analysis;
use super::{Figure, Sheet};
use crate::error::Result;
use crate::report::figure::{render, Axis, Figure as Plot, Kind, Trace};

/// Points of a line.
type Points = Vec<(f64, f64)>;

pub(super) const WIDE: (u32, u32) = (760, 380);
const SQUARE: (u32, u32) = (520, 480);
const LSB: &str = "error (LSB = 2^-F quadrant)";

/// A figure of the page: `plot` rendered under `id` and `caption`.
pub(super) fn fig(id: &str, caption: String, plot: Plot) -> Result<Figure> {
    Ok(Figure {
        id: id.into(),
        caption,
        svg: render(&plot)?,
    })
}

/// Min and max of `points` per 1-degree bin of x in 0..360: the envelope lines.
pub(super) fn envelope(points: &[(f64, f64)]) -> (Points, Points) {
    let mut lo = [f64::INFINITY; 360];
    let mut hi = [f64::NEG_INFINITY; 360];
    for &(x, y) in points {
        let b = (x.floor() as usize).min(359);
        lo[b] = lo[b].min(y);
        hi[b] = hi[b].max(y);
    }
    let line = |v: &[f64; 360]| {
        v.iter()
            .enumerate()
            .filter(|(_, y)| y.is_finite())
            .map(|(i, &y)| (i as f64 + 0.5, y))
            .collect()
    };
    (line(&lo), line(&hi))
}

/// Every `n`-th point so that at most `max` remain (keeps the SVG small).
fn thin<T: Copy>(v: &[T], max: usize) -> Vec<T> {
    let step = v.len().div_ceil(max.max(1)).max(1);
    v.iter().step_by(step).copied().collect()
}

fn axis(desc: &str, integer: bool) -> Axis {
    Axis {
        integer,
        ..Axis::new(desc)
    }
}

/// Every figure, in page order.
pub fn figures(plan: &Plan, an: &Analysis, sheet: &Sheet) -> Result<Vec<Figure>> {
    let mut out = vec![];
    let deg = || Axis {
        range: Some((0.0, 360.0)),
        ..axis("electrical angle (deg)", true)
    };
    // The decoder's output at each speed (one colour each), and the raw codes' error at the
    // middle speed (the raw error does not depend on the speed).
    let mut traces = vec![];
    if let Some(a) = an.accuracy.get(1) {
        let (lo, hi) = envelope(&a.before);
        traces.push(Trace::new(
            "before correction (raw codes)",
            Kind::Dashed,
            1,
            hi,
        ));
        traces.push(Trace::new("", Kind::Dashed, 1, lo));
    }
    for (i, (a, &rpm)) in an.accuracy.iter().zip(&plan.accuracy_rpm).enumerate() {
        let (lo, hi) = envelope(&a.after);
        let color = [0, 2, 4][i % 3];
        traces.push(Trace::new(
            format!("decoder output, {rpm} rpm"),
            Kind::Line,
            color,
            hi,
        ));
        traces.push(Trace::new("", Kind::Line, color, lo));
    }
    out.push(fig(
        "fig-angle",
        "Error against electrical angle with imperfections, before and after correction: the band between the min and max per degree".into(),
        Plot {
            x: deg(),
            y: Axis::new(LSB),
            traces,
            size: WIDE,
        },
    )?);
    out.push(histogram(an)?);
    out.push(speed(plan, sheet)?);
    out.push(lissajous(an)?);
    if sheet.correction.automatic {
        let t = |f: &dyn Fn(&super::samples::CoefPoint) -> f64| -> Vec<(f64, f64)> {
            let mut v: Vec<(f64, f64)> = vec![];
            for c in &an.coefs {
                // Steps: the old value up to the update, then the new one.
                if let Some(&(_, y)) = v.last() {
                    v.push((c.t_s * 1e3, y));
                }
                v.push((c.t_s * 1e3, f(c)));
            }
            if let (Some(&(_, y)), Some(end)) =
                (v.last(), an.accuracy.get(1).and_then(|a| a.samples.last()))
            {
                v.push((end.t * 1e3, y));
            }
            v
        };
        type Pick = fn(&super::samples::CoefPoint, usize) -> f64;
        let quantities: [(&str, &str, &str, Pick); 2] = [
            ("offset", "offsets", "offset (ADC LSB)", |c, i| {
                c.offset[i] as f64
            }),
            ("gain", "gain codes", "gain code", |c, i| c.gain[i] as f64),
        ];
        for (id, what, unit, pick) in quantities {
            out.push(fig(
                &format!("fig-convergence-{id}"),
                format!("Automatic correction: {what} in use against time (middle accuracy speed)"),
                Plot {
                    x: Axis::new("time (ms)"),
                    y: axis(unit, true),
                    traces: vec![
                        Trace::new(format!("sin {id}"), Kind::Line, 0, t(&|c| pick(c, 0))),
                        Trace::new(format!("cos {id}"), Kind::Line, 4, t(&|c| pick(c, 1))),
                    ],
                    size: WIDE,
                },
            )?);
        }
    }
    if sheet.velocity.is_some() {
        out.extend(velocity(an, sheet)?);
    }
    Ok(out)
}

fn histogram(an: &Analysis) -> Result<Figure> {
    let all: Vec<f64> = an
        .accuracy
        .iter()
        .flat_map(|a| a.after.iter().map(|p| p.1))
        .collect();
    let m = all.iter().fold(0.0f64, |m, e| m.max(e.abs())).max(0.5);
    let bins = 41usize;
    let w = 2.0 * m / bins as f64;
    let mut n = vec![0u64; bins];
    for e in &all {
        n[(((e + m) / w).floor() as usize).min(bins - 1)] += 1;
    }
    fig(
        "fig-histogram",
        "Error histogram of the decoder output at the three accuracy speeds, with imperfections"
            .into(),
        Plot {
            x: Axis {
                range: Some((-m, m)),
                ..Axis::new(LSB)
            },
            y: axis("samples", true),
            traces: vec![Trace::new(
                "decoder output, all three speeds",
                Kind::Bars,
                0,
                n.iter()
                    .enumerate()
                    .map(|(i, &c)| (-m + (i as f64 + 0.5) * w, c as f64))
                    .collect(),
            )],
            size: WIDE,
        },
    )
}

fn speed(plan: &Plan, sheet: &Sheet) -> Result<Figure> {
    let s = &sheet.sweep;
    let pts = |f: &dyn Fn(&super::SweepRow) -> f64| s.iter().map(|r| (r.rpm, f(r))).collect();
    // Whole decades around the data (the limit line spans them).
    let positive = s
        .iter()
        .flat_map(|r| [r.max_lsb, r.rms_lsb, r.ideal_max_lsb, r.ideal_rms_lsb])
        .filter(|v| *v > 0.0);
    let lo = 10f64.powf(
        positive
            .clone()
            .fold(f64::INFINITY, f64::min)
            .min(1.0)
            .log10()
            .floor(),
    );
    let hi = 10f64.powf(positive.fold(lo * 10.0, f64::max).log10().ceil());
    let fallback = if sheet.overview.qep_fallback {
        "QEP fallback above it"
    } else {
        "no QEP fallback: the track is lost above it"
    };
    fig(
        "fig-speed",
        format!("Max and RMS error against speed, standstill to 1.5 x the unwrap limit ({:.0} rpm; {fallback})", plan.limit_rpm),
        Plot {
            x: Axis::new("speed (rpm)"),
            y: Axis {
                log: true,
                range: Some((lo, hi)),
                ..Axis::new(LSB)
            },
            traces: vec![
                Trace::new("max, with imperfections", Kind::Line, 0, pts(&|r| r.max_lsb)),
                Trace::new("RMS, with imperfections", Kind::Dashed, 0, pts(&|r| r.rms_lsb)),
                Trace::new("max, ideal encoder", Kind::Line, 2, pts(&|r| r.ideal_max_lsb)),
                Trace::new("RMS, ideal encoder", Kind::Dashed, 2, pts(&|r| r.ideal_rms_lsb)),
                Trace::new(
                    "unwrap limit",
                    Kind::Dashed,
                    6,
                    vec![(plan.limit_rpm, lo), (plan.limit_rpm, hi)],
                ),
            ],
            size: WIDE,
        },
    )
}

fn lissajous(an: &Analysis) -> Result<Figure> {
    let s = an
        .accuracy
        .get(1)
        .map(|a| a.samples.as_slice())
        .unwrap_or_default();
    let s = thin(s, 1200);
    let m = s
        .iter()
        .flat_map(|x| x.raw.iter().chain(x.corrected.iter()))
        .fold(1i64, |m, v| m.max(v.abs())) as f64
        * 1.05;
    let range = Some((-m, m));
    fig(
        "fig-lissajous",
        "Lissajous figure of the ADC samples at the middle accuracy speed: raw codes and the corrected codes the CORDIC is given".into(),
        Plot {
            x: Axis {
                range,
                ..axis("cos (ADC LSB)", true)
            },
            y: Axis {
                range,
                ..axis("sin (ADC LSB)", true)
            },
            traces: vec![
                Trace::new("raw", Kind::Dots, 1, s.iter().map(|x| (x.raw[1] as f64, x.raw[0] as f64)).collect()),
                Trace::new(
                    "corrected",
                    Kind::Dots,
                    0,
                    s.iter().map(|x| (x.corrected[1] as f64, x.corrected[0] as f64)).collect(),
                ),
            ],
            size: SQUARE,
        },
    )
}

fn velocity(an: &Analysis, sheet: &Sheet) -> Result<Vec<Figure>> {
    let mut out = vec![];
    let noise: Vec<(f64, f64)> = sheet
        .sweep
        .iter()
        .filter_map(|r| r.velocity_noise_rpm.map(|n| (r.rpm, n)))
        .collect();
    out.push(fig(
        "fig-velocity-noise",
        "Velocity estimate: standard deviation against speed, with imperfections".into(),
        Plot {
            x: Axis::new("speed (rpm)"),
            y: Axis::new("velocity noise, std (rpm)"),
            traces: vec![Trace::new(
                "estimate - true speed, std",
                Kind::Line,
                0,
                noise,
            )],
            size: WIDE,
        },
    )?);
    for (id, what, trace) in [
        ("fig-velocity-step", "step", &an.step),
        ("fig-velocity-ramp", "ramp", &an.ramp),
    ] {
        let ms = |f: fn(&(f64, f64, f64)) -> f64| trace.iter().map(|p| (p.0 * 1e3, f(p))).collect();
        out.push(fig(
            id,
            format!(
                "Velocity estimate: {what} response, the speed reversing from +{rpm} to -{rpm} rpm",
                rpm = sheet.velocity.as_ref().map(|v| v.step_rpm).unwrap_or(0.0)
            ),
            Plot {
                x: Axis::new("time (ms)"),
                y: Axis::new("speed (rpm)"),
                traces: vec![
                    Trace::new("encoder speed", Kind::Dashed, 3, ms(|p| p.2)),
                    Trace::new("par_velocity", Kind::Line, 0, ms(|p| p.1)),
                ],
                size: WIDE,
            },
        )?);
    }
    Ok(out)
}
