//! The solver's state machine: [`Logic`] for [`FitSolve`] (its module doc has the
//! sketch and the bit growth).
use super::*;

impl Logic for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, busy_r, s_ms, s_mc, s_vs, s_vc, s_cq, s_m1, s_m2, s_m3, s_cv, s_sqs, s_sqc,
            s_chk, s_sn, s_sn2, s_offa, s_cs, s_offb, s_offc, s_q1, s_gc, s_q2, s_ts, s_kd, s_load,
            s_dadj, s_dtst, s_dinc, p_mc, p_vs, p_vc, p_cq, p_m1, p_m2, p_m3, p_cv, p_sqc, p_chk,
            p_sn, p_sn2, p_offa, p_offb, p_q1, p_gc, p_q2, p_ts, p_kd, p_load, f_ret, u_x, u_d,
            u_r, u_mag, u_q, u_neg, u_rnd, u_adj, u_adjq, uxs, it, sn, a1_s, a1_c, n1_s, n1_c,
            a2_s, a2_c, asc, asc_h, asl, ash, alz, nsc, br_s, br_c, m_s, m_c, v_s, v_c, cc, cmag,
            cpos, amp_s, amp_c, smag, sneg, cs, t_s, t_c, o_s, o_c, ng_s, ng_c, q2, r_os, r_oc,
            r_gs, r_gc, r_km, r_kn, r_done, f_div, f_sq, f_mul, f_add, f_sh1, f_sh2, f_qx, f_qd,
            f_last, f_ld, f_80, neg_n, oa, ob, x_a1s, x_uxr, x_scl, x_t30, x_urk, x_q, x_en, d_sn,
            d_udr, d_uq, d_ur, d_scl, d_one, d_en, clr_r, rx_uxr, rx_scl, rx_urk, rx_a1c8, rx_a2s,
            rx_a2c, rx_asc, rx_vs2, rx_tgs, rx_ms32, rx_mc32, rx_vc2, rx_amps32, rx_ampc32,
            rx_cmag16, rx_tgc, rx_tamp32, uxr, uxa, uxb, uxc, rd_st, rd_uq, rd_ur, rd_scl, rd_one,
            rd_sn, rd_ms, rd_mc, rd_cs, rd_smag, rd_q2, rd_amps, udr, vsel, vd, ccp, ccm, ccn, xr,
            rz, req, t30, scl, ngf, lo_s, lo_c, oor_sl, oor_sh, oor_cl, oor_ch, xh1, xh2, xh3, xl,
            xgt_s, xge_s, xff, big_s, big_c, mnz
        );
        // The shared adder, non-restoring, one step over two clocks: a B clock writes the
        // chain's operands oa / ob (free-running, one LUT each from registers: u_r, its sign,
        // u_x's top bits, u_d and the registered flags), the next A clock (f_add) writes
        // their sum into u_r, the chain and nothing else. A remainder below zero adds the
        // divisor (or the square root's trial 4q + 3) back instead of subtracting it (4q + 1),
        // so the sign of the sum is the complement of the quotient bit and the sum is the next
        // remainder. A multiplication (MSB first) doubles u_r and adds u_d when the top bit of
        // u_x is one (the "minus" sum with 0 otherwise).
        self.rneg.next = self.u_r.q.val().get_bit(51);
        self.opa.next = self.u_r.q.val() << self.one32.val();
        if self.f_div.q.val() & !self.f_last.q.val() {
            self.opa.next = (self.u_r.q.val() << self.one32.val())
                | bit_cast::<52, 64>(self.u_x.q.val() >> self.s63.val());
        }
        if self.f_sq.q.val() {
            self.opa.next = (self.u_r.q.val() << self.two32.val())
                | bit_cast::<52, 64>(self.u_x.q.val() >> self.s62.val());
        }
        self.up.next = self.rneg.val();
        if self.f_mul.q.val() {
            self.up.next = self.u_x.q.val().get_bit(63);
        }
        // up ? u_d : !u_d (!0 in a multiplication), carry in !up; in a square root u_d holds
        // 8 q + 1 (q before this step's bit), which gives 4 q' + 3 / !(4 q' + 1) with bit 1
        // set and bit 2 clear (q' = 2 q + bit), except the first step's -1 (bit 2 set).
        self.opb.next = !self.u_d.q.val();
        if self.f_mul.q.val() {
            self.opb.next = self.ones52.val();
        }
        if self.up.val() {
            self.opb.next = self.u_d.q.val();
        }
        if self.f_sq.q.val() {
            self.opb.next = (self.opb.val() & self.nb2.val()) | self.b1.val();
            if !self.f_qd.q.val() {
                self.opb.next = self.opb.val() | self.b2.val();
            }
        }
        self.oa.d.next = self.opa.val();
        self.ob.d.next = bit_cast::<53, 52>(self.opb.val()) << self.one32.val();
        if !self.up.val() {
            self.ob.d.next =
                (bit_cast::<53, 52>(self.opb.val()) << self.one32.val()) | self.one53.val();
        }
        self.adjw.next = self.zero24.val();
        if self.u_adj.q.val() {
            self.adjw.next = self.one24.val();
        }
        self.adjqw.next = self.zero64.val();
        if self.u_adjq.q.val() {
            self.adjqw.next = self.one64.val();
        }
        // Free-running registers: compares and negations one clock ahead of their use.
        self.xr.d.next = (self.u_r.q.val() ^ self.u_d.q.val())
            ^ ((self.u_r.q.val() | self.u_d.q.val()) << self.one32.val());
        self.rz.d.next = self.u_r.q.val() == self.zero52.val();
        self.req.d.next = self.xr.q.val() == self.zero52.val();
        // The subtractions and the sum that end a product's state (V_s -= m_s², V_c -= m_c²,
        // C = Cq -+ |m_s m_c|), free-running from the product in u_r (final from the run's
        // last B clock on): the state after the return loads them through a LUT, not a chain.
        // Each is exact in its width when it is read: u_r then holds m² or |m_s m_c| (< 2^48)
        // or S² (< 2^27), and V (|V| < 2^48), C (|C| < 2^49), 2^30 - S² fit.
        self.vsel.d.next = self.v_s.q.val();
        if self.p_m3.q.val() {
            self.vsel.d.next = self.v_c.q.val();
        }
        self.vd.d.next = self.vsel.q.val() - bit_cast::<49, 52>(self.u_r.q.val());
        self.ccp.d.next = self.cc.q.val() + bit_cast::<50, 52>(self.u_r.q.val());
        self.ccm.d.next = self.cc.q.val() - bit_cast::<50, 52>(self.u_r.q.val());
        self.ccn.d.next = bit_cast::<48, 50>(self.zero50.val() - self.cc.q.val());
        self.t30.d.next = self.two30.val() - bit_cast::<31, 52>(self.u_r.q.val());
        self.lo_s.d.next = self.amp_s.q.val() < self.minamp.val();
        self.lo_c.d.next = self.amp_c.q.val() < self.minamp.val();
        // Offsets out of range: one register per compare (the four chains lie beside
        // their offsets; Q1 ORs the flags).
        self.oor_sl.d.next = (self.o_s.q.val() ^ self.sign32.val()) < self.lo_f.val();
        self.oor_sh.d.next = (self.o_s.q.val() ^ self.sign32.val()) >= self.hi_f.val();
        self.oor_cl.d.next = (self.o_c.q.val() ^ self.sign32.val()) < self.lo_f.val();
        self.oor_ch.d.next = (self.o_c.q.val() ^ self.sign32.val()) >= self.hi_f.val();
        // u_mag's compares from the quotient it rounds (u_mag = u_x + adj): u_x is final from
        // the division's rounding sum on, so these are settled when DivNeg reads big_s / big_c /
        // mnz (u_mag > K <=> u_x > K - adj, K < 2^16; u_mag != 0 <=> u_x != 0 | adj).
        self.xh1.d.next = bit_cast::<16, 64>(self.u_x.q.val() >> self.s16.val()).any();
        self.xh2.d.next = bit_cast::<16, 64>(self.u_x.q.val() >> self.s32.val()).any();
        self.xh3.d.next = bit_cast::<16, 64>(self.u_x.q.val() >> self.s48.val()).any();
        self.xl.d.next = bit_cast::<16, 64>(self.u_x.q.val()).any();
        self.xgt_s.d.next = bit_cast::<16, 64>(self.u_x.q.val()) > self.smax16.val();
        self.xge_s.d.next = bit_cast::<16, 64>(self.u_x.q.val()) >= self.smax16.val();
        self.xff.d.next = bit_cast::<16, 64>(self.u_x.q.val()) == self.cmax16.val();
        self.xh.next = self.xh1.q.val() | self.xh2.q.val() | self.xh3.q.val();
        self.big_s.d.next = self.xh.val() | self.xgt_s.q.val();
        if self.u_adj.q.val() {
            self.big_s.d.next = self.xh.val() | self.xge_s.q.val();
        }
        self.big_c.d.next = self.xh.val() | (self.u_adj.q.val() & self.xff.q.val());
        self.mnz.d.next = self.xh.val() | self.xl.q.val() | self.u_adj.q.val();
        // u_x with its bits inverted for a negative quotient (free-running; u_x and u_neg are
        // settled from the rounding sum on): DivInc adds adj ^ u_neg to it.
        self.uxs.d.next = self.u_x.q.val();
        if self.u_neg.q.val() {
            self.uxs.d.next = !self.u_x.q.val();
        }
        self.scl.d.next = bit_cast::<16, 24>(self.u_mag.q.val());
        if self.big_s.q.val() {
            self.scl.d.next = self.smax16.val();
        }
        self.ngf.d.next = bit_cast::<16, 24>(self.u_mag.q.val());
        if self.big_c.q.val() {
            self.ngf.d.next = self.cmax16.val();
        }
        self.r_done.d.next = false;
        // One-hot control: a flag per state, each set for one clock by the state before (a
        // set-up state's successor is pending in `p_*` while its run goes on and follows
        // `f_ret`). The wide registers load on one flag each.
        self.go.next = !self.busy_r.q.val() & self.start.val();
        self.s_ms.d.next = self.go.val();
        self.s_mc.d.next = self.p_mc.q.val() & self.f_ret.q.val();
        self.s_vs.d.next = self.p_vs.q.val() & self.f_ret.q.val();
        self.s_vc.d.next = self.p_vc.q.val() & self.f_ret.q.val();
        self.s_cq.d.next = self.p_cq.q.val() & self.f_ret.q.val();
        self.s_m1.d.next = self.p_m1.q.val() & self.f_ret.q.val();
        self.s_m2.d.next = self.p_m2.q.val() & self.f_ret.q.val();
        self.s_m3.d.next = self.p_m3.q.val() & self.f_ret.q.val();
        self.s_cv.d.next = self.p_cv.q.val() & self.f_ret.q.val();
        self.s_sqs.d.next = self.s_cv.q.val();
        self.s_sqc.d.next = self.p_sqc.q.val() & self.f_ret.q.val();
        self.s_chk.d.next = self.p_chk.q.val() & self.f_ret.q.val();
        self.s_sn.d.next = self.p_sn.q.val() & self.f_ret.q.val();
        self.s_sn2.d.next = self.p_sn2.q.val() & self.f_ret.q.val();
        self.s_offa.d.next = self.p_offa.q.val() & self.f_ret.q.val();
        self.s_cs.d.next = self.s_offa.q.val();
        self.s_offb.d.next = self.p_offb.q.val() & self.f_ret.q.val();
        self.s_offc.d.next = self.s_offb.q.val();
        self.s_q1.d.next = self.p_q1.q.val() & self.f_ret.q.val();
        self.s_gc.d.next = self.p_gc.q.val() & self.f_ret.q.val();
        self.s_q2.d.next = self.p_q2.q.val() & self.f_ret.q.val();
        self.s_ts.d.next = self.p_ts.q.val() & self.f_ret.q.val();
        self.s_kd.d.next = self.p_kd.q.val() & self.f_ret.q.val();
        self.s_load.d.next = self.p_load.q.val() & self.f_ret.q.val();
        self.s_dadj.d.next = self.f_div.q.val() & self.f_last.q.val();
        self.s_dtst.d.next = self.s_dadj.q.val();
        self.s_dinc.d.next = self.s_dtst.q.val();
        // The checks refuse at Sn (amplitude, its compares registered since Chk) and at Q1
        // (offsets, registered since OffC): no run, nothing pending, busy_r clears.
        self.ok_sn.next = self.s_sn.q.val() & !(self.lo_s.q.val() | self.lo_c.q.val());
        self.ok_q1.next = self.s_q1.q.val()
            & !(self.oor_sl.q.val()
                | self.oor_sh.q.val()
                | self.oor_cl.q.val()
                | self.oor_ch.q.val());
        // Pending successors: set by the set-up state, held until the return.
        self.p_mc.d.next = self.s_ms.q.val() | (self.p_mc.q.val() & !self.f_ret.q.val());
        self.p_vs.d.next = self.s_mc.q.val() | (self.p_vs.q.val() & !self.f_ret.q.val());
        self.p_vc.d.next = self.s_vs.q.val() | (self.p_vc.q.val() & !self.f_ret.q.val());
        self.p_cq.d.next = self.s_vc.q.val() | (self.p_cq.q.val() & !self.f_ret.q.val());
        self.p_m1.d.next = self.s_cq.q.val() | (self.p_m1.q.val() & !self.f_ret.q.val());
        self.p_m2.d.next = self.s_m1.q.val() | (self.p_m2.q.val() & !self.f_ret.q.val());
        self.p_m3.d.next = self.s_m2.q.val() | (self.p_m3.q.val() & !self.f_ret.q.val());
        self.p_cv.d.next = self.s_m3.q.val() | (self.p_cv.q.val() & !self.f_ret.q.val());
        self.p_sqc.d.next = self.s_sqs.q.val() | (self.p_sqc.q.val() & !self.f_ret.q.val());
        self.p_chk.d.next = self.s_sqc.q.val() | (self.p_chk.q.val() & !self.f_ret.q.val());
        self.p_sn.d.next = self.s_chk.q.val() | (self.p_sn.q.val() & !self.f_ret.q.val());
        self.p_sn2.d.next = self.ok_sn.val() | (self.p_sn2.q.val() & !self.f_ret.q.val());
        self.p_offa.d.next = self.s_sn2.q.val() | (self.p_offa.q.val() & !self.f_ret.q.val());
        self.p_offb.d.next = self.s_cs.q.val() | (self.p_offb.q.val() & !self.f_ret.q.val());
        self.p_q1.d.next = self.s_offc.q.val() | (self.p_q1.q.val() & !self.f_ret.q.val());
        self.p_gc.d.next = self.ok_q1.val() | (self.p_gc.q.val() & !self.f_ret.q.val());
        self.p_q2.d.next = self.s_gc.q.val() | (self.p_q2.q.val() & !self.f_ret.q.val());
        self.p_ts.d.next = self.s_q2.q.val() | (self.p_ts.q.val() & !self.f_ret.q.val());
        self.p_kd.d.next = self.s_ts.q.val() | (self.p_kd.q.val() & !self.f_ret.q.val());
        self.p_load.d.next = self.s_kd.q.val() | (self.p_load.q.val() & !self.f_ret.q.val());
        self.busy_r.d.next = self.go.val()
            | (self.busy_r.q.val()
                & !(self.s_load.q.val()
                    | (self.s_sn.q.val() & !self.ok_sn.val())
                    | (self.s_q1.q.val() & !self.ok_q1.val())));
        // The selects a return takes (u_x, u_d), set by the set-up state, held until the
        // return; u_x's sources of the uxr groups and u_d's static sources are final long
        // before it and reach u_x / u_d through free-running registers (uxr, udr).
        self.rx_a1c8.d.next = self.s_ms.q.val() | (self.rx_a1c8.q.val() & !self.f_ret.q.val());
        self.rx_a2s.d.next = self.s_mc.q.val() | (self.rx_a2s.q.val() & !self.f_ret.q.val());
        self.rx_a2c.d.next = self.s_vs.q.val() | (self.rx_a2c.q.val() & !self.f_ret.q.val());
        self.rx_asc.d.next = self.s_vc.q.val() | (self.rx_asc.q.val() & !self.f_ret.q.val());
        self.rx_ms32.d.next =
            self.s_cq.q.val() | self.s_m2.q.val() | (self.rx_ms32.q.val() & !self.f_ret.q.val());
        self.rx_mc32.d.next = self.s_m1.q.val() | (self.rx_mc32.q.val() & !self.f_ret.q.val());
        self.rx_vs2.d.next = self.s_m3.q.val() | (self.rx_vs2.q.val() & !self.f_ret.q.val());
        self.rx_vc2.d.next = self.s_sqs.q.val() | (self.rx_vc2.q.val() & !self.f_ret.q.val());
        self.rx_amps32.d.next =
            self.s_sqc.q.val() | self.s_gc.q.val() | (self.rx_amps32.q.val() & !self.f_ret.q.val());
        self.rx_cmag16.d.next = self.s_chk.q.val() | (self.rx_cmag16.q.val() & !self.f_ret.q.val());
        self.rx_scl.d.next = self.ok_sn.val() | (self.rx_scl.q.val() & !self.f_ret.q.val());
        self.rx_tgs.d.next = self.s_cs.q.val() | (self.rx_tgs.q.val() & !self.f_ret.q.val());
        self.rx_ampc32.d.next =
            self.s_offc.q.val() | (self.rx_ampc32.q.val() & !self.f_ret.q.val());
        self.rx_tgc.d.next = self.ok_q1.val() | (self.rx_tgc.q.val() & !self.f_ret.q.val());
        self.rx_tamp32.d.next = self.s_q2.q.val() | (self.rx_tamp32.q.val() & !self.f_ret.q.val());
        self.rx_urk.d.next = self.s_ts.q.val() | (self.rx_urk.q.val() & !self.f_ret.q.val());
        self.rx_uxr.d.next = self.rx_a1c8.q.val()
            | self.rx_a2s.q.val()
            | self.rx_a2c.q.val()
            | self.rx_asc.q.val()
            | self.rx_vs2.q.val()
            | self.rx_ms32.q.val()
            | self.rx_mc32.q.val()
            | self.rx_vc2.q.val()
            | self.rx_amps32.q.val()
            | self.rx_ampc32.q.val()
            | self.rx_cmag16.q.val()
            | self.rx_tgs.q.val()
            | self.rx_tgc.q.val()
            | self.rx_tamp32.q.val();
        self.rd_sn.d.next = self.s_ms.q.val()
            | self.s_mc.q.val()
            | self.s_vs.q.val()
            | self.s_vc.q.val()
            | (self.rd_sn.q.val() & !self.f_ret.q.val());
        self.rd_ms.d.next = self.s_cq.q.val() | (self.rd_ms.q.val() & !self.f_ret.q.val());
        self.rd_mc.d.next =
            self.s_m1.q.val() | self.s_m2.q.val() | (self.rd_mc.q.val() & !self.f_ret.q.val());
        self.rd_one.d.next = self.s_sqs.q.val() | (self.rd_one.q.val() & !self.f_ret.q.val());
        self.rd_uq.d.next = self.s_sqc.q.val() | (self.rd_uq.q.val() & !self.f_ret.q.val());
        self.rd_ur.d.next =
            self.s_chk.q.val() | self.ok_q1.val() | (self.rd_ur.q.val() & !self.f_ret.q.val());
        self.rd_scl.d.next = self.ok_sn.val() | (self.rd_scl.q.val() & !self.f_ret.q.val());
        self.rd_amps.d.next = self.s_cs.q.val() | (self.rd_amps.q.val() & !self.f_ret.q.val());
        self.rd_cs.d.next =
            self.s_offc.q.val() | self.s_gc.q.val() | (self.rd_cs.q.val() & !self.f_ret.q.val());
        self.rd_smag.d.next = self.s_q2.q.val() | (self.rd_smag.q.val() & !self.f_ret.q.val());
        self.rd_q2.d.next = self.s_ts.q.val() | (self.rd_q2.q.val() & !self.f_ret.q.val());
        self.rd_st.d.next = self.rd_sn.q.val()
            | self.rd_ms.q.val()
            | self.rd_mc.q.val()
            | self.rd_amps.q.val()
            | self.rd_cs.q.val()
            | self.rd_smag.q.val()
            | self.rd_q2.q.val();
        // The loads of u_x and u_d in the next clock, one flag per source (a return takes the
        // stored selects and clears u_r: every state a return enters reads u_r, if at all,
        // before the clear), and their enables.
        self.x_a1s.d.next = self.go.val();
        self.x_uxr.d.next = self.f_ret.q.val() & self.rx_uxr.q.val();
        self.x_scl.d.next = self.f_ret.q.val() & self.rx_scl.q.val();
        self.x_t30.d.next = self.s_offa.q.val();
        self.x_urk.d.next = self.f_ret.q.val() & self.rx_urk.q.val();
        self.x_q.d.next = self.s_dinc.q.val();
        self.d_sn.d.next = self.go.val();
        self.d_udr.d.next = self.f_ret.q.val() & self.rd_st.q.val();
        self.d_uq.d.next = self.f_ret.q.val() & self.rd_uq.q.val();
        self.d_ur.d.next = self.f_ret.q.val() & self.rd_ur.q.val();
        self.d_scl.d.next = self.f_ret.q.val() & self.rd_scl.q.val();
        self.d_one.d.next =
            self.s_cv.q.val() | self.s_offa.q.val() | (self.f_ret.q.val() & self.rd_one.q.val());
        self.clr_r.d.next = self.go.val()
            | self.s_cv.q.val()
            | self.s_offa.q.val()
            | self.s_offb.q.val()
            | self.f_ret.q.val();
        // Run: B and A clocks alternate from a B clock (B_0, the operands of the first step;
        // `it` loads the step count) to a B clock (the last step's result bit); `it` counts
        // the A clocks. Decoded from the mode flags, set by the set-up state.
        self.run.next = self.f_div.q.val() | self.f_sq.q.val() | self.f_mul.q.val();
        // A B clock that is not the last: the next clock is an A clock.
        self.step.next = self.run.val() & !self.f_add.q.val() & !self.f_last.q.val();
        self.f_div.d.next = self.s_ms.q.val()
            | self.s_mc.q.val()
            | self.s_vs.q.val()
            | self.s_vc.q.val()
            | self.s_cq.q.val()
            | self.ok_sn.val()
            | self.s_offc.q.val()
            | self.s_gc.q.val()
            | self.s_kd.q.val()
            | (self.f_div.q.val() & !self.f_last.q.val());
        self.f_sq.d.next = self.s_sqs.q.val()
            | self.s_sqc.q.val()
            | self.s_cs.q.val()
            | (self.f_sq.q.val() & !self.f_last.q.val());
        self.f_mul.d.next = self.s_m1.q.val()
            | self.s_m2.q.val()
            | self.s_m3.q.val()
            | self.s_chk.q.val()
            | self.s_sn2.q.val()
            | self.ok_q1.val()
            | self.s_q2.q.val()
            | self.s_ts.q.val()
            | (self.f_mul.q.val() & !self.f_last.q.val());
        // The 80-step (truncating) divisions, and the sign the division being set up
        // applies: one clock each, read in B_0.
        self.f_80.d.next = self.s_vs.q.val() | self.s_vc.q.val() | self.s_cq.q.val();
        self.neg_n.d.next = (self.s_ms.q.val() & self.n1_s.q.val())
            | (self.s_mc.q.val() & self.n1_c.q.val())
            | (self.s_cq.q.val() & self.nsc.q.val())
            | (self.s_sn.q.val() & self.cpos.q.val())
            | (self.s_kd.q.val() & self.sneg.q.val());
        // f_ld: no run in the clock before (B_0 of a run, and every clock outside one).
        self.f_ld.d.next = !self.run.val();
        if self.f_ld.q.val() {
            self.it.d.next = self.i32c.val();
            if self.f_div.q.val() {
                self.it.d.next = self.i64c.val();
                if self.f_80.q.val() {
                    self.it.d.next = self.i80c.val();
                }
            }
        }
        if self.f_ld.q.val() & self.f_div.q.val() {
            self.u_rnd.d.next = !self.f_80.q.val();
            self.u_neg.d.next = self.neg_n.q.val();
        }
        if self.run.val() & self.f_add.q.val() {
            self.it.d.next = self.it.q.val() - self.one8.val();
        }
        self.f_add.d.next =
            self.step.val() | (self.f_div.q.val() & self.f_last.q.val() & self.u_rnd.q.val());
        self.f_sh1.d.next = self.step.val() & !self.f_sq.q.val();
        self.f_sh2.d.next = self.step.val() & self.f_sq.q.val();
        self.f_qx.d.next = self.f_div.q.val() & self.f_add.q.val();
        self.f_qd.d.next = self.f_sq.q.val() & self.f_add.q.val();
        self.f_last.d.next =
            self.run.val() & self.f_add.q.val() & (self.it.q.val() == self.one8.val());
        // A return: a product's or square root's last B clock (a division goes on to DivAdj:
        // s_dadj), or a division's sign state.
        self.f_ret.d.next = self.s_dinc.q.val()
            | ((self.f_sq.q.val() | self.f_mul.q.val())
                & self.f_add.q.val()
                & (self.it.q.val() == self.one8.val()));
        self.x_en.d.next = self.go.val()
            | (self.f_ret.q.val()
                & (self.rx_uxr.q.val() | self.rx_scl.q.val() | self.rx_urk.q.val()))
            | self.s_offa.q.val()
            | self.s_dinc.q.val()
            | self.step.val();
        self.d_en.d.next = self.go.val()
            | (self.f_ret.q.val()
                & (self.rd_st.q.val()
                    | self.rd_uq.q.val()
                    | self.rd_ur.q.val()
                    | self.rd_scl.q.val()
                    | self.rd_one.q.val()))
            | self.s_cv.q.val()
            | self.s_offa.q.val()
            | (self.f_sq.q.val() & self.f_add.q.val());
        // The states' register writes.
        if self.go.val() {
            self.sn.d.next = bit_cast::<25, 32>(self.n.val());
            self.a1_s.d.next = bit_cast::<40, 64>(self.s1_s.val());
            self.n1_s.d.next = (self.s1_s.val() & self.sign63.val()).any();
            if (self.s1_s.val() & self.sign63.val()).any() {
                self.a1_s.d.next = bit_cast::<40, 64>(self.zero64.val() - self.s1_s.val());
            }
            self.a1_c.d.next = bit_cast::<40, 64>(self.s1_c.val());
            self.n1_c.d.next = (self.s1_c.val() & self.sign63.val()).any();
            if (self.s1_c.val() & self.sign63.val()).any() {
                self.a1_c.d.next = bit_cast::<40, 64>(self.zero64.val() - self.s1_c.val());
            }
            self.a2_s.d.next = bit_cast::<56, 64>(self.s2_s.val());
            self.a2_c.d.next = bit_cast::<56, 64>(self.s2_c.val());
            self.asc.d.next = bit_cast::<56, 64>(self.ssc.val());
            self.nsc.d.next = (self.ssc.val() & self.sign63.val()).any();
            self.br_s.d.next = self.bref_s.val();
            self.br_c.d.next = self.bref_c.val();
        }
        // The clock after Ms: asc takes |Σsc|, -x = ~x + 1 from registers (a select): the
        // low half 0 - lo, the high half 0 - hi when lo = 0, else ~hi. The halves' chains
        // run in Ms from asc (the load's Σsc), beside it. asc is first read at the return
        // after Vc.
        self.asl.d.next = self.zero28.val() - bit_cast::<28, 56>(self.asc.q.val());
        self.ash.d.next =
            self.zero28.val() - bit_cast::<28, 56>(self.asc.q.val() >> self.s28.val());
        self.alz.d.next = bit_cast::<28, 56>(self.asc.q.val()) == self.zero28.val();
        self.asc_h.d.next = self.s_ms.q.val() & self.nsc.q.val();
        if self.asc_h.q.val() {
            self.asc.d.next =
                (bit_cast::<56, 28>(!bit_cast::<28, 56>(self.asc.q.val() >> self.s28.val()))
                    << self.s28.val())
                    | bit_cast::<56, 28>(self.asl.q.val());
            if self.alz.q.val() {
                self.asc.d.next = (bit_cast::<56, 28>(self.ash.q.val()) << self.s28.val())
                    | bit_cast::<56, 28>(self.asl.q.val());
            }
        }
        if self.s_mc.q.val() {
            self.m_s.d.next = self.u_mag.q.val();
        }
        if self.s_vs.q.val() {
            self.m_c.d.next = self.u_mag.q.val();
        }
        if self.s_vc.q.val() {
            self.v_s.d.next = bit_cast::<49, 64>(self.u_x.q.val());
        }
        if self.s_cq.q.val() {
            self.v_c.d.next = bit_cast::<49, 64>(self.u_x.q.val());
        }
        if self.s_m1.q.val() {
            self.cc.d.next = bit_cast::<50, 64>(self.u_x.q.val());
        }
        if self.s_m2.q.val() {
            self.v_s.d.next = self.vd.q.val();
        }
        if self.s_m3.q.val() {
            self.v_c.d.next = self.vd.q.val();
        }
        if self.s_cv.q.val() {
            // C = Cq - m_s m_c, the product's sign from the means' signs.
            self.cc.d.next = self.ccm.q.val();
            if self.n1_s.q.val() ^ self.n1_c.q.val() {
                self.cc.d.next = self.ccp.q.val();
            }
        }
        if self.s_sqc.q.val() {
            // |C| and the sign of -C (rdiv's sign below; C = 0 gives 0 either way), a run
            // after C's load, from C or its free-running negation: a select, no chain.
            self.cmag.d.next = bit_cast::<48, 50>(self.cc.q.val());
            self.cpos.d.next = true;
            if self.cc.q.val().get_bit(49) {
                self.cmag.d.next = self.ccn.q.val();
                self.cpos.d.next = false;
            }
        }
        if self.s_sqc.q.val() {
            self.amp_s.d.next = bit_cast::<25, 52>(self.u_d.q.val() >> self.s3.val());
        }
        if self.s_chk.q.val() {
            self.amp_c.d.next = bit_cast::<25, 52>(self.u_d.q.val() >> self.s3.val());
        }
        if self.s_sn2.q.val() {
            self.smag.d.next = self.scl.q.val();
            self.sneg.d.next = self.u_neg.q.val();
        }
        if self.s_offa.q.val() {
            self.t_s.d.next =
                (bit_cast::<32, 24>(self.m_s.q.val()) + self.half8.val()) >> self.s8.val();
            self.t_c.d.next =
                (bit_cast::<32, 24>(self.m_c.q.val()) + self.half8.val()) >> self.s8.val();
        }
        if self.s_offb.q.val() {
            self.cs.d.next = bit_cast::<16, 52>(self.u_d.q.val() >> self.s3.val());
            self.o_s.d.next = self.br_s.q.val() + self.t_s.q.val();
            if self.n1_s.q.val() {
                self.o_s.d.next = self.br_s.q.val() - self.t_s.q.val();
            }
            self.o_c.d.next = self.br_c.q.val() + self.t_c.q.val();
            if self.n1_c.q.val() {
                self.o_c.d.next = self.br_c.q.val() - self.t_c.q.val();
            }
        }
        if self.s_q1.q.val() {
            self.ng_s.d.next = self.ngf.q.val();
        }
        if self.s_q2.q.val() {
            self.ng_c.d.next = self.ngf.q.val();
        }
        if self.s_ts.q.val() {
            self.q2.d.next = bit_cast::<40, 52>(self.u_r.q.val());
        }
        if self.s_load.q.val() {
            self.r_km.d.next = self.ngf.q.val();
            self.r_kn.d.next = self.sneg.q.val() & self.mnz.q.val();
            self.r_os.d.next = self.o_s.q.val();
            self.r_oc.d.next = self.o_c.q.val();
            self.r_gs.d.next = self.ng_s.q.val();
            self.r_gc.d.next = self.ng_c.q.val();
            self.r_done.d.next = true;
        }
        // DivAdj: a rounding division adds 2 u_r -+ u_d in this clock (2 r >= d is its sign);
        // a truncating one keeps u_r while `req` settles.
        // The true remainder is u_r, or u_r + u_d when u_r < 0 (zero when u_r = -u_d: `req`);
        // truncation toward zero adds one to a negative quotient when r != 0.
        self.adjn.next = self.u_neg.q.val() & !self.rz.q.val();
        if self.rneg.val() {
            self.adjn.next = self.u_neg.q.val() & !self.req.q.val();
        }
        if self.u_rnd.q.val() {
            self.adjn.next = !self.rneg.val();
        }
        if self.s_dtst.q.val() {
            self.u_adj.d.next = self.adjn.val();
            self.u_adjq.d.next = self.adjn.val() ^ self.u_neg.q.val();
        }
        if self.s_dinc.q.val() {
            // u_mag = u_x + adj, and the signed quotient u_q = u_mag or -(u_x + adj) =
            // !u_x + !adj, one chain each from registers: u_q = uxs + (adj ^ u_neg).
            self.u_mag.d.next = bit_cast::<24, 64>(self.u_x.q.val()) + self.adjw.val();
            self.u_q.d.next = self.uxs.q.val() + self.adjqw.val();
        }
        // DivNeg: u_x takes u_q (x_q), f_ret returns.
        // Reset: idle, no state, pending state or stored select, and the mode flags cleared
        // (the run's flags follow them). The load flags act for one more clock on working
        // registers that every solve loads or clears before it reads them.
        if self.rst.val() {
            self.busy_r.d.next = false;
            self.f_ret.d.next = false;
            self.s_ms.d.next = false;
            self.asc_h.d.next = false;
            self.s_mc.d.next = false;
            self.s_vs.d.next = false;
            self.s_vc.d.next = false;
            self.s_cq.d.next = false;
            self.s_m1.d.next = false;
            self.s_m2.d.next = false;
            self.s_m3.d.next = false;
            self.s_cv.d.next = false;
            self.s_sqs.d.next = false;
            self.s_sqc.d.next = false;
            self.s_chk.d.next = false;
            self.s_sn.d.next = false;
            self.s_sn2.d.next = false;
            self.s_offa.d.next = false;
            self.s_cs.d.next = false;
            self.s_offb.d.next = false;
            self.s_offc.d.next = false;
            self.s_q1.d.next = false;
            self.s_gc.d.next = false;
            self.s_q2.d.next = false;
            self.s_ts.d.next = false;
            self.s_kd.d.next = false;
            self.s_load.d.next = false;
            self.s_dadj.d.next = false;
            self.s_dtst.d.next = false;
            self.s_dinc.d.next = false;
            self.p_mc.d.next = false;
            self.p_vs.d.next = false;
            self.p_vc.d.next = false;
            self.p_cq.d.next = false;
            self.p_m1.d.next = false;
            self.p_m2.d.next = false;
            self.p_m3.d.next = false;
            self.p_cv.d.next = false;
            self.p_sqc.d.next = false;
            self.p_chk.d.next = false;
            self.p_sn.d.next = false;
            self.p_sn2.d.next = false;
            self.p_offa.d.next = false;
            self.p_offb.d.next = false;
            self.p_q1.d.next = false;
            self.p_gc.d.next = false;
            self.p_q2.d.next = false;
            self.p_ts.d.next = false;
            self.p_kd.d.next = false;
            self.p_load.d.next = false;
            self.rx_a1c8.d.next = false;
            self.rx_a2s.d.next = false;
            self.rx_a2c.d.next = false;
            self.rx_asc.d.next = false;
            self.rx_ms32.d.next = false;
            self.rx_mc32.d.next = false;
            self.rx_vs2.d.next = false;
            self.rx_vc2.d.next = false;
            self.rx_amps32.d.next = false;
            self.rx_cmag16.d.next = false;
            self.rx_scl.d.next = false;
            self.rx_tgs.d.next = false;
            self.rx_ampc32.d.next = false;
            self.rx_tgc.d.next = false;
            self.rx_tamp32.d.next = false;
            self.rx_urk.d.next = false;
            self.rd_sn.d.next = false;
            self.rd_ms.d.next = false;
            self.rd_mc.d.next = false;
            self.rd_one.d.next = false;
            self.rd_uq.d.next = false;
            self.rd_ur.d.next = false;
            self.rd_scl.d.next = false;
            self.rd_amps.d.next = false;
            self.rd_cs.d.next = false;
            self.rd_smag.d.next = false;
            self.rd_q2.d.next = false;
            self.f_div.d.next = false;
            self.f_sq.d.next = false;
            self.f_mul.d.next = false;
            self.r_os.d.next = self.b0_s.val();
            self.r_oc.d.next = self.b0_c.val();
            self.r_gs.d.next = self.g0_s.val();
            self.r_gc.d.next = self.g0_c.val();
            self.r_km.d.next = self.zero16.val();
            self.r_kn.d.next = false;
            self.r_done.d.next = false;
        }
        // udr: the static sources of a return's u_d, selected by rd_* (zero when none; the
        // flags are one-hot, so the selects are ANDed and ORed).
        self.udn.next = self.zero52.val();
        if self.rd_sn.q.val() {
            self.udn.next = self.udn.val() | bit_cast::<52, 25>(self.sn.q.val());
        }
        if self.rd_ms.q.val() {
            self.udn.next = self.udn.val() | bit_cast::<52, 24>(self.m_s.q.val());
        }
        if self.rd_mc.q.val() {
            self.udn.next = self.udn.val() | bit_cast::<52, 24>(self.m_c.q.val());
        }
        if self.rd_amps.q.val() {
            self.udn.next = self.udn.val() | bit_cast::<52, 25>(self.amp_s.q.val());
        }
        if self.rd_cs.q.val() {
            self.udn.next = self.udn.val() | bit_cast::<52, 16>(self.cs.q.val());
        }
        if self.rd_smag.q.val() {
            self.udn.next = self.udn.val() | bit_cast::<52, 16>(self.smag.q.val());
        }
        if self.rd_q2.q.val() {
            self.udn.next = self.udn.val() | bit_cast::<52, 40>(self.q2.q.val());
        }
        self.udr.d.next = self.udn.val();
        // The sources a return loads into u_x (final long before it) through free-running
        // registers, selected by rx_* in three groups (uxa, uxb, uxc; the flags are one-hot,
        // so the selects are ANDed and ORed), then ORed into uxr.
        self.uxan.next = self.zero64.val();
        self.uxbn.next = self.zero64.val();
        self.uxcn.next = self.zero64.val();
        if self.rx_a1c8.q.val() {
            self.uxan.next =
                self.uxan.val() | (bit_cast::<64, 40>(self.a1_c.q.val()) << self.s8.val());
        }
        if self.rx_a2s.q.val() {
            self.uxan.next = self.uxan.val() | bit_cast::<64, 56>(self.a2_s.q.val());
        }
        if self.rx_a2c.q.val() {
            self.uxan.next = self.uxan.val() | bit_cast::<64, 56>(self.a2_c.q.val());
        }
        if self.rx_asc.q.val() {
            self.uxan.next = self.uxan.val() | bit_cast::<64, 56>(self.asc.q.val());
        }
        if self.rx_vs2.q.val() & !self.v_s.q.val().get_bit(48) {
            self.uxan.next =
                self.uxan.val() | (bit_cast::<64, 49>(self.v_s.q.val()) << self.one32.val());
        }
        if self.rx_ms32.q.val() {
            self.uxbn.next =
                self.uxbn.val() | (bit_cast::<64, 24>(self.m_s.q.val()) << self.s32.val());
        }
        if self.rx_mc32.q.val() {
            self.uxbn.next =
                self.uxbn.val() | (bit_cast::<64, 24>(self.m_c.q.val()) << self.s32.val());
        }
        if self.rx_vc2.q.val() & !self.v_c.q.val().get_bit(48) {
            self.uxbn.next =
                self.uxbn.val() | (bit_cast::<64, 49>(self.v_c.q.val()) << self.one32.val());
        }
        if self.rx_amps32.q.val() {
            self.uxbn.next =
                self.uxbn.val() | (bit_cast::<64, 25>(self.amp_s.q.val()) << self.s32.val());
        }
        if self.rx_ampc32.q.val() {
            self.uxcn.next =
                self.uxcn.val() | (bit_cast::<64, 25>(self.amp_c.q.val()) << self.s32.val());
        }
        if self.rx_cmag16.q.val() {
            self.uxcn.next =
                self.uxcn.val() | (bit_cast::<64, 48>(self.cmag.q.val()) << self.s16.val());
        }
        if self.rx_tgs.q.val() {
            self.uxcn.next = self.uxcn.val() | self.tgs.val();
        }
        if self.rx_tgc.q.val() {
            self.uxcn.next = self.uxcn.val() | self.tgc.val();
        }
        if self.rx_tamp32.q.val() {
            self.uxcn.next = self.uxcn.val() | self.tamp32.val();
        }
        self.uxa.d.next = self.uxan.val();
        self.uxb.d.next = self.uxbn.val();
        self.uxc.d.next = self.uxcn.val();
        self.uxr.d.next = self.uxa.q.val() | self.uxb.q.val() | self.uxc.q.val();
        // u_x: its sources by one-hot registered flags, ANDed and ORed, under one registered
        // enable; then the division's quotient bit from the adder into bit 0.
        self.uxn.next = self.zero64.val();
        if self.x_a1s.q.val() {
            self.uxn.next =
                self.uxn.val() | (bit_cast::<64, 40>(self.a1_s.q.val()) << self.s8.val());
        }
        if self.x_uxr.q.val() {
            self.uxn.next = self.uxn.val() | self.uxr.q.val();
        }
        if self.x_scl.q.val() {
            self.uxn.next =
                self.uxn.val() | (bit_cast::<64, 16>(self.scl.q.val()) << self.s32.val());
        }
        if self.x_t30.q.val() {
            self.uxn.next = self.uxn.val() | bit_cast::<64, 31>(self.t30.q.val());
        }
        if self.x_urk.q.val() {
            self.uxn.next =
                self.uxn.val() | (bit_cast::<64, 52>(self.u_r.q.val()) << self.kshift.val());
        }
        if self.x_q.q.val() {
            self.uxn.next = self.uxn.val() | self.u_q.q.val();
        }
        // An A clock shifts u_x (its top bits are the next step's), the B clock after it
        // writes the quotient bit into bit 0.
        if self.f_sh1.q.val() {
            self.uxn.next = self.uxn.val() | (self.u_x.q.val() << self.one32.val());
        }
        if self.f_sh2.q.val() {
            self.uxn.next = self.uxn.val() | (self.u_x.q.val() << self.two32.val());
        }
        if self.x_en.q.val() {
            self.u_x.d.next = self.uxn.val();
        }
        if self.f_qx.q.val() & !self.rneg.val() {
            self.u_x.d.next = self.u_x.q.val() | self.one64.val();
        }
        // u_d: likewise. In a square root u_d is the trial 8 q + 1: the B clock after an A
        // clock shifts the new root bit in at bit 3 (the old bits 0..2 are 001, one bit up
        // 010).
        self.udn2.next = self.zero52.val();
        if self.d_sn.q.val() {
            self.udn2.next = self.udn2.val() | bit_cast::<52, 25>(self.sn.q.val());
        }
        if self.d_udr.q.val() {
            self.udn2.next = self.udn2.val() | self.udr.q.val();
        }
        if self.d_uq.q.val() {
            self.udn2.next = self.udn2.val() | (self.u_d.q.val() >> self.s3.val());
        }
        if self.d_ur.q.val() {
            self.udn2.next = self.udn2.val() | self.u_r.q.val();
        }
        if self.d_scl.q.val() {
            self.udn2.next = self.udn2.val() | bit_cast::<52, 16>(self.scl.q.val());
        }
        if self.d_one.q.val() {
            self.udn2.next = self.udn2.val() | self.one52.val();
        }
        if self.f_qd.q.val() {
            self.udn2.next = self.udn2.val()
                | ((self.u_d.q.val() << self.one32.val()) & self.nb1.val())
                | self.one52.val();
            if !self.rneg.val() {
                self.udn2.next = self.udn2.val() | self.nine52.val();
            }
        }
        if self.d_en.q.val() {
            self.u_d.d.next = self.udn2.val();
        }
        // u_r: cleared by a setup state, the chain's sum in an A clock (bits 52..1: bit 0 of
        // {opa, 1} + {opb, cin} only carries cin in).
        if self.clr_r.q.val() {
            self.u_r.d.next = self.zero52.val();
        }
        if self.f_add.q.val() {
            self.u_r.d.next = bit_cast::<52, 53>(
                (((bit_cast::<53, 52>(self.oa.q.val()) << self.one32.val()) | self.one53.val())
                    + self.ob.q.val())
                    >> self.one32.val(),
            );
        }
        self.busy.next = self.busy_r.q.val();
        self.done.next = self.r_done.q.val();
        self.off_s.next = self.r_os.q.val();
        self.off_c.next = self.r_oc.q.val();
        self.g_s.next = self.r_gs.q.val();
        self.g_c.next = self.r_gc.q.val();
        self.k_mag.next = self.r_km.q.val();
        self.k_neg.next = self.r_kn.q.val();
    }
}
