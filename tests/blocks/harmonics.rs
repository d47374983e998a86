//! Harmonic-correction block (issue 46): rust-hdl == model cycle for cycle == Icarus ==
//! Verilator == engine, the model's interpolation against an exact computation of the
//! table's line within the documented bound, and a table made from a known distortion (the
//! encoder model's 3rd and 5th harmonics, docs/correction.md) taking it out of the angle.
use crate::common;
use sinedec::blocks::harmonics::hdl::HarmonicCorrection;
use sinedec::blocks::harmonics::model::{correct, HarmonicIn, HarmonicModel};
use sinedec::blocks::harmonics::{HarmonicParams, INTERP_BITS};
use sinedec::blocks::mask;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::verify::Simulators;
use std::f64::consts::{PI, TAU};

/// The default config's angle word: F = 14, Gz = 6, ZW = 22.
const F: u32 = 14;
const GZ: u32 = 6;
const ZW: u32 = F + GZ + 2;

/// A table of `n` entries drawn within +-`amp` LSB.
fn random_table(n: usize, amp: f64, seed: u64) -> Vec<f64> {
    let mut r = SplitMix64(seed);
    (0..n).map(|_| (r.unit() * 2.0 - 1.0) * amp).collect()
}

/// Signed difference of two ZW-bit angle words, wrapped into [-2^(ZW-1), 2^(ZW-1)).
fn wrap(a: f64) -> f64 {
    let m = (1u64 << ZW) as f64;
    a - m * (a / m).round()
}

fn run_four_ways(p: &HarmonicParams, tag: &str, n: usize, seed: u64) {
    let mut r = SplitMix64(seed);
    let ins: Vec<HarmonicIn> = (0..n)
        .map(|c| HarmonicIn {
            // Reset at the start and for two clocks in the middle.
            rst: c < 2 || (c > n / 2 && c < n / 2 + 3),
            // Angles all over the period, with the segment ends and the wrap among them.
            z: match c % 7 {
                0 => (r.next_u64() % p.points() as u64) << (ZW - p.points_log2),
                1 => mask(ZW) - (r.next_u64() & 3),
                _ => r.next_u64() & mask(ZW),
            },
            x: r.next_u64() & mask(32),
            v: r.next_u64() & 3 != 0,
        })
        .collect();
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = HarmonicModel::new(p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row()).collect();
    common::check_against_model(
        HarmonicCorrection::new(p),
        tag,
        &rows,
        &model,
        Simulators::ALL,
    );
}

#[test]
fn rtl_equals_the_model_four_ways_at_16_64_and_256_points() {
    for (n, amp, seed) in [(16, 1000.0, 1), (64, 300.0, 2), (256, 1024.0, 3)] {
        let p = HarmonicParams::new(ZW, GZ, F, &random_table(n, amp, seed)).expect("params");
        run_four_ways(&p, &format!("harmonics_{n}"), 3000, seed);
    }
}

/// Against the table's exact line: z - (c_i + D_i u), u the exact place within the
/// segment, within (max|D| 2^-R + 1/2) z units; at a segment's start exactly z - c_i.
#[test]
fn the_interpolation_is_within_its_bound() {
    for (n, amp, seed) in [(16, 1024.0, 4), (64, 200.0, 5), (256, 50.0, 6)] {
        let p = HarmonicParams::new(ZW, GZ, F, &random_table(n, amp, seed)).expect("params");
        let seg = (1u64 << (ZW - p.points_log2)) as f64;
        let bound_z = p.bound_lsb() * (1u64 << GZ) as f64;
        let dmax = p.slopes().iter().map(|d| d.abs()).max().unwrap() as f64;
        assert_eq!(bound_z, dmax / (1u64 << INTERP_BITS) as f64 + 0.5);
        let mut r = SplitMix64(seed);
        let mut worst: f64 = 0.0;
        for k in 0..200_000u64 {
            let z = if k < n as u64 {
                k << (ZW - p.points_log2)
            } else {
                r.next_u64() & mask(ZW)
            };
            let i = (z as f64 / seg).floor() as usize;
            let u = (z as f64 - i as f64 * seg) / seg;
            let c = p.table[i] as f64 + (p.table[(i + 1) % n] - p.table[i]) as f64 * u;
            let e = wrap(correct(&p, z) as f64 - (z as f64 - c));
            if k < n as u64 {
                assert_eq!(e, 0.0, "{n} points, segment start {k}");
            }
            worst = worst.max(e.abs());
        }
        assert!(worst <= bound_z, "{n} points: {worst} > {bound_z} z units");
        // The bound is not loose by more than a z unit.
        assert!(
            worst > bound_z - 1.0,
            "{n} points: {worst} against {bound_z}"
        );
    }
}

