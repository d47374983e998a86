//! `sinedec simulate`: the cycle-accurate closed-loop simulation of `<name>_top` against the
//! encoder and chip models (see `sim::system`), with error statistics, CSV and VCD output.
use crate::config::Loaded;
use crate::csv_out::CsvText;
use crate::error::{Error, Result};
use crate::sim::encoder::{EncoderModel, Profile};
use crate::sim::system::{ErrorStats, SimResult, System};
use std::fmt::Write as _;

mod capacitive;
mod faults;
mod options;

pub use capacitive::*;
pub use faults::*;
pub use options::*;

/// The encoder model for the options (2048 PPR etc. from the config), with the options'
/// track and speed faults (`--fault`).
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
    e.second_harmonic = o.second_harmonic;
    e.third_harmonic = o.third_harmonic;
    e.fifth_harmonic = o.fifth_harmonic;
    e.harmonic_phase = o.harmonic_phase_deg.map(f64::to_radians);
    e.eccentricity = (o.eccentricity_arcsec / 3600.0).to_radians();
    apply_to_encoder(loaded, o, &mut e);
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
    /// The faults injected (`--fault`).
    pub faults: Vec<FaultSpec>,
    /// The first cycle whose decoded samples count (`--settle`; 0 without it).
    pub settle_cycle: u64,
    /// The encoder's eccentricity, arc-seconds (`--eccentricity`).
    pub eccentricity_arcsec: f64,
}

