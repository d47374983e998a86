//! Configuration: the TOML schema, its validation, and the parameters derived from it.
//!
//! Parameters flow one way: TOML text -> [`Config`] (parsed, ranges checked while
//! deserializing so errors carry line and column) -> [`Derived`] (cross-field checks,
//! widths, tables and figures computed once) -> the rust-hdl blocks and the Rust model.
//!
//! Supported ranges (enforced here, stated in the README):
//!
//! | key | range |
//! |---|---|
//! | `adc.width` | 10..=16 bits |
//! | `cordic.iterations` | 1..=20 |
//! | `cordic.fine_bits` | 2..=16 |
//! | `cordic.guard_bits` | 0..=19 and `adc.width` + 2 + guard <= 31 (default: derived) |
//! | `cordic.architecture` | `"unrolled"` (default) or `"iterative"` |
//! | `encoder.ppr` | 1..=65535 |
//! | `encoder.multiturn_bits` | 0..=16 |
//! | `clock.frequency_hz` | 1 MHz..=500 MHz |
//! | `adc.sample_rate_hz` | up to the ADC's limit and the clock |
//! | `correction.periods` | 1..=256 |
//! | `correction.gain_frac_bits` | 8..=15 |
//! | `monitor.los_window`, `monitor.clip_hold` | 1..=65535 samples |
//!
//! `check`, `generate`, `simulate` and `report` all validate through [`Loaded::parse`]
//! (`Derived::compute`), which also builds the capacitive front end's parameters, so a
//! configuration one command accepts is accepted by all of them.

use crate::blocks::adc::{AdcFrame, AdcParams, AdcTiming, SignFormat};
use crate::blocks::biss::BissParams;
use crate::blocks::correction::{gain_code, CorrectionParams};
use crate::blocks::monitor::MonitorParams;
use crate::blocks::preamp::PreampParams;
use crate::blocks::qep::QepParams;
use crate::blocks::spi_slave::SpiSlaveParams;
use crate::blocks::ssi::SsiParams;
use crate::error::{Error, Quoted, Result};
use crate::exact;
use serde::{Deserialize, Deserializer};

/// The default configuration (the thesis's Spartan-3AN Starter Kit design), embedded.
pub const DEFAULT_CONFIG: &str = include_str!("../configs/spartan3an.toml");
/// Name used in messages for the embedded default.
pub const DEFAULT_NAME: &str = "<default spartan3an.toml>";

/// Largest internal datapath word: rust-hdl stores words above 32 bits bit by bit.
pub const MAX_WORD_BITS: u32 = 31;

macro_rules! ranged {
    ($fn_name:ident, $ty:ty, $key:expr, $lo:expr, $hi:expr, $unit:expr) => {
        #[allow(unused_comparisons)]
        fn $fn_name<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<$ty, D::Error> {
            let v = <$ty>::deserialize(d)?;
            if !($lo..=$hi).contains(&v) {
                return Err(serde::de::Error::custom(format!(
                    "`{}` = {} is out of range: allowed {}..={}{}",
                    $key, v, $lo, $hi, $unit
                )));
            }
            Ok(v)
        }
    };
}

ranged!(r_width, u32, "adc.width", 10, 16, " bits");
ranged!(r_iter, u32, "cordic.iterations", 1, 20, "");
ranged!(r_fine, u32, "cordic.fine_bits", 2, 16, " bits");
ranged!(r_ppr, u32, "encoder.ppr", 1, 65535, " periods per turn");
ranged!(r_mt, u32, "encoder.multiturn_bits", 0, 16, " bits");
ranged!(
    r_periods,
    u32,
    "correction.periods",
    1,
    256,
    " signal periods"
);
ranged!(
    r_gain_frac,
    u32,
    "correction.gain_frac_bits",
    8,
    15,
    " bits"
);
ranged!(r_clk, f64, "clock.frequency_hz", 1.0e6, 500.0e6, " Hz");
ranged!(
    r_amp,
    f64,
    "monitor.min_amplitude",
    0.0,
    0.9,
    " (fraction of full scale)"
);

/// Largest `cordic.guard_bits`: the x/y datapath (adc.width + 2 + guard) holds at most
/// [`MAX_WORD_BITS`] bits, and adc.width is at least 10.
pub const MAX_GUARD_BITS: u32 = MAX_WORD_BITS - 2 - 10;

fn r_guard<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<u32>, D::Error> {
    let v = u32::deserialize(d)?;
    if v > MAX_GUARD_BITS {
        return Err(serde::de::Error::custom(format!(
            "`cordic.guard_bits` = {v} is out of range: allowed 0..={MAX_GUARD_BITS}, and adc.width + 2 + guard_bits <= {MAX_WORD_BITS} (omit it to derive it)"
        )));
    }
    Ok(Some(v))
}

fn r_name<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<String, D::Error> {
    let v = String::deserialize(d)?;
    let ok = !v.is_empty()
        && v.len() <= 32
        && v.chars().next().is_some_and(|c| c.is_ascii_alphabetic())
        && v.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
    if !ok {
        return Err(serde::de::Error::custom(format!(
            "`name` = {} is not allowed: 1 to 32 characters of [A-Za-z0-9_], starting with a letter",
            Quoted(&v)
        )));
    }
    Ok(v)
}

/// The FPGA family the design is emitted for.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "lowercase")]
pub enum Target {
    /// Xilinx Spartan-3AN (XC3S700AN, Starter Kit).
    Spartan3an,
    /// Intel/Altera Cyclone III (EP3C40F324C8).
    Cyclone3,
}

/// ADC chip presets.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum AdcPreset {
    /// LTC1407A-1: dual 14-bit, 3 Msps total (1.5 Msps per channel).
    #[serde(rename = "ltc1407a-1")]
    Ltc1407a1,
    /// Any other SPI ADC (limits come from `adc.max_sample_rate_hz`).
    #[serde(rename = "generic")]
    Generic,
}

/// Whole configuration file.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Config {
    /// Prefix of every emitted module name.
    #[serde(deserialize_with = "r_name")]
    pub name: String,
    /// FPGA family.
    pub target: Target,
    /// System clock.
    pub clock: ClockConfig,
    /// The encoder being read.
    pub encoder: EncoderConfig,
    /// The ADC that samples sin and cos.
    pub adc: AdcConfig,
    /// The CORDIC fine interpolator.
    pub cordic: CordicConfig,
    /// Signal monitoring.
    #[serde(default)]
    pub monitor: MonitorConfig,
    /// Pre-amplifier gains (LTC1407A-1 preset).
    #[serde(default)]
    pub preamp: Option<PreampConfig>,
    /// BiSS-C output of the board top.
    #[serde(default)]
    pub biss: BissConfig,
    /// Offset and gain correction of the board top.
    #[serde(default)]
    pub correction: CorrectionConfig,
    /// External QEP A/B/Z inputs of the board top.
    #[serde(default)]
    pub qep: QepConfig,
    /// Board pins: with this section `generate` writes `<name>_top.ucf` (and, with the kit
    /// preset, the BitGen option file `<name>_top.ut`).
    #[serde(default)]
    pub board: Option<BoardConfig>,
    /// SSI output of the board top (pins `ssi_clk`, `ssi_data`).
    #[serde(default)]
    pub ssi: SsiConfig,
    /// SPI-slave output of the board top (pins `enc_sck`, `enc_cs_n`, `enc_miso`,
    /// `enc_miso_oe`).
    #[serde(default)]
    pub spi: SpiConfig,
    /// Capacitive-encoder path (docs/capacitive.md): with this section `<name>_top` is the
    /// capacitive top (excitation NCO, band-pass, demodulation, low-pass, CORDIC).
    #[serde(default)]
    pub capacitive: Option<CapacitiveConfig>,
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
    /// Data width of the filters and of the CORDIC's inputs (12..=16 bits, >= adc.width).
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
    18
}
fn cap_guard_frac() -> u32 {
    8
}

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

/// `[ssi]`: SSI slave sending the same data word as BiSS (biss.position_bits and
/// biss.multiturn_bits).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SsiConfig {
    /// Include the SSI slave.
    #[serde(default)]
    pub enabled: bool,
    /// Gray-coded data word.
    #[serde(default)]
    pub gray: bool,
    /// Monoflop time in microseconds (default 20).
    pub timeout_us: Option<f64>,
}

/// `[spi]`: SPI slave (modes 0 and 3) sending the BiSS data word then E and W.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpiConfig {
    /// Include the SPI slave.
    #[serde(default)]
    pub enabled: bool,
    /// Gray-coded data word.
    #[serde(default)]
    pub gray: bool,
}

