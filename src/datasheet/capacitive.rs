//! The data sheet of the capacitive path (a config with `[capacitive]`): the capacitive
//! `<name>_top` in its closed loop against the capacitive-encoder model
//! ([`crate::simulate::run_capacitive_report`]: `sim/cap_system.rs`, `sim/capacitive.rs`)
//! over a grid of speeds ([`CapPlan`]), in parallel on rayon's pool like the sinewave grid
//! ([`super::grid`]); results come back in the plan's order, so the page does not depend on
//! the schedule.
//!
//! ```text
//!   accuracy   3 speeds, with ADC noise, records kept   -> error against angle, histogram
//!   sweep      standstill .. speed limit, ideal + noise -> max/RMS error against speed
//!   stages     the derivation `check`/`simulate` print  -> processing time, sample rate
//! ```
//!
//! The error is the one `simulate` prints for this path: decoded - true mechanical angle,
//! less its mean over the run (the filters' group delay is a constant lag at constant
//! speed), in mechanical degrees, after the filters' settling window
//! ([`crate::simulate::CAP_SETTLE_S`]). The speed limit is `check`'s `max speed` line
//! ([`crate::simulate::followable_rpm`]: the low-pass corner, or the CORDIC's unwrap if
//! lower). What the sinewave page shows and this path lacks (correction, the Lissajous
//! figure of sin/cos, the QEP fallback, velocity) is named in one line ([`NOT_APPLICABLE`]).
use super::figures::{envelope, fig, WIDE};
use super::grid::nice;
use super::{Figure, Options};
use crate::config::Loaded;
use crate::error::{Error, Result};
use crate::report::figure::{Axis, Figure as Plot, Kind, Trace};
use crate::sim::cap_system::{CapRecord, CapStats};
use crate::sim::encoder::Profile;
use crate::simulate::{SimOptions, CAP_SETTLE_S};
use rayon::prelude::*;
use serde::Serialize;
use std::sync::atomic::{AtomicU64, Ordering};

/// The line of the page (and the JSON) that names what it leaves out, and why.
pub const NOT_APPLICABLE: &str = "Not on this page, because the capacitive path has none of them: offset/gain/phase correction and its convergence, the Lissajous figure of sin/cos tracks (the filters' I/Q are computed, not sampled), the QEP fallback above the unwrap limit, and velocity (the capacitive top has no velocity estimator).";

/// Mechanical arc-seconds per degree.
const ARCSEC: f64 = 3600.0;

/// The conditions of the runs "with noise": the received amplitude at 80 % of the ADC's
/// range (`simulate`'s default) and 2 LSB RMS of ADC noise (docs/capacitive.md's jitter
/// figure).
pub fn noisy_options() -> SimOptions {
    SimOptions {
        amplitude: 0.8,
        noise_lsb: 2.0,
        seed: 7,
        ..SimOptions::default()
    }
}

/// What runs: speeds and durations.
#[derive(Clone, Debug)]
pub struct CapPlan {
    /// The path's speed limit (`check`'s `max speed`), rpm.
    pub limit_rpm: f64,
    /// The accuracy runs' speeds (slow, middle, near the limit), rpm.
    pub accuracy_rpm: Vec<f64>,
    /// Their simulated time (settling included), seconds.
    pub accuracy_s: f64,
    /// The sweep's speeds, standstill to the limit, rpm.
    pub sweep_rpm: Vec<f64>,
    /// Simulated time of a sweep run (settling included), seconds.
    pub sweep_s: f64,
}

/// One run.
#[derive(Clone, Copy, Debug)]
enum Job {
    Accuracy(f64),
    Sweep { rpm: f64, noisy: bool },
}

/// A finished run.
pub struct CapOut {
    /// Its options.
    pub options: SimOptions,
    /// Its error statistics (after the settling window).
    pub stats: CapStats,
    /// Every decoded position (accuracy runs only).
    pub records: Vec<CapRecord>,
    /// Why the engine is not the one asked for, if it is not.
    pub engine_note: Option<String>,
}

/// Every run of a [`CapPlan`], by purpose.
pub struct CapRuns {
    /// At [`CapPlan::accuracy_rpm`], with noise, records kept.
    pub accuracy: Vec<CapOut>,
    /// At [`CapPlan::sweep_rpm`], ideal encoder.
    pub sweep_ideal: Vec<CapOut>,
    /// At [`CapPlan::sweep_rpm`], with noise.
    pub sweep_noisy: Vec<CapOut>,
    /// The engine's fallback, if any (said once).
    pub engine_note: Option<String>,
}

