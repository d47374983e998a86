//! `simulate`'s options ([`SimOptions`]), their limits and checks, and the speed
//! profiles of `--profile`.

use super::*;

/// What to simulate.
#[derive(Clone, Debug)]
pub struct SimOptions {
    /// Speed profile.
    pub profile: Profile,
    /// Simulated time in seconds.
    pub duration_s: f64,
    /// Track amplitude as a fraction of the ADC's input range (1.25 V): 0.8 = 1.0 V.
    pub amplitude: f64,
    /// Gaussian noise RMS in ADC LSB.
    pub noise_lsb: f64,
    /// Offsets of the sin and cos tracks as fractions of the amplitude.
    pub offset: (f64, f64),
    /// Relative gain mismatch between the tracks.
    pub gain_mismatch: f64,
    /// Quadrature phase error in degrees.
    pub phase_error_deg: f64,
    /// Second-harmonic ratio of both tracks' waveform (`sim::encoder`'s signal model).
    pub second_harmonic: f64,
    /// Third-harmonic ratio.
    pub third_harmonic: f64,
    /// Fifth-harmonic ratio.
    pub fifth_harmonic: f64,
    /// Phases of the 2nd, 3rd and 5th harmonics, degrees.
    pub harmonic_phase_deg: [f64; 3],
    /// Eccentricity of the scale, arc-seconds: a once-per-turn angle error.
    pub eccentricity_arcsec: f64,
    /// Simulated seconds before the statistics start (`--settle`): the decoded samples
    /// that leave the top earlier are not counted.
    pub settle_s: f64,
    /// Noise seed.
    pub seed: u64,
    /// Record every cycle's pins (for a VCD).
    pub record: bool,
    /// Engine of the top: the compiled engine (the default; `crate::engine`, with the
    /// fallbacks of `crate::sim::dut`), its interpreter, or rust-hdl (the reference).
    pub engine: crate::sim::dut::EngineKind,
    /// Keep every decoded sample (for [`SimReport::csv`]); without them the statistics are
    /// gathered as the samples come and memory stays bounded however long the run.
    pub keep_records: bool,
    /// Decoded samples skipped before the statistics (settling: the monitor reports a
    /// loss of signal until its window of good samples has passed after reset).
    pub skip: usize,
    /// Rate of the pulses on `capture` (`[capture] enabled`; [`CAPTURE_PULSE_S`] wide,
    /// the first one period after the start); None: [`DEFAULT_CAPTURE_HZ`] with
    /// `[capture]`, none without.
    pub capture_hz: Option<f64>,
    /// Faults injected (`--fault`, [`FaultSpec`]), each kind at most once.
    pub faults: Vec<FaultSpec>,
}

/// `--capture-hz` when not given: a common PWM frequency.
pub const DEFAULT_CAPTURE_HZ: f64 = 20_000.0;

/// Width of each `capture` pulse of `simulate`, seconds.
pub const CAPTURE_PULSE_S: f64 = 1e-6;

/// Highest `--capture-hz`: 100 kHz, far above PWM rates (the pulses are listed up front:
/// 10 s at 100 kHz is a million).
pub const MAX_CAPTURE_HZ: f64 = 100_000.0;

impl Default for SimOptions {
    fn default() -> Self {
        SimOptions {
            profile: Profile::Constant { rpm: 300.0 },
            duration_s: 0.002,
            amplitude: 0.8,
            noise_lsb: 0.0,
            offset: (0.0, 0.0),
            gain_mismatch: 0.0,
            phase_error_deg: 0.0,
            second_harmonic: 0.0,
            third_harmonic: 0.0,
            fifth_harmonic: 0.0,
            harmonic_phase_deg: [0.0; 3],
            eccentricity_arcsec: 0.0,
            settle_s: 0.0,
            seed: 1,
            record: false,
            engine: Default::default(),
            keep_records: true,
            skip: 12,
            capture_hz: None,
            faults: Vec::new(),
        }
    }
}

/// Largest speed `simulate` accepts, rpm (either direction): far above any servo motor
/// (16,667 turns per second) and small enough that the angle stays exact in f64.
pub const MAX_RPM: f64 = 1.0e6;

/// Largest simulated time, seconds.
pub const MAX_DURATION_S: f64 = 10.0;

/// Largest |`--eccentricity`|, arc-seconds (one degree: far beyond a mounted scale's
/// tens of arc-seconds).
pub const MAX_ECCENTRICITY_ARCSEC: f64 = 3600.0;

