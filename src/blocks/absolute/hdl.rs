//! rust-hdl description of the absolute start (maths, timing and sketch in the module docs
//! of [`crate::blocks::absolute`]). [`AbsoluteModel`](super::model::AbsoluteModel) is its
//! cycle reference; `AbsState` is its `Phase`.
//!
//! Timing: every register-to-register path holds one carry chain at most. The counters
//! count from registers; the merge is one adder per state (Sync, Place, Split, Target), each
//! from registers.
use super::AbsoluteParams;
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// Where a read is (the sketch in the module docs).
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum AbsState {
    /// The clock high for W clocks (after reset, after a failed frame).
    Wait,
    /// Waiting for the line high and a CONV assertion.
    Ready,
    /// Clock low for H clocks.
    Low,
    /// Clock high for H clocks.
    High,
    /// After the last pulse: reading the tail.
    Tail,
    /// δ = (o - c) mod 2^(k+3).
    Sync,
    /// p = c + sext(δ).
    Place,
    /// tq and tt from p.
    Split,
    /// tq - Q, tq + Q, tt - 1, tt + 1.
    Target,
    /// `req` in a clock without a sample.
    Request,
    /// The target was taken.
    Done,
}

/// The SSI master and the merge (ports in the module docs of `absolute`).
#[derive(LogicBlock)]
pub struct AbsoluteStart {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: the clock high, a new read after W clocks.
    pub rst: Signal<In, Bit>,
    /// The ADC's CONV (chip select) register: its assertion edge samples.
    pub conv: Signal<In, Bit>,
    /// The core's output strobe.
    pub in_valid: Signal<In, Bit>,
    /// The core's quadrant count, 0..Q-1.
    pub in_qc: Signal<In, Bits<32>>,
    /// The core's fine part.
    pub in_fine: Signal<In, Bits<32>>,
    /// The core's turn word (M bits).
    pub in_turns: Signal<In, Bits<32>>,
    /// The encoder's SSI data line, asynchronous (two synchronizer flops here).
    pub abs_data: Signal<In, Bit>,
    /// The SSI clock to the encoder: idle high, registered.
    pub abs_clk: Signal<Out, Bit>,
    /// One clock, never with `in_valid`: the target and B are ready for the reference.
    pub req: Signal<Out, Bit>,
    /// Target quadrant count T_q (qb bits).
    pub tq: Signal<Out, Bits<32>>,
    /// T_q - Q (qb + 1 bits two's complement).
    pub tqm: Signal<Out, Bits<32>>,
    /// T_q + Q.
    pub tqp: Signal<Out, Bits<32>>,
    /// Target turn word T_t (M bits).
    pub tt: Signal<Out, Bits<32>>,
    /// T_t - 1 (M bits).
    pub ttm: Signal<Out, Bits<32>>,
    /// T_t + 1 (M bits).
    pub ttp: Signal<Out, Bits<32>>,
    /// Quadrant count B_q of the latch's sample.
    pub bq: Signal<Out, Bits<32>>,
    /// Turn word B_t of the latch's sample.
    pub bt: Signal<Out, Bits<32>>,
    /// The last frame failed (tail not 0, or no sample of the latch's conversion).
    pub fault: Signal<Out, Bit>,
    conv_prev: DFF<Bit>,
    /// Synchronizer of `abs_data`, first flop: it samples the pad.
    s1: DFF<Bit>,
    /// Synchronizer, second flop: the line as the logic reads it.
    s2: DFF<Bit>,
    state: DFF<AbsState>,
    /// Clocks in the phase: the wait W, the half period H, the tail.
    cnt: DFF<Bits<32>>,
    /// Rising clock edges launched in this frame, 0..N+1.
    n: DFF<Bits<32>>,
    /// The SSI clock, inverted (power-up 0 = the line high).
    ckn: DFF<Bit>,
    /// The synchronizer's first flop takes a bit at this clock's edge; `smp1` a clock later.
    /// Timing of the line: the bit enters the word two clocks after its sampling edge.
    smp0: DFF<Bit>,
    smp1: DFF<Bit>,
    /// The word, binary, MSB first.
    w: DFF<Bits<32>>,
    /// The last binary bit (Gray decoding).
    gx: DFF<Bit>,
    /// The latch's conversion, newest in bit 0 (K + 1 bits).
    lt: DFF<Bits<32>>,
    /// The sample of the latch's conversion came: `bq`, `bt` and its sync bits `bo`.
    bvalid: DFF<Bit>,
    bqr: DFF<Bits<32>>,
    btr: DFF<Bits<32>>,
    bo: DFF<Bits<32>>,
    /// δ (k + 3 bits).
    dl: DFF<Bits<32>>,
    /// p = c + sext(δ) (S + 3 bits).
    p: DFF<Bits<32>>,
    tqr: DFF<Bits<32>>,
    tqmr: DFF<Bits<32>>,
    tqpr: DFF<Bits<32>>,
    ttr: DFF<Bits<32>>,
    ttmr: DFF<Bits<32>>,
    ttpr: DFF<Bits<32>>,
    faultr: DFF<Bit>,
    assert_edge: Signal<Local, Bit>,
    start: Signal<Local, Bit>,
    b: Signal<Local, Bit>,
    c: Signal<Local, Bits<32>>,
    dext: Signal<Local, Bits<32>>,
    wt: Signal<Local, Bits<32>>,
    /// The CONV level that samples.
    act: Constant<Bit>,
    /// Gray-coded word.
    gray: Constant<Bit>,
    /// 2^K: the tag of the sample leaving the core.
    kbit: Constant<Bits<32>>,
    /// Mask of `lt` (K + 1 bits).
    lmask: Constant<Bits<32>>,
    /// Masks of the quadrant count (qb), the turn word (M) and the fine part (F).
    qmask: Constant<Bits<32>>,
    tmask: Constant<Bits<32>>,
    fmask: Constant<Bits<32>>,
    three: Constant<Bits<32>>,
    one: Constant<Bits<32>>,
    /// s: the decoded quadrant's shift to the encoder's.
    qshift: Constant<Bits<32>>,
    /// k + 1: the quadrant's place in o.
    oshl: Constant<Bits<32>>,
    /// F - k - 1: the fine part's shift into o.
    fshr: Constant<Bits<32>>,
    /// Mask of `cnt`.
    cmask: Constant<Bits<32>>,
    /// Mask of `n`.
    nmask: Constant<Bits<32>>,
    /// W - 1, H - 1 and N + 1.
    wlast: Constant<Bits<32>>,
    hlast: Constant<Bits<32>>,
    nlast: Constant<Bits<32>>,
    /// Mask of the single-turn code (S bits) and S, the turns' shift.
    smask: Constant<Bits<32>>,
    sshift: Constant<Bits<32>>,
    /// Mask of the word's turns (M_a bits).
    mamask: Constant<Bits<32>>,
    /// Mask of δ (k + 3 bits), its sign bit and the fill above it.
    dmask: Constant<Bits<32>>,
    dsign: Constant<Bits<32>>,
    dfill: Constant<Bits<32>>,
    /// Mask of p (S + 3 bits), its sign bit (S + 2) and its carry bit (S + 1).
    pmask: Constant<Bits<32>>,
    psign: Constant<Bits<32>>,
    pcarry: Constant<Bits<32>>,
    /// Q and the mask of tq - Q (qb + 1 bits).
    quads: Constant<Bits<32>>,
    wmask: Constant<Bits<32>>,
}

