//! rust-hdl description of the position reference (maths, timing and sketch in the module
//! docs of [`crate::blocks::reference`]).
use super::ReferenceParams;
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// Homing on Z, the index latch and the preset: the core's position plus an offset.
#[derive(LogicBlock)]
pub struct PositionReference {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: offset 0, not referenced, nothing pending.
    pub rst: Signal<In, Bit>,
    /// The ADC's CONV (chip select) register: its assertion edge samples.
    pub conv: Signal<In, Bit>,
    /// The QEP decoder's filtered index Z.
    pub z: Signal<In, Bit>,
    /// Preset request, asynchronous (two synchronizer flops here): a rising edge loads the
    /// preset value at the next sample.
    pub preset: Signal<In, Bit>,
    /// The core's output strobe.
    pub in_valid: Signal<In, Bit>,
    /// The core's quadrant count, 0..Q-1.
    pub in_qc: Signal<In, Bits<32>>,
    /// The core's fine part.
    pub in_fine: Signal<In, Bits<32>>,
    /// The core's turn word (M bits).
    pub in_turns: Signal<In, Bits<32>>,
    /// Output strobe, one clock after `in_valid`.
    pub out_valid: Signal<Out, Bit>,
    /// Referenced quadrant count, 0..Q-1.
    pub out_qc: Signal<Out, Bits<32>>,
    /// Fine part, unchanged.
    pub out_fine: Signal<Out, Bits<32>>,
    /// Referenced turn word (M bits).
    pub out_turns: Signal<Out, Bits<32>>,
    /// The output sample is referenced (homed or preset).
    pub referenced: Signal<Out, Bit>,
    /// Not referenced, with `warn_until_referenced` (the top ORs it into the warning).
    pub warning: Signal<Out, Bit>,
    /// One clock: `index_qc` / `index_turns` latched an index.
    pub index_valid: Signal<Out, Bit>,
    /// Referenced quadrant count of the last index.
    pub index_qc: Signal<Out, Bits<32>>,
    /// Referenced turn word of the last index.
    pub index_turns: Signal<Out, Bits<32>>,
    /// The absolute start's request (`[reference] absolute`; unused without it): one
    /// clock, never with `in_valid`, to take the target `abs_t*` for the count `abs_b*` of
    /// an earlier sample (the one the encoder's word belongs to).
    pub abs_req: Signal<In, Bit>,
    /// The absolute target's quadrant count T_q.
    pub abs_tq: Signal<In, Bits<32>>,
    /// T_q - Q (qb + 1 bits two's complement).
    pub abs_tqm: Signal<In, Bits<32>>,
    /// T_q + Q.
    pub abs_tqp: Signal<In, Bits<32>>,
    /// The absolute target's turn word T_t.
    pub abs_tt: Signal<In, Bits<32>>,
    /// T_t - 1 (M bits).
    pub abs_ttm: Signal<In, Bits<32>>,
    /// T_t + 1 (M bits).
    pub abs_ttp: Signal<In, Bits<32>>,
    /// The quadrant count B_q of the word's sample.
    pub abs_bq: Signal<In, Bits<32>>,
    /// The turn word B_t of the word's sample.
    pub abs_bt: Signal<In, Bits<32>>,
    conv_prev: DFF<Bit>,
    /// Z at each conversion, newest in bit 0.
    zt: DFF<Bits<32>>,
    p1: DFF<Bit>,
    p2: DFF<Bit>,
    pp: DFF<Bit>,
    ppend: DFF<Bit>,
    pqual: DFF<Bit>,
    oq: DFF<Bits<32>>,
    /// oq - Q (qb + 1 bits): the wrap's sum s2 from a register, beside oq.
    oqm: DFF<Bits<32>>,
    ot: DFF<Bits<32>>,
    /// ot + 1 (M bits): the turns after a wrap from a register, beside ot.
    otp: DFF<Bits<32>>,
    refd: DFF<Bit>,
    /// A sample asked for a new offset (homing or preset): it is computed in the next clock
    /// from `ubq`, `ubt` and `usel`. Timing: the subtractions start at registers, not at the
    /// core's count (`core.counter.turns` -> `otp` was the top's slowest path).
    upd: DFF<Bit>,
    /// The request is a preset (else homing); loaded with every sample, used with `upd`.
    usel: DFF<Bit>,
    /// The last sample's quadrant count (the requesting sample's while `upd` is high).
    ubq: DFF<Bits<32>>,
    /// The last sample's turn word (likewise).
    ubt: DFF<Bits<32>>,
    /// With the absolute start (one each, or none): the requested target T and its
    /// neighbours (T_q, T_q - Q, T_q + Q, T_t, T_t - 1, T_t + 1), held from the request to
    /// the offset's clock, whichever source asked. Timing: the offset's subtractions start
    /// at registers, not at a select of three sources (the absolute block's `tq` ->
    /// `reference.otp` was the absolute top's slowest path).
    htq: Vec<DFF<Bits<32>>>,
    htqm: Vec<DFF<Bits<32>>>,
    htqp: Vec<DFF<Bits<32>>>,
    htt: Vec<DFF<Bits<32>>>,
    httm: Vec<DFF<Bits<32>>>,
    http: Vec<DFF<Bits<32>>>,
    ilatch: DFF<Bit>,
    /// The homing event, registered: the index latch takes T a clock later. Timing: keeps
    /// the sample's qualification off the index registers' enable (core.counter ->
    /// iturns was the register-map top's slowest path).
    ihome: DFF<Bit>,
    ov: DFF<Bit>,
    oqc: DFF<Bits<32>>,
    ofine: DFF<Bits<32>>,
    oturns: DFF<Bits<32>>,
    oref: DFF<Bit>,
    iv: DFF<Bit>,
    iqc: DFF<Bits<32>>,
    iturns: DFF<Bits<32>>,
    assert_edge: Signal<Local, Bit>,
    zs: Signal<Local, Bit>,
    pnow: Signal<Local, Bit>,
    bq: Signal<Local, Bits<32>>,
    bt: Signal<Local, Bits<32>>,
    qual: Signal<Local, Bit>,
    idx_event: Signal<Local, Bit>,
    s: Signal<Local, Bits<32>>,
    s2: Signal<Local, Bits<32>>,
    tq: Signal<Local, Bits<32>>,
    tqm: Signal<Local, Bits<32>>,
    tqp: Signal<Local, Bits<32>>,
    tt: Signal<Local, Bits<32>>,
    ttm: Signal<Local, Bits<32>>,
    ttp: Signal<Local, Bits<32>>,
    d1: Signal<Local, Bits<32>>,
    /// The CONV level that samples.
    act: Constant<Bit>,
    /// `warn_until_referenced`.
    warn: Constant<Bit>,
    /// 2^K: the tag of the sample leaving the core.
    kbit: Constant<Bits<32>>,
    /// Mask of `zt` (K + 1 bits).
    zmask: Constant<Bits<32>>,
    one: Constant<Bits<32>>,
    three: Constant<Bits<32>>,
    /// The gate quadrant.
    gate: Constant<Bits<32>>,
    /// Q.
    quads: Constant<Bits<32>>,
    /// Mask of the quadrant count (qb bits).
    qmask: Constant<Bits<32>>,
    /// Mask of the sums s, s2 and d (qb + 1 bits).
    wmask: Constant<Bits<32>>,
    /// Their sign bit.
    wsign: Constant<Bits<32>>,
    /// Mask of the turn word (M bits).
    tmask: Constant<Bits<32>>,
    /// -Q (qb + 1 bits): `oqm` after reset.
    oqm0: Constant<Bits<32>>,
    /// 1 (M bits): `otp` after reset.
    otp0: Constant<Bits<32>>,
    /// Index count: quadrant, quadrant - Q, quadrant + Q (qb + 1 bits), turn, turn - 1,
    /// turn + 1.
    iq: Constant<Bits<32>>,
    iqm: Constant<Bits<32>>,
    iqp: Constant<Bits<32>>,
    it: Constant<Bits<32>>,
    itm: Constant<Bits<32>>,
    itp: Constant<Bits<32>>,
    /// Preset count, the same six.
    pq: Constant<Bits<32>>,
    pqm: Constant<Bits<32>>,
    pqp: Constant<Bits<32>>,
    pt: Constant<Bits<32>>,
    ptm: Constant<Bits<32>>,
    ptp: Constant<Bits<32>>,
}

