//! The tracker's and sums' clocked logic: [`Logic`] for [`FitCal`] (its module doc has the
//! sketch, the bit growth and the timing).
use super::*;

// The fit's logic in named stages, run in this order (`logic_stages!`): the stages of
// the module doc's pipeline.
crate::blocks::logic_stages!(FitCal: StageA, StageQ, StageB1, StageB2, StageC, StageD, StageE, Outputs);

/// Stage A: sign-extend, the differences.
impl stages::StageA for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, va0, va, da_s, nda_s, ea_s, nea_s, da_c, nda_c, ea_c, nea_c, bref_s, bref_c,
            tinit, tq, dknown, dneg, open, fresh, sg_s, sg_c, net, nb, bs_s, bs_c, c_v, c_rs,
            c_snap, c_es, c_ec, c_ms, c_mc, c_nsc, d_v, d_es, d_ec, p_ss, p_cc, p_sc, d_nsc, cnt,
            l1_s, l1_c, l2_s, l2_c, lsc, y1_s, y1_c, y2_s, y2_c, ysc, h1_s, h1_c, h2_s, h2_c, hsc,
            x1_s, x1_c, xsc, f_v, o_bs, o_bc, o_gs, o_gc, o_km, o_kn, o_up, kd_m, kd_n, e1_s, e2_s,
            e1_c, e2_c, ta, tc, h_ms, h_mc, h_nsc, ln_v, ln_rs, ln_sn, h_up, h_dn, nbge, nbmx,
            p_r1, p_r2, p_o1, p_o2, p_w1, p_w3, p_w2p, p_w2m, qb, sb, a_v, a_rs, a_rb, a_snap,
            a_ue, cl1, cl3, cl2, rs1, rs3, rs2, av0, av1, av3, av2
        );
        self.slv.clk.next = self.clk.val();
        self.slv.rst.next = self.rst.val();
        // Stage A: sign-extend; differences from b_ref and from the offsets in use, held
        // from one sample to the next (stage B2 reads them a clock after stage B1).
        self.xs.next = bit_cast::<32, 16>(self.x_sin.val()) & self.amask.val();
        if (self.xs.val() & self.asign.val()).any() {
            self.xs.next = self.xs.val() | self.asext.val();
        }
        self.xc.next = bit_cast::<32, 16>(self.x_cos.val()) & self.amask.val();
        if (self.xc.val() & self.asign.val()).any() {
            self.xc.next = self.xc.val() | self.asext.val();
        }
        self.va0.d.next = self.valid.val() & !self.rst.val();
        self.va.d.next = self.va0.q.val() & !self.rst.val();
        // 18-bit differences: x and the offsets lie in [-2^(A-1), 2^(A-1)), so each
        // difference is below 2^A <= 2^16 in magnitude and its low 18 bits are exact.
        self.das.next = bit_cast::<18, 32>(self.xs.val()) - bit_cast::<18, 32>(self.bref_s.q.val());
        self.dac.next = bit_cast::<18, 32>(self.xc.val()) - bit_cast::<18, 32>(self.bref_c.q.val());
        self.eas.next =
            bit_cast::<18, 32>(self.xs.val()) - bit_cast::<18, 32>(self.slv.off_s.val());
        self.eac.next =
            bit_cast::<18, 32>(self.xc.val()) - bit_cast::<18, 32>(self.slv.off_c.val());
        if self.valid.val() {
            self.da_s.d.next = self.das.val();
            self.nda_s.d.next =
                bit_cast::<18, 32>(self.bref_s.q.val()) - bit_cast::<18, 32>(self.xs.val());
            self.ea_s.d.next = self.eas.val();
            self.nea_s.d.next =
                bit_cast::<18, 32>(self.slv.off_s.val()) - bit_cast::<18, 32>(self.xs.val());
            self.da_c.d.next = self.dac.val();
            self.nda_c.d.next =
                bit_cast::<18, 32>(self.bref_c.q.val()) - bit_cast::<18, 32>(self.xc.val());
            self.ea_c.d.next = self.eac.val();
            self.nea_c.d.next =
                bit_cast::<18, 32>(self.slv.off_c.val()) - bit_cast::<18, 32>(self.xc.val());
            // b_ref changes at this clock's edge (the previous sample restarted the window):
            // this sample's entry is e = x - b_cur, the new b_ref.
            self.fresh.d.next = self.a_rs.q.val();
            // The signs stage Q takes the quadrant from: those of d, or of e when b_ref is
            // being loaded with b_cur at this clock's edge (one LUT after the subtractors'
            // top bits, so stage Q's step is one LUT of four registers).
            self.sg_s.d.next = self.das.val().get_bit(17);
            self.sg_c.d.next = self.dac.val().get_bit(17);
            if self.a_rs.q.val() {
                self.sg_s.d.next = self.eas.val().get_bit(17);
                self.sg_c.d.next = self.eac.val().get_bit(17);
            }
        }
    }
}