impl CapPlan {
    /// The default grid, or the reduced one of `--quick` (CI).
    pub fn new(loaded: &Loaded, quick: bool) -> CapPlan {
        let limit = crate::simulate::followable_rpm(loaded);
        let n = if quick { 9 } else { 31 };
        let accuracy_rpm = vec![nice(0.05 * limit), nice(0.3 * limit), nice(0.9 * limit)];
        // The slow run covers one signal period (four on the full grid), within bounds.
        let ppr = (loaded.derived.quadrants_per_turn as f64 / 4.0).max(1.0);
        let period_s = 60.0 / (accuracy_rpm[0] * ppr).max(1e-9);
        let measure_s = if quick {
            period_s.clamp(1e-3, 10e-3)
        } else {
            (4.0 * period_s).clamp(5e-3, 40e-3)
        };
        CapPlan {
            limit_rpm: limit,
            accuracy_rpm,
            accuracy_s: CAP_SETTLE_S + measure_s,
            sweep_rpm: (0..n)
                .map(|i| (limit * i as f64 / (n - 1) as f64).round())
                .collect(),
            sweep_s: CAP_SETTLE_S + if quick { 0.5e-3 } else { 5.0e-3 },
        }
    }

    /// Every run, in the order of the results.
    fn jobs(&self) -> Vec<Job> {
        let mut j: Vec<Job> = self
            .accuracy_rpm
            .iter()
            .map(|&r| Job::Accuracy(r))
            .collect();
        for noisy in [false, true] {
            j.extend(self.sweep_rpm.iter().map(|&rpm| Job::Sweep { rpm, noisy }));
        }
        j
    }

    /// The options of run `j`.
    fn options(&self, j: &Job) -> SimOptions {
        let (rpm, duration_s, keep, noisy) = match *j {
            Job::Accuracy(rpm) => (rpm, self.accuracy_s, true, true),
            Job::Sweep { rpm, noisy } => (rpm, self.sweep_s, false, noisy),
        };
        let base = if noisy {
            noisy_options()
        } else {
            SimOptions::default()
        };
        SimOptions {
            profile: Profile::Constant { rpm },
            duration_s,
            keep_records: keep,
            ..base
        }
    }

    /// Clock cycles of every run together (the progress bar's length).
    pub fn total_cycles(&self, loaded: &Loaded) -> u64 {
        self.jobs()
            .iter()
            .map(|j| (self.options(j).duration_s * loaded.derived.clock_hz).ceil() as u64)
            .sum()
    }

    /// Runs every point in parallel; `progress(cycles)` gets the cycles simulated since its
    /// last call, from any thread.
    pub fn run(&self, loaded: &Loaded, progress: &(dyn Fn(u64) + Sync)) -> Result<CapRuns> {
        let outs: Vec<CapOut> = self
            .jobs()
            .par_iter()
            .map(|j| {
                let o = self.options(j);
                let last = AtomicU64::new(0);
                let r = crate::simulate::run_capacitive_report(
                    loaded,
                    &o,
                    |done, _| progress(done - last.swap(done, Ordering::Relaxed)),
                    None,
                )?;
                Ok(CapOut {
                    options: o,
                    stats: r.stats,
                    records: r.records,
                    engine_note: r.engine_note,
                })
            })
            .collect::<Result<_>>()?;
        let mut it = outs.into_iter();
        let mut take = |n: usize| it.by_ref().take(n).collect::<Vec<CapOut>>();
        let accuracy = take(self.accuracy_rpm.len());
        let sweep_ideal = take(self.sweep_rpm.len());
        let sweep_noisy = take(self.sweep_rpm.len());
        let engine_note = accuracy.iter().find_map(|o| o.engine_note.clone());
        Ok(CapRuns {
            accuracy,
            sweep_ideal,
            sweep_noisy,
            engine_note,
        })
    }
}

/// Key figures of the capacitive path.
#[derive(Clone, Debug, Serialize)]
pub struct CapOverview {
    /// System clock, MHz.
    pub clock_mhz: f64,
    /// ADC samples per second (one channel: the receiver).
    pub sample_rate_sps: f64,
    /// Excitation carrier, Hz.
    pub carrier_hz: f64,
    /// Signal periods per mechanical turn.
    pub periods_per_turn: u64,
    /// Position resolution, bits per turn.
    pub resolution_bits: f64,
    /// One position LSB, mechanical arc-seconds.
    pub lsb_arcsec: f64,
    /// The speed limit (`check`'s `max speed`), rpm.
    pub speed_limit_rpm: f64,
    /// The low-pass corner that sets it, Hz (0: none configured).
    pub lowpass_corner_hz: f64,
}

