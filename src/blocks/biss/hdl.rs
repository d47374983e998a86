//! rust-hdl description of the BiSS-C slave. The line synchronizer and the position word
//! latch it shares with the SSI and SPI slaves are in [`crate::blocks::serial::hdl`].
use crate::blocks::biss::control::BissControl;
use crate::blocks::biss::crc::TAPS;
use crate::blocks::biss::BissParams;
use crate::blocks::serial::hdl::{LineSync, PosWord};
use crate::blocks::serial::timeout_mask;
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// Where the slave is in its frame (the module docs' edge table).
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum BissState {
    /// SLO low until MA has been quiet for the timeout (after a frame, after reset, and at
    /// power-up: the first variant is the register's initial value).
    Timeout,
    /// SLO high, waiting for F1, the first MA falling edge.
    Idle,
    /// After F1, waiting for R1 (SLO high).
    First,
    /// After R1, waiting for R2 (SLO high).
    Second,
    /// Ack: SLO low for `ack_periods` periods.
    Ack,
    /// Start bit (1) on SLO.
    Start,
    /// CDS bit (0, or the control channel's answer) on SLO.
    Cds,
    /// Data bits on SLO (the position word, then the velocity word).
    Data,
    /// nE on SLO.
    Err,
    /// nW on SLO.
    Warn,
    /// CRC bits on SLO.
    Crc,
}

fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
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
    /// The register map's byte port (`user_map`: one each, none without), the control
    /// channel's `ext_*`: byte address, write strobe, written byte, read start, read byte.
    pub reg_addr: Vec<Signal<Out, Bits<32>>>,
    /// See `reg_addr`.
    pub reg_we: Vec<Signal<Out, Bit>>,
    /// See `reg_addr`.
    pub reg_wdata: Vec<Signal<Out, Bits<8>>>,
    /// See `reg_addr`.
    pub reg_snap: Vec<Signal<Out, Bit>>,
    /// See `reg_addr`.
    pub reg_rdata: Vec<Signal<In, Bits<8>>>,
    /// Where the slave is in its frame; power-up Timeout (the enum's first variant is the
    /// register's initial value), like the reset.
    state: DFF<BissState>,
    // What the next rising MA edge does, registered one clock ahead from the state and the
    // counter flags (`NextRise`):
    /// The next rise steps the CRC (its enable a flip-flop, not a state decode).
    pact: DFF<Bit>,
    /// That step's feedback: the bit sent XOR the CRC MSB (the bit's mux off the CRC's D).
    pfb: DFF<Bit>,
    /// The next rise counts cnt up (its enable a flip-flop, not a state decode).
    pinc: DFF<Bit>,
    /// The next rise loads cnt with 1 (likewise).
    pld: DFF<Bit>,
    /// The next rise loads `slo_reg` with `rv` (likewise).
    rven: DFF<Bit>,
    /// The value SLO takes at the next rise (the edge table's mux off `slo_reg`'s D).
    rv: DFF<Bit>,
    /// SLO's output register.
    slo_reg: DFF<Bit>,
    sh: DFF<Bits<32>>,
    crc: DFF<Bits<32>>,
    cnt: DFF<Bits<32>>,
    tcnt: DFF<Bits<32>>,
    /// The error flag latched at F1 (sent as nE = 0).
    errl: DFF<Bit>,
    /// The warning flag latched at F1 (sent as nW = 0).
    warnl: DFF<Bit>,
    /// cnt == A, registered with cnt (the compares are taken on the value before the
    /// step, so none follows the counter's adder on the way to SLO).
    fack: DFF<Bit>,
    /// cnt == N, registered with cnt (like `fack`: no compare on cnt -> state and SLO).
    fnb: DFF<Bit>,
    /// cnt == 6, registered with cnt (like `fack`: no compare on cnt -> state and SLO).
    fsix: DFF<Bit>,
    /// The timeout ends this clock unless MA has an edge: not Idle and tcnt ==
    /// timeout_clocks - 1, registered from their next values, so that the state's timeout
    /// gate waits on the edge pulses only (tcnt and its compare off the path to the state).
    tmoq: DFF<Bit>,
    /// tcnt == timeout_clocks - 2, registered with tcnt: tcnt's end one clock ahead, so
    /// that `tmoq`'s next value is a select of registers (no compare after tcnt's adder).
    fpre: DFF<Bit>,
    /// state == Cds, or state == Data with fnb low, one clock late (see `Shift`): the shift
    /// register's shift enable as one flip-flop (the state decode off the path to the 32
    /// bits of `sh`), read only at a rise.
    sshift: DFF<Bit>,
    /// An MA edge this clock.
    mae: Signal<Local, Bit>,
    /// The timeout ends this clock (MA quiet for timeout_clocks, not in Idle).
    tmo: Signal<Local, Bit>,
    /// tcnt == timeout_clocks - 1 at the next clock.
    ftln: Signal<Local, Bit>,
    /// The state's next value is Idle.
    idlen: Signal<Local, Bit>,
    /// F1: the first MA falling edge, in Idle (latch the word, load the shift register).
    f1: Signal<Local, Bit>,
    /// Not the reset and not the end of the timeout: the state stays or follows an edge.
    live: Signal<Local, Bit>,
    /// The data MSB of the shift register.
    dbit: Signal<Local, Bit>,
    /// The CRC's MSB.
    cmsb: Signal<Local, Bit>,
    /// The CRC's next value when it steps.
    cnext: Signal<Local, Bits<32>>,
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
    /// A - 1, N - 1, 5 and timeout_clocks - 3, masked to their counters: the counter value
    /// before a step up onto A, N, 6 and timeout_clocks - 2 (one clock before SLO returns
    /// high).
    ackn_m1: Constant<Bits<32>>,
    nbits_m1: Constant<Bits<32>>,
    five: Constant<Bits<32>>,
    tlast_m2: Constant<Bits<32>>,
    /// 1 == A, 1 == N: the flags after cnt takes 1.
    ack_is1: Constant<Bit>,
    n_is1: Constant<Bit>,
    /// 0 == timeout_clocks - 1 and 0 == timeout_clocks - 2: tcnt's end flags after it takes 0
    /// (false: `timeout_clocks` >= 8).
    tlast_is0: Constant<Bit>,
    tpre_is0: Constant<Bit>,
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
            ctl: p
                .control
                .iter()
                .map(|id| BissControl::new(id, p.user_map))
                .collect(),
            reg_addr: user(p),
            reg_we: user(p),
            reg_wdata: user(p),
            reg_snap: user(p),
            reg_rdata: user(p),
            state: Default::default(),
            pact: Default::default(),
            pfb: Default::default(),
            pinc: Default::default(),
            pld: Default::default(),
            rven: Default::default(),
            rv: Default::default(),
            slo_reg: Default::default(),
            sh: Default::default(),
            crc: Default::default(),
            cnt: Default::default(),
            tcnt: Default::default(),
            errl: Default::default(),
            warnl: Default::default(),
            fack: Default::default(),
            fnb: Default::default(),
            sshift: Default::default(),
            fsix: Default::default(),
            tmoq: Default::default(),
            fpre: Default::default(),
            mae: Default::default(),
            tmo: Default::default(),
            ftln: Default::default(),
            live: Default::default(),
            dbit: Default::default(),
            cmsb: Default::default(),
            f1: Default::default(),
            idlen: Default::default(),
            cnext: Default::default(),
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
            tlast_m2: c32(
                (p.timeout_clocks as u64 - 1).wrapping_sub(2) & timeout_mask(p.timeout_clocks)
            ),
            ack_is1: Constant::new(p.ack_periods == 1),
            n_is1: Constant::new(nf == 1),
            tlast_is0: Constant::new(p.timeout_clocks == 1),
            tpre_is0: Constant::new(
                (p.timeout_clocks as u64 - 1).wrapping_sub(1) & timeout_mask(p.timeout_clocks) == 0,
            ),
        })
    }
}

