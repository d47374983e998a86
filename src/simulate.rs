//! `sinedec simulate`: the cycle-accurate closed-loop simulation of `<name>_top` against the
//! encoder and chip models (see `sim::system`), with error statistics, CSV and VCD output.
use crate::config::Loaded;
use crate::csv_out::CsvText;
use crate::error::{Error, Result};
use crate::sim::encoder::{EncoderModel, Profile};
use crate::sim::system::{ErrorStats, SimResult, System};
use std::fmt::Write as _;

/// What to simulate.
#[derive(Clone, Debug)]
pub struct SimOptions {
    /// Speed profile.
    pub profile: Profile,
    /// Simulated time in seconds.
    pub duration_s: f64,
    /// Track amplitude as a fraction of the ADC's input range (1.25 V): 0.8 = 1.0 V.
    pub amplitude: f64,
    /// Gaussian noise RMS in ADC LSB.
    pub noise_lsb: f64,
    /// Offsets of the sin and cos tracks as fractions of the amplitude.
    pub offset: (f64, f64),
    /// Relative gain mismatch between the tracks.
    pub gain_mismatch: f64,
    /// Quadrature phase error in degrees.
    pub phase_error_deg: f64,
    /// Third-harmonic ratio.
    pub third_harmonic: f64,
    /// Noise seed.
    pub seed: u64,
    /// Record every cycle's pins (for a VCD).
    pub record: bool,
    /// Engine of the top: the compiled engine (the default; `crate::engine`, with the
    /// fallbacks of `crate::sim::dut`), its interpreter, or rust-hdl (the reference).
    pub engine: crate::sim::dut::EngineKind,
    /// Keep every decoded sample (for [`SimReport::csv`]); without them the statistics are
    /// gathered as the samples come and memory stays bounded however long the run.
    pub keep_records: bool,
    /// Decoded samples skipped before the statistics (settling: the monitor reports a
    /// loss of signal until its window of good samples has passed after reset).
    pub skip: usize,
}

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            profile: Profile::Constant { rpm: 300.0 },
            duration_s: 0.002,
            amplitude: 0.8,
            noise_lsb: 0.0,
            offset: (0.0, 0.0),
            gain_mismatch: 0.0,
            phase_error_deg: 0.0,
            third_harmonic: 0.0,
            seed: 1,
            record: false,
            engine: Default::default(),
            keep_records: true,
            skip: 12,
        }
    }
}

/// Largest speed `simulate` accepts, rpm (either direction): far above any servo motor
/// (16,667 turns per second) and small enough that the angle stays exact in f64.
pub const MAX_RPM: f64 = 1.0e6;

/// Largest simulated time, seconds.
pub const MAX_DURATION_S: f64 = 10.0;

