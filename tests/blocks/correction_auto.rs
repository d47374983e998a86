//! Front-end correction: rust-hdl == model cycle for cycle, rust-hdl == Icarus ==
//! Verilator, the static formula against an independent f64 computation, saturation at
//! full scale, and the automatic calibration's convergence on a sinusoid with 5% offset
//! and 5% gain mismatch.
//!
//! (Second half of the tests of `tests/blocks/correction.rs`; helpers in `tests/blocks/correction_util/`.)
use crate::correction_util;
use correction_util::*;
use sinedec::blocks::correction::hdl::Correction;
use sinedec::blocks::correction::{gain_code, two_point, CorrectionParams, COS, SIN};
use sinedec::blocks::sext;
use sinedec::verify::Simulators;

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

#[test]
fn synthesizes_for_both_families_without_multipliers() {
    // Peak mode (`with_auto`, the peak tracker): the two 16x16 products of run-time gains
    // are shift-add trees (`multree.rs`), no MULT18X18 on Spartan-3A. (The tracker's
    // divider still has paths with two carry chains, so no path rule here.)
    let p = CorrectionParams::identity(14, 14)
        .unwrap()
        .with_auto(6000, 1, 1000)
        .unwrap();
    let (x, c) = synth(Correction::new(&p), "corr_synth_auto");
    assert_eq!(x.multipliers, 0);
    // Registers: pipeline about 200, calibration about 265 (masked words: A-bit peaks),
    // the two run-time trees about 220 each (910 in all with A = 14).
    assert!(x.ffs > 750 && x.ffs < 1000, "{} FF", x.ffs);
    // The same registers in both families (neither flow may keep what the other drops).
    assert_eq!(c.ffs, x.ffs);
    // Static mode has no calibration hardware at all, and its gains are constants: the
    // products are shift-add trees (15000 and 17000 have 7 and 6 one bits: 11 adders), no
    // hard multiplier, one carry chain per register-to-register path.
    let p = CorrectionParams::new(14, 14, [37, -100], [15000, 17000]).unwrap();
    let (x, _) = synth(Correction::new(&p), "corr_synth_static");
    eprintln!(
        "corr_synth_static: xc3sa {} LUT, {} FF, {} multipliers",
        x.luts, x.ffs, x.multipliers
    );
    assert_eq!(x.multipliers, 0);
    assert!(x.ffs < 600, "{} FF", x.ffs);
    let path = x.path.expect("a register-to-register path");
    assert!(path.carry_chains <= 1, "{path:?}");
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
    let lat = p.latency_cycles() as usize;
    ins.extend(vec![idle(); lat]);
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
    // A sample after the update is corrected with the new values (latency_cycles() = 6
    // clocks later: the run-time products' trees add 3).
    assert_eq!(lat, 6);
    let o = &out[probe + lat - 1];
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
