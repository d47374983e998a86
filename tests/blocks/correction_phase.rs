//! Static phase correction of the cos track: the fixed-point formula against an independent
//! integer computation (5-clock latency, 8 with shift-add products), rust-hdl == model ==
//! Icarus == Verilator, a 3 degree phase error removed from a sampled sinusoid, no phase
//! hardware at phase 0, and the synthesized stage (shift-add products, no hard multiplier,
//! one carry chain per register-to-register path).
//!
//! (Helpers in `tests/blocks/correction_util/`.)
use crate::correction_util;
use correction_util::*;
use sinedec::blocks::correction::hdl::Correction;
use sinedec::blocks::correction::model::correct_phase;
use sinedec::blocks::correction::{gain_code, phase_codes, CorrectionParams, COS, SIN};
use sinedec::blocks::{mask, sext};
use sinedec::verify::Simulators;
use std::f64::consts::PI;

/// Independent reference: clamp(floor(S / 2^F + 1/2)) with S = sgn(d_c) floor(|d_c| g_c /
/// 2^s) + sgn(d_s k) floor(|d_s k| / 2^s), s = max(0, A - 14), F = GF - s, in i128 (for A <= 14,
/// s = 0 and this is round-half-up of the exact (d_c g_c + d_s k) / 2^GF).
fn reference(xs: i64, xc: i64, b: [i32; 2], gc: u32, k: i32, a: u32, gf: u32) -> i64 {
    let s = a.saturating_sub(14);
    let (ds, dc) = ((xs - b[0] as i64) as i128, (xc - b[1] as i64) as i128);
    let trunc = |v: i128| v.signum() * (v.abs() >> s);
    let sum = trunc(dc * gc as i128) + trunc(ds * k as i128);
    let f = gf - s;
    let r = (2 * sum + (1i128 << f)).div_euclid(1i128 << (f + 1));
    r.clamp(-(1i128 << (a - 1)), (1i128 << (a - 1)) - 1) as i64
}

fn params(a: u32, gf: u32, offs: [i32; 2], gs: f64, gc: f64, deg: f64) -> CorrectionParams {
    let g_s = gain_code(gf, gs).unwrap();
    let (g_c, k) = phase_codes(gf, gs, gc, deg).unwrap();
    CorrectionParams::new(a, gf, offs, [g_s, g_c])
        .unwrap()
        .with_phase(k)
        .unwrap()
}

