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
    /// (los_cnt == N-1) ^ (N == 1), registered with the counter from its value before the
    /// step (see `update`), so no compare follows the counter's adder; 0 at power-up and
    /// whenever the counter is 0.
    los_lx: DFF<Bit>,
    /// clip = 1 and clip_cnt < H-1 (one more clean sample keeps clip set), registered
    /// with the counter from its value before the step.
    clip_k: DFF<Bit>,
    /// full_scale = 1 and fs_cnt < H-1, the same way.
    fs_k: DFF<Bit>,
    /// los_cnt == N-1 (decoded flag).
    los_last: Signal<Local, Bit>,
    /// The sample counts towards the los window (low while los = 0, good while los = 1).
    los_q: Signal<Local, Bit>,
    /// los_cnt + 1.
    los_inc: Signal<Local, Bits<32>>,
    /// The step lands on N-1: (los_cnt == N-2) ^ (N == 1).
    los_nx: Signal<Local, Bit>,
    /// los_cnt's next value if the sample is good (los = 1 and not at N-1: the step).
    los_ga: Signal<Local, Bits<32>>,
    /// los_cnt's next value if the sample is low (los = 0 and not at N-1: the step).
    los_la: Signal<Local, Bits<32>>,
    /// los_lx's next value if the sample is good.
    los_gx: Signal<Local, Bit>,
    /// los_lx's next value if the sample is low.
    los_lx_l: Signal<Local, Bit>,
    /// good ? los_ga : 0.
    los_gv: Signal<Local, Bits<32>>,
    /// low ? los_la : 0.
    los_lv: Signal<Local, Bits<32>>,
    /// mag < los_threshold.
    low: Signal<Local, Bit>,
    /// mag >= los_release.
    good: Signal<Local, Bit>,
    mag: Signal<Local, Bits<32>>,
    rs: Signal<Local, Bits<32>>,
    rc: Signal<Local, Bits<32>>,
    fs_hit: Signal<Local, Bit>,
    /// mag > clip_threshold.
    over: Signal<Local, Bit>,
    /// W <= 31: the three threshold tests are bit W of (W+1)-bit differences (one carry
    /// chain each) instead of magnitude comparisons, which Yosys maps to LUT cascades.
    narrow: Constant<Bit>,
    /// Bit W (W <= 31): set in 2^W + a - b exactly when a >= b.
    wbit: Constant<Bits<32>>,
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
    /// 2^W + clipping threshold (W <= 31).
    clip_thr_w: Constant<Bits<32>>,
    /// Mask of the window counter bits.
    nmask: Constant<Bits<32>>,
    /// N-2: the counter value before a step onto N-1 (never stepped from when N = 1).
    nlast_m1: Constant<Bits<32>>,
    /// N = 1: the window flag is set at counter 0.
    n_one: Constant<Bit>,
    /// H-2: the counter value before a step onto H-1 (never stepped from when H = 1).
    hlast_m1: Constant<Bits<32>>,
    /// H = 1: a set clip or full_scale clears on the first clean sample.
    h_one: Constant<Bit>,
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
        let wbit = if p.mag_width() <= 31 {
            1u64 << p.mag_width()
        } else {
            0
        };
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
            los_lx: Default::default(),
            clip_k: Default::default(),
            fs_k: Default::default(),
            los_last: Default::default(),
            los_q: Default::default(),
            los_inc: Default::default(),
            los_nx: Default::default(),
            los_ga: Default::default(),
            los_la: Default::default(),
            los_gx: Default::default(),
            los_lx_l: Default::default(),
            los_gv: Default::default(),
            los_lv: Default::default(),
            low: Default::default(),
            good: Default::default(),
            mag: Default::default(),
            rs: Default::default(),
            rc: Default::default(),
            fs_hit: Default::default(),
            over: Default::default(),
            narrow: Constant::new(p.mag_width() <= 31),
            wbit: c32(wbit),
            wmask: c32(mask(p.mag_width())),
            amask: c32(mask(a)),
            code_min: c32(1 << (a - 1)),
            code_max: c32(mask(a - 1)),
            los_thr: c32(p.los_threshold()),
            los_rel: c32(p.los_release()),
            clip_thr: c32(p.clip_threshold()),
            clip_thr_w: c32(p.clip_threshold() | wbit),
            nlast_m1: c32((p.window() as u64).wrapping_sub(2) & 0xffff_ffff),
            n_one: Constant::new(p.window() == 1),
            nmask: c32(mask(count_bits(p.window()))),
            hlast_m1: c32((p.hold() as u64).wrapping_sub(2) & 0xffff_ffff),
            h_one: Constant::new(p.hold() == 1),
            hmask: c32(mask(count_bits(p.hold()))),
            one: c32(1),
            zero: c32(0),
        }
    }
}

