//! Harmonic correction: a table of angle corrections against the angle within the signal
//! period, linearly interpolated and subtracted from the CORDIC's angle before the
//! combiner rounds it and the counter counts it (issue 46; docs/correction.md, "Harmonic
//! distortion").
//!
//! ```text
//!            ┌──────────┐  T, D   ┌──────────────┐ s0..s3 ┌───────┐ s01,s23 ┌───────┐ sum ┌──────────┐
//!  z_in ────►│ ROM_T    ├────────►│ 8 partial    ├───────►│ add   ├────────►│ add   ├────►│ y - sum  ├─► z_out
//!  (ZW b)    │ ROM_D    │ f       │ products of  │ y      │ pairs │ y       │ pair  │ y   │ >> R     │
//!            │ [idx]    │ y=z<<R-T│ D x f, pairs │        │       │         │       │     │ mod 2^ZW │
//!  x_in,v_in └──reg─────┘         └──reg─────────┘        └──reg──┘         └──reg──┘     └──reg─────┘─► x_out, v_out
//!  cycle:        1                    2                      3                 4              5
//! ```
//!
//! Angle word. The CORDIC's z holds the angle within one signal period (four quadrants) in
//! ZW = F + Gz + 2 bits, units 2^-(F+Gz) quadrant ("z units": 2^-Gz position LSB), plus
//! the combiner's rounding half 2^(Gz-1). The table has P = 2^p entries (P = `points`,
//! 16..=256) over the period: entry i is the correction c_i (z units, integer) at angle
//! i 2^(ZW-p), the decoded angle's error there. For a sample
//!
//! ```text
//! idx = z >> (ZW - p)                       (p bits: the segment)
//! f   = (z >> (ZW - p - R)) mod 2^R         (R = 8 bits: the place within it)
//! c   = c_idx + D_idx f / 2^R,  D_i = c_(i+1 mod P) - c_i
//! z'  = floor(z - c + 1/2) mod 2^ZW
//! ```
//!
//! Bit growth. Every sum is taken modulo 2^W, W = ZW + R (<= 32, so ZW <= 24): y = z 2^R -
//! (c_idx 2^R - 2^(R-1)) (the half rounds), the 8 partial products D 2^k (bit k of f set)
//! in a tree of adders, and z' = (y - sum) >> R mod 2^ZW. The result is exact modulo 2^ZW as
//! long as the true value of y - sum, z 2^R - c 2^R + 2^(R-1), is taken modulo 2^W, which
//! modular adders do; no word needs a sign fill. The entries are bounded by |c_i| <=
//! 2^(F-4) LSB (1/16 quadrant, 0.098 rad electrical: a 10 % harmonic), so no correction
//! moves the angle by more than a sixteenth of a quadrant and |D| < 2^(F+Gz-3).
//!
//! Error bound, against the exact interpolation c_idx + D u of the table (u in [0, 1) the
//! exact place in the segment): f truncates u to R bits, at most |D| 2^-R z units, and the
//! result rounds to the z unit, at most 1/2: |z' - (z - c_exact)| <= max|D_i| 2^-R + 1/2
//! z units = (max|D_i| 2^-8 + 1/2) 2^-Gz LSB ([`HarmonicParams::bound_lsb`]). Entries from
//! a config (position LSB, real) round to the z unit: 1/2 more. The interpolation of a
//! smooth correction c(x) itself is within (2 pi / P)^2 / 8 max|c''| of it: a correction
//! of amplitude a at k cycles per period, (2 pi k / P)^2 a / 8 (P = 64, k = 4: 0.019 a).
//!
//! Latency [`HarmonicParams::LATENCY`] = 5 clocks: the ROMs (a LUT lookup from the CORDIC's
//! register), the partial products and the first adders, two adder levels, the final
//! subtract; one carry chain per register stage. One sample per clock; x and v travel with
//! z, v cleared by `rst`.
//!
//! The table in RAM (`mode = "learn"`, [`hdl_ram::HarmonicCorrectionRam`]). The learned
//! table lives in two copies of a RAM of two banks (bank b, entry i at address b P + i;
//! 256 words, so P <= [`hdl_ram::MAX_POINTS`] = 128; each four arrays of 64 words, four
//! Cyclone M9Ks), one read at the segment i, one at i + 1 mod P, so that one read gives c_i
//! and c_(i+1) of the bank the learner names. They hold c_i modulo 2^ZW (z units): the
//! learner's writes arrive in q units (2^-T LSB, T = [`sequencer::TABLE_FRAC`]) and the
//! write stage rounds them, c = floor(q 2^(Gz-T) + 1/2), a sign fill and the half in one
//! adder. Then y = (z - c_i) 2^R + 2^(R-1) and D = c_(i+1) - c_i (a ZW-bit difference,
//! sign-filled to W bits since |D| < 2^(F+Gz-3)) are the static block's y and D modulo
//! 2^W, and the same partial products follow: [`HarmonicParams::LATENCY_RAM`] = 8 clocks
//! (the RAM's read address register, its read over two clocks, four arrays' words into
//! registers and then one of them selected and registered, so that no adder follows a RAM
//! read in the same clock, then the slope's subtract in a stage of its own). A bank the
//! lookup reads changes only when the learner flips `bank` (at its Apply). The RAMs have no
//! initial contents (Yosys 0.23 cannot map a RAM with them to an M9K): after a reset the
//! learner's Clear writes the start table into both banks, and while it does (`clearing`,
//! and one clock more for the write stage) the lookup uses zeros, so that no simulator ever
//! reads an unwritten word.
//!
//! Ports (rust-hdl block [`hdl::HarmonicCorrection`], 32-bit words with the widths above in
//! their low bits):
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clk` | in | 1 | system clock |
//! | `rst` | in | 1 | synchronous reset: clears the valid bits in flight |
//! | `z_in` | in | ZW | the CORDIC's angle (z units, with the rounding half) |
//! | `x_in` | in | W | the CORDIC's magnitude, carried along |
//! | `v_in` | in | 1 | the sample is valid |
//! | `z_out` | out | ZW | the corrected angle, 5 clocks later |
//! | `x_out` | out | W | `x_in` 5 clocks later |
//! | `v_out` | out | 1 | `v_in` 5 clocks later (0 after `rst`) |
pub mod block;
pub mod hdl;
pub mod hdl_ram;
pub mod learn;
pub mod learned;
pub mod learner;
pub mod model;
pub mod sequencer;

use crate::blocks::mask;

pub use block::BLOCK;

/// Bits of the place within a segment (the interpolation's fraction).
pub const INTERP_BITS: u32 = 8;

/// Fewest and most table entries.
pub const POINTS_RANGE: std::ops::RangeInclusive<u32> = 16..=256;

/// The table and the widths of one harmonic-correction block.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct HarmonicParams {
    /// ZW: bits of the angle word (F + Gz + 2).
    pub z_width: u32,
    /// Gz: guard bits of the angle below the position LSB.
    pub z_guard: u32,
    /// F: fine bits of the position.
    pub fine_bits: u32,
    /// log2 of the number of entries P.
    pub points_log2: u32,
    /// The entries c_i, z units (2^-Gz position LSB); zeros with `learn` (the learning's
    /// start).
    pub table: Vec<i64>,
    /// The learner's formats when the table is learned online (`mode = "learn"`: the
    /// table in RAM, [`hdl_ram`]), else none (a fixed table in logic, [`hdl`]).
    #[serde(skip)]
    pub learn: Option<sequencer::LearnParams>,
}

impl HarmonicParams {
    /// Clocks from `z_in` to `z_out` (the one place the latency is stated).
    pub const LATENCY: u32 = 5;

    /// Clocks from `z_in` to `z_out` with the table in RAM (the learned table): the RAM's
    /// read address register, its read over two clocks (the arrays' words registered, then
    /// the selected word), then the slope's subtract before the partial products.
    pub const LATENCY_RAM: u32 = 8;

    /// The block for a ZW-bit angle with Gz guard bits and F fine bits, and the table
    /// `table_lsb` (position LSB, one entry per point of the period from angle 0); the
    /// message says what is allowed when something is not.
    pub fn new(
        z_width: u32,
        z_guard: u32,
        fine_bits: u32,
        table_lsb: &[f64],
    ) -> Result<Self, String> {
        let n = table_lsb.len() as u32;
        if !(POINTS_RANGE.contains(&n) && n.is_power_of_two()) {
            return Err(format!(
                "{n} entries: allowed a power of two from {} to {}",
                POINTS_RANGE.start(),
                POINTS_RANGE.end()
            ));
        }
        if z_width + INTERP_BITS > 32 || z_width != fine_bits + z_guard + 2 {
            return Err(format!(
                "an angle word of {z_width} bits (F = {fine_bits}, Gz = {z_guard}): the table needs F + Gz + 2 <= {}",
                32 - INTERP_BITS
            ));
        }
        let max = Self::max_entry_lsb(fine_bits);
        let mut table = Vec::with_capacity(table_lsb.len());
        for (i, &v) in table_lsb.iter().enumerate() {
            if !(v.is_finite() && v.abs() <= max) {
                return Err(format!(
                    "entry {i} = {v} LSB: allowed -{max}..={max} LSB (2^(F-4), a sixteenth of a quadrant)"
                ));
            }
            table.push((v * (1u64 << z_guard) as f64).round() as i64);
        }
        Ok(HarmonicParams {
            z_width,
            z_guard,
            fine_bits,
            points_log2: n.trailing_zeros(),
            table,
            learn: None,
        })
    }

    /// The learned block of `points` entries, learned by `learn`'s learner from a zero
    /// table; the message says what is allowed when something is not.
    pub fn learned(
        z_width: u32,
        z_guard: u32,
        fine_bits: u32,
        points: u32,
        learn: sequencer::LearnParams,
    ) -> Result<Self, String> {
        let mut p = Self::new(z_width, z_guard, fine_bits, &vec![0.0; points as usize])?;
        if z_guard > sequencer::TABLE_FRAC {
            return Err(format!(
                "{z_guard} guard bits below the LSB: the learned table needs at most {}",
                sequencer::TABLE_FRAC
            ));
        }
        p.learn = Some(learn);
        Ok(p)
    }

    /// Clocks from `z_in` to `z_out`: [`Self::LATENCY`], or [`Self::LATENCY_RAM`] with the
    /// learned table.
    pub fn latency(&self) -> u32 {
        if self.learn.is_some() {
            Self::LATENCY_RAM
        } else {
            Self::LATENCY
        }
    }

    /// The largest |entry|, position LSB: 2^(F-4).
    pub fn max_entry_lsb(fine_bits: u32) -> f64 {
        (1u64 << fine_bits.saturating_sub(4)) as f64
    }

    /// P, the number of entries.
    pub fn points(&self) -> u32 {
        1 << self.points_log2
    }

    /// W = ZW + R: the width of the block's sums.
    pub fn word_width(&self) -> u32 {
        self.z_width + INTERP_BITS
    }

    /// D_i = c_(i+1 mod P) - c_i, z units.
    pub fn slopes(&self) -> Vec<i64> {
        let n = self.table.len();
        (0..n)
            .map(|i| self.table[(i + 1) % n] - self.table[i])
            .collect()
    }

    /// ROM_T: c_i 2^R - 2^(R-1) modulo 2^W (the entry with the rounding half).
    pub fn rom_t(&self) -> Vec<u64> {
        let w = mask(self.word_width());
        self.table
            .iter()
            .map(|&c| ((c << INTERP_BITS) - (1 << (INTERP_BITS - 1))) as u64 & w)
            .collect()
    }

    /// ROM_D: D_i modulo 2^W.
    pub fn rom_d(&self) -> Vec<u64> {
        let w = mask(self.word_width());
        self.slopes().iter().map(|&d| d as u64 & w).collect()
    }

    /// The error bound of the block against the exact linear interpolation of its table,
    /// position LSB: (max|D_i| 2^-R + 1/2) 2^-Gz (module doc).
    pub fn bound_lsb(&self) -> f64 {
        let dmax = self
            .slopes()
            .iter()
            .map(|d| d.unsigned_abs())
            .max()
            .unwrap_or(0);
        (dmax as f64 / (1u64 << INTERP_BITS) as f64 + 0.5) / (1u64 << self.z_guard) as f64
    }
}
