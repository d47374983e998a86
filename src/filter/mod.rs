//! IIR filter design for the capacitive path: Butterworth low-pass, high-pass and
//! band-pass filters designed in f64, split into second-order sections and quantized to a
//! two's-complement coefficient format for the time-multiplexed biquad. Pure Rust, no rust-hdl.
//!
//! # Maths
//!
//! **Analog prototype.** The normalised (cut-off 1 rad/s) Butterworth low-pass of order `n`
//! has the `n` left-half-plane poles
//! `p_k = exp(j pi (2k + n - 1) / (2n))`, `k = 1..n`, no finite zeros and `|H(j W)|^2 =
//! 1 / (1 + W^(2n))` (-3.0103 dB at `W = 1`). See [`butterworth_poles`].
//!
//! **Pre-warping.** Every band-edge frequency `f` is mapped to the analog frequency
//! `W = 2 fs tan(pi f / fs)` ([`prewarp`]) so that after the bilinear transform the digital
//! filter has exactly the analog prototype's response at `f` (-3.01 dB at the corners).
//!
//! **Analog frequency transforms** (on the poles; zeros at `s = inf` or `s = 0`):
//! - low-pass to low-pass: `s = Wc p_k`; `n` zeros at `s = inf`;
//! - low-pass to high-pass: `s = Wc / p_k`; `n` zeros at `s = 0`;
//! - low-pass to band-pass: `p -> (s^2 + W0^2) / (s B)` with `W0 = sqrt(W1 W2)` and
//!   `B = W2 - W1` (both from pre-warped edges), i.e. each prototype pole gives the two roots
//!   `s = (p B +- sqrt((p B)^2 - 4 W0^2)) / 2`; `n` zeros at `s = 0` and `n` at `s = inf`.
//!   **`order` is the prototype order `n`: a band-pass filter has `2n` poles (`n` sections),
//!   a low-/high-pass filter has `n` poles (`ceil(n/2)` sections).**
//!
//! **Bilinear transform.** `z = (2 fs + s) / (2 fs - s)`: a pole at `s` maps to a pole at `z`,
//! `s = inf` maps to `z = -1` and `s = 0` to `z = +1`.
//!
//! **Second-order sections.** Each conjugate digital pole pair `(z, z*)` (or a pair of real
//! poles, or one real pole for odd low-/high-pass orders) forms one section
//! `H_i(z) = g_i P(z) / (1 + a1 z^-1 + a2 z^-2)` with `a1 = -(z1 + z2)`, `a2 = z1 z2`, i.e.
//! `y = b0 x + b1 x1 + b2 x2 - a1 y1 - a2 y2` with `b = g_i P`, where the zero pattern `P`
//! is `[1, 2, 1]` (low-pass, both zeros at `z = -1`), `[1, -2, 1]` (high-pass, `z = +1`),
//! `[1, 0, -1]` (band-pass, one zero at each), or `[1, 1, 0]` / `[1, -1, 0]` for the
//! first-order section of an odd low-/high-pass (with `a2 = 0`).
//!
//! **Gain rule.** The overall gain is distributed so that *every section* has gain exactly 1
//! (0 dB) at the pass-band centre: `g_i = |A_i(z0)| / |P(z0)|` with `z0 = e^(j w0)` and
//! `w0` = 0 (low-pass, DC), `pi` (high-pass, Nyquist), or for the band-pass the digital
//! image of the analog centre `W0`: `f0 = (fs / pi) atan(sqrt(tan(pi f1/fs) tan(pi f2/fs)))`
//! (within a few tens of Hz of `sqrt(f1 f2)` for the paper's 15-25 kHz at 400 kHz). The
//! cascade therefore has gain 1 at the centre (Butterworth: the maximum), while a single
//! high-Q section may peak above 1 elsewhere (the integrator must leave headroom for that).
//!
//! **Section order.** Sections are sorted by increasing pole radius (the most resonant
//! section last, as MATLAB `zp2sos` does by default).
//!
//! **Quantization.** [`CoefFormat`] `{ width, frac }`: two's complement, `width` bits in
//! total, `frac` fractional bits, so the integer `q` stands for `q / 2^frac` and must lie in
//! `[-2^(width-1), 2^(width-1) - 1]` (`width - frac - 1` integer bits besides the sign; the
//! denominators need at least 1 because `|a1| < 2`). Each `a1`, `a2` is quantized as
//! `round_half_away(a * 2^frac)`; the numerator is quantized as **one** integer
//! `G = round_half_away(g * 2^frac)` times the exact integer pattern `P`, so the quantized
//! zeros stay exactly at `z = +-1` (the low-pass keeps an exact null at Nyquist, the
//! high-pass and band-pass an exact null at DC). The rounding is exact: `a * 2^frac` is
//! exact in binary floating point (a power-of-two scale, no overflow for `frac <= 63`) and
//! `f64::round` rounds half away from zero exactly, so the integer is the correctly rounded
//! value of the f64 coefficient (no num-bigint needed).
//!
//! **Stability check.** A quantized section is accepted only if its poles are strictly inside
//! the unit circle: the stability triangle `|a2| < 1` and `|a1| < 1 + a2`, evaluated exactly
//! on the integers (`|A2| < 2^frac`, `|A1| < 2^frac + A2`, in i128). The pole radius
//! (`sqrt(a2)` for complex poles, else the larger real root modulus) is reported in the error.
//! Coefficients outside the format and a numerator that rounds to zero are rejected too.
//!
//! **Response.** [`Response`] compares `|H(e^jw)|` of the ideal (f64) and quantized cascades:
//! maximum |dB difference| over a uniform grid of [`PASSBAND_GRID`] points covering the pass
//! band (`[0, fc]`, `[fc, fs/2]` or `[f1, f2]`, end points included), the gain at the centre,
//! the DC gain and the attenuation at probe frequencies (the integrator asks at
//! 2 x carrier = 40 kHz through [`design_with_probes`]).
//!
//! ```text
//!  spec --prewarp--> Wc | (W1,W2) --prototype poles p_k--> analog poles s
//!       --bilinear--> digital poles z --pair--> (a1,a2) per section --gain rule--> b
//!       --round half away--> integer Sos --triangle check--> Designed { ideal, sos, response }
//! ```

