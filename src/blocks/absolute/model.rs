//! Bit-accurate model of the absolute start: the same registers as the RTL
//! ([`super::hdl::AbsoluteStart`]), updated once per clock edge; `step` returns what the
//! outputs show after the edge.
use super::AbsoluteParams;
use crate::blocks::mask;

/// Where a read is (the RTL's `AbsState`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Phase {
    /// The clock high for W clocks (after reset, after a failed frame).
    #[default]
    Wait,
    /// Waiting for the line high and a CONV assertion.
    Ready,
    /// Clock low for H clocks.
    Low,
    /// Clock high for H clocks.
    High,
    /// After the last pulse: reading the tail.
    Tail,
    /// δ = (o - c) mod 2^(k+3).
    Sync,
    /// p = c + sext(δ).
    Place,
    /// tq and tt from p.
    Split,
    /// tq - Q, tq + Q, tt - 1, tt + 1.
    Target,
    /// `req` in a clock without a sample.
    Request,
    /// The target was taken.
    Done,
}

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AbsoluteIn {
    /// Synchronous reset.
    pub rst: bool,
    /// The ADC's CONV (chip select) level.
    pub conv: bool,
    /// A position sample is present.
    pub valid: bool,
    /// Quadrant count 0..Q-1.
    pub qc: u64,
    /// Fine part.
    pub fine: u64,
    /// Turn word (M bits).
    pub turns: u64,
    /// The SSI data line (before the synchronizer).
    pub data: bool,
}

impl AbsoluteIn {
    /// Stimulus row in [`crate::cosim::CosimBlock::input_ports`] order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.conv as u64,
            self.valid as u64,
            self.qc & mask(32),
            self.fine & mask(32),
            self.turns & mask(32),
            self.data as u64,
        ]
    }
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AbsoluteOut {
    /// The SSI clock.
    pub clk: bool,
    /// One clock: the target and B are ready (never with a sample).
    pub req: bool,
    /// Target quadrant count T_q.
    pub tq: u64,
    /// T_q - Q (qb + 1 bits).
    pub tqm: u64,
    /// T_q + Q.
    pub tqp: u64,
    /// Target turn word T_t.
    pub tt: u64,
    /// T_t - 1 (M bits).
    pub ttm: u64,
    /// T_t + 1 (M bits).
    pub ttp: u64,
    /// Quadrant count of the latch's sample.
    pub bq: u64,
    /// Turn word of the latch's sample.
    pub bt: u64,
    /// The last frame failed.
    pub fault: bool,
}

impl AbsoluteOut {
    /// Trace row in output-port order.
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.clk as u64,
            self.req as u64,
            self.tq,
            self.tqm,
            self.tqp,
            self.tt,
            self.ttm,
            self.ttp,
            self.bq,
            self.bt,
            self.fault as u64,
        ]
    }
}

/// The registers (names as in the RTL).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct Regs {
    conv_prev: bool,
    s1: bool,
    s2: bool,
    state: Phase,
    cnt: u64,
    n: u64,
    /// The SSI clock, inverted (power-up 0 = the line high).
    ckn: bool,
    smp0: bool,
    smp1: bool,
    w: u64,
    gx: bool,
    lt: u64,
    bvalid: bool,
    bq: u64,
    bt: u64,
    bo: u64,
    dl: u64,
    p: u64,
    tq: u64,
    tqm: u64,
    tqp: u64,
    tt: u64,
    ttm: u64,
    ttp: u64,
    fault: bool,
}

/// The absolute start, clock by clock.
#[derive(Clone, Debug)]
pub struct AbsoluteModel {
    p: AbsoluteParams,
    r: Regs,
}

impl AbsoluteModel {
    /// The block after power-up: every register 0 (the SSI clock's register is inverted,
    /// so the clock is high).
    pub fn new(p: &AbsoluteParams) -> Self {
        Self {
            p: *p,
            r: Regs::default(),
        }
    }

    /// The phase after the last edge.
    pub fn phase(&self) -> Phase {
        self.r.state
    }