impl PositionReference {
    /// The block for `p`.
    pub fn new(p: &ReferenceParams) -> Self {
        let q = p.quadrants_per_turn();
        let qb = 64 - (q - 1).leading_zeros();
        let wm = mask(qb + 1);
        let tm = mask(p.turns_bits());
        let (iq, it) = p.index();
        let (pq, pt) = p.preset();
        Self {
            clk: Default::default(),
            rst: Default::default(),
            conv: Default::default(),
            z: Default::default(),
            preset: Default::default(),
            in_valid: Default::default(),
            in_qc: Default::default(),
            in_fine: Default::default(),
            in_turns: Default::default(),
            out_valid: Default::default(),
            out_qc: Default::default(),
            out_fine: Default::default(),
            out_turns: Default::default(),
            referenced: Default::default(),
            warning: Default::default(),
            index_valid: Default::default(),
            index_qc: Default::default(),
            index_turns: Default::default(),
            abs_req: Default::default(),
            abs_tq: Default::default(),
            abs_tqm: Default::default(),
            abs_tqp: Default::default(),
            abs_tt: Default::default(),
            abs_ttm: Default::default(),
            abs_ttp: Default::default(),
            abs_bq: Default::default(),
            abs_bt: Default::default(),
            conv_prev: Default::default(),
            zt: Default::default(),
            p1: Default::default(),
            p2: Default::default(),
            pp: Default::default(),
            ppend: Default::default(),
            pqual: Default::default(),
            oq: Default::default(),
            oqm: Default::default(),
            ot: Default::default(),
            otp: Default::default(),
            refd: Default::default(),
            upd: Default::default(),
            usel: Default::default(),
            ubq: Default::default(),
            ubt: Default::default(),
            htq: held(p),
            htqm: held(p),
            htqp: held(p),
            htt: held(p),
            httm: held(p),
            http: held(p),
            ilatch: Default::default(),
            ihome: Default::default(),
            ov: Default::default(),
            oqc: Default::default(),
            ofine: Default::default(),
            oturns: Default::default(),
            oref: Default::default(),
            iv: Default::default(),
            iqc: Default::default(),
            iturns: Default::default(),
            assert_edge: Default::default(),
            zs: Default::default(),
            pnow: Default::default(),
            bq: Default::default(),
            bt: Default::default(),
            qual: Default::default(),
            idx_event: Default::default(),
            s: Default::default(),
            s2: Default::default(),
            tq: Default::default(),
            tqm: Default::default(),
            tqp: Default::default(),
            tt: Default::default(),
            ttm: Default::default(),
            ttp: Default::default(),
            d1: Default::default(),
            act: Constant::new(p.conv_active_high()),
            warn: Constant::new(p.warn_until_referenced()),
            kbit: c32(1 << p.tag_shift()),
            zmask: c32(mask(p.tag_shift() + 1)),
            one: c32(1),
            three: c32(3),
            gate: c32(p.gate() as u64),
            quads: c32(q),
            qmask: c32(mask(qb)),
            wmask: c32(wm),
            wsign: c32(1 << qb),
            tmask: c32(tm),
            oqm0: c32(q.wrapping_neg() & wm),
            otp0: c32(1 & tm),
            iq: c32(iq),
            iqm: c32(iq.wrapping_sub(q) & wm),
            iqp: c32(iq + q),
            it: c32(it),
            itm: c32(it.wrapping_sub(1)),
            itp: c32(it + 1),
            pq: c32(pq),
            pqm: c32(pq.wrapping_sub(q) & wm),
            pqp: c32(pq + q),
            pt: c32(pt),
            ptm: c32(pt.wrapping_sub(1)),
            ptp: c32(pt + 1),
        }
    }
}

