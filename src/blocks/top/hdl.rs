//! rust-hdl description of the sinewave board top.
use super::ports::{board_top, pins};
use crate::blocks::absolute::hdl::AbsoluteStart;
use crate::blocks::abz::hdl::AbzEmulator;
use crate::blocks::adc::hdl::AdcController;
use crate::blocks::biss::hdl::BissSlave;
use crate::blocks::c32;
use crate::blocks::capture::hdl::Capture;
use crate::blocks::core::hdl::CoreRtl;
use crate::blocks::correction::hdl::Correction;
use crate::blocks::fallback::hdl::{conv_inverted, Fallback};
use crate::blocks::init_bit::InitBit;
use crate::blocks::monitor::hdl::Monitor;
use crate::blocks::params::Derived;
use crate::blocks::preamp::hdl::PreampSetup;
use crate::blocks::qep::hdl::QepDecoder;
use crate::blocks::reference::hdl::PositionReference;
use crate::blocks::regmap::hdl::RegisterMap;
use crate::blocks::regmap::{flag_bit, FLAGS};
use crate::blocks::spi_slave::hdl::SpiSlave;
use crate::blocks::ssi::hdl::SsiSlave;
use crate::blocks::velocity::hdl::Velocity;
use rust_hdl::prelude::*;

board_top! {
    /// The sinewave-path top as simulated in rust-hdl and exported (inside `<name>_top`).
    /// Its ports, in the order of the struct, the rtl and the wrapper: [`SD_TOP_PORTS`].
    pub struct TopRtl / SD_TOP_PORTS / TopParts {
        ports {
            clk: In Clock, Clock, 1, Always, 0, "system clock";
            rst: In Bit, In, 1, Always, 0, "synchronous reset, active high (restarts the set-up); the blocks take it one clock later";
            adc_miso: In Bit, In, 1, Always, 0, "ADC serial data (line A: channel 0, or both channels on one line)";
            adc_miso_b: In Bit, In, 1, AdcB, 0, "ADC serial data, line B: channel 1 (ADCs with two data lines)";
            adc_sck: Out Bit, Out, 1, Always, 0, "ADC serial clock (with the pre-amplifier: the shared SPI clock, set-up then ADC)";
            adc_conv: Out Bit, Out, 1, Always, 0, "ADC conversion start (CONV pulse or chip select, as the preset frames)";
            amp_cs: Out Bit, Out, 1, Preamp, 0, "AMP_CS: LTC6912-1 chip select, active low";
            amp_mosi: Out Bit, Out, 1, Preamp, 0, "SPI_MOSI: LTC6912-1 gain word";
            amp_shdn: Out Bit, Out, 1, Preamp, 0, "AMP_SHDN: 0 = amplifier on";
            dac_cs: Out Bit, Out, 1, Deselect, 0, "DAC_CS: 1 = DAC deselected";
            dac_clr: Out Bit, Out, 1, Deselect, 0, "DAC_CLR: 1 = DAC not cleared";
            spi_ss_b: Out Bit, Out, 1, Deselect, 0, "SPI_SS_B: 1 = SPI flash deselected";
            sf_ce0: Out Bit, Out, 1, Deselect, 0, "SF_CE0: 1 = parallel flash disabled";
            qep_a: In Bit, In, 1, Qep, 0, "QEP A: comparator cos > 0";
            qep_b: In Bit, In, 1, Qep, 0, "QEP B: comparator sin > 0";
            qep_z: In Bit, In, 1, Qep, 0, "QEP Z: index";
            biss_ma: In Bit, In, 1, Always, 1, "BiSS-C MA clock from the master";
            biss_slo: Out Bit, Out, 1, Always, 0, "BiSS-C SLO data to the master";
            ssi_clk: In Bit, In, 1, Ssi, 1, "SSI clock from the master (idle high)";
            ssi_data: Out Bit, Out, 1, Ssi, 0, "SSI data (idle high)";
            enc_sck: In Bit, In, 1, Spi, 0, "SPI-slave clock";
            enc_cs_n: In Bit, In, 1, Spi, 1, "SPI-slave chip select, active low";
            enc_miso: Out Bit, Out, 1, Spi, 0, "SPI-slave data";
            enc_miso_oe: Out Bit, Out, 1, Spi, 0, "SPI-slave output enable (drive enc_miso only when high)";
            par_valid: Out Bit, Out, 1, Parallel, 0, "parallel bus: position strobe";
            par_qc: Out Bits<32>, Out, 32, Parallel, 0, "parallel bus: coarse quadrant count (upper part of the position)" => qc;
            par_fine: Out Bits<32>, Out, 32, Parallel, 0, "parallel bus: fine part of the position" => fine;
            par_turns: Out Bits<32>, Out, 32, Parallel, 0, "parallel bus: turn count (M bits)" => turns;
            par_error: Out Bit, Out, 1, Parallel, 0, "parallel bus: error flag";
            par_warning: Out Bit, Out, 1, Parallel, 0, "parallel bus: warning flag";
        }
        @optional_inputs {
            preset: Bit, 1, "position preset (`[reference] enabled`): a rising edge loads the preset count at the next sample";
            capture: Bit, 1, "capture (`[capture] enabled`): a rising edge latches the position, the velocity and their age on cap_*";
            s_axi_awaddr: Bits<32>, 32, "AXI4-Lite write address (`[registers] enabled`), byte address";
            s_axi_awvalid: Bit, 1, "AXI4-Lite write address valid";
            s_axi_wdata: Bits<32>, 32, "AXI4-Lite write data";
            s_axi_wstrb: Bits<32>, 32, "AXI4-Lite write byte strobes (4 bits)";
            s_axi_wvalid: Bit, 1, "AXI4-Lite write data valid";
            s_axi_bready: Bit, 1, "AXI4-Lite write response ready";
            s_axi_araddr: Bits<32>, 32, "AXI4-Lite read address, byte address";
            s_axi_arvalid: Bit, 1, "AXI4-Lite read address valid";
            s_axi_rready: Bit, 1, "AXI4-Lite read data ready";
            abs_data: Bit, 1, "SSI data from the encoder's digital channel (`[reference] absolute`)";
        }
        @optional_outputs {
            par_velocity: Bits<64>, 64, "velocity (`[velocity] enabled`): `width`-bit two's complement in the low bits, held between strobes";
            par_velocity_valid: Bit, 1, "velocity strobe (`[velocity] enabled`): one clock per update";
            abz_a: Bit, 1, "ABZ emulation (`[abz] enabled`): channel A (leads B when the position increases)";
            abz_b: Bit, 1, "ABZ emulation (`[abz] enabled`): channel B";
            abz_z: Bit, 1, "ABZ emulation (`[abz] enabled`): index, one quarter A/B period at position 0";
            referenced: Bit, 1, "position referenced (`[reference] enabled`): 1 once homed on Z or preset";
            cap_valid: Bit, 1, "capture strobe (`[capture] enabled`): one clock per capture taken";
            cap_qc: Bits<32>, 32, "captured quadrant count (`[capture] enabled`), extrapolated with `extrapolate`";
            cap_fine: Bits<32>, 32, "captured fine part (`[capture] enabled`)";
            cap_turns: Bits<32>, 32, "captured turn count (`[capture] enabled`, M bits)";
            cap_age: Bits<32>, 32, "captured age (`[capture] enabled`): clocks from the sample's CONV edge to the capture";
            cap_velocity: Bits<64>, 64, "captured velocity (`[capture]` with `[velocity]`), as par_velocity";
            s_axi_awready: Bit, 1, "AXI4-Lite write address ready (`[registers] enabled`)";
            s_axi_wready: Bit, 1, "AXI4-Lite write data ready";
            s_axi_bresp: Bits<32>, 32, "AXI4-Lite write response (always OKAY)";
            s_axi_bvalid: Bit, 1, "AXI4-Lite write response valid";
            s_axi_arready: Bit, 1, "AXI4-Lite read address ready";
            s_axi_rdata: Bits<32>, 32, "AXI4-Lite read data";
            s_axi_rresp: Bits<32>, 32, "AXI4-Lite read response (always OKAY)";
            s_axi_rvalid: Bit, 1, "AXI4-Lite read data valid";
            flags: Bits<32>, 32, "live flags (`[registers] enabled`): FLAGS's bits, as the register map reads them";
            abs_clk: Bit, 1, "SSI clock to the encoder's digital channel (`[reference] absolute`): idle high";
        }
        /// The pre-amplifier set-up (`[preamp]`, the LTC1407A-1 kit): one instance or none.
        /// Without it the ADC converts from reset and owns `adc_sck`.
        preamp: Vec<PreampSetup>,
        adc: AdcController,
        correction: Correction,
        core: CoreRtl,
        monitor: Monitor,
        qep_decoder: QepDecoder,
        fallback: Fallback,
        /// One entry (1) when the ADC's conversion start is an active-low chip select: the
        /// fallback takes its inverse, so that it rises at the sampling edge
        /// ([`crate::blocks::fallback::hdl::conv_inverted`]); none for an active-high CONV.
        fb_conv_inv: Vec<Constant<Bit>>,
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
        /// The velocity estimator: one instance with `[velocity] enabled`, none without (no
        /// Verilog, no ports).
        vel: Vec<Velocity>,
        /// F, the shift of the quadrant count above the fine part in the estimator's
        /// position (it uses the low F + 2 bits): one per estimator.
        vel_fshl: Vec<Constant<Bits<32>>>,
        /// The ABZ emulator on the parallel bus's position (`[abz] enabled`): one or none.
        abz: Vec<AbzEmulator>,
        /// The position reference between the core and every position output
        /// (`[reference] enabled`): one or none. The velocity estimator and the QEP
        /// fallback keep the core's count.
        reference: Vec<PositionReference>,
        /// See `rst_adc`: one per position reference.
        rst_ref: Vec<InitBit>,
        /// The absolute start (`[reference] absolute = "ssi"`): an SSI master reading the
        /// encoder's digital channel once after reset, its target taken by the position
        /// reference; one or none.
        absolute: Vec<AbsoluteStart>,
        /// See `rst_adc`: one per absolute start.
        rst_abs: Vec<InitBit>,
        /// The synchronous capture of the position every output takes (`[capture]
        /// enabled`): one or none.
        cap: Vec<Capture>,
        /// See `rst_adc`: one per capture block.
        rst_cap: Vec<InitBit>,
        /// The AXI4-Lite register map (`[registers] enabled`): one or none.
        regs: Vec<RegisterMap>,
        /// See `rst_adc`: one per register map.
        rst_regs: Vec<InitBit>,
        /// The BiSS control channel's byte access to the map (address, write, data, read
        /// begins), registered once between the two (one per BiSS byte port). Timing: the
        /// path from the channel's address register to the map's read select crossed the
        /// die (4.6 ns of routing in 6 ns); the channel reads a frame after it asks.
        bq_addr: Vec<DFF<Bits<32>>>,
        /// See `bq_addr`.
        bq_we: Vec<DFF<Bit>>,
        /// See `bq_addr`.
        bq_wdata: Vec<DFF<Bits<8>>>,
        /// See `bq_addr`.
        bq_snap: Vec<DFF<Bit>>,
        /// The live flags the register map reads (FLAGS's bits): one per register map (a
        /// Vec, so a top without one declares nothing).
        rflags: Vec<Signal<Local, Bits<32>>>,
        /// FLAGS's bits in the order of `regmap::FLAGS`: LOS, CLIP, FULL_SCALE, OVERSPEED,
        /// QEP_MISMATCH, FALLBACK, REFERENCED, ERROR, WARNING, ADC_FRAME, NOT_REFERENCED
        /// (none without a register map).
        fl_bits: Vec<Constant<Bits<32>>>,
        /// The live flags' value before any flag is set: REFERENCED without a position
        /// reference (as FLAGS reads it), else 0; one per register map.
        fl_init: Vec<Constant<Bits<32>>>,
        /// The blocks' reset: `rst` one clock later, from a register per block (powered up
        /// asserted; [`BLOCK_RESET_CLOCKS`]). Timing: one register driving every block's
        /// reset flops was the auto-correction top's slowest net (`rst` -> `core`); a
        /// register of its own per block (`InitBit::kept`) keeps each net local.
        rst_adc: InitBit,
        /// See `rst_adc`.
        rst_correction: InitBit,
        /// See `rst_adc`.
        rst_core: InitBit,
        /// See `rst_adc`.
        rst_monitor: InitBit,
        /// See `rst_adc`: the QEP decoder and the QEP fallback.
        rst_qep: InitBit,
        /// See `rst_adc`.
        rst_biss: InitBit,
        /// See `rst_adc`: one per pre-amplifier set-up.
        rst_preamp: Vec<InitBit>,
        /// See `rst_adc`: one per SSI slave.
        rst_ssi: Vec<InitBit>,
        /// See `rst_adc`: one per SPI slave.
        rst_spi: Vec<InitBit>,
        /// See `rst_adc`: one per ABZ emulator.
        rst_abz: Vec<InitBit>,
        /// See `rst_adc`: one per velocity estimator.
        rst_vel: Vec<InitBit>,
    }
}

