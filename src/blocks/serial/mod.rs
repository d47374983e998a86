//! What the serial position slaves (BiSS-C in [`crate::blocks::biss`], SSI in
//! [`crate::blocks::ssi`], SPI in [`crate::blocks::spi_slave`]) and the parallel bus
//! ([`crate::blocks::parallel`]) share: the line synchronizer, the position word latch, the
//! data word, the timeout counter's width, and the parameter checks.
//!
//! # Structure
//!
//! ```text
//!               ┌─ LineSync (one per asynchronous line: MA, SSI clock, SCK, cs_n) ────────┐
//!  pin ────────>│ n1 -> n2 -> n3 (inverted: power-up 0 = line high)                      │
//!  (async)      │ filter on: a new level needs n2 == n3 (two equal samples)              │
//!               │ nf (filtered level) follows ─────────────────────────────────────────────┼──> level
//!               │ the same edge test on the flops' next values, registered ───────────────┼──> rise, fall
//!               └─────────────────────────────────────────────────────────────────────────┘  (one-clock pulses)
//!               ┌─ PosWord ───────────────────────────────────────────────────────────────┐
//!  pos, turns ─>│ pos_valid ? inputs : held copy (posh, turnsh)                           │
//!  pos_valid ──>│   ((turns & Mmask) << S) | (pos & Smask) -> Gray (optional) ────────────┼──> word
//!  error ──────>│ erracc | error | no valid position since reset ─────────────────────────┼──> err
//!  warning ────>│ warnacc | warning ──────────────────────────────────────────────────────┼──> warn
//!  take ───────>│ the slave latches now: clears erracc, warnacc                           │
//!               └─────────────────────────────────────────────────────────────────────────┘
//!  slave:  rise / fall step its frame state machine; `take` at the frame's first edge
//!          (BiSS F1, SSI F1, SPI chip select); its timeout counter tcnt restarts at every
//!          line edge and ends the frame when it reaches timeout_clocks - 1.
//! ```
//!
//! The synchronizer and the word latch are rust-hdl sub-blocks, so each slave instantiates
//! them (field names `sync`, `sck_sync`, `cs_sync`, `posw`, which name the Verilog modules).
//! The timeout counter stays inside each slave: the BiSS-C slave registers its end-of-count
//! compare (`ftl`) for timing, the SSI slave compares directly, and a sub-block would add a
//! Verilog module to both; what they share is its width ([`timeout_mask`]) and its range
//! ([`MIN_TIMEOUT_CLOCKS`]..=[`MAX_TIMEOUT_CLOCKS`], [`timeout_clocks`]).
//!
//! # Widths (bit growth)
//!
//! Every word is a `Bits<32>` whose upper bits are masked to zero (see [`crate::blocks`]).
//! * Synchronizer: single-bit flops only, no arithmetic.
//! * Data word: N = M + S <= 32 bits ([`check_word`]). The turns (M bits) are shifted above
//!   the position (S bits) into a disjoint field, so the OR has no carry and the word never
//!   exceeds N bits. For S = 32, M = 0: the turns mask is 0 and the shift is clamped to 31
//!   (a 32-bit shift of a 32-bit word is not portable Verilog). Gray coding (`w ^ (w >> 1)`)
//!   keeps the width.
//! * Timeout counter: counts 0 ..= timeout_clocks - 1, so it needs
//!   bits(timeout_clocks - 1) <= 24 bits for the largest timeout 2^24; `tcnt + 1` is masked
//!   to that width (in idle the counter wraps harmlessly).
//! * Bit counters: at most 64 (BiSS Ack periods) or 32 + 2 (data and flags): 7 bits.
//!
//! # Latency
//!
//! A new line level acts at the clock edge [`sync_latency`] cycles after the first cycle in
//! which it is presented (3 with the glitch filter, 2 without), and must last
//! [`min_level_clocks`] clock periods (2, or 1) to be seen for sure.
//!
//! # Line timing (the one derivation; docs/interfaces.md)
//!
//! A master's clock edge (BiSS MA, SSI clock, SPI SCK) reaches the slave's pin at some
//! phase of the system clock; the first clock edge after it (or after the pad's input
//! delay, bounded by the set-up budget t_su) samples it, and the slave's registered output
//! changes L clock edges later (L = [`sync_latency`]), then leaves the pad after the
//! clock-to-out t_co. The answer therefore comes, at the slave's pins,
//!
//! ```text
//!   a_min = L T_clk   <   a   <=   a_max = (L + 1) T_clk + t_su + t_co
//! ```
//!
//! after the edge ([`answer_window`]; t_co and t_su are the `[board]` budgets,
//! `fpga_clock_to_out_ns` and `fpga_input_setup_ns`). A master that samples the answer a
//! fixed window W after the edge that asked for it reads it while the round trip of the
//! line r (cable and transceivers, both directions) satisfies r + a_max <= W
//! ([`max_round_trip_ns`]): W = one clock period for an SSI master or a BiSS master without
//! line-delay compensation (it reads the answer to rising edge n at rising edge n + 1), and
//! the SCK low time for an SPI master (MISO changes after a falling edge and is sampled at
//! the next rising edge). A BiSS-C master with line-delay compensation measures r + a on
//! the Ack edge and samples each bit half an MA period later: every round trip within its
//! compensation range works as long as the answer's spread a_max - a_min stays below half
//! an MA period, which [`min_level_clocks`] already guarantees (an MA level of 2 clocks
//! with the filter, a spread of one clock plus the constant pad delays).
pub mod hdl;

