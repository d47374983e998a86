//! Each block's parameters built from the config and checked against it: correction, monitor, capacitive front end (the ADC and
//! pre-amplifier are in `adc.rs`, the checks across blocks in `checks.rs`, BiSS-C in
//! `biss.rs`). Errors name the config key to change.

use super::*;

pub type ErrFn<'a> = dyn Fn(&str, &str, String) -> Error + 'a;

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
