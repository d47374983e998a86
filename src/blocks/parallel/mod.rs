//! Parallel position bus: the position, the turn count and the flags as registered words
//! with a one-cycle valid strobe, for a drive or processor on the same board (or an FPGA
//! neighbour).
//!
//! ```text
//!  clk        _/‾\_/‾\_/‾\_/‾\_/‾\_/‾\_/‾\_
//!  pos_valid  ____/‾‾‾\___________/‾‾‾\____      (inputs from the decoder core)
//!  pos        ====X p1 X==========X p2 X====
//!  hold       ________________/‾‾‾‾‾‾‾‾‾‾‾\_    (p2 arrives while held: dropped)
//!  par_valid  ________/‾‾‾\_________________
//!  par_pos    ========X p1 ..................
//! ```
//!
//! * On a cycle with `pos_valid` and not `hold`, `par_pos` = pos mod 2^S, `par_turns` =
//!   turns mod 2^M, `par_error` / `par_warning` = the flag in that cycle OR any cycle with the
//!   flag set since the previous update (sticky, so a flag raised while held is not lost),
//!   and `par_valid` pulses for one cycle; all are registered (one cycle of latency).
//! * `hold` (for a reader that needs several cycles, e.g. a processor reading the words one
//!   after the other) freezes the outputs; positions presented meanwhile are dropped, and the
//!   next valid position after `hold` falls is taken.
//! * Reset (synchronous, active high) clears every output.
//!
//! Ports of [`hdl::ParallelBus`]: `clk`, `rst`, `pos` (32), `turns` (32), `pos_valid`,
//! `error`, `warning`, `hold` -> `par_pos` (32), `par_turns` (32), `par_valid`,
//! `par_error`, `par_warning`. Only the low S (M) bits of `par_pos` (`par_turns`) can be
//! non-zero; a top level exports those.
pub mod hdl;

use crate::blocks::serial::check_word;

/// Parameters of the parallel bus.
#[derive(Clone, Debug, PartialEq)]
pub struct ParallelParams {
    /// Single-turn position bits S (1..=32).
    pub position_bits: u32,
    /// Turn count bits M (0..=32; 0 keeps `par_turns` at zero).
    pub multiturn_bits: u32,
}

impl ParallelParams {
    /// Parameters for S position bits and M turn bits.
    pub fn new(position_bits: u32, multiturn_bits: u32) -> crate::error::Result<Self> {
        let p = Self {
            position_bits,
            multiturn_bits,
        };
        p.validate()?;
        Ok(p)
    }

    /// Checks every field.
    pub fn validate(&self) -> crate::error::Result<()> {
        check_word("parallel", self.position_bits, 0)?;
        if self.multiturn_bits > 32 {
            return Err(crate::error::Error::block_params(
                "parallel",
                format!("multiturn_bits must be 0..=32, got {}", self.multiturn_bits),
            ));
        }
        Ok(())
    }
}

/// The block's entry in the registry (`crate::blocks::registry`).
pub const BLOCK: crate::blocks::registry::BlockDef = crate::blocks::registry::BlockDef::report_only(
    "parallel",
    "parallel bus",
    crate::report::jobs::parallel_job,
);
