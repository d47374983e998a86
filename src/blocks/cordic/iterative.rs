//! Iterative CORDIC (`cordic.architecture = "iterative"`): one vectoring stage with a
//! variable shift, reused for the N iterations of a sample.
//!
//! ```text
//!              ┌──────────┐ x,y,q,v  ┌───────────────────────────────┐ x,z,q,v
//!  in_sin ────►│ quadrant ├─────────►│ mux ─► shift-add ─► x,y,z reg ├──► combiner ─► counter
//!  in_cos ────►│ mapper   │          │  ▲   k ─► barrel shift      │ │
//!  in_valid ─┬►│ (gated)  │          │  └──────────────────────────┘ │
//!            │ └──────────┘          │ k reg, busy, atan ROM[k]      │
//!            └── & in_ready ◄────────┤ in_ready, drop/lost flags     │
//!                                    └───────────────────────────────┘
//! ```
//!
//! Arithmetic: identical to the unrolled stages ([`super::hdl::CordicStage`]): iteration k
//! shifts x and y right by k with the arithmetic fill `xmask & !(xmask >> k)` (computed, no
//! literal), adds/subtracts with the same one-adder form, and takes atan(2^-k) from a ROM
//! holding `Derived::atan_table`. The model of both architectures is therefore
//! [`super::model::cordic`]; only the timing differs.
//!
//! Timing (cycle k = inputs before clock edge k; the edge that captures the input counts
//! as the first):
//! * Edge k: the mapper registers an accepted sample (as in the unrolled core).
//! * Edges k+1 .. k+N: iterations 0 .. N-1 (the first one reads the mapper's registers, the
//!   others the engine's own x/y/z registers); the result is held after edge k+N.
//! * Edge k+N+1: combiner; edge k+N+2: counter. Latency N + 2, the same as the unrolled core.
//! * Throughput: one sample per N clocks (the engine starts a new sample at the edge after
//!   its last iteration). For N = 1 that is one per clock.
//!
//! Handshake: `in_ready` is a function of registers only (no path from the inputs). A sample
//! offered with `in_valid` while `in_ready` is high is accepted. A sample offered while it is
//! low is **dropped**, never silently: the next accepted sample carries a `lost` mark, and
//! when that sample reaches the output (its `out_valid` strobe) `out_warning` is raised and
//! held with it, like the counter's own warning (the core's `out_warning` is the counter's
//! warning OR this mark). This is not an AXI-style handshake: `in_valid` held high while
//! `in_ready` is low counts as one dropped offer per cycle, so a producer honours `in_ready`
//! by asserting `in_valid` only in cycles where `in_ready` is high. Such a producer never
//! loses a sample; in the
//! board top the ADC delivers one sample per ADC period, and `sinedec check` rejects an
//! iterative design whose period is shorter than N clocks.
//!
//! `in_ready` is high in cycle m exactly when the engine will be free at edge m+1: the
//! engine is idle with no sample waiting in the mapper, or it performs its last iteration
//! at edge m (or N = 1). Back to back, samples are accepted every N cycles.
use crate::blocks::{c32, mask};
use crate::config::Derived;
use rust_hdl::prelude::*;
use std::collections::BTreeMap;