mod design;
mod error;
mod quant;
mod response;

use serde::{Deserialize, Serialize};

pub use design::{bilinear, butterworth_poles, design_ideal, prewarp};
pub use error::FilterError;
pub use num_complex::Complex64;
pub use quant::{quantize_sections, round_half_away};
pub use response::{Probe, Response, PASSBAND_GRID};

/// Largest accepted prototype order (a band-pass of this order has 32 poles).
pub const MAX_ORDER: u32 = 16;

/// The filter type.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum FilterKind {
    /// Butterworth low-pass (`corner_hz`).
    Lowpass,
    /// Butterworth high-pass (`corner_hz`).
    Highpass,
    /// Butterworth band-pass (`band_hz`), `2 * order` poles.
    Bandpass,
}

/// What to design: a Butterworth filter, plain values (embeddable in the TOML config).
#[derive(Clone, Debug, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FilterSpec {
    /// Low-pass, high-pass or band-pass.
    pub kind: FilterKind,
    /// Prototype order `n` (1..=16): `n` poles for low-/high-pass, `2n` for band-pass.
    pub order: u32,
    /// -3 dB corner in Hz (low-/high-pass only), `0 < corner_hz < sample_rate_hz / 2`.
    #[serde(default)]
    pub corner_hz: Option<f64>,
    /// -3 dB band edges `[f1, f2]` in Hz (band-pass only), `0 < f1 < f2 < sample_rate_hz / 2`.
    #[serde(default)]
    pub band_hz: Option<[f64; 2]>,
    /// Sample rate in Hz.
    pub sample_rate_hz: f64,
}

/// Two's-complement coefficient format: `width` total bits of which `frac` are fractional.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CoefFormat {
    /// Total bits including the sign (2..=64).
    pub width: u32,
    /// Fractional bits (`frac <= width - 1`).
    pub frac: u32,
}

/// One ideal (f64) section: `y = b0 x + b1 x1 + b2 x2 - a1 y1 - a2 y2`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct IdealSection {
    /// Numerator `[b0, b1, b2]`.
    pub b: [f64; 3],
    /// Denominator `[a1, a2]` (the leading 1 is implied).
    pub a: [f64; 2],
}

/// One quantized section: the integers stand for `value / 2^frac` of the [`Sos`] format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Section {
    /// Numerator `[b0, b1, b2]` as integers.
    pub b: [i64; 3],
    /// Denominator `[a1, a2]` as integers (the leading 1 = `2^frac` is implied).
    pub a: [i64; 2],
}

/// Quantized second-order sections in cascade order.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Sos {
    /// Sections, first to last.
    pub sections: Vec<Section>,
    /// The coefficient format of every integer in `sections`.
    pub format: CoefFormat,
}