impl SimOptions {
    /// Rejects meaningless options before anything runs; errors name the command-line
    /// option and its allowed range. `capacitive`: the capacitive path, whose encoder model
    /// has one receiver signal (no sin/cos tracks): the track imperfections do not apply.
    pub fn validate(&self, capacitive: bool) -> Result<()> {
        let bad = |opt: &str, v: f64, allowed: &str| {
            Err(Error::option(opt, format!("{v}: allowed {allowed}")))
        };
        let speed = |v: f64, what: &str| -> Result<()> {
            if v.is_finite() && v.abs() <= MAX_RPM {
                Ok(())
            } else {
                Err(Error::option(
                    "--profile",
                    format!("{what} {v} rpm: allowed a finite speed within -{MAX_RPM:.0}..={MAX_RPM:.0} rpm"),
                ))
            }
        };
        let time = |v: f64, what: &str, zero_ok: bool| -> Result<()> {
            if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) && v <= 1e3 {
                Ok(())
            } else {
                Err(Error::option(
                    "--profile",
                    format!(
                        "{what} {v} s: allowed {} seconds up to 1000",
                        if zero_ok { "0 <=" } else { "0 <" }
                    ),
                ))
            }
        };
        match self.profile {
            Profile::Constant { rpm } => speed(rpm, "speed")?,
            Profile::Ramp { from, to, over } => {
                speed(from, "start speed")?;
                speed(to, "end speed")?;
                time(over, "ramp time", false)?;
            }
            Profile::Reversal { rpm, at, over } => {
                speed(rpm, "speed")?;
                time(at, "reversal start", true)?;
                time(over, "reversal time", false)?;
            }
        }
        if !(self.duration_s > 0.0 && self.duration_s <= MAX_DURATION_S) {
            return bad("--duration", self.duration_s, "0 < seconds <= 10");
        }
        if !(self.amplitude > 0.0 && self.amplitude <= 1.0) {
            return bad(
                "--amplitude",
                self.amplitude,
                "0 < amplitude <= 1 (fraction of the ADC's input range)",
            );
        }
        if !(self.noise_lsb >= 0.0 && self.noise_lsb <= 1e4) {
            return bad("--noise-lsb", self.noise_lsb, "0..=10000 LSB RMS");
        }
        let track = [
            (
                "--offset-sin",
                self.offset.0,
                1.0,
                "-1..=1 (fraction of the amplitude)",
            ),
            (
                "--offset-cos",
                self.offset.1,
                1.0,
                "-1..=1 (fraction of the amplitude)",
            ),
            (
                "--gain-mismatch",
                self.gain_mismatch,
                1.0,
                "-1..=1 (relative)",
            ),
            (
                "--phase-error",
                self.phase_error_deg,
                45.0,
                "-45..=45 degrees",
            ),
            (
                "--harmonic3",
                self.third_harmonic,
                0.5,
                "-0.5..=0.5 (ratio)",
            ),
        ];
        for (opt, v, lim, allowed) in track {
            if v.is_nan() || v.abs() > lim {
                return bad(opt, v, allowed);
            }
            if capacitive && v != 0.0 {
                return Err(Error::option(
                    opt,
                    format!("{v}: does not apply to the capacitive path (its encoder model has one receiver signal, no sin/cos tracks); leave it at 0"),
                ));
            }
        }
        Ok(())
    }
}

/// Parses a profile: `constant:RPM`, `ramp:FROM:TO:SECONDS`, `reversal:RPM:AT_S:OVER_S`,
/// or `creep` (0.3 rpm).
pub fn parse_profile(s: &str) -> Result<Profile> {
    let parts: Vec<&str> = s.split(':').collect();
    let bad = |m: String| Error::option("--profile", m);
    let num = |i: usize| -> Result<f64> {
        parts
            .get(i)
            .ok_or_else(|| bad(format!("`{s}`: missing field {i}")))?
            .parse::<f64>()
            .map_err(|e| bad(format!("`{s}`: field {i}: {e}")))
    };
    let p = match parts[0] {
        "constant" if parts.len() == 2 => Profile::Constant { rpm: num(1)? },
        "ramp" if parts.len() == 4 => Profile::Ramp {
            from: num(1)?,
            to: num(2)?,
            over: num(3)?,
        },
        "reversal" if parts.len() == 4 => Profile::Reversal {
            rpm: num(1)?,
            at: num(2)?,
            over: num(3)?,
        },
        "creep" if parts.len() == 1 => Profile::creep(),
        _ => {
            return Err(bad(format!(
                "`{s}`: allowed constant:RPM, ramp:FROM:TO:SECONDS, reversal:RPM:AT_S:OVER_S, creep"
            )))
        }
    };
    Ok(p)
}

/// The encoder model for the options (2048 PPR etc. from the config).
pub fn encoder(loaded: &Loaded, o: &SimOptions) -> EncoderModel {
    let d = &loaded.derived;
    let gain = d
        .preamp
        .as_ref()
        .map(|p| p.gain_a.unsigned_abs().max(1) as f64)
        .unwrap_or(1.0);
    // Volts per ADC LSB at the ADC input referred back to the encoder: 1.25 V / 8192 / |G|.
    let lsb_v = 1.25 / (1u64 << (d.adc_width - 1)) as f64 / gain;
    let amp_v = o.amplitude * 1.25 / gain;
    let mut e = EncoderModel::ideal(loaded.config.encoder.ppr, amp_v, 0.0).with_seed(o.seed);
    e.profile = o.profile.clone();
    e.noise_rms = o.noise_lsb * lsb_v;
    e.offset_sin = o.offset.0 * amp_v;
    e.offset_cos = o.offset.1 * amp_v;
    e.gain_mismatch = o.gain_mismatch;
    e.phase_error = o.phase_error_deg.to_radians();
    e.third_harmonic = o.third_harmonic;
    e
}

