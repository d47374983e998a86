//! rust-hdl description of the harmonic-correction block with its table in RAM, for the
//! learned table (`[harmonics] mode = "learn"`; maths in the module doc of
//! `crate::blocks::harmonics`, "The table in RAM").
//!
//! ```text
//!  tw, tw_addr, tw_data ──► (q ^ m) + half - m >> s ──reg──► RAM_A[bank P + i], RAM_B[...]
//!  (the learner's writes,     (q units to z units)           (one copy each)
//!   q units)
//!            ┌────────────────┐    ┌──────────────┐    ┌────────────┐ a=c_i ┌──────────────┐ y, D ┌───────────┐ s0..s3 ┌───────┐    ┌──────┐    ┌─────────┐
//!  z_in ────►│ RAM_A[b,idx]   │───►│ 4 arrays'    │───►│ 4:1 select │──────►│ y=(z-a)<<R|h │─────►│ 8 partial │───────►│ add   │───►│ add  │───►│ y - sum │─► z_out
//!  (ZW b)    │ RAM_B[b,idx+1] │    │ words q_k    │    │ & ZW: a, b │ b=c_j │ D=b-a (sext) │ f    │ products, │        │ pairs │    │ pair │    │ >> R    │
//!            │ (the address)  │    │ (in the RAM) │    │ (0: Clear) │       │              │      │ pairs     │        │       │    │      │    │         │
//!            └──reg───────────┘    └──reg─────────┘    └──reg───────┘       └──reg─────────┘      └──reg──────┘        └──reg──┘    └──reg─┘    └──reg────┘
//!  cycle:     1                     1q                  1r                   2                     3                    4            5           6
//! ```
//!
//! The RAMs are [`PipedLutRam`]s (four arrays of 64 words): stage 1 registers the read
//! address, stage 1q the four arrays' words at it (`q_k`, inside the RAM), and stage 1r
//! the word the address's top two bits select, masked to ZW bits (synthesis drops the
//! unused columns) and zeroed during the Clear: the word a
//! [`LutRam`](crate::blocks::lutram::LutRam) gives a clock earlier (the arrays are read at
//! the same edge), so the block is the one-clock read's, a clock later.
use super::{HarmonicParams, INTERP_BITS};
use crate::blocks::lutram::PipedLutRam;
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// Address bits of a table RAM: the bank in bit p, the entry in bits p-1..0 (P <= 128).
pub const RAM_ADDR_BITS: usize = 8;

/// Bits of a RAM word: the entry in z units modulo 2^ZW (ZW <= 24) in the low bits, the
/// only ones read (synthesis drops the other columns). 36 is a Cyclone M9K's widest mode;
/// each of a RAM's four 64-word arrays is one M9K.
pub const RAM_WORD_BITS: usize = 36;

/// The most entries a learned table has: two banks of P in the RAM's 256 words.
pub const MAX_POINTS: u32 = 128;

