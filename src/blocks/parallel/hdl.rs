//! rust-hdl description of the parallel position bus.
use crate::blocks::parallel::ParallelParams;
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// Registered parallel position output with a valid strobe and a hold input.
#[derive(LogicBlock)]
pub struct ParallelBus {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// Single-turn position (low S bits).
    pub pos: Signal<In, Bits<32>>,
    /// Turn count (low M bits).
    pub turns: Signal<In, Bits<32>>,
    /// `pos` and `turns` are new.
    pub pos_valid: Signal<In, Bit>,
    /// Decoder error.
    pub error: Signal<In, Bit>,
    /// Decoder warning.
    pub warning: Signal<In, Bit>,
    /// Freeze the outputs.
    pub hold: Signal<In, Bit>,
    /// Position (S bits).
    pub par_pos: Signal<Out, Bits<32>>,
    /// Turn count (M bits).
    pub par_turns: Signal<Out, Bits<32>>,
    /// One-cycle strobe: new words.
    pub par_valid: Signal<Out, Bit>,
    /// Error since the previous update.
    pub par_error: Signal<Out, Bit>,
    /// Warning since the previous update.
    pub par_warning: Signal<Out, Bit>,
    pos_reg: DFF<Bits<32>>,
    turns_reg: DFF<Bits<32>>,
    valid_reg: DFF<Bit>,
    error_reg: DFF<Bit>,
    warning_reg: DFF<Bit>,
    erracc: DFF<Bit>,
    warnacc: DFF<Bit>,
    upd: Signal<Local, Bit>,
    /// Mask of S bits.
    stmask: Constant<Bits<32>>,
    /// Mask of M bits.
    mtmask: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl ParallelBus {
    /// Bus for validated parameters.
    pub fn new(p: &ParallelParams) -> crate::error::Result<Self> {
        p.validate()?;
        Ok(Self {
            clk: Default::default(),
            rst: Default::default(),
            pos: Default::default(),
            turns: Default::default(),
            pos_valid: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            hold: Default::default(),
            par_pos: Default::default(),
            par_turns: Default::default(),
            par_valid: Default::default(),
            par_error: Default::default(),
            par_warning: Default::default(),
            pos_reg: Default::default(),
            turns_reg: Default::default(),
            valid_reg: Default::default(),
            error_reg: Default::default(),
            warning_reg: Default::default(),
            erracc: Default::default(),
            warnacc: Default::default(),
            upd: Default::default(),
            stmask: c32(mask(p.position_bits)),
            mtmask: c32(mask(p.multiturn_bits)),
            zero: c32(0),
        })
    }
}

impl Logic for ParallelBus {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clk,
            pos_reg,
            turns_reg,
            valid_reg,
            error_reg,
            warning_reg,
            erracc,
            warnacc
        );
        self.upd.next = self.pos_valid.val() & !self.hold.val();
        self.valid_reg.d.next = self.upd.val();
        if self.upd.val() {
            self.pos_reg.d.next = self.pos.val() & self.stmask.val();
            self.turns_reg.d.next = self.turns.val() & self.mtmask.val();
            self.error_reg.d.next = self.error.val() | self.erracc.q.val();
            self.warning_reg.d.next = self.warning.val() | self.warnacc.q.val();
            self.erracc.d.next = false;
            self.warnacc.d.next = false;
        } else {
            if self.error.val() {
                self.erracc.d.next = true;
            }
            if self.warning.val() {
                self.warnacc.d.next = true;
            }
        }
        if self.rst.val() {
            self.pos_reg.d.next = self.zero.val();
            self.turns_reg.d.next = self.zero.val();
            self.valid_reg.d.next = false;
            self.error_reg.d.next = false;
            self.warning_reg.d.next = false;
            self.erracc.d.next = false;
            self.warnacc.d.next = false;
        }
        self.par_pos.next = self.pos_reg.q.val();
        self.par_turns.next = self.turns_reg.q.val();
        self.par_valid.next = self.valid_reg.q.val();
        self.par_error.next = self.error_reg.q.val();
        self.par_warning.next = self.warning_reg.q.val();
    }
}

crate::cosim::cosim_block!(ParallelBus {
    inputs: [rst: 1, pos: 32, turns: 32, pos_valid: 1, error: 1, warning: 1, hold: 1],
    outputs: [par_pos: 32, par_turns: 32, par_valid: 1, par_error: 1, par_warning: 1],
});