/// A finished simulation.
pub struct SimReport {
    /// Raw result.
    pub result: SimResult,
    /// Error statistics.
    pub stats: ErrorStats,
    /// Wall-clock seconds the simulation took.
    pub wall_s: f64,
    /// The engine that ran the top (after any fallback).
    pub engine: crate::sim::dut::EngineKind,
    /// Why that is not the engine asked for, if it is not (one line).
    pub engine_note: Option<String>,
}

/// Runs the simulation; `progress(done, total)` is called every 2^14 cycles.
pub fn run(loaded: &Loaded, o: &SimOptions, progress: impl FnMut(u64, u64)) -> Result<SimReport> {
    run_traced(loaded, o, progress, None)
}

/// The VCD writer for `<name>_top` (see [`crate::sim::vcd`]).
fn top_trace(
    loaded: &Loaded,
    out: Box<dyn std::io::Write>,
    block: &impl crate::cosim::CosimBlock,
) -> Result<crate::sim::vcd::TopTrace> {
    let d = &loaded.derived;
    crate::sim::vcd::TopTrace::new(
        out,
        &crate::emit::top_name(loaded),
        &crate::emit::top_ports(loaded),
        &block.input_ports(),
        &block.output_ports(),
        d.fine_bits,
        (1e12 / d.clock_hz).round() as u64,
    )
    .map_err(|e| Error::io("VCD output", e))
}

/// Settling time of the capacitive path (band-pass, demodulation and low-pass filters):
/// positions before it are not measured, and a shorter `--duration` is refused.
pub const CAP_SETTLE_S: f64 = 1.5e-3;

/// The highest speed `profile` reaches within `duration_s`, rpm (absolute).
pub fn peak_rpm(profile: &Profile, duration_s: f64) -> f64 {
    match *profile {
        Profile::Constant { rpm } => rpm.abs(),
        Profile::Ramp { from, to, over } => {
            let end = from + (to - from) * (duration_s / over).clamp(0.0, 1.0);
            from.abs().max(end.abs())
        }
        Profile::Reversal { rpm, .. } => rpm.abs(),
    }
}

/// The fastest the decoder follows, rpm: the fine-angle unwrap's limit (1.75 quadrants per
/// sample, where the monitor warns) and, on the capacitive path, the low-pass corner.
pub fn followable_rpm(loaded: &Loaded) -> f64 {
    let d = &loaded.derived;
    match &d.capacitive {
        Some(k) => {
            let ppr = d.quadrants_per_turn as f64 / 4.0;
            let corner = k.config.lowpass.corner_hz.unwrap_or(f64::INFINITY);
            (corner / ppr * 60.0).min(d.max_speed_rpm_full_res)
        }
        None => d.max_speed_rpm_full_res,
    }
}

/// A one-line warning when `o`'s profile is faster than the decoder follows
/// ([`followable_rpm`]): its error figures then measure a lost track, not accuracy.
pub fn speed_warning(loaded: &Loaded, o: &SimOptions) -> Option<String> {
    let peak = peak_rpm(&o.profile, o.duration_s);
    let limit = followable_rpm(loaded);
    (peak > limit).then(|| {
        format!(
            "warning: --profile reaches {peak:.0} rpm, above the {limit:.0} rpm this decoder follows (see `sinedec check`, max speed); the error figures measure a lost track, not accuracy"
        )
    })
}

/// The error for a run that decoded no sample past the settling ones.
fn no_sample(duration_s: f64, decoded: usize, skip: String, need_s: f64) -> Error {
    Error::option(
        "--duration",
        format!(
            "{duration_s} s: no decoded sample to compare ({decoded} decoded, {skip}); use at least {need_s:.6} s"
        ),
    )
}

