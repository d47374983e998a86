//! rust-hdl description of the LTC6912-1 set-up (see the module docs of `preamp`).
use super::PreampParams;
use rust_hdl::prelude::*;

/// Step at which AMP_CS falls (MOSI = bit 7).
pub const STEP_CS_LOW: u32 = 1;
/// First step with SCK high.
pub const STEP_FIRST_HIGH: u32 = 2;
/// Last step with SCK high (the 8th rising edge starts it).
pub const STEP_LAST_HIGH: u32 = 16;
/// Last step with AMP_CS low.
pub const STEP_CS_LAST: u32 = 17;
/// Step at which `done` rises (the step counter stops here).
pub const STEP_DONE: u32 = 19;

fn c8(v: u64) -> Constant<Bits<8>> {
    Constant::new(Bits::<8>::from(v & 0xff))
}

/// Shifts the gain word into the LTC6912-1 after reset, then hands SPI_SCK to the ADC.
#[derive(LogicBlock)]
pub struct PreampSetup {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: restarts the set-up.
    pub rst: Signal<In, Bit>,
    /// The ADC controller's SCK, driven onto spi_sck once done.
    pub adc_sck: Signal<In, Bit>,
    /// Shared SPI_SCK pin.
    pub spi_sck: Signal<Out, Bit>,
    /// Shared SPI_MOSI pin.
    pub spi_mosi: Signal<Out, Bit>,
    /// AMP_CS, active low.
    pub amp_cs: Signal<Out, Bit>,
    /// AMP_SHDN: 0, amplifier on.
    pub amp_shdn: Signal<Out, Bit>,
    /// DAC_CS: 1, DAC deselected.
    pub dac_cs: Signal<Out, Bit>,
    /// DAC_CLR: 1, no DAC clear.
    pub dac_clr: Signal<Out, Bit>,
    /// SPI_SS_B: 1, SPI flash deselected.
    pub spi_ss_b: Signal<Out, Bit>,
    /// SF_CE0: 1, parallel flash disabled.
    pub sf_ce0: Signal<Out, Bit>,
    /// The gains are latched; the ADC may start.
    pub done: Signal<Out, Bit>,
    hp: DFF<Bits<8>>,
    step: DFF<Bits<8>>,
    sh: DFF<Bits<8>>,
    sck_reg: DFF<Bit>,
    mosi_reg: DFF<Bit>,
    cs_reg: DFF<Bit>,
    done_reg: DFF<Bit>,
    /// (hp == half period - 1) ^ (half period = 1), registered with hp from its value
    /// before the step (0 at hp = 0, the power-up value).
    hplx: DFF<Bit>,
    /// step == STEP_DONE, registered with step.
    sdone: DFF<Bit>,
    /// The next advance shifts the gain word (step even, STEP_FIRST_HIGH <= step <
    /// STEP_LAST_HIGH), registered with step.
    shf: DFF<Bit>,
    /// hp == half period - 1 (decoded).
    hp_end: Signal<Local, Bit>,
    hp_n: Signal<Local, Bits<8>>,
    step_n: Signal<Local, Bits<8>>,
    sh_n: Signal<Local, Bits<8>>,
    /// The step advances this clock.
    adv: Signal<Local, Bit>,
    /// An advance from step.q shifts the gain word (SCK falls, MOSI takes the next bit).
    shift: Signal<Local, Bit>,
    /// Half period - 1.
    hp_last: Constant<Bits<8>>,
    /// Half period - 2: hp before a step onto half period - 1 (never stepped from when the
    /// half period is 1).
    hp_last_m1: Constant<Bits<8>>,
    /// Half period = 1: hp == half period - 1 at hp = 0.
    hp_one: Constant<Bit>,
    /// The gain word (B nibble high).
    word: Constant<Bits<8>>,
    /// Bit 7 of the shift register.
    msb: Constant<Bits<8>>,
    /// Bit 6 of the shift register (bit 7 after a shift).
    bit6: Constant<Bits<8>>,
    /// STEP_CS_LOW - 1.
    s_cs_low_m1: Constant<Bits<8>>,
    /// STEP_CS_LAST - 1: the last step from which an advance lands with CS low.
    s_cs_last_m1: Constant<Bits<8>>,
    /// STEP_FIRST_HIGH - 1.
    s_first_high_m1: Constant<Bits<8>>,
    /// STEP_LAST_HIGH - 1.
    s_last_high_m1: Constant<Bits<8>>,
    /// STEP_DONE - 1.
    s_done_m1: Constant<Bits<8>>,
    one8: Constant<Bits<8>>,
    zero8: Constant<Bits<8>>,
}

