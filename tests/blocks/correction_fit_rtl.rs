//! The ellipse-fit calibration in RTL (`blocks::correction::fit_hdl`, `fit_solve`) against
//! its integer model (`blocks::correction::fit::EllipseFit`): every update the model makes
//! appears in rust-hdl with the same offsets, gains and cross code a fixed number of clocks
//! after the window's last sample (unless a reset comes first), and nothing else appears;
//! Icarus and Verilator equal rust-hdl on every output at every clock. Streams: windows at
//! 3.8 and at 1000 samples per period, both directions, one sample per clock and sparse
//! samples, an amplitude below the minimum (no update), resets in the middle of a solve,
//! and three parameter sets (A = 14, GF = 14; A = 16, GF = 15; A = 10, GF = 8).
use crate::common;
use crate::correction_util;
use sinedec::blocks::correction::fit::{Coefs, EllipseFit, FitParams};
use sinedec::blocks::correction::fit_hdl::{FitCal, FitConsts};
use sinedec::blocks::correction::fit_solve::{SolveConsts, UPDATE_LATENCY};
use sinedec::blocks::correction::CorrectionParams;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::Simulators;
use std::f64::consts::TAU;

/// One stimulus row: rst, valid, x_sin, x_cos (raw A-bit words).
type Row = [i64; 4];

fn params(a: u32, gf: u32, k: u32, min_samples: u32) -> FitParams {
    let full = (1u32 << (a - 1)) - 1;
    FitParams {
        adc_width: a,
        gain_frac_bits: gf,
        target_amplitude: full * 3 / 4,
        periods: k,
        min_samples,
        min_amplitude: full / 10,
    }
}

fn start(p: &FitParams) -> Coefs {
    Coefs {
        offset: [0, 0],
        gain: [1 << p.gain_frac_bits; 2],
        cross: 0,
    }
}

/// `n` samples of a distorted sinusoid at `spp` samples per period (negative: backwards),
/// one every `gap` clocks; amplitude `amp` of full scale, 3 % offsets, 4 % gain mismatch,
/// 3 deg phase error, +-1 LSB noise.
fn sinusoid(a: u32, amp: f64, spp: f64, gap: usize, n: usize, seed: u64) -> Vec<Row> {
    let mut r = SplitMix64(seed);
    let full = ((1i64 << (a - 1)) - 1) as f64;
    let lim = (1i64 << (a - 1)) as f64;
    let th0 = r.unit() * TAU;
    let mut v = Vec::new();
    for j in 0..n {
        for _ in 1..gap {
            v.push([0, 0, r.range(-100, 100), 0]);
        }
        let t = th0 + TAU * j as f64 / spp;
        let mut noise = || r.unit() - r.unit();
        let s = amp * full * 1.02 * t.sin() + 0.03 * full + noise();
        let c = amp * full * 0.98 * (t + 3f64.to_radians()).cos() - 0.03 * full + noise();
        v.push([
            0,
            1,
            s.round().clamp(-lim, lim - 1.0) as i64,
            c.round().clamp(-lim, lim - 1.0) as i64,
        ]);
    }
    v
}

fn idle(n: usize) -> Vec<Row> {
    vec![[0, 0, 0, 0]; n]
}

/// Runs `rows` through the RTL (rust-hdl, and `sims`) and the model; returns the number of
/// updates. Panics on any difference.
fn check(p: FitParams, tag: &str, rows: &[Row], sims: Simulators) -> usize {
    let a = p.adc_width;
    let amask = (1u64 << 16) - 1;
    let cp = CorrectionParams::identity(a, p.gain_frac_bits).expect("params");
    let k = FitConsts {
        solve: SolveConsts {
            adc_width: a,
            gain_frac_bits: p.gain_frac_bits,
            target_amplitude: p.target_amplitude,
            min_amplitude: p.min_amplitude,
        },
        periods: p.periods,
        min_samples: p.min_samples,
    };
    let raw: Vec<Vec<u64>> = rows
        .iter()
        .map(|r| {
            vec![
                r[0] as u64,
                r[1] as u64,
                r[2] as u64 & amask,
                r[3] as u64 & amask,
            ]
        })
        .collect();
    let dir = common::workdir(tag);
    let t = sinedec::verify::block_traces(FitCal::new(&cp, k), tag, "clk", &raw, sims, &dir)
        .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    // The model, clock by clock: an update of the window ending at row j is due at row
    // j + UPDATE_LATENCY, cancelled by a reset up to then.
    let mut m = EllipseFit::new(p, start(&p));
    let mut due: Vec<(usize, Coefs)> = Vec::new();
    let mut windows = 0;
    for (j, r) in rows.iter().enumerate() {
        if r[0] != 0 {
            due.retain(|(at, _)| *at < j);
            m = EllipseFit::new(p, start(&p));
            continue;
        }
        if r[1] != 0 {
            let before = m.counts().0;
            if let Some(c) = m.sample(r[2], r[3]) {
                due.push((j + UPDATE_LATENCY as usize, c));
            }
            windows += (m.counts().0 - before) as usize;
        }
    }
    let sx = |v: u64| (v as u32) as i32 as i64;
    let got: Vec<(usize, Coefs)> = t
        .rust_hdl
        .iter()
        .enumerate()
        .filter(|(_, o)| o[6] != 0)
        .map(|(j, o)| {
            let km = o[4] as i64;
            (
                j,
                Coefs {
                    offset: [sx(o[0]), sx(o[1])],
                    gain: [o[2], o[3]],
                    cross: if o[5] != 0 { -km } else { km },
                },
            )
        })
        .collect();
    let due: Vec<_> = due.into_iter().filter(|(at, _)| *at < rows.len()).collect();
    eprintln!(
        "{tag}: {} rows, {windows} model windows, {} updates (model) / {} (rtl)",
        rows.len(),
        due.len(),
        got.len()
    );
    assert_eq!(
        got, due,
        "{tag}: RTL updates (row, coefficients) vs the model"
    );
    got.len()
}

