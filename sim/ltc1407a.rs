//! Pin-level model of the LTC1407A-1 dual simultaneous-sampling 14-bit ADC, written from
//! its datasheet (Linear Technology 14071fb) and the Spartan-3A/3AN Starter Kit user guide
//! (UG334), independently of the controller in `blocks::adc`.
//!
//! Driven once per system clock with the CONV and SCK levels the controller's registers
//! take at that clock edge; returns the level the controller's input register reads at
//! `adc_miso` at the next system clock edge. The pins keep real time ([`super::adc_pins`]):
//! an edge reaches the chip FPGA clock-to-out + one trace after its clock edge, SDO comes
//! back over a second trace, and the FPGA needs it set up before its edge (the `[board]`
//! budget of `check`, defaults 6 + 1 + 1 + 3 ns). Behaviour modelled:
//!
//! * A rising CONV edge samples both channels (codes from a caller closure, 0 and 0 without one)
//!   and starts a conversion that needs 32 SCK rising edges; CONV rising edges before those
//!   32 edges are ignored by the chip (and recorded as a violation here).
//! * SDO after a CONV rise, one slot per SCK rising edge: edges 1-2 Hi-Z, 3-16 channel 0
//!   D13..D0, 17-18 Hi-Z, 19-32 channel 1 D13..D0, then Hi-Z (the 34-SCK frame:
//!   2 idle, 14, 2 idle, 14, 2 idle). The words are those of the *previous* conversion
//!   ("each pair of output data words represent the two analog input channels at the start
//!   of the previous conversion"); before any completed conversion they are undefined.
//! * After a rising SCK edge at the chip the previous bit stays valid for 2 ns (t10), the
//!   new one is valid 8 ns after the edge (t8); a level read at the FPGA outside a bit's
//!   valid window (set-up and hold at the pad), and while Hi-Z, is a pseudo-random bit,
//!   so a controller that samples there reads garbage.
//! * Timing checks (violations are recorded, never panics): SCK period >= 19.6 ns and
//!   <= 10 us during a conversion (a slower conversion is corrupted: its data become
//!   undefined), SCK high/low >= 2 ns, CONV high >= 4 ns, CONV low >= 15 ns, CONV rise to
//!   SCK rise >= 3 ns, 32nd SCK rise to CONV rise >= 45 ns (acquisition), CONV rise during
//!   a conversion, two CONV rises without an SCK rise between them (nap/sleep request).
//!
//! Codes: D = GAIN * (VIN - 1.65 V) / 1.25 V * 8192, rounded to nearest and clamped to the
//! 14-bit two's-complement range -8192..=8191 (UG334 equation 9-1; GAIN is the signed
//! pre-amplifier gain, -1 .. -100 on the kit since the LTC6912 inverts).
use super::adc_pins::{DataLine, Level, PinTiming};

/// Timing limits of the LTC1407A-1 in ns (VDD = 3 V).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ltc1407aTiming {
    /// tSCK minimum (SCK period).
    pub sck_min_period_ns: f64,
    /// tSCK maximum while converting.
    pub sck_max_period_ns: f64,
    /// t1: minimum SCK high or low time.
    pub sck_min_pulse_ns: f64,
    /// t2: CONV rise to SCK rise set-up.
    pub conv_to_sck_ns: f64,
    /// t4: minimum CONV high time.
    pub conv_min_high_ns: f64,
    /// Minimum CONV low time (kept above 15 ns by the datasheet's advice).
    pub conv_min_low_ns: f64,
    /// t7: 32nd SCK rise to the next CONV rise (acquisition).
    pub acquisition_ns: f64,
    /// t8: SCK rise to valid SDO.
    pub sdo_valid_ns: f64,
    /// t10: previous SDO bit held after SCK rise.
    pub sdo_hold_ns: f64,
    /// SCK rising edges per conversion.
    pub conversion_edges: u32,
}

impl Ltc1407aTiming {
    /// Datasheet values.
    pub const DATASHEET: Ltc1407aTiming = Ltc1407aTiming {
        sck_min_period_ns: 19.6,
        sck_max_period_ns: 10_000.0,
        sck_min_pulse_ns: 2.0,
        conv_to_sck_ns: 3.0,
        conv_min_high_ns: 4.0,
        conv_min_low_ns: 15.0,
        acquisition_ns: 45.0,
        sdo_valid_ns: 8.0,
        sdo_hold_ns: 2.0,
        conversion_edges: 32,
    };
}

