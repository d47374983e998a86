//! The solver's logic: [`Logic`] for [`FitSolve`] (its module doc has the sketch and the
//! bit growth) in stages: the sequencer, the run's steps, the rounding, the operands, the
//! solve's values, reset.
use super::*;

/// The sequencer's phase.
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum SolveState {
    /// Waiting for `start`.
    Idle,
    /// Operands in, the row before's result out.
    SetUp,
    /// The steps of the row's operation.
    Run,
    /// A division's rounding sum 2 u_r -+ u_d.
    RoundSum,
    /// Its increment adj.
    RoundTst,
    /// u_mag = u_x + adj, u_q the signed quotient.
    RoundInc,
    /// u_x = u_q.
    RoundNeg,
    /// The coefficients load after the last row (a refused solve loads nothing); dn is
    /// back at row 0.
    Load,
}

// The solver's logic in named stages, run in this order: each stage is a `#[hdl_gen]`
// function (simulation, drivers, Verilog), and `FitSolve`'s one combinational block is
// their statements in sequence.
crate::blocks::logic_stages!(FitSolve: Sequencer, Steps, Rounding, Operands, Values, Reset);

/// The sequencer: the table's word, the state, the program counter.
impl stages::Sequencer for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, state, pc, dn, pl, rdy, launch, refuse, f_ret, bad, u_x, u_d, u_r, u_mag,
            u_q, u_neg, u_rnd, u_adj, u_adjq, uxs, it, f_div, f_sq, f_mul, f_add, f_sh1, f_sh2,
            f_qx, f_qd, f_last, x_q, x_en, d_en, clr_r, oa, ob, uxr, uxa, uxb, uxc, udr, xr, rz,
            req, sn, d1_s, d1_c, a1_s, a1_c, n1_s, n1_c, a2_s, a2_c, dsc, asc, asl, ash, alz, nsc,
            br_s, br_c, m_s, m_c, v_s, v_c, cc, amp_s, amp_c, smag, sneg, cs, ng_s, ng_c, q2, vsel,
            vd, ccp, ccm, ccn, cmag, cpos, t30, t_s, t_c, o_s, o_c, lo_s, lo_c, oor_sl, oor_sh,
            oor_cl, oor_ch, xh1, xh2, xh3, xl, xgt_s, xge_s, xff, big_s, big_c, mnz, scl, ngf,
            r_os, r_oc, r_gs, r_gc, r_km, r_kn, r_done
        );
        // ---- Sequencer. The ROM word of pc is registered (dn) and, at a set-up, registered
        // again as one-clock selects (pl); `ret` is the clock before a set-up or Load.
        self.rom.address.next = self.pc.q.val();
        self.dn.d.next = self.rom.data.val();
        self.go.next = self.rdy.q.val() & self.start.val();
        self.rdy.d.next = (self.state.q.val() == SolveState::Load)
            | ((self.state.q.val() == SolveState::Idle) & !self.launch.q.val() & !self.go.val());
        self.launch.d.next = self.go.val();
        self.ret.next = self.launch.q.val() | self.f_ret.q.val();
        self.refuse.d.next = self.dn.q.val().chk & self.bad.q.val();
        self.pl.d.next = self.nosel.val();
        if self.ret.val() & !self.refuse.q.val() {
            self.pl.d.next = self.dn.q.val();
        }
        match self.state.q.val() {
            SolveState::Idle => {
                self.pc.d.next = self.zero5.val();
            }
            SolveState::SetUp => {
                self.pc.d.next = self.pc.q.val() + self.one5.val();
                self.state.d.next = SolveState::Run;
            }
            SolveState::Run => {
                if self.f_div.q.val() & self.f_last.q.val() {
                    self.state.d.next = SolveState::RoundSum;
                }
            }
            SolveState::RoundSum => {
                self.state.d.next = SolveState::RoundTst;
            }
            SolveState::RoundTst => {
                self.state.d.next = SolveState::RoundInc;
            }
            SolveState::RoundInc => {
                self.state.d.next = SolveState::RoundNeg;
            }
            SolveState::RoundNeg => {}
            SolveState::Load => {
                self.state.d.next = SolveState::Idle;
            }
        }
        if self.ret.val() {
            self.state.d.next = SolveState::SetUp;
            if self.refuse.q.val() | self.dn.q.val().end {
                self.state.d.next = SolveState::Load;
                self.pc.d.next = self.zero5.val();
            }
        }
        // The checked row refuses on either amplitude or offset (settled rows earlier).
        self.bad.d.next = self.lo_s.q.val()
            | self.lo_c.q.val()
            | self.oor_sl.q.val()
            | self.oor_sh.q.val()
            | self.oor_cl.q.val()
            | self.oor_ch.q.val();
    }
}

