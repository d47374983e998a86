//! rust-hdl description of the capacitive board top.
use crate::blocks::adc::hdl::AdcController;
use crate::blocks::biss::hdl::BissSlave;
use crate::blocks::capacitive::hdl::CapFront;
use crate::blocks::capacitive::CapFrontParams;
use crate::blocks::core::hdl::CoreRtl;
use crate::blocks::params::Derived;
use crate::blocks::top::ports::{board_top, pins};
use rust_hdl::prelude::*;

board_top! {
    /// The capacitive-path top as simulated in rust-hdl and exported (inside `<name>_top`).
    /// Its ports, in the order of the struct, the rtl and the wrapper: [`CAP_TOP_PORTS`].
    pub struct CapTopRtl / CAP_TOP_PORTS / CapTopParts {
        ports {
            clk: In Clock, Clock, 1, Always, 0, "system clock";
            rst: In Bit, In, 1, Always, 0, "synchronous reset, active high";
            adc_miso: In Bit, In, 1, Always, 0, "ADC serial data";
            adc_sck: Out Bit, Out, 1, Always, 0, "ADC serial clock";
            adc_conv: Out Bit, Out, 1, Always, 0, "ADC conversion start / chip select";
            exc_sin: Out Bits<32>, Out, 32, DacBus, 0, "excitation DAC word A sin(wt), two's complement" => es;
            exc_cos: Out Bits<32>, Out, 32, DacBus, 0, "excitation DAC word A cos(wt), two's complement" => ec;
            exc_strobe: Out Bit, Out, 1, Always, 0, "one clock when new excitation words are out";
            biss_ma: In Bit, In, 1, Always, 1, "BiSS-C MA clock from the master";
            biss_slo: Out Bit, Out, 1, Always, 0, "BiSS-C SLO data to the master";
            par_valid: Out Bit, Out, 1, Parallel, 0, "parallel bus: position strobe";
            par_qc: Out Bits<32>, Out, 32, Parallel, 0, "parallel bus: coarse quadrant count" => qc;
            par_fine: Out Bits<32>, Out, 32, Parallel, 0, "parallel bus: fine part of the position" => fine;
            par_turns: Out Bits<32>, Out, 32, Parallel, 0, "parallel bus: turn count" => turns;
            par_error: Out Bit, Out, 1, Parallel, 0, "parallel bus: error flag";
            par_warning: Out Bit, Out, 1, Parallel, 0, "parallel bus: warning flag";
        }
        adc: AdcController,
        front: CapFront,
        core: CoreRtl,
        biss_slave: BissSlave,
        ovf_hold: DFF<Bit>,
        drop_hold: DFF<Bit>,
        error: Signal<Local, Bit>,
        warning: Signal<Local, Bit>,
        word: Signal<Local, Bits<32>>,
        /// BiSS data word = ((qc << qshl) >> qshr) | (fine >> fshr).
        qshl: Constant<Bits<32>>,
        /// See `qshl`.
        qshr: Constant<Bits<32>>,
        /// See `qshl`.
        fshr: Constant<Bits<32>>,
    }
}

/// Ports of the capacitive board top that need a pin (plus [`CAP_TOP_BUSES`]).
pub const CAP_TOP_PINS: &[&str] = pins!(CAP_TOP_PORTS, Always);
/// Buses of the capacitive board top (`capacitive.dac_width` pins each, LSB first).
pub const CAP_TOP_BUSES: &[&str] = pins!(CAP_TOP_PORTS, DacBus);

impl CapTopRtl {
    /// The top for the derived parameters (needs `[capacitive]`).
    pub fn new(d: &Derived) -> crate::error::Result<Self> {
        let p = CapFrontParams::new(d)?;
        let [qshl, qshr, fshr] = crate::blocks::top::hdl::biss_word_shifts(d);
        Ok(Self::from_parts(CapTopParts {
            adc: AdcController::new(&d.adc),
            front: CapFront::new(&p),
            core: CoreRtl::new(d),
            biss_slave: BissSlave::new(&d.biss)?,
            ovf_hold: Default::default(),
            drop_hold: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            word: Default::default(),
            qshl,
            qshr,
            fshr,
        }))
    }
}

impl Logic for CapTopRtl {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, ovf_hold, drop_hold);
        self.adc.clk.next = self.clk.val();
        self.adc.rst.next = self.rst.val();
        self.adc.enable.next = true;
        self.adc.adc_miso.next = self.adc_miso.val();
        self.front.clk.next = self.clk.val();
        self.front.rst.next = self.rst.val();
        self.front.in_valid.next = self.adc.out_valid.val();
        self.front.in_sample.next = bit_cast::<32, 16>(self.adc.out_ch0.val());
        self.core.clk.next = self.clk.val();
        self.core.rst.next = self.rst.val();
        self.core.in_valid.next = self.front.out_valid.val();
        self.core.in_sin.next = bit_cast::<16, 32>(self.front.out_q.val());
        self.core.in_cos.next = bit_cast::<16, 32>(self.front.out_i.val());
        self.core.load.next = false;
        self.core.load_qc.next = self.core.out_qc.val();
        self.core.load_turns.next = self.core.out_turns.val();
        // Filter flags held from one sample to the next, like the core's own flags.
        if self.front.out_valid.val() {
            self.ovf_hold.d.next = self.front.overflow.val();
            self.drop_hold.d.next = false;
        }
        if self.front.dropped.val() {
            self.drop_hold.d.next = true;
        }
        if self.rst.val() {
            self.ovf_hold.d.next = false;
            self.drop_hold.d.next = false;
        }
        self.error.next = self.core.out_error.val() | self.ovf_hold.q.val();
        self.warning.next = self.core.out_warning.val() | self.drop_hold.q.val();
        self.word.next = ((self.core.out_qc.val() << self.qshl.val()) >> self.qshr.val())
            | (self.core.out_fine.val() >> self.fshr.val());
        self.biss_slave.clk.next = self.clk.val();
        self.biss_slave.rst.next = self.rst.val();
        self.biss_slave.ma.next = self.biss_ma.val();
        self.biss_slave.pos.next = self.word.val();
        self.biss_slave.turns.next = self.core.out_turns.val();
        self.biss_slave.pos_valid.next = self.core.out_valid.val();
        self.biss_slave.error.next = self.error.val();
        self.biss_slave.warning.next = self.warning.val();
        self.biss_slo.next = self.biss_slave.slo.val();
        self.adc_sck.next = self.adc.adc_sck.val();
        self.adc_conv.next = self.adc.adc_conv.val();
        self.exc_sin.next = self.front.exc_sin.val();
        self.exc_cos.next = self.front.exc_cos.val();
        self.exc_strobe.next = self.front.exc_strobe.val();
        self.par_valid.next = self.core.out_valid.val();
        self.par_qc.next = self.core.out_qc.val();
        self.par_fine.next = self.core.out_fine.val();
        self.par_turns.next = self.core.out_turns.val();
        self.par_error.next = self.error.val();
        self.par_warning.next = self.warning.val();
    }
}
