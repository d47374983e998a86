//! Time-multiplexed biquad engine: the model against hand-computed impulse responses and a
//! floating-point reference; rust-hdl == clock-level model == Icarus == Verilator on an
//! impulse, a saturating full-scale step, random stimulus, back-to-back strobes and a reset
//! in the middle of a computation; exactly one `$mul` after Yosys coarse synthesis; the
//! Cyclone III figures.
use rust_hdl::prelude::Block;
use sinedec::blocks::biquad::hdl::BiquadRtl;
use sinedec::blocks::biquad::model::{BiquadCycleModel, BiquadIn, BiquadModel};
use sinedec::blocks::biquad::BiquadParams;
use sinedec::blocks::sext;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::error::Error;
use sinedec::synth::{parse_stat_json, synthesize, Family};
use sinedec::verify::{block_traces, Simulators};
use std::f64::consts::{PI, SQRT_2};
mod common;

const FS: f64 = 400e3;

/// Rounds a real coefficient to an integer with `frac` fractional bits.
fn q(v: f64, frac: u32) -> i64 {
    (v * (1u64 << frac) as f64).round() as i64
}

/// 2nd-order Butterworth low-pass (bilinear transform): (b0, b1, b2, a1, a2) as reals.
fn butter_lp(fc: f64, fs: f64) -> [f64; 5] {
    let k = (PI * fc / fs).tan();
    let d = 1.0 + SQRT_2 * k + k * k;
    let b0 = k * k / d;
    [
        b0,
        2.0 * b0,
        b0,
        2.0 * (k * k - 1.0) / d,
        (1.0 - SQRT_2 * k + k * k) / d,
    ]
}

/// 2nd-order band-pass (bilinear, constant 0 dB peak gain) centred on sqrt(f1 f2).
fn bandpass(f1: f64, f2: f64, fs: f64) -> [f64; 5] {
    let f0 = (f1 * f2).sqrt();
    let w0 = 2.0 * PI * f0 / fs;
    let alpha = w0.sin() / (2.0 * f0 / (f2 - f1));
    let a0 = 1.0 + alpha;
    [
        alpha / a0,
        0.0,
        -alpha / a0,
        -2.0 * w0.cos() / a0,
        (1.0 - alpha) / a0,
    ]
}

fn quant(c: [f64; 5], frac: u32) -> [i64; 5] {
    c.map(|v| q(v, frac))
}

/// The capacitive chain: band-pass on branch 0 (`s0` sections), the 4 kHz low-pass on
/// branches 1 and 2 (`s1` sections each).
fn capacitive(d: u32, c: u32, f: u32, g: u32, s0: usize, s1: usize) -> BiquadParams {
    let bp = quant(bandpass(15e3, 25e3, FS), f);
    let lp = quant(butter_lp(4e3, FS), f);
    BiquadParams::new(d, c, f, g, vec![vec![bp; s0], vec![lp; s1], vec![lp; s1]])
        .expect("valid parameters")
}

/// Float DF-I of one branch with the quantized coefficients, input scaled by 2^G: the
/// exact (unrounded) value the S-bit state approximates.
fn float_branch(p: &BiquadParams, branch: usize, xs: &[i64]) -> Vec<f64> {
    let sc = (1u64 << p.coef_frac) as f64;
    let g = (1u64 << p.guard_frac) as f64;
    let secs = &p.branches[branch];
    let mut h = vec![(0.0f64, 0.0f64); secs.len() + 1];
    xs.iter()
        .map(|&x| {
            let mut v = x as f64 * g;
            for (s, c) in secs.iter().enumerate() {
                let y = (c[0] as f64 * v + c[1] as f64 * h[s].0 + c[2] as f64 * h[s].1
                    - c[3] as f64 * h[s + 1].0
                    - c[4] as f64 * h[s + 1].1)
                    / sc;
                h[s] = (v, h[s].0);
                v = y;
            }
            let n = secs.len();
            h[n] = (v, h[n].0);
            v
        })
        .collect()
}