impl SimOptions {
    /// Rejects meaningless options before anything runs; errors name the command-line
    /// option and its allowed range. `capacitive`: the capacitive path, whose encoder model
    /// has one receiver signal (no sin/cos tracks): the track imperfections do not apply.
    pub fn validate(&self, capacitive: bool) -> Result<()> {
        let bad = |opt: &str, v: f64, allowed: &str| {
            Err(Error::option(opt, format!("{v}: allowed {allowed}")))
        };
        let speed = |v: f64, what: &str| -> Result<()> {
            if v.is_finite() && v.abs() <= MAX_RPM {
                Ok(())
            } else {
                Err(Error::option(
                    "--profile",
                    format!("{what} {v} rpm: allowed a finite speed within -{MAX_RPM:.0}..={MAX_RPM:.0} rpm"),
                ))
            }
        };
        let time = |v: f64, what: &str, zero_ok: bool| -> Result<()> {
            if v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0)) && v <= 1e3 {
                Ok(())
            } else {
                Err(Error::option(
                    "--profile",
                    format!(
                        "{what} {v} s: allowed {} seconds up to 1000",
                        if zero_ok { "0 <=" } else { "0 <" }
                    ),
                ))
            }
        };
        match self.profile {
            Profile::Constant { rpm } => speed(rpm, "speed")?,
            Profile::Ramp { from, to, over } => {
                speed(from, "start speed")?;
                speed(to, "end speed")?;
                time(over, "ramp time", false)?;
            }
            Profile::Reversal { rpm, at, over } => {
                speed(rpm, "speed")?;
                time(at, "reversal start", true)?;
                time(over, "reversal time", false)?;
            }
        }
        if !(self.duration_s > 0.0 && self.duration_s <= MAX_DURATION_S) {
            return bad("--duration", self.duration_s, "0 < seconds <= 10");
        }
        if !(self.amplitude > 0.0 && self.amplitude <= 1.0) {
            return bad(
                "--amplitude",
                self.amplitude,
                "0 < amplitude <= 1 (fraction of the ADC's input range)",
            );
        }
        if !(self.noise_lsb >= 0.0 && self.noise_lsb <= 1e4) {
            return bad("--noise-lsb", self.noise_lsb, "0..=10000 LSB RMS");
        }
        let track = [
            (
                "--offset-sin",
                self.offset.0,
                1.0,
                "-1..=1 (fraction of the amplitude)",
            ),
            (
                "--offset-cos",
                self.offset.1,
                1.0,
                "-1..=1 (fraction of the amplitude)",
            ),
            (
                "--gain-mismatch",
                self.gain_mismatch,
                1.0,
                "-1..=1 (relative)",
            ),
            (
                "--phase-error",
                self.phase_error_deg,
                45.0,
                "-45..=45 degrees",
            ),
            (
                "--harmonic2",
                self.second_harmonic,
                0.5,
                "-0.5..=0.5 (ratio)",
            ),
            (
                "--harmonic3",
                self.third_harmonic,
                0.5,
                "-0.5..=0.5 (ratio)",
            ),
            (
                "--harmonic5",
                self.fifth_harmonic,
                0.5,
                "-0.5..=0.5 (ratio)",
            ),
            (
                "--harmonic2-phase",
                self.harmonic_phase_deg[0],
                360.0,
                "-360..=360 degrees",
            ),
            (
                "--harmonic3-phase",
                self.harmonic_phase_deg[1],
                360.0,
                "-360..=360 degrees",
            ),
            (
                "--harmonic5-phase",
                self.harmonic_phase_deg[2],
                360.0,
                "-360..=360 degrees",
            ),
            (
                "--eccentricity",
                self.eccentricity_arcsec,
                MAX_ECCENTRICITY_ARCSEC,
                "-3600..=3600 arc-seconds",
            ),
        ];
        if !(self.settle_s.is_finite() && self.settle_s >= 0.0) {
            return bad("--settle", self.settle_s, "0 <= seconds < --duration");
        }
        if self.settle_s >= self.duration_s {
            return Err(Error::option(
                "--settle",
                format!(
                    "{} s: leaves no sample of the {} s run; allowed 0 <= seconds < --duration",
                    self.settle_s, self.duration_s
                ),
            ));
        }
        if let Some(hz) = self.capture_hz {
            if !(hz.is_finite() && hz > 0.0 && hz <= MAX_CAPTURE_HZ) {
                return bad(
                    "--capture-hz",
                    hz,
                    &format!("0 < Hz <= {MAX_CAPTURE_HZ:.0} (1 us pulses)"),
                );
            }
        }
        validate_faults(&self.faults, self.duration_s)?;
        if capacitive && !self.faults.is_empty() {
            return Err(Error::option(
                "--fault",
                "does not apply to the capacitive path (its faults are the sinewave path's: tracks, comparators, index, SPI ADC frame); remove it",
            ));
        }
        for (opt, v, lim, allowed) in track {
            if v.is_nan() || v.abs() > lim {
                return bad(opt, v, allowed);
            }
            if capacitive && v != 0.0 {
                return Err(Error::option(
                    opt,
                    format!("{v}: does not apply to the capacitive path (its encoder model has one receiver signal, no sin/cos tracks); leave it at 0"),
                ));
            }
        }
        Ok(())
    }
}

/// Parses a profile: `constant:RPM`, `ramp:FROM:TO:SECONDS`, `reversal:RPM:AT_S:OVER_S`,
/// or `creep` (0.3 rpm).
pub fn parse_profile(s: &str) -> Result<Profile> {
    let parts: Vec<&str> = s.split(':').collect();
    let bad = |m: String| Error::option("--profile", m);
    let num = |i: usize| -> Result<f64> {
        parts
            .get(i)
            .ok_or_else(|| bad(format!("`{s}`: missing field {i}")))?
            .parse::<f64>()
            .map_err(|e| bad(format!("`{s}`: field {i}: {e}")))
    };
    let p = match parts[0] {
        "constant" if parts.len() == 2 => Profile::Constant { rpm: num(1)? },
        "ramp" if parts.len() == 4 => Profile::Ramp {
            from: num(1)?,
            to: num(2)?,
            over: num(3)?,
        },
        "reversal" if parts.len() == 4 => Profile::Reversal {
            rpm: num(1)?,
            at: num(2)?,
            over: num(3)?,
        },
        "creep" if parts.len() == 1 => Profile::creep(),
        _ => {
            return Err(bad(format!(
                "`{s}`: allowed constant:RPM, ramp:FROM:TO:SECONDS, reversal:RPM:AT_S:OVER_S, creep"
            )))
        }
    };
    Ok(p)
}
