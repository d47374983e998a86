//! Helpers shared by `tests/capacitive/biquad.rs` and `tests/capacitive/biquad_cosim.rs` (moved out of `tests/capacitive/biquad.rs` so that
//! no test file is longer than about 600 lines).
#![allow(dead_code)]
use crate::common;
use sinedec::blocks::biquad::hdl::BiquadRtl;
use sinedec::blocks::biquad::model::{BiquadCycleModel, BiquadIn};
use sinedec::blocks::biquad::BiquadParams;
use sinedec::blocks::sext;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::{block_traces, Simulators};
use std::f64::consts::{PI, SQRT_2};

pub const FS: f64 = 400e3;

/// Rounds a real coefficient to an integer with `frac` fractional bits.
pub fn q(v: f64, frac: u32) -> i64 {
    (v * (1u64 << frac) as f64).round() as i64
}

/// 2nd-order Butterworth low-pass (bilinear transform): (b0, b1, b2, a1, a2) as reals.
pub fn butter_lp(fc: f64, fs: f64) -> [f64; 5] {
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
pub fn bandpass(f1: f64, f2: f64, fs: f64) -> [f64; 5] {
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

pub fn quant(c: [f64; 5], frac: u32) -> [i64; 5] {
    c.map(|v| q(v, frac))
}

/// The capacitive chain: band-pass on branch 0 (`s0` sections), the 4 kHz low-pass on
/// branches 1 and 2 (`s1` sections each).
pub fn capacitive(d: u32, c: u32, f: u32, g: u32, s0: usize, s1: usize) -> BiquadParams {
    let bp = quant(bandpass(15e3, 25e3, FS), f);
    let lp = quant(butter_lp(4e3, FS), f);
    BiquadParams::new(d, c, f, g, vec![vec![bp; s0], vec![lp; s1], vec![lp; s1]])
        .expect("valid parameters")
}

/// Float DF-I of one branch with the quantized coefficients, input scaled by 2^G: the
/// exact (unrounded) value the S-bit state approximates.
pub fn float_branch(p: &BiquadParams, branch: usize, xs: &[i64]) -> Vec<f64> {
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
pub fn l1_norm(c: &[i64; 5], frac: u32, feedback_only: bool) -> f64 {
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

pub fn feedback_l1(c: &[i64; 5], frac: u32) -> f64 {
    l1_norm(c, frac, true)
}

/// Worst-case output error (output LSB) of a branch against [`float_branch`] / 2^G: each
/// section injects 5 floors in [-5, 0] S-LSB at its summing node, amplified by its 1/A(z)
/// and then by the following sections' B/A (L1 norms); the output floor adds < 1 LSB.
pub fn branch_bound(p: &BiquadParams, branch: usize) -> f64 {
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

pub fn base(lp: [i64; 5]) -> BiquadParams {
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
pub fn cosim(p: &BiquadParams, ins: &[BiquadIn], tag: &str) -> Vec<Vec<u64>> {
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

pub fn idle(n: usize) -> Vec<BiquadIn> {
    vec![BiquadIn::default(); n]
}

pub fn reset(p: &BiquadParams) -> Vec<BiquadIn> {
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

pub fn sample(data: Vec<i64>) -> BiquadIn {
    BiquadIn {
        rst: false,
        in_valid: true,
        data,
    }
}

/// Samples every `period` clocks.
pub fn strobes(samples: &[Vec<i64>], period: usize) -> Vec<BiquadIn> {
    let mut v = Vec::new();
    for s in samples {
        v.push(sample(s.clone()));
        v.extend(idle(period - 1));
    }
    v
}

/// (row of out_valid, out_data, overflow) of a trace with k branches.
pub fn outputs(rows: &[Vec<u64>], p: &BiquadParams) -> Vec<(usize, Vec<i64>, bool)> {
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

/// Stable random sections: poles at radius r < 0.98, random zeros and gains.
pub fn random_section(r: &mut SplitMix64, f: u32) -> [i64; 5] {
    let rad = 0.3 + 0.68 * r.unit();
    let th = PI * r.unit();
    let (a1, a2) = (-2.0 * rad * th.cos(), rad * rad);
    let g = 0.02 + 0.5 * r.unit();
    let (z1, z2) = (r.unit() * 2.0 - 1.0, r.unit() * 2.0 - 1.0);
    [g, -g * (z1 + z2), g * z1 * z2, a1, a2].map(|v| q(v, f))
}
