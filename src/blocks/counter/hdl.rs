//! rust-hdl description of the combiner and the quadrant counter.
use crate::blocks::params::{Architecture, Derived};
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

mod update;

/// Assembles the electrical angle p, tests the magnitude and takes the step to the last
/// accepted sample (the counter's first carry chain, moved here so that each register
/// stage holds one).
///
/// The rounding half 2^(Gz-1) and the quadrant q 2^(F+Gz) are already in z (the CORDIC
/// starts its angle there instead of at 0: the same value modulo 2^ZW), so p is z >> Gz
/// with no adder. `plast` is p of the last sample this stage passed with `mag_ok`: the
/// counter's p_prev one clock early (see the module docs).
#[derive(LogicBlock)]
pub struct Combiner {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high (clears the valid bit).
    pub rst: Signal<In, Bit>,
    /// Final angle z (ZW-bit), started at 2^(Gz-1) + q 2^(F+Gz).
    pub z_in: Signal<In, Bits<32>>,
    /// Final x, the magnitude times K_N (W-bit).
    pub x_in: Signal<In, Bits<32>>,
    /// Valid bit of the sample.
    pub v_in: Signal<In, Bit>,
    /// Registered electrical angle p (F+2 bits).
    pub p: Signal<Out, Bits<32>>,
    /// Registered magnitude test.
    pub mag_ok: Signal<Out, Bit>,
    /// Registered valid bit.
    pub v: Signal<Out, Bit>,
    /// Registered: the step from the last accepted sample crosses quadrant 3 -> 0 forwards.
    pub up: Signal<Out, Bit>,
    /// Registered: the step crosses quadrant 0 -> 3 backwards.
    pub down: Signal<Out, Bit>,
    /// Registered: up or down (the low bit of the counter's period step, so that the
    /// step's bits come straight from registers into the counter's adder).
    pub step: Signal<Out, Bit>,
    /// Registered: delta >> (F-2), the step in quarter quadrants (4 bits; the counter's
    /// warning compares it).
    pub wq: Signal<Out, Bits<32>>,
    /// Registered: the low F-2 bits of delta are zero.
    pub wz: Signal<Out, Bit>,
    /// Not registered: the quadrant of p before its register (2 bits), so the counter can
    /// decode a load's step a clock ahead.
    pub q_next: Signal<Out, Bits<32>>,
    /// Registered: valid and mag_ok (the sample is accepted).
    pub acc: Signal<Out, Bit>,
    /// `acc`'s register: valid and mag_ok from the compare's chain in one flip-flop, so the
    /// counter's turn selection starts from a register.
    acc_reg: DFF<Bit>,
    p_reg: DFF<Bits<32>>,
    /// `mag_ok`'s register.
    ok_reg: DFF<Bit>,
    /// `v`'s register.
    v_reg: DFF<Bit>,
    plast_reg: DFF<Bits<32>>,
    /// `up`'s register: the step's direction decoded here (one LUT after p - plast), so the
    /// counter's u adder and turn selection start from registers.
    up_reg: DFF<Bit>,
    /// `down`'s register, like `up_reg`.
    down_reg: DFF<Bit>,
    /// `step`'s register (up or down): the low bit of the counter's u step from a register.
    step_reg: DFF<Bit>,
    wq_reg: DFF<Bits<32>>,
    /// `wz`'s register: the low F-2 bits of delta are zero, for the warning's threshold.
    wz_reg: DFF<Bit>,
    /// p of this sample.
    pn: Signal<Local, Bits<32>>,
    /// The magnitude test of this sample.
    okn: Signal<Local, Bit>,
    /// x_in with bit 31 set when the sample is valid (x is at most 31 bits wide).
    xv: Signal<Local, Bits<32>>,
    /// The sample is valid and passes the magnitude test: one compare of xv against
    /// 2^31 + minmag, so the carry chain's output drives plast's enable with no LUT after it.
    okv: Signal<Local, Bit>,
    /// p - plast, 32-bit.
    dfull: Signal<Local, Bits<32>>,
    /// delta = (p - plast) mod 2^(F+2).
    delta: Signal<Local, Bits<32>>,
    /// p < plast (the borrow, bit F+2 of dfull).
    lt: Signal<Local, Bit>,
    /// The step is backwards (delta negative).
    back: Signal<Local, Bit>,
    /// Quadrant of p.
    qnew: Signal<Local, Bits<32>>,
    /// Gz: shift from z units to fine LSB.
    zshift: Constant<Bits<32>>,
    /// F: shift of the quadrant out of p.
    fshift: Constant<Bits<32>>,
    /// Mask of F+2 bits.
    pmask: Constant<Bits<32>>,
    /// Sign bit of an (F+2)-bit word.
    psign: Constant<Bits<32>>,
    /// Bit F+2 (the borrow of p - plast).
    pborrow: Constant<Bits<32>>,
    /// Three (the 2-bit mask).
    three: Constant<Bits<32>>,
    /// F-2: the warning thresholds are multiples of 2^(F-2).
    wshift: Constant<Bits<32>>,
    /// Mask of F-2 bits.
    wmask: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
    /// Magnitude threshold in x units.
    minmag: Constant<Bits<32>>,
    /// 2^31 + the magnitude threshold (clamped to 31 bits: x never reaches 2^31).
    minmag_v: Constant<Bits<32>>,
    /// 2^31: the valid bit of xv.
    vbit: Constant<Bits<32>>,
}

