//! A plain SPI ADC slave model for the `generic` ADC preset, written from the frame
//! description (not from the controller): CONV pulse or chip-select framing, CPOL/CPHA,
//! MSB-first channels at their slots, offset binary or two's complement. The conversion
//! result is taken at the CONV (or chip-select) edge from a code source, so a caller can
//! sample an analog model at that instant. Bits outside the channel slots and an idle line
//! are random, so a controller that reads them is caught.
use crate::blocks::adc::{AdcFrame, SignFormat};
use crate::cosim::stimulus::SplitMix64;

/// The code source: called at each conversion start with the clock index; returns the
/// codes of channel 0 and 1 (channel 1 ignored for a one-channel frame).
pub type CodeSource = Box<dyn FnMut(usize) -> [i32; 2]>;

/// Generic SPI ADC model.
pub struct SpiAdc {
    f: AdcFrame,
    source: CodeSource,
    taken: Vec<(usize, [i32; 2])>,
    clock: usize,
    prev_conv: bool,
    prev_sck: bool,
    active: bool,
    slot: i64,
    out: bool,
    rng: SplitMix64,
}

impl SpiAdc {
    /// A model that converts `source`'s codes.
    pub fn new(f: AdcFrame, source: CodeSource) -> Self {
        SpiAdc {
            f,
            source,
            taken: Vec::new(),
            clock: 0,
            prev_conv: !f.conv_active_high,
            prev_sck: f.cpol,
            active: false,
            slot: -1,
            out: false,
            rng: SplitMix64(77),
        }
    }

    /// A model that cycles through a fixed list of codes.
    pub fn with_codes(f: AdcFrame, codes: Vec<[i32; 2]>) -> Self {
        let mut k = 0usize;
        Self::new(
            f,
            Box::new(move |_| {
                let c = codes[k % codes.len()];
                k += 1;
                c
            }),
        )
    }

    /// Conversions so far: (clock of the conversion start, codes).
    pub fn taken(&self) -> &[(usize, [i32; 2])] {
        &self.taken
    }

    /// Drops every conversion but the latest (the one being shifted out), so a long run
    /// keeps no history; [`taken`](Self::taken) then starts there.
    pub fn forget_old(&mut self) {
        let n = self.taken.len();
        if n > 1 {
            self.taken.drain(..n - 1);
        }
    }

    fn bit(&mut self, slot: i64) -> bool {
        let w = self.f.width as i64;
        let cur = self.taken.last().map(|t| t.1).unwrap_or([0, 0]);
        let n = self.f.channels as usize;
        for (&off, &code) in self.f.offsets.iter().zip(cur.iter()).take(n) {
            let o = off as i64;
            if slot >= o && slot < o + w {
                let mut v = code as i64 & ((1 << w) - 1);
                if self.f.sign == SignFormat::OffsetBinary {
                    v ^= 1 << (w - 1);
                }
                return (v >> (w - 1 - (slot - o))) & 1 == 1;
            }
        }
        self.rng.next_u64() & 1 == 1
    }

    /// One system clock: the pins the model sees; returns its SDO level.
    pub fn step(&mut self, conv: bool, sck: bool) -> bool {
        let on = conv == self.f.conv_active_high;
        let was_on = self.prev_conv == self.f.conv_active_high;
        if on && !was_on {
            let c = (self.source)(self.clock);
            self.taken.push((self.clock, c));
            self.active = true;
            self.slot = 0;
            self.out = if self.f.cpha {
                self.rng.next_u64() & 1 == 1
            } else {
                self.bit(0)
            };
        }
        if !on && self.f.conv_clocks > 1 {
            self.active = false; // chip select framing: deselected ends the frame
        }
        let leading = sck != self.f.cpol && self.prev_sck == self.f.cpol;
        let trailing = sck == self.f.cpol && self.prev_sck != self.f.cpol;
        if self.active {
            if self.f.cpha && leading {
                let s = self.slot;
                self.out = self.bit(s);
                self.slot += 1;
            } else if !self.f.cpha && trailing {
                self.slot += 1;
                let s = self.slot;
                self.out = self.bit(s);
            }
        }
        self.prev_conv = conv;
        self.prev_sck = sck;
        self.clock += 1;
        if self.active {
            self.out
        } else {
            self.rng.next_u64() & 1 == 1
        }
    }
}