/// Sum of |h| over 100k samples of the impulse response of one section with quantized
/// coefficients; `feedback_only` takes 1/A(z) (the gain from an error injected at the
/// summing node to the section output), else B(z)/A(z).
fn l1_norm(c: &[i64; 5], frac: u32, feedback_only: bool) -> f64 {
    let sc = (1u64 << frac) as f64;
    let b = if feedback_only {
        [1.0, 0.0, 0.0]
    } else {
        [c[0] as f64 / sc, c[1] as f64 / sc, c[2] as f64 / sc]
    };
    let (a1, a2) = (c[3] as f64 / sc, c[4] as f64 / sc);
    let (mut x1, mut x2, mut y1, mut y2, mut sum) = (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for n in 0..100_000 {
        let x = if n == 0 { 1.0 } else { 0.0 };
        let y = b[0] * x + b[1] * x1 + b[2] * x2 - a1 * y1 - a2 * y2;
        sum += y.abs();
        (x2, x1, y2, y1) = (x1, x, y1, y);
    }
    sum
}

fn feedback_l1(c: &[i64; 5], frac: u32) -> f64 {
    l1_norm(c, frac, true)
}

/// Worst-case output error (output LSB) of a branch against [`float_branch`] / 2^G: each
/// section injects 5 floors in [-5, 0] S-LSB at its summing node, amplified by its 1/A(z)
/// and then by the following sections' B/A (L1 norms); the output floor adds < 1 LSB.
fn branch_bound(p: &BiquadParams, branch: usize) -> f64 {
    let secs = &p.branches[branch];
    let mut total = 0.0;
    for s in 0..secs.len() {
        let mut gain = 5.0 * feedback_l1(&secs[s], p.coef_frac);
        for t in secs.iter().skip(s + 1) {
            gain *= l1_norm(t, p.coef_frac, false);
        }
        total += gain;
    }
    total / (1u64 << p.guard_frac) as f64 + 1.0
}

// ---------------------------------------------------------------- model, by hand

#[test]
fn model_impulse_of_a_hand_chosen_section() {
    // b = [0.25, 0.5, 0.25], a = [0, 0] in Q2.16: an FIR 1-2-1 / 4.
    let p =
        BiquadParams::new(16, 18, 16, 2, vec![vec![[16384, 32768, 16384, 0, 0]]]).expect("valid");
    let mut m = BiquadModel::new(&p);
    let ys: Vec<i64> = [1000, 0, 0, 0, 0]
        .iter()
        .map(|&x| m.step(&[x]).0[0])
        .collect();
    assert_eq!(ys, vec![250, 500, 250, 0, 0]);
    // Negative impulse: exact products, so exactly the negated response.
    let mut m = BiquadModel::new(&p);
    let ys: Vec<i64> = [-1000, 0, 0, 0]
        .iter()
        .map(|&x| m.step(&[x]).0[0])
        .collect();
    assert_eq!(ys, vec![-250, -500, -250, 0]);
    // Pure feedback y = x + 0.5 y1 (a1 = -0.5): 1024, 512, 256, ... halving exactly.
    let p = BiquadParams::new(16, 18, 16, 0, vec![vec![[65536, 0, 0, -32768, 0]]]).expect("valid");
    let mut m = BiquadModel::new(&p);
    let ys: Vec<i64> = (0..6)
        .map(|n| m.step(&[if n == 0 { 1024 } else { 0 }]).0[0])
        .collect();
    assert_eq!(ys, vec![1024, 512, 256, 128, 64, 32]);
    // a2 = 0.25 with a negative sign in the recursion: y = x - 0.25 y2.
    let p = BiquadParams::new(16, 18, 16, 0, vec![vec![[65536, 0, 0, 0, 16384]]]).expect("valid");
    let mut m = BiquadModel::new(&p);
    let ys: Vec<i64> = (0..6)
        .map(|n| m.step(&[if n == 0 { 4096 } else { 0 }]).0[0])
        .collect();
    assert_eq!(ys, vec![4096, 0, -1024, 0, 256, 0]);
    // Cascade: two 1-2-1/4 sections = 1-4-6-4-1 / 16.
    let f = [16384, 32768, 16384, 0, 0];
    let p = BiquadParams::new(16, 18, 16, 2, vec![vec![f, f]]).expect("valid");
    let mut m = BiquadModel::new(&p);
    let ys: Vec<i64> = (0..6)
        .map(|n| m.step(&[if n == 0 { 1600 } else { 0 }]).0[0])
        .collect();
    assert_eq!(ys, vec![100, 400, 600, 400, 100, 0]);
}

#[test]
fn model_floors_each_product() {
    // b0 = 1/3 (21845 / 2^16), G = 0: y = floor(3 * 21845 / 65536) = floor(0.99998) = 0,
    // and -3 gives floor(-0.99998) = -1 (truncation toward minus infinity, per product).
    let p = BiquadParams::new(16, 18, 16, 0, vec![vec![[21845, 0, 0, 0, 0]]]).expect("valid");
    let mut m = BiquadModel::new(&p);
    assert_eq!(m.step(&[3]).0[0], 0);
    assert_eq!(m.step(&[-3]).0[0], -1);
    // Two terms floored separately: b0 = b1 = 1/2 on x = 1 then 1 with G = 0:
    // floor(0.5) + floor(0.5) = 0, not floor(1.0) = 1.
    let p = BiquadParams::new(16, 18, 16, 0, vec![vec![[32768, 32768, 0, 0, 0]]]).expect("valid");
    let mut m = BiquadModel::new(&p);
    assert_eq!(m.step(&[1]).0[0], 0);
    assert_eq!(m.step(&[1]).0[0], 0);
}

#[test]
fn model_lowpass_matches_float_within_the_quantization_bound() {
    // Precise widths: 25-bit Q2.23 coefficients, 8 guard bits.
    let (d, c, f, g) = (16, 25, 23, 8);
    let lp = quant(butter_lp(4e3, FS), f);
    let p = BiquadParams::new(d, c, f, g, vec![vec![lp]]).expect("valid");
    // Bound (S-format LSB): each sample injects 5 floors in [-5, 0] LSB at the summing
    // node, amplified by sum|h| of 1/A(z); the output floor adds < 1 output LSB.
    let l1 = feedback_l1(&lp, f);
    let bound_s = 5.0 * l1;
    let bound_out = bound_s / (1u64 << g) as f64 + 1.0;
    assert!(bound_out < 8.0, "bound {bound_out} output LSB");
    let mut r = SplitMix64(11);
    let mut xs: Vec<i64> = (0..400).map(|_| r.range(-20000, 20000)).collect();
    xs.extend(std::iter::repeat_n(15000, 1500)); // step: settles to DC gain 1
    let exact = float_branch(&p, 0, &xs);
    let mut m = BiquadModel::new(&p);
    let mut worst = 0.0f64;
    for (n, &x) in xs.iter().enumerate() {
        let y = m.step(&[x]).0[0] as f64;
        let err = (y - exact[n] / (1u64 << g) as f64).abs();
        worst = worst.max(err);
        assert!(
            err <= bound_out,
            "sample {n}: error {err} > bound {bound_out}"
        );
    }
    eprintln!("low-pass: worst error {worst:.3} LSB, bound {bound_out:.3} LSB (sum|h| = {l1:.1})");
    // The quantized filter against the unquantized design: DC gain ~1 (step within 0.1%)
    // and the float response of the real coefficients within 0.5% of full scale.
    let mut m = BiquadModel::new(&p);
    let last = (0..3000).map(|_| m.step(&[15000]).0[0]).last().unwrap_or(0);
    assert!((last - 15000).abs() <= 15, "step settles at {last}");
    let ideal = butter_lp(4e3, FS);
    let (mut y1, mut y2, mut x1, mut x2) = (0.0, 0.0, 0.0, 0.0);
    let mut m = BiquadModel::new(&p);
    for &x in &xs {
        let xf = x as f64;
        let y = ideal[0] * xf + ideal[1] * x1 + ideal[2] * x2 - ideal[3] * y1 - ideal[4] * y2;
        (x2, x1, y2, y1) = (x1, xf, y1, y);
        let ym = m.step(&[x]).0[0] as f64;
        assert!((ym - y).abs() < 0.005 * 32768.0, "{ym} vs ideal {y}");
    }
}

#[test]
fn model_saturates_a_full_scale_step_and_flags_it() {
    // DC gain 4: y = x + 0.75 y1. A full-scale step must clamp at +32767, never wrap.
    let p = BiquadParams::new(16, 18, 16, 2, vec![vec![[65536, 0, 0, -49152, 0]]]).expect("valid");
    let mut m = BiquadModel::new(&p);
    let mut flagged = false;
    for n in 0..50 {
        let (y, ov) = m.step(&[32767]);
        assert!(y[0] > 0, "sample {n}: {} wrapped", y[0]);
        flagged |= ov;
        if n >= 5 {
            assert_eq!(y[0], 32767, "sample {n}");
            assert!(ov, "overflow flag at {n}");
        }
    }
    assert!(flagged);
    let mut m = BiquadModel::new(&p);
    for _ in 0..50 {
        let (y, _) = m.step(&[-32768]);
        assert!(y[0] < 0);
    }
    assert_eq!(m.step(&[-32768]), (vec![-32768], true));
    // A small step: no saturation, no flag, settles at 4x.
    let mut m = BiquadModel::new(&p);
    let mut last = (vec![], true);
    for _ in 0..200 {
        last = m.step(&[1000]);
        assert!(!last.1);
    }
    assert!((last.0[0] - 4000).abs() <= 2, "{:?}", last.0);
}

#[test]
fn invalid_parameters_name_what_is_wrong() {
    let lp = [62, 124, 62, -125254, 59966];
    let key_of = |e: Error| match e {
        Error::ConfigValue { key, message, .. } => format!("{key}: {message}"),
        other => panic!("unexpected error {other}"),
    };
    let cases: Vec<(BiquadParams, &str)> = vec![
        (
            BiquadParams {
                data_width: 40,
                ..base(lp)
            },
            "data_width",
        ),
        (
            BiquadParams {
                coef_width: 1,
                ..base(lp)
            },
            "coef_width",
        ),
        (
            BiquadParams {
                coef_frac: 18,
                ..base(lp)
            },
            "coef_frac",
        ),
        (
            BiquadParams {
                guard_frac: 20,
                ..base(lp)
            },
            "guard_frac",
        ),
        (
            BiquadParams {
                data_width: 20,
                guard_frac: 8,
                coef_width: 25,
                coef_frac: 20,
                ..base(lp)
            },
            "accumulator width",
        ),
        (
            BiquadParams {
                branches: vec![],
                ..base(lp)
            },
            "branches: 0 branches",
        ),
        (
            BiquadParams {
                branches: vec![vec![lp]; 9],
                ..base(lp)
            },
            "1..=8",
        ),
        (
            BiquadParams {
                branches: vec![vec![lp], vec![]],
                ..base(lp)
            },
            "branches[1]",
        ),
        (
            BiquadParams {
                branches: vec![vec![lp; 17]],
                ..base(lp)
            },
            "17 sections",
        ),
        (
            BiquadParams {
                branches: vec![vec![lp], vec![lp, [0, 131072, 0, 0, 0]]],
                ..base(lp)
            },
            "branches[1][1].b1: coefficient 131072 does not fit 18 bits",
        ),
        (
            BiquadParams {
                branches: vec![vec![[0, 0, 0, 0, -131072]]],
                ..base(lp)
            },
            "branches[0][0].a2",
        ),
    ];
    for (p, want) in cases {
        let msg = key_of(p.validate().expect_err(want));
        assert!(msg.contains(want), "`{msg}` should mention `{want}`");
    }
    base(lp).validate().expect("the base is valid");
}

fn base(lp: [i64; 5]) -> BiquadParams {
    BiquadParams {
        data_width: 16,
        coef_width: 18,
        coef_frac: 16,
        guard_frac: 2,
        branches: vec![vec![lp]],
    }
}

// ---------------------------------------------------------------- co-simulation

/// Runs rust-hdl, the clock-level model, Icarus and Verilator on `ins`; panics on any
/// difference; returns the rust-hdl rows.
fn cosim(p: &BiquadParams, ins: &[BiquadIn], tag: &str) -> Vec<Vec<u64>> {
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row(p)).collect();
    let mut cm = BiquadCycleModel::new(p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| cm.tick(i)).collect();
    let dir = common::workdir(&format!("biquad_{tag}"));
    let t = block_traces(
        BiquadRtl::new(p),
        &format!("bq_{tag}"),
        "clk",
        &rows,
        Simulators::ALL,
        &dir,
    )
    .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    for (k, (a, b)) in t.rust_hdl.iter().zip(&model).enumerate() {
        assert_eq!(
            a, b,
            "{tag}: rust-hdl vs model at row {k} (out_valid, out_data.., overflow, busy, dropped)"
        );
    }
    t.rust_hdl
}

