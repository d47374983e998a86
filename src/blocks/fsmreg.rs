//! A state register that synthesis re-encodes one-hot: rust-hdl's `DFF` for an enum, with
//! `(* fsm_encoding = "one-hot" *)` on its register and no initial value for synthesis.
//!
//! ```text
//!   d ──► (* fsm_encoding = "one-hot" *) reg s ──► q        (posedge clock)
//! ```
//!
//! Why: a state decoded from log2(S) bits takes two LUT levels before every select it
//! steers, and in a wide sequencer those decodes fan out into every register
//! (docs/timing.md, "Design rules learned"). One-hot, each state is one flip-flop. Yosys
//! extracts a state machine only from a register without an initial value ("Register has
//! an initialization value"), and rust-hdl's `DFF` always writes one. So the initial value
//! here is for the simulators only (`ifndef SYNTHESIS`, the pattern of
//! `super::biquad::parts::BiquadStateRam`): rust-hdl, Icarus, Verilator and the engine
//! (whose zero start is the enum's first state) power up in the first state; a synthesized
//! design powers up with no state hot and needs one reset after configuration, which
//! `<name>_top`'s reset synchronizer gives at power-up. Written here because rust-hdl has
//! no way to carry an attribute on a register.
use rust_hdl::prelude::*;

/// An enum's state register, re-encoded one-hot by synthesis (see the module doc).
#[derive(Clone, Debug, LogicBlock, Default)]
pub struct FsmReg<T: Synth> {
    /// The next state.
    pub d: Signal<In, T>,
    /// The state (the enum's first at power-up in simulation).
    pub q: Signal<Out, T>,
    /// The clock.
    pub clock: Signal<In, Clock>,
}

impl<T: Synth> Logic for FsmReg<T> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            self.q.next = self.d.val()
        }
    }
    fn connect(&mut self) {
        self.q.connect();
    }
    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
(* fsm_encoding = \"one-hot\" *) reg [{w}:0] s;
`ifndef SYNTHESIS
initial begin
   s = {n}'d{init};
end
`endif

always @(posedge clock) begin
   s <= d;
end

always @(*) begin
   q = s;
end
",
            w = T::BITS - 1,
            n = T::BITS,
            init = T::default().verilog().as_usize(),
        ))
    }
}
