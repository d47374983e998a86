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
    /// Run-time loss-of-signal threshold (one with `run_time_thresholds`, none without:
    /// the configured constant), magnitude units, low W bits used.
    pub thr_los: Vec<Signal<In, Bits<32>>>,
    /// Run-time loss-of-signal release level, as `thr_los`.
    pub thr_rel: Vec<Signal<In, Bits<32>>>,
    /// Run-time clipping threshold, as `thr_los`.
    pub thr_clip: Vec<Signal<In, Bits<32>>>,
    los_reg: DFF<Bit>,
    los_cnt: DFF<Bits<32>>,
    /// The last magnitude sample was over the clipping threshold (clip = clip_reg | clip_b:
    /// the threshold test's chain reaches this register and nothing else).
    clip_reg: DFF<Bit>,
    /// Clean magnitude samples since clip was set, stored one magnitude sample step behind
    /// (the step of the last sample is applied at the next edge, from clip_pv and
    /// clip_reg), as fs_cnt.
    clip_cnt: DFF<Bits<32>>,
    /// The sine of the last raw sample (in_valid) was at a full-scale code.
    fs_reg: DFF<Bit>,
    /// The cosine of the last raw sample was at a full-scale code (full_scale = fs_reg |
    /// fs_c | fs_b: each code test is one register, 14 input bits at A = 14).
    fs_c: DFF<Bit>,
    /// Clean raw samples since full_scale was set, stored one raw sample step behind (the
    /// step of the last sample is applied at the next edge, from fs_pv and fs_reg).
    fs_cnt: DFF<Bits<32>>,
    warn_reg: DFF<Bit>,
    /// (los_cnt == N-1) ^ (N == 1), registered with the counter from its value before the
    /// step (see `update`), so no compare follows the counter's adder; 0 at power-up and
    /// whenever the counter is 0. los_cnt, los_lx and los_nxr lag one clock behind the
    /// magnitude samples: a sample's effect on them is held in los_pv / los_pq and applied
    /// at the next edge (the *logical* counter is the one with it applied), so the
    /// threshold tests' carry chains reach only los_reg and los_pq, through one LUT.
    los_lx: DFF<Bit>,
    /// (los_cnt == N-2) ^ (N == 2), registered with the counter (0 at counter 0).
    los_nxr: DFF<Bit>,
    /// A magnitude sample was taken at the previous edge (its counter step is pending).
    los_pv: DFF<Bit>,
    /// That sample counted towards the window (low while los = 0, good while los = 1).
    los_pq: DFF<Bit>,
    /// clip = 1 and clip_cnt < H-1 (one more clean sample keeps clip set), stored one
    /// magnitude sample step behind with clip_cnt.
    clip_k: DFF<Bit>,
    /// clip held by the counter: the logical clip_k at the last magnitude sample.
    clip_b: DFF<Bit>,
    /// A magnitude sample was taken at the previous edge (its hold counter step is pending).
    clip_pv: DFF<Bit>,
    /// The logical hold counter of clip (the pending step applied), clip_cnt's next value.
    clip_cl: Signal<Local, Bits<32>>,
    /// The logical clip_k, its next value.
    clip_kl: Signal<Local, Bit>,
    /// full_scale = 1 and fs_cnt < H-1 (the next clean raw sample keeps full_scale set),
    /// stored one raw sample step behind with fs_cnt.
    fs_k: DFF<Bit>,
    /// full_scale held by the counter: the logical fs_k at the last raw sample.
    fs_b: DFF<Bit>,
    /// A raw sample was taken at the previous edge (its counter step is pending).
    fs_pv: DFF<Bit>,
    /// The logical full-scale counter (the pending step applied), fs_cnt's next value.
    fs_cl: Signal<Local, Bits<32>>,
    /// The logical fs_k, fs_k's next value and fs_b's on a raw sample.
    fs_kl: Signal<Local, Bit>,
    /// Stored los_cnt == N-1 (decoded los_lx, before the pending step).
    los_last: Signal<Local, Bit>,
    /// The sample counts towards the los window (low while los = 0, good while los = 1).
    los_q: Signal<Local, Bit>,
    /// Stored los_cnt + 1.
    los_inc: Signal<Local, Bits<32>>,
    /// The counter after a counting step from the stored one: 0 at N-1, else los_inc.
    los_x: Signal<Local, Bits<32>>,
    /// los_lx after a counting step: the stored counter is N-2.
    los_y: Signal<Local, Bit>,
    /// The counter after a counting step is N-2.
    los_ny: Signal<Local, Bit>,
    /// The logical counter (the pending step applied), los_cnt's next value.
    los_cl: Signal<Local, Bits<32>>,
    /// The logical los_lx, its next value.
    los_ll: Signal<Local, Bit>,
    /// The logical counter is N-2 (los_nxr's next value XOR (N == 2)).
    los_nl: Signal<Local, Bit>,
    /// The logical counter is N-1: this sample, if it counts, toggles los.
    los_lend: Signal<Local, Bit>,
    /// A good sample at the window's end while los = 1 (and no reset): los clears.
    los_clr: Signal<Local, Bit>,
    /// mag < los_threshold.
    low: Signal<Local, Bit>,
    /// mag >= los_release.
    good: Signal<Local, Bit>,
    mag: Signal<Local, Bits<32>>,
    rs: Signal<Local, Bits<32>>,
    rc: Signal<Local, Bits<32>>,
    /// The sine is at a full-scale code.
    fs_hit: Signal<Local, Bit>,
    /// The cosine is at a full-scale code.
    fs_hc: Signal<Local, Bit>,
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
    /// N-3: the counter value before a step onto N-2 (never reached when N <= 2).
    nlast_m2: Constant<Bits<32>>,
    /// N = 2: the counter is N-2 at 0.
    n_two: Constant<Bit>,
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
            thr_los: (0..usize::from(p.run_time_thresholds()))
                .map(|_| Default::default())
                .collect(),
            thr_rel: (0..usize::from(p.run_time_thresholds()))
                .map(|_| Default::default())
                .collect(),
            thr_clip: (0..usize::from(p.run_time_thresholds()))
                .map(|_| Default::default())
                .collect(),
            los_reg: Default::default(),
            los_cnt: Default::default(),
            clip_reg: Default::default(),
            clip_cnt: Default::default(),
            fs_reg: Default::default(),
            fs_cnt: Default::default(),
            warn_reg: Default::default(),
            los_lx: Default::default(),
            los_nxr: Default::default(),
            los_pv: Default::default(),
            los_pq: Default::default(),
            clip_k: Default::default(),
            clip_b: Default::default(),
            clip_pv: Default::default(),
            clip_cl: Default::default(),
            clip_kl: Default::default(),
            fs_k: Default::default(),
            fs_b: Default::default(),
            fs_c: Default::default(),
            fs_pv: Default::default(),
            fs_cl: Default::default(),
            fs_kl: Default::default(),
            los_last: Default::default(),
            los_q: Default::default(),
            los_inc: Default::default(),
            los_x: Default::default(),
            los_y: Default::default(),
            los_ny: Default::default(),
            los_cl: Default::default(),
            los_ll: Default::default(),
            los_nl: Default::default(),
            los_lend: Default::default(),
            los_clr: Default::default(),
            low: Default::default(),
            good: Default::default(),
            mag: Default::default(),
            rs: Default::default(),
            rc: Default::default(),
            fs_hit: Default::default(),
            fs_hc: Default::default(),
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
            nlast_m2: c32((p.window() as u64).wrapping_sub(3) & 0xffff_ffff),
            n_two: Constant::new(p.window() == 2),
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
            clip_k, fs_k, los_nxr, los_pv, los_pq, fs_b, fs_c, fs_pv, clip_b, clip_pv
        );
        self.mag.next = self.magnitude.val() & self.wmask.val();
        self.rs.next = bit_cast::<32, 16>(self.in_sin.val()) & self.amask.val();
        self.rc.next = bit_cast::<32, 16>(self.in_cos.val()) & self.amask.val();
        // A full-scale code is 1 then A-1 zeros or 0 then A-1 ones: the low A-1 bits are all
        // ones when low + 1 carries into bit A-1, and all zeros when low + 2^(A-1) - 1 does
        // not. Two carry chains per sample word, entered from its register and followed by
        // one LUT of three inputs (Yosys cannot spread that over several levels, as it can
        // an A-bit equality).
        self.fs_hit.next = ((((self.rs.val() & self.code_max.val()) + self.one.val())
            & self.code_min.val())
        .any()
            & !(self.rs.val() & self.code_min.val()).any())
            | (!(((self.rs.val() & self.code_max.val()) + self.code_max.val())
                & self.code_min.val())
            .any()
                & (self.rs.val() & self.code_min.val()).any());
        self.fs_hc.next = ((((self.rc.val() & self.code_max.val()) + self.one.val())
            & self.code_min.val())
        .any()
            & !(self.rc.val() & self.code_min.val()).any())
            | (!(((self.rc.val() & self.code_max.val()) + self.code_max.val())
                & self.code_min.val())
            .any()
                & (self.rc.val() & self.code_min.val()).any());
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
        // Run-time thresholds (`[registers]`): the same tests on the ports' W bits.
        for i in 0..self.thr_los.len() {
            if self.narrow.val() {
                self.low.next = !(((self.mag.val() | self.wbit.val())
                    - (self.thr_los[i].val() & self.wmask.val()))
                    & self.wbit.val())
                .any();
                self.good.next = (((self.mag.val() | self.wbit.val())
                    - (self.thr_rel[i].val() & self.wmask.val()))
                    & self.wbit.val())
                .any();
                self.over.next = !((((self.thr_clip[i].val() & self.wmask.val())
                    | self.wbit.val())
                    - self.mag.val())
                    & self.wbit.val())
                .any();
            } else {
                self.low.next = self.mag.val() < self.thr_los[i].val();
                self.good.next = self.mag.val() >= self.thr_rel[i].val();
                self.over.next = self.mag.val() > self.thr_clip[i].val();
            }
        }
        // Each counter's "at its last value" flag is a register kept with the counter:
        // cleared with it, and on a step to cnt + 1 set from cnt == last - 1 (the value
        // before the step), so no compare follows an adder. Stored XOR its value at counter
        // 0 (N = 1 or H = 1), so the power-up 0 is right.
        self.los_q.next = self.low.val();
        if self.los_reg.q.val() {
            self.los_q.next = self.good.val();
        }
        // Loss-of-signal counter: the stored registers lag one sample step (los_pv,
        // los_pq); the logical values apply it, from registers only, so the threshold
        // tests are followed by one LUT (los_reg's and los_pq's next values) and the
        // counter's update never waits for them.
        self.los_last.next = self.los_lx.q.val() ^ self.n_one.val();
        self.los_inc.next = (self.los_cnt.q.val() + self.one.val()) & self.nmask.val();
        self.los_x.next = self.zero.val();
        self.los_ny.next = self.n_two.val();
        if !self.los_last.val() {
            self.los_x.next = self.los_inc.val();
            self.los_ny.next = self.los_cnt.q.val() == self.nlast_m2.val();
        }
        self.los_y.next = !self.los_last.val() & (self.los_nxr.q.val() ^ self.n_two.val());
        self.los_cl.next = self.los_cnt.q.val();
        self.los_ll.next = self.los_lx.q.val();
        self.los_nl.next = self.los_nxr.q.val() ^ self.n_two.val();
        if self.los_pv.q.val() {
            self.los_cl.next = self.zero.val();
            self.los_ll.next = false;
            self.los_nl.next = self.n_two.val();
            if self.los_pq.q.val() {
                self.los_cl.next = self.los_x.val();
                self.los_ll.next = self.los_y.val();
                self.los_nl.next = self.los_ny.val();
            }
        }
        self.los_lend.next = self.los_ll.val() ^ self.n_one.val();
        self.los_cnt.d.next = self.los_cl.val();
        self.los_lx.d.next = self.los_ll.val();
        self.los_nxr.d.next = self.los_nl.val() ^ self.n_two.val();
        self.los_pv.d.next = self.mag_valid.val();
        self.los_pq.d.next = self.los_q.val();
        // The clip hold counter and clip_k apply a magnitude sample's step at the next edge
        // (clip_pv), from registers only. clip_k = clip & the counter below H - 1 (the next
        // clean sample keeps clip set). While clip = 0 the counter is 0, so loading 0 there
        // is the same as holding it.
        self.clip_cl.next = self.clip_cnt.q.val();
        self.clip_kl.next = self.clip_k.q.val();
        if self.clip_pv.q.val() {
            if self.clip_reg.q.val() {
                self.clip_cl.next = self.zero.val();
                self.clip_kl.next = !self.h_one.val();
            } else if self.clip_k.q.val() {
                self.clip_cl.next = (self.clip_cnt.q.val() + self.one.val()) & self.hmask.val();
                self.clip_kl.next = self.clip_cnt.q.val() != self.hlast_m1.val();
            } else {
                self.clip_cl.next = self.zero.val();
                self.clip_kl.next = false;
            }
        }
        self.clip_cnt.d.next = self.clip_cl.val();
        self.clip_k.d.next = self.clip_kl.val();
        self.clip_pv.d.next = self.mag_valid.val();
        if self.mag_valid.val() {
            // Loss of signal: N consecutive low (good) samples set (clear) it; any other
            // sample clears the counter; the counter's step is pending until the next edge
            // (see above).
            // los = 0: set by a low sample at the window's end; los = 1: held here and
            // cleared by los_clr below (a good sample at the window's end).
            self.los_reg.d.next = self.los_reg.q.val() | (self.low.val() & self.los_lend.val());
            // Clipping: set at once, clear after H clean samples, as full scale below:
            // clip_reg takes the threshold test (the only logic after the magnitude),
            // clip_b the hold by the counter.
            self.clip_reg.d.next = self.over.val();
            self.clip_b.d.next = self.clip_kl.val();
        }
        // Full scale: set at once, clear after H clean raw samples (as clip), as two
        // registers: fs_reg takes the code test of each raw sample (the only logic after
        // the sample), fs_b the hold by the counter; the counter and fs_k apply a sample's
        // step at the next edge (fs_pv), from registers only.
        self.fs_cl.next = self.fs_cnt.q.val();
        self.fs_kl.next = self.fs_k.q.val();
        if self.fs_pv.q.val() {
            if self.fs_reg.q.val() | self.fs_c.q.val() {
                self.fs_cl.next = self.zero.val();
                self.fs_kl.next = !self.h_one.val();
            } else if self.fs_k.q.val() {
                self.fs_cl.next = (self.fs_cnt.q.val() + self.one.val()) & self.hmask.val();
                self.fs_kl.next = self.fs_cnt.q.val() != self.hlast_m1.val();
            } else {
                self.fs_cl.next = self.zero.val();
                self.fs_kl.next = false;
            }
        }
        self.fs_cnt.d.next = self.fs_cl.val();
        self.fs_k.d.next = self.fs_kl.val();
        self.fs_pv.d.next = self.in_valid.val();
        if self.in_valid.val() {
            self.fs_reg.d.next = self.fs_hit.val();
            self.fs_c.d.next = self.fs_hc.val();
            self.fs_b.d.next = self.fs_kl.val();
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
            self.los_nxr.d.next = false;
            self.los_pv.d.next = false;
            self.los_pq.d.next = false;
            self.clip_k.d.next = false;
            self.clip_b.d.next = false;
            self.clip_pv.d.next = false;
            self.fs_k.d.next = false;
            self.fs_b.d.next = false;
            self.fs_c.d.next = false;
            self.fs_pv.d.next = false;
        }
        // Clearing los is the outermost assignment, a synchronous reset of los_reg to its
        // power-up value 0 (the reset above sets it to 1, which the flip-flop's reset
        // cannot, as its power-up value is 0): so los_reg's data input is one LUT of
        // (rst, los, low, los_lend) and its reset one LUT of (good, a register-only
        // term), each one LUT after the threshold tests' chains.
        self.los_clr.next = !self.rst.val()
            & self.mag_valid.val()
            & self.los_reg.q.val()
            & self.good.val()
            & self.los_lend.val();
        if self.los_clr.val() {
            self.los_reg.d.next = false;
        }
        self.error.next = self.los_reg.q.val()
            | self.clip_reg.q.val()
            | self.clip_b.q.val()
            | self.fs_reg.q.val()
            | self.fs_c.q.val()
            | self.fs_b.q.val();
        self.warning.next = self.warn_reg.q.val();
        self.los.next = self.los_reg.q.val();
        self.clip.next = self.clip_reg.q.val() | self.clip_b.q.val();
        self.full_scale.next = self.fs_reg.q.val() | self.fs_c.q.val() | self.fs_b.q.val();
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
        .into_iter()
        .chain(self.thr_los.iter().flat_map(|_| {
            [
                Port::new("thr_los_0", 32),
                Port::new("thr_rel_0", 32),
                Port::new("thr_clip_0", 32),
            ]
        }))
        .collect()
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
        for i in 0..self.thr_los.len() {
            self.thr_los[i].next = Bits::<32>::from(r[8] & 0xffff_ffff);
            self.thr_rel[i].next = Bits::<32>::from(r[9] & 0xffff_ffff);
            self.thr_clip[i].next = Bits::<32>::from(r[10] & 0xffff_ffff);
        }
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
