//! BiSS-C slave: point-to-point, single-cycle data (SCD), optionally with the control channel
//! (register access over CDM/CDS, [`control`], docs/biss_control.md).
//!
//! The drive (BiSS master) clocks MA; the slave answers on SLO. MA is asynchronous to the
//! system clock: it passes a two-flop synchronizer and, by default, a glitch filter
//! ([`crate::blocks::serial::hdl::LineSync`], shared with the SSI and SPI slaves) before its edges drive the frame state machine ([`hdl::BissSlave`]).
//!
//! # Frame
//!
//! MA idles high, SLO idles high (slave ready). Every SLO change is the slave's answer to an
//! MA rising edge (F = falling, R = rising edge; A = `ack_periods`, N = data bits). The
//! sketch shows A = 1, N = 4 (S = Start; D3..D0 data; C5..C0 the inverted CRC); the slave's
//! answers come 2-4 system clocks after each edge (see below), drawn here at the edge:
//!
//! ```text
//!  MA   ‾‾‾‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾\__/‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾
//!           F1 R1   R2   R3   R4   R5   R6   R7   R8   R9   R10  R11  R12  R13  R14  R15  R16  R17
//!  SLO  ‾‾‾‾‾‾‾‾‾‾‾‾_____‾‾‾‾‾_____X====X====X====X====X====X====X====X====X====X====X====X====_______________/‾‾‾‾‾‾‾‾
//!                    Ack  S    CDS  D3   D2   D1   D0   nE   nW   C5   C4   C3   C2   C1   C0
//!           ^ latch                                                                            |<-- t_out -->|
//! ```
//!
//! | MA edge (slave view)      | SLO afterwards                                        |
//! |---------------------------|-------------------------------------------------------|
//! | F1 (first edge from idle) | 1; position, turns, error and warning are latched     |
//! | R1                        | 1                                                     |
//! | R2 .. R(1+A)              | 0: Ack, A MA periods of "processing time"             |
//! | R(2+A)                    | 1: Start                                              |
//! | R(3+A)                    | CDS: 0, or the control channel's answer (see below)   |
//! | R(4+A) .. R(3+A+N)        | data word, MSB first: multi-turn bits, then position  |
//! | R(4+A+N), R(5+A+N)        | nE, nW (active low)                                   |
//! | R(6+A+N) .. R(11+A+N)     | CRC6 over data, nE, nW, inverted, MSB first           |
//! | R(12+A+N) and any later   | 0 (timeout); the master's last clock pulse            |
//! | no MA edge for t_out      | 1: idle, ready for the next frame                     |
//!
//! Falling edges other than F1 change nothing. A master therefore gives 12 + A + N clock
//! pulses per frame ([`BissParams::frame_rising_edges`]), reads SL after each rising edge
//! (with its own line-delay compensation), finds Ack (first 0) and Start (next 1), and then
//! waits for SL to return high.
//!
//! * Data word: `turns` (low `multiturn_bits`) above `pos` (low `position_bits`),
//!   N = multiturn_bits + position_bits <= 32. With `gray` the whole N-bit word is sent
//!   Gray-coded (`w ^ (w >> 1)`), as one continuous code (the usual multi-turn convention).
//! * Position: the block keeps the last word presented with `pos_valid` and latches, at F1,
//!   the word held (or the one presented in the same cycle). The latch takes the inputs
//!   of the cycle [`BissParams::latch_latency`] cycles after the first cycle in which MA is
//!   presented low (3 with the glitch filter, counted from the first of two consecutive low
//!   cycles; 2 without).
//! * Flags: `error` and `warning` are sticky: any cycle with the flag set since the
//!   previous latch (or at the latch) is reported once, as nE = 0 / nW = 0, in the next frame.
//!   Until the first `pos_valid` after reset the error is reported too.
//! * Timeout: SLO returns high `timeout_clocks` system clocks after the last MA edge the
//!   slave detected (after the frame, after an incomplete frame, or after reset). MA edges
//!   during the timeout restart it and never start a frame: a master that clocks too early
//!   reads SLO = 0 throughout (no Ack edge, no Start bit) and must wait for SLO high. A master
//!   that stops clocking mid-frame gets the same: the slave returns to idle t_out after the
//!   last edge. The slowest usable MA clock is the one whose half period reaches the timeout
//!   (clock_hz / (2 timeout_clocks)).
//! * Reset (synchronous, active high) enters the timeout: SLO low, then high once MA has been
//!   quiet for the timeout. A reset in the middle of a frame ends that frame (the master's CRC
//!   check or Start search fails; the next frame is normal). Power-up (register initial
//!   values) is the same state.
//!
//! # MA synchronizer, glitches and speed
//!
//! MA is sampled by two flip-flops (n1, n2, stored inverted so that their power-up value 0
//! means "MA high", the idle level). With `glitch_filter` (the default) a third flop n3 holds
//! the previous sample and the filtered level follows only when n2 == n3, i.e. a new level
//! must be seen on two consecutive clock edges. In a cycle-based view, a glitch shorter than
//! one clock period is either never sampled (invisible) or sampled once (a one-sample pulse):
//!
//! * a one-sample pulse is ignored: in idle it starts no frame, in a frame it adds no edge,
//!   during the timeout it does not restart it;
//! * next to an MA edge it can move that edge by up to 2 clock periods (the slave answers
//!   up to 2 clocks later; a compensating master at 10 MHz has 50 ns of margin for this);
//! * an MA level must last 2 clock periods to be seen for sure: f_MA <= f_clk / 4 at 50 %
//!   duty (12.5 MHz at 50 MHz, 33.3 MHz at 133.33 MHz); and a glitch can only be ignored
//!   inside a level that lasts 3 samples: a one-sample pulse inside a level of exactly two
//!   samples leaves one sample, which is dropped, losing that edge pair. The master's CRC
//!   check catches the shifted frame (tests: a glitch at every cycle of a frame at 4 MHz /
//!   50 MHz and at 10 MHz / 133.33 MHz changes nothing);
//! * SLO answers an MA edge 3 to 4 clock periods after it reaches the pin (the latch takes
//!   the inputs 3 cycles after the first low MA sample).
//!
//! Without the filter a one-sample MA pulse is a genuine edge pair (it starts a frame in idle,
//! or advances the frame by one bit, which the master's CRC check normally catches; the next
//! frame is good), the minimum high and low time is one clock period (f_MA <= f_clk / 2) and
//! the answer comes 2 to 3 clock periods after the edge.
//!
//! Measured (`tests/outputs/biss_corners.rs`, `maximum_ma_rate_measured`): the highest MA frequency, in
//! 0.25 MHz steps, at which every one of 24 frames at varying MA/clock phase was read
//! correctly, with 25 ns of line delay each way (about 5 m of cable); "compensated" is a
//! master with BiSS line-delay compensation (samples at r_n + D + T/2), "next edge" one that
//! samples each answer at the following rising edge (needs 2d + answer time < T):
//!
//! | system clock | filter | master      | max MA    | bound                       |
//! |--------------|--------|-------------|-----------|-----------------------------|
//! | 50 MHz       | on     | compensated | 12.50 MHz | f_clk / 4 = 12.50 MHz       |
//! | 50 MHz       | on     | next edge   |  7.50 MHz | 1 / (2d + 4 T_clk) = 7.69   |
//! | 50 MHz       | off    | compensated | 24.75 MHz | f_clk / 2 = 25.00 MHz       |
//! | 50 MHz       | off    | next edge   |  9.00 MHz | 1 / (2d + 3 T_clk) = 9.09   |
//! | 133.33 MHz   | on     | compensated | 33.25 MHz | f_clk / 4 = 33.33 MHz       |
//! | 133.33 MHz   | on     | next edge   | 12.50 MHz | 1 / (2d + 4 T_clk) = 12.50  |
//! | 133.33 MHz   | off    | compensated | 66.50 MHz | f_clk / 2 = 66.67 MHz       |
//! | 133.33 MHz   | off    | next edge   | 13.75 MHz | 1 / (2d + 3 T_clk) = 13.79  |
//!
//! BiSS-C's 10 MHz therefore needs a compensating master (standard for BiSS) at 50 MHz and
//! works with either master at 133.33 MHz.
//!
//! The line round trip (cable and transceivers) each master supports at each MA rate, with
//! the FPGA's pad budgets, comes from [`crate::blocks::serial::answer_window`] and
//! [`crate::blocks::serial::max_round_trip_ns`]; `check` prints it and docs/interfaces.md
//! tabulates it. A compensating master is limited only by its own compensation range, so
//! `[biss]` has no cable key.
//!
//! # Control channel (`control`)
//!
//! With [`BissParams::control`] set, the slave takes one CDM bit per complete frame: the
//! inverted MA level at the moment its timeout ends (a master holds MA low during the
//! timeout for CDM = 1, high for 0). Its answer goes out as the CDS bit of the next frame,
//! in the slot after Start; data, nE, nW and the CRC6 are unchanged. The control frames
//! (start, CTS, ID, address, CRC4, R/W, data byte, CRC4, stop) and the register file are
//! described in docs/biss_control.md ([`control`], [`control_model`], [`regs`]). Without
//! the channel the slave exports the same Verilog as before (CDS always 0).
//!
//! Ports of [`hdl::BissSlave`]: `clk`, `rst`, `ma`, `pos` (32), `turns` (32), `pos_valid`,
//! `error`, `warning` -> `slo`.
pub mod control;
pub mod control_model;
pub mod crc;
pub mod hdl;
pub mod regs;

