//! rust-hdl description of the QEP decoder and the QEP/CORDIC cross-check (maths and
//! timing in the module docs of [`crate::blocks::qep`]).
use super::{CrossCheckParams, QepParams};
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// Synchronizers, glitch filters, x4 decoder and quadrant counter with index latch.
#[derive(LogicBlock)]
pub struct QepDecoder {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: count, index and flags to 0, filters to the inputs.
    pub rst: Signal<In, Bit>,
    /// QEP channel A from its comparator (asynchronous).
    pub qep_a: Signal<In, Bit>,
    /// QEP channel B from its comparator (asynchronous).
    pub qep_b: Signal<In, Bit>,
    /// QEP index Z from its comparator (asynchronous).
    pub qep_z: Signal<In, Bit>,
    /// Quadrant count, C-bit two's complement in the low bits (wraps modulo 2^C).
    pub count: Signal<Out, Bits<32>>,
    /// Count latched at the last rising edge of the filtered Z (C-bit two's complement).
    pub index_count: Signal<Out, Bits<32>>,
    /// One clock when `index_count` has just been latched.
    pub index_strobe: Signal<Out, Bit>,
    /// An index has been seen since reset (sticky).
    pub index_seen: Signal<Out, Bit>,
    /// One clock per double transition (A and B accepted in the same clock).
    pub illegal: Signal<Out, Bit>,
    /// A double transition has been seen since reset (sticky).
    pub illegal_seen: Signal<Out, Bit>,
    /// Filtered A level.
    pub a_filt: Signal<Out, Bit>,
    /// Filtered B level.
    pub b_filt: Signal<Out, Bit>,
    /// Filtered Z level.
    pub z_filt: Signal<Out, Bit>,
    /// `count` moved +1 at the last clock edge (registered beside `count_reg`).
    pub up: Signal<Out, Bit>,
    /// `count` moved -1 at the last clock edge (registered beside `count_reg`).
    pub down: Signal<Out, Bit>,
    a1: DFF<Bit>,
    a2: DFF<Bit>,
    b1: DFF<Bit>,
    b2: DFF<Bit>,
    z1: DFF<Bit>,
    z2: DFF<Bit>,
    af: DFF<Bit>,
    bf: DFF<Bit>,
    zf: DFF<Bit>,
    acnt: DFF<Bits<32>>,
    bcnt: DFF<Bits<32>>,
    zcnt: DFF<Bits<32>>,
    pa: DFF<Bit>,
    pb: DFF<Bit>,
    pz: DFF<Bit>,
    count_reg: DFF<Bits<32>>,
    icount_reg: DFF<Bits<32>>,
    istrobe_reg: DFF<Bit>,
    iseen_reg: DFF<Bit>,
    ill_reg: DFF<Bit>,
    illseen_reg: DFF<Bit>,
    /// The count's step at the last edge, +1 / -1 (the fallback's tracker reads these
    /// instead of decoding the count's low bits).
    up_reg: DFF<Bit>,
    down_reg: DFF<Bit>,
    da: Signal<Local, Bit>,
    db: Signal<Local, Bit>,
    count_n: Signal<Local, Bits<32>>,
    /// F-1: the filter counter value at which a new level is accepted.
    flast: Constant<Bits<32>>,
    /// Mask of the filter counter bits.
    fmask: Constant<Bits<32>>,
    /// Mask of the C count bits.
    cmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl QepDecoder {
    /// Decoder for `p`.
    pub fn new(p: &QepParams) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            qep_a: Default::default(),
            qep_b: Default::default(),
            qep_z: Default::default(),
            count: Default::default(),
            index_count: Default::default(),
            index_strobe: Default::default(),
            index_seen: Default::default(),
            illegal: Default::default(),
            illegal_seen: Default::default(),
            a_filt: Default::default(),
            b_filt: Default::default(),
            z_filt: Default::default(),
            up: Default::default(),
            down: Default::default(),
            a1: Default::default(),
            a2: Default::default(),
            b1: Default::default(),
            b2: Default::default(),
            z1: Default::default(),
            z2: Default::default(),
            af: Default::default(),
            bf: Default::default(),
            zf: Default::default(),
            acnt: Default::default(),
            bcnt: Default::default(),
            zcnt: Default::default(),
            pa: Default::default(),
            pb: Default::default(),
            pz: Default::default(),
            count_reg: Default::default(),
            icount_reg: Default::default(),
            istrobe_reg: Default::default(),
            iseen_reg: Default::default(),
            ill_reg: Default::default(),
            illseen_reg: Default::default(),
            up_reg: Default::default(),
            down_reg: Default::default(),
            da: Default::default(),
            db: Default::default(),
            count_n: Default::default(),
            flast: c32(p.filter() as u64 - 1),
            fmask: c32(mask(p.filter_bits())),
            cmask: c32(mask(p.count_width())),
            one: c32(1),
            zero: c32(0),
        }
    }
}