/// Stage Q: the quadrant and step; the window's compares and operands.
impl stages::StageQ for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        // Stage Q, a clock after A: the quadrant (CORDIC mapper convention) and step,
        // registered for stage B1, from the signs registered in stage A (of d, or of e when
        // b_ref was being loaded with b_cur at stage A); tq is the previous sample's. No
        // carry chain in front of these LUTs.
        self.q.next = self.q0.val();
        if self.sg_s.q.val() {
            if self.sg_c.q.val() {
                self.q.next = self.q2.val();
            } else {
                self.q.next = self.q3.val();
            }
        } else if self.sg_c.q.val() {
            self.q.next = self.q1.val();
        }
        // q - tq mod 4 as logic (a borrow into bit 1), not a second carry chain after d's.
        self.stp.next = (self.q.val() ^ self.tq.q.val())
            ^ (((!self.q.val()) & self.tq.q.val() & self.q1.val()) << self.one32.val());
        self.qb.d.next = self.q.val();
        self.sb.d.next = self.stp.val();
        // Free-running compares of net and N: |net + s| >= 4K for each step s, N >= min_samples,
        // N >= N_MAX (final two clocks after a sample's stage B1; while a restart clears net
        // and N (a_rs), they describe net = 0 and N = 1). The window closes only where
        // net + s is a multiple of 4 (the p_w* flags below match net mod 4), and there, with
        // q = floor(net / 4), net + s is 4 (q + 1) for s = +1 and +2 (net mod 4 = 3, 2) and
        // 4 q for s = -1 and -2 (net mod 4 = 1, 2): two tests of q's 30 bits, |q + 1| >= K
        // (h_up) and |q| >= K (h_dn), stand for the four. A clock later they and the
        // tracker's flags below form one free-running register per step class and outcome
        // (cl*, rs*, av*), final three clocks after the sample's stage B1, in time for the
        // next sample's (samples at least three clocks apart).
        self.netq.next = (self.net.q.val() ^ self.sign32.val()) >> self.two32.val();
        self.h_up.d.next = ((self.netq.val() >= self.ge_up.val())
            | (self.netq.val() < self.lt_up.val()))
            & !self.a_rs.q.val();
        self.h_dn.d.next = ((self.netq.val() >= self.ge_dn.val())
            | (self.netq.val() < self.lt_dn.val()))
            & !self.a_rs.q.val();
        self.nbge.d.next = self.nb.q.val() >= self.nmin.val();
        self.nbmx.d.next = (self.nb.q.val() & self.nmax.val()).any() & !self.a_rs.q.val();
        if self.a_rs.q.val() {
            self.nbge.d.next = self.one32.val() >= self.nmin.val();
        }
        // The decision's other operands, registered beside the compares from the tracker's
        // state (written in stage B1) and net mod 4 (0 while a restart clears net).
        // An open window implies tinit (both are written at every sample, tinit true, and
        // cleared by reset), so the open terms leave tinit out.
        self.p_r1.d.next = self.tinit.q.val() & !self.open.q.val();
        self.p_r2.d.next = self.tinit.q.val() & self.dknown.q.val() & !self.open.q.val();
        self.p_o1.d.next = self.open.q.val();
        self.p_o2.d.next = self.dknown.q.val() & self.open.q.val();
        self.p_w1.d.next = self.open.q.val()
            & !self.a_rs.q.val()
            & ((self.net.q.val() & self.m2.val()) == self.r3.val());
        self.p_w3.d.next = self.open.q.val()
            & !self.a_rs.q.val()
            & ((self.net.q.val() & self.m2.val()) == self.r1.val());
        self.p_w2p.d.next = self.dknown.q.val()
            & !self.dneg.q.val()
            & self.open.q.val()
            & !self.a_rs.q.val()
            & ((self.net.q.val() & self.m2.val()) == self.r2.val());
        self.p_w2m.d.next = self.dknown.q.val()
            & self.dneg.q.val()
            & self.open.q.val()
            & !self.a_rs.q.val()
            & ((self.net.q.val() & self.m2.val()) == self.r2.val());
    }
}