/// The table lookup from RAM, the interpolation and the subtraction, eight register stages
/// ([`HarmonicParams::LATENCY_RAM`]).
#[derive(LogicBlock)]
pub struct HarmonicCorrectionRam {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset: clears the valid bits in flight.
    pub rst: Signal<In, Bit>,
    /// The CORDIC's angle word (ZW bits, z units).
    pub z_in: Signal<In, Bits<32>>,
    /// The CORDIC's magnitude, carried along.
    pub x_in: Signal<In, Bits<32>>,
    /// The sample is valid.
    pub v_in: Signal<In, Bit>,
    /// The bank of the table the lookup reads.
    pub bank: Signal<In, Bit>,
    /// The learner is writing the start table after a reset (its Clear): the lookup uses
    /// zeros, since the RAMs hold nothing known before (they have no initial contents).
    pub clearing: Signal<In, Bit>,
    /// Write an entry this clock.
    pub tw: Signal<In, Bit>,
    /// The entry written: bank * P + i.
    pub tw_addr: Signal<In, Bits<32>>,
    /// Its value, q units (2^-T LSB), two's complement in the learner's entry width.
    pub tw_data: Signal<In, Bits<32>>,
    /// The corrected angle (ZW bits), eight clocks after `z_in`.
    pub z_out: Signal<Out, Bits<32>>,
    /// `x_in` eight clocks later.
    pub x_out: Signal<Out, Bits<32>>,
    /// `v_in` eight clocks later.
    pub v_out: Signal<Out, Bit>,
    /// c_i (z units mod 2^ZW) at {bank, i}, read at the segment over two clocks.
    ram_a: PipedLutRam<Bits<RAM_WORD_BITS>, RAM_ADDR_BITS>,
    /// The same table, read at the next segment (i + 1 mod P).
    ram_b: PipedLutRam<Bits<RAM_WORD_BITS>, RAM_ADDR_BITS>,
    /// The write stage: the entry converted to z units, its RAM address, the enable.
    wd: DFF<Bits<32>>,
    wa: DFF<Bits<32>>,
    we: DFF<Bit>,
    /// The segment of `z_in` (its top p bits) and the next one, with the bank.
    idx: Signal<Local, Bits<32>>,
    nxt: Signal<Local, Bits<32>>,
    /// The bank's offset in a RAM address (0 or P).
    boff: Signal<Local, Bits<32>>,
    /// `clearing` a clock late: the Clear's last write reaches the RAMs a clock after it
    /// (the write stage), and a read in that clock still sees the word before it.
    cl: DFF<Bit>,
    /// Stage 1: the angle (the RAMs' read addresses registered), and whether the RAMs
    /// were read during the Clear or the clock after it.
    z1: DFF<Bits<32>>,
    c1: DFF<Bit>,
    x1: DFF<Bits<32>>,
    v1: DFF<Bit>,
    /// Stage 1q: the RAMs' arrays read into their registers (inside [`PipedLutRam`]); the
    /// angle, the clearing flag and the valid bits carried along.
    zq: DFF<Bits<32>>,
    cq: DFF<Bit>,
    xq: DFF<Bits<32>>,
    vq: DFF<Bit>,
    /// v1 a clock later, which a reset does not clear: an invalid sample's words are zeroed
    /// by the valid bit it entered with, as the model does.
    vzq: DFF<Bit>,
    /// Stage 1r: c_i and c_(i+1), the RAMs' selected words registered (zeros during the
    /// Clear), so that no adder follows a RAM read in one clock (the read path,
    /// docs/timing.md).
    ar: DFF<Bits<32>>,
    br: DFF<Bits<32>>,
    zr: DFF<Bits<32>>,
    xr: DFF<Bits<32>>,
    vr: DFF<Bit>,
    /// vzq a clock later (v1 two clocks later, not cleared by a reset).
    vz: DFF<Bit>,
    /// c_i and c_(i+1) of stage 1q: the RAMs' read data in ZW bits, or zeros during the
    /// Clear.
    ca: Signal<Local, Bits<32>>,
    cb: Signal<Local, Bits<32>>,
    /// The slope c_(i+1) - c_i modulo 2^ZW, before its sign fill.
    dz: Signal<Local, Bits<32>>,
    /// Stage 2: y = (z - c_i) 2^R + 2^(R-1), the slope D sign-filled to W bits, f.
    y2: DFF<Bits<32>>,
    d2: DFF<Bits<32>>,
    f2: DFF<Bits<32>>,
    x2: DFF<Bits<32>>,
    v2: DFF<Bit>,
    /// Stage 3: y and the partial products in pairs (k = 0+1, 2+3, 4+5, 6+7).
    y3: DFF<Bits<32>>,
    s3a: DFF<Bits<32>>,
    s3b: DFF<Bits<32>>,
    s3c: DFF<Bits<32>>,
    s3d: DFF<Bits<32>>,
    x3: DFF<Bits<32>>,
    v3: DFF<Bit>,
    /// Stage 4: the pairs of pairs.
    y4: DFF<Bits<32>>,
    s4a: DFF<Bits<32>>,
    s4b: DFF<Bits<32>>,
    x4: DFF<Bits<32>>,
    v4: DFF<Bit>,
    /// Stage 5: D f.
    y5: DFF<Bits<32>>,
    s5: DFF<Bits<32>>,
    x5: DFF<Bits<32>>,
    v5: DFF<Bit>,
    /// Stage 6: the corrected angle.
    z6: DFF<Bits<32>>,
    x6: DFF<Bits<32>>,
    v6: DFF<Bit>,
    /// The partial products D 2^k where bit k of f is set, else 0.
    pp: Vec<Signal<Local, Bits<32>>>,
    /// The shifts 0..=7 of the partial products.
    kk: Vec<Constant<Bits<32>>>,
    /// m = 2^(E-1), E the learner's entry width: (q ^ m) - m sign-fills q.
    emask: Constant<Bits<32>>,
    /// 2^(s-1) - m modulo 2^32 (s = T - Gz): the sign fill and the rounding half at once.
    ekadd: Constant<Bits<32>>,
    /// s = T - Gz: q units to z units.
    eshift: Constant<Bits<32>>,
    /// P: bank 1's offset in a RAM address.
    bankbit: Constant<Bits<32>>,
    /// Mask of p + 1 bits (a RAM address: the bank and the entry).
    amask: Constant<Bits<32>>,
    /// ZW - p: the shift of the segment index out of z.
    ishift: Constant<Bits<32>>,
    /// Mask of p bits (the index).
    imask: Constant<Bits<32>>,
    /// ZW - p - R: the shift of f out of z.
    fshift: Constant<Bits<32>>,
    /// Mask of R bits (f).
    fmask: Constant<Bits<32>>,
    /// R: the interpolation's fraction bits.
    rbits: Constant<Bits<32>>,
    /// 2^(R-1): the rounding half.
    rhalf: Constant<Bits<32>>,
    /// Mask of W = ZW + R bits (the sums).
    wmask: Constant<Bits<32>>,
    /// Mask of ZW bits (the angle).
    zmask: Constant<Bits<32>>,
    /// The bits W-1..ZW, set to fill the sign of a ZW-bit slope.
    dfill: Constant<Bits<32>>,
    /// 2^(ZW-1): the sign bit of a ZW-bit slope.
    dsign: Constant<Bits<32>>,
    /// Zero and one.
    zero: Constant<Bits<32>>,
    one: Constant<Bits<32>>,
}

