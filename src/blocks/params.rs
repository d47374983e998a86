//! The parameter set the blocks are built from: [`Derived`], computed once from a validated
//! configuration by `crate::config` (`Derived::compute`), with the CORDIC's
//! [`Architecture`] and the capacitive path's [`CapacitiveConfig`] and [`CapDerived`].
//!
//! It lives with the blocks so that the dependencies run one way: `config` builds these
//! types and the blocks read them; no block imports `config`.

use crate::blocks::adc::AdcParams;
use crate::blocks::biss::BissParams;
use crate::blocks::correction::CorrectionParams;
use crate::blocks::monitor::MonitorParams;
use crate::blocks::preamp::PreampParams;
use crate::blocks::qep::QepParams;
use crate::blocks::spi_slave::SpiSlaveParams;
use crate::blocks::ssi::SsiParams;
use serde::Deserialize;

impl PartialEq for CapDerived {
    /// Equal when the configuration, the rate and the quantized sections are (the rest of a
    /// design follows from them).
    fn eq(&self, o: &Self) -> bool {
        self.config == o.config
            && self.sample_rate_hz == o.sample_rate_hz
            && self.bandpass.sos == o.bandpass.sos
            && self.lowpass.sos == o.lowpass.sos
    }
}

/// Derived capacitive-path parameters: the designed, quantized filters.
#[derive(Clone, Debug, serde::Serialize)]
pub struct CapDerived {
    /// The configuration section.
    pub config: CapacitiveConfig,
    /// The ADC's sample rate (= the filters' sample rate and the NCO update rate).
    pub sample_rate_hz: f64,
    /// Band-pass design (ideal, quantized, response; attenuation probed at 2 carrier).
    pub bandpass: crate::filter::Designed,
    /// Low-pass design (probed at 2 carrier).
    pub lowpass: crate::filter::Designed,
}

/// Parameters computed once from a validated configuration (`crate::config::Config`).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Derived {
    /// ADC controller parameters (validated).
    pub adc: AdcParams,
    /// Pre-amplifier set-up (LTC1407A-1 preset only).
    pub preamp: Option<PreampParams>,
    /// BiSS-C slave of the board top.
    pub biss: BissParams,
    /// SSI slave of the board top, when enabled.
    pub ssi: Option<SsiParams>,
    /// SPI slave of the board top, when enabled.
    pub spi: Option<SpiSlaveParams>,
    /// Offset/gain correction of the board top.
    pub correction: CorrectionParams,
    /// Signal monitor of the board top.
    pub monitor: MonitorParams,
    /// QEP decoder of the board top.
    pub qep: QepParams,
    /// QEP fallback enabled.
    pub qep_enabled: bool,
    /// ABZ emulator of the board top, when `[abz] enabled` (left out of the parameter
    /// file when disabled, so configurations without it keep their bytes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub abz: Option<crate::blocks::abz::AbzParams>,
    /// Velocity estimator of the core, when `[velocity] enabled` (left out of the parameter
    /// file when disabled, like `abz`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub velocity: Option<crate::blocks::velocity::VelocityParams>,
    /// Position reference of the board top, when `[reference] enabled` (left out of the
    /// parameter file when disabled, like `abz`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<crate::blocks::reference::ReferenceParams>,
    /// Absolute start of the board top, when `[reference] absolute = "ssi"` (left out of the
    /// parameter file otherwise, like `abz`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub absolute: Option<crate::blocks::absolute::AbsoluteParams>,
    /// Synchronous capture of the board top, when `[capture] enabled` (left out of the
    /// parameter file when disabled, like `abz`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub capture: Option<crate::blocks::capture::CaptureParams>,
    /// Harmonic-correction table of the core, when `[harmonics] enabled` (left out of the
    /// parameter file when disabled, like `abz`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub harmonics: Option<crate::blocks::harmonics::HarmonicParams>,
    /// Register map of the board top, when `[registers] enabled` (left out of the
    /// parameter file when disabled, like `abz`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub registers: Option<crate::blocks::regmap::RegmapParams>,
    /// ADC sample width A.
    pub adc_width: u32,
    /// Capacitive path, when `[capacitive]` is present.
    pub capacitive: Option<CapDerived>,
    /// CORDIC iterations N.
    pub iterations: u32,
    /// Fine bits F.
    pub fine_bits: u32,
    /// Fractional guard bits of x/y (below the input LSB).
    pub xy_guard: u32,
    /// x/y datapath width: A + 2 integer bits (sign, quadrant mapping of -2^(A-1), CORDIC
    /// growth K*sqrt(2) < 2.33) + guard bits.
    pub xy_width: u32,
    /// Fractional guard bits of the angle accumulator (below the fine LSB).
    pub z_guard: u32,
    /// Angle accumulator width: F + guard + 2 (sign and the 1.11-quadrant reach).
    pub z_width: u32,
    /// atan(2^-i)/(pi/2) in units of 2^-(F + z_guard) quadrant, i = 0..N.
    pub atan_table: Vec<u64>,
    /// CORDIC gain K_N.
    pub gain: f64,
    /// Magnitude threshold in x units (K * min_amplitude * 2^(A-1) * 2^xy_guard, rounded up).
    pub min_magnitude: u64,
    /// Quadrants per turn: 4 * PPR.
    pub quadrants_per_turn: u64,
    /// Bits of the coarse quadrant count (enough for 4*PPR - 1).
    pub quadrant_bits: u32,
    /// Width of `out_position`: quadrant_bits + F.
    pub position_width: u32,
    /// Width of `out_turns` (at least 1; always zero when multiturn_bits = 0).
    pub turns_width: u32,
    /// Multi-turn bits M as configured.
    pub multiturn_bits: u32,
    /// A step of at least this many fine LSB between samples raises the warning.
    pub warn_step: u64,
    /// Latency from the `in_valid` cycle to the `out_valid` cycle.
    pub latency_cycles: u32,
    /// CORDIC architecture.
    pub architecture: Architecture,
    /// Clocks per accepted sample: 1 (unrolled) or N·ceil(W/4) (iterative).
    pub cycles_per_sample: u32,
    /// Clock frequency in Hz.
    pub clock_hz: f64,
    /// Sample rate per channel in Hz.
    pub sample_rate_hz: f64,
    /// Highest speed (rpm) at which every sample stays below `warn_step`.
    pub max_speed_rpm_full_res: f64,
    /// Resolution bits per turn: log2(4 * PPR * 2^F).
    pub resolution_bits: f64,
    /// The board clock (with `[board]`): the oscillator and the DCM/PLL making the system
    /// clock from it, if it differs (see `crate::board`).
    pub board_clock: Option<crate::board::BoardClock>,
    /// The ADC interface's I/O timing budget (`[board]` keys or defaults).
    pub io_timing: crate::board::IoTiming,
}

