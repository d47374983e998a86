//! `<name>_top` with `[harmonics]` in the closed loop (encoder model -> LTC1407A-1 model ->
//! the top -> BiSS master): replayed in Icarus and Verilator bit for bit, and a static table
//! computed from the encoder's distortion (docs/correction.md, "Harmonic distortion")
//! bringing a 2 % third + 1 % fifth harmonic within 1.5 x the clean run's max + 2 LSB at
//! 300, 3000 and 10,000 rpm in both directions; the same run without the table keeps the
//! distortion's 300 LSB.
use crate::common;
use sinedec::blocks::harmonics::block::HELD_CASE;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::dut::EngineKind;
use sinedec::sim::encoder::Profile;
use sinedec::simulate::{run, SimOptions};
use std::f64::consts::{PI, TAU};

#[test]
fn the_top_with_a_table_replays_in_icarus_and_verilator() {
    let l = Loaded::parse(&format!("{DEFAULT_CONFIG}\n{HELD_CASE}"), "h.toml").expect("config");
    let r = common::replay_top_in_simulators(&l, 3000.0, 8000, "harmonics_top_replay");
    assert!(r.records.len() > 40, "{} samples", r.records.len());
}

/// The angle error of the encoder model's tracks with harmonics h3, h5 (phases 0): the
/// vector is e^(ix) (1 - h3 e^(-4ix) + h5 e^(4ix)) (sim/encoder.rs).
fn distortion(h3: f64, h5: f64, x: f64) -> f64 {
    let re = 1.0 - h3 * (4.0 * x).cos() + h5 * (4.0 * x).cos();
    let im = h3 * (4.0 * x).sin() + h5 * (4.0 * x).sin();
    im.atan2(re)
}

/// The table of `n` corrections (position LSB) against the decoded angle m: the error
/// e(x) of the angle x the encoder is at when the decoder reads m = x + pi + e(x) (the
/// kit's inverting pre-amplifier turns the vector by two quadrants).
fn table(h3: f64, h5: f64, n: usize, fine_bits: u32) -> String {
    let lsb = (1u64 << fine_bits) as f64 / (PI / 2.0);
    let entries: Vec<String> = (0..n)
        .map(|i| {
            let m = TAU * i as f64 / n as f64 - PI;
            let mut x = m;
            for _ in 0..50 {
                x = m - distortion(h3, h5, x);
            }
            format!("{:.3}", distortion(h3, h5, x) * lsb)
        })
        .collect();
    format!(
        "[harmonics]\nenabled = true\nmode = \"static\"\npoints = {n}\ntable = [{}]\n",
        entries.join(", ")
    )
}

fn opts(rpm: f64, h3: f64, h5: f64) -> SimOptions {
    SimOptions {
        profile: Profile::Constant { rpm },
        duration_s: 3e-3,
        noise_lsb: 1.0,
        third_harmonic: h3,
        fifth_harmonic: h5,
        seed: 5,
        keep_records: false,
        engine: EngineKind::Compiled,
        ..Default::default()
    }
}

#[test]
fn a_static_table_removes_the_distortion_at_three_speeds_both_ways() {
    let (h3, h5) = (0.02, 0.01);
    let off = Loaded::default_config().expect("default");
    let f = off.derived.fine_bits;
    let on = Loaded::parse(
        &format!("{DEFAULT_CONFIG}\n{}", table(h3, h5, 128, f)),
        "h.toml",
    )
    .expect("config");
    eprintln!("| rpm | clean max | distorted, no table | distorted, 128-point table | bound |");
    eprintln!("|---|---|---|---|---|");
    let mut fails = Vec::new();
    for rpm in [300.0, 3000.0, 10000.0, -300.0, -3000.0, -10000.0] {
        let clean = run(&off, &opts(rpm, 0.0, 0.0), |_, _| {})
            .expect("clean")
            .stats;
        let bare = run(&off, &opts(rpm, h3, h5), |_, _| {})
            .expect("bare")
            .stats;
        let fixed = run(&on, &opts(rpm, h3, h5), |_, _| {})
            .expect("table")
            .stats;
        let bound = 1.5 * clean.max_lsb + 2.0;
        eprintln!(
            "| {rpm} | {:.2} | {:.2} | {:.2} | {bound:.2} |",
            clean.max_lsb, bare.max_lsb, fixed.max_lsb
        );
        // The run without the table shows the distortion (so this test can fail).
        assert!(
            bare.max_lsb > 250.0,
            "{rpm} rpm without a table: {}",
            bare.max_lsb
        );
        if fixed.max_lsb > bound || fixed.errors > 0 || fixed.warnings > 0 {
            fails.push(format!("{rpm} rpm: {:?}, bound {bound:.2}", fixed));
        }
    }
    assert!(fails.is_empty(), "{fails:#?}");
}
