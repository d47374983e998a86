//! rust-hdl description of the front-end correction and its automatic calibration (maths,
//! timing and rules in [`crate::blocks::correction`]).
use super::autocal::{c16, AutoCal};
use super::codes::CodeRegs;
use super::fit_hdl::{FitCal, FitConsts};
use super::multree::MulTree;
use super::phase::PhaseCos;
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{c32, fill, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

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
    /// Strobe of the corrected sample (`latency_cycles()` clocks after `in_valid`: 3
    /// without, 5 with phase correction, 3 more with shift-add products, which auto and
    /// peak modes always have).
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
    /// Writable codes only (one element, else none): one clock, bit w loads word w of
    /// [`super::codes::WORDS`] from the register map.
    pub ld: Vec<Signal<In, Bits<8>>>,
    /// Writable codes only: the written bits, masked by `ld_msk`.
    pub ld_bits: Vec<Signal<In, Bits<32>>>,
    /// Writable codes only: the bits written (the byte strobes as a mask).
    pub ld_msk: Vec<Signal<In, Bits<32>>>,
    /// Writable codes only: OFFSET_SIN in use (sign-extended LSB).
    pub w_off_s: Vec<Signal<Out, Bits<32>>>,
    /// Writable codes only: OFFSET_COS in use.
    pub w_off_c: Vec<Signal<Out, Bits<32>>>,
    /// Writable codes only: GAIN_SIN in use.
    pub w_gain_s: Vec<Signal<Out, Bits<32>>>,
    /// Writable codes only: GAIN_COS in use.
    pub w_gain_c: Vec<Signal<Out, Bits<32>>>,
    /// Writable codes only: PHASE in use (|k| in bits 15..0, k < 0 in bit 16).
    pub w_phase: Vec<Signal<Out, Bits<32>>>,
    /// The writable codes: one instance with `p.writable()`, none otherwise.
    codes: Vec<CodeRegs>,
    /// With writable codes: a copy of `m1_s` for the phase stage (the path from |d_s| to the
    /// first levels of the sine's and the phase stage's run-time trees, which share it).
    m1p_s: Vec<DFF<Bits<16>>>,
    /// The automatic calibration: one instance in auto mode, none in static mode.
    cal: Vec<AutoCal>,
    /// The ellipse-fit calibration: one instance in auto (fit) mode, none otherwise.
    fit: Vec<FitCal>,
    /// The phase correction of the cos track: one instance when k != 0, none otherwise.
    ph: Vec<PhaseCos>,
    /// The sine product as a shift-add tree: one instance when `p.shift_add()`, else none
    /// (the constant gain code in static mode, the gain register g1 in auto and peak modes).
    trs: Vec<MulTree>,
    /// The cosine product as a shift-add tree: one instance when `p.shift_add()`.
    trc: Vec<MulTree>,
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
    /// Bit A: the sign of d = x - b. Both are A-bit two's complement words, so d fits A + 1
    /// bits and bit A equals bit 31: the sign test is a chain of A + 1 bits, not 32.
    dsign: Constant<Bits<32>>,
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
        let fit = FitConsts::of(p).map_or(vec![], |k| vec![FitCal::new(p, k)]);
        let ph = if p.has_phase() {
            vec![PhaseCos::new(p)]
        } else {
            vec![]
        };
        let wr = usize::from(p.writable());
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
            ld: ports(wr),
            ld_bits: ports(wr),
            ld_msk: ports(wr),
            w_off_s: ports(wr),
            w_off_c: ports(wr),
            w_gain_s: ports(wr),
            w_gain_c: ports(wr),
            w_phase: ports(wr),
            codes: if p.writable() {
                vec![CodeRegs::new(p)]
            } else {
                vec![]
            },
            m1p_s: ports(usize::from(p.writable() && p.has_phase())),
            cal,
            fit,
            ph,
            trs: MulTree::of(p, p.gain()[SIN] as u64),
            trc: MulTree::of(p, p.gain()[COS] as u64),
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
            dsign: c32(1 << a),
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
        for i in 0..self.fit.len() {
            self.fit[i].clk.next = self.clk.val();
            self.fit[i].rst.next = self.rst.val();
            self.fit[i].valid.next = self.in_valid.val();
            self.fit[i].x_sin.next = self.in_sin.val();
            self.fit[i].x_cos.next = self.in_cos.val();
            self.b_s.next = self.fit[i].b_sin.val() & self.amask.val();
            self.b_c.next = self.fit[i].b_cos.val() & self.amask.val();
            self.g_s.next = self.fit[i].g_sin.val();
            self.g_c.next = self.fit[i].g_cos.val();
            self.upd.next = self.fit[i].update.val();
        }
        // Writable codes: the registers between the calibration (or the configured values)
        // and stage 1, loaded by the register map.
        for i in 0..self.codes.len() {
            self.codes[i].clk.next = self.clk.val();
            self.codes[i].rst.next = self.rst.val();
            self.codes[i].ld.next = self.ld[i].val();
            self.codes[i].ld_bits.next = self.ld_bits[i].val();
            self.codes[i].ld_msk.next = self.ld_msk[i].val();
            self.codes[i].cal_upd.next = false;
            self.codes[i].cal_b_s.next = self.b0_s.val();
            self.codes[i].cal_b_c.next = self.b0_c.val();
            self.codes[i].cal_g_s.next = self.g0_s.val();
            self.codes[i].cal_g_c.next = self.g0_c.val();
            self.codes[i].cal_k_mag.next = self.g0_s.val();
            self.codes[i].cal_k_neg.next = false;
            for j in 0..self.cal.len() {
                self.codes[i].cal_upd.next = self.cal[j].update.val();
                self.codes[i].cal_b_s.next = self.cal[j].b_sin.val();
                self.codes[i].cal_b_c.next = self.cal[j].b_cos.val();
                self.codes[i].cal_g_s.next = self.cal[j].g_sin.val();
                self.codes[i].cal_g_c.next = self.cal[j].g_cos.val();
            }
            for j in 0..self.fit.len() {
                self.codes[i].cal_upd.next = self.fit[j].update.val();
                self.codes[i].cal_b_s.next = self.fit[j].b_sin.val();
                self.codes[i].cal_b_c.next = self.fit[j].b_cos.val();
                self.codes[i].cal_g_s.next = self.fit[j].g_sin.val();
                self.codes[i].cal_g_c.next = self.fit[j].g_cos.val();
                self.codes[i].cal_k_mag.next = self.fit[j].k_mag.val();
                self.codes[i].cal_k_neg.next = self.fit[j].k_neg.val();
            }
            self.b_s.next = self.codes[i].b_s.val();
            self.b_c.next = self.codes[i].b_c.val();
            self.g_s.next = self.codes[i].g_s.val();
            self.g_c.next = self.codes[i].g_c.val();
            self.w_off_s[i].next = self.codes[i].w_off_s.val();
            self.w_off_c[i].next = self.codes[i].w_off_c.val();
            self.w_gain_s[i].next = self.codes[i].w_gain_s.val();
            self.w_gain_c[i].next = self.codes[i].w_gain_c.val();
            self.w_phase[i].next = self.codes[i].w_phase.val();
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
        if (self.d_s.val() & self.dsign.val()).any() {
            self.md_s.next = self.nd_s.val();
        }
        self.md_c.next = self.d_c.val();
        if (self.d_c.val() & self.dsign.val()).any() {
            self.md_c.next = self.nd_c.val();
        }
        self.v1.d.next = self.in_valid.val() & !self.rst.val();
        self.sg1_s.d.next = (self.d_s.val() & self.dsign.val()).any();
        self.sg1_c.d.next = (self.d_c.val() & self.dsign.val()).any();
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
        // Shift-add products (auto and peak modes, or static mode with a code that is not a
        // power of two): the product from a tree of the gain (three more register levels; its
        // last sum is the product register's input), the sign and the valid bit delayed
        // with it.
        for i in 0..self.trs.len() {
            self.trs[i].clk.next = self.clk.val();
            self.trs[i].rst.next = self.rst.val();
            self.trs[i].a.next = self.m1_s.q.val();
            self.trs[i].code.next = self.g1_s.q.val();
            self.trs[i].neg.next = self.sg1_s.q.val();
            self.trs[i].v.next = self.v1.q.val();
            self.v2.d.next = self.trs[i].out_v.val() & !self.rst.val();
            self.sg2_s.d.next = self.trs[i].out_neg.val();
            self.p2_s.d.next =
                (self.trs[i].out_x.val() + self.trs[i].out_y.val()) >> self.hshift.val();
        }
        for i in 0..self.trc.len() {
            self.trc[i].clk.next = self.clk.val();
            self.trc[i].rst.next = self.rst.val();
            self.trc[i].a.next = self.m1_c.q.val();
            self.trc[i].code.next = self.g1_c.q.val();
            self.trc[i].neg.next = self.sg1_c.q.val();
            self.trc[i].v.next = self.v1.q.val();
            self.sg2_c.d.next = self.trc[i].out_neg.val();
            self.p2_c.d.next =
                (self.trc[i].out_x.val() + self.trc[i].out_y.val()) >> self.hshift.val();
        }
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
        // Phase correction: the cos track from the stage-1 registers through its own
        // stages 2-5; the sine result and the valid bit are delayed to match.
        for i in 0..self.ph.len() {
            self.ph[i].clk.next = self.clk.val();
            self.ph[i].rst.next = self.rst.val();
            self.ph[i].m_s.next = self.m1_s.q.val();
            self.ph[i].neg_s.next = self.sg1_s.q.val();
            self.ph[i].m_c.next = self.m1_c.q.val();
            self.ph[i].neg_c.next = self.sg1_c.q.val();
            self.ph[i].g_c.next = self.g1_c.q.val();
            self.ph[i].sin3.next = self.o3_s.q.val();
            self.ph[i].v3.next = self.v3.q.val();
            // Static mode: unused (k is the phase stage's constant).
            self.ph[i].k_mag.next = self.g0_s.val();
            self.ph[i].k_neg.next = false;
            for j in 0..self.fit.len() {
                self.ph[i].k_mag.next = self.fit[j].k_mag_d.val();
                self.ph[i].k_neg.next = self.fit[j].k_neg_d.val();
            }
            for j in 0..self.codes.len() {
                self.ph[i].k_mag.next = self.codes[j].k_mag_d.val();
                self.ph[i].k_neg.next = self.codes[j].k_neg_d.val();
            }
            for j in 0..self.m1p_s.len() {
                self.m1p_s[j].clock.next = self.clk.val();
                self.m1p_s[j].d.next = bit_cast::<16, 32>(self.md_s.val() & self.amask.val());
                self.ph[i].m_s.next = self.m1p_s[j].q.val();
            }
            self.out_valid.next = self.ph[i].out_valid.val();
            self.out_sin.next = self.ph[i].out_sin.val();
            self.out_cos.next = self.ph[i].out_cos.val();
        }
    }
}

