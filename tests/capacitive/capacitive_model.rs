//! Capacitive encoder model (sim/capacitive.rs), checked independently of the RTL: without
//! impairments the ADC code is g V sin(wt + theta_e) within quantization; demodulating the
//! samples with exact sin/cos and averaging over whole carrier periods recovers theta_e;
//! ripple, feed-through and noise appear with their configured size; a seed fixes the run.
use sinedec::blocks::nco::model::{NcoIn, NcoModel};
use sinedec::blocks::nco::NcoParams;
use sinedec::sim::capacitive::{CapEncoder, CapParams};
use sinedec::sim::encoder::Profile;
use std::f64::consts::{PI, TAU};

const FS: f64 = 400e3;
const FC: f64 = 20e3;
/// Samples per carrier period (400 kHz / 20 kHz).
const SPP: usize = 20;

/// Wraps an angle difference into (-pi, pi].
fn wrap(a: f64) -> f64 {
    let r = a.rem_euclid(TAU);
    if r > PI {
        r - TAU
    } else {
        r
    }
}

/// Excitation words of an exact f64 carrier for `bits`-bit DACs at full scale.
fn exact_words(n: usize, bits: u32) -> (i64, i64, f64) {
    let m = ((1i64 << (bits - 1)) - 1) as f64;
    let wt = TAU * FC * n as f64 / FS;
    (
        (m * wt.sin()).round() as i64,
        (m * wt.cos()).round() as i64,
        wt,
    )
}

#[test]
fn ideal_received_signal_is_the_modulated_carrier() {
    // 1) Exact 24-bit excitation words: the DAC error is 2^-23 of full scale, so the code is
    //    the rounded g V sin(wt + theta_e) (within 0.5 LSB plus 0.01 LSB of DAC error).
    let mut p = CapParams::paper();
    p.dac_bits = 24;
    p.start_turns = 0.013;
    let mut e = CapEncoder::new(p.clone()).expect("valid");
    let half = (1i64 << 23) as f64;
    let m = half - 1.0;
    for n in 0..40_000 {
        let t = n as f64 / FS;
        let (s, c, wt) = exact_words(n, 24);
        let code = e.sample(t, s, c) as f64;
        let ideal = 0.8 * m / half * (wt + e.true_angle(t)).sin() * 32768.0;
        assert!((code - ideal).abs() <= 0.51, "n={n}: {code} vs {ideal}");
    }
    // 2) The NCO's own 16-bit words (paper config): r = g A sin(phi_n + theta_e) with phi_n
    //    the angle the NCO represents; the 16-bit DAC words are each within 0.5 LSB of
    //    A sin / A cos (sqrt(2)/2 LSB as a vector), which reaches the ADC scaled by g.
    let np = NcoParams::paper(50e6).expect("valid");
    let mut nco = NcoModel::new(&np);
    nco.step(NcoIn {
        rst: true,
        tick: false,
    });
    let mut e = CapEncoder::new(CapParams::paper()).expect("valid");
    let bound = 0.5 + 0.8 * std::f64::consts::SQRT_2 / 2.0 + 1e-6;
    let mut worst: f64 = 0.0;
    let mut n = 0usize;
    let mut k = 0;
    while n < 40_000 {
        let o = nco.step(NcoIn {
            rst: false,
            tick: k % 2 == 0,
        });
        k += 1;
        if !o.valid {
            continue;
        }
        let t = n as f64 / FS;
        let code = e.sample(t, o.sin, o.cos) as f64;
        let phi = np.angle_of_phase(o.phase);
        let ideal = 0.8 * np.peak() / 32768.0 * (phi + e.true_angle(t)).sin() * 32768.0;
        worst = worst.max((code - ideal).abs());
        n += 1;
    }
    eprintln!("NCO-driven: max |code - g A sin(phi + theta)| = {worst:.3} LSB (bound {bound:.3})");
    assert!(worst <= bound, "{worst}");
    assert_eq!(e.saturations(), 0);
}

#[test]
fn true_angle_is_periods_times_mechanical_angle() {
    let mut p = CapParams::ideal(16, 800.0);
    p.start_turns = 0.25;
    let e = CapEncoder::new(p).expect("valid");
    assert!((e.mech_angle(0.0) - PI / 2.0).abs() < 1e-12);
    // 800 rpm = 13.33 turns/s.
    let t = 0.01;
    let turns = 0.25 + 800.0 / 60.0 * t;
    assert!((e.mech_angle(t) - turns * TAU).abs() < 1e-9);
    assert!((e.true_angle(t) - 16.0 * turns * TAU).abs() < 1e-9);
}

