//! rust-hdl description of the QEP fallback.
use crate::blocks::params::Derived;
use crate::blocks::{c32, mask};
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
    /// The QEP decoder's count stepped +1 at the last clock edge (its registered `up`).
    pub qep_up: Signal<In, Bit>,
    /// The QEP decoder's count stepped -1 at the last clock edge (its registered `down`).
    pub qep_down: Signal<In, Bit>,
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
    conv_prev: DFF<Bit>,
    qq: DFF<Bits<32>>,
    qt: DFF<Bits<32>>,
    /// qq == 4PPR - 1, registered with qq (power-up 0, as qq = 0).
    qlf: DFF<Bit>,
    /// qq != 0, registered with qq (power-up 0, as qq = 0).
    qnz: DFF<Bit>,
    c1q: DFF<Bits<32>>,
    c1t: DFF<Bits<32>>,
    c2q: DFF<Bits<32>>,
    c2t: DFF<Bits<32>>,
    prevq: DFF<Bits<32>>,
    sq: DFF<Bits<32>>,
    st: DFF<Bits<32>>,
    /// sq - 4PPR and st + 1: the capture with the wrap of dq applied in advance.
    sqm: DFFWithInit<Bits<32>>,
    stp: DFFWithInit<Bits<32>>,
    /// The previous sample's capture (deep mode: two samples in flight), and the same
    /// with the wrap applied.
    sq2: DFF<Bits<32>>,
    st2: DFF<Bits<32>>,
    sq2m: DFFWithInit<Bits<32>>,
    st2p: DFFWithInit<Bits<32>>,
    /// Deep mode: a load waits for the previous sample to leave the core.
    lpend: DFF<Bit>,
    /// Capture of the sample leaving the core now (and with the wrap applied).
    csq: Signal<Local, Bits<32>>,
    cst: Signal<Local, Bits<32>>,
    csqm: Signal<Local, Bits<32>>,
    cstp: Signal<Local, Bits<32>>,
    /// Deep mode: a sample takes longer from the ADC's out_valid to the core's out_valid
    /// (correction + core latency) than one ADC period, so the next sample's out_valid comes
    /// first (the digit-serial iterative core).
    deep: Constant<Bit>,
    fast: DFF<Bit>,
    busy: DFF<Bit>,
    aligned: DFF<Bits<2>>,
    act: DFF<Bit>,
    quiet: DFF<Bits<8>>,
    load_r: DFF<Bit>,
    lqc: DFF<Bits<32>>,
    lturns: DFF<Bits<32>>,
    mis: DFF<Bit>,
    oq: DFF<Bits<32>>,
    ot: DFF<Bits<32>>,
    /// oq - 4PPR and ot + 1: the offset with the wrap of the load value applied.
    oqm: DFFWithInit<Bits<32>>,
    otp: DFFWithInit<Bits<32>>,
    /// Stage k: a good core sample (valid, no error), registered.
    kv: DFF<Bit>,
    /// Stage k: its overspeed warning.
    kw: DFF<Bit>,
    /// Stage k: its offset core - capture in 0..4PPR-1, and the turns.
    kq: DFF<Bits<32>>,
    kt: DFF<Bits<32>>,
    /// Stage k2: the good sample and its warning one clock later, with dd = kq - oq.
    kv2: DFF<Bit>,
    kw2: DFF<Bit>,
    /// dd = kq - oq tested against -1, 0, 1 modulo 4PPR: chunk compares registered from the
    /// subtraction, combined after the register (see [`NearSet`]).
    ddn: NearSet,
    /// kv2 & aligned == 3 & !act: the gate of the mismatch, registered beside kv2 (aligned
    /// and act change only at a kv2 pulse or the reset, and kv2 pulses are a sample apart).
    gk: DFF<Bit>,
    /// The tracker's motion mv = c2q - prevq tested against -1, 0, 1 (`mvn1`) and -2, 2
    /// (`mvn2`) modulo 4PPR, chunk compares registered from the subtraction, and the tests
    /// registered after them: read at the ADC's out_valid, at least three clocks after c2q
    /// and prevq last changed (a CONV rise, the previous out_valid).
    mvn1: NearSet,
    mvn2: NearSet,
    fast_n: DFF<Bit>,
    busy_n: DFF<Bit>,
    lq0: Signal<Local, Bits<32>>,
    lq1: Signal<Local, Bits<32>>,
    lq: Signal<Local, Bits<32>>,
    lt: Signal<Local, Bits<32>>,
    /// All ones when lq1 is negative, else 0 (the select of the load's two turn sums).
    lsel: Signal<Local, Bits<32>>,
    /// The load's turn sums: capture plus the offset, and plus the offset + 1.
    lt0: Signal<Local, Bits<32>>,
    lt1: Signal<Local, Bits<32>>,
    /// All ones when dq0 is negative, else 0 (the select of kt's two differences).
    ksel: Signal<Local, Bits<32>>,
    /// kt's candidates: core turns minus the capture's, and minus the capture's + 1.
    kt0: Signal<Local, Bits<32>>,
    kt1: Signal<Local, Bits<32>>,
    /// QEP count step: +1 / -1 (the count moves by at most one per clock).
    inc: Signal<Local, Bit>,
    dec: Signal<Local, Bit>,
    dq0: Signal<Local, Bits<32>>,
    dq1: Signal<Local, Bits<32>>,

    nq: Signal<Local, Bits<32>>,
    nt: Signal<Local, Bits<32>>,
    bad: Signal<Local, Bit>,
    /// 4 PPR.
    qturn: Constant<Bits<32>>,
    /// 4 PPR - 1 (the last quadrant of a turn).
    qlast: Constant<Bits<32>>,
    /// 4 PPR - 2 (the quadrant before the last).
    qlast_m1: Constant<Bits<32>>,
    /// Minus 4 PPR.
    mqturn: Constant<Bits<32>>,
    /// Mask of quadrant_bits + 1 bits: the differences of two counts in 0..4PPR-1 are
    /// unique modulo 2^(quadrant_bits + 1) >= 8PPR, so the equality tests use these bits.
    dmask: Constant<Bits<32>>,
    /// Turn mask (M bits).
    tmask: Constant<Bits<32>>,
    /// Bit quadrant_bits: the sign of a difference of two counts in 0..4PPR-1 taken
    /// modulo 2^(quadrant_bits + 1) (every such difference lies in -4PPR+1..4PPR-1).
    dsign: Constant<Bits<32>>,
    /// Mask of quadrant_bits bits: the tracker's count stays in 0..4PPR-1.
    qmask: Constant<Bits<32>>,
    /// 1.
    one: Constant<Bits<32>>,
    /// 0.
    zero: Constant<Bits<32>>,
    /// All ones.
    ones: Constant<Bits<32>>,
    /// 3: aligned samples before the checks start (the captures of the two conversions in
    /// flight predate the first alignment).
    three: Constant<Bits<2>>,
    /// 0 and 1 on the 2-bit aligned counter.
    azero: Constant<Bits<2>>,
    aone: Constant<Bits<2>>,
    /// Quiet samples before leaving fallback mode, minus one (the 8-bit quiet counter
    /// stops at QUIET_SAMPLES <= 255).
    quiet_last: Constant<Bits<8>>,
    /// 0 and 1 on the quiet counter.
    qzero: Constant<Bits<8>>,
    qone: Constant<Bits<8>>,
}

