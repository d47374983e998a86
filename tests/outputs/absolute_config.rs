//! `[reference] absolute` and `[reference.ssi]`: off by default (no parameters, no ports),
//! the parameters, the `check` lines (the line timing and the tolerance computed here from
//! their definitions in docs/absolute.md) and the wrapper's and constraints' ports when on,
//! and bad values rejected with file:line:col, the key and what is allowed.
use crate::common;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");

/// The default config with `[reference]` (enabled, absolute = "ssi") and `ssi` in
/// `[reference.ssi]`.
fn with_absolute(ssi: &str) -> String {
    format!("{DEFAULT_CONFIG}\n[reference]\nenabled = true\nabsolute = \"ssi\"\n\n[reference.ssi]\n{ssi}\n")
}

/// Runs `sinedec <args>` on `text` (written as c.toml) in a fresh directory; returns the
/// directory, stdout and stderr, and success.
fn sinedec(text: &str, args: &[&str]) -> (tempfile::TempDir, String, bool) {
    let dir = tempfile::tempdir().expect("dir");
    std::fs::write(dir.path().join("c.toml"), text).expect("write");
    let o = Command::new(BIN)
        .args(args)
        .current_dir(dir.path())
        .output()
        .expect("runs");
    let out = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    (dir, out, o.status.success())
}

#[test]
fn off_by_default_and_derived_when_asked() {
    let l = Loaded::parse(DEFAULT_CONFIG, "d.toml").expect("default");
    assert!(l.derived.absolute.is_none());
    let text = common::with_section("reference", "enabled = true");
    let l = Loaded::parse(&text, "d.toml").expect("reference only");
    assert!(l.derived.absolute.is_none());
    assert!(!l.derived.reference.expect("on").absolute());
    let l = Loaded::parse(&with_absolute(""), "d.toml").expect("absolute");
    let a = l.derived.absolute.expect("absolute on");
    // Defaults: one code per quadrant at 2048 lines (13 bits), single-turn, Gray, 500 kHz,
    // t1 400 ns, t_m 20 us.
    let w = a.word();
    assert_eq!(
        (w.single_turn_bits, w.multiturn_bits, w.gray),
        (13, 0, true)
    );
    assert_eq!(a.sub_quadrant_bits(), 0);
    assert_eq!(
        a.quadrant_shift(),
        2,
        "the kit's LTC6912-1 inverts both channels"
    );
    assert!(l.derived.reference.expect("on").absolute());
    // Without the comparators: the absolute start references, nothing homes.
    let text = with_absolute("");
    let qep = text.find("[qep]").expect("qep");
    let mut t = text.clone();
    let on = qep + t[qep..].find("enabled = true").expect("qep on");
    t.replace_range(on..on + "enabled = true".len(), "enabled = false");
    let l = Loaded::parse(&t, "d.toml").expect("absolute without [qep]");
    assert!(l.derived.absolute.is_some() && !l.derived.qep_enabled);
}

#[test]
fn check_prints_the_line_timing_and_the_tolerance() {
    let text = with_absolute("multiturn_bits = 12\nclock_hz = 1e6");
    let l = Loaded::parse(&text, "c.toml").expect("config");
    let d = &l.derived;
    let (_, out, ok) = sinedec(&text, &["check", "c.toml"]);
    assert!(ok, "{out}");
    // H = ceil(f / 2 MHz) clocks per half period; each bit read 2H clocks after the rising
    // edge it answers, less t_co 6 + 2 x trace 1 + t1 400 + t_su 3 ns for the line.
    let h = (d.clock_hz / 2e6).ceil();
    let rt = 2.0 * h * 1e9 / d.clock_hz - 411.0;
    for want in [
        "25-bit Gray word (12 multi-turn + 13 single-turn bits".to_string(),
        format!("({h} clocks per half period); 26 pulses per read"),
        format!("each bit read 2H = {} clocks after", 2.0 * h),
        format!("up to {rt:.1} ns"),
        "1 clock (7.5 ns) after the ADC's sampling edge".to_string(),
        "within +-1.500 quadrants (135.0 degrees electrical)".to_string(),
    ] {
        assert!(out.contains(&want), "{want:?} missing:\n{out}");
    }
    // Four codes per quadrant: 2 - 1/8 quadrants.
    let (_, out, ok) = sinedec(
        &with_absolute("single_turn_bits = 15"),
        &["check", "c.toml"],
    );
    assert!(ok, "{out}");
    assert!(out.contains("within +-1.875 quadrants"), "{out}");
}

