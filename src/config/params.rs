//! Each block's parameters built from the config and checked against it: ADC and
//! pre-amplifier, ABZ, correction, monitor, capacitive front end (the checks across
//! blocks are in `checks.rs`, BiSS-C in `biss.rs`). Errors name the config key to change.

use super::*;

pub(super) type ErrFn<'a> = dyn Fn(&str, &str, String) -> Error + 'a;

/// ADC and preamp parameters from the config, validated against the chips' limits.
pub(super) fn adc_params(
    c: &Config,
    text: &str,
    err: &ErrFn,
) -> Result<(AdcParams, Option<PreampParams>)> {
    let a = c.adc.width;
    let clock_hz = c.clock.frequency_hz;
    let (frame, timing) = match c.adc.preset {
        AdcPreset::Ltc1407a1 => {
            if a != 14 {
                return Err(err(
                    "adc",
                    "width",
                    format!(
                        "the LTC1407A-1 delivers 14-bit samples; width {a} needs `adc.preset` = \"generic\""
                    ),
                ));
            }
            if c.adc.frame.is_some() || c.adc.timing.is_some() || c.adc.max_sample_rate_hz.is_some()
            {
                return Err(err(
                    "adc",
                    "preset",
                    "[adc.frame], [adc.timing] and max_sample_rate_hz apply to preset \"generic\" only".into(),
                ));
            }
            (AdcFrame::LTC1407A_1, AdcTiming::LTC1407A_1)
        }
        AdcPreset::Generic => {
            let max = c.adc.max_sample_rate_hz.ok_or_else(|| {
                err(
                    "adc",
                    "preset",
                    "preset \"generic\" needs `adc.max_sample_rate_hz` (the chip's per-channel limit)"
                        .into(),
                )
            })?;
            if !(max.is_finite() && max > 0.0) {
                return Err(err(
                    "adc",
                    "max_sample_rate_hz",
                    format!("{max} Hz: allowed a finite rate above 0 (the chip's per-channel limit in samples/s)"),
                ));
            }
            let f = c.adc.frame.clone().unwrap_or_default();
            let channels = f.channels.unwrap_or(2);
            if let Some(o) = &f.offsets {
                // One slot per channel; a one-channel frame may keep a second, unused one.
                let lo = channels.clamp(1, 2) as usize;
                if !(lo..=2).contains(&o.len()) {
                    return Err(err(
                        "adc.frame",
                        "offsets",
                        format!(
                            "{} entries: allowed one SCK slot per channel ({} with channels = {channels}), the first for sin (or the single channel), the second for cos",
                            o.len(),
                            if lo == 1 { "1 or 2" } else { "2" }
                        ),
                    ));
                }
            }
            if let Some(t) = &c.adc.timing {
                for (key, v) in [
                    ("sck_min_period_ns", t.sck_min_period_ns),
                    ("sck_min_pulse_ns", t.sck_min_pulse_ns),
                    ("data_valid_ns", t.data_valid_ns),
                    ("conv_min_pulse_ns", t.conv_min_pulse_ns),
                    ("conv_min_low_ns", t.conv_min_low_ns),
                    ("conv_to_sck_ns", t.conv_to_sck_ns),
                    ("acquisition_ns", t.acquisition_ns),
                ] {
                    if let Some(v) = v {
                        if !(0.0..=1e6).contains(&v) {
                            return Err(err(
                                "adc.timing",
                                key,
                                format!("{v} ns: allowed 0..=1000000 ns (a time from the ADC's data sheet)"),
                            ));
                        }
                    }
                }
            }
            let sign = match f.sign.as_deref() {
                None | Some("twos-complement") => SignFormat::TwosComplement,
                Some("offset-binary") => SignFormat::OffsetBinary,
                Some(other) => {
                    return Err(err(
                        "adc.frame",
                        "sign",
                        format!(
                            "{}: allowed \"twos-complement\" or \"offset-binary\"",
                            Quoted(other)
                        ),
                    ))
                }
            };
            let frame = AdcFrame {
                frame_sck: f.frame_sck.unwrap_or(2 * a + 4),
                channels,
                offsets: match f.offsets.as_deref() {
                    Some([x]) => [*x, 0],
                    Some([x, y, ..]) => [*x, *y],
                    _ => [1, a + 2],
                },
                width: a,
                sign,
                cpol: f.cpol.unwrap_or(false),
                cpha: f.cpha.unwrap_or(true),
                conv_active_high: f.conv_active_high.unwrap_or(true),
                conv_clocks: f.conv_clocks.unwrap_or(0),
                lead_clocks: f.lead_clocks.unwrap_or(0),
                pipeline: f.pipeline.unwrap_or(0),
            };
            let t = c.adc.timing.clone().unwrap_or_default();
            let timing = AdcTiming {
                sck_min_period_ns: t.sck_min_period_ns.unwrap_or(20.0),
                sck_max_period_ns: 0.0,
                sck_min_pulse_ns: t.sck_min_pulse_ns.unwrap_or(5.0),
                data_valid_ns: t.data_valid_ns.unwrap_or(10.0),
                conv_min_pulse_ns: t.conv_min_pulse_ns.unwrap_or(10.0),
                conv_min_low_ns: t.conv_min_low_ns.unwrap_or(10.0),
                conv_to_sck_ns: t.conv_to_sck_ns.unwrap_or(5.0),
                acquisition_ns: t.acquisition_ns.unwrap_or(0.0),
                conversion_edges: 0,
                max_sample_rate_hz: max,
            };
            (frame, timing)
        }
    };
    // SCK divider: as configured, or the smallest the chip's SCK limit allows.
    let d = match c.adc.sck_period_clocks {
        Some(d) => d,
        None => ((timing.sck_min_period_ns * clock_hz / 1e9) - 1e-9)
            .ceil()
            .max(2.0) as u32,
    };
    let build = |period: Option<u32>| match c.adc.preset {
        AdcPreset::Ltc1407a1 => AdcParams::ltc1407a(clock_hz, d, period),
        AdcPreset::Generic => AdcParams::generic(clock_hz, frame, timing, d, period),
    };
    let fastest = build(None);
    // The shortest period that respects the chip's rate limit too.
    let limit_period = AdcParams::period_for_rate(clock_hz, timing.max_sample_rate_hz);
    let mut params = if fastest.period_clocks < limit_period {
        build(Some(limit_period))
    } else {
        fastest
    };
    params
        .validate()
        .map_err(|m| adc_err(c, text, &m.detail(), None, err))?;
    if let Some(rate) = c.adc.sample_rate_hz {
        let p = AdcParams::period_for_rate(clock_hz, rate);
        if rate.is_nan() || rate <= 0.0 || p < params.period_clocks {
            return Err(err(
                "adc",
                "sample_rate_hz",
                format!(
                    "{rate} Hz is not reachable: at most {:.0} samples/s per channel at the clock of {} MHz (`clock.frequency_hz`) with an SCK period of {d} clocks (`adc.sck_period_clocks`), a frame of {} SCK (`adc.frame.frame_sck`) and the ADC's per-channel limit of {} samples/s (`adc.max_sample_rate_hz`); omit the key for the fastest",
                    params.sample_rate_hz(),
                    clock_hz / 1e6,
                    params.frame.frame_sck,
                    timing.max_sample_rate_hz
                ),
            ));
        }
        params = build(Some(p));
        params
            .validate()
            .map_err(|m| adc_err(c, text, &m.detail(), Some("sample_rate_hz"), err))?;
    }
    let preamp = match c.adc.preset {
        AdcPreset::Ltc1407a1 => {
            let pc = c.preamp.clone().unwrap_or_default();
            Some(
                PreampParams::new(clock_hz, pc.gain_a, pc.gain_b).map_err(|m| {
                    let m = m.detail();
                    err(
                        "preamp",
                        if m.contains("gain B") {
                            "gain_b"
                        } else {
                            "gain_a"
                        },
                        m,
                    )
                })?,
            )
        }
        AdcPreset::Generic => {
            if c.preamp.is_some() {
                return Err(err(
                    "preamp",
                    "gain_a",
                    "the LTC6912-1 pre-amplifier belongs to preset \"ltc1407a-1\"".into(),
                ));
            }
            None
        }
    };
    Ok((params, preamp))
}

