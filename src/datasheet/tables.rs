//! The data sheet's numbers: what the runs measured ([`analyse`]: errors against angle,
//! the samples before and after correction, the velocity traces) and the tables
//! ([`sheet`]), which `datasheet.json` holds and the page prints. Latencies and the
//! velocity lag come from the derivations `sinedec check` prints (the top's
//! `conv_to_position_cycles`, each block's latency, `VelocityParams::lag_s`).
use super::grid::{imperfect_options, Out, Plan, Runs};
use super::samples::{raw_angle_errors, samples, CoefPoint, Sample};
use super::{Options, Sheet};
use crate::blocks::top::hdl::conv_to_position_cycles;
use crate::config::Loaded;
use crate::error::Result;
use crate::sim::system::SimResult;
use crate::simulate::SimOptions;
use serde::Serialize;

/// Key figures.
#[derive(Clone, Debug, Serialize)]
pub struct Overview {
    /// System clock, MHz.
    pub clock_mhz: f64,
    /// Samples per second per channel.
    pub sample_rate_sps: f64,
    /// Position resolution, bits per turn.
    pub resolution_bits: f64,
    /// One position LSB, mechanical arc-seconds.
    pub lsb_arcsec: f64,
    /// The unwrap limit (full resolution), rpm.
    pub unwrap_limit_rpm: f64,
    /// Whether the QEP fallback takes over above it.
    pub qep_fallback: bool,
}

/// The imperfections of the runs "with imperfections" (`simulate`'s options).
#[derive(Clone, Debug, Serialize)]
pub struct Conditions {
    /// `--amplitude`, fraction of the ADC's range.
    pub amplitude: f64,
    /// `--noise-lsb`, RMS ADC LSB.
    pub noise_lsb: f64,
    /// `--offset-sin`, fraction of the amplitude.
    pub offset_sin: f64,
    /// `--offset-cos`.
    pub offset_cos: f64,
    /// `--gain-mismatch`.
    pub gain_mismatch: f64,
    /// `--phase-error`, degrees.
    pub phase_error_deg: f64,
    /// `--harmonic3`.
    pub harmonic3: f64,
    /// `--seed`.
    pub seed: u64,
}

/// Error at one accuracy speed (fine LSB = 2^-F quadrant).
#[derive(Clone, Debug, Serialize)]
pub struct AccuracyRow {
    /// Speed, rpm.
    pub rpm: f64,
    /// Decoded samples in the statistics.
    pub samples: usize,
    /// Before correction (the raw codes' angle): max |error|.
    pub raw_max_lsb: f64,
    /// Before correction: RMS.
    pub raw_rms_lsb: f64,
    /// The decoder's output: max |error|.
    pub max_lsb: f64,
    /// The decoder's output: RMS.
    pub rms_lsb: f64,
}

/// Error at one sweep speed.
#[derive(Clone, Debug, Serialize)]
pub struct SweepRow {
    /// Speed, rpm.
    pub rpm: f64,
    /// Above the unwrap limit (QEP fallback, or a lost track without it).
    pub above_limit: bool,
    /// Ideal encoder: max |error|, LSB.
    pub ideal_max_lsb: f64,
    /// Ideal encoder: RMS, LSB.
    pub ideal_rms_lsb: f64,
    /// With imperfections: max |error|, LSB.
    pub max_lsb: f64,
    /// With imperfections: RMS, LSB.
    pub rms_lsb: f64,
    /// With imperfections: the velocity estimate's standard deviation, rpm.
    pub velocity_noise_rpm: Option<f64>,
}

/// Latency from CONV (or the output's own event) to an output.
#[derive(Clone, Debug, Serialize)]
pub struct LatencyRow {
    /// The output.
    pub output: String,
    /// Clock cycles.
    pub cycles: u64,
    /// Nanoseconds at the configured clock.
    pub ns: f64,
    /// What is counted.
    pub note: String,
}