/// Stage B1: the step and the window decision; the restart.
impl stages::StageB1 for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        // The per-step-class flags (registered: formed from the compares and the tracker's
        // flags in the clock before stage B1). Stage B1: the step as a word and the window
        // decision, the registered flags chosen by the step. A 2-step with no known direction, or
        // the first sample, restarts the tracker (nothing taken, the window closed).
        self.sval.next = self.zero32.val();
        if self.sb.q.val() == self.q1.val() {
            self.sval.next = self.sp1.val();
        }
        if self.sb.q.val() == self.q3.val() {
            self.sval.next = self.sm1.val();
        }
        if self.sb.q.val() == self.q2.val() {
            self.sval.next = self.sp2.val();
            if self.dneg.q.val() {
                self.sval.next = self.sm2.val();
            }
        }
        self.cl1.d.next = self.p_w1.q.val() & self.h_up.q.val() & self.nbge.q.val();
        self.cl3.d.next = self.p_w3.q.val() & self.h_dn.q.val() & self.nbge.q.val();
        self.cl2.d.next = ((self.p_w2p.q.val() & self.h_up.q.val())
            | (self.p_w2m.q.val() & self.h_dn.q.val()))
            & self.nbge.q.val();
        self.rs1.d.next = self.p_r1.q.val() | self.cl1.d.val();
        self.rs3.d.next = self.p_r1.q.val() | self.cl3.d.val();
        self.rs2.d.next = self.p_r2.q.val() | self.cl2.d.val();
        self.av0.d.next = self.p_o1.q.val() & !self.nbmx.q.val();
        self.av1.d.next = self.rs1.d.val() | self.av0.d.val();
        self.av3.d.next = self.rs3.d.val() | self.av0.d.val();
        self.av2.d.next = self.rs2.d.val() | (self.p_o2.q.val() & !self.nbmx.q.val());
        self.rsd.next = false;
        self.a_v.d.next = false;
        self.a_snap.d.next = false;
        if self.va.q.val() {
            self.a_v.d.next = self.av0.q.val();
            if self.sb.q.val() == self.q1.val() {
                self.rsd.next = self.rs1.q.val();
                self.a_v.d.next = self.av1.q.val();
                self.a_snap.d.next = self.cl1.q.val();
            }
            if self.sb.q.val() == self.q3.val() {
                self.rsd.next = self.rs3.q.val();
                self.a_v.d.next = self.av3.q.val();
                self.a_snap.d.next = self.cl3.q.val();
            }
            if self.sb.q.val() == self.q2.val() {
                self.rsd.next = self.rs2.q.val();
                self.a_v.d.next = self.av2.q.val();
                self.a_snap.d.next = self.cl2.q.val();
            }
        }
        // The restart (a window opens, or closes and the next one opens at this sample)
        // and its copies: b_ref's loads and the entry from e.
        self.a_rs.d.next = self.rsd.val();
        self.a_rb.d.next = !self.rsd.val();
        self.a_ue.d.next = self.rsd.val() | self.fresh.q.val();
        if self.va.q.val() {
            self.tq.d.next = self.qb.q.val();
            self.net.d.next = self.net.q.val() + self.sval.val();
            self.nb.d.next = self.nb.q.val() + self.one32.val();
            self.tinit.d.next = true;
            // The window stays open exactly when it takes the sample.
            self.open.d.next = self.a_v.d.val();
            if self.tinit.q.val()
                & ((self.sb.q.val() == self.q1.val()) | (self.sb.q.val() == self.q3.val()))
            {
                self.dknown.d.next = true;
                self.dneg.d.next = self.sb.q.val() == self.q3.val();
            }
        }
    }
}

