//! The TOML schema: every `[table]` of a configuration file as a serde struct, with the
//! ranges checked while deserializing (so errors carry line and column) and the defaults.

use super::*;

mod adc;
mod board;

pub use adc::*;
pub use board::*;

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
    pub abz: crate::blocks::abz::AbzConfig,
    /// Velocity estimation (`crate::blocks::velocity`, docs/velocity.md).
    #[serde(default)]
    pub velocity: VelocityConfig,
    /// Position reference: homing on Z, the index latch and the preset
    /// (`crate::blocks::reference`).
    #[serde(default)]
    pub reference: crate::blocks::reference::ReferenceConfig,
    /// Synchronous capture of the position, the velocity and their age
    /// (`crate::blocks::capture`).
    #[serde(default)]
    pub capture: crate::blocks::capture::CaptureConfig,
    /// AXI4-Lite register map (`crate::blocks::regmap`).
    #[serde(default)]
    pub registers: crate::blocks::regmap::RegistersConfig,
    /// Harmonic-correction table between the CORDIC and the combiner
    /// (`crate::blocks::harmonics`).
    #[serde(default)]
    pub harmonics: crate::blocks::harmonics::block::HarmonicsConfig,
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
