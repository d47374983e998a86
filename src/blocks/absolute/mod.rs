//! Absolute start: an SSI master reads the encoder's own digital channel once after reset,
//! and the coarse absolute word is merged with the interpolated position, as the absolute
//! data interface (ADI) of iC-MR does (iC-MR data sheet, rev. A1, "Absolute data interface":
//! a BiSS/SSI master on AMAO/ASLI that reads the absolute data at start-up and synchronizes it
//! on the cycle counter with up to three synchronization bits). This is how encoders with
//! 1 Vpp tracks and an SSI, EnDat 01 or BiSS digital channel (Heidenhain ECN/EQN 413 and
//! ROC/ROQ 425, Kübler and Hengstler SSI + SinCos) give an absolute position with sin/cos
//! interpolation. The block hands a target count T and the count B of the sample it belongs
//! to to the position reference ([`crate::blocks::reference`]), whose offset path makes B read
//! T; from then on every output is absolute (docs/absolute.md).
//!
//! ```text
//!            ┌───────────── state: Wait ─► Ready ─► (Low ─► High) x (N + 1) ─► Tail ──┐
//!  conv ──►[edge]─┤ start at a CONV assertion, line idle                              │
//!            │    └─► lt (K+1 bits): the latch's conversion ─┐                        │
//!  in_valid ─┼───────────────────────────────────────────────┴► B = (bq, bt), o      │
//!  in_qc ────┤                                                  (the sample of that   │
//!  in_fine ──┤                                                   conversion)          │
//!  in_turns ─┘                                                                        │
//!  abs_data ─►[s1]─►[s2]─► bit n at the launch of rising edge n+1 ─► Gray -> binary ─► w │
//!  abs_clk ◄─[ckn] idle high; F1 latches; N + 1 pulses of 2H clocks; the tail reads 0    │
//!            ┌────────────────────────────────────────────────────────────────────────┘
//!            └► Sync: δ = (o - c) mod 2^(k+3), c = 2 st + 1 ─► Place: p = c + sext(δ)
//!               ─► Split: tq = p >> (k+1), tt = turns ± 1 ─► Target: tq ∓ Q, tt ∓ 1
//!               ─► Request: req (a clock without a sample) ─► Done
//! ```
//!
//! # The SSI frame (data sheets)
//! * Quiescent: clock and data high. The first falling clock edge stores the position; the
//!   first rising edge puts the MSB on the data line, each further rising edge the next bit;
//!   after the LSB the encoder answers the next rising edge with 0 and holds the line low
//!   until its monoflop time t_m (Heidenhain t2 = 17 to 20 us) after the last clock edge has
//!   passed, then returns it high (Heidenhain SSI interface description, PWM 20 manual; Posital
//!   SSI interface description: n + 1 clock pulses per read).
//! * The word is N = M_a + S bits, MSB first: M_a multi-turn bits ahead of S single-turn bits,
//!   Gray-coded over the whole word (`gray`) or binary (Heidenhain: 13 bits ECN/ROC, 25 bits
//!   EQN/ROQ, Gray).
//! * The master here gives N + 1 pulses and takes bit n (n = 1..N, the answer to rising edge
//!   n) at the edge that launches rising edge n + 1, and the line's answer to the last pulse
//!   (the tail, which must be 0) 2H clocks after it. Gray is decoded as the bits arrive:
//!   binary bit = the previous binary bit XOR the Gray bit (0 before the MSB).
//! * After reset the clock stays high for W clocks (at least the encoder's t_m, so that a
//!   frame cut by the reset has ended), then the master waits for the line to be high and
//!   starts at the next CONV assertion. A frame whose tail is not 0 (no encoder, the line held
//!   high), or whose conversion gave no sample, sets `fault`, waits W clocks and reads again.
//!
//! # Tying the word to a sample (the latch instant)
//! * The first falling edge leaves the FPGA one clock after the CONV assertion edge that
//!   samples the ADC ([`SsiTiming::LATCH_LAG_CLOCKS`]: the edge register), so the encoder
//!   stores its position one clock plus the cable's one-way delay after the ADC samples
//!   (7.5 ns + 30 ns for 5 m at 133.33 MHz: 0.015 quadrants at 3000 rpm with 2048 lines, a
//!   part of the alignment error the merge tolerates).
//! * As the reference tags Z, `lt` shifts in, at each CONV assertion, whether the frame
//!   started there. The core's `out_valid` for a sample comes L clocks after its assertion
//!   and assertions come every P clocks, so the sample of the latch's conversion is the one
//!   leaving the core with bit K = floor((L - 1) / P) of `lt` set. Its count B = (bq, bt)
//!   and its synchronization bits o (below) are kept.
//!
//! # The merge (synchronization bits)
//! * The absolute word has 2^S codes per turn with 2^S = 4 PPR 2^k, k >= 0: each code is
//!   2^-k quadrant. The interpolator knows its position modulo one signal period exactly: the
//!   quadrant (qc + s) mod 4 (s = 2 when the analog front end inverts both channels, as the
//!   kit's LTC6912-1 does: the decoded angle is the encoder's plus 180 degrees) and the fine
//!   part. In units u = 2^-(k+1) quadrant (half a code), its k + 3 synchronization bits are
//!   o = ((qc + s) mod 4) 2^(k+1) + (fine >> (F - k - 1)).
//! * The absolute word's single-turn code st stands for [st, st + 1) codes; its centre in u is
//!   c = 2 st + 1. The merged position is the one within two quadrants of that centre whose
//!   low k + 3 bits are o: δ = (o - c) mod 2^(k+3) read as a (k+3)-bit two's complement
//!   number (-2..2 quadrants), p = c + δ. Then p and the interpolated position agree modulo
//!   one signal period, so the interpolated quadrant and fine part stay, and the period
//!   comes from the absolute word, also across a period or turn boundary (p < 0 borrows a
//!   turn, p >= 2^(S+1) carries one).
//! * Tolerance: with the digital channel's alignment error e (its code edges against the
//!   interpolated quadrant edges, plus the motion between the latch and the sample) the
//!   right period is found whenever |e| <= 2 quadrants - u = 2 - 2^-(k+1) quadrants, less
//!   the interpolator's own error (a few fine LSB): +-1.5 quadrants (+-135 degrees electrical)
//!   for a word of one code per quadrant (k = 0, e.g. 13 bits at 2048 lines). Proof: with X
//!   the true position in u, o - c = floor(X) - 2 floor((X + e)/2) - 1 lies in
//!   (-e - 2, -e + 1), which stays inside the 2^(k+3) window [-2^(k+2), 2^(k+2)) for all X
//!   exactly when |e| <= 2^(k+2) - 1 u.
//!
//! # Bit growth
//! * w: N <= 32 bits. st: S <= 29 bits; c = 2 st + 1: S + 1 bits.
//! * o and δ: k + 3 bits (k <= F - 1). p = c + sext(δ) lies in -2^(k+2)+1 .. 2^(S+1) +
//!   2^(k+2) - 2: S + 3 bits two's complement (S + 3 <= 32). Its sign bit S + 2 borrows a
//!   turn; bit S + 1 without the sign carries one.
//! * tq = (p >> (k+1)) mod 2^qb (qb = S - k = log2(4 PPR) bits): the low S + 1 bits of p,
//!   shifted, as the wrap into one turn needs. tt = turns + carry - borrow mod 2^M (M the
//!   decoder's turn bits; the word's M_a turn bits zero-extended or cut).
//! * tqm = tq - Q (qb + 1 bits two's complement), tqp = tq + Q, ttm = tt - 1, ttp = tt + 1
//!   (M bits): the six words the reference's offset path takes from a target (its constants
//!   for the index and the preset).
//! * Counters: `cnt` counts to max(W - 1, H + 2) (bits of that), `n` to N + 1 (6 bits).
//!
//! # Latency
//! The read takes W + (up to P) + (N + 1) 2H + H + 2 clocks, the merge five more: 50 us at
//! the defaults (20 us monoflop, 13 bits at 500 kHz, 133.33 MHz; `check` prints it).
//! `referenced` rises with the first output sample after the reference takes the target
//! (its one-clock offset stage).
//!
//! # Ports
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clk`, `rst` | in | 1 | system clock; synchronous reset, active high |
//! | `conv` | in | 1 | the ADC's CONV (or chip select) register |
//! | `in_valid`, `in_qc`, `in_fine`, `in_turns` | in | 1, 32 | the core's position |
//! | `abs_data` | in | 1 | the encoder's SSI data line (asynchronous: two flops here) |
//! | `abs_clk` | out | 1 | the SSI clock to the encoder (registered, idle high) |
//! | `req` | out | 1 | one clock, never with `in_valid`: the target and B are ready |
//! | `tq`, `tqm`, `tqp`, `tt`, `ttm`, `ttp` | out | 32 | the target T and its neighbours |
//! | `bq`, `bt` | out | 32 | the count B of the latch's sample |
//! | `fault` | out | 1 | the last frame failed (until a frame succeeds) |
//!
//! # Line timing (the one derivation; docs/absolute.md)
//! [`SsiTiming`] derives, from the system clock, the configured SSI rate, the encoder's t1
//! (clock edge to valid data) and t_m and the board's I/O budget ([`crate::board::IoTiming`]):
//! the half period H in clocks (RTL), the capture distance C = 2H from the edge launching
//! rising edge n to the synchronizer's first flop taking bit n (RTL), the longest line round
//! trip that leaves (`check`, the SDC/XDC comment), the wait W (RTL) and the latch lag (the
//! sketch above; the closed loop's encoder model keeps its own latch instant):
//!
//! ```text
//!   C T  >=  t_co + 2 t_trace + r + t1 + t_su          r: cable + transceivers, both ways
//!   r_max = 2 H T - (t_co + 2 t_trace + t1 + t_su)
//! ```
//!
//! The hold side needs nothing: the bit changes only after the next rising edge has
//! travelled to the encoder and back, after the edge that samples it.
pub mod block;
pub mod hdl;
pub mod model;

