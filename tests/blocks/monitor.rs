//! Signal monitor: rust-hdl == model cycle for cycle, rust-hdl == Icarus == Verilator, and
//! the stated rules: an amplitude drop to 10% raises `error` exactly at the end of the
//! N-sample window and it clears N good samples after the signal returns; a full-scale
//! raw sample or a clipping magnitude raises it at once; warnings pass through.
use sinedec::blocks::monitor::hdl::Monitor;
use sinedec::blocks::monitor::model::{MonitorIn, MonitorModel};
use sinedec::blocks::monitor::MonitorParams;
use sinedec::cosim::stimulus::SplitMix64;

use crate::common;
use sinedec::synth::{synthesize, Family, SynthStats};
use sinedec::verify::Simulators;

const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

use common::check_against_model as check;

fn run(p: &MonitorParams, tag: &str, ins: &[MonitorIn], sims: Simulators) -> Vec<Vec<u64>> {
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = MonitorModel::new(p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row()).collect();
    check(Monitor::new(p), tag, &rows, &model, sims)
}

/// A = 14, magnitude in W = 18 bits; nominal magnitude M = 10000: low below 25%, good from
/// 30%, clipping above 120%; window N, hold H.
fn params(n: u32, h: u32) -> MonitorParams {
    MonitorParams::new(14, 18, 2500, 3000, n, 12000, h).unwrap()
}

/// A rotating sample of amplitude `amp` (fraction of 8191) with its magnitude (scaled so
/// that amp = 1 gives 10000), one sample every `gap` clocks.
fn signal(amps: &[f64], gap: usize, seed: u64) -> (Vec<MonitorIn>, Vec<usize>) {
    let mut r = SplitMix64(seed);
    let mut ins = vec![
        MonitorIn {
            rst: true,
            ..MonitorIn::default()
        };
        2
    ];
    let mut sample_rows = Vec::new();
    for (k, &amp) in amps.iter().enumerate() {
        for _ in 1..gap {
            ins.push(MonitorIn::default());
        }
        let th = 0.05 * k as f64;
        let n = (r.unit() - 0.5) * 0.002;
        sample_rows.push(ins.len());
        ins.push(MonitorIn {
            rst: false,
            in_valid: true,
            sin: (8000.0 * amp * th.sin()).round() as i32,
            cos: (8000.0 * amp * th.cos()).round() as i32,
            mag_valid: true,
            magnitude: (10000.0 * (amp + n)).round() as u64,
            overspeed: false,
            qep_mismatch: false,
            thresholds: [0; 3],
        });
    }
    (ins, sample_rows)
}

#[test]
fn amplitude_drop_to_ten_percent_raises_error_at_the_window_end_and_clears() {
    for (n, gap) in [(8u32, 3usize), (1, 1), (32, 2)] {
        let p = params(n, 4);
        // 100 samples at full amplitude, 100 at 10%, 100 at full amplitude again.
        let mut amps = vec![1.0; 100];
        amps.extend(vec![0.1; 100]);
        amps.extend(vec![1.0; 100]);
        let (ins, at) = signal(&amps, gap, n as u64);
        let out = run(&p, "mon_drop", &ins, RUST_ONLY);
        let n = n as usize;
        let err = |k: usize| out[k][0] == 1;
        // After reset: loss of signal until N good samples (sample N-1 clears it).
        assert!(err(at[0]) || n == 1);
        assert!(!err(at[n - 1]), "N={n}: cleared by the N-th good sample");
        // Drop at sample 100: error rises exactly with sample 100 + N - 1.
        let rise = at[100 + n - 1];
        for k in at[n - 1]..rise {
            assert!(!err(k), "N={n}: no error before the window's end (row {k})");
        }
        assert!(err(rise), "N={n}: error at the window's end");
        assert_eq!(out[rise][2], 1, "it is a loss of signal");
        // Restored at sample 200: error falls exactly with sample 200 + N - 1.
        let fall = at[200 + n - 1];
        for k in rise..fall {
            assert!(
                err(k),
                "N={n}: error held while the signal is back < N samples (row {k})"
            );
        }
        for k in fall..out.len() {
            assert!(!err(k), "N={n}: error cleared (row {k})");
        }
    }
}

#[test]
fn full_scale_and_clipping_raise_error_at_once_and_clear_after_the_hold() {
    let (n, h) = (4u32, 6u32);
    let p = params(n, h);
    let (mut ins, at) = signal(&vec![1.0; 120], 2, 7);
    // Sample 30: sin at the most positive code; 60: cos at the most negative code;
    // 90: magnitude above the clipping threshold.
    ins[at[30]].sin = 8191;
    ins[at[60]].cos = -8192;
    ins[at[90]].magnitude = 12001;
    let out = run(&p, "mon_fs", &ins, RUST_ONLY);
    for (s, col) in [(30usize, 4usize), (60, 4), (90, 3)] {
        assert_eq!(out[at[s] - 1][0], 0, "no error before sample {s}");
        for j in 0..h as usize {
            let k = at[s + j];
            assert_eq!(out[k][0], 1, "error with and after sample {s} (+{j})");
            assert_eq!(out[k][col], 1);
        }
        assert_eq!(
            out[at[s + h as usize]][0],
            0,
            "cleared after {h} clean samples"
        );
    }
    // One below the codes and at the threshold: no error.
    let (mut ins, at) = signal(&vec![1.0; 40], 2, 8);
    ins[at[20]].sin = 8190;
    ins[at[21]].cos = -8191;
    ins[at[22]].magnitude = 12000;
    let out = run(&p, "mon_fs2", &ins, RUST_ONLY);
    assert!(out[at[n as usize]..].iter().all(|o| o[0] == 0));
}