/// Stage B2: the decision's actions.
impl stages::StageB2 for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        // Stage B2, a clock after B1: the decision's actions. A restart loads b_ref with the
        // offsets in use (the window's snapshot keeps the old one) and clears net and N; the
        // command to the sums carries the entry of the sample (d, or e = x - b_cur at a
        // restart or right after one).
        if self.a_rs.q.val() {
            self.net.d.next = self.zero32.val();
            self.nb.d.next = self.one32.val();
        }
        if !self.a_rb.q.val() {
            self.bref_s.d.next = self.slv.off_s.val();
            self.bref_c.d.next = self.slv.off_c.val();
        }
        if self.a_snap.q.val() {
            self.bs_s.d.next = self.bref_s.q.val();
            self.bs_c.d.next = self.bref_c.q.val();
        }
        self.c_v.d.next = self.a_v.q.val();
        self.c_rs.d.next = self.a_rs.q.val();
        self.c_snap.d.next = self.a_snap.q.val();
        self.ds.next = self.da_s.q.val();
        self.dc.next = self.da_c.q.val();
        self.c_ms.d.next = bit_cast::<16, 18>(self.da_s.q.val());
        if self.da_s.q.val().get_bit(17) {
            self.c_ms.d.next = bit_cast::<16, 18>(self.nda_s.q.val());
        }
        self.c_mc.d.next = bit_cast::<16, 18>(self.da_c.q.val());
        if self.da_c.q.val().get_bit(17) {
            self.c_mc.d.next = bit_cast::<16, 18>(self.nda_c.q.val());
        }
        if self.a_ue.q.val() {
            self.ds.next = self.ea_s.q.val();
            self.dc.next = self.ea_c.q.val();
            self.c_ms.d.next = bit_cast::<16, 18>(self.ea_s.q.val());
            if self.ea_s.q.val().get_bit(17) {
                self.c_ms.d.next = bit_cast::<16, 18>(self.nea_s.q.val());
            }
            self.c_mc.d.next = bit_cast::<16, 18>(self.ea_c.q.val());
            if self.ea_c.q.val().get_bit(17) {
                self.c_mc.d.next = bit_cast::<16, 18>(self.nea_c.q.val());
            }
        }
        self.c_es.d.next = self.ds.val();
        self.c_ec.d.next = self.dc.val();
        self.c_nsc.d.next = self.ds.val().get_bit(17) ^ self.dc.val().get_bit(17);
    }
}

