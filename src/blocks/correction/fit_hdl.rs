//! rust-hdl description of the automatic calibration by least-squares ellipse fit (mode
//! `auto`): the quadrant tracker and the window sums of [`super::fit::EllipseFit`], one
//! sample every second clock at most (the ADC delivers one per frame), feeding the serial
//! solver [`super::fit_solve::FitSolve`], which loads offsets, gains and the phase cross
//! code together.
//!
//! ```text
//!           stage A (reg)           stage B (reg)                stage C (reg)   stage D (reg)
//!  x ─►sext─► d  = x - b_ref ─┐
//!            -d  = b_ref - x  ├─► q, step ──────────► net, N,   ─► e, |e|, cmd ─► |e_s|²,|e_c|²,
//!  (both      e  = x - b_cur  │   (d, or e right after b_ref    (add / restart  |e_s e_c|
//!  tracks)   -e  = b_cur - x ─┘    changed) window open/close     / snapshot)    (3 hard 16x16)
//!            (q, step from the signs of d and tq; the closing compares of net, N registered)
//!                                  b_ref := b_cur at a start ─────────────┐         │
//!  stage E: N, Σe_s, Σe_c, Σe_s², Σe_c², Σe_s e_c (64-bit) ◄───────────────┴─────────┘
//!           at a window's end the sums before the sample and the window's b_ref go to
//!           FitSolve (if it is idle), then restart from the sample ─► b_cur, g, k (all at once)
//! ```
//!
//! # Widths and bit growth (A = 10..=16)
//! * x, b in [-2^(A-1), 2^(A-1)): d = x - b in (-2^A, 2^A), 32-bit two's complement; |d| is
//!   the select of d or -d (two subtractors side by side), at most 2^A - 1 <= 65535, the
//!   unsigned 16-bit multiplier operand; products < 2^32 in 32-bit words.
//! * N <= N_MAX = 2^24 (a longer window is abandoned, [`super::fit::N_MAX`]): |Σd| < 2^40,
//!   Σd² and |Σd_s d_c| < 2^56, so the 64-bit sums never wrap; each is one adder (or a
//!   subtractor beside it for a negative product, selected by the sign).
//! * net (the quadrants since the window opened) changes by at most 2 per sample and is
//!   bounded by 2 N_MAX: 32 bits. The window-closing test |net + s| >= 4K is done as compares
//!   of the registered net against constants (one per step s = +-1, +-2, registered), beside the adder
//!   net + s, so each path has one carry chain; (net + s) mod 4 = 0 is a 2-bit match.
//!
//! # Timing and semantics
//! * The tracker and the sums follow the model sample for sample; the sums are three
//!   clocks behind the tracker, so the snapshot (stage E) holds exactly the window's samples.
//! * The window-closing compares of `net` and N are registered (free-running), so they
//!   describe the last sample's state only when samples are at least two clocks apart; the
//!   ADC controller delivers one per frame (tens of clocks), the tests every 2 to 6 clocks.
//! * b_ref of a new window is b_cur at its first sample, i.e. the offsets before the update
//!   its predecessor triggers (the model does the same, [`super::fit`]). The sample right
//!   after a b_ref change was subtracted from the old b_ref in stage A; stage B then uses its
//!   e = x - b_cur instead.
//! * A window that ends while the solver is still busy is dropped (the model has no such
//!   case: the config requires `min_samples` x clocks per sample > [`super::fit_solve::SOLVE_CYCLES`]).
//! * Reset (synchronous, active high): configured offsets and gains, k = 0, tracker waiting
//!   for its first sample, solver idle.
use super::fit::N_MAX;
use super::fit_solve::{c64, FitSolve, SolveConsts};
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{c32, fill, mask};
use rust_hdl::prelude::*;

fn c2(v: u64) -> Constant<Bits<2>> {
    Constant::new(Bits::<2>::from(v & 3))
}

