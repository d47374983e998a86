//! Bit-accurate model of the quadrant mapper and the CORDIC stages.
use crate::blocks::params::Derived;
use crate::blocks::{mask, sext};

/// Result of the mapper + N stages for one sample: what reaches the combiner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CordicOut {
    /// Quadrant 0..3 from the sign bits.
    pub q: u8,
    /// Final x (W-bit, unsigned view): K_N |v| 2^G.
    pub x: u64,
    /// Final angle z (ZW-bit, raw two's complement).
    pub z: u64,
}

/// Quadrant of a sample from its sign bits (see the module docs).
#[inline]
pub fn quadrant(sin: i32, cos: i32) -> u8 {
    let s = (sin < 0) as u8;
    let c = (cos < 0) as u8;
    (s << 1) | (s ^ c)
}

/// Mapped first-quadrant vector (x', y') of a sample (Table 2-3).
#[inline]
pub fn map(sin: i32, cos: i32) -> (i64, i64) {
    let (x, y) = (cos as i64, sin as i64);
    match quadrant(sin, cos) {
        0 => (x, y),
        1 => (y, -x),
        2 => (-x, -y),
        _ => (-y, x),
    }
}

/// Runs the mapper and the N stages on one sample (inputs already within A bits).
#[inline]
pub fn cordic(d: &Derived, sin: i32, cos: i32) -> CordicOut {
    let w = d.xy_width;
    let zw = d.z_width;
    let q = quadrant(sin, cos);
    let (mx, my) = map(sin, cos);
    let mut x = sext(((mx << d.xy_guard) as u64) & mask(w), w);
    let mut y = sext(((my << d.xy_guard) as u64) & mask(w), w);
    let mut z: i64 = 0;
    for (i, &a) in d.atan_table.iter().enumerate() {
        let xs = x >> i;
        let ys = y >> i;
        if y < 0 {
            x = sext((x - ys) as u64 & mask(w), w);
            y = sext((y + xs) as u64 & mask(w), w);
            z = sext((z - a as i64) as u64 & mask(zw), zw);
        } else {
            x = sext((x + ys) as u64 & mask(w), w);
            y = sext((y - xs) as u64 & mask(w), w);
            z = sext((z + a as i64) as u64 & mask(zw), zw);
        }
    }
    CordicOut {
        q,
        x: x as u64 & mask(w),
        z: z as u64 & mask(zw),
    }
}