#[test]
fn the_wrapper_and_the_constraints_have_the_ssi_pins() {
    let (dir, out, ok) = sinedec(&with_absolute(""), &["generate", "c.toml", "-o", "out"]);
    assert!(ok, "{out}");
    let read = |name: &str| std::fs::read_to_string(dir.path().join("out").join(name)).expect(name);
    let v = read("sd_top.v");
    for line in [
        "output wire         abs_clk,",
        "input  wire         abs_data,",
        ".abs_clk_0(abs_clk), .abs_data_0(abs_data)",
    ] {
        assert!(v.contains(line), "{line:?} missing from the top");
    }
    for ext in ["sdc", "xdc"] {
        let c = read(&format!("sd_top.{ext}"));
        assert!(
            c.contains("set_false_path -from [get_ports abs_data]"),
            "{ext}"
        );
        assert!(c.contains("[get_ports abs_clk]"), "{ext}");
        assert!(c.contains("absolute encoder (SSI)"), "{ext}");
        assert!(c.contains("round trip"), "{ext}: the SSI line's budget");
    }
    let (dir, out, ok) = sinedec(DEFAULT_CONFIG, &["generate", "c.toml", "-o", "out"]);
    assert!(ok, "{out}");
    let v = std::fs::read_to_string(dir.path().join("out").join("sd_top.v")).expect("top");
    assert!(!v.contains("abs_clk"), "the default top has no SSI master");
}

#[test]
fn bad_values_name_the_key_the_position_and_the_range() {
    let reference = |body: &str| common::with_section("reference", body);
    let cases: Vec<(String, &str, &[&str])> = vec![
        (
            reference("enabled = true\nabsolute = \"biss\""),
            "absolute = \"biss\"",
            &["`reference.absolute`", "allowed \"none\" or \"ssi\""],
        ),
        (
            reference("absolute = \"ssi\""),
            "absolute = \"ssi\"",
            &["`reference.absolute`", "[reference] enabled = true"],
        ),
        (
            with_absolute("single_turn_bits = 12"),
            "single_turn_bits = 12",
            &["`reference.ssi.single_turn_bits`", "allowed 13..=26"],
        ),
        (
            with_absolute("single_turn_bits = 30"),
            "single_turn_bits = 30",
            &["`reference.ssi.single_turn_bits`", "at most 29"],
        ),
        (
            with_absolute("multiturn_bits = 25"),
            "multiturn_bits = 25",
            &["`reference.ssi.multiturn_bits`", "allowed 0..=19"],
        ),
        (
            with_absolute("clock_hz = 20e6"),
            "clock_hz = 20e6",
            &["`reference.ssi.clock_hz`", "allowed 10e3..=10e6"],
        ),
        (
            with_absolute("clock_hz = 1e6\ndata_valid_ns = 1000"),
            "clock_hz = 1e6",
            &[
                "`reference.ssi.clock_hz`",
                "`reference.ssi.data_valid_ns`",
                "no cable",
            ],
        ),
        (
            with_absolute("monoflop_us = 0"),
            "monoflop_us = 0",
            &["`reference.ssi.monoflop_us`", "allowed > 0"],
        ),
    ];
    for (text, needle, mentions) in &cases {
        common::assert_config_error(text, needle, mentions);
    }
    // PPR must be a power of two: the error names it.
    let text = with_absolute("").replace("ppr = 2048", "ppr = 2000");
    common::assert_config_error(
        &text,
        "absolute = \"ssi\"",
        &["`reference.absolute`", "`encoder.ppr`", "power of two"],
    );
    // A wrong type points at the value; an unknown key names the table's keys.
    let text = with_absolute("gray = 1");
    let (line, col) = common::line_col(&text, "gray = 1");
    let e = Loaded::parse(&text, "bad.toml").unwrap_err().to_string();
    let at = format!("bad.toml:{line}:{}: ", col + "gray = ".len());
    assert!(
        e.starts_with(&at) && e.contains("`reference.ssi.gray`"),
        "{e}"
    );
    let e = Loaded::parse(&with_absolute("bits = 13"), "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("bits") && e.contains("single_turn_bits"), "{e}");
}
