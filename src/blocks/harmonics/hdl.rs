//! rust-hdl description of the harmonic-correction block (maths and sketch in the module
//! doc of `crate::blocks::harmonics`).
use super::{HarmonicParams, INTERP_BITS};
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// The table lookup, the interpolation and the subtraction, five register stages.
#[derive(LogicBlock)]
pub struct HarmonicCorrection {
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
    /// The corrected angle (ZW bits), five clocks after `z_in`.
    pub z_out: Signal<Out, Bits<32>>,
    /// `x_in` five clocks later.
    pub x_out: Signal<Out, Bits<32>>,
    /// `v_in` five clocks later.
    pub v_out: Signal<Out, Bit>,
    /// ROM_T XOR i: c_i 2^R - 2^(R-1) mod 2^W at segment i, stored XOR-ed with i and
    /// read back XOR-ed with the index. A compare per entry rather than a `case`, so that
    /// no synthesizer maps it to a block RAM (Yosys 0.23's M9K mapping of a ROM fails on
    /// Cyclone); the XOR keeps Yosys from reading the constants as resets of t1 (one
    /// P-bit reset condition, wider than the engine's 64-bit words).
    rom_t: Vec<Constant<Bits<32>>>,
    /// ROM_D XOR i: D_i = c_(i+1) - c_i mod 2^W at segment i, XOR-ed with i.
    rom_d: Vec<Constant<Bits<32>>>,
    /// The entry of the segment, still XOR-ed with its index.
    tx: Signal<Local, Bits<32>>,
    /// The slope of the segment, still XOR-ed with its index.
    dx: Signal<Local, Bits<32>>,
    /// The segment numbers 0..P the index is compared with.
    seg: Vec<Constant<Bits<32>>>,
    /// The segment of `z_in`: its top p bits.
    idx: Signal<Local, Bits<32>>,
    /// Stage 1: the angle, the entry and the slope of its segment.
    z1: DFF<Bits<32>>,
    t1: DFF<Bits<32>>,
    d1: DFF<Bits<32>>,
    x1: DFF<Bits<32>>,
    v1: DFF<Bit>,
    /// Stage 2: y = z 2^R - ROM_T, and the partial products in pairs (k = 0+1, 2+3, 4+5,
    /// 6+7).
    y2: DFF<Bits<32>>,
    s2a: DFF<Bits<32>>,
    s2b: DFF<Bits<32>>,
    s2c: DFF<Bits<32>>,
    s2d: DFF<Bits<32>>,
    x2: DFF<Bits<32>>,
    v2: DFF<Bit>,
    /// Stage 3: the pairs of pairs.
    y3: DFF<Bits<32>>,
    s3a: DFF<Bits<32>>,
    s3b: DFF<Bits<32>>,
    x3: DFF<Bits<32>>,
    v3: DFF<Bit>,
    /// Stage 4: D f, the sum of the partial products.
    y4: DFF<Bits<32>>,
    s4: DFF<Bits<32>>,
    x4: DFF<Bits<32>>,
    v4: DFF<Bit>,
    /// Stage 5: the corrected angle.
    z5: DFF<Bits<32>>,
    x5: DFF<Bits<32>>,
    v5: DFF<Bit>,
    /// f: the place within the segment (R bits) of stage 1's angle.
    f: Signal<Local, Bits<32>>,
    /// The partial products D 2^k where bit k of f is set, else 0.
    pp0: Signal<Local, Bits<32>>,
    pp1: Signal<Local, Bits<32>>,
    pp2: Signal<Local, Bits<32>>,
    pp3: Signal<Local, Bits<32>>,
    pp4: Signal<Local, Bits<32>>,
    pp5: Signal<Local, Bits<32>>,
    pp6: Signal<Local, Bits<32>>,
    pp7: Signal<Local, Bits<32>>,
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
    /// Mask of W = ZW + R bits (the sums).
    wmask: Constant<Bits<32>>,
    /// Mask of ZW bits (the angle).
    zmask: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
    /// The shifts 1..=7 of the partial products.
    k1: Constant<Bits<32>>,
    k2: Constant<Bits<32>>,
    k3: Constant<Bits<32>>,
    k4: Constant<Bits<32>>,
    k5: Constant<Bits<32>>,
    k6: Constant<Bits<32>>,
    k7: Constant<Bits<32>>,
}

/// The words as constants, word i XOR-ed with i.
fn rom(words: &[u64]) -> Vec<Constant<Bits<32>>> {
    words
        .iter()
        .enumerate()
        .map(|(i, &w)| c32(w ^ i as u64))
        .collect()
}

impl HarmonicCorrection {
    /// The block for `p`.
    pub fn new(p: &HarmonicParams) -> Self {
        let (zw, pb, r) = (p.z_width, p.points_log2, INTERP_BITS);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            z_in: Default::default(),
            x_in: Default::default(),
            v_in: Default::default(),
            z_out: Default::default(),
            x_out: Default::default(),
            v_out: Default::default(),
            rom_t: rom(&p.rom_t()),
            rom_d: rom(&p.rom_d()),
            tx: Default::default(),
            dx: Default::default(),
            seg: (0..p.points() as u64).map(c32).collect(),
            idx: Default::default(),
            z1: Default::default(),
            t1: Default::default(),
            d1: Default::default(),
            x1: Default::default(),
            v1: Default::default(),
            y2: Default::default(),
            s2a: Default::default(),
            s2b: Default::default(),
            s2c: Default::default(),
            s2d: Default::default(),
            x2: Default::default(),
            v2: Default::default(),
            y3: Default::default(),
            s3a: Default::default(),
            s3b: Default::default(),
            x3: Default::default(),
            v3: Default::default(),
            y4: Default::default(),
            s4: Default::default(),
            x4: Default::default(),
            v4: Default::default(),
            z5: Default::default(),
            x5: Default::default(),
            v5: Default::default(),
            f: Default::default(),
            pp0: Default::default(),
            pp1: Default::default(),
            pp2: Default::default(),
            pp3: Default::default(),
            pp4: Default::default(),
            pp5: Default::default(),
            pp6: Default::default(),
            pp7: Default::default(),
            ishift: c32((zw - pb) as u64),
            imask: c32(mask(pb)),
            fshift: c32((zw - pb - r) as u64),
            fmask: c32(mask(r)),
            rbits: c32(r as u64),
            wmask: c32(mask(zw + r)),
            zmask: c32(mask(zw)),
            zero: c32(0),
            k1: c32(1),
            k2: c32(2),
            k3: c32(3),
            k4: c32(4),
            k5: c32(5),
            k6: c32(6),
            k7: c32(7),
        }
    }
}

