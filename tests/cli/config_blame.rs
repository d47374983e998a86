//! Which key an error names: the key the user wrote, at its line and column, also when the
//! check involves several keys or a default (then named as such), never a neighbour.
//!
//! Every expected position is computed here from the text the test wrote (byte offset of a
//! unique needle -> line and column), never copied from a run. The helpers (`expect_bad`:
//! the library's error, position and message, then `check` and `generate` on the command
//! line, nothing written) are in `tests/cli/config_errors_util/`.
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

/// The default config with `[velocity] enabled = true` and `keys` appended.
fn with_velocity(keys: &str) -> String {
    format!("{DEFAULT_CONFIG}\n[velocity]\nenabled = true\n{keys}\n")
}

/// `kalman_r = 0` was blamed on `velocity.kalman_q` and `lsq_order = 0` on `lsq_points`:
/// each method key is blamed on itself (the later one of a pair that does not fit).
#[test]
fn velocity_method_keys_are_blamed_on_themselves() {
    for (keys, key, needle) in [
        (
            "method = \"kalman\"\nkalman_r = 0.0",
            "velocity.kalman_r",
            "kalman_r = 0.0\n",
        ),
        (
            "method = \"kalman\"\nkalman_q = -1.0",
            "velocity.kalman_q",
            "kalman_q = -1.0",
        ),
        (
            "method = \"lsq\"\nlsq_order = 0",
            "velocity.lsq_order",
            "lsq_order = 0\n",
        ),
        (
            "method = \"lsq\"\nlsq_points = 17",
            "velocity.lsq_points",
            "lsq_points = 17",
        ),
        (
            "method = \"lsq\"\nlsq_points = 3\nlsq_order = 3",
            "velocity.lsq_order",
            "lsq_order = 3\n",
        ),
        (
            "method = \"diff_lpf\"\ncutoff_hz = -5.0",
            "velocity.cutoff_hz",
            "cutoff_hz = -5.0",
        ),
    ] {
        let t = with_velocity(keys);
        expect_bad(&t, Kind::Value(key), at(&t, needle), &[key]);
    }
}

/// `[velocity] rate_hz = 0.04` said "use a bandwidth below about 0 Hz and at least 0.000
/// Hz", blamed on `velocity.bandwidth_hz` (not in the file) without line:col. The key in the
/// file is blamed, the default it clashes with is named as such, and the advice works.
#[test]
fn a_velocity_rate_too_low_for_the_default_bandwidth_blames_rate_hz() {
    let t = with_velocity("rate_hz = 0.04");
    expect_bad(
        &t,
        Kind::Value("velocity.rate_hz"),
        at(&t, "rate_hz = 0.04"),
        &["velocity.rate_hz", "bandwidth_hz", "default 200"],
    );
    let m = match Loaded::parse(&t, SRC) {
        Err(e) => e.to_string(),
        Ok(_) => unreachable!(),
    };
    assert!(!m.contains("about 0 Hz") && !m.contains(" 0.000 Hz"), "{m}");
    // The advised rate gets past this check (a narrower out_velocity may then need more
    // bits: that is another key's check).
    let rate = m
        .split("rate_hz of at least ")
        .nth(1)
        .and_then(|s| s.split(" Hz").next())
        .unwrap_or_else(|| panic!("no advised rate in {m}"));
    let fixed = with_velocity(&format!("rate_hz = {rate}\nwidth = 62"));
    if let Err(e) = Loaded::parse(&fixed, SRC) {
        let s = e.to_string();
        assert!(
            !s.contains("velocity.bandwidth_hz") && !s.contains("key `velocity.rate_hz`"),
            "advised rate {rate} Hz: {s}"
        );
    }
    // So does a bandwidth inside the advised range, at the low rate.
    let range = m
        .split("bandwidth_hz between ")
        .nth(1)
        .unwrap_or_else(|| panic!("no advised bandwidth in {m}"));
    let mut nums = range
        .split(" and ")
        .take(2)
        .map(|s| s.split_whitespace().next().unwrap().parse::<f64>().unwrap());
    let (lo, hi) = (nums.next().unwrap(), nums.next().unwrap());
    assert!(0.0 < lo && lo < hi, "{m}");
    let mid = (lo * hi).sqrt();
    let t = with_velocity(&format!("rate_hz = 0.04\nbandwidth_hz = {mid:e}"));
    if let Err(e) = Loaded::parse(&t, SRC) {
        let s = e.to_string();
        assert!(
            !s.contains("velocity.bandwidth_hz") && !s.contains("velocity.rate_hz"),
            "bandwidth {mid} Hz: {s}"
        );
    }
}