/// The iterative engine: takes the mapper's registered outputs, returns what the last
/// unrolled stage would (x, z, q, valid), plus `in_ready` and the `lost` warning mark.
#[derive(LogicBlock)]
pub struct IterativeCordic {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: engine idle, marks cleared.
    pub rst: Signal<In, Bit>,
    /// The core's raw `in_valid` (before gating with `in_ready`): counts dropped samples.
    pub in_valid: Signal<In, Bit>,
    /// Mapped x' from the mapper (W-bit).
    pub x_in: Signal<In, Bits<32>>,
    /// Mapped y' from the mapper (W-bit).
    pub y_in: Signal<In, Bits<32>>,
    /// Quadrant from the mapper.
    pub q_in: Signal<In, Bits<2>>,
    /// Mapper valid bit (the mapper's `in_valid` must be `in_valid & in_ready`).
    pub v_in: Signal<In, Bit>,
    /// The core accepts a sample in this cycle.
    pub in_ready: Signal<Out, Bit>,
    /// Final x (W-bit), valid with `v_out`.
    pub x_out: Signal<Out, Bits<32>>,
    /// Final z (ZW-bit), valid with `v_out`.
    pub z_out: Signal<Out, Bits<32>>,
    /// Quadrant, valid with `v_out`.
    pub q_out: Signal<Out, Bits<2>>,
    /// One-cycle strobe: the N iterations of a sample are done.
    pub v_out: Signal<Out, Bit>,
    /// A sample was dropped before the one the counter output last: OR into out_warning.
    pub lost: Signal<Out, Bit>,
    rom: ROM<Bits<32>, 5>,
    x_reg: DFF<Bits<32>>,
    y_reg: DFF<Bits<32>>,
    z_reg: DFF<Bits<32>>,
    q_reg: DFF<Bits<2>>,
    k_reg: DFF<Bits<5>>,
    busy_reg: DFF<Bit>,
    done_reg: DFF<Bit>,
    drop_reg: DFF<Bit>,
    lostm_reg: DFF<Bit>,
    loste_reg: DFF<Bit>,
    donec_reg: DFF<Bit>,
    lostc_reg: DFF<Bit>,
    hold_reg: DFF<Bit>,
    kin: Signal<Local, Bits<5>>,
    ksh: Signal<Local, Bits<5>>,
    sy: Signal<Local, Bits<32>>,
    active: Signal<Local, Bit>,
    last: Signal<Local, Bit>,
    rdy: Signal<Local, Bit>,
    xi: Signal<Local, Bits<32>>,
    yi: Signal<Local, Bits<32>>,
    zi: Signal<Local, Bits<32>>,
    xs: Signal<Local, Bits<32>>,
    ys: Signal<Local, Bits<32>>,
    m: Signal<Local, Bits<32>>,
    c: Signal<Local, Bits<32>>,
    nm: Signal<Local, Bits<32>>,
    nc: Signal<Local, Bits<32>>,
    /// All ones.
    ones: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
    /// Sign bit of a W-bit word.
    xsign: Constant<Bits<32>>,
    /// Mask of W bits.
    xmask: Constant<Bits<32>>,
    /// Mask of ZW bits.
    zmask: Constant<Bits<32>>,
    /// Iteration index 0.
    kzero: Constant<Bits<5>>,
    /// Iteration increment 1.
    kone: Constant<Bits<5>>,
    /// Last iteration index N - 1.
    klast: Constant<Bits<5>>,
    /// Iteration-index bits any k < N uses (the shifter levels that exist).
    kuse: Constant<Bits<5>>,
}

/// The index bits set by some k < N (N - 1 rounded up to all ones below its top bit).
fn kuse(d: &Derived) -> Constant<Bits<5>> {
    let top = d.iterations.saturating_sub(1);
    let v = if top == 0 {
        0
    } else {
        mask(32 - top.leading_zeros())
    };
    Constant::new(Bits::<5>::from(v & 31))
}

impl IterativeCordic {
    /// Engine for the derived parameters (N = `d.iterations` <= 20 iterations).
    pub fn new(d: &Derived) -> Self {
        let w = d.xy_width;
        let mut table = BTreeMap::new();
        for (i, &a) in d.atan_table.iter().enumerate() {
            table.insert(Bits::<5>::from(i as u64), Bits::<32>::from(a & mask(32)));
        }
        Self {
            clk: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            x_in: Default::default(),
            y_in: Default::default(),
            q_in: Default::default(),
            v_in: Default::default(),
            in_ready: Default::default(),
            x_out: Default::default(),
            z_out: Default::default(),
            q_out: Default::default(),
            v_out: Default::default(),
            lost: Default::default(),
            rom: ROM::new(table),
            kuse: kuse(d),
            x_reg: Default::default(),
            y_reg: Default::default(),
            z_reg: Default::default(),
            q_reg: Default::default(),
            k_reg: Default::default(),
            busy_reg: Default::default(),
            done_reg: Default::default(),
            drop_reg: Default::default(),
            lostm_reg: Default::default(),
            loste_reg: Default::default(),
            donec_reg: Default::default(),
            lostc_reg: Default::default(),
            hold_reg: Default::default(),
            kin: Default::default(),
            ksh: Default::default(),
            sy: Default::default(),
            active: Default::default(),
            last: Default::default(),
            rdy: Default::default(),
            xi: Default::default(),
            yi: Default::default(),
            zi: Default::default(),
            xs: Default::default(),
            ys: Default::default(),
            m: Default::default(),
            c: Default::default(),
            nm: Default::default(),
            nc: Default::default(),
            ones: c32(mask(32)),
            one: c32(1),
            zero: c32(0),
            xsign: c32(1 << (w - 1)),
            xmask: c32(mask(w)),
            zmask: c32(mask(d.z_width)),
            kzero: Constant::new(Bits::<5>::from(0u64)),
            kone: Constant::new(Bits::<5>::from(1u64)),
            klast: Constant::new(Bits::<5>::from((d.iterations - 1) as u64)),
        }
    }
}