/// The ellipse-fit calibration: tracker, sums and solver.
#[derive(LogicBlock)]
pub struct FitCal {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// Sample strobe.
    pub valid: Signal<In, Bit>,
    /// Raw sine sample, A-bit two's complement in the low bits (upper bits ignored).
    pub x_sin: Signal<In, Bits<16>>,
    /// Raw cosine sample, A-bit two's complement in the low bits (upper bits ignored).
    pub x_cos: Signal<In, Bits<16>>,
    /// Sine offset in use, 32-bit two's complement.
    pub b_sin: Signal<Out, Bits<32>>,
    /// Cosine offset in use, 32-bit two's complement.
    pub b_cos: Signal<Out, Bits<32>>,
    /// Sine gain code in use, UQ(16-GF).GF.
    pub g_sin: Signal<Out, Bits<16>>,
    /// Cosine gain code in use (carries 1 / cos phi).
    pub g_cos: Signal<Out, Bits<16>>,
    /// |k|, the cross code of the phase correction in use.
    pub k_mag: Signal<Out, Bits<16>>,
    /// k < 0.
    pub k_neg: Signal<Out, Bit>,
    /// One clock when new coefficients have been loaded.
    pub update: Signal<Out, Bit>,
    /// `k_mag` one clock late: the code of the sample in the datapath's stage 1.
    pub k_mag_d: Signal<Out, Bits<16>>,
    /// `k_neg` one clock late.
    pub k_neg_d: Signal<Out, Bit>,
    slv: FitSolve,
    kd_m: DFF<Bits<16>>,
    kd_n: DFF<Bit>,
    va: DFF<Bit>,
    da_s: DFF<Bits<32>>,
    nda_s: DFF<Bits<32>>,
    ea_s: DFF<Bits<32>>,
    nea_s: DFF<Bits<32>>,
    da_c: DFF<Bits<32>>,
    nda_c: DFF<Bits<32>>,
    ea_c: DFF<Bits<32>>,
    nea_c: DFF<Bits<32>>,
    bref_s: DFFWithInit<Bits<32>>,
    bref_c: DFFWithInit<Bits<32>>,
    tinit: DFF<Bit>,
    tq: DFF<Bits<2>>,
    dknown: DFF<Bit>,
    dneg: DFF<Bit>,
    open: DFF<Bit>,
    fresh: DFF<Bit>,
    net: DFF<Bits<32>>,
    nb: DFF<Bits<32>>,
    bs_s: DFF<Bits<32>>,
    bs_c: DFF<Bits<32>>,
    c_v: DFF<Bit>,
    c_rs: DFF<Bit>,
    c_snap: DFF<Bit>,
    c_es: DFF<Bits<32>>,
    c_ec: DFF<Bits<32>>,
    c_ms: DFF<Bits<16>>,
    c_mc: DFF<Bits<16>>,
    c_nsc: DFF<Bit>,
    d_v: DFF<Bit>,
    d_rs: DFF<Bit>,
    d_snap: DFF<Bit>,
    d_es: DFF<Bits<64>>,
    d_ec: DFF<Bits<64>>,
    p_ss: DFF<Bits<32>>,
    p_cc: DFF<Bits<32>>,
    p_sc: DFF<Bits<32>>,
    d_nsc: DFF<Bit>,
    cnt: DFF<Bits<32>>,
    /// The window-closing compares |net + s| >= 4K for s = +1, -1, +2, -2 and N >= min_samples,
    /// registered from `net` and `nb` (free-running; samples are at least two clocks apart).
    h_p1: DFF<Bit>,
    h_m1: DFF<Bit>,
    h_p2: DFF<Bit>,
    h_m2: DFF<Bit>,
    nbge: DFF<Bit>,
    s1_s: DFF<Bits<64>>,
    s1_c: DFF<Bits<64>>,
    s2_s: DFF<Bits<64>>,
    s2_c: DFF<Bits<64>>,
    ssc: DFF<Bits<64>>,
    xs: Signal<Local, Bits<32>>,
    xc: Signal<Local, Bits<32>>,
    /// Stage B: the differences the quadrant is taken from (d, or e after a b_ref change).
    ds: Signal<Local, Bits<32>>,
    dc: Signal<Local, Bits<32>>,
    /// Stage A: x - b_ref (the quadrant's signs), the quadrant and the step from tq.
    das: Signal<Local, Bits<32>>,
    dac: Signal<Local, Bits<32>>,
    q: Signal<Local, Bits<2>>,
    stp: Signal<Local, Bits<2>>,
    /// Stage B: the sample's quadrant and step (registered in stage A).
    qb: DFF<Bits<2>>,
    sb: DFF<Bits<2>>,
    /// Stage B: the step s as a 32-bit word, and the closing tests for it.
    sval: Signal<Local, Bits<32>>,
    netf: Signal<Local, Bits<32>>,
    big: Signal<Local, Bit>,
    whole: Signal<Local, Bit>,
    done: Signal<Local, Bit>,
    /// Stage E: the sums' bases (0 at a restart).
    z1_s: Signal<Local, Bits<64>>,
    z1_c: Signal<Local, Bits<64>>,
    z2_s: Signal<Local, Bits<64>>,
    z2_c: Signal<Local, Bits<64>>,
    zsc: Signal<Local, Bits<64>>,
    zn: Signal<Local, Bits<32>>,
    /// Quadrant codes.
    q0: Constant<Bits<2>>,
    q1: Constant<Bits<2>>,
    q2: Constant<Bits<2>>,
    q3: Constant<Bits<2>>,
    /// Step words +1, -1, +2, -2.
    sp1: Constant<Bits<32>>,
    sm1: Constant<Bits<32>>,
    sp2: Constant<Bits<32>>,
    sm2: Constant<Bits<32>>,
    /// Closing compares (net with its sign bit flipped against flipped constants): for
    /// step s, net >= 4K - s (ge_*) or net < -4K - s + 1 (lt_*).
    ge_p1: Constant<Bits<32>>,
    lt_p1: Constant<Bits<32>>,
    ge_m1: Constant<Bits<32>>,
    lt_m1: Constant<Bits<32>>,
    ge_p2: Constant<Bits<32>>,
    lt_p2: Constant<Bits<32>>,
    ge_m2: Constant<Bits<32>>,
    lt_m2: Constant<Bits<32>>,
    /// net mod 4 that makes net + s a multiple of 4: 3 for +1, 1 for -1, 2 for +-2.
    r3: Constant<Bits<32>>,
    r1: Constant<Bits<32>>,
    r2: Constant<Bits<32>>,
    /// Mask of two bits.
    m2: Constant<Bits<32>>,
    /// min_samples and N_MAX.
    nmin: Constant<Bits<32>>,
    nmax: Constant<Bits<32>>,
    /// A-bit sample handling.
    amask: Constant<Bits<32>>,
    asign: Constant<Bits<32>>,
    asext: Constant<Bits<32>>,
    /// Bit 31 and bits 32..63 (sign extension to 64 bits).
    sign32: Constant<Bits<32>>,
    sext64: Constant<Bits<64>>,
    one32: Constant<Bits<32>>,
    zero32: Constant<Bits<32>>,
    zero64: Constant<Bits<64>>,
    /// Configured (reset) offsets, 32-bit two's complement.
    b0_s: Constant<Bits<32>>,
    b0_c: Constant<Bits<32>>,
}

