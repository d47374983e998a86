//! `[velocity]`: off by default (no parameters, `check` unchanged), the documented defaults
//! when enabled, the velocity LSB in rpm and the representable range printed by `check`
//! (expected figures computed here from the definitions in docs/velocity.md), and bad values
//! rejected with file:line:col, the key and what is allowed.
use sinedec::blocks::velocity::Method;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");

use crate::common;

fn with_velocity(section: &str) -> String {
    common::with_section("velocity", section)
}

#[test]
fn off_by_default_and_the_contract_defaults_when_enabled() {
    let l = Loaded::parse(DEFAULT_CONFIG, "d.toml").unwrap();
    assert!(l.derived.velocity.is_none());
    // Disabled: the keys build nothing, even values that would not do when enabled.
    let l = Loaded::parse(&with_velocity("width = 4"), "d.toml").unwrap();
    assert!(l.derived.velocity.is_none());
    let l = Loaded::parse(&with_velocity("enabled = true"), "d.toml").unwrap();
    let d = &l.derived;
    let v = d.velocity.as_ref().expect("enabled");
    assert_eq!(v.spec.method, Method::Tracking);
    assert_eq!(
        (v.spec.rate_hz, v.spec.frac_bits, v.spec.width),
        (7500.0, 8, 32)
    );
    assert_eq!(
        (v.spec.cutoff_hz, v.spec.lsq_points, v.spec.lsq_order),
        (900.0, 4, 1)
    );
    assert_eq!(
        (v.spec.kalman_q, v.spec.kalman_r, v.spec.bandwidth_hz),
        (0.01, 0.03, 200.0)
    );
    // D = round(clock / rate) clocks per update.
    assert_eq!(v.period_clocks, (d.clock_hz / 7500.0).round() as u64);
    // The maximum speed is the decoder's: just under 1.75 quadrants (2^14 LSB each) per ADC
    // sample, so per update period at most ceil((1.75 * 2^14 - 1) * fs / 7500) LSB.
    let per_sample = 7 * (1u64 << 12) - 1;
    let want = (per_sample as f64 * d.sample_rate_hz / 7500.0).ceil() as u64;
    assert_eq!(v.spec.max_step, want);
    // Each method builds.
    for m in ["diff_lpf", "lsq", "kalman", "tracking"] {
        let l = Loaded::parse(
            &with_velocity(&format!("enabled = true\nmethod = \"{m}\"")),
            "d.toml",
        )
        .unwrap_or_else(|e| panic!("{m}: {e}"));
        assert_eq!(l.derived.velocity.unwrap().spec.method.to_string(), m);
    }
}

