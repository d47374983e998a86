//! Model of an encoder's digital channel: the SSI interface of an absolute encoder with
//! 1 Vpp incremental tracks (Heidenhain ECN/EQN 413, ROC/ROQ 425 with SSI; Kübler and
//! Hengstler SSI + SinCos), written from their data sheets, independently of the master in
//! `blocks::absolute`:
//!
//! * Heidenhain, "Interfaces: SSI absolute position values" (rotary encoder catalogue) and
//!   the SSI interface description of the PWM 20 user manual: quiescent clock and data
//!   high; "the current position value is stored on the first falling edge of the clock.
//!   Data transfer begins with the first rising clock edge", MSB first, Gray code, 13 bits
//!   (ECN/ROC) or 25 bits (EQN/ROQ); after a complete word the data line stays low until the
//!   encoder is ready for a new latch (t2 = 17 to 20 us); a request within t2 outputs the
//!   same data again; a clock held high for t2 or more interrupts the transfer and the next
//!   falling edge stores a new value. T = 1 to 10 us, t1 <= 0.4 us (without cable); RS-485
//!   lines; cable propagation time 6 ns/m, at most 150 m.
//! * Posital (FRABA), "SSI interface": n + 1 clock pulses per read; after the LSB the last
//!   rising edge switches the data line low; a retriggerable monoflop with time t_m after
//!   the last clock edge ends the transfer; multiple transmission repeats the word.
//!
//! Behaviour modelled, in real time (ns): the clock the FPGA launches at system clock edge k
//! reaches the encoder clock-to-out + one board trace + the cable's delay later
//! ([`crate::sim::adc_pins::PinTiming`], the `[board]` budget of `check`). A falling edge from
//! quiescence stores the position at that instant (plus `latch_delay_ns`): the encoder
//! model's mechanical angle, plus the channel's alignment error, quantized to the word's
//! 2^S codes per turn (code edges at whole multiples of 2^-k quadrant, where the incremental
//! tracks' quadrants start at electrical angles of multiples of 90 degrees). Rising edge n
//! (n = 1..N) puts bit N - n on the line, rising edge N + 1 a 0, later ones repeat the word
//! (the n + 1 ring). The previous level is held `data_hold_ns`, the new one valid
//! `data_valid_ns` (t1) after the edge reaches the encoder; both travel the cable and the
//! trace back, and the FPGA's synchronizer reads a pseudo-random bit outside a level's valid
//! window ([`crate::sim::adc_pins::DataLine`]). The monoflop ends t_m after the last clock
//! edge: the line returns high and the next falling edge stores a new position. Clock
//! periods outside T are recorded, never panicked on.
use crate::blocks::absolute::SsiWord;
use crate::blocks::mask;
use crate::sim::adc_pins::{DataLine, Level, PinTiming};
use crate::sim::encoder::EncoderModel;

/// The channel's timing, ns.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SsiEncoderTiming {
    /// Shortest clock period T.
    pub min_period_ns: f64,
    /// Longest clock period T.
    pub max_period_ns: f64,
    /// t1: a clock edge at the encoder to valid data at its output (cable not included).
    pub data_valid_ns: f64,
    /// The previous level is held this long after the edge (no data-sheet figure: 0).
    pub data_hold_ns: f64,
    /// t_m: the line returns high (quiescent) this long after the last clock edge.
    pub monoflop_ns: f64,
    /// The position is stored this long after the first falling edge reaches the encoder
    /// (no data-sheet figure: 0).
    pub latch_delay_ns: f64,
}

impl SsiEncoderTiming {
    /// Heidenhain SSI: T = 1 to 10 us, t1 <= 0.4 us, t2 <= 20 us.
    pub const HEIDENHAIN: SsiEncoderTiming = SsiEncoderTiming {
        min_period_ns: 1000.0,
        max_period_ns: 10_000.0,
        data_valid_ns: 400.0,
        data_hold_ns: 0.0,
        monoflop_ns: 20_000.0,
        latch_delay_ns: 0.0,
    };
}

/// Heidenhain's cable propagation time, ns per metre.
pub const CABLE_NS_PER_M: f64 = 6.0;

/// One stored position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SsiLatch {
    /// When the encoder stored it, ns of simulated time (the encoder's own instant).
    pub at_ns: f64,
    /// The FPGA clock edge that launched the falling edge, ns.
    pub launched_ns: f64,
    /// The mechanical position then, turns (unwrapped).
    pub turns: f64,
    /// The code: floor(turns 2^S + e 2^k), unwrapped.
    pub code: i64,
    /// The word as sent before Gray coding (N bits).
    pub word: u64,
}

/// The shift register of a transfer.
#[derive(Clone, Copy, Debug)]
struct Transfer {
    /// The word as sent (Gray-coded when configured).
    sent: u64,
    /// Rising edges seen.
    rises: u32,
}

