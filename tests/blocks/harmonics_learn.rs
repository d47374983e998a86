//! The table's online learner in integers (`sinedec::blocks::harmonics::sequencer`, the
//! sequencer the RTL will follow; docs/correction.md, "Learning the table online"): against
//! the floating-point design model on the same samples, from a zero table on the closed
//! loop's positions to the bound, the bound on a change per update, reset, and the
//! conditions (unsteady speed, zero speed, reversal).
use sinedec::blocks::harmonics::learn::{toml, Learner};
use sinedec::blocks::harmonics::sequencer::{LearnIn, LearnParams, Sequencer, State, TABLE_FRAC};
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::dut::EngineKind;
use sinedec::sim::encoder::Profile;
use sinedec::simulate::{run, SimOptions};
use std::f64::consts::PI;

/// F of the default config.
const F: u32 = 14;
/// A period, LSB.
const PERIOD: i64 = 1 << (F + 2);
/// Clocks per sample of the default config (133.33 MHz / 1.307 Msps).
const CLOCKS: u32 = 102;
/// The design's step, LSB.
const STEP_LSB: u32 = 32;

fn params() -> LearnParams {
    LearnParams::new(F, 128, 4096, STEP_LSB).expect("the design's learner")
}

/// The angle error (rad) of 1 - h3 e^(-4ix) + h5 e^(4ix) at x (the encoder model's).
fn distortion(h3: f64, h5: f64, x: f64) -> f64 {
    let re = 1.0 - h3 * (4.0 * x).cos() + h5 * (4.0 * x).cos();
    let im = h3 * (4.0 * x).sin() + h5 * (4.0 * x).sin();
    im.atan2(re)
}

/// A synthetic decoded stream: the true position x0 + v j + a j^2 / 2 (LSB) plus the
/// distortion and uniform noise of +-`noise` LSB, rounded to the LSB.
struct Stream {
    h3: f64,
    h5: f64,
    noise: f64,
    seed: u64,
}

impl Stream {
    fn positions(&mut self, x0: f64, v: f64, acc: f64, n: usize) -> Vec<i64> {
        let lsb = (1u64 << F) as f64 / (PI / 2.0);
        (0..n)
            .map(|j| {
                let j = j as f64;
                let x = x0 + v * j + acc * j * j / 2.0;
                self.seed ^= self.seed << 13;
                self.seed ^= self.seed >> 7;
                self.seed ^= self.seed << 17;
                let u = (self.seed >> 11) as f64 / (1u64 << 53) as f64;
                let e = distortion(self.h3, self.h5, x / lsb) * lsb;
                (x + e + self.noise * (2.0 * u - 1.0)).round() as i64
            })
            .collect()
    }
}

/// Feeds `raw` (one sample every [`CLOCKS`] clocks) to the integer learner and the samples
/// it collects to the float model; after every window the two tables must agree within
/// `tol` LSB. Returns the largest difference seen.
fn follow(seq: &mut Sequencer, fl: &mut Learner, raw: &[i64]) -> f64 {
    let mut worst: f64 = 0.0;
    let mut compared = 0;
    for &p in raw {
        let taken = seq.takes_sample();
        let before = seq.windows;
        for c in 0..CLOCKS {
            let strobe = c == 0;
            seq.step(LearnIn {
                strobe,
                angle: p.rem_euclid(PERIOD) as u32,
                update: true,
                ..LearnIn::default()
            });
        }
        if taken {
            fl.sample(p as f64);
        }
        assert!(seq.windows <= before + 1);
        if seq.windows > before {
            assert_eq!(seq.windows as usize, fl.windows, "windows");
            // A constant in the table is a constant in the position, which neither model
            // observes (the residuals lose their mean) and whose roundings walk it apart:
            // compared without it.
            let mean = |t: &[f64]| t.iter().sum::<f64>() / t.len() as f64;
            let ti = seq.table_lsb();
            let (mi, mf) = (mean(&ti), mean(&fl.table));
            let d = ti
                .iter()
                .zip(&fl.table)
                .map(|(a, b)| (a - mi - (b - mf)).abs())
                .fold(0.0, f64::max);
            worst = worst.max(d);
            compared += 1;
            assert!(
                d <= tol_lsb(seq.windows),
                "window {}: the tables differ by {d:.3} LSB",
                seq.windows
            );
        }
    }
    assert!(compared >= 5, "{compared} windows compared");
    worst
}