/// The conditions of the runs "with noise" (`simulate`'s options).
#[derive(Clone, Debug, Serialize)]
pub struct CapConditions {
    /// `--amplitude`, the received amplitude as a fraction of the ADC's range.
    pub amplitude: f64,
    /// `--noise-lsb`, RMS ADC LSB.
    pub noise_lsb: f64,
    /// `--seed`.
    pub seed: u64,
    /// Settling window left out of every statistic, ms.
    pub settle_ms: f64,
}

/// Error at one accuracy speed, mechanical.
#[derive(Clone, Debug, Serialize)]
pub struct CapAccuracyRow {
    /// Speed, rpm.
    pub rpm: f64,
    /// Decoded positions in the statistics.
    pub samples: usize,
    /// Max |error|, degrees.
    pub max_deg: f64,
    /// RMS error, degrees.
    pub rms_deg: f64,
    /// Max |error|, arc-seconds.
    pub max_arcsec: f64,
    /// RMS error, arc-seconds.
    pub rms_arcsec: f64,
    /// Positions with the error or warning flag.
    pub flagged: usize,
}

/// Error at one sweep speed, mechanical degrees.
#[derive(Clone, Debug, Serialize)]
pub struct CapSweepRow {
    /// Speed, rpm.
    pub rpm: f64,
    /// Ideal encoder: max |error|.
    pub ideal_max_deg: f64,
    /// Ideal encoder: RMS.
    pub ideal_rms_deg: f64,
    /// With noise: max |error|.
    pub max_deg: f64,
    /// With noise: RMS.
    pub rms_deg: f64,
    /// Positions with the error or warning flag, both runs.
    pub flagged: usize,
}

/// One stage of the per-sample processing.
#[derive(Clone, Debug, Serialize)]
pub struct CapStage {
    /// The stage.
    pub stage: String,
    /// Clock cycles.
    pub cycles: u64,
    /// Microseconds at the configured clock.
    pub us: f64,
    /// What is counted.
    pub note: String,
}

/// Every number of the capacitive page's tables, as `datasheet.json` holds them.
#[derive(Clone, Debug, Serialize)]
pub struct CapSheet {
    /// `sinedec 0.1.0 (commit abc1234)`.
    pub generator: String,
    /// The config's name (its path as given).
    pub config_name: String,
    /// The config's hash (as in the generated files' headers).
    pub config_hash: String,
    /// The command that wrote the page.
    pub command: String,
    /// Whether the reduced grid ran.
    pub quick: bool,
    /// `capacitive`: which page this is.
    pub path: String,
    /// What the page leaves out ([`NOT_APPLICABLE`]).
    pub not_applicable: String,
    /// Key figures.
    pub overview: CapOverview,
    /// The conditions of the runs with noise.
    pub conditions: CapConditions,
    /// Error at the three accuracy speeds.
    pub accuracy: Vec<CapAccuracyRow>,
    /// Error against speed.
    pub sweep: Vec<CapSweepRow>,
    /// Per-sample processing, CONV to par_valid, and the sample period.
    pub processing: Vec<CapStage>,
    /// Resources and Fmax.
    pub resources: super::resources::Resources,
    /// The config's text, so that the page can be reproduced.
    pub config_text: String,
}

/// Per accuracy speed: (electrical angle deg within the signal period, error mechanical
/// deg) of every decoded position after the settling window.
pub type AngleErrors = Vec<Vec<(f64, f64)>>;

/// The error of each record after the settling window, less the run's mean: (electrical
/// angle deg, error mechanical deg), taken modulo one turn as `simulate`'s CSV does.
fn angle_errors(loaded: &Loaded, out: &CapOut) -> Vec<(f64, f64)> {
    let d = &loaded.derived;
    let turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
    let q = (1u64 << d.fine_bits) as f64;
    let mean = out.stats.mean_deg / 360.0 * turn;
    let skip = (CAP_SETTLE_S * d.clock_hz) as u64;
    out.records
        .iter()
        .filter(|r| r.cycle >= skip)
        .map(|r| {
            let e = r.decoded as f64 - r.truth - mean;
            let e = e - turn * (e / turn).round();
            ((r.truth / q).rem_euclid(4.0) * 90.0, e / turn * 360.0)
        })
        .collect()
}

