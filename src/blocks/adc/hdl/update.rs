//! The logic of [`AdcController`] (`super`), in named stages.
use super::*;

// The controller's logic in named stages, run in this order (`logic_stages!`).
crate::blocks::logic_stages!(AdcController: Period, Counters, Windows, PinsCapture);

/// The period counter and the lead clock.
impl stages::Period for AdcController {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, live, pc, ph, cyc, warm, sr0, sr1, sck_reg, conv_reg, valid_reg, ch0_reg,
            ch1_reg, miso_d, rst_d, pcl_x, pcm_x, wa, w0, w1, wl, wb, wc, cst, plx, atl, ewa_lo,
            ewa_hi, ew0_lo, ew0_hi, ew1_lo, ew1_hi, ewl_lo, ewl_hi, est, cap0_d, cap1_d, capv_d
        );
        self.run.next = self.enable.val() & !self.rst.val();
        // Period counter and warm-up count (flush period, then discarded frames).
        // pc_n == lead, from pc (equality tests, not a compare after the increment). The
        // two tests on pc are flags registered with pc: pc_n = 0 gives (0 == X) ^ k = 0,
        // pc_n = pc + 1 (pc < P - 1, no wrap) gives (pc == X - 1) ^ k.
        self.fl.next = self.pcl_x.q.val() ^ self.kl.val();
        self.fm.next = self.pcm_x.q.val() ^ self.km.val();
        // The lead clock (used only while running, so decoded without `run`: every
        // register below loads its idle value when `run` is low, and that test is the
        // outermost, which Yosys maps onto the flip-flops' synchronous reset). It is
        // (live & !fl) ? fm : (lead = 0), kept in `atl` from the next values.
        self.at_lead.next = self.atl.q.val() ^ self.lead_zero.val();
        self.pc_eqp.next = (self.pc.q.val() & self.pc_mask.val()) == self.p_last_m1.val();
        self.pc_eql.next = (self.pc.q.val() & self.pc_mask.val()) == self.lead_m2.val();
        // Next values while running (`run` is applied last, as the outermost test, so the
        // data inputs below do not depend on it). at_lead of the next state: live' = run,
        // fl' = pcl_x' ^ kl, fm' = pcm_x' ^ km, i.e. (kl ? (lead = 0) : km) unless pc steps
        // (then pc_eqp ? (lead = 0) : pc_eql).
        self.pc_n.next = self.zero16.val();
        self.warm_n.next = self.warm_init.val();
        self.pcl_n.next = false;
        self.pcm_n.next = false;
        self.atl_n.next = self.atl_idle.val();
        if self.live.q.val() {
            if self.fl.val() {
                self.pc_n.next = self.zero16.val();
                if self.warm.q.val() == self.zero4.val() {
                    self.warm_n.next = self.zero4.val();
                } else {
                    self.warm_n.next = self.warm.q.val() - self.one4.val();
                }
            } else {
                self.pc_n.next = self.pc.q.val() + self.one16.val();
                self.warm_n.next = self.warm.q.val();
                self.pcl_n.next = self.pc_eqp.val() ^ self.kl.val();
                self.pcm_n.next = self.pc_eql.val() ^ self.km.val();
                self.atl_n.next = self.lead_zero.val();
                if !self.pc_eqp.val() {
                    self.atl_n.next = self.pc_eql.val();
                }
            }
        }
        if !self.run.val() {
            self.pc_n.next = self.zero16.val();
            self.warm_n.next = self.warm_init.val();
            self.pcl_n.next = false;
            self.pcm_n.next = false;
        }
        self.pcl_x.d.next = self.pcl_n.val();
        self.pcm_x.d.next = self.pcm_n.val();
        // Stopped: at_lead' = (lead = 0), stored 0 (a synchronous reset of atl).
        self.atl.d.next = self.atl_n.val() ^ self.lead_zero.val();
        if !self.run.val() {
            self.atl.d.next = false;
        }
        // The cycle counter's equality tests (see `ewa_lo`).
        self.ewa_lo.d.next = self.cyc.q.val() == self.wa_lo.val();
        self.ewa_hi.d.next = self.cyc.q.val() == self.wa_hi.val();
        self.ew0_lo.d.next = self.cyc.q.val() == self.w0_lo.val();
        self.ew0_hi.d.next = self.cyc.q.val() == self.w0_hi.val();
        self.ew1_lo.d.next = self.cyc.q.val() == self.w1_lo.val();
        self.ew1_hi.d.next = self.cyc.q.val() == self.w1_hi.val();
        self.ewl_lo.d.next = self.cyc.q.val() == self.wl_lo.val();
        self.ewl_hi.d.next = self.cyc.q.val() == self.wl_hi.val();
        self.est.d.next = self.cyc.q.val() == self.cyc_stop_m1.val();
    }
}