/// `[board]`: pin locations of `<name>_top`'s ports for the UCF.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoardConfig {
    /// Board whose fixed pins are filled in: "spartan3an-starter-kit" (see
    /// [`STARTER_KIT_PINS`]; also writes `<name>_top.ut` with `-g UnusedPin:PullUp`).
    #[serde(default)]
    pub preset: Option<String>,
    /// I/O standard of every pin (e.g. "LVCMOS33"); the preset's when omitted.
    #[serde(default)]
    pub iostandard: Option<String>,
    /// Port name -> package pin (e.g. adc_conv = "Y6"), or a list of pins LSB first for a
    /// bus (exc_sin = ["A1", "B1", ...]). Every port of the top except the parallel bus
    /// (`par_*`, meant for logic in the same FPGA) needs one (see [`board_ports`]); the
    /// [`DESELECT_PINS`] are optional and become ports when pinned. These override the
    /// preset's.
    #[serde(default)]
    pub pins: std::collections::BTreeMap<String, PinValue>,
    /// Oscillator on the `clk` pin, Hz: 50 MHz with the Starter Kit preset, else
    /// `clock.frequency_hz`. When it differs from the system clock, `generate` writes
    /// `<name>_board.v` with a DCM_SP (Spartan-3AN) or ALTPLL (Cyclone III) making it.
    #[serde(default)]
    pub clock_hz: Option<f64>,
    /// Budget for the FPGA's clock-to-output of the ADC outputs, ns (default 6; the
    /// UCF/SDC make the vendor tool verify it). See `crate::board`.
    #[serde(default)]
    pub fpga_clock_to_out_ns: Option<f64>,
    /// Budget for the FPGA's pad set-up at `adc_miso`, ns (default 3; verified likewise).
    #[serde(default)]
    pub fpga_input_setup_ns: Option<f64>,
    /// One board trace between the FPGA and the ADC, ns (default 1: about 15 cm).
    #[serde(default)]
    pub trace_delay_ns: Option<f64>,
}

/// A pin (`"Y6"`) or the pins of a bus, LSB first.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(untagged)]
pub enum PinValue {
    /// One package pin.
    One(String),
    /// One package pin per bit, LSB first.
    Bus(Vec<String>),
}

impl PinValue {
    /// The single pin, if this is one.
    pub fn one(&self) -> Option<&str> {
        match self {
            PinValue::One(s) => Some(s),
            PinValue::Bus(_) => None,
        }
    }
}

pub use crate::blocks::captop::hdl::{CAP_TOP_BUSES, CAP_TOP_PINS};

/// The board top's pinned ports for this configuration: (name, None) for a pin,
/// (name, Some(width)) for a bus. These are exactly the ports of `<name>_top` but the
/// parallel bus: on the sinewave top [`TOP_PINS`], the [`QEP_PINS`] with `[qep] enabled`,
/// [`SSI_PINS`] / [`SPI_PINS`] when those slaves are enabled and each of the
/// [`DESELECT_PINS`] that `[board.pins]` pins. Every one needs a pin.
pub fn board_ports(c: &Config) -> Vec<(&'static str, Option<u32>)> {
    match &c.capacitive {
        Some(k) => CAP_TOP_PINS
            .iter()
            .map(|p| (*p, None))
            .chain(CAP_TOP_BUSES.iter().map(|b| (*b, Some(k.dac_width))))
            .collect(),
        None => {
            use crate::blocks::top::ports::Pin;
            let pins = c
                .board
                .as_ref()
                .map(|b| b.effective_pins())
                .unwrap_or_default();
            // In the wrapper's port order (the port table's).
            crate::blocks::top::hdl::SD_TOP_PORTS
                .iter()
                .filter(|p| match p.pin {
                    Pin::Always => true,
                    Pin::Deselect => pins.contains_key(p.name),
                    Pin::Qep => c.qep.enabled,
                    Pin::Ssi => c.ssi.enabled,
                    Pin::Spi => c.spi.enabled,
                    Pin::DacBus | Pin::Parallel => false,
                })
                .map(|p| (p.name, None))
                .collect()
        }
    }
}

/// The Spartan-3A/3AN Starter Kit's pins that sinedec knows with a source: the SPI bus of
/// the analog capture circuit (UG334 chapter 9: SPI_SCK, AD_CONV, AD_DOUT, SPI_MOSI,
/// AMP_CS, AMP_SHDN), the 50 MHz oscillator CLK_50M (E12) and the BTN_SOUTH push button
/// (T15) as reset.
///
/// The header pins for the comparators (`qep_a/b/z` with `[qep] enabled`), the BiSS
/// transceiver and the SSI / SPI slaves are wiring on the kit's headers: give them in
/// `[board.pins]`. The other devices on the kit's SPI bus (DAC_CS, DAC_CLR, SPI_SS_B,
/// SF_CE0; see [`DESELECT_PINS`]) are not filled in either: their locations are not known
/// here. Each SPI slave on the kit has its own data-out line (UG334 chapter 9: AD_DOUT,
/// AMP_DOUT; chapter 10: DAC_OUT), so they cannot contend with the ADC or the amplifier;
/// with the preset, `generate` writes `<name>_top.ut` (BitGen `-g UnusedPin:PullUp`), whose
/// pull-ups on unused pins hold the active-low selects DAC_CS, SPI_SS_B and SF_CE0
/// deasserted. Pin a deselect line in `[board.pins]` to have the top drive it.
pub const STARTER_KIT_PINS: &[(&str, &str)] = &[
    ("clk", "E12"),
    ("rst", "T15"),
    ("adc_sck", "AA20"),
    ("adc_conv", "Y6"),
    ("adc_miso", "D16"),
    ("amp_mosi", "AB14"),
    ("amp_cs", "W6"),
    ("amp_shdn", "W15"),
];

/// Board presets (`board.preset`).
pub const BOARD_PRESETS: &[&str] = &["spartan3an-starter-kit"];

impl BoardConfig {
    /// The preset's pins overridden by `[board.pins]`.
    pub fn effective_pins(&self) -> std::collections::BTreeMap<String, PinValue> {
        let mut m = std::collections::BTreeMap::new();
        if self.preset.as_deref() == Some("spartan3an-starter-kit") {
            for (k, v) in STARTER_KIT_PINS {
                m.insert(k.to_string(), PinValue::One(v.to_string()));
            }
        }
        for (k, v) in &self.pins {
            m.insert(k.clone(), v.clone());
        }
        m
    }

    /// The I/O standard: the configured one, else the preset's (LVCMOS33 on the kit).
    pub fn effective_iostandard(&self) -> Option<String> {
        self.iostandard
            .clone()
            .or_else(|| self.preset.as_ref().map(|_| "LVCMOS33".to_string()))
    }
}

pub use crate::blocks::top::hdl::{DESELECT_PINS, QEP_PINS, SPI_PINS, SSI_PINS, TOP_PINS};

/// `[qep]`: comparator outputs A (cos > 0), B (sin > 0), Z (index) on `qep_a/b/z`.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct QepConfig {
    /// Use the QEP count as cross-check and high-speed fallback.
    pub enabled: bool,
    /// Glitch filter: clocks a level must be stable (1..=65535).
    pub filter_clocks: u32,
}

impl Default for QepConfig {
    fn default() -> Self {
        QepConfig {
            enabled: false,
            filter_clocks: 4,
        }
    }
}

/// `[biss]`: the BiSS-C slave of `<name>_top` (pins `biss_ma`, `biss_slo`).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BissConfig {
    /// Single-turn data bits: the most significant bits of `out_position` (default: all of
    /// them, at most 32).
    pub position_bits: Option<u32>,
    /// Multi-turn bits sent ahead of the position (default 0; at most encoder.multiturn_bits
    /// and position_bits + multiturn_bits <= 32).
    pub multiturn_bits: Option<u32>,
    /// Gray-code the data word (default false).
    pub gray: Option<bool>,
    /// MA periods of Ack before Start (1..=64, default 1).
    pub ack_periods: Option<u32>,
    /// Timeout in microseconds (default 20).
    pub timeout_us: Option<f64>,
}

/// `[clock]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClockConfig {
    /// System clock frequency in Hz.
    #[serde(deserialize_with = "r_clk")]
    pub frequency_hz: f64,
}

/// `[encoder]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EncoderConfig {
    /// Signal periods (sine cycles) per mechanical turn.
    #[serde(deserialize_with = "r_ppr")]
    pub ppr: u32,
    /// Width of the signed multi-turn counter (0 = single-turn only).
    #[serde(deserialize_with = "r_mt")]
    pub multiturn_bits: u32,
}

