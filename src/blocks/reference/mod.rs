//! Position reference: homing on the index Z, the index latch and the preset. The block
//! sits between the core and every position output of the top and adds an offset, in
//! whole quadrants and turns, to the core's count; the fine part passes unchanged.
//!
//! ```text
//!  adc_conv ─►[edge]─► shift ┌──────────────┐ zs: Z at the conversion of the sample
//!  z_filt ──────────────────►│ zt (K+1 bits)├──────────┐
//!                            └──────────────┘          ▼
//!  in_valid ─┬──────────────────────────────► qual = zs & (qc mod 4 = gate quadrant)
//!  in_qc ────┤                                 event = qual & !pqual (first qualified)
//!  in_turns ─┤   ┌────────────────────────────┐        │ home (not referenced) / preset
//!            │   │ offset (oq, ot) = T - B    │◄───────┘ T = index or preset value,
//!            │   │ registered with oq - 4PPR, │          B = the sample's (qc, turns)
//!            │   │ ot + 1                     │
//!            │   └─────────────┬──────────────┘
//!            └─► out = in + offset (mod 4PPR, carry into turns) ─► out_qc, out_turns
//!  in_fine ─────────────────────────────────────────────────────► out_fine
//!  preset ─►[p1]─►[p2]─►[pp] rise: pending until the next sample   referenced, index_*
//! ```
//!
//! # The index at the sample (Z tag)
//! * The ADC samples at the assertion edge of CONV (chip select for the CS-framed chips).
//!   At each assertion, `zt` shifts in the filtered Z of the QEP decoder (`z_filt`: the pin
//!   through two synchronizer flops and the glitch filter, F + 3 clocks behind the pin).
//! * The core's `out_valid` for a sample comes L clocks after its assertion (L =
//!   [`crate::blocks::top::hdl::conv_to_position_cycles`], the ADC, the correction and the
//!   core), and assertions come every P clocks (the ADC period), so when the sample leaves
//!   the core, floor((L - 1) / P) later assertions have shifted in after it: its Z level is
//!   bit K = floor((L - 1) / P) of `zt`. `zt` is K + 1 bits wide (2 at the defaults).
//!
//! # Homing, the index latch and the preset
//! * A sample is *qualified* when its Z level is 1 and its quadrant (qc mod 4) is the gate
//!   quadrant: the quadrant whose comparator state (A = cos > 0, B = sin > 0) the config
//!   names, as the decoded angle numbers it (two on when the analog front end inverts both
//!   channels, as the LTC6912-1 of the Spartan-3AN kit does: the comparators see the
//!   encoder's own tracks, the ADC their inverse, 180 degrees apart). The gate quadrant of the period where Z is high is the reference quadrant; its
//!   count is B = 4u + gate for that period u, whichever side it is entered from and
//!   wherever in it the sample lies. So the index is the same place in both directions.
//! * An *index event* is the first qualified sample after an unqualified one. The first
//!   event after reset (with no preset) *homes*: the offset becomes T - B with T the
//!   configured index count (`[reference] quadrant` and `turn`), so that the reference
//!   quadrant reads T from the next sample on. The sample registers its request (`upd`;
//!   every sample loads its count and kind into `ubq`, `ubt`, `usel`, so the event enables
//!   no more than `upd`) and the offset is computed from those registers in the next
//!   clock, so the subtractions start at registers (the top's samples are an ADC period
//!   apart; a sample in that very next clock still takes the old offset). Each later event latches the position of
//!   its sample's quadrant (`index_qc`, `index_turns`, strobe `index_valid`): B + offset,
//!   which is T again while no count is lost. The homing event latches T itself, a clock
//!   later (`ihome`, registered for timing).
//! * A rising edge of the synchronized `preset` input (2 flops, then an edge register)
//!   is pending until the next sample, which takes the offset T - B with T the preset value
//!   (`preset_quadrant`, `preset_turn`) and B that sample's count: the position at the
//!   preset becomes the preset value with its fine part, so the fine part never jumps.
//!   A preset also counts as referenced; in its sample an index event neither homes nor
//!   latches.
//! * The absolute start (`[reference] absolute`, [`crate::blocks::absolute`]) is a third
//!   source of T: in a clock without a sample it asks (`abs_req`) with its target T
//!   (`abs_tq`, `abs_tt` and their neighbours) and the count B of the sample its word belongs
//!   to (`abs_bq`, `abs_bt`); the offset becomes T - B in the next clock, as for a preset.
//!   With it the requested target is held in registers (`htq` ...) from the request on,
//!   whichever source asked, and an index never homes: it latches once referenced. Without
//!   it those inputs are unused and the block has no logic for them.
//! * `referenced` is 1 from the first sample after the homing (or preset) on: it flags the
//!   output sample's frame, and the top ORs its inverse into the warning
//!   (`warn_until_referenced`).
//! * Homing needs a speed below one quadrant per sample so that no sample jumps over the
//!   reference quadrant: [`ReferenceParams::homing_rpm`].
//!
//! # Bit growth
//! * qc and the offset oq are in 0..4PPR-1 (quadrant_bits <= 18 bits). s = qc + oq lies in
//!   0..2*4PPR-2: one bit more. s2 = qc + oqm with oqm = oq - 4PPR (a 32-bit two's
//!   complement word, registered beside oq) is s - 4PPR; its sign bit chooses: s2 >= 0
//!   means a wrap, out_qc = s2 and the turns take ot + 1 (the register `otp`), else
//!   out_qc = s and the turns take ot. Turns are M-bit two's complement, modulo 2^M.
//! * The offset from T and B: d = Tq - Bq in -(4PPR-1)..4PPR-1; d < 0 borrows one turn:
//!   oq = d + 4PPR, ot = Tt - Bt - 1; else oq = d, ot = Tt - Bt (modulo 2^M). Three
//!   subtractions from the constant T side by side (Tq - Bq, Tq - 4PPR - Bq and
//!   Tq + 4PPR - Bq; Tt - Bt - 1, Tt - Bt and Tt - Bt + 1), chosen by d's sign.
//!
//! # Latency
//! One register stage: `out_valid` one clock after `in_valid`
//! ([`ReferenceParams::LATENCY`]), added to `conv_to_position_cycles` with the block on.
//!
//! # Ports
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clk`, `rst` | in | 1 | system clock; synchronous reset, active high |
//! | `conv` | in | 1 | the ADC's CONV (or chip select) register |
//! | `z` | in | 1 | filtered index Z of the QEP decoder |
//! | `preset` | in | 1 | preset request (asynchronous: synchronized here) |
//! | `in_valid`, `in_qc`, `in_fine`, `in_turns` | in | 1, 32 | the core's position |
//! | `out_valid`, `out_qc`, `out_fine`, `out_turns` | out | 1, 32 | the referenced position |
//! | `referenced` | out | 1 | the output position is referenced |
//! | `warning` | out | 1 | not referenced, with `warn_until_referenced` |
//! | `index_valid` | out | 1 | one clock: `index_qc`/`index_turns` latched an index |
//! | `index_qc`, `index_turns` | out | 32 | the referenced count of the last index |
//! | `abs_req` | in | 1 | the absolute start's request (one clock, no sample in it) |
//! | `abs_tq`, `abs_tqm`, `abs_tqp`, `abs_tt`, `abs_ttm`, `abs_ttp` | in | 32 | its target T_q, T_q - Q, T_q + Q, T_t, T_t - 1, T_t + 1 |
//! | `abs_bq`, `abs_bt` | in | 32 | the count B the target is for |
pub mod block;
pub mod hdl;
pub mod model;

pub use block::{ReferenceConfig, BLOCK};

use crate::blocks::mask;

/// [`crate::error::Error::BlockParams`] for this block.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("reference", message)
}

/// Parameters of [`hdl::PositionReference`] and [`model::ReferenceModel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct ReferenceParams {
    quadrants_per_turn: u64,
    turns_bits: u32,
    gate: u32,
    gate_levels: &'static str,
    index: (u64, u64),
    preset: (u64, u64),
    tag_shift: u32,
    conv_active_high: bool,
    warn_until_referenced: bool,
    /// The absolute start is a source of T (`crate::blocks::absolute`); left out of the
    /// parameter file when false, so configurations without it keep their bytes.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    absolute: bool,
}