/// Stage C: the products on one shift-add tree.
impl stages::StageC for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        // Stage C: the three products of the entry on one shift-add tree of run-time codes,
        // one a clock: phase 0 (a clock after stage C) |e_s|², phase 1 |e_c|², phase 2
        // |e_s e_c|, each from the operand registers ta, tc (so the tree's level 1 reads
        // registers only); the flags of stage C follow in shift lines (bit j: j + 1 clocks
        // after stage C). Samples at least three clocks apart keep the phases apart.
        self.ln_v.d.next =
            (self.ln_v.q.val() << self.one32.val()) | bit_cast::<8, 1>(self.c_v.q.val().into());
        self.ln_rs.d.next = (self.ln_rs.q.val() << self.one32.val())
            | bit_cast::<8, 1>((self.c_v.q.val() & self.c_rs.q.val()).into());
        self.ln_sn.d.next = (self.ln_sn.q.val() << self.one32.val())
            | bit_cast::<8, 1>((self.c_v.q.val() & self.c_snap.q.val()).into());
        if self.c_v.q.val() {
            self.h_ms.d.next = self.c_ms.q.val();
            self.h_mc.d.next = self.c_mc.q.val();
            self.h_nsc.d.next = self.c_nsc.q.val();
            self.e1_s.d.next = self.c_es.q.val();
            self.e1_c.d.next = self.c_ec.q.val();
        }
        self.ta.d.next = self.c_ms.q.val();
        self.tc.d.next = self.c_ms.q.val();
        if self.ln_v.q.val().get_bit(0) {
            self.ta.d.next = self.h_mc.q.val();
            self.tc.d.next = self.h_mc.q.val();
        }
        if self.ln_v.q.val().get_bit(1) {
            self.ta.d.next = self.h_ms.q.val();
            self.tc.d.next = self.h_mc.q.val();
        }
        self.tr.clk.next = self.clk.val();
        self.tr.rst.next = self.rst.val();
        self.tr.a.next = self.ta.q.val();
        self.tr.code.next = self.tc.q.val();
        self.tr.v.next = false;
        // The sign is held from stage C: the tree returns it with phase 2's product.
        self.tr.neg.next = self.h_nsc.q.val();
        // e1 (held from stage C) moves to e2 in phase 2, read by stage D three clocks later.
        if self.ln_v.q.val().get_bit(2) {
            self.e2_s.d.next = self.e1_s.q.val();
            self.e2_c.d.next = self.e1_c.q.val();
        }
    }
}

/// Stage D: the products registered; the snapshot.
impl stages::StageD for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        // Stage D: each product registered as its phase leaves the tree (phase 0 four
        // clocks after stage C, phases 1 and 2 a clock and two later), and in the clock
        // after phase 2 the sign-extended entries and the flags, so stage E adds all five.
        self.pr.next = self.tr.out_x.val() + self.tr.out_y.val();
        if self.ln_v.q.val().get_bit(3) {
            self.p_ss.d.next = self.pr.val();
        }
        if self.ln_v.q.val().get_bit(4) {
            self.p_cc.d.next = self.pr.val();
        }
        self.d_v.d.next = self.ln_v.q.val().get_bit(5);
        self.d_es.d.next = bit_cast::<64, 18>(self.e2_s.q.val());
        if self.e2_s.q.val().get_bit(17) {
            self.d_es.d.next = bit_cast::<64, 18>(self.e2_s.q.val()) | self.sext64.val();
        }
        self.d_ec.d.next = bit_cast::<64, 18>(self.e2_c.q.val());
        if self.e2_c.q.val().get_bit(17) {
            self.d_ec.d.next = bit_cast::<64, 18>(self.e2_c.q.val()) | self.sext64.val();
        }
        // The cross product's sign is applied here, after its adder (one LUT a bit), as a
        // ones' complement whose +1 is stage E's carry-in: an adder then a subtractor in
        // one stage put a negation chain in front of the sum's chain.
        self.nscm.next = self.zero64.val();
        if self.tr.out_neg.val() {
            self.nscm.next = self.ones64.val();
        }
        if self.ln_v.q.val().get_bit(5) {
            self.p_sc.d.next = bit_cast::<64, 32>(self.pr.val()) ^ self.nscm.val();
            self.d_nsc.d.next = self.tr.out_neg.val();
        }
        // The snapshot goes to an idle solver as the closing sample's phase 2 leaves the
        // tree: the sums hold the window's last sample by then (its stage E2, at least
        // three clocks later in the pipeline, was at least one clock earlier).
        self.slv.start.next = self.ln_sn.q.val().get_bit(5) & !self.slv.busy.val();
    }
}