/// One target register with the absolute start (`[reference] absolute`), none without.
fn held(p: &ReferenceParams) -> Vec<DFF<Bits<32>>> {
    (0..usize::from(p.absolute()))
        .map(|_| Default::default())
        .collect()
}

impl Logic for PositionReference {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, conv_prev, zt, p1, p2, pp, ppend, pqual, oq, oqm, ot, otp, refd, upd, usel,
            ubq, ubt, ilatch, ihome, ov, oqc, ofine, oturns, oref, iv, iqc, iturns
        );
        for i in 0..self.htq.len() {
            self.htq[i].clock.next = self.clk.val();
            self.htqm[i].clock.next = self.clk.val();
            self.htqp[i].clock.next = self.clk.val();
            self.htt[i].clock.next = self.clk.val();
            self.httm[i].clock.next = self.clk.val();
            self.http[i].clock.next = self.clk.val();
            self.htq[i].d.next = self.htq[i].q.val();
            self.htqm[i].d.next = self.htqm[i].q.val();
            self.htqp[i].d.next = self.htqp[i].q.val();
            self.htt[i].d.next = self.htt[i].q.val();
            self.httm[i].d.next = self.httm[i].q.val();
            self.http[i].d.next = self.http[i].q.val();
        }
        // Synchronizers and edge registers (no reset).
        self.conv_prev.d.next = self.conv.val();
        self.p1.d.next = self.preset.val();
        self.p2.d.next = self.p1.q.val();
        self.pp.d.next = self.p2.q.val();
        // Z tag: Z shifts in at each conversion; bit K is the sample leaving the core.
        self.assert_edge.next =
            (self.conv.val() == self.act.val()) & (self.conv_prev.q.val() != self.act.val());
        if self.assert_edge.val() & self.z.val() {
            self.zt.d.next =
                ((self.zt.q.val() << self.one.val()) | self.one.val()) & self.zmask.val();
        } else if self.assert_edge.val() {
            self.zt.d.next = (self.zt.q.val() << self.one.val()) & self.zmask.val();
        }
        self.zs.next = (self.zt.q.val() & self.kbit.val()).any();
        self.pnow.next = self.ppend.q.val() | (self.p2.q.val() & !self.pp.q.val());
        // The sample: qualified, the index event, the output moved by the held offset.
        self.bq.next = self.in_qc.val() & self.qmask.val();
        self.bt.next = self.in_turns.val() & self.tmask.val();
        self.qual.next = self.zs.val() & ((self.bq.val() & self.three.val()) == self.gate.val());
        self.idx_event.next = self.qual.val() & !self.pqual.q.val();
        // With the absolute start an index never homes (the word references): it only
        // latches, once referenced.
        for _i in 0..self.htq.len() {
            if !self.refd.q.val() {
                self.idx_event.next = false;
            }
        }
        self.s.next = (self.bq.val() + self.oq.q.val()) & self.wmask.val();
        self.s2.next = (self.bq.val() + self.oqm.q.val()) & self.wmask.val();
        // The offset asked for in the clock before: T - B, T the preset or the index count.
        if self.usel.q.val() {
            self.tq.next = self.pq.val();
            self.tqm.next = self.pqm.val();
            self.tqp.next = self.pqp.val();
            self.tt.next = self.pt.val();
            self.ttm.next = self.ptm.val();
            self.ttp.next = self.ptp.val();
        } else {
            self.tq.next = self.iq.val();
            self.tqm.next = self.iqm.val();
            self.tqp.next = self.iqp.val();
            self.tt.next = self.it.val();
            self.ttm.next = self.itm.val();
            self.ttp.next = self.itp.val();
        }
        // The absolute start's request: T from the absolute block's registers.
        for i in 0..self.htq.len() {
            self.tq.next = self.htq[i].q.val();
            self.tqm.next = self.htqm[i].q.val();
            self.tqp.next = self.htqp[i].q.val();
            self.tt.next = self.htt[i].q.val();
            self.ttm.next = self.httm[i].q.val();
            self.ttp.next = self.http[i].q.val();
        }
        self.d1.next = (self.tq.val() - self.ubq.q.val()) & self.wmask.val();
        self.upd.d.next = false;
        if self.upd.q.val() {
            if (self.d1.val() & self.wsign.val()).any() {
                self.oq.d.next = (self.tqp.val() - self.ubq.q.val()) & self.wmask.val();
                self.oqm.d.next = self.d1.val();
                self.ot.d.next = (self.ttm.val() - self.ubt.q.val()) & self.tmask.val();
                self.otp.d.next = (self.tt.val() - self.ubt.q.val()) & self.tmask.val();
            } else {
                self.oq.d.next = self.d1.val();
                self.oqm.d.next = (self.tqm.val() - self.ubq.q.val()) & self.wmask.val();
                self.ot.d.next = (self.tt.val() - self.ubt.q.val()) & self.tmask.val();
                self.otp.d.next = (self.ttp.val() - self.ubt.q.val()) & self.tmask.val();
            }
            self.refd.d.next = true;
        }
        self.ov.d.next = self.in_valid.val();
        self.iv.d.next = false;
        self.ilatch.d.next = false;
        self.ihome.d.next = false;
        if self.ilatch.q.val() {
            self.iv.d.next = true;
            self.iqc.d.next = self.oqc.q.val();
            self.iturns.d.next = self.oturns.q.val();
        }
        if self.ihome.q.val() {
            self.iv.d.next = true;
            self.iqc.d.next = self.iq.val();
            self.iturns.d.next = self.it.val();
        }
        if self.in_valid.val() {
            self.pqual.d.next = self.qual.val();
            self.ppend.d.next = false;
            if (self.s2.val() & self.wsign.val()).any() {
                self.oqc.d.next = self.s.val();
                self.oturns.d.next = (self.bt.val() + self.ot.q.val()) & self.tmask.val();
            } else {
                self.oqc.d.next = self.s2.val();
                self.oturns.d.next = (self.bt.val() + self.otp.q.val()) & self.tmask.val();
            }
            self.ofine.d.next = self.in_fine.val();
            self.oref.d.next = self.refd.q.val();
            // Homing (the first index, not referenced) or a preset: the offset follows, from
            // this sample's count. Every sample loads the count (`upd` alone says whether it
            // asked): timing, the index event no longer enables those 60-odd flip-flops
            // (core.counter -> qual -> ubt's enable was the register-map top's slowest path).
            self.usel.d.next = self.pnow.val();
            self.ubq.d.next = self.bq.val();
            self.ubt.d.next = self.bt.val();
            if self.pnow.val() | (self.idx_event.val() & !self.refd.q.val() & !self.upd.q.val()) {
                self.upd.d.next = true;
                // With the absolute start T is held: the preset's or the index's.
                for i in 0..self.htq.len() {
                    if self.pnow.val() {
                        self.htq[i].d.next = self.pq.val();
                        self.htqm[i].d.next = self.pqm.val();
                        self.htqp[i].d.next = self.pqp.val();
                        self.htt[i].d.next = self.pt.val();
                        self.httm[i].d.next = self.ptm.val();
                        self.http[i].d.next = self.ptp.val();
                    } else {
                        self.htq[i].d.next = self.iq.val();
                        self.htqm[i].d.next = self.iqm.val();
                        self.htqp[i].d.next = self.iqp.val();
                        self.htt[i].d.next = self.it.val();
                        self.httm[i].d.next = self.itm.val();
                        self.http[i].d.next = self.itp.val();
                    }
                }
            }
            if self.idx_event.val() & !self.refd.q.val() & !self.upd.q.val() & !self.pnow.val() {
                self.ihome.d.next = true;
            } else if self.idx_event.val()
                & self.refd.q.val()
                & !self.upd.q.val()
                & !self.pnow.val()
            {
                self.ilatch.d.next = true;
            }
        } else {
            self.ppend.d.next = self.pnow.val();
        }
        // The absolute start: its B and T, in a clock without a sample.
        for i in 0..self.htq.len() {
            if self.abs_req.val() {
                self.upd.d.next = true;
                self.ubq.d.next = self.abs_bq.val() & self.qmask.val();
                self.ubt.d.next = self.abs_bt.val() & self.tmask.val();
                self.htq[i].d.next = self.abs_tq.val();
                self.htqm[i].d.next = self.abs_tqm.val();
                self.htqp[i].d.next = self.abs_tqp.val();
                self.htt[i].d.next = self.abs_tt.val();
                self.httm[i].d.next = self.abs_ttm.val();
                self.http[i].d.next = self.abs_ttp.val();
            }
        }
        if self.rst.val() {
            self.zt.d.next = 0.into();
            self.ppend.d.next = false;
            self.pqual.d.next = false;
            self.refd.d.next = false;
            self.upd.d.next = false;
            self.ilatch.d.next = false;
            self.ihome.d.next = false;
            self.oq.d.next = 0.into();
            self.oqm.d.next = self.oqm0.val();
            self.ot.d.next = 0.into();
            self.otp.d.next = self.otp0.val();
            self.ov.d.next = false;
            self.oqc.d.next = 0.into();
            self.ofine.d.next = 0.into();
            self.oturns.d.next = 0.into();
            self.oref.d.next = false;
            self.iv.d.next = false;
            self.iqc.d.next = 0.into();
            self.iturns.d.next = 0.into();
        }
        self.out_valid.next = self.ov.q.val();
        self.out_qc.next = self.oqc.q.val();
        self.out_fine.next = self.ofine.q.val();
        self.out_turns.next = self.oturns.q.val();
        self.referenced.next = self.oref.q.val();
        self.warning.next = !self.oref.q.val() & self.warn.val();
        self.index_valid.next = self.iv.q.val();
        self.index_qc.next = self.iqc.q.val();
        self.index_turns.next = self.iturns.q.val();
    }
}

