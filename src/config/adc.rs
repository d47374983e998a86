//! The ADC's and the pre-amplifier's parameters built from `[adc]`, `[adc.frame]`,
//! `[adc.timing]` and `[preamp]`, checked against the chips' limits. Errors name the
//! config key to change.

use super::params::ErrFn;
use super::*;

/// ADC and preamp parameters from the config, validated against the chips' limits.
pub(super) fn adc_params(
    c: &Config,
    text: &str,
    err: &ErrFn,
) -> Result<(AdcParams, Option<PreampParams>)> {
    let clock_hz = c.clock.frequency_hz;
    let (frame, timing) = match c.adc.preset {
        AdcPreset::Ltc1407a1 => ltc1407a_frame(c, err)?,
        AdcPreset::Ads8354 => {
            fixed_frame(c, err, "ads8354", AdcFrame::ADS8354, AdcTiming::ADS8354)?
        }
        AdcPreset::Ad7380 => fixed_frame(c, err, "ad7380", AdcFrame::AD7380, AdcTiming::AD7380)?,
        AdcPreset::Generic => generic_frame(c, err)?,
    };
    let build_with = |d: u32, period: Option<u32>| match c.adc.preset {
        AdcPreset::Ltc1407a1 => AdcParams::ltc1407a(clock_hz, d, period),
        AdcPreset::Ads8354 => AdcParams::ads8354(clock_hz, d, period),
        AdcPreset::Ad7380 => AdcParams::ad7380(clock_hz, d, period),
        AdcPreset::Generic => AdcParams::generic(clock_hz, frame, timing, d, period),
    };
    // SCK divider: as configured, or the smallest that both the chip's SCK limit and the
    // ADC round trip (the I/O budget, `board_timing`) allow. A configured divider, or one
    // no divider up to 64 clocks past the chip's fixes, is checked by `board_timing`,
    // which names the key to change.
    let d = match c.adc.sck_period_clocks {
        Some(d) => d,
        None => {
            let chip_min = ((timing.sck_min_period_ns * clock_hz / 1e9) - 1e-9)
                .ceil()
                .max(2.0) as u32;
            let io = super::checks::io_timing(c);
            let fits = |d: u32| {
                let p = build_with(d, None);
                let (available, needed) = crate::board::adc_round_trip(
                    &io,
                    p.timing.data_valid_ns,
                    p.capture_distance_clocks(),
                    clock_hz,
                );
                available + 1e-9 >= needed
            };
            (chip_min..chip_min + 64)
                .find(|&d| fits(d))
                .unwrap_or(chip_min)
        }
    };
    let build = |period: Option<u32>| build_with(d, period);
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
    let preamp = preamp_params(c, text, err)?;
    Ok((params, preamp))
}

/// The LTC1407A-1's fixed frame and timing: 14-bit samples, no `[adc.frame]` or
/// `[adc.timing]`.
fn ltc1407a_frame(c: &Config, err: &ErrFn) -> Result<(AdcFrame, AdcTiming)> {
    let a = c.adc.width;
    if a != 14 {
        return Err(err(
            "adc",
            "width",
            format!(
                "the LTC1407A-1 delivers 14-bit samples; width {a} needs `adc.preset` = \"generic\""
            ),
        ));
    }
    if c.adc.frame.is_some() || c.adc.timing.is_some() || c.adc.max_sample_rate_hz.is_some() {
        return Err(err(
            "adc",
            "preset",
            "[adc.frame], [adc.timing] and max_sample_rate_hz apply to preset \"generic\" only"
                .into(),
        ));
    }
    Ok((AdcFrame::LTC1407A_1, AdcTiming::LTC1407A_1))
}

/// A preset chip's fixed frame and timing (ADS8354, AD7380): 16-bit samples, no
/// `[adc.frame]`, `[adc.timing]` or `max_sample_rate_hz` (the data sheet sets them).
fn fixed_frame(
    c: &Config,
    err: &ErrFn,
    preset: &str,
    frame: AdcFrame,
    timing: AdcTiming,
) -> Result<(AdcFrame, AdcTiming)> {
    let a = c.adc.width;
    if a != frame.width {
        return Err(err(
            "adc",
            "width",
            format!(
                "preset \"{preset}\" delivers {}-bit samples: allowed width = {} (or `adc.preset` = \"generic\" for another width)",
                frame.width, frame.width
            ),
        ));
    }
    let fixed = [
        (c.adc.frame.is_some(), "frame", "[adc.frame]"),
        (c.adc.timing.is_some(), "timing", "[adc.timing]"),
        (
            c.adc.max_sample_rate_hz.is_some(),
            "max_sample_rate_hz",
            "adc.max_sample_rate_hz",
        ),
    ];
    if let Some((_, key, what)) = fixed.iter().find(|f| f.0) {
        return Err(err(
            "adc",
            key,
            format!(
                "{what} is fixed by preset \"{preset}\" (its data sheet's frame and timing); allowed only with preset \"generic\": remove it, or describe the chip with preset = \"generic\""
            ),
        ));
    }
    Ok((frame, timing))
}

/// A generic ADC's frame and timing from `[adc.frame]` and `[adc.timing]`, each key
/// checked, the defaults filled in.
fn generic_frame(c: &Config, err: &ErrFn) -> Result<(AdcFrame, AdcTiming)> {
    let a = c.adc.width;
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
                        format!(
                            "{v} ns: allowed 0..=1000000 ns (a time from the ADC's data sheet)"
                        ),
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
        lines: f.lines.unwrap_or(1),
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
        conversion_ns: 0.0,
        conversion_edges: 0,
        max_sample_rate_hz: max,
    };
    Ok((frame, timing))
}

/// The LTC6912-1 pre-amplifier's parameters: with preset "ltc1407a-1" only.
fn preamp_params(c: &Config, text: &str, err: &ErrFn) -> Result<Option<PreampParams>> {
    let clock_hz = c.clock.frequency_hz;
    Ok(match c.adc.preset {
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
        AdcPreset::Generic | AdcPreset::Ads8354 | AdcPreset::Ad7380 => {
            if c.preamp.is_some() {
                let key = ["gain_a", "gain_b"]
                    .into_iter()
                    .find(|k| written(text, "preamp", k))
                    .unwrap_or("gain_a");
                return Err(err(
                    "preamp",
                    key,
                    "the LTC6912-1 pre-amplifier belongs to preset \"ltc1407a-1\": [preamp] is allowed only with adc.preset = \"ltc1407a-1\"; remove it".into(),
                ));
            }
            None
        }
    })
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
    let candidates: &[(&'static str, &'static str)] = if message.contains(" data lines with ") {
        &[("adc.frame", "lines"), ("adc.frame", "channels")]
    } else if message.contains(" channels: ") {
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
        .filter(|k| c.adc.preset == AdcPreset::Generic || *k != ("adc", "max_sample_rate_hz"))
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