/// The run: its flags, step count and settings from the set-up, and the chain's operands.
impl stages::Steps for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        // ---- Shared units. The set-up loads the run's flags, step count and settings.
        self.f_div.d.next = self.pl.q.val().div | (self.f_div.q.val() & !self.f_last.q.val());
        self.f_sq.d.next = self.pl.q.val().sq | (self.f_sq.q.val() & !self.f_last.q.val());
        self.f_mul.d.next = self.pl.q.val().mul | (self.f_mul.q.val() & !self.f_last.q.val());
        self.negn.next = (self.pl.q.val().ng_s & self.n1_s.q.val())
            | (self.pl.q.val().ng_c & self.n1_c.q.val())
            | (self.pl.q.val().ng_sc & self.nsc.q.val())
            | (self.pl.q.val().ng_cpos & self.cpos.q.val())
            | (self.pl.q.val().ng_sneg & self.sneg.q.val());
        if self.state.q.val() == SolveState::SetUp {
            self.it.d.next = self.i32c.val();
            if self.pl.q.val().div {
                self.it.d.next = self.i64c.val();
            }
            if self.pl.q.val().n80 {
                self.it.d.next = self.i80c.val();
            }
            self.u_rnd.d.next = self.pl.q.val().rnd;
            self.u_neg.d.next = self.negn.val();
        }
        // Non-restoring steps, each over two clocks: a B clock writes the chain's operands
        // oa / ob (one LUT each from registers), the next A clock (f_add) writes their sum
        // into u_r, the chain and nothing else. A remainder below zero adds the divisor (or
        // the root's trial 4q + 3) back instead of subtracting it (4q + 1); a product (MSB
        // first) doubles u_r and adds u_d when u_x's top bit is one (else the "minus" sum
        // with 0).
        self.rneg.next = self.u_r.q.val().get_bit(51);
        self.opa.next = self.u_r.q.val() << 1;
        if self.f_div.q.val() & !self.f_last.q.val() {
            self.opa.next = (self.u_r.q.val() << 1) | bit_cast::<52, 64>(self.u_x.q.val() >> 63);
        }
        if self.f_sq.q.val() {
            self.opa.next = (self.u_r.q.val() << 2) | bit_cast::<52, 64>(self.u_x.q.val() >> 62);
        }
        self.up.next = self.rneg.val();
        if self.f_mul.q.val() {
            self.up.next = self.u_x.q.val().get_bit(63);
        }
        // up ? u_d : !u_d (!0 in a product), carry in !up; in a square root u_d holds 8 q + 1,
        // which gives 4 q' + 3 / !(4 q' + 1) with bit 1 set and bit 2 clear (q' = 2 q + bit),
        // except the first step's -1 (bit 2 set).
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
        self.ob.d.next = bit_cast::<53, 52>(self.opb.val()) << 1;
        if !self.up.val() {
            self.ob.d.next = (bit_cast::<53, 52>(self.opb.val()) << 1) | self.one53.val();
        }
        self.run.next = self.f_div.q.val() | self.f_sq.q.val() | self.f_mul.q.val();
        self.step.next = self.run.val() & !self.f_add.q.val() & !self.f_last.q.val();
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
        self.f_ret.d.next = (self.state.q.val() == SolveState::RoundInc)
            | ((self.f_sq.q.val() | self.f_mul.q.val())
                & self.f_add.q.val()
                & (self.it.q.val() == self.one8.val()));
        self.x_q.d.next = self.state.q.val() == SolveState::RoundInc;
        self.x_en.d.next =
            self.ret.val() | self.step.val() | (self.state.q.val() == SolveState::RoundInc);
        self.d_en.d.next = self.ret.val() | (self.f_sq.q.val() & self.f_add.q.val());
        self.clr_r.d.next = self.ret.val();
    }
}