/// Quiet samples before the fallback mode ends.
pub const QUIET_SAMPLES: u32 = 8;

/// Deep mode: correction + core latency longer than one ADC period (see `Fallback::deep`).
/// At most two samples are ever in flight: the iterative core takes at most one ADC period
/// per sample (`sinedec check`), so its latency is below two periods.
pub fn deep(d: &Derived) -> bool {
    d.correction.latency_cycles() + d.latency_cycles > d.adc.period_clocks
}

impl Fallback {
    /// Fallback for the derived parameters.
    pub fn new(d: &Derived) -> Self {
        let q = d.quadrants_per_turn;
        let dm = mask(d.quadrant_bits + 1);
        // The differences of two counts in 0..4PPR-1 (in -4PPR+1..4PPR-1) that are -1, 0, 1
        // modulo 4PPR, and those that are -2, 2, modulo 2^(quadrant_bits + 1).
        let near1 = [0, 1, dm, (q - 1) & dm, 1u64.wrapping_sub(q) & dm];
        let near2 = [2, dm - 1, q.wrapping_sub(2) & dm, 2u64.wrapping_sub(q) & dm];
        // The motion's chunk compares and its tests take two clocks: the ADC's out_valid must come at least three
        // clocks after a CONV rise (it comes in the frame's last SCK cycles).
        debug_assert!(d.adc.conv_to_valid_clocks() % d.adc.period_clocks >= 3);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            enable: Default::default(),
            qep_up: Default::default(),
            qep_down: Default::default(),
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
            conv_prev: Default::default(),
            qq: Default::default(),
            qt: Default::default(),
            qlf: Default::default(),
            qnz: Default::default(),
            c1q: Default::default(),
            c1t: Default::default(),
            c2q: Default::default(),
            c2t: Default::default(),
            prevq: Default::default(),
            sq: Default::default(),
            st: Default::default(),
            sqm: DFFWithInit::new(Bits::<32>::from(q.wrapping_neg() & mask(32))),
            stp: DFFWithInit::new(Bits::<32>::from(1)),
            sq2: Default::default(),
            st2: Default::default(),
            sq2m: DFFWithInit::new(Bits::<32>::from(q.wrapping_neg() & mask(32))),
            st2p: DFFWithInit::new(Bits::<32>::from(1)),
            lpend: Default::default(),
            csq: Default::default(),
            cst: Default::default(),
            csqm: Default::default(),
            cstp: Default::default(),
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
            oqm: DFFWithInit::new(Bits::<32>::from(q.wrapping_neg() & mask(32))),
            otp: DFFWithInit::new(Bits::<32>::from(1)),
            kv: Default::default(),
            kw: Default::default(),
            kq: Default::default(),
            kt: Default::default(),
            kv2: Default::default(),
            kw2: Default::default(),
            ddn: NearSet::new(&near1, d.quadrant_bits + 1),
            gk: Default::default(),
            mvn1: NearSet::new(&near1, d.quadrant_bits + 1),
            mvn2: NearSet::new(&near2, d.quadrant_bits + 1),
            fast_n: Default::default(),
            busy_n: Default::default(),
            lq0: Default::default(),
            lq1: Default::default(),
            lq: Default::default(),
            lt: Default::default(),
            lsel: Default::default(),
            lt0: Default::default(),
            lt1: Default::default(),
            ksel: Default::default(),
            kt0: Default::default(),
            kt1: Default::default(),
            inc: Default::default(),
            dec: Default::default(),
            dq0: Default::default(),
            dq1: Default::default(),
            nq: Default::default(),
            nt: Default::default(),
            bad: Default::default(),
            qturn: c32(q),
            dmask: c32(dm),
            qlast: c32(q - 1),
            qlast_m1: c32(q - 2),
            mqturn: c32(q.wrapping_neg() & mask(32)),
            tmask: c32(mask(d.multiturn_bits)),
            dsign: c32(1 << d.quadrant_bits),
            qmask: c32(mask(d.quadrant_bits)),
            one: c32(1),
            zero: c32(0),
            ones: c32(mask(32)),
            three: Constant::new(Bits::<2>::from(3u64)),
            azero: Constant::new(Bits::<2>::from(0u64)),
            aone: Constant::new(Bits::<2>::from(1u64)),
            quiet_last: Constant::new(Bits::<8>::from(QUIET_SAMPLES as u64 - 1)),
            qzero: Constant::new(Bits::<8>::from(0u64)),
            qone: Constant::new(Bits::<8>::from(1u64)),
        }
    }
}