/// A designed filter: the ideal sections, the quantized ones and their response comparison.
#[derive(Clone, Debug, serde::Serialize)]
pub struct Designed {
    /// The specification it was designed from.
    pub spec: FilterSpec,
    /// Ideal f64 sections (same order as `sos.sections`).
    pub ideal: Vec<IdealSection>,
    /// Quantized sections.
    pub sos: Sos,
    /// Ideal vs quantized response figures.
    pub response: Response,
}

impl std::fmt::Display for FilterKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FilterKind::Lowpass => "lowpass",
            FilterKind::Highpass => "highpass",
            FilterKind::Bandpass => "bandpass",
        })
    }
}

impl std::fmt::Display for FilterSpec {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} order {}", self.kind, self.order)?;
        match (self.kind, self.corner_hz, self.band_hz) {
            (FilterKind::Bandpass, _, Some([f1, f2])) => write!(f, ", band {f1}-{f2} Hz")?,
            (_, Some(c), _) => write!(f, ", corner {c} Hz")?,
            _ => {}
        }
        write!(f, ", fs {} Hz", self.sample_rate_hz)
    }
}

impl FilterSpec {
    /// Butterworth low-pass.
    pub fn lowpass(order: u32, corner_hz: f64, sample_rate_hz: f64) -> FilterSpec {
        FilterSpec {
            kind: FilterKind::Lowpass,
            order,
            corner_hz: Some(corner_hz),
            band_hz: None,
            sample_rate_hz,
        }
    }

    /// Butterworth high-pass.
    pub fn highpass(order: u32, corner_hz: f64, sample_rate_hz: f64) -> FilterSpec {
        FilterSpec {
            kind: FilterKind::Highpass,
            ..FilterSpec::lowpass(order, corner_hz, sample_rate_hz)
        }
    }

    /// Butterworth band-pass with `2 * order` poles.
    pub fn bandpass(order: u32, f1_hz: f64, f2_hz: f64, sample_rate_hz: f64) -> FilterSpec {
        FilterSpec {
            kind: FilterKind::Bandpass,
            order,
            corner_hz: None,
            band_hz: Some([f1_hz, f2_hz]),
            sample_rate_hz,
        }
    }

    fn invalid(&self, field: &'static str, message: String) -> FilterError {
        FilterError::InvalidSpec {
            filter: self.to_string(),
            field,
            message,
        }
    }

    /// Checks the spec: order in 1..=[`MAX_ORDER`], finite positive sample rate, the corner
    /// (low-/high-pass) or band (band-pass) strictly between 0 and Nyquist, and not both.
    pub fn validate(&self) -> Result<(), FilterError> {
        let fs = self.sample_rate_hz;
        if !(fs.is_finite() && fs > 0.0) {
            return Err(self.invalid("sample_rate_hz", format!("{fs} must be finite and > 0")));
        }
        if self.order == 0 || self.order > MAX_ORDER {
            return Err(self.invalid(
                "order",
                format!("{} is outside 1..={MAX_ORDER}", self.order),
            ));
        }
        let nyq = fs / 2.0;
        let in_band = |f: f64| f.is_finite() && f > 0.0 && f < nyq;
        match self.kind {
            FilterKind::Lowpass | FilterKind::Highpass => {
                if self.band_hz.is_some() {
                    return Err(self.invalid(
                        "band_hz",
                        format!("not used by a {} filter (give corner_hz)", self.kind),
                    ));
                }
                match self.corner_hz {
                    None => Err(self.invalid(
                        "corner_hz",
                        format!("missing: a {} filter needs corner_hz", self.kind),
                    )),
                    Some(c) if !in_band(c) => Err(self.invalid(
                        "corner_hz",
                        format!("{c} Hz must be > 0 and < fs/2 = {nyq} Hz"),
                    )),
                    Some(_) => Ok(()),
                }
            }
            FilterKind::Bandpass => {
                if self.corner_hz.is_some() {
                    return Err(self.invalid(
                        "corner_hz",
                        "not used by a bandpass filter (give band_hz = [f1, f2])".to_string(),
                    ));
                }
                match self.band_hz {
                    None => Err(self.invalid(
                        "band_hz",
                        "missing: a bandpass filter needs band_hz = [f1, f2]".to_string(),
                    )),
                    Some([f1, f2]) if !(in_band(f1) && in_band(f2) && f1 < f2) => Err(self
                        .invalid(
                            "band_hz",
                            format!("[{f1}, {f2}] Hz must satisfy 0 < f1 < f2 < fs/2 = {nyq} Hz"),
                        )),
                    Some(_) => Ok(()),
                }
            }
        }
    }