/// [`run`], streaming `<name>_top`'s pins as VCD into `vcd` cycle by cycle (bounded
/// memory).
pub fn run_traced(
    loaded: &Loaded,
    o: &SimOptions,
    mut progress: impl FnMut(u64, u64),
    vcd: Option<Box<dyn std::io::Write>>,
) -> Result<SimReport> {
    o.validate(false)?;
    loaded.needs_board_top("simulate")?;
    let d = &loaded.derived;
    let mut sys = System::on(d, encoder(loaded, o), o.engine)?;
    let settle = |e: crate::cosim::step::NoConvergence| Error::HdlCheck {
        block: "top".into(),
        message: e.to_string(),
    };
    if o.record {
        sys.record_inputs();
    }
    if !o.keep_records {
        sys.stream_stats(o.skip);
    }
    let engine = sys.engine();
    let engine_note = sys.engine_note().map(str::to_string);
    if let Some(out) = vcd {
        let t = top_trace(loaded, out, &crate::blocks::top::hdl::TopRtl::new(d)?)?;
        sys.trace_to(t);
    }
    sys.start().map_err(settle)?;
    let total = (o.duration_s * d.clock_hz).ceil() as u64;
    let t0 = std::time::Instant::now();
    let chunk = 1 << 14;
    let mut done = 0;
    while done < total {
        let n = chunk.min(total - done);
        sys.run(n).map_err(settle)?;
        done += n;
        progress(done, total);
    }
    let wall_s = t0.elapsed().as_secs_f64();
    sys.finish_trace().map_err(|e| Error::io("VCD output", e))?;
    let result = sys.finish();
    let stats = result.stats(d, o.skip);
    if stats.samples == 0 {
        // The first position leaves the top at the ADC's start-up plus the latency; the
        // statistics start after `skip` more sample periods.
        let need = (d.adc.startup_clocks() as f64
            + crate::blocks::top::hdl::conv_to_position_cycles(d) as f64
            + (o.skip as f64 + 1.0) * d.adc.period_clocks as f64)
            / d.clock_hz;
        return Err(no_sample(
            o.duration_s,
            result.decoded,
            format!("the first {} are settling", o.skip),
            need,
        ));
    }
    Ok(SimReport {
        result,
        stats,
        wall_s,
        engine,
        engine_note,
    })
}

impl SimReport {
    /// Human-readable summary.
    pub fn summary(&self, loaded: &Loaded) -> String {
        let d = &loaded.derived;
        let counts_per_turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
        let arcsec = 360.0 * 3600.0 / counts_per_turn;
        let s = &self.stats;
        let r = &self.result;
        let mut o = String::new();
        let _ = writeln!(o, "simulated cycles            {}", r.cycles);
        let _ = writeln!(
            o,
            "decoded samples             {} ({} in the statistics)",
            r.decoded, s.samples
        );
        let _ = writeln!(
            o,
            "sample rate                 {:.0} samples/s per channel",
            d.sample_rate_hz
        );
        let _ = writeln!(
            o,
            "latency CONV -> position    {} cycles = {:.0} ns",
            crate::blocks::top::hdl::conv_to_position_cycles(d),
            crate::blocks::top::hdl::conv_to_position_cycles(d) as f64 * 1e9 / d.clock_hz
        );
        let _ = writeln!(
            o,
            "max |error|                 {:.2} LSB = {:.2} arc-seconds",
            s.max_lsb,
            s.max_lsb * arcsec
        );
        let _ = writeln!(
            o,
            "RMS error                   {:.2} LSB = {:.2} arc-seconds",
            s.rms_lsb,
            s.rms_lsb * arcsec
        );
        let _ = writeln!(o, "mean error                  {:.2} LSB", s.mean_lsb);
        let _ = writeln!(o, "samples with error flag     {}", s.errors);
        let _ = writeln!(o, "samples with warning flag   {}", s.warnings);
        let _ = writeln!(o, "latency mismatches          {}", r.latency_mismatches);
        let _ = writeln!(o, "ADC protocol violations     {}", r.adc_violations.len());
        let gains = match r.amp_gains {
            Some((a, b)) => format!("A {a}, B {b}"),
            None => "none (no complete gain word reached the amplifier)".to_string(),
        };
        let _ = writeln!(o, "preamp gains read back      {gains}");
        o.push_str(&self.velocity_summary(loaded));
        let _ = writeln!(
            o,
            "simulation speed            {:.0} cycles/s ({:.2} s, {} engine)",
            r.cycles as f64 / self.wall_s.max(1e-9),
            self.wall_s,
            self.engine.name()
        );
        o
    }