/// One register per BiSS byte port to the register map (the control channel with the
/// map's banks), none otherwise.
fn bus_regs<T: Default>(d: &Derived, nreg: usize) -> Vec<T> {
    let n = usize::from(d.biss.user_map && d.biss.control.is_some()) * nreg;
    (0..n).map(|_| T::default()).collect()
}

/// Ports of the sinewave board top that always need a pin (plus [`QEP_PINS`] with
/// `[qep] enabled`, [`SSI_PINS`] / [`SPI_PINS`] when enabled and the pinned
/// [`DESELECT_PINS`]; see `config::board_ports`).
pub const TOP_PINS: &[&str] = pins!(SD_TOP_PORTS, Always);
/// Pins of the pre-amplifier set-up (`[preamp]`, the LTC1407A-1 kit).
pub const PREAMP_PINS: &[&str] = pins!(SD_TOP_PORTS, Preamp);
/// The ADC's second data line (two-line ADCs).
pub const ADC_B_PINS: &[&str] = pins!(SD_TOP_PORTS, AdcB);
/// Pins of the optional SSI slave.
pub const SSI_PINS: &[&str] = pins!(SD_TOP_PORTS, Ssi);
/// Pins of the optional SPI slave.
pub const SPI_PINS: &[&str] = pins!(SD_TOP_PORTS, Spi);
/// Comparator inputs of the sinewave top: ports (and required pins) only with
/// `[qep] enabled`.
pub const QEP_PINS: &[&str] = pins!(SD_TOP_PORTS, Qep);
/// Outputs of the sinewave top that hold the kit's other SPI-bus devices idle (always 1:
/// DAC deselected, DAC not cleared, SPI flash deselected, parallel flash disabled).
/// Optional: a deselect line is a port of `<name>_top` (with a LOC in the UCF) only when
/// `[board.pins]` pins it; otherwise it stays unconnected inside the top.
pub const DESELECT_PINS: &[&str] = pins!(SD_TOP_PORTS, Deselect);

