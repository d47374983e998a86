//! Pin-level model of the LTC6912-1 dual programmable-gain amplifier's serial interface,
//! written from its datasheet and UG334 (Spartan-3A/3AN Starter Kit), independently of the
//! set-up block in `blocks::preamp`.
//!
//! * While CS/LD is low, DIN is shifted into an 8-bit shift register on each rising SCK
//!   edge, MSB first. The rising CS/LD edge latches the register: the upper nibble sets
//!   amplifier B, the lower nibble amplifier A.
//! * Codes: 0 = gain 0 (input disconnected), 1..=7 = -1, -2, -5, -10, -20, -50, -100
//!   (inverting), 8..=12 = software shutdown, 13..=15 not used (15 draws up to 20 mA).
//! * Malformed transfers are flagged: a count of SCK rising edges other than 8 between the
//!   CS fall and rise, SCK high when CS falls (an extra internal clock pulse), a shutdown
//!   or unused code, AMP_SHDN high during a transfer.
//! * Timing (UG334 Figure 9-4, all minimum): SCK high and low >= 50 ns, CS fall to SCK
//!   rise >= 30 ns, DIN set-up before SCK rise >= 30 ns, DIN hold after SCK rise >= 10 ns
//!   (assumed), last SCK rise to CS rise >= 30 ns.

/// Timing limits in ns (kept here, apart from the set-up block's, so the model is an
/// independent check).
pub mod timing {
    /// SCK high and low minimum.
    pub const SCK_MIN_PULSE_NS: f64 = 50.0;
    /// CS/LD fall to SCK rise.
    pub const CS_SETUP_NS: f64 = 30.0;
    /// DIN set-up before SCK rise.
    pub const DATA_SETUP_NS: f64 = 30.0;
    /// DIN hold after SCK rise (assumed).
    pub const DATA_HOLD_NS: f64 = 10.0;
    /// Last SCK rise to CS/LD rise.
    pub const CS_HOLD_NS: f64 = 30.0;
}

/// LTC6912-1 gain of a 4-bit code (datasheet Table 1): None for the shutdown and unused
/// states 8..=15.
pub fn code_gain(code: u8) -> Option<i32> {
    match code {
        0 => Some(0),
        1 => Some(-1),
        2 => Some(-2),
        3 => Some(-5),
        4 => Some(-10),
        5 => Some(-20),
        6 => Some(-50),
        7 => Some(-100),
        _ => None,
    }
}

/// One completed transfer (CS low then high).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AmpTransfer {
    /// System clock index of the CS rise.
    pub clock: u64,
    /// Rising SCK edges seen while CS was low.
    pub bits: u32,
    /// The latched word (B nibble high).
    pub word: u8,
    /// Gain of amplifier A (None: shutdown/unused code).
    pub gain_a: Option<i32>,
    /// Gain of amplifier B.
    pub gain_b: Option<i32>,
    /// Exactly 8 bits, valid codes, no timing violation during the transfer.
    pub well_formed: bool,
}

/// One recorded violation.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AmpViolation {
    /// System clock index.
    pub clock: u64,
    /// Description with the measured value and the limit.
    pub message: String,
}

/// The amplifier's serial interface.
pub struct Ltc6912 {
    period_ns: f64,
    clock: u64,
    prev_cs: bool,
    prev_sck: bool,
    prev_mosi: bool,
    last_mosi_change: f64,
    last_sck_rise: Option<f64>,
    last_sck_fall: Option<f64>,
    cs_fall: f64,
    in_transfer: bool,
    shift: u8,
    bits: u32,
    transfer_ok: bool,
    latch: Option<u8>,
    transfers: Vec<AmpTransfer>,
    violations: Vec<AmpViolation>,
}

impl Ltc6912 {
    /// The amplifier seen from a controller running at `clock_hz` (CS idle high).
    pub fn new(clock_hz: f64) -> Self {
        let period_ns = if clock_hz.is_finite() && clock_hz > 0.0 {
            1e9 / clock_hz
        } else {
            1.0
        };
        Ltc6912 {
            period_ns,
            clock: 0,
            prev_cs: true,
            prev_sck: false,
            prev_mosi: false,
            last_mosi_change: f64::NEG_INFINITY,
            last_sck_rise: None,
            last_sck_fall: None,
            cs_fall: 0.0,
            in_transfer: false,
            shift: 0,
            bits: 0,
            transfer_ok: true,
            latch: None,
            transfers: Vec::new(),
            violations: Vec::new(),
        }
    }

    fn violation(&mut self, message: String) {
        if self.in_transfer {
            self.transfer_ok = false;
        }
        self.violations.push(AmpViolation {
            clock: self.clock,
            message,
        });
    }