impl Logic for Fallback {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, conv_prev, qq, qt, c1q, c1t, c2q, c2t, prevq, sq, st, sqm, stp, sq2, st2,
            sq2m, st2p, qlf, qnz, lpend, fast, busy, aligned, act, quiet, load_r, lqc, lturns, mis,
            oq, ot, oqm, otp, kv, kw, kq, kt, kv2, kw2, gk, fast_n, busy_n
        );
        self.conv_prev.d.next = self.conv.val();
        // The QEP count's step at the last edge, registered in the decoder (flip-flops, so
        // no decode of the count precedes the tracker's logic).
        self.inc.next = self.qep_up.val();
        self.dec.next = self.qep_down.val();
        // Capture at the CONV rise.
        if self.conv.val() & !self.conv_prev.q.val() {
            self.c1q.d.next = self.qq.q.val();
            self.c1t.d.next = self.qt.q.val();
            self.c2q.d.next = self.c1q.q.val();
            self.c2t.d.next = self.c1t.q.val();
        }
        // The tracker's motion between two conversions, mv = c2q - prevq in -4PPR+1..4PPR-1;
        // modulo 4PPR it is within -2..2 (-1..1) exactly when mv is one of the values
        // tested below (equality tests, no second adder).
        self.mvn1.clk.next = self.clk.val();
        self.mvn2.clk.next = self.clk.val();
        self.mvn1.x.next = (self.c2q.q.val() - self.prevq.q.val()) & self.dmask.val();
        self.mvn2.x.next = (self.c2q.q.val() - self.prevq.q.val()) & self.dmask.val();
        self.fast_n.d.next = !(self.mvn1.hit.val() | self.mvn2.hit.val());
        self.busy_n.d.next = !self.mvn1.hit.val();
        // Load value: the sample's capture plus the QEP-to-CORDIC offset, wrapped at 4PPR
        // (lq1 = lq0 - 4PPR is not negative exactly when lq0 >= 4PPR).
        // On quadrant_bits + 1 bits (lq0 < 8PPR, lq1 in -4PPR+1..4PPR-1, the chosen one in
        // 0..4PPR-1), so the adders are that short and the sign test is bit quadrant_bits.
        self.lq0.next = (self.c2q.q.val() + self.oq.q.val()) & self.dmask.val();
        self.lq1.next = (self.c2q.q.val() + self.oqm.q.val()) & self.dmask.val();
        // The turn sums are selected by AND-OR masks, not by a multiplexer: Yosys folds
        // "s ? a + b : a + c" into a + (s ? b : c), which puts lq1's sign (the end of one
        // carry chain) in front of a second chain; this way each sum is a chain from
        // registers and the sign only drives the select (xc3sa: one chain per path).
        self.lsel.next = self.zero.val();
        if (self.lq1.val() & self.dsign.val()).any() {
            self.lsel.next = self.ones.val();
        }
        self.lq.next = (self.lq0.val() & self.lsel.val()) | (self.lq1.val() & !self.lsel.val());
        self.lt0.next = self.c2t.q.val() + self.ot.q.val();
        self.lt1.next = self.c2t.q.val() + self.otp.q.val();
        self.lt.next = (self.lt0.val() & self.lsel.val()) | (self.lt1.val() & !self.lsel.val());
        self.load_r.d.next = false;
        if self.adc_valid.val() {
            self.sq2.d.next = self.sq.q.val();
            self.st2.d.next = self.st.q.val();
            self.sq2m.d.next = self.sqm.q.val();
            self.st2p.d.next = self.stp.q.val();
            self.sq.d.next = self.c2q.q.val();
            self.st.d.next = self.c2t.q.val();
            self.sqm.d.next = self.c2q.q.val() - self.qturn.val();
            self.stp.d.next = self.c2t.q.val() + self.one.val();
            self.prevq.d.next = self.c2q.q.val();
            self.fast.d.next = self.fast_n.q.val();
            self.busy.d.next = self.busy_n.q.val();
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
        // Stage k: the sample leaving the core, its offset core - capture in 0..4PPR-1 with
        // its turns (the wrap by +4PPR, -1 turn taken from the pre-wrapped capture).
        self.csq.next = self.sq.q.val();
        self.cst.next = self.st.q.val();
        self.csqm.next = self.sqm.q.val();
        self.cstp.next = self.stp.q.val();
        if self.deep.val() {
            self.csq.next = self.sq2.q.val();
            self.cst.next = self.st2.q.val();
            self.csqm.next = self.sq2m.q.val();
            self.cstp.next = self.st2p.q.val();
        }
        // On quadrant_bits + 1 bits as lq above (dq0 in -4PPR+1..4PPR-1, the chosen one in
        // 0..4PPR-1); the turns on M bits (only kt & tmask is ever used).
        self.dq0.next = (self.core_qc.val() - self.csq.val()) & self.dmask.val();
        self.dq1.next = (self.core_qc.val() - self.csqm.val()) & self.dmask.val();
        // kq's and kt's two differences selected by AND-OR masks, as lq and lt above.
        self.ksel.next = self.zero.val();
        if (self.dq0.val() & self.dsign.val()).any() {
            self.ksel.next = self.ones.val();
        }
        self.kt0.next = (self.core_turns.val() - self.cst.val()) & self.tmask.val();
        self.kt1.next = (self.core_turns.val() - self.cstp.val()) & self.tmask.val();
        if self.core_valid.val() {
            self.kq.d.next =
                (self.dq1.val() & self.ksel.val()) | (self.dq0.val() & !self.ksel.val());
            self.kt.d.next =
                (self.kt1.val() & self.ksel.val()) | (self.kt0.val() & !self.ksel.val());
        }
        self.kv.d.next = self.core_valid.val() & !self.core_error.val();
        self.kw.d.next = self.core_warning.val();
        // Disagreement with the held offset: dq - oq in -4PPR+1..4PPR-1 is -1, 0 or 1
        // modulo 4PPR exactly when it is one of the values tested here.
        self.kv2.d.next = self.kv.q.val();
        self.kw2.d.next = self.kw.q.val();
        self.ddn.clk.next = self.clk.val();
        self.ddn.x.next = (self.kq.q.val() - self.oq.q.val()) & self.dmask.val();
        self.gk.d.next =
            self.kv.q.val() & (self.aligned.q.val() == self.three.val()) & !self.act.q.val();
        // bad & !act at a kv2 pulse: gk is kv2 & aligned == 3 & !act there.
        self.bad.next = self.gk.q.val() & !self.ddn.hit.val();
        // Tracker: the QEP steps only, wrapped into 0..4PPR-1 with the turns. The wrap tests
        // (qq == 4PPR - 1, qq == 0) are registered flags kept with qq, so no compare precedes
        // the turn adders: qq stays in 0..4PPR-1 (4PPR >= 4), so a step up lands on the last
        // quadrant exactly from 4PPR - 2 and on 0 exactly from the last, a step down on the
        // last exactly from 0 and on 0 exactly from 1.
        self.nq.next = self.qq.q.val();
        self.nt.next = self.qt.q.val();
        self.qlf.d.next = self.qlf.q.val();
        self.qnz.d.next = self.qnz.q.val();
        if self.inc.val() {
            self.qlf.d.next = self.qq.q.val() == self.qlast_m1.val();
            self.qnz.d.next = !self.qlf.q.val();
            if self.qlf.q.val() {
                self.nq.next = self.zero.val();
                self.nt.next = self.qt.q.val() + self.one.val();
            } else {
                self.nq.next = (self.qq.q.val() + self.one.val()) & self.qmask.val();
            }
        }
        if self.dec.val() {
            self.qlf.d.next = !self.qnz.q.val();
            self.qnz.d.next = (!self.qnz.q.val()) | (self.qq.q.val() != self.one.val());
            if !self.qnz.q.val() {
                self.nq.next = self.qlast.val();
                self.nt.next = self.qt.q.val() - self.one.val();
            } else {
                self.nq.next = (self.qq.q.val() - self.one.val()) & self.qmask.val();
            }
        }
        if self.kv2.q.val() & self.enable.val() {
            self.mis.d.next = self.bad.val();
            // A disagreement alone only warns: with good signals (no core error) the
            // CORDIC count is kept, so a faulty comparator line cannot move the position.
            if self.kw2.q.val() | (self.fast.q.val() & (self.aligned.q.val() == self.three.val())) {
                self.act.d.next = true;
                self.quiet.d.next = self.qzero.val();
            } else if self.act.q.val() & self.busy.q.val() {
                // Still 2 or more QEP quadrants per sample: stay in fallback mode.
                self.quiet.d.next = self.qzero.val();
            } else if self.act.q.val() {
                self.quiet.d.next = self.quiet.q.val() + self.qone.val();
                if self.quiet.q.val() == self.quiet_last.val() {
                    self.act.d.next = false;
                }
            }
            if !self.act.q.val() {
                if self.aligned.q.val() != self.three.val() {
                    self.aligned.d.next = self.aligned.q.val() + self.aone.val();
                }
                // The CORDIC count sets the offset only below the unwrap limit: after the
                // first sample, a sample with the overspeed warning or with 2 or more QEP
                // quadrants since the previous conversion (an aliased count) keeps it, so a
                // decoder started above the limit resynchronises to its first sample's count.
                if (self.aligned.q.val() == self.azero.val())
                    | !(self.kw.q.val() | self.busy.q.val())
                {
                    self.oq.d.next = self.kq.q.val();
                    self.ot.d.next = self.kt.q.val() & self.tmask.val();
                    self.oqm.d.next = self.kq.q.val() - self.qturn.val();
                    self.otp.d.next = (self.kt.q.val() & self.tmask.val()) + self.one.val();
                }
            }
        }
        self.qq.d.next = self.nq.val();
        self.qt.d.next = self.nt.val() & self.tmask.val();
        if self.rst.val() | !self.enable.val() {
            self.qq.d.next = self.zero.val();
            self.qt.d.next = self.zero.val();
            self.qlf.d.next = false;
            self.qnz.d.next = false;
            self.aligned.d.next = self.azero.val();
            self.act.d.next = false;
            self.quiet.d.next = self.qzero.val();
            self.load_r.d.next = false;
            self.lpend.d.next = false;
            self.mis.d.next = false;
            self.fast.d.next = false;
            self.busy.d.next = false;
            self.kv.d.next = false;
            self.kv2.d.next = false;
            self.gk.d.next = false;
            self.oq.d.next = self.zero.val();
            self.ot.d.next = self.zero.val();
            self.oqm.d.next = self.mqturn.val();
            self.otp.d.next = self.one.val();
        }
        self.load.next = self.load_r.q.val();
        self.load_qc.next = self.lqc.q.val();
        self.load_turns.next = self.lturns.q.val();
        self.mismatch.next = self.mis.q.val();
        self.active.next = self.act.q.val();
    }
}

