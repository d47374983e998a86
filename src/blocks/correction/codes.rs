//! The correction's codes as run-time registers (with `[registers]`,
//! [`super::CorrectionParams::with_writable`]): the offsets, gains and cross code the datapath
//! uses, which the register map reads as OFFSET_SIN, OFFSET_COS, GAIN_SIN, GAIN_COS and PHASE
//! and writes through a load port.
//!
//! ```text
//!  ld (one-hot per word), ld_bits, ld_msk ──► merge: (word & !msk) | bits ──┐
//!  cal_upd, cal_b, cal_g, cal_k (modes auto, peak) ─────────────────────────┤ priority:
//!  configured values ───────────────────────────────────────────────────────┤ rst > ld > cal
//!                                                                            ▼
//!                          [ob_s ob_c og_s og_c okm okn] ──► b, g, k in use (datapath)
//!                                     │                  ──► words (register map reads)
//!                                     └─► [kd_m kd_n]: k a clock later, with the sample's
//!                                         stage-1 registers (the phase stage's code)
//! ```
//!
//! # Words and bit growth (A = ADC width, GF = gain fraction bits)
//! * OFFSET_*: b in LSB, stored sign-extended to 32 bits. A write keeps the low A bits of the
//!   merged word and sign-extends bit A-1, so any 32-bit value is an offset modulo 2^A (the
//!   datapath's range); no other bits are stored.
//! * GAIN_*: g, UQ(16-GF).GF in bits 15..0 (bits 31..16 read 0 and are not stored).
//! * PHASE: the cross code k = round(2^GF g_s tan(phi)) as sign and magnitude, the way the
//!   phase stage takes it: |k| in bits 15..0, k < 0 in bit 16 (x_c' = g_c d_c + k d_s, with
//!   g_c carrying 1 / cos(phi); `docs/registers.md`). Mode `peak` has no phase stage: k stays 0.
//! * A write merges with the byte mask as the map's other RW registers do, so a byte write
//!   changes only its lane.
//!
//! # Timing
//! * Each clock: reset loads the configured values; else a load writes its word; else a
//!   calibration update (`cal_upd`, modes `auto` and `peak`) loads the calibration's
//!   values; else the registers hold. So a write is a start value that the calibration's
//!   next update replaces, and a write in the update's clock wins.
//! * The datapath reads the registers: a value loaded at edge k is used by samples
//!   presented before edge k + 1 and later; a calibration update is used one clock after
//!   the calibration's `update` (the registers sit between the calibration and stage 1).
use super::{CorrectionParams, COS, SIN};
use crate::blocks::{c32, fill, mask};
use rust_hdl::prelude::*;

/// The words of the writable codes, in load-port bit order: OFFSET_SIN, OFFSET_COS,
/// GAIN_SIN, GAIN_COS, PHASE (the register map's names).
pub const WORDS: [&str; 5] = ["OFFSET_SIN", "OFFSET_COS", "GAIN_SIN", "GAIN_COS", "PHASE"];

/// Bit of PHASE that holds k < 0 (|k| is in the bits below it).
pub const PHASE_SIGN_BIT: u32 = 16;

/// The PHASE word of a cross code k: |k| in bits 15..0, k < 0 in bit 16.
pub fn phase_word(k: i32) -> u32 {
    (k.unsigned_abs() & 0xffff) | u32::from(k < 0) << PHASE_SIGN_BIT
}

/// The cross code of a PHASE word (bits above 16 ignored).
pub fn phase_of(w: u32) -> i32 {
    let m = (w & 0xffff) as i32;
    if w >> PHASE_SIGN_BIT & 1 == 1 {
        -m
    } else {
        m
    }
}