pub use block::{AbsoluteSsiConfig, BLOCK};

use crate::blocks::mask;

/// [`crate::error::Error::BlockParams`] for this block.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("absolute", message)
}

/// The SSI line timing: the one derivation the RTL, the constraints, `check` and the closed
/// loop read (module docs, "Line timing").
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct SsiTiming {
    /// System clock, Hz.
    pub clock_hz: f64,
    /// H: system clocks per half SSI clock period.
    pub half_clocks: u32,
    /// W: system clocks the SSI clock stays high after reset and after a failed frame.
    pub wait_clocks: u32,
    /// t1: the encoder's clock edge to valid data, ns (data sheet; cable not included).
    pub data_valid_ns: f64,
    /// t_m: the encoder's monoflop time, us (the wait W covers it).
    pub monoflop_us: f64,
    /// The board's I/O budget (clock-to-out, trace, input set-up).
    pub io: crate::board::IoTiming,
}

impl SsiTiming {
    /// Clock edges from the CONV assertion edge that samples the ADC to the edge that
    /// launches the first falling SSI clock edge (the edge register of the start).
    pub const LATCH_LAG_CLOCKS: u32 = 1;
    /// Flops of the `abs_data` synchronizer: a bit sampled at an edge enters the word this
    /// many clocks later.
    pub const SYNC_CLOCKS: u32 = 2;
    /// Smallest H: the synchronizer's two clocks fit inside a half period.
    pub const MIN_HALF_CLOCKS: u32 = 4;