impl Logic for IterativeCordic {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, x_reg, y_reg, z_reg, q_reg, k_reg, busy_reg, done_reg, drop_reg, lostm_reg,
            loste_reg, donec_reg, lostc_reg, hold_reg
        );
        // Operands: a new sample from the mapper when idle, else the engine's registers.
        self.kin.next = self.kzero.val();
        self.xi.next = self.x_in.val();
        self.yi.next = self.y_in.val();
        self.zi.next = self.zero.val();
        self.q_reg.d.next = self.q_in.val();
        self.loste_reg.d.next = self.lostm_reg.q.val();
        if self.busy_reg.q.val() {
            self.kin.next = self.k_reg.q.val();
            self.xi.next = self.x_reg.q.val();
            self.yi.next = self.y_reg.q.val();
            self.zi.next = self.z_reg.q.val();
            self.q_reg.d.next = self.q_reg.q.val();
            self.loste_reg.d.next = self.loste_reg.q.val();
        }
        self.active.next = self.busy_reg.q.val() | self.v_in.val();
        self.last.next = self.kin.val() == self.klast.val();
        self.rdy.next = !(self.active.val() & !self.last.val());
        self.rom.address.next = self.kin.val();
        // Shifts by k: x is never negative (the mapped vector starts in the first quadrant
        // and x only grows in vectoring mode), so its arithmetic shift is the logical one.
        // y's arithmetic shift is done as ((y ^ s) >> k) ^ s with s = the W-bit all-ones
        // word when y < 0 (one's-complement trick: no fill constants). `kin & kuse` clears
        // the index bits no iteration below N sets, so Yosys builds only the shifter
        // levels that are used.
        self.ksh.next = self.kin.val() & self.kuse.val();
        self.sy.next = self.zero.val();
        if (self.yi.val() & self.xsign.val()).any() {
            self.sy.next = self.xmask.val();
        }
        self.xs.next = self.xi.val() >> self.ksh.val();
        self.ys.next = ((self.yi.val() ^ self.sy.val()) >> self.ksh.val()) ^ self.sy.val();
        self.m.next = self.zero.val();
        self.c.next = self.zero.val();
        self.nm.next = self.ones.val();
        self.nc.next = self.one.val();
        if (self.yi.val() & self.xsign.val()).any() {
            self.m.next = self.ones.val();
            self.c.next = self.one.val();
            self.nm.next = self.zero.val();
            self.nc.next = self.zero.val();
        }
        self.x_reg.d.next =
            (self.xi.val() + (self.ys.val() ^ self.m.val()) + self.c.val()) & self.xmask.val();
        self.y_reg.d.next =
            (self.yi.val() + (self.xs.val() ^ self.nm.val()) + self.nc.val()) & self.xmask.val();
        self.z_reg.d.next = (self.zi.val() + (self.rom.data.val() ^ self.m.val()) + self.c.val())
            & self.zmask.val();
        self.k_reg.d.next = self.kin.val() + self.kone.val();
        self.busy_reg.d.next = self.active.val() & !self.last.val() & !self.rst.val();
        self.done_reg.d.next = self.active.val() & self.last.val() & !self.rst.val();
        // Drop bookkeeping: a sample offered while not ready marks the next accepted one.
        self.drop_reg.d.next = self.drop_reg.q.val();
        if self.in_valid.val() {
            self.drop_reg.d.next = !self.rdy.val();
        }
        if self.rst.val() {
            self.drop_reg.d.next = false;
        }
        self.lostm_reg.d.next = self.drop_reg.q.val();
        // Delay of the mark through the combiner, then held like the counter's flags.
        self.donec_reg.d.next = self.done_reg.q.val() & !self.rst.val();
        self.lostc_reg.d.next = self.loste_reg.q.val();
        self.hold_reg.d.next = self.hold_reg.q.val();
        if self.donec_reg.q.val() {
            self.hold_reg.d.next = self.lostc_reg.q.val();
        }
        if self.rst.val() {
            self.hold_reg.d.next = false;
        }
        self.in_ready.next = self.rdy.val();
        self.x_out.next = self.x_reg.q.val();
        self.z_out.next = self.z_reg.q.val();
        self.q_out.next = self.q_reg.q.val();
        self.v_out.next = self.done_reg.q.val();
        self.lost.next = self.hold_reg.q.val();
    }
}