/// Errors of `[adc.frame]` and `[adc.timing]` were all blamed on `adc.preset`.
#[test]
fn adc_frame_and_timing_errors_are_blamed_on_their_keys() {
    for (section, key, needle) in [
        (
            "[adc.frame]\nframe_sck = 20",
            "adc.frame.frame_sck",
            "frame_sck = 20",
        ),
        (
            "[adc.frame]\npipeline = 3",
            "adc.frame.pipeline",
            "pipeline = 3",
        ),
        (
            "[adc.frame]\nchannels = 3",
            "adc.frame.channels",
            "channels = 3",
        ),
        (
            "[adc.frame]\noffsets = [1, 5]",
            "adc.frame.offsets",
            "offsets = [1, 5]",
        ),
        (
            "[adc.timing]\ndata_valid_ns = 2e6",
            "adc.timing.data_valid_ns",
            "data_valid_ns = 2e6",
        ),
        (
            // 0.9 ms: no SCK divider up to 64 clocks past the chip's covers the round trip.
            "[adc.timing]\ndata_valid_ns = 9e5",
            "adc.timing.data_valid_ns",
            "data_valid_ns = 9e5",
        ),
        (
            "[adc.timing]\nsck_min_pulse_ns = 9.0",
            "adc.timing.sck_min_pulse_ns",
            "sck_min_pulse_ns = 9.0",
        ),
    ] {
        let t = generic_with(section);
        expect_bad(&t, Kind::Value(key), at(&t, needle), &[key]);
    }
}

/// `capacitive.coef` of width 1, or with frac = width, was blamed on `capacitive.bandpass`,
/// and its range read 2..=64 in one message and 2..=30 in another: the format's keys are
/// blamed, with the one range the biquad engine takes.
#[test]
fn capacitive_coef_format_is_blamed_on_its_keys_with_one_range() {
    for (coef, key, needle, range) in [
        (
            "coef = { width = 1, frac = 0 }",
            "capacitive.coef.width",
            "width = 1,",
            "2..=30",
        ),
        (
            "coef = { width = 65, frac = 22 }",
            "capacitive.coef.width",
            "width = 65",
            "2..=30",
        ),
        (
            "coef = { width = 25, frac = 25 }",
            "capacitive.coef.frac",
            "frac = 25",
            "1..=24",
        ),
        (
            "coef = { width = 25, frac = 0 }",
            "capacitive.coef.frac",
            "frac = 0",
            "1..=24",
        ),
    ] {
        let t = cap_with(&[("coef = { width = 25, frac = 22 }", coef)]);
        expect_bad(&t, Kind::Value(key), at(&t, needle), &[key, range]);
    }
}

/// A `[board]` without `iostandard` (and without a preset that sets it) was blamed on
/// `board.pins`: the missing key is named, at the `[board]` table's name.
#[test]
fn a_missing_iostandard_is_named_at_the_board_table() {
    let t = format!("{DEFAULT_CONFIG}\n[board]\nclock_hz = 133.33e6\n");
    expect_bad(
        &t,
        Kind::Value("board.iostandard"),
        at(&t, "board]\nclock_hz"),
        &["board.iostandard", "LVCMOS33"],
    );
}

/// `biss.multiturn_bits = 12` on the default config did not say that the word is too long:
/// 12 multi-turn + 27 position bits = 39 > 32.
#[test]
fn biss_multiturn_bits_says_the_word_is_too_long() {
    let t = default_with(&[("multiturn_bits = 0\n", "multiturn_bits = 12\n")]);
    expect_bad(
        &t,
        Kind::Value("biss.multiturn_bits"),
        at(&t, "multiturn_bits = 12\n# Gray"),
        &["biss.multiturn_bits", "12 + 27 = 39", "32"],
    );
}

/// The chip presets fix their frame and timing and have no pre-amplifier: `[preamp]`,
/// `[adc.frame]`, `[adc.timing]` and `max_sample_rate_hz` are refused at the key written.
#[test]
fn chip_presets_refuse_preamp_frame_and_timing() {
    for preset in ["ads8354", "ad7380"] {
        let p = format!("preset = \"{preset}\"");
        let t = default_with(&[
            ("preset = \"ltc1407a-1\"", &p),
            ("width = 14", "width = 16"),
        ]);
        expect_bad(
            &t,
            Kind::Value("preamp.gain_a"),
            at(&t, "gain_a = -1"),
            &["preamp", "ltc1407a-1"],
        );
        let with = |extra: &str| {
            default_with(&[
                ("preset = \"ltc1407a-1\"", &format!("{p}\n{extra}")),
                ("width = 14", "width = 16"),
                NO_PREAMP,
            ])
        };
        let t = with("max_sample_rate_hz = 1e6");
        expect_bad(
            &t,
            Kind::Value("adc.max_sample_rate_hz"),
            at(&t, "max_sample_rate_hz = 1e6"),
            &["adc.max_sample_rate_hz", preset, "generic"],
        );
        let t = with("").replacen(
            "\n[cordic]",
            "\n[adc.timing]\ndata_valid_ns = 5.0\n\n[cordic]",
            1,
        );
        expect_bad(
            &t,
            Kind::Value("adc.timing"),
            at(&t, "timing]"),
            &["[adc.timing]", preset, "generic"],
        );
        let t = default_with(&[
            ("preset = \"ltc1407a-1\"", &p),
            ("width = 14", "width = 12"),
            NO_PREAMP,
        ]);
        expect_bad(
            &t,
            Kind::Value("adc.width"),
            at(&t, "width = 12"),
            &["adc.width", "16"],
        );
    }
}