/// Stages E and E2: the sums.
impl stages::StageE for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        // Stage E: the sums' low halves as 33-bit sums on registers, the carries
        // registered; stage E2, a clock later: the high halves, high addend plus carry. Each
        // is one 33- or 32-bit chain instead of one 64-bit chain; the high half lags a clock,
        // and samples are at least three clocks apart, so a sample's E2 ends before the next
        // sample's E and before any snapshot. A restart clears the sums and N a clock before
        // the sample's stage E (the clock the snapshot is taken; no stage E or E2 of an
        // earlier sample is that late), as the registers' synchronous reset, so no
        // restart select stands in front of the adders.
        self.nsci.next = self.zero33.val();
        if self.d_nsc.q.val() {
            self.nsci.next = self.one33.val();
        }
        self.w1_s.next = bit_cast::<33, 32>(self.l1_s.q.val())
            + bit_cast::<33, 32>(bit_cast::<32, 64>(self.d_es.q.val()));
        self.w1_c.next = bit_cast::<33, 32>(self.l1_c.q.val())
            + bit_cast::<33, 32>(bit_cast::<32, 64>(self.d_ec.q.val()));
        self.w2_s.next =
            bit_cast::<33, 32>(self.l2_s.q.val()) + bit_cast::<33, 32>(self.p_ss.q.val());
        self.w2_c.next =
            bit_cast::<33, 32>(self.l2_c.q.val()) + bit_cast::<33, 32>(self.p_cc.q.val());
        // lsc -+ |e_s e_c| = lsc + (p_sc, inverted when negative) + carry-in.
        self.wsc.next = bit_cast::<33, 32>(self.lsc.q.val())
            + bit_cast::<33, 32>(bit_cast::<32, 64>(self.p_sc.q.val()))
            + self.nsci.val();
        self.f_v.d.next = self.d_v.q.val();
        if self.d_v.q.val() {
            self.l1_s.d.next = bit_cast::<32, 33>(self.w1_s.val());
            self.l1_c.d.next = bit_cast::<32, 33>(self.w1_c.val());
            self.l2_s.d.next = bit_cast::<32, 33>(self.w2_s.val());
            self.l2_c.d.next = bit_cast::<32, 33>(self.w2_c.val());
            self.lsc.d.next = bit_cast::<32, 33>(self.wsc.val());
            self.y1_s.d.next = self.w1_s.val().get_bit(32);
            self.y1_c.d.next = self.w1_c.val().get_bit(32);
            self.y2_s.d.next = self.w2_s.val().get_bit(32);
            self.y2_c.d.next = self.w2_c.val().get_bit(32);
            self.ysc.d.next = self.wsc.val().get_bit(32);
            self.x1_s.d.next = bit_cast::<32, 64>(self.d_es.q.val() >> self.s32w.val());
            self.x1_c.d.next = bit_cast::<32, 64>(self.d_ec.q.val() >> self.s32w.val());
            self.xsc.d.next = bit_cast::<32, 64>(self.p_sc.q.val() >> self.s32w.val());
            self.cnt.d.next = self.cnt.q.val() + self.one32.val();
        }
        if self.f_v.q.val() {
            self.h1_s.d.next =
                self.h1_s.q.val() + self.x1_s.q.val() + bit_cast::<32, 1>(self.y1_s.q.val().into());
            self.h1_c.d.next =
                self.h1_c.q.val() + self.x1_c.q.val() + bit_cast::<32, 1>(self.y1_c.q.val().into());
            self.h2_s.d.next = self.h2_s.q.val() + bit_cast::<32, 1>(self.y2_s.q.val().into());
            self.h2_c.d.next = self.h2_c.q.val() + bit_cast::<32, 1>(self.y2_c.q.val().into());
            self.hsc.d.next =
                self.hsc.q.val() + self.xsc.q.val() + bit_cast::<32, 1>(self.ysc.q.val().into());
        }
        if self.ln_rs.q.val().get_bit(5) {
            self.l1_s.d.next = self.zero32.val();
            self.l1_c.d.next = self.zero32.val();
            self.l2_s.d.next = self.zero32.val();
            self.l2_c.d.next = self.zero32.val();
            self.lsc.d.next = self.zero32.val();
            self.h1_s.d.next = self.zero32.val();
            self.h1_c.d.next = self.zero32.val();
            self.h2_s.d.next = self.zero32.val();
            self.h2_c.d.next = self.zero32.val();
            self.hsc.d.next = self.zero32.val();
            self.cnt.d.next = self.zero32.val();
        }
        self.slv.n.next = self.cnt.q.val();
        self.slv.s1_s.next = (bit_cast::<64, 32>(self.h1_s.q.val()) << self.s32w.val())
            | bit_cast::<64, 32>(self.l1_s.q.val());
        self.slv.s1_c.next = (bit_cast::<64, 32>(self.h1_c.q.val()) << self.s32w.val())
            | bit_cast::<64, 32>(self.l1_c.q.val());
        self.slv.s2_s.next = (bit_cast::<64, 32>(self.h2_s.q.val()) << self.s32w.val())
            | bit_cast::<64, 32>(self.l2_s.q.val());
        self.slv.s2_c.next = (bit_cast::<64, 32>(self.h2_c.q.val()) << self.s32w.val())
            | bit_cast::<64, 32>(self.l2_c.q.val());
        self.slv.ssc.next = (bit_cast::<64, 32>(self.hsc.q.val()) << self.s32w.val())
            | bit_cast::<64, 32>(self.lsc.q.val());
        self.slv.bref_s.next = self.bs_s.q.val();
        self.slv.bref_c.next = self.bs_c.q.val();
        if self.rst.val() {
            self.tinit.d.next = false;
            self.open.d.next = false;
            self.dknown.d.next = false;
            self.dneg.d.next = false;
            self.fresh.d.next = false;
            self.net.d.next = self.zero32.val();
            self.nb.d.next = self.zero32.val();
            self.bref_s.d.next = self.b0_s.val();
            self.bref_c.d.next = self.b0_c.val();
            self.a_v.d.next = false;
            self.a_rs.d.next = false;
            self.a_rb.d.next = true;
            self.a_snap.d.next = false;
            self.c_v.d.next = false;
            self.ln_v.d.next = self.zero8.val();
            self.ln_rs.d.next = self.zero8.val();
            self.ln_sn.d.next = self.zero8.val();
            self.d_v.d.next = false;
        }
    }
}