/// Per-sample processing: the stages `simulate` prints for this path (`check`'s core
/// latency and sample rate; the front end's `CapFrontParams::cycles_per_sample`), their
/// sum, the BiSS-C latch and the sample period.
fn processing(loaded: &Loaded) -> Result<Vec<CapStage>> {
    let d = &loaded.derived;
    let front = crate::blocks::capacitive::CapFrontParams::new(d)?;
    let us = |c: u64| c as f64 * 1e6 / d.clock_hz;
    let adc = d.adc.conv_to_valid_clocks() as u64;
    let filters = front.cycles_per_sample() as u64;
    let core = d.latency_cycles as u64;
    let total = adc + filters + core;
    let mut rows = vec![];
    let mut row = |stage: &str, cycles: u64, note: String| {
        rows.push(CapStage {
            stage: stage.into(),
            cycles,
            us: us(cycles),
            note,
        })
    };
    row(
        "ADC, CONV to sample",
        adc,
        "the ADC controller's conversion and frame".into(),
    );
    row(
        "filters and demodulation",
        filters,
        "band-pass, synchronous demodulation and the low-passes on one engine".into(),
    );
    row(
        "CORDIC core",
        core,
        format!(
            "`check`'s core latency: {} iterations, {}",
            d.iterations, d.architecture
        ),
    );
    row(
        "CONV to par_valid",
        total,
        "the sum of the three stages above".into(),
    );
    row(
        "BiSS-C frame",
        total + d.biss.latch_latency() as u64,
        format!(
            "CONV to par_valid, then the frame latches the newest position {} clocks after the master's first edge (synchronizer); add the wait for that edge",
            d.biss.latch_latency()
        ),
    );
    row(
        "sample period",
        d.adc.period_clocks as u64,
        "one CONV to the next: the processing fits within it".into(),
    );
    Ok(rows)
}

