//! Which keys apply to which design: the capacitive path's own rules (filter kinds, the
//! coefficient format, no QEP or correction), the target against the design, sections that are
//! off, and `check`'s statement of what `generate` writes and whether `simulate` can run.
//!
//! Every expected position is computed here from the text the test wrote (byte offset of a
//! unique needle -> line and column), never copied from a run. The helpers (`expect_bad`:
//! the library's error, position and message, then `check` and `generate` on the command
//! line, nothing written) are in `tests/cli/config_errors_util/`.
use crate::config_errors_util;
use config_errors_util::*;
use sinedec::config::{Loaded, DEFAULT_CONFIG};

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

/// The capacitive top has no QEP inputs and no offset/gain correction: `[qep] enabled = true`
/// and a `[correction]` that would change anything used to be accepted (the Verilog did not
/// change, but `<name>_params.json` said they were on). Each is blamed on its key; the
/// defaults (`enabled = false`, `mode = "static"`) stay accepted.
#[test]
fn qep_and_correction_are_rejected_with_the_capacitive_path() {
    let t = format!("{CAP}\n[qep]\nenabled = true\nfilter_clocks = 4\n");
    expect_bad(
        &t,
        Kind::Value("qep.enabled"),
        at(&t, "enabled = true"),
        &["qep.enabled", "capacitive"],
    );
    for (line, key) in [
        ("mode = \"auto\"", "correction.mode"),
        ("mode = \"peak\"", "correction.mode"),
        ("offset_sin = 3", "correction.offset_sin"),
        ("gain_cos = 1.5", "correction.gain_cos"),
        ("phase_deg = 2.0", "correction.phase_deg"),
    ] {
        // `mode` is required in a `[correction]` table.
        let mode = if line.starts_with("mode") {
            ""
        } else {
            "mode = \"static\"\n"
        };
        let t = format!("{CAP}\n[correction]\n{mode}{line}\n");
        expect_bad(&t, Kind::Value(key), at(&t, line), &[key, "capacitive"]);
    }
    let t = format!(
        "{CAP}\n[qep]\nenabled = false\nfilter_clocks = 4\n[correction]\nmode = \"static\"\n"
    );
    Loaded::parse(&t, SRC).expect("the defaults, written out, are accepted");
}

/// Without `capacitive.data_width` the default (18) was outside the allowed 12..=16: the
/// key can be left out, and the default is the CORDIC's widest input, 16 bits (docs/cli.md,
/// "Supported ranges").
#[test]
fn capacitive_data_width_may_be_left_out() {
    let t = cap_with(&[("data_width = 16\n", "")]);
    let l = Loaded::parse(&t, SRC).unwrap_or_else(|e| panic!("rejected: {e}"));
    assert_eq!(l.derived.adc_width, 16);
    let readme = include_str!("../../docs/cli.md");
    assert!(
        readme
            .lines()
            .any(|l| l.starts_with("| `capacitive.data_width` |") && l.contains("default 16")),
        "docs/cli.md documents the default of capacitive.data_width"
    );
}

/// One rule for the keys of a section that is off (`enabled = false`): they are not checked
/// (they have no effect), and turning the section on checks them at their line. `[abz]` used
/// to be checked while off, `[velocity]` and `[ssi]` not.
#[test]
fn keys_of_a_disabled_section_are_checked_only_when_it_is_on() {
    let appended = |section: &str, on: bool, key_line: &str| {
        format!("{DEFAULT_CONFIG}\n[{section}]\nenabled = {on}\n{key_line}\n")
    };
    for (section, key_line, key) in [
        ("abz", "lines = 0", "abz.lines"),
        ("abz", "max_edge_hz = -1.0", "abz.max_edge_hz"),
        ("velocity", "rate_hz = -1.0", "velocity.rate_hz"),
        ("velocity", "width = 4", "velocity.width"),
    ] {
        let off = appended(section, false, key_line);
        Loaded::parse(&off, SRC).unwrap_or_else(|e| panic!("[{section}] off with {key_line}: {e}"));
        let on = appended(section, true, key_line);
        expect_bad(&on, Kind::Value(key), at(&on, key_line), &[key]);
    }
    // [ssi] is in the shipped config, off.
    let off = default_with(&[("timeout_us = 20.0\n\n[spi]", "timeout_us = -1.0\n\n[spi]")]);
    Loaded::parse(&off, SRC).unwrap_or_else(|e| panic!("[ssi] off: {e}"));
    let on = edit(
        &off,
        "enabled = false\ngray = false\ntimeout_us = -1.0",
        "enabled = true\ngray = false\ntimeout_us = -1.0",
    );
    expect_bad(
        &on,
        Kind::Value("ssi.timeout_us"),
        at(&on, "timeout_us = -1.0"),
        &["ssi.timeout_us"],
    );
    // docs/cli.md states the rule.
    let readme = include_str!("../../docs/cli.md");
    assert!(
        readme.contains("keys of a section that is off"),
        "docs/cli.md states the rule for disabled sections"
    );
}

/// `check` says up front what `generate` will write and whether `simulate` can run: every
/// preset builds its board top (a `generic` sinewave config included, with its ADC model in
/// `simulate`). The statement agrees with what `generate` writes.
#[test]
fn check_says_up_front_what_is_generated_and_simulated() {
    let generic = default_with(&[GENERIC, NO_PREAMP]);
    for (text, top, chip) in [
        (DEFAULT_CONFIG, "sd_top.v", "LTC1407A-1"),
        (CAP, "cap_top.v", "capacitive"),
        (generic.as_str(), "sd_top.v", "generic SPI ADC"),
    ] {
        let tmp = tempfile::tempdir().unwrap();
        std::fs::write(tmp.path().join(SRC), text).unwrap();
        let o = run(tmp.path(), &["check", SRC]);
        assert!(o.status.success(), "{}", stderr(&o));
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        let line = |what: &str| -> (usize, String) {
            out.lines()
                .enumerate()
                .find(|(_, l)| l.starts_with(what))
                .map(|(i, l)| (i, l.to_string()))
                .unwrap_or_else(|| panic!("no `{what}` line in:\n{out}"))
        };
        let (gi, gen) = line("board top");
        let (si, sim) = line("simulate");
        let (ci, _) = line("core input width");
        assert!(gi < ci && si < ci, "not up front:\n{out}");
        let l = Loaded::parse(text, SRC).unwrap();
        let files = sinedec::emit::generate(&l, "test").unwrap();
        assert!(files.files.iter().any(|f| f.name == top), "{top}");
        assert!(gen.contains(top) && gen.contains(chip), "{gen}");
        assert!(
            sim.starts_with("simulate") && sim.contains("available: runs"),
            "{sim}"
        );
        assert!(sim.contains(chip), "{sim}");
    }
}