// The slave's logic in named stages, run in this order (`logic_stages!`).
crate::blocks::logic_stages!(BissSlave: Timeout, FrameState, NextRise, Shift);

/// The MA edges and the timeout.
impl stages::Timeout for BissSlave {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, state, pact, pfb, pinc, pld, rven, rv, slo_reg, sh, crc, cnt, tcnt, errl,
            warnl, fack, fnb, fsix, tmoq, fpre, sshift
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
            self.ctl[i].ext_rdata.next = bit_cast::<8, 32>(self.sh.q.val());
            for j in 0..self.reg_rdata.len() {
                self.ctl[i].ext_rdata.next = self.reg_rdata[j].val();
                self.reg_addr[j].next = self.ctl[i].ext_addr.val();
                self.reg_we[j].next = self.ctl[i].ext_we.val();
                self.reg_wdata[j].next = self.ctl[i].ext_wdata.val();
                self.reg_snap[j].next = self.ctl[i].ext_snap.val();
            }
        }
        self.mae.next = self.sync.rise.val() | self.sync.fall.val();
        // The timeout ends every state but Idle: MA quiet for timeout_clocks -> idle, SLO high.
        // tmoq holds "not Idle and tcnt at its end" (registered), so the state's gate is one
        // LUT on registers (tmoq, the edge pulses, the reset).
        self.tmo.next = self.tmoq.q.val() & !self.mae.val();
        self.live.next = !self.tmo.val() & !self.rst.val();
        // Cycles since the last MA edge, with tcnt == timeout_clocks - 2 registered beside it
        // (the compare is taken on the value before the step), so that the end flag at the
        // next clock is a select of registers.
        if self.mae.val() {
            self.tcnt.d.next = self.zero.val();
            self.ftln.next = self.tlast_is0.val();
            self.fpre.d.next = self.tpre_is0.val();
        } else {
            self.tcnt.d.next = (self.tcnt.q.val() + self.one.val()) & self.tmask.val();
            self.ftln.next = self.fpre.q.val();
            self.fpre.d.next = self.tcnt.q.val() == self.tlast_m2.val();
        }
        if self.rst.val() {
            self.tcnt.d.next = self.zero.val();
            self.ftln.next = self.tlast_is0.val();
            self.fpre.d.next = self.tpre_is0.val();
        }
    }
}

/// The frame state: one arm per row of the module docs' edge table.
impl stages::FrameState for BissSlave {
    #[hdl_gen]
    fn update(&mut self) {
        // F1 leaves Idle, each rise moves on (Ack, Data and Crc stay until their counter
        // flag), the timeout goes to Idle (never with an edge: it needs MA quiet), the reset
        // to Timeout.
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
                    self.state.d.next = BissState::Ack;
                }
            }
            BissState::Ack => {
                if self.sync.rise.val() & self.fack.q.val() {
                    self.state.d.next = BissState::Start;
                }
            }
            BissState::Start => {
                if self.sync.rise.val() {
                    self.state.d.next = BissState::Cds;
                }
            }
            BissState::Cds => {
                if self.sync.rise.val() {
                    self.state.d.next = BissState::Data;
                }
            }
            BissState::Data => {
                if self.sync.rise.val() & self.fnb.q.val() {
                    self.state.d.next = BissState::Err;
                }
            }
            BissState::Err => {
                if self.sync.rise.val() {
                    self.state.d.next = BissState::Warn;
                }
            }
            BissState::Warn => {
                if self.sync.rise.val() {
                    self.state.d.next = BissState::Crc;
                }
            }
            BissState::Crc => {
                if self.sync.rise.val() & self.fsix.q.val() {
                    self.state.d.next = BissState::Timeout;
                    // The final pulse: the frame is complete, its CDM will count.
                    for i in 0..self.ctl.len() {
                        self.ctl[i].done.next = true;
                    }
                }
            }
        }
        if self.tmo.val() {
            self.state.d.next = BissState::Idle;
        }
        if self.rst.val() {
            self.state.d.next = BissState::Timeout;
        }
        // The next state is Idle, written out (not read from `state.d`), so that tmoq's
        // path stays off the state's next-state mux.
        self.idlen.next = !self.rst.val()
            & (self.tmo.val() | ((self.state.q.val() == BissState::Idle) & !self.sync.fall.val()));
        self.tmoq.d.next = !self.idlen.val() & self.ftln.val();
        self.f1.next = (self.state.q.val() == BissState::Idle) & self.sync.fall.val();
    }
}

