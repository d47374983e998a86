//! Bit-accurate models of the QEP decoder and the cross-check: the same registers as the
//! RTL, updated once per clock edge; `step` returns what the outputs show after the edge.
use super::{CrossCheckParams, QepParams};
use crate::blocks::mask;

/// Inputs of one clock cycle of the decoder.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QepIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Channel A level.
    pub a: bool,
    /// Channel B level.
    pub b: bool,
    /// Index Z level.
    pub z: bool,
}

impl QepIn {
    /// Stimulus row in [`crate::cosim::CosimBlock::input_ports`] order.
    pub fn row(&self) -> Vec<u64> {
        vec![self.rst as u64, self.a as u64, self.b as u64, self.z as u64]
    }
}

/// Outputs of the decoder after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QepOut {
    /// Quadrant count, C-bit raw (two's complement in the low C bits).
    pub count: u64,
    /// Count latched at the last index.
    pub index_count: u64,
    /// Index latched this clock.
    pub index_strobe: bool,
    /// Index seen since reset.
    pub index_seen: bool,
    /// Double transition this clock.
    pub illegal: bool,
    /// Double transition seen since reset.
    pub illegal_seen: bool,
    /// Filtered A.
    pub a_filt: bool,
    /// Filtered B.
    pub b_filt: bool,
    /// Filtered Z.
    pub z_filt: bool,
}

impl QepOut {
    /// Trace row in output-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.count,
            self.index_count,
            self.index_strobe as u64,
            self.index_seen as u64,
            self.illegal as u64,
            self.illegal_seen as u64,
            self.a_filt as u64,
            self.b_filt as u64,
            self.z_filt as u64,
        ]
    }
}

/// One synchronizer + glitch filter channel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Channel {
    s1: bool,
    s2: bool,
    f: bool,
    cnt: u64,
    prev: bool,
}

impl Channel {
    /// Next state (synchronizer, filter, previous level) for input `x`.
    fn next(&self, x: bool, flast: u64, fmask: u64, rst: bool) -> Channel {
        let mut n = *self;
        n.s1 = x;
        n.s2 = self.s1;
        n.prev = self.f;
        if self.s2 == self.f {
            n.cnt = 0;
        } else if self.cnt == flast {
            n.f = self.s2;
            n.cnt = 0;
        } else {
            n.cnt = (self.cnt + 1) & fmask;
        }
        if rst {
            n.f = self.s2;
            n.prev = self.s2;
            n.cnt = 0;
        }
        n
    }
}

/// Model of [`super::hdl::QepDecoder`].
#[derive(Clone, Debug)]
pub struct QepModel {
    flast: u64,
    fmask: u64,
    cmask: u64,
    a: Channel,
    b: Channel,
    z: Channel,
    out: QepOut,
}

impl QepModel {
    /// Model at power-up (every register 0).
    pub fn new(p: &QepParams) -> Self {
        Self {
            flast: p.filter() as u64 - 1,
            fmask: mask(p.filter_bits()),
            cmask: mask(p.count_width()),
            a: Channel::default(),
            b: Channel::default(),
            z: Channel::default(),
            out: QepOut::default(),
        }
    }

    /// One clock edge.
    pub fn step(&mut self, i: QepIn) -> QepOut {
        let (a, b, z) = (self.a, self.b, self.z);
        let da = a.f ^ a.prev;
        let db = b.f ^ b.prev;
        let c = self.out.count;
        let mut o = self.out;
        let mut count_n = c;
        o.illegal = false;
        if da && db {
            o.illegal = true;
            o.illegal_seen = true;
        } else if da {
            count_n = (if a.f != b.f { c + 1 } else { c.wrapping_sub(1) }) & self.cmask;
        } else if db {
            count_n = (if a.f == b.f { c + 1 } else { c.wrapping_sub(1) }) & self.cmask;
        }
        o.count = count_n;
        o.index_strobe = false;
        if z.f && !z.prev {
            o.index_count = count_n;
            o.index_strobe = true;
            o.index_seen = true;
        }
        self.a = a.next(i.a, self.flast, self.fmask, i.rst);
        self.b = b.next(i.b, self.flast, self.fmask, i.rst);
        self.z = z.next(i.z, self.flast, self.fmask, i.rst);
        if i.rst {
            o.count = 0;
            o.index_count = 0;
            o.index_strobe = false;
            o.index_seen = false;
            o.illegal = false;
            o.illegal_seen = false;
        }
        o.a_filt = self.a.f;
        o.b_filt = self.b.f;
        o.z_filt = self.z.f;
        self.out = o;
        o
    }
}