    /// The velocity lines of the summary (`[velocity] enabled`; empty otherwise): the
    /// estimate against the encoder model's true speed after the estimator's warm-up, in
    /// position LSB per update period and in rpm.
    fn velocity_summary(&self, loaded: &Loaded) -> String {
        let d = &loaded.derived;
        let Some(v) = &d.velocity else {
            return String::new();
        };
        let mut o = String::new();
        let rate = d.clock_hz / v.period_clocks as f64;
        let _ = writeln!(
            o,
            "velocity updates            {} ({}, {rate:.1} Hz; warm-up: those before the first position, then {})",
            self.result.velocity.len(),
            v.spec.method,
            v.warmup_updates()
        );
        let Some(s) = self.result.velocity_stats(d) else {
            let _ = writeln!(
                o,
                "velocity error              no update after the warm-up; run at least {:.6} s",
                (v.warmup_updates() + 2) as f64 / rate
                    + crate::blocks::top::hdl::conv_to_position_cycles(d) as f64 / d.clock_hz
                    + d.adc.startup_clocks() as f64 / d.clock_hz
            );
            return o;
        };
        let rpm = |x: f64| x * s.rpm_per_lsb;
        let _ = writeln!(
            o,
            "velocity error mean         {:.4} LSB/period = {:.6} rpm ({} updates)",
            s.mean_err,
            rpm(s.mean_err),
            s.updates
        );
        let _ = writeln!(
            o,
            "velocity error std          {:.4} LSB/period = {:.6} rpm (max |error| {:.4} LSB/period)",
            s.std_err,
            rpm(s.std_err),
            s.max_err
        );
        let _ = writeln!(
            o,
            "velocity at the end         {:.4} LSB/period = {:.4} rpm (true {:.4} LSB/period = {:.4} rpm)",
            s.last,
            rpm(s.last),
            s.last_truth,
            rpm(s.last_truth)
        );
        o
    }

    /// CSV of every decoded sample; columns [`CSV_COLUMNS`] (documented in the README), plus
    /// [`VELOCITY_CSV_COLUMNS`] with `[velocity] enabled`.
    /// `error_lsb` = unwrapped - truth_lsb - the constant offset of
    /// [`SimResult::offset_lsb`], modulo the position's range; `warmup` marks the settling
    /// records left out of the statistics. `velocity_lsb` and `velocity_truth_lsb` are the
    /// latest velocity update at or before the record's cycle (par_velocity / 2^frac_bits and
    /// the true speed, position LSB per update period; empty before the first update).
    pub fn csv(&self, loaded: &Loaded, skip: usize) -> String {
        let d = &loaded.derived;
        let offset = self.result.offset_lsb(d);
        let vel = d.velocity.as_ref();
        let mut header: Vec<&str> = CSV_COLUMNS.to_vec();
        if vel.is_some() {
            header.extend(VELOCITY_CSV_COLUMNS);
        }
        let mut t = CsvText::new(header);
        let vs = &self.result.velocity;
        let mut k = 0;
        for (i, r) in self.result.records.iter().enumerate() {
            let (est, truth) = match vel {
                Some(v) => {
                    while k < vs.len() && vs[k].cycle <= r.cycle {
                        k += 1;
                    }
                    match k.checked_sub(1).map(|j| vs[j]) {
                        Some(u) => (
                            format!("{:.4}", u.raw as f64 / (1u64 << v.spec.frac_bits) as f64),
                            format!("{:.4}", u.truth),
                        ),
                        None => (String::new(), String::new()),
                    }
                }
                None => (String::new(), String::new()),
            };
            let base: [&dyn std::fmt::Display; 10] = [
                &r.cycle,
                &r.conv_cycle,
                &r.position,
                &r.turns,
                &r.unwrapped,
                &format_args!("{:.3}", r.truth),
                &format_args!("{:.3}", SimResult::error_lsb(d, r, offset)),
                &(r.error as u8),
                &(r.warning as u8),
                &((i < skip) as u8),
            ];
            if vel.is_some() {
                let mut row = base.to_vec();
                row.push(&est);
                row.push(&truth);
                t.row(&row);
            } else {
                t.row(&base);
            }
        }
        t.finish()
    }
}