use crate::blocks::serial::{
    check_clock, check_frame, check_timeout_clocks, check_word, min_level_clocks, sync_latency,
    timeout_clocks, timeout_us, DEFAULT_TIMEOUT_US,
};

/// Largest number of Ack periods.
pub const MAX_ACK_PERIODS: u32 = 64;

/// Parameters of the BiSS-C slave.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BissParams {
    /// Single-turn position bits: the low `position_bits` of `pos` (1..=32).
    pub position_bits: u32,
    /// Multi-turn bits sent ahead of the position: the low bits of `turns`
    /// (0..=31; position_bits + multiturn_bits <= 32).
    pub multiturn_bits: u32,
    /// Send the data word Gray-coded instead of binary.
    pub gray: bool,
    /// MA periods of Ack (processing time) before the Start bit, 1..=64.
    pub ack_periods: u32,
    /// System clocks from the last MA edge to SLO high (the BiSS timeout).
    pub timeout_clocks: u32,
    /// Ignore MA levels seen on one clock edge only (see the module docs).
    pub glitch_filter: bool,
    /// System clock frequency in Hz (used for the timeout and the reported limits).
    pub clock_hz: f64,
    /// The control channel (CDM/CDS register access) with these identification registers;
    /// None: CDS is always 0 (see docs/biss_control.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub control: Option<regs::BissIdent>,
    /// Bits of the velocity word sent after the data word, before nE (0: none; `[velocity]
    /// in_frames`): two's complement, MSB first, covered by the CRC.
    #[serde(skip_serializing_if = "crate::blocks::serial::is_zero")]
    pub velocity_bits: u32,
    /// With the control channel and `[registers]`: the channel's addresses 0x00..0x3F are the
    /// register map's bytes in banks of 64 (bank select 0x40), not the scratchpad.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub user_map: bool,
}

