//! External digital QEP (A/B/Z from comparators): synchronizers, glitch filters, x4
//! decoder, signed quadrant counter with index latch, and the cross-check of the QEP count
//! against the CORDIC quadrant count (thesis section 3.2.2: above about 1800 rpm the
//! thesis falls back to the external QEP count).
//!
//! ```text
//!          2-flop sync         glitch filter (F clocks)      x4 decoder       counter
//!  qep_a ─►[a1]─►[a2]──┬──►┌──────────────┐ af ┌──►[pa]   ┌───────────┐   ┌──────────┐
//!                      │   │ cnt != F-1:  ├────┤          │ da = af^pa│   │ count    ├─► count
//!  qep_b ─►[b1]─►[b2]──┼──►│  count; at   │ bf ├──►[pb]──►│ db = bf^pb├──►│ +-1 mod  │
//!                      │   │  F-1 accept  │    │          │ up/down/  │   │ 2^C      ├─► illegal
//!  qep_z ─►[z1]─►[z2]──┴──►└──────────────┘ zf └──►[pz]──►│ illegal   │   │ Z rising:├─► index_*
//!                                                         └───────────┘   │ latch    ├─► up, down
//!                                                                         └──────────┘
//! ```
//!
//! # Decoder (`QepDecoder`)
//! * Synchronizers: each of A, B, Z passes two flip-flops (`x1`, `x2`); no reset.
//! * Glitch filter, per input: the accepted level `xf` and a counter `cnt` (0..F-1,
//!   ceil(log2 F) bits, masked). Each clock: if `x2 == xf` then `cnt = 0`; else if
//!   `cnt == F-1` then `xf = x2, cnt = 0`; else `cnt += 1`. A new level is accepted after
//!   it has been seen on `x2` for F consecutive clocks; a pulse of L < F clocks is never
//!   accepted, a pulse of L >= F clocks is (F = 1: no filtering).
//! * x4 decoder on the accepted levels against their values one clock earlier (`pa`, `pb`):
//!   forward (count up) is the sequence (A,B) = 00 -> 10 -> 11 -> 01 -> 00 (A leads B).
//!   With `da = af ^ pa`, `db = bf ^ pb`: A alone changed: up iff `af != bf`; B alone
//!   changed: up iff `bf == af`; both changed (a double transition after filtering):
//!   `illegal` for one clock, count unchanged.
//! * Count: C-bit two's complement (C = 2..=32) in the low bits of a 32-bit word,
//!   `count' = (count +- 1) mod 2^C` (wraps, like the 2^C counter it is).
//! * `up` / `down`: registered beside the count, 1 for one clock after an edge that stepped
//!   it by +1 / -1 (0 after reset); the QEP fallback's tracker counts with them.
//! * Index: on a rising edge of the accepted Z (`zf & !pz`), `index_count` latches the count
//!   *including* the step of that same clock, so in the output cycle where `index_strobe`
//!   is 1, `index_count == count`; `index_seen` is sticky until reset.
//! * Latency: a level change applied before rising edge k is accepted into `xf` at edge
//!   k+F+1 and counted at edge k+F+2 (`count` shows it after that edge): F + 3 rising
//!   edges including the capturing one.
//! * Reset (synchronous, active high): count, index and flags to 0; the filters and the
//!   previous levels load the synchronized inputs (`xf = pa = x2`), so a level present
//!   during reset is never counted. Hold `rst` for at least 3 clocks so `x2` is current.
//!
//! # Cross-check (`QepCrossCheck`)
//! The CORDIC path gives a single-turn quadrant count `qc` in 0..Q-1 (Q = 4 PPR, any
//! integer, from the quadrant counter; only its low ceil(log2 Q) bits are used). On each
//! `valid` sample the cross-check unwraps it
//! into a C-bit linear count `cc`: step = qc - qc_prev, taken into [-Q/2, Q/2] by adding or
//! subtracting Q (so a turn wrap 4PPR-1 -> 0 is one step of +1), `cc' = (cc + step) mod 2^C`.
//! On the first valid sample after reset or after `align`, it captures
//! `off = qep_count - cc` (the counts' arbitrary zero points). Then
//! `diff = (qep_count - cc - off) mod 2^C`, read as C-bit signed, and
//! `mismatch = |diff| > T` (T = tolerance, default 1 quadrant). Both registered, one clock.
//! Modular C-bit arithmetic throughout: no overflow, only wrap.
//!
//! # How the top uses it
//! * Timing: feed `qep_count` sampled at the ADC's conversion instant and delayed with the
//!   sample through the CORDIC pipeline, so both counts describe the same moment; then the
//!   only disagreement is the comparators' hysteresis against the ADC's zero crossings,
//!   well under one quadrant.
//! * Cross-check: `mismatch` goes into the monitor's `qep_mismatch` warning input.
//! * High-speed fallback: the quadrant counter's step warning (|step| >= 1.75 quadrants per
//!   sample) or the `overspeed` flag switches the coarse position source to the QEP count:
//!   the coarse count advances with the QEP steps (count - count at the switch, added to
//!   the CORDIC count at the switch) and the fine part is held at 0. The QEP count is
//!   exact as long as every A and B level lasts at least F clocks and A and B edges are
//!   at least one clock apart (with even quadrants: up to one quadrant per F/2 clocks, far
//!   above the ADC's limit of under two quadrants per sample). When the
//!   speed falls below the limit again, the top resynchronises the quadrant counter to the
//!   QEP-derived count (the counter's `load`/`load_qc`/`load_turns` inputs: qc + diff
//!   wrapped into 0..4PPR-1, turns stepped on each wrap), pulses `align` here, and returns
//!   to the CORDIC position; from then on `mismatch` watches both again.
pub mod hdl;
pub mod model;

