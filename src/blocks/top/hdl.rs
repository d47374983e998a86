//! rust-hdl description of the sinewave board top.
use crate::blocks::adc::hdl::AdcController;
use crate::blocks::biss::hdl::BissSlave;
use crate::blocks::c32;
use crate::blocks::core::hdl::CoreRtl;
use crate::blocks::correction::hdl::Correction;
use crate::blocks::fallback::hdl::Fallback;
use crate::blocks::monitor::hdl::Monitor;
use crate::blocks::preamp::hdl::PreampSetup;
use crate::blocks::qep::hdl::QepDecoder;
use crate::blocks::spi_slave::hdl::SpiSlave;
use crate::blocks::ssi::hdl::SsiSlave;
use crate::config::Derived;
use rust_hdl::prelude::*;

/// The sinewave-path top as simulated in rust-hdl and exported (inside `<name>_top`).
#[derive(LogicBlock)]
pub struct TopRtl {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high (also restarts the preamp set-up).
    pub rst: Signal<In, Bit>,
    /// AD_DOUT: serial data from the LTC1407A-1.
    pub adc_miso: Signal<In, Bit>,
    /// SPI_SCK: the shared SPI clock (preamp set-up, then the ADC).
    pub adc_sck: Signal<Out, Bit>,
    /// AD_CONV: conversion start.
    pub adc_conv: Signal<Out, Bit>,
    /// AMP_CS: LTC6912-1 chip select, active low.
    pub amp_cs: Signal<Out, Bit>,
    /// SPI_MOSI: gain word to the LTC6912-1.
    pub amp_mosi: Signal<Out, Bit>,
    /// AMP_SHDN: 0, amplifier on.
    pub amp_shdn: Signal<Out, Bit>,
    /// DAC_CS: 1, DAC deselected.
    pub dac_cs: Signal<Out, Bit>,
    /// DAC_CLR: 1, DAC not cleared.
    pub dac_clr: Signal<Out, Bit>,
    /// SPI_SS_B: 1, SPI flash deselected.
    pub spi_ss_b: Signal<Out, Bit>,
    /// SF_CE0: 1, parallel flash disabled.
    pub sf_ce0: Signal<Out, Bit>,
    /// QEP A: comparator (cos > 0).
    pub qep_a: Signal<In, Bit>,
    /// QEP B: comparator (sin > 0).
    pub qep_b: Signal<In, Bit>,
    /// QEP Z: index.
    pub qep_z: Signal<In, Bit>,
    /// BiSS-C MA clock from the master.
    pub biss_ma: Signal<In, Bit>,
    /// BiSS-C SLO data to the master.
    pub biss_slo: Signal<Out, Bit>,
    /// SSI clock from the master (used when `[ssi] enabled`).
    pub ssi_clk: Signal<In, Bit>,
    /// SSI data to the master (idle high when disabled).
    pub ssi_data: Signal<Out, Bit>,
    /// SPI-slave clock (used when `[spi] enabled`).
    pub enc_sck: Signal<In, Bit>,
    /// SPI-slave chip select, active low.
    pub enc_cs_n: Signal<In, Bit>,
    /// SPI-slave data out.
    pub enc_miso: Signal<Out, Bit>,
    /// SPI-slave output enable (drive `enc_miso` only when high).
    pub enc_miso_oe: Signal<Out, Bit>,
    /// Parallel bus: position strobe.
    pub par_valid: Signal<Out, Bit>,
    /// Parallel bus: coarse quadrant count (upper part of the position).
    pub par_qc: Signal<Out, Bits<32>>,
    /// Parallel bus: fine part of the position.
    pub par_fine: Signal<Out, Bits<32>>,
    /// Parallel bus: turn count (M bits).
    pub par_turns: Signal<Out, Bits<32>>,
    /// Parallel bus: error flag.
    pub par_error: Signal<Out, Bit>,
    /// Parallel bus: warning flag.
    pub par_warning: Signal<Out, Bit>,
    preamp: PreampSetup,
    adc: AdcController,
    correction: Correction,
    core: CoreRtl,
    monitor: Monitor,
    qep_decoder: QepDecoder,
    fallback: Fallback,
    /// 1 when the QEP fallback is enabled in the config.
    qep_enable: Constant<Bit>,
    biss_slave: BissSlave,
    ssi_slave: Vec<SsiSlave>,
    spi_slave: Vec<SpiSlave>,
    error: Signal<Local, Bit>,
    warning: Signal<Local, Bit>,
    word: Signal<Local, Bits<32>>,
    zero: Constant<Bits<32>>,
    /// BiSS data word = ((qc << qshl) >> qshr) | (fine >> fshr): the top bits of the position.
    qshl: Constant<Bits<32>>,
    /// See `qshl`.
    qshr: Constant<Bits<32>>,
    /// See `qshl`.
    fshr: Constant<Bits<32>>,
}

