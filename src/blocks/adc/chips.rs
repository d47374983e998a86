//! The ADC chips sinedec knows: their timing limits from the data sheets ([`AdcTiming`]) and
//! their frames ([`AdcFrame`]); the controller's parameters are derived from them in
//! `params.rs`.

/// The chip the parameters were made for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum AdcChip {
    /// Linear Technology LTC1407A-1 (Spartan-3A/3AN Starter Kit).
    Ltc1407a1,
    /// Texas Instruments ADS8354 (dual 16-bit, 700 ksps, SDO-A / SDO-B).
    Ads8354,
    /// Analog Devices AD7380 (dual 16-bit, 4 Msps, SDOA / SDOB).
    Ad7380,
    /// Any other SPI ADC.
    Generic,
}

impl std::fmt::Display for AdcChip {
    /// The chip's name as a datasheet spells it.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            AdcChip::Ltc1407a1 => "LTC1407A-1",
            AdcChip::Ads8354 => "ADS8354",
            AdcChip::Ad7380 => "AD7380",
            AdcChip::Generic => "generic SPI ADC",
        })
    }
}

/// Coding of the samples in the frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum SignFormat {
    /// Two's complement (delivered as is).
    TwosComplement,
    /// Offset binary (the MSB is inverted to give two's complement).
    OffsetBinary,
}

/// Timing limits of the ADC chip, in nanoseconds (0 = no limit).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AdcTiming {
    /// Minimum SCK period.
    pub sck_min_period_ns: f64,
    /// Maximum SCK period while a conversion runs (0 = none).
    pub sck_max_period_ns: f64,
    /// Minimum SCK high and low time.
    pub sck_min_pulse_ns: f64,
    /// Delay from the shifting SCK edge to valid data on SDO (maximum).
    pub data_valid_ns: f64,
    /// Minimum CONV active pulse width.
    pub conv_min_pulse_ns: f64,
    /// Minimum CONV inactive time.
    pub conv_min_low_ns: f64,
    /// Minimum set-up from the CONV edge to the first SCK edge.
    pub conv_to_sck_ns: f64,
    /// Minimum time from the SCK edge that ends a conversion to the next CONV edge.
    pub acquisition_ns: f64,
    /// Conversion time from the sampling CONV / CS edge (0 = none, or counted in SCK edges):
    /// with `pipeline` = 0 no bit of the conversion leaves before it; with `pipeline` >= 1
    /// the next conversion starts no earlier.
    pub conversion_ns: f64,
    /// SCK rising edges a conversion needs (the acquisition is counted from the last one;
    /// 0 = no such constraint).
    pub conversion_edges: u32,
    /// Maximum sample rate per channel.
    pub max_sample_rate_hz: f64,
}

impl AdcTiming {
    /// LTC1407A-1 at VDD = 3 V (datasheet 14071fb, Timing Characteristics and
    /// Applications Information): tSCK >= 19.6 ns (<= 10 us), t1 >= 2 ns, t8 = 8 ns,
    /// t4 >= 4 ns (CONV low kept >= 15 ns), t2 >= 3 ns, t7 (32nd SCK rise to CONV rise)
    /// >= 45 ns, conversion over 32 SCK rising edges, 1.5 Msps per channel.
    pub const LTC1407A_1: AdcTiming = AdcTiming {
        sck_min_period_ns: 19.6,
        sck_max_period_ns: 10_000.0,
        sck_min_pulse_ns: 2.0,
        data_valid_ns: 8.0,
        conv_min_pulse_ns: 4.0,
        conv_min_low_ns: 15.0,
        conv_to_sck_ns: 3.0,
        acquisition_ns: 45.0,
        conversion_ns: 0.0,
        conversion_edges: 32,
        max_sample_rate_hz: 1.5e6,
    };