/// The decoded angle of an encoder with h3 = 2 %, h5 = 1 % (phases 0 and 40 degrees) is x +
/// e(x) with e(x) = atan2 of the vector e^(ix) (1 - h3 e^(-i(4x + p3)) + h5 e^(i(4x +
/// p5))) (the encoder model's formula, docs/correction.md). A 64-point table of e against
/// the decoded angle (e found by inverting x + e(x) at each point) takes it out of the
/// angle to within the block's bound, the table's rounding and the interpolation's
/// (2 pi / P)^2 / 8 max|c''| error (c the table's function: 6 LSB at 64 points).
#[test]
fn a_table_of_the_distortion_removes_it() {
    let (h3, p3, h5, p5) = (0.02, 0.0, 0.01, 40f64.to_radians());
    let e = |x: f64| -> f64 {
        // Angle of 1 - h3 e^(-i(4x + p3)) + h5 e^(i(4x + p5)).
        let re = 1.0 - h3 * (4.0 * x + p3).cos() + h5 * (4.0 * x + p5).cos();
        let im = h3 * (4.0 * x + p3).sin() + h5 * (4.0 * x + p5).sin();
        im.atan2(re)
    };
    // Electrical rad to position LSB (2^F per quadrant) and to z units.
    let lsb = (1u64 << F) as f64 / (PI / 2.0);
    let zu = lsb * (1u64 << GZ) as f64;
    let n = 64;
    // c(m) = e(x) where x + e(x) = m: fixed-point iteration (|e'| < 0.2).
    let inverse = |m: f64| {
        let mut x = m;
        for _ in 0..50 {
            x = m - e(x);
        }
        x
    };
    let table: Vec<f64> = (0..n)
        .map(|i| {
            let m = TAU * i as f64 / n as f64;
            e(inverse(m)) * lsb
        })
        .collect();
    let p = HarmonicParams::new(ZW, GZ, F, &table).expect("params");
    // The table's function c(m) = e(x(m)) and its largest second derivative (central
    // differences on a fine grid), in LSB per rad^2.
    let c = |m: f64| e(inverse(m)) * lsb;
    let dm = 1e-3;
    let cpp = (0..6284)
        .map(|k| k as f64 * 1e-3)
        .map(|m| ((c(m + dm) - 2.0 * c(m) + c(m - dm)) / (dm * dm)).abs())
        .fold(0.0, f64::max);
    let interp = (TAU / n as f64).powi(2) / 8.0 * cpp;
    let allowed = p.bound_lsb() + 0.5 / (1u64 << GZ) as f64 + interp;
    let mut worst: f64 = 0.0;
    let mut before: f64 = 0.0;
    for k in 0..100_000 {
        let x = TAU * k as f64 / 100_000.0;
        let m = x + e(x);
        // The CORDIC's word: the decoded angle in z units with the rounding half.
        let z = ((m.rem_euclid(TAU) * zu).round() as u64 + (1 << (GZ - 1))) & mask(ZW);
        let out = correct(&p, z) as f64 - (1u64 << (GZ - 1)) as f64;
        let err = wrap(out - x * zu) / (1u64 << GZ) as f64;
        worst = worst.max(err.abs());
        before = before.max(e(x).abs() * lsb);
    }
    assert!(before > 250.0, "the distortion: {before} LSB");
    assert!(
        worst <= allowed + 0.5 / (1u64 << GZ) as f64,
        "left {worst} LSB of {before}, allowed {allowed}"
    );
    eprintln!(
        "64 points: {before:.1} LSB of distortion left at {worst:.3} LSB (bound {allowed:.3})"
    );
}

#[test]
fn tables_outside_the_limits_are_refused() {
    let e = HarmonicParams::new(ZW, GZ, F, &[0.0; 48]).unwrap_err();
    assert!(
        e.contains("48 entries") && e.contains("power of two from 16 to 256"),
        "{e}"
    );
    let e = HarmonicParams::new(ZW, GZ, F, &[0.0; 512]).unwrap_err();
    assert!(e.contains("512 entries"), "{e}");
    let mut t = vec![0.0; 16];
    t[3] = 1024.5;
    let e = HarmonicParams::new(ZW, GZ, F, &t).unwrap_err();
    assert!(
        e.contains("entry 3") && e.contains("-1024..=1024 LSB"),
        "{e}"
    );
    t[3] = f64::NAN;
    assert!(HarmonicParams::new(ZW, GZ, F, &t).is_err());
    // An angle word too wide for the 32-bit sums.
    let e = HarmonicParams::new(26, 6, 18, &[0.0; 16]).unwrap_err();
    assert!(e.contains("F + Gz + 2 <= 24"), "{e}");
}