fn idle(n: usize) -> Vec<BiquadIn> {
    vec![BiquadIn::default(); n]
}

fn reset(p: &BiquadParams) -> Vec<BiquadIn> {
    let mut v = vec![
        BiquadIn {
            rst: true,
            ..Default::default()
        };
        2
    ];
    v.extend(idle(p.state_words() as usize));
    v
}

fn sample(data: Vec<i64>) -> BiquadIn {
    BiquadIn {
        rst: false,
        in_valid: true,
        data,
    }
}

/// Samples every `period` clocks.
fn strobes(samples: &[Vec<i64>], period: usize) -> Vec<BiquadIn> {
    let mut v = Vec::new();
    for s in samples {
        v.push(sample(s.clone()));
        v.extend(idle(period - 1));
    }
    v
}

/// (row of out_valid, out_data, overflow) of a trace with k branches.
fn outputs(rows: &[Vec<u64>], p: &BiquadParams) -> Vec<(usize, Vec<i64>, bool)> {
    let k = p.branch_count();
    rows.iter()
        .enumerate()
        .filter(|(_, r)| r[0] == 1)
        .map(|(n, r)| {
            (
                n,
                r[1..=k].iter().map(|&v| sext(v, p.data_width)).collect(),
                r[k + 1] == 1,
            )
        })
        .collect()
}

