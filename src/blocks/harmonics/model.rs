//! Bit-accurate model of the harmonic-correction block: the sample function
//! [`correct`] and the cycle model [`HarmonicModel`].
use super::{HarmonicParams, INTERP_BITS};
use crate::blocks::mask;
use std::collections::VecDeque;

/// The corrected angle z' of the angle word `z` (module doc of `crate::blocks::harmonics`),
/// computed as the RTL does: modulo 2^W sums, then the shift.
pub fn correct(p: &HarmonicParams, z: u64) -> u64 {
    let (zw, r) = (p.z_width, INTERP_BITS);
    let w = mask(zw + r);
    let z = z & mask(zw);
    let idx = (z >> (zw - p.points_log2)) as usize;
    let f = (z >> (zw - p.points_log2 - r)) & mask(r);
    let t = p.rom_t()[idx];
    let d = p.rom_d()[idx];
    let y = ((z << r).wrapping_sub(t)) & w;
    let sum = (0..r)
        .filter(|k| f >> k & 1 == 1)
        .fold(0u64, |s, k| s.wrapping_add(d << k) & w);
    ((y.wrapping_sub(sum) & w) >> r) & mask(zw)
}

/// The combiner's output for the CORDIC's result `c` with the table between them: the
/// RTL's angle word (the quadrant and the rounding half in it, as the CORDIC starts its
/// angle), corrected, then p = z' >> Gz as the combiner takes it.
pub fn combine_corrected(
    d: &crate::blocks::params::Derived,
    p: &HarmonicParams,
    c: &crate::blocks::cordic::model::CordicOut,
) -> crate::blocks::counter::model::Combined {
    let f = d.fine_bits;
    let z = (c.z + (1 << (d.z_guard - 1)) + ((c.q as u64) << (f + d.z_guard))) & mask(d.z_width);
    crate::blocks::counter::model::Combined {
        p: (correct(p, z) >> d.z_guard) & mask(f + 2),
        mag_ok: c.x >= d.min_magnitude,
    }
}

/// Inputs of one clock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HarmonicIn {
    /// Synchronous reset.
    pub rst: bool,
    /// The angle word (ZW bits).
    pub z: u64,
    /// The magnitude carried along (32 bits).
    pub x: u64,
    /// Valid.
    pub v: bool,
}

impl HarmonicIn {
    /// The row of input port values (`HarmonicCorrection`'s port order).
    pub fn row(&self) -> Vec<u64> {
        vec![self.rst as u64, self.z, self.x, self.v as u64]
    }
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HarmonicOut {
    /// z_out.
    pub z: u64,
    /// x_out.
    pub x: u64,
    /// v_out.
    pub v: bool,
}

impl HarmonicOut {
    /// The row of output port values.
    pub fn row(&self) -> Vec<u64> {
        vec![self.z, self.x, self.v as u64]
    }
}

/// The block cycle by cycle: a delay line of [`HarmonicParams::LATENCY`] stages holding
/// each sample's result, zero at power-up, the valid bits cleared by `rst`.
#[derive(Clone, Debug)]
pub struct HarmonicModel {
    p: HarmonicParams,
    line: VecDeque<HarmonicOut>,
}

impl HarmonicModel {
    /// The block at power-up.
    pub fn new(p: &HarmonicParams) -> Self {
        HarmonicModel {
            p: p.clone(),
            line: (0..HarmonicParams::LATENCY)
                .map(|_| HarmonicOut::default())
                .collect(),
        }
    }

    /// One clock: inputs before the edge, outputs after it.
    pub fn step(&mut self, i: HarmonicIn) -> HarmonicOut {
        self.line.pop_back();
        if i.rst {
            self.line.iter_mut().for_each(|s| s.v = false);
        }
        self.line.push_front(HarmonicOut {
            z: correct(&self.p, i.z),
            x: i.x & mask(32),
            v: i.v && !i.rst,
        });
        self.line[self.line.len() - 1]
    }
}