/// Clock cycles from the CONV rise that samples the inputs to `par_valid` for that sample:
/// ADC controller + correction + core.
pub fn conv_to_position_cycles(d: &Derived) -> u32 {
    d.adc.conv_to_valid_clocks() + crate::blocks::correction::LATENCY_CYCLES + d.latency_cycles
}

/// Shifts of the BiSS data word ((qc << qshl) >> qshr) | (fine >> fshr): the top
/// `biss.position_bits` of the position (qc and fine side by side). Shared by both tops.
pub fn biss_word_shifts(d: &Derived) -> [Constant<Bits<32>>; 3] {
    let f = d.fine_bits;
    let drop = d.position_width - d.biss.position_bits;
    [
        c32(f.saturating_sub(drop) as u64),
        c32(drop.saturating_sub(f) as u64),
        c32(drop.min(32) as u64),
    ]
}

impl TopRtl {
    /// The top for the derived parameters (preset `ltc1407a-1`).
    pub fn new(d: &Derived) -> Result<Self, String> {
        let pre = d
            .preamp
            .as_ref()
            .ok_or_else(|| "the sinewave board top needs the LTC1407A-1 preset".to_string())?;
        let [qshl, qshr, fshr] = biss_word_shifts(d);
        Ok(Self {
            clk: Default::default(),
            rst: Default::default(),
            adc_miso: Default::default(),
            adc_sck: Default::default(),
            adc_conv: Default::default(),
            amp_cs: Default::default(),
            amp_mosi: Default::default(),
            amp_shdn: Default::default(),
            dac_cs: Default::default(),
            dac_clr: Default::default(),
            spi_ss_b: Default::default(),
            sf_ce0: Default::default(),
            qep_a: Default::default(),
            qep_b: Default::default(),
            qep_z: Default::default(),
            biss_ma: Default::default(),
            biss_slo: Default::default(),
            ssi_clk: Default::default(),
            ssi_data: Default::default(),
            enc_sck: Default::default(),
            enc_cs_n: Default::default(),
            enc_miso: Default::default(),
            enc_miso_oe: Default::default(),
            par_valid: Default::default(),
            par_qc: Default::default(),
            par_fine: Default::default(),
            par_turns: Default::default(),
            par_error: Default::default(),
            par_warning: Default::default(),
            preamp: PreampSetup::new(pre),
            adc: AdcController::new(&d.adc),
            correction: Correction::new(&d.correction),
            core: CoreRtl::new(d),
            monitor: Monitor::new(&d.monitor),
            qep_decoder: QepDecoder::new(&d.qep),
            fallback: Fallback::new(d),
            qep_enable: Constant::new(d.qep_enabled),
            error: Default::default(),
            warning: Default::default(),
            biss_slave: BissSlave::new(&d.biss)?,
            ssi_slave: match &d.ssi {
                Some(p) => vec![SsiSlave::new(p)?],
                None => vec![],
            },
            spi_slave: match &d.spi {
                Some(p) => vec![SpiSlave::new(p)?],
                None => vec![],
            },
            word: Default::default(),
            zero: c32(0),
            qshl,
            qshr,
            fshr,
        })
    }
}

