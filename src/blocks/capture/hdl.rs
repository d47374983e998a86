//! rust-hdl description of the capture block (maths, timing and sketch in the module docs
//! of [`crate::blocks::capture`]). [`CaptureModel`](super::model::CaptureModel) is its
//! cycle reference.
//!
//! Words: the position sum and the velocity are `Bits<64>` holding a w-bit value in their
//! low bits (upper bits zero), w through per-instance masks, as in the other blocks
//! (`crate::blocks`). Timing: every register-to-register path holds one carry chain at
//! most: `since` and `ager` count from registers; the multiplier adds registers only; the
//! sum adds two registers; the wrap's two adders start at the registered sum and a select
//! follows them.
use super::CaptureParams;
use crate::blocks::velocity::VelMul;
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

fn c64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// Where a capture is (the sketch in the module docs).
#[derive(Copy, Clone, PartialEq, Eq, Debug, LogicState)]
pub enum CapState {
    /// Waiting for an edge (reset and power-up).
    Idle,
    /// Multiplier started with the latched velocity and `ager`.
    Start,
    /// Multiplier running: n + 1 clocks.
    Multiply,
    /// Sum s = p + d.
    Add,
    /// s wrapped into one turn; outputs loaded, strobe raised.
    Wrap,
}

/// The capture block (ports in the module docs of `capture`).
#[derive(LogicBlock)]
pub struct Capture {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: nothing held, the age saturated, no capture running.
    pub rst: Signal<In, Bit>,
    /// Capture request, asynchronous (two synchronizer flops here): a rising edge captures.
    pub capture: Signal<In, Bit>,
    /// A position sample is on `in_qc`, `in_fine`, `in_turns`.
    pub in_valid: Signal<In, Bit>,
    /// Quadrant count, 0..Q-1.
    pub in_qc: Signal<In, Bits<32>>,
    /// Fine part.
    pub in_fine: Signal<In, Bits<32>>,
    /// Turn word (M bits).
    pub in_turns: Signal<In, Bits<32>>,
    /// The velocity estimate, held between its strobes (its width's low bits).
    pub in_velocity: Signal<In, Bits<64>>,
    /// One clock: a capture's values are on `out_*`.
    pub out_valid: Signal<Out, Bit>,
    /// Captured (extrapolated) quadrant count.
    pub out_qc: Signal<Out, Bits<32>>,
    /// Captured (extrapolated) fine part.
    pub out_fine: Signal<Out, Bits<32>>,
    /// Captured (extrapolated) turn word.
    pub out_turns: Signal<Out, Bits<32>>,
    /// Captured velocity.
    pub out_velocity: Signal<Out, Bits<64>>,
    /// Clocks from the captured sample's CONV edge to the capture (saturating).
    pub out_age: Signal<Out, Bits<32>>,
    /// The extrapolation's multiplier: one with `extrapolate`, none without.
    mul: Vec<VelMul>,
    /// Synchronizer, first flop.
    c1: DFF<Bit>,
    /// Synchronizer, second flop.
    c2: DFF<Bit>,
    /// Edge register: c2 one clock later.
    c3: DFF<Bit>,
    /// The held sample: quadrant count, fine part, turn word.
    hq: DFF<Bits<32>>,
    hf: DFF<Bits<32>>,
    ht: DFF<Bits<32>>,
    /// Clocks since the held sample's CONV edge, less the synchronizer's (saturating).
    since: DFF<Bits<32>>,
    /// `since` is saturated (since = 2^A - 1), registered beside it. Timing: keeps the
    /// 24-bit compare off the since -> since path.
    sat: DFF<Bit>,
    /// since < H, registered beside it with `hleft` = H - since while it holds. Timing:
    /// keeps the 24-bit compare off the since -> ager path (the capture top's slowest).
    young: DFF<Bit>,
    hleft: DFF<Bits<32>>,
    /// R min(since, H) + floor(R / 2): the multiplier's operand a, counted beside `since`.
    ager: DFF<Bits<64>>,
    state: DFF<CapState>,
    /// Multiplier clocks in `Multiply`, 0..n (bits(n) bits).
    mw: DFF<Bits<32>>,
    /// mw = n (the multiplier's last clock), registered a clock ahead. Timing: keeps the
    /// `mw` compare off the mw -> state path (the register-map top's slowest).
    mlast: DFF<Bit>,
    /// The latched sample, age, velocity and `ager` (extrapolation).
    cq: DFF<Bits<32>>,
    cf: DFF<Bits<32>>,
    ct: DFF<Bits<32>>,
    cage: DFF<Bits<32>>,
    cv: DFF<Bits<64>>,
    cb: DFF<Bits<64>>,
    /// s = p + d (sum bits).
    s: DFF<Bits<64>>,
    ov: DFF<Bit>,
    oq: DFF<Bits<32>>,
    ofine: DFF<Bits<32>>,
    ot: DFF<Bits<32>>,
    ovel: DFF<Bits<64>>,
    oage: DFF<Bits<32>>,
    cap_edge: Signal<Local, Bit>,
    vel: Signal<Local, Bits<64>>,
    prod: Signal<Local, Bits<64>>,
    dext: Signal<Local, Bits<64>>,
    pos: Signal<Local, Bits<64>>,
    sm: Signal<Local, Bits<64>>,
    sp: Signal<Local, Bits<64>>,
    sel: Signal<Local, Bits<64>>,
    /// 1 with `extrapolate`: the edge starts the multiply instead of the outputs.
    extra: Constant<Bit>,
    /// Saturation of `since` (2^A - 1).
    amax: Constant<Bits<32>>,
    /// `since` after a sample: L + 1 - 2.
    load: Constant<Bits<32>>,
    /// 2^A - 2: `since` saturates in the next clock.
    amax1: Constant<Bits<32>>,
    /// `hleft` after a sample: H - (L + 1 - 2).
    hload: Constant<Bits<32>>,
    /// Mask of `hleft` (bits(H - L + 1) bits), so its decrement and compare are narrow.
    hmask: Constant<Bits<32>>,
    /// R.
    recip: Constant<Bits<64>>,
    /// R (L + 1 - 2) + floor(R / 2): `ager` after a sample.
    ager_load: Constant<Bits<64>>,
    /// R H + floor(R / 2): `ager` after reset.
    ager_max: Constant<Bits<64>>,
    /// n - 1: `mlast` rises after the clock with this `mw`.
    steps1: Constant<Bits<32>>,
    /// Mask of `mw` (bits(n) bits).
    mwmask: Constant<Bits<32>>,
    one: Constant<Bits<32>>,
    /// F.
    fshift: Constant<Bits<64>>,
    /// t: the velocity's shift before the multiply.
    vshift: Constant<Bits<64>>,
    /// Masks of the quadrant count, the fine part and the turn word.
    qmask: Constant<Bits<32>>,
    fmask: Constant<Bits<32>>,
    fmask64: Constant<Bits<64>>,
    tmask: Constant<Bits<32>>,
    /// Mask of the velocity word (0 without an estimator).
    vmask: Constant<Bits<64>>,
    /// The product's sign bit and the fill above it up to the sum's width.
    psign: Constant<Bits<64>>,
    pext: Constant<Bits<64>>,
    /// Mask of the sum and its sign bit.
    smask: Constant<Bits<64>>,
    ssign: Constant<Bits<64>>,
    /// Q 2^F, one turn in LSB.
    turn: Constant<Bits<64>>,
}

