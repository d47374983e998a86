//! Model of a capacitive encoder with carrier excitation (docs/capacitive.md), independent of the RTL:
//! the two excitation DAC words in, one received signal sampled by a signed 16-bit ADC out.
//!
//! ```text
//!  exc_sin ─►[DAC]─ v_s ─┐
//!  exc_cos ─►[DAC]─ v_c ─┤   rotor angle theta_e = periods_per_turn * 2 pi * turns(t)
//!                        ▼
//!  r = g [ (1 + m cos(h theta_e + phi_m)) (cos(theta_e) v_s + sin(theta_e) v_c)
//!          + f v_s ] + n(t)
//!  code = clamp(round(r / V_adc * 2^15), -2^15, 2^15 - 1)
//! ```
//! * DAC: an ideal bipolar converter of `dac_bits`: a word w (clamped to the signed
//!   `dac_bits` range) gives `v = w / 2^(dac_bits-1) * dac_full_scale_v` volts, held (the
//!   caller passes the words present at the sample instant; the model has no memory).
//! * With v_s = V sin(wt) and v_c = V cos(wt): r = g V sin(wt + theta_e), the paper's
//!   modulated signal.
//! * g: coupling gain (received volts per excitation volt).
//! * Amplitude ripple: relative depth m at harmonic h of the electrical angle, phase phi_m.
//! * Carrier feed-through: a fraction f of the sin excitation reaches the receiver
//!   directly (scaled by g like the signal, so f is relative to the signal amplitude).
//! * n: white Gaussian noise of `noise_rms_v` volts RMS (Box-Muller on SplitMix64, one
//!   draw per sample; deterministic for a seed).
//! * ADC: code = round half away from zero of r / adc_full_scale_v * 2^15, saturated to
//!   -32768..=32767 (the paper's 16-bit ADC); saturations are counted.
//!
//! The rotor angle comes from [`Profile`] (the sinewave encoder's speed profiles, closed
//! forms, no drift), so the true angle at each sample is exact.
use crate::cosim::stimulus::SplitMix64;
use crate::sim::encoder::Profile;
use std::f64::consts::TAU;

/// Parameters of [`CapEncoder`].
#[derive(Clone, Debug, PartialEq)]
pub struct CapParams {
    /// Signal periods per mechanical turn (16 in the paper).
    pub periods_per_turn: u32,
    /// Mechanical angle at t = 0, turns.
    pub start_turns: f64,
    /// Speed profile.
    pub profile: Profile,
    /// Width of the signed excitation DAC words, 2..=32 bits (16 in the paper).
    pub dac_bits: u32,
    /// DAC output in volts for the word 2^(dac_bits-1) (the gain: V per full scale).
    pub dac_full_scale_v: f64,
    /// Coupling gain g from excitation volts to received volts.
    pub coupling: f64,
    /// Amplitude ripple depth m (fraction of the amplitude), 0 for none.
    pub ripple: f64,
    /// Harmonic h of the electrical angle at which the amplitude ripples.
    pub ripple_harmonic: u32,
    /// Phase phi_m of the ripple, radians.
    pub ripple_phase: f64,
    /// Carrier feed-through f: fraction of v_sin added to the received signal.
    pub feedthrough: f64,
    /// RMS of the white Gaussian noise at the ADC input, volts.
    pub noise_rms_v: f64,
    /// ADC input in volts that maps to code 2^15 (full scale).
    pub adc_full_scale_v: f64,
    /// Noise generator seed.
    pub seed: u64,
}

impl CapParams {
    /// An ideal encoder: `periods_per_turn`, constant `rpm`, 16-bit DAC of 1 V full scale,
    /// coupling 0.8 into a 1 V ADC (full-scale excitation reaches 80% of the ADC range),
    /// no ripple, feed-through or noise.
    pub fn ideal(periods_per_turn: u32, rpm: f64) -> CapParams {
        CapParams {
            periods_per_turn,
            start_turns: 0.0,
            profile: Profile::Constant { rpm },
            dac_bits: 16,
            dac_full_scale_v: 1.0,
            coupling: 0.8,
            ripple: 0.0,
            ripple_harmonic: 1,
            ripple_phase: 0.0,
            feedthrough: 0.0,
            noise_rms_v: 0.0,
            adc_full_scale_v: 1.0,
            seed: 1,
        }
    }

    /// The paper's set-up: 16 periods per turn at 800 rpm.
    pub fn paper() -> CapParams {
        Self::ideal(16, 800.0)
    }