/// `[adc]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AdcConfig {
    /// Chip preset.
    pub preset: AdcPreset,
    /// Sample width in bits (two's complement).
    #[serde(deserialize_with = "r_width")]
    pub width: u32,
    /// Target sample rate per channel (the rate reached is at most this); omitted: the
    /// fastest the chip and the clock allow.
    #[serde(default)]
    pub sample_rate_hz: Option<f64>,
    /// SCK period in system clocks (>= 2, odd allowed); omitted: the fastest allowed.
    #[serde(default)]
    pub sck_period_clocks: Option<u32>,
    /// Upper limit of the chip's per-channel rate (required for `generic`).
    #[serde(default)]
    pub max_sample_rate_hz: Option<f64>,
    /// Frame format of a `generic` ADC.
    #[serde(default)]
    pub frame: Option<FrameConfig>,
    /// Timing limits of a `generic` ADC, in ns.
    #[serde(default)]
    pub timing: Option<TimingConfig>,
}

/// `[adc.frame]` (preset `generic`): defaults describe two channels of W bits, MSB first,
/// one idle slot before each, shifted on rising SCK edges after a CONV pulse.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrameConfig {
    /// SCK cycles per frame (default 2W + 4).
    pub frame_sck: Option<u32>,
    /// Channels: 1 or 2 (default 2).
    pub channels: Option<u32>,
    /// Slot of each channel's MSB (default [1, W + 2]).
    pub offsets: Option<[u32; 2]>,
    /// "twos-complement" (default) or "offset-binary".
    pub sign: Option<String>,
    /// SCK idle level (default false).
    pub cpol: Option<bool>,
    /// The slave shifts on leading edges (default true).
    pub cpha: Option<bool>,
    /// CONV / chip select active high (default true).
    pub conv_active_high: Option<bool>,
    /// CONV active clocks (default 0 = the minimum pulse).
    pub conv_clocks: Option<u32>,
    /// Clocks from CONV to the first SCK cycle (default 0).
    pub lead_clocks: Option<u32>,
    /// Frames between a conversion and its data (default 0).
    pub pipeline: Option<u32>,
}

/// `[adc.timing]` (preset `generic`), all in ns.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TimingConfig {
    /// Minimum SCK period (default 20).
    pub sck_min_period_ns: Option<f64>,
    /// Minimum SCK high/low time (default 5).
    pub sck_min_pulse_ns: Option<f64>,
    /// SDO valid after the shifting edge (default 10).
    pub data_valid_ns: Option<f64>,
    /// Minimum CONV pulse (default 10).
    pub conv_min_pulse_ns: Option<f64>,
    /// Minimum CONV inactive time (default 10).
    pub conv_min_low_ns: Option<f64>,
    /// CONV to first SCK edge (default 5).
    pub conv_to_sck_ns: Option<f64>,
    /// Acquisition time before the next CONV (default 0).
    pub acquisition_ns: Option<f64>,
}

/// `[preamp]`: LTC6912-1 gains (preset `ltc1407a-1` only).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreampConfig {
    /// Gain of amplifier A (ADC channel 0, sin): -1, -2, -5, -10, -20, -50 or -100.
    pub gain_a: i32,
    /// Gain of amplifier B (ADC channel 1, cos).
    pub gain_b: i32,
}

impl Default for PreampConfig {
    fn default() -> Self {
        PreampConfig {
            gain_a: -1,
            gain_b: -1,
        }
    }
}

/// `[cordic]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CordicConfig {
    /// Number of vectoring iterations N (one pipeline stage each).
    #[serde(deserialize_with = "r_iter")]
    pub iterations: u32,
    /// Fine bits F: the interpolated angle is a fraction of a quadrant in units of 2^-F.
    #[serde(deserialize_with = "r_fine")]
    pub fine_bits: u32,
    /// Fractional guard bits of the x/y datapath; derived when omitted.
    #[serde(default, deserialize_with = "r_guard")]
    pub guard_bits: Option<u32>,
    /// CORDIC architecture: N unrolled stages (one sample per clock) or one digit-serial
    /// iterative stage (one sample per N·ceil(W/4) clocks, see
    /// `crate::blocks::cordic::iterative`).
    #[serde(default)]
    pub architecture: Architecture,
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

/// `[monitor]`
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MonitorConfig {
    /// Signal amplitude (fraction of ADC full scale) below which a sample is rejected
    /// and the error flag raised.
    #[serde(default = "default_min_amplitude", deserialize_with = "r_amp")]
    pub min_amplitude: f64,
    /// Loss of signal: amplitude below this fraction of full scale for `los_window`
    /// samples raises the error flag (board top).
    #[serde(default)]
    pub los_amplitude: Option<f64>,
    /// The loss of signal clears after `los_window` samples at or above this amplitude.
    #[serde(default)]
    pub los_release: Option<f64>,
    /// Samples in the loss-of-signal window.
    #[serde(default)]
    pub los_window: Option<u32>,
    /// Clipping: amplitude above this fraction of full scale raises the error flag.
    #[serde(default)]
    pub clip_amplitude: Option<f64>,
    /// Clean samples before clipping / full-scale errors clear.
    #[serde(default)]
    pub clip_hold: Option<u32>,
}

/// `[correction]`: offset and gain correction between the ADC and the core.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CorrectionConfig {
    /// "static" (the values below) or "auto" (peak tracking; the values below are the
    /// start values after reset).
    pub mode: String,
    /// Offset of the sin channel in LSB (b of x' = (x - b) / m).
    #[serde(default)]
    pub offset_sin: i32,
    /// Offset of the cos channel in LSB.
    #[serde(default)]
    pub offset_cos: i32,
    /// Gain correction 1/m of the sin channel.
    #[serde(default = "one")]
    pub gain_sin: f64,
    /// Gain correction 1/m of the cos channel.
    #[serde(default = "one")]
    pub gain_cos: f64,
    /// Fraction bits of the gain words (8..=15).
    #[serde(default = "fourteen", deserialize_with = "r_gain_frac")]
    pub gain_frac_bits: u32,
    /// Auto: amplitude both channels are scaled to, fraction of full scale.
    #[serde(default = "target")]
    pub target_amplitude: f64,
    /// Auto: signal periods per update (1..=256; checked in both modes).
    #[serde(default = "one_u32", deserialize_with = "r_periods")]
    pub periods: u32,
    /// Auto: no update below this amplitude, fraction of full scale.
    #[serde(default = "min_cal")]
    pub min_amplitude: f64,
}

fn one() -> f64 {
    1.0
}
fn one_u32() -> u32 {
    1
}
fn fourteen() -> u32 {
    14
}
fn target() -> f64 {
    0.75
}
fn min_cal() -> f64 {
    0.1
}

impl Default for CorrectionConfig {
    fn default() -> Self {
        CorrectionConfig {
            mode: "static".into(),
            offset_sin: 0,
            offset_cos: 0,
            gain_sin: 1.0,
            gain_cos: 1.0,
            gain_frac_bits: 14,
            target_amplitude: target(),
            periods: 1,
            min_amplitude: min_cal(),
        }
    }
}

fn default_min_amplitude() -> f64 {
    0.0625
}

impl Default for MonitorConfig {
    fn default() -> Self {
        MonitorConfig {
            min_amplitude: default_min_amplitude(),
            los_amplitude: None,
            los_release: None,
            los_window: None,
            clip_amplitude: None,
            clip_hold: None,
        }
    }
}

/// Parameters computed once from a validated [`Config`].
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

