//! rust-hdl description of the phase correction of the cos track: the stages that replace
//! the cos channel's stages 2-3 when a phase error is corrected (maths, rounding and bit
//! growth in [`crate::blocks::correction`]). Built only when k != 0, so a design without
//! phase correction has none of it.
use super::multree::MulTree;
use super::{CorrectionParams, COS};
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// The stage-4 constants for n = 0, 1, 2 (the ones of the ones' complements not yet
/// added): the rounding addend 2^(F-1) + n and the saturation limits C - n, the latter with
/// the sign bit flipped so that an unsigned compare orders two's complement words.
fn stage4_constants(a: u32, f: u32) -> ([u64; 3], [u64; 3], [u64; 3]) {
    let h = 1i64 << (f - 1);
    let lim = 1i64 << (a - 1 + f);
    let m32 = mask(32);
    let flip = |v: i64| (v as u64 & m32) ^ (1 << 31);
    (
        [0, 1, 2].map(|n| (h + n) as u64),
        [0, 1, 2].map(|n| flip(lim - h - n)),
        [0, 1, 2].map(|n| flip(-lim - h - n)),
    )
}

/// The stage-4 constants as used by [`super::model`]: (rounding addends, high limits, low
/// limits), see [`PhaseCos`].
pub(super) fn constants(p: &CorrectionParams) -> ([u64; 3], [u64; 3], [u64; 3]) {
    stage4_constants(p.adc_width(), p.gain_frac_bits() - p.phase_shift())
}

/// Cos track with phase correction, stages 2-5: x_c' = clamp(floor((+-P_c +- Q) / 2^F + 1/2))
/// with P_c = |d_c| g_c >> s and Q = |d_s| |k| >> s; the sine result is delayed two stages
/// to stay aligned.
#[derive(LogicBlock)]
pub struct PhaseCos {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: clears the valid bit.
    pub rst: Signal<In, Bit>,
    /// |d_s| = |x_s - b_s| (stage-1 register of the correction).
    pub m_s: Signal<In, Bits<16>>,
    /// d_s < 0 (stage-1 register).
    pub neg_s: Signal<In, Bit>,
    /// |d_c| = |x_c - b_c| (stage-1 register).
    pub m_c: Signal<In, Bits<16>>,
    /// d_c < 0 (stage-1 register).
    pub neg_c: Signal<In, Bit>,
    /// Cos gain g_c (carrying 1 / cos(phi)) of the same sample, UQ(16-GF).GF.
    pub g_c: Signal<In, Bits<16>>,
    /// Corrected sine of the correction's stage 3, A-bit two's complement.
    pub sin3: Signal<In, Bits<16>>,
    /// Valid bit of the correction's stage 3.
    pub v3: Signal<In, Bit>,
    /// Auto mode: |k| in use when the sample was in stage 1 (the fit's code delayed one
    /// clock), UQ(16-GF).GF; ignored in static mode (k is a constant).
    pub k_mag: Signal<In, Bits<16>>,
    /// k < 0, with `k_mag`.
    pub k_neg: Signal<In, Bit>,
    /// Strobe of the corrected sample (two clocks after `v3`).
    pub out_valid: Signal<Out, Bit>,
    /// Corrected sine (stage-3 value, delayed two clocks).
    pub out_sin: Signal<Out, Bits<16>>,
    /// Phase-corrected cosine, A-bit two's complement (saturated).
    pub out_cos: Signal<Out, Bits<16>>,
    /// P_c as a shift-add tree when `p.shift_add()` (of the constant g_c in static mode, of
    /// the `g_c` port in auto mode), else none.
    tpc: Vec<MulTree>,
    /// Q as a shift-add tree when `p.shift_add()` (of the constant |k|, or of `k_mag`),
    /// else none.
    tq: Vec<MulTree>,
    pc2: DFF<Bits<32>>,
    q2: DFF<Bits<32>>,
    na2: DFF<Bit>,
    nb2: DFF<Bit>,
    s3: DFF<Bits<32>>,
    /// Stage 3: the stage-4 constants for n = na + nb, selected a clock ahead (registered,
    /// so stage 4's adder and compares see only registers).
    rnd3: DFF<Bits<32>>,
    chi3: DFF<Bits<32>>,
    clo3: DFF<Bits<32>>,
    v4: DFF<Bit>,
    o4_s: DFF<Bits<16>>,
    /// Stage 4: the rounded code (A bits), and the two compares S' >= high limit and
    /// S' < low limit, registered straight from their carry chains.
    o4_c: DFF<Bits<16>>,
    hi4: DFF<Bit>,
    lo4: DFF<Bit>,
    /// Stage 5: the saturated code selected by the registered compares.
    v5: DFF<Bit>,
    o5_s: DFF<Bits<16>>,
    o5_c: DFF<Bits<16>>,
    /// Stage 3: ones' complement masks of the two products.
    ma: Signal<Local, Bits<32>>,
    mb: Signal<Local, Bits<32>>,
    /// Stage 3: the per-n constants selected by the two negation bits.
    rnd: Signal<Local, Bits<32>>,
    chi: Signal<Local, Bits<32>>,
    clo: Signal<Local, Bits<32>>,
    /// Stage 4: s3 with its sign bit flipped (signed order as unsigned order).
    sf: Signal<Local, Bits<32>>,
    /// Stage 4: rounded sum (bits F.. of the word are the result modulo 2^A).
    r: Signal<Local, Bits<32>>,
    /// Stage 5: the output code.
    o: Signal<Local, Bits<16>>,
    /// Static mode: |k| and k < 0 of `p.cross()`; auto mode (`kdyn`): the ports instead.
    kmag0: Constant<Bits<16>>,
    kneg0: Constant<Bit>,
    kdyn: Constant<Bit>,
    /// k in use (the constants or the ports).
    km: Signal<Local, Bits<16>>,
    kn: Signal<Local, Bit>,
    /// s = max(0, A - 14): right shift of both products.
    pshift: Constant<Bits<32>>,
    /// F = GF - s: fraction bits of the sum.
    fshift: Constant<Bits<32>>,
    /// 2^(F-1) + n for n = 0, 1, 2 (rounding half plus the ones not yet added).
    rnd0: Constant<Bits<32>>,
    rnd1: Constant<Bits<32>>,
    rnd2: Constant<Bits<32>>,
    /// 2^(A-1+F) - 2^(F-1) - n, sign bit flipped: S' at or above it saturates high.
    hi0: Constant<Bits<32>>,
    hi1: Constant<Bits<32>>,
    hi2: Constant<Bits<32>>,
    /// -2^(A-1+F) - 2^(F-1) - n, sign bit flipped: S' below it saturates low.
    lo0: Constant<Bits<32>>,
    lo1: Constant<Bits<32>>,
    lo2: Constant<Bits<32>>,
    /// All ones.
    ones: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
    /// Bit 31.
    sign32: Constant<Bits<32>>,
    /// Mask of the A sample bits.
    amask: Constant<Bits<32>>,
    /// 2^(A-1): the most negative A-bit code.
    asign: Constant<Bits<16>>,
    /// 2^(A-1) - 1.
    pmax: Constant<Bits<16>>,
}

