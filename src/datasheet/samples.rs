//! The samples behind the accuracy's "before correction" curve, the Lissajous figure and the
//! fit's convergence: the encoder model of `simulate` (the same imperfections) sampled at the
//! ADC's rate and converted as the ADC chip model converts (`sim::system`'s chip models),
//! then corrected by the correction block's bit-exact models (`crate::blocks::correction`:
//! the pipeline model for static and peak-tracking correction, the ellipse fit's integer
//! specification for `mode = "auto"`), which the block tests check against the RTL.
use crate::blocks::correction::fit::{Coefs, EllipseFit, FitParams};
use crate::blocks::correction::model::{correct, correct_phase, CorrectionIn, CorrectionModel};
use crate::config::Loaded;
use crate::simulate::SimOptions;
use std::f64::consts::TAU;

/// One ADC sample pair.
#[derive(Clone, Copy, Debug)]
pub struct Sample {
    /// Time, seconds.
    pub t: f64,
    /// True electrical angle, radians (unwrapped).
    pub theta: f64,
    /// Raw codes [sin, cos].
    pub raw: [i64; 2],
    /// Corrected codes [sin, cos] (what the CORDIC is given).
    pub corrected: [i64; 2],
}

/// The correction's coefficients at one time (automatic correction).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct CoefPoint {
    /// Time, seconds.
    pub t_s: f64,
    /// Offsets [sin, cos], LSB.
    pub offset: [i64; 2],
    /// Gain codes [sin, cos].
    pub gain: [u64; 2],
}

/// The ADC's code for an encoder voltage: through the kit's LTC6912-1 gain, else the
/// encoder's swing about 1.65 V with 1.25 V at full scale (as `sim::system` converts).
fn code(loaded: &Loaded, v: f64, channel: usize) -> i64 {
    let d = &loaded.derived;
    let gain = d
        .preamp
        .as_ref()
        .map(|p| [p.gain_a, p.gain_b][channel] as f64)
        .unwrap_or(1.0);
    let half = (1i64 << (d.adc_width - 1)) as f64;
    let x = gain * (v - 1.65) / 1.25 * half;
    if x.is_nan() {
        return 0;
    }
    x.round().clamp(-half, half - 1.0) as i64
}

/// `n` samples at the ADC's rate under `o` (its profile and imperfections), corrected; and
/// the coefficients in use whenever they change (automatic correction only).
pub fn samples(loaded: &Loaded, o: &SimOptions, n: usize) -> (Vec<Sample>, Vec<CoefPoint>) {
    let d = &loaded.derived;
    let p = d.correction;
    let mut enc = crate::simulate::encoder(loaded, o);
    let fs = d.sample_rate_hz;
    let (a, gf) = (p.adc_width(), p.gain_frac_bits());
    let start = Coefs {
        offset: [p.offset()[0] as i64, p.offset()[1] as i64],
        gain: [p.gain()[0] as u64, p.gain()[1] as u64],
        cross: p.cross() as i64,
    };
    let mut fit = p.fit().map(|f| {
        EllipseFit::new(
            FitParams {
                adc_width: a,
                gain_frac_bits: gf,
                target_amplitude: f.target_amplitude(),
                periods: f.periods(),
                min_samples: f.min_samples(),
                min_amplitude: f.min_amplitude(),
            },
            start,
        )
    });
    let mut model = CorrectionModel::new(&p);
    let automatic = fit.is_some() || p.auto().is_some();
    let mut coefs = vec![];
    let mut out = Vec::with_capacity(n);
    let mut last: Option<([i64; 2], [u64; 2])> = None;
    for k in 0..n {
        let t = k as f64 / fs;
        let (vs, vc) = enc.voltages(t);
        let raw = [code(loaded, vs, 0), code(loaded, vc, 1)];
        let (corrected, offset, gain) = match fit.as_mut() {
            Some(f) => {
                let c = f.coefs();
                let s = correct(raw[0], c.offset[0], c.gain[0], a, gf);
                let cc = if p.has_phase() {
                    let (bs, bc) = (c.offset[0], c.offset[1]);
                    correct_phase(
                        raw[0],
                        raw[1],
                        bs,
                        bc,
                        c.gain[1],
                        c.cross,
                        a,
                        gf,
                        p.phase_shift(),
                    )
                } else {
                    correct(raw[1], c.offset[1], c.gain[1], a, gf)
                };
                f.sample(raw[0], raw[1]);
                ([s, cc], c.offset, c.gain)
            }
            None => {
                // One valid clock, then idle clocks to the next sample (the pipeline's
                // output of this sample appears within them).
                let mut got = None;
                let mut o = model.step(CorrectionIn {
                    rst: false,
                    valid: true,
                    sin: raw[0] as i32,
                    cos: raw[1] as i32,
                    ..CorrectionIn::default()
                });
                for _ in 1..d.adc.period_clocks.max(8) {
                    if o.valid && got.is_none() {
                        got = Some(([o.sin, o.cos], o.offset, o.gain));
                    }
                    o = model.step(CorrectionIn::default());
                }
                got.unwrap_or(([0, 0], o.offset, o.gain))
            }
        };
        if automatic && last != Some((offset, gain)) {
            coefs.push(CoefPoint {
                t_s: t,
                offset,
                gain,
            });
            last = Some((offset, gain));
        }
        out.push(Sample {
            t,
            theta: enc.electrical_angle(t),
            raw,
            corrected,
        });
    }
    (out, coefs)
}

/// Error of the angle of the raw codes (atan2) against the true angle, in fine LSB (2^-F
/// quadrant), wrapped to half a period; with the kit's inverting pre-amplifier the vector
/// is turned by two quadrants, which is taken out (as `SimResult::offset_lsb` does).
pub fn raw_angle_errors(loaded: &Loaded, s: &[Sample]) -> Vec<f64> {
    let lsb_per_rad = 4.0 * (1u64 << loaded.derived.fine_bits) as f64 / TAU;
    let turned = if loaded.derived.preamp.is_some() {
        TAU / 2.0
    } else {
        0.0
    };
    let wrap = |x: f64| x - TAU * (x / TAU).round();
    s.iter()
        .map(|x| wrap((x.raw[0] as f64).atan2(x.raw[1] as f64) - x.theta - turned) * lsb_per_rad)
        .collect()
}
