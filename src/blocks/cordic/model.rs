//! Bit-accurate model of the quadrant mapper and the CORDIC stages.
use crate::blocks::params::Derived;
use crate::blocks::{mask, sext};

/// Result of the mapper + N stages for one sample: what reaches the combiner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CordicOut {
    /// Quadrant 0..3 from the sign bits.
    pub q: u8,
    /// Final x (W-bit, unsigned view): K_N |v| 2^G.
    pub x: u64,
    /// Final angle z (ZW-bit, raw two's complement).
    pub z: u64,
}

/// Quadrant of a sample from its sign bits (see the module docs).
#[inline]
pub fn quadrant(sin: i32, cos: i32) -> u8 {
    let s = (sin < 0) as u8;
    let c = (cos < 0) as u8;
    (s << 1) | (s ^ c)
}

/// Mapped first-quadrant vector (x', y') of a sample (Table 2-3).
#[inline]
pub fn map(sin: i32, cos: i32) -> (i64, i64) {
    let (x, y) = (cos as i64, sin as i64);
    match quadrant(sin, cos) {
        0 => (x, y),
        1 => (y, -x),
        2 => (-x, -y),
        _ => (-y, x),
    }
}

/// Runs the mapper and the N stages on one sample (inputs already within A bits).
#[inline]
pub fn cordic(d: &Derived, sin: i32, cos: i32) -> CordicOut {
    let w = d.xy_width;
    let zw = d.z_width;
    let q = quadrant(sin, cos);
    let (mx, my) = map(sin, cos);
    let mut x = sext(((mx << d.xy_guard) as u64) & mask(w), w);
    let mut y = sext(((my << d.xy_guard) as u64) & mask(w), w);
    let mut z: i64 = 0;
    for (i, &a) in d.atan_table.iter().enumerate() {
        let xs = x >> i;
        let ys = y >> i;
        if y < 0 {
            x = sext((x - ys) as u64 & mask(w), w);
            y = sext((y + xs) as u64 & mask(w), w);
            z = sext((z - a as i64) as u64 & mask(zw), zw);
        } else {
            x = sext((x + ys) as u64 & mask(w), w);
            y = sext((y - xs) as u64 & mask(w), w);
            z = sext((z + a as i64) as u64 & mask(zw), zw);
        }
    }
    CordicOut {
        q,
        x: x as u64 & mask(w),
        z: z as u64 & mask(zw),
    }
}

/// Cycle-level model of the iterative timing (the arithmetic is the shared sample model):
/// used by [`crate::blocks::core::model::CoreModel`] in iterative mode.
#[derive(Clone, Debug)]
pub struct IterTiming<S: Clone> {
    /// Sample in the mapper register, with its lost mark.
    pub mapper: Option<(S, bool)>,
    /// Engine busy with clocks 1.. of `cur`.
    pub busy: bool,
    /// Next clock index (0..S-1) when busy.
    pub k: u32,
    /// Sample in the engine.
    pub cur: Option<(S, bool)>,
    /// Sample whose S clocks finished at the last edge.
    pub done: Option<(S, bool)>,
    /// Sample in the combiner register.
    pub comb: Option<(S, bool)>,
    /// A sample was dropped since the last accepted one.
    pub dropped: bool,
    /// Held lost mark (ORed into out_warning).
    pub hold: bool,
}

impl<S: Clone> Default for IterTiming<S> {
    fn default() -> Self {
        Self::new()
    }
}

impl<S: Clone> IterTiming<S> {
    /// Power-up state.
    pub fn new() -> Self {
        IterTiming {
            mapper: None,
            busy: false,
            k: 0,
            cur: None,
            done: None,
            comb: None,
            dropped: false,
            hold: false,
        }
    }

    /// in_ready for the coming cycle (a function of the state only); `steps` = S, the
    /// engine's clocks per sample ([`super::iterative::steps`]).
    pub fn ready(&self, steps: u32) -> bool {
        let active = self.busy || self.mapper.is_some();
        let kin = if self.busy { self.k } else { 0 };
        !(active && kin != steps - 1)
    }

    /// One clock edge. `offer` is the sample presented with in_valid (computed lazily by
    /// the caller); returns the sample the combiner hands to the counter at this edge.
    pub fn clock(
        &mut self,
        steps: u32,
        rst: bool,
        valid: bool,
        offer: impl FnOnce() -> S,
    ) -> Option<S> {
        let ready = self.ready(steps);
        let to_counter = self.comb.clone().map(|c| c.0);
        let hold = if rst {
            false
        } else if let Some(c) = &self.comb {
            c.1
        } else {
            self.hold
        };
        let comb = if rst { None } else { self.done.clone() };
        let active = self.busy || self.mapper.is_some();
        let kin = if self.busy { self.k } else { 0 };
        let last = kin == steps - 1;
        let cur = if self.busy {
            self.cur.clone()
        } else {
            self.mapper.clone()
        };
        let done = if active && last && !rst {
            cur.clone()
        } else {
            None
        };
        let busy = active && !last && !rst;
        let mapper = if valid && ready && !rst {
            Some((offer(), self.dropped))
        } else {
            None
        };
        let dropped = if rst {
            false
        } else if valid {
            !ready
        } else {
            self.dropped
        };
        *self = IterTiming {
            mapper,
            busy,
            k: kin + 1,
            cur: if active { cur } else { self.cur.clone() },
            done,
            comb,
            dropped,
            hold,
        };
        to_counter
    }
}