/// SDO state.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sdo {
    /// High impedance.
    HiZ,
    /// Driven but not valid (changing, or data of no completed conversion).
    Undefined,
    /// A valid data bit.
    Bit(bool),
}

/// Kinds of protocol violations.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViolationKind {
    /// SCK period below tSCK minimum.
    SckTooFast,
    /// SCK period above the maximum during a conversion (conversion corrupted).
    SckTooSlow,
    /// SCK high or low time below t1.
    SckPulseTooShort,
    /// CONV high time below t4.
    ConvPulseTooShort,
    /// CONV low time too short.
    ConvLowTooShort,
    /// CONV rise to SCK rise below t2.
    ConvToSckSetup,
    /// 32nd SCK rise to CONV rise below t7.
    AcquisitionTooShort,
    /// CONV rose before the running conversion got its 32 SCK edges (ignored by the chip).
    ConvBeforeConversionDone,
    /// Two CONV rises without an SCK rise between them (the chip would nap or sleep).
    NapOrSleep,
}

/// One recorded violation.
#[derive(Clone, Debug, PartialEq)]
pub struct Violation {
    /// System clock index (step count) at which it was seen.
    pub clock: u64,
    /// What was violated.
    pub kind: ViolationKind,
    /// Measured value and limit.
    pub message: String,
}

/// One accepted conversion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Conversion {
    /// Clock index of the CONV rise.
    pub clock: u64,
    /// Codes sampled for channel 0 and channel 1.
    pub codes: [i16; 2],
}

type CodeFn = Box<dyn FnMut(u64, f64) -> [i16; 2]>;

/// The ADC.
pub struct Ltc1407a {
    period_ns: f64,
    timing: Ltc1407aTiming,
    source: Option<CodeFn>,
    clock: u64,
    prev_conv: bool,
    prev_sck: bool,
    last_conv_rise: Option<f64>,
    last_conv_fall: Option<f64>,
    last_sck_rise: Option<f64>,
    last_sck_fall: Option<f64>,
    conv_rises_without_sck: u32,
    converting: bool,
    edges: u32,
    accepted_rise: f64,
    conversion_end: Option<f64>,
    current: [i16; 2],
    corrupted: bool,
    result: Option<[i16; 2]>,
    out_frame: Option<[i16; 2]>,
    frame_edges: u32,
    framed: bool,
    /// SDO at the FPGA's pad.
    line: DataLine,
    /// Seed of the random bits read outside the valid window.
    seed: u64,
    conversions: Vec<Conversion>,
    /// Conversions ever made (the source's index; survives [`Ltc1407a::clear_conversions`]).
    count: u64,
    violations: Vec<Violation>,
}

impl Ltc1407a {
    /// The chip clocked by a controller running at `clock_hz`, with codes 0, 0 until a source
    /// is set (`with_codes`, `with_voltages`), pseudo-random Hi-Z bits from `seed`, the
    /// datasheet timing and the default board pins ([`PinTiming::board_default`]).
    pub fn new(clock_hz: f64, seed: u64) -> Self {
        let period_ns = if clock_hz.is_finite() && clock_hz > 0.0 {
            1e9 / clock_hz
        } else {
            1.0
        };
        Ltc1407a {
            period_ns,
            timing: Ltc1407aTiming::DATASHEET,
            source: None,
            clock: 0,
            prev_conv: false,
            prev_sck: false,
            last_conv_rise: None,
            last_conv_fall: None,
            last_sck_rise: None,
            last_sck_fall: None,
            conv_rises_without_sck: 0,
            converting: false,
            edges: 0,
            accepted_rise: 0.0,
            conversion_end: None,
            current: [0, 0],
            corrupted: false,
            result: None,
            out_frame: None,
            frame_edges: 0,
            framed: false,
            line: DataLine::new(PinTiming::board_default(), seed),
            seed,
            conversions: Vec::new(),
            count: 0,
            violations: Vec::new(),
        }
    }

    /// The pins between the FPGA and the chip (`[board]` budget of the config).
    pub fn with_pins(mut self, pins: PinTiming) -> Self {
        self.line = DataLine::new(pins, self.seed);
        self
    }

