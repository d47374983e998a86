//! rust-hdl description of the ADC frame check (rule, per chip, and sketch in
//! [`crate::blocks::adc::frame_check`]); [`crate::blocks::adc::model::AdcModel`] with
//! `with_frame_check` is its cycle reference.
use crate::blocks::adc::FrameCheck;
use rust_hdl::prelude::*;

/// Per data line: did the frame show a 1, did it show a 0; at the frame's last data bit,
/// the verdict "every line showed one level only".
#[derive(LogicBlock)]
pub struct FrameChecker {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high (the controller's data reset, `rst_d`): no frame seen.
    pub rst: Signal<In, Bit>,
    /// A channel-0 data bit is shifted in at this edge (the controller's `cap0_d`).
    pub en0: Signal<In, Bit>,
    /// A channel-1 data bit is shifted in at this edge (`cap1_d`).
    pub en1: Signal<In, Bit>,
    /// Line A's sampled bit (`miso_d`).
    pub bit_a: Signal<In, Bit>,
    /// Line B's sampled bit (`miso_b_d`; 0 with one line).
    pub bit_b: Signal<In, Bit>,
    /// The capture state of a frame's last data slot was entered at the previous edge (any
    /// frame, delivered or not): registered here, so it marks the edge of that bit's shift.
    pub last: Signal<In, Bit>,
    /// The last data bit of a delivered frame is shifted in at this edge (`capv_d`).
    pub deliver: Signal<In, Bit>,
    /// The last delivered frame had every data line stuck (changes with `out_valid`).
    pub frame_error: Signal<Out, Bit>,
    /// Line A showed a 1 / a 0 in this frame so far.
    hi_a: DFF<Bit>,
    lo_a: DFF<Bit>,
    /// Line B showed a 1 / a 0 (never set with one line).
    hi_b: DFF<Bit>,
    lo_b: DFF<Bit>,
    /// `last`, registered: this edge shifts a frame's last data bit in.
    last_d: DFF<Bit>,
    /// The verdict of the last delivered frame.
    err: DFF<Bit>,
    /// A line-A data bit at this edge: channel 0's, and channel 1's with one line.
    ea: Signal<Local, Bit>,
    /// A line-B data bit at this edge (two lines only).
    eb: Signal<Local, Bit>,
    /// The seen flags with this edge's bit.
    hi_an: Signal<Local, Bit>,
    lo_an: Signal<Local, Bit>,
    hi_bn: Signal<Local, Bit>,
    lo_bn: Signal<Local, Bit>,
    /// Every line showed one level only (with this edge's bit).
    stuck: Signal<Local, Bit>,
    /// Two data lines: channel 1 on line B.
    two: Constant<Bit>,
}

impl FrameChecker {
    /// The check for `c`.
    pub fn new(c: &FrameCheck) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            en0: Default::default(),
            en1: Default::default(),
            bit_a: Default::default(),
            bit_b: Default::default(),
            last: Default::default(),
            deliver: Default::default(),
            frame_error: Default::default(),
            hi_a: Default::default(),
            lo_a: Default::default(),
            hi_b: Default::default(),
            lo_b: Default::default(),
            last_d: Default::default(),
            err: Default::default(),
            ea: Default::default(),
            eb: Default::default(),
            hi_an: Default::default(),
            lo_an: Default::default(),
            hi_bn: Default::default(),
            lo_bn: Default::default(),
            stuck: Default::default(),
            two: Constant::new(c.two_lines()),
        }
    }
}

impl Logic for FrameChecker {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, hi_a, lo_a, hi_b, lo_b, last_d, err);
        // The data bits shifted in at this edge, by line.
        self.ea.next = self.en0.val() | (self.en1.val() & !self.two.val());
        self.eb.next = self.en1.val() & self.two.val();
        self.hi_an.next = self.hi_a.q.val() | (self.ea.val() & self.bit_a.val());
        self.lo_an.next = self.lo_a.q.val() | (self.ea.val() & !self.bit_a.val());
        self.hi_bn.next = self.hi_b.q.val() | (self.eb.val() & self.bit_b.val());
        self.lo_bn.next = self.lo_b.q.val() | (self.eb.val() & !self.bit_b.val());
        // A line that showed both levels toggled; the frame is stuck when none did (line B
        // never shows a level with one line).
        self.stuck.next =
            !(self.hi_an.val() & self.lo_an.val()) & !(self.hi_bn.val() & self.lo_bn.val());
        self.hi_a.d.next = self.hi_an.val();
        self.lo_a.d.next = self.lo_an.val();
        self.hi_b.d.next = self.hi_bn.val();
        self.lo_b.d.next = self.lo_bn.val();
        // After a frame's last bit the next frame starts unseen.
        if self.last_d.q.val() {
            self.hi_a.d.next = false;
            self.lo_a.d.next = false;
            self.hi_b.d.next = false;
            self.lo_b.d.next = false;
        }
        self.last_d.d.next = self.last.val();
        if self.deliver.val() {
            self.err.d.next = self.stuck.val();
        }
        if self.rst.val() {
            self.hi_a.d.next = false;
            self.lo_a.d.next = false;
            self.hi_b.d.next = false;
            self.lo_b.d.next = false;
            self.last_d.d.next = false;
            self.err.d.next = false;
        }
        self.frame_error.next = self.err.q.val();
    }
}