/// Settings of the fit besides the datapath's.
#[derive(Clone, Copy, Debug)]
pub struct FitConsts {
    /// The solver's constants.
    pub solve: SolveConsts,
    /// Least whole periods K per window.
    pub periods: u32,
    /// Least samples per window (<= N_MAX).
    pub min_samples: u32,
}

impl FitConsts {
    /// The fit's settings of `p` (None unless `p.fit()` is on).
    pub fn of(p: &CorrectionParams) -> Option<Self> {
        p.fit().map(|f| FitConsts {
            solve: SolveConsts {
                adc_width: p.adc_width(),
                gain_frac_bits: p.gain_frac_bits(),
                target_amplitude: f.target_amplitude(),
                min_amplitude: f.min_amplitude(),
            },
            periods: f.periods(),
            min_samples: f.min_samples(),
        })
    }
}

impl FitCal {
    /// Fit for `k`, reset to the offsets and gains of `p`.
    pub fn new(p: &CorrectionParams, k: FitConsts) -> Self {
        let a = k.solve.adc_width;
        let w = 4 * k.periods as i64;
        let flip = |v: i64| (v as u64 & mask(32)) ^ (1 << 31);
        let sext = |v: i32| v as i64 as u64 & mask(32);
        assert!(
            k.min_samples <= N_MAX,
            "min_samples is checked against N_MAX by the config"
        );
        Self {
            clk: Default::default(),
            rst: Default::default(),
            valid: Default::default(),
            x_sin: Default::default(),
            x_cos: Default::default(),
            b_sin: Default::default(),
            b_cos: Default::default(),
            g_sin: Default::default(),
            g_cos: Default::default(),
            k_mag: Default::default(),
            k_neg: Default::default(),
            update: Default::default(),
            k_mag_d: Default::default(),
            k_neg_d: Default::default(),
            slv: FitSolve::new(p, k.solve),
            kd_m: Default::default(),
            kd_n: Default::default(),
            va: Default::default(),
            da_s: Default::default(),
            nda_s: Default::default(),
            ea_s: Default::default(),
            nea_s: Default::default(),
            da_c: Default::default(),
            nda_c: Default::default(),
            ea_c: Default::default(),
            nea_c: Default::default(),
            bref_s: DFFWithInit::new(Bits::<32>::from(sext(p.offset()[SIN]))),
            bref_c: DFFWithInit::new(Bits::<32>::from(sext(p.offset()[COS]))),
            tinit: Default::default(),
            tq: Default::default(),
            dknown: Default::default(),
            dneg: Default::default(),
            open: Default::default(),
            fresh: Default::default(),
            net: Default::default(),
            nb: Default::default(),
            bs_s: Default::default(),
            bs_c: Default::default(),
            c_v: Default::default(),
            c_rs: Default::default(),
            c_snap: Default::default(),
            c_es: Default::default(),
            c_ec: Default::default(),
            c_ms: Default::default(),
            c_mc: Default::default(),
            c_nsc: Default::default(),
            d_v: Default::default(),
            d_rs: Default::default(),
            d_snap: Default::default(),
            d_es: Default::default(),
            d_ec: Default::default(),
            p_ss: Default::default(),
            p_cc: Default::default(),
            p_sc: Default::default(),
            d_nsc: Default::default(),
            cnt: Default::default(),
            h_p1: Default::default(),
            h_m1: Default::default(),
            h_p2: Default::default(),
            h_m2: Default::default(),
            nbge: Default::default(),
            s1_s: Default::default(),
            s1_c: Default::default(),
            s2_s: Default::default(),
            s2_c: Default::default(),
            ssc: Default::default(),
            xs: Default::default(),
            xc: Default::default(),
            ds: Default::default(),
            dc: Default::default(),
            das: Default::default(),
            dac: Default::default(),
            q: Default::default(),
            stp: Default::default(),
            qb: Default::default(),
            sb: Default::default(),
            sval: Default::default(),
            netf: Default::default(),
            big: Default::default(),
            whole: Default::default(),
            done: Default::default(),
            z1_s: Default::default(),
            z1_c: Default::default(),
            z2_s: Default::default(),
            z2_c: Default::default(),
            zsc: Default::default(),
            zn: Default::default(),
            q0: c2(0),
            q1: c2(1),
            q2: c2(2),
            q3: c2(3),
            sp1: c32(1),
            sm1: c32(mask(32)),
            sp2: c32(2),
            sm2: c32(mask(32) - 1),
            ge_p1: c32(flip(w - 1)),
            lt_p1: c32(flip(-w)),
            ge_m1: c32(flip(w + 1)),
            lt_m1: c32(flip(-w + 2)),
            ge_p2: c32(flip(w - 2)),
            lt_p2: c32(flip(-w - 1)),
            ge_m2: c32(flip(w + 2)),
            lt_m2: c32(flip(-w + 3)),
            r3: c32(3),
            r1: c32(1),
            r2: c32(2),
            m2: c32(3),
            nmin: c32(k.min_samples as u64),
            nmax: c32(N_MAX as u64),
            amask: c32(mask(a)),
            asign: c32(1 << (a - 1)),
            asext: c32(fill(32, 32 - a)),
            sign32: c32(1 << 31),
            sext64: c64(fill(64, 32)),
            one32: c32(1),
            zero32: c32(0),
            zero64: c64(0),
            b0_s: c32(sext(p.offset()[SIN])),
            b0_c: c32(sext(p.offset()[COS])),
        }
    }
}