/// The tolerance derived in the sequencer's module doc: delta = 2.3 q units per window, the
/// windows' deltas added without credit for the update's contraction.
fn tol_lsb(windows: u64) -> f64 {
    windows as f64 * 2.3 / f64::from(1u32 << TABLE_FRAC)
}

#[test]
fn the_integer_learner_follows_the_float_model() {
    for (v, h3, h5) in [
        (512.0, 0.02, 0.01),
        (733.7, 0.02, 0.01),
        (-3000.0, 0.02, 0.01),
        (17_000.0, 0.03, 0.0),
        (-9000.0, 0.0, 0.02),
    ] {
        let mut s = Stream {
            h3,
            h5,
            noise: 1.0,
            seed: 0x9e37_79b9_7f4a_7c15,
        };
        let raw = s.positions(12345.0, v, 0.0, 30 * 4096);
        let mut seq = Sequencer::new(params());
        let mut fl = Learner::new(128, 4096, 0.5, f64::from(STEP_LSB), F);
        let worst = follow(&mut seq, &mut fl, &raw);
        eprintln!(
            "{v} LSB/sample: {} windows, largest difference {worst:.3} LSB, last change {:.3} LSB",
            seq.windows,
            seq.last_change as f64 / f64::from(1u32 << TABLE_FRAC)
        );
        assert!(seq.windows >= 29, "{} windows", seq.windows);
    }
}

/// The solve's clocks, counted by hand from the formats in docs/correction.md (F = 14, p =
/// 7, w = 12, T = 8): Line 12 + 44 quotient bits (|U| < 2^60, D > 2^22: floor(2^6 |U| / D)
/// < 2^44), Residual 23 product bits + 1 + 21 quotient bits + 14 per bin, Mean 21 + 5,
/// Update 7 per bin, Apply 1 (each two-clock 64-bit sum, src/blocks/splitadd.rs, counted
/// in the states it settles in); a sample's Collect 11 + s = 20 clocks, 22 with a load's
/// two writes.
#[test]
fn the_solve_takes_the_documented_clocks() {
    let p = params();
    assert_eq!(p.line_clocks(), 12 + 44);
    assert_eq!(p.residual_clocks(), 24 + 21 + 14);
    assert_eq!(p.mean_clocks(), 26);
    assert_eq!(p.solve_clocks(), 56 + 59 * 128 + 26 + 7 * 128 + 1);
    assert_eq!((p.collect_clocks(), p.min_sample_clocks()), (20, 22));
    assert_eq!(p.clear_clocks(), 257);
    assert_eq!(
        (p.entry_width(), p.q_width(), p.sum_p_width(), p.ps_width()),
        (20, 37, 49, 61)
    );
    assert_eq!((p.b_width(), p.a_width()), (40, 54));
    // The widest word fits the engine's 64 bits: a larger window at F = 14 is refused.
    assert!(LearnParams::new(F, 128, 8192, STEP_LSB).is_ok());
    let e = LearnParams::new(F, 128, 16384, STEP_LSB).unwrap_err();
    assert!(e.contains("64") && e.contains("8192"), "{e}");
}

#[test]
fn no_entry_moves_by_more_than_the_step_and_reset_clears() {
    // 8 % H3: residuals of 1300 LSB, so the first updates clip.
    let mut s = Stream {
        h3: 0.08,
        h5: 0.0,
        noise: 1.0,
        seed: 7,
    };
    let raw = s.positions(0.0, 2100.0, 0.0, 12 * 4096);
    let mut seq = Sequencer::new(params());
    let step = seq.params.step;
    let mut table = seq.table().to_vec();
    let mut jumps = 0;
    for &p in &raw {
        for c in 0..CLOCKS {
            let before = seq.table().to_vec();
            seq.step(LearnIn {
                strobe: c == 0,
                angle: p.rem_euclid(PERIOD) as u32,
                update: true,
                ..LearnIn::default()
            });
            if seq.table() != before.as_slice() {
                // The table changes only at Apply, and the correction at any angle by at
                // most the step.
                jumps += 1;
                let worst = (0..PERIOD as u32)
                    .step_by(37)
                    .map(|m| {
                        let new = seq.correction(m);
                        let s = F + 2 - 7;
                        let i = (m >> s) as usize % 128;
                        let j = (i + 1) % 128;
                        let f = i64::from(m & ((1 << s) - 1));
                        let old = ((before[i] << s) + (before[j] - before[i]) * f) >> s;
                        (new - old).abs()
                    })
                    .max()
                    .unwrap_or(0);
                assert!(worst <= step, "the correction moved by {worst} > {step}");
            }
        }
        table = seq.table().to_vec();
    }
    assert!(jumps >= 10, "{jumps} updates");
    assert_eq!(seq.max_change, step, "the first updates clip at the step");
    assert!(table.iter().any(|&c| c != 0));
    seq.step(LearnIn {
        rst: true,
        ..LearnIn::default()
    });
    assert_eq!(seq.state, State::Clear);
    assert_eq!((seq.windows, seq.max_change), (0, 0));
    // Clear writes the start table back into both banks, one entry a clock, then Collect.
    for _ in 0..seq.params.clear_clocks() {
        assert_eq!(seq.state, State::Clear);
        seq.step(LearnIn::default());
    }
    assert!(seq.table().iter().all(|&c| c == 0));
    assert_eq!(seq.state, State::Wait);
}