#[test]
fn phase_correction_is_the_formula_with_eight_cycle_latency() {
    let cases = [
        (14, 14, [37, -1200], 1.25, 0.8, 3.0),
        (14, 14, [0, 0], 1.0, 1.0, -7.5),
        (16, 15, [-32768, 32767], 1.9, 1.9, 15.0),
        (16, 14, [100, -90], 1.0, 1.02, -15.0),
        (15, 13, [5, 5], 0.7, 3.5, 1.0),
        (10, 8, [-3, 5], 1.0 / 1.07, 1.1, -2.0),
        (12, 15, [100, -100], 0.9, 0.95, 0.5),
    ];
    for (i, (a, gf, offs, gs, gcf, deg)) in cases.into_iter().enumerate() {
        let p = params(a, gf, offs, gs, gcf, deg);
        // 3 + the phase stage's 2 (sum; round and compare, then select) + the shift-add
        // trees' 3 (every case has a non-zero cross code k and a folded cos gain that are not
        // powers of two).
        assert!(p.has_phase() && p.latency_cycles() == 8, "case {i}");
        let (gc, k) = (p.gain()[COS], p.cross());
        // The codes are the folded gain and g_s tan(phi), independently rounded here.
        let scale = (1u64 << gf) as f64;
        let phi = deg * PI / 180.0;
        assert_eq!(gc as f64, (gcf / phi.cos() * scale).round(), "case {i}");
        assert_eq!(k as f64, (gs * phi.tan() * scale).round(), "case {i}");
        let ins = stimulus(a, offs, 3000, 40 + i as u64);
        let out = run(&p, &format!("corr_phase{i}"), &ins, RUST_ONLY);
        let mut checked = 0;
        for k_row in 7..ins.len() {
            let x = &ins[k_row - 7];
            let clean = (k_row - 7..=k_row).all(|j| !ins[j].rst);
            assert_eq!(
                out[k_row][0] == 1,
                x.valid && clean,
                "case {i}: row {k_row}"
            );
            if x.rst || !x.valid {
                continue;
            }
            let xs = sext(x.sin as u64 & mask(a), a);
            let xc = sext(x.cos as u64 & mask(a), a);
            let want_c = reference(xs, xc, offs, gc, k, a, gf);
            let s = p.phase_shift();
            assert_eq!(
                correct_phase(
                    xs,
                    xc,
                    offs[0] as i64,
                    offs[1] as i64,
                    gc as u64,
                    k as i64,
                    a,
                    gf,
                    s
                ),
                want_c
            );
            let want_s = correction_util::reference(xs, offs[SIN] as i64, p.gain()[SIN], a, gf);
            assert_eq!(
                sext(out[k_row][1], a),
                want_s,
                "case {i}: sin at row {k_row}"
            );
            assert_eq!(
                sext(out[k_row][2], a),
                want_c,
                "case {i}: cos at row {k_row}: xs = {xs}, xc = {xc}, g_c = {gc}, k = {k}"
            );
            // Against the real-valued formula (d_c g_c + d_s k) / 2^GF: within the rounding
            // half plus the truncation of the two products (2 / 2^F).
            let ideal = ((xc - offs[1] as i64) as f64 * gc as f64
                + (xs - offs[0] as i64) as f64 * k as f64)
                / scale;
            let lim = (1i64 << (a - 1)) as f64;
            if ideal.abs() < lim - 2.0 {
                let f = gf - s;
                let tol = 0.5 + 2.0 / (1u64 << f) as f64 + 1e-9;
                assert!(
                    (sext(out[k_row][2], a) as f64 - ideal).abs() <= tol,
                    "case {i}"
                );
            }
            checked += 1;
        }
        assert!(checked > 2000, "case {i}: {checked}");
    }
}

#[test]
fn phase_correction_in_four_simulators() {
    // Default width with a negative phase; the widest word (A = 16, GF = 15, s = 2) with the
    // largest products and saturation both ways; a narrow one with a positive phase.
    for (i, (a, gf, offs, gs, gc, deg)) in [
        (14u32, 14u32, [-300, 410], 1.04, 0.96, -3.0),
        (16, 15, [-32768, 32767], 1.99, 1.9, 15.0),
        (10, 8, [7, -9], 1.0, 1.0, 12.0),
    ]
    .into_iter()
    .enumerate()
    {
        let p = params(a, gf, offs, gs, gc, deg);
        let ins = stimulus(a, offs, 1500, 90 + i as u64);
        let out = run(&p, &format!("corr_phase_cosim{i}"), &ins, Simulators::ALL);
        let lim = 1u64 << (a - 1);
        let sat = out
            .iter()
            .filter(|o| o[0] == 1 && (o[2] == lim - 1 || o[2] == lim))
            .count();
        if i == 1 {
            assert!(sat > 10, "saturation exercised: {sat}");
        }
    }
}

/// Angle error (rad) of atan2(sin, cos) against the true angle, worst over the samples.
fn worst_angle_error(
    p: &CorrectionParams,
    tag: &str,
    amp: [f64; 2],
    off: [f64; 2],
    phi: f64,
) -> f64 {
    let a = p.adc_width();
    let n = 2000;
    let mut ins = vec![reset()];
    let mut th = Vec::new();
    for j in 0..n {
        let t = 2.0 * PI * j as f64 / 157.3 + 0.3;
        th.push(t);
        let s = amp[0] * t.sin() + off[0];
        let c = amp[1] * (t + phi).cos() + off[1];
        ins.push(sample(s.round() as i64, c.round() as i64));
    }
    let lat = p.latency_cycles() as usize - 1;
    ins.extend(vec![idle(); lat + 1]);
    let out = run(p, tag, &ins, RUST_ONLY);
    let mut worst = 0f64;
    for (j, t) in th.iter().enumerate() {
        let o = &out[1 + j + lat];
        assert_eq!(o[0], 1);
        let e = (sext(o[1], a) as f64).atan2(sext(o[2], a) as f64) - t;
        let e = (e + PI).rem_euclid(2.0 * PI) - PI;
        worst = worst.max(e.abs());
    }
    worst
}

