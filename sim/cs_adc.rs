//! Pin-level core shared by the models of CS-framed dual simultaneous-sampling SAR ADCs
//! with one data line per channel (`sim::ads8354`, `sim::ad7380`). Each of those files
//! states its chip's behaviour and limits from the chip's data sheet as a [`CsAdcSpec`];
//! this file turns a spec into a model that keeps real time, independently of the
//! controller in `blocks::adc` (nothing here reads `AdcFrame` or `AdcParams`).
//!
//! ```text
//! CS    ‾‾\_________________________________________________/‾‾‾‾‾‾\____
//!          ^ samples both inputs, starts a conversion (conversion_ns)
//! SCLK  ‾‾‾‾‾‾\_/‾\_/‾\_/ ... ‾\_/‾\_/‾‾‾‾‾‾‾  (idle level: the spec's)
//! SDO-x       launch edge n shifts out bit (msb_edge + width - 1 - n) of the word:
//!             this conversion's (pipeline 0) or the previous one's (pipeline 1)
//! ```
//!
//! Driven once per system clock with the CS and SCLK levels the FPGA launches at that
//! clock edge; returns what the FPGA's input registers read at the next edge on SDO-A
//! and SDO-B ([`super::adc_pins`]: clock-to-out and a trace to the chip, the chip's
//! valid / hold delays after its launch edge, a trace back, the FPGA's set-up). A bit
//! read outside its valid window, a word of a conversion not finished when its first bit
//! leaves, and a tri-stated line read as pseudo-random bits. Every limit of the spec is
//! checked and a violation recorded (never a panic).
use super::adc_pins::{DataLine, Level, PinTiming};

/// A chip's interface as its data sheet gives it (times in ns, 0 = no limit).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CsAdcSpec {
    /// The chip's name, for messages.
    pub name: &'static str,
    /// SCLK idle level (its level while CS is high).
    pub sclk_idle_high: bool,
    /// The chip launches data on SCLK rising edges (else falling).
    pub launch_on_rising: bool,
    /// The launch edge (1-based, counted from CS falling) that shifts out the MSB.
    pub msb_edge: u32,
    /// Sample width in bits.
    pub width: u32,
    /// Launch edges a complete frame has (fewer before CS rises: frame abort).
    pub frame_edges: u32,
    /// 0: a frame carries the conversion its CS falling edge started; 1: the previous one.
    pub pipeline: u32,
    /// Codes are straight binary (offset binary); else two's complement.
    pub straight_binary: bool,
    /// Minimum SCLK period.
    pub sclk_min_period_ns: f64,
    /// Minimum SCLK high and low time.
    pub sclk_min_pulse_ns: f64,
    /// Launch edge to new data valid at the pin (maximum).
    pub data_valid_ns: f64,
    /// Launch edge to old data no longer held (minimum).
    pub data_hold_ns: f64,
    /// Minimum CS high time.
    pub cs_min_high_ns: f64,
    /// Minimum CS falling edge to first SCLK edge.
    pub cs_to_sclk_ns: f64,
    /// Minimum last SCLK read edge (the edge that does not launch data) to CS rising edge.
    pub sclk_to_cs_ns: f64,
    /// Conversion time from the CS falling edge.
    pub conversion_ns: f64,
    /// Minimum time between CS falling edges (1 / maximum rate).
    pub cycle_min_ns: f64,
}

/// Kinds of violations of a [`CsAdcSpec`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CsViolationKind {
    /// SCLK period below the minimum.
    SclkTooFast,
    /// SCLK high or low time below the minimum.
    SclkPulseTooShort,
    /// CS high shorter than the minimum.
    CsHighTooShort,
    /// First SCLK edge too soon after CS falling.
    CsToSclk,
    /// CS rising too soon after the last SCLK edge.
    SclkToCs,
    /// A word left the chip before its conversion ended (read as garbage).
    ConversionNotDone,
    /// CS falling edges closer than the minimum cycle time.
    CycleTooShort,
    /// CS rose before the frame's launch edges were all given.
    FrameAborted,
}

/// One recorded violation.
#[derive(Clone, Debug, PartialEq)]
pub struct CsViolation {
    /// System clock index (step count) at which it was seen.
    pub clock: u64,
    /// What was violated.
    pub kind: CsViolationKind,
    /// Measured value and limit.
    pub message: String,
}

/// One conversion: the clock of its CS falling edge and the codes sampled (two's
/// complement values as a host delivers them, whatever the chip's output coding).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CsConversion {
    /// Clock index of the CS falling edge.
    pub clock: u64,
    /// Codes of channel A and channel B.
    pub codes: [i32; 2],
}

/// The code source: `f(conversion index, time of the CS falling edge in s)`.
pub type CsCodeFn = Box<dyn FnMut(u64, f64) -> [i32; 2]>;

