//! The checks of [`AdcParams`] against the frame's layout and the chip's limits; each error
//! names the value, the limit and what to change.
use super::params::{ceil_clocks, invalid, MAX_PERIOD_CLOCKS};
use super::{AdcChip, AdcParams};

impl AdcParams {
    /// Checks every limit; the error names the value, the limit and what to change.
    pub fn validate(&self) -> crate::error::Result<()> {
        self.validate_frame()?;
        self.validate_pins()?;
        self.validate_period()
    }

    /// The clock and the frame layout.
    fn validate_frame(&self) -> crate::error::Result<()> {
        let f = &self.frame;
        if !(self.clock_hz.is_finite() && self.clock_hz > 0.0) {
            return Err(invalid(format!(
                "clock {} Hz is not a positive frequency",
                self.clock_hz
            )));
        }
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
        Ok(())
    }

    /// The SCK divider and the CONV / CS pulse against the chip's limits.
    fn validate_pins(&self) -> crate::error::Result<()> {
        let (f, t, name) = (&self.frame, &self.timing, self.limit_name());
        let ns = 1e9 / self.clock_hz;
        let mhz = self.clock_hz / 1e6;
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
        Ok(())
    }

    /// The conversion period against the frame and the chip's times.
    fn validate_period(&self) -> crate::error::Result<()> {
        let (f, t, name) = (&self.frame, &self.timing, self.limit_name());
        let d = self.sck_period_clocks;
        let ns = 1e9 / self.clock_hz;
        let mhz = self.clock_hz / 1e6;
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

    /// The chip's name in the limit messages: a preset's data-sheet name, or "ADC".
    fn limit_name(&self) -> String {
        match self.chip {
            AdcChip::Generic => "ADC".to_string(),
            chip => chip.to_string(),
        }
    }
}
