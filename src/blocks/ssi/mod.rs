//! SSI slave: synchronous serial position output, binary or Gray, with a monoflop timeout.
//!
//! The master's clock (here called `ma`, as in BiSS) idles high; the data line `slo` idles
//! high. The first falling edge latches the position (the "monoflop" is triggered), each
//! rising edge puts the next bit on the line, MSB first, and after the last bit the line is
//! held low until the clock has been quiet for the monoflop time t_m:
//!
//! ```text
//!            │F1 R1     R2     R3             R(N)   R(N+1)
//!  ma   ‾‾‾‾‾│\__/‾‾\__/‾‾\__/‾‾\__ .. __/‾‾\__/‾‾\__/‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾
//!  slo  ‾‾‾‾‾‾‾‾‾‾‾X D(N-1)X D(N-2)X .. X  D1  X  D0  X [E] X___________________/‾‾‾‾
//!            │latch│                                        │<- t_m after the ->│ idle
//!                                                           │   last clock edge │
//! ```
//!
//! | clock edge (slave view) | `slo` afterwards                                      |
//! |-------------------------|-------------------------------------------------------|
//! | F1 (first from idle)    | 1; position, turns and error latched                  |
//! | R1 .. R(N)              | data word, MSB first (multi-turn bits, then position) |
//! | R(N+1)                  | error bit E (1 = error) if `error_bit`, else 0        |
//! | later rising edges      | 0                                                     |
//! | no edge for t_m         | 1: idle                                               |
//!
//! A master gives N + 1 clock pulses (N + 2 with the error bit) and reads each bit at the
//! next rising edge (the slave's answer, 2-4 clock periods plus the cable round trip, must
//! arrive within one clock period; the supported round trip per rate is
//! [`crate::blocks::serial::max_round_trip_ns`], printed by `check`, docs/interfaces.md), or
//! at a compensated delay. The data word, the Gray code,
//! the position hold, the sticky error and the synchronizer with its glitch filter are those
//! of the BiSS slave ([`crate::blocks::serial`]); so are the behaviour during the timeout (clock
//! edges restart it and start nothing) and after reset (line low for t_m, then idle).
//!
//! Ports of [`hdl::SsiSlave`]: `clk`, `rst`, `ma`, `pos` (32), `turns` (32), `pos_valid`,
//! `error` -> `slo`.
pub mod hdl;

use crate::blocks::serial::{
    check_clock, check_timeout_clocks, check_word, sync_latency, timeout_clocks, timeout_us,
    DEFAULT_TIMEOUT_US,
};

/// Parameters of the SSI slave.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SsiParams {
    /// Single-turn position bits: the low `position_bits` of `pos` (1..=32).
    pub position_bits: u32,
    /// Multi-turn bits sent ahead of the position (position_bits + multiturn_bits <= 32).
    pub multiturn_bits: u32,
    /// Send the data word Gray-coded instead of binary.
    pub gray: bool,
    /// Append one error bit (1 = error) after the data word.
    pub error_bit: bool,
    /// Monoflop time in system clocks.
    pub timeout_clocks: u32,
    /// Ignore clock levels seen on one clock edge only.
    pub glitch_filter: bool,
    /// System clock frequency in Hz.
    pub clock_hz: f64,
    /// Bits of the velocity word sent after the data word, before the error bit (0: none;
    /// `[velocity] in_frames`): two's complement, MSB first, never Gray-coded.
    #[serde(skip_serializing_if = "crate::blocks::serial::is_zero")]
    pub velocity_bits: u32,
}

impl SsiParams {
    /// Parameters with the defaults: binary, no error bit, 20 us monoflop, glitch filter on.
    pub fn new(
        position_bits: u32,
        multiturn_bits: u32,
        clock_hz: f64,
    ) -> crate::error::Result<Self> {
        check_clock("ssi", clock_hz)?;
        let p = Self {
            position_bits,
            multiturn_bits,
            gray: false,
            error_bit: false,
            timeout_clocks: timeout_clocks("ssi", DEFAULT_TIMEOUT_US, clock_hz)?,
            glitch_filter: true,
            clock_hz,
            velocity_bits: 0,
        };
        p.validate()?;
        Ok(p)
    }

    /// Sets the monoflop time from microseconds (rounded to whole system clocks).
    pub fn set_timeout_us(&mut self, us: f64) -> crate::error::Result<()> {
        self.timeout_clocks = timeout_clocks("ssi", us, self.clock_hz)?;
        Ok(())
    }

    /// Checks every field.
    pub fn validate(&self) -> crate::error::Result<()> {
        check_clock("ssi", self.clock_hz)?;
        check_word("ssi", self.position_bits, self.multiturn_bits)?;
        crate::blocks::serial::check_frame("ssi", self.data_bits(), self.velocity_bits)?;
        check_timeout_clocks("ssi", self.timeout_clocks)
    }

    /// Data bits N.
    pub fn data_bits(&self) -> u32 {
        self.position_bits + self.multiturn_bits
    }

    /// Bits a master reads: N, the velocity word, plus the error bit.
    pub fn frame_bits(&self) -> u32 {
        self.data_bits() + self.velocity_bits + self.error_bit as u32
    }

    /// Cycles from a new clock level at the input to the clock edge that acts on it.
    pub fn latch_latency(&self) -> u32 {
        sync_latency(self.glitch_filter)
    }

    /// Monoflop time in microseconds.
    pub fn timeout_us(&self) -> f64 {
        timeout_us(self.timeout_clocks, self.clock_hz)
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "ssi",
    "SSI slave",
    crate::report::jobs::ssi_job,
);