impl PhaseCos {
    /// Phase stage for `p` (k comes in on `k_mag`, `k_neg`).
    pub fn new(p: &CorrectionParams) -> Self {
        let a = p.adc_width();
        let s = p.phase_shift();
        let f = p.gain_frac_bits() - s;
        let (rnd, hi, lo) = constants(p);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            m_s: Default::default(),
            neg_s: Default::default(),
            m_c: Default::default(),
            neg_c: Default::default(),
            g_c: Default::default(),
            sin3: Default::default(),
            v3: Default::default(),
            k_mag: Default::default(),
            k_neg: Default::default(),
            out_valid: Default::default(),
            out_sin: Default::default(),
            out_cos: Default::default(),
            tpc: MulTree::of(p, p.gain()[COS] as u64),
            tq: MulTree::of(p, p.cross().unsigned_abs() as u64),
            pc2: Default::default(),
            q2: Default::default(),
            na2: Default::default(),
            nb2: Default::default(),
            s3: Default::default(),
            rnd3: Default::default(),
            chi3: Default::default(),
            clo3: Default::default(),
            v4: Default::default(),
            o4_s: Default::default(),
            o4_c: Default::default(),
            hi4: Default::default(),
            lo4: Default::default(),
            v5: Default::default(),
            o5_s: Default::default(),
            o5_c: Default::default(),
            ma: Default::default(),
            mb: Default::default(),
            rnd: Default::default(),
            chi: Default::default(),
            clo: Default::default(),
            sf: Default::default(),
            r: Default::default(),
            o: Default::default(),
            kmag0: Constant::new(Bits::<16>::from(p.cross().unsigned_abs() as u64 & 0xffff)),
            kneg0: Constant::new(p.cross() < 0),
            kdyn: Constant::new(p.dynamic_cross()),
            km: Default::default(),
            kn: Default::default(),
            pshift: c32(s as u64),
            fshift: c32(f as u64),
            rnd0: c32(rnd[0]),
            rnd1: c32(rnd[1]),
            rnd2: c32(rnd[2]),
            hi0: c32(hi[0]),
            hi1: c32(hi[1]),
            hi2: c32(hi[2]),
            lo0: c32(lo[0]),
            lo1: c32(lo[1]),
            lo2: c32(lo[2]),
            ones: c32(mask(32)),
            zero: c32(0),
            sign32: c32(1 << 31),
            amask: c32(mask(a)),
            asign: Constant::new(Bits::<16>::from(1u64 << (a - 1))),
            pmax: Constant::new(Bits::<16>::from(mask(a - 1))),
        }
    }
}