    /// The timing at `clock_hz` for an SSI clock of at most `rate_hz`, an encoder with
    /// `data_valid_ns` (t1) and `monoflop_us` (t_m), on the board budget `io`.
    pub fn new(
        clock_hz: f64,
        rate_hz: f64,
        data_valid_ns: f64,
        monoflop_us: f64,
        io: crate::board::IoTiming,
    ) -> crate::error::Result<Self> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(invalid(format!("the SSI clock {rate_hz} Hz must be > 0")));
        }
        let h = (clock_hz / (2.0 * rate_hz)).ceil();
        if h < Self::MIN_HALF_CLOCKS as f64 {
            return Err(invalid(format!(
                "an SSI clock of {:.3} MHz leaves {h:.0} system clocks per half period at {:.3} MHz; at least {} are needed (at most {:.3} MHz)",
                rate_hz / 1e6,
                clock_hz / 1e6,
                Self::MIN_HALF_CLOCKS,
                clock_hz / (2.0 * Self::MIN_HALF_CLOCKS as f64) / 1e6
            )));
        }
        if h > (1u64 << 20) as f64 {
            return Err(invalid(format!(
                "an SSI clock of {rate_hz} Hz is {h:.0} system clocks per half period: at most 2^20"
            )));
        }
        let w = (monoflop_us * 1e-6 * clock_hz).ceil();
        if !(1.0..=(1u64 << 24) as f64).contains(&w) {
            return Err(invalid(format!(
                "a monoflop time of {monoflop_us} us is {w:.0} system clocks: allowed 1..=2^24"
            )));
        }
        let t = Self {
            clock_hz,
            half_clocks: h as u32,
            wait_clocks: w as u32,
            data_valid_ns,
            monoflop_us,
            io,
        };
        if t.max_round_trip_ns() < 0.0 {
            return Err(invalid(format!(
                "at {:.3} MHz the encoder's data ({data_valid_ns} ns after its clock edge) arrives {:.1} ns after the edge that samples it, even with no cable: {}; lower the SSI clock",
                t.rate_hz() / 1e6,
                -t.max_round_trip_ns(),
                t.budget_text()
            )));
        }
        Ok(t)
    }

    /// The SSI clock the master gives: clock / 2H, Hz.
    pub fn rate_hz(&self) -> f64 {
        self.clock_hz / (2 * self.half_clocks) as f64
    }
    /// System clock period, ns.
    pub fn tclk_ns(&self) -> f64 {
        1e9 / self.clock_hz
    }
    /// C: clocks from the edge that launches rising edge n to the edge at which the
    /// synchronizer's first flop takes bit n (the launch of rising edge n + 1): 2H.
    pub fn capture_clocks(&self) -> u32 {
        2 * self.half_clocks
    }
    /// The round trip the sample needs without the line: t_co + 2 t_trace + t1 + t_su, ns.
    pub fn needed_ns(&self) -> f64 {
        self.io.clock_to_out_ns
            + 2.0 * self.io.trace_ns
            + self.data_valid_ns
            + self.io.input_setup_ns
    }
    /// The longest line round trip (cable and transceivers, both ways), ns: C T less
    /// [`needed_ns`](Self::needed_ns).
    pub fn max_round_trip_ns(&self) -> f64 {
        self.capture_clocks() as f64 * self.tclk_ns() - self.needed_ns()
    }
    /// The budget as `check` and the constraints print it.
    pub fn budget_text(&self) -> String {
        format!(
            "clock-to-out {:.2} + 2 x trace {:.2} + data valid t1 {:.2} + input set-up {:.2} = {:.2} ns of C T = {} x {:.3} = {:.2} ns",
            self.io.clock_to_out_ns,
            self.io.trace_ns,
            self.data_valid_ns,
            self.io.input_setup_ns,
            self.needed_ns(),
            self.capture_clocks(),
            self.tclk_ns(),
            self.capture_clocks() as f64 * self.tclk_ns()
        )
    }
    /// Clocks of one frame of `bits` data bits from its first falling edge to the tail's
    /// sample leaving the synchronizer: (N + 1) 2H + H + 2.
    pub fn frame_clocks(&self, bits: u32) -> u32 {
        (bits + 1) * 2 * self.half_clocks + self.half_clocks + Self::SYNC_CLOCKS
    }
    /// The instant the encoder latches, after the ADC's sampling instant, ns: the latch lag
    /// and the cable's one-way delay `line_ns` (both pins leave the FPGA through the same
    /// clock-to-out and trace).
    pub fn latch_after_sample_ns(&self, line_ns: f64) -> f64 {
        Self::LATCH_LAG_CLOCKS as f64 * self.tclk_ns() + line_ns
    }
}