impl HarmonicCorrectionRam {
    /// The block for `p`; `entry_width` E is the width of the learner's entries on
    /// `tw_data`. The RAMs start empty: the learner's Clear writes the start table (Yosys
    /// 0.23 cannot map a RAM with initial contents to Cyclone's M9K).
    pub fn new(p: &HarmonicParams, entry_width: u32) -> Self {
        let (zw, pb, r) = (p.z_width, p.points_log2, INTERP_BITS);
        let s = super::sequencer::TABLE_FRAC - p.z_guard;
        let m = 1u64 << (entry_width - 1);
        let half = if s == 0 { 0 } else { 1u64 << (s - 1) };
        Self {
            clk: Default::default(),
            rst: Default::default(),
            z_in: Default::default(),
            x_in: Default::default(),
            v_in: Default::default(),
            bank: Default::default(),
            clearing: Default::default(),
            tw: Default::default(),
            tw_addr: Default::default(),
            tw_data: Default::default(),
            z_out: Default::default(),
            x_out: Default::default(),
            v_out: Default::default(),
            ram_a: Default::default(),
            ram_b: Default::default(),
            wd: Default::default(),
            wa: Default::default(),
            we: Default::default(),
            idx: Default::default(),
            nxt: Default::default(),
            boff: Default::default(),
            z1: Default::default(),
            cl: Default::default(),
            c1: Default::default(),
            x1: Default::default(),
            v1: Default::default(),
            zq: Default::default(),
            cq: Default::default(),
            xq: Default::default(),
            vq: Default::default(),
            vzq: Default::default(),
            ar: Default::default(),
            br: Default::default(),
            zr: Default::default(),
            xr: Default::default(),
            vr: Default::default(),
            vz: Default::default(),
            ca: Default::default(),
            cb: Default::default(),
            dz: Default::default(),
            y2: Default::default(),
            d2: Default::default(),
            f2: Default::default(),
            x2: Default::default(),
            v2: Default::default(),
            y3: Default::default(),
            s3a: Default::default(),
            s3b: Default::default(),
            s3c: Default::default(),
            s3d: Default::default(),
            x3: Default::default(),
            v3: Default::default(),
            y4: Default::default(),
            s4a: Default::default(),
            s4b: Default::default(),
            x4: Default::default(),
            v4: Default::default(),
            y5: Default::default(),
            s5: Default::default(),
            x5: Default::default(),
            v5: Default::default(),
            z6: Default::default(),
            x6: Default::default(),
            v6: Default::default(),
            pp: (0..r).map(|_| Default::default()).collect(),
            kk: (0..u64::from(r)).map(c32).collect(),
            emask: c32(m),
            ekadd: c32(half.wrapping_sub(m)),
            eshift: c32(u64::from(s)),
            bankbit: c32(1 << pb),
            amask: c32(mask(pb + 1)),
            ishift: c32(u64::from(zw - pb)),
            imask: c32(mask(pb)),
            fshift: c32(u64::from(zw - pb - r)),
            fmask: c32(mask(r)),
            rbits: c32(u64::from(r)),
            rhalf: c32(1 << (r - 1)),
            wmask: c32(mask(zw + r)),
            zmask: c32(mask(zw)),
            dfill: c32(mask(zw + r) & !mask(zw)),
            dsign: c32(1 << (zw - 1)),
            zero: c32(0),
            one: c32(1),
        }
    }
}