impl AbsoluteStart {
    /// The block for `p`.
    pub fn new(p: &AbsoluteParams) -> Self {
        let t = p.timing();
        let (s, k, qb, f) = (
            p.word().single_turn_bits,
            p.sub_quadrant_bits(),
            p.quadrant_bits(),
            p.fine_bits(),
        );
        Self {
            clk: Default::default(),
            rst: Default::default(),
            conv: Default::default(),
            in_valid: Default::default(),
            in_qc: Default::default(),
            in_fine: Default::default(),
            in_turns: Default::default(),
            abs_data: Default::default(),
            abs_clk: Default::default(),
            req: Default::default(),
            tq: Default::default(),
            tqm: Default::default(),
            tqp: Default::default(),
            tt: Default::default(),
            ttm: Default::default(),
            ttp: Default::default(),
            bq: Default::default(),
            bt: Default::default(),
            fault: Default::default(),
            conv_prev: Default::default(),
            s1: Default::default(),
            s2: Default::default(),
            state: Default::default(),
            cnt: Default::default(),
            n: Default::default(),
            ckn: Default::default(),
            smp0: Default::default(),
            smp1: Default::default(),
            w: Default::default(),
            gx: Default::default(),
            lt: Default::default(),
            bvalid: Default::default(),
            bqr: Default::default(),
            btr: Default::default(),
            bo: Default::default(),
            dl: Default::default(),
            p: Default::default(),
            tqr: Default::default(),
            tqmr: Default::default(),
            tqpr: Default::default(),
            ttr: Default::default(),
            ttmr: Default::default(),
            ttpr: Default::default(),
            faultr: Default::default(),
            assert_edge: Default::default(),
            start: Default::default(),
            b: Default::default(),
            c: Default::default(),
            dext: Default::default(),
            wt: Default::default(),
            act: Constant::new(p.conv_active_high()),
            gray: Constant::new(p.word().gray),
            kbit: c32(1 << p.tag_shift()),
            lmask: c32(mask(p.tag_shift() + 1)),
            qmask: c32(mask(qb)),
            tmask: c32(mask(p.turns_bits())),
            fmask: c32(mask(f)),
            three: c32(3),
            one: c32(1),
            qshift: c32(p.quadrant_shift() as u64),
            oshl: c32((k + 1) as u64),
            fshr: c32((f - k - 1) as u64),
            cmask: c32(mask(p.count_bits())),
            nmask: c32(mask(p.pulse_bits())),
            wlast: c32((t.wait_clocks - 1) as u64),
            hlast: c32((t.half_clocks - 1) as u64),
            nlast: c32((p.word().bits() + 1) as u64),
            smask: c32(mask(s)),
            sshift: c32(s as u64),
            mamask: c32(mask(p.word().multiturn_bits)),
            dmask: c32(mask(k + 3)),
            dsign: c32(1 << (k + 2)),
            dfill: c32(mask(32) & !mask(k + 3)),
            pmask: c32(mask(s + 3)),
            psign: c32(1 << (s + 2)),
            pcarry: c32(1 << (s + 1)),
            quads: c32(p.quadrants_per_turn()),
            wmask: c32(mask(qb + 1)),
        }
    }
}