    /// TI ADS8354 in its 32-CLK, dual-SDO mode. The ADS8354 data sheet's own tables could
    /// not be consulted; the interface figures are those of its pin- and
    /// interface-compatible sibling ADS8353-Q1 (TI SBAS931B, 6.6 Timing Requirements,
    /// 32-CLK dual-SDO mode), each the conservative side for the ADS8354:
    /// * SCK period >= 50 ns: fCLK <= 20 MHz (SBAS931B 6.6; a slower SCLK is always
    ///   allowed, so the ADS8354's own, possibly higher, limit is not exceeded).
    /// * SCK high and low >= 20 ns: tPH_CK, tPL_CK >= 0.4 tCLK at 50 ns (SBAS931B 6.6).
    /// * Data valid 25 ns after the launching SCLK rising edge: tD_CKDO not found; the
    ///   figure is half the 50 ns minimum SCLK period, the longest delay with which the
    ///   part's own read at the next falling edge works (conservative); hold: none assumed.
    /// * CS high >= 40 ns (tPH_CS, SBAS931B 6.6); CS falling to the first SCLK falling
    ///   edge >= 15 ns (tSU_CSCK, SBAS931B 6.6). The last SCLK falling edge to CS rising
    ///   (tD_CKCS >= 15 ns) is met by the CS framing of [`AdcParams::ads8354`].
    /// * Conversion 730 ns from the CS falling edge (tCONV, SBAS931B 6.6; "the conversion
    ///   is completed during the first 16 periods of SCLK", SBAS931B 7.5.3.2): the MSB,
    ///   shifted out on the 16th SCLK rising edge, leaves no earlier.
    /// * 700 ksps per channel (ADS8354 product description).
    pub const ADS8354: AdcTiming = AdcTiming {
        sck_min_period_ns: 50.0,
        sck_max_period_ns: 0.0,
        sck_min_pulse_ns: 20.0,
        data_valid_ns: 25.0,
        conv_min_pulse_ns: 0.0,
        conv_min_low_ns: 40.0,
        conv_to_sck_ns: 15.0,
        acquisition_ns: 0.0,
        conversion_ns: 730.0,
        conversion_edges: 0,
        max_sample_rate_hz: 700e3,
    };

    /// ADI AD7380 (data sheet AD7380-7381, as cited by the Linux IIO driver
    /// `drivers/iio/adc/ad7380.c`, whose figures are used where the data sheet's tables
    /// could not be consulted):
    /// * SCK period >= 12.5 ns: 80 MHz SCLK (the driver's binding example,
    ///   `spi-max-frequency = <80000000>`, SPI mode 3: `spi-cpol`, `spi-cpha`).
    /// * SCK high and low >= 5.625 ns: not found; 0.45 x 12.5 ns assumed (the usual
    ///   45 % duty limit of ADI SAR interfaces).
    /// * Data valid 6.25 ns after the launching SCLK falling edge: not found; half the
    ///   12.5 ns minimum period, the longest delay with which the part's own mode-3 read at
    ///   the next rising edge works (conservative); hold: none assumed.
    /// * CS high >= 10 ns (tCSH: the driver's `t_csh_ns = 10` for the 2-channel parts).
    /// * CS falling to the first SCLK edge >= 10 ns: not found; 10 ns assumed.
    /// * Conversion 190 ns from the CS falling edge (tCONVERT: the driver's
    ///   `T_CONVERT_NS = 190`); the frame of a CS low carries the previous conversion.
    /// * 4 Msps per channel (AD7380 product description: tCYC = 250 ns).
    pub const AD7380: AdcTiming = AdcTiming {
        sck_min_period_ns: 12.5,
        sck_max_period_ns: 0.0,
        sck_min_pulse_ns: 5.625,
        data_valid_ns: 6.25,
        conv_min_pulse_ns: 0.0,
        conv_min_low_ns: 10.0,
        conv_to_sck_ns: 10.0,
        acquisition_ns: 0.0,
        conversion_ns: 190.0,
        conversion_edges: 0,
        max_sample_rate_hz: 4e6,
    };
}