impl Logic for QepDecoder {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clk,
            a1,
            a2,
            b1,
            b2,
            z1,
            z2,
            af,
            bf,
            zf,
            acnt,
            bcnt,
            zcnt,
            pa,
            pb,
            pz,
            count_reg,
            icount_reg,
            istrobe_reg,
            iseen_reg,
            ill_reg,
            illseen_reg,
            up_reg,
            down_reg
        );
        // Two-flop synchronizers.
        self.a1.d.next = self.qep_a.val();
        self.a2.d.next = self.a1.q.val();
        self.b1.d.next = self.qep_b.val();
        self.b2.d.next = self.b1.q.val();
        self.z1.d.next = self.qep_z.val();
        self.z2.d.next = self.z1.q.val();
        // Glitch filters: accept a level seen for F consecutive clocks.
        if self.a2.q.val() == self.af.q.val() {
            self.acnt.d.next = self.zero.val();
        } else if self.acnt.q.val() == self.flast.val() {
            self.af.d.next = self.a2.q.val();
            self.acnt.d.next = self.zero.val();
        } else {
            self.acnt.d.next = (self.acnt.q.val() + self.one.val()) & self.fmask.val();
        }
        if self.b2.q.val() == self.bf.q.val() {
            self.bcnt.d.next = self.zero.val();
        } else if self.bcnt.q.val() == self.flast.val() {
            self.bf.d.next = self.b2.q.val();
            self.bcnt.d.next = self.zero.val();
        } else {
            self.bcnt.d.next = (self.bcnt.q.val() + self.one.val()) & self.fmask.val();
        }
        if self.z2.q.val() == self.zf.q.val() {
            self.zcnt.d.next = self.zero.val();
        } else if self.zcnt.q.val() == self.flast.val() {
            self.zf.d.next = self.z2.q.val();
            self.zcnt.d.next = self.zero.val();
        } else {
            self.zcnt.d.next = (self.zcnt.q.val() + self.one.val()) & self.fmask.val();
        }
        // x4 decoder: forward is 00 -> 10 -> 11 -> 01 (A leads B).
        self.pa.d.next = self.af.q.val();
        self.pb.d.next = self.bf.q.val();
        self.pz.d.next = self.zf.q.val();
        self.da.next = self.af.q.val() ^ self.pa.q.val();
        self.db.next = self.bf.q.val() ^ self.pb.q.val();
        // Holds are masked too, so Yosys sees the constant-zero upper bits.
        self.count_n.next = self.count_reg.q.val() & self.cmask.val();
        self.icount_reg.d.next = self.icount_reg.q.val() & self.cmask.val();
        self.ill_reg.d.next = false;
        self.up_reg.d.next = false;
        self.down_reg.d.next = false;
        if self.da.val() & self.db.val() {
            self.ill_reg.d.next = true;
            self.illseen_reg.d.next = true;
        } else if self.da.val() {
            if self.af.q.val() ^ self.bf.q.val() {
                self.count_n.next = (self.count_reg.q.val() + self.one.val()) & self.cmask.val();
                self.up_reg.d.next = true;
            } else {
                self.count_n.next = (self.count_reg.q.val() - self.one.val()) & self.cmask.val();
                self.down_reg.d.next = true;
            }
        } else if self.db.val() {
            if self.af.q.val() == self.bf.q.val() {
                self.count_n.next = (self.count_reg.q.val() + self.one.val()) & self.cmask.val();
                self.up_reg.d.next = true;
            } else {
                self.count_n.next = (self.count_reg.q.val() - self.one.val()) & self.cmask.val();
                self.down_reg.d.next = true;
            }
        }
        self.count_reg.d.next = self.count_n.val();
        // Index: latch on the rising edge of the filtered Z.
        self.istrobe_reg.d.next = false;
        if self.zf.q.val() & !self.pz.q.val() {
            self.icount_reg.d.next = self.count_n.val();
            self.istrobe_reg.d.next = true;
            self.iseen_reg.d.next = true;
        }
        if self.rst.val() {
            self.af.d.next = self.a2.q.val();
            self.bf.d.next = self.b2.q.val();
            self.zf.d.next = self.z2.q.val();
            self.pa.d.next = self.a2.q.val();
            self.pb.d.next = self.b2.q.val();
            self.pz.d.next = self.z2.q.val();
            self.acnt.d.next = self.zero.val();
            self.bcnt.d.next = self.zero.val();
            self.zcnt.d.next = self.zero.val();
            self.count_reg.d.next = self.zero.val();
            self.icount_reg.d.next = self.zero.val();
            self.istrobe_reg.d.next = false;
            self.iseen_reg.d.next = false;
            self.ill_reg.d.next = false;
            self.illseen_reg.d.next = false;
            self.up_reg.d.next = false;
            self.down_reg.d.next = false;
        }
        self.count.next = self.count_reg.q.val();
        self.index_count.next = self.icount_reg.q.val();
        self.index_strobe.next = self.istrobe_reg.q.val();
        self.index_seen.next = self.iseen_reg.q.val();
        self.illegal.next = self.ill_reg.q.val();
        self.illegal_seen.next = self.illseen_reg.q.val();
        self.a_filt.next = self.af.q.val();
        self.b_filt.next = self.bf.q.val();
        self.z_filt.next = self.zf.q.val();
        self.up.next = self.up_reg.q.val();
        self.down.next = self.down_reg.q.val();
    }
}