/// The correction.
#[derive(Clone, Debug, Serialize)]
pub struct CorrectionSheet {
    /// `correction.mode`.
    pub mode: String,
    /// Whether the coefficients adapt (peak tracker or ellipse fit).
    pub automatic: bool,
    /// Coefficient updates within the middle accuracy run's time (automatic only).
    pub updates: usize,
    /// Time of the last update, ms (automatic only).
    pub last_update_ms: Option<f64>,
}

/// The velocity estimator.
#[derive(Clone, Debug, Serialize)]
pub struct VelocitySheet {
    /// Method.
    pub method: String,
    /// Update rate, Hz.
    pub rate_hz: f64,
    /// One velocity LSB, rpm.
    pub lsb_rpm: f64,
    /// Clocks from a tick to `out_velocity_valid`.
    pub latency_cycles: u64,
    /// Lag behind a ramp, update periods (`VelocityParams::lag_periods`).
    pub lag_periods: f64,
    /// The same with the output latency, ms (`VelocityParams::lag_s`).
    pub lag_ms: f64,
    /// Measured on the ramp run: the estimate's lag behind the encoder's speed at the
    /// update's strobe, ms (includes the position's age, CONV -> position).
    pub measured_lag_ms: Option<f64>,
    /// The step and ramp runs' speed before the reversal, rpm.
    pub step_rpm: f64,
}

/// What the runs measured, beyond the statistics.
pub struct Analysis {
    /// Per accuracy speed: (angle deg, error LSB) of the decoder, of the raw codes, and the
    /// samples (raw and corrected codes).
    pub accuracy: Vec<AccuracyData>,
    /// The coefficients whenever they changed (automatic correction), middle speed.
    pub coefs: Vec<CoefPoint>,
    /// Velocity step and ramp: (time s, estimate rpm, encoder speed rpm).
    pub step: Vec<(f64, f64, f64)>,
    /// As `step`, for the ramp.
    pub ramp: Vec<(f64, f64, f64)>,
}

/// One accuracy speed's data.
pub struct AccuracyData {
    /// The decoder's error against electrical angle (deg within the signal period).
    pub after: Vec<(f64, f64)>,
    /// The raw codes' error against electrical angle.
    pub before: Vec<(f64, f64)>,
    /// The samples.
    pub samples: Vec<Sample>,
}

/// Electrical angle in degrees within the signal period of a position `lsb` (fine LSB).
fn degrees(loaded: &Loaded, lsb: f64) -> f64 {
    let q = (1u64 << loaded.derived.fine_bits) as f64;
    (lsb / q).rem_euclid(4.0) * 90.0
}

/// The velocity trace of a run: (time, estimate, the encoder's speed at the strobe), rpm.
fn velocity_trace(loaded: &Loaded, out: &Out) -> Vec<(f64, f64, f64)> {
    let d = &loaded.derived;
    let Some(v) = &d.velocity else {
        return vec![];
    };
    let lsb_per_turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
    let rpm_per_lsb = d.clock_hz / v.period_clocks as f64 * 60.0 / lsb_per_turn;
    let scale = (1u64 << v.spec.frac_bits) as f64;
    out.result
        .velocity
        .iter()
        .map(|r| {
            let t = r.cycle as f64 / d.clock_hz;
            (
                t,
                r.raw as f64 / scale * rpm_per_lsb,
                out.options.profile.rpm(t),
            )
        })
        .collect()
}