/// The run-time code registers.
#[derive(LogicBlock)]
pub struct CodeRegs {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: the configured values.
    pub rst: Signal<In, Bit>,
    /// One clock: bit w loads word w of [`WORDS`] (at most one bit set).
    pub ld: Signal<In, Bits<8>>,
    /// The written bits (already masked by `ld_msk`).
    pub ld_bits: Signal<In, Bits<32>>,
    /// The bits written (the byte strobes as a mask).
    pub ld_msk: Signal<In, Bits<32>>,
    /// One clock: the calibration has new values on `cal_*` (0 in static mode).
    pub cal_upd: Signal<In, Bit>,
    /// The calibration's sine offset, A-bit two's complement in the low bits.
    pub cal_b_s: Signal<In, Bits<32>>,
    /// The calibration's cosine offset, A-bit two's complement in the low bits.
    pub cal_b_c: Signal<In, Bits<32>>,
    /// The calibration's sine gain.
    pub cal_g_s: Signal<In, Bits<16>>,
    /// The calibration's cosine gain.
    pub cal_g_c: Signal<In, Bits<16>>,
    /// The calibration's |k| (the fit's; 0 in mode peak).
    pub cal_k_mag: Signal<In, Bits<16>>,
    /// The calibration's k < 0.
    pub cal_k_neg: Signal<In, Bit>,
    /// Sine offset in use, A-bit two's complement in the low bits.
    pub b_s: Signal<Out, Bits<32>>,
    /// Cosine offset in use, A-bit two's complement in the low bits.
    pub b_c: Signal<Out, Bits<32>>,
    /// Sine gain in use.
    pub g_s: Signal<Out, Bits<16>>,
    /// Cosine gain in use.
    pub g_c: Signal<Out, Bits<16>>,
    /// |k| in use a clock late: the code of the sample in the datapath's stage 1.
    pub k_mag_d: Signal<Out, Bits<16>>,
    /// k < 0 with `k_mag_d`.
    pub k_neg_d: Signal<Out, Bit>,
    /// OFFSET_SIN as the map reads it (sign-extended).
    pub w_off_s: Signal<Out, Bits<32>>,
    /// OFFSET_COS as the map reads it.
    pub w_off_c: Signal<Out, Bits<32>>,
    /// GAIN_SIN as the map reads it.
    pub w_gain_s: Signal<Out, Bits<32>>,
    /// GAIN_COS as the map reads it.
    pub w_gain_c: Signal<Out, Bits<32>>,
    /// PHASE as the map reads it.
    pub w_phase: Signal<Out, Bits<32>>,
    /// The codes, initialized to the configured values (power-up equals reset).
    ob_s: DFFWithInit<Bits<32>>,
    ob_c: DFFWithInit<Bits<32>>,
    og_s: DFFWithInit<Bits<16>>,
    og_c: DFFWithInit<Bits<16>>,
    okm: DFFWithInit<Bits<16>>,
    okn: DFFWithInit<Bit>,
    kd_m: DFF<Bits<16>>,
    kd_n: DFF<Bit>,
    /// The PHASE word of the registers.
    wk: Signal<Local, Bits<32>>,
    /// Merged words before their sign extension / truncation.
    mb_s: Signal<Local, Bits<32>>,
    mb_c: Signal<Local, Bits<32>>,
    mg_s: Signal<Local, Bits<32>>,
    mg_c: Signal<Local, Bits<32>>,
    mk: Signal<Local, Bits<32>>,
    /// The calibration's offsets sign-extended.
    cb_s: Signal<Local, Bits<32>>,
    cb_c: Signal<Local, Bits<32>>,
    /// Mask of the A sample bits.
    amask: Constant<Bits<32>>,
    /// Bit A-1, the sample's sign.
    asign: Constant<Bits<32>>,
    /// Bits A..31.
    asext: Constant<Bits<32>>,
    /// Bits 15..0.
    m16: Constant<Bits<32>>,
    /// Bit 16 (PHASE's sign).
    ksign: Constant<Bits<32>>,
    /// One-hot bits of the load port.
    l_bs: Constant<Bits<8>>,
    l_bc: Constant<Bits<8>>,
    l_gs: Constant<Bits<8>>,
    l_gc: Constant<Bits<8>>,
    l_k: Constant<Bits<8>>,
    /// k can change (not mode peak).
    kw: Constant<Bit>,
    /// The configured values.
    b0_s: Constant<Bits<32>>,
    b0_c: Constant<Bits<32>>,
    g0_s: Constant<Bits<16>>,
    g0_c: Constant<Bits<16>>,
    k0_m: Constant<Bits<16>>,
    k0_n: Constant<Bit>,
    zero: Constant<Bits<32>>,
}

fn c8(v: u64) -> Constant<Bits<8>> {
    Constant::new(Bits::<8>::from(v & 0xff))
}

fn c16(v: u64) -> Constant<Bits<16>> {
    Constant::new(Bits::<16>::from(v & 0xffff))
}

