//! Bad configurations: the library reports `ConfigSyntax` / `ConfigValue` with 1-based line
//! and column, and the command line (`check` and `generate`) exits non-zero with a message
//! naming the key, the position and what is allowed, without writing or touching any output.
//!
//! Every expected position is computed here from the text the test wrote (byte offset of a
//! unique needle -> line and column), never copied from a run.
//!
//! (Second half of the tests of `tests/cli/config_errors.rs`; helpers in `tests/cli/config_errors_util/`.)
use crate::config_errors_util;
use config_errors_util::*;
use sinedec::config::{Loaded, DEFAULT_CONFIG};

#[test]
fn value_error_key_named_in_a_comment_first() {
    // A comment mentioning `width = ...` before the real key must not be reported.
    let t = default_with(&[
        (
            "[adc]",
            "[adc]\n# width = 14 is what the LTC1407A-1 delivers",
        ),
        ("width = 14\n", "width = 12\n"),
    ]);
    expect_bad(
        &t,
        Kind::Value("adc.width"),
        at(&t, "width = 12"),
        &["adc.width"],
    );
}

// ---------------------------------------------------------------------------------------
// Sanity: the edits above start from a config that is accepted.

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

#[test]
fn sck_beyond_the_adc_limit() {
    // 2 clocks at 133.33 MHz = 66.7 MHz, above the LTC1407A-1's 1/19.6 ns = 51 MHz.
    let t = default_with(&[("# sck_period_clocks = 3", "sck_period_clocks = 2")]);
    expect_bad(
        &t,
        Kind::Value("adc.sck_period_clocks"),
        at(&t, "sck_period_clocks = 2"),
        &["adc.sck_period_clocks", "LTC1407A-1", "at least 3 clocks"],
    );
}

#[test]
fn preamp_gain_not_in_the_ltc6912_set() {
    let t = default_with(&[("gain_b = -1", "gain_b = -3")]);
    expect_bad(
        &t,
        Kind::Value("preamp.gain_b"),
        at(&t, "gain_b = -3"),
        &["preamp.gain_b", "-3", "-1, -2, -5, -10, -20, -50, -100"],
    );
}

#[test]
fn preamp_section_with_the_generic_preset() {
    let t = default_with(&[GENERIC, ("width = 14", "width = 12")]);
    expect_bad(
        &t,
        Kind::Value("preamp.gain_a"),
        at(&t, "gain_a = -1"),
        &["preamp", "ltc1407a-1"],
    );
}

/// A low-pass section declared as a high-pass used to be accepted (simulate then reported
/// 219 degrees of error): the low-pass after the demodulator must be a low-pass.
#[test]
fn capacitive_lowpass_declared_highpass() {
    let t = cap_with(&[("kind = \"lowpass\"", "kind = \"highpass\"")]);
    expect_bad(
        &t,
        Kind::Value("capacitive.lowpass.kind"),
        at(&t, "kind = \"highpass\""),
        &["capacitive.lowpass.kind", "\"highpass\"", "\"lowpass\""],
    );
}

/// The band-pass in front of the demodulator must be a band-pass.
#[test]
fn capacitive_bandpass_declared_lowpass() {
    let t = cap_with(&[(
        "kind = \"bandpass\", order = 2, band_hz = [15_000.0, 25_000.0]",
        "kind = \"lowpass\", order = 2, corner_hz = 25_000.0",
    )]);
    expect_bad(
        &t,
        Kind::Value("capacitive.bandpass.kind"),
        at(&t, "kind = \"lowpass\", order = 2"),
        &["capacitive.bandpass.kind", "\"bandpass\""],
    );
}

/// `target = "spartan3an"` with `[capacitive]` used to write a Quartus QSF.
#[test]
fn spartan3an_target_with_the_capacitive_path() {
    let t = cap_with(&[("target = \"cyclone3\"", "target = \"spartan3an\"")]);
    expect_bad(
        &t,
        Kind::Value("target"),
        at(&t, "target = \"spartan3an\""),
        &["`target`", "\"cyclone3\"", "[capacitive]"],
    );
}