impl Combiner {
    /// Combiner for the derived parameters.
    pub fn new(d: &Derived) -> Self {
        let f = d.fine_bits;
        Self {
            clk: Default::default(),
            rst: Default::default(),
            z_in: Default::default(),
            x_in: Default::default(),
            v_in: Default::default(),
            p: Default::default(),
            mag_ok: Default::default(),
            v: Default::default(),
            up: Default::default(),
            down: Default::default(),
            step: Default::default(),
            wq: Default::default(),
            wz: Default::default(),
            q_next: Default::default(),
            acc: Default::default(),
            acc_reg: Default::default(),
            p_reg: Default::default(),
            ok_reg: Default::default(),
            v_reg: Default::default(),
            plast_reg: Default::default(),
            up_reg: Default::default(),
            down_reg: Default::default(),
            step_reg: Default::default(),
            wq_reg: Default::default(),
            wz_reg: Default::default(),
            pn: Default::default(),
            okn: Default::default(),
            xv: Default::default(),
            okv: Default::default(),
            dfull: Default::default(),
            delta: Default::default(),
            lt: Default::default(),
            back: Default::default(),
            qnew: Default::default(),
            zshift: c32(d.z_guard as u64),
            fshift: c32(f as u64),
            pmask: c32(mask(f + 2)),
            psign: c32(1 << (f + 1)),
            pborrow: c32(1 << (f + 2)),
            three: c32(3),
            wshift: c32((f - 2) as u64),
            wmask: c32(mask(f - 2)),
            zero: c32(0),
            minmag: c32(d.min_magnitude.min(mask(32))),
            minmag_v: c32((1 << 31) | d.min_magnitude.min(mask(31))),
            vbit: c32(1 << 31),
        }
    }
}

/// The initial angle of the CORDIC for a sample in quadrant q: 2^(Gz-1) + q 2^(F+Gz), the
/// combiner's rounding half and the quadrant (see [`Combiner`]), as the constants
/// (half, shift of q).
pub fn z_start(d: &Derived) -> (u64, u64) {
    (1 << (d.z_guard - 1), (d.fine_bits + d.z_guard) as u64)
}

