//! rust-hdl description of the BiSS-C slave, with the line synchronizer and the position
//! word latch that the SSI and SPI slaves share.
use crate::blocks::biss::crc::TAPS;
use crate::blocks::biss::BissParams;
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// Two-flop synchronizer with an optional one-sample glitch filter and edge detection for
/// an asynchronous line that idles high (MA, SSI clock, SPI chip select and clock).
///
/// The flops hold the inverted line (n1, n2, n3, nf), so their power-up and reset value 0
/// means "high". `rise` / `fall` are one-cycle pulses; the parent acts on them at the next
/// clock edge, which is also when `level` (the filtered level) changes. They are registered:
/// the pipeline of flops shows the next clock's edge one clock early (the flops' next
/// values n1 -> n2, n2 -> n3 and nf's update are known now), so each pulse is computed from
/// those next values and comes straight from a flip-flop, with no LUT between the
/// synchronizer and the parent's decode; cycle for cycle they equal the edge test on the
/// current flops.
#[derive(LogicBlock)]
pub struct LineSync {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: the line is taken as high.
    pub rst: Signal<In, Bit>,
    /// The asynchronous line.
    pub pin: Signal<In, Bit>,
    /// Filtered, synchronized level.
    pub level: Signal<Out, Bit>,
    /// The filtered level rises at the next clock edge.
    pub rise: Signal<Out, Bit>,
    /// The filtered level falls at the next clock edge.
    pub fall: Signal<Out, Bit>,
    n1: DFF<Bit>,
    n2: DFF<Bit>,
    n3: DFF<Bit>,
    nf: DFF<Bit>,
    /// rise, registered (computed from the flops' next values).
    rise_r: DFF<Bit>,
    /// fall, registered.
    fall_r: DFF<Bit>,
    src: Signal<Local, Bit>,
    change: Signal<Local, Bit>,
    /// nf at the next clock.
    nfn: Signal<Local, Bit>,
    /// The edge test at the next clock (on n2 -> n1, n3 -> n2, nf -> nfn).
    chn: Signal<Local, Bit>,
    /// Glitch filter on.
    filter: Constant<Bit>,
}

impl LineSync {
    /// Synchronizer, with or without the glitch filter.
    pub fn new(glitch_filter: bool) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            pin: Default::default(),
            level: Default::default(),
            rise: Default::default(),
            fall: Default::default(),
            n1: Default::default(),
            n2: Default::default(),
            n3: Default::default(),
            nf: Default::default(),
            rise_r: Default::default(),
            fall_r: Default::default(),
            src: Default::default(),
            change: Default::default(),
            nfn: Default::default(),
            chn: Default::default(),
            filter: Constant::new(glitch_filter),
        }
    }
}

impl Logic for LineSync {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, n1, n2, n3, nf, rise_r, fall_r);
        self.n1.d.next = !self.pin.val();
        self.n2.d.next = self.n1.q.val();
        self.n3.d.next = self.n2.q.val();
        if self.filter.val() {
            self.src.next = self.n3.q.val();
            self.change.next =
                (self.n2.q.val() == self.n3.q.val()) & (self.n3.q.val() != self.nf.q.val());
        } else {
            self.src.next = self.n2.q.val();
            self.change.next = self.n2.q.val() != self.nf.q.val();
        }
        self.nfn.next = self.nf.q.val();
        if self.change.val() {
            self.nfn.next = self.src.val();
        }
        self.nf.d.next = self.nfn.val();
        // The same edge test one clock ahead: n2, n3 and nf at the next clock are n1, n2
        // and nfn.
        if self.filter.val() {
            self.chn.next =
                (self.n1.q.val() == self.n2.q.val()) & (self.n2.q.val() != self.nfn.val());
        } else {
            self.chn.next = self.n1.q.val() != self.nfn.val();
        }
        self.rise_r.d.next = self.chn.val() & self.nfn.val();
        self.fall_r.d.next = self.chn.val() & !self.nfn.val();
        self.level.next = !self.nf.q.val();
        self.rise.next = self.rise_r.q.val();
        self.fall.next = self.fall_r.q.val();
        if self.rst.val() {
            self.n1.d.next = false;
            self.n2.d.next = false;
            self.n3.d.next = false;
            self.nf.d.next = false;
            self.rise_r.d.next = false;
            self.fall_r.d.next = false;
        }
    }
}

/// Holds the last valid position and composes the data word and the sticky flags that a
/// slave latches at the start of a frame.
///
/// `word` = Gray or binary of (turns mod 2^M) * 2^S + (pos mod 2^S), from the inputs when
/// `pos_valid` is set in this cycle, otherwise from the held copy. `err` = a sticky error
/// since the last `take`, the current `error`, or no valid position since reset; `warn`
/// likewise. `take` (the slave latches this cycle) clears the sticky flags.
#[derive(LogicBlock)]
pub struct PosWord {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: no position, no flags.
    pub rst: Signal<In, Bit>,
    /// Single-turn position (low S bits).
    pub pos: Signal<In, Bits<32>>,
    /// Turn count (low M bits).
    pub turns: Signal<In, Bits<32>>,
    /// `pos` and `turns` are new.
    pub pos_valid: Signal<In, Bit>,
    /// Error flag (any cycle counts).
    pub error: Signal<In, Bit>,
    /// Warning flag (any cycle counts).
    pub warning: Signal<In, Bit>,
    /// The slave latches `word`, `err`, `warn` in this cycle.
    pub take: Signal<In, Bit>,
    /// Data word (S + M bits).
    pub word: Signal<Out, Bits<32>>,
    /// Error to report.
    pub err: Signal<Out, Bit>,
    /// Warning to report.
    pub warn: Signal<Out, Bit>,
    posh: DFF<Bits<32>>,
    turnsh: DFF<Bits<32>>,
    have: DFF<Bit>,
    erracc: DFF<Bit>,
    warnacc: DFF<Bit>,
    pm: Signal<Local, Bits<32>>,
    tm: Signal<Local, Bits<32>>,
    wb: Signal<Local, Bits<32>>,
    /// Mask of S position bits.
    stmask: Constant<Bits<32>>,
    /// Mask of M turn bits.
    mtmask: Constant<Bits<32>>,
    /// S, the shift of the turns (at most 31; the turns mask is 0 when S = 32).
    stshift: Constant<Bits<32>>,
    /// Gray-code the word.
    gray: Constant<Bit>,
    /// One.
    one: Constant<Bits<32>>,
}

