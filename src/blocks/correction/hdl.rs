//! rust-hdl description of the front-end correction and its automatic calibration (maths,
//! timing and rules in [`crate::blocks::correction`]).
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{c32, fill, mask};
use crate::cosim::Port;
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

fn c16(v: u64) -> Constant<Bits<16>> {
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

/// Offset and gain correction with saturation; optional automatic calibration.
#[derive(LogicBlock)]
pub struct Correction {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: valid bits cleared, configured b and g restored.
    pub rst: Signal<In, Bit>,
    /// Sample strobe.
    pub in_valid: Signal<In, Bit>,
    /// Raw sine sample, A-bit two's complement in the low bits (upper bits ignored).
    pub in_sin: Signal<In, Bits<16>>,
    /// Raw cosine sample, A-bit two's complement in the low bits (upper bits ignored).
    pub in_cos: Signal<In, Bits<16>>,
    /// Strobe of the corrected sample (3 clocks after `in_valid`).
    pub out_valid: Signal<Out, Bit>,
    /// Corrected sine, A-bit two's complement in the low bits (saturated).
    pub out_sin: Signal<Out, Bits<16>>,
    /// Corrected cosine, A-bit two's complement in the low bits (saturated).
    pub out_cos: Signal<Out, Bits<16>>,
    /// Sine offset b in use, A-bit two's complement in the low bits.
    pub offset_sin: Signal<Out, Bits<16>>,
    /// Cosine offset b in use, A-bit two's complement in the low bits.
    pub offset_cos: Signal<Out, Bits<16>>,
    /// Sine gain g in use, UQ(16-GF).GF.
    pub gain_sin: Signal<Out, Bits<16>>,
    /// Cosine gain g in use, UQ(16-GF).GF.
    pub gain_cos: Signal<Out, Bits<16>>,
    /// One clock when the calibration has just applied new b and g (always 0 when static).
    pub cal_update: Signal<Out, Bit>,
    /// The automatic calibration: one instance in auto mode, none in static mode.
    cal: Vec<AutoCal>,
    v1: DFF<Bit>,
    sg1_s: DFF<Bit>,
    sg1_c: DFF<Bit>,
    m1_s: DFF<Bits<16>>,
    m1_c: DFF<Bits<16>>,
    g1_s: DFF<Bits<16>>,
    g1_c: DFF<Bits<16>>,
    u1_s: DFF<Bits<32>>,
    u1_c: DFF<Bits<32>>,
    v2: DFF<Bit>,
    sg2_s: DFF<Bit>,
    sg2_c: DFF<Bit>,
    p2_s: DFF<Bits<32>>,
    p2_c: DFF<Bits<32>>,
    v3: DFF<Bit>,
    o3_s: DFF<Bits<16>>,
    o3_c: DFF<Bits<16>>,
    b_s: Signal<Local, Bits<32>>,
    b_c: Signal<Local, Bits<32>>,
    g_s: Signal<Local, Bits<16>>,
    g_c: Signal<Local, Bits<16>>,
    upd: Signal<Local, Bit>,
    xs_s: Signal<Local, Bits<32>>,
    xs_c: Signal<Local, Bits<32>>,
    bs_s: Signal<Local, Bits<32>>,
    bs_c: Signal<Local, Bits<32>>,
    /// d = x - b (32-bit two's complement).
    d_s: Signal<Local, Bits<32>>,
    d_c: Signal<Local, Bits<32>>,
    /// -d = b - x, a second adder beside d: |d| is a select, not a negation after it.
    nd_s: Signal<Local, Bits<32>>,
    nd_c: Signal<Local, Bits<32>>,
    md_s: Signal<Local, Bits<32>>,
    md_c: Signal<Local, Bits<32>>,
    /// Stage 3: all ones (on the 33-GF bits of P') when the sample is negative (the
    /// product is inverted).
    im_s: Signal<Local, Bits<32>>,
    im_c: Signal<Local, Bits<32>>,
    /// Stage 3: the rounded, signed result before saturation, modulo 2^(32-GF).
    r_s: Signal<Local, Bits<32>>,
    r_c: Signal<Local, Bits<32>>,
    /// Stage 3: the rounded magnitude reaches 2^(A-1) (saturate).
    big_s: Signal<Local, Bit>,
    big_c: Signal<Local, Bit>,
    o_s: Signal<Local, Bits<32>>,
    o_c: Signal<Local, Bits<32>>,
    /// Mask of the A sample bits.
    amask: Constant<Bits<32>>,
    /// Sign bit of an A-bit sample (= 2^(A-1), also the magnitude of the most negative code).
    asign: Constant<Bits<32>>,
    /// Bits A..31: sign extension of a negative sample.
    asext: Constant<Bits<32>>,
    /// Largest positive A-bit value 2^(A-1)-1.
    pmax: Constant<Bits<32>>,
    /// (2^(A-1+GF) - 2^(GF-1)) >> (GF-1) = 2^A - 1: the smallest P' whose rounded magnitude
    /// is 2^(A-1).
    pbig: Constant<Bits<32>>,
    /// Bit 31: sign of a 32-bit word.
    sign32: Constant<Bits<32>>,
    /// GF-1: the product bits below the rounding half that are dropped.
    hshift: Constant<Bits<32>>,
    /// Mask of the 33-GF bits of P'.
    phmask: Constant<Bits<32>>,
    /// One: the rounding half in P' units, and the last shift.
    one1: Constant<Bits<32>>,
    /// Configured sine offset, A-bit raw (static value).
    b0_s: Constant<Bits<32>>,
    /// Configured cosine offset, A-bit raw (static value).
    b0_c: Constant<Bits<32>>,
    /// Configured sine gain (static value).
    g0_s: Constant<Bits<16>>,
    /// Configured cosine gain (static value).
    g0_c: Constant<Bits<16>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl Correction {
    /// Correction for `p` (with an [`AutoCal`] when `p.auto()` is set).
    pub fn new(p: &CorrectionParams) -> Self {
        let a = p.adc_width();
        let gf = p.gain_frac_bits();
        let cal = if p.auto().is_some() {
            vec![AutoCal::new(p)]
        } else {
            vec![]
        };
        Self {
            clk: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_sin: Default::default(),
            in_cos: Default::default(),
            out_valid: Default::default(),
            out_sin: Default::default(),
            out_cos: Default::default(),
            offset_sin: Default::default(),
            offset_cos: Default::default(),
            gain_sin: Default::default(),
            gain_cos: Default::default(),
            cal_update: Default::default(),
            cal,
            v1: Default::default(),
            sg1_s: Default::default(),
            sg1_c: Default::default(),
            m1_s: Default::default(),
            m1_c: Default::default(),
            g1_s: Default::default(),
            g1_c: Default::default(),
            u1_s: Default::default(),
            u1_c: Default::default(),
            v2: Default::default(),
            sg2_s: Default::default(),
            sg2_c: Default::default(),
            p2_s: Default::default(),
            p2_c: Default::default(),
            v3: Default::default(),
            o3_s: Default::default(),
            o3_c: Default::default(),
            b_s: Default::default(),
            b_c: Default::default(),
            g_s: Default::default(),
            g_c: Default::default(),
            upd: Default::default(),
            xs_s: Default::default(),
            xs_c: Default::default(),
            bs_s: Default::default(),
            bs_c: Default::default(),
            d_s: Default::default(),
            d_c: Default::default(),
            nd_s: Default::default(),
            nd_c: Default::default(),
            md_s: Default::default(),
            md_c: Default::default(),
            im_s: Default::default(),
            im_c: Default::default(),
            r_s: Default::default(),
            r_c: Default::default(),
            big_s: Default::default(),
            big_c: Default::default(),
            o_s: Default::default(),
            o_c: Default::default(),
            amask: c32(mask(a)),
            asign: c32(1 << (a - 1)),
            asext: c32(fill(32, 32 - a)),
            pmax: c32(mask(a - 1)),
            pbig: c32(((1u64 << (a - 1 + gf)) - (1u64 << (gf - 1))) >> (gf - 1)),
            sign32: c32(1 << 31),
            hshift: c32((gf - 1) as u64),
            phmask: c32(mask(33 - gf)),
            one1: c32(1),
            b0_s: c32(p.offset()[SIN] as u64 & mask(a)),
            b0_c: c32(p.offset()[COS] as u64 & mask(a)),
            g0_s: c16(p.gain()[SIN] as u64),
            g0_c: c16(p.gain()[COS] as u64),
            zero: c32(0),
        }
    }
}

impl Logic for Correction {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, v1, sg1_s, sg1_c, m1_s, m1_c, g1_s, g1_c, u1_s, u1_c, v2, sg2_s, sg2_c,
            p2_s, p2_c, v3, o3_s, o3_c
        );
        // Offsets and gains in use: the configured constants, or the calibration's registers.
        self.b_s.next = self.b0_s.val();
        self.b_c.next = self.b0_c.val();
        self.g_s.next = self.g0_s.val();
        self.g_c.next = self.g0_c.val();
        self.upd.next = false;
        for i in 0..self.cal.len() {
            self.cal[i].clk.next = self.clk.val();
            self.cal[i].rst.next = self.rst.val();
            self.cal[i].v.next = self.v1.q.val();
            self.cal[i].u_sin.next = self.u1_s.q.val();
            self.cal[i].u_cos.next = self.u1_c.q.val();
            self.cal[i].neg_sin.next = self.sg1_s.q.val();
            self.cal[i].neg_cos.next = self.sg1_c.q.val();
            self.b_s.next = self.cal[i].b_sin.val();
            self.b_c.next = self.cal[i].b_cos.val();
            self.g_s.next = self.cal[i].g_sin.val();
            self.g_c.next = self.cal[i].g_cos.val();
            self.upd.next = self.cal[i].update.val();
        }
        // Stage 1: sign-extend, subtract the offset, split into sign and magnitude.
        self.xs_s.next = bit_cast::<32, 16>(self.in_sin.val()) & self.amask.val();
        if (self.xs_s.val() & self.asign.val()).any() {
            self.xs_s.next = self.xs_s.val() | self.asext.val();
        }
        self.xs_c.next = bit_cast::<32, 16>(self.in_cos.val()) & self.amask.val();
        if (self.xs_c.val() & self.asign.val()).any() {
            self.xs_c.next = self.xs_c.val() | self.asext.val();
        }
        self.bs_s.next = self.b_s.val();
        if (self.b_s.val() & self.asign.val()).any() {
            self.bs_s.next = self.b_s.val() | self.asext.val();
        }
        self.bs_c.next = self.b_c.val();
        if (self.b_c.val() & self.asign.val()).any() {
            self.bs_c.next = self.b_c.val() | self.asext.val();
        }
        self.d_s.next = self.xs_s.val() - self.bs_s.val();
        self.d_c.next = self.xs_c.val() - self.bs_c.val();
        self.nd_s.next = self.bs_s.val() - self.xs_s.val();
        self.nd_c.next = self.bs_c.val() - self.xs_c.val();
        self.md_s.next = self.d_s.val();
        if (self.d_s.val() & self.sign32.val()).any() {
            self.md_s.next = self.nd_s.val();
        }
        self.md_c.next = self.d_c.val();
        if (self.d_c.val() & self.sign32.val()).any() {
            self.md_c.next = self.nd_c.val();
        }
        self.v1.d.next = self.in_valid.val() & !self.rst.val();
        self.sg1_s.d.next = (self.d_s.val() & self.sign32.val()).any();
        self.sg1_c.d.next = (self.d_c.val() & self.sign32.val()).any();
        self.m1_s.d.next = bit_cast::<16, 32>(self.md_s.val() & self.amask.val());
        self.m1_c.d.next = bit_cast::<16, 32>(self.md_c.val() & self.amask.val());
        self.g1_s.d.next = self.g_s.val();
        self.g1_c.d.next = self.g_c.val();
        self.u1_s.d.next =
            (bit_cast::<32, 16>(self.in_sin.val()) & self.amask.val()) ^ self.asign.val();
        self.u1_c.d.next =
            (bit_cast::<32, 16>(self.in_cos.val()) & self.amask.val()) ^ self.asign.val();
        // Stage 2: unsigned 16 x 16 -> 32 products.
        self.v2.d.next = self.v1.q.val() & !self.rst.val();
        self.sg2_s.d.next = self.sg1_s.q.val();
        self.sg2_c.d.next = self.sg1_c.q.val();
        // The product is registered without its low GF-1 bits: below the rounding half they
        // can carry nothing into the rounded result (adding 2^(GF-1) to P leaves them as
        // they are), and the saturation limit is a multiple of 2^(GF-1). Registering them
        // would only feed a carry chain whose carry is provably zero.
        self.p2_s.d.next = (self.m1_s.q.val() * self.g1_s.q.val()) >> self.hshift.val();
        self.p2_c.d.next = (self.m1_c.q.val() * self.g1_c.q.val()) >> self.hshift.val();
        // Stage 3: round half up (magnitude), apply the sign, saturate. One adder: with
        // the sign, -floor((P + 2^(GF-1)) / 2^GF) = floor((!P + 2^(GF-1)) / 2^GF) (!P = -P - 1),
        // taken from the 32-bit word modulo 2^(32-GF) >= 2^A. The magnitude reaches 2^(A-1)
        // (both saturation limits) exactly when P >= 2^(A-1+GF) - 2^(GF-1), a compare beside
        // the adder.
        // With P' = P >> (GF-1): floor((X + 2^(GF-1)) / 2^GF) = floor((X >> (GF-1) + 1) / 2)
        // for X = P or !P, and !P >> (GF-1) = P' ^ (the 33-GF ones).
        self.im_s.next = self.zero.val();
        if self.sg2_s.q.val() {
            self.im_s.next = self.phmask.val();
        }
        self.im_c.next = self.zero.val();
        if self.sg2_c.q.val() {
            self.im_c.next = self.phmask.val();
        }
        self.r_s.next =
            ((self.p2_s.q.val() ^ self.im_s.val()) + self.one1.val()) >> self.one1.val();
        self.r_c.next =
            ((self.p2_c.q.val() ^ self.im_c.val()) + self.one1.val()) >> self.one1.val();
        self.big_s.next = self.p2_s.q.val() >= self.pbig.val();
        self.big_c.next = self.p2_c.q.val() >= self.pbig.val();
        self.o_s.next = self.r_s.val();
        if self.big_s.val() {
            if self.sg2_s.q.val() {
                self.o_s.next = self.asign.val();
            } else {
                self.o_s.next = self.pmax.val();
            }
        }
        self.o_c.next = self.r_c.val();
        if self.big_c.val() {
            if self.sg2_c.q.val() {
                self.o_c.next = self.asign.val();
            } else {
                self.o_c.next = self.pmax.val();
            }
        }
        self.v3.d.next = self.v2.q.val() & !self.rst.val();
        self.o3_s.d.next = bit_cast::<16, 32>(self.o_s.val() & self.amask.val());
        self.o3_c.d.next = bit_cast::<16, 32>(self.o_c.val() & self.amask.val());
        self.out_valid.next = self.v3.q.val();
        self.out_sin.next = self.o3_s.q.val();
        self.out_cos.next = self.o3_c.q.val();
        self.offset_sin.next = bit_cast::<16, 32>(self.b_s.val());
        self.offset_cos.next = bit_cast::<16, 32>(self.b_c.val());
        self.gain_sin.next = self.g_s.val();
        self.gain_cos.next = self.g_c.val();
        self.cal_update.next = self.upd.val();
    }
}

impl crate::cosim::step::Clocked for Correction {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for Correction {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("in_valid", 1),
            Port::new("in_sin", 16),
            Port::new("in_cos", 16),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("out_valid", 1),
            Port::new("out_sin", 16),
            Port::new("out_cos", 16),
            Port::new("offset_sin", 16),
            Port::new("offset_cos", 16),
            Port::new("gain_sin", 16),
            Port::new("gain_cos", 16),
            Port::new("cal_update", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.in_valid.next = r[1] != 0;
        self.in_sin.next = Bits::<16>::from(r[2] & 0xffff);
        self.in_cos.next = Bits::<16>::from(r[3] & 0xffff);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.out_valid.val() as u64,
            self.out_sin.val().to_u64(),
            self.out_cos.val().to_u64(),
            self.offset_sin.val().to_u64(),
            self.offset_cos.val().to_u64(),
            self.gain_sin.val().to_u64(),
            self.gain_cos.val().to_u64(),
            self.cal_update.val() as u64,
        ]
    }
}
