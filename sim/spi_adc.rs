//! A plain SPI ADC slave model for the `generic` ADC preset, written from the frame
//! description (not from the controller): CONV pulse or chip-select framing, CPOL/CPHA,
//! MSB-first channels at their slots, offset binary or two's complement. The conversion
//! result is taken at the CONV (or chip-select) edge from a code source, so a caller can
//! sample an analog model at that instant. Bits outside the channel slots and an idle line
//! are random, so a controller that reads them is caught. With two data lines
//! (`AdcFrame::lines`) channel 0 leaves on SDO-A and channel 1 on SDO-B, each at its slot.
//!
//! The pins keep real time ([`super::adc_pins`]): an SCK or CONV / CS edge reaches the chip
//! FPGA clock-to-out + one trace after the clock edge that launched it; the chip drives
//! the new bit `data_valid_ns` after it (`[adc.timing] data_valid_ns`, default 10 ns) and
//! holds the old one `data_hold_ns` (0: `[adc.timing]` has no hold figure, so none is
//! assumed); the bit travels one trace back and the FPGA reads it with its input set-up
//! (the `[board]` budget of `check`). A level read outside its valid window is random.
use super::adc_pins::{DataLine, Level, PinTiming};
use crate::blocks::adc::{AdcFrame, AdcParams, SignFormat};

/// The code source: called at each conversion start with the clock index; returns the
/// codes of channel 0 and 1 (channel 1 ignored for a one-channel frame).
pub type CodeSource = Box<dyn FnMut(usize) -> [i32; 2]>;

/// Generic SPI ADC model.
pub struct SpiAdc {
    f: AdcFrame,
    /// System clock period, ns.
    period_ns: f64,
    /// SCK (or CONV / CS) edge at the chip to the new bit valid, ns.
    valid_ns: f64,
    /// SCK edge at the chip to the old bit no longer held, ns.
    hold_ns: f64,
    /// SDO (SDO-A with two lines) at the FPGA's pad.
    line: DataLine,
    /// SDO-B at the FPGA's pad (two-line frames: channel 1).
    line_b: DataLine,
    source: CodeSource,
    taken: Vec<(usize, [i32; 2])>,
    clock: usize,
    prev_conv: bool,
    prev_sck: bool,
    active: bool,
    slot: i64,
}

impl SpiAdc {
    /// A model of the chip the controller parameters `p` describe (frame, system clock,
    /// `data_valid_ns`, no hold) behind the board pins `pins`, converting `source`'s codes.
    pub fn new(p: &AdcParams, pins: PinTiming, source: CodeSource) -> Self {
        let period_ns = if p.clock_hz.is_finite() && p.clock_hz > 0.0 {
            1e9 / p.clock_hz
        } else {
            1.0
        };
        let f = p.frame;
        SpiAdc {
            f,
            period_ns,
            valid_ns: p.timing.data_valid_ns,
            hold_ns: 0.0,
            line: DataLine::new(pins, 78),
            line_b: DataLine::new(pins, 79),
            source,
            taken: Vec::new(),
            clock: 0,
            prev_conv: !f.conv_active_high,
            prev_sck: f.cpol,
            active: false,
            slot: -1,
        }
    }

    /// Other chip delays: new bit valid `valid_ns` and old bit held `hold_ns` after the
    /// edge at the chip (a sweep, a part with a hold figure).
    pub fn with_delays(mut self, valid_ns: f64, hold_ns: f64) -> Self {
        self.valid_ns = valid_ns;
        self.hold_ns = hold_ns;
        self
    }

    /// A model that cycles through a fixed list of codes.
    pub fn with_codes(p: &AdcParams, pins: PinTiming, codes: Vec<[i32; 2]>) -> Self {
        let mut k = 0usize;
        Self::new(
            p,
            pins,
            Box::new(move |_| {
                let c = codes[k % codes.len()];
                k += 1;
                c
            }),
        )
    }

    /// A fault of both data lines at the FPGA's pads (None: none; see `DataLine::stick`).
    pub fn set_sdo_stuck(&mut self, level: Option<bool>) {
        self.line.stick(level);
        self.line_b.stick(level);
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

    /// The level of `line` (0: SDO / SDO-A, 1: SDO-B) at `slot`: with one line every
    /// channel at its slot, with two lines channel `line` alone at its slot.
    fn bit(&self, line: usize, slot: i64) -> Level {
        let w = self.f.width as i64;
        let cur = self.taken.last().map(|t| t.1).unwrap_or([0, 0]);
        let n = self.f.channels as usize;
        for (c, (&off, &code)) in self.f.offsets.iter().zip(cur.iter()).enumerate().take(n) {
            if self.f.lines >= 2 && c != line {
                continue;
            }
            let o = off as i64;
            if slot >= o && slot < o + w {
                let mut v = code as i64 & ((1 << w) - 1);
                if self.f.sign == SignFormat::OffsetBinary {
                    v ^= 1 << (w - 1);
                }
                return Level::Bit((v >> (w - 1 - (slot - o))) & 1 == 1);
            }
        }
        Level::Undefined
    }

    /// Both lines change at a pin edge the FPGA launched at `t`.
    fn change(&mut self, t: f64, slot: Option<i64>) {
        let (valid, hold) = (self.valid_ns, self.hold_ns);
        let a = slot.map_or(Level::Undefined, |k| self.bit(0, k));
        let b = slot.map_or(Level::Undefined, |k| self.bit(1, k));
        self.line.change(t, hold, valid, a);
        self.line_b.change(t, hold, valid, b);
    }

    /// One system clock: `conv` and `sck` are the levels the FPGA launches at this clock
    /// edge. Returns what the FPGA reads at `adc_miso` at the next clock edge.
    pub fn step(&mut self, conv: bool, sck: bool) -> bool {
        self.step_lines(conv, sck)[0]
    }

    /// [`step`](Self::step) for both data lines: what the FPGA reads at `adc_miso` (SDO-A)
    /// and `adc_miso_b` (SDO-B; random with a one-line frame) at the next clock edge.
    pub fn step_lines(&mut self, conv: bool, sck: bool) -> [bool; 2] {
        let t = self.clock as f64 * self.period_ns;
        let on = conv == self.f.conv_active_high;
        let was_on = self.prev_conv == self.f.conv_active_high;
        if on && !was_on {
            let c = (self.source)(self.clock);
            self.taken.push((self.clock, c));
            self.active = true;
            self.slot = 0;
            self.change(t, (!self.f.cpha).then_some(0));
        }
        if !on && self.f.conv_clocks > 1 && self.active {
            // Chip select framing: deselected ends the frame.
            self.active = false;
            self.change(t, None);
        }
        let leading = sck != self.f.cpol && self.prev_sck == self.f.cpol;
        let trailing = sck == self.f.cpol && self.prev_sck != self.f.cpol;
        if self.active {
            if self.f.cpha && leading {
                let k = self.slot;
                self.slot += 1;
                self.change(t, Some(k));
            } else if !self.f.cpha && trailing {
                self.slot += 1;
                self.change(t, Some(self.slot));
            }
        }
        self.prev_conv = conv;
        self.prev_sck = sck;
        self.clock += 1;
        let at = self.clock as f64 * self.period_ns;
        [self.line.sample(at), self.line_b.sample(at)]
    }
}
