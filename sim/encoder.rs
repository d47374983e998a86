//! Model of a sine/cosine (sinewave) incremental encoder: the analog sin and cos track
//! voltages as a function of time, with the imperfections real encoders have, and the
//! speed profiles of the tests (constant, ramp, reversal, creep).
//!
//! Signal model (per track, angle theta = PPR * mechanical angle):
//! ```text
//! v_sin(t) = Vc + off_s + A (1 + g/2) [ sin(theta)         + h3 sin(3 theta) ] + n_s(t)
//! v_cos(t) = Vc + off_c + A (1 - g/2) [ cos(theta + phi)   + h3 cos(3 theta) ] + n_c(t)
//! ```
//! A: amplitude (V), Vc: common-mode (V), off: offsets (V), g: relative gain mismatch,
//! phi: quadrature phase error (rad), h3: third-harmonic ratio, n: white Gaussian noise of
//! the given RMS (Box-Muller on SplitMix64, deterministic per seed).
//!
//! The mechanical angle is integrated exactly from the speed profile (closed forms), so the
//! "true angle" against which the decoder is judged has no numerical drift.
use crate::cosim::stimulus::SplitMix64;
use std::f64::consts::TAU;

/// Speed profiles, speeds in rpm, times in seconds.
#[derive(Clone, Debug, PartialEq)]
pub enum Profile {
    /// Constant speed.
    Constant {
        /// Speed in rpm (sign = direction).
        rpm: f64,
    },
    /// Linear ramp from `from` to `to` rpm over `over` seconds, then constant.
    Ramp {
        /// Start speed.
        from: f64,
        /// End speed.
        to: f64,
        /// Ramp duration.
        over: f64,
    },
    /// `rpm` until `at`, then a linear reversal to `-rpm` within `over` seconds.
    Reversal {
        /// Speed before the reversal.
        rpm: f64,
        /// Start of the reversal.
        at: f64,
        /// Duration of the reversal.
        over: f64,
    },
}

impl Profile {
    /// The thesis's creep test: 0.3 rpm.
    pub fn creep() -> Profile {
        Profile::Constant { rpm: 0.3 }
    }

    /// Mechanical angle in turns at time t (from 0 at t = 0).
    pub fn turns(&self, t: f64) -> f64 {
        let rps = |rpm: f64| rpm / 60.0;
        match *self {
            Profile::Constant { rpm } => rps(rpm) * t,
            Profile::Ramp { from, to, over } => {
                if t <= over {
                    rps(from) * t + 0.5 * rps(to - from) / over * t * t
                } else {
                    rps(from + to) * 0.5 * over + rps(to) * (t - over)
                }
            }
            Profile::Reversal { rpm, at, over } => {
                if t <= at {
                    rps(rpm) * t
                } else if t <= at + over {
                    let u = t - at;
                    rps(rpm) * at + rps(rpm) * u - rps(rpm) / over * u * u
                } else {
                    rps(rpm) * at + 0.0 - rps(rpm) * (t - at - over)
                }
            }
        }
    }

    /// Speed in rpm at time t.
    pub fn rpm(&self, t: f64) -> f64 {
        match *self {
            Profile::Constant { rpm } => rpm,
            Profile::Ramp { from, to, over } => {
                if t <= over {
                    from + (to - from) * t / over
                } else {
                    to
                }
            }
            Profile::Reversal { rpm, at, over } => {
                if t <= at {
                    rpm
                } else if t <= at + over {
                    rpm * (1.0 - 2.0 * (t - at) / over)
                } else {
                    -rpm
                }
            }
        }
    }
}

