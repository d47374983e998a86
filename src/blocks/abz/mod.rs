//! ABZ incremental encoder emulation: the decoded single-turn position becomes the A/B
//! quadrature signals and the Z index of an incremental encoder with `lines` A/B periods
//! per turn, for drives and second controllers that accept only A/B/Z.
//!
//! ```text
//!             capture        serial divider (Wp clocks)      fold (3 stages)        emitter
//!  in_valid ─►[have]  ┌──────────────────────────────┐  ┌──────────────────┐  ┌──────────────────┐
//!  in_qc ────►[qcap]─►│ p = qc·2^F + fine, MSB first │  │ d = t - t_old    │  │ pend += dd       │
//!  in_fine ──►[fcap]─►│ r' = 2r + bit·a - k·b        ├─►│ fold into        ├─►│ step ±1 toward 0 │─► abz_a
//!                     │ t' = 2t + k, k in {0,1,2}    │ t│ (-E/2, E/2]: dd  │dd│ every >= S clocks│─► abz_b
//!                     │ (largest k with r' >= 0)     │  └──────────────────┘  │ c ±1 mod E       │─► abz_z
//!                     └──────────────────────────────┘                        │ A,B from c mod 4 │─► warning
//!                                                                             └──────────────────┘
//! ```
//!
//! # Position -> count: the rounding rule
//! * The position is `p = qc · 2^F + fine` in 0..P, P = Q · 2^F positions per turn (Q = 4 PPR
//!   quadrants, F fine bits). The emulator has E = 4 · lines edges (counts) per turn.
//! * Count of a position: **t = floor(p · E / P)**, computed exactly (integer arithmetic,
//!   no approximated ratio). With g = gcd(E, P), a = E/g and b = P/g, t = floor(p · a / b).
//!   Count t covers the positions ceil(t·P/E) ..= ceil((t+1)·P/E) - 1. Because every
//!   sample is converted from its absolute position, the rule cannot drift: t(P) = E, so a
//!   whole turn is exactly E counts and the count of position 0 is 0 on every turn, however
//!   E and P relate (e.g. PPR 2048, F 14, lines 1000: P/E = 2^27/4000, not an integer).
//! * Allowed: 1 <= lines and E = 4·lines <= P (at most one edge per position LSB), b <= 2^30
//!   (the remainder's 32-bit sign test below), E <= 2^30.
//! * The default lines = 16 PPR gives E/P = 16 / 2^F, i.e. t = p >> (F - 4).
//!
//! # Serial divider (bit growth)
//! The Wp = ceil(log2 Q) + F bits of p enter MSB first, one per clock. With p_k the first k
//! bits, the invariant is p_k · a = t_k · b + r_k, 0 <= r_k < b. Appending bit β:
//! p_(k+1) · a = 2 t_k b + (2 r_k + β a), and 2 r_k + β a < 2b + a <= 3b (a <= b since
//! E <= P), so the quotient digit k = floor((2 r_k + β a) / b) is 0, 1 or 2. Three adders
//! side by side form c_j = 2 r_k + β a - j b (j = 0, 1, 2; the addend a constant chosen by β)
//! and the largest j with c_j >= 0 wins: r_(k+1) = c_j, t_(k+1) = 2 t_k + j (2t, 2t | 1, or
//! (t + 1) << 1, with t + 1 formed beside them). Widths: r < b <= 2^30, so c_1 lies in
//! (-b, 2b) and c_2 in [-2b, b): both fit a signed R_w-bit word, R_w = bits(2b) + 1 <= 32
//! (the adders are R_w bits wide, their sign is bit R_w - 1; 13 bits at the default
//! b = 2^10). t < E <= 2^30 holds at every step (t_k <= t), so t, and the emitted count c,
//! are E_w = bits(E - 1) bits wide (17 at the default E = 2^17): short carry chains.
//! After Wp clocks t = floor(p a / b).
//! The qc and fine bits shift through two registers: qsh (ceil(log2 Q) bits) takes the fine
//! register's MSB in at its LSB, so the current bit is always qsh's MSB.
//!
//! # Fold and emitter
//! * d = t - t_old (32-bit, in (-E, E)); dd = d folded into (-E/2, E/2] by +-E: the shortest
//!   way round the turn, so a turn wrap (t from E-1 to 0) is one count, not -(E-1). The
//!   position may therefore move less than half a turn between conversions.
//! * `pend` (32-bit two's complement) holds the counts still owed: pend += dd per sample,
//!   -1 per step up, +1 per step down. The emitted count c (0..E-1) always satisfies
//!   c + pend = t_old (mod E): no count is dropped or invented, however far behind it is.
//! * A step is taken when pend != 0 and at least S clocks have passed since the last step
//!   (S = ceil(f_clk / max_edge_hz) >= 2, a down-counter and a registered `hold` flag).
//!   pend's flags (nonzero, sign, |pend| = 1) are registered from pend, so they describe
//!   the previous clock; after a step (pend moved one toward 0) `|pend| = 1` says whether it
//!   is now 0, and S >= 2 means no step follows a step directly. In the clock after a sample
//!   was added the flags still describe pend before it: a step then goes toward the previous
//!   sample's count, which the position did reach, so the output follows the sampled path.
//!   A sample's dd is added in a clock without a step (a step first delays it one clock).
//! * c steps by +-1 modulo E (E need not be a power of two): c + cadd, one adder whose
//!   addend is a register, 1 or -1 as pend's sign says, or on a wrap (c = E-1 going up,
//!   c = 0 going down) the addend that lands on 0 or E-1; it is registered from the values
//!   pend's sign and c's flags have next clock, so it describes the registers it is added
//!   to. A and B come from c mod 4 (forward 00 -> 10 -> 11 -> 01:
//!   A leads B), Z = (c = 0): one quarter A/B period, at position 0 of each turn (the
//!   positions 0 ..= ceil(P/E) - 1). A, B and Z are registered from c in the same clock.
//! * `warning` rises when a sample's counts are added while counts of the previous one are
//!   still owed (the output lags the position by more than one sample period: the position
//!   runs faster than max_edge_hz allows, or jumped) and falls when pend is 0 again.
//! * The first converted sample after reset sets c = t (A/B/Z jump to that state without
//!   counting); a receiver counts from there.
//!
//! # Timing
//! * Latency from `in_valid` to the first edge of a sample (emitter idle): the capture (1),
//!   the start (1), Wp divider clocks, three fold stages, the add (1) and two clocks until
//!   pend's flags are fresh, then A/B/Z are registered (1): [`AbzParams::latency`] clocks.
//! * Samples arriving while the divider is busy replace the captured one: the newest is
//!   converted next (no count is lost, only the intermediate positions are not visited).
//! * Maximum sustained edge rate f_clk / S; maximum speed 60 · f_clk / (S · E) rpm.
//! * No register-to-register path holds more than one carry chain: the divider's adders
//!   take a constant chosen by a registered bit and end in a sign-bit select; the fold's
//!   compares and its add are in separate stages; the emitter's step decision is one LUT of
//!   registered flags in front of pend's adders (pend ± 1, pend + dd side by side).
//! * c's adder feeds only the select of the first sample's load (a step never meets a load:
//!   pend is 0 until a sample is folded, which needs the first one). The compares on c
//!   (c = 0, c = E-1) and on pend (bits 31..1 all zero, all one) are the sign bits of one
//!   subtraction each, carry chains from registers with at most one LUT after them, not
//!   17- and 32-input LUT trees.
pub mod block;
pub mod hdl;
pub mod model;

