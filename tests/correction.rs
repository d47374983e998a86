//! Front-end correction: rust-hdl == model cycle for cycle, rust-hdl == Icarus ==
//! Verilator, the static formula against an independent f64 computation, saturation at
//! full scale, and the automatic calibration's convergence on a sinusoid with 5% offset
//! and 5% gain mismatch.
use sinedec::blocks::correction::hdl::Correction;
use sinedec::blocks::correction::model::{correct, CorrectionIn, CorrectionModel};
use sinedec::blocks::correction::{gain_code, two_point, CorrectionParams, COS, SIN};
use sinedec::blocks::{mask, sext};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::cosim::CosimBlock;
use sinedec::synth::{synthesize, Family, SynthStats};
use sinedec::verify::{block_traces, Simulators};
mod common;

const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

/// Runs `uut` on `rows`; asserts rust-hdl == `model` row by row and the Verilog simulators
/// == rust-hdl; returns the rust-hdl trace.
fn check<B: CosimBlock>(
    uut: B,
    tag: &str,
    rows: &[Vec<u64>],
    model: &[Vec<u64>],
    sims: Simulators,
) -> Vec<Vec<u64>> {
    let dir = common::workdir(tag);
    let t = block_traces(uut, tag, "clk", rows, sims, &dir).expect("simulators ran");
    for (k, (r, m)) in t.rust_hdl.iter().zip(model).enumerate() {
        assert_eq!(
            r, m,
            "{tag} row {k}: rust-hdl vs model (inputs {:?})",
            rows[k]
        );
    }
    assert_eq!(t.rust_hdl.len(), model.len());
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    t.rust_hdl
}

fn run(p: &CorrectionParams, tag: &str, ins: &[CorrectionIn], sims: Simulators) -> Vec<Vec<u64>> {
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = CorrectionModel::new(p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row(p.adc_width())).collect();
    check(Correction::new(p), tag, &rows, &model, sims)
}

fn sample(sin: i64, cos: i64) -> CorrectionIn {
    CorrectionIn {
        rst: false,
        valid: true,
        sin: sin as i32,
        cos: cos as i32,
    }
}

fn idle() -> CorrectionIn {
    CorrectionIn::default()
}

fn reset() -> CorrectionIn {
    CorrectionIn {
        rst: true,
        ..CorrectionIn::default()
    }
}

/// Directed and random A-bit samples: full-scale corners back to back, zero, +-1, the
/// offsets themselves and one LSB either side, raw words with junk above bit A, idle gaps
/// and resets in the middle of the stream.
fn stimulus(a: u32, offs: [i32; 2], n: usize, seed: u64) -> Vec<CorrectionIn> {
    let max = (1i64 << (a - 1)) - 1;
    let min = -(1i64 << (a - 1));
    let mut v = vec![reset(), reset()];
    let mut specials = vec![0, 1, -1, max, min, max - 1, min + 1, max / 2, min / 2];
    for o in offs {
        let o = o as i64;
        specials.extend(
            [o - 1, o, o + 1]
                .into_iter()
                .filter(|x| (min..=max).contains(x)),
        );
    }
    for &s in &specials {
        for &c in &specials {
            v.push(sample(s, c));
        }
    }
    v.push(reset());
    v.extend([
        sample(max, min),
        idle(),
        sample(min, max),
        reset(),
        sample(max, max),
    ]);
    let mut r = SplitMix64(seed);
    for k in 0..n {
        if r.unit() < 0.3 {
            v.push(idle());
        }
        if k % 997 == 500 {
            v.push(reset());
        }
        let mut x = sample(r.range(min, max), r.range(min, max));
        if r.unit() < 0.1 {
            // Junk above the A sample bits must be ignored.
            x.sin |= (r.next_u64() as i32) << a;
            x.cos |= (r.next_u64() as i32) << a;
        }
        v.push(x);
    }
    v
}

/// Independent reference: clamp(round_half_away((x - b) g / 2^GF)) in f64.
fn reference(x: i64, b: i64, g: u32, a: u32, gf: u32) -> i64 {
    let y = ((x - b) as f64 * g as f64 / (1u64 << gf) as f64).round();
    y.clamp(-(1i64 << (a - 1)) as f64, ((1i64 << (a - 1)) - 1) as f64) as i64
}

