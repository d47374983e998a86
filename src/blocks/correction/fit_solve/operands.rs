//! The solver's operands u_x, u_d, u_r (a stage of [`super::update`]).
use super::update::stages::Operands;
use super::*;

/// u_x, u_d and u_r: their sources, shifts and the chain's sum.
impl Operands for FitSolve {
    #[hdl_gen]
    fn update(&mut self) {
        // ---- u_x, u_d, u_r. Sources written rows earlier reach them through free-running
        // registers that dn selects (AND-OR, the selects one-hot); a set-up loads those or a
        // result of the row before by pl's one-hot selects, ANDed and ORed under one
        // registered enable each.
        self.uxan.next = self.zero64.val();
        self.uxbn.next = self.zero64.val();
        self.uxcn.next = self.zero64.val();
        self.udrn.next = self.zero52.val();
        if self.dn.q.val().xs_a1c {
            self.uxan.next = self.uxan.val() | (bit_cast::<64, 40>(self.a1_c.q.val()) << 8);
        }
        if self.dn.q.val().xs_a2s {
            self.uxan.next = self.uxan.val() | bit_cast::<64, 56>(self.a2_s.q.val());
        }
        if self.dn.q.val().xs_a2c {
            self.uxan.next = self.uxan.val() | bit_cast::<64, 56>(self.a2_c.q.val());
        }
        if self.dn.q.val().xs_asc {
            self.uxan.next = self.uxan.val() | bit_cast::<64, 56>(self.asc.q.val());
        }
        if self.dn.q.val().xs_vs2 & !self.v_s.q.val().get_bit(48) {
            self.uxan.next = self.uxan.val() | (bit_cast::<64, 49>(self.v_s.q.val()) << 1);
        }
        if self.dn.q.val().xs_ms {
            self.uxbn.next = self.uxbn.val() | (bit_cast::<64, 24>(self.m_s.q.val()) << 32);
        }
        if self.dn.q.val().xs_mc {
            self.uxbn.next = self.uxbn.val() | (bit_cast::<64, 24>(self.m_c.q.val()) << 32);
        }
        if self.dn.q.val().xs_vc2 & !self.v_c.q.val().get_bit(48) {
            self.uxbn.next = self.uxbn.val() | (bit_cast::<64, 49>(self.v_c.q.val()) << 1);
        }
        if self.dn.q.val().xs_amps {
            self.uxbn.next = self.uxbn.val() | (bit_cast::<64, 25>(self.amp_s.q.val()) << 32);
        }
        if self.dn.q.val().xs_ampc {
            self.uxcn.next = self.uxcn.val() | (bit_cast::<64, 25>(self.amp_c.q.val()) << 32);
        }
        if self.dn.q.val().xs_cmag {
            self.uxcn.next = self.uxcn.val() | (bit_cast::<64, 48>(self.cmag.q.val()) << 16);
        }
        if self.dn.q.val().xs_tgs {
            self.uxcn.next = self.uxcn.val() | self.tgs.val();
        }
        if self.dn.q.val().xs_tgc {
            self.uxcn.next = self.uxcn.val() | self.tgc.val();
        }
        if self.dn.q.val().xs_t32 {
            self.uxcn.next = self.uxcn.val() | self.tamp32.val();
        }
        self.uxa.d.next = self.uxan.val();
        self.uxb.d.next = self.uxbn.val();
        self.uxc.d.next = self.uxcn.val();
        self.uxr.d.next = self.uxa.q.val() | self.uxb.q.val() | self.uxc.q.val();
        if self.dn.q.val().ds_ms {
            self.udrn.next = self.udrn.val() | bit_cast::<52, 24>(self.m_s.q.val());
        }
        if self.dn.q.val().ds_mc {
            self.udrn.next = self.udrn.val() | bit_cast::<52, 24>(self.m_c.q.val());
        }
        if self.dn.q.val().ds_amps {
            self.udrn.next = self.udrn.val() | bit_cast::<52, 25>(self.amp_s.q.val());
        }
        if self.dn.q.val().ds_cs {
            self.udrn.next = self.udrn.val() | bit_cast::<52, 16>(self.cs.q.val());
        }
        if self.dn.q.val().ds_smag {
            self.udrn.next = self.udrn.val() | bit_cast::<52, 16>(self.smag.q.val());
        }
        if self.dn.q.val().ds_q2 {
            self.udrn.next = self.udrn.val() | bit_cast::<52, 40>(self.q2.q.val());
        }
        self.udr.d.next = self.udrn.val();
        self.uxn.next = self.zero64.val();
        if self.pl.q.val().x_a1s {
            self.uxn.next = self.uxn.val() | (bit_cast::<64, 40>(self.a1_s.q.val()) << 8);
        }
        if self.pl.q.val().x_st {
            self.uxn.next = self.uxn.val() | self.uxr.q.val();
        }
        if self.pl.q.val().x_scl {
            self.uxn.next = self.uxn.val() | (bit_cast::<64, 16>(self.scl.q.val()) << 32);
        }
        if self.pl.q.val().x_t30 {
            self.uxn.next = self.uxn.val() | bit_cast::<64, 31>(self.t30.q.val());
        }
        if self.pl.q.val().x_urk {
            self.uxn.next =
                self.uxn.val() | (bit_cast::<64, 52>(self.u_r.q.val()) << self.kshift.val());
        }
        if self.x_q.q.val() {
            self.uxn.next = self.uxn.val() | self.u_q.q.val();
        }
        // An A clock shifts u_x; the B clock after it writes the quotient bit into bit 0.
        if self.f_sh1.q.val() {
            self.uxn.next = self.uxn.val() | (self.u_x.q.val() << 1);
        }
        if self.f_sh2.q.val() {
            self.uxn.next = self.uxn.val() | (self.u_x.q.val() << 2);
        }
        if self.x_en.q.val() {
            self.u_x.d.next = self.uxn.val();
        }
        if self.f_qx.q.val() & !self.rneg.val() {
            self.u_x.d.next = self.u_x.q.val() | self.one64.val();
        }
        // u_d likewise; in a square root the trial 8 q + 1 takes the new root bit at bit 3
        // in the B clock after an A clock (the old bits 0..2 are 001, one bit up 010).
        self.udn.next = self.zero52.val();
        if self.pl.q.val().d_sn {
            self.udn.next = self.udn.val() | bit_cast::<52, 25>(self.sn.q.val());
        }
        if self.pl.q.val().d_st {
            self.udn.next = self.udn.val() | self.udr.q.val();
        }
        if self.pl.q.val().d_root {
            self.udn.next = self.udn.val() | (self.u_d.q.val() >> 3);
        }
        if self.pl.q.val().d_prod {
            self.udn.next = self.udn.val() | self.u_r.q.val();
        }
        if self.pl.q.val().d_scl {
            self.udn.next = self.udn.val() | bit_cast::<52, 16>(self.scl.q.val());
        }
        if self.pl.q.val().d_one {
            self.udn.next = self.udn.val() | self.one52.val();
        }
        if self.f_qd.q.val() {
            self.udn.next =
                self.udn.val() | ((self.u_d.q.val() << 1) & self.nb1.val()) | self.one52.val();
            if !self.rneg.val() {
                self.udn.next = self.udn.val() | self.nine52.val();
            }
        }
        if self.d_en.q.val() {
            self.u_d.d.next = self.udn.val();
        }
        // u_r: cleared at a set-up, the chain's sum in an A clock (bits 52..1: bit 0 of
        // {oa, 1} + {opb, cin} only carries cin in).
        if self.clr_r.q.val() {
            self.u_r.d.next = self.zero52.val();
        }
        if self.f_add.q.val() {
            self.u_r.d.next = bit_cast::<52, 53>(
                (((bit_cast::<53, 52>(self.oa.q.val()) << 1) | self.one53.val()) + self.ob.q.val())
                    >> 1,
            );
        }
    }
}
