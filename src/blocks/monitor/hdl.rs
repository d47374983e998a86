//! rust-hdl description of the signal monitor (rules in [`crate::blocks::monitor`]).
use super::{count_bits, MonitorParams};
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// Loss of signal, clipping and full-scale detection; warning combiner.
#[derive(LogicBlock)]
pub struct Monitor {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: los = 1, clip = full_scale = warning = 0.
    pub rst: Signal<In, Bit>,
    /// Raw sample strobe.
    pub in_valid: Signal<In, Bit>,
    /// Raw sine sample, A-bit two's complement in the low bits.
    pub in_sin: Signal<In, Bits<16>>,
    /// Raw cosine sample, A-bit two's complement in the low bits.
    pub in_cos: Signal<In, Bits<16>>,
    /// Magnitude strobe.
    pub mag_valid: Signal<In, Bit>,
    /// CORDIC magnitude, W-bit unsigned in the low bits.
    pub magnitude: Signal<In, Bits<32>>,
    /// Overspeed flag from the counter (a warning).
    pub overspeed: Signal<In, Bit>,
    /// QEP/CORDIC disagreement from the cross-check (a warning).
    pub qep_mismatch: Signal<In, Bit>,
    /// los | clip | full_scale.
    pub error: Signal<Out, Bit>,
    /// overspeed | qep_mismatch, registered.
    pub warning: Signal<Out, Bit>,
    /// Loss of signal.
    pub los: Signal<Out, Bit>,
    /// Magnitude above the clipping threshold (held H samples).
    pub clip: Signal<Out, Bit>,
    /// ADC at a full-scale code (held H samples).
    pub full_scale: Signal<Out, Bit>,
    los_reg: DFF<Bit>,
    los_cnt: DFF<Bits<32>>,
    clip_reg: DFF<Bit>,
    clip_cnt: DFF<Bits<32>>,
    fs_reg: DFF<Bit>,
    fs_cnt: DFF<Bits<32>>,
    warn_reg: DFF<Bit>,
    mag: Signal<Local, Bits<32>>,
    rs: Signal<Local, Bits<32>>,
    rc: Signal<Local, Bits<32>>,
    fs_hit: Signal<Local, Bit>,
    /// mag < los_threshold.
    low: Signal<Local, Bit>,
    /// mag >= los_release.
    good: Signal<Local, Bit>,
    /// mag > clip_threshold.
    over: Signal<Local, Bit>,
    /// W <= 31: the three threshold tests are the sign bits of 32-bit differences (one
    /// carry chain each) instead of magnitude comparisons, which Yosys maps to LUT cascades.
    narrow: Constant<Bit>,
    /// Bit 31: the sign of a difference.
    sign32: Constant<Bits<32>>,
    /// Mask of the W magnitude bits.
    wmask: Constant<Bits<32>>,
    /// Mask of the A sample bits.
    amask: Constant<Bits<32>>,
    /// Most negative A-bit code (-2^(A-1) as raw bits).
    code_min: Constant<Bits<32>>,
    /// Most positive A-bit code (2^(A-1)-1).
    code_max: Constant<Bits<32>>,
    /// Loss-of-signal threshold (low below it).
    los_thr: Constant<Bits<32>>,
    /// Release level (good at or above it).
    los_rel: Constant<Bits<32>>,
    /// Clipping threshold (clip above it).
    clip_thr: Constant<Bits<32>>,
    /// N-1.
    nlast: Constant<Bits<32>>,
    /// Mask of the window counter bits.
    nmask: Constant<Bits<32>>,
    /// H-1.
    hlast: Constant<Bits<32>>,
    /// Mask of the hold counter bits.
    hmask: Constant<Bits<32>>,
    /// One.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl Monitor {
    /// Monitor for `p`.
    pub fn new(p: &MonitorParams) -> Self {
        let a = p.adc_width();
        Self {
            clk: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_sin: Default::default(),
            in_cos: Default::default(),
            mag_valid: Default::default(),
            magnitude: Default::default(),
            overspeed: Default::default(),
            qep_mismatch: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            los: Default::default(),
            clip: Default::default(),
            full_scale: Default::default(),
            los_reg: Default::default(),
            los_cnt: Default::default(),
            clip_reg: Default::default(),
            clip_cnt: Default::default(),
            fs_reg: Default::default(),
            fs_cnt: Default::default(),
            warn_reg: Default::default(),
            mag: Default::default(),
            rs: Default::default(),
            rc: Default::default(),
            fs_hit: Default::default(),
            low: Default::default(),
            good: Default::default(),
            over: Default::default(),
            narrow: Constant::new(p.mag_width() <= 31),
            sign32: c32(1 << 31),
            wmask: c32(mask(p.mag_width())),
            amask: c32(mask(a)),
            code_min: c32(1 << (a - 1)),
            code_max: c32(mask(a - 1)),
            los_thr: c32(p.los_threshold()),
            los_rel: c32(p.los_release()),
            clip_thr: c32(p.clip_threshold()),
            nlast: c32(p.window() as u64 - 1),
            nmask: c32(mask(count_bits(p.window()))),
            hlast: c32(p.hold() as u64 - 1),
            hmask: c32(mask(count_bits(p.hold()))),
            one: c32(1),
            zero: c32(0),
        }
    }
}