/// The board clock and the ADC's I/O timing budget, checked: the synthesizer must reach
/// `clock.frequency_hz` from `board.clock_hz`, and the SCK period must leave room for the
/// ADC round trip (see `crate::board`).
fn board_timing(
    c: &Config,
    adc: &AdcParams,
    err: &dyn Fn(&str, &str, String) -> Error,
) -> Result<(Option<crate::board::BoardClock>, crate::board::IoTiming)> {
    use crate::board::{IoTiming, STARTER_KIT_CLOCK_HZ};
    let mut io = IoTiming::DEFAULT;
    let mut board_clock = None;
    if let Some(b) = &c.board {
        for (key, v, slot) in [
            (
                "fpga_clock_to_out_ns",
                b.fpga_clock_to_out_ns,
                &mut io.clock_to_out_ns,
            ),
            (
                "fpga_input_setup_ns",
                b.fpga_input_setup_ns,
                &mut io.input_setup_ns,
            ),
            ("trace_delay_ns", b.trace_delay_ns, &mut io.trace_ns),
        ] {
            if let Some(v) = v {
                if !(0.0..=100.0).contains(&v) {
                    return Err(err(
                        "board",
                        key,
                        format!("`{key}` = {v} is out of range: allowed 0..=100 ns"),
                    ));
                }
                *slot = v;
            }
        }
        let kit = b.preset.as_deref() == Some("spartan3an-starter-kit");
        let osc = match (b.clock_hz, kit) {
            (Some(f), _) => {
                if !(1.0e6..=500.0e6).contains(&f) {
                    return Err(err(
                        "board",
                        "clock_hz",
                        format!("`clock_hz` = {f} is out of range: allowed 1e6..=500e6 Hz"),
                    ));
                }
                f
            }
            (None, true) => STARTER_KIT_CLOCK_HZ,
            (None, false) => c.clock.frequency_hz,
        };
        let key = if b.clock_hz.is_some() {
            "clock_hz"
        } else {
            "preset"
        };
        board_clock = Some(
            crate::board::board_clock(c.target, osc, c.clock.frequency_hz)
                .map_err(|m| err("board", key, m.to_string()))?,
        );
    }
    let d = adc.sck_period_clocks;
    let (available, needed) =
        crate::board::adc_round_trip(&io, adc.timing.data_valid_ns, d, adc.clock_hz);
    if available + 1e-9 < needed {
        let t = 1e9 / adc.clock_hz;
        let min_d = ((needed / t) - 1e-9).ceil() as u32;
        // Blame the SCK period when the config sets it, else the board budget it sets.
        let b = c.board.as_ref();
        let (table, key) = if c.adc.sck_period_clocks.is_some() {
            ("adc", "sck_period_clocks")
        } else if b.is_some_and(|b| b.trace_delay_ns.is_some()) {
            ("board", "trace_delay_ns")
        } else if b.is_some_and(|b| b.fpga_clock_to_out_ns.is_some()) {
            ("board", "fpga_clock_to_out_ns")
        } else if b.is_some_and(|b| b.fpga_input_setup_ns.is_some()) {
            ("board", "fpga_input_setup_ns")
        } else {
            ("adc", "sck_period_clocks")
        };
        return Err(err(
            table,
            key,
            format!(
                "an SCK period of {d} clocks ({available:.2} ns at {:.3} MHz) is shorter than the ADC round trip of {needed:.2} ns: FPGA clock-to-out {:.2} + 2 x board trace {:.2} + the ADC's SCK-to-data delay {:.2} + FPGA input set-up {:.2} ns (board.fpga_clock_to_out_ns, board.trace_delay_ns, board.fpga_input_setup_ns); use an SCK period of at least {min_d} clocks",
                adc.clock_hz / 1e6,
                io.clock_to_out_ns,
                io.trace_ns,
                adc.timing.data_valid_ns,
                io.input_setup_ns,
            ),
        ));
    }
    Ok((board_clock, io))
}

/// `s` cut to 40 characters for echoing in a message.
pub fn clip(s: &str) -> String {
    if s.chars().count() <= 40 {
        s.to_string()
    } else {
        format!("{}...", s.chars().take(40).collect::<String>())
    }
}

/// A `[board.pins]` value as TOML text: "Y6" or ["A1", "B1"].
fn pin_text(v: &PinValue) -> String {
    match v {
        PinValue::One(p) => format!("\"{}\"", clip(p)),
        PinValue::Bus(ps) => format!(
            "[{}]",
            ps.iter()
                .take(8)
                .map(|p| format!("\"{}\"", clip(p)))
                .collect::<Vec<_>>()
                .join(", ")
                + if ps.len() > 8 { ", ..." } else { "" }
        ),
    }
}

fn ceil_log2(v: u32) -> u32 {
    if v <= 1 {
        0
    } else {
        32 - (v - 1).leading_zeros()
    }
}

/// Checks that the CORDIC keeps up with the ADC: the iterative architecture accepts one
/// sample per `cycles` = N·D clocks (D digit clocks per iteration), so clock / cycles must
/// be at least the sample rate.
pub fn check_throughput(
    architecture: Architecture,
    n: u32,
    cycles: u32,
    clock_hz: f64,
    rate: f64,
) -> Result<()> {
    if architecture == Architecture::Unrolled {
        return Ok(());
    }
    if rate * cycles as f64 > clock_hz * (1.0 + 1e-9) {
        let per_iter = (cycles / n.max(1)).max(1);
        return Err(Error::block_params("cordic", format!(
            "the iterative CORDIC accepts one sample per {cycles} clocks (N = {n} iterations of {per_iter} digit clocks): {:.0} samples/s at {:.3} MHz, below the ADC sample rate of {rate:.0} samples/s; use at most {} iterations, a faster clock, a lower sample rate, or architecture = \"unrolled\"",
            clock_hz / cycles as f64,
            clock_hz / 1e6,
            ((clock_hz / rate + 1e-9).floor() as u64) / per_iter as u64
        )));
    }
    Ok(())
}

/// Finds `key` in `[table]` (`""`: top level; a dotted path such as `capacitive.coef` for a
/// nested or inline table) of the TOML text, in any layout (table headers, dotted keys,
/// inline tables, quoted names), and returns "line:column: " of the key or "".
pub fn locate(text: &str, table: &str, key: &str) -> String {
    let Ok(doc) = toml::de::DeTable::parse(text) else {
        return String::new();
    };
    let mut t = doc.get_ref();
    for part in table.split('.').filter(|p| !p.is_empty()) {
        match t.get(part).and_then(|v| v.get_ref().as_table()) {
            Some(inner) => t = inner,
            None => return String::new(),
        }
    }
    match t.get_key_value(key) {
        Some((k, _)) => {
            let (line, col) = line_col(text, k.span().start);
            format!("{line}:{col}: ")
        }
        None => String::new(),
    }
}

/// toml's message, plus the dotted key it concerns when the message does not name it.
fn syntax_message(e: &toml::de::Error, text: &str) -> String {
    let message = e.message().trim().to_string();
    let keys = e.span().and_then(|s| key_path_at(text, s.start));
    match keys {
        Some(k) if !message.contains(&format!("`{k}`")) => format!("{message} (in `{k}`)"),
        Some(_) => message,
        None if message == "duplicate key" => match e.span().and_then(|s| text.get(s)) {
            Some(k) if !k.is_empty() => format!("duplicate key `{k}`"),
            _ => message,
        },
        None => message,
    }
}

/// The dotted key path of the value at byte offset `pos`, from the spans of toml's document
/// tree: a position inside a value (or on a table's header) names its key; a position on a
/// key (an unknown field) names the table holding it. `None` when the text does not parse
/// as TOML or `pos` lies outside every key and value.
fn key_path_at(text: &str, pos: usize) -> Option<String> {
    fn find(table: &toml::de::DeTable<'_>, pos: usize, path: &mut Vec<String>) -> bool {
        for (k, v) in table.iter() {
            if k.span().contains(&pos) {
                return true;
            }
            path.push(k.get_ref().to_string());
            // A `[table]`'s span is its header; its keys lie outside it, so look inside too.
            let inside = v.span().contains(&pos)
                || v.get_ref().as_table().is_some_and(|t| find(t, pos, path));
            if inside {
                return true;
            }
            path.pop();
        }
        false
    }
    let doc = toml::de::DeTable::parse(text).ok()?;
    let mut path = Vec::new();
    (find(doc.get_ref(), pos, &mut path) && !path.is_empty()).then(|| path.join("."))
}

/// A parsed configuration together with the text it came from.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The validated config.
    pub config: Config,
    /// Derived parameters.
    pub derived: Derived,
    /// The exact TOML text (hashed into file headers).
    pub text: String,
    /// Name of the source for messages.
    pub source_name: String,
}

impl Loaded {
    /// Parses and validates `text`; `source_name` is used in error messages.
    pub fn parse(text: &str, source_name: &str) -> Result<Loaded> {
        let config: Config = toml::from_str(text).map_err(|e| {
            let (line, column) = e.span().map(|s| line_col(text, s.start)).unwrap_or((1, 1));
            Error::ConfigSyntax {
                source_name: source_name.to_string(),
                line,
                column,
                message: syntax_message(&e, text),
            }
        })?;
        let derived = Derived::compute(&config, text, source_name)?;
        Ok(Loaded {
            config,
            derived,
            text: text.to_string(),
            source_name: source_name.to_string(),
        })
    }

    /// The embedded default configuration.
    pub fn default_config() -> Result<Loaded> {
        Loaded::parse(DEFAULT_CONFIG, DEFAULT_NAME)
    }

    /// Reads and parses a file.
    pub fn from_file(path: &std::path::Path) -> Result<Loaded> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        Loaded::parse(&text, &path.display().to_string())
    }

    /// FNV-1a 64-bit hash of the config text, printed in every file header. Written out
    /// here (five lines) rather than taken from a hashing crate: the value is part of every
    /// emitted file, so it must never move with a dependency's version.
    pub fn hash(&self) -> String {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in self.text.bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        format!("{h:016x}")
    }
}

/// 1-based line and column of byte offset `pos` in `text`.
pub fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let before = &text[..pos.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.len() - before.rfind('\n').map(|i| i + 1).unwrap_or(0) + 1;
    (line, col)
}