#[test]
fn cosim_impulse_on_the_capacitive_chain() {
    let p = capacitive(16, 18, 16, 2, 1, 2);
    let per = p.cycles_per_sample() as usize;
    let lat = p.latency() as usize;
    // 8 clocks per section: 5 MACs, the RAM read, the operand and the product registers.
    assert_eq!((per, lat), (8 * 5 + 3, 8 * 5 + 2));
    let mut samples = vec![vec![12000, 20000, -15000]];
    samples.extend(vec![vec![0, 0, 0]; 40]);
    let mut ins = reset(&p);
    let start = ins.len();
    ins.extend(strobes(&samples, per));
    ins.extend(idle(per + 2));
    let rows = cosim(&p, &ins, "impulse");
    let outs = outputs(&rows, &p);
    assert_eq!(outs.len(), samples.len());
    // Measured latency and period = cycles_per_sample; busy exactly while computing.
    for (j, (row, _, _)) in outs.iter().enumerate() {
        assert_eq!(*row, start + j * per + lat, "out_valid of sample {j}");
    }
    for (n, r) in rows.iter().enumerate().skip(start).take(lat) {
        assert_eq!(r[p.branch_count() + 2], 1, "busy at row {n}");
    }
    assert_eq!(
        rows[start + lat][p.branch_count() + 2],
        0,
        "idle when out_valid"
    );
    // The responses are the independent float filter's within the quantization bound.
    let mut m = BiquadModel::new(&p);
    for b in 0..3 {
        let xs: Vec<i64> = samples.iter().map(|s| s[b]).collect();
        let exact = float_branch(&p, b, &xs);
        let bound = branch_bound(&p, b);
        let mut worst = 0.0f64;
        for (n, (_, y, ov)) in outs.iter().enumerate() {
            assert!(!ov);
            let e = exact[n] / 4.0;
            worst = worst.max((y[b] as f64 - e).abs());
            assert!(
                (y[b] as f64 - e).abs() <= bound,
                "branch {b} sample {n}: {} vs {e}",
                y[b]
            );
        }
        eprintln!("impulse branch {b}: worst error {worst:.2} LSB, bound {bound:.2} LSB");
    }
    // And the model replays the same samples.
    for (s, (_, y, _)) in samples.iter().zip(&outs) {
        assert_eq!(&m.step(s).0, y);
    }
}