impl Capture {
    /// The block for `p`.
    pub fn new(p: &CaptureParams) -> Self {
        let e = p.extrapolation().copied();
        let (recip, horizon) = e.map_or((0, 0), |e| (e.recip, e.horizon as u64));
        let ow = e.map_or(2, |e| e.out_width);
        let sw = p.sum_bits();
        let f = p.fine_bits();
        Self {
            clk: Default::default(),
            rst: Default::default(),
            capture: Default::default(),
            in_valid: Default::default(),
            in_qc: Default::default(),
            in_fine: Default::default(),
            in_turns: Default::default(),
            in_velocity: Default::default(),
            out_valid: Default::default(),
            out_qc: Default::default(),
            out_fine: Default::default(),
            out_turns: Default::default(),
            out_velocity: Default::default(),
            out_age: Default::default(),
            mul: e
                .iter()
                .map(|e| VelMul::new(e.a_width, e.b_width, e.out_width, e.shift))
                .collect(),
            c1: Default::default(),
            c2: Default::default(),
            c3: Default::default(),
            hq: Default::default(),
            hf: Default::default(),
            ht: Default::default(),
            since: Default::default(),
            ager: Default::default(),
            state: Default::default(),
            mw: Default::default(),
            mlast: Default::default(),
            cq: Default::default(),
            cf: Default::default(),
            ct: Default::default(),
            cage: Default::default(),
            cv: Default::default(),
            cb: Default::default(),
            s: Default::default(),
            ov: Default::default(),
            oq: Default::default(),
            ofine: Default::default(),
            ot: Default::default(),
            ovel: Default::default(),
            oage: Default::default(),
            cap_edge: Default::default(),
            sat: Default::default(),
            young: Default::default(),
            hleft: Default::default(),
            vel: Default::default(),
            prod: Default::default(),
            dext: Default::default(),
            pos: Default::default(),
            sm: Default::default(),
            sp: Default::default(),
            sel: Default::default(),
            extra: Constant::new(e.is_some()),
            amax: c32(mask(p.age_bits())),
            load: c32(p.since_load()),
            amax1: c32(mask(p.age_bits()) - 1),
            hload: c32(horizon.saturating_sub(p.since_load())),
            hmask: c32(mask(
                64 - horizon.saturating_sub(p.since_load()).leading_zeros(),
            )),
            recip: c64(recip),
            ager_load: c64(p.ager_for(p.since_load())),
            ager_max: c64(p.ager_for(u64::MAX)),
            steps1: c32((p.mul_steps() as u64).saturating_sub(1)),
            mwmask: c32(mask(32 - p.mul_steps().leading_zeros())),
            one: c32(1),
            fshift: c64(f as u64),
            vshift: c64(e.map_or(0, |e| e.vshift as u64)),
            qmask: c32(mask(p.quadrant_bits())),
            fmask: c32(mask(f)),
            fmask64: c64(mask(f)),
            tmask: c32(mask(p.turns_bits())),
            vmask: c64(mask(p.velocity_width())),
            psign: c64(1 << (ow - 1)),
            pext: c64(mask(sw) & !mask(ow)),
            smask: c64(mask(sw)),
            ssign: c64(1 << (sw - 1)),
            turn: c64(p.quadrants_per_turn() << f),
        }
    }
}