/// Samples and errors of the runs.
pub fn analyse(loaded: &Loaded, plan: &Plan, runs: &Runs) -> Analysis {
    let d = &loaded.derived;
    let mut coefs = vec![];
    let accuracy = runs
        .accuracy
        .iter()
        .enumerate()
        .map(|(i, out)| {
            let r = &out.result;
            let offset = r.offset_lsb(d);
            let after = r
                .records
                .iter()
                .skip(out.options.skip)
                .map(|x| (degrees(loaded, x.truth), SimResult::error_lsb(d, x, offset)))
                .collect();
            let n = ((plan.accuracy_s * d.sample_rate_hz) as usize).clamp(64, 40_000);
            let (s, c) = samples(loaded, &out.options, n);
            if i == 1 {
                coefs = c;
            }
            let lsb = (1u64 << d.fine_bits) as f64;
            let before = raw_angle_errors(loaded, &s)
                .into_iter()
                .zip(&s)
                .map(|(e, x)| {
                    let turned = x.theta / std::f64::consts::FRAC_PI_2 * lsb;
                    (degrees(loaded, turned), e)
                })
                .collect();
            AccuracyData {
                after,
                before,
                samples: s,
            }
        })
        .collect();
    Analysis {
        accuracy,
        coefs,
        step: runs
            .step
            .as_ref()
            .map(|o| velocity_trace(loaded, o))
            .unwrap_or_default(),
        ramp: runs
            .ramp
            .as_ref()
            .map(|o| velocity_trace(loaded, o))
            .unwrap_or_default(),
    }
}

fn max_rms(e: impl Iterator<Item = f64>) -> (f64, f64) {
    let (mut m, mut s, mut n) = (0.0f64, 0.0, 0usize);
    for x in e {
        m = m.max(x.abs());
        s += x * x;
        n += 1;
    }
    (m, if n > 0 { (s / n as f64).sqrt() } else { 0.0 })
}

/// Latencies, from the derivations `check` prints.
fn latency(loaded: &Loaded) -> Vec<LatencyRow> {
    let d = &loaded.derived;
    let ns = |c: u64| c as f64 * 1e9 / d.clock_hz;
    let pos = conv_to_position_cycles(d) as u64;
    let mut rows = vec![];
    let mut row = |output: &str, cycles: u64, note: String| {
        rows.push(LatencyRow {
            output: output.into(),
            cycles,
            ns: ns(cycles),
            note,
        })
    };
    row(
        "parallel (par_position)",
        pos,
        format!(
            "{} to par_valid: ADC {} + correction {} + core {}",
            d.adc.frame.start_edge(),
            d.adc.conv_to_valid_clocks(),
            d.correction.latency_cycles(),
            d.latency_cycles
        ),
    );
    let start = d.adc.frame.start_edge();
    let latch = |l: u32| {
        format!(
            "{start} to par_position, then the frame latches the newest position {l} clocks after the master's first edge (synchronizer); add the wait for that edge"
        )
    };
    row(
        "BiSS-C frame",
        pos + d.biss.latch_latency() as u64,
        latch(d.biss.latch_latency()),
    );
    if let Some(s) = &d.ssi {
        row(
            "SSI frame",
            pos + s.latch_latency() as u64,
            latch(s.latch_latency()),
        );
    }
    if let Some(s) = &d.spi {
        row(
            "SPI word",
            pos + s.latch_latency() as u64,
            latch(s.latch_latency()),
        );
    }
    if let Some(a) = &d.abz {
        row(
            "ABZ first edge",
            pos + a.latency() as u64,
            format!(
                "{start} to par_position, then {} clocks to the first A/B edge of the new position (emitter idle)",
                a.latency()
            ),
        );
    }
    if let Some(v) = &d.velocity {
        row(
            "velocity (par_velocity)",
            v.latency(),
            "from the update's tick to par_velocity_valid (the position it uses is already CONV-to-position old)".into(),
        );
    }
    rows
}