#[test]
fn cosim_full_scale_step_saturates_with_the_flag() {
    // Branch 0: DC gain 4 (saturates), branch 1: the low-pass (DC gain 1, does not).
    let lp = quant(butter_lp(4e3, FS), 16);
    let p = BiquadParams::new(
        16,
        18,
        16,
        2,
        vec![vec![[65536, 0, 0, -49152, 0]], vec![lp]],
    )
    .expect("valid");
    let per = p.cycles_per_sample() as usize;
    let mut samples = vec![vec![32767, 32767]; 30];
    samples.extend(vec![vec![-32768, -32768]; 30]);
    let mut ins = reset(&p);
    ins.extend(strobes(&samples, per + 3));
    ins.extend(idle(per + 2));
    let rows = cosim(&p, &ins, "fullscale");
    let outs = outputs(&rows, &p);
    assert_eq!(outs.len(), 60);
    let mut flagged = 0;
    for (n, (_, y, ov)) in outs.iter().enumerate() {
        if n < 30 {
            assert!(y[0] > 0 && y[1] >= 0, "sample {n}: {y:?} wrapped");
        } else if n >= 33 {
            assert!(y[0] < 0, "sample {n}: {y:?} wrapped");
        }
        if (5..30).contains(&n) || n >= 36 {
            assert_eq!(y[0], if n < 30 { 32767 } else { -32768 }, "sample {n}");
            assert!(*ov, "overflow with sample {n}");
        }
        flagged += *ov as usize;
    }
    assert!(flagged >= 50);
    // overflow is a one-clock flag: never high without out_valid.
    let k = p.branch_count();
    assert!(rows.iter().all(|r| r[k + 1] == 0 || r[0] == 1));
}