/// Runs `raw` through a fresh learner; returns it.
fn learn(raw: &[i64]) -> Sequencer {
    let mut seq = Sequencer::new(params());
    for &p in raw {
        for c in 0..CLOCKS {
            seq.step(LearnIn {
                strobe: c == 0,
                angle: p.rem_euclid(PERIOD) as u32,
                update: true,
                ..LearnIn::default()
            });
        }
    }
    seq
}

#[test]
fn zero_speed_and_less_than_a_period_per_window_do_not_update() {
    // At rest on the boundary of bins 4 and 5 (4.5 x 512 LSB) with noise: the two bins'
    // residuals differ by the noise's split.
    let mut rest = Stream {
        h3: 0.0,
        h5: 0.0,
        noise: 1.0,
        seed: 11,
    };
    let mut s = Stream {
        h3: 0.02,
        h5: 0.01,
        noise: 1.0,
        seed: 11,
    };
    let mut streams = vec![rest.positions(2304.0, 0.0, 0.0, 6 * 4096)];
    // 0.9 periods per window both ways.
    for v in [0.9, -0.9] {
        streams.push(s.positions(0.0, v * PERIOD as f64 / 4096.0, 0.0, 6 * 4096));
    }
    for (v, raw) in streams.iter().enumerate() {
        let seq = learn(raw);
        assert!(seq.windows >= 5, "{v}: {} windows", seq.windows);
        assert!(
            seq.table().iter().all(|&c| c == 0),
            "stream {v} updated the table: {:?}",
            seq.table()
        );
    }
    // 1.2 periods per window does update.
    let seq = learn(&s.positions(0.0, 1.2 * PERIOD as f64 / 4096.0, 0.0, 6 * 4096));
    assert!(seq.table().iter().any(|&c| c != 0));
}

#[test]
fn an_unsteady_speed_updates_within_the_step() {
    let step = params().step;
    let mut s = Stream {
        h3: 0.02,
        h5: 0.01,
        noise: 1.0,
        seed: 3,
    };
    // From 300 to 10,000 rpm in 20 ms (a = 0.63 LSB per sample^2: the window's line bends
    // by a N^2 / 8 = 1.3e6 LSB, far outside the condition of 1 LSB).
    let n = 26_000;
    let (v0, v1) = (512.0, 17_000.0);
    let acc = (v1 - v0) / n as f64;
    let seq = learn(&s.positions(0.0, v0, acc, n));
    assert!(seq.windows >= 5, "{} windows", seq.windows);
    assert!(seq.max_change <= step, "{} > {step}", seq.max_change);
    // The bent line's residuals are far beyond the step, so the updates clip there.
    assert_eq!(seq.max_change, step);
}

