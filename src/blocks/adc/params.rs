//! Parameters of the ADC controller: the chip presets, the frame layout, the timing derived
//! from the clock and their checks (maths in the module docs of [`super`]).

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

/// [`crate::error::Error::BlockParams`] for this block: `message` says what is wrong and what
/// is allowed.
fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("adc", message)
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

/// Parameters of one ADC controller instance, all in system clocks (derived once).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct AdcParams {
    /// Which preset made these parameters.
    pub chip: AdcChip,
    /// System clock in Hz.
    pub clock_hz: f64,
    /// Frame format.
    pub frame: AdcFrame,
    /// Chip limits.
    pub timing: AdcTiming,
    /// SCK period D in system clocks (>= 2, odd allowed).
    pub sck_period_clocks: u32,
    /// SCK active-level clocks H (1..D-1); the idle-level part is L = D - H.
    pub sck_high_clocks: u32,
    /// CONV active clocks per period.
    pub conv_clocks: u32,
    /// Conversion period P in system clocks.
    pub period_clocks: u32,
}

/// Clocks from the edge that enters a controller state to the edge that moves the pins
/// (SCK, CONV) of that state: the pins are registers loaded from the state.
pub const PIN_LAG_CLOCKS: u32 = 1;

/// Clocks from the edge that enters a capture state to the edge at which `adc_miso` is
/// sampled for it: the input register `miso_d` takes the pin at the next edge (the one that
/// moves the capture state's pins), and the registered capture enables shift it in one
/// clock after that.
pub const MISO_SAMPLE_LAG_CLOCKS: u32 = 1;

/// Largest supported period (16-bit period counter).
pub const MAX_PERIOD_CLOCKS: u32 = 65_535;

fn ceil_clocks(ns: f64, clock_hz: f64) -> u32 {
    if ns <= 0.0 {
        return 0;
    }
    // Small tolerance so that an exact multiple is not rounded up by float error.
    (ns * clock_hz / 1e9 - 1e-9).ceil().max(0.0) as u32
}

impl AdcParams {
    /// LTC1407A-1 at `clock_hz` with an SCK period of `sck_period_clocks` system clocks and
    /// a conversion period of `period_clocks` (None: the shortest the chip allows, at least
    /// the 34-SCK frame). Call [`validate`](Self::validate) before use.
    pub fn ltc1407a(clock_hz: f64, sck_period_clocks: u32, period_clocks: Option<u32>) -> Self {
        Self::build(
            AdcChip::Ltc1407a1,
            clock_hz,
            AdcFrame::LTC1407A_1,
            AdcTiming::LTC1407A_1,
            sck_period_clocks,
            period_clocks,
        )
    }

    /// LTC1407A-1 with the fastest SCK divider the chip allows at `clock_hz`.
    pub fn ltc1407a_fastest(clock_hz: f64) -> crate::error::Result<Self> {
        let d = ceil_clocks(AdcTiming::LTC1407A_1.sck_min_period_ns, clock_hz).max(2);
        let p = Self::ltc1407a(clock_hz, d, None);
        p.validate()?;
        Ok(p)
    }

    /// A CS-framed preset chip (ADS8354, AD7380): `frame` with the lead clocks the chip's
    /// CS-to-SCLK set-up needs at `clock_hz`, and CS active from the period start to one
    /// clock past the last SCK cycle (so the last SCK edge is at least one SCK high time
    /// plus a clock before CS rises).
    fn cs_framed(
        chip: AdcChip,
        mut frame: AdcFrame,
        timing: AdcTiming,
        clock_hz: f64,
        d: u32,
        period_clocks: Option<u32>,
    ) -> Self {
        // Lead clocks: the fewest that give the chip's CS-to-first-SCLK set-up with the
        // L = D - H idle-level clocks that precede the first SCK edge (see `validate`).
        let idle = d.saturating_sub(d / 2);
        frame.lead_clocks = ceil_clocks(timing.conv_to_sck_ns, clock_hz).saturating_sub(idle);
        frame.conv_clocks = frame
            .lead_clocks
            .saturating_add(frame.frame_sck.saturating_mul(d))
            .saturating_add(1);
        Self::build(chip, clock_hz, frame, timing, d, period_clocks)
    }