/// `cordic.architecture`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Architecture {
    /// N registered stages: latency N + 2, one sample per clock.
    #[default]
    Unrolled,
    /// One digit-serial shift-add stage reused N times: S = N·ceil(W/4) clocks per
    /// sample, latency S + 2 (see `crate::blocks::cordic::iterative`).
    Iterative,
}

impl std::fmt::Display for Architecture {
    /// The spelling of `cordic.architecture`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Architecture::Unrolled => "unrolled",
            Architecture::Iterative => "iterative",
        })
    }
}

/// `[capacitive]`: excitation NCO, filters and widths of the capacitive path. The ADC
/// (`[adc]`, preset `generic`, one channel) samples the receiver signal A sin(wt + theta);
/// `encoder.ppr` is the number of signal periods per turn (16 in the paper).
#[derive(Clone, Debug, PartialEq, Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct CapacitiveConfig {
    /// Excitation carrier frequency in Hz (10 kHz..1 MHz, below half the sample rate).
    pub carrier_hz: f64,
    /// Excitation amplitude as a fraction of the DAC's full scale, (0, 1].
    pub amplitude: f64,
    /// Width of the excitation DAC words exc_sin/exc_cos (8..=16).
    #[serde(default = "cap_dac_width")]
    pub dac_width: u32,
    /// NCO phase accumulator bits (8..=32).
    #[serde(default = "cap_phase_bits")]
    pub phase_bits: u32,
    /// NCO quarter-wave table address bits (4..=12).
    #[serde(default = "cap_table_bits")]
    pub table_bits: u32,
    /// Data width of the filters and of the CORDIC's inputs (12..=16 bits, >= adc.width;
    /// default 16, the CORDIC's widest input).
    #[serde(default = "cap_data_width")]
    pub data_width: u32,
    /// Fractional guard bits the biquad engine keeps below the data LSB in its state.
    #[serde(default = "cap_guard_frac")]
    pub guard_frac: u32,
    /// Filter coefficient format.
    pub coef: crate::filter::CoefFormat,
    /// Band-pass in front of the demodulator (the paper: 15-25 kHz at 400 kHz).
    pub bandpass: crate::filter::FilterSpec,
    /// Low-pass after the demodulator (removes 2w), applied to both branches.
    pub lowpass: crate::filter::FilterSpec,
}

fn cap_dac_width() -> u32 {
    16
}

fn cap_phase_bits() -> u32 {
    32
}

fn cap_table_bits() -> u32 {
    8
}

fn cap_data_width() -> u32 {
    16
}

fn cap_guard_frac() -> u32 {
    8
}