#[test]
fn warnings_pass_through_one_clock_later() {
    let p = params(4, 4);
    let mut r = SplitMix64(3);
    let ins: Vec<MonitorIn> = (0..300)
        .map(|k| MonitorIn {
            rst: k < 2,
            overspeed: r.unit() < 0.3,
            qep_mismatch: r.unit() < 0.3,
            ..MonitorIn::default()
        })
        .collect();
    let out = run(&p, "mon_warn", &ins, RUST_ONLY);
    for k in 2..ins.len() {
        assert_eq!(
            out[k][1] == 1,
            ins[k].overspeed || ins[k].qep_mismatch,
            "row {k}"
        );
    }
}

/// Random stimulus: raw words of any value (junk in the upper bits), magnitudes around
/// every threshold, both strobes independent, warnings, resets.
fn random(p: &MonitorParams, n: usize, seed: u64) -> Vec<MonitorIn> {
    let mut r = SplitMix64(seed);
    let th = [p.los_threshold(), p.los_release(), p.clip_threshold()];
    let mut level = 1.0f64;
    (0..n)
        .map(|k| {
            if r.unit() < 0.01 {
                level = [0.05, 0.27, 0.5, 1.0, 1.3][r.range(0, 4) as usize];
            }
            let magnitude = if r.unit() < 0.1 {
                let t = th[r.range(0, 2) as usize] as i64;
                (t + r.range(-1, 1)) as u64
            } else if r.unit() < 0.02 {
                r.next_u64() & 0xffff_ffff
            } else {
                (10000.0 * level * (1.0 + 0.05 * (r.unit() - 0.5))) as u64
            };
            let code = |r: &mut SplitMix64| -> i32 {
                match r.range(0, 9) {
                    0 => 8191,
                    1 => -8192,
                    2 => r.next_u64() as u16 as i32,
                    _ => r.range(-8000, 8000) as i32,
                }
            };
            MonitorIn {
                rst: k < 2 || r.unit() < 0.003,
                in_valid: r.unit() < 0.4,
                sin: code(&mut r),
                cos: code(&mut r),
                mag_valid: r.unit() < 0.4,
                magnitude,
                overspeed: r.unit() < 0.05,
                qep_mismatch: r.unit() < 0.05,
                thresholds: [0; 3],
            }
        })
        .collect()
}

#[test]
fn monitor_matches_model_in_three_simulators() {
    let p = params(5, 3);
    let ins = random(&p, 6000, 11);
    let out = run(&p, "mon_cosim", &ins, Simulators::ALL);
    for col in 0..5 {
        assert!(
            out.iter().any(|o| o[col] == 1),
            "output {col} was exercised"
        );
    }
    // Other widths (window 1, 32-bit magnitude, A = 10 and 16) and the short windows and
    // holds (N = 2, 3; H = 1, 2: the corner cases of the pending counter steps) in rust-hdl
    // vs the model.
    for (tag, p) in [
        ("mon_n2", params(2, 2)),
        ("mon_n3", params(3, 1)),
        (
            "mon_a10",
            MonitorParams::new(10, 32, 100, 100, 1, 4_000_000_000, 1).unwrap(),
        ),
        (
            "mon_a16",
            MonitorParams::new(16, 12, 500, 900, 300, 4000, 70).unwrap(),
        ),
    ] {
        let ins = random(&p, 4000, 12);
        run(&p, tag, &ins, RUST_ONLY);
    }
}

#[test]
fn bad_parameters_are_rejected_with_a_message() {
    let ok = MonitorParams::new(14, 18, 2500, 3000, 8, 12000, 4);
    assert!(ok.is_ok());
    assert!(MonitorParams::new(9, 18, 2500, 3000, 8, 12000, 4)
        .unwrap_err()
        .to_string()
        .contains("ADC width"));
    assert!(MonitorParams::new(14, 33, 2500, 3000, 8, 12000, 4).is_err());
    assert!(MonitorParams::new(14, 18, 0, 3000, 8, 12000, 4).is_err());
    assert!(MonitorParams::new(14, 18, 2500, 2000, 8, 12000, 4)
        .unwrap_err()
        .to_string()
        .contains("release"));
    assert!(MonitorParams::new(14, 18, 2500, 3000, 8, 2900, 4)
        .unwrap_err()
        .to_string()
        .contains("clipping"));
    assert!(MonitorParams::new(14, 12, 2500, 3000, 8, 4095, 4).is_err());
    assert!(MonitorParams::new(14, 18, 2500, 3000, 0, 12000, 4)
        .unwrap_err()
        .to_string()
        .contains("window"));
    assert!(MonitorParams::new(14, 18, 2500, 3000, 8, 12000, 70000)
        .unwrap_err()
        .to_string()
        .contains("hold"));
}