impl PreampSetup {
    /// Set-up for validated parameters.
    pub fn new(p: &PreampParams) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            adc_sck: Default::default(),
            spi_sck: Default::default(),
            spi_mosi: Default::default(),
            amp_cs: Default::default(),
            amp_shdn: Default::default(),
            dac_cs: Default::default(),
            dac_clr: Default::default(),
            spi_ss_b: Default::default(),
            sf_ce0: Default::default(),
            done: Default::default(),
            hp: Default::default(),
            step: Default::default(),
            sh: Default::default(),
            sck_reg: Default::default(),
            mosi_reg: Default::default(),
            cs_reg: Default::default(),
            done_reg: Default::default(),
            hplx: Default::default(),
            sdone: Default::default(),
            shf: Default::default(),
            hp_end: Default::default(),
            hp_n: Default::default(),
            step_n: Default::default(),
            sh_n: Default::default(),
            adv: Default::default(),
            shift: Default::default(),
            hp_last: c8(p.half_period_clocks.saturating_sub(1) as u64),
            hp_last_m1: c8((p.half_period_clocks.saturating_sub(1) as u64).wrapping_sub(1) & 0xff),
            hp_one: Constant::new(p.half_period_clocks.saturating_sub(1) == 0),
            word: c8(p.word() as u64),
            msb: c8(0x80),
            bit6: c8(0x40),
            s_cs_low_m1: c8(STEP_CS_LOW as u64 - 1),
            s_cs_last_m1: c8(STEP_CS_LAST as u64 - 1),
            s_first_high_m1: c8(STEP_FIRST_HIGH as u64 - 1),
            s_last_high_m1: c8(STEP_LAST_HIGH as u64 - 1),
            s_done_m1: c8(STEP_DONE as u64 - 1),
            one8: c8(1),
            zero8: c8(0),
        }
    }
}