impl Derived {
    /// Cross-field validation and derivation.
    pub fn compute(c: &Config, text: &str, source_name: &str) -> Result<Derived> {
        let err = |table: &str, key: &str, message: String| Error::ConfigValue {
            source_name: source_name.to_string(),
            location: locate(text, table, key),
            key: if table.is_empty() {
                key.to_string()
            } else {
                format!("{table}.{key}")
            },
            message,
        };
        check_target(c, &err)?;
        // The core's input width: the ADC's, or the filters' on the capacitive path.
        let a = match &c.capacitive {
            Some(k) => {
                // Checked here, before any width arithmetic uses it (the rest of the
                // capacitive checks run after the core's derivation).
                if !(12..=16).contains(&k.data_width) {
                    return Err(err(
                        "capacitive",
                        "data_width",
                        format!("{}: allowed 12..=16", k.data_width),
                    ));
                }
                k.data_width
            }
            None => c.adc.width,
        };
        let n = c.cordic.iterations;
        let f = c.cordic.fine_bits;
        // Guard bits so that truncation in the x/y shifts stays below 1/4 fine LSB for
        // inputs of at least 1/8 full scale: each stage truncates by < 1 unit of
        // 2^-G input LSB; the final angle error is about 2N * 2^-G / (K |v|) rad with
        // |v| >= 2^(A-4), which in fine LSB ((pi/2) 2^-F rad) is 0.78 N 2^(F+4-A-G).
        // At least enough that the last stage's shift stays inside the word.
        let auto_guard = (f as i64 + 4 - a as i64 + ceil_log2(n) as i64 + 2)
            .max(n as i64 - a as i64)
            .max(1) as u32;
        let xy_guard = c.cordic.guard_bits.unwrap_or(auto_guard);
        let xy_width = a + 2 + xy_guard;
        if xy_width > MAX_WORD_BITS {
            return Err(err(
                "cordic",
                "guard_bits",
                format!(
                    "x/y datapath would be {xy_width} bits (adc.width {a} + 2 + guard {xy_guard}); at most {MAX_WORD_BITS} are supported"
                ),
            ));
        }
        // Angle table rounding: N entries each within 1/2 unit of 2^-(F+Gz) -> N/2^(Gz+1)
        // fine LSB; ceil(log2 N) + 2 keeps it below 1/8 LSB.
        let z_guard = ceil_log2(n) + 2;
        let z_width = f + z_guard + 2;
        if n > a + xy_guard {
            return Err(err(
                "cordic",
                "iterations",
                format!(
                    "{n} iterations shift beyond the {} bits of the x/y datapath (adc.width {a} + guard {xy_guard}); use at most {}",
                    a + xy_guard,
                    a + xy_guard
                ),
            ));
        }
        let atan_table = exact::atan_table_quadrant(n, f + z_guard);
        let gain = exact::cordic_gain(n);
        let full_scale = 1u64 << (a - 1);
        let min_in = (c.monitor.min_amplitude * full_scale as f64).ceil() as u64;
        let min_magnitude = exact::gain_times_ceil(n, min_in << xy_guard);
        let quadrants_per_turn = 4 * c.encoder.ppr as u64;
        let quadrant_bits = 64 - (quadrants_per_turn - 1).leading_zeros();
        let position_width = quadrant_bits + f;
        let clock_hz = c.clock.frequency_hz;
        let (adc, preamp) = adc_params(c, &err)?;
        let rate = adc.sample_rate_hz();
        // Warn at 1.75 quadrants per sample: the fine-angle unwrap is exact below 2.
        let warn_step = 7u64 << (f - 2);
        let max_speed_rpm_full_res =
            (warn_step - 1) as f64 / (1u64 << f) as f64 * rate / quadrants_per_turn as f64 * 60.0;
        let architecture = c.cordic.architecture;
        let (cycles_per_sample, latency_cycles) = match architecture {
            Architecture::Unrolled => (1, n + 2),
            Architecture::Iterative => {
                let s = crate::blocks::cordic::iterative::steps(n, xy_width);
                (s, s + 2)
            }
        };
        check_throughput(architecture, n, cycles_per_sample, clock_hz, rate)
            .map_err(|m| err("cordic", "architecture", m.detail()))?;
        let biss = biss_params(c, position_width, &err)?;
        let capacitive = match &c.capacitive {
            Some(k) => Some(cap_params(c, k, rate, &err)?),
            None => None,
        };
        let correction = correction_params(c, &err)?;
        let ssi = if c.ssi.enabled {
            let mut p = SsiParams::new(biss.position_bits, biss.multiturn_bits, clock_hz)
                .map_err(|m| err("ssi", "enabled", m.to_string()))?;
            p.gray = c.ssi.gray;
            if let Some(t) = c.ssi.timeout_us {
                p.set_timeout_us(t)
                    .map_err(|m| err("ssi", "timeout_us", m.to_string()))?;
            }
            p.validate()
                .map_err(|m| err("ssi", "enabled", m.to_string()))?;
            Some(p)
        } else {
            None
        };
        let spi = if c.spi.enabled {
            let mut p = SpiSlaveParams::new(biss.position_bits, biss.multiturn_bits, clock_hz)
                .map_err(|m| err("spi", "enabled", m.to_string()))?;
            p.gray = c.spi.gray;
            p.validate()
                .map_err(|m| err("spi", "enabled", m.to_string()))?;
            Some(p)
        } else {
            None
        };
        let monitor = monitor_params(c, n, xy_guard, xy_width, &err)?;
        if let Some(b) = &c.board {
            if let Some(p) = &b.preset {
                if !BOARD_PRESETS.contains(&p.as_str()) {
                    return Err(err(
                        "board",
                        "preset",
                        format!(
                            "unknown board preset {}; allowed: {}",
                            Quoted(p),
                            BOARD_PRESETS.join(", ")
                        ),
                    ));
                }
            }
            let stds = crate::board::iostandards(c.target);
            match b.effective_iostandard() {
                Some(s) if stds.contains(&s.as_str()) => {}
                Some(s) => {
                    return Err(err(
                        "board",
                        "iostandard",
                        format!(
                            "`iostandard` = \"{}\" is not a single-ended I/O standard of {}; allowed: {}",
                            clip(&s),
                            crate::board::package(c.target).0,
                            stds.join(", ")
                        ),
                    ))
                }
                None => {
                    return Err(err(
                        "board",
                        "pins",
                        format!(
                            "`iostandard` is required without a `preset`; allowed: {}",
                            stds.join(", ")
                        ),
                    ))
                }
            }
            if b.preset.is_some() && (c.target != Target::Spartan3an || c.capacitive.is_some()) {
                return Err(err(
                    "board",
                    "preset",
                    "the spartan3an-starter-kit preset applies to the sinewave top with target = \"spartan3an\"".into(),
                ));
            }
            let pins = b.effective_pins();
            let (package_name, package_file, balls) = crate::board::package(c.target);
            let valid = |v: &str| balls.contains(&v);
            let ports = board_ports(c);
            let mut names: Vec<String> = ports
                .iter()
                .filter(|(p, _)| !DESELECT_PINS.contains(p))
                .map(|(p, w)| match w {
                    Some(w) => format!("{p} ({w} pins)"),
                    None => p.to_string(),
                })
                .collect();
            if c.capacitive.is_none() {
                names.extend(DESELECT_PINS.iter().map(|p| format!("{p} (optional)")));
            }
            for (k, v) in &b.pins {
                let ok = match (ports.iter().find(|p| p.0 == k.as_str()), v) {
                    (Some((_, None)), PinValue::One(p)) => valid(p),
                    (Some((_, Some(w))), PinValue::Bus(ps)) => {
                        ps.len() == *w as usize && ps.iter().all(|p| valid(p))
                    }
                    _ => false,
                };
                if !ok {
                    return Err(err(
                        "board.pins",
                        k,
                        format!(
                            "`{}` = {}: the key must be one of the top's ports ({}) and the value a ball of the {package_name} package like \"{}\" (listed in {package_file}; a list of that many balls, LSB first, for a bus)",
                            clip(k),
                            pin_text(v),
                            names.join(", "),
                            balls.get(balls.len() / 2).copied().unwrap_or("A1"),
                        ),
                    ));
                }
            }
            // One ball, one port: a pin given twice, or on a pin the preset already uses.
            let preset_pins = BoardConfig {
                pins: Default::default(),
                ..b.clone()
            }
            .effective_pins();
            let mut owner: std::collections::BTreeMap<&str, &str> = Default::default();
            let in_use: Vec<&str> = ports.iter().map(|p| p.0).collect();
            for (port, v) in pins.iter().filter(|(p, _)| in_use.contains(&p.as_str())) {
                let balls_of: Vec<&str> = match v {
                    PinValue::One(x) => vec![x.as_str()],
                    PinValue::Bus(xs) => xs.iter().map(String::as_str).collect(),
                };
                for ball in balls_of {
                    if let Some(first) = owner.insert(ball, port.as_str()) {
                        // Blame the key the user wrote (the later one when both are theirs).
                        let (blamed, other) = if b.pins.contains_key(port) {
                            (port.as_str(), first)
                        } else {
                            (first, port.as_str())
                        };
                        let whose = if preset_pins
                            .get(other)
                            .is_some_and(|p| p.one() == Some(ball))
                            && !b.pins.contains_key(other)
                        {
                            format!("the preset's pin for `{other}`")
                        } else {
                            format!("already given to `{other}`")
                        };
                        return Err(err(
                            "board.pins",
                            blamed,
                            format!(
                                "`{blamed}`: pin {ball} is {whose}; every port needs a ball of its own"
                            ),
                        ));
                    }
                }
            }
            let missing: Vec<&str> = ports
                .iter()
                .map(|p| p.0)
                .filter(|p| !pins.contains_key(*p))
                .collect();
            if !missing.is_empty() {
                let preset = if b.preset.is_some() {
                    "; the preset fills in the kit's fixed pins, these are wiring on the kit's headers: give them in [board.pins]"
                } else {
                    ""
                };
                return Err(err(
                    "board",
                    "pins",
                    format!("pins missing for the board: {} (every port of <name>_top but the parallel bus needs one{preset})", missing.join(", ")),
                ));
            }
        }
        let (board_clock, io_timing) = board_timing(c, &adc, &err)?;
        let qep = QepParams::new(c.qep.filter_clocks, 32)
            .map_err(|m| err("qep", "filter_clocks", m.detail()))?;
        let derived = Derived {
            board_clock,
            io_timing,
            adc,
            preamp,
            biss,
            ssi,
            spi,
            correction,
            monitor,
            qep,
            qep_enabled: c.qep.enabled,
            adc_width: a,
            capacitive,
            iterations: n,
            fine_bits: f,
            xy_guard,
            xy_width,
            z_guard,
            z_width,
            atan_table,
            gain,
            min_magnitude,
            quadrants_per_turn,
            quadrant_bits,
            position_width,
            turns_width: c.encoder.multiturn_bits.max(1),
            multiturn_bits: c.encoder.multiturn_bits,
            warn_step,
            latency_cycles,
            architecture,
            cycles_per_sample,
            clock_hz,
            sample_rate_hz: rate,
            max_speed_rpm_full_res,
            resolution_bits: (quadrants_per_turn as f64).log2() + f as f64,
        };
        // The capacitive front end's own checks (NCO, biquad engine widths and
        // coefficients, clocks per sample) run here too, so that `check` accepts exactly
        // what `generate` builds, and their errors point at the key.
        if derived.capacitive.is_some() {
            crate::blocks::capacitive::CapFrontParams::new(&derived).map_err(|e| match e {
                Error::ConfigValue { key, message, .. } => {
                    let (table, key) = key.rsplit_once('.').unwrap_or(("", key.as_str()));
                    err(table, key, message)
                }
                e => e,
            })?;
        }
        Ok(derived)
    }

