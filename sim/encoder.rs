//! Model of a sine/cosine (sinewave) incremental encoder: the analog sin and cos track
//! voltages as a function of time, with the imperfections real encoders have, and the
//! speed profiles of the tests (constant, ramp, reversal, creep).
//!
//! Signal model. Both tracks read the same grating, so they carry the same periodic
//! waveform w, the cos track a quarter period (plus the phase error phi) later:
//! ```text
//! w(x)     = sin(x) + h2 sin(2x + p2) + h3 sin(3x + p3) + h5 sin(5x + p5)
//! v_sin(t) = Vc + off_s + A (1 + g/2) w(theta_s)            + n_s(t)
//! v_cos(t) = Vc + off_c + A (1 - g/2) w(theta_s + pi/2 + phi) + n_c(t)
//! theta_s  = PPR * 2 pi * (turns + e / (2 pi) * sin(2 pi turns))
//! ```
//! A: amplitude (V), Vc: common-mode (V), off: offsets (V), g: relative gain mismatch,
//! phi: quadrature phase error (rad), hk, pk: ratio and phase of the k-th harmonic (a
//! harmonic of the cos track is the sin track's shifted by k quarter periods: the 3rd is
//! -h3 cos(3x + p3)), n: white Gaussian noise of the given RMS (Box-Muller on SplitMix64,
//! deterministic per seed). e: eccentricity of the scale on the shaft (rad mechanical):
//! the head reads the scale at the shaft's angle plus e sin(2 pi turns), a once-per-turn
//! error no per-period correction can see.
//!
//! Angle error of one harmonic (small hk, the other imperfections zero): the vector
//! (cos track, sin track) is e^(i x) + hk e^(i k x) (k = 1 mod 4: 5) or e^(i x) - hk e^(-i k x)
//! (k = 3 mod 4: 3), so atan2 is off by about hk sin((k - 1) x) or hk sin((k + 1) x) rad
//! electrical: 4 cycles per period for the 3rd and 5th harmonics. The 2nd harmonic gives
//! 1 and 3 cycles per period.
//!
//! The mechanical angle is integrated exactly from the speed profile (closed forms), so the
//! "true angle" against which the decoder is judged has no numerical drift; the true angle
//! is the shaft's ([`EncoderModel::electrical_angle`]), the tracks follow the scale's
//! ([`EncoderModel::scale_angle`]).
use crate::cosim::stimulus::SplitMix64;
use std::f64::consts::{FRAC_PI_2, TAU};

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
    /// Second-harmonic ratio h2.
    pub second_harmonic: f64,
    /// Third-harmonic ratio h3.
    pub third_harmonic: f64,
    /// Fifth-harmonic ratio h5.
    pub fifth_harmonic: f64,
    /// Phases p2, p3, p5 of the harmonics, radians (see the module's signal model).
    pub harmonic_phase: [f64; 3],
    /// Eccentricity e of the scale, radians mechanical: the angle the head reads is off by
    /// e sin(2 pi turns), once per turn.
    pub eccentricity: f64,
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
            second_harmonic: 0.0,
            third_harmonic: 0.0,
            fifth_harmonic: 0.0,
            harmonic_phase: [0.0; 3],
            eccentricity: 0.0,
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

    /// Electrical angle the read head sees on the scale (rad, unwrapped) at time t: the
    /// shaft's [`electrical_angle`](Self::electrical_angle) plus the eccentricity's
    /// once-per-turn error. The tracks and comparators follow it.
    pub fn scale_angle(&self, t: f64) -> f64 {
        let turns = self.turns(t);
        let wobble = self.eccentricity / TAU * (TAU * turns).sin();
        (turns + wobble) * self.ppr as f64 * TAU
    }

    /// The tracks' waveform w(x) (module doc): the fundamental plus the harmonics.
    pub fn waveform(&self, x: f64) -> f64 {
        let h = [
            (2.0, self.second_harmonic),
            (3.0, self.third_harmonic),
            (5.0, self.fifth_harmonic),
        ];
        let mut w = x.sin();
        for ((k, r), p) in h.into_iter().zip(self.harmonic_phase) {
            if r != 0.0 {
                w += r * (k * x + p).sin();
            }
        }
        w
    }

    fn gauss(&mut self) -> f64 {
        // Box-Muller.
        let u1 = self.rng.unit().max(1e-300);
        let u2 = self.rng.unit();
        (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
    }

    /// (v_sin, v_cos) in volts at time t, noise drawn fresh on each call.
    pub fn voltages(&mut self, t: f64) -> (f64, f64) {
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
        let th = self.scale_angle(t);
        let g = self.gain_mismatch;
        let ns = self.noise_rms * self.gauss();
        let nc = self.noise_rms * self.gauss();
        let s = self.common_mode + self.offset_sin + a * (1.0 + g / 2.0) * self.waveform(th) + ns;
        let c = self.common_mode
            + self.offset_cos
            + a * (1.0 - g / 2.0) * self.waveform(th + FRAC_PI_2 + self.phase_error)
            + nc;
        (if sin_broken { 0.0 } else { s }, c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

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

    /// The angle atan2 reads from the tracks (common mode removed) less the shaft's
    /// electrical angle, wrapped into (-pi, pi].
    fn read_error(e: &mut EncoderModel, t: f64) -> f64 {
        let (s, c) = e.voltages(t);
        let d = (s - e.common_mode).atan2(c - e.common_mode) - e.electrical_angle(t);
        (d + PI).rem_euclid(TAU) - PI
    }

    #[test]
    fn a_third_harmonic_moves_the_angle_four_times_a_period() {
        // v_sin = A (sin x + h sin 3x), v_cos = A (cos x - h cos 3x): the vector is
        // e^(ix) - h e^(-3ix) = e^(ix) (1 - h e^(-4ix)), so atan2 reads x plus
        // atan2(h sin 4x, 1 - h cos 4x), whose largest value is asin(h).
        let h = 0.02;
        let mut e = EncoderModel::ideal(2048, 0.5, 60.0);
        e.third_harmonic = h;
        let period = 1.0 / 2048.0; // 60 rpm: one turn per second
        let mut max: f64 = 0.0;
        for k in 0..4096 {
            let t = k as f64 / 4096.0 * period;
            let x = e.electrical_angle(t);
            let want = (h * (4.0 * x).sin()).atan2(1.0 - h * (4.0 * x).cos());
            let got = read_error(&mut e, t);
            assert!((got - want).abs() < 1e-12, "x = {x}: {got} against {want}");
            max = max.max(got.abs());
        }
        assert!((max - h.asin()).abs() < 1e-6, "{max}");
    }

    #[test]
    fn a_fifth_harmonic_and_its_phase_follow_their_formula() {
        // k = 5: the cos track's harmonic is h cos(5x + p), the vector e^(ix) (1 + h
        // e^(i(4x + p))); its angle error atan2(h sin(4x + p), 1 + h cos(4x + p)).
        let (h, p) = (0.01, 30f64.to_radians());
        let mut e = EncoderModel::ideal(512, 0.5, 60.0);
        e.fifth_harmonic = h;
        e.harmonic_phase = [0.0, 0.0, p];
        for k in 0..1000 {
            let t = k as f64 * 1.3e-6;
            let x = e.electrical_angle(t);
            let u = 4.0 * x + p;
            let want = (h * u.sin()).atan2(1.0 + h * u.cos());
            let got = read_error(&mut e, t);
            assert!((got - want).abs() < 1e-12, "x = {x}: {got} against {want}");
        }
    }

    #[test]
    fn a_second_harmonic_is_the_same_waveform_on_both_tracks() {
        // Each track alone: the cos track is the sin track a quarter period later.
        let mut e = EncoderModel::ideal(1, 1.0, 60.0);
        e.second_harmonic = 0.03;
        e.harmonic_phase = [0.4, 0.0, 0.0];
        for k in 0..100 {
            let t = k as f64 * 0.01; // one turn = one period per second
            let (_, c) = e.voltages(t);
            let (s, _) = e.voltages(t + 0.25);
            assert!((s - c).abs() < 1e-12, "{t}");
            let x = TAU * t;
            let want = 1.65 + x.sin() + 0.03 * (2.0 * x + 0.4).sin();
            assert!((e.voltages(t).0 - want).abs() < 1e-12);
        }
    }

    #[test]
    fn eccentricity_is_a_once_per_turn_error_of_the_stated_size() {
        // 20 arc-seconds on a 2048-period scale: the tracks' angle is off the shaft's by
        // 20" x 2048 electrical, as e sin(shaft angle), once per turn.
        let arcsec = 20.0;
        let mut e = EncoderModel::ideal(2048, 0.5, 60.0);
        e.eccentricity = (arcsec / 3600.0f64).to_radians();
        let mut max: f64 = 0.0;
        for k in 0..1000 {
            let t = k as f64 / 1000.0; // one turn
            let got = read_error(&mut e, t) / 2048.0; // rad mechanical
            let want = e.eccentricity * (TAU * t).sin();
            assert!((got - want).abs() < 1e-12, "{t}: {got} against {want}");
            max = max.max(got.abs());
        }
        let max_arcsec = max.to_degrees() * 3600.0;
        assert!((max_arcsec - arcsec).abs() < 1e-3, "{max_arcsec}");
        // The shaft's angle, the one the decoder is judged against, has no such error.
        assert_eq!(e.electrical_angle(0.25), 0.25 * 2048.0 * TAU);
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