// The block's logic in named stages, run in this order (`logic_stages!`).
crate::blocks::logic_stages!(AbsoluteStart: Line, Frame, Reset);

/// The line: synchronizer, the CONV edge, the latch's tag and its sample.
impl stages::Line for AbsoluteStart {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, conv_prev, s1, s2, state, cnt, n, ckn, smp0, smp1, w, gx, lt, bvalid, bqr,
            btr, bo, dl, p, tqr, tqmr, tqpr, ttr, ttmr, ttpr, faultr
        );
        // Synchronizer and edge register (no reset).
        self.conv_prev.d.next = self.conv.val();
        self.s1.d.next = self.abs_data.val();
        self.s2.d.next = self.s1.q.val();
        self.assert_edge.next =
            (self.conv.val() == self.act.val()) & (self.conv_prev.q.val() != self.act.val());
        // A frame starts at a CONV assertion with the line idle (high).
        self.start.next =
            (self.state.q.val() == AbsState::Ready) & self.assert_edge.val() & self.s2.q.val();
        // The latch's tag: shifted at each conversion; bit K is the sample leaving the core.
        if self.assert_edge.val() & self.start.val() {
            self.lt.d.next =
                ((self.lt.q.val() << self.one.val()) | self.one.val()) & self.lmask.val();
        } else if self.assert_edge.val() {
            self.lt.d.next = (self.lt.q.val() << self.one.val()) & self.lmask.val();
        }
        // The sample of the latch's conversion: B and its synchronization bits o.
        if self.in_valid.val() & (self.lt.q.val() & self.kbit.val()).any() {
            self.bqr.d.next = self.in_qc.val() & self.qmask.val();
            self.btr.d.next = self.in_turns.val() & self.tmask.val();
            self.bo.d.next = (((self.in_qc.val() + self.qshift.val()) & self.three.val())
                << self.oshl.val())
                | ((self.in_fine.val() & self.fmask.val()) >> self.fshr.val());
            self.bvalid.d.next = true;
        }
        self.smp0.d.next = false;
        self.smp1.d.next = self.smp0.q.val();
        // The bit as the line gives it, Gray decoded: the previous binary bit XOR it.
        self.b.next = self.s2.q.val() ^ (self.gx.q.val() & self.gray.val());
        // c = 2 st + 1, the centre of the word's single-turn code in half codes.
        self.c.next = ((self.w.q.val() & self.smask.val()) << self.one.val()) | self.one.val();
        self.dext.next = self.dl.q.val();
        if (self.dl.q.val() & self.dsign.val()).any() {
            self.dext.next = self.dl.q.val() | self.dfill.val();
        }
        self.wt.next = (self.w.q.val() >> self.sshift.val()) & self.mamask.val();
    }
}