impl Logic for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, va, da_s, nda_s, ea_s, nea_s, da_c, nda_c, ea_c, nea_c, bref_s, bref_c,
            tinit, tq, dknown, dneg, open, fresh, net, nb, bs_s, bs_c, c_v, c_rs, c_snap, c_es,
            c_ec, c_ms, c_mc, c_nsc, d_v, d_rs, d_snap, d_es, d_ec, p_ss, p_cc, p_sc, d_nsc, cnt,
            s1_s, s1_c, s2_s, s2_c, ssc, kd_m, kd_n, h_p1, h_m1, h_p2, h_m2, nbge, qb, sb
        );
        self.slv.clk.next = self.clk.val();
        self.slv.rst.next = self.rst.val();
        // Stage A: sign-extend; differences from b_ref and from the offsets in use.
        self.xs.next = bit_cast::<32, 16>(self.x_sin.val()) & self.amask.val();
        if (self.xs.val() & self.asign.val()).any() {
            self.xs.next = self.xs.val() | self.asext.val();
        }
        self.xc.next = bit_cast::<32, 16>(self.x_cos.val()) & self.amask.val();
        if (self.xc.val() & self.asign.val()).any() {
            self.xc.next = self.xc.val() | self.asext.val();
        }
        self.va.d.next = self.valid.val() & !self.rst.val();
        self.das.next = self.xs.val() - self.bref_s.q.val();
        self.dac.next = self.xc.val() - self.bref_c.q.val();
        self.da_s.d.next = self.das.val();
        self.nda_s.d.next = self.bref_s.q.val() - self.xs.val();
        self.ea_s.d.next = self.xs.val() - self.slv.off_s.val();
        self.nea_s.d.next = self.slv.off_s.val() - self.xs.val();
        self.da_c.d.next = self.dac.val();
        self.nda_c.d.next = self.bref_c.q.val() - self.xc.val();
        self.ea_c.d.next = self.xc.val() - self.slv.off_c.val();
        self.nea_c.d.next = self.slv.off_c.val() - self.xc.val();
        // Quadrant (CORDIC mapper convention) and step, registered for stage B: the tracker's
        // b_ref and tq are the previous sample's (at least two clocks ago), so d is final.
        self.q.next = self.q0.val();
        if (self.das.val() & self.sign32.val()).any() {
            if (self.dac.val() & self.sign32.val()).any() {
                self.q.next = self.q2.val();
            } else {
                self.q.next = self.q3.val();
            }
        } else if (self.dac.val() & self.sign32.val()).any() {
            self.q.next = self.q1.val();
        }
        // q - tq mod 4 as logic (a borrow into bit 1), not a second carry chain after d's.
        self.stp.next = (self.q.val() ^ self.tq.q.val())
            ^ (((!self.q.val()) & self.tq.q.val() & self.q1.val()) << self.one32.val());
        self.qb.d.next = self.q.val();
        self.sb.d.next = self.stp.val();
        // Stage B: the differences of the sums' entry (d, or e after a b_ref change).
        self.ds.next = self.da_s.q.val();
        self.dc.next = self.da_c.q.val();
        if self.fresh.q.val() {
            self.ds.next = self.ea_s.q.val();
            self.dc.next = self.ea_c.q.val();
        }
        // The step as a word and the window-closing test |net + s| >= 4K, 4 | net + s: the
        // compares of net against constants are registered (net changed at least two clocks
        // ago), so only their selection by the step is in this path.
        self.netf.next = self.net.q.val() ^ self.sign32.val();
        self.h_p1.d.next =
            (self.netf.val() >= self.ge_p1.val()) | (self.netf.val() < self.lt_p1.val());
        self.h_m1.d.next =
            (self.netf.val() >= self.ge_m1.val()) | (self.netf.val() < self.lt_m1.val());
        self.h_p2.d.next =
            (self.netf.val() >= self.ge_p2.val()) | (self.netf.val() < self.lt_p2.val());
        self.h_m2.d.next =
            (self.netf.val() >= self.ge_m2.val()) | (self.netf.val() < self.lt_m2.val());
        self.nbge.d.next = self.nb.q.val() >= self.nmin.val();
        self.sval.next = self.zero32.val();
        self.big.next = false;
        self.whole.next = false;
        if self.sb.q.val() == self.q1.val() {
            self.sval.next = self.sp1.val();
            self.big.next = self.h_p1.q.val();
            self.whole.next = (self.net.q.val() & self.m2.val()) == self.r3.val();
        }
        if self.sb.q.val() == self.q3.val() {
            self.sval.next = self.sm1.val();
            self.big.next = self.h_m1.q.val();
            self.whole.next = (self.net.q.val() & self.m2.val()) == self.r1.val();
        }
        if self.sb.q.val() == self.q2.val() {
            self.whole.next = (self.net.q.val() & self.m2.val()) == self.r2.val();
            if self.dneg.q.val() {
                self.sval.next = self.sm2.val();
                self.big.next = self.h_m2.q.val();
            } else {
                self.sval.next = self.sp2.val();
                self.big.next = self.h_p2.q.val();
            }
        }
        self.done.next = self.big.val() & self.whole.val() & self.nbge.q.val();
        // Defaults of the command to the sums: nothing; the entry of the sample as it would
        // be added (d, or e after a b_ref change).
        self.fresh.d.next = false;
        self.c_v.d.next = false;
        self.c_rs.d.next = false;
        self.c_snap.d.next = false;
        self.c_es.d.next = self.ds.val();
        self.c_ec.d.next = self.dc.val();
        self.c_ms.d.next = bit_cast::<16, 32>(self.ds.val());
        if (self.da_s.q.val() & self.sign32.val()).any() & !self.fresh.q.val() {
            self.c_ms.d.next = bit_cast::<16, 32>(self.nda_s.q.val());
        }
        if (self.ea_s.q.val() & self.sign32.val()).any() & self.fresh.q.val() {
            self.c_ms.d.next = bit_cast::<16, 32>(self.nea_s.q.val());
        }
        self.c_mc.d.next = bit_cast::<16, 32>(self.dc.val());
        if (self.da_c.q.val() & self.sign32.val()).any() & !self.fresh.q.val() {
            self.c_mc.d.next = bit_cast::<16, 32>(self.nda_c.q.val());
        }
        if (self.ea_c.q.val() & self.sign32.val()).any() & self.fresh.q.val() {
            self.c_mc.d.next = bit_cast::<16, 32>(self.nea_c.q.val());
        }
        self.c_nsc.d.next =
            (self.ds.val() & self.sign32.val()).any() ^ (self.dc.val() & self.sign32.val()).any();
        if self.va.q.val() {
            self.tq.d.next = self.qb.q.val();
            if !self.tinit.q.val() {
                self.tinit.d.next = true;
                self.open.d.next = false;
            } else if (self.sb.q.val() == self.q2.val()) & !self.dknown.q.val() {
                // A two-quadrant step with no known direction: restart.
                self.open.d.next = false;
            } else {
                if (self.sb.q.val() == self.q1.val()) | (self.sb.q.val() == self.q3.val()) {
                    self.dknown.d.next = true;
                    self.dneg.d.next = self.sb.q.val() == self.q3.val();
                }
                if !self.open.q.val() {
                    if self.sb.q.val().any() {
                        // Open a window at this boundary, from the offsets in use.
                        self.open.d.next = true;
                        self.bref_s.d.next = self.slv.off_s.val();
                        self.bref_c.d.next = self.slv.off_c.val();
                        self.fresh.d.next = true;
                        self.net.d.next = self.zero32.val();
                        self.nb.d.next = self.one32.val();
                        self.c_v.d.next = true;
                        self.c_rs.d.next = true;
                        self.c_es.d.next = self.ea_s.q.val();
                        self.c_ec.d.next = self.ea_c.q.val();
                        self.c_ms.d.next = bit_cast::<16, 32>(self.ea_s.q.val());
                        if (self.ea_s.q.val() & self.sign32.val()).any() {
                            self.c_ms.d.next = bit_cast::<16, 32>(self.nea_s.q.val());
                        }
                        self.c_mc.d.next = bit_cast::<16, 32>(self.ea_c.q.val());
                        if (self.ea_c.q.val() & self.sign32.val()).any() {
                            self.c_mc.d.next = bit_cast::<16, 32>(self.nea_c.q.val());
                        }
                        self.c_nsc.d.next = (self.ea_s.q.val() & self.sign32.val()).any()
                            ^ (self.ea_c.q.val() & self.sign32.val()).any();
                    }
                } else if self.done.val() {
                    // The window ends before this sample, which opens the next one.
                    self.bs_s.d.next = self.bref_s.q.val();
                    self.bs_c.d.next = self.bref_c.q.val();
                    self.bref_s.d.next = self.slv.off_s.val();
                    self.bref_c.d.next = self.slv.off_c.val();
                    self.fresh.d.next = true;
                    self.net.d.next = self.zero32.val();
                    self.nb.d.next = self.one32.val();
                    self.c_v.d.next = true;
                    self.c_rs.d.next = true;
                    self.c_snap.d.next = true;
                    self.c_es.d.next = self.ea_s.q.val();
                    self.c_ec.d.next = self.ea_c.q.val();
                    self.c_ms.d.next = bit_cast::<16, 32>(self.ea_s.q.val());
                    if (self.ea_s.q.val() & self.sign32.val()).any() {
                        self.c_ms.d.next = bit_cast::<16, 32>(self.nea_s.q.val());
                    }
                    self.c_mc.d.next = bit_cast::<16, 32>(self.ea_c.q.val());
                    if (self.ea_c.q.val() & self.sign32.val()).any() {
                        self.c_mc.d.next = bit_cast::<16, 32>(self.nea_c.q.val());
                    }
                    self.c_nsc.d.next = (self.ea_s.q.val() & self.sign32.val()).any()
                        ^ (self.ea_c.q.val() & self.sign32.val()).any();
                } else if self.nb.q.val() == self.nmax.val() {
                    // Too long without closing: abandon, reopen at the next boundary.
                    self.open.d.next = false;
                } else {
                    self.net.d.next = self.net.q.val() + self.sval.val();
                    self.nb.d.next = self.nb.q.val() + self.one32.val();
                    self.c_v.d.next = true;
                }
            }
        }
        // Stage C: the three products of the entry.
        self.d_v.d.next = self.c_v.q.val();
        self.d_rs.d.next = self.c_rs.q.val();
        self.d_snap.d.next = self.c_snap.q.val();
        self.d_es.d.next = bit_cast::<64, 32>(self.c_es.q.val());
        if (self.c_es.q.val() & self.sign32.val()).any() {
            self.d_es.d.next = bit_cast::<64, 32>(self.c_es.q.val()) | self.sext64.val();
        }
        self.d_ec.d.next = bit_cast::<64, 32>(self.c_ec.q.val());
        if (self.c_ec.q.val() & self.sign32.val()).any() {
            self.d_ec.d.next = bit_cast::<64, 32>(self.c_ec.q.val()) | self.sext64.val();
        }
        self.p_ss.d.next = self.c_ms.q.val() * self.c_ms.q.val();
        self.p_cc.d.next = self.c_mc.q.val() * self.c_mc.q.val();
        self.p_sc.d.next = self.c_ms.q.val() * self.c_mc.q.val();
        self.d_nsc.d.next = self.c_nsc.q.val();
        // Stage E: the sums (restart: from zero); the snapshot goes to an idle solver.
        self.z1_s.next = self.s1_s.q.val();
        self.z1_c.next = self.s1_c.q.val();
        self.z2_s.next = self.s2_s.q.val();
        self.z2_c.next = self.s2_c.q.val();
        self.zsc.next = self.ssc.q.val();
        self.zn.next = self.cnt.q.val();
        if self.d_rs.q.val() {
            self.z1_s.next = self.zero64.val();
            self.z1_c.next = self.zero64.val();
            self.z2_s.next = self.zero64.val();
            self.z2_c.next = self.zero64.val();
            self.zsc.next = self.zero64.val();
            self.zn.next = self.zero32.val();
        }
        if self.d_v.q.val() {
            self.s1_s.d.next = self.z1_s.val() + self.d_es.q.val();
            self.s1_c.d.next = self.z1_c.val() + self.d_ec.q.val();
            self.s2_s.d.next = self.z2_s.val() + bit_cast::<64, 32>(self.p_ss.q.val());
            self.s2_c.d.next = self.z2_c.val() + bit_cast::<64, 32>(self.p_cc.q.val());
            self.ssc.d.next = self.zsc.val() + bit_cast::<64, 32>(self.p_sc.q.val());
            if self.d_nsc.q.val() {
                self.ssc.d.next = self.zsc.val() - bit_cast::<64, 32>(self.p_sc.q.val());
            }
            self.cnt.d.next = self.zn.val() + self.one32.val();
        }
        self.slv.start.next = self.d_v.q.val() & self.d_snap.q.val() & !self.slv.busy.val();
        self.slv.n.next = self.cnt.q.val();
        self.slv.s1_s.next = self.s1_s.q.val();
        self.slv.s1_c.next = self.s1_c.q.val();
        self.slv.s2_s.next = self.s2_s.q.val();
        self.slv.s2_c.next = self.s2_c.q.val();
        self.slv.ssc.next = self.ssc.q.val();
        self.slv.bref_s.next = self.bs_s.q.val();
        self.slv.bref_c.next = self.bs_c.q.val();
        if self.rst.val() {
            self.tinit.d.next = false;
            self.open.d.next = false;
            self.dknown.d.next = false;
            self.dneg.d.next = false;
            self.fresh.d.next = false;
            self.net.d.next = self.zero32.val();
            self.nb.d.next = self.zero32.val();
            self.bref_s.d.next = self.b0_s.val();
            self.bref_c.d.next = self.b0_c.val();
            self.c_v.d.next = false;
            self.d_v.d.next = false;
        }
        self.b_sin.next = self.slv.off_s.val();
        self.b_cos.next = self.slv.off_c.val();
        self.g_sin.next = self.slv.g_s.val();
        self.g_cos.next = self.slv.g_c.val();
        self.k_mag.next = self.slv.k_mag.val();
        self.k_neg.next = self.slv.k_neg.val();
        self.update.next = self.slv.done.val();
        self.kd_m.d.next = self.slv.k_mag.val();
        self.kd_n.d.next = self.slv.k_neg.val();
        self.k_mag_d.next = self.kd_m.q.val();
        self.k_neg_d.next = self.kd_n.q.val();
    }
}

crate::cosim::cosim_block!(FitCal {
    inputs: [rst: 1, valid: 1, x_sin: 16, x_cos: 16],
    outputs: [b_sin: 32, b_cos: 32, g_sin: 16, g_cos: 16, k_mag: 16, k_neg: 1, update: 1],
});
