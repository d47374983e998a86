//! rust-hdl description of the ABZ emulator (maths, timing and sketch in the module docs of
//! [`crate::blocks::abz`]).
use super::AbzParams;
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// Position -> A/B/Z incremental encoder emulation.
#[derive(LogicBlock)]
pub struct AbzEmulator {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: everything to 0; the next sample sets the count.
    pub rst: Signal<In, Bit>,
    /// A position sample is on `qc` and `fine` this clock.
    pub in_valid: Signal<In, Bit>,
    /// Single-turn quadrant count, 0..Q-1 (Q = 4 PPR; higher bits ignored).
    pub in_qc: Signal<In, Bits<32>>,
    /// Fine position, 0..2^F-1 (higher bits ignored).
    pub in_fine: Signal<In, Bits<32>>,
    /// Channel A (leads B when the position increases).
    pub abz_a: Signal<Out, Bit>,
    /// Channel B.
    pub abz_b: Signal<Out, Bit>,
    /// Index: high for the quarter A/B period of count 0 (position 0 of the turn).
    pub abz_z: Signal<Out, Bit>,
    /// Catching up: a sample came while counts of the previous one were still owed.
    pub warning: Signal<Out, Bit>,
    have: DFF<Bit>,
    qcap: DFF<Bits<32>>,
    fcap: DFF<Bits<32>>,
    busy: DFF<Bit>,
    pbit: DFF<Bit>,
    qsh: DFF<Bits<32>>,
    fsh: DFF<Bits<32>>,
    cnt: DFF<Bits<32>>,
    r: DFF<Bits<32>>,
    t: DFF<Bits<32>>,
    done: DFF<Bit>,
    init: DFF<Bit>,
    told: DFF<Bits<32>>,
    /// d = t - t_old of the module docs (not named `d`: its DFF's port `d` would hide it,
    /// VARHIDDEN).
    dt: DFF<Bits<32>>,
    s1: DFF<Bit>,
    d2: DFF<Bits<32>>,
    fh: DFF<Bit>,
    fl: DFF<Bit>,
    s2: DFF<Bit>,
    dd: DFF<Bits<32>>,
    incp: DFF<Bit>,
    incd: DFF<Bit>,
    pend: DFF<Bits<32>>,
    pnz: DFF<Bit>,
    pn: DFF<Bit>,
    p1: DFF<Bit>,
    stepped: DFF<Bit>,
    hold: DFF<Bit>,
    tm: DFF<Bits<32>>,
    c: DFF<Bits<32>>,
    /// c's addend on a step (E_w bits): 1 or -1, or on a wrap -(E-1) or E-1, registered
    /// beside `pn` from the same pend sign and from c's flags (c = E-1, c = 0) of this
    /// clock; steps are at least two clocks apart (spacing >= 2), so c has settled.
    cadd: DFF<Bits<32>>,
    ao: DFF<Bit>,
    bo: DFF<Bit>,
    zo: DFF<Bit>,
    warn: DFF<Bit>,
    start: Signal<Local, Bit>,
    r2: Signal<Local, Bits<32>>,
    c0: Signal<Local, Bits<32>>,
    c1: Signal<Local, Bits<32>>,
    c2: Signal<Local, Bits<32>>,
    nonzero: Signal<Local, Bit>,
    step: Signal<Local, Bit>,
    apply: Signal<Local, Bit>,
    /// c + cadd (E_w bits): c's next value on a step.
    cstep: Signal<Local, Bits<32>>,
    /// c = 0 and c = E-1 (as c >= E-1): the sign bits of 0 - c and c - (E-1) (E_w + 1
    /// bits) clear, one carry chain each.
    cisz: Signal<Local, Bit>,
    cist: Signal<Local, Bit>,
    /// pend < 0: pn's next value.
    pneg: Signal<Local, Bit>,
    /// pend's bits 31..1 are not all zero / are all one: the sign bits of 0 - (pend >> 1)
    /// and (pend >> 1) + 1, one carry chain each.
    phnz: Signal<Local, Bit>,
    phones: Signal<Local, Bit>,
    /// Mask of the quadrant-count bits.
    qmask: Constant<Bits<32>>,
    /// Mask of the fine bits.
    fmask: Constant<Bits<32>>,
    /// MSB of the quadrant count.
    qtop: Constant<Bits<32>>,
    /// MSB of the fine part.
    ftop: Constant<Bits<32>>,
    /// Wp - 1: divider clocks after the start.
    wlast: Constant<Bits<32>>,
    /// a (E/P = a/b in lowest terms).
    ka: Constant<Bits<32>>,
    /// -b mod 2^32.
    kb1: Constant<Bits<32>>,
    /// -2b mod 2^32.
    kb2: Constant<Bits<32>>,
    /// a - b mod 2^32.
    kab1: Constant<Bits<32>>,
    /// a - 2b mod 2^32.
    kab2: Constant<Bits<32>>,
    /// E = edges per turn.
    edges: Constant<Bits<32>>,
    /// E - 1.
    emax: Constant<Bits<32>>,
    /// 2^E_w - (E - 1): the addend that wraps c from E - 1 to 0.
    ewrap: Constant<Bits<32>>,
    /// E / 2.
    half: Constant<Bits<32>>,
    /// 2^32 - E/2: -E/2 as a 32-bit word.
    nhalf: Constant<Bits<32>>,
    /// S - 1: the timer's load after a step.
    slast: Constant<Bits<32>>,
    /// Mask of the timer bits.
    tmask: Constant<Bits<32>>,
    /// Sign bit of a 32-bit word.
    sign: Constant<Bits<32>>,
    /// Mask of the count bits (t and c lie in 0..E-1): E_w = bits of E - 1.
    emask: Constant<Bits<32>>,
    /// 2^E_w: the sign bit of a difference of two counts.
    ebit: Constant<Bits<32>>,
    /// Mask of the divider's remainder words (R_w bits, two's complement).
    rmask: Constant<Bits<32>>,
    /// Sign bit of a remainder word, bit R_w - 1.
    rsign: Constant<Bits<32>>,
    /// Mask of the divider's bit counter (values 0..Wp-1).
    cntmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Two.
    two: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl AbzEmulator {
    /// The emulator for `p`.
    pub fn new(p: &AbzParams) -> Self {
        let (a, b) = p.ratio();
        let qb = p.quadrant_bits();
        let e = p.edges();
        let rm = mask(p.remainder_bits());
        Self {
            clk: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_qc: Default::default(),
            in_fine: Default::default(),
            abz_a: Default::default(),
            abz_b: Default::default(),
            abz_z: Default::default(),
            warning: Default::default(),
            have: Default::default(),
            qcap: Default::default(),
            fcap: Default::default(),
            busy: Default::default(),
            pbit: Default::default(),
            qsh: Default::default(),
            fsh: Default::default(),
            cnt: Default::default(),
            r: Default::default(),
            t: Default::default(),
            done: Default::default(),
            init: Default::default(),
            told: Default::default(),
            dt: Default::default(),
            s1: Default::default(),
            d2: Default::default(),
            fh: Default::default(),
            fl: Default::default(),
            s2: Default::default(),
            dd: Default::default(),
            incp: Default::default(),
            incd: Default::default(),
            pend: Default::default(),
            pnz: Default::default(),
            pn: Default::default(),
            p1: Default::default(),
            stepped: Default::default(),
            hold: Default::default(),
            tm: Default::default(),
            c: Default::default(),
            cadd: Default::default(),
            ao: Default::default(),
            bo: Default::default(),
            zo: Default::default(),
            warn: Default::default(),
            start: Default::default(),
            r2: Default::default(),
            c0: Default::default(),
            c1: Default::default(),
            c2: Default::default(),
            nonzero: Default::default(),
            step: Default::default(),
            apply: Default::default(),
            cstep: Default::default(),
            cisz: Default::default(),
            cist: Default::default(),
            pneg: Default::default(),
            phnz: Default::default(),
            phones: Default::default(),
            qmask: c32(mask(qb)),
            fmask: c32(mask(p.fine_bits())),
            qtop: c32(1 << (qb - 1)),
            ftop: c32(1 << (p.fine_bits() - 1)),
            wlast: c32(p.position_bits() as u64 - 1),
            ka: c32(a),
            kb1: c32(b.wrapping_neg() & rm),
            kb2: c32((2 * b).wrapping_neg() & rm),
            kab1: c32(a.wrapping_sub(b) & rm),
            kab2: c32(a.wrapping_sub(2 * b) & rm),
            edges: c32(e),
            emax: c32(e - 1),
            ewrap: c32(((1u64 << p.count_bits()) - (e - 1)) & mask(p.count_bits())),
            half: c32(e / 2),
            nhalf: c32((1u64 << 32) - e / 2),
            slast: c32(p.spacing() as u64 - 1),
            tmask: c32(mask(p.timer_bits())),
            sign: c32(1 << 31),
            emask: c32(mask(p.count_bits())),
            ebit: c32(1 << p.count_bits()),
            rmask: c32(mask(p.remainder_bits())),
            rsign: c32(1 << (p.remainder_bits() - 1)),
            cntmask: c32(mask(32 - (p.position_bits() - 1).leading_zeros())),
            one: c32(1),
            two: c32(2),
            zero: c32(0),
        }
    }
}

// The emulator's logic in named stages, run in this order (`logic_stages!`).
crate::blocks::logic_stages!(AbzEmulator: Divide, Fold, Emit, Reset);

/// The capture and the serial divider t = floor(p a / b).
impl stages::Divide for AbzEmulator {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, have, qcap, fcap, busy, pbit, qsh, fsh, cnt, r, t, done, init, told, dt, s1,
            d2, fh, fl, s2, dd, incp, incd, pend, pnz, pn, p1, stepped, hold, tm, c, cadd, ao, bo,
            zo, warn
        );
        // Capture: the newest sample waits for the divider.
        self.start.next = !self.busy.q.val() & self.have.q.val();
        if self.in_valid.val() {
            self.have.d.next = true;
            self.qcap.d.next = self.in_qc.val() & self.qmask.val();
            self.fcap.d.next = self.in_fine.val() & self.fmask.val();
        } else if self.start.val() {
            self.have.d.next = false;
        }
        // Serial divider: t = floor(p a / b), one position bit per clock, MSB first.
        self.done.d.next = false;
        self.r2.next = self.r.q.val() << self.one.val();
        if self.pbit.q.val() {
            self.c0.next = (self.r2.val() + self.ka.val()) & self.rmask.val();
            self.c1.next = (self.r2.val() + self.kab1.val()) & self.rmask.val();
            self.c2.next = (self.r2.val() + self.kab2.val()) & self.rmask.val();
        } else {
            self.c0.next = self.r2.val();
            self.c1.next = (self.r2.val() + self.kb1.val()) & self.rmask.val();
            self.c2.next = (self.r2.val() + self.kb2.val()) & self.rmask.val();
        }
        if self.start.val() {
            self.pbit.d.next = (self.qcap.q.val() & self.qtop.val()).any();
            if (self.fcap.q.val() & self.ftop.val()).any() {
                self.qsh.d.next =
                    ((self.qcap.q.val() << self.one.val()) & self.qmask.val()) | self.one.val();
            } else {
                self.qsh.d.next = (self.qcap.q.val() << self.one.val()) & self.qmask.val();
            }
            self.fsh.d.next = (self.fcap.q.val() << self.one.val()) & self.fmask.val();
            self.cnt.d.next = self.wlast.val();
            self.r.d.next = self.zero.val();
            self.t.d.next = self.zero.val();
            self.busy.d.next = true;
        } else if self.busy.q.val() {
            if !(self.c2.val() & self.rsign.val()).any() {
                self.r.d.next = self.c2.val();
                self.t.d.next =
                    ((self.t.q.val() + self.one.val()) << self.one.val()) & self.emask.val();
            } else if !(self.c1.val() & self.rsign.val()).any() {
                self.r.d.next = self.c1.val();
                self.t.d.next =
                    ((self.t.q.val() << self.one.val()) | self.one.val()) & self.emask.val();
            } else {
                self.r.d.next = self.c0.val();
                self.t.d.next = (self.t.q.val() << self.one.val()) & self.emask.val();
            }
            self.pbit.d.next = (self.qsh.q.val() & self.qtop.val()).any();
            if (self.fsh.q.val() & self.ftop.val()).any() {
                self.qsh.d.next =
                    ((self.qsh.q.val() << self.one.val()) & self.qmask.val()) | self.one.val();
            } else {
                self.qsh.d.next = (self.qsh.q.val() << self.one.val()) & self.qmask.val();
            }
            self.fsh.d.next = (self.fsh.q.val() << self.one.val()) & self.fmask.val();
            if self.cnt.q.val() == self.zero.val() {
                self.busy.d.next = false;
                self.done.d.next = true;
            } else {
                self.cnt.d.next = (self.cnt.q.val() - self.one.val()) & self.cntmask.val();
            }
        }
    }
}