use crate::error::{Error, Result};

/// Largest timeout in system clocks (24-bit counter).
pub const MAX_TIMEOUT_CLOCKS: u32 = 1 << 24;
/// Smallest timeout in system clocks.
pub const MIN_TIMEOUT_CLOCKS: u32 = 8;
/// Default timeout (BiSS-C) and monoflop time (SSI) in microseconds.
pub const DEFAULT_TIMEOUT_US: f64 = 20.0;

/// Cycles from a new line level at the input to the clock edge that acts on it.
pub fn sync_latency(glitch_filter: bool) -> u32 {
    if glitch_filter {
        3
    } else {
        2
    }
}

/// Clock periods a line level must last to be seen for sure.
pub fn min_level_clocks(glitch_filter: bool) -> u32 {
    if glitch_filter {
        2
    } else {
        1
    }
}

/// When a serial slave's answer leaves its pin after the master's clock edge reaches the
/// pin, ns (see the module docs, "Line timing").
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AnswerWindow {
    /// Earliest: L system clock periods (the answer comes strictly later).
    pub min_ns: f64,
    /// Latest: L + 1 periods, the input pad's set-up budget and the output's clock-to-out.
    pub max_ns: f64,
}

/// The answer window of a slave at `clock_hz` with or without the glitch filter; `io`
/// gives the pads' budgets (clock-to-out, input set-up).
pub fn answer_window(
    clock_hz: f64,
    glitch_filter: bool,
    io: &crate::board::IoTiming,
) -> AnswerWindow {
    let t = 1e9 / clock_hz;
    let l = sync_latency(glitch_filter) as f64;
    AnswerWindow {
        min_ns: l * t,
        max_ns: (l + 1.0) * t + io.input_setup_ns + io.clock_to_out_ns,
    }
}

/// No pad delays (a simulation's ideal pins): the answer window of the synchronizer alone.
pub const NO_PADS: crate::board::IoTiming = crate::board::IoTiming {
    clock_to_out_ns: 0.0,
    input_setup_ns: 0.0,
    ..crate::board::IoTiming::DEFAULT
};

/// The longest line round trip (cable and transceivers, both directions), ns, for a master
/// that samples the answer `sample_after_ns` after the clock edge that asks for it (one
/// clock period for SSI and uncompensated BiSS, the SCK low time for SPI); negative when
/// even a zero-length line is too slow.
pub fn max_round_trip_ns(sample_after_ns: f64, a: &AnswerWindow) -> f64 {
    sample_after_ns - a.max_ns
}

/// MA / SSI clock / SCK rates at which `check` states the supported round trip, Hz (those
/// up to the synchronizer's limit are printed).
pub const LINE_RATES_HZ: [f64; 6] = [100e3, 500e3, 1e6, 2e6, 5e6, 10e6];

/// Mask of a timeout counter that counts 0 ..= `timeout_clocks` - 1.
pub fn timeout_mask(timeout_clocks: u32) -> u64 {
    crate::blocks::mask(32 - (timeout_clocks - 1).leading_zeros().min(31))
}

/// Checks the system clock: 1 MHz to 1 GHz.
pub(crate) fn check_clock(block: &str, clock_hz: f64) -> Result<()> {
    if clock_hz.is_finite() && (1e6..=1e9).contains(&clock_hz) {
        Ok(())
    } else {
        Err(Error::block_params(
            block,
            format!("clock_hz must be between 1 MHz and 1 GHz, got {clock_hz}"),
        ))
    }
}