/// An error of the ADC's checks (`AdcParams::validate`) at the key it belongs to (see
/// [`adc_keys`]): the first of the keys that set the value at fault that the text holds, else
/// `fallback` (in `[adc]`) or the first of them; the others the text holds are named after
/// the message.
fn adc_err(c: &Config, text: &str, m: &str, fallback: Option<&str>, err: &ErrFn) -> Error {
    let keys = adc_keys(c, m);
    let mut given = keys.iter().filter(|(t, k)| written(text, t, k));
    let (table, key) = match (given.next(), fallback) {
        (Some(&k), _) => k,
        (None, Some(f)) => ("adc", f),
        (None, None) => keys.first().copied().unwrap_or(("adc", "preset")),
    };
    let also: Vec<String> = keys
        .iter()
        .filter(|(t, k)| (*t, *k) != (table, key) && written(text, t, k))
        .map(|(t, k)| format!("`{t}.{k}`"))
        .collect();
    let m = if also.is_empty() {
        m.to_string()
    } else {
        format!("{m} (set by {})", also.join(", "))
    };
    err(table, key, m)
}

/// The keys that set the value an ADC check found at fault, by the message's subject, most
/// specific first (`adc.preset` when the preset's own limits are at fault).
fn adc_keys(c: &Config, message: &str) -> Vec<(&'static str, &'static str)> {
    let candidates: &[(&'static str, &'static str)] = if message.contains(" channels: ") {
        &[("adc.frame", "channels")]
    } else if message.starts_with("sample width") {
        &[("adc", "width")]
    } else if message.starts_with("frame of") {
        &[("adc.frame", "frame_sck")]
    } else if message.starts_with("pipeline of") {
        &[("adc.frame", "pipeline")]
    } else if message.starts_with("channel ") {
        &[
            ("adc.frame", "offsets"),
            ("adc.frame", "frame_sck"),
            ("adc.frame", "channels"),
            ("adc", "width"),
        ]
    } else if message.starts_with("SCK period of") || message.starts_with("SCK of") {
        &[
            ("adc", "sck_period_clocks"),
            ("adc.timing", "sck_min_period_ns"),
        ]
    } else if message.starts_with("SCK pulse") {
        &[
            ("adc.timing", "sck_min_pulse_ns"),
            ("adc", "sck_period_clocks"),
        ]
    } else if message.starts_with("SCK period") && message.contains("data-valid") {
        &[
            ("adc.timing", "data_valid_ns"),
            ("adc", "sck_period_clocks"),
        ]
    } else if message.starts_with("CONV pulse") {
        &[
            ("adc.frame", "conv_clocks"),
            ("adc.timing", "conv_min_pulse_ns"),
        ]
    } else if message.starts_with("CONV to first SCK") {
        &[
            ("adc.frame", "lead_clocks"),
            ("adc.timing", "conv_to_sck_ns"),
        ]
    } else if message.starts_with("CONV is active") {
        &[
            ("adc.frame", "conv_clocks"),
            ("adc.timing", "conv_min_low_ns"),
        ]
    } else if message.contains("acquisition time") {
        &[("adc.timing", "acquisition_ns"), ("adc", "sample_rate_hz")]
    } else if message.starts_with("conversion period") {
        &[
            ("adc", "sample_rate_hz"),
            ("adc", "sck_period_clocks"),
            ("adc.frame", "frame_sck"),
            ("adc.frame", "lead_clocks"),
            ("adc.frame", "pipeline"),
            ("adc", "max_sample_rate_hz"),
        ]
    } else if message.starts_with("sample rate") {
        &[("adc", "sample_rate_hz"), ("adc", "max_sample_rate_hz")]
    } else {
        &[]
    };
    // The LTC1407A-1's frame and timing are fixed: only the `[adc]` keys are the user's.
    let mut keys: Vec<(&'static str, &'static str)> = candidates
        .iter()
        .copied()
        .filter(|(t, _)| c.adc.preset == AdcPreset::Generic || *t == "adc")
        .collect();
    // Times in clocks come from times in ns at the system clock.
    if ["SCK", "CONV", "conversion", "sample rate"]
        .iter()
        .any(|p| message.starts_with(p))
    {
        keys.push(("clock", "frequency_hz"));
    }
    keys
}

