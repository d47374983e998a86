//! rust-hdl description of the pieces every serial slave shares: the line synchronizer
//! ([`LineSync`]) and the position word latch ([`PosWord`]). See the module docs of
//! [`crate::blocks::serial`] for the sketch and the widths.
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// Two-flop synchronizer with an optional one-sample glitch filter and edge detection for
/// an asynchronous line that idles high (MA, SSI clock, SPI chip select and clock).
///
/// The flops hold the inverted line (n1, n2, n3, nf), so their power-up and reset value 0
/// means "high". `rise` / `fall` are one-cycle pulses; the parent acts on them at the next
/// clock edge, which is also when `level` (the filtered level) changes. They are registered:
/// the pipeline of flops shows the next clock's edge one clock early (the flops' next
/// values n1 -> n2, n2 -> n3 and nf's update are known now), so each pulse is computed from
/// those next values and comes straight from a flip-flop, with no LUT between the
/// synchronizer and the parent's decode; cycle for cycle they equal the edge test on the
/// current flops.
#[derive(LogicBlock)]
pub struct LineSync {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: the line is taken as high.
    pub rst: Signal<In, Bit>,
    /// The asynchronous line.
    pub pin: Signal<In, Bit>,
    /// Filtered, synchronized level.
    pub level: Signal<Out, Bit>,
    /// The filtered level rises at the next clock edge.
    pub rise: Signal<Out, Bit>,
    /// The filtered level falls at the next clock edge.
    pub fall: Signal<Out, Bit>,
    n1: DFF<Bit>,
    n2: DFF<Bit>,
    n3: DFF<Bit>,
    nf: DFF<Bit>,
    /// rise, registered (computed from the flops' next values).
    rise_r: DFF<Bit>,
    /// fall, registered.
    fall_r: DFF<Bit>,
    src: Signal<Local, Bit>,
    change: Signal<Local, Bit>,
    /// nf at the next clock.
    nfn: Signal<Local, Bit>,
    /// The edge test at the next clock (on n2 -> n1, n3 -> n2, nf -> nfn).
    chn: Signal<Local, Bit>,
    /// Glitch filter on.
    filter: Constant<Bit>,
}

impl LineSync {
    /// Synchronizer, with or without the glitch filter.
    pub fn new(glitch_filter: bool) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            pin: Default::default(),
            level: Default::default(),
            rise: Default::default(),
            fall: Default::default(),
            n1: Default::default(),
            n2: Default::default(),
            n3: Default::default(),
            nf: Default::default(),
            rise_r: Default::default(),
            fall_r: Default::default(),
            src: Default::default(),
            change: Default::default(),
            nfn: Default::default(),
            chn: Default::default(),
            filter: Constant::new(glitch_filter),
        }
    }
}

impl Logic for LineSync {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, n1, n2, n3, nf, rise_r, fall_r);
        self.n1.d.next = !self.pin.val();
        self.n2.d.next = self.n1.q.val();
        self.n3.d.next = self.n2.q.val();
        if self.filter.val() {
            self.src.next = self.n3.q.val();
            self.change.next =
                (self.n2.q.val() == self.n3.q.val()) & (self.n3.q.val() != self.nf.q.val());
        } else {
            self.src.next = self.n2.q.val();
            self.change.next = self.n2.q.val() != self.nf.q.val();
        }
        self.nfn.next = self.nf.q.val();
        if self.change.val() {
            self.nfn.next = self.src.val();
        }
        self.nf.d.next = self.nfn.val();
        // The same edge test one clock ahead: n2, n3 and nf at the next clock are n1, n2
        // and nfn.
        if self.filter.val() {
            self.chn.next =
                (self.n1.q.val() == self.n2.q.val()) & (self.n2.q.val() != self.nfn.val());
        } else {
            self.chn.next = self.n1.q.val() != self.nfn.val();
        }
        self.rise_r.d.next = self.chn.val() & self.nfn.val();
        self.fall_r.d.next = self.chn.val() & !self.nfn.val();
        self.level.next = !self.nf.q.val();
        self.rise.next = self.rise_r.q.val();
        self.fall.next = self.fall_r.q.val();
        if self.rst.val() {
            self.n1.d.next = false;
            self.n2.d.next = false;
            self.n3.d.next = false;
            self.nf.d.next = false;
            self.rise_r.d.next = false;
            self.fall_r.d.next = false;
        }
    }
}