/// The frame and the merge: one state per phase.
impl stages::Frame for AbsoluteStart {
    #[hdl_gen]
    fn update(&mut self) {
        match self.state.q.val() {
            AbsState::Wait => {
                self.cnt.d.next = (self.cnt.q.val() + self.one.val()) & self.cmask.val();
                if self.cnt.q.val() == self.wlast.val() {
                    self.state.d.next = AbsState::Ready;
                    self.cnt.d.next = 0.into();
                }
            }
            AbsState::Ready => {
                if self.start.val() {
                    self.ckn.d.next = true;
                    self.state.d.next = AbsState::Low;
                    self.cnt.d.next = 0.into();
                    self.n.d.next = 0.into();
                    self.w.d.next = 0.into();
                    self.gx.d.next = false;
                    self.bvalid.d.next = false;
                }
            }
            AbsState::Low => {
                self.cnt.d.next = (self.cnt.q.val() + self.one.val()) & self.cmask.val();
                if self.cnt.q.val() == self.hlast.val() {
                    self.ckn.d.next = false;
                    self.n.d.next = (self.n.q.val() + self.one.val()) & self.nmask.val();
                    self.state.d.next = AbsState::High;
                    self.cnt.d.next = 0.into();
                    // The launch of rising edge n + 1 samples bit n.
                    self.smp0.d.next = self.n.q.val().any();
                }
            }
            AbsState::High => {
                self.cnt.d.next = (self.cnt.q.val() + self.one.val()) & self.cmask.val();
                if self.smp1.q.val() & self.b.val() {
                    self.w.d.next = (self.w.q.val() << self.one.val()) | self.one.val();
                } else if self.smp1.q.val() {
                    self.w.d.next = self.w.q.val() << self.one.val();
                }
                if self.smp1.q.val() {
                    self.gx.d.next = self.b.val();
                }
                if self.cnt.q.val() == self.hlast.val() {
                    self.cnt.d.next = 0.into();
                    if self.n.q.val() == self.nlast.val() {
                        self.state.d.next = AbsState::Tail;
                    } else {
                        self.ckn.d.next = true;
                        self.state.d.next = AbsState::Low;
                    }
                }
            }
            AbsState::Tail => {
                self.cnt.d.next = (self.cnt.q.val() + self.one.val()) & self.cmask.val();
                if self.cnt.q.val() == self.hlast.val() {
                    self.smp0.d.next = true;
                }
                if self.smp1.q.val() {
                    if !self.s2.q.val() & self.bvalid.q.val() {
                        self.state.d.next = AbsState::Sync;
                    } else {
                        self.state.d.next = AbsState::Wait;
                        self.cnt.d.next = 0.into();
                        self.faultr.d.next = true;
                    }
                }
            }
            AbsState::Sync => {
                self.dl.d.next = (self.bo.q.val() - self.c.val()) & self.dmask.val();
                self.state.d.next = AbsState::Place;
            }
            AbsState::Place => {
                self.p.d.next = (self.c.val() + self.dext.val()) & self.pmask.val();
                self.state.d.next = AbsState::Split;
            }
            AbsState::Split => {
                self.tqr.d.next = (self.p.q.val() >> self.oshl.val()) & self.qmask.val();
                if (self.p.q.val() & self.psign.val()).any() {
                    self.ttr.d.next = (self.wt.val() - self.one.val()) & self.tmask.val();
                } else if (self.p.q.val() & self.pcarry.val()).any() {
                    self.ttr.d.next = (self.wt.val() + self.one.val()) & self.tmask.val();
                } else {
                    self.ttr.d.next = self.wt.val() & self.tmask.val();
                }
                self.state.d.next = AbsState::Target;
            }
            AbsState::Target => {
                self.tqmr.d.next = (self.tqr.q.val() - self.quads.val()) & self.wmask.val();
                self.tqpr.d.next = self.tqr.q.val() + self.quads.val();
                self.ttmr.d.next = (self.ttr.q.val() - self.one.val()) & self.tmask.val();
                self.ttpr.d.next = (self.ttr.q.val() + self.one.val()) & self.tmask.val();
                self.faultr.d.next = false;
                self.state.d.next = AbsState::Request;
            }
            AbsState::Request => {
                if !self.in_valid.val() {
                    self.state.d.next = AbsState::Done;
                }
            }
            AbsState::Done => {}
        }
    }
}

