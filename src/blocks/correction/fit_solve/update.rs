//! The solver's state machine: [`Logic`] for [`FitSolve`] (its module doc has the
//! sketch and the bit growth).
use super::*;

impl Logic for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, state, ret, u_x, u_d, u_r, u_q, u_mag, u_neg, u_rnd, u_adj, it, sn, a1_s,
            a1_c, n1_s, n1_c, a2_s, a2_c, asc, nsc, br_s, br_c, m_s, m_c, v_s, v_c, cc, cmag, cpos,
            amp_s, amp_c, smag, sneg, cs, t_s, t_c, o_s, o_c, ng_s, ng_c, q2, r_os, r_oc, r_gs,
            r_gc, r_km, r_kn, r_done, f_div, f_sq, f_mul
        );
        self.nstate.next = self.state.q.val();
        // The flags are set with every transition into their state (one-hot, no decode).
        self.f_div.d.next = false;
        self.f_sq.d.next = false;
        self.f_mul.d.next = false;
        // The shared adder (one carry chain), non-restoring: a remainder below zero adds the
        // divisor (or the square root's trial 4q + 3) back instead of subtracting it, so the
        // chain's sign bit is the quotient bit and the sum is the next remainder directly.
        self.rneg.next = (self.u_r.q.val() & self.sign63.val()).any();
        self.tt.next = self.u_r.q.val() << self.one32.val();
        if self.f_div.q.val() & (self.u_x.q.val() & self.sign63.val()).any() {
            self.tt.next = (self.u_r.q.val() << self.one32.val()) | self.one64.val();
        }
        self.sb.next = !self.u_d.q.val();
        if self.rneg.val() {
            self.sb.next = self.u_d.q.val();
        }
        self.cin.next = !self.rneg.val();
        if self.f_sq.q.val() {
            self.tt.next =
                (self.u_r.q.val() << self.two32.val()) | (self.u_x.q.val() >> self.s62.val());
            self.sb.next = !((self.u_q.q.val() << self.two32.val()) | self.one64.val());
            if self.rneg.val() {
                self.sb.next = (self.u_q.q.val() << self.two32.val()) | self.three64.val();
            }
        }
        if self.f_mul.q.val() {
            self.tt.next = self.u_r.q.val();
            self.sb.next = self.zero64.val();
            if (self.u_d.q.val() & self.one64.val()).any() {
                self.sb.next = self.u_x.q.val();
            }
            self.cin.next = false;
        }
        // Bit 0 of the 64-bit chain carries cin in: {tt, 1} + {sb, cin}, whose bits 63..1 are
        // the 63-bit sum, sign-extended (every sum is below 2^51 in magnitude, module doc).
        self.sbc.next = self.sb.val() << self.one32.val();
        if self.cin.val() {
            self.sbc.next = (self.sb.val() << self.one32.val()) | self.one64.val();
        }
        self.s65.next = ((self.tt.val() << self.one32.val()) | self.one64.val()) + self.sbc.val();
        self.sum.next = (self.s65.val() >> self.one32.val()) | (self.s65.val() & self.sign63.val());
        self.zr.next = self.u_r.q.val() + self.u_d.q.val();
        self.sclamp.next = self.u_mag.q.val();
        if self.u_mag.q.val() > self.smax.val() {
            self.sclamp.next = self.smax.val();
        }
        self.r_done.d.next = false;
        match self.state.q.val() {
            FitState::Idle => {
                if self.start.val() {
                    self.sn.d.next = bit_cast::<64, 32>(self.n.val());
                    self.a1_s.d.next = self.s1_s.val();
                    self.n1_s.d.next = (self.s1_s.val() & self.sign63.val()).any();
                    if (self.s1_s.val() & self.sign63.val()).any() {
                        self.a1_s.d.next = self.zero64.val() - self.s1_s.val();
                    }
                    self.a1_c.d.next = self.s1_c.val();
                    self.n1_c.d.next = (self.s1_c.val() & self.sign63.val()).any();
                    if (self.s1_c.val() & self.sign63.val()).any() {
                        self.a1_c.d.next = self.zero64.val() - self.s1_c.val();
                    }
                    self.a2_s.d.next = self.s2_s.val();
                    self.a2_c.d.next = self.s2_c.val();
                    self.asc.d.next = self.ssc.val();
                    self.nsc.d.next = (self.ssc.val() & self.sign63.val()).any();
                    if (self.ssc.val() & self.sign63.val()).any() {
                        self.asc.d.next = self.zero64.val() - self.ssc.val();
                    }
                    self.br_s.d.next = self.bref_s.val();
                    self.br_c.d.next = self.bref_c.val();
                    self.nstate.next = FitState::Ms;
                }
            }
            FitState::Ms => {
                self.u_x.d.next = self.a1_s.q.val() << self.s8.val();
                self.u_d.d.next = self.sn.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i64c.val();
                self.u_rnd.d.next = true;
                self.u_neg.d.next = self.n1_s.q.val();
                self.ret.d.next = FitState::Mc;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
            }
            FitState::Mc => {
                self.m_s.d.next = self.u_mag.q.val();
                self.u_x.d.next = self.a1_c.q.val() << self.s8.val();
                self.u_d.d.next = self.sn.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i64c.val();
                self.u_rnd.d.next = true;
                self.u_neg.d.next = self.n1_c.q.val();
                self.ret.d.next = FitState::Vs;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
            }
            FitState::Vs => {
                self.m_c.d.next = self.u_mag.q.val();
                self.u_x.d.next = self.a2_s.q.val();
                self.u_d.d.next = self.sn.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i80c.val();
                self.u_rnd.d.next = false;
                self.u_neg.d.next = false;
                self.ret.d.next = FitState::Vc;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
            }
            FitState::Vc => {
                self.v_s.d.next = self.u_x.q.val();
                self.u_x.d.next = self.a2_c.q.val();
                self.u_d.d.next = self.sn.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i80c.val();
                self.u_rnd.d.next = false;
                self.u_neg.d.next = false;
                self.ret.d.next = FitState::Cq;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
            }
            FitState::Cq => {
                self.v_c.d.next = self.u_x.q.val();
                self.u_x.d.next = self.asc.q.val();
                self.u_d.d.next = self.sn.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i80c.val();
                self.u_rnd.d.next = false;
                self.u_neg.d.next = self.nsc.q.val();
                self.ret.d.next = FitState::M1;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
            }
            FitState::M1 => {
                self.cc.d.next = self.u_x.q.val();
                self.u_x.d.next = self.m_s.q.val();
                self.u_d.d.next = self.m_s.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::M2;
                self.nstate.next = FitState::MulRun;
                self.f_mul.d.next = true;
            }
            FitState::M2 => {
                self.v_s.d.next = self.v_s.q.val() - self.u_r.q.val();
                self.u_x.d.next = self.m_c.q.val();
                self.u_d.d.next = self.m_c.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::M3;
                self.nstate.next = FitState::MulRun;
                self.f_mul.d.next = true;
            }
            FitState::M3 => {
                self.v_c.d.next = self.v_c.q.val() - self.u_r.q.val();
                self.u_x.d.next = self.m_s.q.val();
                self.u_d.d.next = self.m_c.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::Cv;
                self.nstate.next = FitState::MulRun;
                self.f_mul.d.next = true;
            }
            FitState::Cv => {
                // C = Cq - m_s m_c, the product's sign from the means' signs.
                self.cc.d.next = self.cc.q.val() - self.u_r.q.val();
                if self.n1_s.q.val() ^ self.n1_c.q.val() {
                    self.cc.d.next = self.cc.q.val() + self.u_r.q.val();
                }
                self.nstate.next = FitState::SqS;
            }
            FitState::SqS => {
                // |C| and the sign of -C (rdiv's sign below; C = 0 gives 0 either way).
                self.cmag.d.next = self.cc.q.val();
                self.cpos.d.next = true;
                if (self.cc.q.val() & self.sign63.val()).any() {
                    self.cmag.d.next = self.zero64.val() - self.cc.q.val();
                    self.cpos.d.next = false;
                }
                self.u_x.d.next = self.v_s.q.val() << self.one32.val();
                if (self.v_s.q.val() & self.sign63.val()).any() {
                    self.u_x.d.next = self.zero64.val();
                }
                self.u_r.d.next = self.zero64.val();
                self.u_q.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::SqC;
                self.nstate.next = FitState::SqRun;
                self.f_sq.d.next = true;
            }
            FitState::SqC => {
                self.amp_s.d.next = self.u_q.q.val();
                self.u_x.d.next = self.v_c.q.val() << self.one32.val();
                if (self.v_c.q.val() & self.sign63.val()).any() {
                    self.u_x.d.next = self.zero64.val();
                }
                self.u_r.d.next = self.zero64.val();
                self.u_q.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::Chk;
                self.nstate.next = FitState::SqRun;
                self.f_sq.d.next = true;
            }
            FitState::Chk => {
                self.amp_c.d.next = self.u_q.q.val();
                self.u_x.d.next = self.amp_s.q.val();
                self.u_d.d.next = self.u_q.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::Sn;
                self.nstate.next = FitState::MulRun;
                self.f_mul.d.next = true;
                if (self.amp_s.q.val() < self.minamp.val()) | (self.u_q.q.val() < self.minamp.val())
                {
                    self.nstate.next = FitState::Idle;
                    self.f_div.d.next = false;
                    self.f_mul.d.next = false;
                }
            }
            FitState::Sn => {
                self.u_x.d.next = self.cmag.q.val() << self.s16.val();
                self.u_d.d.next = self.u_r.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i64c.val();
                self.u_rnd.d.next = true;
                self.u_neg.d.next = self.cpos.q.val();
                self.ret.d.next = FitState::Sn2;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
            }
            FitState::Sn2 => {
                self.smag.d.next = self.sclamp.val();
                self.sneg.d.next = self.u_neg.q.val();
                self.u_x.d.next = self.sclamp.val();
                self.u_d.d.next = self.sclamp.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::Cs;
                self.nstate.next = FitState::MulRun;
                self.f_mul.d.next = true;
            }
            FitState::Cs => {
                self.u_x.d.next = self.two30.val() - self.u_r.q.val();
                self.u_r.d.next = self.zero64.val();
                self.u_q.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::OffA;
                self.nstate.next = FitState::SqRun;
                self.f_sq.d.next = true;
            }
            FitState::OffA => {
                self.cs.d.next = self.u_q.q.val();
                self.t_s.d.next =
                    (bit_cast::<32, 64>(self.m_s.q.val()) + self.half8.val()) >> self.s8.val();
                self.t_c.d.next =
                    (bit_cast::<32, 64>(self.m_c.q.val()) + self.half8.val()) >> self.s8.val();
                self.nstate.next = FitState::OffB;
            }
            FitState::OffB => {
                self.o_s.d.next = self.br_s.q.val() + self.t_s.q.val();
                if self.n1_s.q.val() {
                    self.o_s.d.next = self.br_s.q.val() - self.t_s.q.val();
                }
                self.o_c.d.next = self.br_c.q.val() + self.t_c.q.val();
                if self.n1_c.q.val() {
                    self.o_c.d.next = self.br_c.q.val() - self.t_c.q.val();
                }
                self.nstate.next = FitState::OffC;
            }
            FitState::OffC => {
                self.u_x.d.next = self.tgs.val();
                self.u_d.d.next = self.amp_s.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i64c.val();
                self.u_rnd.d.next = true;
                self.u_neg.d.next = false;
                self.ret.d.next = FitState::Q1;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
                if ((self.o_s.q.val() ^ self.sign32.val()) < self.lo_f.val())
                    | ((self.o_s.q.val() ^ self.sign32.val()) >= self.hi_f.val())
                    | ((self.o_c.q.val() ^ self.sign32.val()) < self.lo_f.val())
                    | ((self.o_c.q.val() ^ self.sign32.val()) >= self.hi_f.val())
                {
                    self.nstate.next = FitState::Idle;
                    self.f_div.d.next = false;
                    self.f_mul.d.next = false;
                }
            }
            FitState::Q1 => {
                self.ng_s.d.next = bit_cast::<16, 64>(self.u_x.q.val() & self.m16.val());
                if self.u_x.q.val() > self.cmax.val() {
                    self.ng_s.d.next = bit_cast::<16, 64>(self.cmax.val());
                }
                self.u_x.d.next = self.amp_c.q.val();
                self.u_d.d.next = self.cs.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::Gc;
                self.nstate.next = FitState::MulRun;
                self.f_mul.d.next = true;
            }
            FitState::Gc => {
                self.u_x.d.next = self.tgc.val();
                self.u_d.d.next = self.u_r.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i64c.val();
                self.u_rnd.d.next = true;
                self.u_neg.d.next = false;
                self.ret.d.next = FitState::Q2;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
            }
            FitState::Q2 => {
                self.ng_c.d.next = bit_cast::<16, 64>(self.u_x.q.val() & self.m16.val());
                if self.u_x.q.val() > self.cmax.val() {
                    self.ng_c.d.next = bit_cast::<16, 64>(self.cmax.val());
                }
                self.u_x.d.next = self.amp_s.q.val();
                self.u_d.d.next = self.cs.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::Ts;
                self.nstate.next = FitState::MulRun;
                self.f_mul.d.next = true;
            }
            FitState::Ts => {
                self.q2.d.next = self.u_r.q.val();
                self.u_x.d.next = self.tamp.val();
                self.u_d.d.next = self.smag.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i32c.val();
                self.ret.d.next = FitState::Kd;
                self.nstate.next = FitState::MulRun;
                self.f_mul.d.next = true;
            }
            FitState::Kd => {
                self.u_x.d.next = self.u_r.q.val() << self.kshift.val();
                self.u_d.d.next = self.q2.q.val();
                self.u_r.d.next = self.zero64.val();
                self.it.d.next = self.i64c.val();
                self.u_rnd.d.next = true;
                self.u_neg.d.next = self.sneg.q.val();
                self.ret.d.next = FitState::Load;
                self.nstate.next = FitState::DivRun;
                self.f_div.d.next = true;
            }
            FitState::Load => {
                self.r_km.d.next = bit_cast::<16, 64>(self.u_mag.q.val() & self.m16.val());
                if self.u_mag.q.val() > self.cmax.val() {
                    self.r_km.d.next = bit_cast::<16, 64>(self.cmax.val());
                }
                self.r_kn.d.next = self.sneg.q.val() & self.u_mag.q.val().any();
                self.r_os.d.next = self.o_s.q.val();
                self.r_oc.d.next = self.o_c.q.val();
                self.r_gs.d.next = self.ng_s.q.val();
                self.r_gc.d.next = self.ng_c.q.val();
                self.r_done.d.next = true;
                self.nstate.next = FitState::Idle;
            }
            FitState::DivRun => {
                self.f_div.d.next = true;
                self.u_r.d.next = self.sum.val();
                self.u_x.d.next = self.u_x.q.val() << self.one32.val();
                if !(self.sum.val() & self.sign63.val()).any() {
                    self.u_x.d.next = (self.u_x.q.val() << self.one32.val()) | self.one64.val();
                }
                self.it.d.next = self.it.q.val() - self.one32.val();
                if self.it.q.val() == self.one32.val() {
                    self.f_div.d.next = false;
                    self.nstate.next = FitState::DivAdj;
                }
            }
            FitState::DivAdj => {
                // The true remainder is u_r, or u_r + u_d when u_r < 0. Rounding: 2 r >= d is
                // the sign of the shared sum 2 u_r -+ u_d; truncation toward zero: r != 0.
                self.u_adj.d.next = self.u_neg.q.val() & self.u_r.q.val().any();
                if self.rneg.val() {
                    self.u_adj.d.next = self.u_neg.q.val() & self.zr.val().any();
                }
                if self.u_rnd.q.val() {
                    self.u_adj.d.next = !(self.sum.val() & self.sign63.val()).any();
                }
                self.nstate.next = FitState::DivInc;
            }
            FitState::DivInc => {
                self.u_mag.d.next = self.u_x.q.val();
                if self.u_adj.q.val() {
                    self.u_mag.d.next = self.u_x.q.val() + self.one64.val();
                }
                self.nstate.next = FitState::DivNeg;
            }
            FitState::DivNeg => {
                self.u_x.d.next = self.u_mag.q.val();
                if self.u_neg.q.val() {
                    self.u_x.d.next = self.zero64.val() - self.u_mag.q.val();
                }
                self.nstate.next = self.ret.q.val();
            }
            FitState::SqRun => {
                self.f_sq.d.next = true;
                self.u_r.d.next = self.sum.val();
                self.u_q.d.next = self.u_q.q.val() << self.one32.val();
                if !(self.sum.val() & self.sign63.val()).any() {
                    self.u_q.d.next = (self.u_q.q.val() << self.one32.val()) | self.one64.val();
                }
                self.u_x.d.next = self.u_x.q.val() << self.two32.val();
                self.it.d.next = self.it.q.val() - self.one32.val();
                if self.it.q.val() == self.one32.val() {
                    self.f_sq.d.next = false;
                    self.nstate.next = self.ret.q.val();
                }
            }
            FitState::MulRun => {
                self.f_mul.d.next = true;
                self.u_r.d.next = self.sum.val();
                self.u_x.d.next = self.u_x.q.val() << self.one32.val();
                self.u_d.d.next = self.u_d.q.val() >> self.one32.val();
                self.it.d.next = self.it.q.val() - self.one32.val();
                if self.it.q.val() == self.one32.val() {
                    self.f_mul.d.next = false;
                    self.nstate.next = self.ret.q.val();
                }
            }
        }
        if self.rst.val() {
            self.nstate.next = FitState::Idle;
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
        self.state.d.next = self.nstate.val();
        self.busy.next = !(self.state.q.val() == FitState::Idle);
        self.done.next = self.r_done.q.val();
        self.off_s.next = self.r_os.q.val();
        self.off_c.next = self.r_oc.q.val();
        self.g_s.next = self.r_gs.q.val();
        self.g_c.next = self.r_gc.q.val();
        self.k_mag.next = self.r_km.q.val();
        self.k_neg.next = self.r_kn.q.val();
    }
}
