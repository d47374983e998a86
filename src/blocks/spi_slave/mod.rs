//! SPI slave for the position: SPI modes 0 and 3 (the master samples MISO on rising SCK
//! edges, the slave changes it on falling edges), one word per chip-select period.
//!
//! Word, MSB first: N data bits (multi-turn bits, then position; binary or Gray, as in
//! [`crate::blocks::serial`]), then the error flag E and the warning flag W (1 = set, sticky
//! since the previous word as in BiSS), then zeros for any further clocks.
//!
//! ```text
//!  mode 0 (SCK idles low)
//!  cs_n ‾‾‾\____________________________________________ .. ___________/‾‾‾
//!  sck  ________/‾‾\__/‾‾\__/‾‾\__ .. __/‾‾\__/‾‾\__/‾‾\__ .. _____________
//!  miso ----X D(N-1) X D(N-2) X .. X  D0  X  E   X  W   X 0 ..        X----
//!  mode 3 (SCK idles high)
//!  sck  ‾‾‾‾‾‾‾‾\__/‾‾\__/‾‾\__/‾ .. ‾\__/‾‾\__/‾‾\__/‾‾ .. ‾‾‾‾‾‾‾‾‾‾‾‾‾‾‾
//!  miso ----X D(N-1)   X D(N-2) X .. X  D0  X  E   X  W  X 0 ..       X----
//!          │latch                        (samples on every rising edge)
//! ```
//!
//! Both modes work with one rule, so the slave needs no mode setting: the falling edge of
//! the (synchronized) chip select latches the word and puts its MSB on MISO; a falling SCK
//! edge moves to the next bit only if a rising edge came since the last move. In mode 3 the
//! first falling edge (before any rising edge) therefore changes nothing. Modes 1 and 2
//! (sampling on falling edges) are not supported.
//!
//! `cs_n` and `sck` pass the same synchronizer and glitch filter as BiSS MA
//! ([`crate::blocks::serial::hdl::LineSync`]), so their order is kept. Timing that the master
//! must meet (L = 3 clocks with the filter, 2 without; d = one-way line delay):
//! * cs_n low to the first SCK rising edge (mode 0) or falling edge (mode 3):
//!   more than (L + 1) clock periods + 2d;
//! * SCK low time and high time: at least 2 clock periods (1 without the filter);
//! * the new bit appears (L + 1) clock periods + 2d after the falling edge, at most, so the
//!   SCK low time must exceed that: f_SCK <= 1 / (2 ((L + 1) T_clk + 2d)) at 50 % duty.
//!   With the FPGA's pad budgets the supported round trip per SCK rate is
//!   [`crate::blocks::serial::max_round_trip_ns`] of the SCK low time, printed by `check`
//!   (docs/interfaces.md).
//!
//! `miso_oe` is high while the slave is selected (a top level drives a tri-state pin with it);
//! `miso` is 0 while deselected. Ports of [`hdl::SpiSlave`]: `clk`, `rst`, `sck`, `cs_n`,
//! `pos` (32), `turns` (32), `pos_valid`, `error`, `warning` -> `miso`, `miso_oe`.
pub mod hdl;

use crate::blocks::serial::{check_clock, check_word, min_level_clocks, sync_latency};

/// Parameters of the SPI slave.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct SpiSlaveParams {
    /// Single-turn position bits: the low `position_bits` of `pos` (1..=32).
    pub position_bits: u32,
    /// Multi-turn bits sent ahead of the position (position_bits + multiturn_bits <= 32).
    pub multiturn_bits: u32,
    /// Send the data word Gray-coded instead of binary.
    pub gray: bool,
    /// Ignore SCK / chip-select levels seen on one clock edge only.
    pub glitch_filter: bool,
    /// System clock frequency in Hz.
    pub clock_hz: f64,
    /// Bits of the velocity word sent after the data word, before E (0: none; `[velocity]
    /// in_frames`): two's complement, MSB first, never Gray-coded.
    #[serde(skip_serializing_if = "crate::blocks::serial::is_zero")]
    pub velocity_bits: u32,
}

impl SpiSlaveParams {
    /// Parameters with the defaults: binary, glitch filter on.
    pub fn new(
        position_bits: u32,
        multiturn_bits: u32,
        clock_hz: f64,
    ) -> crate::error::Result<Self> {
        let p = Self {
            position_bits,
            multiturn_bits,
            gray: false,
            glitch_filter: true,
            clock_hz,
            velocity_bits: 0,
        };
        p.validate()?;
        Ok(p)
    }

    /// Checks every field.
    pub fn validate(&self) -> crate::error::Result<()> {
        check_clock("spi", self.clock_hz)?;
        check_word("spi", self.position_bits, self.multiturn_bits)?;
        crate::blocks::serial::check_frame("spi", self.data_bits(), self.velocity_bits)
    }

    /// Data bits N.
    pub fn data_bits(&self) -> u32 {
        self.position_bits + self.multiturn_bits
    }

    /// Word bits: N data bits, the velocity word, E, W.
    pub fn word_bits(&self) -> u32 {
        self.data_bits() + self.velocity_bits + 2
    }

    /// Cycles from a new SCK / chip-select level at the input to the clock edge that acts on it.
    pub fn latch_latency(&self) -> u32 {
        sync_latency(self.glitch_filter)
    }

    /// Longest time from an SCK falling edge (or chip select) at the slave's pin to the new
    /// bit on MISO, in ns, without the pads' delays: (L + 1) clock periods
    /// ([`crate::blocks::serial::answer_window`] with no pad budget).
    pub fn response_ns(&self) -> f64 {
        crate::blocks::serial::answer_window(
            self.clock_hz,
            self.glitch_filter,
            &crate::blocks::serial::NO_PADS,
        )
        .max_ns
    }

    /// Highest SCK frequency at 50 % duty for a one-way line delay (see the module docs).
    pub fn max_sck_hz(&self, line_delay_ns: f64) -> f64 {
        let by_sync = self.clock_hz / (2 * min_level_clocks(self.glitch_filter)) as f64;
        let by_response = 1e9 / (2.0 * (self.response_ns() + 2.0 * line_delay_ns));
        by_sync.min(by_response)
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "spi",
    "SPI slave",
    crate::report::jobs::spi_job,
);