    /// Pass band `[lo, hi]` in Hz: `[0, fc]`, `[fc, fs/2]` or `[f1, f2]`.
    /// Call on a validated spec (otherwise missing values read as 0).
    pub fn passband_hz(&self) -> [f64; 2] {
        let c = self.corner_hz.unwrap_or(0.0);
        match self.kind {
            FilterKind::Lowpass => [0.0, c],
            FilterKind::Highpass => [c, self.sample_rate_hz / 2.0],
            FilterKind::Bandpass => self.band_hz.unwrap_or([0.0, 0.0]),
        }
    }

    /// Pass-band centre in Hz where every section has unity gain: 0 (low-pass), fs/2
    /// (high-pass), `(fs/pi) atan(sqrt(tan(pi f1/fs) tan(pi f2/fs)))` (band-pass).
    pub fn centre_hz(&self) -> f64 {
        let fs = self.sample_rate_hz;
        match self.kind {
            FilterKind::Lowpass => 0.0,
            FilterKind::Highpass => fs / 2.0,
            FilterKind::Bandpass => {
                let [f1, f2] = self.passband_hz();
                let t = ((std::f64::consts::PI * f1 / fs).tan()
                    * (std::f64::consts::PI * f2 / fs).tan())
                .sqrt();
                fs / std::f64::consts::PI * t.atan()
            }
        }
    }

    /// Default probe frequencies for [`design`]: one octave into the stop band, i.e.
    /// `2 fc` (low-pass), `fc / 2` (high-pass), `f1 / 2` and `2 f2` (band-pass), keeping
    /// only those below fs/2.
    pub fn default_probes_hz(&self) -> Vec<f64> {
        let [lo, hi] = self.passband_hz();
        let v = match self.kind {
            FilterKind::Lowpass => vec![2.0 * hi],
            FilterKind::Highpass => vec![lo / 2.0],
            FilterKind::Bandpass => vec![lo / 2.0, 2.0 * hi],
        };
        v.into_iter()
            .filter(|&f| f > 0.0 && f <= self.sample_rate_hz / 2.0)
            .collect()
    }
}

impl CoefFormat {
    /// Checks `2 <= width <= 64` and `frac <= width - 1`.
    pub fn validate(&self) -> Result<(), FilterError> {
        let bad = |message: &str| FilterError::InvalidFormat {
            width: self.width,
            frac: self.frac,
            message: message.to_string(),
        };
        if !(2..=64).contains(&self.width) {
            return Err(bad("width must be 2..=64"));
        }
        if self.frac > self.width - 1 {
            return Err(bad(
                "frac must be <= width - 1 (the sign bit is not fractional)",
            ));
        }
        Ok(())
    }

    /// Smallest integer: `-2^(width-1)`.
    pub fn min_int(&self) -> i128 {
        -(1i128 << (self.width - 1))
    }

    /// Largest integer: `2^(width-1) - 1`.
    pub fn max_int(&self) -> i128 {
        (1i128 << (self.width - 1)) - 1
    }

    /// `2^frac` as f64 (exact).
    pub fn scale(&self) -> f64 {
        2f64.powi(self.frac as i32)
    }

    /// The real value of an integer coefficient.
    pub fn to_real(&self, q: i64) -> f64 {
        q as f64 / self.scale()
    }
}

/// Pole radius (largest pole modulus) of `1 + a1 z^-1 + a2 z^-2`: `sqrt(a2)` for a complex
/// pair, else the larger of the two real roots' moduli (`|a1|` when `a2 = 0`).
pub fn pole_radius(a1: f64, a2: f64) -> f64 {
    let d = a1 * a1 - 4.0 * a2;
    if d < 0.0 {
        a2.sqrt()
    } else {
        let r = d.sqrt();
        ((-a1 + r) / 2.0).abs().max(((-a1 - r) / 2.0).abs())
    }
}

impl IdealSection {
    /// Largest pole modulus.
    pub fn pole_radius(&self) -> f64 {
        pole_radius(self.a[0], self.a[1])
    }

    /// The two poles (roots of `z^2 + a1 z + a2`).
    pub fn poles(&self) -> [Complex64; 2] {
        let [a1, a2] = self.a;
        let d = Complex64::from(a1 * a1 - 4.0 * a2).sqrt();
        let m = Complex64::from(-a1);
        [(m + d) * 0.5, (m - d) * 0.5]
    }