/// Default `abz.max_edge_hz`: 12.5 M edges per second (or clock / 2 if that is lower).
pub const ABZ_DEFAULT_EDGE_HZ: f64 = 12.5e6;

/// `[abz]`: the emulator's parameters when enabled (None otherwise). `lines` defaults to
/// 16 x PPR (at most a quarter of the positions per turn); `max_edge_hz` to
/// [`ABZ_DEFAULT_EDGE_HZ`], at most clock / 2 and at least clock / 2^24; the edge spacing is
/// ceil(clock / max_edge_hz) clocks. The keys are checked only when enabled.
pub(super) fn abz_params(
    c: &Config,
    quadrants_per_turn: u64,
    fine_bits: u32,
    err: &ErrFn,
) -> Result<Option<AbzParams>> {
    let a = &c.abz;
    // Off: the keys have no effect and are not checked (the rule for every section with an
    // `enabled` key).
    if !a.enabled {
        return Ok(None);
    }
    let clock = c.clock.frequency_hz;
    let positions = quadrants_per_turn << fine_bits;
    let lines = a
        .lines
        .unwrap_or((4 * quadrants_per_turn).min(positions / 4));
    if lines == 0 || 4 * lines > positions || 4 * lines > 1 << 30 {
        return Err(err(
            "abz",
            "lines",
            format!(
                "{lines}: allowed 1..={} A/B periods per turn (4 edges each, at most one edge per position LSB: {positions} positions per turn{})",
                (positions / 4).min(1 << 28),
                if positions / 4 > 1 << 28 { "; at most 2^28" } else { "" }
            ),
        ));
    }
    let hz = a
        .max_edge_hz
        .unwrap_or(ABZ_DEFAULT_EDGE_HZ.min(clock / 2.0));
    let lo = clock / (1u64 << 24) as f64;
    if !hz.is_finite() || hz < lo || hz > clock / 2.0 {
        return Err(err(
            "abz",
            "max_edge_hz",
            format!(
                "{hz} Hz: allowed {lo:.3}..={:.0} Hz (at {clock:.0} Hz the emulator needs 2 to 2^24 clocks between two edges)",
                clock / 2.0
            ),
        ));
    }
    if c.capacitive.is_some() {
        return Err(err(
            "abz",
            "enabled",
            "ABZ emulation is built into the sinewave board top only; remove [abz] or set enabled = false with [capacitive]".into(),
        ));
    }
    if c.adc.preset != AdcPreset::Ltc1407a1 || c.target != Target::Spartan3an {
        return Err(err(
            "abz",
            "enabled",
            "ABZ emulation drives abz_a/abz_b/abz_z of <name>_top, the sinewave board top, which exists with adc.preset = \"ltc1407a-1\" and target = \"spartan3an\"; set enabled = false otherwise".into(),
        ));
    }
    // Spacing in clocks: the smallest S with clock / S <= max_edge_hz.
    let mut spacing = (clock / hz).ceil().max(2.0) as u32;
    if clock / ((spacing - 1) as f64) <= hz && spacing > 2 {
        spacing -= 1;
    }
    AbzParams::new(quadrants_per_turn, fine_bits, lines, spacing)
        .map(Some)
        .map_err(|m| err("abz", "lines", m.detail()))
}