/// The tables.
pub fn sheet(
    loaded: &Loaded,
    opts: &Options,
    plan: &Plan,
    runs: &Runs,
    an: &Analysis,
) -> Result<Sheet> {
    let d = &loaded.derived;
    let counts_per_turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
    let io: SimOptions = imperfect_options();
    let accuracy = runs
        .accuracy
        .iter()
        .zip(&an.accuracy)
        .zip(&plan.accuracy_rpm)
        .map(|((out, a), &rpm)| {
            let (raw_max, raw_rms) = max_rms(a.before.iter().map(|p| p.1));
            AccuracyRow {
                rpm,
                samples: out.stats.samples,
                raw_max_lsb: raw_max,
                raw_rms_lsb: raw_rms,
                max_lsb: out.stats.max_lsb,
                rms_lsb: out.stats.rms_lsb,
            }
        })
        .collect();
    let sweep = plan
        .sweep_rpm
        .iter()
        .zip(runs.sweep_ideal.iter().zip(&runs.sweep_imperfect))
        .map(|(&rpm, (i, m))| SweepRow {
            rpm,
            above_limit: rpm > plan.limit_rpm,
            ideal_max_lsb: i.stats.max_lsb,
            ideal_rms_lsb: i.stats.rms_lsb,
            max_lsb: m.stats.max_lsb,
            rms_lsb: m.stats.rms_lsb,
            velocity_noise_rpm: m
                .result
                .velocity_stats(d)
                .map(|v| v.std_err * v.rpm_per_lsb),
        })
        .collect();
    let p = &d.correction;
    let automatic = p.fit().is_some() || p.auto().is_some();
    let velocity = d.velocity.as_ref().map(|v| VelocitySheet {
        method: v.spec.method.to_string(),
        rate_hz: v.spec.rate_hz,
        lsb_rpm: v.lsb_rpm(d.quadrants_per_turn as f64),
        latency_cycles: v.latency(),
        lag_periods: v.lag_periods(),
        lag_ms: v.lag_s() * 1e3,
        measured_lag_ms: plan
            .velocity
            .and_then(|vp| measured_lag(&an.ramp, vp.at, vp.ramp_s, vp.rpm)),
        step_rpm: plan.velocity.map(|vp| vp.rpm).unwrap_or(0.0),
    });
    Ok(Sheet {
        generator: format!(
            "sinedec {} (commit {})",
            crate::emit::VERSION,
            crate::emit::commit()
        ),
        config_name: loaded.source_name.clone(),
        config_hash: loaded.hash(),
        command: opts.command.clone(),
        quick: opts.quick,
        overview: Overview {
            clock_mhz: d.clock_hz / 1e6,
            sample_rate_sps: d.sample_rate_hz,
            resolution_bits: d.resolution_bits,
            lsb_arcsec: 360.0 * 3600.0 / counts_per_turn,
            unwrap_limit_rpm: plan.limit_rpm,
            qep_fallback: d.qep_enabled,
        },
        conditions: Conditions {
            amplitude: io.amplitude,
            noise_lsb: io.noise_lsb,
            offset_sin: io.offset.0,
            offset_cos: io.offset.1,
            gain_mismatch: io.gain_mismatch,
            phase_error_deg: io.phase_error_deg,
            harmonic3: io.third_harmonic,
            seed: io.seed,
        },
        accuracy,
        sweep,
        latency: latency(loaded),
        correction: CorrectionSheet {
            mode: loaded.config.correction.mode.clone(),
            automatic,
            updates: an.coefs.len().saturating_sub(1),
            last_update_ms: automatic
                .then(|| an.coefs.last().map(|c| c.t_s * 1e3))
                .flatten(),
        },
        velocity,
        resources: super::resources::resources(loaded, opts.config_arg.as_deref())?,
        config_text: loaded.text.clone(),
    })
}

/// The estimate's mean lag behind the encoder's speed over the middle half of the ramp
/// (from `at` for `ramp_s`, `rpm` to `-rpm`), seconds -> ms.
fn measured_lag(trace: &[(f64, f64, f64)], at: f64, ramp_s: f64, rpm: f64) -> Option<f64> {
    let accel = -2.0 * rpm / ramp_s;
    if accel == 0.0 {
        return None;
    }
    let lags: Vec<f64> = trace
        .iter()
        .filter(|p| p.0 > at + ramp_s * 0.25 && p.0 < at + ramp_s * 0.75)
        .map(|p| (p.1 - p.2) / -accel)
        .collect();
    (!lags.is_empty()).then(|| lags.iter().sum::<f64>() / lags.len() as f64 * 1e3)
}
