//! `[capture]`: off by default (no parameters, no ports), the parameters, the `check` lines
//! (the age range computed here from its definition: from L - 1 to L + P - 2 clocks, L the
//! CONV-to-position latency and P the ADC period) and the wrapper's ports when on, and bad
//! values rejected with file:line:col, the key and what is allowed.
use crate::common;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");

const VELOCITY: &str = "\n[velocity]\nenabled = true\n";

fn with_capture(section: &str) -> String {
    common::with_section("capture", section)
}

/// Runs `sinedec <args>` on `text` (written as c.toml) in a fresh directory; returns the
/// directory, stdout and success.
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
fn off_by_default_and_derived_when_enabled() {
    let l = Loaded::parse(DEFAULT_CONFIG, "d.toml").expect("default");
    assert!(l.derived.capture.is_none());
    let l = Loaded::parse(&with_capture("extrapolate = true"), "d.toml").expect("off");
    assert!(
        l.derived.capture.is_none(),
        "keys of a disabled section are not checked"
    );
    let text = with_capture("enabled = true");
    let l = Loaded::parse(&text, "d.toml").expect("on");
    let d = &l.derived;
    let p = d.capture.expect("enabled");
    let lat = sinedec::blocks::top::hdl::conv_to_position_cycles(d);
    assert_eq!(
        p.latency(),
        lat,
        "the age counts from the one CONV-to-position figure"
    );
    assert!(!p.velocity() && p.extrapolation().is_none());
    let (_, out, ok) = sinedec(&text, &["check", "c.toml"]);
    assert!(ok, "{out}");
    let per = d.adc.period_clocks;
    assert!(
        out.contains(&format!("to the capture: {} to {}", lat - 1, lat + per - 2)),
        "{out}"
    );
    assert!(out.contains("latches the position and age"), "{out}");
    // With the position reference the capture takes the referenced position, one clock
    // later: its age counts that clock too.
    let both = format!("{text}\n[reference]\nenabled = true\n");
    let l2 = Loaded::parse(&both, "d.toml").expect("with reference");
    assert_eq!(l2.derived.capture.expect("on").latency(), lat + 1);
    // With the velocity and extrapolation.
    let text = with_capture(&format!("enabled = true\nextrapolate = true\n{VELOCITY}"));
    let (_, out, ok) = sinedec(&text, &["check", "c.toml"]);
    assert!(ok, "{out}");
    assert!(out.contains("velocity x (age + 1/2 clock)"), "{out}");
    assert!(
        out.contains("latches the position, velocity and age"),
        "{out}"
    );
}

#[test]
fn the_wrapper_has_the_capture_input_and_outputs() {
    let text = with_capture(&format!("enabled = true\nextrapolate = true\n{VELOCITY}"));
    let l = Loaded::parse(&text, "c.toml").expect("config");
    let d = &l.derived;
    let (dir, out, ok) = sinedec(&text, &["generate", "c.toml", "-o", "out"]);
    assert!(ok, "{out}");
    let top = std::fs::read_dir(dir.path().join("out"))
        .expect("out")
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .find(|p| p.to_string_lossy().ends_with("_top.v"))
        .expect("a top");
    let v = std::fs::read_to_string(top).expect("read");
    let pw = d.position_width - 1;
    let vw = d.velocity.as_ref().expect("velocity").spec.width - 1;
    for line in [
        "input  wire         capture,".to_string(),
        "output wire         cap_valid,".to_string(),
        format!("output wire [{pw}:0]  cap_position,"),
        format!("output wire [{}:0]  cap_turns,", d.turns_width - 1),
        "output wire [23:0] cap_age,".to_string(),
        format!("output wire signed [{vw}:0]  cap_velocity,"),
        ".capture_0(capture)".to_string(),
        ".cap_velocity_0(cap_vel_w)".to_string(),
    ] {
        assert!(v.contains(&line), "{line:?} missing from the top");
    }
    // Without [capture] none of it.
    let (dir, out, ok) = sinedec(DEFAULT_CONFIG, &["generate", "c.toml", "-o", "out"]);
    assert!(ok, "{out}");
    let any_cap = std::fs::read_dir(dir.path().join("out"))
        .expect("out")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().extension().is_some_and(|x| x == "v"))
        .any(|e| std::fs::read_to_string(e.path()).is_ok_and(|t| t.contains("cap_valid")));
    assert!(!any_cap, "the default top has no capture");
}

#[test]
fn bad_values_name_the_key_the_position_and_the_range() {
    common::assert_config_error(
        &with_capture("enabled = true\nextrapolate = true"),
        "extrapolate = true",
        &["`capture.extrapolate`", "[velocity] enabled = true"],
    );
    // A wrong type points at the value.
    let text = with_capture("enabled = true\nextrapolate = 1");
    let (line, col) = common::line_col(&text, "extrapolate = 1");
    let e = Loaded::parse(&text, "bad.toml").unwrap_err().to_string();
    let at = format!("bad.toml:{line}:{}: ", col + "extrapolate = ".len());
    assert!(
        e.starts_with(&at) && e.contains("`capture.extrapolate`"),
        "{e}"
    );
    let e = Loaded::parse(&with_capture("enable = true"), "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("enable") && e.contains("extrapolate"), "{e}");
}
