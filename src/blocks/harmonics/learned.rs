//! The learned harmonic correction (`[harmonics] mode = "learn"`): the learner
//! ([`super::learner::HarmonicLearner`], the sequencer of `super::sequencer`) beside the
//! table's lookup in RAM ([`super::hdl_ram::HarmonicCorrectionRam`]), as the core
//! instantiates them (docs/correction.md, "Learning the table online").
//!
//! ```text
//!               ┌─────────────────────────── HarmonicLearner ─────────────────────────┐
//!  v_in ───────►│ strobe        Collect ► Line ► Residual ► Mean ► Update ► Apply     │
//!  z_in >> Gz ─►│ angle m       (its own table and bin sums in RAM)                   ├─► tw, tw_addr, tw_data,
//!  update, ld ─►│                                                                     │   bank, clearing, ld_busy
//!               └───────────────────────────────┬─────────────────────────────────────┘
//!                                               │ every table write, the bank, the Clear
//!               ┌───────────────────────────────▼─────────────────────────────────────┐
//!  z_in, x_in ─►│ HarmonicCorrectionRam: c_i, c_(i+1) of the bank, interpolate, subtract ├─► z_out, x_out, v_out
//!  v_in         │ (8 clocks)                                                          │
//!               └─────────────────────────────────────────────────────────────────────┘
//! ```
//!
//! The learner sits beside the position path, not in it, so its ports are registered at
//! the block's edge: its reset (`rst_l`, a flop of its own: the core's reset net would
//! otherwise reach the learner's every flop), its sample (`smp_v`, `smp_a`) and the table
//! writes, bank and Clear flag the lookup takes (`lk_*`). The learner therefore sees each
//! sample a clock later and the lookup each write and bank flip a clock later than the
//! learner makes them; neither changes what is learned or which entries a sample reads
//! between two flips. The register map's mirror takes the writes straight from the
//! learner (its own timing, `super::super::regmap`).
//!
//! The learner takes the raw angle m = z >> Gz (F + 2 bits: the CORDIC's angle rounded to
//! the position LSB, the combiner's own rounding), not the corrected one: it corrects its
//! samples with its own copy of the table (q units), so the lookup's copy (z units, rounded
//! from it) never feeds back into the learning.
use super::hdl_ram::HarmonicCorrectionRam;
use super::learner::HarmonicLearner;
use super::HarmonicParams;
use crate::blocks::init_bit::InitBit;
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// The learner and the lookup, wired.
#[derive(LogicBlock)]
pub struct LearnedHarmonics {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset: the learner's Clear, the valid bits in flight cleared.
    pub rst: Signal<In, Bit>,
    /// The CORDIC's angle word (ZW bits, z units).
    pub z_in: Signal<In, Bits<32>>,
    /// The CORDIC's magnitude, carried along.
    pub x_in: Signal<In, Bits<32>>,
    /// The sample is valid.
    pub v_in: Signal<In, Bit>,
    /// 1: the learning moves entries; 0: the table stays (the register map's LEARN).
    pub update: Signal<In, Bit>,
    /// A request to set entry `ld_addr` to `ld_data` (q units) in both banks.
    pub ld: Signal<In, Bit>,
    /// The entry of the request.
    pub ld_addr: Signal<In, Bits<32>>,
    /// Its value, q units (2^-T LSB), two's complement in the learner's entry width.
    pub ld_data: Signal<In, Bits<32>>,
    /// The corrected angle (ZW bits), `LATENCY_RAM` clocks after `z_in`.
    pub z_out: Signal<Out, Bits<32>>,
    /// `x_in` as late.
    pub x_out: Signal<Out, Bits<32>>,
    /// `v_in` as late.
    pub v_out: Signal<Out, Bit>,
    /// The learner writes an entry (q units) this clock, for the register map's copy.
    pub tw: Signal<Out, Bit>,
    /// Its address: bank P + i.
    pub tw_addr: Signal<Out, Bits<32>>,
    /// Its value, q units.
    pub tw_data: Signal<Out, Bits<32>>,
    /// The bank in use.
    pub bank: Signal<Out, Bit>,
    /// A load request is pending.
    pub ld_busy: Signal<Out, Bit>,
    learner: HarmonicLearner,
    lookup: HarmonicCorrectionRam,
    /// The learner's reset, `rst` a clock later (powered up asserted). Timing: the core's
    /// reset register drove the core's and the learner's every flop (rst_core -> core).
    rst_l: InitBit,
    /// The sample the learner takes, a clock late: valid, raw angle. Timing: the CORDIC's
    /// last stage -> the learner's first sum.
    smp_v: DFF<Bit>,
    smp_a: DFF<Bits<32>>,
    /// The lookup's copy of the learner's table writes, bank and Clear flag, a clock late.
    /// Timing: the learner's output registers -> the lookup's RAMs and read address.
    lk_tw: DFF<Bit>,
    lk_twa: DFF<Bits<32>>,
    lk_twd: DFF<Bits<32>>,
    lk_bank: DFF<Bit>,
    lk_clr: DFF<Bit>,
    /// Gz: the shift from the angle word to the position LSB.
    gz: Constant<Bits<32>>,
    /// Mask of F + 2 bits (the raw angle within the period).
    amask: Constant<Bits<32>>,
}

