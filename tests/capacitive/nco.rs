//! Excitation NCO: the exact table against f64 sin (0.5 LSB and round-to-nearest), the
//! quarter-wave symmetries, sin^2 + cos^2 against A^2, the carrier measured from zero
//! crossings of long runs against the configured one, rust-hdl == model == Icarus ==
//! Verilator with ticks at several spacings and resets mid-run, parameter checks, and
//! Yosys synthesis for both families.
use crate::common;
use sinedec::blocks::nco::hdl::Nco;
use sinedec::blocks::nco::model::{NcoIn, NcoModel, NcoOut};
use sinedec::blocks::nco::{sine_table, NcoParams, LATENCY};
use sinedec::blocks::sext;
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::synth::{synthesize, Family};
use sinedec::verify::{block_traces, Simulators};
use std::f64::consts::{FRAC_PI_2, TAU};

const F50: f64 = 50e6;

fn paper() -> NcoParams {
    NcoParams::new(F50, 400e3, 20e3, 32, 10, 16, 1.0).expect("valid")
}

/// A small, fast configuration: 1 MHz carrier stepped every clock of 50 MHz.
fn fast() -> NcoParams {
    NcoParams::new(F50, F50, 1e6, 24, 8, 12, 0.8).expect("valid")
}

#[test]
fn table_is_f64_sin_within_half_lsb_and_rounded_to_nearest() {
    for (t, w, a) in [
        (10, 16, 1.0),
        (8, 16, 0.75),
        (9, 12, 0.5),
        (4, 8, 0.3),
        (12, 16, 0.9),
        (6, 10, 0.123456789),
    ] {
        let tab = sine_table(t, w, a);
        assert_eq!(tab.len(), 1 << t);
        let m = ((1u64 << (w - 1)) - 1) as f64;
        let mut exact_checks = 0;
        for (i, &v) in tab.iter().enumerate() {
            let f = a * m * (FRAC_PI_2 * (i as f64 + 0.5) / (1u64 << t) as f64).sin();
            // f64 sin is within a few ulps; allow 1e-9 LSB for it.
            assert!(
                (v as f64 - f).abs() <= 0.5 + 1e-9,
                "T={t} W={w} A={a} i={i}: {v} vs {f}"
            );
            // Away from a tie the rounding rule decides the value uniquely.
            if (f - f.floor() - 0.5).abs() > 1e-6 {
                assert_eq!(v, f.round() as u64, "T={t} W={w} A={a} i={i}: {f}");
                exact_checks += 1;
            }
            assert!(v < 1 << (w - 1));
        }
        assert!(exact_checks as f64 > 0.99 * tab.len() as f64);
        // Increasing (a quarter wave) and the last entry below the full scale.
        assert!(tab.windows(2).all(|p| p[0] <= p[1]));
        assert!(*tab.last().unwrap_or(&0) as f64 <= a * m);
    }
    // Deterministic: the same inputs give the same table.
    assert_eq!(sine_table(10, 16, 0.7), sine_table(10, 16, 0.7));
}

#[test]
fn quarter_wave_symmetries_hold_exactly() {
    for p in [paper(), fast()] {
        let m = NcoModel::new(&p);
        let t = p.table_bits();
        let n = 1u64 << (t + 2);
        let sh = p.phase_bits() - t - 2;
        let at = |k: u64| m.lookup((k % n) << sh);
        for k in 0..n {
            let (s, c) = at(k);
            // sin(pi - x) = sin x; sin(x + pi) = -sin x; cos x = sin(x + pi/2);
            // cos(-x) = cos x, sin(-x) = -sin x (phase k+1/2 -> -(k+1/2) = N-1-k + 1/2).
            assert_eq!(at(n + n / 2 - 1 - k).0, s, "k={k}");
            assert_eq!(at(k + n / 2), (-s, -c), "k={k}");
            assert_eq!(at(k + n / 4).0, c, "k={k}");
            assert_eq!(at(n - 1 - k), (-s, c), "k={k}");
            // And each word is the exact value at the represented angle within 0.5 LSB.
            let phi = p.angle_of_phase(k << sh);
            assert!(
                (s as f64 - p.peak() * phi.sin()).abs() <= 0.5 + 1e-9,
                "k={k}"
            );
            assert!(
                (c as f64 - p.peak() * phi.cos()).abs() <= 0.5 + 1e-9,
                "k={k}"
            );
        }
        // The low phase bits below the table are truncated (ignored).
        let mut r = SplitMix64(3);
        for _ in 0..1000 {
            let ph = r.next_u64() & sinedec::blocks::mask(p.phase_bits());
            assert_eq!(m.lookup(ph), at(ph >> sh));
        }
    }
}