/// The fold: S1 difference, S2 compares, S3 add of +-E.
impl stages::Fold for AbzEmulator {
    #[hdl_gen]
    fn update(&mut self) {
        // Fold: S1 difference, S2 compares, S3 add of +-E.
        self.s1.d.next = false;
        if self.done.q.val() {
            self.told.d.next = self.t.q.val();
            if self.init.q.val() {
                self.dt.d.next = self.t.q.val() - self.told.q.val();
                self.s1.d.next = true;
            } else {
                self.init.d.next = true;
            }
        }
        self.s2.d.next = self.s1.q.val();
        if self.s1.q.val() {
            self.d2.d.next = self.dt.q.val();
            self.fh.d.next =
                !(self.dt.q.val() & self.sign.val()).any() & (self.dt.q.val() > self.half.val());
            self.fl.d.next =
                (self.dt.q.val() & self.sign.val()).any() & (self.dt.q.val() <= self.nhalf.val());
        }
    }
}

/// The emitter: one step toward pend = 0 at most every S clocks, and the counter c.
impl stages::Emit for AbzEmulator {
    #[hdl_gen]
    fn update(&mut self) {
        // Emitter: one step toward pend = 0 at most every S clocks.
        self.nonzero.next = self.pnz.q.val() & !(self.stepped.q.val() & self.p1.q.val());
        self.step.next = !self.hold.q.val() & self.nonzero.val();
        self.apply.next = self.incp.q.val() & !self.step.val();
        if self.s2.q.val() {
            if self.fh.q.val() {
                self.dd.d.next = self.d2.q.val() - self.edges.val();
            } else if self.fl.q.val() {
                self.dd.d.next = self.d2.q.val() + self.edges.val();
            } else {
                self.dd.d.next = self.d2.q.val();
            }
        }
        // incp: set by S2, cleared when applied (one LUT of step's flags).
        self.incp.d.next = self.s2.q.val() | (self.incp.q.val() & self.step.val());
        self.incd.d.next = self.apply.val();
        self.stepped.d.next = self.step.val();
        // c's step: one adder, c + cadd, the addend a register (the wrap included), so the
        // adder's sum meets only the load select.
        self.cstep.next = (self.c.q.val() + self.cadd.q.val()) & self.emask.val();
        if self.step.val() {
            if !self.pn.q.val() {
                self.pend.d.next = self.pend.q.val() - self.one.val();
            } else {
                self.pend.d.next = self.pend.q.val() + self.one.val();
            }
        } else if self.apply.val() {
            self.pend.d.next = self.pend.q.val() + self.dd.q.val();
        }
        // The first converted sample sets c = t. No step comes before it (pend stays 0 until
        // a sample is folded, which needs init), so the two never meet: c's enable is
        // load | step, and its value load ? t : c + cadd.
        if self.done.q.val() & !self.init.q.val() {
            self.c.d.next = self.t.q.val();
        } else if self.step.val() {
            self.c.d.next = self.cstep.val();
        }
        // pend's flags from two carry chains on bits 31..1 and bit 0: pend != 0, and
        // pend = 1 or -1 (bits 31..1 all zero or all one, bit 0 set).
        self.phnz.next =
            ((self.zero.val() - (self.pend.q.val() >> self.one.val())) & self.sign.val()).any();
        self.phones.next =
            (((self.pend.q.val() >> self.one.val()) + self.one.val()) & self.sign.val()).any();
        self.pnz.d.next = (self.pend.q.val() & self.one.val()).any() | self.phnz.val();
        self.pneg.next = (self.pend.q.val() & self.sign.val()).any();
        self.pn.d.next = self.pneg.val();
        self.p1.d.next =
            (self.pend.q.val() & self.one.val()).any() & (!self.phnz.val() | self.phones.val());
        if self.step.val() {
            self.tm.d.next = self.slast.val();
            self.hold.d.next = true;
        } else if self.hold.q.val() {
            self.tm.d.next = (self.tm.q.val() - self.one.val()) & self.tmask.val();
            if self.tm.q.val() == self.one.val() {
                self.hold.d.next = false;
            }
        }
        // c's next addend: +1 (pend >= 0) or -1, and on a wrap (c = E-1 going up, c = 0
        // going down) the addend that lands on 0 or E-1. c = E-1 as c >= E-1 (c < E).
        self.cisz.next = !((self.zero.val() - self.c.q.val()) & self.ebit.val()).any();
        self.cist.next = !((self.c.q.val() - self.emax.val()) & self.ebit.val()).any();
        if self.pneg.val() {
            self.cadd.d.next = self.emask.val();
            if self.cisz.val() {
                self.cadd.d.next = self.emax.val();
            }
        } else {
            self.cadd.d.next = self.one.val();
            if self.cist.val() {
                self.cadd.d.next = self.ewrap.val();
            }
        }
        self.ao.d.next =
            (self.c.q.val() & self.one.val()).any() ^ (self.c.q.val() & self.two.val()).any();
        self.bo.d.next = (self.c.q.val() & self.two.val()).any();
        self.zo.d.next = self.init.q.val() & self.cisz.val();
        if self.apply.val() {
            if self.nonzero.val() {
                self.warn.d.next = true;
            }
        } else if !self.incd.q.val() & !self.nonzero.val() {
            self.warn.d.next = false;
        }
    }
}