/// The encoder's SSI channel.
#[derive(Clone, Debug)]
pub struct SsiEncoder {
    word: SsiWord,
    position: EncoderModel,
    timing: SsiEncoderTiming,
    pins: PinTiming,
    line_delay_ns: f64,
    alignment_quadrants: f64,
    period_ns: f64,
    clock: u64,
    prev_clk: bool,
    transfer: Option<Transfer>,
    last_rise_ns: Option<f64>,
    monoflop_end_ns: Option<f64>,
    line: DataLine,
    latches: Vec<SsiLatch>,
    repeats: u64,
    violations: Vec<String>,
}

impl SsiEncoder {
    /// The channel of the encoder `position` (its mechanical angle; the tracks' periods are
    /// `position.ppr`) sending `word`, clocked by a master at `clock_hz` across the board
    /// `pins` and a cable of `line_delay_ns` one way, with the Heidenhain timing and no
    /// alignment error; random bits from `seed`.
    pub fn new(
        word: SsiWord,
        position: EncoderModel,
        clock_hz: f64,
        pins: PinTiming,
        line_delay_ns: f64,
        seed: u64,
    ) -> Self {
        let mut line = DataLine::new(pins, seed);
        // Quiescent: the line high since power-up.
        line.change(-1e9, 0.0, 0.0, Level::Bit(true));
        Self {
            word,
            position,
            timing: SsiEncoderTiming::HEIDENHAIN,
            pins,
            line_delay_ns,
            alignment_quadrants: 0.0,
            period_ns: 1e9 / clock_hz,
            clock: 0,
            prev_clk: true,
            transfer: None,
            last_rise_ns: None,
            monoflop_end_ns: None,
            line,
            latches: Vec::new(),
            repeats: 0,
            violations: Vec::new(),
        }
    }

    /// Other channel timing (a slower encoder, a longer t1).
    pub fn set_timing(&mut self, t: SsiEncoderTiming) {
        self.timing = t;
    }
    /// The channel timing.
    pub fn timing(&self) -> SsiEncoderTiming {
        self.timing
    }
    /// The cable's one-way delay, ns.
    pub fn set_line_delay_ns(&mut self, ns: f64) {
        self.line_delay_ns = ns;
    }
    /// The cable's one-way delay, ns.
    pub fn line_delay_ns(&self) -> f64 {
        self.line_delay_ns
    }
    /// The digital channel's alignment error against the incremental tracks, quadrants
    /// (positive: its code edges come before the tracks' quadrant edges).
    pub fn set_alignment_quadrants(&mut self, e: f64) {
        self.alignment_quadrants = e;
    }
    /// Positions stored so far, in order.
    pub fn latches(&self) -> &[SsiLatch] {
        &self.latches
    }
    /// Reads started while the monoflop ran (the same word again).
    pub fn repeats(&self) -> u64 {
        self.repeats
    }
    /// Timing violations recorded so far (messages).
    pub fn violations(&self) -> &[String] {
        &self.violations
    }

    /// The code of the position `turns` (unwrapped): floor(turns 2^S + e 2^k).
    pub fn code_of(&self, turns: f64) -> i64 {
        let s = self.word.single_turn_bits;
        let codes_per_quadrant = (1u64 << s) as f64 / (4.0 * self.position.ppr as f64);
        (turns * (1u64 << s) as f64 + self.alignment_quadrants * codes_per_quadrant).floor() as i64
    }

    /// The N-bit word of a code: the turns (mod 2^M_a) above the single-turn code, Gray-coded
    /// when configured.
    pub fn word_of(&self, code: i64) -> u64 {
        let b = code.rem_euclid(1i64 << self.word.bits().min(62)) as u64 & mask(self.word.bits());
        if self.word.gray {
            b ^ (b >> 1)
        } else {
            b
        }
    }

    /// The level leaving the encoder after rising edge `r` of a transfer (the n + 1 ring).
    fn bit_after_rise(&self, sent: u64, r: u32) -> bool {
        let n = self.word.bits();
        let m = (r - 1) % (n + 1);
        m < n && (sent >> (n - 1 - m)) & 1 == 1
    }

