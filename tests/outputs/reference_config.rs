//! `[reference]`: off by default (no parameters, no ports), the parameters and `check` lines
//! when on (the homing limit computed here from its definition: one quadrant per sample),
//! and bad values rejected with file:line:col, the key and what is allowed.
use crate::common;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");

fn with_reference(section: &str) -> String {
    common::with_section("reference", section)
}

#[test]
fn off_by_default_and_derived_when_enabled() {
    let l = Loaded::parse(DEFAULT_CONFIG, "d.toml").expect("default");
    assert!(l.derived.reference.is_none());
    let l = Loaded::parse(&with_reference("quadrant = 9999"), "d.toml").expect("off");
    assert!(
        l.derived.reference.is_none(),
        "keys of a disabled section are not checked"
    );
    let text = with_reference("enabled = true\ngate = \"01\"\nquadrant = 17");
    let l = Loaded::parse(&text, "d.toml").expect("on");
    let r = l.derived.reference.expect("enabled");
    // "01" is quadrant 1 of the comparators; the kit's LTC6912-1 inverts both channels, so
    // the decoded angle numbers it 3.
    assert_eq!(r.gate(), 3);
    assert_eq!(r.index(), (17, 0));
    let d = &l.derived;
    let dir = tempfile::tempdir().expect("dir");
    std::fs::write(dir.path().join("r.toml"), &text).expect("write");
    let o = Command::new(BIN)
        .args(["check", "r.toml"])
        .current_dir(dir.path())
        .output()
        .expect("runs");
    let out = String::from_utf8(o.stdout).expect("utf-8");
    assert!(o.status.success(), "{out}");
    let rpm = d.sample_rate_hz / d.quadrants_per_turn as f64 * 60.0;
    assert!(out.contains(&format!("below {rpm:.0} rpm")), "{out}");
    assert!(out.contains("A/B = 01 (decoded quadrant 3"), "{out}");
    let lat = sinedec::blocks::top::hdl::conv_to_position_cycles(d);
    let base = d.adc.conv_to_valid_clocks() + d.correction.latency_cycles() + d.latency_cycles;
    assert_eq!(lat, base + 1, "one clock more on every position output");
}

#[test]
fn bad_values_name_the_key_the_position_and_the_range() {
    let cases: &[(&str, &str, &[&str])] = &[
        (
            "enabled = true\ngate = \"12\"",
            "gate = \"12\"",
            &["`reference.gate`", "\"11\", \"01\", \"00\" or \"10\""],
        ),
        (
            "enabled = true\nquadrant = 8192",
            "quadrant = 8192",
            &["`reference.quadrant`", "allowed 0..=8191"],
        ),
        (
            "enabled = true\npreset_quadrant = -1",
            "preset_quadrant = -1",
            &["`reference.preset_quadrant`", "allowed 0..=8191"],
        ),
        // The default's 12 multi-turn bits: a signed 12-bit turn count.
        (
            "enabled = true\nturn = 2048",
            "turn = 2048",
            &["`reference.turn`", "allowed -2048..=2047"],
        ),
    ];
    for (section, needle, mentions) in cases {
        common::assert_config_error(&with_reference(section), needle, mentions);
    }
    // Homing needs the comparators.
    let qep = DEFAULT_CONFIG.find("[qep]").expect("a [qep] table");
    let on = qep
        + DEFAULT_CONFIG[qep..]
            .find("enabled = true")
            .expect("qep enabled");
    let mut text = DEFAULT_CONFIG.to_string();
    text.replace_range(on..on + "enabled = true".len(), "enabled = false");
    let qep_off = format!("{text}\n[reference]\nenabled = true\n");
    let e = Loaded::parse(&qep_off, "bad.toml").unwrap_err().to_string();
    assert!(e.contains("[qep] enabled = true"), "{e}");
    let e = Loaded::parse(&with_reference("enable = true"), "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("enable"), "{e}");
}
