//! rust-hdl description of the SPI ADC controller (see the module docs of `adc` for the
//! frame, the timing maths and the ports).
//!
//! Every register (counters, pins, shift registers, outputs) loads at the same clock edge
//! from the *next* counter state, so the pins in a clock cycle always match the counter
//! values of that cycle (no decode glitches on SCK or CONV, no hidden one-clock skew).
//!
//! For timing (docs/timing.md) the decodes in front of the counters are registers: the
//! lead clock (`atl`, computed from the next values of the period counter's flags), the
//! cycle counter's equality tests (`ewa_lo` ..., exact wherever they are used because the
//! cycle counter never changes in the clock before a step when D >= 2), and the period
//! counter's tests compare only its ceil(log2 P) low bits. `run` (enable and not reset)
//! is the outermost test of every register, so it is the flip-flops' synchronous reset or
//! one LUT in front of their data inputs.
use super::{AdcParams, SignFormat};
use crate::blocks::init_bit::InitBit;
use crate::blocks::mask;
use rust_hdl::prelude::*;

mod frame_check;
mod update;

pub use frame_check::FrameChecker;

fn c16(v: u64) -> Constant<Bits<16>> {
    Constant::new(Bits::<16>::from(v & 0xffff))
}

fn c8(v: u64) -> Constant<Bits<8>> {
    Constant::new(Bits::<8>::from(v & 0xff))
}

fn c4(v: u64) -> Constant<Bits<4>> {
    Constant::new(Bits::<4>::from(v & 0xf))
}

/// A window flag's constants: a predicate `lo <= c < hi` on a counter `c` in `0..=top`
/// that, each clock, reloads to 0, holds, or steps to `c + 1` (only from `c < top`).
///
/// Stepping, `c + 1` is in the range exactly when `c == lo - 1`, or when `c` is in it and
/// `c != hi - 1`: two equality tests on the old counter and the old flag, no compare after
/// the increment. `lo - 1` and `hi - 1` outside `0..top` become `top`, a value never
/// stepped from, so their tests are never true; an empty range never sets the flag.
struct Win {
    /// lo - 1 (or `top`).
    lo_m1: u64,
    /// hi - 1 (or `top`).
    hi_m1: u64,
    /// The predicate at c = 0 (the power-up and reload value).
    at_zero: bool,
    /// The predicate at c = top.
    at_top: bool,
}

impl Win {
    fn new(lo: u64, hi: u64, top: u64) -> Self {
        if lo >= hi {
            return Self {
                lo_m1: top,
                hi_m1: top,
                at_zero: false,
                at_top: false,
            };
        }
        let inside = |v: u64| if v < top { v } else { top };
        Self {
            lo_m1: if lo == 0 { top } else { inside(lo - 1) },
            hi_m1: inside(hi - 1),
            at_zero: lo == 0,
            at_top: lo <= top && top < hi,
        }
    }
}

