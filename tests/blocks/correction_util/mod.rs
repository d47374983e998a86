//! Helpers shared by `tests/blocks/correction.rs` and `tests/blocks/correction_auto.rs` (moved out of `tests/blocks/correction.rs` so that
//! no test file is longer than about 600 lines).
#![allow(dead_code)]
use crate::common;
use sinedec::blocks::correction::hdl::Correction;
use sinedec::blocks::correction::model::{CorrectionIn, CorrectionModel};
use sinedec::blocks::correction::CorrectionParams;
use sinedec::cosim::stimulus::SplitMix64;

use sinedec::synth::{synthesize, Family, SynthStats};
use sinedec::verify::Simulators;

pub const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

pub use crate::common::check_against_model as check;

pub fn run(
    p: &CorrectionParams,
    tag: &str,
    ins: &[CorrectionIn],
    sims: Simulators,
) -> Vec<Vec<u64>> {
    let rows: Vec<Vec<u64>> = ins
        .iter()
        .map(|i| {
            if p.writable() {
                i.row_writable()
            } else {
                i.row()
            }
        })
        .collect();
    let mut m = CorrectionModel::new(p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row(p.adc_width())).collect();
    check(Correction::new(p), tag, &rows, &model, sims)
}

pub fn sample(sin: i64, cos: i64) -> CorrectionIn {
    CorrectionIn {
        rst: false,
        valid: true,
        sin: sin as i32,
        cos: cos as i32,
        ..CorrectionIn::default()
    }
}

pub fn idle() -> CorrectionIn {
    CorrectionIn::default()
}

pub fn reset() -> CorrectionIn {
    CorrectionIn {
        rst: true,
        ..CorrectionIn::default()
    }
}

/// Directed and random A-bit samples: full-scale corners back to back, zero, +-1, the
/// offsets themselves and one LSB either side, raw words with junk above bit A, idle gaps
/// and resets in the middle of the stream.
pub fn stimulus(a: u32, offs: [i32; 2], n: usize, seed: u64) -> Vec<CorrectionIn> {
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
pub fn reference(x: i64, b: i64, g: u32, a: u32, gf: u32) -> i64 {
    let y = ((x - b) as f64 * g as f64 / (1u64 << gf) as f64).round();
    y.clamp(-(1i64 << (a - 1)) as f64, ((1i64 << (a - 1)) - 1) as f64) as i64
}

/// A rotating vector: sin = amp_s sin(th) + off_s, cos = amp_c cos(th) + off_c, rounded,
/// plus uniform noise of +-`noise` LSB; `spp` samples per period (negative: backwards), one
/// sample every `gap` clocks.
#[allow(clippy::too_many_arguments)]
pub fn sinusoid(
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

/// Calibration stimulus for the model/RTL comparison: sinusoids of changing speed and
/// direction (including faster than the divider: windows are dropped), small amplitudes
/// (no update), two-quadrant jumps, chatter, resets in the middle of a division.
pub fn auto_stimulus(a: u32, n_segments: usize, seed: u64) -> Vec<CorrectionIn> {
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

/// Exports `uut` and synthesizes it with Yosys for xc3sa and cycloneive under the project's
/// rules (no latch, no undriven net, no unexpected warning); returns both statistics.
pub fn synth<B: rust_hdl::prelude::Block>(mut uut: B, name: &str) -> (SynthStats, SynthStats) {
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
