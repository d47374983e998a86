//! Ranges: every documented bound is the accepted one (docs/cli.md, "Supported ranges", and the
//! usage lines), values outside a key's range are rejected at that key, and a value that
//! rounds to a code the hardware cannot use is rejected with the code it rounds to.
//!
//! Every expected position is computed here from the text the test wrote (byte offset of a
//! unique needle -> line and column), never copied from a run. The helpers (`expect_bad`:
//! the library's error, position and message, then `check` and `generate` on the command
//! line, nothing written) are in `tests/cli/config_errors_util/`.
use crate::config_errors_util;
use config_errors_util::*;
use sinedec::config::{Loaded, DEFAULT_CONFIG};

#[test]
fn default_and_generic_base_configs_are_accepted() {
    Loaded::parse(DEFAULT_CONFIG, SRC).expect("default");
    Loaded::parse(
        &default_with(&[GENERIC, NO_PREAMP, ("width = 14", "width = 16")]),
        SRC,
    )
    .expect("generic 16");
    Loaded::parse(
        &default_with(&[
            GENERIC,
            NO_PREAMP,
            ("width = 14", "width = 10"),
            ("iterations = 14", "iterations = 10"),
            ("# guard_bits = 10", "guard_bits = 0"),
        ]),
        SRC,
    )
    .expect("generic 10, guard 0, 10 iterations (the most that fit)");
}

/// `correction.periods` is documented as 1..=256: 0 and 257 were accepted in static mode.
#[test]
fn correction_periods_out_of_range_in_static_mode() {
    for v in ["0", "257"] {
        let new = format!("\nperiods = {v}");
        let t = default_with(&[("\nperiods = 1", &new)]);
        expect_bad(
            &t,
            Kind::Syntax,
            value_at(&t, new.trim_start()),
            &["`correction.periods`", "1..=256"],
        );
    }
}

/// Every documented bound is accepted and the value just outside it rejected, each in a
/// configuration where that bound is reachable (`guard_bits` = 20 used to be documented and
/// always rejected; `correction.periods` 0 and 257 accepted).
#[test]
fn documented_ranges_equal_accepted_ones() {
    // (key, line to replace, template with {}, extra edits that make both ends reachable)
    let generic10: Vec<(&str, &str)> = vec![
        GENERIC,
        NO_PREAMP,
        ("width = 14", "width = 10"),
        ("iterations = 14", "iterations = 10"),
    ];
    let cases: Vec<RangeCase> = vec![
        (
            "adc.width",
            "width = 14",
            "width = {}",
            vec![GENERIC, NO_PREAMP],
        ),
        (
            "cordic.iterations",
            "iterations = 14",
            "iterations = {}",
            vec![],
        ),
        (
            "cordic.fine_bits",
            "fine_bits = 14",
            "fine_bits = {}",
            vec![],
        ),
        (
            "cordic.guard_bits",
            "# guard_bits = 10",
            "guard_bits = {}",
            generic10,
        ),
        ("encoder.ppr", "ppr = 2048", "ppr = {}", vec![]),
        (
            "encoder.multiturn_bits",
            "multiturn_bits = 12",
            "multiturn_bits = {}",
            vec![],
        ),
        (
            "correction.periods",
            "\nperiods = 1",
            "\nperiods = {}",
            vec![],
        ),
        (
            "correction.gain_frac_bits",
            "gain_frac_bits = 14",
            "gain_frac_bits = {}",
            vec![],
        ),
        (
            "adc.sck_period_clocks",
            "# sck_period_clocks = 3",
            "sck_period_clocks = {}",
            // A generic ADC at 50 MHz: 2 clocks (40 ns) meet its 20 ns SCK limit and the
            // board round trip; 255 clocks keep the frame within the longest period.
            vec![
                GENERIC,
                NO_PREAMP,
                (
                    "frequency_hz = 133_330_000.0",
                    "frequency_hz = 50_000_000.0",
                ),
            ],
        ),
        (
            "qep.filter_clocks",
            "filter_clocks = 4",
            "filter_clocks = {}",
            vec![],
        ),
    ];
    for (key, old, template, extra) in cases {
        let (lo, hi) = documented_range(key);
        for (v, ok) in [(lo, true), (hi, true), (lo - 1, false), (hi + 1, false)] {
            if v < 0 {
                continue; // unsigned key: a negative value is a type error, not a range one
            }
            let new = template.replace("{}", &v.to_string());
            let mut edits = vec![(old, new.as_str())];
            edits.extend(extra.iter().copied());
            let t = default_with(&edits);
            let r = Loaded::parse(&t, SRC);
            assert_eq!(
                r.is_ok(),
                ok,
                "`{key}` = {v} (documented {lo}..={hi}): {}",
                match &r {
                    Ok(_) => "accepted".to_string(),
                    Err(e) => e.to_string(),
                }
            );
            if let Err(e) = r {
                assert!(e.to_string().contains(key), "{key} = {v}: {e}");
            }
        }
    }
}

