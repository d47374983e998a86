//! rust-hdl description of the QEP fallback.
use crate::blocks::{c32, mask};
use crate::config::Derived;
use rust_hdl::prelude::*;

/// See the module docs.
#[derive(LogicBlock)]
pub struct Fallback {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// Enable (0: never active, no mismatch, no loads).
    pub enable: Signal<In, Bit>,
    /// QEP decoder count (32-bit, wrapping).
    pub qep_count: Signal<In, Bits<32>>,
    /// ADC CONV pin level.
    pub conv: Signal<In, Bit>,
    /// ADC sample strobe.
    pub adc_valid: Signal<In, Bit>,
    /// Core output strobe.
    pub core_valid: Signal<In, Bit>,
    /// Core sample rejected.
    pub core_error: Signal<In, Bit>,
    /// Core overspeed warning.
    pub core_warning: Signal<In, Bit>,
    /// Core coarse count.
    pub core_qc: Signal<In, Bits<32>>,
    /// Core turn count (M bits).
    pub core_turns: Signal<In, Bits<32>>,
    /// Resynchronise the core (one-cycle pulse).
    pub load: Signal<Out, Bit>,
    /// Coarse count for the core.
    pub load_qc: Signal<Out, Bits<32>>,
    /// Turn count for the core.
    pub load_turns: Signal<Out, Bits<32>>,
    /// QEP and CORDIC disagree by more than one quadrant (warning).
    pub mismatch: Signal<Out, Bit>,
    /// Fallback mode.
    pub active: Signal<Out, Bit>,
    cnt_prev: DFF<Bits<32>>,
    conv_prev: DFF<Bit>,
    qq: DFF<Bits<32>>,
    qt: DFF<Bits<32>>,
    c1q: DFF<Bits<32>>,
    c1t: DFF<Bits<32>>,
    c2q: DFF<Bits<32>>,
    c2t: DFF<Bits<32>>,
    prevq: DFF<Bits<32>>,
    sq: DFF<Bits<32>>,
    st: DFF<Bits<32>>,
    /// The previous sample's capture (deep mode: two samples in flight).
    sq2: DFF<Bits<32>>,
    st2: DFF<Bits<32>>,
    /// Deep mode: a load waits for the previous sample to leave the core.
    lpend: DFF<Bit>,
    /// Capture of the sample leaving the core now.
    csq: Signal<Local, Bits<32>>,
    cst: Signal<Local, Bits<32>>,
    /// Deep mode: a sample takes longer from the ADC's out_valid to the core's out_valid
    /// (correction + core latency) than one ADC period, so the next sample's out_valid comes
    /// first (the digit-serial iterative core).
    deep: Constant<Bit>,
    fast: DFF<Bit>,
    busy: DFF<Bit>,
    aligned: DFF<Bits<32>>,
    act: DFF<Bit>,
    quiet: DFF<Bits<32>>,
    load_r: DFF<Bit>,
    lqc: DFF<Bits<32>>,
    lturns: DFF<Bits<32>>,
    mis: DFF<Bit>,
    oq: DFF<Bits<32>>,
    ot: DFF<Bits<32>>,
    lq: Signal<Local, Bits<32>>,
    lt: Signal<Local, Bits<32>>,
    step: Signal<Local, Bits<32>>,
    dq: Signal<Local, Bits<32>>,
    dt: Signal<Local, Bits<32>>,
    dd: Signal<Local, Bits<32>>,
    mv: Signal<Local, Bits<32>>,
    nq: Signal<Local, Bits<32>>,
    nt: Signal<Local, Bits<32>>,
    bad: Signal<Local, Bit>,
    /// 4 PPR.
    qturn: Constant<Bits<32>>,
    /// 2 PPR (half a turn of quadrants).
    qhalf: Constant<Bits<32>>,
    /// Minus 2 PPR.
    mqhalf: Constant<Bits<32>>,
    /// Turn mask (M bits).
    tmask: Constant<Bits<32>>,
    /// Bit 31.
    sign32: Constant<Bits<32>>,
    /// 1.
    one: Constant<Bits<32>>,
    /// -1.
    minus_one: Constant<Bits<32>>,
    /// 2.
    two: Constant<Bits<32>>,
    /// -2.
    minus_two: Constant<Bits<32>>,
    /// -3.
    minus_three: Constant<Bits<32>>,
    /// 0.
    zero: Constant<Bits<32>>,
    /// 3: aligned samples before the checks start (the captures of the two conversions in
    /// flight predate the first alignment).
    three: Constant<Bits<32>>,
    /// Quiet samples before leaving fallback mode, minus one.
    quiet_last: Constant<Bits<32>>,
}

/// Quiet samples before the fallback mode ends.
pub const QUIET_SAMPLES: u32 = 8;