impl Logic for Monitor {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, los_reg, los_cnt, clip_reg, clip_cnt, fs_reg, fs_cnt, warn_reg, los_lx,
            clip_k, fs_k
        );
        self.mag.next = self.magnitude.val() & self.wmask.val();
        self.rs.next = bit_cast::<32, 16>(self.in_sin.val()) & self.amask.val();
        self.rc.next = bit_cast::<32, 16>(self.in_cos.val()) & self.amask.val();
        self.fs_hit.next = (self.rs.val() == self.code_min.val())
            | (self.rs.val() == self.code_max.val())
            | (self.rc.val() == self.code_min.val())
            | (self.rc.val() == self.code_max.val());
        // With W <= 31 the magnitude and the thresholds are below 2^W, so bit W of
        // 2^W + a - b is set exactly when a >= b: one carry chain of W + 1 bits per test
        // (Yosys drops the unused bits above W).
        if self.narrow.val() {
            self.low.next = !(((self.mag.val() | self.wbit.val()) - self.los_thr.val())
                & self.wbit.val())
            .any();
            self.good.next =
                (((self.mag.val() | self.wbit.val()) - self.los_rel.val()) & self.wbit.val()).any();
            self.over.next = !((self.clip_thr_w.val() - self.mag.val()) & self.wbit.val()).any();
        } else {
            self.low.next = self.mag.val() < self.los_thr.val();
            self.good.next = self.mag.val() >= self.los_rel.val();
            self.over.next = self.mag.val() > self.clip_thr.val();
        }
        // Each counter's "at its last value" flag is a register kept with the counter:
        // cleared with it, and on a step to cnt + 1 set from cnt == last - 1 (the value
        // before the step), so the flags and the counters' next values are one level of
        // logic after the threshold tests. Stored XOR its value at counter 0 (N = 1 or
        // H = 1), so the power-up 0 is right.
        self.los_last.next = self.los_lx.q.val() ^ self.n_one.val();
        self.los_q.next = self.low.val();
        if self.los_reg.q.val() {
            self.los_q.next = self.good.val();
        }
        // The counter's next value and flag as (good & A) | (low & B), A and B from
        // registers only, so the threshold tests' carry chains are not followed by the
        // low/good selection.
        self.los_inc.next = (self.los_cnt.q.val() + self.one.val()) & self.nmask.val();
        self.los_nx.next = (self.los_cnt.q.val() == self.nlast_m1.val()) ^ self.n_one.val();
        self.los_ga.next = self.zero.val();
        self.los_la.next = self.zero.val();
        if !self.los_last.val() {
            if self.los_reg.q.val() {
                self.los_ga.next = self.los_inc.val();
            } else {
                self.los_la.next = self.los_inc.val();
            }
        }
        self.los_gx.next = !self.los_last.val() & self.los_reg.q.val() & self.los_nx.val();
        self.los_lx_l.next = !self.los_last.val() & !self.los_reg.q.val() & self.los_nx.val();
        self.los_gv.next = self.zero.val();
        if self.good.val() {
            self.los_gv.next = self.los_ga.val();
        }
        self.los_lv.next = self.zero.val();
        if self.low.val() {
            self.los_lv.next = self.los_la.val();
        }
        if self.mag_valid.val() {
            // Loss of signal: N consecutive low (good) samples set (clear) it; any other
            // sample clears the counter.
            self.los_reg.d.next = self.los_reg.q.val() ^ (self.los_q.val() & self.los_last.val());
            self.los_cnt.d.next = self.los_gv.val() | self.los_lv.val();
            self.los_lx.d.next =
                (self.good.val() & self.los_gx.val()) | (self.low.val() & self.los_lx_l.val());
            // Clipping: set at once, clear after H clean samples. clip_k = clip & the
            // counter below H - 1, so clip' = over | clip_k. While clip = 0 the counter is
            // 0, so loading 0 there is the same as holding it.
            self.clip_reg.d.next = self.over.val() | self.clip_k.q.val();
            self.clip_cnt.d.next = self.zero.val();
            if self.over.val() {
                self.clip_k.d.next = !self.h_one.val();
            } else if self.clip_k.q.val() {
                self.clip_cnt.d.next = (self.clip_cnt.q.val() + self.one.val()) & self.hmask.val();
                self.clip_k.d.next = self.clip_cnt.q.val() != self.hlast_m1.val();
            } else {
                self.clip_k.d.next = false;
            }
        }
        if self.in_valid.val() {
            // Full scale: set at once, clear after H clean raw samples (as clip).
            self.fs_reg.d.next = self.fs_hit.val() | self.fs_k.q.val();
            self.fs_cnt.d.next = self.zero.val();
            if self.fs_hit.val() {
                self.fs_k.d.next = !self.h_one.val();
            } else if self.fs_k.q.val() {
                self.fs_cnt.d.next = (self.fs_cnt.q.val() + self.one.val()) & self.hmask.val();
                self.fs_k.d.next = self.fs_cnt.q.val() != self.hlast_m1.val();
            } else {
                self.fs_k.d.next = false;
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
            self.los_lx.d.next = false;
            self.clip_k.d.next = false;
            self.fs_k.d.next = false;
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