#[test]
fn fit_rtl_equals_the_model_at_1000_samples_per_period_in_four_simulators() {
    // One sample every 3 clocks: a window of one period lasts 3000 clocks > UPDATE_LATENCY.
    let p = params(14, 14, 1, 600);
    let mut rows = vec![[1, 0, 0, 0]; 2];
    rows.extend(sinusoid(14, 0.75, 1000.0, 3, 3500, 1));
    rows.extend(idle(UPDATE_LATENCY as usize + 4));
    assert!(check(p, "fit_rtl_1000", &rows, Simulators::ALL) >= 2);
}

#[test]
fn fit_rtl_equals_the_model_at_3_8_samples_per_period_in_four_simulators() {
    // K = 2 periods, 300 samples, one sample every 8 clocks: windows of ~2400 clocks.
    let p = params(14, 14, 2, 300);
    let mut rows = vec![[1, 0, 0, 0]; 2];
    rows.extend(sinusoid(14, 0.75, 3.8, 8, 1000, 2));
    rows.extend(sinusoid(14, 0.75, -3.8, 8, 700, 3));
    rows.extend(idle(UPDATE_LATENCY as usize + 4));
    assert!(check(p, "fit_rtl_3p8", &rows, Simulators::ALL) >= 3);
}

#[test]
fn fit_rtl_resets_mid_solve_and_refuses_small_amplitudes() {
    let p = params(14, 14, 1, 200);
    let mut rows = vec![[1, 0, 0, 0]; 2];
    // Windows (200 samples x 12 clocks) close; a reset 400 clocks after one closes aborts
    // its solve.
    rows.extend(sinusoid(14, 0.75, 50.0, 12, 260, 4));
    rows.extend(idle(400));
    rows.push([1, 0, 0, 0]);
    rows.extend(sinusoid(14, 0.75, 37.0, 12, 600, 5));
    // Below the minimum amplitude: windows close, no update.
    rows.extend(sinusoid(14, 0.05, 40.0, 12, 500, 6));
    rows.extend(idle(UPDATE_LATENCY as usize + 4));
    let n = check(p, "fit_rtl_reset", &rows, Simulators::ALL);
    assert!(n >= 1, "{n}");
}

#[test]
fn fit_rtl_equals_the_model_at_other_widths() {
    for (i, (a, gf)) in [(16u32, 15u32), (10, 8)].into_iter().enumerate() {
        // 600 samples at >= 4 clocks each: every window outlasts the solve.
        let p = params(a, gf, 1, 600);
        let mut rows = vec![[1, 0, 0, 0]; 2];
        rows.extend(sinusoid(a, 0.9, 25.0, 5, 1300, 7 + i as u64));
        rows.extend(sinusoid(a, 0.6, -90.0, 4, 2500, 9 + i as u64));
        rows.extend(idle(UPDATE_LATENCY as usize + 4));
        let n = check(p, &format!("fit_rtl_w{a}"), &rows, Simulators::ALL);
        assert!(n >= 2, "{n}");
    }
}

/// The whole correction block in auto mode (datapath, phase stage with the fit's k, the
/// fit): Yosys for xc3sa and cycloneive, every register-to-register path on xc3sa with at
/// most one carry chain (the timing rule), and no hard multiplier: the sin and cos gain
/// products, the cross product with the fit's k and the fit's three sample products are
/// run-time shift-add trees (`multree.rs`).
#[test]
fn fit_mode_synthesizes_without_multipliers_and_one_carry_chain_per_path() {
    use sinedec::blocks::correction::hdl::Correction;
    let p = CorrectionParams::identity(14, 14)
        .and_then(|p| p.with_fit(6143, 1, 819, 4096))
        .expect("params");
    let (x, c) = correction_util::synth(Correction::new(&p), "corr_synth_fit");
    let path = x.path.expect("a register-to-register path");
    eprintln!(
        "corr_synth_fit: xc3sa {} LUT, {} FF, {} MULT18X18; cycloneive {} LE, {} FF; worst path {} -> {}: {} carry chains, {} LUT levels",
        x.luts, x.ffs, x.multipliers, c.luts, c.ffs, path.from, path.to, path.carry_chains, path.lut_levels
    );
    assert_eq!(x.multipliers, 0);
    assert!(path.carry_chains <= 1, "{path:?}");
}