#[test]
fn static_correction_is_the_formula_with_three_cycle_latency() {
    let cases = [
        // (A, GF, offsets, gains): thesis default width, unity, strong gains, extremes.
        (
            14,
            14,
            [37, -1200],
            [gain_code(14, 1.25).unwrap(), gain_code(14, 0.8).unwrap()],
        ),
        (14, 14, [0, 0], [1 << 14, 1 << 14]),
        (16, 14, [-32768, 32767], [0xffff, 1]),
        (10, 8, [-3, 5], [gain_code(8, 1.0 / 1.07).unwrap(), 0]),
        (12, 15, [100, -100], [gain_code(15, 1.9).unwrap(), 32767]),
    ];
    for (i, (a, gf, offs, gains)) in cases.into_iter().enumerate() {
        let p = CorrectionParams::new(a, gf, offs, gains).unwrap();
        let ins = stimulus(a, offs, 3000, i as u64);
        let out = run(&p, &format!("corr_static{i}"), &ins, RUST_ONLY);
        let mut checked = 0;
        for k in 2..ins.len() {
            let want_valid = ins[k - 2].valid && !ins[k - 2].rst && !ins[k - 1].rst && !ins[k].rst;
            assert_eq!(out[k][0] == 1, want_valid, "case {i}: out_valid at row {k}");
            if ins[k - 2].rst {
                continue;
            }
            let x = &ins[k - 2];
            for (c, raw) in [(SIN, x.sin), (COS, x.cos)] {
                let xv = sext(raw as u64 & mask(a), a);
                let want = reference(xv, offs[c] as i64, gains[c], a, gf);
                assert_eq!(correct(xv, offs[c] as i64, gains[c] as u64, a, gf), want);
                assert_eq!(
                    sext(out[k][1 + c], a),
                    want,
                    "case {i}: channel {c} at row {k}: x = {xv}, b = {}, g = {}",
                    offs[c],
                    gains[c]
                );
                checked += 1;
            }
            assert_eq!(sext(out[k][3], a), offs[SIN] as i64);
            assert_eq!(sext(out[k][4], a), offs[COS] as i64);
            assert_eq!(out[k][5], gains[SIN] as u64);
            assert_eq!(out[k][6], gains[COS] as u64);
            assert_eq!(out[k][7], 0, "no calibration update in static mode");
        }
        assert!(checked > 4000);
    }
}

#[test]
fn full_scale_inputs_saturate_never_wrap() {
    let a = 14;
    let (max, min) = (8191i64, -8192i64);
    // g = 1.5: +-full scale would be +-12288; offsets of -8192 / 8191 double the range.
    let p = CorrectionParams::new(a, 14, [0, 0], [24576, 24576]).unwrap();
    let q = CorrectionParams::new(a, 14, [min as i32, max as i32], [1 << 14, 1 << 14]).unwrap();
    let ins = vec![
        reset(),
        sample(max, min),
        sample(min, max),
        sample(5462, -5462), // 8193 -> 8191, -8193 -> -8192
        sample(5461, -5461), // 8191.5 -> 8191 (saturated), -8191.5 -> -8192
        sample(5460, -5460), // 8190, -8190
        idle(),
        idle(),
        idle(),
    ];
    let out = run(&p, "corr_sat", &ins, Simulators::ALL);
    let got: Vec<(i64, i64)> = (3..8)
        .map(|k| (sext(out[k][1], a), sext(out[k][2], a)))
        .collect();
    assert_eq!(
        got,
        vec![
            (max, min),
            (min, max),
            (max, min),
            (max, min),
            (8190, -8190)
        ]
    );
    let out = run(&q, "corr_sat2", &ins, RUST_ONLY);
    // sin: x + 8192 (x = max -> 16383 -> max; x = min -> 0); cos: x - 8191.
    assert_eq!(sext(out[3][1], a), max);
    assert_eq!(sext(out[3][2], a), min);
    assert_eq!(sext(out[4][1], a), 0);
    assert_eq!(sext(out[4][2], a), 0);
}