#[test]
fn a_reversal_updates_within_the_step_and_learns_the_other_way() {
    let mut s = Stream {
        h3: 0.02,
        h5: 0.01,
        noise: 1.0,
        seed: 5,
    };
    let fwd = s.positions(0.0, 3000.0, 0.0, 4 * 4096 + 1000);
    let end = *fwd.last().expect("samples") as f64;
    // Reverse within a window: 3000 to -3000 LSB per sample in 2000 samples, then steady.
    let mut raw = fwd;
    let turn = s.positions(end, 3000.0, -3.0, 2000);
    let end = *turn.last().expect("samples") as f64;
    raw.extend(turn);
    raw.extend(s.positions(end, -3000.0, 0.0, 26 * 4096));
    // The turn's window bends the line far beyond the residuals' saturation, so the two
    // models differ there (the float one does not saturate): bound and convergence only.
    let seq = learn(&raw);
    assert!(seq.windows >= 30, "{} windows", seq.windows);
    assert!(seq.max_change <= seq.params.step);
    assert_eq!(seq.max_change, seq.params.step, "the turn's window clips");
    // Learning the other way: the last update is out of the clip (a quarter of the step).
    assert!(
        seq.last_change <= seq.params.step / 4,
        "{}",
        seq.last_change
    );
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

/// The integer learner, clock by clock, from a zero table on the positions of the closed
/// loop with the imperfections (2 % H3 + 1 % H5, offsets 3 % of full scale, 4 % gain
/// mismatch, 3 degrees, `mode = "auto"`), after the fit's 10 ms: its 128-point table, loaded
/// as a static table, must bring the max error within 1.5 x the clean auto run's max + 2 LSB
/// at 300, 3000 and 10,000 rpm both ways. The same learner with its update off leaves a
/// zero table and the distortion's 300 LSB (so the test can fail).
#[test]
fn the_learned_table_meets_the_bound_at_three_speeds_both_ways() {
    let auto = DEFAULT_CONFIG.replace("mode = \"static\"", "mode = \"auto\"");
    let off = Loaded::parse(&auto, "auto.toml").expect("auto");
    assert_eq!(off.derived.fine_bits, F);
    let settle = 10e-3;
    let full = |rpm: f64, duration_s: f64, keep: bool| SimOptions {
        offset: (0.03 / 0.8, -0.03 / 0.8),
        gain_mismatch: 0.04,
        phase_error_deg: 3.0,
        duration_s,
        settle_s: settle,
        keep_records: keep,
        ..opts(rpm, 0.02, 0.01)
    };
    eprintln!("| rpm | clean auto max | windows (ms) | last change | learned table max | update off max | bound |");
    eprintln!("|---|---|---|---|---|---|---|");
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
        let rec = run(&off, &full(rpm, 80e-3, true), |_, _| {}).expect("learning run");
        let first = (settle * off.derived.clock_hz) as u64;
        let recs: Vec<_> = rec
            .result
            .records
            .iter()
            .filter(|r| r.cycle >= first)
            .collect();
        let mut tables = Vec::new();
        let mut changes = (0, 0);
        for update in [true, false] {
            let mut seq = Sequencer::new(params());
            let mut prev = recs[0];
            for r in &recs {
                // The clocks between two samples, then the sample's.
                for _ in prev.cycle..r.cycle.saturating_sub(1) {
                    seq.step(LearnIn {
                        update,
                        ..LearnIn::default()
                    });
                }
                seq.step(LearnIn {
                    strobe: true,
                    angle: r.unwrapped.rem_euclid(PERIOD) as u32,
                    update,
                    ..LearnIn::default()
                });
                prev = r;
            }
            assert!(seq.max_change <= seq.params.step, "{}", seq.max_change);
            if update {
                changes = (seq.windows, seq.last_change);
            }
            tables.push(seq.table_lsb());
        }
        let mut maxes = Vec::new();
        for t in &tables {
            let on = Loaded::parse(&format!("{auto}\n{}", toml(t)), "learned.toml")
                .expect("learned table loads");
            let s = run(&on, &full(rpm, 20e-3, false), |_, _| {})
                .expect("with the table")
                .stats;
            maxes.push(s);
        }
        let bound = 1.5 * clean.max_lsb + 2.0;
        eprintln!(
            "| {rpm} | {:.2} | {} ({:.1}) | {:.3} | {:.2} | {:.2} | {bound:.2} |",
            clean.max_lsb,
            changes.0,
            changes.0 as f64
                * (4096.0 / off.derived.sample_rate_hz
                    + f64::from(params().solve_clocks()) / off.derived.clock_hz)
                * 1e3,
            changes.1 as f64 / f64::from(1u32 << TABLE_FRAC),
            maxes[0].max_lsb,
            maxes[1].max_lsb,
        );
        assert!(tables[1].iter().all(|&c| c == 0.0));
        assert!(maxes[1].max_lsb > 250.0, "{rpm}: {}", maxes[1].max_lsb);
        if maxes[0].max_lsb > bound || maxes[0].errors > 0 || maxes[0].warnings > 0 {
            fails.push(format!("{rpm} rpm: {:?}, bound {bound:.2}", maxes[0]));
        }
    }
    assert!(fails.is_empty(), "{fails:#?}");
}