/// The SCK phase and cycle counters.
impl stages::Counters for AdcController {
    #[hdl_gen]
    fn update(&mut self) {
        // SCK phase and cycle counters: restart at the lead clock, stop after the frame.
        // cyc == frame + 1 and ph == D - 1 are flags registered with the counters (set
        // from the old count on a step), so no compare sits in front of the step enables.
        self.pl_end.next = self.plx.q.val() ^ self.d_one.val();
        self.cinc.next = false;
        self.pinc.next = false;
        self.crel.next = false;
        self.prel.next = true;
        self.cst.d.next = self.cst.q.val();
        self.plx.d.next = false;
        if self.at_lead.val() {
            self.ph_n.next = self.zero8.val();
            self.cyc_n.next = self.zero8.val();
            self.crel.next = true;
            self.cst.d.next = false;
        } else if self.cst.q.val() {
            self.ph_n.next = self.ph.q.val();
            self.cyc_n.next = self.cyc.q.val();
            self.prel.next = false;
            self.plx.d.next = self.plx.q.val();
        } else if self.pl_end.val() {
            self.ph_n.next = self.zero8.val();
            self.cyc_n.next = self.cyc.q.val() + self.one8.val();
            self.cinc.next = true;
            self.cst.d.next = self.est.q.val();
        } else {
            self.ph_n.next = self.ph.q.val() + self.one8.val();
            self.cyc_n.next = self.cyc.q.val();
            self.pinc.next = true;
            self.prel.next = false;
            self.plx.d.next = (self.ph.q.val() == self.d_last_m1.val()) ^ self.d_one.val();
        }
        if !self.run.val() {
            self.ph_n.next = self.zero8.val();
            self.cyc_n.next = self.cyc_stop.val();
            self.cst.d.next = true;
            self.plx.d.next = false;
        }
    }
}

/// The window flags.
impl stages::Windows for AdcController {
    #[hdl_gen]
    fn update(&mut self) {
        // Window flags follow the counters: hold, reload to 0, step (see `Win`), or park
        // at the stop value (not running, the outermost test). Stored XOR the power-up
        // value.
        self.pa.next = self.wa.q.val() ^ self.wa_z.val();
        self.p0.next = self.w0.q.val() ^ self.w0_z.val();
        self.p1.next = self.w1.q.val() ^ self.w1_z.val();
        self.pl.next = self.wl.q.val() ^ self.wl_z.val();
        self.pb.next = self.wb.q.val() ^ self.wb_z.val();
        self.pcp.next = self.wc.q.val() ^ self.wc_z.val();
        self.wa.d.next = self.wa.q.val();
        self.w0.d.next = self.w0.q.val();
        self.w1.d.next = self.w1.q.val();
        self.wl.d.next = self.wl.q.val();
        if self.crel.val() {
            self.wa.d.next = false;
            self.w0.d.next = false;
            self.w1.d.next = false;
            self.wl.d.next = false;
        }
        if self.cinc.val() {
            self.wa.d.next =
                (self.ewa_lo.q.val() | (self.pa.val() & !self.ewa_hi.q.val())) ^ self.wa_z.val();
            self.w0.d.next =
                (self.ew0_lo.q.val() | (self.p0.val() & !self.ew0_hi.q.val())) ^ self.w0_z.val();
            self.w1.d.next =
                (self.ew1_lo.q.val() | (self.p1.val() & !self.ew1_hi.q.val())) ^ self.w1_z.val();
            self.wl.d.next =
                (self.ewl_lo.q.val() | (self.pl.val() & !self.ewl_hi.q.val())) ^ self.wl_z.val();
        }
        if !self.run.val() {
            self.wa.d.next = self.wa_s.val() ^ self.wa_z.val();
            self.w0.d.next = self.w0_s.val() ^ self.w0_z.val();
            self.w1.d.next = self.w1_s.val() ^ self.w1_z.val();
            self.wl.d.next = self.wl_s.val() ^ self.wl_z.val();
        }
        self.wb.d.next = self.wb.q.val();
        self.wc.d.next = self.wc.q.val();
        if self.prel.val() {
            self.wb.d.next = false;
            self.wc.d.next = false;
        }
        if self.pinc.val() {
            self.wb.d.next = ((self.ph.q.val() == self.wb_lo.val())
                | (self.pb.val() & (self.ph.q.val() != self.wb_hi.val())))
                ^ self.wb_z.val();
            self.wc.d.next = ((self.ph.q.val() == self.wc_lo.val())
                | (self.pcp.val() & (self.ph.q.val() != self.wc_hi.val())))
                ^ self.wc_z.val();
        }
        if !self.run.val() {
            self.wb.d.next = false;
            self.wc.d.next = false;
        }
    }
}