/// `target = "cyclone3"` with the LTC1407A-1 preset used to leave out `<name>_top.v`
/// without a word.
#[test]
fn cyclone3_target_with_the_ltc1407a1_preset() {
    let t = default_with(&[("target = \"spartan3an\"", "target = \"cyclone3\"")]);
    expect_bad(
        &t,
        Kind::Value("target"),
        at(&t, "target = \"cyclone3\""),
        &["`target`", "\"spartan3an\"", "ltc1407a-1"],
    );
}

/// `capacitive.coef.width` 30 and 31 were accepted by `check` and rejected by `generate`
/// with a message without a location: both now fail the same way, at the key.
#[test]
fn capacitive_coef_width_30_and_31_rejected_by_check_too() {
    for w in [30, 31] {
        let t = cap_with(&[(
            "coef = { width = 25, frac = 22 }",
            &format!("coef = {{ width = {w}, frac = 22 }}"),
        )]);
        expect_bad(
            &t,
            Kind::Value("capacitive.coef.width"),
            at(&t, &format!("width = {w}")),
            &["capacitive.coef.width", &format!("{w}")],
        );
    }
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

/// `gain_frac_bits` = 16 used to be blamed on `gain_sin`.
#[test]
fn gain_frac_bits_named_not_gain_sin() {
    for v in ["16", "7", "64"] {
        let new = format!("gain_frac_bits = {v}");
        let t = default_with(&[("gain_frac_bits = 14", &new)]);
        expect_bad(
            &t,
            Kind::Syntax,
            value_at(&t, &new),
            &["`correction.gain_frac_bits`", "8..=15"],
        );
    }
}

/// Loss-of-signal and clipping settings are blamed on their own key, in fractions of full
/// scale (the user's units), not on `los_amplitude` in internal magnitude units.
#[test]
fn monitor_keys_blamed_on_themselves_in_user_units() {
    let t = default_with(&[("los_release = 0.3", "los_release = 0.2")]);
    expect_bad(
        &t,
        Kind::Value("monitor.los_release"),
        at(&t, "los_release = 0.2"),
        &[
            "monitor.los_release",
            "0.2",
            "0.25",
            "fractions of full scale",
        ],
    );
    let t = default_with(&[("clip_amplitude = 1.0", "clip_amplitude = 0.28")]);
    expect_bad(
        &t,
        Kind::Value("monitor.clip_amplitude"),
        at(&t, "clip_amplitude = 0.28"),
        &["monitor.clip_amplitude", "0.28", "0.3"],
    );
    for (old, new, key) in [
        ("los_window = 8", "los_window = 0", "monitor.los_window"),
        ("los_window = 8", "los_window = 65536", "monitor.los_window"),
        ("clip_hold = 16", "clip_hold = 0", "monitor.clip_hold"),
    ] {
        let t = default_with(&[(old, new)]);
        expect_bad(&t, Kind::Value(key), at(&t, new), &[key, "1..=65535"]);
    }
    // A los_amplitude above the default release level is blamed on los_amplitude, the key in
    // the file, and the message says where the other value comes from.
    let t = default_with(&[
        ("los_amplitude = 0.25", "los_amplitude = 0.5"),
        ("los_release = 0.3\n", ""),
    ]);
    expect_bad(
        &t,
        Kind::Value("monitor.los_amplitude"),
        at(&t, "los_amplitude = 0.5"),
        &[
            "monitor.los_amplitude",
            "0.5",
            "monitor.los_release",
            "default 0.3",
        ],
    );
}

/// `report --angle-n 0` used to be blamed on `cordic.iterations`.
#[test]
fn report_angle_n_zero_names_the_option() {
    let l = Loaded::default_config().unwrap();
    let mut o = sinedec::report::Options::new("test");
    o.iterations = vec![14];
    o.angle_n = Some(0);
    let e = match sinedec::report::build(&l, &o) {
        Ok(_) => panic!("--angle-n 0 accepted"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("--angle-n"), "{e}");
    assert!(e.contains("1..=20"), "{e}");
    assert!(!e.contains("cordic.iterations"), "{e}");
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