impl crate::cosim::CosimBlock for PositionReference {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("conv", 1),
            Port::new("z", 1),
            Port::new("preset", 1),
            Port::new("in_valid", 1),
            Port::new("in_qc", 32),
            Port::new("in_fine", 32),
            Port::new("in_turns", 32),
            Port::new("abs_req", 1),
            Port::new("abs_tq", 32),
            Port::new("abs_tqm", 32),
            Port::new("abs_tqp", 32),
            Port::new("abs_tt", 32),
            Port::new("abs_ttm", 32),
            Port::new("abs_ttp", 32),
            Port::new("abs_bq", 32),
            Port::new("abs_bt", 32),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("out_valid", 1),
            Port::new("out_qc", 32),
            Port::new("out_fine", 32),
            Port::new("out_turns", 32),
            Port::new("referenced", 1),
            Port::new("warning", 1),
            Port::new("index_valid", 1),
            Port::new("index_qc", 32),
            Port::new("index_turns", 32),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.conv.next = r[1] != 0;
        self.z.next = r[2] != 0;
        self.preset.next = r[3] != 0;
        self.in_valid.next = r[4] != 0;
        self.in_qc.next = Bits::<32>::from(r[5]);
        self.in_fine.next = Bits::<32>::from(r[6]);
        self.in_turns.next = Bits::<32>::from(r[7]);
        self.abs_req.next = r[8] != 0;
        self.abs_tq.next = Bits::<32>::from(r[9]);
        self.abs_tqm.next = Bits::<32>::from(r[10]);
        self.abs_tqp.next = Bits::<32>::from(r[11]);
        self.abs_tt.next = Bits::<32>::from(r[12]);
        self.abs_ttm.next = Bits::<32>::from(r[13]);
        self.abs_ttp.next = Bits::<32>::from(r[14]);
        self.abs_bq.next = Bits::<32>::from(r[15]);
        self.abs_bt.next = Bits::<32>::from(r[16]);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.out_valid.val() as u64,
            self.out_qc.val().to_u64(),
            self.out_fine.val().to_u64(),
            self.out_turns.val().to_u64(),
            self.referenced.val() as u64,
            self.warning.val() as u64,
            self.index_valid.val() as u64,
            self.index_qc.val().to_u64(),
            self.index_turns.val().to_u64(),
        ]
    }
}

impl crate::cosim::step::Clocked for PositionReference {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}