/// `<name>_core` with the held 64-point table (`HELD_CASE`) in Icarus, Verilator and the
/// engine == rust-hdl == the core's model, on the directed, random and rotating stimulus of
/// the core's own co-simulation; and the table does move the positions.
#[test]
fn the_core_with_a_table_equals_its_model_four_ways() {
    use sinedec::blocks::harmonics::block::HELD_CASE;
    use sinedec::config::{Loaded, DEFAULT_CONFIG};
    use sinedec::cosim::stimulus;
    use sinedec::verify::core_traces;
    let on = Loaded::parse(&format!("{DEFAULT_CONFIG}\n{HELD_CASE}"), "h.toml").expect("on");
    let a = on.derived.adc_width;
    let mut s = stimulus::directed(a);
    s.extend(stimulus::random(a, 1500, 0.25, 46));
    let step = std::f64::consts::FRAC_PI_2 * 0.3;
    s.extend(stimulus::rotation(a, 0.7, 0.0, step, 400));
    s.extend(stimulus::rotation(a, 0.7, 0.0, -step, 400));
    let dir = common::workdir("cosim_core_harmonics");
    let t = core_traces(&on, &s, Simulators::ALL, &dir).expect("all simulators ran");
    if let Some(m) = t.mismatch(&on) {
        panic!("core with [harmonics]: {m}");
    }
    let valid = |rows: &[Vec<u64>]| -> Vec<u64> {
        rows.iter().filter(|r| r[0] == 1).map(|r| r[1]).collect()
    };
    let off = Loaded::default_config().expect("off");
    let plain = core_traces(
        &off,
        &s,
        Simulators {
            icarus: false,
            verilator: false,
        },
        &dir,
    )
    .expect("rust-hdl ran");
    let (p_on, p_off) = (valid(&t.rust_hdl), valid(&plain.rust_hdl));
    // The last samples of the stimulus leave the longer pipeline after it ends.
    assert!(
        p_off.len() - p_on.len() <= 5 * 2,
        "{} {}",
        p_on.len(),
        p_off.len()
    );
    assert!(p_on.len() > 1000);
    let moved = p_on.iter().zip(&p_off).filter(|(a, b)| a != b).count();
    assert!(
        moved > p_on.len() / 2,
        "{moved} of {} positions moved",
        p_on.len()
    );
}

/// The held 64-point block alone in Yosys: no hard multiplier (the interpolation is a
/// shift-add tree) and at most one carry chain on every register-to-register path of the
/// xc3sa mapping (the timing rule, docs/timing.md); the figures are printed for
/// docs/correction.md.
#[test]
fn the_block_synthesizes_with_one_carry_chain_per_path_and_no_multiplier() {
    use sinedec::blocks::harmonics::block::HELD_CASE;
    use sinedec::config::{Loaded, DEFAULT_CONFIG};
    let on = Loaded::parse(&format!("{DEFAULT_CONFIG}\n{HELD_CASE}"), "h.toml").expect("on");
    let p = on.derived.harmonics.clone().expect("enabled");
    let (x, c) = crate::correction_util::synth(HarmonicCorrection::new(&p), "harmonics_synth");
    let path = x.path.expect("a register-to-register path");
    eprintln!(
        "harmonics_synth: xc3sa {} LUT, {} FF, {} MULT18X18, {} BRAM; cycloneive {} LE, {} FF, {} multipliers; worst path {} -> {}: {} carry chains, {} LUT levels",
        x.luts, x.ffs, x.multipliers, x.brams, c.luts, c.ffs, c.multipliers, path.from, path.to, path.carry_chains, path.lut_levels
    );
    assert_eq!(x.multipliers + c.multipliers, 0);
    assert!(path.carry_chains <= 1, "{path:?}");
    // `check`'s line for the block: present with [harmonics], absent without.
    let line = sinedec::report::block_resource_line(&on, "harmonics", Some("h.toml"))
        .expect("line")
        .expect("the block is in this design");
    assert!(line.starts_with("resources (harmonics)"), "{line}");
    let off = Loaded::default_config().expect("default");
    assert!(
        sinedec::report::block_resource_line(&off, "harmonics", None)
            .expect("line")
            .is_none()
    );
}
