//! A RAM with one write port and one registered read port, marked for distributed (LUT)
//! RAM: rust-hdl's `RAM` (same ports, same simulation, same Verilog) plus the attribute
//! `(* ram_style = "distributed" *)` on its array. Written here because rust-hdl's `RAM`
//! has no way to carry an attribute.
//!
//! Why distributed: on the ECP5 of the timing rule (docs/timing.md) Yosys maps a block RAM
//! to a DP16KD without its output register, whose clock-to-out alone (5.61 ns at speed 6)
//! nearly fills the rule's 6.0 ns at 133.33 MHz; LUT RAM (TRELLIS_DPR16X4) reads in about
//! 1 ns. Yosys honours the attribute on ECP5 and xc3sa (RAM16X1D); its Cyclone IV E flow
//! ignores it and maps an M9K, cleanly when the words are 36 bits wide and at most 256
//! deep (other widths have ports resized, a warning the synthesis flow refuses).
//!
//! ```text
//!  write_address, write_data, write_enable ──► mem[2^N] ──► read_data (registered)
//!  read_address ───────────────────────────────────┘
//! ```
use rust_hdl::prelude::*;
use std::collections::BTreeMap;

/// One write port and one registered read port; read-during-write gives the old word.
#[derive(LogicBlock, Default)]
pub struct LutRam<D: Synth, const N: usize> {
    /// The word read at the next `read_clock` edge.
    pub read_address: Signal<In, Bits<N>>,
    /// The read port's clock.
    pub read_clock: Signal<In, Clock>,
    /// The word at `read_address` at the last edge.
    pub read_data: Signal<Out, D>,
    /// The word written at the next `write_clock` edge when `write_enable` is high.
    pub write_address: Signal<In, Bits<N>>,
    /// The write port's clock.
    pub write_clock: Signal<In, Clock>,
    /// The word written.
    pub write_data: Signal<In, D>,
    /// Write this clock.
    pub write_enable: Signal<In, bool>,
    /// The simulation's words (none known at power-up: they read as 0 here, `x` in
    /// Verilog).
    _sim: Box<BTreeMap<Bits<N>, D>>,
}

impl<D: Synth, const N: usize> Logic for LutRam<D, N> {
    fn update(&mut self) {
        if self.read_clock.pos_edge() {
            self.read_data.next = *self
                ._sim
                .get(&self.read_address.val())
                .unwrap_or(&D::default());
        }
        if self.write_clock.pos_edge() && self.write_enable.val() {
            self._sim
                .insert(self.write_address.val(), self.write_data.val());
        }
    }

    fn connect(&mut self) {
        self.read_data.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
(* ram_style = \"distributed\" *) reg[{d}:0] mem[{a}:0];

always @(posedge read_clock) begin
   read_data <= mem[read_address];
end

always @(posedge write_clock) begin
   if (write_enable) begin
      mem[write_address] <= write_data;
   end
end
",
            d = D::BITS - 1,
            a = (1usize << N) - 1,
        ))
    }
}