/// Demodulates `codes` with the exact carrier and a low-pass that averages over whole
/// carrier periods twice (a one-period moving average applied two times: a triangular
/// window over two periods, double zeros at every multiple of the carrier). One output per
/// period: (centre time, I, Q), I = gV/2 cos theta, Q = gV/2 sin theta. A single boxcar
/// would leave a 2w residue proportional to the angle's rate (0.5% at 800 rpm); the
/// double average makes it second order.
fn demod(codes: &[(f64, f64, f64)]) -> Vec<(f64, f64, f64)> {
    let n = SPP as isize;
    (SPP..codes.len().saturating_sub(SPP))
        .step_by(SPP)
        .map(|c| {
            let (mut i, mut q) = (0.0, 0.0);
            for j in -(n - 1)..n {
                let (_, r, wt) = codes[(c as isize + j) as usize];
                let w = (n - j.abs()) as f64;
                i += w * r * wt.sin();
                q += w * r * wt.cos();
            }
            let norm = (SPP * SPP) as f64;
            (codes[c].0, i / norm, q / norm)
        })
        .collect()
}

/// Samples (t, code, wt) of `n` samples of an exact-carrier, 16-bit-DAC run.
fn run(e: &mut CapEncoder, n: usize) -> Vec<(f64, f64, f64)> {
    (0..n)
        .map(|k| {
            let t = k as f64 / FS;
            let (s, c, wt) = exact_words(k, 16);
            (t, e.sample(t, s, c) as f64, wt)
        })
        .collect()
}

#[test]
fn exact_demodulation_recovers_the_electrical_angle() {
    // Standing still at many angles, creeping, the paper's 800 rpm, and a reversal.
    let mut cases: Vec<(CapParams, f64)> = Vec::new();
    for j in 0..24 {
        let mut p = CapParams::ideal(16, 0.0);
        p.start_turns = j as f64 / (24.0 * 16.0) + 0.001;
        cases.push((p, 2e-4));
    }
    cases.push((CapParams::ideal(16, 0.3), 2e-4));
    cases.push((CapParams::paper(), 2e-3));
    let mut rev = CapParams::paper();
    rev.profile = Profile::Reversal {
        rpm: 800.0,
        at: 0.01,
        over: 0.02,
    };
    cases.push((rev, 2e-3));
    for (p, tol) in cases {
        let mut e = CapEncoder::new(p.clone()).expect("valid");
        let s = run(&mut e, 16_000);
        let mut worst: f64 = 0.0;
        for (tc, i, q) in demod(&s) {
            let err = wrap(q.atan2(i) - e.true_angle(tc));
            worst = worst.max(err.abs());
            // The amplitude is g V / 2 in codes.
            let amp = 2.0 * (i * i + q * q).sqrt();
            assert!((amp / (0.8 * 32767.0) - 1.0).abs() < 2e-3, "{amp}");
        }
        assert!(
            worst < tol,
            "{:?}: worst angle error {worst} rad",
            p.profile
        );
        if p.profile == CapParams::paper().profile {
            eprintln!("800 rpm: worst demodulated angle error {worst:.2e} rad");
        }
    }
}

