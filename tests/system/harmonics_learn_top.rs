//! `<name>_top` learning its harmonic table online (`[harmonics] enabled`, `mode = "learn"`
//! from a zero table; docs/correction.md, "Learning the table online") in the closed loop
//! on the compiled engine (encoder model -> LTC1407A-1 model -> the top -> BiSS master),
//! at 100 MHz (a learned table is built up to 119 MHz, docs/timing.md), with the issue's
//! imperfections: 2 % third + 1 % fifth harmonic, offsets of 3 % of full scale, 4 % gain
//! mismatch, 3 degrees of phase, `[correction] mode = "auto"`. After the learning the max
//! error is within 1.5 x the clean run's max + 2 LSB at 300, 3000 and 10,000 rpm in both
//! directions; the same runs with `[harmonics]` off keep the distortion's 300 LSB (so the
//! test can fail). And the learning top replayed in rust-hdl, Icarus, Verilator and the
//! engine bit for bit over two learning windows.
use crate::common;
use sinedec::blocks::harmonics::block::{learned_case, with_clock, LEARNED_CLOCK_TOML};
use sinedec::blocks::harmonics::sequencer::LearnParams;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::dut::EngineKind;
use sinedec::sim::encoder::Profile;
use sinedec::simulate::{run, SimOptions};

/// Seconds of learning before the statistics start: the ellipse fit's first 10 ms and the
/// learner's windows from a zero table (docs/correction.md gives the count).
const LEARN_S: f64 = 90e-3;

/// The top with a 16-point table learned over windows of 256 samples, replayed for long
/// enough to hold the Clear and two whole windows with their solves and Applies (derived
/// from the learner's clocks), so that the replay covers table writes and bank flips.
#[test]
fn the_learning_top_replays_in_icarus_and_verilator_over_two_windows() {
    let l = Loaded::parse(
        &format!(
            "{}points = 16\nwindow = 256\n",
            learned_case(DEFAULT_CONFIG)
        ),
        "learn16.toml",
    )
    .expect("config");
    let d = &l.derived;
    let lp: LearnParams = d
        .harmonics
        .as_ref()
        .and_then(|h| h.learn)
        .expect("a learned table");
    let spacing = (d.clock_hz / d.sample_rate_hz).ceil() as usize;
    // The ADC's first sample, the Clear, two windows of samples and their solves.
    let cycles =
        2000 + lp.clear_clocks() as usize + 2 * (256 * spacing + lp.solve_clocks() as usize);
    let r = common::replay_top_in_simulators(&l, 3000.0, cycles, "harmonics_learn_replay");
    assert!(r.records.len() > 2 * 256, "{} samples", r.records.len());
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
fn the_top_learns_the_table_from_a_cold_start_at_three_speeds_both_ways() {
    // All three at the learned top's clock (100 MHz: a learned table is built up to 119).
    let auto = DEFAULT_CONFIG.replace("mode = \"static\"", "mode = \"auto\"");
    let off = Loaded::parse(&with_clock(&auto, LEARNED_CLOCK_TOML), "auto.toml").expect("auto");
    let on = Loaded::parse(
        &format!("{}points = 128\n", learned_case(&auto)),
        "learn.toml",
    )
    .expect("learn");
    assert_eq!(off.derived.clock_hz, 100e6);
    let settle = 10e-3;
    let full = |rpm: f64, duration_s: f64, settle_s: f64| SimOptions {
        offset: (0.03 / 0.8, -0.03 / 0.8),
        gain_mismatch: 0.04,
        phase_error_deg: 3.0,
        duration_s,
        settle_s,
        ..opts(rpm, 0.02, 0.01)
    };
    eprintln!("| rpm | clean auto max | [harmonics] off max | learned max | bound |");
    eprintln!("|---|---|---|---|---|");
    let mut fails = Vec::new();
    for rpm in [300.0, 3000.0, 10000.0, -300.0, -3000.0, -10000.0] {
        let clean = run(
            &off,
            &SimOptions {
                duration_s: 20e-3,
                settle_s: settle,
                ..opts(rpm, 0.0, 0.0)
            },
            |_, _| {},
        )
        .expect("clean")
        .stats;
        let bare = run(&off, &full(rpm, 20e-3, settle), |_, _| {})
            .expect("harmonics off")
            .stats;
        let learned = run(&on, &full(rpm, LEARN_S + 10e-3, LEARN_S), |_, _| {})
            .expect("learning")
            .stats;
        let bound = 1.5 * clean.max_lsb + 2.0;
        eprintln!(
            "| {rpm} | {:.2} | {:.2} | {:.2} | {bound:.2} |",
            clean.max_lsb, bare.max_lsb, learned.max_lsb
        );
        assert!(
            bare.max_lsb > 250.0,
            "{rpm} rpm with [harmonics] off: {}",
            bare.max_lsb
        );
        if learned.max_lsb > bound || learned.errors > 0 || learned.warnings > 0 {
            fails.push(format!("{rpm} rpm: {:?}, bound {bound:.2}", learned));
        }
    }
    assert!(fails.is_empty(), "{fails:#?}");
}
