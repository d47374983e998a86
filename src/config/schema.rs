//! The TOML schema: every `[table]` of a configuration file as a serde struct, with the
//! ranges checked while deserializing (so errors carry line and column) and the defaults.

use super::*;

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
    r_min_samples,
    u32,
    "correction.min_samples",
    1,
    crate::blocks::correction::fit::N_MAX,
    " samples"
);
ranged!(
    r_gain_frac,
    u32,
    "correction.gain_frac_bits",
    8,
    15,
    " bits"
);
ranged!(
    r_phase,
    f64,
    "correction.phase_deg",
    -crate::blocks::correction::MAX_PHASE_DEG,
    crate::blocks::correction::MAX_PHASE_DEG,
    " degrees"
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
    /// ABZ incremental encoder emulation (`crate::blocks::abz`).
    #[serde(default)]
    pub abz: AbzConfig,
    /// Velocity estimation (`crate::blocks::velocity`, docs/velocity.md).
    #[serde(default)]
    pub velocity: VelocityConfig,
}

/// `[velocity]`: velocity estimation from the decoded position (docs/velocity.md). Every key
/// has the documented default; the keys are checked even when the block is disabled.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VelocityConfig {
    /// Include the estimator (default false: no velocity logic at all).
    pub enabled: bool,
    /// "tracking" (default) | "kalman" | "lsq" | "diff_lpf".
    pub method: crate::blocks::velocity::Method,
    /// Update rate in Hz (default 7500).
    pub rate_hz: f64,
    /// Fractional bits of out_velocity (default 8).
    pub frac_bits: u32,
    /// Bits of out_velocity (default 32; checked against the maximum speed).
    pub width: u32,
    /// diff_lpf: low-pass cut-off in Hz (default 900).
    pub cutoff_hz: f64,
    /// lsq: points M (default 4).
    pub lsq_points: u32,
    /// lsq: polynomial order N (default 1).
    pub lsq_order: u32,
    /// kalman: process-noise variance (default 0.01).
    pub kalman_q: f64,
    /// kalman: measurement-noise variance (default 0.03).
    pub kalman_r: f64,
    /// tracking: loop bandwidth (natural frequency) in Hz (default 200).
    pub bandwidth_hz: f64,
    /// Append the velocity word (`width` bits, two's complement, MSB first) to the data of
    /// every serial frame: BiSS (before nE, nW and the CRC, which covers it), SSI (before
    /// the error bit) and SPI (before E and W). Default false; needs `enabled = true`.
    pub in_frames: bool,
}

impl Default for VelocityConfig {
    fn default() -> Self {
        let d = crate::blocks::velocity::VelocitySpec::defaults(1.0, 14, 1);
        VelocityConfig {
            enabled: false,
            method: d.method,
            rate_hz: d.rate_hz,
            frac_bits: d.frac_bits,
            width: d.width,
            cutoff_hz: d.cutoff_hz,
            lsq_points: d.lsq_points,
            lsq_order: d.lsq_order,
            kalman_q: d.kalman_q,
            kalman_r: d.kalman_r,
            bandwidth_hz: d.bandwidth_hz,
            in_frames: false,
        }
    }
}

/// `[abz]`: A/B/Z incremental encoder emulation of the decoded position.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AbzConfig {
    /// Include the emulator (default false: no logic).
    #[serde(default)]
    pub enabled: bool,
    /// A/B periods per turn (default 16 x PPR, at most a quarter of the positions per turn).
    pub lines: Option<u64>,
    /// Highest edge rate on A and B together, edges per second (the minimum edge spacing;
    /// default 12.5 MHz, at most clock / 2).
    pub max_edge_hz: Option<f64>,
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
    /// Slot of each channel's MSB (default [1, W + 2]); one entry per channel (a
    /// one-channel frame may keep an unused second one).
    pub offsets: Option<Vec<u32>>,
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
    /// "static" (the values below), "auto" (least-squares ellipse fit of offset, gain and
    /// phase over whole periods) or "peak" (the older per-track peak tracker, offset and
    /// gain only); in "auto" and "peak" the values below are the start values after reset.
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
    /// Static mode: phase error phi of the cos track in degrees (cos = A cos(t + phi)),
    /// -15..=15; 0 builds no phase hardware.
    #[serde(default, deserialize_with = "r_phase")]
    pub phase_deg: f64,
    /// Auto: amplitude both channels are scaled to, fraction of full scale.
    #[serde(default = "target")]
    pub target_amplitude: f64,
    /// Auto: signal periods per update (1..=256; checked in both modes).
    #[serde(default = "one_u32", deserialize_with = "r_periods")]
    pub periods: u32,
    /// Auto: no update below this amplitude, fraction of full scale.
    #[serde(default = "min_cal")]
    pub min_amplitude: f64,
    /// Auto: least samples per fit window (1..=2^24; with the periods, the window length).
    #[serde(default = "min_samples", deserialize_with = "r_min_samples")]
    pub min_samples: u32,
}

fn min_samples() -> u32 {
    4096
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
            phase_deg: 0.0,
            target_amplitude: target(),
            periods: 1,
            min_amplitude: min_cal(),
            min_samples: min_samples(),
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
