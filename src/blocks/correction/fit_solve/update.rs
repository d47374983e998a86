//! The solver's state machine: [`Logic`] for [`FitSolve`] (its module doc has the
//! sketch and the bit growth).
use super::*;

impl Logic for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, state, ret, u_x, u_d, u_r, u_mag, u_nmag, u_neg, u_rnd, u_adj, it, sn, a1_s,
            a1_c, n1_s, n1_c, a2_s, a2_c, asc, nsc, br_s, br_c, m_s, m_c, v_s, v_c, cc, cmag, cpos,
            amp_s, amp_c, smag, sneg, cs, t_s, t_c, o_s, o_c, ng_s, ng_c, q2, r_os, r_oc, r_gs,
            r_gc, r_km, r_kn, r_done, f_div, f_sq, f_mul, f_add, f_sh1, f_sh2, f_qx, f_qd, f_last,
            xs, ds, clr_r, itn, f_ld, oa, ob, pm, nd, xr, rz, req, t30, scl, ngf, lo_s, lo_c, oor,
            rxs, rds, uxa, uxb, uxc, uxr
        );
        self.nstate.next = self.state.q.val();
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
        self.oa.d.next =
            (bit_cast::<53, 52>(self.opa.val()) << self.one32.val()) | self.one53.val();
        self.ob.d.next = bit_cast::<53, 52>(self.opb.val()) << self.one32.val();
        if !self.up.val() {
            self.ob.d.next =
                (bit_cast::<53, 52>(self.opb.val()) << self.one32.val()) | self.one53.val();
        }
        self.adjw.next = self.zero64.val();
        self.nadjw.next = self.one64.val();
        if self.u_adj.q.val() {
            self.adjw.next = self.one64.val();
            self.nadjw.next = self.zero64.val();
        }
        // Free-running registers: compares and negations one clock ahead of their use.
        self.nd.d.next = self.zero52.val() - self.u_d.q.val();
        self.xr.d.next = self.u_r.q.val() ^ self.nd.q.val();
        self.rz.d.next = self.u_r.q.val() == self.zero52.val();
        self.req.d.next = self.xr.q.val() == self.zero52.val();
        self.pm.d.next = self.zero64.val() - bit_cast::<64, 52>(self.u_r.q.val());
        if self.n1_s.q.val() ^ self.n1_c.q.val() {
            self.pm.d.next = bit_cast::<64, 52>(self.u_r.q.val());
        }
        self.t30.d.next = self.two30.val() - bit_cast::<64, 52>(self.u_r.q.val());
        self.scl.d.next = self.u_mag.q.val();
        if self.u_mag.q.val() > self.smax.val() {
            self.scl.d.next = self.smax.val();
        }
        self.ngf.d.next = bit_cast::<16, 64>(self.u_mag.q.val() & self.m16.val());
        if self.u_mag.q.val() > self.cmax.val() {
            self.ngf.d.next = self.cmax16.val();
        }
        self.lo_s.d.next = self.amp_s.q.val() < self.minamp.val();
        self.lo_c.d.next = self.amp_c.q.val() < self.minamp.val();
        self.oor.d.next = ((self.o_s.q.val() ^ self.sign32.val()) < self.lo_f.val())
            | ((self.o_s.q.val() ^ self.sign32.val()) >= self.hi_f.val())
            | ((self.o_c.q.val() ^ self.sign32.val()) < self.lo_f.val())
            | ((self.o_c.q.val() ^ self.sign32.val()) >= self.hi_f.val());
        self.r_done.d.next = false;
        // The flags and selects of the next state (registered: the wide registers below see
        // no state decode); a return to `ret` takes the selects stored with it and clears u_r
        // (every state `ret` names reads it, if at all, before the clear).
        self.f_div.d.next = false;
        self.f_sq.d.next = false;
        self.f_mul.d.next = false;
        self.f_add.d.next = false;
        self.f_sh1.d.next = false;
        self.f_sh2.d.next = false;
        self.f_qx.d.next = false;
        self.f_qd.d.next = false;
        self.f_last.d.next = false;
        self.f_ld.d.next = false;
        self.xs.d.next = XSel::Hold;
        self.ds.d.next = DSel::Hold;
        self.clr_r.d.next = false;
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
                    self.xs.d.next = XSel::A1s8;
                    self.ds.d.next = DSel::Sn;
                    self.clr_r.d.next = true;
                }
            }
            FitState::Ms => {
                self.itn.d.next = self.i64c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = true;
                self.u_neg.d.next = self.n1_s.q.val();
                self.ret.d.next = FitState::Mc;
                self.rxs.d.next = XSel::A1c8;
                self.rds.d.next = DSel::Sn;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
            }
            FitState::Mc => {
                self.m_s.d.next = self.u_mag.q.val();
                self.itn.d.next = self.i64c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = true;
                self.u_neg.d.next = self.n1_c.q.val();
                self.ret.d.next = FitState::Vs;
                self.rxs.d.next = XSel::A2s;
                self.rds.d.next = DSel::Sn;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
            }
            FitState::Vs => {
                self.m_c.d.next = self.u_mag.q.val();
                self.itn.d.next = self.i80c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = false;
                self.u_neg.d.next = false;
                self.ret.d.next = FitState::Vc;
                self.rxs.d.next = XSel::A2c;
                self.rds.d.next = DSel::Sn;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
            }
            FitState::Vc => {
                self.v_s.d.next = self.u_x.q.val();
                self.itn.d.next = self.i80c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = false;
                self.u_neg.d.next = false;
                self.ret.d.next = FitState::Cq;
                self.rxs.d.next = XSel::Asc;
                self.rds.d.next = DSel::Sn;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
            }
            FitState::Cq => {
                self.v_c.d.next = self.u_x.q.val();
                self.itn.d.next = self.i80c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = false;
                self.u_neg.d.next = self.nsc.q.val();
                self.ret.d.next = FitState::M1;
                self.rxs.d.next = XSel::Ms32;
                self.rds.d.next = DSel::Ms;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
            }
            FitState::M1 => {
                self.cc.d.next = self.u_x.q.val();
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::M2;
                self.rxs.d.next = XSel::Mc32;
                self.rds.d.next = DSel::Mc;
                self.nstate.next = FitState::Run;
                self.f_mul.d.next = true;
            }
            FitState::M2 => {
                self.v_s.d.next = self.v_s.q.val() - bit_cast::<64, 52>(self.u_r.q.val());
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::M3;
                self.rxs.d.next = XSel::Ms32;
                self.rds.d.next = DSel::Mc;
                self.nstate.next = FitState::Run;
                self.f_mul.d.next = true;
            }
            FitState::M3 => {
                self.v_c.d.next = self.v_c.q.val() - bit_cast::<64, 52>(self.u_r.q.val());
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::Cv;
                self.rxs.d.next = XSel::Hold;
                self.rds.d.next = DSel::Hold;
                self.nstate.next = FitState::Run;
                self.f_mul.d.next = true;
            }
            FitState::Cv => {
                // C = Cq - m_s m_c, the product's sign from the means' signs.
                self.cc.d.next = self.cc.q.val() + self.pm.q.val();
                self.nstate.next = FitState::SqS;
                self.xs.d.next = XSel::Vs2;
                self.ds.d.next = DSel::One;
                self.clr_r.d.next = true;
            }
            FitState::SqS => {
                // |C| and the sign of -C (rdiv's sign below; C = 0 gives 0 either way).
                self.cmag.d.next = self.cc.q.val();
                self.cpos.d.next = true;
                if (self.cc.q.val() & self.sign63.val()).any() {
                    self.cmag.d.next = self.zero64.val() - self.cc.q.val();
                    self.cpos.d.next = false;
                }
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::SqC;
                self.rxs.d.next = XSel::Vc2;
                self.rds.d.next = DSel::One;
                self.nstate.next = FitState::Run;
                self.f_sq.d.next = true;
            }
            FitState::SqC => {
                self.amp_s.d.next = bit_cast::<64, 52>(self.u_d.q.val() >> self.s3.val());
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::Chk;
                self.rxs.d.next = XSel::Amps32;
                self.rds.d.next = DSel::Uq;
                self.nstate.next = FitState::Run;
                self.f_sq.d.next = true;
            }
            FitState::Chk => {
                self.amp_c.d.next = bit_cast::<64, 52>(self.u_d.q.val() >> self.s3.val());
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::Sn;
                self.rxs.d.next = XSel::Cmag16;
                self.rds.d.next = DSel::Ur;
                self.nstate.next = FitState::Run;
                self.f_mul.d.next = true;
            }
            FitState::Sn => {
                self.itn.d.next = self.i64c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = true;
                self.u_neg.d.next = self.cpos.q.val();
                self.ret.d.next = FitState::Sn2;
                self.rxs.d.next = XSel::Scl32;
                self.rds.d.next = DSel::Scl;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
                // The amplitude check (its compares registered since Chk).
                if self.lo_s.q.val() | self.lo_c.q.val() {
                    self.nstate.next = FitState::Idle;
                    self.f_div.d.next = false;
                    self.f_mul.d.next = false;
                }
            }
            FitState::Sn2 => {
                self.smag.d.next = self.scl.q.val();
                self.sneg.d.next = self.u_neg.q.val();
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::OffA;
                self.rxs.d.next = XSel::Hold;
                self.rds.d.next = DSel::Hold;
                self.nstate.next = FitState::Run;
                self.f_mul.d.next = true;
            }
            FitState::OffA => {
                self.t_s.d.next =
                    (bit_cast::<32, 64>(self.m_s.q.val()) + self.half8.val()) >> self.s8.val();
                self.t_c.d.next =
                    (bit_cast::<32, 64>(self.m_c.q.val()) + self.half8.val()) >> self.s8.val();
                self.nstate.next = FitState::Cs;
                self.xs.d.next = XSel::T30;
                self.ds.d.next = DSel::One;
                self.clr_r.d.next = true;
            }
            FitState::Cs => {
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::OffB;
                self.rxs.d.next = XSel::Hold;
                self.rds.d.next = DSel::Hold;
                self.nstate.next = FitState::Run;
                self.f_sq.d.next = true;
            }
            FitState::OffB => {
                self.cs.d.next = bit_cast::<64, 52>(self.u_d.q.val() >> self.s3.val());
                self.o_s.d.next = self.br_s.q.val() + self.t_s.q.val();
                if self.n1_s.q.val() {
                    self.o_s.d.next = self.br_s.q.val() - self.t_s.q.val();
                }
                self.o_c.d.next = self.br_c.q.val() + self.t_c.q.val();
                if self.n1_c.q.val() {
                    self.o_c.d.next = self.br_c.q.val() - self.t_c.q.val();
                }
                self.nstate.next = FitState::OffC;
                self.xs.d.next = XSel::Tgs;
                self.ds.d.next = DSel::Amps;
                self.clr_r.d.next = true;
            }
            FitState::OffC => {
                self.itn.d.next = self.i64c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = true;
                self.u_neg.d.next = false;
                self.ret.d.next = FitState::Q1;
                self.rxs.d.next = XSel::Ampc32;
                self.rds.d.next = DSel::Cs;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
            }
            FitState::Q1 => {
                self.ng_s.d.next = self.ngf.q.val();
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::Gc;
                self.rxs.d.next = XSel::Tgc;
                self.rds.d.next = DSel::Ur;
                self.nstate.next = FitState::Run;
                self.f_mul.d.next = true;
                // The offset range check (its compares registered since OffC).
                if self.oor.q.val() {
                    self.nstate.next = FitState::Idle;
                    self.f_div.d.next = false;
                    self.f_mul.d.next = false;
                }
            }
            FitState::Gc => {
                self.itn.d.next = self.i64c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = true;
                self.u_neg.d.next = false;
                self.ret.d.next = FitState::Q2;
                self.rxs.d.next = XSel::Amps32;
                self.rds.d.next = DSel::Cs;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
            }
            FitState::Q2 => {
                self.ng_c.d.next = self.ngf.q.val();
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::Ts;
                self.rxs.d.next = XSel::Tamp32;
                self.rds.d.next = DSel::Smag;
                self.nstate.next = FitState::Run;
                self.f_mul.d.next = true;
            }
            FitState::Ts => {
                self.q2.d.next = bit_cast::<64, 52>(self.u_r.q.val());
                self.itn.d.next = self.i32c.val();
                self.f_ld.d.next = true;
                self.ret.d.next = FitState::Kd;
                self.rxs.d.next = XSel::Urk;
                self.rds.d.next = DSel::Q2;
                self.nstate.next = FitState::Run;
                self.f_mul.d.next = true;
            }
            FitState::Kd => {
                self.itn.d.next = self.i64c.val();
                self.f_ld.d.next = true;
                self.u_rnd.d.next = true;
                self.u_neg.d.next = self.sneg.q.val();
                self.ret.d.next = FitState::Load;
                self.rxs.d.next = XSel::Hold;
                self.rds.d.next = DSel::Hold;
                self.nstate.next = FitState::Run;
                self.f_div.d.next = true;
            }
            FitState::Load => {
                self.r_km.d.next = self.ngf.q.val();
                self.r_kn.d.next = self.sneg.q.val() & self.u_mag.q.val().any();
                self.r_os.d.next = self.o_s.q.val();
                self.r_oc.d.next = self.o_c.q.val();
                self.r_gs.d.next = self.ng_s.q.val();
                self.r_gc.d.next = self.ng_c.q.val();
                self.r_done.d.next = true;
                self.nstate.next = FitState::Idle;
            }
            FitState::Run => {
                // The steps' flags and counter below (no state decode).
            }
            FitState::DivAdj => {
                // A rounding division adds 2 u_r -+ u_d in this clock (2 r >= d is its sign);
                // a truncating one keeps u_r while `req` settles.
                self.nstate.next = FitState::DivTst;
            }
            FitState::DivTst => {
                // The true remainder is u_r, or u_r + u_d when u_r < 0 (zero when u_r = -u_d:
                // `req`); truncation toward zero adds one to a negative quotient when r != 0.
                self.u_adj.d.next = self.u_neg.q.val() & !self.rz.q.val();
                if self.rneg.val() {
                    self.u_adj.d.next = self.u_neg.q.val() & !self.req.q.val();
                }
                if self.u_rnd.q.val() {
                    self.u_adj.d.next = !self.rneg.val();
                }
                self.nstate.next = FitState::DivInc;
            }
            FitState::DivInc => {
                // u_mag = u_x + adj and u_nmag = -(u_x + adj) = !u_x + !adj, adj the carry in.
                self.u_mag.d.next = self.u_x.q.val() + self.adjw.val();
                self.u_nmag.d.next = !self.u_x.q.val() + self.nadjw.val();
                self.nstate.next = FitState::DivNeg;
                self.xs.d.next = XSel::Mag;
                if self.u_neg.q.val() {
                    self.xs.d.next = XSel::NMag;
                }
            }
            FitState::DivNeg => {
                self.nstate.next = self.ret.q.val();
                self.xs.d.next = self.rxs.q.val();
                self.ds.d.next = self.rds.q.val();
                self.clr_r.d.next = true;
            }
        }
        // Run: B and A clocks alternate from a B clock (B_0, the operands of the first step;
        // `it` loads the step count) to a B clock (the last step's result bit); `it` counts
        // the A clocks. Decoded from the mode flags, which are set only in Run.
        if self.f_ld.q.val() {
            self.it.d.next = self.itn.q.val();
        }
        if self.f_div.q.val() | self.f_sq.q.val() | self.f_mul.q.val() {
            self.f_div.d.next = self.f_div.q.val();
            self.f_sq.d.next = self.f_sq.q.val();
            self.f_mul.d.next = self.f_mul.q.val();
            if self.f_add.q.val() {
                self.it.d.next = self.it.q.val() - self.one8.val();
                self.f_qx.d.next = self.f_div.q.val();
                self.f_qd.d.next = self.f_sq.q.val();
                self.f_last.d.next = self.it.q.val() == self.one8.val();
            } else if self.f_last.q.val() {
                self.f_div.d.next = false;
                self.f_sq.d.next = false;
                self.f_mul.d.next = false;
                if self.f_div.q.val() {
                    // The operands just written are those of the rounding sum.
                    self.nstate.next = FitState::DivAdj;
                    self.f_add.d.next = self.u_rnd.q.val();
                } else {
                    self.nstate.next = self.ret.q.val();
                    self.xs.d.next = self.rxs.q.val();
                    self.ds.d.next = self.rds.q.val();
                    self.clr_r.d.next = true;
                }
            } else {
                self.f_add.d.next = true;
                self.f_sh1.d.next = !self.f_sq.q.val();
                self.f_sh2.d.next = self.f_sq.q.val();
            }
        }
        // Reset: Idle, and the mode flags cleared (the run's flags follow them). The other
        // flags and selects act for one more clock on working registers that every solve
        // loads or clears before it reads them.
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
        // The sources a return loads (final long before it) through free-running registers,
        // selected by `rxs` (set at least 65 clocks before the return) in three groups of
        // four (uxa, uxb, uxc; zero when not selected), then ORed into uxr; u_x's own select keeps the sources written just
        // before their load.
        self.uxa.d.next = self.zero64.val();
        self.uxb.d.next = self.zero64.val();
        self.uxc.d.next = self.zero64.val();
        match self.rxs.q.val() {
            XSel::A1c8 => {
                self.uxa.d.next = self.a1_c.q.val() << self.s8.val();
            }
            XSel::A2s => {
                self.uxa.d.next = self.a2_s.q.val();
            }
            XSel::A2c => {
                self.uxa.d.next = self.a2_c.q.val();
            }
            XSel::Asc => {
                self.uxa.d.next = self.asc.q.val();
            }
            XSel::Ms32 => {
                self.uxb.d.next = self.m_s.q.val() << self.s32.val();
            }
            XSel::Mc32 => {
                self.uxb.d.next = self.m_c.q.val() << self.s32.val();
            }
            XSel::Vc2 => {
                self.uxb.d.next = self.v_c.q.val() << self.one32.val();
                if (self.v_c.q.val() & self.sign63.val()).any() {
                    self.uxb.d.next = self.zero64.val();
                }
            }
            XSel::Amps32 => {
                self.uxb.d.next = self.amp_s.q.val() << self.s32.val();
            }
            XSel::Ampc32 => {
                self.uxc.d.next = self.amp_c.q.val() << self.s32.val();
            }
            XSel::Cmag16 => {
                self.uxc.d.next = self.cmag.q.val() << self.s16.val();
            }
            XSel::Tgc => {
                self.uxc.d.next = self.tgc.val();
            }
            XSel::Tamp32 => {
                self.uxc.d.next = self.tamp32.val();
            }
            XSel::Hold => {}
            XSel::A1s8 => {}
            XSel::Vs2 => {}
            XSel::T30 => {}
            XSel::Tgs => {}
            XSel::Scl32 => {}
            XSel::Urk => {}
            XSel::Mag => {}
            XSel::NMag => {}
        }
        self.uxr.d.next = self.uxa.q.val() | self.uxb.q.val() | self.uxc.q.val();
        // u_x: a registered select of its sources, then the run states' shifts (the division's
        // quotient bit from the adder goes through the last mux only).
        match self.xs.q.val() {
            XSel::Hold => {}
            XSel::A1s8 => {
                self.u_x.d.next = self.a1_s.q.val() << self.s8.val();
            }
            XSel::A1c8 => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::A2s => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::A2c => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Asc => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Ms32 => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Mc32 => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Vs2 => {
                self.u_x.d.next = self.v_s.q.val() << self.one32.val();
                if (self.v_s.q.val() & self.sign63.val()).any() {
                    self.u_x.d.next = self.zero64.val();
                }
            }
            XSel::Vc2 => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Amps32 => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Ampc32 => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Cmag16 => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Scl32 => {
                self.u_x.d.next = self.scl.q.val() << self.s32.val();
            }
            XSel::T30 => {
                self.u_x.d.next = self.t30.q.val();
            }
            XSel::Tgs => {
                self.u_x.d.next = self.tgs.val();
            }
            XSel::Tgc => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Tamp32 => {
                self.u_x.d.next = self.uxr.q.val();
            }
            XSel::Urk => {
                self.u_x.d.next = bit_cast::<64, 52>(self.u_r.q.val()) << self.kshift.val();
            }
            XSel::Mag => {
                self.u_x.d.next = self.u_mag.q.val();
            }
            XSel::NMag => {
                self.u_x.d.next = self.u_nmag.q.val();
            }
        }
        // An A clock shifts u_x (its top bits are the next step's), the B clock after it
        // writes the quotient bit into bit 0.
        if self.f_sh1.q.val() {
            self.u_x.d.next = self.u_x.q.val() << self.one32.val();
        }
        if self.f_sh2.q.val() {
            self.u_x.d.next = self.u_x.q.val() << self.two32.val();
        }
        if self.f_qx.q.val() & !self.rneg.val() {
            self.u_x.d.next = self.u_x.q.val() | self.one64.val();
        }
        match self.ds.q.val() {
            DSel::Hold => {}
            DSel::Sn => {
                self.u_d.d.next = bit_cast::<52, 64>(self.sn.q.val());
            }
            DSel::Ms => {
                self.u_d.d.next = bit_cast::<52, 64>(self.m_s.q.val());
            }
            DSel::Mc => {
                self.u_d.d.next = bit_cast::<52, 64>(self.m_c.q.val());
            }
            DSel::Uq => {
                self.u_d.d.next = self.u_d.q.val() >> self.s3.val();
            }
            DSel::Ur => {
                self.u_d.d.next = self.u_r.q.val();
            }
            DSel::Scl => {
                self.u_d.d.next = bit_cast::<52, 64>(self.scl.q.val());
            }
            DSel::Amps => {
                self.u_d.d.next = bit_cast::<52, 64>(self.amp_s.q.val());
            }
            DSel::Cs => {
                self.u_d.d.next = bit_cast::<52, 64>(self.cs.q.val());
            }
            DSel::Smag => {
                self.u_d.d.next = bit_cast::<52, 64>(self.smag.q.val());
            }
            DSel::Q2 => {
                self.u_d.d.next = bit_cast::<52, 64>(self.q2.q.val());
            }
            DSel::One => {
                self.u_d.d.next = self.one52.val();
            }
        }
        // In a square root u_d is the trial 8 q + 1: the B clock after an A clock shifts the
        // new root bit in at bit 3 (the old bits 0..2 are 001, one bit up 010).
        if self.f_qd.q.val() {
            self.u_d.d.next =
                ((self.u_d.q.val() << self.one32.val()) & self.nb1.val()) | self.one52.val();
            if !self.rneg.val() {
                self.u_d.d.next =
                    ((self.u_d.q.val() << self.one32.val()) & self.nb1.val()) | self.nine52.val();
            }
        }
        // u_r: cleared by a setup state, the chain's sum in an A clock (bits 52..1: bit 0 of
        // {opa, 1} + {opb, cin} only carries cin in).
        if self.clr_r.q.val() {
            self.u_r.d.next = self.zero52.val();
        }
        if self.f_add.q.val() {
            self.u_r.d.next =
                bit_cast::<52, 53>((self.oa.q.val() + self.ob.q.val()) >> self.one32.val());
        }
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
