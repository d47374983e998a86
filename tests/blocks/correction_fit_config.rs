//! `[correction]` keys of the ellipse fit: `mode = "auto"` builds the fit (phase stage
//! included), `"peak"` the older peak tracker; `min_samples` is range-checked and must
//! outlast the solve, with file:line:col errors; `check` explains the fit's limits.
use crate::common;
use sinedec::config::{Loaded, DEFAULT_CONFIG};

fn with(lines: &str) -> String {
    DEFAULT_CONFIG.replace("mode = \"static\"", lines)
}

#[test]
fn auto_is_the_fit_and_peak_the_tracker() {
    let a = Loaded::parse(&with("mode = \"auto\""), "a.toml").expect("auto");
    let c = &a.derived.correction;
    let f = c.fit().expect("fit");
    assert_eq!(f.min_samples(), 4096);
    assert!(c.auto().is_none() && c.has_phase());
    // 3 + the phase stage's 2 + the run-time shift-add trees' 3.
    assert!(c.shift_add() && c.run_time_codes());
    assert_eq!(c.latency_cycles(), 8);
    let p = Loaded::parse(&with("mode = \"peak\""), "p.toml").expect("peak");
    assert!(p.derived.correction.auto().is_some() && p.derived.correction.fit().is_none());
    // 3 + the run-time shift-add trees' 3.
    assert_eq!(p.derived.correction.latency_cycles(), 6);
}

/// The error names bad.toml and the line of `needle` (the column is the key's or the
/// value's, as for the other keys) and mentions each of `mentions`.
fn refused(text: &str, needle: &str, mentions: &[&str]) {
    let (line, _) = common::line_col(text, needle);
    let e = Loaded::parse(text, "bad.toml").unwrap_err().to_string();
    assert!(e.starts_with(&format!("bad.toml:{line}:")), "{e}");
    for m in mentions {
        assert!(e.contains(m), "{e} should mention {m}");
    }
}

#[test]
fn min_samples_out_of_range_or_too_short_is_refused_at_the_key() {
    refused(
        &with("mode = \"auto\"\nmin_samples = 0"),
        "min_samples = 0",
        &["correction.min_samples", "0"],
    );
    refused(
        &with("mode = \"auto\"\nmin_samples = 16777217"),
        "min_samples = 16777217",
        &["correction.min_samples"],
    );
    // 133.33 MHz / 1.307157 Msps = 102.0 clocks per sample (a hair under): 20 samples =
    // 2040 clocks, not more than 2041 (the 2030-clock solve: the launch clock, 6 divisions of
    // 64 steps at 134 clocks, 3 of 80 at 166, 11 products and roots of 32 at 66, and Load; and the fit's 11
    // stages A, Q, B1, B2, the tree's operand register, C1-C3, the products' phases 1 and 2
    // and the coefficients' output copy).
    refused(
        &with("mode = \"auto\"\nmin_samples = 20"),
        "min_samples = 20",
        &[
            "outlast the 2041 clocks",
            "2030-clock solve",
            "at least 21 samples",
        ],
    );
    assert!(Loaded::parse(&with("mode = \"auto\"\nmin_samples = 21"), "ok.toml").is_ok());
    refused(
        &with("mode = \"auto\"\nphase_deg = 2.0"),
        "phase_deg = 2.0",
        &["static only"],
    );
    refused(&with("mode = \"fit\""), "mode = \"fit\"", &["\"peak\""]);
}

#[test]
fn check_explains_the_fits_window_speed_limit_and_minimum() {
    let a = Loaded::parse(&with("mode = \"auto\""), "a.toml").expect("auto");
    let s = a.derived.describe();
    assert!(s.contains("least-squares ellipse fit"), "{s}");
    // 4096 samples at 1,307,157 samples/s = 3.13 ms.
    let ms = format!("{:.2} ms", 4096.0 / 1_307_157.0 * 1e3);
    assert_eq!(ms, "3.13 ms");
    assert!(s.contains(&format!("4096 samples ({ms}")), "{s}");
    assert!(s.contains("2030-clock solve"), "{s}");
    // 2030 + the fit's 11 stages (A, Q, B1, B2, the tree's operand register, C1-C3, the
    // products' phases 1 and 2, the coefficients' output copy).
    assert!(
        s.contains("new coefficients 2041 clocks after the window's closing sample"),
        "{s}"
    );
    assert!(
        s.contains(&format!(
            "{:.0} rpm unwrap limit",
            a.derived.max_speed_rpm_full_res
        )),
        "{s}"
    );
    let min = a.derived.correction.fit().expect("fit").min_amplitude();
    assert!(s.contains(&format!("no update below {min} LSB")), "{s}");
}
