//! The solve's values (a stage of [`super::update`]).
use super::update::stages::Values;
use super::*;

/// The solve's values: the snapshot, the free-running registers, the destinations.
impl Values for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        // ---- The solve's values. The snapshot follows the sums while `rdy` (its last load
        // is the start's); the magnitudes are free-running from it: |Σd| a clock later, and
        // |Σd_s d_c| two: -x = ~x + 1 in two 28-bit halves from registers (the high half
        // 0 - hi when the low half is zero, else ~hi).
        if self.rdy.q.val() {
            self.sn.d.next = bit_cast::<25, 32>(self.n.val());
            self.d1_s.d.next = bit_cast::<40, 64>(self.s1_s.val());
            self.n1_s.d.next = self.s1_s.val().get_bit(63);
            self.d1_c.d.next = bit_cast::<40, 64>(self.s1_c.val());
            self.n1_c.d.next = self.s1_c.val().get_bit(63);
            self.a2_s.d.next = bit_cast::<56, 64>(self.s2_s.val());
            self.a2_c.d.next = bit_cast::<56, 64>(self.s2_c.val());
            self.dsc.d.next = bit_cast::<56, 64>(self.ssc.val());
            self.nsc.d.next = self.ssc.val().get_bit(63);
            self.br_s.d.next = self.bref_s.val();
            self.br_c.d.next = self.bref_c.val();
        }
        self.a1_s.d.next = self.d1_s.q.val();
        if self.n1_s.q.val() {
            self.a1_s.d.next = self.zero40.val() - self.d1_s.q.val();
        }
        self.a1_c.d.next = self.d1_c.q.val();
        if self.n1_c.q.val() {
            self.a1_c.d.next = self.zero40.val() - self.d1_c.q.val();
        }
        self.asl.d.next = self.zero28.val() - bit_cast::<28, 56>(self.dsc.q.val());
        self.ash.d.next = self.zero28.val() - bit_cast::<28, 56>(self.dsc.q.val() >> 28);
        self.alz.d.next = bit_cast::<28, 56>(self.dsc.q.val()) == self.zero28.val();
        self.asc.d.next = self.dsc.q.val();
        if self.nsc.q.val() {
            self.asc.d.next = (bit_cast::<56, 28>(!bit_cast::<28, 56>(self.dsc.q.val() >> 28))
                << 28)
                | bit_cast::<56, 28>(self.asl.q.val());
            if self.alz.q.val() {
                self.asc.d.next = (bit_cast::<56, 28>(self.ash.q.val()) << 28)
                    | bit_cast::<56, 28>(self.asl.q.val());
            }
        }
        // Free-running sums, compares and selects, each exact in its width when read: V - m²
        // (vsel: the row writing V_c - m_c²), Cq -+ |m_s m_c|, |C|, 2^30 - S², the offsets
        // b_ref +- round(|m| / 2^8) and their range, the amplitude check.
        self.vsel.d.next = self.v_s.q.val();
        if self.dn.q.val().w_vcs {
            self.vsel.d.next = self.v_c.q.val();
        }
        self.vd.d.next = self.vsel.q.val() - bit_cast::<49, 52>(self.u_r.q.val());
        self.ccp.d.next = self.cc.q.val() + bit_cast::<50, 52>(self.u_r.q.val());
        self.ccm.d.next = self.cc.q.val() - bit_cast::<50, 52>(self.u_r.q.val());
        self.ccn.d.next = bit_cast::<48, 50>(self.zero50.val() - self.cc.q.val());
        self.cmag.d.next = bit_cast::<48, 50>(self.cc.q.val());
        self.cpos.d.next = !self.cc.q.val().get_bit(49);
        if self.cc.q.val().get_bit(49) {
            self.cmag.d.next = self.ccn.q.val();
        }
        self.t30.d.next = self.two30.val() - bit_cast::<31, 52>(self.u_r.q.val());
        self.t_s.d.next = (bit_cast::<32, 24>(self.m_s.q.val()) + self.half8.val()) >> 8;
        self.t_c.d.next = (bit_cast::<32, 24>(self.m_c.q.val()) + self.half8.val()) >> 8;
        self.o_s.d.next = self.br_s.q.val() + self.t_s.q.val();
        if self.n1_s.q.val() {
            self.o_s.d.next = self.br_s.q.val() - self.t_s.q.val();
        }
        self.o_c.d.next = self.br_c.q.val() + self.t_c.q.val();
        if self.n1_c.q.val() {
            self.o_c.d.next = self.br_c.q.val() - self.t_c.q.val();
        }
        self.oor_sl.d.next = (self.o_s.q.val() ^ self.sign32.val()) < self.lo_f.val();
        self.oor_sh.d.next = (self.o_s.q.val() ^ self.sign32.val()) >= self.hi_f.val();
        self.oor_cl.d.next = (self.o_c.q.val() ^ self.sign32.val()) < self.lo_f.val();
        self.oor_ch.d.next = (self.o_c.q.val() ^ self.sign32.val()) >= self.hi_f.val();
        self.lo_s.d.next = self.amp_s.q.val() < self.minamp.val();
        self.lo_c.d.next = self.amp_c.q.val() < self.minamp.val();
        // The row before's result into its destination (pl's w_*, at a set-up or Load).
        if self.pl.q.val().w_ms {
            self.m_s.d.next = self.u_mag.q.val();
        }
        if self.pl.q.val().w_mc {
            self.m_c.d.next = self.u_mag.q.val();
        }
        if self.pl.q.val().w_vs {
            self.v_s.d.next = bit_cast::<49, 64>(self.u_x.q.val());
        }
        if self.pl.q.val().w_vc {
            self.v_c.d.next = bit_cast::<49, 64>(self.u_x.q.val());
        }
        if self.pl.q.val().w_cq {
            self.cc.d.next = bit_cast::<50, 64>(self.u_x.q.val());
        }
        if self.pl.q.val().w_vss {
            self.v_s.d.next = self.vd.q.val();
        }
        if self.pl.q.val().w_vcs {
            self.v_c.d.next = self.vd.q.val();
        }
        if self.pl.q.val().w_c {
            // C = Cq - m_s m_c, the product's sign from the means' signs.
            self.cc.d.next = self.ccm.q.val();
            if self.n1_s.q.val() ^ self.n1_c.q.val() {
                self.cc.d.next = self.ccp.q.val();
            }
        }
        if self.pl.q.val().w_amps {
            self.amp_s.d.next = bit_cast::<25, 52>(self.u_d.q.val() >> 3);
        }
        if self.pl.q.val().w_ampc {
            self.amp_c.d.next = bit_cast::<25, 52>(self.u_d.q.val() >> 3);
        }
        if self.pl.q.val().w_s {
            self.smag.d.next = self.scl.q.val();
            self.sneg.d.next = self.u_neg.q.val();
        }
        if self.pl.q.val().w_cs {
            self.cs.d.next = bit_cast::<16, 52>(self.u_d.q.val() >> 3);
        }
        if self.pl.q.val().w_gs {
            self.ng_s.d.next = self.ngf.q.val();
        }
        if self.pl.q.val().w_gc {
            self.ng_c.d.next = self.ngf.q.val();
        }
        if self.pl.q.val().w_q2 {
            self.q2.d.next = bit_cast::<40, 52>(self.u_r.q.val());
        }
        self.r_done.d.next = false;
        if self.pl.q.val().w_k {
            self.r_km.d.next = self.ngf.q.val();
            self.r_kn.d.next = self.sneg.q.val() & self.mnz.q.val();
            self.r_os.d.next = self.o_s.q.val();
            self.r_oc.d.next = self.o_c.q.val();
            self.r_gs.d.next = self.ng_s.q.val();
            self.r_gc.d.next = self.ng_c.q.val();
            self.r_done.d.next = true;
        }
    }
}