/// Deep mode: correction + core latency longer than one ADC period (see `Fallback::deep`).
/// At most two samples are ever in flight: the iterative core takes at most one ADC period
/// per sample (`sinedec check`), so its latency is below two periods.
pub fn deep(d: &Derived) -> bool {
    crate::blocks::correction::LATENCY_CYCLES + d.latency_cycles > d.adc.period_clocks
}

impl Fallback {
    /// Fallback for the derived parameters.
    pub fn new(d: &Derived) -> Self {
        let q = d.quadrants_per_turn;
        Self {
            clk: Default::default(),
            rst: Default::default(),
            enable: Default::default(),
            qep_count: Default::default(),
            conv: Default::default(),
            adc_valid: Default::default(),
            core_valid: Default::default(),
            core_error: Default::default(),
            core_warning: Default::default(),
            core_qc: Default::default(),
            core_turns: Default::default(),
            load: Default::default(),
            load_qc: Default::default(),
            load_turns: Default::default(),
            mismatch: Default::default(),
            active: Default::default(),
            cnt_prev: Default::default(),
            conv_prev: Default::default(),
            qq: Default::default(),
            qt: Default::default(),
            c1q: Default::default(),
            c1t: Default::default(),
            c2q: Default::default(),
            c2t: Default::default(),
            prevq: Default::default(),
            sq: Default::default(),
            st: Default::default(),
            sq2: Default::default(),
            st2: Default::default(),
            lpend: Default::default(),
            csq: Default::default(),
            cst: Default::default(),
            deep: Constant::new(deep(d)),
            fast: Default::default(),
            busy: Default::default(),
            aligned: Default::default(),
            act: Default::default(),
            quiet: Default::default(),
            load_r: Default::default(),
            lqc: Default::default(),
            lturns: Default::default(),
            mis: Default::default(),
            oq: Default::default(),
            ot: Default::default(),
            lq: Default::default(),
            lt: Default::default(),
            step: Default::default(),
            dq: Default::default(),
            dt: Default::default(),
            dd: Default::default(),
            mv: Default::default(),
            nq: Default::default(),
            nt: Default::default(),
            bad: Default::default(),
            qturn: c32(q),
            qhalf: c32(q / 2),
            mqhalf: c32((q / 2).wrapping_neg() & mask(32)),
            tmask: c32(mask(d.multiturn_bits)),
            sign32: c32(1 << 31),
            one: c32(1),
            minus_one: c32(mask(32)),
            two: c32(2),
            minus_two: c32(mask(32) - 1),
            minus_three: c32(mask(32) - 2),
            zero: c32(0),
            three: c32(3),
            quiet_last: c32(QUIET_SAMPLES as u64 - 1),
        }
    }
}