/// Runs the grid and builds the tables and figures of the capacitive page.
pub fn build(
    loaded: &Loaded,
    opts: &Options,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<(CapSheet, Vec<Figure>, Option<String>)> {
    let d = &loaded.derived;
    let k = d.capacitive.as_ref().ok_or_else(|| {
        Error::Datasheet("the capacitive page needs a configuration with [capacitive]".into())
    })?;
    let plan = CapPlan::new(loaded, opts.quick);
    let runs = plan.run(loaded, progress)?;
    let angles: AngleErrors = runs
        .accuracy
        .iter()
        .map(|o| angle_errors(loaded, o))
        .collect();
    let counts_per_turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
    let accuracy = runs
        .accuracy
        .iter()
        .zip(&plan.accuracy_rpm)
        .map(|(o, &rpm)| CapAccuracyRow {
            rpm,
            samples: o.stats.samples,
            max_deg: o.stats.max_deg,
            rms_deg: o.stats.rms_deg,
            max_arcsec: o.stats.max_deg * ARCSEC,
            rms_arcsec: o.stats.rms_deg * ARCSEC,
            flagged: o.stats.flagged,
        })
        .collect();
    let sweep = plan
        .sweep_rpm
        .iter()
        .zip(runs.sweep_ideal.iter().zip(&runs.sweep_noisy))
        .map(|(&rpm, (i, m))| CapSweepRow {
            rpm,
            ideal_max_deg: i.stats.max_deg,
            ideal_rms_deg: i.stats.rms_deg,
            max_deg: m.stats.max_deg,
            rms_deg: m.stats.rms_deg,
            flagged: i.stats.flagged + m.stats.flagged,
        })
        .collect();
    let no = noisy_options();
    let sheet = CapSheet {
        generator: format!(
            "sinedec {} (commit {})",
            crate::emit::VERSION,
            crate::emit::commit()
        ),
        config_name: loaded.source_name.clone(),
        config_hash: loaded.hash(),
        command: opts.command.clone(),
        quick: opts.quick,
        path: "capacitive".into(),
        not_applicable: NOT_APPLICABLE.into(),
        overview: CapOverview {
            clock_mhz: d.clock_hz / 1e6,
            sample_rate_sps: d.sample_rate_hz,
            carrier_hz: k.config.carrier_hz,
            periods_per_turn: d.quadrants_per_turn / 4,
            resolution_bits: d.resolution_bits,
            lsb_arcsec: 360.0 * ARCSEC / counts_per_turn,
            speed_limit_rpm: plan.limit_rpm,
            lowpass_corner_hz: k.config.lowpass.corner_hz.unwrap_or(0.0),
        },
        conditions: CapConditions {
            amplitude: no.amplitude,
            noise_lsb: no.noise_lsb,
            seed: no.seed,
            settle_ms: CAP_SETTLE_S * 1e3,
        },
        accuracy,
        sweep,
        processing: processing(loaded)?,
        resources: super::resources::resources(loaded, opts.config_arg.as_deref())?,
        config_text: loaded.text.clone(),
    };
    let figures = figures(&plan, &angles, &sheet)?;
    Ok((sheet, figures, runs.engine_note))
}

const MECH: &str = "error (mechanical deg)";
/// The size of an error-against-angle figure (three of them, one per speed).
const ANGLE: (u32, u32) = (760, 300);

/// The figures: error against angle, its histogram, error against speed.
fn figures(plan: &CapPlan, angles: &AngleErrors, sheet: &CapSheet) -> Result<Vec<Figure>> {
    // One figure per speed: the error near the limit is tens of times that at low speed,
    // and would flatten the others on a shared axis.
    let mut out = vec![];
    for (i, (a, &rpm)) in angles.iter().zip(&plan.accuracy_rpm).enumerate() {
        let (lo, hi) = envelope(a);
        let color = [0, 2, 4][i % 3];
        out.push(fig(
            &format!("fig-angle-{}", i + 1),
            format!(
                "Error against the angle within the signal period ({} per turn) at {rpm} rpm, with {} LSB RMS of ADC noise: the band between the min and max per degree",
                sheet.overview.periods_per_turn, sheet.conditions.noise_lsb
            ),
            Plot {
                x: Axis {
                    range: Some((0.0, 360.0)),
                    integer: true,
                    ..Axis::new("electrical angle (deg within the signal period)")
                },
                y: Axis::new(MECH),
                traces: vec![
                    Trace::new(format!("decoder output, {rpm} rpm"), Kind::Line, color, hi),
                    Trace::new("", Kind::Line, color, lo),
                ],
                size: ANGLE,
            },
        )?);
    }
    // Histogram of every accuracy run's error.
    let all: Vec<f64> = angles.iter().flatten().map(|p| p.1).collect();
    let m = all.iter().fold(0.0f64, |m, e| m.max(e.abs())).max(1e-6);
    let bins = 41usize;
    let w = 2.0 * m / bins as f64;
    let mut n = vec![0u64; bins];
    for e in &all {
        n[(((e + m) / w).floor().max(0.0) as usize).min(bins - 1)] += 1;
    }
    let top = n.iter().copied().max().unwrap_or(1).max(1) as f64;
    out.push(fig(
        "fig-histogram",
        "Error histogram of the decoder output at the three accuracy speeds, with ADC noise (log scale: the tails are the fast runs)".into(),
        Plot {
            x: Axis {
                range: Some((-m, m)),
                ..Axis::new(MECH)
            },
            y: Axis {
                log: true,
                range: Some((0.5, 10f64.powf(top.log10().ceil()).max(10.0))),
                ..Axis::new("positions")
            },
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
    )?);
    // Error against speed, log y over whole decades around the data.
    let s = &sheet.sweep;
    let pts = |f: &dyn Fn(&CapSweepRow) -> f64| s.iter().map(|r| (r.rpm, f(r))).collect();
    let positive = s
        .iter()
        .flat_map(|r| [r.max_deg, r.rms_deg, r.ideal_max_deg, r.ideal_rms_deg])
        .filter(|v| *v > 0.0);
    let lo = 10f64.powf(
        positive
            .clone()
            .fold(f64::INFINITY, f64::min)
            .min(1e-3)
            .log10()
            .floor(),
    );
    let hi = 10f64.powf(positive.fold(lo * 10.0, f64::max).log10().ceil());
    out.push(fig(
        "fig-speed",
        format!(
            "Max and RMS error against speed, standstill to the speed limit ({:.0} rpm: the low-pass corner, `sinedec check`'s max speed)",
            plan.limit_rpm
        ),
        Plot {
            x: Axis::new("speed (rpm)"),
            y: Axis {
                log: true,
                range: Some((lo, hi)),
                ..Axis::new(MECH)
            },
            traces: vec![
                // The ideal encoder first: where the two agree, the noisy run is on top.
                Trace::new("max, ideal encoder", Kind::Line, 2, pts(&|r| r.ideal_max_deg)),
                Trace::new("RMS, ideal encoder", Kind::Dashed, 2, pts(&|r| r.ideal_rms_deg)),
                Trace::new("max, with noise", Kind::Line, 0, pts(&|r| r.max_deg)),
                Trace::new("RMS, with noise", Kind::Dashed, 0, pts(&|r| r.rms_deg)),
                Trace::new(
                    "speed limit",
                    Kind::Dashed,
                    6,
                    vec![(plan.limit_rpm, lo), (plan.limit_rpm, hi)],
                ),
            ],
            size: WIDE,
        },
    )?);
    Ok(out)
}
