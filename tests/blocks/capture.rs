//! Capture block: rust-hdl == model cycle for cycle, rust-hdl == Icarus == Verilator ==
//! engine, and its behaviour against expectations written from the spec (the age from the
//! sampling CONV to the capture, the held sample, the extrapolation within 3/4 LSB of
//! velocity x (age + 1/2), its wrap into the turns, a capture while one runs being ignored).
use crate::common;
use sinedec::blocks::capture::hdl::Capture;
use sinedec::blocks::capture::model::{CaptureIn, CaptureModel, CaptureOut};
use sinedec::blocks::capture::{CaptureParams, AGE_BITS};
use sinedec::blocks::mask;
use sinedec::blocks::velocity::{Method, VelocityParams, VelocitySpec};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::synth::{synthesize, Family};
use sinedec::verify::{block_traces, Simulators};

const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

/// L = 220 clocks from CONV to the position, P = 102 per conversion.
const L: u32 = 220;
const P: u32 = 102;
/// Q = 8192 (PPR 2048), F = 10, M = 12.
const Q: u64 = 8192;
const F: u32 = 10;
const M: u32 = 12;

/// A velocity estimator at 100 MHz, 7500 Hz (D = 13333 clocks), S = 8, for 1.75 quadrants
/// per sample at most.
fn velocity() -> VelocityParams {
    let max_step = (1.75 * (1u64 << F) as f64 * (13333.0 / P as f64)).ceil() as u64;
    let mut spec = VelocitySpec::defaults(100e6, F, max_step);
    spec.method = Method::Lsq;
    VelocityParams::new(&spec).expect("velocity")
}

fn params(extrapolate: bool) -> CaptureParams {
    CaptureParams::new(L, P, Q, F, M, Some(&velocity()), extrapolate).expect("params")
}

/// Runs the block on `ins` in the chosen simulators; asserts rust-hdl == model row by row
/// and the Verilog simulators == rust-hdl; returns the model's outputs.
fn run(p: &CaptureParams, ins: &[CaptureIn], tag: &str, sims: Simulators) -> Vec<CaptureOut> {
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = CaptureModel::new(p);
    let model: Vec<CaptureOut> = ins.iter().map(|i| m.step(*i)).collect();
    let dir = common::workdir(tag);
    let t = block_traces(Capture::new(p), tag, "clk", &rows, sims, &dir).expect("simulators ran");
    for (k, (r, m)) in t.rust_hdl.iter().zip(&model).enumerate() {
        assert_eq!(
            r,
            &m.row(),
            "{tag} row {k}: rust-hdl vs model (inputs {:?})",
            rows[k]
        );
    }
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    model
}

/// A decoder's samples: `in_valid` in clock 300 + P k with quadrant count `start + k`
/// (wrapping into the turns), fine part 7 k mod 2^F; the velocity `vel` (raw, S = 8) held
/// throughout; `capture` high in rows [x, x + 4] for each x of `pins`.
fn stimulus(clocks: usize, start: i64, vel: i64, pins: &[usize]) -> Vec<CaptureIn> {
    (0..clocks)
        .map(|c| {
            let k = (c as i64 - 300) / P as i64;
            let valid = c >= 300 && (c - 300) % P as usize == 0;
            let qf = start + k;
            CaptureIn {
                rst: c < 2,
                capture: pins.iter().any(|&x| c >= x && c < x + 5),
                valid,
                qc: if valid {
                    qf.rem_euclid(Q as i64) as u64
                } else {
                    0
                },
                fine: if valid { (7 * k as u64) & mask(F) } else { 0 },
                turns: if valid {
                    qf.div_euclid(Q as i64) as u64 & mask(M)
                } else {
                    0
                },
                velocity: vel as u64 & mask(32),
            }
        })
        .collect()
}

/// The latest `in_valid` clock at or before `c` (the held sample in clock `c + 1`).
fn held_before(ins: &[CaptureIn], c: usize) -> usize {
    (0..=c).rev().find(|&k| ins[k].valid).expect("a sample")
}