    /// One system clock: `clk` is the level the FPGA launches at this clock edge. Returns
    /// the level the FPGA's input flop takes at `abs_data` at the next clock edge.
    pub fn step(&mut self, clk: bool) -> bool {
        let t = self.clock as f64 * self.period_ns;
        let to_enc = self.pins.to_chip_ns() + self.line_delay_ns;
        let at_enc = t + to_enc;
        let tm = self.timing;
        // The monoflop ran out before this edge reached the encoder: quiescent again.
        if let Some(end) = self.monoflop_end_ns.filter(|e| *e <= at_enc) {
            self.monoflop_end_ns = None;
            self.transfer = None;
            self.line.change(
                end - self.pins.to_chip_ns(),
                self.line_delay_ns,
                self.line_delay_ns,
                Level::Bit(true),
            );
        }
        if clk != self.prev_clk {
            if !clk {
                match self.transfer {
                    None => {
                        let at_ns = at_enc + tm.latch_delay_ns;
                        let turns = self.position.turns(at_ns * 1e-9);
                        let code = self.code_of(turns);
                        let word = code.rem_euclid(1i64 << self.word.bits().min(62)) as u64
                            & mask(self.word.bits());
                        self.latches.push(SsiLatch {
                            at_ns,
                            launched_ns: t,
                            turns,
                            code,
                            word,
                        });
                        self.transfer = Some(Transfer {
                            sent: self.word_of(code),
                            rises: 0,
                        });
                        self.last_rise_ns = None;
                    }
                    Some(x) if x.rises > self.word.bits() => self.repeats += 1,
                    Some(_) => {}
                }
            } else if let Some(mut x) = self.transfer {
                if let Some(r) = self.last_rise_ns {
                    let p = at_enc - r;
                    if p + 1e-9 < tm.min_period_ns || p > tm.max_period_ns + 1e-9 {
                        self.violations.push(format!(
                            "clock {}: SSI clock period {p:.1} ns outside {}..{} ns",
                            self.clock, tm.min_period_ns, tm.max_period_ns
                        ));
                    }
                }
                x.rises += 1;
                let level = self.bit_after_rise(x.sent, x.rises);
                self.transfer = Some(x);
                self.line.change(
                    t,
                    2.0 * self.line_delay_ns + tm.data_hold_ns,
                    2.0 * self.line_delay_ns + tm.data_valid_ns,
                    Level::Bit(level),
                );
                self.last_rise_ns = Some(at_enc);
            }
            self.monoflop_end_ns = Some(at_enc + tm.monoflop_ns);
        }
        self.prev_clk = clk;
        self.clock += 1;
        self.line.sample(self.clock as f64 * self.period_ns)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::encoder::EncoderModel;

    /// A 13-bit Gray encoder at rest at `turns`, clocked at 100 MHz with ideal pins.
    fn encoder(turns: f64, gray: bool) -> SsiEncoder {
        let mut e = EncoderModel::ideal(2048, 0.5, 0.0);
        e.start_turns = turns;
        let pins = PinTiming {
            clock_to_out_ns: 0.0,
            trace_ns: 0.0,
            input_setup_ns: 0.0,
            input_hold_ns: 0.0,
        };
        let word = SsiWord {
            single_turn_bits: 13,
            multiturn_bits: 4,
            gray,
        };
        SsiEncoder::new(word, e, 100e6, pins, 0.0, 1)
    }

    /// Clocks one read of `pulses` pulses at 1 MHz (50 system clocks per half period) and
    /// returns the level the FPGA reads at the end of each high phase but the last (the
    /// answer to that pulse's rising edge), then once more a period after the last rising
    /// edge.
    fn read(enc: &mut SsiEncoder, pulses: u32) -> Vec<bool> {
        let mut got = Vec::new();
        for _ in 0..10 {
            enc.step(true);
        }
        for p in 0..pulses {
            for _ in 0..50 {
                enc.step(false);
            }
            for k in 0..50 {
                let v = enc.step(true);
                if k == 49 && p + 1 < pulses {
                    got.push(v);
                }
            }
        }
        for k in 0..50 {
            let v = enc.step(true);
            if k == 49 {
                got.push(v);
            }
        }
        got
    }

    #[test]
    fn a_read_sends_the_stored_word_msb_first_then_a_zero() {
        // 3.25 turns + 100.5 quadrants: code 3 x 8192 + 100 (one code per quadrant).
        let turns = 3.0 + 100.5 / 8192.0;
        let mut enc = encoder(turns, false);
        let bits = read(&mut enc, 18);
        let want = 3u64 << 13 | 100;
        let got = bits[..17].iter().fold(0u64, |w, b| w << 1 | *b as u64);
        assert_eq!(got, want);
        assert!(!bits[17], "the answer to the last pulse is 0");
        assert_eq!(enc.latches().len(), 1);
        assert!(enc.violations().is_empty(), "{:?}", enc.violations());
    }

    #[test]
    fn gray_code_and_the_alignment_error_shift_the_code() {
        let turns = 5.0 / 8192.0 + 0.1 / 8192.0;
        let mut enc = encoder(turns, true);
        enc.set_alignment_quadrants(0.95);
        let bits = read(&mut enc, 18);
        let g = bits[..17].iter().fold(0u64, |w, b| w << 1 | *b as u64);
        // Gray 6 = 0b101.
        assert_eq!(g, 6 ^ 3);
        assert_eq!(enc.latches()[0].code, 6);
    }

    #[test]
    fn the_line_returns_high_after_the_monoflop_and_a_new_read_stores_anew() {
        let mut enc = encoder(0.25, false);
        read(&mut enc, 18);
        // Low during t_m (20 us = 2000 clocks), high after it.
        let mut levels = Vec::new();
        for _ in 0..2200 {
            levels.push(enc.step(true));
        }
        assert!(!levels[1800]);
        assert!(levels[2199]);
        read(&mut enc, 18);
        assert_eq!(enc.latches().len(), 2);
        assert_eq!(enc.repeats(), 0);
    }

    #[test]
    fn a_clock_faster_than_the_data_sheet_allows_is_recorded() {
        let mut enc = encoder(0.0, false);
        for _ in 0..5 {
            enc.step(true);
        }
        for _ in 0..10 {
            for _ in 0..20 {
                enc.step(false);
            }
            for _ in 0..20 {
                enc.step(true);
            }
        }
        assert!(!enc.violations().is_empty());
    }
}
