//! Bit-accurate model of the ABZ emulator: the same registers as the RTL, updated once per
//! clock edge; `step` returns what the outputs show after the edge.
use super::AbzParams;
use crate::blocks::mask;

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AbzIn {
    /// Synchronous reset.
    pub rst: bool,
    /// A position sample is present.
    pub valid: bool,
    /// Quadrant count 0..Q-1 (bits above ceil(log2 Q) ignored).
    pub qc: u64,
    /// Fine position 0..2^F-1 (bits above F ignored).
    pub fine: u64,
}

impl AbzIn {
    /// Stimulus row in [`crate::cosim::CosimBlock::input_ports`] order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.valid as u64,
            self.qc & mask(32),
            self.fine & mask(32),
        ]
    }
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AbzOut {
    /// Channel A.
    pub a: bool,
    /// Channel B.
    pub b: bool,
    /// Index Z.
    pub z: bool,
    /// Catching up: a sample arrived while counts of the previous one were still owed.
    pub warning: bool,
}

impl AbzOut {
    /// Trace row in output-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.a as u64,
            self.b as u64,
            self.z as u64,
            self.warning as u64,
        ]
    }
}

/// The registers (names as in the RTL).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Regs {
    have: bool,
    qcap: u64,
    fcap: u64,
    busy: bool,
    pbit: bool,
    qsh: u64,
    fsh: u64,
    cnt: u64,
    r: u64,
    t: u64,
    done: bool,
    init: bool,
    told: u64,
    d: u64,
    s1: bool,
    d2: u64,
    fh: bool,
    fl: bool,
    s2: bool,
    dd: u64,
    incp: bool,
    incd: bool,
    pend: u64,
    pnz: bool,
    pn: bool,
    p1: bool,
    stepped: bool,
    hold: bool,
    tm: u64,
    c: u64,
    ctop: bool,
    czero: bool,
    a: bool,
    b: bool,
    z: bool,
    warn: bool,
}

/// Model of [`super::hdl::AbzEmulator`].
#[derive(Clone, Debug)]
pub struct AbzModel {
    qmask: u64,
    fmask: u64,
    qtop: u64,
    ftop: u64,
    wp: u64,
    a: u64,
    b: u64,
    e: u64,
    half: u64,
    s: u64,
    tmask: u64,
    r: Regs,
}

const M32: u64 = 0xffff_ffff;
const SIGN: u64 = 1 << 31;

impl AbzModel {
    /// Model at power-up (every register 0).
    pub fn new(p: &AbzParams) -> Self {
        let (a, b) = p.ratio();
        let qb = p.quadrant_bits();
        Self {
            qmask: mask(qb),
            fmask: mask(p.fine_bits()),
            qtop: 1 << (qb - 1),
            ftop: 1 << (p.fine_bits() - 1),
            wp: p.position_bits() as u64,
            a,
            b,
            e: p.edges(),
            half: p.edges() / 2,
            s: p.spacing() as u64,
            tmask: mask(p.timer_bits()),
            r: Regs::default(),
        }
    }

    /// One clock edge.
    pub fn step(&mut self, i: AbzIn) -> AbzOut {
        let q = self.r;
        let mut n = q;
        // Capture.
        let start = !q.busy && q.have;
        if i.valid {
            n.have = true;
            n.qcap = i.qc & self.qmask;
            n.fcap = i.fine & self.fmask;
        } else if start {
            n.have = false;
        }
        // Serial divider.
        n.done = false;
        if start {
            n.pbit = q.qcap & self.qtop != 0;
            n.qsh = ((q.qcap << 1) & self.qmask) | (q.fcap & self.ftop != 0) as u64;
            n.fsh = (q.fcap << 1) & self.fmask;
            n.cnt = self.wp - 1;
            n.r = 0;
            n.t = 0;
            n.busy = true;
        } else if q.busy {
            let r2 = (q.r << 1) & M32;
            let ka = if q.pbit { self.a } else { 0 };
            let c0 = (r2 + ka) & M32;
            let c1 = (r2 + ka).wrapping_sub(self.b) & M32;
            let c2 = (r2 + ka).wrapping_sub(2 * self.b) & M32;
            if c2 & SIGN == 0 {
                n.r = c2;
                n.t = ((q.t + 1) << 1) & M32;
            } else if c1 & SIGN == 0 {
                n.r = c1;
                n.t = ((q.t << 1) | 1) & M32;
            } else {
                n.r = c0;
                n.t = (q.t << 1) & M32;
            }
            n.pbit = q.qsh & self.qtop != 0;
            n.qsh = ((q.qsh << 1) & self.qmask) | (q.fsh & self.ftop != 0) as u64;
            n.fsh = (q.fsh << 1) & self.fmask;
            if q.cnt == 0 {
                n.busy = false;
                n.done = true;
            } else {
                n.cnt = q.cnt - 1;
            }
        }
        // Fold: S1 difference, S2 compares, S3 add.
        n.s1 = false;
        if q.done {
            n.told = q.t;
            if q.init {
                n.d = q.t.wrapping_sub(q.told) & M32;
                n.s1 = true;
            } else {
                n.init = true;
                n.c = q.t;
            }
        }
        n.s2 = q.s1;
        if q.s1 {
            n.d2 = q.d;
            n.fh = q.d & SIGN == 0 && q.d > self.half;
            n.fl = q.d & SIGN != 0 && q.d <= (1u64 << 32) - self.half;
        }
        // Emitter.
        let nonzero = q.pnz && !(q.stepped && q.p1);
        let step = !q.hold && nonzero;
        let up = !q.pn;
        let apply = q.incp && !step;
        if q.s2 {
            n.dd = if q.fh {
                q.d2.wrapping_sub(self.e) & M32
            } else if q.fl {
                (q.d2 + self.e) & M32
            } else {
                q.d2
            };
            n.incp = true;
        } else if apply {
            n.incp = false;
        }
        n.incd = apply;
        n.stepped = step;
        if step {
            n.pend = if up {
                q.pend.wrapping_sub(1) & M32
            } else {
                (q.pend + 1) & M32
            };
            n.c = if up {
                if q.ctop {
                    0
                } else {
                    q.c + 1
                }
            } else if q.czero {
                self.e - 1
            } else {
                q.c - 1
            };
        } else if apply {
            n.pend = (q.pend + q.dd) & M32;
        }
        n.pnz = q.pend != 0;
        n.pn = q.pend & SIGN != 0;
        n.p1 = q.pend == 1 || q.pend == M32;
        if step {
            n.tm = self.s - 1;
            n.hold = true;
        } else if q.hold {
            n.tm = q.tm.wrapping_sub(1) & self.tmask;
            if q.tm == 1 {
                n.hold = false;
            }
        }
        n.ctop = q.c == self.e - 1;
        n.czero = q.c == 0;
        n.a = (q.c & 1 != 0) ^ (q.c & 2 != 0);
        n.b = q.c & 2 != 0;
        n.z = q.init && q.c == 0;
        if apply {
            if nonzero {
                n.warn = true;
            }
        } else if !q.incd && !nonzero {
            n.warn = false;
        }
        if i.rst {
            n = Regs::default();
        }
        self.r = n;
        AbzOut {
            a: n.a,
            b: n.b,
            z: n.z,
            warning: n.warn,
        }
    }
}