#[test]
fn ripple_feedthrough_and_noise_have_their_configured_size() {
    // Ripple m = 5% at the 2nd harmonic: the demodulated amplitude follows
    // 1 + m cos(2 theta_e + phi_m). 30 rpm: one electrical period in 0.125 s.
    let mut p = CapParams::ideal(16, 30.0);
    p.ripple = 0.05;
    p.ripple_harmonic = 2;
    p.ripple_phase = 0.3;
    let mut e = CapEncoder::new(p).expect("valid");
    let s = run(&mut e, 50_000);
    let nominal = 0.8 * 32767.0;
    let mut worst: f64 = 0.0;
    let (mut lo, mut hi) = (f64::MAX, f64::MIN);
    for (tc, i, q) in demod(&s) {
        let amp = 2.0 * (i * i + q * q).sqrt() / nominal;
        let th = e.true_angle(tc);
        worst = worst.max((amp - (1.0 + 0.05 * (2.0 * th + 0.3).cos())).abs());
        lo = lo.min(amp);
        hi = hi.max(amp);
    }
    let m = (hi - lo) / (hi + lo);
    eprintln!("ripple: measured depth {m:.5} (configured 0.05)");
    assert!((m - 0.05).abs() < 5e-4, "{m}");
    assert!(worst < 1e-3, "{worst}");

    // Feed-through f = 2% of v_sin: I = gV/2 (cos theta + f) and Q = gV/2 sin theta, so
    // the mean of I / (gV/2) - cos theta is f and the angle error peaks at about f rad
    // (first order: -f sin theta).
    let mut p = CapParams::ideal(16, 30.0);
    p.feedthrough = 0.02;
    let mut e = CapEncoder::new(p).expect("valid");
    let s = run(&mut e, 50_000);
    let d = demod(&s);
    let f = d
        .iter()
        .map(|&(tc, i, _)| i / (nominal / 2.0) - e.true_angle(tc).cos())
        .sum::<f64>()
        / d.len() as f64;
    let peak_err = d
        .iter()
        .map(|&(tc, i, q)| wrap(q.atan2(i) - e.true_angle(tc)).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "feed-through: measured {f:.5} (configured 0.02), peak angle error {peak_err:.5} rad"
    );
    assert!((f - 0.02).abs() < 2e-4, "{f}");
    assert!((peak_err - 0.02).abs() < 2e-3, "{peak_err}");

    // Noise of 10 LSB RMS with the excitation off: the codes have that RMS (plus the
    // 1/12 LSB^2 of quantization) and zero mean.
    let mut p = CapParams::ideal(16, 800.0);
    p.noise_rms_v = 10.0 / 32768.0;
    p.seed = 42;
    let mut e = CapEncoder::new(p).expect("valid");
    let n = 200_000;
    let codes: Vec<f64> = (0..n)
        .map(|k| e.sample(k as f64 / FS, 0, 0) as f64)
        .collect();
    let mean = codes.iter().sum::<f64>() / n as f64;
    let rms = (codes.iter().map(|c| (c - mean).powi(2)).sum::<f64>() / n as f64).sqrt();
    let expect = (100.0f64 + 1.0 / 12.0).sqrt();
    eprintln!("noise: measured {rms:.4} LSB RMS (expected {expect:.4}), mean {mean:.4}");
    assert!((rms / expect - 1.0).abs() < 0.01, "{rms}");
    assert!(mean.abs() < 0.1, "{mean}");
    // And on top of the signal: the residual after subtracting the clean model.
    let mut e2 = CapEncoder::new(CapParams {
        noise_rms_v: 3.0 / 32768.0,
        ..CapParams::paper()
    })
    .expect("valid");
    let mut acc = 0.0;
    for k in 0..n {
        let t = k as f64 / FS;
        let (s, c, _) = exact_words(k, 16);
        let clean = e2.clean_volts(t, s, c) * 32768.0;
        acc += (e2.sample(t, s, c) as f64 - clean).powi(2);
    }
    let r = (acc / n as f64).sqrt();
    assert!((r / (9.0f64 + 1.0 / 12.0).sqrt() - 1.0).abs() < 0.01, "{r}");
}

#[test]
fn runs_are_deterministic_for_a_seed() {
    let noisy = |seed: u64| {
        let mut p = CapParams::paper();
        p.noise_rms_v = 1e-3;
        p.ripple = 0.01;
        p.feedthrough = 0.005;
        p.seed = seed;
        let mut e = CapEncoder::new(p).expect("valid");
        run(&mut e, 5000)
            .iter()
            .map(|x| x.1 as i64)
            .collect::<Vec<_>>()
    };
    assert_eq!(noisy(7), noisy(7));
    assert_ne!(noisy(7), noisy(8));
}

#[test]
fn saturation_is_counted_and_bad_parameters_rejected() {
    let mut p = CapParams::paper();
    p.coupling = 2.0;
    let mut e = CapEncoder::new(p).expect("valid");
    let s = run(&mut e, 2000);
    assert!(s.iter().any(|x| x.1 == 32767.0) && s.iter().any(|x| x.1 == -32768.0));
    assert!(e.saturations() > 0);
    // DAC words beyond the range are clamped.
    assert_eq!(e.dac_volts(1 << 20), e.dac_volts(32767));
    for f in [
        |p: &mut CapParams| p.periods_per_turn = 0,
        |p: &mut CapParams| p.dac_bits = 1,
        |p: &mut CapParams| p.coupling = 0.0,
        |p: &mut CapParams| p.ripple = 1.5,
        |p: &mut CapParams| p.feedthrough = f64::NAN,
        |p: &mut CapParams| p.noise_rms_v = -1.0,
        |p: &mut CapParams| p.adc_full_scale_v = 0.0,
    ] {
        let mut p = CapParams::paper();
        f(&mut p);
        let m = CapEncoder::new(p).expect_err("invalid").to_string();
        assert!(m.starts_with("capacitive encoder:"), "{m}");
    }
}