/// A fault of the analog tracks, from `from` to `to` seconds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TrackFault {
    /// The amplitude multiplied by `factor` (below 1: a dirty scale, loss of signal; above
    /// the ADC's range: clipping).
    Amplitude {
        /// Start, seconds.
        from: f64,
        /// End, seconds.
        to: f64,
        /// Amplitude factor.
        factor: f64,
    },
    /// The sin track's wire broken: the ADC's input reads 0 V (pulled to ground), the cos
    /// track unchanged.
    SinAtZero {
        /// Start, seconds.
        from: f64,
        /// End, seconds.
        to: f64,
    },
}

/// Encoder parameters.
#[derive(Clone, Debug)]
pub struct EncoderModel {
    /// Signal periods per turn.
    pub ppr: u32,
    /// Amplitude A of each track, volts.
    pub amplitude: f64,
    /// Common-mode voltage Vc, volts (1.65 V for the kit's ADC reference).
    pub common_mode: f64,
    /// Offset of the sin track, volts.
    pub offset_sin: f64,
    /// Offset of the cos track, volts.
    pub offset_cos: f64,
    /// Relative gain mismatch g (sin gets 1 + g/2, cos 1 - g/2).
    pub gain_mismatch: f64,
    /// Quadrature phase error phi, radians.
    pub phase_error: f64,
    /// Third-harmonic ratio h3.
    pub third_harmonic: f64,
    /// RMS of the white Gaussian noise on each track, volts.
    pub noise_rms: f64,
    /// Mechanical angle at t = 0, turns.
    pub start_turns: f64,
    /// Speed profile.
    pub profile: Profile,
    /// Amplitude fault: from `.0` to `.1` seconds the amplitude is multiplied by `.2`
    /// (loss of signal, e.g. a dirty scale).
    pub fault: Option<(f64, f64, f64)>,
    /// More faults of the tracks (`simulate --fault`), each in its time window.
    pub track_faults: Vec<TrackFault>,
    /// A speed excursion: from `.0` to `.1` seconds the encoder turns at `.2` rpm instead of
    /// its profile's speed, the angle continuous (e.g. above the decoder's unwrap limit).
    pub excursion: Option<(f64, f64, f64)>,
    rng: SplitMix64,
}

impl EncoderModel {
    /// An ideal encoder: `ppr` periods, amplitude `amplitude` V around 1.65 V, constant speed.
    pub fn ideal(ppr: u32, amplitude: f64, rpm: f64) -> EncoderModel {
        EncoderModel {
            ppr,
            amplitude,
            common_mode: 1.65,
            offset_sin: 0.0,
            offset_cos: 0.0,
            gain_mismatch: 0.0,
            phase_error: 0.0,
            third_harmonic: 0.0,
            noise_rms: 0.0,
            start_turns: 0.0,
            profile: Profile::Constant { rpm },
            fault: None,
            track_faults: Vec::new(),
            excursion: None,
            rng: SplitMix64(1),
        }
    }

    /// Sets the noise generator's seed.
    pub fn with_seed(mut self, seed: u64) -> EncoderModel {
        self.rng = SplitMix64(seed);
        self
    }

    /// Mechanical angle in turns at time t (the profile's, with the speed excursion).
    pub fn turns(&self, t: f64) -> f64 {
        let p = &self.profile;
        let base = match self.excursion {
            Some((a, b, rpm)) if t > a => {
                let tb = t.min(b);
                let after = if t > b { p.turns(t) - p.turns(b) } else { 0.0 };
                p.turns(a) + rpm / 60.0 * (tb - a) + after
            }
            _ => p.turns(t),
        };
        self.start_turns + base
    }

    /// True electrical angle (rad, unwrapped) at time t.
    pub fn electrical_angle(&self, t: f64) -> f64 {
        self.turns(t) * self.ppr as f64 * TAU
    }