/// Parameters of [`hdl::QepDecoder`] and [`model::QepModel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct QepParams {
    filter: u32,
    count_width: u32,
}

/// [`crate::error::Error::BlockParams`] for this block: `message` says what is wrong and what
/// is allowed.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("qep", message)
}

impl QepParams {
    /// `filter`: clocks a level must be stable before it is accepted, 1..=65535
    /// (1 = no filtering); `count_width`: quadrant counter width C, 2..=32 bits.
    pub fn new(filter: u32, count_width: u32) -> crate::error::Result<Self> {
        if !(1..=65535).contains(&filter) {
            return Err(invalid(format!(
                "QEP glitch filter length {filter} clocks is out of range: 1..=65535"
            )));
        }
        if !(2..=32).contains(&count_width) {
            return Err(invalid(format!(
                "QEP count width {count_width} bits is out of range: 2..=32"
            )));
        }
        Ok(Self {
            filter,
            count_width,
        })
    }
    /// Filter length F in clocks.
    pub fn filter(&self) -> u32 {
        self.filter
    }
    /// Counter width C in bits.
    pub fn count_width(&self) -> u32 {
        self.count_width
    }
    /// Bits of the filter counters (values 0..F-1), at least 1.
    pub fn filter_bits(&self) -> u32 {
        (32 - (self.filter - 1).leading_zeros()).max(1)
    }
}

/// Parameters of [`hdl::QepCrossCheck`] and [`model::CrossCheckModel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CrossCheckParams {
    count_width: u32,
    quadrants_per_turn: u64,
    tolerance: u32,
}

impl CrossCheckParams {
    /// `count_width`: C of the QEP count, 2..=32; `quadrants_per_turn`: Q = 4 PPR, the
    /// modulus of the CORDIC quadrant count, 4..=2^30 and a multiple of 4; `tolerance`:
    /// the largest |difference| in quadrants that is not a mismatch, 0..2^(C-1)-1
    /// (the thesis's rule is 1).
    pub fn new(
        count_width: u32,
        quadrants_per_turn: u64,
        tolerance: u32,
    ) -> crate::error::Result<Self> {
        if !(2..=32).contains(&count_width) {
            return Err(invalid(format!(
                "cross-check count width {count_width} bits is out of range: 2..=32"
            )));
        }
        if !(4..=1 << 30).contains(&quadrants_per_turn) || !quadrants_per_turn.is_multiple_of(4) {
            return Err(invalid(format!(
                "quadrants per turn {quadrants_per_turn} must be 4 * PPR in 4..=2^30"
            )));
        }
        if (tolerance as u64) >= (1u64 << (count_width - 1)) - 1 {
            return Err(invalid(format!(
                "cross-check tolerance {tolerance} quadrants does not fit a {count_width}-bit \
                 signed difference (max {})",
                (1u64 << (count_width - 1)).saturating_sub(2)
            )));
        }
        Ok(Self {
            count_width,
            quadrants_per_turn,
            tolerance,
        })
    }
    /// Count width C.
    pub fn count_width(&self) -> u32 {
        self.count_width
    }
    /// Quadrants per turn Q = 4 PPR.
    pub fn quadrants_per_turn(&self) -> u64 {
        self.quadrants_per_turn
    }
    /// Largest tolerated |difference| in quadrants.
    pub fn tolerance(&self) -> u32 {
        self.tolerance
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "qep",
    "QEP decoder",
    crate::report::jobs::qep_job,
);