impl Logic for PhaseCos {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, pc2, q2, na2, nb2, s3, rnd3, chi3, clo3, v4, o4_s, o4_c, hi4, lo4, v5, o5_s,
            o5_c
        );
        self.km.next = self.kmag0.val();
        self.kn.next = self.kneg0.val();
        if self.kdyn.val() {
            self.km.next = self.k_mag.val();
            self.kn.next = self.k_neg.val();
        }
        // Stage 2: the two unsigned 16 x 16 -> 32 products, shifted right by s.
        self.pc2.d.next = (self.m_c.val() * self.g_c.val()) >> self.pshift.val();
        self.q2.d.next = (self.m_s.val() * self.km.val()) >> self.pshift.val();
        self.na2.d.next = self.neg_c.val();
        self.nb2.d.next = self.neg_s.val() ^ self.kn.val();
        // Shift-add products (auto mode, or static mode with a code that is not a power of
        // two): both from trees (three more register levels, their last sums the stage-2
        // registers' inputs), the negation bits delayed with them.
        for i in 0..self.tpc.len() {
            self.tpc[i].clk.next = self.clk.val();
            self.tpc[i].rst.next = self.rst.val();
            self.tpc[i].a.next = self.m_c.val();
            self.tpc[i].code.next = self.g_c.val();
            self.tpc[i].neg.next = self.neg_c.val();
            self.tpc[i].v.next = false;
            self.pc2.d.next =
                (self.tpc[i].out_x.val() + self.tpc[i].out_y.val()) >> self.pshift.val();
            self.na2.d.next = self.tpc[i].out_neg.val();
        }
        for i in 0..self.tq.len() {
            self.tq[i].clk.next = self.clk.val();
            self.tq[i].rst.next = self.rst.val();
            self.tq[i].a.next = self.m_s.val();
            self.tq[i].code.next = self.km.val();
            self.tq[i].neg.next = self.neg_s.val() ^ self.kn.val();
            self.tq[i].v.next = false;
            self.q2.d.next = (self.tq[i].out_x.val() + self.tq[i].out_y.val()) >> self.pshift.val();
            self.nb2.d.next = self.tq[i].out_neg.val();
        }
        // Stage 3: S' = (P_c or !P_c) + (Q or !Q) = S - n, one adder (|S| < 2^31).
        self.ma.next = self.zero.val();
        if self.na2.q.val() {
            self.ma.next = self.ones.val();
        }
        self.mb.next = self.zero.val();
        if self.nb2.q.val() {
            self.mb.next = self.ones.val();
        }
        self.s3.d.next = (self.pc2.q.val() ^ self.ma.val()) + (self.q2.q.val() ^ self.mb.val());
        // n = na + nb picks the stage-4 constants here, a clock ahead, into registers.
        self.rnd.next = self.rnd0.val();
        self.chi.next = self.hi0.val();
        self.clo.next = self.lo0.val();
        if self.na2.q.val() ^ self.nb2.q.val() {
            self.rnd.next = self.rnd1.val();
            self.chi.next = self.hi1.val();
            self.clo.next = self.lo1.val();
        }
        if self.na2.q.val() & self.nb2.q.val() {
            self.rnd.next = self.rnd2.val();
            self.chi.next = self.hi2.val();
            self.clo.next = self.lo2.val();
        }
        self.rnd3.d.next = self.rnd.val();
        self.chi3.d.next = self.chi.val();
        self.clo3.d.next = self.clo.val();
        // Stage 4: round half up, and the two saturation compares of S' beside the adder,
        // each a carry chain between registers straight into a register.
        self.sf.next = self.s3.q.val() ^ self.sign32.val();
        self.r.next =
            ((self.s3.q.val() + self.rnd3.q.val()) >> self.fshift.val()) & self.amask.val();
        self.o4_c.d.next = bit_cast::<16, 32>(self.r.val());
        self.hi4.d.next = self.sf.val() >= self.chi3.q.val();
        self.lo4.d.next = self.sf.val() < self.clo3.q.val();
        self.v4.d.next = self.v3.val() & !self.rst.val();
        self.o4_s.d.next = self.sin3.val();
        // Stage 5: select the saturated code (low wins, as in the model; the two exclude
        // each other).
        self.o.next = self.o4_c.q.val();
        if self.hi4.q.val() {
            self.o.next = self.pmax.val();
        }
        if self.lo4.q.val() {
            self.o.next = self.asign.val();
        }
        self.v5.d.next = self.v4.q.val() & !self.rst.val();
        self.o5_s.d.next = self.o4_s.q.val();
        self.o5_c.d.next = self.o.val();
        self.out_valid.next = self.v5.q.val();
        self.out_sin.next = self.o5_s.q.val();
        self.out_cos.next = self.o5_c.q.val();
    }
}
