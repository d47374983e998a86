//! Bit-accurate model of the NCO: the RTL's registers, one update per clock edge, and the
//! pure look-up `phase -> (sin, cos)` the demodulator's model can use.
use super::NcoParams;
use crate::blocks::{mask, sext};

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NcoIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Advance strobe.
    pub tick: bool,
}

impl NcoIn {
    /// Stimulus row in input-port order (rst, tick).
    pub fn row(&self) -> Vec<u64> {
        vec![self.rst as u64, self.tick as u64]
    }
}

/// Outputs after one clock edge.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NcoOut {
    /// Strobe: new words this clock.
    pub valid: bool,
    /// A sin(phi), signed.
    pub sin: i64,
    /// A cos(phi), signed.
    pub cos: i64,
    /// Phase word the outputs belong to.
    pub phase: u64,
}

impl NcoOut {
    /// Trace row in output-port order (out_valid, out_sin, out_cos, out_phase), the words
    /// as W-bit two's complement.
    pub fn row(&self, width: u32) -> Vec<u64> {
        vec![
            self.valid as u64,
            self.sin as u64 & mask(width),
            self.cos as u64 & mask(width),
            self.phase,
        ]
    }
}

/// The sin/cos words of phase word `phase` (what the NCO outputs for it), from the
/// quarter table `table` of `p` ([`NcoParams::table`]).
pub fn lookup(p: &NcoParams, table: &[u64], phase: u64) -> (i64, i64) {
    let t = p.table_bits();
    let k = (phase & mask(p.phase_bits())) >> (p.phase_bits() - t - 2);
    let i = (k & mask(t)) as usize;
    let mi = (!k & mask(t)) as usize;
    let (a, b) = (table[i] as i64, table[mi] as i64);
    match k >> t {
        0 => (a, b),
        1 => (b, -a),
        2 => (-a, -b),
        _ => (-b, a),
    }
}

/// Model of [`super::hdl::Nco`].
#[derive(Clone, Debug)]
pub struct NcoModel {
    p: NcoParams,
    table: Vec<u64>,
    fw: u64,
    phase: u64,
    out: NcoOut,
}

impl NcoModel {
    /// Model at power-up (every register 0).
    pub fn new(p: &NcoParams) -> Self {
        Self {
            p: *p,
            table: p.table(),
            fw: p.freq_word(),
            phase: 0,
            out: NcoOut::default(),
        }
    }

    /// The quarter table in use.
    pub fn table(&self) -> &[u64] {
        &self.table
    }

    /// The sin/cos words of `phase`.
    pub fn lookup(&self, phase: u64) -> (i64, i64) {
        lookup(&self.p, &self.table, phase)
    }

    /// The phase register (the phase the next tick will output).
    pub fn phase(&self) -> u64 {
        self.phase
    }

    /// One clock edge.
    pub fn step(&mut self, i: NcoIn) -> NcoOut {
        if i.rst {
            self.phase = 0;
            self.out = NcoOut::default();
            return self.out;
        }
        self.out.valid = i.tick;
        if i.tick {
            let (s, c) = self.lookup(self.phase);
            let w = self.p.width();
            self.out.sin = sext(s as u64 & mask(w), w);
            self.out.cos = sext(c as u64 & mask(w), w);
            self.out.phase = self.phase;
            self.phase = (self.phase + self.fw) & mask(self.p.phase_bits());
        }
        self.out
    }
}