impl Logic for Capture {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, c1, c2, c3, hq, hf, ht, since, sat, young, hleft, ager, state, mw, mlast,
            cq, cf, ct, cage, cv, cb, s, ov, oq, ofine, ot, ovel, oage
        );
        // Synchronizer and edge register (no reset).
        self.c1.d.next = self.capture.val();
        self.c2.d.next = self.c1.q.val();
        self.c3.d.next = self.c2.q.val();
        self.cap_edge.next = self.c2.q.val() & !self.c3.q.val();
        self.vel.next = self.in_velocity.val() & self.vmask.val();
        // The multiplier (with `extrapolate`): a = ager (cb), b = v' = cv >> t (its low bits
        // are v' in two's complement), started in `Start`.
        self.prod.next = 0.into();
        for i in 0..self.mul.len() {
            self.mul[i].clk.next = self.clk.val();
            self.mul[i].a.next = self.cb.q.val();
            self.mul[i].b.next = self.cv.q.val() >> self.vshift.val();
            self.mul[i].start.next = self.state.q.val() == CapState::Start;
            self.prod.next = self.mul[i].p.val();
        }
        // The held sample and its age; `sat` is since = 2^A - 1 and `young` since < H, each
        // kept a clock ahead.
        if self.in_valid.val() {
            self.hq.d.next = self.in_qc.val() & self.qmask.val();
            self.hf.d.next = self.in_fine.val() & self.fmask.val();
            self.ht.d.next = self.in_turns.val() & self.tmask.val();
            self.since.d.next = self.load.val();
            self.sat.d.next = false;
            self.ager.d.next = self.ager_load.val();
            self.young.d.next = true;
            self.hleft.d.next = self.hload.val();
        } else {
            if !self.sat.q.val() {
                self.since.d.next = self.since.q.val() + self.one.val();
                self.sat.d.next = self.since.q.val() == self.amax1.val();
            }
            if self.young.q.val() {
                self.ager.d.next = self.ager.q.val() + self.recip.val();
                self.hleft.d.next = (self.hleft.q.val() - self.one.val()) & self.hmask.val();
                self.young.d.next = self.hleft.q.val() != self.one.val();
            }
        }
        // The sum p + sext(d) and its wrap into one turn.
        self.dext.next = self.prod.val();
        if (self.prod.val() & self.psign.val()).any() {
            self.dext.next = self.prod.val() | self.pext.val();
        }
        self.pos.next = (bit_cast::<64, 32>(self.cq.q.val()) << self.fshift.val())
            | bit_cast::<64, 32>(self.cf.q.val());
        self.sm.next = (self.s.q.val() - self.turn.val()) & self.smask.val();
        self.sp.next = (self.s.q.val() + self.turn.val()) & self.smask.val();
        self.sel.next = self.s.q.val();
        if (self.s.q.val() & self.ssign.val()).any() {
            self.sel.next = self.sp.val();
        } else if !(self.sm.val() & self.ssign.val()).any() {
            self.sel.next = self.sm.val();
        }
        self.ov.d.next = false;
        match self.state.q.val() {
            CapState::Idle => {
                if self.cap_edge.val() & self.extra.val() {
                    self.cq.d.next = self.hq.q.val();
                    self.cf.d.next = self.hf.q.val();
                    self.ct.d.next = self.ht.q.val();
                    self.cage.d.next = self.since.q.val();
                    self.cv.d.next = self.vel.val();
                    self.cb.d.next = self.ager.q.val();
                    self.state.d.next = CapState::Start;
                } else if self.cap_edge.val() {
                    self.ov.d.next = true;
                    self.oq.d.next = self.hq.q.val();
                    self.ofine.d.next = self.hf.q.val();
                    self.ot.d.next = self.ht.q.val();
                    self.ovel.d.next = self.vel.val();
                    self.oage.d.next = self.since.q.val();
                }
            }
            CapState::Start => {
                self.mw.d.next = 0.into();
                self.mlast.d.next = false;
                self.state.d.next = CapState::Multiply;
            }
            CapState::Multiply => {
                self.mw.d.next = (self.mw.q.val() + self.one.val()) & self.mwmask.val();
                self.mlast.d.next = self.mw.q.val() == self.steps1.val();
                if self.mlast.q.val() {
                    self.state.d.next = CapState::Add;
                }
            }
            CapState::Add => {
                self.s.d.next = (self.pos.val() + self.dext.val()) & self.smask.val();
                self.state.d.next = CapState::Wrap;
            }
            CapState::Wrap => {
                self.ov.d.next = true;
                self.oq.d.next = bit_cast::<32, 64>(self.sel.val() >> self.fshift.val());
                self.ofine.d.next = bit_cast::<32, 64>(self.sel.val() & self.fmask64.val());
                self.ot.d.next = self.ct.q.val();
                if (self.s.q.val() & self.ssign.val()).any() {
                    self.ot.d.next = (self.ct.q.val() - self.one.val()) & self.tmask.val();
                } else if !(self.sm.val() & self.ssign.val()).any() {
                    self.ot.d.next = (self.ct.q.val() + self.one.val()) & self.tmask.val();
                }
                self.ovel.d.next = self.cv.q.val();
                self.oage.d.next = self.cage.q.val();
                self.state.d.next = CapState::Idle;
            }
        }
        if self.rst.val() {
            self.hq.d.next = 0.into();
            self.hf.d.next = 0.into();
            self.ht.d.next = 0.into();
            self.since.d.next = self.amax.val();
            self.sat.d.next = true;
            self.young.d.next = false;
            self.hleft.d.next = 0.into();
            self.ager.d.next = self.ager_max.val();
            self.state.d.next = CapState::Idle;
            self.mw.d.next = 0.into();
            self.mlast.d.next = false;
            self.cq.d.next = 0.into();
            self.cf.d.next = 0.into();
            self.ct.d.next = 0.into();
            self.cage.d.next = 0.into();
            self.cv.d.next = 0.into();
            self.cb.d.next = 0.into();
            self.s.d.next = 0.into();
            self.ov.d.next = false;
            self.oq.d.next = 0.into();
            self.ofine.d.next = 0.into();
            self.ot.d.next = 0.into();
            self.ovel.d.next = 0.into();
            self.oage.d.next = 0.into();
        }
        self.out_valid.next = self.ov.q.val();
        self.out_qc.next = self.oq.q.val();
        self.out_fine.next = self.ofine.q.val();
        self.out_turns.next = self.ot.q.val();
        self.out_velocity.next = self.ovel.q.val();
        self.out_age.next = self.oage.q.val();
    }
}

impl crate::cosim::CosimBlock for Capture {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("capture", 1),
            Port::new("in_valid", 1),
            Port::new("in_qc", 32),
            Port::new("in_fine", 32),
            Port::new("in_turns", 32),
            Port::new("in_velocity", 64),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("out_valid", 1),
            Port::new("out_qc", 32),
            Port::new("out_fine", 32),
            Port::new("out_turns", 32),
            Port::new("out_velocity", 64),
            Port::new("out_age", 32),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.capture.next = r[1] != 0;
        self.in_valid.next = r[2] != 0;
        self.in_qc.next = Bits::<32>::from(r[3]);
        self.in_fine.next = Bits::<32>::from(r[4]);
        self.in_turns.next = Bits::<32>::from(r[5]);
        self.in_velocity.next = Bits::<64>::from(r[6]);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.out_valid.val() as u64,
            self.out_qc.val().to_u64(),
            self.out_fine.val().to_u64(),
            self.out_turns.val().to_u64(),
            self.out_velocity.val().to_u64(),
            self.out_age.val().to_u64(),
        ]
    }
}

impl crate::cosim::step::Clocked for Capture {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}
