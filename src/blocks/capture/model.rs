//! Bit-accurate model of the capture block: the same registers as the RTL, updated once
//! per clock edge; `step` returns what the outputs show after the edge. The multiplier is
//! its result: q(v ager / 2^(S+B)) in the clock the RTL's Booth multiplier has it.
use super::CaptureParams;
use crate::blocks::{mask, sext};

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CaptureIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Capture request (before the synchronizer).
    pub capture: bool,
    /// A position sample is present.
    pub valid: bool,
    /// Quadrant count 0..Q-1.
    pub qc: u64,
    /// Fine part.
    pub fine: u64,
    /// Turn word (M bits).
    pub turns: u64,
    /// The velocity estimate (its width's two's complement in the low bits).
    pub velocity: u64,
}

impl CaptureIn {
    /// Stimulus row in [`crate::cosim::CosimBlock::input_ports`] order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.capture as u64,
            self.valid as u64,
            self.qc & mask(32),
            self.fine & mask(32),
            self.turns & mask(32),
            self.velocity,
        ]
    }
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CaptureOut {
    /// One clock: a capture's values are out.
    pub valid: bool,
    /// Captured quadrant count.
    pub qc: u64,
    /// Captured fine part.
    pub fine: u64,
    /// Captured turn word.
    pub turns: u64,
    /// Captured velocity.
    pub velocity: u64,
    /// Clocks from the sample's CONV edge to the capture.
    pub age: u64,
}

impl CaptureOut {
    /// Trace row in output-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.valid as u64,
            self.qc,
            self.fine,
            self.turns,
            self.velocity,
            self.age,
        ]
    }
}

/// Where a capture is (the RTL's `CapState`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum State {
    #[default]
    Idle,
    Start,
    Wait,
    Add,
    Wrap,
}

/// The registers (names as in the RTL).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Regs {
    c1: bool,
    c2: bool,
    c3: bool,
    hq: u64,
    hf: u64,
    ht: u64,
    since: u64,
    ager: u64,
    state: State,
    mw: u64,
    cq: u64,
    cf: u64,
    ct: u64,
    cage: u64,
    cv: u64,
    cb: u64,
    /// The multiplier's result once it has run (the RTL's `mul.p`).
    prod: u64,
    s: u64,
    out: CaptureOut,
}

/// The capture block, clock by clock.
#[derive(Clone, Debug)]
pub struct CaptureModel {
    p: CaptureParams,
    r: Regs,
}

impl CaptureModel {
    /// The block after power-up (registers 0; the age saturated, as after a reset).
    pub fn new(p: &CaptureParams) -> Self {
        let mut m = Self {
            p: *p,
            r: Regs::default(),
        };
        m.r.since = mask(p.age_bits());
        m.r.ager = m.ager_max();
        m
    }

    /// `ager` at the horizon (0 without extrapolation).
    fn ager_max(&self) -> u64 {
        self.p.ager_for(u64::MAX)
    }

    /// One clock edge with inputs `i`; returns the outputs after it.
    pub fn step(&mut self, i: CaptureIn) -> CaptureOut {
        let p = self.p;
        let o = self.r;
        let mut n = o;
        let f = p.fine_bits();
        let (qm, tm, fm) = (mask(p.quadrant_bits()), mask(p.turns_bits()), mask(f));
        // The synchronizer and the edge register run through the reset.
        n.c1 = i.capture;
        n.c2 = o.c1;
        n.c3 = o.c2;
        if i.rst {
            n = Regs {
                c1: n.c1,
                c2: n.c2,
                c3: n.c3,
                since: mask(p.age_bits()),
                ager: self.ager_max(),
                ..Regs::default()
            };
            self.r = n;
            return n.out;
        }
        let amax = mask(p.age_bits());
        // The held sample and its age.
        if i.valid {
            n.hq = i.qc & qm;
            n.hf = i.fine & fm;
            n.ht = i.turns & tm;
            n.since = p.since_load();
            n.ager = p.ager_for(p.since_load());
        } else {
            if o.since != amax {
                n.since = o.since + 1;
            }
            if let Some(e) = p.extrapolation() {
                if o.since < e.horizon as u64 {
                    n.ager = o.ager + e.recip;
                }
            }
        }
        let vel = i.velocity & mask(p.velocity_width());
        let edge = o.c2 && !o.c3;
        n.out.valid = false;
        match (o.state, p.extrapolation()) {
            (State::Idle, None) if edge => {
                n.out = CaptureOut {
                    valid: true,
                    qc: o.hq,
                    fine: o.hf,
                    turns: o.ht,
                    velocity: vel,
                    age: o.since,
                };
            }
            (State::Idle, Some(_)) if edge => {
                n.cq = o.hq;
                n.cf = o.hf;
                n.ct = o.ht;
                n.cage = o.since;
                n.cv = vel;
                n.cb = o.ager;
                n.state = State::Start;
            }
            (State::Start, Some(e)) => {
                // The multiply of (ager, v'), ready when the state reaches Add.
                let a = sext(o.cb, e.a_width) as i128;
                let vs = (sext(o.cv, p.velocity_width()) >> e.vshift) as u64;
                let b = sext(vs & mask(e.b_width), e.b_width) as i128;
                let prod = crate::blocks::velocity::qround(a * b, e.shift);
                n.prod = prod as u64 & mask(e.out_width);
                n.mw = 0;
                n.state = State::Wait;
            }
            (State::Wait, Some(_)) => {
                n.mw = o.mw + 1;
                if o.mw == p.mul_steps() as u64 {
                    n.state = State::Add;
                }
            }
            (State::Add, Some(e)) => {
                let pos = (o.cq << f) | o.cf;
                let d = sext(o.prod, e.out_width);
                n.s = (pos as i64).wrapping_add(d) as u64 & mask(p.sum_bits());
                n.state = State::Wrap;
            }
            (State::Wrap, Some(_)) => {
                let sw = p.sum_bits();
                let turn = p.quadrants_per_turn() << f;
                let s = sext(o.s, sw);
                let (pos, turns) = if s < 0 {
                    (s + turn as i64, o.ct.wrapping_sub(1))
                } else if s >= turn as i64 {
                    (s - turn as i64, o.ct + 1)
                } else {
                    (s, o.ct)
                };
                n.out = CaptureOut {
                    valid: true,
                    qc: pos as u64 >> f,
                    fine: pos as u64 & fm,
                    turns: turns & tm,
                    velocity: o.cv,
                    age: o.cage,
                };
                n.state = State::Idle;
            }
            _ => {}
        }
        self.r = n;
        n.out
    }
}
