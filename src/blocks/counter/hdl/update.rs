//! The logic of [`QuadrantCounter`] (`super`), in named stages.
use super::*;

// The counter's logic in named stages, run in this order (`logic_stages!`).
crate::blocks::logic_stages!(QuadrantCounter: Steps, Wrap, Turns, TurnRegister);

/// The two candidate steps and their period adders.
impl stages::Steps for QuadrantCounter {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clk,
            init_reg,
            pprev_reg,
            u_reg,
            fine_reg,
            turns_reg,
            tinc_reg,
            tdec_reg,
            tio_reg,
            tdo_reg,
            ovi_reg,
            ovd_reg,
            valid_reg,
            error_reg,
            warning_reg,
            pending_reg,
            lqc_reg,
            lturns_reg,
            ltinc_reg,
            ltdec_reg,
            llast_reg,
            lzero_reg,
            lpen_reg,
            lone_reg,
            ul_reg,
            dl_reg,
            uwl_reg,
            dwl_reg,
            ulast_reg,
            unz_reg
        );
        // Two candidate steps side by side, each with its own period adder, chosen by
        // `pending` after the adders (a mux in front of an adder is a LUT level more):
        // the running count's, whose direction comes from the combiner (up, down: the sign
        // of delta and the quadrants), and, when a resynchronisation is pending, the latched
        // count's, whose direction is the nearest step to the sample's quadrant (+0, +1,
        // +2 forwards, -1 backwards), from the two quadrants.
        // ustep = +1, -1 or 0 with its bits taken from registers: bit 0 is step_in, the
        // bits above it down_in (no LUT in front of the adder).
        self.ustep.next = self.zero.val();
        if self.down_in.val() {
            self.ustep.next = self.minus_two.val();
        }
        if self.step_in.val() {
            self.ustep.next = self.ustep.val() | self.one.val();
        }
        self.usum.next = (self.u_reg.q.val() + self.ustep.val()) & self.usmask.val();
    }
}

/// The wrap at 4PPR and the load's step decode.
impl stages::Wrap for QuadrantCounter {
    #[hdl_gen]
    fn update(&mut self) {
        // Wrap at 4PPR: period PPR-1 -> 0 steps the turns up, 0 -> PPR-1 down. u = 0 down
        // is the borrow of usum; with PPR a power of two, u = PPR-1 up is its carry and u
        // wraps by itself, else a compare and a constant take over. The turn counter's
        // +1 and -1 are short adders of their own (on the running count, or taken at the
        // load), selected after the wrap, so no second carry chain follows usum's.
        // The wrap from the flags kept with u (u = PPR - 1, u = 0), not from usum's carry
        // out, so the turn counter's selection does not wait for the u adder.
        self.wrap.next = (self.up_in.val() & (self.ulast_reg.q.val() | self.ppr1.val()))
            | (self.down_in.val() & (!self.unz_reg.q.val() | self.ppr1.val()));
        // The flags' next values: compares of the register u with constants, chosen by the
        // step (up: u = PPR - 2 ends on the last period, u = PPR - 1 on 0; down: u = 0 ends
        // on the last, u = 1 on 0; no step: u itself).
        self.upen.next = (self.u_reg.q.val() & self.umask.val()) == self.upenult.val();
        self.ulst.next = (self.u_reg.q.val() & self.umask.val()) == self.ulast.val();
        self.uzer.next = (self.u_reg.q.val() & self.umask.val()) == self.zero.val();
        self.uone.next = (self.u_reg.q.val() & self.umask.val()) == self.uone_c.val();
        // Iterative: the wrap from compares of u itself, so the flags kept with u go unread
        // and synthesis drops them (fewer LUTs; `tests/blocks/iterative.rs`).
        if !self.flat.val() {
            self.wrap.next = (self.up_in.val() & (self.ulst.val() | self.ppr1.val()))
                | (self.down_in.val() & (self.uzer.val() | self.ppr1.val()));
        }
        self.nlast.next = self.ulst.val();
        self.nzero.next = self.uzer.val();
        if self.up_in.val() {
            self.nlast.next = self.upen.val();
            self.nzero.next = self.ulst.val();
        }
        if self.down_in.val() {
            self.nlast.next = self.uzer.val();
            self.nzero.next = self.uone.val();
        }
        self.base_u.next = (self.lqc_reg.q.val() >> self.two.val()) & self.umask.val();
        // Four-input functions of the two quadrants written out, so that no 2-bit
        // subtractor or comparator (a carry chain on xc3sa) sits in front of usum_l.
        // Forward steps +1, +2 pass 3 -> 0 from quadrant 2 to 0 and from 3 to 0 or 1;
        // the backward step -1 passes 0 -> 3 only from 0 to 3.
        // The unrolled architecture takes them from the registers decoded a clock ahead
        // (below); the iterative one decodes them here, from the latched count and this
        // clock's sample (the registers cost it LUTs; `tests/blocks/iterative.rs`).
        if self.flat.val() {
            self.up_l.next = self.ul_reg.q.val();
            self.down_l.next = self.dl_reg.q.val();
            self.uwl.next = self.uwl_reg.q.val();
            self.dwl.next = self.dwl_reg.q.val();
        } else {
            self.qlat.next = self.lqc_reg.q.val() & self.three.val();
            self.qnow.next = (self.p_in.val() >> self.fshift.val()) & self.three.val();
            self.up_l.next = self.qlat.val().get_bit(1)
                & !self.qnow.val().get_bit(1)
                & (self.qlat.val().get_bit(0) | !self.qnow.val().get_bit(0));
            self.down_l.next = !self.qlat.val().get_bit(1)
                & !self.qlat.val().get_bit(0)
                & self.qnow.val().get_bit(1)
                & self.qnow.val().get_bit(0);
            self.uwl.next = self.up_l.val() & self.llast_reg.q.val();
            self.dwl.next = self.down_l.val() & self.lzero_reg.q.val();
        }
        self.ustep_l.next = self.zero.val();
        if self.up_l.val() {
            self.ustep_l.next = self.one.val();
        }
        if self.down_l.val() {
            self.ustep_l.next = self.minus_one.val();
        }
        self.usum_l.next = (self.base_u.val() + self.ustep_l.val()) & self.usmask.val();
        self.wrap_l.next = self.uwl.val() | self.dwl.val();
    }
}

