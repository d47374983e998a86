//! Front-end correction: rust-hdl == model cycle for cycle, rust-hdl == Icarus ==
//! Verilator, the static formula against an independent f64 computation, saturation at
//! full scale, and the automatic calibration's convergence on a sinusoid with 5% offset
//! and 5% gain mismatch.
//!
//! (More tests in `tests/blocks/correction_auto.rs`; the helpers are in `tests/blocks/correction_util/`.)
use crate::correction_util;
use correction_util::*;
use sinedec::blocks::correction::model::correct;
use sinedec::blocks::correction::{gain_code, CorrectionParams, COS, SIN};
use sinedec::blocks::{mask, sext};
use sinedec::verify::Simulators;

#[test]
fn static_correction_is_the_formula_with_three_or_six_cycle_latency() {
    // Latency 3 when every gain code is 0 or a power of two (the product is a shift);
    // otherwise the constant products are shift-add trees with three more register levels
    // (module doc of `multree.rs`): 6.
    let cases = [
        // (A, GF, offsets, gains, latency): thesis default width, unity, strong gains,
        // extremes.
        (
            14,
            14,
            [37, -1200],
            [gain_code(14, 1.25).unwrap(), gain_code(14, 0.8).unwrap()],
            6,
        ),
        (14, 14, [0, 0], [1 << 14, 1 << 14], 3),
        (16, 14, [-32768, 32767], [0xffff, 1], 6),
        (10, 8, [-3, 5], [gain_code(8, 1.0 / 1.07).unwrap(), 0], 6),
        (12, 15, [100, -100], [gain_code(15, 1.9).unwrap(), 32767], 6),
        (12, 12, [100, -100], [1 << 13, 0], 3),
    ];
    for (i, (a, gf, offs, gains, lat)) in cases.into_iter().enumerate() {
        let p = CorrectionParams::new(a, gf, offs, gains).unwrap();
        assert_eq!(p.latency_cycles(), lat, "case {i}");
        // A sample presented before edge k comes out after edge k + lat - 1: lat - 1 rows on.
        let l = lat as usize - 1;
        let ins = stimulus(a, offs, 3000, i as u64);
        let out = run(&p, &format!("corr_static{i}"), &ins, RUST_ONLY);
        let mut checked = 0;
        for k in l..ins.len() {
            let want_valid = ins[k - l].valid && (k - l..=k).all(|j| !ins[j].rst);
            assert_eq!(out[k][0] == 1, want_valid, "case {i}: out_valid at row {k}");
            if ins[k - l].rst {
                continue;
            }
            let x = &ins[k - l];
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
        idle(),
        idle(),
        idle(),
    ];
    // g = 24576 is not a power of two: shift-add products, latency 6 (rows 1..5 -> 6..10).
    assert_eq!(p.latency_cycles(), 6);
    let out = run(&p, "corr_sat", &ins, Simulators::ALL);
    let got: Vec<(i64, i64)> = (6..11)
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
    assert_eq!(q.latency_cycles(), 3);
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
    let l = p.latency_cycles() as usize - 1;
    let k = (l..ins.len())
        .find(|&k| ins[k - l].sin == 32767 && ins[k - l].cos == -32768)
        .unwrap();
    assert_eq!(
        (out[k][1], out[k][2]),
        (0x7fff, 0x8000),
        "saturated, not wrapped"
    );
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
