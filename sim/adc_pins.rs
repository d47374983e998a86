//! The pins between the FPGA and an SPI ADC, in nanoseconds, shared by the chip models
//! (`sim::ltc1407a`, `sim::spi_adc`): when an SCK or CONV edge the FPGA launches at a system
//! clock edge reaches the chip, when the data bit the chip shifts out in answer is at the
//! FPGA's `adc_miso` pad, and what the FPGA's input register reads there.
//!
//! ```text
//!  FPGA clock edge n          chip                         FPGA clock edge m
//!   |-- t_co --|-- trace -->| SCK edge                       |
//!                           |-- hold --| old bit stops       |
//!                           |------ valid ------| new bit    |
//!                                       |-- trace -->| at the adc_miso pad
//!                                  reads the new bit when it is there t_su before edge m
//!                                  and the old one held t_h after it; otherwise undefined
//! ```
//!
//! The FPGA figures are the I/O budget of `check` (`[board]` keys `fpga_clock_to_out_ns`,
//! `trace_delay_ns`, `fpga_input_setup_ns`, defaults in [`crate::board::IoTiming`]); the
//! chip's valid and hold delays come from its data sheet (LTC1407A-1) or `[adc.timing]`
//! (generic). A level read outside its valid window is a pseudo-random bit.
use crate::cosim::stimulus::SplitMix64;
use std::collections::VecDeque;

/// FPGA-side pin timing, ns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinTiming {
    /// FPGA clock edge to the SCK / CONV pad (the `check` budget).
    pub clock_to_out_ns: f64,
    /// One board trace, each way.
    pub trace_ns: f64,
    /// Set-up the FPGA's input register needs at `adc_miso` before its clock edge.
    pub input_setup_ns: f64,
    /// Hold it needs after the edge (0: an input flip-flop with its delay element off).
    pub input_hold_ns: f64,
}

impl PinTiming {
    /// The budget of `check`: [`crate::board::IoTiming`] (`[board]` keys or their
    /// defaults 6, 1 and 3 ns), no input hold.
    pub fn from_io(io: &crate::board::IoTiming) -> Self {
        PinTiming {
            clock_to_out_ns: io.clock_to_out_ns,
            trace_ns: io.trace_ns,
            input_setup_ns: io.input_setup_ns,
            input_hold_ns: 0.0,
        }
    }

    /// The documented defaults ([`crate::board::IoTiming::DEFAULT`]).
    pub fn board_default() -> Self {
        Self::from_io(&crate::board::IoTiming::DEFAULT)
    }

    /// From an FPGA clock edge to the pin edge at the chip, ns.
    pub fn to_chip_ns(&self) -> f64 {
        self.clock_to_out_ns + self.trace_ns
    }
}

/// A level the chip drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Level {
    /// High impedance, changing, or data of no conversion: reads as a random bit.
    Undefined,
    /// A valid bit.
    Bit(bool),
}

/// One change of the data line as seen at the FPGA pad: the old level is held until
/// `hold_end`, the new one is valid from `valid_from` (ns of simulated time).
#[derive(Clone, Copy, Debug)]
struct Change {
    hold_end: f64,
    valid_from: f64,
    level: Level,
}

/// The data line at the FPGA pad.
#[derive(Clone, Debug)]
pub struct DataLine {
    pins: PinTiming,
    initial: Level,
    changes: VecDeque<Change>,
    rng: SplitMix64,
    /// A fault of the line ([`DataLine::stick`]): the pad reads this level whatever the
    /// chip drives.
    stuck: Option<bool>,
}

impl DataLine {
    /// A line that is undefined until the first change; random bits from `seed`.
    pub fn new(pins: PinTiming, seed: u64) -> Self {
        DataLine {
            pins,
            initial: Level::Undefined,
            changes: VecDeque::new(),
            rng: SplitMix64(seed),
            stuck: None,
        }
    }

    /// A fault of the line (None: none): from now on the FPGA's pad reads `level` whatever
    /// the chip drives. Stuck at 1 is SDO shorted to the supply, or the trace broken with a
    /// pull-up at the FPGA's input; stuck at 0 a short to ground or a pull-down. The chip
    /// itself goes on (its conversions, its checks); only what reaches the pad changes.
    pub fn stick(&mut self, level: Option<bool>) {
        self.stuck = level;
    }

    /// The pin timing.
    pub fn pins(&self) -> PinTiming {
        self.pins
    }

    /// The chip changes its output to `level` in answer to a pin edge the FPGA launched at
    /// `fpga_edge_ns`: the old level is held `hold_ns` and the new one valid `valid_ns`
    /// after the edge reaches the chip (both then travel one trace back).
    pub fn change(&mut self, fpga_edge_ns: f64, hold_ns: f64, valid_ns: f64, level: Level) {
        let at_pad = fpga_edge_ns + self.pins.to_chip_ns() + self.pins.trace_ns;
        self.changes.push_back(Change {
            hold_end: at_pad + hold_ns.min(valid_ns),
            valid_from: at_pad + valid_ns,
            level,
        });
    }

    /// The level the FPGA's input register takes at its clock edge `edge_ns`: the last
    /// level valid `input_setup_ns` before the edge, if no later change stops holding it
    /// before `input_hold_ns` after the edge; otherwise a random bit.
    pub fn sample(&mut self, edge_ns: f64) -> bool {
        let (a, b) = (
            edge_ns - self.pins.input_setup_ns,
            edge_ns + self.pins.input_hold_ns,
        );
        const EPS: f64 = 1e-9;
        let last = self.changes.iter().rposition(|c| c.valid_from <= a + EPS);
        let first_later = last.map_or(0, |i| i + 1);
        let stable = self
            .changes
            .iter()
            .skip(first_later)
            .all(|c| c.hold_end + EPS >= b);
        let level = match last {
            Some(i) => self.changes[i].level,
            None => self.initial,
        };
        // Time only advances: the changes before the one read are not needed again.
        if let Some(i) = last {
            self.initial = self.changes[i].level;
            self.changes.drain(..i);
            // Keep the one read (index 0 now) as the reference for the next samples.
        }
        if let Some(v) = self.stuck {
            return v;
        }
        match (stable, level) {
            (true, Level::Bit(v)) => v,
            _ => self.rng.next_u64() & 1 == 1,
        }
    }
}