/// The selection and the turns' +-1 registers.
impl stages::Turns for QuadrantCounter {
    #[hdl_gen]
    fn update(&mut self) {
        // The selection.
        self.up.next = self.up_in.val();
        self.down.next = self.down_in.val();
        self.un.next = self.usum.val() & self.umask.val();
        // turns +- 1 into registers at every clock (the only carry chains on the turns).
        // In the clock after an update that moves the turns they are stale, and that
        // update leaves the value the next sample may read in tio / tdo with a flag (below).
        // A step forward over quadrant 3 -> 0 ends in quadrant 0 or 1 (steps are under 2
        // quadrants), so the next sample cannot step forward over it again: after a wrap
        // up only turns - 1 can be read at the next sample, and it is the turn count the
        // wrap started from; after a wrap down only turns + 1, likewise; after a load's
        // step without a wrap both, the latched + 1 and - 1.
        self.tinc_reg.d.next = (self.turns_reg.q.val() + self.one.val()) & self.tmask.val();
        self.tdec_reg.d.next = (self.turns_reg.q.val() + self.minus_one.val()) & self.tmask.val();
        // Only the flat form (unrolled) reads these; the iterative one adds + 1 / - 1 after
        // the choice of base (below), and synthesis drops the registers it does not read.
        self.tinc.next = self.tinc_reg.q.val();
        if self.ovi_reg.q.val() {
            self.tinc.next = self.tio_reg.q.val();
        }
        self.tdec.next = self.tdec_reg.q.val();
        if self.ovd_reg.q.val() {
            self.tdec.next = self.tdo_reg.q.val();
        }
        self.base_turns.next = self.turns_reg.q.val();
        if self.pending_reg.q.val() {
            self.up.next = self.up_l.val();
            self.down.next = self.down_l.val();
            self.un.next = self.usum_l.val() & self.umask.val();
            self.wrap.next = self.wrap_l.val();
            self.base_turns.next = self.lturns_reg.q.val();
            self.nlast.next = self.llast_reg.q.val();
            self.nzero.next = self.lzero_reg.q.val();
            if self.up_l.val() {
                self.nlast.next = self.lpen_reg.q.val();
                self.nzero.next = self.llast_reg.q.val();
            }
            if self.down_l.val() {
                self.nlast.next = self.lzero_reg.q.val();
                self.nzero.next = self.lone_reg.q.val();
            }
        }
        self.valid_reg.d.next = self.v_in.val() & !self.rst.val();
        if self.load.val() {
            self.pending_reg.d.next = true;
            self.lqc_reg.d.next = self.load_qc.val();
            self.lturns_reg.d.next = self.load_turns.val();
            self.ltinc_reg.d.next = (self.load_turns.val() + self.one.val()) & self.tmask.val();
            self.ltdec_reg.d.next =
                (self.load_turns.val() + self.minus_one.val()) & self.tmask.val();
            self.llast_reg.d.next =
                ((self.load_qc.val() >> self.two.val()) & self.umask.val()) == self.ulast.val();
            self.lzero_reg.d.next =
                ((self.load_qc.val() >> self.two.val()) & self.umask.val()) == self.zero.val();
            self.lpen_reg.d.next =
                ((self.load_qc.val() >> self.two.val()) & self.umask.val()) == self.upenult.val();
            self.lone_reg.d.next =
                ((self.load_qc.val() >> self.two.val()) & self.umask.val()) == self.uone_c.val();
        }
        if self.rst.val() {
            self.init_reg.d.next = false;
            self.pprev_reg.d.next = self.zero.val();
            self.u_reg.d.next = self.zero.val();
            self.ulast_reg.d.next = false;
            self.unz_reg.d.next = false;
            self.fine_reg.d.next = self.zero.val();
            self.turns_reg.d.next = self.zero.val();
            self.error_reg.d.next = false;
            self.warning_reg.d.next = false;
            self.pending_reg.d.next = false;
            self.lqc_reg.d.next = self.zero.val();
            self.lturns_reg.d.next = self.zero.val();
        } else if self.v_in.val() {
            if !self.ok_in.val() {
                self.error_reg.d.next = true;
                self.warning_reg.d.next = false;
            } else if !self.init_reg.q.val() {
                // qc = p >> F and turns = 0: u and turns are still 0 from the reset (or the
                // power-up) since only an initialised counter moves them.
                self.init_reg.d.next = true;
                self.fine_reg.d.next = self.p_in.val() & self.fmask.val();
                self.error_reg.d.next = false;
                self.warning_reg.d.next = false;
                self.pprev_reg.d.next = self.p_in.val();
            } else {
                self.error_reg.d.next = false;
                if self.pending_reg.q.val() {
                    self.warning_reg.d.next = false;
                    if !self.load.val() {
                        self.pending_reg.d.next = false;
                    }
                } else {
                    // wlo <= delta <= whi, in units of 2^(F-2) (the thresholds' LSB).
                    self.warning_reg.d.next = (self.wq_in.val() >= self.wlo.val())
                        & ((self.wq_in.val() < self.whi.val())
                            | ((self.wq_in.val() == self.whi.val()) & self.wz_in.val()));
                }
                self.u_reg.d.next = self.un.val();
                self.ulast_reg.d.next = self.nlast.val();
                self.unz_reg.d.next = !self.nzero.val();
                if !self.pow2.val() & self.wrap.val() {
                    if self.up.val() {
                        self.u_reg.d.next = self.zero.val();
                    } else {
                        self.u_reg.d.next = self.ulast.val();
                    }
                }
                // Iterative: the turns from the selected step (the flat form is below).
                if !self.flat.val() {
                    self.turns_reg.d.next = self.base_turns.val() & self.tmask.val();
                    if self.wrap.val() {
                        if self.up.val() {
                            self.turns_reg.d.next =
                                (self.base_turns.val() + self.one.val()) & self.tmask.val();
                        } else {
                            self.turns_reg.d.next =
                                (self.base_turns.val() + self.minus_one.val()) & self.tmask.val();
                        }
                    }
                }
                self.fine_reg.d.next = self.p_in.val() & self.fmask.val();
                self.pprev_reg.d.next = self.p_in.val();
            }
        }
    }
}