    /// Other chip timing (a sweep of t8, a slower part).
    pub fn with_timing(mut self, timing: Ltc1407aTiming) -> Self {
        self.timing = timing;
        self
    }

    /// A fault of SDO at the FPGA's pad (None: none; see `DataLine::stick`).
    pub fn set_sdo_stuck(&mut self, level: Option<bool>) {
        self.line.stick(level);
    }

    /// The chip timing in use.
    pub fn timing(&self) -> Ltc1407aTiming {
        self.timing
    }

    /// Codes for each conversion from `f(conversion index, time of the CONV rise in s)`.
    pub fn with_codes(mut self, f: impl FnMut(u64, f64) -> [i16; 2] + 'static) -> Self {
        self.source = Some(Box::new(f));
        self
    }

    /// Codes from input voltages `f(conversion index, time in s) -> [VINA, VINB]` through
    /// the pre-amplifier gains `gain` (signed, e.g. -1.0).
    pub fn with_voltages(
        mut self,
        gain: [f64; 2],
        mut f: impl FnMut(u64, f64) -> [f64; 2] + 'static,
    ) -> Self {
        self.source = Some(Box::new(move |k, t| {
            let v = f(k, t);
            [
                Self::code_from_voltage(v[0], gain[0]),
                Self::code_from_voltage(v[1], gain[1]),
            ]
        }));
        self
    }

    /// D = gain * (vin - 1.65) / 1.25 * 8192, rounded, clamped to -8192..=8191.
    pub fn code_from_voltage(vin: f64, gain: f64) -> i16 {
        let d = gain * (vin - 1.65) / 1.25 * 8192.0;
        if d.is_nan() {
            return 0;
        }
        clamp14(d.round().clamp(-1e9, 1e9) as i64)
    }

    /// Conversions accepted so far, in order.
    pub fn conversions(&self) -> &[Conversion] {
        &self.conversions
    }

    /// Forgets the conversions so far (a long run keeps no history: the closed loop counts
    /// them as they come).
    pub fn clear_conversions(&mut self) {
        self.conversions.clear();
    }

    /// Violations recorded so far.
    pub fn violations(&self) -> &[Violation] {
        &self.violations
    }

    fn violation(&mut self, kind: ViolationKind, message: String) {
        self.violations.push(Violation {
            clock: self.clock,
            kind,
            message,
        });
    }

    fn slot(&self, edge: u32) -> Sdo {
        let word = |c: usize, bit: u32| match self.out_frame {
            Some(w) => Sdo::Bit((w[c] as u16 >> bit) & 1 == 1),
            None => Sdo::Undefined,
        };
        match edge {
            3..=16 => word(0, 16 - edge),
            19..=32 => word(1, 32 - edge),
            _ => Sdo::HiZ,
        }
    }