/// What the next rise does: data bit, CRC, counter, SLO.
impl stages::NextRise for BissSlave {
    #[hdl_gen]
    fn update(&mut self) {
        // What the next rise does, registered one clock ahead from the state and the flags.
        // A rise reads them at least two clocks after the previous rise (the synchronizer's
        // level must fall in between), and between rises the state, cnt's flags, the CRC, the
        // shift register, errl, warnl and the control channel's CDS bit change only at F1
        // (Idle -> First: a rise does nothing in either), at the end of the timeout (-> Idle)
        // and at the reset (-> Timeout), which clear these flags; so at every rise they equal
        // the decode of that clock's state. The CRC steps at a rise in Cds, Data and Err with
        // the bit sent (serial CRC6 of the data, nE and nW bits, feedback `pfb`), and shifts
        // out in Warn and Crc before the last bit; cnt takes 1 on entering Ack, Data and Crc
        // and counts up in them before their flag; SLO takes the value of the edge table.
        self.dbit.next = (self.sh.q.val() & self.msb.val()).any();
        self.cmsb.next = (self.crc.q.val() & self.crcmsb.val()).any();
        self.pact.d.next = false;
        self.pfb.d.next = false;
        self.pinc.d.next = false;
        self.pld.d.next = false;
        self.rven.d.next = true;
        self.rv.d.next = false;
        self.sshift.d.next = false;
        match self.state.q.val() {
            BissState::Timeout => {
                self.rven.d.next = false;
            }
            BissState::Idle => {
                self.rven.d.next = false;
            }
            BissState::First => {
                self.rven.d.next = false;
            }
            BissState::Second => {
                // -> Ack: SLO 0.
                self.pld.d.next = true;
            }
            BissState::Ack => {
                // At its end -> Start: SLO 1.
                self.pinc.d.next = !self.fack.q.val();
                self.rven.d.next = self.fack.q.val();
                self.rv.d.next = true;
            }
            BissState::Start => {
                // -> Cds: SLO 0, or with the control channel the CDS bit it prepared.
                for i in 0..self.ctl.len() {
                    self.rv.d.next = self.ctl[i].cds.val();
                }
            }
            BissState::Cds => {
                // -> Data: SLO the data MSB.
                self.pact.d.next = true;
                self.pfb.d.next = self.dbit.val() ^ self.cmsb.val();
                self.pld.d.next = true;
                self.rv.d.next = self.dbit.val();
                self.sshift.d.next = true;
            }
            BissState::Data => {
                // The next data bit, or after the last -> Err: SLO nE.
                self.pact.d.next = true;
                if self.fnb.q.val() {
                    self.pfb.d.next = !self.errl.q.val() ^ self.cmsb.val();
                    self.rv.d.next = !self.errl.q.val();
                } else {
                    self.pfb.d.next = self.dbit.val() ^ self.cmsb.val();
                    self.pinc.d.next = true;
                    self.rv.d.next = self.dbit.val();
                    self.sshift.d.next = true;
                }
            }
            BissState::Err => {
                // -> Warn: SLO nW.
                self.pact.d.next = true;
                self.pfb.d.next = !self.warnl.q.val() ^ self.cmsb.val();
                self.rv.d.next = !self.warnl.q.val();
            }
            BissState::Warn => {
                // -> Crc: SLO the inverted CRC MSB.
                self.pact.d.next = true;
                self.pld.d.next = true;
                self.rv.d.next = !self.cmsb.val();
            }
            BissState::Crc => {
                // The next inverted CRC bit, or after the last -> Timeout: SLO 0.
                if !self.fsix.q.val() {
                    self.pact.d.next = true;
                    self.pinc.d.next = true;
                    self.rv.d.next = !self.cmsb.val();
                }
            }
        }
        // The timeout and the reset clear the enables (see above).
        if !self.live.val() {
            self.pact.d.next = false;
            self.pinc.d.next = false;
            self.pld.d.next = false;
            self.rven.d.next = false;
            self.sshift.d.next = false;
        }
        if self.sync.rise.val() & self.rven.q.val() {
            self.slo_reg.d.next = self.rv.q.val();
        }
    }
}

