//! rust-hdl description of the automatic calibration of the front-end correction: per-track
//! window extremes into offset and gain by a serial divider (maths, timing and rules in
//! [`crate::blocks::correction`]).
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// State of the calibration's serial divider.
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum CalState {
    /// Waiting for a window snapshot.
    Idle,
    /// Dividing for the sine gain (32 clocks).
    DivSin,
    /// Dividing for the cosine gain (32 clocks), then applying b and g.
    DivCos,
}

pub(super) fn c16(v: u64) -> Constant<Bits<16>> {
    Constant::new(Bits::<16>::from(v & 0xffff))
}

fn c2(v: u64) -> Constant<Bits<2>> {
    Constant::new(Bits::<2>::from(v & 3))
}

/// Automatic calibration: period tracker, peak registers, serial divider and the offset and
/// gain registers.
#[derive(LogicBlock)]
pub struct AutoCal {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: configured b, g; tracker and divider idle.
    pub rst: Signal<In, Bit>,
    /// A sample is in the correction's stage 1.
    pub v: Signal<In, Bit>,
    /// Sine sample in offset binary (x + 2^(A-1), A bits).
    pub u_sin: Signal<In, Bits<32>>,
    /// Cosine sample in offset binary.
    pub u_cos: Signal<In, Bits<32>>,
    /// Sign of (sin - b_sin) of the same sample.
    pub neg_sin: Signal<In, Bit>,
    /// Sign of (cos - b_cos) of the same sample.
    pub neg_cos: Signal<In, Bit>,
    /// Sine offset b, A-bit two's complement in the low bits.
    pub b_sin: Signal<Out, Bits<32>>,
    /// Cosine offset b, A-bit two's complement in the low bits.
    pub b_cos: Signal<Out, Bits<32>>,
    /// Sine gain g, UQ(16-GF).GF.
    pub g_sin: Signal<Out, Bits<16>>,
    /// Cosine gain g, UQ(16-GF).GF.
    pub g_cos: Signal<Out, Bits<16>>,
    /// One clock when new b and g take effect.
    pub update: Signal<Out, Bit>,
    tinit: DFF<Bit>,
    wopen: DFF<Bit>,
    tq: DFF<Bits<2>>,
    net: DFF<Bits<32>>,
    nper: DFF<Bits<32>>,
    mx_s: DFF<Bits<32>>,
    mn_s: DFF<Bits<32>>,
    mx_c: DFF<Bits<32>>,
    mn_c: DFF<Bits<32>>,
    go: DFF<Bit>,
    sx_s: DFF<Bits<32>>,
    sn_s: DFF<Bits<32>>,
    sx_c: DFF<Bits<32>>,
    sn_c: DFF<Bits<32>>,
    state: DFF<CalState>,
    it: DFF<Bits<32>>,
    rem: DFF<Bits<32>>,
    dq: DFF<Bits<32>>,
    dv: DFF<Bits<32>>,
    ng_s: DFF<Bits<16>>,
    b_s: DFFWithInit<Bits<32>>,
    b_c: DFFWithInit<Bits<32>>,
    g_s: DFFWithInit<Bits<16>>,
    g_c: DFFWithInit<Bits<16>>,
    upd: DFF<Bit>,
    q: Signal<Local, Bits<2>>,
    stp: Signal<Local, Bits<2>>,
    netn: Signal<Local, Bits<32>>,
    mxn_s: Signal<Local, Bits<32>>,
    mnn_s: Signal<Local, Bits<32>>,
    mxn_c: Signal<Local, Bits<32>>,
    mnn_c: Signal<Local, Bits<32>>,
    span_s: Signal<Local, Bits<32>>,
    span_c: Signal<Local, Bits<32>>,
    t: Signal<Local, Bits<32>>,
    remn: Signal<Local, Bits<32>>,
    dqn: Signal<Local, Bits<32>>,
    gsat: Signal<Local, Bits<32>>,
    /// Quadrant codes 0..3.
    q0: Constant<Bits<2>>,
    q1: Constant<Bits<2>>,
    q2: Constant<Bits<2>>,
    q3: Constant<Bits<2>>,
    /// Mask of the 4-bit net quadrant count.
    nmask: Constant<Bits<32>>,
    /// +4 in 4 bits.
    plus4: Constant<Bits<32>>,
    /// -4 in 4 bits.
    minus4: Constant<Bits<32>>,
    /// -1 in 4 bits.
    minus1: Constant<Bits<32>>,
    /// K-1: last period of a window.
    klast: Constant<Bits<32>>,
    /// Mask of the period counter bits.
    kmask: Constant<Bits<32>>,
    /// T 2^(GF+1): the divider's dividend before rounding.
    num: Constant<Bits<32>>,
    /// 2 min_amplitude: smallest span that allows an update.
    minspan: Constant<Bits<32>>,
    /// 31: last divider iteration.
    itlast: Constant<Bits<32>>,
    /// Mask of the 5-bit iteration counter.
    itmask: Constant<Bits<32>>,
    /// Shift of the dividend's MSB to bit 0.
    s31: Constant<Bits<32>>,
    /// Largest gain code.
    gmax: Constant<Bits<32>>,
    /// 2^(A-1): offset-binary zero.
    asign: Constant<Bits<32>>,
    /// Mask of the A sample bits.
    amask: Constant<Bits<32>>,
    /// Configured sine offset (reset value), A-bit raw.
    b0_s: Constant<Bits<32>>,
    /// Configured cosine offset (reset value), A-bit raw.
    b0_c: Constant<Bits<32>>,
    /// Configured sine gain (reset value).
    g0_s: Constant<Bits<16>>,
    /// Configured cosine gain (reset value).
    g0_c: Constant<Bits<16>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl AutoCal {
    /// Calibration for `p` (which must have auto mode on).
    pub fn new(p: &CorrectionParams) -> Self {
        let a = p.adc_width();
        let ac = p.auto().expect("AutoCal needs auto calibration parameters");
        let kbits = crate::blocks::monitor::count_bits(ac.periods());
        let b0 = |c: usize| c32(p.offset()[c] as u64 & mask(a));
        let g0 = |c: usize| c16(p.gain()[c] as u64);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            v: Default::default(),
            u_sin: Default::default(),
            u_cos: Default::default(),
            neg_sin: Default::default(),
            neg_cos: Default::default(),
            b_sin: Default::default(),
            b_cos: Default::default(),
            g_sin: Default::default(),
            g_cos: Default::default(),
            update: Default::default(),
            tinit: Default::default(),
            wopen: Default::default(),
            tq: Default::default(),
            net: Default::default(),
            nper: Default::default(),
            mx_s: Default::default(),
            mn_s: Default::default(),
            mx_c: Default::default(),
            mn_c: Default::default(),
            go: Default::default(),
            sx_s: Default::default(),
            sn_s: Default::default(),
            sx_c: Default::default(),
            sn_c: Default::default(),
            state: Default::default(),
            it: Default::default(),
            rem: Default::default(),
            dq: Default::default(),
            dv: Default::default(),
            ng_s: Default::default(),
            b_s: DFFWithInit::new(Bits::<32>::from(p.offset()[SIN] as u64 & mask(a))),
            b_c: DFFWithInit::new(Bits::<32>::from(p.offset()[COS] as u64 & mask(a))),
            g_s: DFFWithInit::new(Bits::<16>::from(p.gain()[SIN] as u64)),
            g_c: DFFWithInit::new(Bits::<16>::from(p.gain()[COS] as u64)),
            upd: Default::default(),
            q: Default::default(),
            stp: Default::default(),
            netn: Default::default(),
            mxn_s: Default::default(),
            mnn_s: Default::default(),
            mxn_c: Default::default(),
            mnn_c: Default::default(),
            span_s: Default::default(),
            span_c: Default::default(),
            t: Default::default(),
            remn: Default::default(),
            dqn: Default::default(),
            gsat: Default::default(),
            q0: c2(0),
            q1: c2(1),
            q2: c2(2),
            q3: c2(3),
            nmask: c32(15),
            plus4: c32(4),
            minus4: c32(12),
            minus1: c32(15),
            klast: c32(ac.periods() as u64 - 1),
            kmask: c32(mask(kbits)),
            num: c32((ac.target_amplitude() as u64) << (p.gain_frac_bits() + 1)),
            minspan: c32(2 * ac.min_amplitude() as u64),
            itlast: c32(31),
            itmask: c32(31),
            s31: c32(31),
            gmax: c32(0xffff),
            asign: c32(1 << (a - 1)),
            amask: c32(mask(a)),
            b0_s: b0(SIN),
            b0_c: b0(COS),
            g0_s: g0(SIN),
            g0_c: g0(COS),
            one: c32(1),
            zero: c32(0),
        }
    }
}