impl LearnedHarmonics {
    /// The block for `p` (which has `learn`).
    pub fn new(p: &HarmonicParams) -> Self {
        let lp = p.learn.expect("a learned table");
        Self {
            clk: Default::default(),
            rst: Default::default(),
            z_in: Default::default(),
            x_in: Default::default(),
            v_in: Default::default(),
            update: Default::default(),
            ld: Default::default(),
            ld_addr: Default::default(),
            ld_data: Default::default(),
            z_out: Default::default(),
            x_out: Default::default(),
            v_out: Default::default(),
            tw: Default::default(),
            tw_addr: Default::default(),
            tw_data: Default::default(),
            bank: Default::default(),
            ld_busy: Default::default(),
            learner: HarmonicLearner::new(&lp, &vec![0; lp.points()]),
            lookup: HarmonicCorrectionRam::new(p, lp.entry_width()),
            rst_l: InitBit::kept(true),
            smp_v: Default::default(),
            smp_a: Default::default(),
            lk_tw: Default::default(),
            lk_twa: Default::default(),
            lk_twd: Default::default(),
            lk_bank: Default::default(),
            lk_clr: Default::default(),
            gz: c32(u64::from(p.z_guard)),
            amask: c32(mask(p.fine_bits + 2)),
        }
    }
}

impl Logic for LearnedHarmonics {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, smp_v, smp_a, lk_tw, lk_twa, lk_twd, lk_bank, lk_clr);
        self.rst_l.clock.next = self.clk.val();
        self.rst_l.d.next = self.rst.val();
        self.smp_v.d.next = self.v_in.val();
        self.smp_a.d.next = (self.z_in.val() >> self.gz.val()) & self.amask.val();
        self.learner.clk.next = self.clk.val();
        self.learner.rst.next = self.rst_l.q.val();
        self.learner.strobe.next = self.smp_v.q.val();
        self.learner.angle.next = self.smp_a.q.val();
        self.learner.update.next = self.update.val();
        self.learner.ld.next = self.ld.val();
        self.learner.ld_addr.next = self.ld_addr.val();
        self.learner.ld_data.next = self.ld_data.val();
        self.lk_tw.d.next = self.learner.tw.val();
        self.lk_twa.d.next = self.learner.tw_addr.val();
        self.lk_twd.d.next = self.learner.tw_data.val();
        self.lk_bank.d.next = self.learner.bank.val();
        self.lk_clr.d.next = self.learner.clearing.val();
        self.lookup.clk.next = self.clk.val();
        self.lookup.rst.next = self.rst.val();
        self.lookup.z_in.next = self.z_in.val();
        self.lookup.x_in.next = self.x_in.val();
        self.lookup.v_in.next = self.v_in.val();
        self.lookup.bank.next = self.lk_bank.q.val();
        self.lookup.clearing.next = self.lk_clr.q.val();
        self.lookup.tw.next = self.lk_tw.q.val();
        self.lookup.tw_addr.next = self.lk_twa.q.val();
        self.lookup.tw_data.next = self.lk_twd.q.val();
        self.z_out.next = self.lookup.z_out.val();
        self.x_out.next = self.lookup.x_out.val();
        self.v_out.next = self.lookup.v_out.val();
        self.tw.next = self.learner.tw.val();
        self.tw_addr.next = self.learner.tw_addr.val();
        self.tw_data.next = self.learner.tw_data.val();
        self.bank.next = self.learner.bank.val();
        self.ld_busy.next = self.learner.ld_busy.val();
    }
}