/// Stable random sections: poles at radius r < 0.98, random zeros and gains.
fn random_section(r: &mut SplitMix64, f: u32) -> [i64; 5] {
    let rad = 0.3 + 0.68 * r.unit();
    let th = PI * r.unit();
    let (a1, a2) = (-2.0 * rad * th.cos(), rad * rad);
    let g = 0.02 + 0.5 * r.unit();
    let (z1, z2) = (r.unit() * 2.0 - 1.0, r.unit() * 2.0 - 1.0);
    [g, -g * (z1 + z2), g * z1 * z2, a1, a2].map(|v| q(v, f))
}

#[test]
fn cosim_random_stimulus_several_shapes() {
    let mut r = SplitMix64(2024);
    // (data, coef, frac, guard, sections per branch)
    let shapes: [(u32, u32, u32, u32, &[usize]); 4] = [
        (16, 18, 16, 2, &[2, 1, 1]),
        (16, 25, 23, 8, &[1, 2, 2]),
        (18, 18, 16, 0, &[3]),
        (17, 20, 17, 4, &[1, 1, 2, 1]),
    ];
    for (i, (d, c, f, g, secs)) in shapes.iter().enumerate() {
        let branches = secs
            .iter()
            .map(|&n| (0..n).map(|_| random_section(&mut r, *f)).collect())
            .collect();
        let p = BiquadParams::new(*d, *c, *f, *g, branches).expect("valid");
        let per = p.cycles_per_sample() as usize;
        let full = 1i64 << (d - 1);
        let mut ins = reset(&p);
        for _ in 0..60 {
            let data = (0..p.branch_count())
                .map(|_| r.range(-full, full - 1))
                .collect();
            ins.push(sample(data));
            // Random gaps: some shorter than the period (dropped), some longer.
            let gap = r.range(per as i64 / 2, per as i64 + 6) as usize;
            ins.extend(idle(gap));
        }
        ins.extend(idle(per + 2));
        let rows = cosim(&p, &ins, &format!("random{i}"));
        let k = p.branch_count();
        let dropped = rows.iter().filter(|r| r[k + 3] == 1).count();
        let accepted = outputs(&rows, &p).len();
        assert_eq!(dropped + accepted, 60, "shape {i}");
        assert!(dropped > 0 && accepted > 20, "shape {i}: {dropped} dropped");
    }
}

