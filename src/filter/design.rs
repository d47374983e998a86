//! f64 design: prototype poles, pre-warping, analog transforms, bilinear transform, pairing
//! into sections and the per-section gain rule (see the module doc of `filter`).

use super::{Complex64, FilterError, FilterKind, FilterSpec, IdealSection};
use std::f64::consts::PI;

/// The `n` poles of the normalised analog Butterworth low-pass:
/// `p_k = exp(j pi (2k + n - 1) / (2n))`, `k = 1..n` (all with negative real part; the
/// first `n/2` in the upper half plane, `p_{n+1-k} = conj(p_k)`, `-1` in the middle for odd
/// `n`).
pub fn butterworth_poles(order: u32) -> Vec<Complex64> {
    let n = order as f64;
    (1..=order)
        .map(|k| {
            let th = PI * (2.0 * k as f64 + n - 1.0) / (2.0 * n);
            // The middle pole of an odd order is exactly -1 (avoid a 1e-16 imaginary part).
            if 2 * k == order + 1 {
                Complex64::from(-1.0)
            } else {
                Complex64::from_polar(1.0, th)
            }
        })
        .collect()
}

/// Pre-warped analog frequency (rad/s) of the digital frequency `f_hz`:
/// `W = 2 fs tan(pi f / fs)`.
pub fn prewarp(f_hz: f64, fs_hz: f64) -> f64 {
    2.0 * fs_hz * (PI * f_hz / fs_hz).tan()
}

/// Bilinear transform of an analog point: `z = (2 fs + s) / (2 fs - s)`.
pub fn bilinear(s: Complex64, fs_hz: f64) -> Complex64 {
    let k = Complex64::from(2.0 * fs_hz);
    (k + s) / (k - s)
}

/// Principal square root by the half-angle formulas, `re = sqrt((|z| + x) / 2)`,
/// `im = ±sqrt((|z| - x) / 2)` with the sign of `z.im`. Kept by hand rather than
/// `Complex64::sqrt`, which goes through the polar form (`atan2`, `cos`, `sin`): that can
/// move the band-pass poles by an ulp, and so the designed coefficients, which must stay
/// bit-identical to the designs this tool has always emitted for the same config.
fn principal_sqrt(z: Complex64) -> Complex64 {
    let r = z.norm();
    let re = ((r + z.re) * 0.5).max(0.0).sqrt();
    let im = ((r - z.re) * 0.5).max(0.0).sqrt();
    Complex64::new(re, if z.im < 0.0 { -im } else { im })
}

/// Poles of one section: a conjugate/real pair, or one real pole (first-order section).
enum Poles {
    Two(Complex64, Complex64),
    One(f64),
}

/// Designs the ideal f64 sections of a validated `spec` (sorted by increasing pole radius,
/// unity gain at the pass-band centre each). Validates `spec` again and rejects a section
/// whose f64 poles are not strictly inside the unit circle (only on numerical breakdown).
pub fn design_ideal(spec: &FilterSpec) -> Result<Vec<IdealSection>, FilterError> {
    spec.validate()?;
    let fs = spec.sample_rate_hz;
    let n = spec.order as usize;
    let protos = butterworth_poles(spec.order);
    let upper = &protos[..n / 2];
    let odd = n % 2 == 1;
    let mut groups: Vec<Poles> = Vec::new();
    match spec.kind {
        FilterKind::Lowpass | FilterKind::Highpass => {
            let wc = prewarp(spec.corner_hz.unwrap_or(0.0), fs);
            let map = |p: Complex64| match spec.kind {
                FilterKind::Lowpass => p * wc,
                _ => Complex64::from(wc) / p,
            };
            for &p in upper {
                let z = bilinear(map(p), fs);
                groups.push(Poles::Two(z, z.conj()));
            }
            if odd {
                // s = -wc for both LP (wc * -1) and HP (wc / -1).
                groups.push(Poles::One(bilinear(Complex64::from(-wc), fs).re));
            }
        }
        FilterKind::Bandpass => {
            let [f1, f2] = spec.band_hz.unwrap_or([0.0, 0.0]);
            let (w1, w2) = (prewarp(f1, fs), prewarp(f2, fs));
            let w0sq = w1 * w2;
            let bw = w2 - w1;
            let roots = |p: Complex64| {
                let q = p * bw;
                let d = principal_sqrt(q * q - Complex64::from(4.0 * w0sq));
                ((q + d) * 0.5, (q - d) * 0.5)
            };
            for &p in upper {
                let (s1, s2) = roots(p);
                for s in [s1, s2] {
                    let z = bilinear(s, fs);
                    groups.push(Poles::Two(z, z.conj()));
                }
            }
            if odd {
                let disc = bw * bw - 4.0 * w0sq;
                if disc < 0.0 {
                    let s = Complex64::new(-bw / 2.0, (-disc).sqrt() / 2.0);
                    let z = bilinear(s, fs);
                    groups.push(Poles::Two(z, z.conj()));
                } else {
                    let r = disc.sqrt();
                    let z1 = bilinear(Complex64::from((-bw + r) / 2.0), fs);
                    let z2 = bilinear(Complex64::from((-bw - r) / 2.0), fs);
                    groups.push(Poles::Two(z1, z2));
                }
            }
        }
    }

    let w0 = 2.0 * PI * spec.centre_hz() / fs;
    let mut sections: Vec<IdealSection> = groups
        .into_iter()
        .map(|g| {
            let (a, pattern) = match g {
                Poles::Two(z1, z2) => {
                    let a = [-(z1 + z2).re, (z1 * z2).re];
                    let p = match spec.kind {
                        FilterKind::Lowpass => [1.0, 2.0, 1.0],
                        FilterKind::Highpass => [1.0, -2.0, 1.0],
                        FilterKind::Bandpass => [1.0, 0.0, -1.0],
                    };
                    (a, p)
                }
                Poles::One(z) => {
                    let p = match spec.kind {
                        FilterKind::Highpass => [1.0, -1.0, 0.0],
                        _ => [1.0, 1.0, 0.0],
                    };
                    ([-z, 0.0], p)
                }
            };
            let unit = IdealSection { b: pattern, a };
            let g = 1.0 / unit.eval(w0).norm();
            IdealSection {
                b: pattern.map(|c| c * g),
                a,
            }
        })
        .collect();
    sections.sort_by(|x, y| x.pole_radius().total_cmp(&y.pole_radius()));
    for (i, s) in sections.iter().enumerate() {
        let r = s.pole_radius();
        if r >= 1.0 || r.is_nan() {
            return Err(FilterError::UnstableSection {
                filter: spec.to_string(),
                stage: "ideal",
                section: i,
                radius: r,
                a1: s.a[0],
                a2: s.a[1],
                hint: "; the f64 design broke down (corner too close to 0 or fs/2 for this order)",
            });
        }
    }
    Ok(sections)
}