#[test]
fn the_age_counts_from_the_sampling_conv_to_the_pin() {
    let p = params(false);
    // Pins at every phase of a period; one whose latch sees a sample of the clock after
    // the pin (4889: sample 4890, held from 4891), one of two clocks after (4991: 4992), and
    // one whose latch does not yet see the next (5092: sample 5094).
    let pins: Vec<usize> = (0..12)
        .map(|i| 1000 + i * 311)
        .chain([4889, 4991, 5092])
        .collect();
    let ins = stimulus(6000, 40, 256, &pins);
    let out = run(&p, &ins, "cap_age", RUST_ONLY);
    let caps: Vec<(usize, &CaptureOut)> = out.iter().enumerate().filter(|(_, o)| o.valid).collect();
    assert_eq!(caps.len(), pins.len(), "one capture per pin pulse");
    for (&x, (k, o)) in pins.iter().zip(&caps) {
        // The pin first high in row x is in the first flop after edge x, the second after
        // x + 1; the edge register latches at edge x + 2 what is held then: the samples of
        // clocks up to x + 1.
        assert_eq!(*k, x + 2, "pin {x}: out_valid after edge x + 2");
        let v = held_before(&ins, x + 1);
        // That sample's CONV began clock v - L: the age is x - (v - L).
        assert_eq!(o.age, (x + L as usize - v) as u64, "pin {x}: age");
        assert_eq!(
            (o.qc, o.fine, o.turns),
            (ins[v].qc, ins[v].fine, ins[v].turns)
        );
        assert_eq!(o.velocity, 256, "the velocity held at the capture");
        assert!(o.age >= (L - 1) as u64 && o.age <= (L + P - 2) as u64);
    }
}

#[test]
fn before_any_sample_the_age_is_saturated() {
    let p = params(false);
    let ins = stimulus(290, 0, 0, &[100]);
    let out = run(&p, &ins, "cap_sat", RUST_ONLY);
    let o = out.iter().find(|o| o.valid).expect("captured");
    assert_eq!(o.age, mask(AGE_BITS));
}

#[test]
fn extrapolation_is_velocity_times_age_within_three_quarters_of_an_lsb() {
    let p = params(true);
    let e = *p.extrapolation().expect("extrapolation");
    let v = velocity();
    let (s, d) = (v.spec.frac_bits, v.period_clocks as f64);
    let turn = (Q << F) as i64;
    // (start quadrant, raw velocity): forward and backward, slow and near the maximum
    // speed, across the turn's end forward and its start backward (the wrap).
    let vmax = v.max_output as i64 - 1;
    for (start, vel, tag) in [
        (40, 1000, "cap_x_slow"),
        (40, -1000, "cap_x_back"),
        (8180, vmax, "cap_x_wrap_up"),
        (-3, -vmax, "cap_x_wrap_down"),
        (4000, 0, "cap_x_still"),
    ] {
        let pins: Vec<usize> = (0..10).map(|i| 700 + i * 257).collect();
        let ins = stimulus(4000, start, vel, &pins);
        let out = run(&p, &ins, tag, RUST_ONLY);
        let caps: Vec<(usize, &CaptureOut)> =
            out.iter().enumerate().filter(|(_, o)| o.valid).collect();
        assert_eq!(caps.len(), pins.len(), "{tag}");
        let mut wrapped = false;
        for (&x, (k, o)) in pins.iter().zip(&caps) {
            assert_eq!(*k as u32, x as u32 + p.capture_latency() - 1, "{tag}");
            let h = held_before(&ins, x + 1);
            let age = (x + L as usize - h) as f64;
            assert_eq!(o.age as f64, age, "{tag}");
            let unwrap = |qc: u64, fine: u64, turns: u64| {
                sinedec::blocks::sext(turns, M) * turn + ((qc << F) | fine) as i64
            };
            let base = unwrap(ins[h].qc, ins[h].fine, ins[h].turns);
            let got = unwrap(o.qc, o.fine, o.turns);
            // Carried to the middle of the pin's clock: age + 1/2.
            let want = base as f64 + vel as f64 / (1u64 << s) as f64 * (age + 0.5) / d;
            assert!(
                (got as f64 - want).abs() <= 0.75,
                "{tag} pin {x}: {got} vs {want:.3} (age {age})"
            );
            assert!(o.qc < Q && o.fine < 1 << F);
            wrapped |= o.turns != ins[h].turns;
        }
        if tag.contains("wrap") {
            assert!(wrapped, "{tag}: a capture crossed the turn");
        }
        assert!(e.max_step >= 1);
    }
}