    /// The board clock and the ADC round trip, for `describe`.
    fn describe_board(&self) -> String {
        let mut s = String::new();
        if let Some(b) = &self.board_clock {
            match b.synth {
                None => s.push_str(&format!(
                    "board clock                 {:.3} MHz oscillator = the system clock (no clock synthesizer)\n",
                    b.osc_hz / 1e6
                )),
                Some(x) => s.push_str(&format!(
                    "board clock                 {:.3} MHz oscillator -> {} x {} / {} = {:.3} MHz ({:+.0} ppm from clock.frequency_hz), reset held until locked\n",
                    b.osc_hz / 1e6,
                    x.kind.label(),
                    x.multiply,
                    x.divide,
                    x.out_hz / 1e6,
                    x.error_ppm
                )),
            }
        }
        let io = &self.io_timing;
        let (available, needed) = crate::board::adc_round_trip(
            io,
            self.adc.timing.data_valid_ns,
            self.adc.sck_period_clocks,
            self.adc.clock_hz,
        );
        s.push_str(&format!(
            "ADC round trip              {needed:.2} ns of {available:.2} ns (SCK period {} clocks): clock-to-out {:.2} + 2 x trace {:.2} + SCK-to-data {:.2} + input set-up {:.2}; slack {:.2} ns\n",
            self.adc.sck_period_clocks,
            io.clock_to_out_ns,
            io.trace_ns,
            self.adc.timing.data_valid_ns,
            io.input_setup_ns,
            available - needed
        ));
        s
    }

    /// Latency in nanoseconds at the configured clock.
    pub fn latency_ns(&self) -> f64 {
        self.latency_cycles as f64 * 1e9 / self.clock_hz
    }

    /// Human-readable listing printed by `sinedec check`.
    pub fn describe(&self) -> String {
        let core = self.describe_core();
        let Some(k) = &self.capacitive else {
            let mut s = core;
            if self.preamp.is_some() {
                // The same quantity, under the same name, as `simulate` prints.
                let c = crate::blocks::top::hdl::conv_to_position_cycles(self);
                s.push_str(&format!(
                    "latency CONV -> position    {c} cycles = {:.0} ns (ADC {} + correction {} + core {})\n",
                    c as f64 * 1e9 / self.clock_hz,
                    self.adc.conv_to_valid_clocks(),
                    crate::blocks::correction::LATENCY_CYCLES,
                    self.latency_cycles
                ));
            }
            s.push_str(&self.describe_board());
            return s;
        };
        // One speed limit: theta moves periods_per_turn x rpm / 60 Hz, and the low-pass
        // corner bounds it far below the CORDIC's unwrap limit.
        let mut s: String = core
            .lines()
            .filter(|l| !l.starts_with("max speed at full res."))
            .map(|l| format!("{l}\n"))
            .collect();
        let corner = k.config.lowpass.corner_hz.unwrap_or(0.0);
        let ppr = self.quadrants_per_turn as f64 / 4.0;
        let lp_rpm = corner / ppr * 60.0;
        let limit = lp_rpm.min(self.max_speed_rpm_full_res);
        s.push_str(&format!(
            "core input                  the filters' I/Q outputs ({} bits; ADC {} bits)\n\
             carrier                     {:.0} Hz, {:.1} samples per carrier period\n\
             max speed                   {:.0} rpm: the low-pass corner {:.0} Hz with {} periods per turn (the CORDIC's unwrap alone would allow {:.0} rpm)\n",
            self.adc_width,
            self.adc.frame.width,
            k.config.carrier_hz,
            k.sample_rate_hz / k.config.carrier_hz,
            limit,
            corner,
            ppr,
            self.max_speed_rpm_full_res
        ));
        s.push_str(&self.describe_board());
        s
    }

    fn describe_core(&self) -> String {
        format!(
            "core input width A          {} bits\n\
             cordic iterations N         {}\n\
             fine bits F                 {} (1 LSB = {:.4} arc-seconds of electrical angle)\n\
             x/y datapath                {} bits ({} guard bits)\n\
             angle accumulator           {} bits ({} guard bits)\n\
             cordic gain K_N             {:.12}\n\
             min magnitude (x units)     {}\n\
             quadrant count              {} bits (4 x PPR = {} quadrants per turn)\n\
             out_position width          {} bits ({:.2} bits per turn)\n\
             out_turns width             {} bits\n\
             core latency in -> out      {} cycles = {:.1} ns at {:.3} MHz\n\
             throughput                  1 sample per {} clock(s) ({} CORDIC)\n\
             sample rate                 {:.0} samples/s per channel\n\
             max speed at full res.      {:.0} rpm (steps below {:.2} quadrants per sample)\n",
            self.adc_width,
            self.iterations,
            self.fine_bits,
            90.0 * 3600.0 / (1u64 << self.fine_bits) as f64,
            self.xy_width,
            self.xy_guard,
            self.z_width,
            self.z_guard,
            self.gain,
            self.min_magnitude,
            self.quadrant_bits,
            self.quadrants_per_turn,
            self.position_width,
            self.resolution_bits,
            self.turns_width,
            self.latency_cycles,
            self.latency_ns(),
            self.clock_hz / 1e6,
            self.cycles_per_sample,
            self.architecture,
            self.sample_rate_hz,
            self.max_speed_rpm_full_res,
            self.warn_step as f64 / (1u64 << self.fine_bits) as f64,
        )
    }
}

type ErrFn<'a> = dyn Fn(&str, &str, String) -> Error + 'a;