impl PosWord {
    /// Word latch for S = `position_bits` and M = `multiturn_bits` (S + M <= 32).
    pub fn new(position_bits: u32, multiturn_bits: u32, gray: bool) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            pos: Default::default(),
            turns: Default::default(),
            pos_valid: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            take: Default::default(),
            word: Default::default(),
            err: Default::default(),
            warn: Default::default(),
            posh: Default::default(),
            turnsh: Default::default(),
            have: Default::default(),
            erracc: Default::default(),
            warnacc: Default::default(),
            pm: Default::default(),
            tm: Default::default(),
            wb: Default::default(),
            stmask: c32(mask(position_bits)),
            mtmask: c32(if position_bits >= 32 {
                0
            } else {
                mask(multiturn_bits)
            }),
            stshift: c32(position_bits.min(31) as u64),
            gray: Constant::new(gray),
            one: c32(1),
        }
    }
}

impl Logic for PosWord {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, posh, turnsh, have, erracc, warnacc);
        if self.pos_valid.val() {
            self.posh.d.next = self.pos.val();
            self.turnsh.d.next = self.turns.val();
            self.have.d.next = true;
            self.pm.next = self.pos.val();
            self.tm.next = self.turns.val();
        } else {
            self.pm.next = self.posh.q.val();
            self.tm.next = self.turnsh.q.val();
        }
        self.wb.next = ((self.tm.val() & self.mtmask.val()) << self.stshift.val())
            | (self.pm.val() & self.stmask.val());
        if self.gray.val() {
            self.word.next = self.wb.val() ^ (self.wb.val() >> self.one.val());
        } else {
            self.word.next = self.wb.val();
        }
        self.err.next =
            self.erracc.q.val() | self.error.val() | !(self.have.q.val() | self.pos_valid.val());
        self.warn.next = self.warnacc.q.val() | self.warning.val();
        if self.take.val() {
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
            self.have.d.next = false;
            self.erracc.d.next = false;
            self.warnacc.d.next = false;
        }
    }
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
    sync: LineSync,
    posw: PosWord,
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
    /// state == Cds, or state == Data with fnb low: the shift register's shift states,
    /// registered with state and fnb the same way.
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
            sync: LineSync::new(p.glitch_filter),
            posw: PosWord::new(p.position_bits, p.multiturn_bits, p.gray),
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
            tmask: c32(mask(32 - (p.timeout_clocks - 1).leading_zeros().min(31))),
            one: c32(1),
            zero: c32(0),
            ackn_m1: c32((p.ack_periods as u64).wrapping_sub(1) & mask(7)),
            nbits_m1: c32((n as u64).wrapping_sub(1) & mask(7)),
            five: c32(5),
            tlast_m1: c32((p.timeout_clocks as u64 - 1).wrapping_sub(1)
                & mask(32 - (p.timeout_clocks - 1).leading_zeros().min(31))),
            ack_is1: Constant::new(p.ack_periods == 1),
            n_is1: Constant::new(n == 1),
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
        }
        if self.rst.val() {
            self.state.d.next = BissState::Timeout;
            self.slo_reg.d.next = false;
            self.tcnt.d.next = self.zero.val();
            self.ftl.d.next = self.tlast_is0.val();
        }
        self.sidle.d.next = self.state.d.val() == BissState::Idle;
        self.sshift.d.next = (self.state.d.val() == BissState::Cds)
            | ((self.state.d.val() == BissState::Data) & !self.fnb.d.val());
        self.slo.next = self.slo_reg.q.val();
    }
}

impl crate::cosim::step::Clocked for BissSlave {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for BissSlave {
    fn input_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("rst", 1),
            Port::new("ma", 1),
            Port::new("pos", 32),
            Port::new("turns", 32),
            Port::new("pos_valid", 1),
            Port::new("error", 1),
            Port::new("warning", 1),
        ]
    }
    fn output_ports(&self) -> Vec<crate::cosim::Port> {
        vec![crate::cosim::Port::new("slo", 1)]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.ma.next = r[1] != 0;
        self.pos.next = Bits::<32>::from(r[2] & 0xffff_ffff);
        self.turns.next = Bits::<32>::from(r[3] & 0xffff_ffff);
        self.pos_valid.next = r[4] != 0;
        self.error.next = r[5] != 0;
        self.warning.next = r[6] != 0;
    }
    fn sample(&self) -> Vec<u64> {
        vec![self.slo.val() as u64]
    }
}
