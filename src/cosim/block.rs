//! The contract between a rust-hdl block and the co-simulation harness: its ports with
//! their Verilog names and widths, and how rows of values are applied to and read from it.
use super::step::Clocked;
use super::Port;

/// A rust-hdl block that can be co-simulated as the top of its own exported Verilog: its
/// ports (besides the clock) are listed with their Verilog names and widths, and rows of
/// values are applied to / read from the block in that order.
pub trait CosimBlock: Clocked + Sized {
    /// Inputs besides the clock, in stimulus-row order (names = the struct's field names).
    fn input_ports(&self) -> Vec<Port>;
    /// Outputs in trace-row order.
    fn output_ports(&self) -> Vec<Port>;
    /// Drives the inputs from one stimulus row (`.next` of each input).
    fn apply(&mut self, row: &[u64]);
    /// Reads the outputs into one trace row.
    fn sample(&self) -> Vec<u64>;
}