/// Every output pair lies within sqrt(2)/2 LSB of the circle of radius A (2^(W-1) - 1):
/// each word is within 0.5 LSB of the exact value at one common angle.
#[test]
fn sin_squared_plus_cos_squared_is_a_squared() {
    for p in [paper(), fast()] {
        let m = NcoModel::new(&p);
        let t = p.table_bits();
        let sh = p.phase_bits() - t - 2;
        let bound = std::f64::consts::SQRT_2 / 2.0;
        let mut worst: f64 = 0.0;
        for k in 0..(1u64 << (t + 2)) {
            let (s, c) = m.lookup(k << sh);
            let r = ((s * s + c * c) as f64).sqrt();
            worst = worst.max((r - p.peak()).abs());
        }
        eprintln!(
            "T={t} W={} A={}: max |sqrt(s^2+c^2) - A| = {worst:.4} LSB (bound {bound:.4})",
            p.width(),
            p.amplitude()
        );
        assert!(worst <= bound + 1e-12, "{worst}");
    }
}

#[test]
fn frequency_word_and_achieved_carrier() {
    let p = paper();
    // 2^32 / 20 = 214748364.8 -> 214748365.
    assert_eq!(p.freq_word(), 214_748_365);
    assert!((p.achieved_hz() - 20e3).abs() <= p.resolution_hz() / 2.0);
    assert!((p.error_hz() - 0.2 * 400e3 / 2f64.powi(32)).abs() < 1e-9);
    assert_eq!(p.clocks_per_update(), 125.0);
    // 1 MHz at 50 MHz: 2^24 / 50 = 335544.32 -> 335544.
    assert_eq!(fast().freq_word(), 335_544);
    assert!((fast().achieved_hz() - 1e6).abs() <= fast().resolution_hz() / 2.0);
}

/// Sine words of the first `updates` updates after reset, from the model (ticks on every
/// other clock: the sequence does not depend on the spacing, see the co-simulation test).
fn model_run(p: &NcoParams, updates: usize) -> Vec<NcoOut> {
    let mut m = NcoModel::new(p);
    m.step(NcoIn {
        rst: true,
        tick: false,
    });
    let mut outs = Vec::with_capacity(updates);
    let mut k = 0;
    while outs.len() < updates {
        let o = m.step(NcoIn {
            rst: false,
            tick: k % 2 == 0,
        });
        if o.valid {
            outs.push(o);
        }
        k += 1;
    }
    outs
}

/// Frequency from the rising zero crossings of `s` sampled at `fs`, each located by
/// linear interpolation: (crossings - 1) periods between the first and the last.
fn zero_crossing_hz(s: &[i64], fs: f64) -> f64 {
    let mut times = Vec::new();
    for n in 1..s.len() {
        let (a, b) = (s[n - 1] as f64, s[n] as f64);
        if a < 0.0 && b >= 0.0 {
            times.push((n - 1) as f64 + a / (a - b));
        }
    }
    assert!(times.len() > 10, "{} crossings", times.len());
    let span = (times[times.len() - 1] - times[0]) / fs;
    (times.len() - 1) as f64 / span
}

#[test]
fn carrier_measured_from_zero_crossings() {
    for (p, seconds, tol) in [
        // The paper's 20 kHz at 400 kHz updates from 50 MHz; 0.5 s = 10^4 periods.
        (paper(), 0.5, 1e-3),
        // A coarse 16-bit phase: fw = 3277 instead of 3276.8, the carrier is 1.22 Hz high
        // and the measurement must see it.
        (
            NcoParams::new(F50, 400e3, 20e3, 16, 10, 16, 1.0).expect("valid"),
            0.5,
            1e-3,
        ),
        // 1 MHz stepped every clock at 50 MHz, 24-bit phase: 2*10^4 periods.
        (fast(), 0.02, 0.05),
        // 1 MHz at 10 MHz updates, 32-bit phase.
        (
            NcoParams::new(F50, 10e6, 1e6, 32, 10, 16, 1.0).expect("valid"),
            0.02,
            0.05,
        ),
    ] {
        let n = (seconds * p.update_hz()) as usize;
        let s: Vec<i64> = model_run(&p, n).iter().map(|o| o.sin).collect();
        let f = zero_crossing_hz(&s, p.update_hz());
        eprintln!(
            "carrier {} Hz, update {} Hz, P={}: fw={} achieved {:.6} Hz, measured {:.6} Hz",
            p.carrier_hz(),
            p.update_hz(),
            p.phase_bits(),
            p.freq_word(),
            p.achieved_hz(),
            f
        );
        assert!(
            (f - p.achieved_hz()).abs() < tol,
            "{f} vs {}",
            p.achieved_hz()
        );
        assert!((f - p.carrier_hz()).abs() < p.error_hz().abs() + tol);
        // The cos word crosses a quarter period earlier: same frequency.
        let c: Vec<i64> = model_run(&p, n.min(200_000))
            .iter()
            .map(|o| o.cos)
            .collect();
        let fc = zero_crossing_hz(&c, p.update_hz());
        assert!((fc - p.achieved_hz()).abs() < 20.0 * tol.max(0.01), "{fc}");
    }
    let coarse = NcoParams::new(F50, 400e3, 20e3, 16, 10, 16, 1.0).expect("valid");
    assert!((coarse.error_hz() - 1.220703125).abs() < 1e-9);
}