/// `correction.phase_deg` outside -15..=15 degrees (and NaN) is a range error at the value;
/// with `mode = "auto"` a non-zero phase is blamed on `phase_deg` itself; both ends of the
/// range and 0 are accepted, and 0 builds no phase stage.
#[test]
fn correction_phase_deg_range_and_mode() {
    for v in ["15.5", "-16.0", "90.0", "nan"] {
        let new = format!("gain_frac_bits = 14\nphase_deg = {v}");
        let t = default_with(&[("gain_frac_bits = 14", &new)]);
        let needle = format!("phase_deg = {v}");
        expect_bad(
            &t,
            Kind::Syntax,
            value_at(&t, &needle),
            &["`correction.phase_deg`", "-15..=15", "degrees"],
        );
    }
    // An integer (3) reads as 3.0 degrees.
    for (v, phase) in [("15.0", true), ("-15.0", true), ("3", true), ("0.0", false)] {
        let t = default_with(&[(
            "gain_frac_bits = 14",
            &format!("gain_frac_bits = 14\nphase_deg = {v}"),
        )]);
        let l = Loaded::parse(&t, SRC).expect("accepted");
        let c = &l.derived.correction;
        assert_eq!(c.has_phase(), phase, "phase_deg = {v}");
        // Unity gains: 3 clocks. A phase adds its stages (2) and makes the folded cos gain
        // and k constants that are not powers of two: shift-add products (3 more).
        assert_eq!(c.latency_cycles(), if phase { 8 } else { 3 });
    }
    let t = default_with(&[
        ("mode = \"static\"", "mode = \"auto\""),
        (
            "gain_frac_bits = 14",
            "gain_frac_bits = 14\nphase_deg = 2.5",
        ),
    ]);
    expect_bad(
        &t,
        Kind::Value("correction.phase_deg"),
        at(&t, "phase_deg = 2.5"),
        &["correction.phase_deg", "static"],
    );
}

/// A static gain that rounds to code 0 (`gain_sin = 0.0`, or 1e-9) passed `check`, then
/// every sample was flagged: it is rejected at the key, and the smallest gain whose code is
/// 1 (2^-14 x 0.5 rounds up to it at 14 fraction bits) is accepted.
#[test]
fn a_gain_that_rounds_to_code_0_is_rejected() {
    for v in ["0.0", "1e-9", "0.00003"] {
        let new = format!("gain_sin = {v}");
        let t = default_with(&[("gain_sin = 1.0", &new)]);
        expect_bad(
            &t,
            Kind::Value("correction.gain_sin"),
            at(&t, &new),
            &["correction.gain_sin", "code 0"],
        );
    }
    // 0.00004 x 2^14 = 0.66: code 1.
    let t = default_with(&[("gain_cos = 1.0", "gain_cos = 0.00004")]);
    Loaded::parse(&t, SRC).unwrap_or_else(|e| panic!("code 1 rejected: {e}"));
}

/// `gain_sin = 1.99999` at 15 fraction bits was reported as "outside 0..2": the message
/// says that the code rounds to 65536, one above the 16-bit word's 65535.
#[test]
fn a_gain_that_rounds_to_65536_says_so() {
    let t = default_with(&[
        ("gain_sin = 1.0", "gain_sin = 1.99999"),
        ("gain_frac_bits = 14", "gain_frac_bits = 15"),
    ]);
    expect_bad(
        &t,
        Kind::Value("correction.gain_sin"),
        at(&t, "gain_sin = 1.99999"),
        &["correction.gain_sin", "65536", "65535"],
    );
}

/// The generic ADC's limits: `max_sample_rate_hz` 0, -1 or NaN, a negative
/// `sck_min_period_ns` and a NaN `conv_min_pulse_ns` were accepted, and so was a third
/// channel offset on a one-channel frame. Each is rejected at its key.
#[test]
fn generic_adc_limits_are_checked_at_their_keys() {
    for v in ["0.0", "-1.0", "nan", "inf"] {
        let new = format!("max_sample_rate_hz = {v}");
        let t = default_with(&[
            (
                "preset = \"ltc1407a-1\"",
                &format!("preset = \"generic\"\n{new}"),
            ),
            NO_PREAMP,
        ]);
        expect_bad(
            &t,
            Kind::Value("adc.max_sample_rate_hz"),
            at(&t, &new),
            &["adc.max_sample_rate_hz"],
        );
    }
    for (section, key, needle) in [
        (
            "[adc.timing]\nsck_min_period_ns = -5.0",
            "adc.timing.sck_min_period_ns",
            "sck_min_period_ns = -5.0",
        ),
        (
            "[adc.timing]\nconv_min_pulse_ns = nan",
            "adc.timing.conv_min_pulse_ns",
            "conv_min_pulse_ns = nan",
        ),
        (
            "[adc.timing]\nacquisition_ns = -1.0",
            "adc.timing.acquisition_ns",
            "acquisition_ns = -1.0",
        ),
        (
            "[adc.frame]\nchannels = 1\noffsets = [1, 0, 0]",
            "adc.frame.offsets",
            "offsets = [1, 0, 0]",
        ),
        (
            "[adc.frame]\noffsets = [1]",
            "adc.frame.offsets",
            "offsets = [1]",
        ),
    ] {
        let t = generic_with(section);
        expect_bad(&t, Kind::Value(key), at(&t, needle), &[key]);
    }
}

/// `report --iterations` accepts what docs/cli.md's usage line documents, and nothing
/// outside it (`--iterations 1` was accepted while the docs said 2..=20).
#[test]
fn report_iterations_documented_range_is_the_accepted_one() {
    let readme = include_str!("../../docs/cli.md");
    let row = readme
        .lines()
        .find(|l| l.starts_with("| `sinedec report"))
        .expect("docs/cli.md has the report row");
    let range = row
        .split("[--iterations ")
        .nth(1)
        .and_then(|s| s.split(']').next())
        .expect("the usage documents --iterations");
    let (lo, hi) = range.split_once("..=").expect("a lo..=hi range");
    let (lo, hi): (u32, u32) = (lo.parse().unwrap(), hi.parse().unwrap());
    for (n, ok) in [(lo, true), (hi, true), (lo - 1, false), (hi + 1, false)] {
        assert_eq!(
            sinedec::report::parse_iterations(&n.to_string()).is_ok(),
            ok,
            "--iterations {n} (docs/cli.md: {range})"
        );
    }
}
