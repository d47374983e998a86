//! Predicted error figures and the thesis's own figures.
use crate::config::Derived;
use std::f64::consts::{FRAC_PI_2, PI};

/// Predicted error of one design, in fine LSB (2^-F quadrant).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Predicted {
    /// CORDIC residual bound (2/pi) atan(2^-(N-1)) 2^F: the angle the N stages cannot
    /// resolve.
    pub residual_lsb: f64,
    /// Quantization RMS as ZipCPU's cordic generator (`phase_variance` in sw/cordiclib.cpp)
    /// estimates it: sqrt(1/12 + sum over the stages of the squared rounding error of the
    /// angle table entry), here in units of the output LSB (our table is rounded, ZipCPU's
    /// truncated; the measured table errors are used).
    pub quant_rms_lsb: f64,
    /// RMS prediction: quantization variance plus the residual taken as uniform within
    /// +-residual (residual^2 / 3).
    pub rms_lsb: f64,
}

/// Predicted error figures of a design.
pub fn predict(d: &Derived) -> Predicted {
    let f = d.fine_bits;
    let n = d.iterations;
    let residual_lsb = (2.0 / PI) * 2f64.powi(1 - n as i32).atan() * (1u64 << f) as f64;
    let unit = (1u64 << (f + d.z_guard)) as f64;
    let table_var: f64 = d
        .atan_table
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let exact = 2f64.powi(-(i as i32)).atan() / FRAC_PI_2 * unit;
            let e = (t as f64 - exact) / (1u64 << d.z_guard) as f64;
            e * e
        })
        .sum();
    let quant_var = 1.0 / 12.0 + table_var;
    Predicted {
        residual_lsb,
        quant_rms_lsb: quant_var.sqrt(),
        rms_lsb: (quant_var + residual_lsb * residual_lsb / 3.0).sqrt(),
    }
}

/// Thesis Table 3-2: (N, gates, cycles) of its unrolled QEP-CORDIC on the XC3S700AN.
pub const THESIS_TABLE_3_2: [(u32, u64, u32); 5] = [
    (2, 313, 8),
    (5, 4231, 11),
    (8, 8782, 14),
    (11, 13177, 17),
    (14, 17521, 20),
];

/// Thesis Table 2-2: (N, max error as a fraction of a quadrant, max error in mechanical
/// degrees at 2048 PPR, resolution bits per turn). The text gives the fractions
/// (+-0.24853 %, +-0.01552 %, +-3.8674e-5) and converts them as 360/2048/4 x fraction.
pub const THESIS_TABLE_2_2: [(u32, f64, f64, u32); 3] = [
    (8, 2.4853e-3, 1.0921e-4, 21),
    (12, 1.552e-4, 6.8203e-6, 25),
    (14, 3.8674e-5, 1.7000e-6, 27),
];

/// PPR of the thesis's encoder (Table 2-2 is for it).
pub const THESIS_PPR: u32 = 2048;

/// Table 3-2 row for N, if the thesis has one.
pub fn thesis_gates(n: u32) -> Option<(u64, u32)> {
    THESIS_TABLE_3_2
        .iter()
        .find(|r| r.0 == n)
        .map(|r| (r.1, r.2))
}

/// Table 2-2 row for N, if the thesis has one: (fraction of a quadrant, mechanical
/// degrees at 2048 PPR, bits per turn).
pub fn thesis_error(n: u32) -> Option<(f64, f64, u32)> {
    THESIS_TABLE_2_2
        .iter()
        .find(|r| r.0 == n)
        .map(|r| (r.1, r.2, r.3))
}
