//! rust-hdl description of the BiSS-C slave. The line synchronizer and the position word
//! latch it shares with the SSI and SPI slaves are in [`crate::blocks::serial::hdl`].
use crate::blocks::biss::control::BissControl;
use crate::blocks::biss::crc::TAPS;
use crate::blocks::biss::BissParams;
use crate::blocks::serial::hdl::{LineSync, PosWord};
use crate::blocks::serial::timeout_mask;
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// Where the BiSS slave is in its frame (see the module docs for the edge table).
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum BissState {
    /// SLO low until MA has been quiet for the timeout (after a frame and after reset).
    Timeout,
    /// SLO high, waiting for the first MA falling edge.
    Idle,
    /// After F1, waiting for R1 (SLO high).
    First,
    /// After R1, waiting for R2 (SLO high).
    Second,
    /// Ack: SLO low for `ack_periods` periods.
    Ack,
    /// Start bit (1) on SLO.
    Start,
    /// CDS bit (0) on SLO.
    Cds,
    /// Data bits on SLO.
    Data,
    /// nE on SLO.
    Err,
    /// nW on SLO.
    Warn,
    /// CRC bits on SLO.
    Crc,
}

/// BiSS-C slave, point-to-point, single-cycle data.
#[derive(LogicBlock)]
pub struct BissSlave {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// BiSS master clock MA (asynchronous, idles high).
    pub ma: Signal<In, Bit>,
    /// Single-turn position (low `position_bits`).
    pub pos: Signal<In, Bits<32>>,
    /// Turn count (low `multiturn_bits`).
    pub turns: Signal<In, Bits<32>>,
    /// `pos` and `turns` are new.
    pub pos_valid: Signal<In, Bit>,
    /// Decoder error (sent as nE = 0 in the next frame).
    pub error: Signal<In, Bit>,
    /// Decoder warning (sent as nW = 0 in the next frame).
    pub warning: Signal<In, Bit>,
    /// BiSS slave output SLO (registered).
    pub slo: Signal<Out, Bit>,
    /// The velocity word sent after the data (`velocity_bits` > 0: one input, latched with
    /// the position at F1; none without, so no port and no logic): two's complement in the
    /// low `velocity_bits`.
    pub vel: Vec<Signal<In, Bits<64>>>,
    /// The velocity shift register: its MSB enters `sh` at every data shift.
    vsh: Vec<DFF<Bits<64>>>,
    /// Mask of the velocity bits.
    vmask: Vec<Constant<Bits<64>>>,
    /// Bit `velocity_bits` - 1 of `vsh`.
    vmsb: Vec<Constant<Bits<64>>>,
    sync: LineSync,
    posw: PosWord,
    /// The control channel: one instance with `control`, none without (no Verilog).
    ctl: Vec<BissControl>,
    state: DFF<BissState>,
    slo_reg: DFF<Bit>,
    sh: DFF<Bits<32>>,
    crc: DFF<Bits<32>>,
    cnt: DFF<Bits<32>>,
    tcnt: DFF<Bits<32>>,
    errl: DFF<Bit>,
    warnl: DFF<Bit>,
    /// cnt == A, registered with cnt (the compares are taken on the value before the
    /// step, so none follows the counter's adder on the way to SLO).
    fack: DFF<Bit>,
    /// cnt == N, registered with cnt.
    fnb: DFF<Bit>,
    /// cnt == 6, registered with cnt.
    fsix: DFF<Bit>,
    /// tcnt == timeout_clocks - 1, registered with tcnt.
    ftl: DFF<Bit>,
    /// state == Idle, registered with state (decoded from its next value), so the shift
    /// register's load enable is one LUT of registers, not a state decode.
    sidle: DFF<Bit>,
    /// state == Cds, or state == Data with fnb low, one clock late (see `update`): the
    /// shift register's shift states, read only at a rise.
    sshift: DFF<Bit>,
    /// cnt takes 1 this clock.
    cld1: Signal<Local, Bit>,
    /// cnt counts up this clock.
    cinc: Signal<Local, Bit>,
    mae: Signal<Local, Bit>,
    dbit: Signal<Local, Bit>,
    cbit: Signal<Local, Bit>,
    cupd: Signal<Local, Bit>,
    fb: Signal<Local, Bit>,
    /// Mask of the N data bits.
    nmask: Constant<Bits<32>>,
    /// Bit N-1: the data MSB in the shift register.
    msb: Constant<Bits<32>>,
    /// Mask of the bit counter (7 bits).
    cmask: Constant<Bits<32>>,
    /// Mask of the six CRC bits.
    crcmask: Constant<Bits<32>>,
    /// CRC bit 5.
    crcmsb: Constant<Bits<32>>,
    /// CRC feedback taps (x + 1).
    taps: Constant<Bits<32>>,
    /// Mask of the timeout counter.
    tmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
    /// A - 1, N - 1, 5 and timeout_clocks - 2, masked to their counters: the counter value
    /// before a step up onto A, N, 6 and timeout_clocks - 1 (where SLO returns high).
    ackn_m1: Constant<Bits<32>>,
    nbits_m1: Constant<Bits<32>>,
    five: Constant<Bits<32>>,
    tlast_m1: Constant<Bits<32>>,
    /// 1 == A, 1 == N: the flags after cnt takes 1.
    ack_is1: Constant<Bit>,
    n_is1: Constant<Bit>,
    /// 0 == timeout_clocks - 1: the flag after tcnt takes 0.
    tlast_is0: Constant<Bit>,
}