impl Logic for TopRtl {
    #[hdl_gen]
    fn update(&mut self) {
        self.preamp.clk.next = self.clk.val();
        self.preamp.rst.next = self.rst.val();
        self.preamp.adc_sck.next = self.adc.adc_sck.val();
        self.adc.clk.next = self.clk.val();
        self.adc.rst.next = self.rst.val();
        self.adc.enable.next = self.preamp.done.val();
        self.adc.adc_miso.next = self.adc_miso.val();
        self.core.clk.next = self.clk.val();
        self.core.rst.next = self.rst.val();
        self.correction.clk.next = self.clk.val();
        self.correction.rst.next = self.rst.val();
        self.correction.in_valid.next = self.adc.out_valid.val();
        self.correction.in_sin.next = self.adc.out_ch0.val();
        self.correction.in_cos.next = self.adc.out_ch1.val();
        self.core.in_valid.next = self.correction.out_valid.val();
        self.core.in_sin.next = self.correction.out_sin.val();
        self.core.in_cos.next = self.correction.out_cos.val();
        // Monitor: raw samples (full scale), CORDIC magnitude (loss of signal, clipping).
        self.monitor.clk.next = self.clk.val();
        self.monitor.rst.next = self.rst.val();
        self.monitor.in_valid.next = self.adc.out_valid.val();
        self.monitor.in_sin.next = self.adc.out_ch0.val();
        self.monitor.in_cos.next = self.adc.out_ch1.val();
        self.monitor.mag_valid.next = self.core.out_mag_valid.val();
        self.monitor.magnitude.next = self.core.out_mag.val();
        self.monitor.overspeed.next = false;
        self.monitor.qep_mismatch.next = self.fallback.mismatch.val();
        self.error.next = self.core.out_error.val() | self.monitor.error.val();
        self.warning.next =
            self.core.out_warning.val() | self.monitor.warning.val() | self.fallback.active.val();
        self.qep_decoder.clk.next = self.clk.val();
        self.qep_decoder.rst.next = self.rst.val();
        self.qep_decoder.qep_a.next = self.qep_a.val();
        self.qep_decoder.qep_b.next = self.qep_b.val();
        self.qep_decoder.qep_z.next = self.qep_z.val();
        self.fallback.clk.next = self.clk.val();
        self.fallback.rst.next = self.rst.val();
        self.fallback.enable.next = self.qep_enable.val();
        self.fallback.qep_count.next = self.qep_decoder.count.val();
        self.fallback.conv.next = self.adc.adc_conv.val();
        self.fallback.adc_valid.next = self.adc.out_valid.val();
        self.fallback.core_valid.next = self.core.out_valid.val();
        self.fallback.core_error.next = self.core.out_error.val();
        self.fallback.core_warning.next = self.core.out_warning.val();
        self.fallback.core_qc.next = self.core.out_qc.val();
        self.fallback.core_turns.next = self.core.out_turns.val();
        self.core.load.next = self.fallback.load.val();
        self.core.load_qc.next = self.fallback.load_qc.val();
        self.core.load_turns.next = self.fallback.load_turns.val();
        // BiSS data: the top position_bits of the position (qc and fine side by side).
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
        // Optional SSI and SPI slaves (a Vec of length 0 or 1), same data word as BiSS.
        self.ssi_data.next = true;
        for i in 0..self.ssi_slave.len() {
            self.ssi_slave[i].clk.next = self.clk.val();
            self.ssi_slave[i].rst.next = self.rst.val();
            self.ssi_slave[i].ma.next = self.ssi_clk.val();
            self.ssi_slave[i].pos.next = self.word.val();
            self.ssi_slave[i].turns.next = self.core.out_turns.val();
            self.ssi_slave[i].pos_valid.next = self.core.out_valid.val();
            self.ssi_slave[i].error.next = self.error.val();
            self.ssi_data.next = self.ssi_slave[i].slo.val();
        }
        self.enc_miso.next = false;
        self.enc_miso_oe.next = false;
        for i in 0..self.spi_slave.len() {
            self.spi_slave[i].clk.next = self.clk.val();
            self.spi_slave[i].rst.next = self.rst.val();
            self.spi_slave[i].sck.next = self.enc_sck.val();
            self.spi_slave[i].cs_n.next = self.enc_cs_n.val();
            self.spi_slave[i].pos.next = self.word.val();
            self.spi_slave[i].turns.next = self.core.out_turns.val();
            self.spi_slave[i].pos_valid.next = self.core.out_valid.val();
            self.spi_slave[i].error.next = self.error.val();
            self.spi_slave[i].warning.next = self.warning.val();
            self.enc_miso.next = self.spi_slave[i].miso.val();
            self.enc_miso_oe.next = self.spi_slave[i].miso_oe.val();
        }
        self.adc_sck.next = self.preamp.spi_sck.val();
        self.adc_conv.next = self.adc.adc_conv.val();
        self.amp_cs.next = self.preamp.amp_cs.val();
        self.amp_mosi.next = self.preamp.spi_mosi.val();
        self.amp_shdn.next = self.preamp.amp_shdn.val();
        self.dac_cs.next = self.preamp.dac_cs.val();
        self.dac_clr.next = self.preamp.dac_clr.val();
        self.spi_ss_b.next = self.preamp.spi_ss_b.val();
        self.sf_ce0.next = self.preamp.sf_ce0.val();
        self.par_valid.next = self.core.out_valid.val();
        self.par_qc.next = self.core.out_qc.val();
        self.par_fine.next = self.core.out_fine.val();
        self.par_turns.next = self.core.out_turns.val();
        self.par_error.next = self.error.val();
        self.par_warning.next = self.warning.val();
    }
}