#[test]
fn cosim_back_to_back_strobes_are_dropped_while_busy() {
    let p = capacitive(16, 18, 16, 2, 1, 1);
    let per = p.cycles_per_sample() as usize;
    let mut ins = reset(&p);
    let start = ins.len();
    let n = 5 * per + 3;
    let mut rng = SplitMix64(5);
    for _ in 0..n {
        ins.push(sample(vec![
            rng.range(-30000, 30000),
            rng.range(-30000, 30000),
            rng.range(-30000, 30000),
        ]));
    }
    ins.extend(idle(per + 2));
    let rows = cosim(&p, &ins, "b2b");
    let k = p.branch_count();
    // in_valid every clock: exactly the strobes at start + j * per are accepted (busy is
    // low before those edges), every other one is flagged by the edge that ignores it.
    let accepted: Vec<usize> = (start..start + n)
        .filter(|&row| rows[row - 1][k + 2] == 0)
        .collect();
    let want: Vec<usize> = (0..n).step_by(per).map(|j| start + j).collect();
    assert_eq!(accepted, want);
    for (row, r) in rows.iter().enumerate().skip(start).take(n) {
        assert_eq!(
            r[k + 3] == 1,
            !want.contains(&row),
            "dropped flag at row {row}"
        );
    }
    // The outputs are those of the accepted samples only.
    let mut m = BiquadModel::new(&p);
    let outs = outputs(&rows, &p);
    assert_eq!(outs.len(), want.len());
    for (&row, (_, y, _)) in want.iter().zip(&outs) {
        assert_eq!(&m.step(&ins[row].data).0, y);
    }
}

#[test]
fn cosim_reset_mid_computation_restarts_clean() {
    let p = capacitive(16, 18, 16, 2, 2, 2);
    let per = p.cycles_per_sample() as usize;
    let mut rng = SplitMix64(77);
    let mut rand_samples = |n: usize| -> Vec<Vec<i64>> {
        (0..n)
            .map(|_| (0..3).map(|_| rng.range(-20000, 20000)).collect())
            .collect()
    };
    let before = rand_samples(6);
    let after = rand_samples(8);
    let mut ins = reset(&p);
    ins.extend(strobes(&before, per));
    // One more sample, cut by a reset in the middle of its computation (and a strobe
    // during the clearing sweep, which is dropped).
    ins.push(sample(vec![30000, -30000, 30000]));
    ins.extend(idle(per / 2));
    ins.push(BiquadIn {
        rst: true,
        ..Default::default()
    });
    ins.push(sample(vec![1, 2, 3]));
    ins.extend(idle(p.state_words() as usize));
    let restart = ins.len();
    ins.extend(strobes(&after, per));
    ins.extend(idle(per + 2));
    let rows = cosim(&p, &ins, "reset");
    let k = p.branch_count();
    let outs = outputs(&rows, &p);
    assert_eq!(
        outs.len(),
        before.len() + after.len(),
        "the cut sample has no output"
    );
    // After the reset: out_data cleared, and the new samples' outputs are those of a
    // freshly reset filter (no state left from before).
    let rst_row = restart - p.state_words() as usize - 2;
    assert!(rows[rst_row][1..=k].iter().all(|&v| v == 0));
    assert_eq!(
        rows[rst_row + 1][k + 3],
        1,
        "strobe during clearing flagged"
    );
    let mut fresh = BiquadModel::new(&p);
    for (s, (_, y, _)) in after.iter().zip(&outs[before.len()..]) {
        assert_eq!(&fresh.step(s).0, y);
    }
}

// ---------------------------------------------------------------- synthesis