impl crate::cosim::step::Clocked for Correction {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for Correction {
    fn input_ports(&self) -> Vec<Port> {
        let mut v = vec![
            Port::new("rst", 1),
            Port::new("in_valid", 1),
            Port::new("in_sin", 16),
            Port::new("in_cos", 16),
        ];
        if !self.codes.is_empty() {
            v.extend([
                Port::new("ld_0", 8),
                Port::new("ld_bits_0", 32),
                Port::new("ld_msk_0", 32),
            ]);
        }
        v
    }
    fn output_ports(&self) -> Vec<Port> {
        let mut v = vec![
            Port::new("out_valid", 1),
            Port::new("out_sin", 16),
            Port::new("out_cos", 16),
            Port::new("offset_sin", 16),
            Port::new("offset_cos", 16),
            Port::new("gain_sin", 16),
            Port::new("gain_cos", 16),
            Port::new("cal_update", 1),
        ];
        if !self.codes.is_empty() {
            v.extend([
                Port::new("w_off_s_0", 32),
                Port::new("w_off_c_0", 32),
                Port::new("w_gain_s_0", 32),
                Port::new("w_gain_c_0", 32),
                Port::new("w_phase_0", 32),
            ]);
        }
        v
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.in_valid.next = r[1] != 0;
        self.in_sin.next = Bits::<16>::from(r[2] & 0xffff);
        self.in_cos.next = Bits::<16>::from(r[3] & 0xffff);
        for i in 0..self.ld.len() {
            self.ld[i].next = Bits::<8>::from(r[4] & 0xff);
            self.ld_bits[i].next = Bits::<32>::from(r[5] & 0xffff_ffff);
            self.ld_msk[i].next = Bits::<32>::from(r[6] & 0xffff_ffff);
        }
    }
    fn sample(&self) -> Vec<u64> {
        let mut v = vec![
            self.out_valid.val() as u64,
            self.out_sin.val().to_u64(),
            self.out_cos.val().to_u64(),
            self.offset_sin.val().to_u64(),
            self.offset_cos.val().to_u64(),
            self.gain_sin.val().to_u64(),
            self.gain_cos.val().to_u64(),
            self.cal_update.val() as u64,
        ];
        for i in 0..self.w_off_s.len() {
            v.extend([
                self.w_off_s[i].val().to_u64(),
                self.w_off_c[i].val().to_u64(),
                self.w_gain_s[i].val().to_u64(),
                self.w_gain_c[i].val().to_u64(),
                self.w_phase[i].val().to_u64(),
            ]);
        }
        v
    }
}

/// `n` default signals (the ports of optional logic: one element or none).
fn ports<T: Default>(n: usize) -> Vec<T> {
    (0..n).map(|_| T::default()).collect()
}