    /// TI ADS8354 ([`AdcFrame::ADS8354`], [`AdcTiming::ADS8354`]) at `clock_hz`, SCK of
    /// `sck_period_clocks`, period `period_clocks` (None: the shortest allowed).
    pub fn ads8354(clock_hz: f64, sck_period_clocks: u32, period_clocks: Option<u32>) -> Self {
        Self::cs_framed(
            AdcChip::Ads8354,
            AdcFrame::ADS8354,
            AdcTiming::ADS8354,
            clock_hz,
            sck_period_clocks,
            period_clocks,
        )
    }

    /// ADI AD7380 ([`AdcFrame::AD7380`], [`AdcTiming::AD7380`]), as [`Self::ads8354`].
    pub fn ad7380(clock_hz: f64, sck_period_clocks: u32, period_clocks: Option<u32>) -> Self {
        Self::cs_framed(
            AdcChip::Ad7380,
            AdcFrame::AD7380,
            AdcTiming::AD7380,
            clock_hz,
            sck_period_clocks,
            period_clocks,
        )
    }

    /// Any SPI ADC: frame format, chip limits, SCK divider and conversion period (None: the
    /// shortest allowed). Call [`validate`](Self::validate) before use.
    pub fn generic(
        clock_hz: f64,
        frame: AdcFrame,
        timing: AdcTiming,
        sck_period_clocks: u32,
        period_clocks: Option<u32>,
    ) -> Self {
        Self::build(
            AdcChip::Generic,
            clock_hz,
            frame,
            timing,
            sck_period_clocks,
            period_clocks,
        )
    }

    fn build(
        chip: AdcChip,
        clock_hz: f64,
        frame: AdcFrame,
        timing: AdcTiming,
        d: u32,
        period_clocks: Option<u32>,
    ) -> Self {
        let conv_clocks = if frame.conv_clocks > 0 {
            frame.conv_clocks
        } else {
            ceil_clocks(timing.conv_min_pulse_ns, clock_hz).max(1)
        };
        let mut p = AdcParams {
            chip,
            clock_hz,
            frame,
            timing,
            sck_period_clocks: d,
            sck_high_clocks: d / 2,
            conv_clocks,
            period_clocks: 0,
        };
        p.period_clocks = period_clocks.unwrap_or_else(|| p.min_period_clocks());
        p
    }

    /// Period for a target sample rate per channel (rounded up to whole clocks: the rate
    /// reached is at most the target).
    pub fn period_for_rate(clock_hz: f64, rate_hz: f64) -> u32 {
        if rate_hz.is_nan() || rate_hz <= 0.0 || !clock_hz.is_finite() {
            return 0;
        }
        (clock_hz / rate_hz - 1e-9).ceil().max(0.0) as u32
    }

    /// Shortest period the frame and the chip's timing allow at this divider.
    pub fn min_period_clocks(&self) -> u32 {
        let f = &self.frame;
        let d = self.sck_period_clocks;
        let frame_end = f.lead_clocks.saturating_add(f.frame_sck.saturating_mul(d));
        let mut p = frame_end.max(self.last_capture_clock().saturating_add(1));
        p = p.max(
            self.conv_clocks
                .saturating_add(ceil_clocks(self.timing.conv_min_low_ns, self.clock_hz)),
        );
        if self.timing.conversion_edges > 0 {
            let end = self.conversion_end_clock();
            p = p.max(
                end.saturating_add(ceil_clocks(self.timing.acquisition_ns, self.clock_hz).max(1)),
            );
        }
        if self.frame.pipeline >= 1 {
            p = p.max(ceil_clocks(self.timing.conversion_ns, self.clock_hz));
        }
        if self.timing.max_sample_rate_hz > 0.0 {
            p = p.max(Self::period_for_rate(
                self.clock_hz,
                self.timing.max_sample_rate_hz,
            ));
        }
        p
    }