/// The load's step ahead, the turn register and the flat form's update.
impl stages::TurnRegister for QuadrantCounter {
    #[hdl_gen]
    fn update(&mut self) {
        // A load's step for the next clock's sample, from the quadrant of the count latched
        // by then (lqc's next value) and of that sample (the combiner's p before its
        // register, which p_in will be), so the load's step direction comes from registers.
        self.base_q.next = self.lqc_reg.d.val() & self.three.val();
        self.qnew.next = self.q_next.val() & self.three.val();
        self.ul_reg.d.next = self.base_q.val().get_bit(1)
            & !self.qnew.val().get_bit(1)
            & (self.base_q.val().get_bit(0) | !self.qnew.val().get_bit(0));
        self.dl_reg.d.next = !self.base_q.val().get_bit(1)
            & !self.base_q.val().get_bit(0)
            & self.qnew.val().get_bit(1)
            & self.qnew.val().get_bit(0);
        self.uwl_reg.d.next = self.ul_reg.d.val() & self.llast_reg.d.val();
        self.dwl_reg.d.next = self.dl_reg.d.val() & self.lzero_reg.d.val();
        // The turn register, a selection from registers with its selects from registered
        // flags (no carry chain, and no decode of p or of the step's direction): hold; a
        // load's step (latched count, + 1 on uwl, - 1 on dwl); the running step (turns,
        // + 1 at u = PPR - 1 forwards, - 1 at u = 0 backwards); 0 at a reset.
        self.rwu.next =
            self.acc_in.val() & self.up_in.val() & (self.ulast_reg.q.val() | self.ppr1.val());
        self.rwd.next =
            self.acc_in.val() & self.down_in.val() & (!self.unz_reg.q.val() | self.ppr1.val());
        self.tsel_p.next = self.lturns_reg.q.val();
        if self.uwl.val() {
            self.tsel_p.next = self.ltinc_reg.q.val();
        }
        if self.dwl.val() {
            self.tsel_p.next = self.ltdec_reg.q.val();
        }
        // The running step's value, read only when rwu or rwd holds: then up and down are
        // exclusive and the step is backwards exactly when down is set, so the select
        // needs neither rwu nor rwd (the enable below has them).
        self.tsel_r.next = self.tinc.val();
        if self.down_in.val() {
            self.tsel_r.next = self.tdec.val();
        }
        // The values for the clock after the update (turns +- 1 stale, see above): the
        // count a step started from, the latched +- 1 after a load's step; the flags say
        // which the next sample may read (after a wrap up turns - 1, after a wrap down
        // turns + 1, after a load's step without a wrap both).
        self.ovi_reg.d.next = false;
        self.ovd_reg.d.next = false;
        self.tio_reg.d.next = self.turns_reg.q.val();
        self.tdo_reg.d.next = self.turns_reg.q.val();
        if self.pending_reg.q.val() {
            self.tio_reg.d.next = self.ltinc_reg.q.val();
            self.tdo_reg.d.next = self.ltdec_reg.q.val();
            if self.dwl.val() {
                self.tio_reg.d.next = self.lturns_reg.q.val();
            }
            if self.uwl.val() {
                self.tdo_reg.d.next = self.lturns_reg.q.val();
            }
        }
        // Flat form: the turn register's update (selected above) on an accepted sample of an
        // initialised counter, then the reset again (as above), which overrides it: so the
        // reset is the flip-flops' synchronous reset over the enable, and the enable reads
        // acc_in, init and the selects only (rst is not one of its inputs).
        if self.flat.val() & self.acc_in.val() & self.init_reg.q.val() {
            if self.pending_reg.q.val() {
                self.turns_reg.d.next = self.tsel_p.val() & self.tmask.val();
            } else if self.rwu.val() | self.rwd.val() {
                self.turns_reg.d.next = self.tsel_r.val() & self.tmask.val();
            }
        }
        if self.rst.val() {
            self.turns_reg.d.next = self.zero.val();
        }
        if self.flat.val() & self.acc_in.val() & self.init_reg.q.val() & !self.rst.val() {
            if self.pending_reg.q.val() {
                self.ovi_reg.d.next = !self.uwl.val();
                self.ovd_reg.d.next = !self.dwl.val();
            } else {
                self.ovi_reg.d.next = self.rwd.val();
                self.ovd_reg.d.next = self.rwu.val();
            }
        }
        self.qc.next = (self.u_reg.q.val() << self.two.val())
            | ((self.pprev_reg.q.val() >> self.fshift.val()) & self.three.val());
        self.fine.next = self.fine_reg.q.val();
        self.turns.next = self.turns_reg.q.val();
        self.valid.next = self.valid_reg.q.val();
        self.error.next = self.error_reg.q.val();
        self.warning.next = self.warning_reg.q.val();
    }
}