/// Extra columns of `simulate --csv` with `[velocity] enabled` (see [`SimReport::csv`]).
pub const VELOCITY_CSV_COLUMNS: [&str; 2] = ["velocity_lsb", "velocity_truth_lsb"];

/// Columns of `simulate --csv`, the same on both paths (documented in the README):
/// `truth_cycle` is the cycle at which the true angle `truth_lsb` is taken (the CONV rise
/// that sampled the inputs on the sinewave path; `par_valid` on the capacitive path).
pub const CSV_COLUMNS: [&str; 10] = [
    "cycle",
    "truth_cycle",
    "position",
    "turns",
    "unwrapped",
    "truth_lsb",
    "error_lsb",
    "error",
    "warning",
    "warmup",
];

/// `simulate` for a configuration with `[capacitive]`: the capacitive top against the
/// capacitive-encoder model (16-bit ADC of 1 V full scale; `amplitude` is the received
/// amplitude as a fraction of the ADC's range, `noise_lsb` its noise in ADC LSB RMS;
/// offsets, gain mismatch, phase error and harmonics do not apply and are rejected).
/// Returns the summary and a CSV of every decoded position ([`CSV_COLUMNS`]).
pub fn run_capacitive(
    loaded: &Loaded,
    o: &SimOptions,
    progress: impl FnMut(u64, u64),
) -> Result<(String, String)> {
    run_capacitive_traced(loaded, o, progress, None)
}

/// [`run_capacitive`], streaming the capacitive `<name>_top`'s pins as VCD into `vcd`.
pub fn run_capacitive_traced(
    loaded: &Loaded,
    o: &SimOptions,
    progress: impl FnMut(u64, u64),
    vcd: Option<Box<dyn std::io::Write>>,
) -> Result<(String, String)> {
    let r = run_capacitive_report(loaded, o, progress, vcd)?;
    Ok((r.summary, r.csv))
}

/// A finished capacitive simulation.
pub struct CapReport {
    /// Human-readable summary.
    pub summary: String,
    /// CSV of every decoded position ([`CSV_COLUMNS`]; only the header when
    /// [`SimOptions::keep_records`] is off).
    pub csv: String,
    /// The engine that ran the top (after any fallback).
    pub engine: crate::sim::dut::EngineKind,
    /// Why that is not the engine asked for, if it is not (one line).
    pub engine_note: Option<String>,
}