/// The latch at F1, the CRC, the shift register and the bit counter.
impl stages::Shift for BissSlave {
    #[hdl_gen]
    fn update(&mut self) {
        // F1 in Idle: latch the word and the flags, clear the CRC.
        if self.f1.val() {
            self.posw.take.next = true;
            self.errl.d.next = self.posw.err.val();
            self.warnl.d.next = self.posw.warn.val();
            self.crc.d.next = self.zero.val();
        }
        // The CRC step of a rise (6 bits, taps x + 1 with the feedback).
        self.cnext.next = (self.crc.q.val() << self.one.val()) & self.crcmask.val();
        if self.pfb.q.val() {
            self.cnext.next =
                ((self.crc.q.val() << self.one.val()) & self.crcmask.val()) ^ self.taps.val();
        }
        if self.sync.rise.val() & self.pact.q.val() {
            self.crc.d.next = self.cnext.val();
        }
        // The shift register: loaded at F1 in Idle, shifted at each rising MA edge in Cds
        // and in Data before the last bit (the state decodes are registered flags).
        if self.f1.val() {
            self.sh.d.next = self.posw.word.val() & self.nmask.val();
        }
        if self.sshift.q.val() & self.sync.rise.val() {
            self.sh.d.next = (self.sh.q.val() << self.one.val()) & self.nmask.val();
        }
        // The velocity word: latched with the data word, shifted into sh's LSB behind it.
        for i in 0..self.vsh.len() {
            self.vsh[i].clock.next = self.clk.val();
            self.vsh[i].d.next = self.vsh[i].q.val();
            if self.f1.val() {
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
        if self.sync.rise.val() & self.pinc.q.val() {
            self.cnt.d.next = (self.cnt.q.val() + self.one.val()) & self.cmask.val();
            self.fack.d.next = self.cnt.q.val() == self.ackn_m1.val();
            self.fnb.d.next = self.cnt.q.val() == self.nbits_m1.val();
            self.fsix.d.next = self.cnt.q.val() == self.five.val();
        }
        if self.sync.rise.val() & self.pld.q.val() {
            self.cnt.d.next = self.one.val();
            self.fack.d.next = self.ack_is1.val();
            self.fnb.d.next = self.n_is1.val();
            self.fsix.d.next = false;
        }
        if self.tmo.val() {
            self.slo_reg.d.next = true;
            // The control channel takes the CDM bit (the MA level held during the timeout).
            for i in 0..self.ctl.len() {
                self.ctl[i].expire.next = true;
            }
        }
        if self.rst.val() {
            self.slo_reg.d.next = false;
        }
        self.slo.next = self.slo_reg.q.val();
    }
}

/// One port of the register map's byte bus with `user_map` (and the control channel), none
/// without.
fn user<D: Default>(p: &BissParams) -> Vec<D> {
    (0..usize::from(p.user_map && p.control.is_some()))
        .map(|_| D::default())
        .collect()
}

crate::cosim::cosim_block!(BissSlave {
    inputs: [rst: 1, ma: 1, pos: 32, turns: 32, pos_valid: 1, error: 1, warning: 1],
    outputs: [slo: 1],
});