impl Logic for HarmonicCorrection {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, z1, t1, d1, x1, v1, y2, s2a, s2b, s2c, s2d, x2, v2, y3, s3a, s3b, x3, v3,
            y4, s4, x4, v4, z5, x5, v5
        );
        // Stage 1: the segment's entry and slope, looked up from the CORDIC's register.
        self.idx.next = (self.z_in.val() >> self.ishift.val()) & self.imask.val();
        self.z1.d.next = self.z_in.val();
        self.tx.next = self.zero.val();
        self.dx.next = self.zero.val();
        for i in 0..self.seg.len() {
            if self.idx.val() == self.seg[i].val() {
                self.tx.next = self.rom_t[i].val();
                self.dx.next = self.rom_d[i].val();
            }
        }
        self.t1.d.next = self.tx.val() ^ self.idx.val();
        self.d1.d.next = self.dx.val() ^ self.idx.val();
        self.x1.d.next = self.x_in.val();
        self.v1.d.next = self.v_in.val() & !self.rst.val();
        // Stage 2: y and the partial products of D f added in pairs.
        self.f.next = (self.z1.q.val() >> self.fshift.val()) & self.fmask.val();
        self.pp0.next = self.zero.val();
        self.pp1.next = self.zero.val();
        self.pp2.next = self.zero.val();
        self.pp3.next = self.zero.val();
        self.pp4.next = self.zero.val();
        self.pp5.next = self.zero.val();
        self.pp6.next = self.zero.val();
        self.pp7.next = self.zero.val();
        if self.f.val().get_bit(0) {
            self.pp0.next = self.d1.q.val();
        }
        if self.f.val().get_bit(1) {
            self.pp1.next = self.d1.q.val() << self.k1.val();
        }
        if self.f.val().get_bit(2) {
            self.pp2.next = self.d1.q.val() << self.k2.val();
        }
        if self.f.val().get_bit(3) {
            self.pp3.next = self.d1.q.val() << self.k3.val();
        }
        if self.f.val().get_bit(4) {
            self.pp4.next = self.d1.q.val() << self.k4.val();
        }
        if self.f.val().get_bit(5) {
            self.pp5.next = self.d1.q.val() << self.k5.val();
        }
        if self.f.val().get_bit(6) {
            self.pp6.next = self.d1.q.val() << self.k6.val();
        }
        if self.f.val().get_bit(7) {
            self.pp7.next = self.d1.q.val() << self.k7.val();
        }
        self.y2.d.next =
            ((self.z1.q.val() << self.rbits.val()) - self.t1.q.val()) & self.wmask.val();
        self.s2a.d.next = (self.pp0.val() + self.pp1.val()) & self.wmask.val();
        self.s2b.d.next = (self.pp2.val() + self.pp3.val()) & self.wmask.val();
        self.s2c.d.next = (self.pp4.val() + self.pp5.val()) & self.wmask.val();
        self.s2d.d.next = (self.pp6.val() + self.pp7.val()) & self.wmask.val();
        self.x2.d.next = self.x1.q.val();
        self.v2.d.next = self.v1.q.val() & !self.rst.val();
        // Stage 3: pairs of pairs.
        self.y3.d.next = self.y2.q.val();
        self.s3a.d.next = (self.s2a.q.val() + self.s2b.q.val()) & self.wmask.val();
        self.s3b.d.next = (self.s2c.q.val() + self.s2d.q.val()) & self.wmask.val();
        self.x3.d.next = self.x2.q.val();
        self.v3.d.next = self.v2.q.val() & !self.rst.val();
        // Stage 4: D f.
        self.y4.d.next = self.y3.q.val();
        self.s4.d.next = (self.s3a.q.val() + self.s3b.q.val()) & self.wmask.val();
        self.x4.d.next = self.x3.q.val();
        self.v4.d.next = self.v3.q.val() & !self.rst.val();
        // Stage 5: z' = (y - D f) >> R modulo 2^ZW.
        self.z5.d.next = (((self.y4.q.val() - self.s4.q.val()) & self.wmask.val())
            >> self.rbits.val())
            & self.zmask.val();
        self.x5.d.next = self.x4.q.val();
        self.v5.d.next = self.v4.q.val() & !self.rst.val();
        self.z_out.next = self.z5.q.val();
        self.x_out.next = self.x5.q.val();
        self.v_out.next = self.v5.q.val();
    }
}

impl crate::cosim::step::Clocked for HarmonicCorrection {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for HarmonicCorrection {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("z_in", 32),
            Port::new("x_in", 32),
            Port::new("v_in", 1),
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
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.z_out.val().to_u64(),
            self.x_out.val().to_u64(),
            self.v_out.val() as u64,
        ]
    }
}