/// The first cycle whose decoded samples count in the statistics: `--settle` in cycles.
pub fn settle_cycle(d: &crate::config::Derived, o: &SimOptions) -> u64 {
    (o.settle_s * d.clock_hz).ceil() as u64
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

/// MA frequency of the BiSS-C master `simulate` reads the top with (or the slave's limit,
/// if lower): a common rate for a few metres of cable.
pub const BISS_MA_HZ: f64 = 2.5e6;

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

/// How often `simulate` reads STATUS (`[registers] enabled`): every 10 us, in cycles.
pub fn status_poll_cycles(d: &crate::config::Derived) -> u64 {
    (d.clock_hz * 10e-6).round() as u64
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
    let d = &loaded.derived;
    let mut sys = System::on(d, encoder(loaded, o), o.engine)?;
    apply_to_system(o, &mut sys);
    let settle = |e: crate::cosim::step::NoConvergence| Error::HdlCheck {
        block: "top".into(),
        message: e.to_string(),
    };
    if o.record {
        sys.record_inputs();
    }
    let from_cycle = settle_cycle(d, o);
    if !o.keep_records {
        sys.stream_stats_from(o.skip, from_cycle);
    }
    sys.monitor_biss(BISS_MA_HZ.min(d.biss.max_ma_hz()), o.duration_s);
    // SSI and SPI masters at the BiSS rate, slower where the slave's synchronizer or the
    // round trip (the master reads at the next rising edge) needs it.
    if let Some(x) = &d.ssi {
        let a = crate::blocks::serial::answer_window(x.clock_hz, x.glitch_filter, &d.io_timing);
        let by_line = 1e9 / (a.max_ns + 2.0 * d.io_timing.trace_ns);
        let by_sync =
            x.clock_hz / (2 * crate::blocks::serial::min_level_clocks(x.glitch_filter)) as f64;
        sys.monitor_ssi(BISS_MA_HZ.min(by_line).min(by_sync), o.duration_s);
    }
    if let Some(x) = &d.spi {
        sys.monitor_spi(
            BISS_MA_HZ.min(x.max_sck_hz(d.io_timing.trace_ns)),
            o.duration_s,
        );
    }
    match (&d.capture, o.capture_hz) {
        (None, Some(hz)) => {
            return Err(Error::option(
                "--capture-hz",
                format!("{hz}: this config has no capture input; set [capture] enabled = true"),
            ))
        }
        (None, None) => {}
        (Some(_), hz) => {
            let hz = hz.unwrap_or(DEFAULT_CAPTURE_HZ);
            let n = (o.duration_s * hz).floor() as usize;
            let pulses: Vec<(f64, f64)> = (1..=n)
                .map(|k| k as f64 / hz)
                .map(|t| (t, t + CAPTURE_PULSE_S))
                .collect();
            sys.capture_pulses(&pulses);
        }
    }
    // With the register map the loop reads STATUS's latched faults as a drive would.
    if d.registers.is_some() {
        sys.poll_status(status_poll_cycles(d));
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
    let stats = result.stats_from(d, o.skip, from_cycle);
    if stats.samples == 0 && o.settle_s > 0.0 && result.decoded > o.skip {
        // Samples were decoded past the settling ones, all before `--settle`.
        return Err(Error::option(
            "--settle",
            format!(
                "{} s: leaves no sample: the {} samples decoded in the {} s run all left the top before it; use a shorter --settle or a longer --duration",
                o.settle_s, result.decoded, o.duration_s
            ),
        ));
    }
    if stats.samples == 0 {
        // The first position leaves the top at the ADC's start-up plus the latency; the
        // statistics start after `skip` more sample periods.
        let need = ((d.adc.startup_clocks() + crate::blocks::top::hdl::BLOCK_RESET_CLOCKS) as f64
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
        settle_cycle: from_cycle,
        eccentricity_arcsec: o.eccentricity_arcsec,
        wall_s,
        engine,
        engine_note,
        faults: o.faults.clone(),
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
        if self.settle_cycle > 0 {
            let _ = writeln!(
                o,
                "statistics from             {:.6} s (--settle; cycle {})",
                self.settle_cycle as f64 / d.clock_hz,
                self.settle_cycle
            );
        }
        if self.eccentricity_arcsec != 0.0 {
            let _ = writeln!(
                o,
                "eccentricity                {:.2} arc-seconds = {:.2} LSB once per turn, in the figures above: an error of the shaft's angle, which no per-period correction (offset, gain, phase, harmonic table) can remove",
                self.eccentricity_arcsec.abs(),
                self.eccentricity_arcsec.abs() / arcsec
            );
        }
        let _ = writeln!(o, "samples with error flag     {}", s.errors);
        let _ = writeln!(o, "samples with warning flag   {}", s.warnings);
        let _ = writeln!(o, "latency mismatches          {}", r.latency_mismatches);
        let _ = match r.adc_violations.first() {
            Some(first) => writeln!(
                o,
                "ADC protocol violations     {} (first: {first})",
                r.adc_violations.len()
            ),
            None => writeln!(o, "ADC protocol violations     0"),
        };
        if d.preamp.is_some() {
            let gains = match r.amp_gains {
                Some((a, b)) => format!("A {a}, B {b}"),
                None => "none (no complete gain word reached the amplifier)".to_string(),
            };
            let _ = writeln!(o, "preamp gains read back      {gains}");
        }
        o.push_str(&self.velocity_summary(loaded));
        o.push_str(&self.capture_summary(loaded));
        o.push_str(&self.absolute_summary(loaded));
        o.push_str(&self.fault_summary(loaded));
        if let Some(b) = &r.biss {
            let _ = writeln!(
                o,
                "BiSS-C frames               {} read at {:.2} MHz MA: {} good, {} CRC errors, {} unreadable; {} positions unequal to par_position",
                b.frames,
                b.ma_hz as f64 / 1e6,
                b.good,
                b.crc_errors,
                b.failed,
                b.position_mismatches
            );
        }
        for (name, c) in [("SSI frames ", &r.ssi), ("SPI words  ", &r.spi)] {
            if let Some(c) = c {
                let _ = writeln!(
                    o,
                    "{name}                 {} read at {:.2} MHz: {} good, {} unreadable; {} positions unequal to par_position",
                    c.frames,
                    c.clock_hz as f64 / 1e6,
                    c.good,
                    c.failed,
                    c.position_mismatches
                );
            }
        }
        if let Some(c) = &r.abz {
            let _ = writeln!(
                o,
                "ABZ quadrature count        {} edges, {} index pulses, {} illegal transitions; against {} samples' positions: max {} edges off, {} at the end",
                c.edges, c.index_pulses, c.illegal, c.checked, c.max_lag, c.last_lag
            );
        }
        let _ = writeln!(
            o,
            "simulation speed            {:.0} cycles/s ({:.2} s, {} engine)",
            r.cycles as f64 / self.wall_s.max(1e-9),
            self.wall_s,
            self.engine.name()
        );
        o
    }

    /// The absolute start's lines of the summary (`[reference] absolute`; empty otherwise):
    /// what the encoder's SSI channel stored and when the position became absolute; the
    /// error figures above count the referenced samples only, against the absolute truth.
    fn absolute_summary(&self, loaded: &Loaded) -> String {
        let d = &loaded.derived;
        let (Some(p), Some(a)) = (&d.absolute, &self.result.absolute) else {
            return String::new();
        };
        let us = |c: u64| c as f64 * 1e6 / d.clock_hz;
        let q = d.quadrants_per_turn as f64;
        let mut o = String::new();
        let w = p.word();
        let stored = match a.latches.first() {
            Some(l) => {
                let x = l.turns * q;
                format!(
                    "{} word(s) of {} bits stored, the first at {:.2} us: turn {}, quadrant {:.3}",
                    a.latches.len(),
                    w.bits(),
                    l.at_ns * 1e-3,
                    (x / q).floor(),
                    x.rem_euclid(q)
                )
            }
            None => "no word stored".to_string(),
        };
        let refd = match a.referenced_cycle {
            Some(c) => format!("absolute from cycle {c} ({:.1} us)", us(c)),
            None => "never referenced".to_string(),
        };
        let _ = writeln!(
            o,
            "absolute start              {stored}; {refd}; {} timing violations of the channel ({:.0} ns cable); the error figures count the referenced samples against the absolute position",
            a.violations.len(),
            a.line_delay_ns
        );
        o
    }

    /// The fault lines of the summary: the faults injected (`--fault`), and with
    /// `[registers] enabled` each fault STATUS latched, with the exact cycle its live flag
    /// rose (the top's `flags` port) and the polls that read it through AXI4-Lite.
    fn fault_summary(&self, loaded: &Loaded) -> String {
        let d = &loaded.derived;
        let mut out = String::new();
        let injected = &self.faults;
        if !injected.is_empty() {
            let list: Vec<String> = injected.iter().map(FaultSpec::describe).collect();
            let _ = writeln!(out, "faults injected             {}", list.join("; "));
        }
        if d.registers.is_none() {
            if !injected.is_empty() {
                let _ = writeln!(
                    out,
                    "latched faults              not read: no register map ([registers] enabled = true adds STATUS)"
                );
            }
            return out;
        }
        let r = &self.result;
        let us = |c: u64| c as f64 * 1e6 / d.clock_hz;
        let _ = writeln!(
            out,
            "STATUS polls                {} (every {} cycles = 10 us through AXI4-Lite, each clearing what it read): {}",
            r.status_polls,
            status_poll_cycles(d),
            if r.faults.is_empty() { "no fault latched" } else { "faults below (cycles exact, from the live flags)" }
        );
        for f in &r.faults {
            let raised = match f.raised {
                Some(c) => format!(
                    "raised at cycle {c} ({:.3} us), live last at {} ({:.3} us), {} rise{}",
                    us(c),
                    f.last,
                    us(f.last),
                    f.rises,
                    if f.rises == 1 { "" } else { "s" }
                ),
                None => "raised (no cycle showed its live flag)".to_string(),
            };
            let polled = match f.polls {
                0 => "not polled yet".to_string(),
                n => format!(
                    "found by {n} poll{} (first in cycles {}..{}), {}",
                    if n == 1 { "" } else { "s" },
                    f.after,
                    f.by,
                    if f.cleared {
                        "cleared"
                    } else {
                        "still set at the last poll"
                    }
                ),
            };
            let _ = writeln!(out, "latched fault {:<14} {raised}; {polled}", f.name);
        }
        out
    }

    /// The capture lines of the summary (`[capture] enabled`; empty otherwise): the ages
    /// and the captured positions against the encoder's angle at each pin.
    fn capture_summary(&self, loaded: &Loaded) -> String {
        let d = &loaded.derived;
        let (Some(c), Some(s)) = (&d.capture, self.result.capture_stats(d)) else {
            return String::new();
        };
        let ns = |a: u64| a as f64 * 1e9 / d.clock_hz;
        let mut o = String::new();
        let _ = writeln!(
            o,
            "captures                    {}: age {}..{} clocks = {:.0}..{:.0} ns from the sampling CONV edge",
            s.captures,
            s.age.0,
            s.age.1,
            ns(s.age.0),
            ns(s.age.1)
        );
        let how = if c.extrapolation().is_some() {
            "extrapolated by velocity x (age + 1/2 clock); after the velocity's warm-up"
        } else {
            "not extrapolated: the position trails by the motion during its age"
        };
        let _ = match s.counted {
            0 => writeln!(
                o,
                "capture error at the pin    no capture counted yet ({how}); run longer"
            ),
            n => writeln!(
                o,
                "capture error at the pin    max {:.2} LSB, RMS {:.2} LSB over {n} captures ({how})",
                s.max_lsb, s.rms_lsb
            ),
        };
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
                    + (d.adc.startup_clocks() + crate::blocks::top::hdl::BLOCK_RESET_CLOCKS) as f64
                        / d.clock_hz
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
                &((i < skip || r.cycle < self.settle_cycle) as u8),
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
/// `truth_cycle` is the cycle at which the true angle `truth_lsb` is taken (the conversion
/// start that sampled the inputs on the sinewave path, a CONV rise or a chip-select fall;
/// `par_valid` on the capacitive path).
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