/// [`run_capacitive_traced`] with the engine that ran.
pub fn run_capacitive_report(
    loaded: &Loaded,
    o: &SimOptions,
    mut progress: impl FnMut(u64, u64),
    vcd: Option<Box<dyn std::io::Write>>,
) -> Result<CapReport> {
    use crate::sim::cap_system::CapSystem;
    use crate::sim::capacitive::CapParams;
    o.validate(true)?;
    let d = &loaded.derived;
    let k = d.capacitive.as_ref().ok_or_else(|| {
        Error::Simulation("run_capacitive needs a configuration with [capacitive]".into())
    })?;
    // The settling window is fixed: a shorter run would measure the filters' transient.
    let skip = CAP_SETTLE_S;
    // Ten decoded positions past the settling window at least.
    let need = CAP_SETTLE_S + 10.0 / k.sample_rate_hz;
    if o.duration_s < need {
        return Err(Error::option(
            "--duration",
            format!(
                "{} s: the capacitive path's filters settle for the first {:.1} ms, which are not measured; use at least {need:.6} s",
                o.duration_s,
                CAP_SETTLE_S * 1e3
            ),
        ));
    }
    let mut p = CapParams::ideal(loaded.config.encoder.ppr, 0.0);
    p.profile = o.profile.clone();
    p.dac_bits = k.config.dac_width;
    p.coupling = o.amplitude / k.config.amplitude;
    p.noise_rms_v = o.noise_lsb * p.adc_full_scale_v / (1u64 << (d.adc.frame.width - 1)) as f64;
    p.seed = o.seed;
    let mut sys = CapSystem::on(d, p, o.engine)?;
    sys.keep_records(o.keep_records);
    let engine = sys.engine();
    let engine_note = sys.engine_note().map(str::to_string);
    if let Some(out) = vcd {
        let top = crate::blocks::captop::hdl::CapTopRtl::new(d)?;
        let t = top_trace(loaded, out, &top)?;
        sys.trace_to(t);
    }
    let settle = |e: crate::cosim::step::NoConvergence| Error::HdlCheck {
        block: "top".into(),
        message: e.to_string(),
    };
    sys.start().map_err(settle)?;
    let total = (o.duration_s * d.clock_hz).ceil() as u64;
    let t0 = std::time::Instant::now();
    let mut done = 0;
    while done < total {
        let n = (1u64 << 14).min(total - done);
        sys.run(n).map_err(settle)?;
        done += n;
        progress(done, total);
    }
    let wall = t0.elapsed().as_secs_f64();
    sys.finish_trace().map_err(|e| Error::io("VCD output", e))?;
    let s = sys.stats(skip);
    if s.samples == 0 {
        return Err(no_sample(
            o.duration_s,
            sys.decoded(),
            format!("those of the first {:.3} ms are settling", skip * 1e3),
            need,
        ));
    }
    let front = crate::blocks::capacitive::CapFrontParams::new(d)?;
    let us = |c: u32| c as f64 / d.clock_hz * 1e6;
    // error_lsb: decoded - truth minus the constant lag/offset the summary removes (the
    // mean over the statistics window), taken modulo one turn like the statistics.
    let turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
    let mean_lsb = s.mean_deg / 360.0 * turn;
    let skip_cycles = (skip * d.clock_hz) as u64;
    let mut t = CsvText::new(CSV_COLUMNS);
    for r in &sys.records {
        let e = r.decoded as f64 - r.truth - mean_lsb;
        t.row(&[
            &r.cycle,
            &r.cycle,
            &r.position,
            &r.turns,
            &r.decoded,
            &format_args!("{:.3}", r.truth),
            &format_args!("{:.3}", e - turn * (e / turn).round()),
            &(r.error as u8),
            &(r.warning as u8),
            &((r.cycle < skip_cycles) as u8),
        ]);
    }
    let csv = t.finish();
    let summary = format!(
        "capacitive path: {} periods per turn, carrier {:.0} Hz, {:.0} samples/s\n\
         positions after {:.1} ms of settling: {} ({} flagged)\n\
         error after removing the constant lag/offset ({:.4} deg): max {:.5} deg, mean |e| {:.5} deg, RMS {:.5} deg, p-p {:.5} deg (mechanical)\n\
         per sample: ADC conv->sample {} clocks ({:.2} us), filters+demod {} clocks ({:.2} us), CORDIC core {} clocks ({:.2} us), period {} clocks ({:.2} us)\n\
         simulated {} cycles in {:.2} s ({:.0} cycles/s, {} engine)\n",
        loaded.config.encoder.ppr,
        k.config.carrier_hz,
        k.sample_rate_hz,
        skip * 1e3,
        s.samples,
        s.flagged,
        s.mean_deg,
        s.max_deg,
        s.mean_abs_deg,
        s.rms_deg,
        s.pp_deg,
        d.adc.conv_to_valid_clocks(),
        us(d.adc.conv_to_valid_clocks()),
        front.cycles_per_sample(),
        us(front.cycles_per_sample()),
        d.latency_cycles,
        us(d.latency_cycles),
        d.adc.period_clocks,
        us(d.adc.period_clocks),
        sys.cycles(),
        wall,
        sys.cycles() as f64 / wall.max(1e-9),
        engine.name(),
    );
    Ok(CapReport {
        summary,
        csv,
        engine,
        engine_note,
    })
}