#[test]
fn yosys_coarse_has_exactly_one_multiplier() {
    use sinedec::cosim::require_tool;
    if let Err(e) = require_tool("yosys") {
        panic!("yosys is needed for this test: {e}");
    }
    for (tag, p) in [
        ("bqm18", capacitive(16, 18, 16, 2, 2, 2)),
        ("bqm25", capacitive(16, 25, 23, 8, 2, 2)),
    ] {
        let mut uut = BiquadRtl::new(&p);
        uut.connect_all();
        let v = sinedec::emit::verilog::export(&uut, tag, tag).expect("export");
        let dir = common::workdir(&format!("biquad_{tag}_coarse"));
        let vf = dir.join("bq.v");
        std::fs::write(&vf, &v).expect("write verilog");
        // Before alumacc (which rewrites a lone $mul into a one-product $macc in Yosys
        // 0.23): exactly one $mul; after the whole coarse script: one $mul or $macc.
        let run = |tail: &str, name: &str| {
            let stat = dir.join(name);
            let out = std::process::Command::new("yosys")
                .arg("-q")
                .arg("-p")
                .arg(format!(
                    "read_verilog {}; hierarchy -check -top {tag}; proc; flatten; {tail}; tee -q -o {} stat -json",
                    vf.display(),
                    stat.display()
                ))
                .output()
                .expect("yosys runs");
            assert!(
                out.status.success(),
                "yosys failed: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            parse_stat_json(&std::fs::read_to_string(&stat).expect("stat written"), tag)
                .expect("stat -json has the module")
        };
        let n =
            |c: &std::collections::BTreeMap<String, u64>, k: &str| c.get(k).copied().unwrap_or(0);
        let early = run("opt; wreduce", "stat_early.json");
        eprintln!("{tag}: proc; opt; wreduce: {early:?}");
        assert_eq!(n(&early, "$mul"), 1, "{tag}: exactly one $mul ({early:?})");
        assert_eq!(n(&early, "$macc"), 0);
        let coarse = run(&format!("synth -run coarse -top {tag}"), "stat_coarse.json");
        eprintln!("{tag}: synth -run coarse: {coarse:?}");
        assert_eq!(
            n(&coarse, "$mul") + n(&coarse, "$macc"),
            1,
            "{tag}: one multiplier cell after coarse synthesis ({coarse:?})"
        );
    }
}

#[test]
fn cyclone_iii_synthesis_figures() {
    // Yosys 0.23 `synth_intel -family cycloneive` has no DSP mapping: it builds the product
    // from logic cells (Quartus would use embedded 18x18 multipliers: one for 18 x 18, more
    // for 18 x 25). The multiplier alone is synthesized too so
    // its share of the logic is visible.
    use sinedec::blocks::biquad::hdl::BiquadMul;
    for (tag, p) in [
        ("bqc18", capacitive(16, 18, 16, 2, 2, 2)),
        // S = 18 here: with S > 18 (e.g. G = 8) Yosys 0.23 maps the state RAM to the M9K
        // 36-bit mode and warns "Resizing cell port ... from 32 bits to 36 bits", which
        // the project's synthesis gate rejects.
        ("bqc25", capacitive(16, 25, 23, 2, 2, 2)),
    ] {
        let mut uut = BiquadRtl::new(&p);
        uut.connect_all();
        let v = sinedec::emit::verilog::export(&uut, tag, tag).expect("export");
        let dir = common::workdir(&format!("biquad_{tag}_synth"));
        let s = synthesize(&v, tag, Family::CycloneIve, &dir).expect("cycloneive synthesis");
        let ram = s.cells.get("altsyncram").copied().unwrap_or(0);
        let mut mul = BiquadMul::new(p.state_width(), p.coef_width, p.coef_frac);
        mul.connect_all();
        let mtag = format!("{tag}_mul");
        let vm = sinedec::emit::verilog::export(&mul, &mtag, &mtag).expect("export");
        let sm = synthesize(&vm, &mtag, Family::CycloneIve, &dir).expect("multiplier synthesis");
        eprintln!(
            "{tag}: {}x{} product, {} sections, {} clocks/sample: cycloneive {} LE ({} in the multiplier), {} FF, {} DSP multiplier cells, {} altsyncram (state RAM); cells {:?}",
            p.state_width(),
            p.coef_width,
            p.total_sections(),
            p.cycles_per_sample(),
            s.luts,
            sm.luts,
            s.ffs,
            s.multipliers,
            ram,
            s.cells
        );
        assert!(s.luts > sm.luts && sm.luts > 0);
        assert_eq!(ram, 1, "{tag}: the state memory is one RAM block");
        // Registers: pc, parity, clear counter, xcur, coef, prod, acc, 3 x (input latch,
        // output stage, output) and flags: well below the RAM's bits; plus the multiplier's
        // operand registers (S + C) and the program word register (C + 19 control bits).
        let k = p.branch_count() as u64;
        let (d, sw, c, a) = (
            p.data_width as u64,
            p.state_width() as u64,
            p.coef_width as u64,
            p.acc_width() as u64,
        );
        let bound = 3 * k * d + k + sw + c + 2 * a + 2 * 10 + 16 + (sw + c) + (c + 19);
        assert!(s.ffs <= bound, "{tag}: {} FF > {bound}", s.ffs);
    }
}