impl CodeRegs {
    /// The registers for `p` (configured values from `p`).
    pub fn new(p: &CorrectionParams) -> Self {
        let a = p.adc_width();
        let w = p.reset_words();
        let k = phase_of(w[4]);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            ld: Default::default(),
            ld_bits: Default::default(),
            ld_msk: Default::default(),
            cal_upd: Default::default(),
            cal_b_s: Default::default(),
            cal_b_c: Default::default(),
            cal_g_s: Default::default(),
            cal_g_c: Default::default(),
            cal_k_mag: Default::default(),
            cal_k_neg: Default::default(),
            b_s: Default::default(),
            b_c: Default::default(),
            g_s: Default::default(),
            g_c: Default::default(),
            k_mag_d: Default::default(),
            k_neg_d: Default::default(),
            w_off_s: Default::default(),
            w_off_c: Default::default(),
            w_gain_s: Default::default(),
            w_gain_c: Default::default(),
            w_phase: Default::default(),
            ob_s: DFFWithInit::new(Bits::<32>::from(w[SIN] as u64)),
            ob_c: DFFWithInit::new(Bits::<32>::from(w[COS] as u64)),
            og_s: DFFWithInit::new(Bits::<16>::from(w[2] as u64)),
            og_c: DFFWithInit::new(Bits::<16>::from(w[3] as u64)),
            okm: DFFWithInit::new(Bits::<16>::from(k.unsigned_abs() as u64)),
            okn: DFFWithInit::new(k < 0),
            kd_m: Default::default(),
            kd_n: Default::default(),
            wk: Default::default(),
            mb_s: Default::default(),
            mb_c: Default::default(),
            mg_s: Default::default(),
            mg_c: Default::default(),
            mk: Default::default(),
            cb_s: Default::default(),
            cb_c: Default::default(),
            amask: c32(mask(a)),
            asign: c32(1 << (a - 1)),
            asext: c32(fill(32, 32 - a)),
            m16: c32(0xffff),
            ksign: c32(1 << PHASE_SIGN_BIT),
            l_bs: c8(1),
            l_bc: c8(2),
            l_gs: c8(4),
            l_gc: c8(8),
            l_k: c8(16),
            kw: Constant::new(p.auto().is_none()),
            b0_s: c32(w[SIN] as u64),
            b0_c: c32(w[COS] as u64),
            g0_s: c16(w[2] as u64),
            g0_c: c16(w[3] as u64),
            k0_m: c16(k.unsigned_abs() as u64),
            k0_n: Constant::new(k < 0),
            zero: c32(0),
        }
    }
}

impl Logic for CodeRegs {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, ob_s, ob_c, og_s, og_c, okm, okn, kd_m, kd_n);
        // The words as the map reads them.
        self.wk.next = bit_cast::<32, 16>(self.okm.q.val());
        if self.okn.q.val() {
            self.wk.next = bit_cast::<32, 16>(self.okm.q.val()) | self.ksign.val();
        }
        // A load merges its bits into the word; an offset keeps A bits, sign-extended.
        self.mb_s.next = (self.ob_s.q.val() & !self.ld_msk.val()) | self.ld_bits.val();
        if (self.mb_s.val() & self.asign.val()).any() {
            self.mb_s.next = self.mb_s.val() | self.asext.val();
        } else {
            self.mb_s.next = self.mb_s.val() & self.amask.val();
        }
        self.mb_c.next = (self.ob_c.q.val() & !self.ld_msk.val()) | self.ld_bits.val();
        if (self.mb_c.val() & self.asign.val()).any() {
            self.mb_c.next = self.mb_c.val() | self.asext.val();
        } else {
            self.mb_c.next = self.mb_c.val() & self.amask.val();
        }
        self.mg_s.next =
            (bit_cast::<32, 16>(self.og_s.q.val()) & !self.ld_msk.val()) | self.ld_bits.val();
        self.mg_c.next =
            (bit_cast::<32, 16>(self.og_c.q.val()) & !self.ld_msk.val()) | self.ld_bits.val();
        self.mk.next = (self.wk.val() & !self.ld_msk.val()) | self.ld_bits.val();
        self.cb_s.next = self.cal_b_s.val() & self.amask.val();
        if (self.cal_b_s.val() & self.asign.val()).any() {
            self.cb_s.next = self.cal_b_s.val() | self.asext.val();
        }
        self.cb_c.next = self.cal_b_c.val() & self.amask.val();
        if (self.cal_b_c.val() & self.asign.val()).any() {
            self.cb_c.next = self.cal_b_c.val() | self.asext.val();
        }
        // Priority: reset, then a load, then the calibration's update.
        if self.cal_upd.val() {
            self.ob_s.d.next = self.cb_s.val();
            self.ob_c.d.next = self.cb_c.val();
            self.og_s.d.next = self.cal_g_s.val();
            self.og_c.d.next = self.cal_g_c.val();
            if self.kw.val() {
                self.okm.d.next = self.cal_k_mag.val();
                self.okn.d.next = self.cal_k_neg.val();
            }
        }
        if (self.ld.val() & self.l_bs.val()).any() {
            self.ob_s.d.next = self.mb_s.val();
        }
        if (self.ld.val() & self.l_bc.val()).any() {
            self.ob_c.d.next = self.mb_c.val();
        }
        if (self.ld.val() & self.l_gs.val()).any() {
            self.og_s.d.next = bit_cast::<16, 32>(self.mg_s.val() & self.m16.val());
        }
        if (self.ld.val() & self.l_gc.val()).any() {
            self.og_c.d.next = bit_cast::<16, 32>(self.mg_c.val() & self.m16.val());
        }
        if (self.ld.val() & self.l_k.val()).any() & self.kw.val() {
            self.okm.d.next = bit_cast::<16, 32>(self.mk.val() & self.m16.val());
            self.okn.d.next = (self.mk.val() & self.ksign.val()).any();
        }
        if self.rst.val() {
            self.ob_s.d.next = self.b0_s.val();
            self.ob_c.d.next = self.b0_c.val();
            self.og_s.d.next = self.g0_s.val();
            self.og_c.d.next = self.g0_c.val();
            self.okm.d.next = self.k0_m.val();
            self.okn.d.next = self.k0_n.val();
        }
        self.kd_m.d.next = self.okm.q.val();
        self.kd_n.d.next = self.okn.q.val();
        self.b_s.next = self.ob_s.q.val() & self.amask.val();
        self.b_c.next = self.ob_c.q.val() & self.amask.val();
        self.g_s.next = self.og_s.q.val();
        self.g_c.next = self.og_c.q.val();
        self.k_mag_d.next = self.kd_m.q.val();
        self.k_neg_d.next = self.kd_n.q.val();
        self.w_off_s.next = self.ob_s.q.val();
        self.w_off_c.next = self.ob_c.q.val();
        self.w_gain_s.next = bit_cast::<32, 16>(self.og_s.q.val());
        self.w_gain_c.next = bit_cast::<32, 16>(self.og_c.q.val());
        self.w_phase.next = self.wk.val();
    }
}