/// Input rows: reset, then ticks every `gap` clocks; `resets` lists (row, length) of reset
/// pulses; `random` makes the tick spacing random (1..=gap).
fn rows(n: usize, gap: usize, resets: &[(usize, usize)], random: bool, seed: u64) -> Vec<NcoIn> {
    let mut r = SplitMix64(seed);
    let mut next = 3;
    (0..n)
        .map(|k| {
            let rst = k < 2 || resets.iter().any(|&(at, len)| k >= at && k < at + len);
            let tick = k == next;
            if tick {
                next += if random {
                    r.range(1, gap as i64) as usize
                } else {
                    gap
                };
            }
            NcoIn { rst, tick }
        })
        .collect()
}

fn check(p: &NcoParams, tag: &str, ins: &[NcoIn]) -> Vec<Vec<u64>> {
    let w = p.width();
    let mut m = NcoModel::new(p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row(w)).collect();
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let dir = common::workdir(tag);
    let t = block_traces(Nco::new(p), tag, "clk", &rows, Simulators::ALL, &dir)
        .expect("simulators ran");
    for (k, (r, mm)) in t.rust_hdl.iter().zip(&model).enumerate() {
        assert_eq!(
            r, mm,
            "{tag} row {k}: rust-hdl vs model (inputs {:?})",
            ins[k]
        );
    }
    assert_eq!(t.rust_hdl.len(), model.len());
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    t.rust_hdl
}

#[test]
fn rtl_equals_model_icarus_verilator_with_resets_mid_run() {
    // Paper config, ticks every 7 clocks, then random spacing, with resets in the middle of
    // the pipeline (a reset on the tick, one clock after it, and a long one).
    let p = paper();
    let n = 3000;
    let mut ins = rows(n, 7, &[(700, 1), (1201, 3), (2000, 40)], false, 1);
    ins.extend(rows(1500, 4, &[(300, 2)], true, 2));
    // Reset exactly on a tick and one clock after one.
    let ticks: Vec<usize> = (0..ins.len()).filter(|&k| ins[k].tick).collect();
    ins[ticks[50]].rst = true;
    ins[ticks[80] + 1].rst = true;
    let out = check(&p, "nco_paper", &ins);
    // The phase output counts ticks since the last reset: n * fw, in the row of the tick
    // (the trace row is read after the edge; one register stage).
    let mut since = 0u64;
    let mut pending = Vec::new();
    for (k, i) in ins.iter().enumerate() {
        if i.rst {
            since = 0;
            pending.clear();
        } else if i.tick {
            pending.push((
                k + LATENCY as usize - 1,
                since * p.freq_word() % (1u64 << 32),
            ));
            since += 1;
        }
        if let Some(&(at, ph)) = pending.first() {
            if at == k {
                assert_eq!(out[k][0], 1, "valid at {k}");
                assert_eq!(out[k][3], ph, "phase at {k}");
                pending.remove(0);
            }
        }
    }
    // Tick every clock with a small table and 1 MHz carrier.
    let p = fast();
    let ins = rows(2500, 1, &[(400, 1), (900, 5)], false, 3);
    let out = check(&p, "nco_fast", &ins);
    assert!(out.iter().filter(|o| o[0] == 1).count() > 2000);
}