impl Logic for HarmonicCorrectionRam {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, wd, wa, we, cl, z1, c1, x1, v1, zq, cq, xq, vq, vzq, ar, br, zr, xr, vr, vz,
            y2, d2, f2, x2, v2, y3, s3a, s3b, s3c, s3d, x3, v3, y4, s4a, s4b, x4, v4, y5, s5, x5,
            v5, z6, x6, v6
        );
        // The write stage: the learner's entry in z units, rounded half up (a sign fill
        // and the half in one adder), at {bank, i} = bank P + i, as `tw_addr` holds it.
        self.wd.d.next = (((self.tw_data.val() ^ self.emask.val()) + self.ekadd.val())
            >> self.eshift.val())
            & self.zmask.val();
        self.wa.d.next = self.tw_addr.val() & self.amask.val();
        self.we.d.next = self.tw.val();
        self.ram_a.clock.next = self.clk.val();
        self.ram_b.clock.next = self.clk.val();
        self.ram_a.write_enable.next = self.we.q.val();
        self.ram_b.write_enable.next = self.we.q.val();
        self.ram_a.write_address.next = bit_cast::<RAM_ADDR_BITS, 32>(self.wa.q.val());
        self.ram_b.write_address.next = bit_cast::<RAM_ADDR_BITS, 32>(self.wa.q.val());
        self.ram_a.write_data.next = bit_cast::<RAM_WORD_BITS, 32>(self.wd.q.val());
        self.ram_b.write_data.next = bit_cast::<RAM_WORD_BITS, 32>(self.wd.q.val());
        // Stage 1: the addresses of c_i and c_(i+1 mod P) of the bank, from the CORDIC's
        // register.
        self.idx.next = (self.z_in.val() >> self.ishift.val()) & self.imask.val();
        self.nxt.next = (self.idx.val() + self.one.val()) & self.imask.val();
        self.boff.next = self.zero.val();
        if self.bank.val() {
            self.boff.next = self.bankbit.val();
        }
        self.ram_a.read_address.next =
            bit_cast::<RAM_ADDR_BITS, 32>(self.boff.val() | self.idx.val());
        self.ram_b.read_address.next =
            bit_cast::<RAM_ADDR_BITS, 32>(self.boff.val() | self.nxt.val());
        self.z1.d.next = self.z_in.val();
        self.cl.d.next = self.clearing.val();
        self.c1.d.next = self.clearing.val() | self.cl.q.val();
        self.x1.d.next = self.x_in.val();
        self.v1.d.next = self.v_in.val() & !self.rst.val();
        // Stage 1q: the RAMs read their arrays into their registers; the rest follows.
        self.zq.d.next = self.z1.q.val();
        self.cq.d.next = self.c1.q.val();
        self.xq.d.next = self.x1.q.val();
        self.vq.d.next = self.v1.q.val() & !self.rst.val();
        self.vzq.d.next = self.v1.q.val();
        // Stage 1r: the selected words registered, in ZW bits.
        self.ca.next = bit_cast::<32, RAM_WORD_BITS>(self.ram_a.read_data.val()) & self.zmask.val();
        self.cb.next = bit_cast::<32, RAM_WORD_BITS>(self.ram_b.read_data.val()) & self.zmask.val();
        if self.cq.q.val() {
            self.ca.next = self.zero.val();
            self.cb.next = self.zero.val();
        }
        self.ar.d.next = self.ca.val();
        self.br.d.next = self.cb.val();
        self.zr.d.next = self.zq.q.val();
        self.xr.d.next = self.xq.q.val();
        self.vr.d.next = self.vq.q.val() & !self.rst.val();
        self.vz.d.next = self.vzq.q.val();
        // Stage 2: y = (z - c_i) 2^R + 2^(R-1) and D = c_(i+1) - c_i, sign-filled to W bits.
        self.y2.d.next = ((((self.zr.q.val() - self.ar.q.val()) & self.zmask.val())
            << self.rbits.val())
            | self.rhalf.val())
            & self.wmask.val();
        self.dz.next = (self.br.q.val() - self.ar.q.val()) & self.zmask.val();
        self.d2.d.next = self.dz.val();
        if (self.dz.val() & self.dsign.val()) != self.zero.val() {
            self.d2.d.next = self.dz.val() | self.dfill.val();
        }
        // No sample: zeros, so that the RAMs' read registers (unknown in Verilog until
        // their first read) never reach z_out.
        if !self.vz.q.val() {
            self.y2.d.next = self.zero.val();
            self.d2.d.next = self.zero.val();
        }
        self.f2.d.next = (self.zr.q.val() >> self.fshift.val()) & self.fmask.val();
        self.x2.d.next = self.xr.q.val();
        self.v2.d.next = self.vr.q.val() & !self.rst.val();
        // Stage 3: the partial products of D f added in pairs.
        for k in 0..self.pp.len() {
            self.pp[k].next = self.zero.val();
            if self.f2.q.val().get_bit(k) {
                self.pp[k].next = self.d2.q.val() << self.kk[k].val();
            }
        }
        self.y3.d.next = self.y2.q.val();
        self.s3a.d.next = (self.pp[0].val() + self.pp[1].val()) & self.wmask.val();
        self.s3b.d.next = (self.pp[2].val() + self.pp[3].val()) & self.wmask.val();
        self.s3c.d.next = (self.pp[4].val() + self.pp[5].val()) & self.wmask.val();
        self.s3d.d.next = (self.pp[6].val() + self.pp[7].val()) & self.wmask.val();
        self.x3.d.next = self.x2.q.val();
        self.v3.d.next = self.v2.q.val() & !self.rst.val();
        // Stage 4: pairs of pairs.
        self.y4.d.next = self.y3.q.val();
        self.s4a.d.next = (self.s3a.q.val() + self.s3b.q.val()) & self.wmask.val();
        self.s4b.d.next = (self.s3c.q.val() + self.s3d.q.val()) & self.wmask.val();
        self.x4.d.next = self.x3.q.val();
        self.v4.d.next = self.v3.q.val() & !self.rst.val();
        // Stage 5: D f.
        self.y5.d.next = self.y4.q.val();
        self.s5.d.next = (self.s4a.q.val() + self.s4b.q.val()) & self.wmask.val();
        self.x5.d.next = self.x4.q.val();
        self.v5.d.next = self.v4.q.val() & !self.rst.val();
        // Stage 6: z' = (y - D f) >> R modulo 2^ZW.
        self.z6.d.next = (((self.y5.q.val() - self.s5.q.val()) & self.wmask.val())
            >> self.rbits.val())
            & self.zmask.val();
        self.x6.d.next = self.x5.q.val();
        self.v6.d.next = self.v5.q.val() & !self.rst.val();
        self.z_out.next = self.z6.q.val();
        self.x_out.next = self.x6.q.val();
        self.v_out.next = self.v6.q.val();
    }
}

impl crate::cosim::step::Clocked for HarmonicCorrectionRam {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for HarmonicCorrectionRam {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("z_in", 32),
            Port::new("x_in", 32),
            Port::new("v_in", 1),
            Port::new("bank", 1),
            Port::new("clearing", 1),
            Port::new("tw", 1),
            Port::new("tw_addr", 32),
            Port::new("tw_data", 32),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("z_out", 32),
            Port::new("x_out", 32),
            Port::new("v_out", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.z_in.next = Bits::<32>::from(r[1]);
        self.x_in.next = Bits::<32>::from(r[2]);
        self.v_in.next = r[3] != 0;
        self.bank.next = r[4] != 0;
        self.clearing.next = r[5] != 0;
        self.tw.next = r[6] != 0;
        self.tw_addr.next = Bits::<32>::from(r[7]);
        self.tw_data.next = Bits::<32>::from(r[8]);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.z_out.val().to_u64(),
            self.x_out.val().to_u64(),
            self.v_out.val() as u64,
        ]
    }
}