/// Checks the data word: 1..=32 position bits, at most 32 bits with the turns.
pub(crate) fn check_word(block: &str, position_bits: u32, multiturn_bits: u32) -> Result<()> {
    if !(1..=32).contains(&position_bits) {
        return Err(Error::block_params(
            block,
            format!("position_bits must be 1..=32, got {position_bits}"),
        ));
    }
    if position_bits + multiturn_bits > 32 {
        return Err(Error::block_params(
            block,
            format!(
                "position_bits + multiturn_bits = {} + {} = {} exceeds the 32-bit data word",
                position_bits,
                multiturn_bits,
                position_bits + multiturn_bits
            ),
        ));
    }
    Ok(())
}

/// Largest data part of a frame: the data word and the velocity word together, as one
/// 64-bit word of the master (the master models read it so; the slaves' bit counters
/// reach 127).
pub const MAX_FRAME_DATA_BITS: u32 = 64;

/// Checks the velocity word appended to the data word: 0 (none) or 8..=62 bits, and data +
/// velocity <= [`MAX_FRAME_DATA_BITS`].
pub(crate) fn check_frame(block: &str, data_bits: u32, velocity_bits: u32) -> Result<()> {
    if velocity_bits != 0 && !(8..=62).contains(&velocity_bits) {
        return Err(Error::block_params(
            block,
            format!("the velocity word must be 8..=62 bits, got {velocity_bits}"),
        ));
    }
    if data_bits + velocity_bits > MAX_FRAME_DATA_BITS {
        return Err(Error::block_params(
            block,
            format!(
                "the frame's data part of {data_bits} position bits + {velocity_bits} velocity bits = {} exceeds {MAX_FRAME_DATA_BITS} bits",
                data_bits + velocity_bits
            ),
        ));
    }
    Ok(())
}

/// serde: leave a zero field out (the parameter files of configurations without it stay
/// as they were).
pub(crate) fn is_zero(v: &u32) -> bool {
    *v == 0
}

/// Checks a timeout in clocks against [`MIN_TIMEOUT_CLOCKS`]..=[`MAX_TIMEOUT_CLOCKS`].
pub(crate) fn check_timeout_clocks(block: &str, clocks: u32) -> Result<()> {
    if (MIN_TIMEOUT_CLOCKS..=MAX_TIMEOUT_CLOCKS).contains(&clocks) {
        Ok(())
    } else {
        Err(Error::block_params(block, format!(
            "the timeout must be {MIN_TIMEOUT_CLOCKS}..={MAX_TIMEOUT_CLOCKS} system clocks, got {clocks}"
        )))
    }
}

/// Timeout in clocks from microseconds (rounded), checked.
pub(crate) fn timeout_clocks(block: &str, us: f64, clock_hz: f64) -> Result<u32> {
    if !us.is_finite() || us <= 0.0 {
        return Err(Error::block_params(
            block,
            format!("the timeout must be a positive number of microseconds, got {us}"),
        ));
    }
    let c = (us * clock_hz / 1e6).round();
    if c < MIN_TIMEOUT_CLOCKS as f64 || c > MAX_TIMEOUT_CLOCKS as f64 {
        return Err(Error::block_params(block, format!(
            "a timeout of {us} us is {c} clocks at {} MHz; it must be {MIN_TIMEOUT_CLOCKS}..={MAX_TIMEOUT_CLOCKS} clocks",
            clock_hz / 1e6
        )));
    }
    Ok(c as u32)
}

/// Timeout in microseconds from clocks.
pub(crate) fn timeout_us(timeout_clocks: u32, clock_hz: f64) -> f64 {
    timeout_clocks as f64 * 1e6 / clock_hz
}

/// Gray code of a word.
pub fn gray(w: u64) -> u64 {
    w ^ (w >> 1)
}

/// The data word a slave sends for a position and a turn count (binary or Gray).
pub fn data_word(
    pos: u64,
    turns: u64,
    position_bits: u32,
    multiturn_bits: u32,
    gray_code: bool,
) -> u64 {
    use crate::blocks::mask;
    let w = ((turns & mask(multiturn_bits)) << position_bits) | (pos & mask(position_bits));
    if gray_code {
        gray(w)
    } else {
        w
    }
}