/// A CS-framed dual-SDO ADC.
pub struct CsAdc {
    spec: CsAdcSpec,
    period_ns: f64,
    source: Option<CsCodeFn>,
    clock: u64,
    prev_cs: bool,
    prev_sclk: bool,
    cs_rise: Option<f64>,
    cs_fall: Option<f64>,
    sclk_rise: Option<f64>,
    sclk_fall: Option<f64>,
    /// Last SCLK read edge (not a launch edge) while CS was low, for the CS-rising check.
    last_edge: Option<f64>,
    /// CS is low (a frame runs).
    framed: bool,
    /// SCLK edges seen in this frame (either) and launch edges.
    edges: u32,
    launches: u32,
    /// The word this frame shifts out (None: no valid word) and its conversion's start.
    word: Option<[i32; 2]>,
    word_start: f64,
    /// The running or last conversion: its start and codes.
    current: Option<(f64, [i32; 2])>,
    lines: [DataLine; 2],
    seed: u64,
    count: u64,
    conversions: Vec<CsConversion>,
    violations: Vec<CsViolation>,
}

impl CsAdc {
    /// The chip of `spec` clocked by an FPGA at `clock_hz`, codes 0 until a source is set,
    /// random bits from `seed`, the default board pins.
    pub fn new(spec: CsAdcSpec, clock_hz: f64, seed: u64) -> Self {
        let period_ns = if clock_hz.is_finite() && clock_hz > 0.0 {
            1e9 / clock_hz
        } else {
            1.0
        };
        let pins = PinTiming::board_default();
        CsAdc {
            spec,
            period_ns,
            source: None,
            clock: 0,
            prev_cs: true,
            prev_sclk: spec.sclk_idle_high,
            cs_rise: None,
            cs_fall: None,
            sclk_rise: None,
            sclk_fall: None,
            last_edge: None,
            framed: false,
            edges: 0,
            launches: 0,
            word: None,
            word_start: 0.0,
            current: None,
            lines: [
                DataLine::new(pins, seed),
                DataLine::new(pins, seed ^ 0x5a5a),
            ],
            seed,
            count: 0,
            conversions: Vec::new(),
            violations: Vec::new(),
        }
    }

    /// The pins between the FPGA and the chip.
    pub fn with_pins(mut self, pins: PinTiming) -> Self {
        self.lines = [
            DataLine::new(pins, self.seed),
            DataLine::new(pins, self.seed ^ 0x5a5a),
        ];
        self
    }

    /// A fault of both data lines at the FPGA's pads (None: none; see `DataLine::stick`):
    /// a common connector or supply fault.
    pub fn set_sdo_stuck(&mut self, level: Option<bool>) {
        for l in self.lines.iter_mut() {
            l.stick(level);
        }
    }

    /// Codes for each conversion from `f(conversion index, time of CS falling in s)`.
    pub fn with_codes(mut self, f: impl FnMut(u64, f64) -> [i32; 2] + 'static) -> Self {
        self.source = Some(Box::new(f));
        self
    }

    /// The spec in use.
    pub fn spec(&self) -> CsAdcSpec {
        self.spec
    }

    /// Conversions so far, in order.
    pub fn conversions(&self) -> &[CsConversion] {
        &self.conversions
    }

    /// Forgets the conversions so far (a long run keeps no history).
    pub fn clear_conversions(&mut self) {
        self.conversions.clear();
    }

    /// Violations recorded so far.
    pub fn violations(&self) -> &[CsViolation] {
        &self.violations
    }

    fn violation(&mut self, kind: CsViolationKind, message: String) {
        self.violations.push(CsViolation {
            clock: self.clock,
            kind,
            message,
        });
    }

    /// The chip's range of codes.
    fn clamp(&self, v: i32) -> i32 {
        let w = self.spec.width.clamp(2, 31);
        v.clamp(-(1 << (w - 1)), (1 << (w - 1)) - 1)
    }

    /// The level launch edge `n` shifts out on line `c`.
    fn level(&self, c: usize, n: u32) -> Level {
        let s = &self.spec;
        let Some(w) = self.word else {
            return Level::Undefined;
        };
        if n < s.msb_edge || n >= s.msb_edge + s.width {
            return Level::Undefined;
        }
        let mut raw = (w[c] as i64) & ((1i64 << s.width) - 1);
        if s.straight_binary {
            raw ^= 1 << (s.width - 1);
        }
        let bit = s.width - 1 - (n - s.msb_edge);
        Level::Bit((raw >> bit) & 1 == 1)
    }

    fn drive(&mut self, t: f64, n: u32) {
        let (valid, hold) = (self.spec.data_valid_ns, self.spec.data_hold_ns);
        for c in 0..2 {
            let l = self.level(c, n);
            self.lines[c].change(t, hold, valid, l);
        }
    }