    fn gauss(&mut self) -> f64 {
        // Box-Muller.
        let u1 = self.rng.unit().max(1e-300);
        let u2 = self.rng.unit();
        (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
    }

    /// (v_sin, v_cos) in volts at time t, noise drawn fresh on each call.
    pub fn voltages(&mut self, t: f64) -> (f64, f64) {
        let th = self.electrical_angle(t);
        let mut a = match self.fault {
            Some((t0, t1, k)) if t >= t0 && t < t1 => self.amplitude * k,
            _ => self.amplitude,
        };
        let mut sin_broken = false;
        for f in &self.track_faults {
            match *f {
                TrackFault::Amplitude { from, to, factor } if t >= from && t < to => a *= factor,
                TrackFault::SinAtZero { from, to } if t >= from && t < to => sin_broken = true,
                _ => {}
            }
        }
        let g = self.gain_mismatch;
        let h = self.third_harmonic;
        let ns = self.noise_rms * self.gauss();
        let nc = self.noise_rms * self.gauss();
        let s = self.common_mode
            + self.offset_sin
            + a * (1.0 + g / 2.0) * (th.sin() + h * (3.0 * th).sin())
            + ns;
        let c = self.common_mode
            + self.offset_cos
            + a * (1.0 - g / 2.0) * ((th + self.phase_error).cos() + h * (3.0 * th).cos())
            + nc;
        (if sin_broken { 0.0 } else { s }, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn profiles_integrate_their_speed() {
        let ps = [
            Profile::Constant { rpm: 300.0 },
            Profile::Ramp {
                from: 0.0,
                to: 3000.0,
                over: 0.01,
            },
            Profile::Reversal {
                rpm: 600.0,
                at: 0.002,
                over: 0.004,
            },
        ];
        for p in ps {
            // d(turns)/dt == rpm/60 by central differences.
            for k in 1..200 {
                let t = k as f64 * 1e-4;
                let h = 1e-7;
                let d = (p.turns(t + h) - p.turns(t - h)) / (2.0 * h) * 60.0;
                assert!(
                    (d - p.rpm(t)).abs() < 1e-3 * (1.0 + p.rpm(t).abs()),
                    "{p:?} at {t}: {d}"
                );
            }
        }
    }

    #[test]
    fn an_excursion_keeps_the_angle_continuous() {
        let mut e = EncoderModel::ideal(2048, 0.5, 600.0);
        e.excursion = Some((1e-3, 2e-3, 6000.0));
        let base = EncoderModel::ideal(2048, 0.5, 600.0);
        assert_eq!(e.turns(0.5e-3), base.turns(0.5e-3));
        // 1 ms at 6000 rpm: 0.1 turn instead of 0.01, then the profile's speed again.
        let extra = (6000.0 - 600.0) / 60.0 * 1e-3;
        for t in [1.5e-3, 2e-3, 3e-3] {
            let want = base.turns(t) + extra * ((t.min(2e-3) - 1e-3) / 1e-3);
            assert!((e.turns(t) - want).abs() < 1e-12, "{t}");
        }
    }

    #[test]
    fn a_broken_sin_wire_reads_zero_volts() {
        let mut e = EncoderModel::ideal(2048, 0.5, 60.0);
        e.track_faults.push(TrackFault::SinAtZero {
            from: 1e-3,
            to: 2e-3,
        });
        assert!(e.voltages(0.5e-3).0 > 1.0);
        let (s, c) = e.voltages(1.5e-3);
        assert_eq!(s, 0.0);
        assert!(c > 1.0 && c < 2.2);
    }

    #[test]
    fn ideal_tracks_are_in_quadrature() {
        let mut e = EncoderModel::ideal(2048, 0.5, 60.0);
        // At electrical angle 0: sin = Vc, cos = Vc + A.
        let (s, c) = e.voltages(0.0);
        assert!((s - 1.65).abs() < 1e-12 && (c - 2.15).abs() < 1e-12);
        // A quarter period later: sin = Vc + A.
        let t = 0.25 / 2048.0; // 60 rpm = 1 turn/s
        let (s, c) = e.voltages(t);
        assert!((s - 2.15).abs() < 1e-9 && (c - 1.65).abs() < 1e-9);
    }
}