#[test]
fn static_correction_in_three_simulators() {
    let offs = [-4000, 2500];
    let gains = [gain_code(14, 0.93).unwrap(), gain_code(14, 2.2).unwrap()];
    let p = CorrectionParams::new(16, 14, offs, gains).unwrap();
    let ins = stimulus(16, offs, 2000, 77);
    run(&p, "corr_static_cosim", &ins, Simulators::ALL);
    // The largest product: |d| = 65535 times g = 65535 (plus the rounding half) must not
    // overflow 32 bits in any simulator.
    let offs = [-32768, 32767];
    let p = CorrectionParams::new(16, 15, offs, [0xffff, 0xffff]).unwrap();
    let ins = stimulus(16, offs, 500, 78);
    let out = run(&p, "corr_static_cosim2", &ins, Simulators::ALL);
    let k = (2..ins.len())
        .find(|&k| ins[k - 2].sin == 32767 && ins[k - 2].cos == -32768)
        .unwrap();
    assert_eq!(
        (out[k][1], out[k][2]),
        (0x7fff, 0x8000),
        "saturated, not wrapped"
    );
}

/// A rotating vector: sin = amp_s sin(th) + off_s, cos = amp_c cos(th) + off_c, rounded,
/// plus uniform noise of +-`noise` LSB; `spp` samples per period (negative: backwards), one
/// sample every `gap` clocks.
#[allow(clippy::too_many_arguments)]
fn sinusoid(
    a: u32,
    amp: [f64; 2],
    off: [f64; 2],
    spp: f64,
    gap: usize,
    samples: usize,
    noise: f64,
    seed: u64,
) -> Vec<CorrectionIn> {
    let mut r = SplitMix64(seed);
    let lim = (1i64 << (a - 1)) as f64;
    let mut v = Vec::new();
    let th0 = r.unit() * std::f64::consts::TAU;
    for k in 0..samples {
        for _ in 1..gap {
            v.push(idle());
        }
        let th = th0 + std::f64::consts::TAU * k as f64 / spp;
        let s = amp[0] * th.sin() + off[0] + noise * (2.0 * r.unit() - 1.0);
        let c = amp[1] * th.cos() + off[1] + noise * (2.0 * r.unit() - 1.0);
        v.push(sample(
            s.round().clamp(-lim, lim - 1.0) as i64,
            c.round().clamp(-lim, lim - 1.0) as i64,
        ));
    }
    v
}

