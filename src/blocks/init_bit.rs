//! A one-bit register that powers up at a chosen level, with nothing after its flop.
//!
//! ```text
//!            +--------+
//!   d ------>| D    Q |------> q      power-up value: init (Verilog `initial`)
//!   clock -->|>       |
//!            +--------+
//! ```
//!
//! Written by hand because rust-hdl's `DFF` always powers up at 0, and its `DFFWithInit`
//! stores `d ^ init` in a zero flop and drives `q ^ init`: for init = 1 Yosys `synth_ecp5`
//! keeps that inverter as a LUT4 after the flop (measured on the ADS8354 top), so a pin
//! register carries a LUT and a net more than its clock-to-out. This block's Verilog is a
//! plain `reg q = init`, which maps to one flip-flop with its power-up value (ECP5:
//! `TRELLIS_FF` with `REGSET`).
//!
//! [`InitBit::kept`] marks the register `keep`, so synthesis never merges it with an
//! equal register: a reset fan-out register per block (`blocks::top`) must stay its own
//! flop to cut the reset net, and Yosys `opt_merge` would otherwise fold every such copy
//! into one. No bit growth: one bit in, one bit out, one clock later.
use rust_hdl::prelude::*;

/// A one-bit D flip-flop with a power-up value.
#[derive(Clone, Debug, LogicBlock)]
pub struct InitBit {
    /// Next value, taken at every rising clock edge.
    pub d: Signal<In, Bit>,
    /// The register; `init` from power-up to the first clock edge.
    pub q: Signal<Out, Bit>,
    /// The system clock.
    pub clock: Signal<In, Clock>,
    /// Power-up value.
    init: Constant<Bit>,
    /// 1: the flop is marked `keep` (never merged with an equal one).
    kept: Constant<Bit>,
}

impl InitBit {
    /// A register that powers up at `init`.
    pub fn new(init: bool) -> Self {
        Self::build(init, false)
    }

    /// A register that powers up at `init` and that synthesis keeps as a flop of its own.
    pub fn kept(init: bool) -> Self {
        Self::build(init, true)
    }

    fn build(init: bool, kept: bool) -> Self {
        Self {
            d: Default::default(),
            q: Signal::new_with_default(init),
            clock: Default::default(),
            init: Constant::new(init),
            kept: Constant::new(kept),
        }
    }
}

impl Logic for InitBit {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            self.q.next = self.d.val();
        }
    }

    fn connect(&mut self) {
        self.q.connect();
    }

    fn hdl(&self) -> Verilog {
        let keep = if self.kept.val() { "(* keep *) " } else { "" };
        Verilog::Custom(format!(
            "initial begin\n   q = 1'b{};\nend\n\n{keep}always @(posedge clock) begin\n   q <= d;\nend\n",
            u8::from(self.init.val())
        ))
    }

    fn timing(&self) -> Vec<TimingInfo> {
        vec![TimingInfo {
            name: "init_bit".into(),
            clock: "clock".into(),
            inputs: vec!["d".into()],
            outputs: vec!["q".into()],
        }]
    }
}