/// Cycle-level model of the iterative timing (the arithmetic is the shared sample model):
/// used by [`crate::blocks::core::model::CoreModel`] in iterative mode.
#[derive(Clone, Debug)]
pub struct IterTiming<S: Clone> {
    /// Sample in the mapper register, with its lost mark.
    pub mapper: Option<(S, bool)>,
    /// Engine busy with iterations 1.. of `cur`.
    pub busy: bool,
    /// Next iteration index when busy.
    pub k: u32,
    /// Sample in the engine.
    pub cur: Option<(S, bool)>,
    /// Sample whose iterations finished at the last edge.
    pub done: Option<(S, bool)>,
    /// Sample in the combiner register.
    pub comb: Option<(S, bool)>,
    /// A sample was dropped since the last accepted one.
    pub dropped: bool,
    /// Held lost mark (ORed into out_warning).
    pub hold: bool,
}

impl<S: Clone> IterTiming<S> {
    /// Power-up state.
    pub fn new() -> Self {
        IterTiming {
            mapper: None,
            busy: false,
            k: 0,
            cur: None,
            done: None,
            comb: None,
            dropped: false,
            hold: false,
        }
    }

    /// in_ready for the coming cycle (a function of the state only).
    pub fn ready(&self, n: u32) -> bool {
        let active = self.busy || self.mapper.is_some();
        let kin = if self.busy { self.k } else { 0 };
        !(active && kin != n - 1)
    }

    /// One clock edge. `offer` is the sample presented with in_valid (computed lazily by
    /// the caller); returns the sample the combiner hands to the counter at this edge.
    pub fn clock(
        &mut self,
        n: u32,
        rst: bool,
        valid: bool,
        offer: impl FnOnce() -> S,
    ) -> Option<S> {
        let ready = self.ready(n);
        let to_counter = self.comb.clone().map(|c| c.0);
        let hold = if rst {
            false
        } else if let Some(c) = &self.comb {
            c.1
        } else {
            self.hold
        };
        let comb = if rst { None } else { self.done.clone() };
        let active = self.busy || self.mapper.is_some();
        let kin = if self.busy { self.k } else { 0 };
        let last = kin == n - 1;
        let cur = if self.busy {
            self.cur.clone()
        } else {
            self.mapper.clone()
        };
        let done = if active && last && !rst {
            cur.clone()
        } else {
            None
        };
        let busy = active && !last && !rst;
        let mapper = if valid && ready && !rst {
            Some((offer(), self.dropped))
        } else {
            None
        };
        let dropped = if rst {
            false
        } else if valid {
            !ready
        } else {
            self.dropped
        };
        *self = IterTiming {
            mapper,
            busy,
            k: kin + 1,
            cur: if active { cur } else { self.cur.clone() },
            done,
            comb,
            dropped,
            hold,
        };
        to_counter
    }
}