/// Reset and the outputs.
impl stages::Reset for AbsoluteStart {
    #[hdl_gen]
    fn update(&mut self) {
        if self.rst.val() {
            self.state.d.next = AbsState::Wait;
            self.cnt.d.next = 0.into();
            self.n.d.next = 0.into();
            self.ckn.d.next = false;
            self.smp0.d.next = false;
            self.smp1.d.next = false;
            self.w.d.next = 0.into();
            self.gx.d.next = false;
            self.lt.d.next = 0.into();
            self.bvalid.d.next = false;
            self.bqr.d.next = 0.into();
            self.btr.d.next = 0.into();
            self.bo.d.next = 0.into();
            self.dl.d.next = 0.into();
            self.p.d.next = 0.into();
            self.tqr.d.next = 0.into();
            self.tqmr.d.next = 0.into();
            self.tqpr.d.next = 0.into();
            self.ttr.d.next = 0.into();
            self.ttmr.d.next = 0.into();
            self.ttpr.d.next = 0.into();
            self.faultr.d.next = false;
        }
        self.abs_clk.next = !self.ckn.q.val();
        self.req.next = (self.state.q.val() == AbsState::Request) & !self.in_valid.val();
        self.tq.next = self.tqr.q.val();
        self.tqm.next = self.tqmr.q.val();
        self.tqp.next = self.tqpr.q.val();
        self.tt.next = self.ttr.q.val();
        self.ttm.next = self.ttmr.q.val();
        self.ttp.next = self.ttpr.q.val();
        self.bq.next = self.bqr.q.val();
        self.bt.next = self.btr.q.val();
        self.fault.next = self.faultr.q.val();
    }
}

impl crate::cosim::CosimBlock for AbsoluteStart {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("conv", 1),
            Port::new("in_valid", 1),
            Port::new("in_qc", 32),
            Port::new("in_fine", 32),
            Port::new("in_turns", 32),
            Port::new("abs_data", 1),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("abs_clk", 1),
            Port::new("req", 1),
            Port::new("tq", 32),
            Port::new("tqm", 32),
            Port::new("tqp", 32),
            Port::new("tt", 32),
            Port::new("ttm", 32),
            Port::new("ttp", 32),
            Port::new("bq", 32),
            Port::new("bt", 32),
            Port::new("fault", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.conv.next = r[1] != 0;
        self.in_valid.next = r[2] != 0;
        self.in_qc.next = Bits::<32>::from(r[3]);
        self.in_fine.next = Bits::<32>::from(r[4]);
        self.in_turns.next = Bits::<32>::from(r[5]);
        self.abs_data.next = r[6] != 0;
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.abs_clk.val() as u64,
            self.req.val() as u64,
            self.tq.val().to_u64(),
            self.tqm.val().to_u64(),
            self.tqp.val().to_u64(),
            self.tt.val().to_u64(),
            self.ttm.val().to_u64(),
            self.ttp.val().to_u64(),
            self.bq.val().to_u64(),
            self.bt.val().to_u64(),
            self.fault.val() as u64,
        ]
    }
}

impl crate::cosim::step::Clocked for AbsoluteStart {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}