#[test]
fn auto_calibration_removes_five_percent_offset_and_gain_mismatch() {
    // A = 14, target amplitude T = 6000 LSB; true amplitudes 6000 * (1 +- 5%), offsets
    // +-5% of full scale (+-410 LSB); +-1 LSB noise; 157.3 samples per period.
    let (a, gf, t) = (14u32, 14u32, 6000u32);
    let amp = [6000.0 * 1.05, 6000.0 * 0.95];
    let off = [409.6, -409.6];
    for (k_periods, spp) in [(1u32, 157.3), (4, 157.3), (1, 611.7)] {
        let p = CorrectionParams::identity(a, gf)
            .unwrap()
            .with_auto(t, k_periods, 1000)
            .unwrap();
        let periods = 3 + 2 * k_periods as usize;
        let mut ins = vec![reset(), reset()];
        ins.extend(sinusoid(
            a,
            amp,
            off,
            spp,
            3,
            (spp * periods as f64) as usize,
            1.0,
            5,
        ));
        let out = run(&p, "corr_auto", &ins, RUST_ONLY);
        // First update: after at most 1/4 period to the first boundary, K periods and
        // the 66-clock computation.
        let updates: Vec<usize> = (0..out.len()).filter(|&k| out[k][7] == 1).collect();
        let first = updates[0];
        let bound = 2 + ((0.3 + k_periods as f64) * spp * 3.0) as usize + 66 + 3 * 3;
        assert!(first <= bound, "first update at row {first}, bound {bound}");
        assert!(updates.len() >= 2, "later windows update again");
        eprintln!(
            "K={k_periods} spp={spp}: first update after {:.2} periods, {} updates",
            (first - 2) as f64 / (3.0 * spp),
            updates.len()
        );
        // Open loop: the values right after the first update are already converged; check
        // them and the final ones.
        let mut worst_off = 0f64;
        let mut worst_gain = 0f64;
        for (when, row) in [("first", &out[first]), ("last", out.last().unwrap())] {
            for c in [SIN, COS] {
                let b = sext(row[3 + c], a) as f64;
                let g = row[5 + c] as f64 / (1u64 << gf) as f64;
                // Residual offset of the corrected signal, and its amplitude against T.
                let res_off = (off[c] - b) * g;
                let gain_err = amp[c] * g / t as f64 - 1.0;
                eprintln!(
                    "K={k_periods} spp={spp} {when} ch{c}: b = {b} (true {}), g = {:.5} \
                     (ideal {:.5}): residual offset {res_off:+.3} LSB, gain error {:+.4}%",
                    off[c],
                    g,
                    t as f64 / amp[c],
                    100.0 * gain_err
                );
                worst_off = worst_off.max(res_off.abs());
                worst_gain = worst_gain.max(gain_err.abs());
            }
        }
        // The corrected output over the last full period: offset and amplitude measured.
        let tail: Vec<&Vec<u64>> = out[out.len() - (spp * 3.0) as usize..]
            .iter()
            .filter(|o| o[0] == 1)
            .collect();
        for c in [SIN, COS] {
            let ys: Vec<i64> = tail.iter().map(|o| sext(o[1 + c], a)).collect();
            let (mx, mn) = (*ys.iter().max().unwrap(), *ys.iter().min().unwrap());
            let mid = (mx + mn) as f64 / 2.0;
            let ampl = (mx - mn) as f64 / 2.0;
            eprintln!(
                "K={k_periods} spp={spp} ch{c}: output peaks {mn}..{mx}: offset {mid:+.1} LSB, \
                 amplitude {ampl} ({:+.3}% vs T)",
                100.0 * (ampl / t as f64 - 1.0)
            );
            assert!(mid.abs() <= 2.0, "measured output offset {mid}");
            assert!(
                (ampl / t as f64 - 1.0).abs() < 0.005,
                "measured output amplitude {ampl}"
            );
        }
        assert!(worst_off < 1.0, "residual offset {worst_off} LSB");
        assert!(worst_gain < 0.005, "gain error {worst_gain}");
    }
}

/// Calibration stimulus for the model/RTL comparison: sinusoids of changing speed and
/// direction (including faster than the divider: windows are dropped), small amplitudes
/// (no update), two-quadrant jumps, chatter, resets in the middle of a division.
fn auto_stimulus(a: u32, n_segments: usize, seed: u64) -> Vec<CorrectionIn> {
    let mut r = SplitMix64(seed);
    let full = ((1i64 << (a - 1)) - 1) as f64;
    let mut v = vec![reset(), reset()];
    for _ in 0..n_segments {
        let kind = r.range(0, 9);
        let amp = [full * (0.3 + 0.8 * r.unit()), full * (0.3 + 0.8 * r.unit())];
        let off = [full * 0.2 * (r.unit() - 0.5), full * 0.2 * (r.unit() - 0.5)];
        let spp = match kind {
            0 => -(8.0 + 40.0 * r.unit()),
            1 => 8.0 + 10.0 * r.unit(),
            _ => (20.0 + 100.0 * r.unit()) * if r.unit() < 0.3 { -1.0 } else { 1.0 },
        };
        let gap = if kind == 1 { 1 } else { r.range(1, 4) as usize };
        let samples = (spp.abs() * (1.0 + 3.0 * r.unit())) as usize;
        let small = if kind == 2 { 0.05 } else { 1.0 };
        let mut seg = sinusoid(
            a,
            [amp[0] * small, amp[1] * small],
            off,
            spp,
            gap,
            samples,
            if kind == 3 { 40.0 } else { 1.0 },
            r.next_u64(),
        );
        if kind == 4 {
            let at = r.range(0, seg.len() as i64 - 1) as usize;
            seg[at] = reset();
        }
        if kind == 5 {
            // A two-quadrant jump: negate one sample.
            let at = r.range(0, seg.len() as i64 - 1) as usize;
            seg[at].sin = -seg[at].sin;
            seg[at].cos = -seg[at].cos;
        }
        v.extend(seg);
    }
    v
}