/// Clock cycles from the rtl's `rst` to the blocks' reset, both ways: each block's reset is
/// `rst` registered once (`TopRtl::rst_adc` ...). `<name>_top`'s synchronizer adds
/// [`RESET_SYNC_CLOCKS`] on release.
pub const BLOCK_RESET_CLOCKS: u32 = 1;

/// Clock edges from the fall of `<name>_top`'s asynchronous `rst` to the fall of the rtl's
/// reset: the two flops of the wrapper's synchronizer (`rst_sync`); it asserts at once.
pub const RESET_SYNC_CLOCKS: u32 = 2;

/// Clock edges from the fall of `<name>_top`'s `rst` to the blocks' reset release.
pub const TOP_RESET_RELEASE_CLOCKS: u32 = RESET_SYNC_CLOCKS + BLOCK_RESET_CLOCKS;

/// Clock cycles from the conversion start that samples the inputs (a CONV rise, or a chip
/// select's fall on the chip-select ADCs) to `par_valid` for that sample:
/// ADC controller + correction + core (+ the position reference's stage with
/// `[reference]`, [`reference_cycles`]).
pub fn conv_to_position_cycles(d: &Derived) -> u32 {
    d.adc.conv_to_valid_clocks()
        + d.correction.latency_cycles()
        + d.latency_cycles
        + reference_cycles(d)
}

