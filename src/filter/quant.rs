//! Quantization of ideal sections to a [`CoefFormat`], with overflow, stability and
//! zero-gain checks.

use super::{CoefFormat, FilterError, FilterSpec, IdealSection, Section, Sos};

/// `round_half_away(x * 2^frac)` as an integer-valued f64. Exact: the power-of-two scale is
/// exact in binary floating point and `f64::round` rounds half away from zero exactly.
pub fn round_half_away(x: f64, frac: u32) -> f64 {
    (x * 2f64.powi(frac as i32)).round()
}

/// Quantizes `ideal` (from [`super::design_ideal`] for `spec`) to `fmt`.
///
/// Per section: `A1 = round_half_away(a1 2^frac)`, `A2 = round_half_away(a2 2^frac)`, the
/// numerator gain `G = round_half_away(b0 2^frac)` and `B = G * P` with the exact integer
/// zero pattern `P = b / b0` (`[1, +-2, 1]`, `[1, 0, -1]`, `[1, +-1, 0]`), so the quantized
/// zeros stay at `z = +-1`. Rejects, naming the filter and the section: a coefficient outside
/// `[-2^(width-1), 2^(width-1) - 1]` ([`FilterError::CoefficientOverflow`]), a section whose
/// quantized poles are not strictly inside the unit circle ([`FilterError::UnstableSection`],
/// exact integer triangle test), both checked section by section in cascade order, and then
/// `G = 0` in any section ([`FilterError::GainUnderflow`]).
pub fn quantize_sections(
    spec: &FilterSpec,
    ideal: &[IdealSection],
    fmt: CoefFormat,
) -> Result<Sos, FilterError> {
    fmt.validate()?;
    let (min, max) = (fmt.min_int(), fmt.max_int());
    let mut sections = Vec::with_capacity(ideal.len());
    for (i, s) in ideal.iter().enumerate() {
        let g = s.b[0];
        // The zero pattern is a small exact integer vector: b = g * P.
        let pattern = s.b.map(|c| (c / g).round() as i128);
        let gq = round_half_away(g, fmt.frac);
        let overflow = |coef: &'static str, value: f64| FilterError::CoefficientOverflow {
            filter: spec.to_string(),
            section: i,
            coef,
            value,
            min: min as f64 / fmt.scale(),
            max: max as f64 / fmt.scale(),
            width: fmt.width,
            frac: fmt.frac,
        };
        // Range checks in f64 first (|x| may exceed i128 only for absurd inputs).
        let in_range = |q: f64| q >= min as f64 && q < (max as f64) + 1.0;
        let mut b = [0i64; 3];
        for (k, name) in ["b0", "b1", "b2"].into_iter().enumerate() {
            let q = if in_range(gq) {
                gq as i128 * pattern[k]
            } else {
                return Err(overflow(name, g * pattern[k] as f64));
            };
            if q < min || q > max {
                return Err(overflow(name, q as f64 / fmt.scale()));
            }
            b[k] = q as i64;
        }
        let mut a = [0i64; 2];
        for (k, name) in ["a1", "a2"].into_iter().enumerate() {
            let q = round_half_away(s.a[k], fmt.frac);
            if !in_range(q) {
                return Err(overflow(name, s.a[k]));
            }
            a[k] = q as i64;
        }
        let sec = Section { b, a };
        if !sec.is_stable(fmt) {
            return Err(FilterError::UnstableSection {
                filter: spec.to_string(),
                stage: "quantized",
                section: i,
                radius: sec.pole_radius(fmt),
                a1: fmt.to_real(a[0]),
                a2: fmt.to_real(a[1]),
                hint: "; use more fractional bits",
            });
        }
        sections.push(sec);
    }
    // Second pass, so that an unstable section anywhere is reported before a zero gain.
    for (i, (s, q)) in ideal.iter().zip(&sections).enumerate() {
        if q.b[0] == 0 {
            return Err(FilterError::GainUnderflow {
                filter: spec.to_string(),
                section: i,
                gain: s.b[0],
                frac: fmt.frac,
            });
        }
    }
    Ok(Sos {
        sections,
        format: fmt,
    })
}