impl crate::cosim::step::Clocked for TopRtl {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for TopRtl {
    fn input_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("rst", 1),
            Port::new("adc_miso", 1),
            Port::new("biss_ma", 1),
            Port::new("qep_a", 1),
            Port::new("qep_b", 1),
            Port::new("qep_z", 1),
            Port::new("ssi_clk", 1),
            Port::new("enc_sck", 1),
            Port::new("enc_cs_n", 1),
        ]
    }
    fn output_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        let mut v: Vec<Port> = [
            "adc_sck",
            "adc_conv",
            "amp_cs",
            "amp_mosi",
            "amp_shdn",
            "dac_cs",
            "dac_clr",
            "spi_ss_b",
            "sf_ce0",
            "biss_slo",
            "ssi_data",
            "enc_miso",
            "enc_miso_oe",
            "par_valid",
        ]
        .iter()
        .map(|n| Port::new(n, 1))
        .collect();
        v.push(Port::new("par_qc", 32));
        v.push(Port::new("par_fine", 32));
        v.push(Port::new("par_turns", 32));
        v.push(Port::new("par_error", 1));
        v.push(Port::new("par_warning", 1));
        v
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.adc_miso.next = r[1] != 0;
        self.biss_ma.next = r[2] != 0;
        self.qep_a.next = r[3] != 0;
        self.qep_b.next = r[4] != 0;
        self.qep_z.next = r[5] != 0;
        self.ssi_clk.next = r.get(6).is_none_or(|v| *v != 0);
        self.enc_sck.next = r.get(7).is_some_and(|v| *v != 0);
        self.enc_cs_n.next = r.get(8).is_none_or(|v| *v != 0);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.adc_sck.val() as u64,
            self.adc_conv.val() as u64,
            self.amp_cs.val() as u64,
            self.amp_mosi.val() as u64,
            self.amp_shdn.val() as u64,
            self.dac_cs.val() as u64,
            self.dac_clr.val() as u64,
            self.spi_ss_b.val() as u64,
            self.sf_ce0.val() as u64,
            self.biss_slo.val() as u64,
            self.ssi_data.val() as u64,
            self.enc_miso.val() as u64,
            self.enc_miso_oe.val() as u64,
            self.par_valid.val() as u64,
            self.par_qc.val().to_u64(),
            self.par_fine.val().to_u64(),
            self.par_turns.val().to_u64(),
            self.par_error.val() as u64,
            self.par_warning.val() as u64,
        ]
    }
}