#[test]
fn a_three_degree_phase_error_is_removed() {
    // A = 14, amplitudes 6000 (1 +- 2%), offsets, cos leading by 3 degrees.
    let (a, gf) = (14u32, 14u32);
    let amp = [6000.0 * 1.02, 6000.0 * 0.98];
    let off = [120.0, -80.0];
    let phi = 3.0f64.to_radians();
    let (gs, gc) = (1.0 / 1.02, 1.0 / 0.98);
    let offs = [120, -80];
    let without = CorrectionParams::new(
        a,
        gf,
        offs,
        [gain_code(gf, gs).unwrap(), gain_code(gf, gc).unwrap()],
    )
    .unwrap();
    let with = params(a, gf, offs, gs, gc, 3.0);
    let e0 = worst_angle_error(&without, "corr_phase_off", amp, off, phi);
    let e1 = worst_angle_error(&with, "corr_phase_on", amp, off, phi);
    eprintln!(
        "3 deg phase error: worst angle error {:.4} deg without, {:.5} deg with phase correction",
        e0.to_degrees(),
        e1.to_degrees()
    );
    // Uncorrected: the angle error of a phase shift between the tracks is about
    // phi sin^2(t), from 0 to phi.
    assert!(e0 > 0.9 * phi, "{e0}");
    // Corrected: ADC rounding (+-0.5 LSB on each track, about 1.2e-4 rad at 6000 LSB) and
    // the output rounding; well below 1% of the uncorrected error.
    assert!(e1 < 3e-4, "{e1}");
}

#[test]
fn phase_zero_builds_no_phase_stage() {
    let p0 = CorrectionParams::new(14, 14, [3, -4], [16000, 17000]).unwrap();
    let (gc, k) = phase_codes(14, 16000.0 / 16384.0, 17000.0 / 16384.0, 0.0).unwrap();
    assert_eq!((gc, k), (17000, 0));
    let p0k = p0.with_phase(0).unwrap();
    assert_eq!(p0k, p0);
    // No phase stage; 17000 and 16000 are not powers of two: shift-add products (3 + 3).
    assert_eq!(p0.latency_cycles(), 6);
    assert_eq!(
        CorrectionParams::identity(14, 14).unwrap().latency_cycles(),
        3
    );
    let export = |p: &CorrectionParams, name: &str| {
        use rust_hdl::prelude::Block;
        let mut uut = Correction::new(p);
        uut.connect_all();
        sinedec::emit::verilog::export(&uut, name, name).expect("export")
    };
    let v0 = export(&p0, "corr_p0");
    assert!(
        !v0.contains("PhaseCos") && !v0.contains("ph_0"),
        "phase 0 has no phase stage"
    );
    let p1 = params(14, 14, [3, -4], 1.0, 1.0, 1.0);
    let v1 = export(&p1, "corr_p1");
    assert!(v1.contains("ph_0"), "phase stage instantiated");
    // Phase and the automatic calibration do not mix; out-of-range phases are refused.
    assert!(p1
        .with_auto(6000, 1, 1000)
        .unwrap_err()
        .to_string()
        .contains("static"));
    let auto = CorrectionParams::identity(14, 14)
        .unwrap()
        .with_auto(6000, 1, 1000)
        .unwrap();
    assert!(auto
        .with_phase(100)
        .unwrap_err()
        .to_string()
        .contains("static"));
    assert!(auto.with_phase(0).is_ok());
    assert!(p0.with_phase(65536).is_err());
    assert!(phase_codes(14, 1.0, 1.0, 15.01).is_err());
    assert!(phase_codes(14, 1.0, 1.0, f64::NAN).is_err());
    assert!(
        phase_codes(14, 1.0, 3.99, 15.0).is_err(),
        "folded cos gain beyond 16 bits"
    );
}