impl BissSlave {
    /// Slave for validated parameters.
    pub fn new(p: &BissParams) -> crate::error::Result<Self> {
        p.validate()?;
        let n = p.data_bits();
        // The data state runs over the position word and the velocity word: N + V bits.
        let nf = p.frame_data_bits();
        let v = p.velocity_bits;
        let nv = (v > 0) as usize;
        Ok(Self {
            clk: Default::default(),
            rst: Default::default(),
            ma: Default::default(),
            pos: Default::default(),
            turns: Default::default(),
            pos_valid: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            slo: Default::default(),
            vel: (0..nv).map(|_| Default::default()).collect(),
            vsh: (0..nv).map(|_| Default::default()).collect(),
            vmask: (0..nv).map(|_| c64(mask(v))).collect(),
            vmsb: (0..nv).map(|_| c64(1 << (v.max(1) - 1))).collect(),
            sync: LineSync::new(p.glitch_filter),
            posw: PosWord::new(p.position_bits, p.multiturn_bits, p.gray),
            ctl: p.control.iter().map(BissControl::new).collect(),
            state: Default::default(),
            slo_reg: Default::default(),
            sh: Default::default(),
            crc: Default::default(),
            cnt: Default::default(),
            tcnt: Default::default(),
            errl: Default::default(),
            warnl: Default::default(),
            fack: Default::default(),
            fnb: Default::default(),
            sidle: Default::default(),
            sshift: Default::default(),
            fsix: Default::default(),
            ftl: Default::default(),
            cld1: Default::default(),
            cinc: Default::default(),
            mae: Default::default(),
            dbit: Default::default(),
            cbit: Default::default(),
            cupd: Default::default(),
            fb: Default::default(),
            nmask: c32(mask(n)),
            msb: c32(1 << (n - 1)),
            cmask: c32(mask(7)),
            crcmask: c32(mask(6)),
            crcmsb: c32(1 << 5),
            taps: c32(TAPS as u64),
            tmask: c32(timeout_mask(p.timeout_clocks)),
            one: c32(1),
            zero: c32(0),
            ackn_m1: c32((p.ack_periods as u64).wrapping_sub(1) & mask(7)),
            nbits_m1: c32((nf as u64).wrapping_sub(1) & mask(7)),
            five: c32(5),
            tlast_m1: c32(
                (p.timeout_clocks as u64 - 1).wrapping_sub(1) & timeout_mask(p.timeout_clocks)
            ),
            ack_is1: Constant::new(p.ack_periods == 1),
            n_is1: Constant::new(nf == 1),
            tlast_is0: Constant::new(p.timeout_clocks == 1),
        })
    }
}