    /// One clock edge with inputs `i`; returns the outputs after it.
    pub fn step(&mut self, i: AbsoluteIn) -> AbsoluteOut {
        let p = self.p;
        let t = p.timing();
        let (s, k, qb) = (
            p.word().single_turn_bits,
            p.sub_quadrant_bits(),
            p.quadrant_bits(),
        );
        let q = p.quadrants_per_turn();
        let (cm, tm, dm) = (mask(p.count_bits()), mask(p.turns_bits()), mask(k + 3));
        let o = self.r;
        let mut n = o;
        // Synchronizers and the edge register (no reset).
        n.conv_prev = i.conv;
        n.s1 = i.data;
        n.s2 = o.s1;
        let act = p.conv_active_high();
        let assert_edge = i.conv == act && o.conv_prev != act;
        let start = o.state == Phase::Ready && assert_edge && o.s2;
        if assert_edge {
            n.lt = ((o.lt << 1) | start as u64) & mask(p.tag_shift() + 1);
        }
        // The sample of the latch's conversion.
        if i.valid && (o.lt >> p.tag_shift()) & 1 == 1 {
            n.bq = i.qc & mask(qb);
            n.bt = i.turns & tm;
            n.bo = p.sync_of(i.qc, i.fine);
            n.bvalid = true;
        }
        n.smp0 = false;
        n.smp1 = o.smp0;
        let b = o.s2 ^ (o.gx && p.word().gray);
        let c = ((o.w & mask(s)) << 1) | 1;
        let h1 = (t.half_clocks - 1) as u64;
        match o.state {
            Phase::Wait => {
                n.cnt = (o.cnt + 1) & cm;
                if o.cnt == (t.wait_clocks - 1) as u64 {
                    n.state = Phase::Ready;
                    n.cnt = 0;
                }
            }
            Phase::Ready => {
                if start {
                    n.ckn = true;
                    n.state = Phase::Low;
                    n.cnt = 0;
                    n.n = 0;
                    n.w = 0;
                    n.gx = false;
                    n.bvalid = false;
                }
            }
            Phase::Low => {
                n.cnt = (o.cnt + 1) & cm;
                if o.cnt == h1 {
                    n.ckn = false;
                    n.n = (o.n + 1) & mask(p.pulse_bits());
                    n.state = Phase::High;
                    n.cnt = 0;
                    n.smp0 = o.n != 0;
                }
            }
            Phase::High => {
                n.cnt = (o.cnt + 1) & cm;
                if o.smp1 {
                    n.w = ((o.w << 1) | b as u64) & mask(32);
                    n.gx = b;
                }
                if o.cnt == h1 {
                    n.cnt = 0;
                    if o.n == (p.word().bits() + 1) as u64 {
                        n.state = Phase::Tail;
                    } else {
                        n.ckn = true;
                        n.state = Phase::Low;
                    }
                }
            }
            Phase::Tail => {
                n.cnt = (o.cnt + 1) & cm;
                if o.cnt == h1 {
                    n.smp0 = true;
                }
                if o.smp1 {
                    if !o.s2 && o.bvalid {
                        n.state = Phase::Sync;
                    } else {
                        n.state = Phase::Wait;
                        n.cnt = 0;
                        n.fault = true;
                    }
                }
            }
            Phase::Sync => {
                n.dl = o.bo.wrapping_sub(c) & dm;
                n.state = Phase::Place;
            }
            Phase::Place => {
                let dext = if o.dl >> (k + 2) & 1 == 1 {
                    o.dl | (mask(32) & !dm)
                } else {
                    o.dl
                };
                n.p = (c + dext) & mask(s + 3);
                n.state = Phase::Split;
            }
            Phase::Split => {
                let wt = (o.w >> s) & mask(p.word().multiturn_bits);
                n.tq = (o.p >> (k + 1)) & mask(qb);
                n.tt = if o.p >> (s + 2) & 1 == 1 {
                    wt.wrapping_sub(1) & tm
                } else if o.p >> (s + 1) & 1 == 1 {
                    (wt + 1) & tm
                } else {
                    wt & tm
                };
                n.state = Phase::Target;
            }
            Phase::Target => {
                n.tqm = o.tq.wrapping_sub(q) & mask(qb + 1);
                n.tqp = o.tq + q;
                n.ttm = o.tt.wrapping_sub(1) & tm;
                n.ttp = (o.tt + 1) & tm;
                n.fault = false;
                n.state = Phase::Request;
            }
            Phase::Request => {
                if !i.valid {
                    n.state = Phase::Done;
                }
            }
            Phase::Done => {}
        }
        if i.rst {
            n = Regs {
                conv_prev: n.conv_prev,
                s1: n.s1,
                s2: n.s2,
                ..Regs::default()
            };
        }
        self.r = n;
        AbsoluteOut {
            clk: !n.ckn,
            req: n.state == Phase::Request && !i.valid,
            tq: n.tq,
            tqm: n.tqm,
            tqp: n.tqp,
            tt: n.tt,
            ttm: n.ttm,
            ttp: n.ttp,
            bq: n.bq,
            bt: n.bt,
            fault: n.fault,
        }
    }
}