/// A division's rounding, sign and clamps.
impl stages::Rounding for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        // Rounding. The true remainder is u_r, or u_r + u_d when u_r < 0 (zero when u_r =
        // -u_d: req); RoundSum leaves the sign of 2 r - u_d in u_r for a rounding division,
        // a floor adds one to a negative quotient when r != 0.
        self.xr.d.next =
            (self.u_r.q.val() ^ self.u_d.q.val()) ^ ((self.u_r.q.val() | self.u_d.q.val()) << 1);
        self.rz.d.next = self.u_r.q.val() == self.zero52.val();
        self.req.d.next = self.xr.q.val() == self.zero52.val();
        self.adjn.next = self.u_neg.q.val() & !self.rz.q.val();
        if self.rneg.val() {
            self.adjn.next = self.u_neg.q.val() & !self.req.q.val();
        }
        if self.u_rnd.q.val() {
            self.adjn.next = !self.rneg.val();
        }
        if self.state.q.val() == SolveState::RoundTst {
            self.u_adj.d.next = self.adjn.val();
            self.u_adjq.d.next = self.adjn.val() ^ self.u_neg.q.val();
        }
        self.adjw.next = self.zero24.val();
        if self.u_adj.q.val() {
            self.adjw.next = self.one24.val();
        }
        self.adjqw.next = self.zero64.val();
        if self.u_adjq.q.val() {
            self.adjqw.next = self.one64.val();
        }
        self.uxs.d.next = self.u_x.q.val();
        if self.u_neg.q.val() {
            self.uxs.d.next = !self.u_x.q.val();
        }
        if self.state.q.val() == SolveState::RoundInc {
            // u_mag = u_x + adj and u_q = uxs + (adj ^ u_neg), one chain each from registers.
            self.u_mag.d.next = bit_cast::<24, 64>(self.u_x.q.val()) + self.adjw.val();
            self.u_q.d.next = self.uxs.q.val() + self.adjqw.val();
        }
        // u_mag's compares from the quotient it rounds (u_mag > K <=> u_x > K - adj): settled
        // when RoundNeg and the set-up read big_s, big_c, mnz, scl, ngf.
        self.xh1.d.next = bit_cast::<16, 64>(self.u_x.q.val() >> 16).any();
        self.xh2.d.next = bit_cast::<16, 64>(self.u_x.q.val() >> 32).any();
        self.xh3.d.next = bit_cast::<16, 64>(self.u_x.q.val() >> 48).any();
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
        self.scl.d.next = bit_cast::<16, 24>(self.u_mag.q.val());
        if self.big_s.q.val() {
            self.scl.d.next = self.smax16.val();
        }
        self.ngf.d.next = bit_cast::<16, 24>(self.u_mag.q.val());
        if self.big_c.q.val() {
            self.ngf.d.next = self.cmax16.val();
        }
    }
}

/// Reset and the outputs.
impl stages::Reset for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        // Reset: idle and ready at row 0 (dn its word from the next clock on), no run, no
        // launch or return, no pending selects; the configured coefficients. Working
        // registers are loaded or cleared by every solve before it reads them.
        if self.rst.val() {
            self.state.d.next = SolveState::Idle;
            self.pc.d.next = self.zero5.val();
            self.dn.d.next = self.row0.val();
            self.pl.d.next = self.nosel.val();
            self.launch.d.next = false;
            self.rdy.d.next = true;
            self.f_ret.d.next = false;
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
        self.busy.next = self.state.q.val() != SolveState::Idle;
        self.done.next = self.r_done.q.val();
        self.off_s.next = self.r_os.q.val();
        self.off_c.next = self.r_oc.q.val();
        self.g_s.next = self.r_gs.q.val();
        self.g_c.next = self.r_gc.q.val();
        self.k_mag.next = self.r_km.q.val();
        self.k_neg.next = self.r_kn.q.val();
    }
}