impl Logic for Combiner {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, p_reg, ok_reg, v_reg, plast_reg, up_reg, down_reg, step_reg, wq_reg, wz_reg,
            acc_reg
        );
        self.pn.next = (self.z_in.val() >> self.zshift.val()) & self.pmask.val();
        self.okn.next = self.x_in.val() >= self.minmag.val();
        self.p_reg.d.next = self.pn.val();
        self.ok_reg.d.next = self.okn.val();
        self.v_reg.d.next = self.v_in.val() & !self.rst.val();
        self.xv.next = self.x_in.val();
        if self.v_in.val() & !self.rst.val() {
            self.xv.next = self.x_in.val() | self.vbit.val();
        }
        self.okv.next = self.xv.val() >= self.minmag_v.val();
        if self.okv.val() {
            self.plast_reg.d.next = self.pn.val();
        }
        // The step to the last accepted sample, as the counter takes it (module docs).
        // One subtractor of F+3 bits: bit F+1 of p - plast is delta's sign (back), bit F+2
        // its borrow (p < plast). For p, plast in [0, 2^(F+2)): a forward step (delta <
        // half a turn) has p < plast exactly when it crosses 3 -> 0 (then plast - p is over
        // two quadrants, so q < qlast; and p >= plast gives q >= qlast), and a backward
        // step has p > plast exactly when it crosses 0 -> 3 (p - plast is at least two
        // quadrants). So up, down and step are one LUT after the chain.
        self.dfull.next = self.pn.val() - self.plast_reg.q.val();
        self.delta.next = self.dfull.val() & self.pmask.val();
        self.back.next = (self.dfull.val() & self.psign.val()).any();
        self.lt.next = (self.dfull.val() & self.pborrow.val()).any();
        self.qnew.next = (self.pn.val() >> self.fshift.val()) & self.three.val();
        self.up_reg.d.next = !self.back.val() & self.lt.val();
        self.down_reg.d.next = self.back.val() & !self.lt.val();
        self.step_reg.d.next = self.back.val() ^ self.lt.val();
        // The sample is accepted (valid and mag_ok) in one register, from the compare's
        // chain, so the counter's turn selection starts from it.
        self.acc_reg.d.next = self.okv.val();
        self.wq_reg.d.next = self.delta.val() >> self.wshift.val();
        // (pn - plast) mod 2^(F-2) is zero exactly when the low F-2 bits agree: an
        // equality test, off the subtractor's carry chain.
        self.wz_reg.d.next =
            ((self.pn.val() ^ self.plast_reg.q.val()) & self.wmask.val()) == self.zero.val();
        self.p.next = self.p_reg.q.val();
        self.mag_ok.next = self.ok_reg.q.val();
        self.v.next = self.v_reg.q.val();
        self.up.next = self.up_reg.q.val();
        self.down.next = self.down_reg.q.val();
        self.step.next = self.step_reg.q.val();
        self.wq.next = self.wq_reg.q.val();
        self.wz.next = self.wz_reg.q.val();
        self.q_next.next = self.qnew.val();
        self.acc.next = self.acc_reg.q.val();
    }
}