impl Logic for BissSlave {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, state, slo_reg, sh, crc, cnt, tcnt, errl, warnl, fack, fnb, fsix, ftl,
            sidle, sshift
        );
        self.sync.clk.next = self.clk.val();
        self.sync.rst.next = self.rst.val();
        self.sync.pin.next = self.ma.val();
        self.posw.clk.next = self.clk.val();
        self.posw.rst.next = self.rst.val();
        self.posw.pos.next = self.pos.val();
        self.posw.turns.next = self.turns.val();
        self.posw.pos_valid.next = self.pos_valid.val();
        self.posw.error.next = self.error.val();
        self.posw.warning.next = self.warning.val();
        self.posw.take.next = false;
        for i in 0..self.ctl.len() {
            self.ctl[i].clk.next = self.clk.val();
            self.ctl[i].rst.next = self.rst.val();
            self.ctl[i].ma.next = self.sync.level.val();
            self.ctl[i].done.next = false;
            self.ctl[i].expire.next = false;
        }
        self.mae.next = self.sync.rise.val() | self.sync.fall.val();
        // Data MSB of the shift register, and the bit that enters the CRC this cycle.
        self.dbit.next = (self.sh.q.val() & self.msb.val()).any();
        self.cbit.next = self.dbit.val();
        self.cupd.next = false;
        self.cld1.next = false;
        self.cinc.next = false;
        // Cycles since the last MA edge.
        if self.mae.val() {
            self.tcnt.d.next = self.zero.val();
            self.ftl.d.next = self.tlast_is0.val();
        } else {
            self.tcnt.d.next = (self.tcnt.q.val() + self.one.val()) & self.tmask.val();
            self.ftl.d.next = self.tcnt.q.val() == self.tlast_m1.val();
        }
        match self.state.q.val() {
            BissState::Timeout => {}
            BissState::Idle => {
                if self.sync.fall.val() {
                    self.state.d.next = BissState::First;
                }
            }
            BissState::First => {
                if self.sync.rise.val() {
                    self.state.d.next = BissState::Second;
                }
            }
            BissState::Second => {
                if self.sync.rise.val() {
                    self.slo_reg.d.next = false;
                    self.cld1.next = true;
                    self.state.d.next = BissState::Ack;
                }
            }
            BissState::Ack => {
                if self.sync.rise.val() {
                    if self.fack.q.val() {
                        self.slo_reg.d.next = true;
                        self.state.d.next = BissState::Start;
                    } else {
                        self.cinc.next = true;
                    }
                }
            }
            BissState::Start => {
                if self.sync.rise.val() {
                    self.slo_reg.d.next = false;
                    // With the control channel, the CDS bit it prepared.
                    for i in 0..self.ctl.len() {
                        self.slo_reg.d.next = self.ctl[i].cds.val();
                    }
                    self.state.d.next = BissState::Cds;
                }
            }
            BissState::Cds => {
                if self.sync.rise.val() {
                    self.slo_reg.d.next = self.dbit.val();
                    self.cupd.next = true;
                    self.cld1.next = true;
                    self.state.d.next = BissState::Data;
                }
            }
            BissState::Data => {
                if self.sync.rise.val() {
                    self.cupd.next = true;
                    if self.fnb.q.val() {
                        self.cbit.next = !self.errl.q.val();
                        self.slo_reg.d.next = !self.errl.q.val();
                        self.state.d.next = BissState::Err;
                    } else {
                        self.slo_reg.d.next = self.dbit.val();
                        self.cinc.next = true;
                    }
                }
            }
            BissState::Err => {
                if self.sync.rise.val() {
                    self.cupd.next = true;
                    self.cbit.next = !self.warnl.q.val();
                    self.slo_reg.d.next = !self.warnl.q.val();
                    self.state.d.next = BissState::Warn;
                }
            }
            BissState::Warn => {
                if self.sync.rise.val() {
                    self.slo_reg.d.next = !(self.crc.q.val() & self.crcmsb.val()).any();
                    self.crc.d.next = (self.crc.q.val() << self.one.val()) & self.crcmask.val();
                    self.cld1.next = true;
                    self.state.d.next = BissState::Crc;
                }
            }
            BissState::Crc => {
                if self.sync.rise.val() {
                    if self.fsix.q.val() {
                        self.slo_reg.d.next = false;
                        self.state.d.next = BissState::Timeout;
                        // The final pulse: the frame is complete, its CDM will count.
                        for i in 0..self.ctl.len() {
                            self.ctl[i].done.next = true;
                        }
                    } else {
                        self.slo_reg.d.next = !(self.crc.q.val() & self.crcmsb.val()).any();
                        self.crc.d.next = (self.crc.q.val() << self.one.val()) & self.crcmask.val();
                        self.cinc.next = true;
                    }
                }
            }
        }
        // F1 in Idle (sidle is the registered state == Idle): latch the word and the flags,
        // clear the CRC.
        if self.sidle.q.val() & self.sync.fall.val() {
            self.posw.take.next = true;
            self.errl.d.next = self.posw.err.val();
            self.warnl.d.next = self.posw.warn.val();
            self.crc.d.next = self.zero.val();
        }
        // The shift register: loaded at F1 in Idle, shifted at each rising MA edge in Cds
        // and in Data before the last bit (the state decodes are registered flags).
        if self.sidle.q.val() & self.sync.fall.val() {
            self.sh.d.next = self.posw.word.val() & self.nmask.val();
        }
        if self.sshift.q.val() & self.sync.rise.val() {
            self.sh.d.next = (self.sh.q.val() << self.one.val()) & self.nmask.val();
        }
        // The velocity word: latched with the data word, shifted into sh's LSB behind it.
        for i in 0..self.vsh.len() {
            self.vsh[i].clock.next = self.clk.val();
            self.vsh[i].d.next = self.vsh[i].q.val();
            if self.sidle.q.val() & self.sync.fall.val() {
                self.vsh[i].d.next = self.vel[i].val() & self.vmask[i].val();
            }
            if self.sshift.q.val() & self.sync.rise.val() {
                self.vsh[i].d.next = (self.vsh[i].q.val() << self.one.val()) & self.vmask[i].val();
                if (self.vsh[i].q.val() & self.vmsb[i].val()).any() {
                    self.sh.d.next =
                        ((self.sh.q.val() << self.one.val()) & self.nmask.val()) | self.one.val();
                }
            }
        }
        // The bit counter and its compare flags.
        if self.cinc.val() {
            self.cnt.d.next = (self.cnt.q.val() + self.one.val()) & self.cmask.val();
            self.fack.d.next = self.cnt.q.val() == self.ackn_m1.val();
            self.fnb.d.next = self.cnt.q.val() == self.nbits_m1.val();
            self.fsix.d.next = self.cnt.q.val() == self.five.val();
        }
        if self.cld1.val() {
            self.cnt.d.next = self.one.val();
            self.fack.d.next = self.ack_is1.val();
            self.fnb.d.next = self.n_is1.val();
            self.fsix.d.next = false;
        }
        // Serial CRC6 of the data, nE and nW bits as they are put on SLO.
        self.fb.next = self.cbit.val() ^ (self.crc.q.val() & self.crcmsb.val()).any();
        if self.cupd.val() {
            if self.fb.val() {
                self.crc.d.next =
                    ((self.crc.q.val() << self.one.val()) & self.crcmask.val()) ^ self.taps.val();
            } else {
                self.crc.d.next = (self.crc.q.val() << self.one.val()) & self.crcmask.val();
            }
        }
        // The timeout ends every state but Idle: MA quiet for timeout_clocks -> idle, SLO high.
        if (self.state.q.val() != BissState::Idle) & !self.mae.val() & self.ftl.q.val() {
            self.slo_reg.d.next = true;
            self.state.d.next = BissState::Idle;
            // The control channel takes the CDM bit (the MA level held during the timeout).
            for i in 0..self.ctl.len() {
                self.ctl[i].expire.next = true;
            }
        }
        if self.rst.val() {
            self.state.d.next = BissState::Timeout;
            self.slo_reg.d.next = false;
            self.tcnt.d.next = self.zero.val();
            self.ftl.d.next = self.tlast_is0.val();
        }
        // Decoded from the next state: following sidle through its own transitions measured
        // 168.18 MHz on the default top at seed 1 against 176.12 MHz with this decode
        // (docs/timing.md, third round).
        self.sidle.d.next = self.state.d.val() == BissState::Idle;
        // sshift is read only with `rise`, and rises are at least two clocks apart (the
        // synchronizer's level must fall in between), so it may lag the state by a clock: it
        // is decoded from the registered state and fnb, which change only at a rise, a fall
        // (Idle -> First, where it is low either way), the timeout (-> Idle) or the reset;
        // the last two clear it. Registers in, one or two LUTs deep.
        self.sshift.d.next = ((self.state.q.val() == BissState::Cds)
            | ((self.state.q.val() == BissState::Data) & !self.fnb.q.val()))
            & !(!self.mae.val() & self.ftl.q.val())
            & !self.rst.val();
        self.slo.next = self.slo_reg.q.val();
    }
}

crate::cosim::cosim_block!(BissSlave {
    inputs: [rst: 1, ma: 1, pos: 32, turns: 32, pos_valid: 1, error: 1, warning: 1],
    outputs: [slo: 1],
});
