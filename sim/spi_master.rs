//! SPI master model (modes 0 and 3) for the position slave ([`crate::blocks::spi_slave`]),
//! on the line model the BiSS-C and SSI masters share ([`crate::sim::serial_line`]:
//! continuous-time master, line delay d both ways, slave stepped one system clock at a time).
//!
//! An SPI master does not react to MISO, so it needs none of the phase loop of
//! [`crate::sim::serial_master`] (no Ack to find, no timeout to wait for): its SCK and
//! chip-select waveforms and its sampling instants are planned ahead, one transaction after
//! the other, and MISO is read at those instants afterwards.
//!
//! ```text
//!  mode 0:  cs_n ‾‾\______________________________ .. ______/‾‾    samples at rising SCK
//!           sck  ______/‾‾\__/‾‾\__/‾‾\__ .. __/‾‾\__________
//!  mode 3:  sck  ‾‾‾‾‾‾\__/‾‾\__/‾‾\__/‾ .. ‾\__/‾‾‾‾‾‾‾‾‾‾‾‾
//!                 │<-T->│ first clock one SCK period after chip select; cs_n rises one
//!                         period after the last clock, the next gap starts one period later
//! ```
use crate::sim::serial_line::{LineTiming, MaLine, SlaveLine};

/// One SPI transaction as the master clocks it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpiTxn {
    /// SPI mode, 0 (SCK idles low) or 3 (SCK idles high).
    pub mode: u8,
    /// SCK frequency in Hz.
    pub sck_hz: f64,
    /// SCK periods given (the word has N + 2 bits; more read zeros, fewer end it early).
    pub clocks: u32,
    /// Pause before chip select, ns.
    pub gap_ns: f64,
}

/// A planned transaction: when chip select falls and when each bit is sampled.
#[derive(Clone, Debug, PartialEq)]
pub struct SpiPlanned {
    /// Chip select falls at the master, ns.
    pub t_cs_ns: f64,
    /// Sampling instants (rising SCK edges), ns.
    pub samples: Vec<f64>,
}

/// The SPI master model: its SCK and cs_n lines, planned ahead, and the MISO line it reads.
#[derive(Clone, Debug)]
pub struct SpiMaster {
    timing: LineTiming,
    sck: MaLine,
    cs: MaLine,
    miso: SlaveLine,
    txns: Vec<SpiPlanned>,
    end_ns: f64,
}

impl SpiMaster {
    /// Master that clocks `txns` in order, the first gap starting at `start_ns`.
    pub fn new(timing: LineTiming, txns: &[SpiTxn], start_ns: f64) -> Self {
        let (mut sck, mut cs) = (MaLine::default(), MaLine::default());
        let mut t = start_ns;
        let mut out = Vec::new();
        // SCK idles at the mode's level; the line starts high (mode 3), so mode 0 first
        // drops it.
        let mut sck_level = true;
        for x in txns {
            t += x.gap_ns;
            let per = 1e9 / x.sck_hz;
            let idle = x.mode == 3;
            if sck_level != idle {
                sck.push(t, idle);
                sck_level = idle;
                t += per;
            }
            let t_cs = t;
            cs.push(t_cs, false);
            let first = t_cs + per;
            let mut samples = Vec::new();
            for i in 0..x.clocks {
                let a = first + i as f64 * per;
                // Mode 0: rise (sample) then fall; mode 3: fall then rise (sample).
                if x.mode == 0 {
                    sck.push(a, true);
                    samples.push(a);
                    sck.push(a + per / 2.0, false);
                } else {
                    sck.push(a, false);
                    sck.push(a + per / 2.0, true);
                    samples.push(a + per / 2.0);
                }
            }
            t = first + x.clocks as f64 * per;
            cs.push(t, true);
            out.push(SpiPlanned {
                t_cs_ns: t_cs,
                samples,
            });
            t += per;
        }
        Self {
            timing,
            sck,
            cs,
            miso: SlaveLine::new(&timing, false),
            txns: out,
            end_ns: t,
        }
    }

    /// The planned transactions.
    pub fn txns(&self) -> &[SpiPlanned] {
        &self.txns
    }

    /// When the last transaction has ended (chip select high for one SCK period), ns.
    pub fn end_ns(&self) -> f64 {
        self.end_ns
    }

    /// SCK and cs_n at the slave's pins as the slave's clock edge k samples them. Called
    /// once per cycle, k = 0, 1, 2, ...
    pub fn lines_for_cycle(&mut self, k: usize) -> (bool, bool) {
        let at = self.timing.edge_ns(k) - self.timing.line_delay_ns;
        (self.sck.before(at), self.cs.before(at))
    }

    /// The slave's MISO after clock edge k (called after `lines_for_cycle(k)`).
    pub fn push_miso(&mut self, miso: bool) {
        self.miso.push(miso);
    }

    /// The bits read in transaction `i` (its sampling instants must be known).
    pub fn word(&self, i: usize) -> Vec<bool> {
        self.txns[i]
            .samples
            .iter()
            .map(|&ts| self.miso.at(ts))
            .collect()
    }

    /// The bits read in each transaction (every sampling instant must be known).
    pub fn words(&self) -> Vec<Vec<bool>> {
        self.txns
            .iter()
            .map(|x| x.samples.iter().map(|&ts| self.miso.at(ts)).collect())
            .collect()
    }
}

/// An SPI slave's word as the master decodes it, from the frame definition: N data bits
/// (binary or Gray per `format`), the velocity word (`format.velocity_bits`, two's
/// complement; `[velocity] in_frames`), E (1 = error), W (1 = warning), MSB first.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SpiWord {
    /// Single-turn position.
    pub position: u64,
    /// Turn count.
    pub turns: u64,
    /// The velocity word, sign-extended.
    pub velocity: Option<i64>,
    /// E.
    pub error: bool,
    /// W.
    pub warning: bool,
}

/// Decodes the first N + V + 2 bits of a transaction; None when it has fewer.
pub fn decode_word(bits: &[bool], format: &crate::sim::serial_line::WordFormat) -> Option<SpiWord> {
    let n = format.data_bits as usize;
    let e = n + format.velocity_bits as usize;
    if bits.len() < e + 2 {
        return None;
    }
    let (position, turns) = format.split(crate::sim::serial_line::word_of(&bits[..n]));
    Some(SpiWord {
        position,
        turns,
        velocity: format.velocity(&bits[n..e]),
        error: bits[e],
        warning: bits[e + 1],
    })
}
