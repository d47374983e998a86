//! Time-multiplexed biquad engine: the model against hand-computed impulse responses and a
//! floating-point reference; rust-hdl == clock-level model == Icarus == Verilator on an
//! impulse, a saturating full-scale step, random stimulus, back-to-back strobes and a reset
//! in the middle of a computation; exactly one `$mul` after Yosys coarse synthesis; the
//! Cyclone III figures.
//!
//! (More tests in `tests/capacitive/biquad_cosim.rs`; the helpers are in `tests/capacitive/biquad_util/`.)
use crate::biquad_util;
use biquad_util::*;
use sinedec::blocks::biquad::model::BiquadModel;
use sinedec::blocks::biquad::BiquadParams;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::error::Error;

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