fn frac_of_fs(c: &Config, table: &str, key: &str, v: f64, err: &ErrFn) -> Result<u32> {
    let fs = (1u32 << (c.adc.width - 1)) - 1;
    if !(v > 0.0 && v <= 1.0) {
        return Err(err(
            table,
            key,
            format!("{v}: allowed 0 < value <= 1 (fraction of full scale)"),
        ));
    }
    Ok(((v * fs as f64).round() as u32).max(1))
}

/// Correction parameters from `[correction]`.
pub(super) fn correction_params(c: &Config, rate: f64, err: &ErrFn) -> Result<CorrectionParams> {
    let k = &c.correction;
    let a = c.adc.width;
    let gf = k.gain_frac_bits;
    let gs = gain_code(gf, k.gain_sin).map_err(|m| err("correction", "gain_sin", m.detail()))?;
    let gc = gain_code(gf, k.gain_cos).map_err(|m| err("correction", "gain_cos", m.detail()))?;
    // Phase correction folds 1 / cos(phi) into the cos gain and adds the cross coefficient.
    let (gc, cross) = if k.phase_deg != 0.0 {
        if k.mode != "static" {
            return Err(err(
                "correction",
                "phase_deg",
                format!(
                    "{}: phase correction is static only; use mode = \"static\" or phase_deg = 0",
                    k.phase_deg
                ),
            ));
        }
        phase_codes(gf, k.gain_sin, k.gain_cos, k.phase_deg)
            .map_err(|m| err("correction", "phase_deg", m.detail()))?
    } else {
        (gc, 0)
    };
    let p = CorrectionParams::new(a, gf, [k.offset_sin, k.offset_cos], [gs, gc]).map_err(|m| {
        let m = m.detail();
        err(
            "correction",
            if m.contains("cos offset") {
                "offset_cos"
            } else if m.contains("offset") {
                "offset_sin"
            } else {
                "gain_frac_bits"
            },
            m,
        )
    })?;
    let p = p
        .with_phase(cross)
        .map_err(|m| err("correction", "phase_deg", m.detail()))?;
    match k.mode.as_str() {
        "static" => Ok(p),
        "peak" => {
            let t = frac_of_fs(c, "correction", "target_amplitude", k.target_amplitude, err)?;
            let m = frac_of_fs(c, "correction", "min_amplitude", k.min_amplitude, err)?;
            p.with_auto(t, k.periods, m)
                .map_err(|e| err("correction", "periods", e.detail()))
        }
        "auto" => {
            let t = frac_of_fs(c, "correction", "target_amplitude", k.target_amplitude, err)?;
            let m = frac_of_fs(c, "correction", "min_amplitude", k.min_amplitude, err)?;
            // The solve must end before the next window does (the fit drops a window that
            // ends while it is busy): min_samples samples take min_samples x clocks per
            // sample.
            let clocks = c.clock.frequency_hz / rate;
            let need = crate::blocks::correction::fit_solve::UPDATE_LATENCY as f64;
            if k.min_samples as f64 * clocks <= need {
                return Err(err(
                    "correction",
                    "min_samples",
                    format!(
                        "{}: a fit window must outlast the {need:.0} clocks from its closing \
                         sample to the update (the fit's {} pipeline stages and the {}-clock \
                         solve); at {clocks:.1} clocks per sample use at least {} samples",
                        k.min_samples,
                        crate::blocks::correction::fit_hdl::FIT_STAGES,
                        crate::blocks::correction::fit_solve::SOLVE_CYCLES,
                        (need / clocks).floor() as u64 + 1
                    ),
                ));
            }
            p.with_fit(t, k.periods, m, k.min_samples)
                .map_err(|e| err("correction", "min_samples", e.detail()))
        }
        other => Err(err(
            "correction",
            "mode",
            format!(
                "{}: allowed \"static\", \"auto\" or \"peak\"",
                Quoted(other)
            ),
        )),
    }
}

