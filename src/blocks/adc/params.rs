//! Parameters of the ADC controller: the timing derived from the clock for a chip of
//! `chips.rs`, and their checks (maths in the module docs of [`super`]).

pub use super::chips::{AdcChip, AdcFrame, AdcTiming, SignFormat};

/// [`crate::error::Error::BlockParams`] for this block: `message` says what is wrong and what
/// is allowed.
pub(super) fn invalid(message: String) -> crate::error::Error {
    crate::error::Error::block_params("adc", message)
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

pub(super) fn ceil_clocks(ns: f64, clock_hz: f64) -> u32 {
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
