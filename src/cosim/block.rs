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

/// A port value as it travels in a stimulus or trace row (one `u64` per port).
pub trait RowValue: Sized {
    /// The port's value from a row entry (a word keeps its low bits).
    fn from_row(v: u64) -> Self;
    /// The row entry for the port's value.
    fn to_row(&self) -> u64;
}

impl RowValue for bool {
    fn from_row(v: u64) -> Self {
        v != 0
    }
    fn to_row(&self) -> u64 {
        *self as u64
    }
}

impl<const N: usize> RowValue for rust_hdl::prelude::Bits<N> {
    fn from_row(v: u64) -> Self {
        Self::from(v & crate::blocks::mask(N as u32))
    }
    fn to_row(&self) -> u64 {
        self.to_u64()
    }
}

/// Implements [`Clocked`] (on the field `clk`) and [`CosimBlock`] for a block from one list
/// of its ports: each input and output is named once, as its field (= Verilog port) name,
/// with its width, so the port lists, the row order and the fields driven and read cannot
/// drift apart.
///
/// ```ignore
/// cosim_block!(SsiSlave {
///     inputs: [rst: 1, ma: 1, pos: 32, turns: 32, pos_valid: 1, error: 1],
///     outputs: [slo: 1],
/// });
/// ```
macro_rules! cosim_block {
    ($ty:ty {
        inputs: [$($i:ident : $iw:expr),* $(,)?],
        outputs: [$($o:ident : $ow:expr),* $(,)?] $(,)?
    }) => {
        impl $crate::cosim::step::Clocked for $ty {
            fn set_clock(&mut self, high: bool) {
                self.clk.next = rust_hdl::prelude::Clock::from(high);
            }
        }
        impl $crate::cosim::CosimBlock for $ty {
            fn input_ports(&self) -> Vec<$crate::cosim::Port> {
                vec![$($crate::cosim::Port::new(stringify!($i), $iw)),*]
            }
            fn output_ports(&self) -> Vec<$crate::cosim::Port> {
                vec![$($crate::cosim::Port::new(stringify!($o), $ow)),*]
            }
            fn apply(&mut self, row: &[u64]) {
                use $crate::cosim::RowValue;
                let names = [$(stringify!($i)),*];
                assert_eq!(row.len(), names.len(), "one value per input port: {names:?}");
                let mut r = row.iter();
                $(if let Some(&v) = r.next() {
                    self.$i.next = RowValue::from_row(v);
                })*
            }
            fn sample(&self) -> Vec<u64> {
                use $crate::cosim::RowValue;
                vec![$(self.$o.val().to_row()),*]
            }
        }
    };
}
pub(crate) use cosim_block;