/// Monitor parameters: thresholds in CORDIC magnitude units (K_N * amplitude * 2^G).
pub(super) fn monitor_params(
    c: &Config,
    n: u32,
    xy_guard: u32,
    xy_width: u32,
    err: &ErrFn,
) -> Result<MonitorParams> {
    let m = &c.monitor;
    let fs = ((1u64 << (c.adc.width - 1)) - 1) as f64;
    let units = |v: f64| exact::gain_times_ceil(n, ((v * fs).round() as u64) << xy_guard);
    let los = m.los_amplitude.unwrap_or(0.25);
    let rel = m.los_release.unwrap_or(0.3);
    let clip = m.clip_amplitude.unwrap_or(1.0);
    for (key, v) in [
        ("los_amplitude", los),
        ("los_release", rel),
        ("clip_amplitude", clip),
    ] {
        if !(v > 0.0 && v <= 1.3) {
            return Err(err(
                "monitor",
                key,
                format!("{v}: allowed 0 < value <= 1.3 (fraction of full scale)"),
            ));
        }
    }
    // The levels must rise: loss threshold <= release level <= clipping level. The key in
    // the file is blamed (the later one when both are given); a default is named as such.
    let shown = |key: &str, v: f64, given: bool| {
        if given {
            format!("`monitor.{key}` = {v}")
        } else {
            format!("`monitor.{key}` (default {v})")
        }
    };
    for ((lo_key, lo, lo_given), (hi_key, hi, hi_given), what) in [
        (
            ("los_amplitude", los, m.los_amplitude.is_some()),
            ("los_release", rel, m.los_release.is_some()),
            "the loss-of-signal release level must be at least the loss threshold",
        ),
        (
            ("los_release", rel, m.los_release.is_some()),
            ("clip_amplitude", clip, m.clip_amplitude.is_some()),
            "the clipping level must be at least the loss-of-signal release level",
        ),
    ] {
        if hi < lo {
            let key = if hi_given || !lo_given {
                hi_key
            } else {
                lo_key
            };
            return Err(err(
                "monitor",
                key,
                format!(
                    "{} is below {}: {what} (fractions of full scale)",
                    shown(hi_key, hi, hi_given),
                    shown(lo_key, lo, lo_given)
                ),
            ));
        }
    }
    for (key, v) in [("los_window", m.los_window), ("clip_hold", m.clip_hold)] {
        if let Some(v) = v {
            if !(1..=65535).contains(&v) {
                return Err(err(
                    "monitor",
                    key,
                    format!("{v} samples: allowed 1..=65535"),
                ));
            }
        }
    }
    MonitorParams::new(
        c.adc.width,
        xy_width,
        units(los),
        units(rel),
        m.los_window.unwrap_or(8),
        units(clip),
        m.clip_hold.unwrap_or(16),
    )
    .map_err(|e| err("monitor", "los_amplitude", e.detail()))
}