/// The target must fit the design: the capacitive top is built for the Cyclone III (QSF and
/// SDC), the LTC1407A-1 / LTC6912-1 board top for the Spartan-3AN Starter Kit (UCF).
fn check_target(c: &Config, err: &ErrFn) -> Result<()> {
    match (c.target, c.capacitive.is_some(), c.adc.preset) {
        (Target::Spartan3an, true, _) => Err(err(
            "",
            "target",
            "\"spartan3an\" with [capacitive]: the capacitive path's board top is built for the Cyclone III EP3C40F324C8 (Quartus QSF and SDC); set target = \"cyclone3\"".into(),
        )),
        (Target::Cyclone3, false, AdcPreset::Ltc1407a1) => Err(err(
            "",
            "target",
            "\"cyclone3\" with adc.preset = \"ltc1407a-1\": the LTC1407A-1 / LTC6912-1 board top (<name>_top, UCF) is the Spartan-3AN Starter Kit's, so nothing but the core would be written; set target = \"spartan3an\" for the board top, or use adc.preset = \"generic\" for the core alone".into(),
        )),
        _ => Ok(()),
    }
}

/// ADC and preamp parameters from the config, validated against the chips' limits.
fn adc_params(c: &Config, err: &ErrFn) -> Result<(AdcParams, Option<PreampParams>)> {
    let a = c.adc.width;
    let clock_hz = c.clock.frequency_hz;
    let (frame, timing) = match c.adc.preset {
        AdcPreset::Ltc1407a1 => {
            if a != 14 {
                return Err(err(
                    "adc",
                    "width",
                    format!(
                        "the LTC1407A-1 delivers 14-bit samples; width {a} needs preset \"generic\""
                    ),
                ));
            }
            if c.adc.frame.is_some() || c.adc.timing.is_some() || c.adc.max_sample_rate_hz.is_some()
            {
                return Err(err(
                    "adc",
                    "preset",
                    "[adc.frame], [adc.timing] and max_sample_rate_hz apply to preset \"generic\" only".into(),
                ));
            }
            (AdcFrame::LTC1407A_1, AdcTiming::LTC1407A_1)
        }
        AdcPreset::Generic => {
            let max = c.adc.max_sample_rate_hz.ok_or_else(|| {
                err(
                    "adc",
                    "preset",
                    "preset \"generic\" needs `adc.max_sample_rate_hz` (the chip's per-channel limit)"
                        .into(),
                )
            })?;
            let f = c.adc.frame.clone().unwrap_or_default();
            let sign = match f.sign.as_deref() {
                None | Some("twos-complement") => SignFormat::TwosComplement,
                Some("offset-binary") => SignFormat::OffsetBinary,
                Some(other) => {
                    return Err(err(
                        "adc.frame",
                        "sign",
                        format!(
                            "{}: allowed \"twos-complement\" or \"offset-binary\"",
                            Quoted(other)
                        ),
                    ))
                }
            };
            let frame = AdcFrame {
                frame_sck: f.frame_sck.unwrap_or(2 * a + 4),
                channels: f.channels.unwrap_or(2),
                offsets: f.offsets.unwrap_or([1, a + 2]),
                width: a,
                sign,
                cpol: f.cpol.unwrap_or(false),
                cpha: f.cpha.unwrap_or(true),
                conv_active_high: f.conv_active_high.unwrap_or(true),
                conv_clocks: f.conv_clocks.unwrap_or(0),
                lead_clocks: f.lead_clocks.unwrap_or(0),
                pipeline: f.pipeline.unwrap_or(0),
            };
            let t = c.adc.timing.clone().unwrap_or_default();
            let timing = AdcTiming {
                sck_min_period_ns: t.sck_min_period_ns.unwrap_or(20.0),
                sck_max_period_ns: 0.0,
                sck_min_pulse_ns: t.sck_min_pulse_ns.unwrap_or(5.0),
                data_valid_ns: t.data_valid_ns.unwrap_or(10.0),
                conv_min_pulse_ns: t.conv_min_pulse_ns.unwrap_or(10.0),
                conv_min_low_ns: t.conv_min_low_ns.unwrap_or(10.0),
                conv_to_sck_ns: t.conv_to_sck_ns.unwrap_or(5.0),
                acquisition_ns: t.acquisition_ns.unwrap_or(0.0),
                conversion_edges: 0,
                max_sample_rate_hz: max,
            };
            (frame, timing)
        }
    };
    // SCK divider: as configured, or the smallest the chip's SCK limit allows.
    let d = match c.adc.sck_period_clocks {
        Some(d) => d,
        None => ((timing.sck_min_period_ns * clock_hz / 1e9) - 1e-9)
            .ceil()
            .max(2.0) as u32,
    };
    let build = |period: Option<u32>| match c.adc.preset {
        AdcPreset::Ltc1407a1 => AdcParams::ltc1407a(clock_hz, d, period),
        AdcPreset::Generic => AdcParams::generic(clock_hz, frame, timing, d, period),
    };
    let fastest = build(None);
    // The shortest period that respects the chip's rate limit too.
    let limit_period = AdcParams::period_for_rate(clock_hz, timing.max_sample_rate_hz);
    let mut params = if fastest.period_clocks < limit_period {
        build(Some(limit_period))
    } else {
        fastest
    };
    let key = if c.adc.sck_period_clocks.is_some() {
        "sck_period_clocks"
    } else {
        "preset"
    };
    params.validate().map_err(|m| err("adc", key, m.detail()))?;
    if let Some(rate) = c.adc.sample_rate_hz {
        let p = AdcParams::period_for_rate(clock_hz, rate);
        if rate.is_nan() || rate <= 0.0 || p < params.period_clocks {
            return Err(err(
                "adc",
                "sample_rate_hz",
                format!(
                    "{rate} Hz is not reachable: at most {:.0} samples/s per channel at the clock of {} MHz with an SCK period of {d} clocks (the ADC's per-channel limit is {} samples/s); omit the key for the fastest",
                    params.sample_rate_hz(),
                    clock_hz / 1e6,
                    timing.max_sample_rate_hz
                ),
            ));
        }
        params = build(Some(p));
        params
            .validate()
            .map_err(|m| err("adc", "sample_rate_hz", m.detail()))?;
    }
    let preamp = match c.adc.preset {
        AdcPreset::Ltc1407a1 => {
            let pc = c.preamp.clone().unwrap_or_default();
            Some(
                PreampParams::new(clock_hz, pc.gain_a, pc.gain_b).map_err(|m| {
                    let m = m.detail();
                    err(
                        "preamp",
                        if m.contains("gain B") {
                            "gain_b"
                        } else {
                            "gain_a"
                        },
                        m,
                    )
                })?,
            )
        }
        AdcPreset::Generic => {
            if c.preamp.is_some() {
                return Err(err(
                    "preamp",
                    "gain_a",
                    "the LTC6912-1 pre-amplifier belongs to preset \"ltc1407a-1\"".into(),
                ));
            }
            None
        }
    };
    Ok((params, preamp))
}

/// BiSS-C parameters: data bits default to the whole single-turn position (at most 32).
fn biss_params(c: &Config, position_width: u32, err: &ErrFn) -> Result<BissParams> {
    let b = &c.biss;
    let pb = b.position_bits.unwrap_or(position_width.min(32));
    if pb == 0 || pb > position_width.min(32) {
        return Err(err(
            "biss",
            "position_bits",
            format!(
                "{pb} bits: allowed 1..={} (out_position has {position_width} bits; BiSS words hold 32)",
                position_width.min(32)
            ),
        ));
    }
    let mb = b.multiturn_bits.unwrap_or(0);
    if mb > c.encoder.multiturn_bits || pb + mb > 32 {
        return Err(err(
            "biss",
            "multiturn_bits",
            format!(
                "{mb} bits: at most encoder.multiturn_bits ({}) and position_bits + multiturn_bits <= 32 (position_bits = {pb})",
                c.encoder.multiturn_bits
            ),
        ));
    }
    let mut p = BissParams::new(pb, mb, c.clock.frequency_hz)
        .map_err(|m| err("biss", "position_bits", m.to_string()))?;
    p.gray = b.gray.unwrap_or(false);
    p.ack_periods = b.ack_periods.unwrap_or(1);
    if let Some(t) = b.timeout_us {
        p.set_timeout_us(t)
            .map_err(|m| err("biss", "timeout_us", m.to_string()))?;
    }
    p.validate()
        .map_err(|m| err("biss", "ack_periods", m.to_string()))?;
    Ok(p)
}

fn frac_of_fs(c: &Config, table: &str, key: &str, v: f64, err: &ErrFn) -> Result<u32> {
    let fs = (1u32 << (c.adc.width - 1)) - 1;
    if !(v > 0.0 && v <= 1.0) {
        return Err(err(
            table,
            key,
            format!("{v}: allowed 0 < value <= 1 (fraction of full scale)"),
        ));
    }
    Ok(((v * fs as f64).round() as u32).max(1))
}

