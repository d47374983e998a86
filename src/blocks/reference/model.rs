//! Bit-accurate model of the position reference: the same registers as the RTL, updated
//! once per clock edge; `step` returns what the outputs show after the edge.
use super::ReferenceParams;
use crate::blocks::mask;

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReferenceIn {
    /// Synchronous reset.
    pub rst: bool,
    /// The ADC's CONV (chip select) level.
    pub conv: bool,
    /// Filtered index Z.
    pub z: bool,
    /// Preset request (before the synchronizer).
    pub preset: bool,
    /// A position sample is present.
    pub valid: bool,
    /// Quadrant count 0..Q-1.
    pub qc: u64,
    /// Fine part (passed through).
    pub fine: u64,
    /// Turn word (M bits).
    pub turns: u64,
    /// The absolute start's request (with `[reference] absolute`).
    pub abs_req: bool,
    /// Its target: T_q, T_q - Q, T_q + Q, T_t, T_t - 1, T_t + 1.
    pub abs_t: [u64; 6],
    /// The count (B_q, B_t) the target is for.
    pub abs_b: (u64, u64),
}

impl ReferenceIn {
    /// Stimulus row in [`crate::cosim::CosimBlock::input_ports`] order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.conv as u64,
            self.z as u64,
            self.preset as u64,
            self.valid as u64,
            self.qc & mask(32),
            self.fine & mask(32),
            self.turns & mask(32),
            self.abs_req as u64,
            self.abs_t[0] & mask(32),
            self.abs_t[1] & mask(32),
            self.abs_t[2] & mask(32),
            self.abs_t[3] & mask(32),
            self.abs_t[4] & mask(32),
            self.abs_t[5] & mask(32),
            self.abs_b.0 & mask(32),
            self.abs_b.1 & mask(32),
        ]
    }
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ReferenceOut {
    /// Output strobe.
    pub valid: bool,
    /// Referenced quadrant count.
    pub qc: u64,
    /// Fine part.
    pub fine: u64,
    /// Referenced turn word.
    pub turns: u64,
    /// The output sample is referenced.
    pub referenced: bool,
    /// Not referenced, with `warn_until_referenced`.
    pub warning: bool,
    /// One clock: an index was latched.
    pub index_valid: bool,
    /// Referenced quadrant count of the last index.
    pub index_qc: u64,
    /// Referenced turn word of the last index.
    pub index_turns: u64,
}

impl ReferenceOut {
    /// Trace row in output-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.valid as u64,
            self.qc,
            self.fine,
            self.turns,
            self.referenced as u64,
            self.warning as u64,
            self.index_valid as u64,
            self.index_qc,
            self.index_turns,
        ]
    }
}

/// The registers (names as in the RTL).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Regs {
    conv_prev: bool,
    zt: u64,
    p1: bool,
    p2: bool,
    pp: bool,
    ppend: bool,
    pqual: bool,
    oq: u64,
    oqm: u64,
    ot: u64,
    otp: u64,
    refd: bool,
    upd: bool,
    usel: bool,
    ubq: u64,
    ubt: u64,
    /// The held target (with the absolute start).
    ht: [u64; 6],
    ilatch: bool,
    ihome: bool,
    out: ReferenceOut,
}

/// The position reference, clock by clock.
#[derive(Clone, Debug)]
pub struct ReferenceModel {
    p: ReferenceParams,
    r: Regs,
}

impl ReferenceModel {
    /// The block after power-up (every register 0 but the offset's `oqm` and `otp`, which
    /// a reset also sets).
    pub fn new(p: &ReferenceParams) -> Self {
        let mut m = Self {
            p: *p,
            r: Regs::default(),
        };
        m.reset_offset();
        m.r.out.warning = p.warn_until_referenced();
        m
    }

    /// Bits of the quadrant count and of the signed sums s2, d (qb + 1).
    fn widths(&self) -> (u32, u32) {
        let qb = 64 - (self.p.quadrants_per_turn() - 1).leading_zeros();
        (qb, qb + 1)
    }

    fn reset_offset(&mut self) {
        let (_, qw) = self.widths();
        let q = self.p.quadrants_per_turn();
        self.r.oq = 0;
        self.r.oqm = q.wrapping_neg() & mask(qw);
        self.r.ot = 0;
        self.r.otp = 1 & mask(self.p.turns_bits());
    }

