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

/// The corrected angle of the angle word `z` from the entries `a` = c_i and `b` = c_(i+1)
/// of its segment (z units modulo 2^ZW), as [`super::hdl_ram::HarmonicCorrectionRam`]
/// computes it: y = (z - a) 2^R + 2^(R-1), D = b - a sign-filled from ZW to W bits, the
/// partial products of D f modulo 2^W, then the shift.
pub fn correct_ab(zw: u32, points_log2: u32, z: u64, a: u64, b: u64) -> u64 {
    let r = INTERP_BITS;
    let w = mask(zw + r);
    let z = z & mask(zw);
    let y = ((z.wrapping_sub(a) & mask(zw)) << r | 1 << (r - 1)) & w;
    let dz = b.wrapping_sub(a) & mask(zw);
    let d = if dz >> (zw - 1) & 1 == 1 {
        dz | (w & !mask(zw))
    } else {
        dz
    };
    let f = (z >> (zw - points_log2 - r)) & mask(r);
    let sum = (0..r)
        .filter(|k| f >> k & 1 == 1)
        .fold(0u64, |s, k| s.wrapping_add(d << k) & w);
    ((y.wrapping_sub(sum) & w) >> r) & mask(zw)
}

/// An entry of the learner's table on the write port (q units, two's complement in
/// `entry_width` bits) in z units modulo 2^ZW, as the write stage converts it: a sign fill
/// and the rounding half in one modulo-2^32 adder, then the shift by s = T - Gz.
pub fn q_to_z(p: &HarmonicParams, entry_width: u32, q: u64) -> u64 {
    let s = super::sequencer::TABLE_FRAC - p.z_guard;
    let m = 1u64 << (entry_width - 1);
    let half = if s == 0 { 0 } else { 1u64 << (s - 1) };
    ((((q & mask(32)) ^ m).wrapping_add(half.wrapping_sub(m)) & mask(32)) >> s) & mask(p.z_width)
}

/// Inputs of one clock of the block with its table in RAM.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HarmonicRamIn {
    /// The lookup's inputs.
    pub core: HarmonicIn,
    /// The bank the lookup reads.
    pub bank: bool,
    /// Write an entry.
    pub tw: bool,
    /// bank * P + i.
    pub tw_addr: u64,
    /// The entry, q units.
    pub tw_data: u64,
}

impl HarmonicRamIn {
    /// The row of input port values (`HarmonicCorrectionRam`'s port order).
    pub fn row(&self) -> Vec<u64> {
        let mut r = self.core.row();
        r.extend([self.bank as u64, self.tw as u64, self.tw_addr, self.tw_data]);
        r
    }
}

/// The block with its table in RAM, cycle by cycle: two banks of the table (z units), the
/// write stage (one clock), the read at the edge before the write it holds, and a delay
/// line of [`HarmonicParams::LATENCY_RAM`] stages.
#[derive(Clone, Debug)]
pub struct HarmonicRamModel {
    p: HarmonicParams,
    entry_width: u32,
    banks: [Vec<u64>; 2],
    /// The write stage: the RAM address's bank and entry, the value in z units.
    write: Option<(usize, usize, u64)>,
    line: VecDeque<HarmonicOut>,
}

impl HarmonicRamModel {
    /// The block at power-up: the start table in both banks.
    pub fn new(p: &HarmonicParams, entry_width: u32) -> Self {
        let t: Vec<u64> = p
            .table
            .iter()
            .map(|&c| c as u64 & mask(p.z_width))
            .collect();
        HarmonicRamModel {
            p: p.clone(),
            entry_width,
            banks: [t.clone(), t],
            write: None,
            line: (0..HarmonicParams::LATENCY_RAM)
                .map(|_| HarmonicOut::default())
                .collect(),
        }
    }

    /// Entry `i` of `bank`, z units modulo 2^ZW.
    pub fn entry(&self, bank: usize, i: usize) -> u64 {
        self.banks[bank][i]
    }

    /// One clock: inputs before the edge, outputs after it.
    pub fn step(&mut self, i: HarmonicRamIn) -> HarmonicOut {
        let (zw, pb) = (self.p.z_width, self.p.points_log2);
        let n = self.p.points() as u64;
        let z = i.core.z & mask(zw);
        let idx = (z >> (zw - pb)) & (n - 1);
        let bank = &self.banks[i.bank as usize];
        let (a, b) = (bank[idx as usize], bank[((idx + 1) % n) as usize]);
        if let Some((bk, e, v)) = self.write.take() {
            self.banks[bk][e] = v;
        }
        if i.tw {
            // The RAM address keeps bit p of tw_addr (the bank) and its low p bits.
            let bk = ((i.tw_addr & mask(32)) >> pb) & 1;
            let e = i.tw_addr & (n - 1);
            let v = q_to_z(&self.p, self.entry_width, i.tw_data);
            self.write = Some((bk as usize, e as usize, v));
        }
        self.line.pop_back();
        if i.core.rst {
            self.line.iter_mut().for_each(|s| s.v = false);
        }
        let v = i.core.v && !i.core.rst;
        self.line.push_front(HarmonicOut {
            // Stage 2 zeroes an invalid sample's words: its z' is 0.
            z: if v { correct_ab(zw, pb, z, a, b) } else { 0 },
            x: i.core.x & mask(32),
            v,
        });
        self.line[self.line.len() - 1]
    }
}