pub use block::{AbzConfig, ABZ_DEFAULT_EDGE_HZ, BLOCK};

/// [`crate::error::Error::BlockParams`] for this block.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("abz", message)
}

/// Greatest common divisor.
fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Parameters of [`hdl::AbzEmulator`] and [`model::AbzModel`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct AbzParams {
    quadrants_per_turn: u64,
    fine_bits: u32,
    lines: u64,
    spacing: u32,
}

impl AbzParams {
    /// `quadrants_per_turn`: Q = 4 PPR (4..=2^18, a multiple of 4); `fine_bits`: F (1..=16);
    /// `lines`: A/B periods per turn, 1..=P/4 (P = Q 2^F), with P / gcd(4 lines, P) <= 2^30
    /// and 4 lines <= 2^30; `spacing`: minimum clocks between two edges, 2..=2^24.
    pub fn new(
        quadrants_per_turn: u64,
        fine_bits: u32,
        lines: u64,
        spacing: u32,
    ) -> crate::error::Result<Self> {
        if !(4..=1 << 18).contains(&quadrants_per_turn) || !quadrants_per_turn.is_multiple_of(4) {
            return Err(invalid(format!(
                "quadrants per turn {quadrants_per_turn} must be 4 * PPR in 4..=2^18"
            )));
        }
        if !(1..=16).contains(&fine_bits) {
            return Err(invalid(format!(
                "fine bits {fine_bits} out of range: allowed 1..=16"
            )));
        }
        let p = quadrants_per_turn << fine_bits;
        if lines == 0 || 4 * lines > p {
            return Err(invalid(format!(
                "{lines} lines per turn: allowed 1..={} (4 edges per line, at most one edge per position LSB: {p} positions per turn)",
                p / 4
            )));
        }
        if 4 * lines > 1 << 30 {
            return Err(invalid(format!(
                "{lines} lines per turn: at most 2^28 (= {})",
                1u64 << 28
            )));
        }
        let b = p / gcd(4 * lines, p);
        if b > 1 << 30 {
            return Err(invalid(format!(
                "{lines} lines per turn: positions per turn / gcd(4 lines, positions per turn) = {b} exceeds 2^30 (the divider's remainder); choose lines sharing more factors of two with 4 PPR 2^F, e.g. a multiple of {}",
                (p >> 30).next_power_of_two()
            )));
        }
        if !(2..=1 << 24).contains(&spacing) {
            return Err(invalid(format!(
                "minimum edge spacing {spacing} clocks out of range: allowed 2..=2^24 (max_edge_hz at most clock / 2)"
            )));
        }
        Ok(Self {
            quadrants_per_turn,
            fine_bits,
            lines,
            spacing,
        })
    }
    /// Q = 4 PPR.
    pub fn quadrants_per_turn(&self) -> u64 {
        self.quadrants_per_turn
    }
    /// F.
    pub fn fine_bits(&self) -> u32 {
        self.fine_bits
    }
    /// A/B periods per turn.
    pub fn lines(&self) -> u64 {
        self.lines
    }
    /// Minimum clocks between two edges, S.
    pub fn spacing(&self) -> u32 {
        self.spacing
    }
    /// Edges (counts) per turn E = 4 lines.
    pub fn edges(&self) -> u64 {
        4 * self.lines
    }
    /// Positions per turn P = Q 2^F.
    pub fn positions(&self) -> u64 {
        self.quadrants_per_turn << self.fine_bits
    }
    /// (a, b): E/P in lowest terms.
    pub fn ratio(&self) -> (u64, u64) {
        let g = gcd(self.edges(), self.positions());
        (self.edges() / g, self.positions() / g)
    }
    /// Bits of the quadrant count qc (enough for Q - 1).
    pub fn quadrant_bits(&self) -> u32 {
        64 - (self.quadrants_per_turn - 1).leading_zeros()
    }
    /// Bits of the position, Wp: one divider clock each.
    pub fn position_bits(&self) -> u32 {
        self.quadrant_bits() + self.fine_bits
    }
    /// The count of position `p` (0..P): floor(p E / P), the rounding rule.
    pub fn count_of(&self, p: u64) -> u64 {
        ((p as u128 * self.edges() as u128) / self.positions() as u128) as u64
    }
    /// Clocks from the `in_valid` clock (the sample on the inputs before edge 0) to the first
    /// output edge of that sample when the emitter is idle: the edge after which A/B show it.
    pub fn latency(&self) -> u32 {
        self.position_bits() + 8
    }
    /// Bits of a count, E_w: t and c lie in 0..E-1 (at least 1 bit).
    pub fn count_bits(&self) -> u32 {
        (64 - (self.edges() - 1).leading_zeros()).max(1)
    }
    /// Bits of the divider's remainder words, R_w = bits(2b) + 1 (at most 32): the
    /// candidates c_1, c_2 lie in (-2b, 2b), a signed R_w-bit range (module docs).
    pub fn remainder_bits(&self) -> u32 {
        (64 - (2 * self.ratio().1).leading_zeros() + 1).min(32)
    }
    /// Bits of the edge-spacing counter (values 0..S-1).
    pub fn timer_bits(&self) -> u32 {
        (32 - (self.spacing - 1).leading_zeros()).max(1)
    }
}
