//! Bit-accurate model of the combiner and the quadrant counter.
use crate::blocks::cordic::model::CordicOut;
use crate::blocks::params::Derived;
use crate::blocks::{mask, sext};

/// Combiner output for one sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Combined {
    /// Electrical angle in 2^-F quadrant, modulo 2^(F+2).
    pub p: u64,
    /// Magnitude above the monitor threshold.
    pub mag_ok: bool,
}

/// The combiner: rounding of z and assembly of p.
#[inline]
pub fn combine(d: &Derived, c: &CordicOut) -> Combined {
    let f = d.fine_bits;
    let pm = mask(f + 2);
    let zr = (c.z + (1 << (d.z_guard - 1))) & mask(d.z_width);
    let fine = (zr >> d.z_guard) & pm;
    Combined {
        p: (fine + ((c.q as u64) << f)) & pm,
        mag_ok: c.x >= d.min_magnitude,
    }
}

/// State and registered outputs of the quadrant counter.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Counter {
    /// A sample has been accepted since reset.
    pub init: bool,
    /// p of the last accepted sample.
    pub p_prev: u64,
    /// Coarse quadrant count, 0..4PPR-1.
    pub qc: u64,
    /// Fine part, 0..2^F-1.
    pub fine: u64,
    /// Turn counter, M bits raw.
    pub turns: u64,
    /// Registered out_valid.
    pub valid: bool,
    /// Registered out_error.
    pub error: bool,
    /// Registered out_warning.
    pub warning: bool,
    /// A resynchronisation is pending (see [`Counter::load`]).
    pub pending: bool,
    /// Latched coarse count to resynchronise to.
    pub load_qc: u64,
    /// Latched turn count to resynchronise to.
    pub load_turns: u64,
}

/// A resynchronisation request: at the next accepted sample the counter takes this coarse
/// count and turn count, moved by at most +-2 quadrants to the value congruent (mod 4) with
/// the sample's own quadrant.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Load {
    /// Coarse quadrant count, 0..4PPR-1.
    pub qc: u64,
    /// Turn count (M bits).
    pub turns: u64,
}

impl Counter {
    /// One clock edge: `sample` is the combiner's registered output when its valid bit is
    /// set.
    pub fn clock(&mut self, d: &Derived, rst: bool, sample: Option<Combined>, load: Option<Load>) {
        if rst {
            *self = Counter::default();
            return;
        }
        self.valid = sample.is_some();
        // A load request is latched; a sample accepted in the same cycle still uses the
        // previous request state (the latch is a register).
        let pending = self.pending;
        let (lqc, lturns) = (self.load_qc, self.load_turns);
        if let Some(l) = load {
            self.pending = true;
            self.load_qc = l.qc & mask(32);
            self.load_turns = l.turns & mask(32);
        }
        let Some(s) = sample else { return };
        let f = d.fine_bits;
        if !s.mag_ok {
            self.error = true;
            self.warning = false;
            return;
        }
        self.error = false;
        if !self.init {
            self.init = true;
            self.qc = s.p >> f;
            self.fine = s.p & mask(f);
            self.turns = 0;
            self.warning = false;
            self.p_prev = s.p;
            return;
        }
        let span = 1u64 << (f + 2);
        let delta = s.p.wrapping_sub(self.p_prev) & (span - 1);
        let tm = mask(d.multiturn_bits);
        let (base_qc, base_turns, step) = if pending {
            if load.is_none() {
                self.pending = false;
            }
            self.warning = false;
            // Nearest count congruent with the sample's quadrant: +0, +1, +2, -1.
            let dq = (s.p >> f).wrapping_sub(lqc) & 3;
            let adj = if dq == 3 { -1 } else { dq as i64 };
            (lqc, lturns, adj)
        } else {
            self.warning = delta >= d.warn_step && delta <= span - d.warn_step;
            let total = self.fine as i64 + sext(delta, f + 2);
            (self.qc, self.turns, total >> f)
        };
        let qn = sext((base_qc as i64 + step) as u64 & mask(32), 32);
        let q = d.quadrants_per_turn as i64;
        if qn < 0 {
            self.qc = ((qn + q) as u64) & mask(32);
            self.turns = base_turns.wrapping_sub(1) & tm;
        } else if qn >= q {
            self.qc = ((qn - q) as u64) & mask(32);
            self.turns = (base_turns + 1) & tm;
        } else {
            self.qc = qn as u64;
            self.turns = base_turns & tm;
        }
        self.fine = s.p & mask(f);
        self.p_prev = s.p;
    }
}