/// The sequence of words per update does not depend on the tick spacing (1, 2, 5, random).
#[test]
fn output_sequence_is_independent_of_tick_spacing() {
    let p = fast();
    let seq = |ins: &[NcoIn]| -> Vec<(i64, i64, u64)> {
        let mut uut = Nco::new(&p);
        prepare(&mut uut).expect("settles");
        let mut v = Vec::new();
        for i in ins {
            uut.rst.next = i.rst;
            uut.tick.next = i.tick;
            tick(&mut uut).expect("settles");
            if uut.out_valid.val() {
                v.push((
                    sext(uut.out_sin.val().to_u64(), p.width()),
                    sext(uut.out_cos.val().to_u64(), p.width()),
                    uut.out_phase.val().to_u64(),
                ));
            }
        }
        v
    };
    let base = seq(&rows(300, 1, &[], false, 0));
    assert!(base.len() > 290);
    for (gap, random) in [(2, false), (5, false), (6, true)] {
        let s = seq(&rows(300 * gap, gap, &[], random, 9));
        let k = s.len().min(base.len());
        assert!(k > 40);
        assert_eq!(s[..k], base[..k], "gap {gap} random {random}");
    }
    // And the RTL's frequency matches too (400 periods of the 1 MHz carrier).
    let s: Vec<i64> = seq(&rows(20_000, 1, &[], false, 0))
        .iter()
        .map(|o| o.0)
        .collect();
    let f = zero_crossing_hz(&s, p.update_hz());
    assert!((f - p.achieved_hz()).abs() < 2.0, "{f}");
    // Against an independent f64 carrier: word n = round(A M sin(2 pi f n / fs)) within
    // the phase truncation (one table step of angle) plus rounding.
    let step = TAU / (1u64 << (p.table_bits() + 2)) as f64;
    for (n, &v) in s.iter().enumerate().take(5000) {
        let th = TAU * p.achieved_hz() * n as f64 / p.update_hz();
        assert!(
            (v as f64 - p.peak() * th.sin()).abs() <= p.peak() * step + 0.5,
            "n={n}"
        );
    }
}

#[test]
fn bad_parameters_are_rejected_with_a_message() {
    let e = |r: Result<NcoParams, sinedec::error::Error>| r.expect_err("invalid").to_string();
    let m = e(NcoParams::new(F50, 400e3, 5e3, 32, 10, 16, 1.0));
    assert!(m.contains("10 kHz..=1 MHz"), "{m}");
    let m = e(NcoParams::new(F50, 400e3, 2e6, 32, 10, 16, 1.0));
    assert!(m.contains("10 kHz..=1 MHz"), "{m}");
    let m = e(NcoParams::new(F50, 400e3, 200e3, 32, 10, 16, 1.0));
    assert!(m.contains("below half the update rate"), "{m}");
    let m = e(NcoParams::new(F50, 1.5e6, 1e6, 32, 10, 16, 1.0));
    assert!(m.contains("below half the update rate"), "{m}");
    let m = e(NcoParams::new(F50, 100e6, 1e6, 32, 10, 16, 1.0));
    assert!(m.contains("at most the clock"), "{m}");
    for t in [3, 13] {
        let m = e(NcoParams::new(F50, 400e3, 20e3, 32, t, 16, 1.0));
        assert!(m.contains("4..=12"), "{m}");
    }
    for pb in [11, 33] {
        let m = e(NcoParams::new(F50, 400e3, 20e3, pb, 10, 16, 1.0));
        assert!(m.contains("12..=32"), "{m}");
    }
    for w in [3, 17] {
        let m = e(NcoParams::new(F50, 400e3, 20e3, 32, 10, w, 1.0));
        assert!(m.contains("4..=16"), "{m}");
    }
    for a in [0.0, -0.5, 1.01, f64::NAN] {
        let m = e(NcoParams::new(F50, 400e3, 20e3, 32, 10, 16, a));
        assert!(m.contains("amplitude"), "{m}");
    }
    // 10 kHz / 50 MHz * 2^11 = 0.41 rounds to a zero frequency word.
    let m = e(NcoParams::new(F50, F50, 10e3, 11, 4, 8, 1.0));
    assert!(m.contains("frequency word"), "{m}");
    assert!(NcoParams::new(0.0, 400e3, 20e3, 32, 10, 16, 1.0).is_err());
}

#[test]
fn synthesizes_for_both_families() {
    use rust_hdl::prelude::Block;
    let dir = common::workdir("nco_synth");
    let t8 = NcoParams::new(F50, 400e3, 20e3, 32, 8, 16, 1.0).expect("valid");
    for (p, tag) in [
        (paper(), "sd_nco"),
        (t8, "sd_nco_t8"),
        (fast(), "sd_nco_fast"),
    ] {
        let mut uut = Nco::new(&p);
        uut.connect_all();
        let v = sinedec::emit::verilog::export(&uut, "nco", tag).expect("export");
        for fam in [Family::CycloneIve, Family::Xc3sa] {
            let s = synthesize(&v, tag, fam, &dir).expect("synthesis");
            eprintln!(
                "NCO T={} W={} P={} {}: {} LUT/LE, {} FF, {} carry, {} BRAM; cells {:?}",
                p.table_bits(),
                p.width(),
                p.phase_bits(),
                fam.name(),
                s.luts,
                s.ffs,
                s.carry,
                s.brams,
                s.cells
            );
            // phase and out_phase (P each), out_sin/out_cos (W each), out_valid.
            let pb = p.phase_bits() as u64;
            let w = p.width() as u64;
            assert!(s.ffs <= 2 * pb + 2 * w + 1, "{} FF", s.ffs);
            assert!(s.luts > 0);
        }
    }
}