/// SPI ADC controller: CONV pulse, SCK divider, frame capture, sample strobe.
#[derive(LogicBlock)]
pub struct AdcController {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: pins idle, counters and outputs cleared.
    pub rst: Signal<In, Bit>,
    /// Run enable; low behaves like reset (hold low until the preamp set-up is done).
    pub enable: Signal<In, Bit>,
    /// Serial data from the ADC (line A: every channel with one line, channel 0 with two).
    pub adc_miso: Signal<In, Bit>,
    /// Serial data line B (channel 1) of a two-line ADC; absent (length 0) with one line.
    pub adc_miso_b: Vec<Signal<In, Bit>>,
    /// Serial clock to the ADC.
    pub adc_sck: Signal<Out, Bit>,
    /// Conversion start (or chip select) to the ADC.
    pub adc_conv: Signal<Out, Bit>,
    /// One-clock strobe: a new sample pair is on out_ch0 / out_ch1.
    pub out_valid: Signal<Out, Bit>,
    /// Channel 0 sample: W-bit two's complement in the low bits, upper bits zero.
    pub out_ch0: Signal<Out, Bits<16>>,
    /// Channel 1 sample (zero with one channel).
    pub out_ch1: Signal<Out, Bits<16>>,
    /// The last delivered frame had every data line stuck (`frame_check`): one output with
    /// [`AdcController::with_frame_check`], none otherwise.
    pub frame_error: Vec<Signal<Out, Bit>>,
    /// The frame check (`[registers] enabled`): one or none.
    fcheck: Vec<FrameChecker>,
    // State.
    live: DFF<Bit>,
    pc: DFF<Bits<16>>,
    ph: DFF<Bits<8>>,
    cyc: DFF<Bits<8>>,
    warm: DFF<Bits<4>>,
    sr0: DFF<Bits<16>>,
    sr1: DFF<Bits<16>>,
    /// The SCK pin's register; it powers up at the idle level (CPOL), so the pin does not
    /// show an edge before the first frame.
    sck_reg: InitBit,
    /// The CONV/CS pin's register; it powers up inactive, so a CS-framed chip is not
    /// selected during the first clock.
    conv_reg: InitBit,
    valid_reg: DFF<Bit>,
    ch0_reg: DFF<Bits<16>>,
    ch1_reg: DFF<Bits<16>>,
    /// adc_miso registered at every edge (the input flip-flop the pad set-up budget
    /// `board.fpga_input_setup_ns` is for). A capture state S samples it at the edge one
    /// clock after S is entered (`MISO_SAMPLE_LAG_CLOCKS`), the edge that also moves the
    /// pins of S: D clocks after the pin edge that shifted the bit out.
    miso_d: DFF<Bit>,
    /// adc_miso_b registered the same way (length 1 with two lines, else 0): channel 1's
    /// bits, sampled at the same edge as line A's.
    miso_b_d: Vec<DFF<Bit>>,
    /// rst one clock late: the data registers are cleared with the pins, one clock after
    /// the state (see the module docs).
    rst_d: DFF<Bit>,
    /// The capture enables of the state entered at the previous edge, registered, so the
    /// shift (one clock after miso_d sampled the bit) and the sample strobe follow the
    /// capture state by two clocks: channel 0, channel 1, and the last slot of a frame
    /// that is delivered (warm-up over).
    cap0_d: DFF<Bit>,
    cap1_d: DFF<Bit>,
    capv_d: DFF<Bit>,
    /// The state entered at the previous edge starts an SCK frame (pc_n == lead): decoded
    /// from `atl`.
    at_lead: Signal<Local, Bit>,
    /// at_lead ^ (lead = 0), registered: at_lead of the next state is computed from the
    /// next values of live, pcl_x and pcm_x (see `update`), so the counters' reloads and
    /// the window flags start from a flip-flop (0 at power-up, where at_lead = (lead = 0)).
    atl: DFF<Bit>,
    /// Next value of pcl_x (see `pcl_x`).
    pcl_n: Signal<Local, Bit>,
    /// Next value of pcm_x.
    pcm_n: Signal<Local, Bit>,
    /// at_lead of the next state.
    atl_n: Signal<Local, Bit>,
    /// pc == P - 2 (pc's low bits: pc <= P - 1 always).
    pc_eqp: Signal<Local, Bit>,
    /// pc == lead - 2.
    pc_eql: Signal<Local, Bit>,
    /// at_lead of the next state when running and pc does not step: kl ? (lead = 0) : km.
    atl_idle: Constant<Bit>,
    /// Equality tests of the cycle counter, registered every clock, so each holds the test
    /// of the current `cyc` whenever `cyc` was the same one clock before. The counters step
    /// (`cinc`) only at ph = D - 1, and every change of `cyc` puts ph at 0, so with D >= 2
    /// (checked by `AdcParams::validate`) `cyc` never changes in the clock before a step
    /// and the tests used there are exact: cyc == lo - 1 and cyc == hi - 1 per window flag,
    /// cyc == frame (the step onto the stop value).
    ewa_lo: DFF<Bit>,
    ewa_hi: DFF<Bit>,
    ew0_lo: DFF<Bit>,
    ew0_hi: DFF<Bit>,
    ew1_lo: DFF<Bit>,
    ew1_hi: DFF<Bit>,
    ewl_lo: DFF<Bit>,
    ewl_hi: DFF<Bit>,
    est: DFF<Bit>,
    // Next-state values.
    run: Signal<Local, Bit>,
    pc_n: Signal<Local, Bits<16>>,
    /// (pc == P - 1) ^ kl, registered with pc (taken on pc before its step; the XOR with
    /// a constant makes the power-up 0 right for pc = 0).
    pcl_x: DFF<Bit>,
    /// (pc == lead - 1) ^ km, registered with pc.
    pcm_x: DFF<Bit>,
    /// pc == P - 1 (the last value of the period counter).
    fl: Signal<Local, Bit>,
    /// pc == lead - 1.
    fm: Signal<Local, Bit>,
    ph_n: Signal<Local, Bits<8>>,
    cyc_n: Signal<Local, Bits<8>>,
    warm_n: Signal<Local, Bits<4>>,
    sck_act: Signal<Local, Bit>,
    conv_act: Signal<Local, Bit>,
    cap: Signal<Local, Bit>,
    /// Window flags of the state entered at the previous edge, each a predicate on `cyc`
    /// or `ph` registered with it and XORed with its value at power-up (cyc = ph = 0), so a
    /// zero register is right then. They are updated from equality tests on the old
    /// counter (see [`Win`]) instead of compares after it, so the capture enables are a
    /// register each: cyc < frame (SCK active part), slots of ch0, ch1 and the last slot
    /// (each intersected with 1..=frame, the capture range).
    wa: DFF<Bit>,
    w0: DFF<Bit>,
    w1: DFF<Bit>,
    wl: DFF<Bit>,
    /// ph >= L (SCK at its active level) and ph == capture phase, the same way.
    wb: DFF<Bit>,
    wc: DFF<Bit>,
    /// cyc == frame + 1 (the stop value), registered with cyc from its value before the
    /// step (0 at cyc = 0, the power-up value).
    cst: DFF<Bit>,
    /// (ph == D - 1) ^ (D == 1), registered with ph the same way.
    plx: DFF<Bit>,
    /// ph == D - 1 (decoded).
    pl_end: Signal<Local, Bit>,
    /// The decoded predicates (flag XOR power-up value).
    pa: Signal<Local, Bit>,
    p0: Signal<Local, Bit>,
    p1: Signal<Local, Bit>,
    pl: Signal<Local, Bit>,
    pb: Signal<Local, Bit>,
    pcp: Signal<Local, Bit>,
    /// The cycle and phase counters step (cyc + 1 / ph + 1) at this edge.
    cinc: Signal<Local, Bit>,
    pinc: Signal<Local, Bit>,
    /// Counters reload at this edge: cyc to 0 and ph to 0 (at the lead clock; ph also at
    /// the end of an SCK cycle).
    crel: Signal<Local, Bit>,
    prel: Signal<Local, Bit>,
    /// Per flag: lo - 1 and hi - 1 of its range [lo, hi) (a counter value never stepped
    /// from when there is none), its value at power-up (0) and at the stop value
    /// (cyc = frame + 1, where a stopped controller parks).
    wa_lo: Constant<Bits<8>>,
    wa_hi: Constant<Bits<8>>,
    wa_z: Constant<Bit>,
    wa_s: Constant<Bit>,
    w0_lo: Constant<Bits<8>>,
    w0_hi: Constant<Bits<8>>,
    w0_z: Constant<Bit>,
    w0_s: Constant<Bit>,
    w1_lo: Constant<Bits<8>>,
    w1_hi: Constant<Bits<8>>,
    w1_z: Constant<Bit>,
    w1_s: Constant<Bit>,
    wl_lo: Constant<Bits<8>>,
    wl_hi: Constant<Bits<8>>,
    wl_z: Constant<Bit>,
    wl_s: Constant<Bit>,
    wb_lo: Constant<Bits<8>>,
    wb_hi: Constant<Bits<8>>,
    wb_z: Constant<Bit>,
    wc_lo: Constant<Bits<8>>,
    wc_hi: Constant<Bits<8>>,
    wc_z: Constant<Bit>,
    shifted0: Signal<Local, Bits<16>>,
    shifted1: Signal<Local, Bits<16>>,
    sr0_n: Signal<Local, Bits<16>>,
    sr1_n: Signal<Local, Bits<16>>,
    /// Lead clocks: period counter value at which SCK cycle 0 starts.
    lead: Constant<Bits<16>>,
    /// CONV active while the period counter is below this.
    conv_end: Constant<Bits<16>>,
    /// D - 2: the phase before a step onto D - 1 (never stepped from when D = 1).
    d_last_m1: Constant<Bits<8>>,
    /// D = 1: ph == D - 1 at ph = 0.
    d_one: Constant<Bit>,
    /// Frame + 1: the SCK cycle counter stops here.
    cyc_stop: Constant<Bits<8>>,
    /// Frame: the cycle before the stop value.
    cyc_stop_m1: Constant<Bits<8>>,
    /// Periods to run before delivering: 1 flush period + pipeline discarded frames.
    warm_init: Constant<Bits<4>>,
    /// Mask of the W sample bits.
    wmask: Constant<Bits<16>>,
    /// MSB flip for offset binary (0 for two's complement).
    flip: Constant<Bits<16>>,
    /// SCK idle level (CPOL).
    cpol: Constant<Bit>,
    /// CONV inactive level.
    conv_idle: Constant<Bit>,
    /// lead = 0.
    lead_zero: Constant<Bit>,
    /// P - 2 and lead - 2: pc before a step onto P - 1 and lead - 1 (lead = 0: never reached).
    p_last_m1: Constant<Bits<16>>,
    lead_m2: Constant<Bits<16>>,
    /// Mask of the period counter's bits (pc <= P - 1 always, so its equality tests need
    /// only these).
    pc_mask: Constant<Bits<16>>,
    /// P - 1 == 0 and lead - 1 == 0: the flags' values at pc = 0.
    kl: Constant<Bit>,
    km: Constant<Bit>,
    /// One channel only: ch1 reads 0.
    one_ch: Constant<Bit>,
    one16: Constant<Bits<16>>,
    zero16: Constant<Bits<16>>,
    one8: Constant<Bits<8>>,
    zero8: Constant<Bits<8>>,
    one4: Constant<Bits<4>>,
    zero4: Constant<Bits<4>>,
}