    fn cs_falls(&mut self, t: f64) {
        let s = self.spec;
        if let Some(r) = self.cs_rise {
            if t - r + 1e-9 < s.cs_min_high_ns {
                self.violation(
                    CsViolationKind::CsHighTooShort,
                    format!("CS high for {:.2} ns < {} ns", t - r, s.cs_min_high_ns),
                );
            }
        }
        if let Some(f) = self.cs_fall {
            if t - f + 1e-9 < s.cycle_min_ns {
                self.violation(
                    CsViolationKind::CycleTooShort,
                    format!(
                        "CS falling edges {:.2} ns apart < {} ns",
                        t - f,
                        s.cycle_min_ns
                    ),
                );
            }
        }
        // The previous conversion's result is complete only after its conversion time.
        let previous = match self.current {
            Some((start, codes)) if t - start + 1e-9 >= s.conversion_ns => Some((start, codes)),
            Some(_) => {
                self.violation(
                    CsViolationKind::ConversionNotDone,
                    format!(
                        "CS fell before the {} ns conversion of the previous one ended",
                        s.conversion_ns
                    ),
                );
                None
            }
            None => None,
        };
        let k = self.count;
        self.count += 1;
        let codes = match self.source.as_mut() {
            Some(f) => f(k, t * 1e-9),
            None => [0, 0],
        };
        let codes = [self.clamp(codes[0]), self.clamp(codes[1])];
        self.conversions.push(CsConversion {
            clock: self.clock,
            codes,
        });
        self.current = Some((t, codes));
        (self.word, self.word_start) = if s.pipeline == 0 {
            (Some(codes), t)
        } else {
            previous.map_or((None, t), |(st, c)| (Some(c), st))
        };
        self.framed = true;
        self.edges = 0;
        self.launches = 0;
        self.last_edge = None;
        self.cs_fall = Some(t);
        // Out of tri-state: nothing valid before the first launch edge.
        self.drive(t, 0);
    }

    fn cs_rises(&mut self, t: f64) {
        let s = self.spec;
        if let Some(e) = self.last_edge {
            if t - e + 1e-9 < s.sclk_to_cs_ns {
                self.violation(
                    CsViolationKind::SclkToCs,
                    format!(
                        "last SCLK read edge to CS rising {:.2} ns < {} ns",
                        t - e,
                        s.sclk_to_cs_ns
                    ),
                );
            }
        }
        if self.launches < s.frame_edges {
            self.violation(
                CsViolationKind::FrameAborted,
                format!(
                    "CS rose after {} of {} SCLK launch edges",
                    self.launches, s.frame_edges
                ),
            );
        }
        self.framed = false;
        self.cs_rise = Some(t);
        // Tri-state.
        for l in self.lines.iter_mut() {
            l.change(t, s.data_hold_ns, s.data_valid_ns, Level::Undefined);
        }
    }

    fn sclk_edge(&mut self, t: f64, rising: bool) {
        let s = self.spec;
        let (same, other) = if rising {
            (self.sclk_rise, self.sclk_fall)
        } else {
            (self.sclk_fall, self.sclk_rise)
        };
        if let Some(p) = same {
            if t - p + 1e-9 < s.sclk_min_period_ns {
                self.violation(
                    CsViolationKind::SclkTooFast,
                    format!("SCLK period {:.2} ns < {} ns", t - p, s.sclk_min_period_ns),
                );
            }
        }
        if let Some(o) = other {
            if t - o + 1e-9 < s.sclk_min_pulse_ns {
                self.violation(
                    CsViolationKind::SclkPulseTooShort,
                    format!(
                        "SCLK {} for {:.2} ns < {} ns",
                        if rising { "low" } else { "high" },
                        t - o,
                        s.sclk_min_pulse_ns
                    ),
                );
            }
        }
        if rising {
            self.sclk_rise = Some(t);
        } else {
            self.sclk_fall = Some(t);
        }
        if !self.framed {
            return;
        }
        if self.edges == 0 {
            if let Some(f) = self.cs_fall {
                if t - f + 1e-9 < s.cs_to_sclk_ns {
                    self.violation(
                        CsViolationKind::CsToSclk,
                        format!(
                            "CS falling to the first SCLK edge {:.2} ns < {} ns",
                            t - f,
                            s.cs_to_sclk_ns
                        ),
                    );
                }
            }
        }
        self.edges += 1;
        if rising != s.launch_on_rising {
            self.last_edge = Some(t);
        }
        if rising == s.launch_on_rising {
            self.launches += 1;
            let n = self.launches;
            if n == s.msb_edge
                && self.word.is_some()
                && t - self.word_start + 1e-9 < s.conversion_ns
            {
                self.violation(
                    CsViolationKind::ConversionNotDone,
                    format!(
                        "MSB shifted out {:.2} ns after the conversion started < {} ns",
                        t - self.word_start,
                        s.conversion_ns
                    ),
                );
                self.word = None;
            }
            self.drive(t, n);
        }
    }

    /// One system clock: `cs` and `sclk` are the levels the FPGA launches at this clock
    /// edge. Returns what the FPGA reads on SDO-A and SDO-B at the next clock edge.
    pub fn step(&mut self, cs: bool, sclk: bool) -> [bool; 2] {
        let t = self.clock as f64 * self.period_ns;
        if !cs && self.prev_cs {
            self.cs_falls(t);
        }
        if sclk != self.prev_sclk {
            self.sclk_edge(t, sclk);
        }
        if cs && !self.prev_cs {
            self.cs_rises(t);
        }
        self.prev_cs = cs;
        self.prev_sclk = sclk;
        self.clock += 1;
        let at = self.clock as f64 * self.period_ns;
        [self.lines[0].sample(at), self.lines[1].sample(at)]
    }
}