#[test]
fn auto_calibration_matches_model_in_three_simulators() {
    let a = 12;
    let p = CorrectionParams::new(a, 13, [10, -20], [8192, 8000])
        .unwrap()
        .with_auto(1500, 1, 300)
        .unwrap();
    let ins = auto_stimulus(a, 40, 21);
    let out = run(&p, "corr_auto_cosim", &ins, Simulators::ALL);
    let updates = out.iter().filter(|o| o[7] == 1).count();
    assert!(updates >= 5, "{updates} calibration updates were exercised");
}

#[test]
fn auto_calibration_matches_model_over_long_runs() {
    for (i, (a, gf, t, k, minamp)) in [
        (14u32, 14u32, 6000u32, 1u32, 500u32),
        (16, 15, 30000, 3, 4000),
        (10, 8, 400, 2, 50),
    ]
    .into_iter()
    .enumerate()
    {
        let p = CorrectionParams::identity(a, gf)
            .unwrap()
            .with_auto(t, k, minamp)
            .unwrap();
        let ins = auto_stimulus(a, 120, 100 + i as u64);
        let out = run(&p, &format!("corr_auto_long{i}"), &ins, RUST_ONLY);
        let updates = out.iter().filter(|o| o[7] == 1).count();
        assert!(
            updates >= 5,
            "case {i}: {updates} calibration updates were exercised"
        );
    }
}

#[test]
fn small_signals_do_not_update_the_calibration() {
    let p = CorrectionParams::new(14, 14, [3, 4], [16000, 17000])
        .unwrap()
        .with_auto(6000, 1, 1000)
        .unwrap();
    let mut ins = vec![reset()];
    // Amplitude 900 < min_amplitude 1000: four periods, no update.
    ins.extend(sinusoid(
        14,
        [900.0, 900.0],
        [0.0, 0.0],
        50.0,
        2,
        200,
        0.0,
        1,
    ));
    let out = run(&p, "corr_small", &ins, RUST_ONLY);
    assert!(out.iter().all(|o| o[7] == 0));
    let l = out.last().unwrap();
    assert_eq!((l[3], l[4], l[5], l[6]), (3, 4, 16000, 17000));
}

#[test]
fn two_point_calibration_follows_the_thesis_equations() {
    // Ideal codes x_l = -4000, x_h = 4000 read back as y = 1.1 x + 50.
    let (b, g) = two_point(
        14,
        1.1 * 4000.0 + 50.0,
        1.1 * -4000.0 + 50.0,
        4000.0,
        -4000.0,
    )
    .unwrap();
    assert_eq!(b, 50);
    assert_eq!(g, (16384.0 / 1.1f64).round() as u32);
    assert!(two_point(14, 1.0, 1.0, 2.0, 1.0).is_err());
}

