//! rust-hdl description of the SSI slave.
use crate::blocks::serial::hdl::{LineSync, PosWord};
use crate::blocks::serial::timeout_mask;
use crate::blocks::ssi::SsiParams;
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// Where the SSI slave is in its frame.
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum SsiState {
    /// Line low until the clock has been quiet for the monoflop time.
    Timeout,
    /// Line high, waiting for the first falling clock edge.
    Idle,
    /// After F1, waiting for R1.
    First,
    /// Data bits on the line.
    Data,
    /// Error bit on the line.
    ErrBit,
}

/// SSI slave.
#[derive(LogicBlock)]
pub struct SsiSlave {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// SSI clock from the master (asynchronous, idles high).
    pub ma: Signal<In, Bit>,
    /// Single-turn position (low `position_bits`).
    pub pos: Signal<In, Bits<32>>,
    /// Turn count (low `multiturn_bits`).
    pub turns: Signal<In, Bits<32>>,
    /// `pos` and `turns` are new.
    pub pos_valid: Signal<In, Bit>,
    /// Decoder error (sent in the error bit of the next frame, when enabled).
    pub error: Signal<In, Bit>,
    /// SSI data output (registered).
    pub slo: Signal<Out, Bit>,
    /// The velocity word sent after the data when `velocity_bits` > 0 (latched with the
    /// position), two's complement in the low `velocity_bits`; unused otherwise. A plain
    /// port, not a `Vec` like BiSS's: the top reaches it through its own `Vec` of slaves, and
    /// rust-hdl's Verilog resolves only one index per name.
    pub vel: Signal<In, Bits<64>>,
    /// The velocity shift register: its MSB enters `sh` at every data shift.
    vsh: Vec<DFF<Bits<64>>>,
    /// Mask of the velocity bits.
    vmask: Vec<Constant<Bits<64>>>,
    /// Bit `velocity_bits` - 1 of `vsh`.
    vmsb: Vec<Constant<Bits<64>>>,
    sync: LineSync,
    posw: PosWord,
    state: DFF<SsiState>,
    slo_reg: DFF<Bit>,
    sh: DFF<Bits<32>>,
    cnt: DFF<Bits<32>>,
    tcnt: DFF<Bits<32>>,
    errl: DFF<Bit>,
    mae: Signal<Local, Bit>,
    dbit: Signal<Local, Bit>,
    /// Mask of the N data bits.
    nmask: Constant<Bits<32>>,
    /// Bit N-1.
    msb: Constant<Bits<32>>,
    /// N.
    nbits: Constant<Bits<32>>,
    /// Append the error bit.
    ebit: Constant<Bit>,
    /// Mask of the bit counter.
    cmask: Constant<Bits<32>>,
    /// Monoflop time in clocks minus one.
    tlast: Constant<Bits<32>>,
    /// Mask of the monoflop counter.
    tmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl SsiSlave {
    /// Slave for validated parameters.
    pub fn new(p: &SsiParams) -> crate::error::Result<Self> {
        p.validate()?;
        let n = p.data_bits();
        let v = p.velocity_bits;
        let nv = (v > 0) as usize;
        Ok(Self {
            vel: Default::default(),
            vsh: (0..nv).map(|_| Default::default()).collect(),
            vmask: (0..nv).map(|_| c64(mask(v))).collect(),
            vmsb: (0..nv).map(|_| c64(1 << (v.max(1) - 1))).collect(),
            clk: Default::default(),
            rst: Default::default(),
            ma: Default::default(),
            pos: Default::default(),
            turns: Default::default(),
            pos_valid: Default::default(),
            error: Default::default(),
            slo: Default::default(),
            sync: LineSync::new(p.glitch_filter),
            posw: PosWord::new(p.position_bits, p.multiturn_bits, p.gray),
            state: Default::default(),
            slo_reg: Default::default(),
            sh: Default::default(),
            cnt: Default::default(),
            tcnt: Default::default(),
            errl: Default::default(),
            mae: Default::default(),
            dbit: Default::default(),
            nmask: c32(mask(n)),
            msb: c32(1 << (n - 1)),
            nbits: c32((n + v) as u64),
            ebit: Constant::new(p.error_bit),
            cmask: c32(mask(7)),
            tlast: c32(p.timeout_clocks as u64 - 1),
            tmask: c32(timeout_mask(p.timeout_clocks)),
            one: c32(1),
            zero: c32(0),
        })
    }
}

impl Logic for SsiSlave {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, state, slo_reg, sh, cnt, tcnt, errl);
        self.sync.clk.next = self.clk.val();
        self.sync.rst.next = self.rst.val();
        self.sync.pin.next = self.ma.val();
        self.posw.clk.next = self.clk.val();
        self.posw.rst.next = self.rst.val();
        self.posw.pos.next = self.pos.val();
        self.posw.turns.next = self.turns.val();
        self.posw.pos_valid.next = self.pos_valid.val();
        self.posw.error.next = self.error.val();
        self.posw.warning.next = false;
        self.posw.take.next = false;
        self.mae.next = self.sync.rise.val() | self.sync.fall.val();
        for i in 0..self.vsh.len() {
            self.vsh[i].clock.next = self.clk.val();
            self.vsh[i].d.next = self.vsh[i].q.val();
        }
        self.dbit.next = (self.sh.q.val() & self.msb.val()).any();
        if self.mae.val() {
            self.tcnt.d.next = self.zero.val();
        } else {
            self.tcnt.d.next = (self.tcnt.q.val() + self.one.val()) & self.tmask.val();
        }
        match self.state.q.val() {
            SsiState::Timeout => {}
            SsiState::Idle => {
                if self.sync.fall.val() {
                    self.posw.take.next = true;
                    self.sh.d.next = self.posw.word.val() & self.nmask.val();
                    for i in 0..self.vsh.len() {
                        self.vsh[i].d.next = self.vel.val() & self.vmask[i].val();
                    }
                    self.errl.d.next = self.posw.err.val();
                    self.state.d.next = SsiState::First;
                }
            }
            SsiState::First => {
                if self.sync.rise.val() {
                    self.slo_reg.d.next = self.dbit.val();
                    self.sh.d.next = (self.sh.q.val() << self.one.val()) & self.nmask.val();
                    for i in 0..self.vsh.len() {
                        self.vsh[i].d.next =
                            (self.vsh[i].q.val() << self.one.val()) & self.vmask[i].val();
                        if (self.vsh[i].q.val() & self.vmsb[i].val()).any() {
                            self.sh.d.next = ((self.sh.q.val() << self.one.val())
                                & self.nmask.val())
                                | self.one.val();
                        }
                    }
                    self.cnt.d.next = self.one.val();
                    self.state.d.next = SsiState::Data;
                }
            }
            SsiState::Data => {
                if self.sync.rise.val() {
                    if self.cnt.q.val() == self.nbits.val() {
                        if self.ebit.val() {
                            self.slo_reg.d.next = self.errl.q.val();
                            self.state.d.next = SsiState::ErrBit;
                        } else {
                            self.slo_reg.d.next = false;
                            self.state.d.next = SsiState::Timeout;
                        }
                    } else {
                        self.slo_reg.d.next = self.dbit.val();
                        self.sh.d.next = (self.sh.q.val() << self.one.val()) & self.nmask.val();
                        for i in 0..self.vsh.len() {
                            self.vsh[i].d.next =
                                (self.vsh[i].q.val() << self.one.val()) & self.vmask[i].val();
                            if (self.vsh[i].q.val() & self.vmsb[i].val()).any() {
                                self.sh.d.next = ((self.sh.q.val() << self.one.val())
                                    & self.nmask.val())
                                    | self.one.val();
                            }
                        }
                        self.cnt.d.next = (self.cnt.q.val() + self.one.val()) & self.cmask.val();
                    }
                }
            }
            SsiState::ErrBit => {
                if self.sync.rise.val() {
                    self.slo_reg.d.next = false;
                    self.state.d.next = SsiState::Timeout;
                }
            }
        }
        // Monoflop: the clock quiet for timeout_clocks ends every state but Idle.
        if (self.state.q.val() != SsiState::Idle)
            & !self.mae.val()
            & (self.tcnt.q.val() == self.tlast.val())
        {
            self.slo_reg.d.next = true;
            self.state.d.next = SsiState::Idle;
        }
        if self.rst.val() {
            self.state.d.next = SsiState::Timeout;
            self.slo_reg.d.next = false;
            self.tcnt.d.next = self.zero.val();
        }
        self.slo.next = self.slo_reg.q.val();
    }
}

crate::cosim::cosim_block!(SsiSlave {
    inputs: [rst: 1, ma: 1, pos: 32, turns: 32, pos_valid: 1, error: 1],
    outputs: [slo: 1],
});