    /// One system clock with the pin levels driven from this clock edge on.
    pub fn step(&mut self, cs: bool, sck: bool, mosi: bool, shdn: bool) {
        let t = self.clock as f64 * self.period_ns;
        if mosi != self.prev_mosi {
            if self.in_transfer && !cs {
                if let Some(r) = self.last_sck_rise {
                    if r >= self.cs_fall && t - r + 1e-9 < timing::DATA_HOLD_NS {
                        self.violation(format!(
                            "DIN changed {:.1} ns after SCK rose (hold {} ns)",
                            t - r,
                            timing::DATA_HOLD_NS
                        ));
                    }
                }
            }
            self.last_mosi_change = t;
        }
        if !cs && self.prev_cs {
            self.in_transfer = true;
            self.transfer_ok = true;
            self.bits = 0;
            self.cs_fall = t;
            if sck {
                self.violation(
                    "SCK high when CS/LD fell: an extra clock pulse is shifted in".into(),
                );
            }
        }
        if !cs && shdn {
            self.violation("AMP_SHDN high while CS/LD is low (hardware shutdown)".into());
        }
        if sck && !self.prev_sck && !cs {
            if self.bits == 0 && t - self.cs_fall + 1e-9 < timing::CS_SETUP_NS {
                self.violation(format!(
                    "CS/LD fall to SCK rise {:.1} ns < {} ns",
                    t - self.cs_fall,
                    timing::CS_SETUP_NS
                ));
            }
            if t - self.last_mosi_change + 1e-9 < timing::DATA_SETUP_NS {
                self.violation(format!(
                    "DIN set-up {:.1} ns < {} ns",
                    t - self.last_mosi_change,
                    timing::DATA_SETUP_NS
                ));
            }
            if let Some(f) = self.last_sck_fall {
                if f >= self.cs_fall && t - f + 1e-9 < timing::SCK_MIN_PULSE_NS {
                    self.violation(format!(
                        "SCK low {:.1} ns < {} ns",
                        t - f,
                        timing::SCK_MIN_PULSE_NS
                    ));
                }
            }
            self.shift = (self.shift << 1) | mosi as u8;
            self.bits += 1;
        }
        if sck && !self.prev_sck {
            self.last_sck_rise = Some(t);
        }
        if !sck && self.prev_sck {
            if !cs {
                if let Some(r) = self.last_sck_rise {
                    if t - r + 1e-9 < timing::SCK_MIN_PULSE_NS {
                        self.violation(format!(
                            "SCK high {:.1} ns < {} ns",
                            t - r,
                            timing::SCK_MIN_PULSE_NS
                        ));
                    }
                }
            }
            self.last_sck_fall = Some(t);
        }
        if cs && !self.prev_cs && self.in_transfer {
            if let Some(r) = self.last_sck_rise {
                if r >= self.cs_fall && t - r + 1e-9 < timing::CS_HOLD_NS {
                    self.violation(format!(
                        "SCK rise to CS/LD rise {:.1} ns < {} ns",
                        t - r,
                        timing::CS_HOLD_NS
                    ));
                }
            }
            if self.bits != 8 {
                self.violation(format!(
                    "{} SCK rising edges while CS/LD was low, not 8",
                    self.bits
                ));
            }
            let word = self.shift;
            let (gain_a, gain_b) = (code_gain(word & 0xf), code_gain(word >> 4));
            for (name, code, g) in [("A", word & 0xf, gain_a), ("B", word >> 4, gain_b)] {
                if g.is_none() {
                    let what = if code >= 13 { "unused" } else { "shutdown" };
                    self.violation(format!("amplifier {name} code {code} is a {what} state"));
                }
            }
            self.latch = Some(word);
            self.transfers.push(AmpTransfer {
                clock: self.clock,
                bits: self.bits,
                word,
                gain_a,
                gain_b,
                well_formed: self.transfer_ok,
            });
            self.in_transfer = false;
        }
        self.prev_cs = cs;
        self.prev_sck = sck;
        self.prev_mosi = mosi;
        self.clock += 1;
    }

    /// Latched gains (A, B) after the last transfer; None before any transfer or when a
    /// channel is in a shutdown state.
    pub fn gains(&self) -> Option<(i32, i32)> {
        let w = self.latch?;
        Some((code_gain(w & 0xf)?, code_gain(w >> 4)?))
    }

    /// Completed transfers.
    pub fn transfers(&self) -> &[AmpTransfer] {
        &self.transfers
    }

    /// Violations so far.
    pub fn violations(&self) -> &[AmpViolation] {
        &self.violations
    }
}