#[test]
fn phase_stage_synthesizes_without_hard_multipliers_and_one_carry_chain_per_path() {
    let p = params(14, 14, [37, -100], 1.0, 1.03, 3.0);
    let (x, c) = synth(Correction::new(&p), "corr_synth_phase");
    // Static mode: every code is a constant that is not a power of two, so the sin, cos and
    // cross products are shift-add trees (multree.rs), no hard multiplier.
    assert_eq!(x.multipliers, 0, "shift-add products");
    // Pipeline about 120 FF plus the trees' levels (only the non-zero partial sums), the
    // phase stage's sum and 4th stage.
    eprintln!(
        "corr_synth_phase: xc3sa {} LUT, {} FF; cycloneive {} FF",
        x.luts, x.ffs, c.ffs
    );
    assert!(x.ffs > 150 && x.ffs < 900, "{} FF", x.ffs);
    assert!(c.ffs > 150 && c.ffs < 900, "{} FF", c.ffs);
    let path = x.path.expect("a register-to-register path");
    eprintln!(
        "corr_synth_phase: worst path {} -> {}: {} carry chains, {} LUT levels, {} multipliers",
        path.from, path.to, path.carry_chains, path.lut_levels, path.multipliers
    );
    assert!(path.carry_chains <= 1, "{path:?}");
    let p0 = CorrectionParams::new(14, 14, [37, -100], [15000, 17000]).unwrap();
    let (x0, _) = synth(Correction::new(&p0), "corr_synth_nophase");
    eprintln!(
        "phase stage: +{} LUT, +{} FF on xc3sa",
        x.luts - x0.luts,
        x.ffs - x0.ffs
    );
}

#[test]
fn check_explains_the_correction_mode_and_the_peak_trackers_limit() {
    use sinedec::config::{Loaded, DEFAULT_CONFIG};
    let check = |extra: &str| {
        assert!(
            DEFAULT_CONFIG.contains("\nmode = \"static\"\n"),
            "the default's mode line"
        );
        let text = DEFAULT_CONFIG.replace("\nmode = \"static\"\n", &format!("\n{extra}\n"));
        Loaded::parse(&text, "check.toml")
            .expect("config")
            .derived
            .describe()
    };
    let s = check("mode = \"static\"");
    assert!(s.contains("correction                  static:"), "{s}");
    assert!(s.contains("no phase correction"), "{s}");
    // Unity gains: the product is a shift, latency 3 in the CONV -> position sum.
    assert!(
        !s.contains("shift-add") && s.contains(" + correction 3 + "),
        "{s}"
    );
    let s = check("mode = \"static\"\nphase_deg = 3.0");
    assert!(s.contains("static phase correction"), "{s}");
    // 1 / cos(3 deg) and tan(3 deg) codes are not powers of two: shift-add products, and the
    // latency shown is 3 + 2 (phase) + 3 (the trees' levels).
    assert!(
        s.contains("shift-add trees") && s.contains(" + correction 8 + "),
        "{s}"
    );
    let s = check("mode = \"peak\"");
    assert!(s.contains("peak tracker"), "{s}");
    // Independently: the default samples 1,307,157 times per second per channel; at
    // 3000 rpm a 2048-line track has 1307157 / (2048 x 50) = 12.77 samples per period, and
    // the sample nearest the crest is at most pi / 12.77 away: 1 - cos = 3.01 %.
    let n = 1_307_157.0 / (2048.0 * 50.0);
    let at3000 = format!("{:.2} % at 3000 rpm", 100.0 * (1.0 - (PI / n).cos()));
    assert_eq!(at3000, "3.01 % at 3000 rpm");
    assert!(s.contains(&at3000), "{s}");
    // The speed where the deficit is one LSB of 2^13, found by bisection on the speed.
    let deficit = |rpm: f64| 1.0 - (PI * 2048.0 * rpm / 60.0 / 1_307_157.0).cos();
    let (mut lo, mut hi) = (1.0, 3000.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if deficit(mid) < 1.0 / 8192.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    let want = format!("within 1 LSB of 2^13 up to {lo:.0} rpm");
    assert!(s.contains(&want), "{want} in {s}");
}
