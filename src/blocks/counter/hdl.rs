//! rust-hdl description of the combiner and the quadrant counter.
use crate::blocks::{c32, fill, mask};
use crate::config::Derived;
use rust_hdl::prelude::*;

/// Rounds the CORDIC angle, assembles the electrical angle p and tests the magnitude.
#[derive(LogicBlock)]
pub struct Combiner {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high (clears the valid bit).
    pub rst: Signal<In, Bit>,
    /// Final angle z (ZW-bit).
    pub z_in: Signal<In, Bits<32>>,
    /// Final x, the magnitude times K_N (W-bit).
    pub x_in: Signal<In, Bits<32>>,
    /// Quadrant of the sample.
    pub q_in: Signal<In, Bits<2>>,
    /// Valid bit of the sample.
    pub v_in: Signal<In, Bit>,
    /// Registered electrical angle p (F+2 bits).
    pub p: Signal<Out, Bits<32>>,
    /// Registered magnitude test.
    pub mag_ok: Signal<Out, Bit>,
    /// Registered valid bit.
    pub v: Signal<Out, Bit>,
    p_reg: DFF<Bits<32>>,
    ok_reg: DFF<Bit>,
    v_reg: DFF<Bit>,
    zr: Signal<Local, Bits<32>>,
    /// 2^(Gz-1): rounding half.
    zhalf: Constant<Bits<32>>,
    /// Mask of ZW bits.
    zmask: Constant<Bits<32>>,
    /// Gz: shift from z units to fine LSB.
    zshift: Constant<Bits<32>>,
    /// F: shift of the quadrant into p.
    fshift: Constant<Bits<32>>,
    /// Mask of F+2 bits.
    pmask: Constant<Bits<32>>,
    /// Magnitude threshold in x units.
    minmag: Constant<Bits<32>>,
}

impl Combiner {
    /// Combiner for the derived parameters.
    pub fn new(d: &Derived) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            z_in: Default::default(),
            x_in: Default::default(),
            q_in: Default::default(),
            v_in: Default::default(),
            p: Default::default(),
            mag_ok: Default::default(),
            v: Default::default(),
            p_reg: Default::default(),
            ok_reg: Default::default(),
            v_reg: Default::default(),
            zr: Default::default(),
            zhalf: c32(1 << (d.z_guard - 1)),
            zmask: c32(mask(d.z_width)),
            zshift: c32(d.z_guard as u64),
            fshift: c32(d.fine_bits as u64),
            pmask: c32(mask(d.fine_bits + 2)),
            minmag: c32(d.min_magnitude.min(mask(32))),
        }
    }
}

impl Logic for Combiner {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, p_reg, ok_reg, v_reg);
        self.zr.next = (self.z_in.val() + self.zhalf.val()) & self.zmask.val();
        self.p_reg.d.next = ((self.zr.val() >> self.zshift.val())
            + (bit_cast::<32, 2>(self.q_in.val()) << self.fshift.val()))
            & self.pmask.val();
        self.ok_reg.d.next = self.x_in.val() >= self.minmag.val();
        self.v_reg.d.next = self.v_in.val() & !self.rst.val();
        self.p.next = self.p_reg.q.val();
        self.mag_ok.next = self.ok_reg.q.val();
        self.v.next = self.v_reg.q.val();
    }
}