    /// One system clock: `conv` and `sck` are the levels the FPGA launches at this clock
    /// edge (they reach the chip clock-to-out + one trace later; the chip's own checks use
    /// differences of these times). Returns what the FPGA reads at `adc_miso` at the next
    /// clock edge.
    pub fn step(&mut self, conv: bool, sck: bool) -> bool {
        let t = self.clock as f64 * self.period_ns;
        let tm = self.timing;
        if conv && !self.prev_conv {
            if let Some(f) = self.last_conv_fall {
                if t - f + 1e-9 < tm.conv_min_low_ns {
                    self.violation(
                        ViolationKind::ConvLowTooShort,
                        format!("CONV low for {:.2} ns < {} ns", t - f, tm.conv_min_low_ns),
                    );
                }
            }
            if self.conv_rises_without_sck >= 1 {
                self.violation(
                    ViolationKind::NapOrSleep,
                    "two CONV rises without an SCK rise between them (nap/sleep request)".into(),
                );
            }
            self.conv_rises_without_sck += 1;
            if self.converting {
                let msg = format!(
                    "CONV rose after {} of {} SCK rising edges: the conversion was not finished (CONV ignored)",
                    self.edges, tm.conversion_edges
                );
                self.violation(ViolationKind::ConvBeforeConversionDone, msg);
            } else {
                if let Some(e) = self.conversion_end {
                    if t - e + 1e-9 < tm.acquisition_ns {
                        self.violation(
                            ViolationKind::AcquisitionTooShort,
                            format!(
                                "{:.2} ns from the last conversion edge to CONV < {} ns",
                                t - e,
                                tm.acquisition_ns
                            ),
                        );
                    }
                }
                let k = self.count;
                self.count += 1;
                let codes = match self.source.as_mut() {
                    Some(f) => {
                        let c = f(k, t * 1e-9);
                        [clamp14(c[0] as i64), clamp14(c[1] as i64)]
                    }
                    None => [0, 0],
                };
                self.conversions.push(Conversion {
                    clock: self.clock,
                    codes,
                });
                self.current = codes;
                self.corrupted = false;
                self.converting = true;
                self.edges = 0;
                self.accepted_rise = t;
                self.out_frame = self.result;
                self.frame_edges = 0;
                self.framed = true;
                self.line
                    .change(t, tm.sdo_hold_ns, tm.sdo_valid_ns, Level::Undefined);
            }
            self.last_conv_rise = Some(t);
        }
        if !conv && self.prev_conv {
            if let Some(r) = self.last_conv_rise {
                if t - r + 1e-9 < tm.conv_min_high_ns {
                    self.violation(
                        ViolationKind::ConvPulseTooShort,
                        format!("CONV high for {:.2} ns < {} ns", t - r, tm.conv_min_high_ns),
                    );
                }
            }
            self.last_conv_fall = Some(t);
        }
        if sck && !self.prev_sck {
            if let Some(r) = self.last_sck_rise {
                if t - r + 1e-9 < tm.sck_min_period_ns {
                    self.violation(
                        ViolationKind::SckTooFast,
                        format!("SCK period {:.2} ns < {} ns", t - r, tm.sck_min_period_ns),
                    );
                }
                if self.converting && self.edges > 0 && t - r > tm.sck_max_period_ns {
                    self.violation(
                        ViolationKind::SckTooSlow,
                        format!(
                            "SCK period {:.1} ns > {} ns during a conversion (data lost)",
                            t - r,
                            tm.sck_max_period_ns
                        ),
                    );
                    self.corrupted = true;
                }
            }
            if let Some(f) = self.last_sck_fall {
                if t - f + 1e-9 < tm.sck_min_pulse_ns {
                    self.violation(
                        ViolationKind::SckPulseTooShort,
                        format!("SCK low for {:.2} ns < {} ns", t - f, tm.sck_min_pulse_ns),
                    );
                }
            }
            if self.converting
                && self.edges == 0
                && t - self.accepted_rise + 1e-9 < tm.conv_to_sck_ns
            {
                self.violation(
                    ViolationKind::ConvToSckSetup,
                    format!(
                        "CONV to SCK rise {:.2} ns < {} ns",
                        t - self.accepted_rise,
                        tm.conv_to_sck_ns
                    ),
                );
            }
            self.conv_rises_without_sck = 0;
            if self.converting {
                self.edges += 1;
                if self.edges >= tm.conversion_edges {
                    self.converting = false;
                    self.conversion_end = Some(t);
                    self.result = if self.corrupted {
                        None
                    } else {
                        Some(self.current)
                    };
                }
            }
            if self.framed {
                self.frame_edges = self.frame_edges.saturating_add(1);
                let level = match self.slot(self.frame_edges) {
                    Sdo::Bit(b) => Level::Bit(b),
                    Sdo::HiZ | Sdo::Undefined => Level::Undefined,
                };
                self.line.change(t, tm.sdo_hold_ns, tm.sdo_valid_ns, level);
            }
            self.last_sck_rise = Some(t);
        }
        if !sck && self.prev_sck {
            if let Some(r) = self.last_sck_rise {
                if t - r + 1e-9 < tm.sck_min_pulse_ns {
                    self.violation(
                        ViolationKind::SckPulseTooShort,
                        format!("SCK high for {:.2} ns < {} ns", t - r, tm.sck_min_pulse_ns),
                    );
                }
            }
            self.last_sck_fall = Some(t);
        }
        self.prev_conv = conv;
        self.prev_sck = sck;
        self.clock += 1;
        // The level the FPGA's input register takes at the next clock edge.
        self.line.sample(self.clock as f64 * self.period_ns)
    }
}

fn clamp14(v: i64) -> i16 {
    v.clamp(-8192, 8191) as i16
}