impl Logic for AutoCal {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, tinit, wopen, tq, net, nper, mx_s, mn_s, mx_c, mn_c, go, sx_s, sn_s, sx_c,
            sn_c, state, it, rem, dq, dv, ng_s, b_s, b_c, g_s, g_c, upd
        );
        // Holds are masked to the words' widths, so Yosys sees constant-zero upper bits.
        self.net.d.next = self.net.q.val() & self.nmask.val();
        self.nper.d.next = self.nper.q.val() & self.kmask.val();
        self.mx_s.d.next = self.mx_s.q.val() & self.amask.val();
        self.mn_s.d.next = self.mn_s.q.val() & self.amask.val();
        self.mx_c.d.next = self.mx_c.q.val() & self.amask.val();
        self.mn_c.d.next = self.mn_c.q.val() & self.amask.val();
        self.sx_s.d.next = self.sx_s.q.val() & self.amask.val();
        self.sn_s.d.next = self.sn_s.q.val() & self.amask.val();
        self.sx_c.d.next = self.sx_c.q.val() & self.amask.val();
        self.sn_c.d.next = self.sn_c.q.val() & self.amask.val();
        self.it.d.next = self.it.q.val() & self.itmask.val();
        self.rem.d.next = self.rem.q.val() & self.amask.val();
        self.dv.d.next = self.dv.q.val() & self.amask.val();
        self.b_s.d.next = self.b_s.q.val() & self.amask.val();
        self.b_c.d.next = self.b_c.q.val() & self.amask.val();
        // Quadrant of the sample (CORDIC mapper convention) and the step since the last one.
        self.q.next = self.q0.val();
        if self.neg_sin.val() {
            if self.neg_cos.val() {
                self.q.next = self.q2.val();
            } else {
                self.q.next = self.q3.val();
            }
        } else if self.neg_cos.val() {
            self.q.next = self.q1.val();
        }
        self.stp.next = self.q.val() - self.tq.q.val();
        self.netn.next = self.net.q.val() & self.nmask.val();
        if self.stp.val() == self.q1.val() {
            self.netn.next = (self.net.q.val() + self.one.val()) & self.nmask.val();
        }
        if self.stp.val() == self.q3.val() {
            self.netn.next = (self.net.q.val() + self.minus1.val()) & self.nmask.val();
        }
        // Running peaks including this sample.
        self.mxn_s.next = self.mx_s.q.val();
        if self.u_sin.val() > self.mx_s.q.val() {
            self.mxn_s.next = self.u_sin.val();
        }
        self.mnn_s.next = self.mn_s.q.val();
        if self.u_sin.val() < self.mn_s.q.val() {
            self.mnn_s.next = self.u_sin.val();
        }
        self.mxn_c.next = self.mx_c.q.val();
        if self.u_cos.val() > self.mx_c.q.val() {
            self.mxn_c.next = self.u_cos.val();
        }
        self.mnn_c.next = self.mn_c.q.val();
        if self.u_cos.val() < self.mn_c.q.val() {
            self.mnn_c.next = self.u_cos.val();
        }
        // Divider: spans of the snapshot and one restoring step.
        self.span_s.next = self.sx_s.q.val() - self.sn_s.q.val();
        self.span_c.next = self.sx_c.q.val() - self.sn_c.q.val();
        self.t.next = (self.rem.q.val() << self.one.val()) | (self.dq.q.val() >> self.s31.val());
        if self.t.val() >= self.dv.q.val() {
            self.remn.next = self.t.val() - self.dv.q.val();
            self.dqn.next = (self.dq.q.val() << self.one.val()) | self.one.val();
        } else {
            self.remn.next = self.t.val();
            self.dqn.next = self.dq.q.val() << self.one.val();
        }
        self.gsat.next = self.dqn.val();
        if self.dqn.val() > self.gmax.val() {
            self.gsat.next = self.gmax.val();
        }
        self.upd.d.next = false;
        match self.state.q.val() {
            CalState::Idle => {
                if self.go.q.val() {
                    self.go.d.next = false;
                    if (self.span_s.val() >= self.minspan.val())
                        & (self.span_c.val() >= self.minspan.val())
                    {
                        self.dv.d.next = self.span_s.val() & self.amask.val();
                        self.rem.d.next = self.zero.val();
                        self.dq.d.next = self.num.val() + (self.span_s.val() >> self.one.val());
                        self.it.d.next = self.zero.val();
                        self.state.d.next = CalState::DivSin;
                    }
                }
            }
            CalState::DivSin => {
                self.rem.d.next = self.remn.val() & self.amask.val();
                self.dq.d.next = self.dqn.val();
                self.it.d.next = (self.it.q.val() + self.one.val()) & self.itmask.val();
                if self.it.q.val() == self.itlast.val() {
                    self.ng_s.d.next = bit_cast::<16, 32>(self.gsat.val());
                    self.dv.d.next = self.span_c.val() & self.amask.val();
                    self.rem.d.next = self.zero.val();
                    self.dq.d.next = self.num.val() + (self.span_c.val() >> self.one.val());
                    self.state.d.next = CalState::DivCos;
                }
            }
            CalState::DivCos => {
                self.rem.d.next = self.remn.val() & self.amask.val();
                self.dq.d.next = self.dqn.val();
                self.it.d.next = (self.it.q.val() + self.one.val()) & self.itmask.val();
                if self.it.q.val() == self.itlast.val() {
                    self.g_c.d.next = bit_cast::<16, 32>(self.gsat.val());
                    self.g_s.d.next = self.ng_s.q.val();
                    self.b_s.d.next = (((self.sx_s.q.val() + self.sn_s.q.val() + self.one.val())
                        >> self.one.val())
                        - self.asign.val())
                        & self.amask.val();
                    self.b_c.d.next = (((self.sx_c.q.val() + self.sn_c.q.val() + self.one.val())
                        >> self.one.val())
                        - self.asign.val())
                        & self.amask.val();
                    self.upd.d.next = true;
                    self.state.d.next = CalState::Idle;
                }
            }
        }
        // Period tracker.
        if self.v.val() {
            self.tq.d.next = self.q.val();
            if !self.tinit.q.val() | (self.stp.val() == self.q2.val()) {
                // (Re)start: wait for the next quadrant boundary.
                self.tinit.d.next = true;
                self.wopen.d.next = false;
            } else if !self.wopen.q.val() {
                // The window opens at the first quadrant boundary.
                if (self.stp.val() == self.q1.val()) | (self.stp.val() == self.q3.val()) {
                    self.wopen.d.next = true;
                    self.net.d.next = self.zero.val();
                    self.nper.d.next = self.zero.val();
                    self.mx_s.d.next = self.u_sin.val() & self.amask.val();
                    self.mn_s.d.next = self.u_sin.val() & self.amask.val();
                    self.mx_c.d.next = self.u_cos.val() & self.amask.val();
                    self.mn_c.d.next = self.u_cos.val() & self.amask.val();
                }
            } else if (self.netn.val() == self.plus4.val()) | (self.netn.val() == self.minus4.val())
            {
                self.net.d.next = self.zero.val();
                if self.nper.q.val() == self.klast.val() {
                    self.nper.d.next = self.zero.val();
                    self.mx_s.d.next = self.u_sin.val() & self.amask.val();
                    self.mn_s.d.next = self.u_sin.val() & self.amask.val();
                    self.mx_c.d.next = self.u_cos.val() & self.amask.val();
                    self.mn_c.d.next = self.u_cos.val() & self.amask.val();
                    if (self.state.q.val() == CalState::Idle) & !self.go.q.val() {
                        self.go.d.next = true;
                        self.sx_s.d.next = self.mxn_s.val() & self.amask.val();
                        self.sn_s.d.next = self.mnn_s.val() & self.amask.val();
                        self.sx_c.d.next = self.mxn_c.val() & self.amask.val();
                        self.sn_c.d.next = self.mnn_c.val() & self.amask.val();
                    }
                } else {
                    self.nper.d.next = (self.nper.q.val() + self.one.val()) & self.kmask.val();
                    self.mx_s.d.next = self.mxn_s.val() & self.amask.val();
                    self.mn_s.d.next = self.mnn_s.val() & self.amask.val();
                    self.mx_c.d.next = self.mxn_c.val() & self.amask.val();
                    self.mn_c.d.next = self.mnn_c.val() & self.amask.val();
                }
            } else {
                self.net.d.next = self.netn.val();
                self.mx_s.d.next = self.mxn_s.val() & self.amask.val();
                self.mn_s.d.next = self.mnn_s.val() & self.amask.val();
                self.mx_c.d.next = self.mxn_c.val() & self.amask.val();
                self.mn_c.d.next = self.mnn_c.val() & self.amask.val();
            }
        }
        if self.rst.val() {
            self.tinit.d.next = false;
            self.wopen.d.next = false;
            self.net.d.next = self.zero.val();
            self.nper.d.next = self.zero.val();
            self.go.d.next = false;
            self.state.d.next = CalState::Idle;
            self.it.d.next = self.zero.val();
            self.b_s.d.next = self.b0_s.val();
            self.b_c.d.next = self.b0_c.val();
            self.g_s.d.next = self.g0_s.val();
            self.g_c.d.next = self.g0_c.val();
            self.upd.d.next = false;
        }
        self.b_sin.next = self.b_s.q.val();
        self.b_cos.next = self.b_c.q.val();
        self.g_sin.next = self.g_s.q.val();
        self.g_cos.next = self.g_c.q.val();
        self.update.next = self.upd.q.val();
    }
}