/// A registered test of whether a (quadrant_bits + 1)-bit difference x is one of a few
/// constants, with no wide compare behind a register: each 4-bit chunk of x is compared
/// with the chunks the constants have there (one LUT behind x's subtraction), the distinct
/// chunk compares are registered as bits of `f`, and `hit` is the OR over the constants of
/// the AND of their chunk bits (masks of `f`), one or two LUTs of flip-flops. `hit` is the
/// test of the x presented one clock earlier.
#[derive(LogicBlock)]
pub struct NearSet {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// The difference to test (upper bits 0).
    pub x: Signal<In, Bits<32>>,
    /// x of the previous clock was one of the constants.
    pub hit: Signal<Out, Bit>,
    /// The registered chunk compares, one bit per distinct (chunk, value).
    f: DFF<Bits<32>>,
    /// Per distinct chunk compare: the chunk's value in place, its mask, its bit in `f`.
    pv: Vec<Constant<Bits<32>>>,
    pm: Vec<Constant<Bits<32>>>,
    pb: Vec<Constant<Bits<32>>>,
    /// Per constant: the bits of `f` that must all be set.
    cm: Vec<Constant<Bits<32>>>,
    /// The chunk compares being collected.
    acc: Signal<Local, Bits<32>>,
    /// 0.
    zero: Constant<Bits<32>>,
}

