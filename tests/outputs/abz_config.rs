//! `[abz]`: defaults (off: no parameters; on: 16 x PPR lines, 12.5 MHz edges), the derived
//! edge spacing and maximum speed printed by `check` (expected figures computed here from
//! the definitions), and bad values rejected with file:line:col, the key and what is allowed.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");

use crate::common;

fn with_abz(section: &str) -> String {
    common::with_section("abz", section)
}

#[test]
fn off_by_default_and_defaults_when_enabled() {
    let l = Loaded::parse(DEFAULT_CONFIG, "d.toml").unwrap();
    assert!(l.derived.abz.is_none());
    // Off, the keys are not checked (they have no effect) and build nothing.
    let l = Loaded::parse(&with_abz("lines = 1000"), "d.toml").unwrap();
    assert!(l.derived.abz.is_none());
    let l = Loaded::parse(&with_abz("enabled = true"), "d.toml").unwrap();
    let p = l.derived.abz.expect("enabled");
    let ppr = l.derived.quadrants_per_turn / 4;
    assert_eq!(p.lines(), 16 * ppr);
    // 12.5 MHz at 133.33 MHz: the smallest S with clock / S <= 12.5 MHz.
    let clock = l.derived.clock_hz;
    let s = (1..).find(|&s| clock / s as f64 <= 12.5e6).unwrap();
    assert_eq!(p.spacing(), s);
}

#[test]
fn check_prints_the_edge_rate_and_the_maximum_speed() {
    let dir = tempfile::tempdir().unwrap();
    let text = with_abz("enabled = true\nlines = 2000\nmax_edge_hz = 20e6");
    std::fs::write(dir.path().join("a.toml"), &text).unwrap();
    let o = Command::new(BIN)
        .args(["check", "a.toml"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8(o.stdout).unwrap();
    let clock = Loaded::parse(&text, "a.toml").unwrap().derived.clock_hz;
    let s = (1..).find(|&s| clock / s as f64 <= 20e6).unwrap();
    let rate = clock / s as f64;
    let rpm = rate / 8000.0 * 60.0;
    let line = |label: &str| {
        out.lines()
            .find(|l| l.starts_with(label))
            .unwrap_or_else(|| panic!("no `{label}` line in:\n{out}"))
            .to_string()
    };
    assert!(line("abz lines").contains("2000 A/B periods per turn = 8000 edges"));
    let r = line("abz max edge rate");
    assert!(
        r.contains(&format!("{:.3} M edges/s", rate / 1e6)) && r.contains(&format!("{s} clocks")),
        "{r}"
    );
    assert!(
        line("abz max speed").contains(&format!("{rpm:.0} rpm")),
        "{out}"
    );
    // Without [abz] there is no such line (the default listing is unchanged).
    std::fs::write(dir.path().join("d.toml"), DEFAULT_CONFIG).unwrap();
    let o = Command::new(BIN)
        .args(["check", "d.toml"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(!String::from_utf8(o.stdout).unwrap().contains("abz"));
}

#[test]
fn bad_values_name_the_key_the_position_and_the_range() {
    let cases: &[(&str, &str, &[&str])] = &[
        // 4 lines > positions per turn (2^27 at PPR 2048, F 14): allowed 1..=2^25.
        (
            "enabled = true\nlines = 40000000",
            "lines = 40000000",
            &["`abz.lines`", "allowed 1..=33554432"],
        ),
        (
            "enabled = true\nlines = 0",
            "lines = 0",
            &["`abz.lines`", "allowed 1..="],
        ),
        // Above clock / 2.
        (
            "enabled = true\nmax_edge_hz = 80e6",
            "max_edge_hz = 80e6",
            &["`abz.max_edge_hz`", "66665000 Hz"],
        ),
        (
            "enabled = true\nmax_edge_hz = 1.0",
            "max_edge_hz = 1.0",
            &["`abz.max_edge_hz`", "allowed"],
        ),
    ];
    for (section, needle, mentions) in cases {
        common::assert_config_error(&with_abz(section), needle, mentions);
    }
    // Unknown keys are rejected by the schema.
    let e = Loaded::parse(&with_abz("enable = true"), "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("enable"), "{e}");
}

/// The default config shows the optional `[abz]` and `[velocity]` tables and the BiSS
/// control keys as comments: uncommented, they must parse to what their comments say.
#[test]
fn commented_examples_in_the_default_config_are_valid() {
    let control_keys = [
        "control = true",
        "device_id =",
        "manufacturer_id =",
        "profile_id =",
        "serial_number =",
        "eds_bank =",
    ];
    // Inside a commented table (from `# [abz]` or `# [velocity]` to the next blank line)
    // every line is uncommented; elsewhere only the control keys.
    let mut in_table = false;
    let mut text = String::new();
    for l in DEFAULT_CONFIG.lines() {
        if l == "# [abz]" || l == "# [velocity]" {
            in_table = true;
        } else if l.trim().is_empty() {
            in_table = false;
        }
        let line = match l.strip_prefix("# ") {
            Some(rest) if in_table || control_keys.iter().any(|k| rest.starts_with(k)) => {
                // Drop the example line's trailing explanation.
                rest.split("  #").next().unwrap_or(rest).trim_end()
            }
            _ => l,
        };
        text.push_str(line);
        text.push('\n');
    }
    assert_ne!(
        text,
        format!("{DEFAULT_CONFIG}\n"),
        "no example uncommented"
    );
    let l = Loaded::parse(&text, "d.toml").unwrap();
    let abz = l.derived.abz.expect("[abz] enabled");
    // The comment: 16 x PPR lines (PPR 2048), 12.5 MHz edges.
    assert_eq!(abz.lines(), 16 * 2048);
    let clock = l.derived.clock_hz;
    assert_eq!(
        abz.spacing(),
        (1..).find(|&s| clock / s as f64 <= 12.5e6).unwrap()
    );
    // The velocity comments: tracking at 7.5 kHz, 32 bits with 8 fraction bits, no frames.
    let v = l.derived.velocity.as_ref().expect("[velocity] enabled");
    assert_eq!((v.spec.width, v.spec.frac_bits), (32, 8));
    let id = l.derived.biss.control.expect("[biss] control = true");
    assert_eq!(&id.device_id, b"SINDEC");
    assert_eq!(&id.manufacturer_id, b"SD");
    assert_eq!((id.profile_id, id.serial_number, id.eds_bank), (0, 0, 0));
    // `check` lists the control channel's ID registers.
    let out = check_ok(&text);
    assert!(
        out.contains("biss control channel        on:")
            && out.contains("device 0x78..7D = \"SINDEC\""),
        "{out}"
    );
}

/// `check` without `[biss] control` says the channel is off, and the data word's bits.
#[test]
fn check_prints_the_biss_word_and_the_control_channel_off() {
    let out = check_ok(DEFAULT_CONFIG);
    // Default: 2048 PPR x 4 quadrants x 2^14 fine steps = 2^27 positions per turn, no turns.
    assert!(
        out.contains("biss data word              27 bits (0 multi-turn + 27 single-turn, binary)"),
        "{out}"
    );
    assert!(out.contains("biss control channel        off"), "{out}");
}

/// `sinedec check` on `text` (written to a temporary file): its standard output, after
/// asserting that it succeeded.
fn check_ok(text: &str) -> String {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("c.toml"), text).unwrap();
    let o = Command::new(BIN)
        .args(["check", "c.toml"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    out
}
