//! Errors of the filter designer.

/// Errors of the filter designer (the integrator wraps them in the crate error).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilterError {
    /// The filter specification is not valid.
    #[error("filter `{filter}`: `{field}`: {message}")]
    InvalidSpec {
        /// The filter, as [`super::FilterSpec`]'s `Display`.
        filter: String,
        /// The offending field.
        field: &'static str,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// The coefficient format is not valid.
    #[error("coefficient format width {width}, frac {frac}: {message}")]
    InvalidFormat {
        /// Total bits.
        width: u32,
        /// Fractional bits.
        frac: u32,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A coefficient does not fit the format.
    #[error(
        "filter `{filter}`: section {section} coefficient {coef} = {value} does not fit \
         {width}-bit two's complement with {frac} fractional bits (range {min} ..= {max}); \
         use more integer bits"
    )]
    CoefficientOverflow {
        /// The filter, as [`super::FilterSpec`]'s `Display`.
        filter: String,
        /// 0-based section index.
        section: usize,
        /// `b0`, `b1`, `b2`, `a1` or `a2`.
        coef: &'static str,
        /// The real value that overflowed.
        value: f64,
        /// Smallest representable value.
        min: f64,
        /// Largest representable value.
        max: f64,
        /// Total bits.
        width: u32,
        /// Fractional bits.
        frac: u32,
    },
    /// A section has a pole on or outside the unit circle.
    #[error(
        "filter `{filter}`: {stage} section {section} is unstable: pole radius {radius} >= 1 \
         (a1 = {a1}, a2 = {a2}; stable needs |a2| < 1 and |a1| < 1 + a2){hint}"
    )]
    UnstableSection {
        /// The filter, as [`super::FilterSpec`]'s `Display`.
        filter: String,
        /// `quantized` or `ideal` (the latter only on f64 breakdown).
        stage: &'static str,
        /// 0-based section index.
        section: usize,
        /// Largest pole modulus of the section.
        radius: f64,
        /// The section's a1 (real value).
        a1: f64,
        /// The section's a2 (real value).
        a2: f64,
        /// Advice appended to the message.
        hint: &'static str,
    },
    /// A section's numerator gain rounds to zero: the filter would output nothing.
    #[error(
        "filter `{filter}`: section {section} gain {gain} rounds to 0 with {frac} fractional \
         bits; use more fractional bits"
    )]
    GainUnderflow {
        /// The filter, as [`super::FilterSpec`]'s `Display`.
        filter: String,
        /// 0-based section index.
        section: usize,
        /// The ideal section gain `g`.
        gain: f64,
        /// Fractional bits.
        frac: u32,
    },
}
