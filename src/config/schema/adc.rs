//! The ADC's tables: the chip preset, `[adc]`, `[adc.frame]` and `[adc.timing]` (preset
//! `generic`), and `[preamp]` (preset `ltc1407a-1`). `ads8354` and `ad7380` have fixed
//! frames and timing (`crate::blocks::adc::AdcFrame`, `AdcTiming`) and no pre-amplifier.

use super::*;

/// ADC chip presets.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
pub enum AdcPreset {
    /// LTC1407A-1: dual 14-bit, 3 Msps total (1.5 Msps per channel).
    #[serde(rename = "ltc1407a-1")]
    Ltc1407a1,
    /// TI ADS8354: dual 16-bit, 700 ksps per channel, CS framing, SDO-A / SDO-B.
    #[serde(rename = "ads8354")]
    Ads8354,
    /// ADI AD7380: dual 16-bit, 4 Msps per channel, CS framing, SDOA / SDOB.
    #[serde(rename = "ad7380")]
    Ad7380,
    /// Any other SPI ADC (limits come from `adc.max_sample_rate_hz`).
    #[serde(rename = "generic")]
    Generic,
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
    /// Data lines: 1 (default: every channel on `adc_miso`) or 2 (channel 0 on
    /// `adc_miso`, channel 1 on `adc_miso_b`, at the same SCK edges).
    pub lines: Option<u32>,
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
