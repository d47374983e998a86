//! The logic of [`Fallback`] (`super`), in named stages.
use super::*;

// The tracker's logic in named stages, run in this order (`logic_stages!`): the capture
// at CONV and the load it issues, the comparison of the sample leaving the core, the QEP
// tracker and its mode, then the registers' commit, reset and the outputs.
crate::blocks::logic_stages!(Fallback: Capture, Compare, Track, Commit);

/// The capture at each conversion start (the sampling edge), the tracker's motion between
/// conversions and the load.
impl stages::Capture for Fallback {
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
        // Capture at the conversion start's rise (the sampling edge): K = 1, c1 takes the
        // tracker and c2 the capture before, so c2 holds the capture of the sample the ADC
        // delivers next (see `capture_depth`).
        if self.conv.val() & !self.conv_prev.q.val() {
            self.c1q.d.next = self.qq.q.val();
            self.c1t.d.next = self.qt.q.val();
            self.c2q.d.next = self.c1q.q.val();
            self.c2t.d.next = self.c1t.q.val();
        }
        // K = 2: one more capture in front of c1.
        for i in 0..self.c0q.len() {
            self.c0q[i].clock.next = self.clk.val();
            self.c0t[i].clock.next = self.clk.val();
            self.c0q[i].d.next = self.c0q[i].q.val();
            self.c0t[i].d.next = self.c0t[i].q.val();
            if self.conv.val() & !self.conv_prev.q.val() {
                self.c0q[i].d.next = self.qq.q.val();
                self.c0t[i].d.next = self.qt.q.val();
                self.c1q.d.next = self.c0q[i].q.val();
                self.c1t.d.next = self.c0t[i].q.val();
            }
        }
        // K = 0 (no pipeline): the sample's own capture goes straight to c2.
        for i in 0..self.direct.len() {
            if self.conv.val() & !self.conv_prev.q.val() & self.direct[i].val() {
                self.c2q.d.next = self.qq.q.val();
                self.c2t.d.next = self.qt.q.val();
            }
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
    }
}

/// The sample leaving the core against its capture and the held offset.
impl stages::Compare for Fallback {
    #[hdl_gen]
    fn update(&mut self) {
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
    }
}

/// The QEP tracker and the fallback mode.
impl stages::Track for Fallback {
    #[hdl_gen]
    fn update(&mut self) {
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
    }
}

/// The tracker's registers, reset, and the outputs.
impl stages::Commit for Fallback {
    #[hdl_gen]
    fn update(&mut self) {
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
