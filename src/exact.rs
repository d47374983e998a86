//! Exact constants with `num-bigint`: pi, the arctangent table atan(2^-i) scaled to a
//! fraction of a quadrant, and the CORDIC gain.
//!
//! Everything is computed in fixed point with `WORK` fractional bits (far more than any
//! table needs) and rounded once at the end, so a table entry is the correctly rounded
//! value of the real number, independent of `f64`.
//!
//! * pi by Machin's formula: pi/4 = 4 atan(1/5) - atan(1/239).
//! * atan(1/k) by its Taylor series sum (-1)^j / ((2j+1) k^(2j+1)); each term is
//!   floored, so the sum is within (terms) ulps of the truth; `WORK` leaves 64 bits
//!   of margin above the output precision.
//! * The gain after n stages is K_n = prod_{i<n} sqrt(1 + 2^-2i)
//!   = sqrt(prod (4^i + 1) / 4^(sum i)), an integer square root of an exact rational.

use num_bigint::BigInt;
use num_traits::{One, Signed, ToPrimitive, Zero};

/// Fractional bits used internally for every series.
const WORK: u32 = 192;

/// atan(1/k) * 2^WORK (k >= 2), by the Taylor series.
fn atan_inv(k: u64) -> BigInt {
    let one = BigInt::one() << WORK;
    let k = BigInt::from(k);
    let k2 = &k * &k;
    let mut power = &one / &k; // 1/k^(2j+1) scaled
    let mut sum = BigInt::zero();
    let mut j: u64 = 0;
    while !power.is_zero() {
        let term = &power / BigInt::from(2 * j + 1);
        if j.is_multiple_of(2) {
            sum += term;
        } else {
            sum -= term;
        }
        power /= &k2;
        j += 1;
    }
    sum
}

/// pi * 2^WORK.
pub fn pi_fixed() -> BigInt {
    (atan_inv(5) * 16) - (atan_inv(239) * 4)
}

/// atan(2^-i) * 2^WORK.
fn atan_pow2_fixed(i: u32) -> BigInt {
    if i == 0 {
        return pi_fixed() / 4;
    }
    // atan(x) = sum (-1)^j x^(2j+1)/(2j+1), x = 2^-i.
    let mut sum = BigInt::zero();
    let mut j: u32 = 0;
    loop {
        let exp = i * (2 * j + 1);
        if exp > WORK {
            break;
        }
        let term = (BigInt::one() << (WORK - exp)) / BigInt::from(2 * j + 1);
        if j.is_multiple_of(2) {
            sum += term;
        } else {
            sum -= term;
        }
        j += 1;
    }
    sum
}

/// Rounds `num / den` to the nearest integer (ties away from zero); den > 0.
fn div_round(num: &BigInt, den: &BigInt) -> BigInt {
    let twice = num * 2;
    (&twice + if num.is_negative() { -den } else { den.clone() }) / (den * 2)
}

/// round(atan(2^-i) / (pi/2) * 2^frac_bits) for i in 0..n: the CORDIC angle table in
/// units of 2^-frac_bits quadrant.
pub fn atan_table_quadrant(n: u32, frac_bits: u32) -> Vec<u64> {
    let pi = pi_fixed();
    (0..n)
        .map(|i| {
            let num = atan_pow2_fixed(i) << (frac_bits + 1);
            div_round(&num, &pi).to_u64().unwrap_or(u64::MAX)
        })
        .collect()
}

/// CORDIC gain after `n` stages as f64 (exactly rounded from the big-integer value).
pub fn cordic_gain(n: u32) -> f64 {
    let g = cordic_gain_fixed(n, 60);
    g.to_f64().unwrap_or(f64::NAN) / (1u64 << 60) as f64
}

/// floor(K_n * 2^frac_bits), K_n = prod_{i<n} sqrt(1 + 2^-2i).
pub fn cordic_gain_fixed(n: u32, frac_bits: u32) -> BigInt {
    let mut p = BigInt::one();
    let mut shift: u32 = 0;
    for i in 0..n {
        p *= (BigInt::one() << (2 * i)) + 1;
        shift += 2 * i;
    }
    // K * 2^b = sqrt(p * 2^(2b) / 2^shift)
    let scaled = (p << (2 * frac_bits)) >> shift;
    scaled.sqrt()
}

/// ceil(K_n * v) for a non-negative integer v: smallest integer >= the gain times v.
pub fn gain_times_ceil(n: u32, v: u64) -> u64 {
    let fb = 64;
    let g = cordic_gain_fixed(n, fb) + 1; // upper bound of K * 2^fb
    let prod = g * BigInt::from(v);
    let one = BigInt::one() << fb;
    let q: BigInt = (&prod + &one - 1) / &one;
    q.to_u64().unwrap_or(u64::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pi_matches_known_digits() {
        // pi in hexadecimal is 3.243F6A8885A308D313198A2E0370734...; compare the first 26
        // fraction digits (104 bits).
        let pi = pi_fixed() >> (WORK - 104);
        let expect = BigInt::parse_bytes(b"3243F6A8885A308D313198A2E03", 16).unwrap_or_default();
        assert_eq!(pi, expect);
    }

    #[test]
    fn atan_table_matches_f64() {
        let t = atan_table_quadrant(20, 30);
        for (i, v) in t.iter().enumerate() {
            let f = (2f64.powi(-(i as i32))).atan() / std::f64::consts::FRAC_PI_2 * 2f64.powi(30);
            assert!((*v as f64 - f).abs() <= 0.5 + 1e-6, "i={i} {v} vs {f}");
        }
        // atan(1) = pi/4 is exactly half a quadrant.
        assert_eq!(t[0], 1 << 29);
    }

    #[test]
    fn gain_matches_known_value() {
        // K_inf = 1.646760258121065648366...
        assert!((cordic_gain(30) - 1.646_760_258_121_065_6).abs() < 1e-15);
        assert!((cordic_gain(1) - std::f64::consts::SQRT_2).abs() < 1e-15);
        assert_eq!(gain_times_ceil(1, 100), 142); // 141.42..
    }
}