/// The pins and the capture.
impl stages::PinsCapture for AdcController {
    #[hdl_gen]
    fn update(&mut self) {
        // Pins of the state entered at the previous edge (live = run then), registered:
        // the pins show the state one clock after it is entered.
        self.sck_act.next = self.live.q.val() & self.pa.val() & self.pb.val();
        self.conv_act.next = self.live.q.val()
            & (self.pc.q.val() < self.conv_end.val())
            & (self.warm.q.val() < self.warm_init.val());
        self.sck_reg.d.next = self.sck_act.val() ^ self.cpol.val();
        self.conv_reg.d.next = self.conv_act.val() ^ self.conv_idle.val();
        // Capture: the state entered at the previous edge (capture state S) launches the
        // next shifting SCK edge at this edge; miso_d samples adc_miso at this same edge,
        // D clocks after the pin edge that shifted the bit out
        // (`AdcParams::capture_distance_clocks`). The enables of S are registered
        // (cap0_d ...) and the bit is shifted in at the next edge. Slot k is cycle k + 1
        // (the constants hold slot + 1).
        self.miso_d.d.next = self.adc_miso.val();
        self.rst_d.d.next = self.rst.val();
        self.cap.next = self.live.q.val() & self.pcp.val();
        self.cap0_d.d.next = self.cap.val() & self.p0.val();
        self.cap1_d.d.next = self.cap.val() & self.p1.val();
        self.capv_d.d.next =
            self.cap.val() & self.pl.val() & (self.warm.q.val() == self.zero4.val());
        self.shifted0.next = (self.sr0.q.val() << self.one16.val()) & self.wmask.val();
        if self.miso_d.q.val() {
            self.shifted0.next =
                ((self.sr0.q.val() << self.one16.val()) | self.one16.val()) & self.wmask.val();
        }
        self.shifted1.next = (self.sr1.q.val() << self.one16.val()) & self.wmask.val();
        if self.miso_d.q.val() {
            self.shifted1.next =
                ((self.sr1.q.val() << self.one16.val()) | self.one16.val()) & self.wmask.val();
        }
        // Two data lines: channel 1 shifts line B's bit, sampled at the same edge as line
        // A's (no loop body with one line).
        for i in 0..self.miso_b_d.len() {
            self.miso_b_d[i].clock.next = self.clk.val();
            self.miso_b_d[i].d.next = self.adc_miso_b[i].val();
            self.shifted1.next = (self.sr1.q.val() << self.one16.val()) & self.wmask.val();
            if self.miso_b_d[i].q.val() {
                self.shifted1.next =
                    ((self.sr1.q.val() << self.one16.val()) | self.one16.val()) & self.wmask.val();
            }
        }
        self.sr0_n.next = self.sr0.q.val();
        if self.cap0_d.q.val() {
            self.sr0_n.next = self.shifted0.val();
        }
        self.sr1_n.next = self.sr1.q.val();
        if self.cap1_d.q.val() {
            self.sr1_n.next = self.shifted1.val();
        }
        self.sr0.d.next = self.sr0_n.val();
        self.sr1.d.next = self.sr1_n.val();
        self.valid_reg.d.next = false;
        if self.capv_d.q.val() {
            self.valid_reg.d.next = true;
            self.ch0_reg.d.next = (self.sr0_n.val() ^ self.flip.val()) & self.wmask.val();
            self.ch1_reg.d.next = (self.sr1_n.val() ^ self.flip.val()) & self.wmask.val();
            if self.one_ch.val() {
                self.ch1_reg.d.next = self.zero16.val();
            }
        }
        self.live.d.next = self.run.val();
        self.pc.d.next = self.pc_n.val();
        self.ph.d.next = self.ph_n.val();
        self.cyc.d.next = self.cyc_n.val();
        self.warm.d.next = self.warm_n.val();
        if self.rst_d.q.val() {
            self.sr0.d.next = self.zero16.val();
            self.sr1.d.next = self.zero16.val();
            self.ch0_reg.d.next = self.zero16.val();
            self.ch1_reg.d.next = self.zero16.val();
            self.valid_reg.d.next = false;
        }
        // The frame check (`with_frame_check`): the data bits shifted in at this edge, and
        // the verdict with the frame's last one, registered with out_valid.
        for i in 0..self.fcheck.len() {
            self.fcheck[i].clk.next = self.clk.val();
            self.fcheck[i].rst.next = self.rst_d.q.val();
            self.fcheck[i].en0.next = self.cap0_d.q.val();
            self.fcheck[i].en1.next = self.cap1_d.q.val();
            self.fcheck[i].bit_a.next = self.miso_d.q.val();
            self.fcheck[i].bit_b.next = false;
            for k in 0..self.miso_b_d.len() {
                self.fcheck[i].bit_b.next = self.miso_b_d[k].q.val();
            }
            self.fcheck[i].last.next = self.cap.val() & self.pl.val();
            self.fcheck[i].deliver.next = self.capv_d.q.val();
            self.frame_error[i].next = self.fcheck[i].frame_error.val();
        }
        self.adc_sck.next = self.sck_reg.q.val();
        self.adc_conv.next = self.conv_reg.q.val();
        self.out_valid.next = self.valid_reg.q.val();
        self.out_ch0.next = self.ch0_reg.q.val();
        self.out_ch1.next = self.ch1_reg.q.val();
    }
}