    /// Shortest period the frame and the chip's times allow at this divider, without the
    /// chip's rate limit: what the clock (SCK divider, whole clocks) alone sets.
    fn clock_bound_period_clocks(&self) -> u32 {
        let mut q = self.clone();
        q.timing.max_sample_rate_hz = 0.0;
        q.min_period_clocks()
    }

    /// What sets the sample rate reached, for `check`: the configured target, the chip's
    /// per-channel limit, or the clock (the frame's SCK cycles at the SCK divider and the
    /// chip's times in whole system clocks).
    pub fn rate_bound(&self) -> String {
        let fastest = self.min_period_clocks();
        let by_clock = self.clock_bound_period_clocks();
        let limit = self.timing.max_sample_rate_hz;
        if self.period_clocks > fastest {
            format!(
                "the configured adc.sample_rate_hz (the fastest is {:.0} samples/s)",
                self.clock_hz / fastest.max(1) as f64
            )
        } else if limit > 0.0 && by_clock < fastest {
            format!(
                "the {}'s limit of {limit:.0} samples/s per channel binds (the clock alone would allow {:.0})",
                self.chip,
                self.clock_hz / by_clock.max(1) as f64
            )
        } else {
            format!(
                "the clock binds: {} clocks per frame ({} SCK x {} clocks at {:.3} MHz, with the chip's times in whole clocks), below the {}'s limit of {limit:.0} samples/s",
                by_clock,
                self.frame.frame_sck,
                self.sck_period_clocks,
                self.clock_hz / 1e6,
                self.chip
            )
        }
    }

    /// SCK idle-level clocks L = D - H.
    pub fn sck_low_clocks(&self) -> u32 {
        self.sck_period_clocks.saturating_sub(self.sck_high_clocks)
    }

    /// Clocks after the start of an SCK cycle at which a slot is captured (in the next
    /// cycle): L for CPHA = 1, 0 for CPHA = 0.
    pub fn capture_phase(&self) -> u32 {
        if self.frame.cpha {
            self.sck_low_clocks()
        } else {
            0
        }
    }

    /// Slots holding data bits: (first, last) over all channels.
    pub fn data_slots(&self) -> (u32, u32) {
        let f = &self.frame;
        let n = f.channels.clamp(1, 2) as usize;
        let first = f.offsets[..n].iter().copied().min().unwrap_or(0);
        let last = f.offsets[..n]
            .iter()
            .map(|o| o.saturating_add(f.width.max(1) - 1))
            .max()
            .unwrap_or(0);
        (first, last)
    }

    /// Period counter value (clocks after the CONV edge) at which slot `k` is captured.
    pub fn capture_clock(&self, k: u32) -> u32 {
        self.frame
            .lead_clocks
            .saturating_add(k.saturating_add(1).saturating_mul(self.sck_period_clocks))
            .saturating_add(self.capture_phase())
    }

    /// Period counter value of the state whose pins make the SCK edge that shifts slot `k`
    /// out of the chip (k >= 1): the leading edge of SCK cycle k for CPHA = 1, the trailing
    /// edge of cycle k - 1 for CPHA = 0 (slot 0 of CPHA = 0 is shifted by CONV / CS).
    pub fn shift_clock(&self, k: u32) -> u32 {
        let edge = if self.frame.cpha {
            self.sck_low_clocks()
        } else {
            0
        };
        self.frame
            .lead_clocks
            .saturating_add(k.saturating_mul(self.sck_period_clocks))
            .saturating_add(edge)
    }

    /// The capture distance: system clocks from the clock edge that moves the `adc_sck` pin
    /// (the edge that shifts a bit out of the chip) to the clock edge whose register
    /// (`miso_d`) samples `adc_miso` for that bit. Derived from the controller's structure
    /// (capture state, shifting state, pin and sample lags); it is the same for every slot.
    /// The I/O budget (`check`, the UCF/SDC, the chip models' valid window) is this many
    /// clock periods: D with the capture at the edge that launches the next shifting edge.
    pub fn capture_distance_clocks(&self) -> u32 {
        let k = 1;
        (self.capture_clock(k) + MISO_SAMPLE_LAG_CLOCKS)
            .saturating_sub(self.shift_clock(k) + PIN_LAG_CLOCKS)
    }