/// Exports `uut` and synthesizes it with Yosys for xc3sa and cycloneive under the project's
/// rules (no latch, no undriven net, no unexpected warning); returns both statistics.
fn synth<B: rust_hdl::prelude::Block>(mut uut: B, name: &str) -> (SynthStats, SynthStats) {
    uut.connect_all();
    let v = sinedec::emit::verilog::export(&uut, name, name).expect("export");
    let dir = common::workdir(name);
    let x = synthesize(&v, name, Family::Xc3sa, &dir).expect("xc3sa synthesis");
    let c = synthesize(&v, name, Family::CycloneIve, &dir).expect("cycloneive synthesis");
    eprintln!(
        "{name}: xc3sa {} LUT, {} FF, {} MULT18X18; cycloneive {} LE, {} FF",
        x.luts, x.ffs, x.multipliers, c.luts, c.ffs
    );
    (x, c)
}

#[test]
fn synthesizes_for_both_families() {
    let (x, c) = synth(Monitor::new(&params(8, 4)), "mon_synth");
    // Flags (los, clip, full scale as sine, cosine and hold), warning, counters of 3, 2 and
    // 2 bits, and for timing: the registered counter flags (los window end and N-2, clip
    // and full-scale hold) and the pending-step registers of the los and full-scale
    // counters (src/blocks/monitor/hdl.rs): 20.
    assert!(x.ffs >= 15 && x.ffs <= 21, "{} FF", x.ffs);
    assert_eq!(c.ffs, x.ffs);
    assert_eq!(x.multipliers, 0);
}

/// Run-time thresholds (`[registers]`: the map's LOS_THRESHOLD, LOS_RELEASE and
/// CLIP_THRESHOLD on ports): at a steady magnitude of 10000, raising the loss-of-signal
/// threshold to 10001 sets `los` on the N-th sample after it and lowering it again clears
/// it N good samples later; a clipping threshold of 9999 clips at once. Then random
/// traffic with the thresholds changing: rust-hdl == model == Icarus == Verilator == engine.
#[test]
fn run_time_thresholds_act_at_once_and_match_four_ways() {
    let n = 4;
    let p = params(n, 3).with_run_time_thresholds();
    let cfg = [2500, 3000, 12000];
    // Sample k every 2 clocks; the thresholds change at samples 20 (LOS up), 40 (back),
    // 60 (clip down), 70 (back).
    let set = |k: usize| match k {
        20..=39 => [10001, 10001, 12000],
        60..=69 => [2500, 3000, 9999],
        _ => cfg,
    };
    let mut ins = vec![
        MonitorIn {
            rst: true,
            thresholds: cfg,
            ..MonitorIn::default()
        };
        2
    ];
    let mut at = vec![];
    for k in 0..90 {
        ins.push(MonitorIn {
            thresholds: set(k),
            ..MonitorIn::default()
        });
        at.push(ins.len());
        ins.push(MonitorIn {
            mag_valid: true,
            magnitude: 10000,
            thresholds: set(k),
            ..MonitorIn::default()
        });
    }
    let mut m = MonitorModel::new(&p);
    let outs: Vec<_> = ins.iter().map(|i| m.step(*i)).collect();
    let los = |k: usize| outs[at[k]].los;
    let clip = |k: usize| outs[at[k]].clip;
    // After reset los = 1 until N good samples.
    assert!(los(n as usize - 2) && !los(n as usize - 1));
    assert!(
        !los(20 + n as usize - 2) && los(20 + n as usize - 1),
        "set on the N-th low"
    );
    assert!(
        los(40 + n as usize - 2) && !los(40 + n as usize - 1),
        "clear on the N-th good"
    );
    assert!(!clip(59) && clip(60), "clips at the first sample over 9999");
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row_with_thresholds()).collect();
    let model: Vec<Vec<u64>> = outs.iter().map(|o| o.row()).collect();
    check(
        Monitor::new(&p),
        "mon_runtime",
        &rows,
        &model,
        Simulators::ALL,
    );
    // Random traffic, the thresholds changing every 300 clocks (around the magnitudes).
    let mut r = SplitMix64(21);
    let mut ins = random(&p, 6000, 13);
    let mut t = cfg;
    for (k, i) in ins.iter_mut().enumerate() {
        if k % 300 == 0 {
            let lo = r.range(500, 12000) as u64;
            t = [
                lo,
                lo + r.range(0, 3000) as u64,
                lo + r.range(3000, 9000) as u64,
            ];
        }
        i.thresholds = t;
    }
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row_with_thresholds()).collect();
    let mut m = MonitorModel::new(&p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row()).collect();
    check(
        Monitor::new(&p),
        "mon_runtime_rand",
        &rows,
        &model,
        Simulators::ALL,
    );
}