impl AdcController {
    /// Controller for validated parameters (validate them first: `new` does not check).
    pub fn new(p: &AdcParams) -> Self {
        let f = &p.frame;
        let w = f.width as u64;
        let (_, last) = p.data_slots();
        let (ch1_first, ch1_end) = if f.channels >= 2 {
            (f.offsets[1] as u64, (f.offsets[1] + f.width) as u64)
        } else {
            (0, 0)
        };
        // Window flags (see `Win`): cyc in 0..=frame + 1, ph in 0..=D - 1. The capture
        // range of slots is 1..=frame (cycle k + 1 holds slot k).
        let stop = f.frame_sck as u64 + 1;
        let d_last = p.sck_period_clocks.saturating_sub(1) as u64;
        let cap_in = |lo: u64, hi: u64| Win::new(lo.max(1), hi.min(stop), stop);
        let wa = Win::new(0, f.frame_sck as u64, stop);
        let w0 = cap_in(f.offsets[0] as u64 + 1, (f.offsets[0] + f.width) as u64 + 1);
        let w1 = cap_in(ch1_first + 1, ch1_end + 1);
        let wl = cap_in(last as u64 + 1, last as u64 + 2);
        let wb = Win::new(p.sck_low_clocks() as u64, d_last + 1, d_last);
        let wc = Win::new(
            p.capture_phase() as u64,
            p.capture_phase() as u64 + 1,
            d_last,
        );
        Self {
            clk: Default::default(),
            rst: Default::default(),
            enable: Default::default(),
            adc_miso: Default::default(),
            adc_miso_b: (1..f.lines.clamp(1, 2))
                .map(|_| Default::default())
                .collect(),
            adc_sck: Default::default(),
            adc_conv: Default::default(),
            out_valid: Default::default(),
            out_ch0: Default::default(),
            out_ch1: Default::default(),
            frame_error: Vec::new(),
            fcheck: Vec::new(),
            live: Default::default(),
            pc: Default::default(),
            ph: Default::default(),
            cyc: Default::default(),
            warm: Default::default(),
            sr0: Default::default(),
            sr1: Default::default(),
            sck_reg: InitBit::new(f.cpol),
            conv_reg: InitBit::new(!f.conv_active_high),
            valid_reg: Default::default(),
            ch0_reg: Default::default(),
            ch1_reg: Default::default(),
            miso_d: Default::default(),
            miso_b_d: (1..f.lines.clamp(1, 2))
                .map(|_| Default::default())
                .collect(),
            rst_d: Default::default(),
            cap0_d: Default::default(),
            cap1_d: Default::default(),
            capv_d: Default::default(),
            at_lead: Default::default(),
            atl: Default::default(),
            pcl_n: Default::default(),
            pcm_n: Default::default(),
            atl_n: Default::default(),
            pc_eqp: Default::default(),
            pc_eql: Default::default(),
            atl_idle: Constant::new(if p.period_clocks.saturating_sub(1) == 0 {
                f.lead_clocks == 0
            } else {
                f.lead_clocks == 1
            }),
            ewa_lo: Default::default(),
            ewa_hi: Default::default(),
            ew0_lo: Default::default(),
            ew0_hi: Default::default(),
            ew1_lo: Default::default(),
            ew1_hi: Default::default(),
            ewl_lo: Default::default(),
            ewl_hi: Default::default(),
            est: Default::default(),
            run: Default::default(),
            pc_n: Default::default(),
            pcl_x: Default::default(),
            pcm_x: Default::default(),
            fl: Default::default(),
            fm: Default::default(),
            ph_n: Default::default(),
            cyc_n: Default::default(),
            warm_n: Default::default(),
            sck_act: Default::default(),
            conv_act: Default::default(),
            cap: Default::default(),
            wa: Default::default(),
            w0: Default::default(),
            w1: Default::default(),
            wl: Default::default(),
            wb: Default::default(),
            wc: Default::default(),
            cst: Default::default(),
            plx: Default::default(),
            pl_end: Default::default(),
            pa: Default::default(),
            p0: Default::default(),
            p1: Default::default(),
            pl: Default::default(),
            pb: Default::default(),
            pcp: Default::default(),
            cinc: Default::default(),
            pinc: Default::default(),
            crel: Default::default(),
            prel: Default::default(),
            wa_lo: c8(wa.lo_m1),
            wa_hi: c8(wa.hi_m1),
            wa_z: Constant::new(wa.at_zero),
            wa_s: Constant::new(wa.at_top),
            w0_lo: c8(w0.lo_m1),
            w0_hi: c8(w0.hi_m1),
            w0_z: Constant::new(w0.at_zero),
            w0_s: Constant::new(w0.at_top),
            w1_lo: c8(w1.lo_m1),
            w1_hi: c8(w1.hi_m1),
            w1_z: Constant::new(w1.at_zero),
            w1_s: Constant::new(w1.at_top),
            wl_lo: c8(wl.lo_m1),
            wl_hi: c8(wl.hi_m1),
            wl_z: Constant::new(wl.at_zero),
            wl_s: Constant::new(wl.at_top),
            wb_lo: c8(wb.lo_m1),
            wb_hi: c8(wb.hi_m1),
            wb_z: Constant::new(wb.at_zero),
            wc_lo: c8(wc.lo_m1),
            wc_hi: c8(wc.hi_m1),
            wc_z: Constant::new(wc.at_zero),
            shifted0: Default::default(),
            shifted1: Default::default(),
            sr0_n: Default::default(),
            sr1_n: Default::default(),
            lead: c16(f.lead_clocks as u64),
            conv_end: c16(p.conv_clocks as u64),
            d_last_m1: c8((p.sck_period_clocks.saturating_sub(1) as u64).wrapping_sub(1) & 0xff),
            d_one: Constant::new(p.sck_period_clocks.saturating_sub(1) == 0),
            cyc_stop: c8(f.frame_sck as u64 + 1),
            cyc_stop_m1: c8(f.frame_sck as u64),
            warm_init: c4(1 + f.pipeline as u64),
            wmask: c16(mask(w as u32)),
            flip: c16(match f.sign {
                SignFormat::TwosComplement => 0,
                SignFormat::OffsetBinary => 1 << (w - 1),
            }),
            cpol: Constant::new(f.cpol),
            conv_idle: Constant::new(!f.conv_active_high),
            lead_zero: Constant::new(f.lead_clocks == 0),
            p_last_m1: c16((p.period_clocks.saturating_sub(1) as u64).wrapping_sub(1) & 0xffff),
            lead_m2: c16((f.lead_clocks as u64).wrapping_sub(2) & 0xffff),
            pc_mask: c16(mask(32 - p.period_clocks.saturating_sub(1).leading_zeros())),
            kl: Constant::new(p.period_clocks.saturating_sub(1) == 0),
            km: Constant::new(f.lead_clocks == 1),
            one_ch: Constant::new(f.channels < 2),
            one16: c16(1),
            zero16: c16(0),
            one8: c8(1),
            zero8: c8(0),
            one4: c4(1),
            zero4: c4(0),
        }
    }
}