    /// [`capture_distance_clocks`](Self::capture_distance_clocks) in ns.
    pub fn capture_window_ns(&self) -> f64 {
        self.capture_distance_clocks() as f64 * 1e9 / self.clock_hz
    }

    /// Period counter value at which the last data bit is captured (its capture state).
    pub fn last_capture_clock(&self) -> u32 {
        self.capture_clock(self.data_slots().1)
    }

    /// Period counter value of the SCK rising (leading) edge that completes a conversion.
    pub fn conversion_end_clock(&self) -> u32 {
        let e = self.timing.conversion_edges.max(1);
        self.frame
            .lead_clocks
            .saturating_add((e - 1).saturating_mul(self.sck_period_clocks))
            .saturating_add(self.sck_low_clocks())
    }

    /// SCK frequency in Hz.
    pub fn sck_hz(&self) -> f64 {
        self.clock_hz / self.sck_period_clocks.max(1) as f64
    }

    /// Sample rate per channel in samples per second.
    pub fn sample_rate_hz(&self) -> f64 {
        self.clock_hz / self.period_clocks.max(1) as f64
    }

    /// Clocks from the first clock CONV is active (the sampling edge) to the `out_valid`
    /// strobe that delivers that sample.
    pub fn conv_to_valid_clocks(&self) -> u32 {
        // CONV and out_valid both leave registers: CONV one clock after its state, the
        // strobe one clock after the shift, which is MISO_SAMPLE_LAG_CLOCKS + 1 after the
        // capture state.
        self.frame
            .pipeline
            .saturating_mul(self.period_clocks)
            .saturating_add(self.last_capture_clock())
            .saturating_add(MISO_SAMPLE_LAG_CLOCKS + 1 - PIN_LAG_CLOCKS)
    }

    /// [`conv_to_valid_clocks`](Self::conv_to_valid_clocks) in seconds.
    pub fn conv_to_valid_s(&self) -> f64 {
        self.conv_to_valid_clocks() as f64 / self.clock_hz
    }

    /// Clocks from reset release (with `enable` high) to the first `out_valid`: one flush
    /// period, `pipeline` discarded frames, then the latency of the first sample.
    pub fn startup_clocks(&self) -> u32 {
        // Row 0 after release enters pc = 0 of the flush period; the pins and the data are
        // registered one clock after the state (see `hdl::AdcController`), hence the + 1.
        self.period_clocks
            .saturating_add(self.conv_to_valid_clocks())
            .saturating_add(1)
    }