#[test]
fn an_edge_while_an_extrapolation_runs_is_ignored() {
    let p = params(true);
    // Two pulses 4 clocks apart (each 5 clocks high, so the second is a new edge only if
    // the first fell: 10 apart) and a third well after.
    let ins = stimulus(2000, 40, 500, &[700, 710, 900]);
    let out = run(&p, &ins, "cap_busy", RUST_ONLY);
    let n = out.iter().filter(|o| o.valid).count();
    assert!(
        p.busy_clocks() > 10,
        "the multiply takes longer than the gap"
    );
    assert_eq!(n, 2, "the second edge fell in the first's extrapolation");
}

#[test]
fn four_way_cosimulation() {
    // A 10-bit age (saturating at 1023) so that the sample gaps reach the saturation.
    for (extrapolate, tag, seed) in [(false, "cap_cosim_a", 5u64), (true, "cap_cosim_b", 6)] {
        let p = params(extrapolate).with_age_bits(10).expect("age bits");
        let mut r = SplitMix64(seed);
        let mut ins = vec![];
        let mut pos: i64 = 8000 << F;
        let mut vel: i64 = 0;
        let mut cap = false;
        for k in 0..6000 {
            // Samples every 50 clocks on average, none in 2000..3500 (the age saturates).
            let valid = r.unit() < 0.02 && !(2000..3500).contains(&k);
            if valid {
                pos += r.range(-3000, 3001);
            }
            if r.unit() < 0.001 {
                vel = r.range(
                    -(velocity().max_output as i64),
                    velocity().max_output as i64,
                );
            }
            if r.unit() < 0.03 {
                cap = !cap;
            }
            let qf = pos >> F;
            ins.push(CaptureIn {
                rst: k < 2 || r.unit() < 0.0005,
                capture: cap,
                valid,
                qc: qf.rem_euclid(Q as i64) as u64,
                fine: (pos as u64) & mask(F),
                turns: qf.div_euclid(Q as i64) as u64 & mask(M),
                velocity: vel as u64 & mask(32),
            });
        }
        let out = run(&p, &ins, tag, Simulators::ALL);
        assert!(out.iter().filter(|o| o.valid).count() > 20, "{tag}");
        assert!(
            out.iter().any(|o| o.valid && o.age == mask(10)),
            "{tag}: a capture saw the saturated age"
        );
    }
}

#[test]
fn bad_parameters_are_rejected_with_a_message() {
    let msg = |r: sinedec::error::Result<CaptureParams>| r.expect_err("rejected").to_string();
    assert!(msg(CaptureParams::new(L, P, 6, F, M, None, false)).contains("4 * PPR"));
    assert!(msg(CaptureParams::new(2, P, Q, F, M, None, false)).contains("latency"));
    assert!(msg(CaptureParams::new(L, P, Q, F, M, None, true)).contains("velocity"));
}

#[test]
fn synthesizes_for_both_families() {
    for (extrapolate, name) in [(false, "capture_synth"), (true, "capture_x_synth")] {
        let p = params(extrapolate);
        let mut uut = Capture::new(&p);
        rust_hdl::prelude::Block::connect_all(&mut uut);
        let v = sinedec::emit::verilog::export(&uut, name, name).expect("export");
        let dir = common::workdir(name);
        let x = synthesize(&v, name, Family::Xc3sa, &dir).expect("xc3sa synthesis");
        let c = synthesize(&v, name, Family::CycloneIve, &dir).expect("cycloneive synthesis");
        eprintln!(
            "{name}: xc3sa {} LUT, {} FF; cycloneive {} LE, {} FF",
            x.luts, x.ffs, c.luts, c.ffs
        );
        // Registers: the held sample (13 + 10 + 12), the age (24), the output (13 + 10 + 12
        // + 24 + the velocity's 32), the synchronizer: about 150; the extrapolation adds
        // the latched copy, ager, the sum and the multiplier's registers.
        let (lo, hi) = if extrapolate { (250, 700) } else { (100, 220) };
        assert!(x.ffs > lo && x.ffs < hi, "{name}: {} FF", x.ffs);
    }
}