/// Holds the last valid position and composes the data word and the sticky flags that a
/// slave latches at the start of a frame.
///
/// `word` = Gray or binary of (turns mod 2^M) * 2^S + (pos mod 2^S), from the inputs when
/// `pos_valid` is set in this cycle, otherwise from the held copy. `err` = a sticky error
/// since the last `take`, the current `error`, or no valid position since reset; `warn`
/// likewise. `take` (the slave latches this cycle) clears the sticky flags.
#[derive(LogicBlock)]
pub struct PosWord {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: no position, no flags.
    pub rst: Signal<In, Bit>,
    /// Single-turn position (low S bits).
    pub pos: Signal<In, Bits<32>>,
    /// Turn count (low M bits).
    pub turns: Signal<In, Bits<32>>,
    /// `pos` and `turns` are new.
    pub pos_valid: Signal<In, Bit>,
    /// Error flag (any cycle counts).
    pub error: Signal<In, Bit>,
    /// Warning flag (any cycle counts).
    pub warning: Signal<In, Bit>,
    /// The slave latches `word`, `err`, `warn` in this cycle.
    pub take: Signal<In, Bit>,
    /// Data word (S + M bits).
    pub word: Signal<Out, Bits<32>>,
    /// Error to report.
    pub err: Signal<Out, Bit>,
    /// Warning to report.
    pub warn: Signal<Out, Bit>,
    posh: DFF<Bits<32>>,
    turnsh: DFF<Bits<32>>,
    have: DFF<Bit>,
    erracc: DFF<Bit>,
    warnacc: DFF<Bit>,
    pm: Signal<Local, Bits<32>>,
    tm: Signal<Local, Bits<32>>,
    wb: Signal<Local, Bits<32>>,
    /// Mask of S position bits.
    stmask: Constant<Bits<32>>,
    /// Mask of M turn bits.
    mtmask: Constant<Bits<32>>,
    /// S, the shift of the turns (at most 31; the turns mask is 0 when S = 32).
    stshift: Constant<Bits<32>>,
    /// Gray-code the word.
    gray: Constant<Bit>,
    /// One.
    one: Constant<Bits<32>>,
}

impl PosWord {
    /// Word latch for S = `position_bits` and M = `multiturn_bits` (S + M <= 32).
    pub fn new(position_bits: u32, multiturn_bits: u32, gray: bool) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            pos: Default::default(),
            turns: Default::default(),
            pos_valid: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            take: Default::default(),
            word: Default::default(),
            err: Default::default(),
            warn: Default::default(),
            posh: Default::default(),
            turnsh: Default::default(),
            have: Default::default(),
            erracc: Default::default(),
            warnacc: Default::default(),
            pm: Default::default(),
            tm: Default::default(),
            wb: Default::default(),
            stmask: c32(mask(position_bits)),
            mtmask: c32(if position_bits >= 32 {
                0
            } else {
                mask(multiturn_bits)
            }),
            stshift: c32(position_bits.min(31) as u64),
            gray: Constant::new(gray),
            one: c32(1),
        }
    }
}

impl Logic for PosWord {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, posh, turnsh, have, erracc, warnacc);
        if self.pos_valid.val() {
            self.posh.d.next = self.pos.val();
            self.turnsh.d.next = self.turns.val();
            self.have.d.next = true;
            self.pm.next = self.pos.val();
            self.tm.next = self.turns.val();
        } else {
            self.pm.next = self.posh.q.val();
            self.tm.next = self.turnsh.q.val();
        }
        self.wb.next = ((self.tm.val() & self.mtmask.val()) << self.stshift.val())
            | (self.pm.val() & self.stmask.val());
        if self.gray.val() {
            self.word.next = self.wb.val() ^ (self.wb.val() >> self.one.val());
        } else {
            self.word.next = self.wb.val();
        }
        self.err.next =
            self.erracc.q.val() | self.error.val() | !(self.have.q.val() | self.pos_valid.val());
        self.warn.next = self.warnacc.q.val() | self.warning.val();
        if self.take.val() {
            self.erracc.d.next = false;
            self.warnacc.d.next = false;
        } else {
            if self.error.val() {
                self.erracc.d.next = true;
            }
            if self.warning.val() {
                self.warnacc.d.next = true;
            }
        }
        if self.rst.val() {
            self.have.d.next = false;
            self.erracc.d.next = false;
            self.warnacc.d.next = false;
        }
    }
}