    /// One clock edge with inputs `i`; returns the outputs after it.
    pub fn step(&mut self, i: ReferenceIn) -> ReferenceOut {
        let p = self.p;
        let (qb, qw) = self.widths();
        let (tm, qm, wm) = (mask(p.turns_bits()), mask(qb), mask(qw));
        let sign = 1u64 << (qw - 1);
        let q = p.quadrants_per_turn();
        let o = self.r;
        let mut n = o;
        // Synchronizers and edge registers run through the reset.
        n.conv_prev = i.conv;
        n.p1 = i.preset;
        n.p2 = o.p1;
        n.pp = o.p2;
        if i.rst {
            n.zt = 0;
            n.ppend = false;
            n.pqual = false;
            n.refd = false;
            n.upd = false;
            n.ilatch = false;
            n.ihome = false;
            n.out = ReferenceOut {
                warning: p.warn_until_referenced(),
                ..Default::default()
            };
            self.r = n;
            self.reset_offset();
            return self.r.out;
        }
        let act = p.conv_active_high();
        if i.conv == act && o.conv_prev != act {
            n.zt = ((o.zt << 1) | i.z as u64) & mask(p.tag_shift() + 1);
        }
        let zs = (o.zt >> p.tag_shift()) & 1 == 1;
        let pnow = o.ppend | (o.p2 & !o.pp);
        n.out.valid = i.valid;
        n.out.index_valid = false;
        n.ilatch = false;
        n.ihome = false;
        if o.ilatch {
            n.out.index_valid = true;
            n.out.index_qc = o.out.qc;
            n.out.index_turns = o.out.turns;
        }
        if o.ihome {
            n.out.index_valid = true;
            n.out.index_qc = p.index().0;
            n.out.index_turns = p.index().1;
        }
        // The offset taken from a sample in the clock before: T - B from registers.
        n.upd = false;
        if o.upd {
            // T and its neighbours: held since the request (with the absolute start), or
            // the constants of the preset or the index count.
            let [tq, tqm, tqp, tt, ttm, ttp] = if p.absolute() {
                o.ht
            } else {
                let (tq, tt) = if o.usel { p.preset() } else { p.index() };
                [
                    tq,
                    tq.wrapping_sub(q) & wm,
                    tq + q,
                    tt,
                    tt.wrapping_sub(1),
                    tt + 1,
                ]
            };
            let (bq, bt) = (o.ubq, o.ubt);
            let d1 = tq.wrapping_sub(bq) & wm;
            if d1 & sign != 0 {
                n.oq = tqp.wrapping_sub(bq) & wm;
                n.oqm = d1;
                n.ot = ttm.wrapping_sub(bt) & tm;
                n.otp = tt.wrapping_sub(bt) & tm;
            } else {
                n.oq = d1;
                n.oqm = tqm.wrapping_sub(bq) & wm;
                n.ot = tt.wrapping_sub(bt) & tm;
                n.otp = ttp.wrapping_sub(bt) & tm;
            }
            n.refd = true;
        }
        if !i.valid {
            n.ppend = pnow;
            self.absolute_request(&mut n, &i);
            self.r = n;
            return n.out;
        }
        let (bq, bt) = (i.qc & qm, i.turns & tm);
        let qual = zs && bq & 3 == p.gate() as u64;
        // With the absolute start an index only latches, once referenced: it never homes.
        let event = qual && !o.pqual && (!p.absolute() || o.refd);
        n.pqual = qual;
        n.ppend = false;
        // The output: the sample moved by the offset held before it.
        let s = (bq + o.oq) & wm;
        let s2 = (bq + o.oqm) & wm;
        let carry = s2 & sign == 0;
        n.out.qc = if carry { s2 } else { s };
        n.out.turns = (bt + if carry { o.otp } else { o.ot }) & tm;
        n.out.fine = i.fine & mask(32);
        n.out.referenced = o.refd;
        n.out.warning = !o.refd && p.warn_until_referenced();
        let home = event && !o.refd && !o.upd && !pnow;
        // Every sample loads its count; `upd` says whether it asked (as the RTL).
        n.usel = pnow;
        n.ubq = bq;
        n.ubt = bt;
        if pnow || home {
            n.upd = true;
        }
        if (pnow || home) && p.absolute() {
            n.ht = Self::constants(&p, if pnow { p.preset() } else { p.index() });
        }
        if home {
            n.ihome = true;
        } else if event && o.refd && !o.upd && !pnow {
            n.ilatch = true;
        }
        self.absolute_request(&mut n, &i);
        self.r = n;
        n.out
    }

    /// T = (quadrant count, turn word) with its neighbours, as the RTL's constants hold
    /// them.
    fn constants(p: &ReferenceParams, t: (u64, u64)) -> [u64; 6] {
        let q = p.quadrants_per_turn();
        let wm = mask(64 - (q - 1).leading_zeros() + 1);
        let m32 = |v: u64| v & mask(32);
        [
            t.0,
            t.0.wrapping_sub(q) & wm,
            t.0 + q,
            t.1,
            m32(t.1.wrapping_sub(1)),
            m32(t.1 + 1),
        ]
    }

    /// The absolute start's request (`[reference] absolute`): its B, and T from its words.
    fn absolute_request(&self, n: &mut Regs, i: &ReferenceIn) {
        if self.p.absolute() && i.abs_req {
            let qb = self.widths().0;
            n.upd = true;
            n.ht = i.abs_t.map(|v| v & mask(32));
            n.ubq = i.abs_b.0 & mask(qb);
            n.ubt = i.abs_b.1 & mask(self.p.turns_bits());
        }
    }
}