impl AdcController {
    /// [`new`](Self::new) with the frame check of `p` ([`AdcParams::frame_check`]) and its
    /// `frame_error` output (the register map's STATUS.ADC_FRAME).
    pub fn with_frame_check(p: &AdcParams) -> Self {
        let mut c = Self::new(p);
        c.frame_error = vec![Default::default()];
        c.fcheck = vec![FrameChecker::new(&p.frame_check())];
        c
    }
}

impl crate::cosim::step::Clocked for AdcController {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for AdcController {
    fn input_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        let mut v = vec![
            Port::new("rst", 1),
            Port::new("enable", 1),
            Port::new("adc_miso", 1),
        ];
        v.extend((0..self.adc_miso_b.len()).map(|k| Port::new(&format!("adc_miso_b_{k}"), 1)));
        v
    }
    fn output_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        let mut v = vec![
            Port::new("adc_sck", 1),
            Port::new("adc_conv", 1),
            Port::new("out_valid", 1),
            Port::new("out_ch0", 16),
            Port::new("out_ch1", 16),
        ];
        v.extend((0..self.frame_error.len()).map(|k| Port::new(&format!("frame_error_{k}"), 1)));
        v
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r.first().copied().unwrap_or(0) != 0;
        self.enable.next = r.get(1).copied().unwrap_or(0) != 0;
        self.adc_miso.next = r.get(2).copied().unwrap_or(0) != 0;
        for (k, s) in self.adc_miso_b.iter_mut().enumerate() {
            s.next = r.get(3 + k).copied().unwrap_or(0) != 0;
        }
    }
    fn sample(&self) -> Vec<u64> {
        let mut v = vec![
            self.adc_sck.val() as u64,
            self.adc_conv.val() as u64,
            self.out_valid.val() as u64,
            self.out_ch0.val().to_u64(),
            self.out_ch1.val().to_u64(),
        ];
        v.extend(self.frame_error.iter().map(|s| s.val() as u64));
        v
    }
}
