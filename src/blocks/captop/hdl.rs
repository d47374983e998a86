//! rust-hdl description of the capacitive board top.
use crate::blocks::adc::hdl::AdcController;
use crate::blocks::biss::hdl::BissSlave;
use crate::blocks::capacitive::hdl::CapFront;
use crate::blocks::capacitive::CapFrontParams;
use crate::blocks::core::hdl::CoreRtl;
use crate::config::Derived;
use crate::sim::cosim::Port;
use rust_hdl::prelude::*;

/// The capacitive-path top as simulated in rust-hdl and exported (inside `<name>_top`).
#[derive(LogicBlock)]
pub struct CapTopRtl {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// ADC serial data.
    pub adc_miso: Signal<In, Bit>,
    /// ADC serial clock.
    pub adc_sck: Signal<Out, Bit>,
    /// ADC conversion start / chip select.
    pub adc_conv: Signal<Out, Bit>,
    /// Excitation DAC word A sin(wt), W-bit two's complement.
    pub exc_sin: Signal<Out, Bits<32>>,
    /// Excitation DAC word A cos(wt), W-bit two's complement.
    pub exc_cos: Signal<Out, Bits<32>>,
    /// One clock when new excitation words are out (DAC load strobe).
    pub exc_strobe: Signal<Out, Bit>,
    /// BiSS-C MA clock from the master.
    pub biss_ma: Signal<In, Bit>,
    /// BiSS-C SLO data to the master.
    pub biss_slo: Signal<Out, Bit>,
    /// Parallel bus: position strobe.
    pub par_valid: Signal<Out, Bit>,
    /// Parallel bus: coarse quadrant count.
    pub par_qc: Signal<Out, Bits<32>>,
    /// Parallel bus: fine part of the position.
    pub par_fine: Signal<Out, Bits<32>>,
    /// Parallel bus: turn count.
    pub par_turns: Signal<Out, Bits<32>>,
    /// Parallel bus: error flag.
    pub par_error: Signal<Out, Bit>,
    /// Parallel bus: warning flag.
    pub par_warning: Signal<Out, Bit>,
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

impl CapTopRtl {
    /// The top for the derived parameters (needs `[capacitive]`).
    pub fn new(d: &Derived) -> crate::error::Result<Self> {
        let p = CapFrontParams::new(d)?;
        let [qshl, qshr, fshr] = crate::blocks::top::hdl::biss_word_shifts(d);
        Ok(Self {
            clk: Default::default(),
            rst: Default::default(),
            adc_miso: Default::default(),
            adc_sck: Default::default(),
            adc_conv: Default::default(),
            exc_sin: Default::default(),
            exc_cos: Default::default(),
            exc_strobe: Default::default(),
            biss_ma: Default::default(),
            biss_slo: Default::default(),
            par_valid: Default::default(),
            par_qc: Default::default(),
            par_fine: Default::default(),
            par_turns: Default::default(),
            par_error: Default::default(),
            par_warning: Default::default(),
            adc: AdcController::new(&d.adc),
            front: CapFront::new(&p),
            core: CoreRtl::new(d),
            biss_slave: BissSlave::new(&d.biss).map_err(|message| crate::error::Error::Params {
                block: "biss".into(),
                message,
            })?,
            ovf_hold: Default::default(),
            drop_hold: Default::default(),
            error: Default::default(),
            warning: Default::default(),
            word: Default::default(),
            qshl,
            qshr,
            fshr,
        })
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

impl crate::sim::step::Clocked for CapTopRtl {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::verify::CosimBlock for CapTopRtl {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("adc_miso", 1),
            Port::new("biss_ma", 1),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("adc_sck", 1),
            Port::new("adc_conv", 1),
            Port::new("exc_sin", 32),
            Port::new("exc_cos", 32),
            Port::new("exc_strobe", 1),
            Port::new("biss_slo", 1),
            Port::new("par_valid", 1),
            Port::new("par_qc", 32),
            Port::new("par_fine", 32),
            Port::new("par_turns", 32),
            Port::new("par_error", 1),
            Port::new("par_warning", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.adc_miso.next = r[1] != 0;
        self.biss_ma.next = r.get(2).is_none_or(|v| *v != 0);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.adc_sck.val() as u64,
            self.adc_conv.val() as u64,
            self.exc_sin.val().to_u64(),
            self.exc_cos.val().to_u64(),
            self.exc_strobe.val() as u64,
            self.biss_slo.val() as u64,
            self.par_valid.val() as u64,
            self.par_qc.val().to_u64(),
            self.par_fine.val().to_u64(),
            self.par_turns.val().to_u64(),
            self.par_error.val() as u64,
            self.par_warning.val() as u64,
        ]
    }
}