/// Validates `[capacitive]` and designs its filters at the ADC's sample rate.
pub(super) fn cap_params(
    c: &Config,
    k: &CapacitiveConfig,
    rate: f64,
    err: &ErrFn,
) -> Result<CapDerived> {
    let t = "capacitive";
    if c.adc.preset != AdcPreset::Generic {
        return Err(err(
            "adc",
            "preset",
            "the capacitive path reads one receiver channel: use preset = \"generic\" with [adc.frame] channels = 1".into(),
        ));
    }
    if c.adc.frame.as_ref().and_then(|f| f.channels) != Some(1) {
        return Err(err(
            "adc",
            "frame",
            "the capacitive path reads one receiver channel: set [adc.frame] channels = 1".into(),
        ));
    }
    if c.ssi.enabled || c.spi.enabled {
        return Err(err(
            if c.ssi.enabled { "ssi" } else { "spi" },
            "enabled",
            "the capacitive top serves BiSS-C and the parallel bus; SSI and SPI are not in it"
                .into(),
        ));
    }
    if !(10e3..=1e6).contains(&k.carrier_hz) || k.carrier_hz >= rate / 2.0 {
        return Err(err(
            t,
            "carrier_hz",
            format!(
                "{} Hz: allowed 10 kHz..1 MHz and below half the ADC's sample rate ({:.0} Hz)",
                k.carrier_hz,
                rate / 2.0
            ),
        ));
    }
    if k.amplitude.is_nan() || k.amplitude <= 0.0 || k.amplitude > 1.0 {
        return Err(err(
            t,
            "amplitude",
            format!("{}: allowed (0, 1]", k.amplitude),
        ));
    }
    let ranged = |key: &str, v: u32, lo: u32, hi: u32| -> Result<()> {
        if (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(err(t, key, format!("{v}: allowed {lo}..={hi}")))
        }
    };
    ranged("dac_width", k.dac_width, 8, 16)?;
    ranged("phase_bits", k.phase_bits, 8, 32)?;
    ranged("table_bits", k.table_bits, 4, 12.min(k.phase_bits - 2))?;
    ranged("data_width", k.data_width, 12, 16)?;
    ranged("guard_frac", k.guard_frac, 0, 12)?;
    // The coefficient format: the biquad engine's ROM words (2..=30 bits) with at least one
    // integer bit besides the sign.
    let (cw, cf) = (k.coef.width, k.coef.frac);
    if !(2..=30).contains(&cw) {
        return Err(err(
            "capacitive.coef",
            "width",
            format!("{cw} bits: allowed 2..=30 (the biquad engine's coefficient words)"),
        ));
    }
    if !(1..cw).contains(&cf) {
        return Err(err(
            "capacitive.coef",
            "frac",
            format!(
                "{cf} fractional bits: allowed 1..={} for `capacitive.coef.width` = {cw} (the sign bit is not fractional)",
                cw - 1
            ),
        ));
    }
    // The biquad engine's accumulator: data + guard + integer bits of the coefficients + 2.
    let acc =
        k.data_width as i64 + k.guard_frac as i64 + k.coef.width as i64 - k.coef.frac as i64 + 2;
    if acc > 32 {
        return Err(err(
            "capacitive.coef",
            "width",
            format!(
                "the filters' accumulator `capacitive.data_width` + `capacitive.guard_frac` + `capacitive.coef.width` - `capacitive.coef.frac` + 2 = {} + {} + {} - {} + 2 = {acc} bits exceeds the 32-bit word; use fewer integer bits (width - frac) or a smaller guard_frac",
                k.data_width, k.guard_frac, k.coef.width, k.coef.frac
            ),
        ));
    }
    if k.data_width < c.adc.width {
        return Err(err(
            t,
            "data_width",
            format!(
                "{} bits is narrower than the ADC's {} bits",
                k.data_width, c.adc.width
            ),
        ));
    }
    // Each filter's kind must fit its role: the band-pass isolates the carrier in front of
    // the demodulator, the low-pass removes 2w after it.
    for (key, spec, want) in [
        ("bandpass", &k.bandpass, crate::filter::FilterKind::Bandpass),
        ("lowpass", &k.lowpass, crate::filter::FilterKind::Lowpass),
    ] {
        if spec.kind != want {
            let name = |f: crate::filter::FilterKind| match f {
                crate::filter::FilterKind::Lowpass => "\"lowpass\"",
                crate::filter::FilterKind::Highpass => "\"highpass\"",
                crate::filter::FilterKind::Bandpass => "\"bandpass\"",
            };
            let role = if key == "bandpass" {
                "the band-pass in front of the demodulator isolates the carrier"
            } else {
                "the low-pass after the demodulator removes twice the carrier"
            };
            return Err(err(
                &format!("{t}.{key}"),
                "kind",
                format!("{}: {role}; allowed {}", name(spec.kind), name(want)),
            ));
        }
    }
    let design = |key: &str, spec: &crate::filter::FilterSpec| -> Result<crate::filter::Designed> {
        if (spec.sample_rate_hz - rate).abs() > rate * 1e-3 {
            return Err(err(
                &format!("{t}.{key}"),
                "sample_rate_hz",
                format!(
                    "sample_rate_hz = {} but the ADC samples at {:.3} Hz (`clock.frequency_hz` / the ADC period, `adc.sample_rate_hz`): make them equal",
                    spec.sample_rate_hz, rate
                ),
            ));
        }
        let mut s = spec.clone();
        s.sample_rate_hz = rate;
        crate::filter::design_with_probes(&s, k.coef, &[2.0 * k.carrier_hz]).map_err(|e| {
            use crate::filter::FilterError as F;
            match &e {
                // The specification's own field.
                F::InvalidSpec { field, .. } => err(&format!("{t}.{key}"), field, e.to_string()),
                // The quantization: more integer or fractional bits, i.e. the format.
                F::InvalidFormat { .. }
                | F::CoefficientOverflow { .. }
                | F::UnstableSection { .. }
                | F::GainUnderflow { .. } => err(
                    "capacitive.coef",
                    "frac",
                    format!(
                        "{e} (the filter of `{t}.{key}.order` and `{t}.{key}.{}`)",
                        if key == "bandpass" {
                            "band_hz"
                        } else {
                            "corner_hz"
                        }
                    ),
                ),
            }
        })
    };
    let bandpass = design("bandpass", &k.bandpass)?;
    let lowpass = design("lowpass", &k.lowpass)?;
    Ok(CapDerived {
        config: k.clone(),
        sample_rate_hz: rate,
        bandpass,
        lowpass,
    })
}