impl Logic for Monitor {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, los_reg, los_cnt, clip_reg, clip_cnt, fs_reg, fs_cnt, warn_reg);
        self.mag.next = self.magnitude.val() & self.wmask.val();
        self.rs.next = bit_cast::<32, 16>(self.in_sin.val()) & self.amask.val();
        self.rc.next = bit_cast::<32, 16>(self.in_cos.val()) & self.amask.val();
        self.fs_hit.next = (self.rs.val() == self.code_min.val())
            | (self.rs.val() == self.code_max.val())
            | (self.rc.val() == self.code_min.val())
            | (self.rc.val() == self.code_max.val());
        // With W <= 31 both operands are below 2^31, so a - b < 0 exactly when a < b.
        if self.narrow.val() {
            self.low.next = ((self.mag.val() - self.los_thr.val()) & self.sign32.val()).any();
            self.good.next = !((self.mag.val() - self.los_rel.val()) & self.sign32.val()).any();
            self.over.next = ((self.clip_thr.val() - self.mag.val()) & self.sign32.val()).any();
        } else {
            self.low.next = self.mag.val() < self.los_thr.val();
            self.good.next = self.mag.val() >= self.los_rel.val();
            self.over.next = self.mag.val() > self.clip_thr.val();
        }
        if self.mag_valid.val() {
            // Loss of signal: N consecutive low (good) samples set (clear) it.
            if !self.los_reg.q.val() {
                if self.low.val() {
                    if self.los_cnt.q.val() == self.nlast.val() {
                        self.los_reg.d.next = true;
                        self.los_cnt.d.next = self.zero.val();
                    } else {
                        self.los_cnt.d.next =
                            (self.los_cnt.q.val() + self.one.val()) & self.nmask.val();
                    }
                } else {
                    self.los_cnt.d.next = self.zero.val();
                }
            } else if self.good.val() {
                if self.los_cnt.q.val() == self.nlast.val() {
                    self.los_reg.d.next = false;
                    self.los_cnt.d.next = self.zero.val();
                } else {
                    self.los_cnt.d.next =
                        (self.los_cnt.q.val() + self.one.val()) & self.nmask.val();
                }
            } else {
                self.los_cnt.d.next = self.zero.val();
            }
            // Clipping: set at once, clear after H clean samples.
            if self.over.val() {
                self.clip_reg.d.next = true;
                self.clip_cnt.d.next = self.zero.val();
            } else if self.clip_reg.q.val() {
                if self.clip_cnt.q.val() == self.hlast.val() {
                    self.clip_reg.d.next = false;
                    self.clip_cnt.d.next = self.zero.val();
                } else {
                    self.clip_cnt.d.next =
                        (self.clip_cnt.q.val() + self.one.val()) & self.hmask.val();
                }
            }
        }
        if self.in_valid.val() {
            // Full scale: set at once, clear after H clean raw samples.
            if self.fs_hit.val() {
                self.fs_reg.d.next = true;
                self.fs_cnt.d.next = self.zero.val();
            } else if self.fs_reg.q.val() {
                if self.fs_cnt.q.val() == self.hlast.val() {
                    self.fs_reg.d.next = false;
                    self.fs_cnt.d.next = self.zero.val();
                } else {
                    self.fs_cnt.d.next = (self.fs_cnt.q.val() + self.one.val()) & self.hmask.val();
                }
            }
        }
        self.warn_reg.d.next = self.overspeed.val() | self.qep_mismatch.val();
        if self.rst.val() {
            self.los_reg.d.next = true;
            self.los_cnt.d.next = self.zero.val();
            self.clip_reg.d.next = false;
            self.clip_cnt.d.next = self.zero.val();
            self.fs_reg.d.next = false;
            self.fs_cnt.d.next = self.zero.val();
            self.warn_reg.d.next = false;
        }
        self.error.next = self.los_reg.q.val() | self.clip_reg.q.val() | self.fs_reg.q.val();
        self.warning.next = self.warn_reg.q.val();
        self.los.next = self.los_reg.q.val();
        self.clip.next = self.clip_reg.q.val();
        self.full_scale.next = self.fs_reg.q.val();
    }
}

impl crate::cosim::step::Clocked for Monitor {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for Monitor {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("in_valid", 1),
            Port::new("in_sin", 16),
            Port::new("in_cos", 16),
            Port::new("mag_valid", 1),
            Port::new("magnitude", 32),
            Port::new("overspeed", 1),
            Port::new("qep_mismatch", 1),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("error", 1),
            Port::new("warning", 1),
            Port::new("los", 1),
            Port::new("clip", 1),
            Port::new("full_scale", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.in_valid.next = r[1] != 0;
        self.in_sin.next = Bits::<16>::from(r[2] & 0xffff);
        self.in_cos.next = Bits::<16>::from(r[3] & 0xffff);
        self.mag_valid.next = r[4] != 0;
        self.magnitude.next = Bits::<32>::from(r[5] & 0xffff_ffff);
        self.overspeed.next = r[6] != 0;
        self.qep_mismatch.next = r[7] != 0;
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.error.val() as u64,
            self.warning.val() as u64,
            self.los.val() as u64,
            self.clip.val() as u64,
            self.full_scale.val() as u64,
        ]
    }
}