    /// Checks the values.
    pub fn validate(&self) -> crate::error::Result<()> {
        let fin = |v: f64| v.is_finite();
        if self.periods_per_turn == 0 {
            return Err(model_err("periods_per_turn must be at least 1".into()));
        }
        if !(2..=32).contains(&self.dac_bits) {
            return Err(model_err(format!(
                "DAC width {} bits out of range: 2..=32",
                self.dac_bits
            )));
        }
        for (name, v) in [
            ("dac_full_scale_v", self.dac_full_scale_v),
            ("adc_full_scale_v", self.adc_full_scale_v),
        ] {
            if !(fin(v) && v > 0.0) {
                return Err(model_err(format!(
                    "{name} = {v} must be a positive voltage"
                )));
            }
        }
        if !(fin(self.coupling) && self.coupling > 0.0) {
            return Err(model_err(format!(
                "coupling {} must be positive",
                self.coupling
            )));
        }
        if !(fin(self.ripple) && (0.0..1.0).contains(&self.ripple)) {
            return Err(model_err(format!(
                "ripple {} out of range: 0..1",
                self.ripple
            )));
        }
        if !(fin(self.feedthrough) && self.feedthrough.abs() < 1.0) {
            return Err(model_err(format!(
                "feed-through {} out of range: |f| < 1",
                self.feedthrough
            )));
        }
        if !(fin(self.noise_rms_v) && self.noise_rms_v >= 0.0) {
            return Err(model_err(format!(
                "noise RMS {} V must be >= 0",
                self.noise_rms_v
            )));
        }
        if !(fin(self.start_turns) && fin(self.ripple_phase)) {
            return Err(model_err(
                "start_turns and ripple_phase must be finite".into(),
            ));
        }
        Ok(())
    }
}

/// [`crate::error::Error::ModelParams`] of the capacitive encoder.
fn model_err(message: String) -> crate::error::Error {
    crate::error::Error::ModelParams {
        model: "capacitive encoder".into(),
        message,
    }
}

/// The encoder with its noise generator and saturation count.
#[derive(Clone, Debug)]
pub struct CapEncoder {
    p: CapParams,
    rng: SplitMix64,
    saturations: u64,
}

/// Most positive code of the 16-bit ADC.
pub const ADC_MAX: i64 = 32767;
/// Most negative code of the 16-bit ADC.
pub const ADC_MIN: i64 = -32768;

impl CapEncoder {
    /// Encoder for checked parameters.
    pub fn new(p: CapParams) -> crate::error::Result<CapEncoder> {
        p.validate()?;
        Ok(CapEncoder {
            rng: SplitMix64(p.seed),
            p,
            saturations: 0,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &CapParams {
        &self.p
    }

    /// Mechanical angle at `t_s`, radians, unwrapped (0 at t = 0 when start_turns = 0).
    pub fn mech_angle(&self, t_s: f64) -> f64 {
        (self.p.start_turns + self.p.profile.turns(t_s)) * TAU
    }

    /// True electrical angle theta_e = periods_per_turn * mechanical angle at `t_s`,
    /// radians, unwrapped.
    pub fn true_angle(&self, t_s: f64) -> f64 {
        self.mech_angle(t_s) * self.p.periods_per_turn as f64
    }

    /// DAC output voltage for a word (clamped to the signed `dac_bits` range).
    pub fn dac_volts(&self, word: i64) -> f64 {
        let half = 1i64 << (self.p.dac_bits - 1).min(62);
        let w = word.clamp(-half, half - 1);
        w as f64 / half as f64 * self.p.dac_full_scale_v
    }

    /// Received voltage at `t_s` for the given DAC words, without noise.
    pub fn clean_volts(&self, t_s: f64, exc_sin: i64, exc_cos: i64) -> f64 {
        let p = &self.p;
        let th = self.true_angle(t_s);
        let (vs, vc) = (self.dac_volts(exc_sin), self.dac_volts(exc_cos));
        let amp = 1.0 + p.ripple * (p.ripple_harmonic as f64 * th + p.ripple_phase).cos();
        p.coupling * (amp * (th.cos() * vs + th.sin() * vc) + p.feedthrough * vs)
    }

    fn gauss(&mut self) -> f64 {
        let u1 = self.rng.unit().max(1e-300);
        let u2 = self.rng.unit();
        (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
    }

    /// Received voltage at `t_s` with a fresh noise draw.
    pub fn volts(&mut self, t_s: f64, exc_sin: i64, exc_cos: i64) -> f64 {
        let n = if self.p.noise_rms_v > 0.0 {
            self.p.noise_rms_v * self.gauss()
        } else {
            0.0
        };
        self.clean_volts(t_s, exc_sin, exc_cos) + n
    }

    /// The 16-bit ADC code of a voltage (round half away from zero, saturated).
    pub fn quantize(&mut self, v: f64) -> i16 {
        let x = (v / self.p.adc_full_scale_v * 32768.0).round();
        if x > ADC_MAX as f64 || x < ADC_MIN as f64 {
            self.saturations += 1;
        }
        x.clamp(ADC_MIN as f64, ADC_MAX as f64) as i16
    }

    /// One ADC sample at `t_s` with the excitation DAC words `exc_sin`, `exc_cos` present.
    pub fn sample(&mut self, t_s: f64, exc_sin: i64, exc_cos: i64) -> i16 {
        let v = self.volts(t_s, exc_sin, exc_cos);
        self.quantize(v)
    }

    /// Samples that hit the ADC's range limits so far.
    pub fn saturations(&self) -> u64 {
        self.saturations
    }
}