    /// Checks every limit; the error names the value, the limit and what to change.
    pub fn validate(&self) -> crate::error::Result<()> {
        let f = &self.frame;
        let t = &self.timing;
        let name = match self.chip {
            AdcChip::Ltc1407a1 => "LTC1407A-1",
            AdcChip::Ads8354 => "ADS8354",
            AdcChip::Ad7380 => "AD7380",
            AdcChip::Generic => "ADC",
        };
        if !(self.clock_hz.is_finite() && self.clock_hz > 0.0) {
            return Err(invalid(format!(
                "clock {} Hz is not a positive frequency",
                self.clock_hz
            )));
        }
        let ns = 1e9 / self.clock_hz;
        let mhz = self.clock_hz / 1e6;
        if !(1..=2).contains(&f.channels) {
            return Err(invalid(format!(
                "{} channels: 1 or 2 are supported",
                f.channels
            )));
        }
        if !(10..=16).contains(&f.width) {
            return Err(invalid(format!(
                "sample width {} bits: 10..=16 are supported",
                f.width
            )));
        }
        if !(1..=250).contains(&f.frame_sck) {
            return Err(invalid(format!(
                "frame of {} SCK cycles: 1..=250 are supported",
                f.frame_sck
            )));
        }
        if f.pipeline > 2 {
            return Err(invalid(format!(
                "pipeline of {} frames: 0..=2 are supported",
                f.pipeline
            )));
        }
        for c in 0..f.channels as usize {
            if f.offsets[c].saturating_add(f.width) > f.frame_sck {
                return Err(invalid(format!(
                    "channel {c}: bits {}..{} do not fit in the {}-SCK frame",
                    f.offsets[c],
                    f.offsets[c].saturating_add(f.width - 1),
                    f.frame_sck
                )));
            }
        }
        if !(1..=2).contains(&f.lines) || f.lines > f.channels {
            return Err(invalid(format!(
                "{} data lines with {} channels: 1 line, or 2 lines with 2 channels (one per channel) are supported",
                f.lines, f.channels
            )));
        }
        if f.channels == 2 && f.lines == 1 {
            let (a, b) = (f.offsets[0], f.offsets[1]);
            if a < b.saturating_add(f.width) && b < a.saturating_add(f.width) {
                return Err(invalid(format!(
                    "channel bit ranges overlap: {a}..{} and {b}..{}",
                    a + f.width - 1,
                    b + f.width - 1
                )));
            }
        }
        let d = self.sck_period_clocks;
        if !(2..=255).contains(&d) {
            return Err(invalid(format!(
                "SCK period of {d} system clocks: 2..=255 are supported (SCK needs a high and a low clock)"
            )));
        }
        let (h, l) = (self.sck_high_clocks, self.sck_low_clocks());
        if h == 0 || h >= d {
            return Err(invalid(format!(
                "SCK high time {h} clocks must be 1..={}",
                d - 1
            )));
        }
        let tsck = d as f64 * ns;
        if tsck + 1e-9 < t.sck_min_period_ns {
            let need = ceil_clocks(t.sck_min_period_ns, self.clock_hz).max(2);
            return Err(invalid(format!(
                "SCK of {:.2} MHz ({d} clocks = {tsck:.2} ns at {mhz:.2} MHz) is above the {name} limit of {:.2} MHz (tSCK >= {} ns); use an SCK period of at least {need} clocks",
                1e3 / tsck,
                1e3 / t.sck_min_period_ns,
                t.sck_min_period_ns
            )));
        }
        if t.sck_max_period_ns > 0.0 && tsck > t.sck_max_period_ns {
            return Err(invalid(format!(
                "SCK period {tsck:.1} ns is above the {name} maximum of {} ns during a conversion",
                t.sck_max_period_ns
            )));
        }
        if (h.min(l) as f64 * ns) + 1e-9 < t.sck_min_pulse_ns {
            return Err(invalid(format!(
                "SCK pulse of {:.2} ns is shorter than the {name} minimum of {} ns",
                h.min(l) as f64 * ns,
                t.sck_min_pulse_ns
            )));
        }
        if tsck + 1e-9 < t.data_valid_ns {
            return Err(invalid(format!(
                "SCK period {tsck:.2} ns is shorter than the {name} data-valid delay of {} ns: data would be read before it is valid",
                t.data_valid_ns
            )));
        }
        if self.conv_clocks == 0 || (self.conv_clocks as f64 * ns) + 1e-9 < t.conv_min_pulse_ns {
            return Err(invalid(format!(
                "CONV pulse of {} clocks ({:.2} ns) is shorter than the {name} minimum of {} ns",
                self.conv_clocks,
                self.conv_clocks as f64 * ns,
                t.conv_min_pulse_ns
            )));
        }
        if f.lead_clocks.saturating_add(l) as f64 * ns + 1e-9 < t.conv_to_sck_ns {
            return Err(invalid(format!(
                "CONV to first SCK edge is {:.2} ns, below the {name} set-up of {} ns; raise the lead clocks",
                f.lead_clocks.saturating_add(l) as f64 * ns,
                t.conv_to_sck_ns
            )));
        }
        let p = self.period_clocks;
        if p > MAX_PERIOD_CLOCKS {
            return Err(invalid(format!(
                "conversion period of {p} clocks exceeds the supported {MAX_PERIOD_CLOCKS} (sample rate {:.0} Hz is too low for {mhz:.2} MHz)",
                self.sample_rate_hz()
            )));
        }
        let frame_end = f.lead_clocks.saturating_add(f.frame_sck.saturating_mul(d));
        if p < frame_end {
            return Err(invalid(format!(
                "conversion period of {p} clocks is shorter than the frame ({} + {} SCK x {d} clocks = {frame_end} clocks); the shortest allowed is {}",
                f.lead_clocks,
                f.frame_sck,
                self.min_period_clocks()
            )));
        }
        if p <= self.last_capture_clock() {
            return Err(invalid(format!(
                "conversion period of {p} clocks ends before the last data bit is read (clock {}); the shortest allowed is {}",
                self.last_capture_clock(),
                self.min_period_clocks()
            )));
        }
        if self.conv_clocks >= p || ((p - self.conv_clocks) as f64 * ns) + 1e-9 < t.conv_min_low_ns
        {
            return Err(invalid(format!(
                "CONV is active {} of {p} clocks; it must stay inactive at least {} ns per period",
                self.conv_clocks, t.conv_min_low_ns
            )));
        }
        if t.conversion_edges > 0 {
            if t.conversion_edges > f.frame_sck {
                return Err(invalid(format!(
                    "the {name} needs {} SCK edges per conversion but the frame has {}",
                    t.conversion_edges, f.frame_sck
                )));
            }
            let acq = (p - self.conversion_end_clock()) as f64 * ns;
            if acq + 1e-9 < t.acquisition_ns {
                return Err(invalid(format!(
                    "conversion period of {p} clocks leaves {acq:.1} ns from the {}th SCK rising edge to the next CONV, below the {name} acquisition time of {} ns; the shortest allowed is {}",
                    t.conversion_edges,
                    t.acquisition_ns,
                    self.min_period_clocks()
                )));
            }
        }
        if t.conversion_ns > 0.0 {
            if f.pipeline == 0 {
                // The first data bit leaves at its shifting pin edge (slot 0 of CPHA = 0
                // at the CS edge itself), both pins one clock after their states.
                let first = f.offsets[..f.channels as usize]
                    .iter()
                    .copied()
                    .min()
                    .unwrap_or(0);
                let at = if first == 0 && !f.cpha {
                    0
                } else {
                    self.shift_clock(first)
                };
                if (at as f64 * ns) + 1e-9 < t.conversion_ns {
                    return Err(invalid(format!(
                        "SCK period of {d} clocks shifts the first data bit out {:.1} ns after CS, before the {name} conversion time of {} ns ends; use an SCK period of at least {} clocks",
                        at as f64 * ns,
                        t.conversion_ns,
                        d + 1
                    )));
                }
            } else if (p as f64 * ns) + 1e-9 < t.conversion_ns {
                return Err(invalid(format!(
                    "conversion period of {p} clocks is shorter than the {name} conversion time of {} ns; the shortest allowed is {}",
                    t.conversion_ns,
                    self.min_period_clocks()
                )));
            }
        }
        if t.max_sample_rate_hz > 0.0
            && self.sample_rate_hz() > t.max_sample_rate_hz * (1.0 + 1e-12)
        {
            return Err(invalid(format!(
                "sample rate {:.0} Hz per channel is above the {name} limit of {:.0} Hz; the shortest period is {} clocks",
                self.sample_rate_hz(),
                t.max_sample_rate_hz,
                self.min_period_clocks()
            )));
        }
        Ok(())
    }

    /// Derived figures, one per line (for `check` and reports).
    pub fn describe(&self) -> String {
        format!(
            "adc chip                    {}\n\
             system clock                {:.3} MHz\n\
             SCK                         {:.3} MHz ({} clocks: {} high, {} low)\n\
             conversion period           {} clocks ({:.1} ns)\n\
             sample rate per channel     {:.0} samples/s ({})\n\
             ADC latency CONV -> sample  {} clocks ({:.1} ns)\n\
             first sample after reset    {} clocks\n",
            self.chip,
            self.clock_hz / 1e6,
            self.sck_hz() / 1e6,
            self.sck_period_clocks,
            self.sck_high_clocks,
            self.sck_low_clocks(),
            self.period_clocks,
            self.period_clocks as f64 * 1e9 / self.clock_hz,
            self.sample_rate_hz(),
            self.rate_bound(),
            self.conv_to_valid_clocks(),
            self.conv_to_valid_s() * 1e9,
            self.startup_clocks(),
        )
    }
}