impl BissParams {
    /// Parameters with the defaults: binary, one Ack period, 20 us timeout, glitch filter on.
    pub fn new(
        position_bits: u32,
        multiturn_bits: u32,
        clock_hz: f64,
    ) -> crate::error::Result<Self> {
        check_clock("biss", clock_hz)?;
        let p = Self {
            position_bits,
            multiturn_bits,
            gray: false,
            ack_periods: 1,
            timeout_clocks: timeout_clocks("biss", DEFAULT_TIMEOUT_US, clock_hz)?,
            glitch_filter: true,
            clock_hz,
            control: None,
            velocity_bits: 0,
            user_map: false,
        };
        p.validate()?;
        Ok(p)
    }

    /// Sets the timeout from microseconds (rounded to whole system clocks).
    pub fn set_timeout_us(&mut self, us: f64) -> crate::error::Result<()> {
        self.timeout_clocks = timeout_clocks("biss", us, self.clock_hz)?;
        Ok(())
    }

    /// Checks every field; the message names the field and the allowed range.
    pub fn validate(&self) -> crate::error::Result<()> {
        check_clock("biss", self.clock_hz)?;
        check_word("biss", self.position_bits, self.multiturn_bits)?;
        check_frame("biss", self.data_bits(), self.velocity_bits)?;
        if !(1..=MAX_ACK_PERIODS).contains(&self.ack_periods) {
            return Err(crate::error::Error::block_params(
                "biss",
                format!(
                    "ack_periods must be 1..={MAX_ACK_PERIODS}, got {}",
                    self.ack_periods
                ),
            ));
        }
        check_timeout_clocks("biss", self.timeout_clocks)
    }

    /// Data bits N = multi-turn + single-turn.
    pub fn data_bits(&self) -> u32 {
        self.position_bits + self.multiturn_bits
    }

    /// Bits of the frame's data part: N, plus the velocity word.
    pub fn frame_data_bits(&self) -> u32 {
        self.data_bits() + self.velocity_bits
    }

    /// MA rising edges a master gives per frame, the final (timeout) pulse included.
    pub fn frame_rising_edges(&self) -> u32 {
        12 + self.ack_periods + self.frame_data_bits()
    }

    /// Cycles from the first stimulus cycle that presents a new MA level to the cycle whose
    /// clock edge acts on it (latches the position at F1, changes SLO at a rising edge).
    pub fn latch_latency(&self) -> u32 {
        sync_latency(self.glitch_filter)
    }

    /// Timeout in microseconds.
    pub fn timeout_us(&self) -> f64 {
        timeout_us(self.timeout_clocks, self.clock_hz)
    }

    /// Highest MA frequency the synchronizer can follow at 50 % duty (see the module docs).
    pub fn max_ma_hz(&self) -> f64 {
        self.clock_hz / (2 * min_level_clocks(self.glitch_filter)) as f64
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "biss",
    "BiSS-C slave",
    crate::report::jobs::biss_job,
);