impl Logic for PreampSetup {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, hp, step, sh, sck_reg, mosi_reg, cs_reg, done_reg, hplx, sdone, shf);
        // Step timer: each step lasts half_period_clocks; the step counter stops at done.
        // `adv`: the step advances this clock. The pins of the step being entered are
        // decoded from step.q for both cases side by side (for the advanced step with the
        // compare constants shifted by one: s + 1 >= A <=> s >= A - 1, parity flips; step
        // stays <= STEP_DONE, so s + 1 never wraps) and then muxed, so no adder precedes a
        // compare; the cycle behaviour is the same as decoding step + 1.
        // hp == half period - 1, step == STEP_DONE and the shift condition are flags
        // registered with their counters (set from the old count on a step), so `adv` and
        // the shift register's enable are one LUT of registers.
        self.hp_end.next = self.hplx.q.val() ^ self.hp_one.val();
        self.adv.next = (!self.rst.val()) & !self.sdone.q.val() & self.hp_end.val();
        // Entering an odd step from 3 on: SCK falls, MOSI moves to the next bit.
        self.shift.next = self.shf.q.val();
        self.hp_n.next = self.zero8.val();
        self.step_n.next = self.zero8.val();
        self.sh_n.next = self.word.val();
        self.hplx.d.next = false;
        self.sdone.d.next = false;
        self.shf.d.next = false;
        if !self.rst.val() {
            self.step_n.next = self.step.q.val();
            self.sh_n.next = self.sh.q.val();
            self.sdone.d.next = self.sdone.q.val();
            self.shf.d.next = self.shf.q.val();
            if self.sdone.q.val() {
                self.hp_n.next = self.hp.q.val();
                self.hplx.d.next = self.hplx.q.val();
            } else if self.hp_end.val() {
                self.hp_n.next = self.zero8.val();
                self.step_n.next = self.step.q.val() + self.one8.val();
                self.sdone.d.next = self.step.q.val() == self.s_done_m1.val();
                // step + 1 even and in [FIRST_HIGH, LAST_HIGH) <=> step odd and in
                // [FIRST_HIGH - 1, LAST_HIGH - 1).
                self.shf.d.next = ((self.step.q.val() & self.one8.val()) != self.zero8.val())
                    & (self.step.q.val() >= self.s_first_high_m1.val())
                    & (self.step.q.val() < self.s_last_high_m1.val());
                if self.shift.val() {
                    self.sh_n.next = self.sh.q.val() << self.one8.val();
                }
            } else {
                self.hp_n.next = self.hp.q.val() + self.one8.val();
                self.hplx.d.next = (self.hp.q.val() == self.hp_last_m1.val()) ^ self.hp_one.val();
            }
        }
        // Pins for the step being entered.
        // The register holds "selected", so its power-up value 0 keeps AMP_CS high (no
        // spurious select between configuration and reset). In reset the step entered is 0:
        // every pin register low.
        self.cs_reg.d.next = false;
        self.sck_reg.d.next = false;
        self.mosi_reg.d.next = false;
        self.done_reg.d.next = false;
        if self.adv.val() {
            // Step s + 1 with s = step.q.
            self.cs_reg.d.next = (self.step.q.val() >= self.s_cs_low_m1.val())
                & (self.step.q.val() <= self.s_cs_last_m1.val());
            self.sck_reg.d.next = (self.step.q.val() >= self.s_first_high_m1.val())
                & (self.step.q.val() <= self.s_last_high_m1.val())
                & ((self.step.q.val() & self.one8.val()) != self.zero8.val());
            self.mosi_reg.d.next = (self.step.q.val() >= self.s_cs_low_m1.val())
                & (self.step.q.val() <= self.s_cs_last_m1.val())
                & ((((self.sh.q.val() & self.msb.val()) != self.zero8.val()) & !self.shift.val())
                    | (((self.sh.q.val() & self.bit6.val()) != self.zero8.val())
                        & self.shift.val()));
            self.done_reg.d.next = self.step.q.val() == self.s_done_m1.val();
        } else if !self.rst.val() {
            // Step s stays: every pin register already holds the decode of s (it was
            // loaded with it when s was entered, and reset and power-up give step 0 with
            // every pin low), so it holds.
            self.cs_reg.d.next = self.cs_reg.q.val();
            self.sck_reg.d.next = self.sck_reg.q.val();
            self.mosi_reg.d.next = self.mosi_reg.q.val();
            self.done_reg.d.next = self.done_reg.q.val();
        }
        self.hp.d.next = self.hp_n.val();
        self.step.d.next = self.step_n.val();
        self.sh.d.next = self.sh_n.val();
        // Outputs.
        self.spi_sck.next = self.sck_reg.q.val();
        if self.done_reg.q.val() {
            self.spi_sck.next = self.adc_sck.val();
        }
        self.spi_mosi.next = self.mosi_reg.q.val();
        self.amp_cs.next = !self.cs_reg.q.val();
        self.done.next = self.done_reg.q.val();
        self.amp_shdn.next = false;
        self.dac_cs.next = true;
        self.dac_clr.next = true;
        self.spi_ss_b.next = true;
        self.sf_ce0.next = true;
    }
}

impl crate::cosim::step::Clocked for PreampSetup {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for PreampSetup {
    fn input_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![Port::new("rst", 1), Port::new("adc_sck", 1)]
    }
    fn output_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        [
            "spi_sck", "spi_mosi", "amp_cs", "amp_shdn", "dac_cs", "dac_clr", "spi_ss_b", "sf_ce0",
            "done",
        ]
        .iter()
        .map(|n| Port::new(n, 1))
        .collect()
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r.first().copied().unwrap_or(0) != 0;
        self.adc_sck.next = r.get(1).copied().unwrap_or(0) != 0;
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.spi_sck.val() as u64,
            self.spi_mosi.val() as u64,
            self.amp_cs.val() as u64,
            self.amp_shdn.val() as u64,
            self.dac_cs.val() as u64,
            self.dac_clr.val() as u64,
            self.spi_ss_b.val() as u64,
            self.sf_ce0.val() as u64,
            self.done.val() as u64,
        ]
    }
}
