//! Stimulus for the core: random, directed and rotating sample streams, shared by the
//! tests, the co-simulation and the emitted testbench.
use crate::blocks::core::model::CoreIn;

/// SplitMix64: a small deterministic generator (same seed, same stream, on any machine).
/// Written out here (ten lines) rather than taken from the `rand` crate: the stimuli, and so
/// the tests' expected traces, depend on this exact stream, which must not move with a
/// dependency's version (`rand` documents its generators' output as not portable across
/// versions).
#[derive(Clone, Debug)]
pub struct SplitMix64(pub u64);

impl SplitMix64 {
    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in lo..=hi.
    pub fn range(&mut self, lo: i64, hi: i64) -> i64 {
        lo + (self.next_u64() % ((hi - lo + 1) as u64)) as i64
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

fn valid(sin: i64, cos: i64) -> CoreIn {
    CoreIn {
        rst: false,
        valid: true,
        sin: sin as i32,
        cos: cos as i32,
        load: None,
    }
}

/// Idle cycle (no sample).
pub fn idle() -> CoreIn {
    CoreIn::default()
}

/// Reset cycle.
pub fn reset() -> CoreIn {
    CoreIn {
        rst: true,
        ..CoreIn::default()
    }
}

/// Directed samples for A-bit inputs: the axes and 45-degree diagonals in every quadrant at
/// several amplitudes, one LSB either side of each axis, zero, and the full-scale corners
/// (positive and negative) that exercise every word's largest value.
pub fn directed(a: u32) -> Vec<CoreIn> {
    let max = (1i64 << (a - 1)) - 1;
    let min = -(1i64 << (a - 1));
    let mut v = vec![reset(), reset()];
    for amp in [max, max / 2, max / 8] {
        for (s, c) in [
            (0, amp),
            (amp, 0),
            (0, -amp),
            (-amp, 0),
            (amp, amp),
            (amp, -amp),
            (-amp, -amp),
            (-amp, amp),
        ] {
            v.push(valid(s, c));
        }
        // One LSB either side of each axis.
        for (s, c) in [
            (1, amp),
            (-1, amp),
            (amp, 1),
            (amp, -1),
            (1, -amp),
            (-1, -amp),
            (-amp, 1),
            (-amp, -1),
        ] {
            v.push(valid(s, c));
        }
    }
    for (s, c) in [
        (0, 0),
        (max, max),
        (min, min),
        (min, max),
        (max, min),
        (min, 0),
        (0, min),
        (min, 1),
        (1, min),
        (0, 0),
    ] {
        v.push(valid(s, c));
    }
    v
}

/// `n` random samples on circles of random radius (1/16 .. 1 of full scale) and random angle,
/// with idle gaps (probability `gap`) and an occasional reset in the middle of the stream.
pub fn random(a: u32, n: usize, gap: f64, seed: u64) -> Vec<CoreIn> {
    let mut r = SplitMix64(seed);
    let full = ((1i64 << (a - 1)) - 1) as f64;
    let mut v = Vec::with_capacity(n + n / 4);
    for k in 0..n {
        if r.unit() < gap {
            v.push(idle());
        }
        if k == n / 2 {
            v.push(reset());
        }
        if r.unit() < 0.05 {
            // Raw random words, any magnitude (including tiny ones).
            let lim = 1i64 << (a - 1);
            v.push(valid(r.range(-lim, lim - 1), r.range(-lim, lim - 1)));
        } else {
            let rad = full * (0.0625 + 0.9375 * r.unit());
            let th = r.unit() * std::f64::consts::TAU;
            v.push(valid(
                (rad * th.sin()).round() as i64,
                (rad * th.cos()).round() as i64,
            ));
        }
    }
    v
}

/// A vector of amplitude `amp` (fraction of full scale) turning by `step` radians per
/// sample for `n` samples from angle `start`.
pub fn rotation(a: u32, amp: f64, start: f64, step: f64, n: usize) -> Vec<CoreIn> {
    let full = ((1i64 << (a - 1)) - 1) as f64 * amp;
    (0..n)
        .map(|k| {
            let th = start + step * k as f64;
            valid(
                (full * th.sin()).round() as i64,
                (full * th.cos()).round() as i64,
            )
        })
        .collect()
}