impl crate::cosim::step::Clocked for QepDecoder {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for QepDecoder {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("qep_a", 1),
            Port::new("qep_b", 1),
            Port::new("qep_z", 1),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("count", 32),
            Port::new("index_count", 32),
            Port::new("index_strobe", 1),
            Port::new("index_seen", 1),
            Port::new("illegal", 1),
            Port::new("illegal_seen", 1),
            Port::new("a_filt", 1),
            Port::new("b_filt", 1),
            Port::new("z_filt", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.qep_a.next = r[1] != 0;
        self.qep_b.next = r[2] != 0;
        self.qep_z.next = r[3] != 0;
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.count.val().to_u64(),
            self.index_count.val().to_u64(),
            self.index_strobe.val() as u64,
            self.index_seen.val() as u64,
            self.illegal.val() as u64,
            self.illegal_seen.val() as u64,
            self.a_filt.val() as u64,
            self.b_filt.val() as u64,
            self.z_filt.val() as u64,
        ]
    }
}

/// Cross-check of the QEP count against the CORDIC quadrant count.
#[derive(LogicBlock)]
pub struct QepCrossCheck {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: forget the alignment, clear the outputs.
    pub rst: Signal<In, Bit>,
    /// A CORDIC sample is present (compare this clock).
    pub valid: Signal<In, Bit>,
    /// Re-align: the next valid sample captures a new offset (diff = 0).
    pub align: Signal<In, Bit>,
    /// QEP count at the sample's instant (C-bit two's complement, wraps modulo 2^C).
    pub qep_count: Signal<In, Bits<32>>,
    /// CORDIC single-turn quadrant count, 0..Q-1 (Q = 4 PPR; bits above ceil(log2 Q) ignored).
    pub cordic_qc: Signal<In, Bits<32>>,
    /// |diff| > tolerance at the last valid sample.
    pub mismatch: Signal<Out, Bit>,
    /// QEP count minus CORDIC count since the alignment (C-bit two's complement).
    pub diff: Signal<Out, Bits<32>>,
    /// An alignment has been captured (the comparison is live).
    pub aligned: Signal<Out, Bit>,
    init: DFF<Bit>,
    qc_prev: DFF<Bits<32>>,
    cc: DFF<Bits<32>>,
    off: DFF<Bits<32>>,
    diff_reg: DFF<Bits<32>>,
    mis_reg: DFF<Bit>,
    qc: Signal<Local, Bits<32>>,
    step: Signal<Local, Bits<32>>,
    cc_n: Signal<Local, Bits<32>>,
    diff_n: Signal<Local, Bits<32>>,
    /// Q = 4 PPR.
    qturn: Constant<Bits<32>>,
    /// Mask of the bits of a count 0..Q-1.
    qmask: Constant<Bits<32>>,
    /// Q/2: steps beyond it are turn wraps.
    qhalf: Constant<Bits<32>>,
    /// Mask of the C count bits.
    cmask: Constant<Bits<32>>,
    /// Tolerance + 1: smallest positive mismatch.
    lo: Constant<Bits<32>>,
    /// 2^C - tolerance - 1: largest (C-bit unsigned) negative mismatch.
    hi: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl QepCrossCheck {
    /// Cross-check for `p`.
    pub fn new(p: &CrossCheckParams) -> Self {
        let c = p.count_width();
        let t = p.tolerance() as u64;
        Self {
            clk: Default::default(),
            rst: Default::default(),
            valid: Default::default(),
            align: Default::default(),
            qep_count: Default::default(),
            cordic_qc: Default::default(),
            mismatch: Default::default(),
            diff: Default::default(),
            aligned: Default::default(),
            init: Default::default(),
            qc_prev: Default::default(),
            cc: Default::default(),
            off: Default::default(),
            diff_reg: Default::default(),
            mis_reg: Default::default(),
            qc: Default::default(),
            step: Default::default(),
            cc_n: Default::default(),
            diff_n: Default::default(),
            qturn: c32(p.quadrants_per_turn()),
            qmask: c32(mask(64 - (p.quadrants_per_turn() - 1).leading_zeros())),
            qhalf: c32(p.quadrants_per_turn() / 2),
            cmask: c32(mask(c)),
            lo: c32(t + 1),
            hi: c32((1u64 << c) - t - 1),
            zero: c32(0),
        }
    }
}

impl Logic for QepCrossCheck {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, init, qc_prev, cc, off, diff_reg, mis_reg);
        self.qc.next = self.cordic_qc.val() & self.qmask.val();
        // Holds are masked too, so Yosys sees the constant-zero upper bits.
        self.qc_prev.d.next = self.qc_prev.q.val() & self.qmask.val();
        self.cc.d.next = self.cc.q.val() & self.cmask.val();
        self.off.d.next = self.off.q.val() & self.cmask.val();
        self.diff_reg.d.next = self.diff_reg.q.val() & self.cmask.val();
        // Unwrapped step of the single-turn count, in (-Q/2, Q/2].
        if self.qc.val() < self.qc_prev.q.val() {
            if (self.qc_prev.q.val() - self.qc.val()) > self.qhalf.val() {
                self.step.next = (self.qc.val() + self.qturn.val()) - self.qc_prev.q.val();
            } else {
                self.step.next = self.qc.val() - self.qc_prev.q.val();
            }
        } else if (self.qc.val() - self.qc_prev.q.val()) > self.qhalf.val() {
            self.step.next = (self.qc.val() - self.qturn.val()) - self.qc_prev.q.val();
        } else {
            self.step.next = self.qc.val() - self.qc_prev.q.val();
        }
        self.cc_n.next = (self.cc.q.val() + self.step.val()) & self.cmask.val();
        self.diff_n.next =
            (self.qep_count.val() - self.cc_n.val() - self.off.q.val()) & self.cmask.val();
        if self.valid.val() {
            if !self.init.q.val() {
                self.init.d.next = true;
                self.qc_prev.d.next = self.qc.val();
                self.cc.d.next = self.zero.val();
                self.off.d.next = self.qep_count.val() & self.cmask.val();
                self.diff_reg.d.next = self.zero.val();
                self.mis_reg.d.next = false;
            } else {
                self.qc_prev.d.next = self.qc.val();
                self.cc.d.next = self.cc_n.val();
                self.diff_reg.d.next = self.diff_n.val();
                self.mis_reg.d.next =
                    (self.diff_n.val() >= self.lo.val()) & (self.diff_n.val() <= self.hi.val());
            }
        }
        if self.align.val() {
            self.init.d.next = false;
        }
        if self.rst.val() {
            self.init.d.next = false;
            self.qc_prev.d.next = self.zero.val();
            self.cc.d.next = self.zero.val();
            self.off.d.next = self.zero.val();
            self.diff_reg.d.next = self.zero.val();
            self.mis_reg.d.next = false;
        }
        self.mismatch.next = self.mis_reg.q.val();
        self.diff.next = self.diff_reg.q.val();
        self.aligned.next = self.init.q.val();
    }
}

impl crate::cosim::step::Clocked for QepCrossCheck {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for QepCrossCheck {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("valid", 1),
            Port::new("align", 1),
            Port::new("qep_count", 32),
            Port::new("cordic_qc", 32),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("mismatch", 1),
            Port::new("diff", 32),
            Port::new("aligned", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.valid.next = r[1] != 0;
        self.align.next = r[2] != 0;
        self.qep_count.next = Bits::<32>::from(r[3]);
        self.cordic_qc.next = Bits::<32>::from(r[4]);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.mismatch.val() as u64,
            self.diff.val().to_u64(),
            self.aligned.val() as u64,
        ]
    }
}