/// Clock cycles the position reference adds between the core and every position output
/// (0 without `[reference]`).
pub fn reference_cycles(d: &Derived) -> u32 {
    d.reference
        .map_or(0, |_| crate::blocks::reference::ReferenceParams::LATENCY)
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

/// `n` reset registers of optional blocks (see `TopRtl::rst_adc`).
fn resets(n: usize) -> Vec<InitBit> {
    (0..n).map(|_| InitBit::kept(true)).collect()
}

impl TopRtl {
    /// The top for the derived parameters: the blocks the configuration enables.
    pub fn new(d: &Derived) -> crate::error::Result<Self> {
        let [qshl, qshr, fshr] = biss_word_shifts(d);
        let vel = match &d.velocity {
            Some(p) => vec![Velocity::new(p)?],
            None => vec![],
        };
        let nvel = vel.len();
        let abz: Vec<AbzEmulator> = d.abz.iter().map(AbzEmulator::new).collect();
        let nabz = abz.len();
        let reference: Vec<PositionReference> =
            d.reference.iter().map(PositionReference::new).collect();
        let nref = reference.len();
        let absolute: Vec<AbsoluteStart> = d.absolute.iter().map(AbsoluteStart::new).collect();
        let nabs = absolute.len();
        let cap: Vec<Capture> = d.capture.iter().map(Capture::new).collect();
        let ncap = cap.len();
        let regs: Vec<RegisterMap> = d.registers.iter().map(RegisterMap::new).collect();
        let nreg = regs.len();
        Ok(Self::from_parts(TopParts {
            s_axi_awaddr: nreg,
            s_axi_awvalid: nreg,
            s_axi_wdata: nreg,
            s_axi_wstrb: nreg,
            s_axi_wvalid: nreg,
            s_axi_bready: nreg,
            s_axi_araddr: nreg,
            s_axi_arvalid: nreg,
            s_axi_rready: nreg,
            s_axi_awready: nreg,
            s_axi_wready: nreg,
            s_axi_bresp: nreg,
            s_axi_bvalid: nreg,
            s_axi_arready: nreg,
            s_axi_rdata: nreg,
            s_axi_rresp: nreg,
            s_axi_rvalid: nreg,
            regs,
            rst_regs: resets(nreg),
            bq_addr: bus_regs(d, nreg),
            bq_we: bus_regs(d, nreg),
            bq_wdata: bus_regs(d, nreg),
            bq_snap: bus_regs(d, nreg),
            rflags: (0..nreg).map(|_| Default::default()).collect(),
            fl_bits: (0..nreg)
                .flat_map(|_| FLAGS.iter().map(|f| c32(1 << f.lsb)))
                .collect(),
            fl_init: (0..nreg)
                .map(|_| {
                    c32(if d.reference.is_none() {
                        flag_bit("REFERENCED") as u64
                    } else {
                        0
                    })
                })
                .collect(),
            flags: nreg,
            capture: ncap,
            cap_valid: ncap,
            cap_qc: ncap,
            cap_fine: ncap,
            cap_turns: ncap,
            cap_age: ncap,
            cap_velocity: ncap.min(nvel),
            cap,
            rst_cap: resets(ncap),
            preset: nref,
            referenced: nref,
            reference,
            rst_ref: resets(nref),
            abs_data: nabs,
            abs_clk: nabs,
            absolute,
            rst_abs: resets(nabs),
            par_velocity: nvel,
            par_velocity_valid: nvel,
            abz_a: nabz,
            abz_b: nabz,
            abz_z: nabz,
            abz,
            vel,
            vel_fshl: (0..nvel).map(|_| c32(d.fine_bits as u64)).collect(),
            preamp: d.preamp.iter().map(PreampSetup::new).collect(),
            // With the register map the controller checks every frame (STATUS.ADC_FRAME).
            adc: if nreg > 0 {
                AdcController::with_frame_check(&d.adc)
            } else {
                AdcController::new(&d.adc)
            },
            correction: Correction::new(&d.correction),
            core: CoreRtl::new(d),
            monitor: Monitor::new(&d.monitor),
            qep_decoder: QepDecoder::new(&d.qep),
            fallback: Fallback::new(d),
            fb_conv_inv: (0..usize::from(conv_inverted(d)))
                .map(|_| Constant::new(true))
                .collect(),
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
            rst_adc: InitBit::kept(true),
            rst_correction: InitBit::kept(true),
            rst_core: InitBit::kept(true),
            rst_monitor: InitBit::kept(true),
            rst_qep: InitBit::kept(true),
            rst_biss: InitBit::kept(true),
            rst_preamp: resets(d.preamp.iter().count()),
            rst_ssi: resets(usize::from(d.ssi.is_some())),
            rst_spi: resets(usize::from(d.spi.is_some())),
            rst_abz: resets(nabz),
            rst_vel: resets(nvel),
        }))
    }
}

impl Logic for TopRtl {
    #[hdl_gen]
    fn update(&mut self) {
        // The ADC converts from reset, or once the pre-amplifier set-up is done; it owns
        // the serial clock, or shares it with the set-up.
        // The blocks' reset registers (see `rst_adc`).
        self.rst_adc.clock.next = self.clk.val();
        self.rst_adc.d.next = self.rst.val();
        self.rst_correction.clock.next = self.clk.val();
        self.rst_correction.d.next = self.rst.val();
        self.rst_core.clock.next = self.clk.val();
        self.rst_core.d.next = self.rst.val();
        self.rst_monitor.clock.next = self.clk.val();
        self.rst_monitor.d.next = self.rst.val();
        self.rst_qep.clock.next = self.clk.val();
        self.rst_qep.d.next = self.rst.val();
        self.rst_biss.clock.next = self.clk.val();
        self.rst_biss.d.next = self.rst.val();
        self.adc.clk.next = self.clk.val();
        self.adc.rst.next = self.rst_adc.q.val();
        self.adc.enable.next = true;
        self.adc_sck.next = self.adc.adc_sck.val();
        self.amp_cs.next = true;
        self.amp_mosi.next = false;
        self.amp_shdn.next = false;
        self.dac_cs.next = true;
        self.dac_clr.next = true;
        self.spi_ss_b.next = true;
        self.sf_ce0.next = true;
        for i in 0..self.preamp.len() {
            self.preamp[i].clk.next = self.clk.val();
            self.rst_preamp[i].clock.next = self.clk.val();
            self.rst_preamp[i].d.next = self.rst.val();
            self.preamp[i].rst.next = self.rst_preamp[i].q.val();
            self.preamp[i].adc_sck.next = self.adc.adc_sck.val();
            self.adc.enable.next = self.preamp[i].done.val();
            self.adc_sck.next = self.preamp[i].spi_sck.val();
            self.amp_cs.next = self.preamp[i].amp_cs.val();
            self.amp_mosi.next = self.preamp[i].spi_mosi.val();
            self.amp_shdn.next = self.preamp[i].amp_shdn.val();
            self.dac_cs.next = self.preamp[i].dac_cs.val();
            self.dac_clr.next = self.preamp[i].dac_clr.val();
            self.spi_ss_b.next = self.preamp[i].spi_ss_b.val();
            self.sf_ce0.next = self.preamp[i].sf_ce0.val();
        }
        self.adc.adc_miso.next = self.adc_miso.val();
        // The second data line (channel 1) of a two-line ADC.
        for i in 0..self.adc.adc_miso_b.len() {
            self.adc.adc_miso_b[i].next = self.adc_miso_b.val();
        }
        self.core.clk.next = self.clk.val();
        self.core.rst.next = self.rst_core.q.val();
        self.correction.clk.next = self.clk.val();
        self.correction.rst.next = self.rst_correction.q.val();
        self.correction.in_valid.next = self.adc.out_valid.val();
        self.correction.in_sin.next = self.adc.out_ch0.val();
        self.correction.in_cos.next = self.adc.out_ch1.val();
        self.core.in_valid.next = self.correction.out_valid.val();
        self.core.in_sin.next = self.correction.out_sin.val();
        self.core.in_cos.next = self.correction.out_cos.val();
        // The learned harmonic table learns from reset unless the register map says
        // otherwise (below).
        for j in 0..self.core.h_freeze.len() {
            self.core.h_freeze[j].next = false;
            self.core.h_ld[j].next = false;
            self.core.h_ld_addr[j].next = self.zero.val();
            self.core.h_ld_data[j].next = self.zero.val();
        }
        // Monitor: raw samples (full scale), CORDIC magnitude (loss of signal, clipping).
        self.monitor.clk.next = self.clk.val();
        self.monitor.rst.next = self.rst_monitor.q.val();
        self.monitor.in_valid.next = self.adc.out_valid.val();
        self.monitor.in_sin.next = self.adc.out_ch0.val();
        self.monitor.in_cos.next = self.adc.out_ch1.val();
        self.monitor.mag_valid.next = self.core.out_mag_valid.val();
        self.monitor.magnitude.next = self.core.out_mag.val();
        self.monitor.overspeed.next = false;
        self.monitor.qep_mismatch.next = self.fallback.mismatch.val();
        self.error.next = self.core.out_error.val() | self.monitor.error.val();
        // An ADC frame error (the frame check, with the register map) joins the error: the
        // sample is not the chip's.
        for i in 0..self.adc.frame_error.len() {
            self.error.next = self.core.out_error.val()
                | self.monitor.error.val()
                | self.adc.frame_error[i].val();
        }
        self.warning.next =
            self.core.out_warning.val() | self.monitor.warning.val() | self.fallback.active.val();
        // The position reference (`[reference] enabled`): "not referenced" joins the warning.
        for i in 0..self.reference.len() {
            self.warning.next = self.core.out_warning.val()
                | self.monitor.warning.val()
                | self.fallback.active.val()
                | self.reference[i].warning.val();
        }
        self.qep_decoder.clk.next = self.clk.val();
        self.qep_decoder.rst.next = self.rst_qep.q.val();
        self.qep_decoder.qep_a.next = self.qep_a.val();
        self.qep_decoder.qep_b.next = self.qep_b.val();
        self.qep_decoder.qep_z.next = self.qep_z.val();
        self.fallback.clk.next = self.clk.val();
        self.fallback.rst.next = self.rst_qep.q.val();
        self.fallback.enable.next = self.qep_enable.val();
        self.fallback.qep_up.next = self.qep_decoder.up.val();
        self.fallback.qep_down.next = self.qep_decoder.down.val();
        self.fallback.conv.next = self.adc.adc_conv.val();
        for i in 0..self.fb_conv_inv.len() {
            self.fallback.conv.next = self.adc.adc_conv.val() ^ self.fb_conv_inv[i].val();
        }
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
        // With the position reference every position output takes its position, one clock
        // after the core's; here the data word, below the others.
        for i in 0..self.reference.len() {
            self.reference[i].clk.next = self.clk.val();
            self.rst_ref[i].clock.next = self.clk.val();
            self.rst_ref[i].d.next = self.rst.val();
            self.reference[i].rst.next = self.rst_ref[i].q.val();
            self.reference[i].conv.next = self.adc.adc_conv.val();
            self.reference[i].z.next = self.qep_decoder.z_filt.val();
            self.reference[i].preset.next = self.preset[i].val();
            // A PRESET write of the register map acts as the pin does.
            for k in 0..self.regs.len() {
                self.reference[i].preset.next = self.preset[i].val() | self.regs[k].preset.val();
            }
            self.reference[i].in_valid.next = self.core.out_valid.val();
            self.reference[i].in_qc.next = self.core.out_qc.val();
            self.reference[i].in_fine.next = self.core.out_fine.val();
            self.reference[i].in_turns.next = self.core.out_turns.val();
            self.referenced[i].next = self.reference[i].referenced.val();
            // The absolute start's target (`[reference] absolute`; none: never asked).
            self.reference[i].abs_req.next = false;
            self.reference[i].abs_tq.next = self.zero.val();
            self.reference[i].abs_tqm.next = self.zero.val();
            self.reference[i].abs_tqp.next = self.zero.val();
            self.reference[i].abs_tt.next = self.zero.val();
            self.reference[i].abs_ttm.next = self.zero.val();
            self.reference[i].abs_ttp.next = self.zero.val();
            self.reference[i].abs_bq.next = self.zero.val();
            self.reference[i].abs_bt.next = self.zero.val();
            for k in 0..self.absolute.len() {
                self.reference[i].abs_req.next = self.absolute[k].req.val();
                self.reference[i].abs_tq.next = self.absolute[k].tq.val();
                self.reference[i].abs_tqm.next = self.absolute[k].tqm.val();
                self.reference[i].abs_tqp.next = self.absolute[k].tqp.val();
                self.reference[i].abs_tt.next = self.absolute[k].tt.val();
                self.reference[i].abs_ttm.next = self.absolute[k].ttm.val();
                self.reference[i].abs_ttp.next = self.absolute[k].ttp.val();
                self.reference[i].abs_bq.next = self.absolute[k].bq.val();
                self.reference[i].abs_bt.next = self.absolute[k].bt.val();
            }
            self.word.next = ((self.reference[i].out_qc.val() << self.qshl.val())
                >> self.qshr.val())
                | (self.reference[i].out_fine.val() >> self.fshr.val());
        }
        // The absolute start (`[reference] absolute`): the SSI master on abs_clk/abs_data,
        // tied to the ADC's conversions and the core's samples.
        for i in 0..self.absolute.len() {
            self.absolute[i].clk.next = self.clk.val();
            self.rst_abs[i].clock.next = self.clk.val();
            self.rst_abs[i].d.next = self.rst.val();
            self.absolute[i].rst.next = self.rst_abs[i].q.val();
            self.absolute[i].conv.next = self.adc.adc_conv.val();
            self.absolute[i].in_valid.next = self.core.out_valid.val();
            self.absolute[i].in_qc.next = self.core.out_qc.val();
            self.absolute[i].in_fine.next = self.core.out_fine.val();
            self.absolute[i].in_turns.next = self.core.out_turns.val();
            self.absolute[i].abs_data.next = self.abs_data[i].val();
            self.abs_clk[i].next = self.absolute[i].abs_clk.val();
        }
        self.biss_slave.clk.next = self.clk.val();
        self.biss_slave.rst.next = self.rst_biss.q.val();
        self.biss_slave.ma.next = self.biss_ma.val();
        self.biss_slave.pos.next = self.word.val();
        self.biss_slave.turns.next = self.core.out_turns.val();
        self.biss_slave.pos_valid.next = self.core.out_valid.val();
        self.biss_slave.error.next = self.error.val();
        self.biss_slave.warning.next = self.warning.val();
        for i in 0..self.reference.len() {
            self.biss_slave.turns.next = self.reference[i].out_turns.val();
            self.biss_slave.pos_valid.next = self.reference[i].out_valid.val();
        }
        self.biss_slo.next = self.biss_slave.slo.val();
        // Optional SSI and SPI slaves (a Vec of length 0 or 1), same data word as BiSS.
        self.ssi_data.next = true;
        for i in 0..self.ssi_slave.len() {
            self.ssi_slave[i].clk.next = self.clk.val();
            self.rst_ssi[i].clock.next = self.clk.val();
            self.rst_ssi[i].d.next = self.rst.val();
            self.ssi_slave[i].rst.next = self.rst_ssi[i].q.val();
            self.ssi_slave[i].ma.next = self.ssi_clk.val();
            self.ssi_slave[i].pos.next = self.word.val();
            self.ssi_slave[i].turns.next = self.core.out_turns.val();
            self.ssi_slave[i].pos_valid.next = self.core.out_valid.val();
            self.ssi_slave[i].error.next = self.error.val();
            for k in 0..self.reference.len() {
                self.ssi_slave[i].turns.next = self.reference[k].out_turns.val();
                self.ssi_slave[i].pos_valid.next = self.reference[k].out_valid.val();
            }
            // The velocity word (sent only with `[velocity] in_frames`).
            self.ssi_slave[i].vel.next = bit_cast::<64, 32>(self.zero.val());
            for k in 0..self.vel.len() {
                self.ssi_slave[i].vel.next = self.vel[k].out_velocity.val();
            }
            self.ssi_data.next = self.ssi_slave[i].slo.val();
        }
        self.enc_miso.next = false;
        self.enc_miso_oe.next = false;
        for i in 0..self.spi_slave.len() {
            self.spi_slave[i].clk.next = self.clk.val();
            self.rst_spi[i].clock.next = self.clk.val();
            self.rst_spi[i].d.next = self.rst.val();
            self.spi_slave[i].rst.next = self.rst_spi[i].q.val();
            self.spi_slave[i].sck.next = self.enc_sck.val();
            self.spi_slave[i].cs_n.next = self.enc_cs_n.val();
            self.spi_slave[i].pos.next = self.word.val();
            self.spi_slave[i].turns.next = self.core.out_turns.val();
            self.spi_slave[i].pos_valid.next = self.core.out_valid.val();
            self.spi_slave[i].error.next = self.error.val();
            self.spi_slave[i].warning.next = self.warning.val();
            for k in 0..self.reference.len() {
                self.spi_slave[i].turns.next = self.reference[k].out_turns.val();
                self.spi_slave[i].pos_valid.next = self.reference[k].out_valid.val();
            }
            self.spi_slave[i].vel.next = bit_cast::<64, 32>(self.zero.val());
            for k in 0..self.vel.len() {
                self.spi_slave[i].vel.next = self.vel[k].out_velocity.val();
            }
            self.enc_miso.next = self.spi_slave[i].miso.val();
            self.enc_miso_oe.next = self.spi_slave[i].miso_oe.val();
        }
        self.adc_conv.next = self.adc.adc_conv.val();
        self.par_valid.next = self.core.out_valid.val();
        self.par_qc.next = self.core.out_qc.val();
        self.par_fine.next = self.core.out_fine.val();
        self.par_turns.next = self.core.out_turns.val();
        self.par_error.next = self.error.val();
        self.par_warning.next = self.warning.val();
        for i in 0..self.reference.len() {
            self.par_valid.next = self.reference[i].out_valid.val();
            self.par_qc.next = self.reference[i].out_qc.val();
            self.par_fine.next = self.reference[i].out_fine.val();
            self.par_turns.next = self.reference[i].out_turns.val();
        }
        // The ABZ emulator of the parallel bus's position (`[abz] enabled`); its catch-up
        // flag joins the parallel bus's warning.
        for i in 0..self.abz.len() {
            self.abz[i].clk.next = self.clk.val();
            self.rst_abz[i].clock.next = self.clk.val();
            self.rst_abz[i].d.next = self.rst.val();
            self.abz[i].rst.next = self.rst_abz[i].q.val();
            self.abz[i].in_valid.next = self.core.out_valid.val();
            self.abz[i].in_qc.next = self.core.out_qc.val();
            self.abz[i].in_fine.next = self.core.out_fine.val();
            for k in 0..self.reference.len() {
                self.abz[i].in_valid.next = self.reference[k].out_valid.val();
                self.abz[i].in_qc.next = self.reference[k].out_qc.val();
                self.abz[i].in_fine.next = self.reference[k].out_fine.val();
            }
            self.abz_a[i].next = self.abz[i].abz_a.val();
            self.abz_b[i].next = self.abz[i].abz_b.val();
            self.abz_z[i].next = self.abz[i].abz_z.val();
            self.par_warning.next = self.warning.val() | self.abz[i].warning.val();
        }
        // The velocity estimator on the position modulo 2^(F+2) (`[velocity] enabled`).
        for i in 0..self.vel.len() {
            self.vel[i].clk.next = self.clk.val();
            self.rst_vel[i].clock.next = self.clk.val();
            self.rst_vel[i].d.next = self.rst.val();
            self.vel[i].rst.next = self.rst_vel[i].q.val();
            self.vel[i].in_valid.next = self.core.out_valid.val();
            self.vel[i].in_p.next =
                (self.core.out_qc.val() << self.vel_fshl[i].val()) | self.core.out_fine.val();
            self.par_velocity[i].next = self.vel[i].out_velocity.val();
            self.par_velocity_valid[i].next = self.vel[i].out_velocity_valid.val();
            // `[velocity] in_frames`: the serial slaves send it after the data word.
            for j in 0..self.biss_slave.vel.len() {
                self.biss_slave.vel[j].next = self.vel[i].out_velocity.val();
            }
        }
        // The synchronous capture (`[capture] enabled`) of the position every output takes
        // and of the velocity estimate.
        for i in 0..self.cap.len() {
            self.cap[i].clk.next = self.clk.val();
            self.rst_cap[i].clock.next = self.clk.val();
            self.rst_cap[i].d.next = self.rst.val();
            self.cap[i].rst.next = self.rst_cap[i].q.val();
            self.cap[i].capture.next = self.capture[i].val();
            self.cap[i].in_valid.next = self.core.out_valid.val();
            self.cap[i].in_qc.next = self.core.out_qc.val();
            self.cap[i].in_fine.next = self.core.out_fine.val();
            self.cap[i].in_turns.next = self.core.out_turns.val();
            for k in 0..self.reference.len() {
                self.cap[i].in_valid.next = self.reference[k].out_valid.val();
                self.cap[i].in_qc.next = self.reference[k].out_qc.val();
                self.cap[i].in_fine.next = self.reference[k].out_fine.val();
                self.cap[i].in_turns.next = self.reference[k].out_turns.val();
            }
            self.cap[i].in_velocity.next = bit_cast::<64, 32>(self.zero.val());
            for k in 0..self.vel.len() {
                self.cap[i].in_velocity.next = self.vel[k].out_velocity.val();
            }
            self.cap_valid[i].next = self.cap[i].out_valid.val();
            self.cap_qc[i].next = self.cap[i].out_qc.val();
            self.cap_fine[i].next = self.cap[i].out_fine.val();
            self.cap_turns[i].next = self.cap[i].out_turns.val();
            self.cap_age[i].next = self.cap[i].out_age.val();
        }
        for i in 0..self.cap_velocity.len() {
            self.cap_velocity[i].next = self.cap[i].out_velocity.val();
        }
        // The AXI4-Lite register map (`[registers] enabled`): the live flags, the position
        // every output takes, the velocity, the index and the capture.
        for i in 0..self.regs.len() {
            self.regs[i].clk.next = self.clk.val();
            self.rst_regs[i].clock.next = self.clk.val();
            self.rst_regs[i].d.next = self.rst.val();
            self.regs[i].rst.next = self.rst_regs[i].q.val();
            self.regs[i].s_axi_awaddr.next = self.s_axi_awaddr[i].val();
            self.regs[i].s_axi_awvalid.next = self.s_axi_awvalid[i].val();
            self.regs[i].s_axi_wdata.next = self.s_axi_wdata[i].val();
            self.regs[i].s_axi_wstrb.next = self.s_axi_wstrb[i].val();
            self.regs[i].s_axi_wvalid.next = self.s_axi_wvalid[i].val();
            self.regs[i].s_axi_bready.next = self.s_axi_bready[i].val();
            self.regs[i].s_axi_araddr.next = self.s_axi_araddr[i].val();
            self.regs[i].s_axi_arvalid.next = self.s_axi_arvalid[i].val();
            self.regs[i].s_axi_rready.next = self.s_axi_rready[i].val();
            self.s_axi_awready[i].next = self.regs[i].s_axi_awready.val();
            self.s_axi_wready[i].next = self.regs[i].s_axi_wready.val();
            self.s_axi_bresp[i].next = self.regs[i].s_axi_bresp.val();
            self.s_axi_bvalid[i].next = self.regs[i].s_axi_bvalid.val();
            self.s_axi_arready[i].next = self.regs[i].s_axi_arready.val();
            self.s_axi_rdata[i].next = self.regs[i].s_axi_rdata.val();
            self.s_axi_rresp[i].next = self.regs[i].s_axi_rresp.val();
            self.s_axi_rvalid[i].next = self.regs[i].s_axi_rvalid.val();
            self.rflags[i].next = self.fl_init[i].val();
            if self.monitor.los.val() {
                self.rflags[i].next = self.rflags[i].val() | self.fl_bits[0].val();
            }
            if self.monitor.clip.val() {
                self.rflags[i].next = self.rflags[i].val() | self.fl_bits[1].val();
            }
            if self.monitor.full_scale.val() {
                self.rflags[i].next = self.rflags[i].val() | self.fl_bits[2].val();
            }
            if self.core.out_warning.val() {
                self.rflags[i].next = self.rflags[i].val() | self.fl_bits[3].val();
            }
            if self.fallback.mismatch.val() {
                self.rflags[i].next = self.rflags[i].val() | self.fl_bits[4].val();
            }
            if self.fallback.active.val() {
                self.rflags[i].next = self.rflags[i].val() | self.fl_bits[5].val();
            }
            for k in 0..self.reference.len() {
                if self.reference[k].referenced.val() {
                    self.rflags[i].next = self.rflags[i].val() | self.fl_bits[6].val();
                }
            }
            if self.error.val() {
                self.rflags[i].next = self.rflags[i].val() | self.fl_bits[7].val();
            }
            if self.warning.val() {
                self.rflags[i].next = self.rflags[i].val() | self.fl_bits[8].val();
            }
            for k in 0..self.adc.frame_error.len() {
                if self.adc.frame_error[k].val() {
                    self.rflags[i].next = self.rflags[i].val() | self.fl_bits[9].val();
                }
            }
            for k in 0..self.reference.len() {
                if !self.reference[k].referenced.val() {
                    self.rflags[i].next = self.rflags[i].val() | self.fl_bits[10].val();
                }
            }
            self.regs[i].flags.next = self.rflags[i].val();
            self.flags[i].next = self.rflags[i].val();
            // The BiSS control channel's user area is the map's banks (docs/registers.md).
            self.regs[i].bus_addr.next = self.zero.val();
            self.regs[i].bus_we.next = false;
            self.regs[i].bus_wdata.next = bit_cast::<8, 32>(self.zero.val());
            self.regs[i].bus_snap.next = false;
            // The learned harmonic table's learner (`[harmonics] mode = "learn"`): its
            // writes feed the map's copy; HARM_CONTROL and HARM_ENTRY steer it.
            self.regs[i].h_tw.next = false;
            self.regs[i].h_tw_addr.next = self.zero.val();
            self.regs[i].h_tw_data.next = self.zero.val();
            self.regs[i].h_bank.next = false;
            self.regs[i].h_ld_busy.next = false;
            for j in 0..self.core.h_tw.len() {
                self.regs[i].h_tw.next = self.core.h_tw[j].val();
                self.regs[i].h_tw_addr.next = self.core.h_tw_addr[j].val();
                self.regs[i].h_tw_data.next = self.core.h_tw_data[j].val();
                self.regs[i].h_bank.next = self.core.h_bank[j].val();
                self.regs[i].h_ld_busy.next = self.core.h_ld_busy[j].val();
                self.core.h_freeze[j].next = !self.regs[i].h_update.val();
                self.core.h_ld[j].next = self.regs[i].h_ld.val();
                self.core.h_ld_addr[j].next = self.regs[i].h_ld_addr.val();
                self.core.h_ld_data[j].next = self.regs[i].h_ld_data.val();
            }
            for j in 0..self.biss_slave.reg_addr.len() {
                self.bq_addr[j].clock.next = self.clk.val();
                self.bq_we[j].clock.next = self.clk.val();
                self.bq_wdata[j].clock.next = self.clk.val();
                self.bq_snap[j].clock.next = self.clk.val();
                self.bq_addr[j].d.next = self.biss_slave.reg_addr[j].val();
                self.bq_we[j].d.next = self.biss_slave.reg_we[j].val();
                self.bq_wdata[j].d.next = self.biss_slave.reg_wdata[j].val();
                self.bq_snap[j].d.next = self.biss_slave.reg_snap[j].val();
                self.regs[i].bus_addr.next = self.bq_addr[j].q.val();
                self.regs[i].bus_we.next = self.bq_we[j].q.val();
                self.regs[i].bus_wdata.next = self.bq_wdata[j].q.val();
                self.regs[i].bus_snap.next = self.bq_snap[j].q.val();
                self.biss_slave.reg_rdata[j].next = self.regs[i].bus_rdata.val();
            }
            self.monitor.thr_los[i].next = self.regs[i].los_threshold.val();
            self.monitor.thr_rel[i].next = self.regs[i].los_release.val();
            self.monitor.thr_clip[i].next = self.regs[i].clip_threshold.val();
            // The correction's codes: read live, written through its load port.
            self.regs[i].cor_off_s.next = self.correction.w_off_s[i].val();
            self.regs[i].cor_off_c.next = self.correction.w_off_c[i].val();
            self.regs[i].cor_gain_s.next = self.correction.w_gain_s[i].val();
            self.regs[i].cor_gain_c.next = self.correction.w_gain_c[i].val();
            self.regs[i].cor_phase.next = self.correction.w_phase[i].val();
            self.correction.ld[i].next = self.regs[i].cor_ld.val();
            self.correction.ld_bits[i].next = self.regs[i].cor_bits.val();
            self.correction.ld_msk[i].next = self.regs[i].cor_msk.val();
            self.regs[i].amp_valid.next = self.core.out_mag_valid.val();
            self.regs[i].amplitude.next = self.core.out_mag.val();
            self.regs[i].qc.next = self.core.out_qc.val();
            self.regs[i].fine.next = self.core.out_fine.val();
            self.regs[i].turns.next = self.core.out_turns.val();
            self.regs[i].index_qc.next = self.zero.val();
            self.regs[i].index_turns.next = self.zero.val();
            for k in 0..self.reference.len() {
                self.regs[i].qc.next = self.reference[k].out_qc.val();
                self.regs[i].fine.next = self.reference[k].out_fine.val();
                self.regs[i].turns.next = self.reference[k].out_turns.val();
                self.regs[i].index_qc.next = self.reference[k].index_qc.val();
                self.regs[i].index_turns.next = self.reference[k].index_turns.val();
            }
            self.regs[i].velocity.next = bit_cast::<64, 32>(self.zero.val());
            for k in 0..self.vel.len() {
                self.regs[i].velocity.next = self.vel[k].out_velocity.val();
            }
            self.regs[i].cap_qc.next = self.zero.val();
            self.regs[i].cap_fine.next = self.zero.val();
            self.regs[i].cap_turns.next = self.zero.val();
            self.regs[i].cap_velocity.next = bit_cast::<64, 32>(self.zero.val());
            self.regs[i].cap_age.next = self.zero.val();
            for k in 0..self.cap.len() {
                self.regs[i].cap_qc.next = self.cap[k].out_qc.val();
                self.regs[i].cap_fine.next = self.cap[k].out_fine.val();
                self.regs[i].cap_turns.next = self.cap[k].out_turns.val();
                self.regs[i].cap_velocity.next = self.cap[k].out_velocity.val();
                self.regs[i].cap_age.next = self.cap[k].out_age.val();
            }
        }
    }
}