impl ReferenceParams {
    /// Clocks from `in_valid` to `out_valid`.
    pub const LATENCY: u32 = 1;

    /// `quadrants_per_turn`: Q = 4 PPR (4..=2^18, a multiple of 4); `turns_bits`: M
    /// (0..=31); `gate`: the reference quadrant 0..=3; `index` and `preset`: (quadrant
    /// count 0..Q-1, turn count as an M-bit two's-complement word); `latency`: L, clocks
    /// from a CONV assertion to the core's `out_valid` of its sample; `period`: P, clocks
    /// between assertions.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        quadrants_per_turn: u64,
        turns_bits: u32,
        gate: u32,
        index: (u64, u64),
        preset: (u64, u64),
        latency: u32,
        period: u32,
        conv_active_high: bool,
        warn_until_referenced: bool,
    ) -> crate::error::Result<Self> {
        if !(4..=1 << 18).contains(&quadrants_per_turn) || !quadrants_per_turn.is_multiple_of(4) {
            return Err(invalid(format!(
                "quadrants per turn {quadrants_per_turn} must be 4 * PPR in 4..=2^18"
            )));
        }
        if turns_bits > 31 || gate > 3 {
            return Err(invalid(format!(
                "turn bits {turns_bits} (allowed 0..=31) or gate quadrant {gate} (allowed 0..=3)"
            )));
        }
        for (what, (q, t)) in [("index", index), ("preset", preset)] {
            if q >= quadrants_per_turn || t > mask(turns_bits) {
                return Err(invalid(format!(
                    "{what} count ({q}, {t}): the quadrant must be below {quadrants_per_turn} and the turn fit {turns_bits} bits"
                )));
            }
        }
        if period == 0 || latency == 0 {
            return Err(invalid("the ADC period and the latency must be > 0".into()));
        }
        let tag_shift = (latency - 1) / period;
        if tag_shift > 30 {
            return Err(invalid(format!(
                "{latency} clocks from a conversion to its position is {tag_shift} ADC periods: at most 30"
            )));
        }
        Ok(Self {
            quadrants_per_turn,
            turns_bits,
            gate,
            gate_levels: "",
            index,
            preset,
            tag_shift,
            conv_active_high,
            warn_until_referenced,
            absolute: false,
        })
    }

    /// With the absolute start's target as a third source of T (its ports `abs_*`).
    pub fn with_absolute(mut self, on: bool) -> Self {
        self.absolute = on;
        self
    }
    /// The absolute start is a source of T.
    pub fn absolute(&self) -> bool {
        self.absolute
    }

    /// Q = 4 PPR.
    pub fn quadrants_per_turn(&self) -> u64 {
        self.quadrants_per_turn
    }
    /// M: bits of the turn count.
    pub fn turns_bits(&self) -> u32 {
        self.turns_bits
    }
    /// The reference (gate) quadrant of the decoded angle, 0..=3.
    pub fn gate(&self) -> u32 {
        self.gate
    }
    /// The comparator levels "AB" the config named for the gate.
    pub fn gate_levels(&self) -> &'static str {
        self.gate_levels
    }
    /// With the comparator levels "AB" of the gate, for `check`.
    pub fn with_gate_levels(mut self, levels: &'static str) -> Self {
        self.gate_levels = levels;
        self
    }
    /// (quadrant count, turn word) the reference quadrant reads after homing.
    pub fn index(&self) -> (u64, u64) {
        self.index
    }
    /// (quadrant count, turn word) a preset loads.
    pub fn preset(&self) -> (u64, u64) {
        self.preset
    }
    /// K: the bit of `zt` that holds the Z level of the sample leaving the core.
    pub fn tag_shift(&self) -> u32 {
        self.tag_shift
    }
    /// CONV (chip select) is active high: its rising edge samples.
    pub fn conv_active_high(&self) -> bool {
        self.conv_active_high
    }
    /// The top ORs "not referenced" into the warning.
    pub fn warn_until_referenced(&self) -> bool {
        self.warn_until_referenced
    }
    /// Highest speed at which homing cannot miss the reference quadrant: one quadrant per
    /// sample, in rpm, at `sample_rate_hz`.
    pub fn homing_rpm(&self, sample_rate_hz: f64) -> f64 {
        sample_rate_hz / self.quadrants_per_turn as f64 * 60.0
    }
    /// The offset (oq, ot) that makes base count `b` read target `t` (both (quadrant count,
    /// turn word)): oq = (tq - bq) mod Q, ot = tt - bt - borrow (mod 2^M).
    pub fn offset(&self, t: (u64, u64), b: (u64, u64)) -> (u64, u64) {
        let q = self.quadrants_per_turn as i64;
        let d = t.0 as i64 - b.0 as i64;
        let borrow = u64::from(d < 0);
        let oq = d.rem_euclid(q) as u64;
        let ot = t.1.wrapping_sub(b.1).wrapping_sub(borrow) & mask(self.turns_bits);
        (oq, ot)
    }
    /// Count `c` moved by offset `o` (both (quadrant count, turn word)): the quadrant count
    /// modulo Q, its wrap carried into the turns (mod 2^M).
    pub fn apply(&self, c: (u64, u64), o: (u64, u64)) -> (u64, u64) {
        let s = c.0 + o.0;
        let carry = u64::from(s >= self.quadrants_per_turn);
        (
            s - carry * self.quadrants_per_turn,
            c.1.wrapping_add(o.1).wrapping_add(carry) & mask(self.turns_bits),
        )
    }
}