/// Reset.
impl stages::Reset for AbzEmulator {
    #[hdl_gen]
    fn update(&mut self) {
        if self.rst.val() {
            self.have.d.next = false;
            self.qcap.d.next = self.zero.val();
            self.fcap.d.next = self.zero.val();
            self.busy.d.next = false;
            self.pbit.d.next = false;
            self.qsh.d.next = self.zero.val();
            self.fsh.d.next = self.zero.val();
            self.cnt.d.next = self.zero.val();
            self.r.d.next = self.zero.val();
            self.t.d.next = self.zero.val();
            self.done.d.next = false;
            self.init.d.next = false;
            self.told.d.next = self.zero.val();
            self.dt.d.next = self.zero.val();
            self.s1.d.next = false;
            self.d2.d.next = self.zero.val();
            self.fh.d.next = false;
            self.fl.d.next = false;
            self.s2.d.next = false;
            self.dd.d.next = self.zero.val();
            self.incp.d.next = false;
            self.incd.d.next = false;
            self.pend.d.next = self.zero.val();
            self.pnz.d.next = false;
            self.pn.d.next = false;
            self.p1.d.next = false;
            self.stepped.d.next = false;
            self.hold.d.next = false;
            self.tm.d.next = self.zero.val();
            self.c.d.next = self.zero.val();
            self.cadd.d.next = self.one.val();
            self.ao.d.next = false;
            self.bo.d.next = false;
            self.zo.d.next = false;
            self.warn.d.next = false;
        }
        self.abz_a.next = self.ao.q.val();
        self.abz_b.next = self.bo.q.val();
        self.abz_z.next = self.zo.q.val();
        self.warning.next = self.warn.q.val();
    }
}

impl crate::cosim::step::Clocked for AbzEmulator {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for AbzEmulator {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("in_valid", 1),
            Port::new("in_qc", 32),
            Port::new("in_fine", 32),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("abz_a", 1),
            Port::new("abz_b", 1),
            Port::new("abz_z", 1),
            Port::new("warning", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.in_valid.next = r[1] != 0;
        self.in_qc.next = Bits::<32>::from(r[2]);
        self.in_fine.next = Bits::<32>::from(r[3]);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.abz_a.val() as u64,
            self.abz_b.val() as u64,
            self.abz_z.val() as u64,
            self.warning.val() as u64,
        ]
    }
}