/// The absolute word's format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct SsiWord {
    /// S: single-turn bits (2^S = 4 PPR 2^k).
    pub single_turn_bits: u32,
    /// M_a: multi-turn bits ahead of them.
    pub multiturn_bits: u32,
    /// Gray code over the whole word (else binary).
    pub gray: bool,
}

impl SsiWord {
    /// N = M_a + S.
    pub fn bits(&self) -> u32 {
        self.single_turn_bits + self.multiturn_bits
    }
}

/// Parameters of [`hdl::AbsoluteStart`] and [`model::AbsoluteModel`].
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AbsoluteParams {
    word: SsiWord,
    quadrant_bits: u32,
    fine_bits: u32,
    turns_bits: u32,
    quadrant_shift: u32,
    tag_shift: u32,
    conv_active_high: bool,
    timing: SsiTiming,
}

impl AbsoluteParams {
    /// `word`: the absolute word; `quadrant_bits`: qb = log2(4 PPR) (4 PPR a power of two,
    /// 4..=2^18); `fine_bits`: F; `turns_bits`: M (0..=31); `inverted`: the front end inverts
    /// both channels (s = 2); `latency`: L, clocks from a CONV assertion to the core's
    /// `out_valid` of its sample; `period`: P, clocks between assertions.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        word: SsiWord,
        quadrant_bits: u32,
        fine_bits: u32,
        turns_bits: u32,
        inverted: bool,
        latency: u32,
        period: u32,
        conv_active_high: bool,
        timing: SsiTiming,
    ) -> crate::error::Result<Self> {
        if !(2..=18).contains(&quadrant_bits) || turns_bits > 31 || !(2..=16).contains(&fine_bits) {
            return Err(invalid(format!(
                "quadrant bits {quadrant_bits} (allowed 2..=18), fine bits {fine_bits} (2..=16) or turn bits {turns_bits} (0..=31)"
            )));
        }
        let s = word.single_turn_bits;
        if s < quadrant_bits {
            return Err(invalid(format!(
                "a single-turn word of {s} bits has {} codes per turn, fewer than the {} quadrants (4 x PPR): at least {quadrant_bits} bits are needed",
                1u64 << s,
                1u64 << quadrant_bits
            )));
        }
        if s > 29 {
            return Err(invalid(format!(
                "{s} single-turn bits: at most 29 (the merge's sum has S + 3 bits)"
            )));
        }
        let k = s - quadrant_bits;
        if k + 1 > fine_bits {
            return Err(invalid(format!(
                "{s} single-turn bits resolve 2^-{k} quadrant: the merge compares k + 1 = {} fine bits, more than the {fine_bits} the core has",
                k + 1
            )));
        }
        if word.bits() > 32 || word.multiturn_bits > 24 {
            return Err(invalid(format!(
                "{} multi-turn + {s} single-turn bits: at most 24 multi-turn bits and 32 in all",
                word.multiturn_bits
            )));
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
            word,
            quadrant_bits,
            fine_bits,
            turns_bits,
            quadrant_shift: if inverted { 2 } else { 0 },
            tag_shift,
            conv_active_high,
            timing,
        })
    }

    /// The absolute word's format.
    pub fn word(&self) -> SsiWord {
        self.word
    }
    /// The line timing.
    pub fn timing(&self) -> &SsiTiming {
        &self.timing
    }
    /// qb: bits of the quadrant count.
    pub fn quadrant_bits(&self) -> u32 {
        self.quadrant_bits
    }
    /// Q = 4 PPR = 2^qb.
    pub fn quadrants_per_turn(&self) -> u64 {
        1 << self.quadrant_bits
    }
    /// F.
    pub fn fine_bits(&self) -> u32 {
        self.fine_bits
    }
    /// M: bits of the decoder's turn word.
    pub fn turns_bits(&self) -> u32 {
        self.turns_bits
    }
    /// k: bits of the absolute word below the quadrant.
    pub fn sub_quadrant_bits(&self) -> u32 {
        self.word.single_turn_bits - self.quadrant_bits
    }
    /// k + 3: the synchronization bits (quadrant, k code bits and half a code).
    pub fn sync_bits(&self) -> u32 {
        self.sub_quadrant_bits() + 3
    }
    /// s: added to the decoded quadrant count for the encoder's quadrant (2 with an
    /// inverting front end).
    pub fn quadrant_shift(&self) -> u32 {
        self.quadrant_shift
    }
    /// K: the bit of `lt` that marks the sample leaving the core.
    pub fn tag_shift(&self) -> u32 {
        self.tag_shift
    }
    /// CONV (chip select) is active high: its rising edge samples.
    pub fn conv_active_high(&self) -> bool {
        self.conv_active_high
    }
    /// The largest alignment error between the digital and the analog channel that the
    /// merge takes, in quadrants: 2 - 2^-(k+1) (module docs, "The merge").
    pub fn tolerance_quadrants(&self) -> f64 {
        2.0 - 0.5f64.powi(self.sub_quadrant_bits() as i32 + 1)
    }
    /// Bits of the wait / half-period counter.
    pub fn count_bits(&self) -> u32 {
        let top = (self.timing.wait_clocks.max(1) - 1).max(self.timing.half_clocks + 2);
        32 - top.leading_zeros()
    }
    /// Bits of the pulse counter (0..=N + 1).
    pub fn pulse_bits(&self) -> u32 {
        32 - (self.word.bits() + 1).leading_zeros()
    }

    /// The synchronization bits o of a sample: ((qc + s) mod 4) 2^(k+1) + fine >> (F-k-1).
    pub fn sync_of(&self, qc: u64, fine: u64) -> u64 {
        let k = self.sub_quadrant_bits();
        (((qc + self.quadrant_shift as u64) & 3) << (k + 1))
            | ((fine & mask(self.fine_bits)) >> (self.fine_bits - k - 1))
    }

    /// The target (quadrant count, turn word) for the binary absolute word `w` and a
    /// sample with synchronization bits `o` (module docs, "The merge").
    pub fn target(&self, w: u64, o: u64) -> (u64, u64) {
        let s = self.word.single_turn_bits;
        let k = self.sub_quadrant_bits();
        let st = w & mask(s);
        let turns = (w >> s) & mask(self.word.multiturn_bits);
        let c = 2 * st + 1;
        let d = crate::blocks::sext(o.wrapping_sub(c) & mask(k + 3), k + 3);
        let p = c as i64 + d;
        let q = (p.rem_euclid(1 << (s + 1)) as u64) >> (k + 1);
        let carry = p.div_euclid(1 << (s + 1));
        let t = (turns as i64 + carry) as u64 & mask(self.turns_bits);
        (q & mask(self.quadrant_bits), t)
    }
}