#[test]
fn check_prints_the_lsb_in_rpm_and_the_range() {
    let dir = tempfile::tempdir().unwrap();
    let text = with_velocity("enabled = true\nmethod = \"lsq\"\nfrac_bits = 4\nwidth = 30");
    std::fs::write(dir.path().join("v.toml"), &text).unwrap();
    let o = Command::new(BIN)
        .args(["check", "v.toml"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8(o.stdout).unwrap();
    let line = |label: &str| {
        out.lines()
            .find(|l| l.starts_with(label))
            .unwrap_or_else(|| panic!("no `{label}` line in:\n{out}"))
            .to_string()
    };
    // One LSB = 2^-(F + S) quadrant per update period; 4 x 2048 quadrants per turn:
    // 7500 / 2^18 / 8192 turns per second.
    let lsb = 7500.0 / (1u64 << 18) as f64 / 8192.0 * 60.0;
    let l = line("velocity LSB");
    assert!(l.contains(&format!("{lsb:.6e} rpm")), "{l}");
    let range = ((1u64 << 29) - 1) as f64 * lsb;
    let r = line("velocity range");
    assert!(r.contains(&format!("+-{range:.0} rpm")), "{r}");
    assert!(line("velocity  ").contains("method lsq"), "{out}");
    // Without [velocity] there is no such line.
    std::fs::write(dir.path().join("d.toml"), DEFAULT_CONFIG).unwrap();
    let o = Command::new(BIN)
        .args(["check", "d.toml"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(!String::from_utf8(o.stdout).unwrap().contains("velocity"));
}

#[test]
fn bad_values_name_the_key_the_position_and_the_range() {
    let cases: &[(&str, &str, &[&str])] = &[
        // Above the ADC's sample rate (about 1.3 Msps at the default clock).
        (
            "enabled = true\nrate_hz = 2e6",
            "rate_hz = 2e6",
            &["`velocity.rate_hz`", "at most the ADC's sample rate"],
        ),
        (
            "enabled = true\nrate_hz = -5.0",
            "rate_hz = -5.0",
            &["`velocity.rate_hz`", "above 0"],
        ),
        // 16 lsq multiplies do not fit the 133 clocks of a 1 MHz update period.
        (
            "enabled = true\nmethod = \"lsq\"\nlsq_points = 16\nrate_hz = 1e6",
            "rate_hz = 1e6",
            &["`velocity.rate_hz`", "not longer than an update"],
        ),
        // An unstable loop: 2 alpha + beta >= 4 at 5 kHz bandwidth and 7.5 kHz updates.
        (
            "enabled = true\nbandwidth_hz = 5000.0",
            "bandwidth_hz = 5000.0",
            &["`velocity.bandwidth_hz`", "unstable"],
        ),
        // Overflow at the maximum speed: 16 bits cannot hold 5.7 M LSB per period.
        (
            "enabled = true\nwidth = 16",
            "width = 16",
            &["`velocity.width`", "overflows at the maximum speed"],
        ),
        (
            "enabled = true\nwidth = 80",
            "width = 80",
            &["`velocity.width`", "8..=62"],
        ),
        (
            "enabled = true\nmethod = \"lsq\"\nlsq_points = 1",
            "lsq_points = 1",
            &["`velocity.lsq_points`", "2..=16"],
        ),
        (
            "enabled = true\nmethod = \"diff_lpf\"\ncutoff_hz = 0.0",
            "cutoff_hz = 0.0",
            &["`velocity.cutoff_hz`", "must be > 0"],
        ),
        (
            "enabled = true\nfrac_bits = 20",
            "frac_bits = 20",
            &["`velocity.frac_bits`", "0..=16"],
        ),
    ];
    for (section, needle, mentions) in cases {
        common::assert_config_error(&with_velocity(section), needle, mentions);
    }
    // An unknown method names the allowed ones; unknown keys are rejected by the schema.
    let e = Loaded::parse(&with_velocity("method = \"pll\""), "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("tracking") && e.contains("diff_lpf"), "{e}");
    let e = Loaded::parse(&with_velocity("rate = 1.0"), "bad.toml")
        .unwrap_err()
        .to_string();
    assert!(e.contains("rate"), "{e}");
}

#[test]
fn in_frames_sets_the_velocity_word_of_every_serial_frame_or_is_rejected() {
    // Off by default: no velocity word anywhere.
    let l = Loaded::parse(&with_velocity("enabled = true"), "d.toml").unwrap();
    assert_eq!(l.derived.biss.velocity_bits, 0);
    // On: the word has the estimator's width in BiSS, SSI and SPI.
    let text = DEFAULT_CONFIG
        .replace(
            "[ssi]\n# SSI slave on ssi_clk/ssi_data, sending the BiSS data word (binary or Gray).\nenabled = false",
            "[ssi]\nenabled = true",
        )
        .replace(
            "enc_miso: the BiSS data word, then E and W.\nenabled = false",
            "enc_miso: the BiSS data word, then E and W.\nenabled = true",
        );
    let on = format!("{text}\n[velocity]\nenabled = true\nwidth = 34\nin_frames = true\n");
    let l = Loaded::parse(&on, "d.toml").unwrap();
    let d = &l.derived;
    assert_eq!(d.biss.velocity_bits, 34);
    assert_eq!(d.ssi.as_ref().expect("ssi").velocity_bits, 34);
    assert_eq!(d.spi.as_ref().expect("spi").velocity_bits, 34);
    // The BiSS frame: Start, CDS, N + V, nE, nW, 6 CRC, Ack and the timeout pulse.
    assert_eq!(d.biss.frame_rising_edges(), 12 + 1 + 27 + 34);
    // in_frames without the estimator.
    common::assert_config_error(
        &with_velocity("in_frames = true"),
        "in_frames = true",
        &["velocity.in_frames", "enabled = true"],
    );
    // The frame's data part beyond 64 bits: 27 position bits + 40 velocity bits.
    common::assert_config_error(
        &with_velocity("enabled = true\nwidth = 40\nin_frames = true"),
        "in_frames = true",
        &[
            "velocity.in_frames",
            "27 position bits + 40 velocity bits = 67",
            "64",
        ],
    );
}