/// Frame format of a generic SPI ADC.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct AdcFrame {
    /// SCK cycles per frame (1..=250).
    pub frame_sck: u32,
    /// Channels in the frame: 1 or 2.
    pub channels: u32,
    /// Data lines: 1 (every channel on `adc_miso`) or 2 (two channels, channel 0 on
    /// `adc_miso` = SDO-A, channel 1 on `adc_miso_b` = SDO-B, read at the same SCK edges).
    pub lines: u32,
    /// Slot index (0-based SCK cycle) of each channel's MSB on its line; MSB first.
    pub offsets: [u32; 2],
    /// Sample width W (10..=16).
    pub width: u32,
    /// Coding of the samples.
    pub sign: SignFormat,
    /// SCK idle level.
    pub cpol: bool,
    /// false: the slave shifts on trailing edges (first bit valid at CONV/CS);
    /// true: the slave shifts on leading edges.
    pub cpha: bool,
    /// CONV / chip-select active level.
    pub conv_active_high: bool,
    /// CONV active clocks from the period start (0 = the minimum pulse from the timing;
    /// a chip select that frames the whole transfer needs >= lead + frame*D).
    pub conv_clocks: u32,
    /// Clocks from the CONV assertion to the first SCK cycle.
    pub lead_clocks: u32,
    /// Frames between a conversion and its data on SDO (0, 1 or 2).
    pub pipeline: u32,
}

impl AdcFrame {
    /// The edge of `adc_conv` that starts a conversion, as reports name it: "CONV rise" for
    /// an active-high CONV pulse, "CS fall" for an active-low chip select.
    pub fn start_edge(&self) -> &'static str {
        if self.conv_active_high {
            "CONV rise"
        } else {
            "CS fall"
        }
    }

    /// The LTC1407A-1 frame: 34 SCK, 2 idle, 14 bits channel 0, 2 idle, 14 bits channel 1,
    /// 2 idle; two's complement; SCK idle low, data shifted on rising edges; CONV pulse
    /// active high; data one conversion late.
    pub const LTC1407A_1: AdcFrame = AdcFrame {
        frame_sck: 34,
        channels: 2,
        lines: 1,
        offsets: [2, 18],
        width: 14,
        sign: SignFormat::TwosComplement,
        cpol: false,
        cpha: true,
        conv_active_high: true,
        conv_clocks: 0,
        lead_clocks: 0,
        pipeline: 1,
    };

    /// The ADS8354 in 32-CLK, dual-SDO mode (ADS8353-Q1 SBAS931B 7.5.3.2.1, the same
    /// interface): an active-low CS frames 32 SCLK cycles; its falling edge samples both
    /// inputs and the conversion runs during the first 16 SCLK periods; SCLK idles high,
    /// the device launches data on SCLK rising (trailing) edges and the host reads on the
    /// falling ones (CPOL = 1, CPHA = 0); SDO-A carries channel A and SDO-B channel B,
    /// MSB first from the 16th rising edge (slot 16 of each line) to the 32nd, of *this*
    /// conversion (pipeline 0). Unipolar inputs: straight binary (offset binary around
    /// mid-scale). CS stays low one clock past the frame (`AdcParams::ads8354`).
    pub const ADS8354: AdcFrame = AdcFrame {
        frame_sck: 32,
        channels: 2,
        lines: 2,
        offsets: [16, 16],
        width: 16,
        sign: SignFormat::OffsetBinary,
        cpol: true,
        cpha: false,
        conv_active_high: false,
        conv_clocks: 0,
        lead_clocks: 0,
        pipeline: 0,
    };

    /// The AD7380 in 2-wire serial mode: an active-low CS frames 16 SCLK cycles; its
    /// falling edge samples both inputs and starts the conversion, and the frame carries
    /// the previous conversion (pipeline 1); SPI mode 3 (SCLK idle high, data launched on
    /// falling = leading edges, read on rising ones); SDOA carries channel A and SDOB
    /// channel B, MSB first in slot 0; fully differential inputs: two's complement.
    pub const AD7380: AdcFrame = AdcFrame {
        frame_sck: 16,
        channels: 2,
        lines: 2,
        offsets: [0, 0],
        width: 16,
        sign: SignFormat::TwosComplement,
        cpol: true,
        cpha: true,
        conv_active_high: false,
        conv_clocks: 0,
        lead_clocks: 0,
        pipeline: 1,
    };
}