#[test]
fn bad_parameters_are_rejected_with_a_message() {
    assert!(CorrectionParams::new(9, 14, [0, 0], [0, 0])
        .unwrap_err()
        .to_string()
        .contains("ADC width"));
    assert!(CorrectionParams::new(17, 14, [0, 0], [0, 0]).is_err());
    assert!(CorrectionParams::new(14, 16, [0, 0], [0, 0])
        .unwrap_err()
        .to_string()
        .contains("fraction"));
    assert!(CorrectionParams::new(14, 14, [8192, 0], [0, 0])
        .unwrap_err()
        .to_string()
        .contains("offset"));
    assert!(CorrectionParams::new(14, 14, [0, -8193], [0, 0]).is_err());
    assert!(CorrectionParams::new(14, 14, [0, 0], [0, 65536])
        .unwrap_err()
        .to_string()
        .contains("gain"));
    let ok = CorrectionParams::identity(14, 14).unwrap();
    assert!(ok
        .with_auto(0, 1, 1)
        .unwrap_err()
        .to_string()
        .contains("target"));
    assert!(ok.with_auto(8192, 1, 1).is_err());
    assert!(ok
        .with_auto(6000, 0, 1)
        .unwrap_err()
        .to_string()
        .contains("periods"));
    assert!(ok.with_auto(6000, 257, 1).is_err());
    assert!(ok
        .with_auto(6000, 1, 0)
        .unwrap_err()
        .to_string()
        .contains("minimum"));
    assert!(gain_code(14, 4.0).is_err());
    assert!(gain_code(14, -0.1).is_err());
    assert_eq!(gain_code(14, 1.0).unwrap(), 16384);
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
fn synthesizes_for_both_families_with_two_multipliers() {
    // Auto mode: two 16x16 products (MULT18X18 on Spartan-3A); Yosys's cycloneive flow
    // has no multiplier mapping and builds them from logic cells.
    let p = CorrectionParams::identity(14, 14)
        .unwrap()
        .with_auto(6000, 1, 1000)
        .unwrap();
    let (x, c) = synth(Correction::new(&p), "corr_synth_auto");
    assert_eq!(x.multipliers, 2);
    // Registers: pipeline about 200, calibration about 265 (masked words: A-bit peaks).
    // The same registers in both families (neither flow may keep what the other drops).
    assert!(x.ffs > 350 && x.ffs < 520, "{} FF", x.ffs);
    assert_eq!(c.ffs, x.ffs);
    // Static mode has no calibration hardware at all.
    let p = CorrectionParams::new(14, 14, [37, -100], [15000, 17000]).unwrap();
    let (x, _) = synth(Correction::new(&p), "corr_synth_static");
    assert_eq!(x.multipliers, 2);
    assert!(x.ffs < 130, "{} FF", x.ffs);
}

#[test]
fn auto_calibration_timing_and_arithmetic_on_one_directed_period() {
    // One quadrant per sample, back to back: q0, then q1 (the window opens at this first
    // boundary), q2, q3, q0, q1 (net count +4: the window completes with this sample).
    let (a, gf, t) = (14u32, 14u32, 1000u32);
    let p = CorrectionParams::identity(a, gf)
        .unwrap()
        .with_auto(t, 1, 500)
        .unwrap();
    let pts: [(i64, i64); 6] = [
        (1000, 1000),
        (1200, -900),
        (-800, -1100),
        (-1300, 700),
        (900, 1250),
        (1100, -1000),
    ];
    let mut ins = vec![reset()];
    ins.extend(pts.iter().map(|&(s, c)| sample(s, c)));
    let done = ins.len() - 1;
    ins.extend(vec![idle(); 80]);
    let probe = ins.len();
    ins.push(sample(3000, -3000));
    ins.extend(vec![idle(); 3]);
    let out = run(&p, "corr_auto_directed", &ins, Simulators::ALL);
    let updates: Vec<usize> = (0..out.len()).filter(|&k| out[k][7] == 1).collect();
    assert_eq!(
        updates,
        vec![done + 66],
        "new values 66 clocks after the window's sample"
    );
    // Independent arithmetic over the window's samples (the opening one to the completing
    // one): b = floor((max + min + 1) / 2), g = floor((T 2^(GF+1) + floor(S/2)) / S).
    let mut want = [(0i64, 0u64); 2];
    for c in [SIN, COS] {
        let xs: Vec<i64> = pts[1..]
            .iter()
            .map(|p| if c == SIN { p.0 } else { p.1 })
            .collect();
        let (mx, mn) = (*xs.iter().max().unwrap(), *xs.iter().min().unwrap());
        let s = (mx - mn) as u64;
        let b = (mx + mn + 1).div_euclid(2);
        let g = (((t as u64) << (gf + 1)) + s / 2) / s;
        // The same within one code as round(T / (S/2) * 2^GF) in f64.
        let gf64 = (t as f64 / (s as f64 / 2.0) * (1u64 << gf) as f64).round();
        assert!((g as f64 - gf64).abs() <= 1.0);
        want[c] = (b, g);
    }
    assert_eq!(want, [(-50, 13107), (75, 13944)]);
    let k = done + 66;
    assert_eq!(out[k - 1][5], 1 << gf, "old gain until the update");
    for c in [SIN, COS] {
        assert_eq!(sext(out[k][3 + c], a), want[c].0, "offset of channel {c}");
        assert_eq!(out[k][5 + c], want[c].1, "gain of channel {c}");
    }
    // A sample after the update is corrected with the new values (3 clocks later).
    let o = &out[probe + 2];
    assert_eq!(o[0], 1);
    assert_eq!(
        sext(o[1], a),
        reference(3000, want[SIN].0, want[SIN].1 as u32, a, gf)
    );
    assert_eq!(
        sext(o[2], a),
        reference(-3000, want[COS].0, want[COS].1 as u32, a, gf)
    );
}