/// Unwraps the electrical angle into a single-turn position and a turn count.
///
/// The coarse count is kept as qc = 4 u + q, where q = p_prev >> F is the quadrant of the
/// last accepted sample (so only u, the signal period within the turn, has its own
/// register) and the carry of the module docs reduces to a period step of -1, 0 or +1
/// from 2-bit quadrant compares (see the module docs).
#[derive(LogicBlock)]
pub struct QuadrantCounter {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: position, turns and flags to 0.
    pub rst: Signal<In, Bit>,
    /// Electrical angle p of the sample (F+2 bits).
    pub p_in: Signal<In, Bits<32>>,
    /// The quadrant of the next clock's p_in (2 bits; the combiner's `q_next`).
    pub q_next: Signal<In, Bits<32>>,
    /// v_in and ok_in (the combiner's `acc`).
    pub acc_in: Signal<In, Bit>,
    /// Magnitude test of the sample.
    pub ok_in: Signal<In, Bit>,
    /// Valid bit of the sample.
    pub v_in: Signal<In, Bit>,
    /// The step from the last accepted sample crosses quadrant 3 -> 0 forwards (combiner).
    pub up_in: Signal<In, Bit>,
    /// The step crosses quadrant 0 -> 3 backwards (combiner).
    pub down_in: Signal<In, Bit>,
    /// up_in or down_in (combiner).
    pub step_in: Signal<In, Bit>,
    /// The step delta >> (F-2) in quarter quadrants (combiner, 4 bits).
    pub wq_in: Signal<In, Bits<32>>,
    /// The low F-2 bits of the step are zero (combiner).
    pub wz_in: Signal<In, Bit>,
    /// Resynchronisation request (one-cycle pulse); applied at the next accepted sample.
    pub load: Signal<In, Bit>,
    /// Coarse count to resynchronise to; must be within 0..4PPR-1 (only its low
    /// quadrant_bits are used).
    pub load_qc: Signal<In, Bits<32>>,
    /// Turn count to resynchronise to (only its low M bits are used).
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
    /// The first accepted sample since reset has loaded the count.
    init_reg: DFF<Bit>,
    pprev_reg: DFF<Bits<32>>,
    /// Signal period within the turn, u = qc >> 2 (quadrant_bits - 2 bits).
    u_reg: DFF<Bits<32>>,
    fine_reg: DFF<Bits<32>>,
    turns_reg: DFF<Bits<32>>,
    /// `valid`'s register.
    valid_reg: DFF<Bit>,
    /// `error`'s register.
    error_reg: DFF<Bit>,
    /// `warning`'s register.
    warning_reg: DFF<Bit>,
    /// A load is latched (`lqc_reg`, `lturns_reg`) and waits for the next accepted sample.
    pending_reg: DFF<Bit>,
    lqc_reg: DFF<Bits<32>>,
    lturns_reg: DFF<Bits<32>>,
    /// turns_reg + 1 (M bits), taken at every clock: one clock stale after the turns move.
    tinc_reg: DFF<Bits<32>>,
    /// turns_reg - 1 (M bits), taken at every clock like `tinc_reg`.
    tdec_reg: DFF<Bits<32>>,
    /// The turns + 1 to use instead of `tinc_reg` in the clock after an update (`ovi_reg`).
    tio_reg: DFF<Bits<32>>,
    /// The turns - 1 to use instead of `tdec_reg` in the clock after an update (`ovd_reg`).
    tdo_reg: DFF<Bits<32>>,
    /// The last clock's update left `tinc_reg` stale where the next sample may read it.
    ovi_reg: DFF<Bit>,
    /// The last clock's update left `tdec_reg` stale where the next sample may read it.
    ovd_reg: DFF<Bit>,
    /// The latched turn count plus and minus one (M bits), taken at the load, so a load's
    /// step adds no carry chain after `pending`.
    ltinc_reg: DFF<Bits<32>>,
    ltdec_reg: DFF<Bits<32>>,
    /// The latched count's period is PPR - 1 (a forward step from it wraps), taken at the
    /// load with the count.
    llast_reg: DFF<Bit>,
    /// The latched count's period is 0 (a backward step from it wraps).
    lzero_reg: DFF<Bit>,
    /// The latched count's period is PPR - 2 (a forward step from it ends on PPR - 1).
    lpen_reg: DFF<Bit>,
    /// The latched count's period is 1 (a backward step from it ends on 0).
    lone_reg: DFF<Bit>,
    /// A load's step from the latched count to this clock's sample crosses quadrant 3 -> 0
    /// forwards, decoded a clock ahead from the count being latched and `q_next`.
    ul_reg: DFF<Bit>,
    /// A load's step crosses quadrant 0 -> 3 backwards, decoded like `ul_reg`.
    dl_reg: DFF<Bit>,
    /// A load's step wraps the turn forwards (`ul_reg` and the latched period is PPR - 1),
    /// decoded like `ul_reg`.
    uwl_reg: DFF<Bit>,
    /// A load's step wraps the turn backwards (`dl_reg` and the latched period is 0).
    dwl_reg: DFF<Bit>,
    /// A load's step wraps the turn forwards (`uwl_reg`, or decoded in this clock when not
    /// `flat`).
    uwl: Signal<Local, Bit>,
    /// A load's step wraps the turn backwards (`dwl_reg`, or decoded in this clock).
    dwl: Signal<Local, Bit>,
    /// Quadrant of the latched count (2 bits; the decode in the clock when not `flat`).
    qlat: Signal<Local, Bits<32>>,
    /// Quadrant of this clock's sample, p_in >> F (2 bits; likewise).
    qnow: Signal<Local, Bits<32>>,
    /// The running count's step wraps the turn forwards (acc_in, up_in at u = PPR - 1).
    rwu: Signal<Local, Bit>,
    /// The running count's step wraps the turn backwards (acc_in, down_in at u = 0).
    rwd: Signal<Local, Bit>,
    /// Iterative (not `flat`): the turn count the selected step starts from (turns, or the
    /// latched count when a load is pending).
    base_turns: Signal<Local, Bits<32>>,
    /// The turn count after a load's step (latched count, + 1 or - 1).
    tsel_p: Signal<Local, Bits<32>>,
    /// The turn count after the running count's step (turns, + 1 or - 1).
    tsel_r: Signal<Local, Bits<32>>,
    /// u = PPR - 1, registered with u (a forward step from it wraps), so the wrap comes
    /// from flags instead of the end of the u adder's carry chain.
    ulast_reg: DFF<Bit>,
    /// u != 0, registered with u (a backward step from u = 0 wraps); stored inverted so
    /// that the power-up value 0 agrees with u = 0.
    unz_reg: DFF<Bit>,
    /// u = PPR - 2, u = PPR - 1, u = 0, u = 1: the compares the flags' next values are
    /// chosen from, on the register u (beside the adder, not after it).
    upen: Signal<Local, Bit>,
    ulst: Signal<Local, Bit>,
    uzer: Signal<Local, Bit>,
    uone: Signal<Local, Bit>,
    /// The next u is PPR - 1 / is 0 (from the compares and the step's direction).
    nlast: Signal<Local, Bit>,
    nzero: Signal<Local, Bit>,
    /// Quadrant of the next clock's sample (`q_next`, 2 bits).
    qnew: Signal<Local, Bits<32>>,
    /// Quadrant of the count latched for the next clock (2 bits), where a load's step starts.
    base_q: Signal<Local, Bits<32>>,
    /// The latched count's period (quadrant_bits - 2 bits), where a load's step starts.
    base_u: Signal<Local, Bits<32>>,
    /// The step crosses into the next period (carry from quadrant 3 to 0).
    up: Signal<Local, Bit>,
    /// The step crosses into the previous period (carry from quadrant 0 to 3).
    down: Signal<Local, Bit>,
    /// +1 (up), -1 (down) or 0: the addend of the running period counter.
    ustep: Signal<Local, Bits<32>>,
    /// A load's step crosses into the next period (`ul_reg`).
    up_l: Signal<Local, Bit>,
    /// A load's step crosses into the previous period (`dl_reg`).
    down_l: Signal<Local, Bit>,
    /// +1, -1 or 0: the addend of a load's period.
    ustep_l: Signal<Local, Bits<32>>,
    /// base_u + ustep_l modulo 2^(quadrant_bits - 1), as usum for a load.
    usum_l: Signal<Local, Bits<32>>,
    /// A load's step leaves the turn (from the flags taken at the load: no adder).
    wrap_l: Signal<Local, Bit>,
    /// u + ustep modulo 2^(quadrant_bits - 1): bit quadrant_bits - 2 is set when u + ustep
    /// leaves 0..2^(quadrant_bits - 2) - 1 (u = 0 down, u all ones up).
    usum: Signal<Local, Bits<32>>,
    /// The next u without the wrap (quadrant_bits - 2 bits).
    un: Signal<Local, Bits<32>>,
    /// The step leaves the turn (u = PPR-1 up, or u = 0 down).
    wrap: Signal<Local, Bit>,
    /// The turn count plus one (`tinc_reg`, or `tio_reg` in the clock after an update).
    tinc: Signal<Local, Bits<32>>,
    /// The turn count minus one (`tdec_reg`, or `tdo_reg` in the clock after an update).
    tdec: Signal<Local, Bits<32>>,
    /// F.
    fshift: Constant<Bits<32>>,
    /// Mask of F bits.
    fmask: Constant<Bits<32>>,
    /// Warning threshold (1.75 quadrants) in 2^(F-2) LSB (7).
    wlo: Constant<Bits<32>>,
    /// 2^(F+2) minus the warning threshold, in 2^(F-2) LSB (9).
    whi: Constant<Bits<32>>,
    /// Two: shift from qc to u.
    two: Constant<Bits<32>>,
    /// Mask of the quadrant_bits - 2 bits of u.
    umask: Constant<Bits<32>>,
    /// Mask of quadrant_bits - 1 bits: the width of usum.
    usmask: Constant<Bits<32>>,
    /// PPR is a power of two: u wraps by itself (PPR - 1 is all ones).
    pow2: Constant<Bit>,
    /// PPR - 1: the last period of the turn.
    ulast: Constant<Bits<32>>,
    /// PPR - 2 modulo 2^(quadrant_bits - 2) (u's width): the period before the last.
    upenult: Constant<Bits<32>>,
    /// One modulo 2^(quadrant_bits - 2).
    uone_c: Constant<Bits<32>>,
    /// PPR = 1: every step wraps (u has no bits; the flags are not used).
    ppr1: Constant<Bit>,
    /// The unrolled architecture's timing form: the turns' + 1 and - 1 from registers
    /// (`tinc_reg`, `tdec_reg`, with the stale-value fix), a load's step decoded a clock
    /// ahead, the wrap from the flags kept with u. The iterative architecture (not `flat`)
    /// adds + 1 / - 1 after the choice of base, decodes a load's step in the clock and takes
    /// the wrap from compares of u: fewer LUTs, which its area target needs
    /// (`tests/blocks/iterative.rs`).
    flat: Constant<Bit>,
    /// Mask of M turn bits.
    tmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Three (also the 2-bit mask).
    three: Constant<Bits<32>>,
    /// Minus one (32-bit two's complement).
    minus_one: Constant<Bits<32>>,
    /// Minus two (32-bit two's complement): the running step's bits above bit 0 when down.
    minus_two: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl QuadrantCounter {
    /// Counter for the derived parameters.
    pub fn new(d: &Derived) -> Self {
        let f = d.fine_bits;
        // The warning compares delta >> (F-2) only: the thresholds have no lower bits.
        debug_assert_eq!(d.warn_step & mask(f - 2), 0);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            p_in: Default::default(),
            q_next: Default::default(),
            acc_in: Default::default(),
            ok_in: Default::default(),
            v_in: Default::default(),
            up_in: Default::default(),
            down_in: Default::default(),
            step_in: Default::default(),
            wq_in: Default::default(),
            wz_in: Default::default(),
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
            u_reg: Default::default(),
            fine_reg: Default::default(),
            turns_reg: Default::default(),
            tinc_reg: Default::default(),
            tdec_reg: Default::default(),
            tio_reg: Default::default(),
            tdo_reg: Default::default(),
            ovi_reg: Default::default(),
            ovd_reg: Default::default(),
            valid_reg: Default::default(),
            error_reg: Default::default(),
            warning_reg: Default::default(),
            pending_reg: Default::default(),
            lqc_reg: Default::default(),
            lturns_reg: Default::default(),
            ltinc_reg: Default::default(),
            ltdec_reg: Default::default(),
            llast_reg: Default::default(),
            lzero_reg: Default::default(),
            lpen_reg: Default::default(),
            lone_reg: Default::default(),
            ul_reg: Default::default(),
            dl_reg: Default::default(),
            uwl_reg: Default::default(),
            dwl_reg: Default::default(),
            uwl: Default::default(),
            dwl: Default::default(),
            qlat: Default::default(),
            qnow: Default::default(),
            rwu: Default::default(),
            rwd: Default::default(),
            base_turns: Default::default(),
            tsel_p: Default::default(),
            tsel_r: Default::default(),
            ulast_reg: Default::default(),
            unz_reg: Default::default(),
            upen: Default::default(),
            ulst: Default::default(),
            uzer: Default::default(),
            uone: Default::default(),
            nlast: Default::default(),
            nzero: Default::default(),
            qnew: Default::default(),
            base_q: Default::default(),
            base_u: Default::default(),
            up: Default::default(),
            down: Default::default(),
            ustep: Default::default(),
            up_l: Default::default(),
            down_l: Default::default(),
            ustep_l: Default::default(),
            usum_l: Default::default(),
            wrap_l: Default::default(),
            usum: Default::default(),
            un: Default::default(),
            wrap: Default::default(),
            tinc: Default::default(),
            tdec: Default::default(),
            fshift: c32(f as u64),
            fmask: c32(mask(f)),
            wlo: c32(d.warn_step >> (f - 2)),
            whi: c32(((1 << (f + 2)) - d.warn_step) >> (f - 2)),
            two: c32(2),
            umask: c32(mask(d.quadrant_bits - 2)),
            usmask: c32(mask(d.quadrant_bits - 1)),
            pow2: Constant::new((d.quadrants_per_turn / 4).is_power_of_two()),
            ulast: c32(d.quadrants_per_turn / 4 - 1),
            upenult: c32((d.quadrants_per_turn / 4).wrapping_sub(2) & mask(d.quadrant_bits - 2)),
            uone_c: c32(1 & mask(d.quadrant_bits - 2)),
            ppr1: Constant::new(d.quadrants_per_turn == 4),
            flat: Constant::new(d.architecture == Architecture::Unrolled),
            tmask: c32(mask(d.multiturn_bits)),
            one: c32(1),
            three: c32(3),
            minus_one: c32(mask(32)),
            minus_two: c32(mask(32) - 1),
            zero: c32(0),
        }
    }
}
