//! rust-hdl description of the SPI ADC controller (see the module docs of `adc` for the
//! frame, the timing maths and the ports).
//!
//! Every register (counters, pins, shift registers, outputs) loads at the same clock edge
//! from the *next* counter state, so the pins in a clock cycle always match the counter
//! values of that cycle (no decode glitches on SCK or CONV, no hidden one-clock skew).
use super::{AdcParams, SignFormat};
use crate::blocks::mask;
use rust_hdl::prelude::*;

fn c16(v: u64) -> Constant<Bits<16>> {
    Constant::new(Bits::<16>::from(v & 0xffff))
}

fn c8(v: u64) -> Constant<Bits<8>> {
    Constant::new(Bits::<8>::from(v & 0xff))
}

fn c4(v: u64) -> Constant<Bits<4>> {
    Constant::new(Bits::<4>::from(v & 0xf))
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
    /// Serial data from the ADC.
    pub adc_miso: Signal<In, Bit>,
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
    // State.
    live: DFF<Bit>,
    pc: DFF<Bits<16>>,
    ph: DFF<Bits<8>>,
    cyc: DFF<Bits<8>>,
    warm: DFF<Bits<4>>,
    sr0: DFF<Bits<16>>,
    sr1: DFF<Bits<16>>,
    sck_reg: DFF<Bit>,
    conv_reg: DFF<Bit>,
    valid_reg: DFF<Bit>,
    ch0_reg: DFF<Bits<16>>,
    ch1_reg: DFF<Bits<16>>,
    /// adc_miso and rst one clock late: the pins and the capture are decoded from the
    /// registered state, one clock after it is entered (see the module docs).
    miso_d: DFF<Bit>,
    rst_d: DFF<Bit>,
    /// The state entered at the previous edge starts an SCK frame (pc_n == lead).
    at_lead: Signal<Local, Bit>,
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
    shifted0: Signal<Local, Bits<16>>,
    shifted1: Signal<Local, Bits<16>>,
    sr0_n: Signal<Local, Bits<16>>,
    sr1_n: Signal<Local, Bits<16>>,
    /// Lead clocks: period counter value at which SCK cycle 0 starts.
    lead: Constant<Bits<16>>,
    /// CONV active while the period counter is below this.
    conv_end: Constant<Bits<16>>,
    /// D - 1: last SCK phase.
    d_last: Constant<Bits<8>>,
    /// L: first phase at the active SCK level.
    sck_on: Constant<Bits<8>>,
    /// Phase at which a slot is captured (L for CPHA = 1, 0 for CPHA = 0).
    cap_ph: Constant<Bits<8>>,
    /// Frame length in SCK cycles.
    frame: Constant<Bits<8>>,
    /// Frame + 1: the SCK cycle counter stops here.
    cyc_stop: Constant<Bits<8>>,
    /// First and one-past-last slot of channel 0.
    ch0_first: Constant<Bits<8>>,
    ch0_end: Constant<Bits<8>>,
    /// First and one-past-last slot of channel 1 (empty range with one channel).
    ch1_first: Constant<Bits<8>>,
    ch1_end: Constant<Bits<8>>,
    /// Slot of the last data bit (out_valid at its capture).
    last_slot: Constant<Bits<8>>,
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
        Self {
            clk: Default::default(),
            rst: Default::default(),
            enable: Default::default(),
            adc_miso: Default::default(),
            adc_sck: Default::default(),
            adc_conv: Default::default(),
            out_valid: Default::default(),
            out_ch0: Default::default(),
            out_ch1: Default::default(),
            live: Default::default(),
            pc: Default::default(),
            ph: Default::default(),
            cyc: Default::default(),
            warm: Default::default(),
            sr0: Default::default(),
            sr1: Default::default(),
            sck_reg: Default::default(),
            conv_reg: Default::default(),
            valid_reg: Default::default(),
            ch0_reg: Default::default(),
            ch1_reg: Default::default(),
            miso_d: Default::default(),
            rst_d: Default::default(),
            at_lead: Default::default(),
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
            shifted0: Default::default(),
            shifted1: Default::default(),
            sr0_n: Default::default(),
            sr1_n: Default::default(),
            lead: c16(f.lead_clocks as u64),
            conv_end: c16(p.conv_clocks as u64),
            d_last: c8(p.sck_period_clocks.saturating_sub(1) as u64),
            sck_on: c8(p.sck_low_clocks() as u64),
            cap_ph: c8(p.capture_phase() as u64),
            frame: c8(f.frame_sck as u64),
            cyc_stop: c8(f.frame_sck as u64 + 1),
            ch0_first: c8(f.offsets[0] as u64 + 1),
            ch0_end: c8((f.offsets[0] + f.width) as u64 + 1),
            ch1_first: c8(ch1_first + 1),
            ch1_end: c8(ch1_end + 1),
            last_slot: c8(last as u64 + 1),
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

impl Logic for AdcController {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, live, pc, ph, cyc, warm, sr0, sr1, sck_reg, conv_reg, valid_reg, ch0_reg,
            ch1_reg, miso_d, rst_d, pcl_x, pcm_x
        );
        self.run.next = self.enable.val() & !self.rst.val();
        // Period counter and warm-up count (flush period, then discarded frames).
        self.pc_n.next = self.zero16.val();
        self.warm_n.next = self.warm_init.val();
        // pc_n == lead, from pc (equality tests, not a compare after the increment). The
        // two tests on pc are flags registered with pc: pc_n = 0 gives (0 == X) ^ k = 0,
        // pc_n = pc + 1 (pc < P - 1, no wrap) gives (pc == X - 1) ^ k.
        self.fl.next = self.pcl_x.q.val() ^ self.kl.val();
        self.fm.next = self.pcm_x.q.val() ^ self.km.val();
        self.pcl_x.d.next = false;
        self.pcm_x.d.next = false;
        self.at_lead.next = self.lead_zero.val();
        if self.run.val() & self.live.q.val() {
            if self.fl.val() {
                self.pc_n.next = self.zero16.val();
                if self.warm.q.val() == self.zero4.val() {
                    self.warm_n.next = self.zero4.val();
                } else {
                    self.warm_n.next = self.warm.q.val() - self.one4.val();
                }
            } else {
                self.pc_n.next = self.pc.q.val() + self.one16.val();
                self.warm_n.next = self.warm.q.val();
                self.at_lead.next = self.fm.val();
                self.pcl_x.d.next = (self.pc.q.val() == self.p_last_m1.val()) ^ self.kl.val();
                self.pcm_x.d.next = (self.pc.q.val() == self.lead_m2.val()) ^ self.km.val();
            }
        }
        // SCK phase and cycle counters: restart at the lead clock, stop after the frame.
        self.ph_n.next = self.zero8.val();
        self.cyc_n.next = self.cyc_stop.val();
        if self.run.val() {
            if self.at_lead.val() {
                self.ph_n.next = self.zero8.val();
                self.cyc_n.next = self.zero8.val();
            } else if self.cyc.q.val() == self.cyc_stop.val() {
                self.ph_n.next = self.ph.q.val();
                self.cyc_n.next = self.cyc.q.val();
            } else if self.ph.q.val() == self.d_last.val() {
                self.ph_n.next = self.zero8.val();
                self.cyc_n.next = self.cyc.q.val() + self.one8.val();
            } else {
                self.ph_n.next = self.ph.q.val() + self.one8.val();
                self.cyc_n.next = self.cyc.q.val();
            }
        }
        // Pins of the state entered at the previous edge (live = run then), registered:
        // the pins show the state one clock after it is entered.
        self.sck_act.next = self.live.q.val()
            & (self.cyc.q.val() < self.frame.val())
            & (self.ph.q.val() >= self.sck_on.val());
        self.conv_act.next = self.live.q.val()
            & (self.pc.q.val() < self.conv_end.val())
            & (self.warm.q.val() < self.warm_init.val());
        self.sck_reg.d.next = self.sck_act.val() ^ self.cpol.val();
        self.conv_reg.d.next = self.conv_act.val() ^ self.conv_idle.val();
        // Capture: the state entered at the previous edge launches the next shifting SCK
        // edge; the bit is adc_miso of the clock before that edge (miso_d). Slot k is
        // cycle k + 1 (the constants hold slot + 1).
        self.miso_d.d.next = self.adc_miso.val();
        self.rst_d.d.next = self.rst.val();
        self.cap.next = self.live.q.val()
            & (self.ph.q.val() == self.cap_ph.val())
            & (self.cyc.q.val() >= self.one8.val())
            & (self.cyc.q.val() <= self.frame.val());
        self.shifted0.next = (self.sr0.q.val() << self.one16.val()) & self.wmask.val();
        if self.miso_d.q.val() {
            self.shifted0.next =
                ((self.sr0.q.val() << self.one16.val()) | self.one16.val()) & self.wmask.val();
        }
        self.shifted1.next = (self.sr1.q.val() << self.one16.val()) & self.wmask.val();
        if self.miso_d.q.val() {
            self.shifted1.next =
                ((self.sr1.q.val() << self.one16.val()) | self.one16.val()) & self.wmask.val();
        }
        self.sr0_n.next = self.sr0.q.val();
        if self.cap.val()
            & (self.cyc.q.val() >= self.ch0_first.val())
            & (self.cyc.q.val() < self.ch0_end.val())
        {
            self.sr0_n.next = self.shifted0.val();
        }
        self.sr1_n.next = self.sr1.q.val();
        if self.cap.val()
            & (self.cyc.q.val() >= self.ch1_first.val())
            & (self.cyc.q.val() < self.ch1_end.val())
        {
            self.sr1_n.next = self.shifted1.val();
        }
        self.sr0.d.next = self.sr0_n.val();
        self.sr1.d.next = self.sr1_n.val();
        self.valid_reg.d.next = false;
        if self.cap.val()
            & (self.cyc.q.val() == self.last_slot.val())
            & (self.warm.q.val() == self.zero4.val())
        {
            self.valid_reg.d.next = true;
            self.ch0_reg.d.next = (self.sr0_n.val() ^ self.flip.val()) & self.wmask.val();
            self.ch1_reg.d.next = (self.sr1_n.val() ^ self.flip.val()) & self.wmask.val();
            if self.one_ch.val() {
                self.ch1_reg.d.next = self.zero16.val();
            }
        }
        self.live.d.next = self.run.val();
        self.pc.d.next = self.pc_n.val();
        self.ph.d.next = self.ph_n.val();
        self.cyc.d.next = self.cyc_n.val();
        self.warm.d.next = self.warm_n.val();
        if self.rst_d.q.val() {
            self.sr0.d.next = self.zero16.val();
            self.sr1.d.next = self.zero16.val();
            self.ch0_reg.d.next = self.zero16.val();
            self.ch1_reg.d.next = self.zero16.val();
            self.valid_reg.d.next = false;
        }
        self.adc_sck.next = self.sck_reg.q.val();
        self.adc_conv.next = self.conv_reg.q.val();
        self.out_valid.next = self.valid_reg.q.val();
        self.out_ch0.next = self.ch0_reg.q.val();
        self.out_ch1.next = self.ch1_reg.q.val();
    }
}

impl crate::sim::step::Clocked for AdcController {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::verify::CosimBlock for AdcController {
    fn input_ports(&self) -> Vec<crate::sim::cosim::Port> {
        use crate::sim::cosim::Port;
        vec![
            Port::new("rst", 1),
            Port::new("enable", 1),
            Port::new("adc_miso", 1),
        ]
    }
    fn output_ports(&self) -> Vec<crate::sim::cosim::Port> {
        use crate::sim::cosim::Port;
        vec![
            Port::new("adc_sck", 1),
            Port::new("adc_conv", 1),
            Port::new("out_valid", 1),
            Port::new("out_ch0", 16),
            Port::new("out_ch1", 16),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r.first().copied().unwrap_or(0) != 0;
        self.enable.next = r.get(1).copied().unwrap_or(0) != 0;
        self.adc_miso.next = r.get(2).copied().unwrap_or(0) != 0;
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.adc_sck.val() as u64,
            self.adc_conv.val() as u64,
            self.out_valid.val() as u64,
            self.out_ch0.val().to_u64(),
            self.out_ch1.val().to_u64(),
        ]
    }
}