impl Logic for Fallback {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, cnt_prev, conv_prev, qq, qt, c1q, c1t, c2q, c2t, prevq, sq, st, sq2, st2,
            lpend, fast, busy, aligned, act, quiet, load_r, lqc, lturns, mis, oq, ot
        );
        self.cnt_prev.d.next = self.qep_count.val();
        self.conv_prev.d.next = self.conv.val();
        self.step.next = self.qep_count.val() - self.cnt_prev.q.val();
        // Capture at the CONV rise.
        if self.conv.val() & !self.conv_prev.q.val() {
            self.c1q.d.next = self.qq.q.val();
            self.c1t.d.next = self.qt.q.val();
            self.c2q.d.next = self.c1q.q.val();
            self.c2t.d.next = self.c1t.q.val();
        }
        // The sample's capture; the tracker's motion between two conversions.
        self.mv.next = self.c2q.q.val() - self.prevq.q.val();
        if (self.mv.val() & self.sign32.val()).any() {
            if self.mv.val() < self.mqhalf.val() {
                self.mv.next = self.mv.val() + self.qturn.val();
            }
        } else if self.mv.val() >= self.qhalf.val() {
            self.mv.next = self.mv.val() - self.qturn.val();
        }
        // Load value: the sample's capture plus the QEP-to-CORDIC offset.
        self.lq.next = self.c2q.q.val() + self.oq.q.val();
        self.lt.next = self.c2t.q.val() + self.ot.q.val();
        if self.lq.val() >= self.qturn.val() {
            self.lq.next = self.lq.val() - self.qturn.val();
            self.lt.next = self.lt.val() + self.one.val();
        }
        self.load_r.d.next = false;
        if self.adc_valid.val() {
            self.sq2.d.next = self.sq.q.val();
            self.st2.d.next = self.st.q.val();
            self.sq.d.next = self.c2q.q.val();
            self.st.d.next = self.c2t.q.val();
            self.prevq.d.next = self.c2q.q.val();
            self.fast.d.next = ((self.mv.val() >= self.three.val())
                & !(self.mv.val() & self.sign32.val()).any())
                | (((self.mv.val() & self.sign32.val()).any())
                    & (self.mv.val() <= self.minus_three.val()));
            self.busy.d.next = ((self.mv.val() >= self.two.val())
                & !(self.mv.val() & self.sign32.val()).any())
                | (((self.mv.val() & self.sign32.val()).any())
                    & (self.mv.val() <= self.minus_two.val()));
            if self.act.q.val() & self.enable.val() {
                // Deep mode: the load is issued when the previous sample leaves the core, so
                // that the counter applies it to this one.
                self.load_r.d.next = !self.deep.val();
                self.lpend.d.next = self.deep.val();
                self.lqc.d.next = self.lq.val();
                self.lturns.d.next = self.lt.val() & self.tmask.val();
            }
        }
        if self.core_valid.val() & self.lpend.q.val() {
            self.load_r.d.next = true;
            self.lpend.d.next = false;
        }
        self.csq.next = self.sq.q.val();
        self.cst.next = self.st.q.val();
        if self.deep.val() {
            self.csq.next = self.sq2.q.val();
            self.cst.next = self.st2.q.val();
        }
        // Core sample: offset of this sample (core - capture) in 0..4PPR-1 with its turns.
        self.dq.next = self.core_qc.val() - self.csq.val();
        self.dt.next = self.core_turns.val() - self.cst.val();
        if (self.dq.val() & self.sign32.val()).any() {
            self.dq.next = self.dq.val() + self.qturn.val();
            self.dt.next = self.dt.val() - self.one.val();
        }
        // Disagreement with the held offset, reduced into -2PPR..2PPR-1.
        self.dd.next = self.dq.val() - self.oq.q.val();
        if (self.dd.val() & self.sign32.val()).any() {
            if self.dd.val() < self.mqhalf.val() {
                self.dd.next = self.dd.val() + self.qturn.val();
            }
        } else if self.dd.val() >= self.qhalf.val() {
            self.dd.next = self.dd.val() - self.qturn.val();
        }
        self.bad.next = (self.aligned.q.val() == self.three.val())
            & !((self.dd.val() == self.zero.val())
                | (self.dd.val() == self.one.val())
                | (self.dd.val() == self.minus_one.val()));
        // Tracker: the QEP steps only.
        self.nq.next = self.qq.q.val() + self.step.val();
        self.nt.next = self.qt.q.val();
        if self.core_valid.val() & !self.core_error.val() & self.enable.val() {
            self.mis.d.next = self.bad.val() & !self.act.q.val();
            // A disagreement alone only warns: with good signals (no core error) the
            // CORDIC count is kept, so a faulty comparator line cannot move the position.
            if self.core_warning.val()
                | (self.fast.q.val() & (self.aligned.q.val() == self.three.val()))
            {
                self.act.d.next = true;
                self.quiet.d.next = self.zero.val();
            } else if self.act.q.val() & self.busy.q.val() {
                // Still 2 or more QEP quadrants per sample: stay in fallback mode.
                self.quiet.d.next = self.zero.val();
            } else if self.act.q.val() {
                self.quiet.d.next = self.quiet.q.val() + self.one.val();
                if self.quiet.q.val() == self.quiet_last.val() {
                    self.act.d.next = false;
                }
            }
            if !self.act.q.val() {
                if self.aligned.q.val() != self.three.val() {
                    self.aligned.d.next = self.aligned.q.val() + self.one.val();
                }
                // The CORDIC count sets the offset only below the unwrap limit: after the
                // first sample, a sample with the overspeed warning or with 2 or more QEP
                // quadrants since the previous conversion (an aliased count) keeps it, so a
                // decoder started above the limit resynchronises to its first sample's count.
                if (self.aligned.q.val() == self.zero.val())
                    | !(self.core_warning.val() | self.busy.q.val())
                {
                    self.oq.d.next = self.dq.val();
                    self.ot.d.next = self.dt.val() & self.tmask.val();
                }
            }
        }
        if (self.nq.val() & self.sign32.val()).any() {
            self.nq.next = self.nq.val() + self.qturn.val();
            self.nt.next = self.nt.val() - self.one.val();
        } else if self.nq.val() >= self.qturn.val() {
            self.nq.next = self.nq.val() - self.qturn.val();
            self.nt.next = self.nt.val() + self.one.val();
        }
        self.qq.d.next = self.nq.val();
        self.qt.d.next = self.nt.val() & self.tmask.val();
        if self.rst.val() | !self.enable.val() {
            self.qq.d.next = self.zero.val();
            self.qt.d.next = self.zero.val();
            self.aligned.d.next = self.zero.val();
            self.act.d.next = false;
            self.quiet.d.next = self.zero.val();
            self.load_r.d.next = false;
            self.lpend.d.next = false;
            self.mis.d.next = false;
            self.fast.d.next = false;
            self.busy.d.next = false;
            self.oq.d.next = self.zero.val();
            self.ot.d.next = self.zero.val();
        }
        self.load.next = self.load_r.q.val();
        self.load_qc.next = self.lqc.q.val();
        self.load_turns.next = self.lturns.q.val();
        self.mismatch.next = self.mis.q.val();
        self.active.next = self.act.q.val();
    }
}