/// The registers, clock by clock (the model of [`CodeRegs`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CodesModel {
    /// Offsets [sin, cos], sign-extended 32-bit words.
    pub b: [u32; 2],
    /// Gains [sin, cos].
    pub g: [u32; 2],
    /// Cross code.
    pub k: i32,
}

impl CodesModel {
    /// After power-up (the configured values; `k_d` 0 as the RTL's register).
    pub fn new(p: &CorrectionParams) -> Self {
        let w = p.reset_words();
        Self {
            b: [w[SIN], w[COS]],
            g: [w[2], w[3]],
            k: phase_of(w[4]),
        }
    }

    /// The five words the map reads ([`WORDS`] order).
    pub fn words(&self) -> [u32; 5] {
        [
            self.b[SIN],
            self.b[COS],
            self.g[SIN],
            self.g[COS],
            phase_word(self.k),
        ]
    }

    /// One edge: `ld` one-hot over [`WORDS`] with `bits` under `msk`; `cal` the
    /// calibration's (offsets as A-bit words, gains, k) when it updates.
    pub fn step(
        &mut self,
        p: &CorrectionParams,
        rst: bool,
        ld: u8,
        bits: u32,
        msk: u32,
        cal: Option<([u64; 2], [u64; 2], i32)>,
    ) {
        let a = p.adc_width();
        let sx = |v: u32| crate::blocks::sext(v as u64 & mask(a), a) as u32;
        let w = self.words();
        let merged = |i: usize| (w[i] & !msk) | bits;
        let kw = p.auto().is_none();
        if let Some((b, g, k)) = cal {
            self.b = [sx(b[SIN] as u32), sx(b[COS] as u32)];
            self.g = [g[SIN] as u32 & 0xffff, g[COS] as u32 & 0xffff];
            if kw {
                self.k = k;
            }
        }
        for i in 0..2 {
            if ld >> i & 1 == 1 {
                self.b[i] = sx(merged(i));
            }
            if ld >> (2 + i) & 1 == 1 {
                self.g[i] = merged(2 + i) & 0xffff;
            }
        }
        if ld >> 4 & 1 == 1 && kw {
            self.k = phase_of(merged(4));
        }
        if rst {
            *self = Self::new(p);
        }
    }
}