impl NearSet {
    /// Test against `consts` (each below 2^bits, bits <= 20: at most 32 distinct chunk
    /// compares for the at most five constants of a set).
    pub fn new(consts: &[u64], bits: u32) -> Self {
        let chunks = bits.div_ceil(4);
        let mut pairs: Vec<(u32, u64)> = Vec::new();
        let mut cm = Vec::new();
        for &c in consts {
            let mut m = 0u64;
            for k in 0..chunks {
                let key = (k, (c >> (4 * k)) & 0xf);
                let j = match pairs.iter().position(|p| *p == key) {
                    Some(j) => j,
                    None => {
                        pairs.push(key);
                        pairs.len() - 1
                    }
                };
                m |= 1 << j;
            }
            cm.push(c32(m));
        }
        debug_assert!(pairs.len() <= 32);
        Self {
            clk: Default::default(),
            x: Default::default(),
            hit: Default::default(),
            f: Default::default(),
            pv: pairs.iter().map(|&(k, v)| c32(v << (4 * k))).collect(),
            pm: pairs
                .iter()
                .map(|&(k, _)| c32((0xf << (4 * k)) & mask(bits)))
                .collect(),
            pb: (0..pairs.len()).map(|j| c32(1 << j)).collect(),
            cm,
            acc: Default::default(),
            zero: c32(0),
        }
    }
}

impl Logic for NearSet {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, f);
        self.acc.next = self.zero.val();
        for i in 0..self.pv.len() {
            if !((self.x.val() ^ self.pv[i].val()) & self.pm[i].val()).any() {
                self.acc.next = self.acc.val() | self.pb[i].val();
            }
        }
        self.f.d.next = self.acc.val();
        self.hit.next = false;
        for i in 0..self.cm.len() {
            if (self.f.q.val() & self.cm[i].val()) == self.cm[i].val() {
                self.hit.next = true;
            }
        }
    }
}