/// Correction parameters from `[correction]`.
fn correction_params(c: &Config, err: &ErrFn) -> Result<CorrectionParams> {
    let k = &c.correction;
    let a = c.adc.width;
    let gf = k.gain_frac_bits;
    let gs = gain_code(gf, k.gain_sin).map_err(|m| err("correction", "gain_sin", m.detail()))?;
    let gc = gain_code(gf, k.gain_cos).map_err(|m| err("correction", "gain_cos", m.detail()))?;
    let p = CorrectionParams::new(a, gf, [k.offset_sin, k.offset_cos], [gs, gc]).map_err(|m| {
        let m = m.detail();
        err(
            "correction",
            if m.contains("offset") {
                "offset_sin"
            } else {
                "gain_frac_bits"
            },
            m,
        )
    })?;
    match k.mode.as_str() {
        "static" => Ok(p),
        "auto" => {
            let t = frac_of_fs(c, "correction", "target_amplitude", k.target_amplitude, err)?;
            let m = frac_of_fs(c, "correction", "min_amplitude", k.min_amplitude, err)?;
            p.with_auto(t, k.periods, m)
                .map_err(|e| err("correction", "periods", e.detail()))
        }
        other => Err(err(
            "correction",
            "mode",
            format!("{}: allowed \"static\" or \"auto\"", Quoted(other)),
        )),
    }
}

/// Monitor parameters: thresholds in CORDIC magnitude units (K_N * amplitude * 2^G).
fn monitor_params(
    c: &Config,
    n: u32,
    xy_guard: u32,
    xy_width: u32,
    err: &ErrFn,
) -> Result<MonitorParams> {
    let m = &c.monitor;
    let fs = ((1u64 << (c.adc.width - 1)) - 1) as f64;
    let units = |v: f64| exact::gain_times_ceil(n, ((v * fs).round() as u64) << xy_guard);
    let los = m.los_amplitude.unwrap_or(0.25);
    let rel = m.los_release.unwrap_or(0.3);
    let clip = m.clip_amplitude.unwrap_or(1.0);
    for (key, v) in [
        ("los_amplitude", los),
        ("los_release", rel),
        ("clip_amplitude", clip),
    ] {
        if !(v > 0.0 && v <= 1.3) {
            return Err(err(
                "monitor",
                key,
                format!("{v}: allowed 0 < value <= 1.3 (fraction of full scale)"),
            ));
        }
    }
    // The levels must rise: loss threshold <= release level <= clipping level. The key in
    // the file is blamed (the later one when both are given); a default is named as such.
    let shown = |key: &str, v: f64, given: bool| {
        if given {
            format!("`monitor.{key}` = {v}")
        } else {
            format!("`monitor.{key}` (default {v})")
        }
    };
    for ((lo_key, lo, lo_given), (hi_key, hi, hi_given), what) in [
        (
            ("los_amplitude", los, m.los_amplitude.is_some()),
            ("los_release", rel, m.los_release.is_some()),
            "the loss-of-signal release level must be at least the loss threshold",
        ),
        (
            ("los_release", rel, m.los_release.is_some()),
            ("clip_amplitude", clip, m.clip_amplitude.is_some()),
            "the clipping level must be at least the loss-of-signal release level",
        ),
    ] {
        if hi < lo {
            let key = if hi_given || !lo_given {
                hi_key
            } else {
                lo_key
            };
            return Err(err(
                "monitor",
                key,
                format!(
                    "{} is below {}: {what} (fractions of full scale)",
                    shown(hi_key, hi, hi_given),
                    shown(lo_key, lo, lo_given)
                ),
            ));
        }
    }
    for (key, v) in [("los_window", m.los_window), ("clip_hold", m.clip_hold)] {
        if let Some(v) = v {
            if !(1..=65535).contains(&v) {
                return Err(err(
                    "monitor",
                    key,
                    format!("{v} samples: allowed 1..=65535"),
                ));
            }
        }
    }
    MonitorParams::new(
        c.adc.width,
        xy_width,
        units(los),
        units(rel),
        m.los_window.unwrap_or(8),
        units(clip),
        m.clip_hold.unwrap_or(16),
    )
    .map_err(|e| err("monitor", "los_amplitude", e.detail()))
}

/// Validates `[capacitive]` and designs its filters at the ADC's sample rate.
fn cap_params(c: &Config, k: &CapacitiveConfig, rate: f64, err: &ErrFn) -> Result<CapDerived> {
    let t = "capacitive";
    if c.adc.preset != AdcPreset::Generic {
        return Err(err(
            "adc",
            "preset",
            "the capacitive path reads one receiver channel: use preset = \"generic\" with [adc.frame] channels = 1".into(),
        ));
    }
    if c.adc.frame.as_ref().and_then(|f| f.channels) != Some(1) {
        return Err(err(
            "adc",
            "frame",
            "the capacitive path reads one receiver channel: set [adc.frame] channels = 1".into(),
        ));
    }
    if c.ssi.enabled || c.spi.enabled {
        return Err(err(
            if c.ssi.enabled { "ssi" } else { "spi" },
            "enabled",
            "the capacitive top serves BiSS-C and the parallel bus; SSI and SPI are not in it"
                .into(),
        ));
    }
    if !(10e3..=1e6).contains(&k.carrier_hz) || k.carrier_hz >= rate / 2.0 {
        return Err(err(
            t,
            "carrier_hz",
            format!(
                "{} Hz: allowed 10 kHz..1 MHz and below half the ADC's sample rate ({:.0} Hz)",
                k.carrier_hz,
                rate / 2.0
            ),
        ));
    }
    if k.amplitude.is_nan() || k.amplitude <= 0.0 || k.amplitude > 1.0 {
        return Err(err(
            t,
            "amplitude",
            format!("{}: allowed (0, 1]", k.amplitude),
        ));
    }
    let ranged = |key: &str, v: u32, lo: u32, hi: u32| -> Result<()> {
        if (lo..=hi).contains(&v) {
            Ok(())
        } else {
            Err(err(t, key, format!("{v}: allowed {lo}..={hi}")))
        }
    };
    ranged("dac_width", k.dac_width, 8, 16)?;
    ranged("phase_bits", k.phase_bits, 8, 32)?;
    ranged("table_bits", k.table_bits, 4, 12.min(k.phase_bits - 2))?;
    ranged("data_width", k.data_width, 12, 16)?;
    ranged("guard_frac", k.guard_frac, 0, 12)?;
    if k.data_width < c.adc.width {
        return Err(err(
            t,
            "data_width",
            format!(
                "{} bits is narrower than the ADC's {} bits",
                k.data_width, c.adc.width
            ),
        ));
    }
    // Each filter's kind must fit its role: the band-pass isolates the carrier in front of
    // the demodulator, the low-pass removes 2w after it.
    for (key, spec, want) in [
        ("bandpass", &k.bandpass, crate::filter::FilterKind::Bandpass),
        ("lowpass", &k.lowpass, crate::filter::FilterKind::Lowpass),
    ] {
        if spec.kind != want {
            let name = |f: crate::filter::FilterKind| match f {
                crate::filter::FilterKind::Lowpass => "\"lowpass\"",
                crate::filter::FilterKind::Highpass => "\"highpass\"",
                crate::filter::FilterKind::Bandpass => "\"bandpass\"",
            };
            let role = if key == "bandpass" {
                "the band-pass in front of the demodulator isolates the carrier"
            } else {
                "the low-pass after the demodulator removes twice the carrier"
            };
            return Err(err(
                &format!("{t}.{key}"),
                "kind",
                format!("{}: {role}; allowed {}", name(spec.kind), name(want)),
            ));
        }
    }
    let design = |key: &str, spec: &crate::filter::FilterSpec| -> Result<crate::filter::Designed> {
        if (spec.sample_rate_hz - rate).abs() > rate * 1e-3 {
            return Err(err(
                t,
                key,
                format!(
                    "sample_rate_hz = {} but the ADC samples at {:.3} Hz (clock / adc period): make them equal",
                    spec.sample_rate_hz, rate
                ),
            ));
        }
        let mut s = spec.clone();
        s.sample_rate_hz = rate;
        crate::filter::design_with_probes(&s, k.coef, &[2.0 * k.carrier_hz])
            .map_err(|e| err(t, key, e.to_string()))
    };
    let bandpass = design("bandpass", &k.bandpass)?;
    let lowpass = design("lowpass", &k.lowpass)?;
    Ok(CapDerived {
        config: k.clone(),
        sample_rate_hz: rate,
        bandpass,
        lowpass,
    })
}