    /// `H(z)` at `z = e^(j w)`, `w = 2 pi f / fs`.
    pub fn eval(&self, w: f64) -> Complex64 {
        let zi = Complex64::from_polar(1.0, -w);
        let zi2 = zi * zi;
        let num = Complex64::from(self.b[0]) + zi * self.b[1] + zi2 * self.b[2];
        let den = Complex64::from(1.0) + zi * self.a[0] + zi2 * self.a[1];
        num / den
    }
}

impl Section {
    /// The real-valued section these integers stand for in `format`.
    pub fn to_ideal(&self, format: CoefFormat) -> IdealSection {
        IdealSection {
            b: self.b.map(|q| format.to_real(q)),
            a: self.a.map(|q| format.to_real(q)),
        }
    }

    /// Exact stability test on the integers: `|a2| < 2^frac` and `|a1| < 2^frac + a2`.
    pub fn is_stable(&self, format: CoefFormat) -> bool {
        let one = 1i128 << format.frac;
        let (a1, a2) = (self.a[0] as i128, self.a[1] as i128);
        a2.abs() < one && a1.abs() < one + a2
    }

    /// Largest pole modulus of the quantized section.
    pub fn pole_radius(&self, format: CoefFormat) -> f64 {
        pole_radius(format.to_real(self.a[0]), format.to_real(self.a[1]))
    }
}

/// `|H(e^jw)|` of a cascade at `f_hz` (sample rate `fs_hz`).
pub fn cascade_gain(sections: &[IdealSection], f_hz: f64, fs_hz: f64) -> f64 {
    let w = 2.0 * std::f64::consts::PI * f_hz / fs_hz;
    sections.iter().map(|s| s.eval(w).norm()).product()
}

impl Sos {
    /// The real-valued sections these integers stand for.
    pub fn to_ideal(&self) -> Vec<IdealSection> {
        self.sections
            .iter()
            .map(|s| s.to_ideal(self.format))
            .collect()
    }

    /// Markdown table of the integer coefficients with the quantized pole radius.
    pub fn to_markdown(&self) -> String {
        let mut s = format!(
            "Coefficients: {}-bit two's complement, {} fractional bits (value = integer / 2^{}).\n\n\
             | section | b0 | b1 | b2 | a1 | a2 | pole radius |\n|---|---|---|---|---|---|---|\n",
            self.format.width, self.format.frac, self.format.frac
        );
        for (i, x) in self.sections.iter().enumerate() {
            s += &format!(
                "| {i} | {} | {} | {} | {} | {} | {:.9} |\n",
                x.b[0],
                x.b[1],
                x.b[2],
                x.a[0],
                x.a[1],
                x.pole_radius(self.format)
            );
        }
        s
    }
}

/// Designs `spec`, quantizes it to `fmt` and compares the responses; the attenuation is
/// probed at [`FilterSpec::default_probes_hz`]. See the module doc for the maths.
pub fn design(spec: &FilterSpec, fmt: CoefFormat) -> Result<Designed, FilterError> {
    design_with_probes(spec, fmt, &spec.default_probes_hz())
}

/// As [`design`], with the attenuation reported at `probes_hz` (each in `[0, fs/2]`), e.g.
/// `&[40_000.0]` for twice the 20 kHz carrier.
pub fn design_with_probes(
    spec: &FilterSpec,
    fmt: CoefFormat,
    probes_hz: &[f64],
) -> Result<Designed, FilterError> {
    spec.validate()?;
    fmt.validate()?;
    for &f in probes_hz {
        if !(f.is_finite() && f >= 0.0 && f <= spec.sample_rate_hz / 2.0) {
            return Err(spec.invalid(
                "probe frequency",
                format!(
                    "{f} Hz must be in [0, fs/2 = {} Hz]",
                    spec.sample_rate_hz / 2.0
                ),
            ));
        }
    }
    let ideal = design_ideal(spec)?;
    let sos = quantize_sections(spec, &ideal, fmt)?;
    let response = Response::compute(spec, &ideal, &sos, probes_hz);
    Ok(Designed {
        spec: spec.clone(),
        ideal,
        sos,
        response,
    })
}

impl Designed {
    /// Markdown: the spec, the integer coefficients and the response table.
    pub fn to_markdown(&self) -> String {
        format!(
            "Filter: {} ({} sections).\n\n{}\n{}",
            self.spec,
            self.sos.sections.len(),
            self.sos.to_markdown(),
            self.response.to_markdown()
        )
    }
}