/// Unwraps the electrical angle into a single-turn position and a turn count.
#[derive(LogicBlock)]
pub struct QuadrantCounter {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: position, turns and flags to 0.
    pub rst: Signal<In, Bit>,
    /// Electrical angle p of the sample (F+2 bits).
    pub p_in: Signal<In, Bits<32>>,
    /// Magnitude test of the sample.
    pub ok_in: Signal<In, Bit>,
    /// Valid bit of the sample.
    pub v_in: Signal<In, Bit>,
    /// Resynchronisation request (one-cycle pulse); applied at the next accepted sample.
    pub load: Signal<In, Bit>,
    /// Coarse count to resynchronise to (0..4PPR-1).
    pub load_qc: Signal<In, Bits<32>>,
    /// Turn count to resynchronise to (M bits).
    pub load_turns: Signal<In, Bits<32>>,
    /// Coarse quadrant count 0..4PPR-1.
    pub qc: Signal<Out, Bits<32>>,
    /// Fine part 0..2^F-1.
    pub fine: Signal<Out, Bits<32>>,
    /// Turn count (M bits, two's complement).
    pub turns: Signal<Out, Bits<32>>,
    /// Output strobe, one cycle per sample.
    pub valid: Signal<Out, Bit>,
    /// Sample rejected (no magnitude).
    pub error: Signal<Out, Bit>,
    /// Step near the 2-quadrant ambiguity.
    pub warning: Signal<Out, Bit>,
    init_reg: DFF<Bit>,
    pprev_reg: DFF<Bits<32>>,
    qc_reg: DFF<Bits<32>>,
    fine_reg: DFF<Bits<32>>,
    turns_reg: DFF<Bits<32>>,
    valid_reg: DFF<Bit>,
    error_reg: DFF<Bit>,
    warning_reg: DFF<Bit>,
    pending_reg: DFF<Bit>,
    lqc_reg: DFF<Bits<32>>,
    lturns_reg: DFF<Bits<32>>,
    base_qc: Signal<Local, Bits<32>>,
    base_turns: Signal<Local, Bits<32>>,
    dq: Signal<Local, Bits<32>>,
    delta: Signal<Local, Bits<32>>,
    total: Signal<Local, Bits<32>>,
    carry: Signal<Local, Bits<32>>,
    qn: Signal<Local, Bits<32>>,
    /// F.
    fshift: Constant<Bits<32>>,
    /// Mask of F bits.
    fmask: Constant<Bits<32>>,
    /// Mask of F+2 bits.
    pmask: Constant<Bits<32>>,
    /// Sign bit of an (F+2)-bit word.
    psign: Constant<Bits<32>>,
    /// Bits F+2..31: sign extension of a negative delta.
    psext: Constant<Bits<32>>,
    /// Bit 31: sign of a 32-bit word.
    sign32: Constant<Bits<32>>,
    /// Fill for an arithmetic shift by F of a 32-bit word.
    cfill: Constant<Bits<32>>,
    /// Warning threshold (1.75 quadrants).
    wlo: Constant<Bits<32>>,
    /// 2^(F+2) minus the warning threshold.
    whi: Constant<Bits<32>>,
    /// 4 PPR: quadrants per turn.
    qturn: Constant<Bits<32>>,
    /// Mask of M turn bits.
    tmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Three (also the 2-bit mask).
    three: Constant<Bits<32>>,
    /// Minus one (32-bit two's complement).
    minus_one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl QuadrantCounter {
    /// Counter for the derived parameters.
    pub fn new(d: &Derived) -> Self {
        let f = d.fine_bits;
        Self {
            clk: Default::default(),
            rst: Default::default(),
            p_in: Default::default(),
            ok_in: Default::default(),
            v_in: Default::default(),
            load: Default::default(),
            load_qc: Default::default(),
            load_turns: Default::default(),
            qc: Default::default(),
            fine: Default::default(),
            turns: Default::default(),
            valid: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            init_reg: Default::default(),
            pprev_reg: Default::default(),
            qc_reg: Default::default(),
            fine_reg: Default::default(),
            turns_reg: Default::default(),
            valid_reg: Default::default(),
            error_reg: Default::default(),
            warning_reg: Default::default(),
            pending_reg: Default::default(),
            lqc_reg: Default::default(),
            lturns_reg: Default::default(),
            base_qc: Default::default(),
            base_turns: Default::default(),
            dq: Default::default(),
            delta: Default::default(),
            total: Default::default(),
            carry: Default::default(),
            qn: Default::default(),
            fshift: c32(f as u64),
            fmask: c32(mask(f)),
            pmask: c32(mask(f + 2)),
            psign: c32(1 << (f + 1)),
            psext: c32(fill(32, 30 - f)),
            sign32: c32(1 << 31),
            cfill: c32(fill(32, f)),
            wlo: c32(d.warn_step),
            whi: c32((1 << (f + 2)) - d.warn_step),
            qturn: c32(d.quadrants_per_turn),
            tmask: c32(mask(d.multiturn_bits)),
            one: c32(1),
            three: c32(3),
            minus_one: c32(mask(32)),
            zero: c32(0),
        }
    }
}

impl Logic for QuadrantCounter {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self,
            clk,
            init_reg,
            pprev_reg,
            qc_reg,
            fine_reg,
            turns_reg,
            valid_reg,
            error_reg,
            warning_reg,
            pending_reg,
            lqc_reg,
            lturns_reg
        );
        self.delta.next = (self.p_in.val() - self.pprev_reg.q.val()) & self.pmask.val();
        if (self.delta.val() & self.psign.val()).any() {
            self.total.next = self.fine_reg.q.val() + (self.delta.val() | self.psext.val());
        } else {
            self.total.next = self.fine_reg.q.val() + self.delta.val();
        }
        self.carry.next = self.total.val() >> self.fshift.val();
        if (self.total.val() & self.sign32.val()).any() {
            self.carry.next = self.carry.val() | self.cfill.val();
        }
        // Base and step: the running count and the unwrapped carry, or, when a
        // resynchronisation is pending, the latched count and the nearest step (+0, +1,
        // +2, -1) to the sample's own quadrant.
        self.base_qc.next = self.qc_reg.q.val();
        self.base_turns.next = self.turns_reg.q.val();
        self.dq.next =
            ((self.p_in.val() >> self.fshift.val()) - self.lqc_reg.q.val()) & self.three.val();
        if self.pending_reg.q.val() {
            self.base_qc.next = self.lqc_reg.q.val();
            self.base_turns.next = self.lturns_reg.q.val();
            self.carry.next = self.dq.val();
            if self.dq.val() == self.three.val() {
                self.carry.next = self.minus_one.val();
            }
        }
        self.qn.next = self.base_qc.val() + self.carry.val();
        self.valid_reg.d.next = self.v_in.val() & !self.rst.val();
        if self.load.val() {
            self.pending_reg.d.next = true;
            self.lqc_reg.d.next = self.load_qc.val();
            self.lturns_reg.d.next = self.load_turns.val();
        }
        if self.rst.val() {
            self.init_reg.d.next = false;
            self.pprev_reg.d.next = self.zero.val();
            self.qc_reg.d.next = self.zero.val();
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
                self.init_reg.d.next = true;
                self.qc_reg.d.next = self.p_in.val() >> self.fshift.val();
                self.fine_reg.d.next = self.p_in.val() & self.fmask.val();
                self.turns_reg.d.next = self.zero.val();
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
                    self.warning_reg.d.next =
                        (self.delta.val() >= self.wlo.val()) & (self.delta.val() <= self.whi.val());
                }
                if (self.qn.val() & self.sign32.val()).any() {
                    self.qc_reg.d.next = self.qn.val() + self.qturn.val();
                    self.turns_reg.d.next =
                        (self.base_turns.val() - self.one.val()) & self.tmask.val();
                } else if self.qn.val() >= self.qturn.val() {
                    self.qc_reg.d.next = self.qn.val() - self.qturn.val();
                    self.turns_reg.d.next =
                        (self.base_turns.val() + self.one.val()) & self.tmask.val();
                } else {
                    self.qc_reg.d.next = self.qn.val();
                    self.turns_reg.d.next = self.base_turns.val() & self.tmask.val();
                }
                self.fine_reg.d.next = self.p_in.val() & self.fmask.val();
                self.pprev_reg.d.next = self.p_in.val();
            }
        }
        self.qc.next = self.qc_reg.q.val();
        self.fine.next = self.fine_reg.q.val();
        self.turns.next = self.turns_reg.q.val();
        self.valid.next = self.valid_reg.q.val();
        self.error.next = self.error_reg.q.val();
        self.warning.next = self.warning_reg.q.val();
    }
}