/// The outputs.
impl stages::Outputs for FitCal {
    #[hdl_gen]
    fn update(&mut self) {
        // The outputs: copies of the solver's coefficient registers, a clock later (the
        // tracker above reads the solver's own), reset with them.
        self.o_bs.d.next = self.slv.off_s.val();
        self.o_bc.d.next = self.slv.off_c.val();
        self.o_gs.d.next = self.slv.g_s.val();
        self.o_gc.d.next = self.slv.g_c.val();
        self.o_km.d.next = self.slv.k_mag.val();
        self.o_kn.d.next = self.slv.k_neg.val();
        self.o_up.d.next = self.slv.done.val();
        if self.rst.val() {
            self.o_bs.d.next = self.b0_s.val();
            self.o_bc.d.next = self.b0_c.val();
            self.o_gs.d.next = self.g0_s.val();
            self.o_gc.d.next = self.g0_c.val();
            self.o_km.d.next = self.zero16.val();
            self.o_kn.d.next = false;
            self.o_up.d.next = false;
        }
        self.b_sin.next = self.o_bs.q.val();
        self.b_cos.next = self.o_bc.q.val();
        self.g_sin.next = self.o_gs.q.val();
        self.g_cos.next = self.o_gc.q.val();
        self.k_mag.next = self.o_km.q.val();
        self.k_neg.next = self.o_kn.q.val();
        self.update.next = self.o_up.q.val();
        self.kd_m.d.next = self.o_km.q.val();
        self.kd_n.d.next = self.o_kn.q.val();
        self.k_mag_d.next = self.kd_m.q.val();
        self.k_neg_d.next = self.kd_n.q.val();
    }
}