/// Inputs of one clock cycle of the cross-check.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CrossCheckIn {
    /// Synchronous reset.
    pub rst: bool,
    /// A CORDIC sample is present.
    pub valid: bool,
    /// Re-align at the next valid sample.
    pub align: bool,
    /// QEP count (C-bit raw; higher bits are ignored).
    pub qep_count: u64,
    /// CORDIC single-turn quadrant count 0..Q-1.
    pub cordic_qc: u64,
}

impl CrossCheckIn {
    /// Stimulus row in input-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.valid as u64,
            self.align as u64,
            self.qep_count & mask(32),
            self.cordic_qc & mask(32),
        ]
    }
}

/// Outputs of the cross-check after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CrossCheckOut {
    /// |diff| > tolerance.
    pub mismatch: bool,
    /// QEP minus CORDIC count since alignment, C-bit raw.
    pub diff: u64,
    /// Alignment captured.
    pub aligned: bool,
}

impl CrossCheckOut {
    /// Trace row in output-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![self.mismatch as u64, self.diff, self.aligned as u64]
    }
}

/// Model of [`super::hdl::QepCrossCheck`].
#[derive(Clone, Debug)]
pub struct CrossCheckModel {
    q: u64,
    qmask: u64,
    cmask: u64,
    lo: u64,
    hi: u64,
    init: bool,
    qc_prev: u64,
    cc: u64,
    off: u64,
    diff: u64,
    mismatch: bool,
}

impl CrossCheckModel {
    /// Model at power-up.
    pub fn new(p: &CrossCheckParams) -> Self {
        let c = p.count_width();
        let t = p.tolerance() as u64;
        Self {
            q: p.quadrants_per_turn(),
            qmask: mask(64 - (p.quadrants_per_turn() - 1).leading_zeros()),
            cmask: mask(c),
            lo: t + 1,
            hi: (1u64 << c) - t - 1,
            init: false,
            qc_prev: 0,
            cc: 0,
            off: 0,
            diff: 0,
            mismatch: false,
        }
    }

    /// One clock edge.
    pub fn step(&mut self, i: CrossCheckIn) -> CrossCheckOut {
        let m32 = mask(32);
        let (qc, prev) = (i.cordic_qc & self.qmask, self.qc_prev);
        let step = (if qc < prev {
            if prev - qc > self.q / 2 {
                (qc + self.q).wrapping_sub(prev)
            } else {
                qc.wrapping_sub(prev)
            }
        } else if qc - prev > self.q / 2 {
            qc.wrapping_sub(self.q).wrapping_sub(prev)
        } else {
            qc - prev
        }) & m32;
        let cc_n = (self.cc + step) & self.cmask;
        let diff_n = (i.qep_count & m32)
            .wrapping_sub(cc_n)
            .wrapping_sub(self.off)
            & self.cmask;
        if i.valid {
            if !self.init {
                self.init = true;
                self.qc_prev = qc;
                self.cc = 0;
                self.off = i.qep_count & self.cmask;
                self.diff = 0;
                self.mismatch = false;
            } else {
                self.qc_prev = qc;
                self.cc = cc_n;
                self.diff = diff_n;
                self.mismatch = diff_n >= self.lo && diff_n <= self.hi;
            }
        }
        if i.align {
            self.init = false;
        }
        if i.rst {
            self.init = false;
            self.qc_prev = 0;
            self.cc = 0;
            self.off = 0;
            self.diff = 0;
            self.mismatch = false;
        }
        CrossCheckOut {
            mismatch: self.mismatch,
            diff: self.diff,
            aligned: self.init,
        }
    }
}
