//! Closed-loop simulation of `<name>_top` (sinewave path): the rust-hdl design stepped by
//! hand, clock by clock, against the encoder model, the LTC1407A-1 model answering its SPI
//! frames and the LTC6912-1 model recording the gain word.
//!
//! ```text
//!  EncoderModel ──v_sin,v_cos──► Ltc1407a ──AD_DOUT──► TopRtl ──par_*──► records
//!        ▲ (voltages at each CONV rise)     ◄─SCK,CONV──  │
//!        │                                  Ltc6912 ◄─────┘ CS, SCK, MOSI
//!   true angle at the conversion time of every decoded sample (for the error figures)
//! ```
//!
//! Every decoded sample is matched to the ADC conversion that produced it by the design's
//! fixed latency (CONV rise to `par_valid` = the ADC controller's latency + the core's
//! N + 2 cycles); a sample with no conversion at that clock is reported as a latency error.
use crate::blocks::sext;
use crate::blocks::top::hdl::TopRtl;
use crate::config::Derived;
use crate::cosim::step::NoConvergence;
use crate::sim::adc_chip::{adc_chip_model, AdcChipModel};
use crate::sim::dut::{Dut, EngineKind, IN_PINS, OUT_PINS};
use crate::sim::encoder::EncoderModel;
use crate::sim::ltc1407a::Ltc1407a;
use crate::sim::ltc6912::Ltc6912;
use std::collections::HashMap;
use std::f64::consts::FRAC_PI_2;

// Pin indices of [`crate::sim::dut::IN_PINS`] / [`crate::sim::dut::OUT_PINS`].
const I_RST: usize = 0;
const I_MISO: usize = 1;
const I_MA: usize = 2;
const I_QEP_A: usize = 3;
const I_QEP_B: usize = 4;
const I_QEP_Z: usize = 5;
const I_SSI_CLK: usize = 6;
const I_ENC_SCK: usize = 7;
const I_ENC_CS_N: usize = 8;
const I_MISO_B: usize = 9;
const I_PRESET: usize = 10;
const I_CAPTURE: usize = 11;
const I_AWADDR: usize = 12;
const I_AWVALID: usize = 13;
const I_WDATA: usize = 14;
const I_WSTRB: usize = 15;
const I_WVALID: usize = 16;
const I_BREADY: usize = 17;
const I_ARADDR: usize = 18;
const I_ARVALID: usize = 19;
const I_RREADY: usize = 20;
const I_ABS_DATA: usize = 21;
const O_CONV: usize = 0;
const O_SCK: usize = 1;
const O_AMP_CS: usize = 2;
const O_AMP_MOSI: usize = 3;
const O_AMP_SHDN: usize = 4;
const O_SLO: usize = 5;
const O_SSI_DATA: usize = 6;
const O_VALID: usize = 7;
const O_QC: usize = 8;
const O_FINE: usize = 9;
const O_TURNS: usize = 10;
const O_ERROR: usize = 11;
const O_WARNING: usize = 12;
const O_ENC_MISO: usize = 13;
const O_VELOCITY: usize = 14;
const O_VELOCITY_VALID: usize = 15;
const O_ABZ_A: usize = 16;
const O_ABZ_B: usize = 17;
const O_ABZ_Z: usize = 18;
const O_REFERENCED: usize = 19;
const O_CAP_VALID: usize = 20;
const O_CAP_QC: usize = 21;
const O_CAP_FINE: usize = 22;
const O_CAP_TURNS: usize = 23;
const O_CAP_AGE: usize = 24;
const O_CAP_VELOCITY: usize = 25;
const O_RDATA: usize = 30;
const O_RVALID: usize = 31;
const O_FLAGS: usize = 32;
const O_ABS_CLK: usize = 33;

/// What a quadrature counter on `abz_a`/`abz_b` read over a run (`[abz] enabled`), against
/// the position on the parallel bus.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct AbzCount {
    /// A/B edges seen.
    pub edges: u64,
    /// Transitions where A and B changed at once (a count lost).
    pub illegal: u64,
    /// Rising edges of Z.
    pub index_pulses: u64,
    /// Samples checked: the counter against floor(position * E / P) of each sample (E edges
    /// and P positions per turn) just before the next sample can move the outputs.
    pub checked: u64,
    /// The largest distance found, in edges (0 while the emulator keeps up).
    pub max_lag: i64,
    /// The distance at the last check.
    pub last_lag: i64,
}

/// The quadrature counter behind [`AbzCount`]: it starts at the first sample's count when
/// the emulator shows it (the emulator's latency after that sample), then counts edges.
struct AbzCounter {
    p: crate::blocks::abz::AbzParams,
    figures: AbzCount,
    /// The counter, once started.
    count: Option<i64>,
    /// (A, B, Z) at the previous clock.
    prev: (bool, bool, bool),
    /// (cycle, count): start the counter at that cycle.
    start: Option<(u64, i64)>,
    /// The latest sample's count, to check at the cycle before the next sample's shows.
    last: Option<i64>,
    /// (cycle, count) checks due.
    due: std::collections::VecDeque<(u64, i64)>,
}

impl AbzCounter {
    fn new(p: &crate::blocks::abz::AbzParams) -> Self {
        AbzCounter {
            p: *p,
            figures: AbzCount::default(),
            count: None,
            prev: (false, false, false),
            start: None,
            last: None,
            due: Default::default(),
        }
    }

    /// Gray index of (A, B): 00 -> 0, 10 -> 1, 11 -> 2, 01 -> 3 (A leads B forward).
    fn gray(a: bool, b: bool) -> i64 {
        match (a, b) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        }
    }

    /// Clock `cycle`'s levels; `sample` is the single-turn position when `par_valid` is high.
    fn step(&mut self, cycle: u64, (a, b, z): (bool, bool, bool), sample: Option<u64>) {
        let e = 4 * self.p.lines() as i64;
        let (pa, pb, pz) = self.prev;
        if let Some(c) = self.count.as_mut() {
            match (Self::gray(a, b) - Self::gray(pa, pb)).rem_euclid(4) {
                0 => {}
                1 => {
                    *c += 1;
                    self.figures.edges += 1;
                }
                3 => {
                    *c -= 1;
                    self.figures.edges += 1;
                }
                _ => self.figures.illegal += 1,
            }
        }
        if z && !pz {
            self.figures.index_pulses += 1;
        }
        self.prev = (a, b, z);
        if let Some((at, t0)) = self.start {
            if cycle == at {
                if Self::gray(a, b) != t0.rem_euclid(4) {
                    self.figures.illegal += 1;
                }
                self.count = Some(t0);
                self.start = None;
            }
        }
        while let Some(&(at, want)) = self.due.front() {
            if at > cycle {
                break;
            }
            self.due.pop_front();
            if let Some(c) = self.count {
                let mut lag = (c - want).rem_euclid(e);
                if lag > e / 2 {
                    lag -= e;
                }
                let f = &mut self.figures;
                f.checked += 1;
                f.last_lag = lag;
                f.max_lag = f.max_lag.max(lag.abs());
            }
        }
        if let Some(pos) = sample {
            let want = ((pos as u128 * e as u128) / self.p.positions() as u128) as i64;
            let lat = self.p.latency() as u64;
            match self.last {
                None => self.start = Some((cycle + lat, want)),
                Some(prev) => self.due.push_back((cycle + lat - 1, prev)),
            }
            self.last = Some(want);
        }
    }
}

/// What the BiSS-C master model read over a run ([`System::monitor_biss`]), against the
/// parallel bus.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BissCheck {
    /// MA frequency, Hz.
    pub ma_hz: u64,
    /// Frames the master finished.
    pub frames: u64,
    /// Frames read completely with a good CRC.
    pub good: u64,
    /// Frames read completely whose CRC was wrong.
    pub crc_errors: u64,
    /// Frames the master could not read (no Ack or Start, the slave not ready).
    pub failed: u64,
    /// Good frames whose position and turn count equal neither of the parallel bus's two
    /// latest positions when the slave latched (its first MA edge plus the synchronizer).
    pub position_mismatches: u64,
}

/// What an SSI or SPI master model read over a run ([`System::monitor_ssi`],
/// [`System::monitor_spi`]), against the parallel bus.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WordCheck {
    /// Clock (SSI) or SCK (SPI) frequency, Hz.
    pub clock_hz: u64,
    /// Frames (SSI) or transactions (SPI) the master finished.
    pub frames: u64,
    /// Frames read completely.
    pub good: u64,
    /// Frames the master could not read (SSI: aborted, or the line never returned high).
    pub failed: u64,
    /// Good frames whose position and turn count equal neither of the parallel bus's two
    /// latest positions when the slave latched (its first clock edge, or chip select, plus
    /// the synchronizer).
    pub position_mismatches: u64,
}

/// Whether `got` (position word of `pb` bits, turns of `mt` bits) equals one of the two
/// latest parallel-bus positions at or before `latch + 1` in `history` (cycle, position of
/// `pw` bits, turns), or the reset value 0 when the slave latched before the first one.
fn par_match(
    history: &std::collections::VecDeque<(u64, u64, u64)>,
    latch: u64,
    (pw, pb, mt): (u32, u32, u32),
    got: (u64, u64),
) -> bool {
    let word = |h: &(u64, u64, u64)| {
        let pos = if pb <= pw {
            h.1 >> (pw - pb)
        } else {
            h.1 << (pb - pw)
        };
        (pos, h.2 & crate::blocks::mask(mt))
    };
    let mut near = history.iter().rev().filter(|h| h.0 <= latch + 1).peekable();
    if near.peek().is_none() && history.front().is_none_or(|h| h.0 > latch + 1) {
        // Latched before the first position: the slave sends its reset value.
        return got == (0, 0);
    }
    near.take(2).any(|h| word(h) == got)
}

/// The cycle at which a serial slave latches the word of a frame the master starts at
/// `t_ns`: its first edge reaches the pin a trace delay later, and the slave's synchronizer
/// acts `latency` clocks after the cycle that first sees it.
fn latch_cycle(d: &Derived, t_ns: f64, latency: u32) -> u64 {
    ((t_ns + d.io_timing.trace_ns) * d.clock_hz / 1e9).ceil() as u64 + latency as u64
}

/// Parallel-bus positions kept for [`BissCheck`]: a frame is checked when it ends, its
/// timeout included (tens of microseconds after its latch: thousands of samples at the
/// fastest ADCs).
const PAR_HISTORY: usize = 8192;

/// One decoded sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    /// Clock cycle of `par_valid`.
    pub cycle: u64,
    /// Clock cycle of the conversion start (CONV rise or chip-select fall) that sampled it.
    pub conv_cycle: u64,
    /// Single-turn position (2^-F quadrant units).
    pub position: u64,
    /// Signed turn count.
    pub turns: i64,
    /// Error flag.
    pub error: bool,
    /// Warning flag.
    pub warning: bool,
    /// The position is referenced (`[reference] enabled`; false without it).
    pub referenced: bool,
    /// Unwrapped decoded position in fine LSB: turns * 4PPR * 2^F + position.
    pub unwrapped: i64,
    /// The encoder's true electrical angle at the conversion, in fine LSB (unwrapped).
    pub truth: f64,
}

/// One velocity update (`par_velocity_valid`, `[velocity] enabled`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VelRecord {
    /// Clock cycle of `par_velocity_valid` (the value is read after that edge).
    pub cycle: u64,
    /// `par_velocity` as a signed number: 2^-(F + frac_bits) quadrant per update period.
    pub raw: i64,
    /// The encoder's true mean speed over the update period the estimate ends with, in
    /// position LSB (2^-F quadrant) per update period: the model's angle change from
    /// (tick - D) to the tick, both taken back by the CONV-to-position latency (the tick is
    /// `latency()` clocks before the strobe).
    pub truth: f64,
}

/// One capture (`[capture] enabled`): what `cap_*` showed with `cap_valid`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CaptureRecord {
    /// Clock cycle of `cap_valid`.
    pub cycle: u64,
    /// The cycle whose input first had `capture` high (the pin rose in the clock before).
    pub pin_cycle: u64,
    /// Captured single-turn position (2^-F quadrant units).
    pub position: u64,
    /// Captured signed turn count.
    pub turns: i64,
    /// Unwrapped captured position in fine LSB: turns * 4PPR * 2^F + position.
    pub unwrapped: i64,
    /// `cap_age`: clocks from the sample's CONV edge to the capture.
    pub age: u64,
    /// `cap_velocity` as a signed number (0 without `[velocity]`).
    pub velocity: i64,
    /// The encoder's true electrical angle when the pin rose (the pulse's start, in the
    /// clock before `pin_cycle`), in fine LSB (unwrapped).
    pub truth: f64,
}

/// The absolute start over a run (`[reference] absolute`): what the encoder's digital
/// channel stored and sent, and when the position became absolute.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AbsoluteCheck {
    /// Every position the channel stored (one per read), with its instant and word.
    pub latches: Vec<crate::sim::ssi_encoder::SsiLatch>,
    /// The channel's timing violations (messages).
    pub violations: Vec<String>,
    /// The cycle of the first referenced sample on the parallel bus.
    pub referenced_cycle: Option<u64>,
    /// The cable's one-way delay the channel was given, ns.
    pub line_delay_ns: f64,
}

/// A fault STATUS latched (`[registers] enabled`, [`System::poll_status`]), by its field
/// of `crate::blocks::regmap::FAULTS`. The exact clocks come from the top's live `flags`
/// port, read every cycle; the loop also reads STATUS through the AXI4-Lite slave every poll
/// period and clears (write 1) what it read, as a drive would.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FaultRecord {
    /// The field's name (`crate::blocks::regmap::FAULTS`).
    pub name: &'static str,
    /// The first cycle (counted as [`Record::cycle`]) at whose end the live flag was high:
    /// STATUS latches it at the next clock edge. None when no cycle showed it (a fault
    /// only a poll found).
    pub raised: Option<u64>,
    /// The last cycle the live flag was high (0 if none).
    pub last: u64,
    /// Rises of the live flag (the first included).
    pub rises: u64,
    /// The first poll that found STATUS's bit set: the fault was raised after this cycle
    /// (the poll before)...
    pub after: u64,
    /// ... and by this one (the read's data cycle); both 0 while no poll found it.
    pub by: u64,
    /// Polls that found it set (each clears it; a fault still present sets it again).
    pub polls: u64,
    /// The last poll found STATUS's bit clear after it had been found set: the write of 1
    /// cleared it and the fault did not come back.
    pub cleared: bool,
}

impl FaultRecord {
    fn new(name: &'static str) -> Self {
        FaultRecord {
            name,
            raised: None,
            last: 0,
            rises: 0,
            after: 0,
            by: 0,
            polls: 0,
            cleared: false,
        }
    }
}

/// Result of a closed-loop run.
#[derive(Clone, Debug, Default)]
pub struct SimResult {
    /// Decoded samples in order.
    pub records: Vec<Record>,
    /// Velocity updates in order (empty without `[velocity] enabled`).
    pub velocity: Vec<VelRecord>,
    /// Captures in order (empty without `[capture] enabled`).
    pub captures: Vec<CaptureRecord>,
    /// Faults STATUS latched, in the order first raised ([`System::poll_status`]).
    pub faults: Vec<FaultRecord>,
    /// STATUS polls done (0 without [`System::poll_status`]).
    pub status_polls: u64,
    /// The quadrature counter on the ABZ outputs (with `[abz] enabled`).
    pub abz: Option<AbzCount>,
    /// The BiSS-C master's frames against the parallel bus ([`System::monitor_biss`]).
    pub biss: Option<BissCheck>,
    /// The SSI master's frames against the parallel bus ([`System::monitor_ssi`]).
    pub ssi: Option<WordCheck>,
    /// The SPI master's words against the parallel bus ([`System::monitor_spi`]).
    pub spi: Option<WordCheck>,
    /// The absolute start's read (with `[reference] absolute`).
    pub absolute: Option<AbsoluteCheck>,
    /// Clock cycles simulated.
    pub cycles: u64,
    /// Decoded samples whose conversion could not be found at the expected latency.
    pub latency_mismatches: u64,
    /// LTC1407A-1 protocol violations (messages).
    pub adc_violations: Vec<String>,
    /// LTC6912-1 protocol violations (messages).
    pub amp_violations: Vec<String>,
    /// Gains the LTC6912-1 model decoded, if a word was shifted in.
    pub amp_gains: Option<(i32, i32)>,
    /// Per-cycle inputs of the design (`TopRtl`'s port-table input order), when recording
    /// was asked for: a stimulus that replays the run in a Verilog simulator.
    pub inputs: Vec<Vec<u64>>,
    /// Per-cycle outputs (`CosimBlock` output order), when recording was asked for.
    pub outputs: Vec<Vec<u64>>,
    /// Decoded samples (equal to `records.len()` when the records are kept).
    pub decoded: usize,
    /// The statistics gathered as the samples came, when the records are not kept
    /// ([`System::stream_stats`]).
    pub streamed: Option<StreamStats>,
}

/// Error statistics gathered sample by sample (bounded memory on long runs): the same
/// figures as [`SimResult::stats`] over the same samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StreamStats {
    /// Decoded samples left out at the start.
    pub skip: usize,
    /// Samples that leave the top before this cycle are left out too (`--settle`).
    pub from_cycle: u64,
    /// The first decoded sample (it fixes the offset).
    pub first: Option<Record>,
    /// The offset it fixed, fine LSB.
    pub offset: f64,
    /// Samples seen.
    pub seen: usize,
    /// The figures so far (mean and RMS as sums until [`StreamStats::stats`]).
    acc: ErrorStats,
    sum: f64,
    sum2: f64,
}

impl StreamStats {
    fn add(&mut self, d: &Derived, r: &Record) {
        if d.absolute.is_some() && !r.referenced {
            // Before the absolute start the position is the decoder's own: not counted.
            self.seen += 1;
            return;
        }
        if self.first.is_none() {
            self.first = Some(*r);
            self.offset = SimResult::offset_of(d, r);
        }
        self.seen += 1;
        if self.seen <= self.skip || r.cycle < self.from_cycle {
            return;
        }
        let e = SimResult::error_lsb(d, r, self.offset);
        let s = &mut self.acc;
        s.samples += 1;
        s.max_lsb = s.max_lsb.max(e.abs());
        self.sum += e;
        self.sum2 += e * e;
        s.errors += r.error as usize;
        s.warnings += r.warning as usize;
    }

    /// The statistics of the samples after the first `skip` and from `from_cycle` on.
    pub fn stats(&self) -> ErrorStats {
        let mut s = self.acc;
        if s.samples > 0 {
            s.mean_lsb = self.sum / s.samples as f64;
            s.rms_lsb = (self.sum2 / s.samples as f64).sqrt();
        }
        s
    }
}

/// The captures of a run (`[capture] enabled`) against the encoder's angle at each pin.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CaptureStats {
    /// Captures taken.
    pub captures: usize,
    /// Captures in the error figures: after the first sample of the statistics and, with
    /// extrapolation, after the velocity estimator's warm-up.
    pub counted: usize,
    /// Smallest and largest age, clocks, over the captures after the first sample of the
    /// statistics ((0, 0) when there is none).
    pub age: (u64, u64),
    /// Largest |captured - true angle at the pin|, fine LSB.
    pub max_lsb: f64,
    /// RMS of the same.
    pub rms_lsb: f64,
}

/// Error statistics of a run, after a settling time.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorStats {
    /// Samples counted.
    pub samples: usize,
    /// Largest |error| in fine LSB.
    pub max_lsb: f64,
    /// RMS error in fine LSB.
    pub rms_lsb: f64,
    /// Mean error in fine LSB.
    pub mean_lsb: f64,
    /// Samples with the error flag.
    pub errors: usize,
    /// Samples with the warning flag.
    pub warnings: usize,
}

impl SimResult {
    /// The constant offset between the decoded and the true position, in fine LSB, fixed
    /// by the first record: two quadrants with the pre-amplifier (it inverts, turning the vector by
    /// two quadrants) plus the whole signal periods that make the first sample's error
    /// smallest (the first sample fixes which signal period counts as period 0).
    pub fn offset_lsb(&self, d: &Derived) -> f64 {
        match (self.records.first(), &self.streamed) {
            (Some(first), _) => Self::offset_of(d, first),
            (None, Some(s)) => s.offset,
            (None, None) => 0.0,
        }
    }

    /// The captures against the encoder's angle at their pins (None without a capture):
    /// the error of each is its unwrapped position less the true angle when the pin rose
    /// and [`offset_lsb`](Self::offset_lsb), taken modulo the position's range as
    /// [`error_lsb`](Self::error_lsb) does.
    pub fn capture_stats(&self, d: &Derived) -> Option<CaptureStats> {
        let c = d.capture.as_ref()?;
        let start = match (self.records.first(), &self.streamed) {
            (Some(r), _) => Some(r.cycle),
            (None, Some(s)) => s.first.map(|r| r.cycle),
            (None, None) => None,
        };
        // With extrapolation, the captures after the velocity's warm-up (as the velocity
        // figures count it).
        let warm = match (&d.velocity, c.extrapolation()) {
            (Some(v), Some(_)) => {
                let before = self
                    .velocity
                    .iter()
                    .take_while(|r| start.is_some_and(|s| r.cycle <= s))
                    .count();
                self.velocity
                    .get(before + v.warmup_updates() as usize)
                    .map_or(u64::MAX, |r| r.cycle)
            }
            _ => 0,
        };
        let from = start.map_or(u64::MAX, |s| s.max(warm));
        let offset = self.offset_lsb(d);
        let range = d.quadrants_per_turn as f64
            * (1u64 << d.fine_bits) as f64
            * (1u64 << d.multiturn_bits) as f64;
        let mut s = CaptureStats {
            captures: self.captures.len(),
            age: (u64::MAX, 0),
            ..Default::default()
        };
        let mut sum2 = 0.0;
        for k in &self.captures {
            if start.is_some_and(|st| k.cycle >= st) {
                s.age = (s.age.0.min(k.age), s.age.1.max(k.age));
            }
            if k.cycle < from {
                continue;
            }
            let e = k.unwrapped as f64 - k.truth - offset;
            let e = e - range * (e / range).round();
            s.counted += 1;
            s.max_lsb = s.max_lsb.max(e.abs());
            sum2 += e * e;
        }
        if s.counted > 0 {
            s.rms_lsb = (sum2 / s.counted as f64).sqrt();
        }
        if s.age.0 > s.age.1 {
            s.age = (0, 0);
        }
        Some(s)
    }

    /// [`offset_lsb`](Self::offset_lsb) fixed by the record `first`: 0 with the absolute
    /// start (`[reference] absolute`), whose referenced position is the encoder's own.
    fn offset_of(d: &Derived, first: &Record) -> f64 {
        if d.absolute.is_some() {
            return 0.0;
        }
        let q = (1u64 << d.fine_bits) as f64;
        let period = 4.0 * q;
        // The inverting pre-amplifier turns the vector by two quadrants; without it the
        // ADC's codes follow the encoder's signals.
        let turned = if d.preamp.is_some() { 2.0 * q } else { 0.0 };
        let raw = first.unwrapped as f64 - first.truth - turned;
        turned + period * (raw / period).round()
    }

    /// Error of record `r` in fine LSB: decoded - truth - [`offset_lsb`](Self::offset_lsb),
    /// taken modulo the position's range (one turn times 2^M with M multi-turn bits: a
    /// single-turn position wraps every turn, an M-bit turn count every 2^M turns) into
    /// [-range/2, range/2).
    pub fn error_lsb(d: &Derived, r: &Record, offset: f64) -> f64 {
        let range = d.quadrants_per_turn as f64
            * (1u64 << d.fine_bits) as f64
            * (1u64 << d.multiturn_bits) as f64;
        let e = r.unwrapped as f64 - r.truth - offset;
        e - range * (e / range).round()
    }

    /// Error statistics over the records from index `skip` on (see
    /// [`error_lsb`](Self::error_lsb)); when the records were not kept, the streamed
    /// statistics (their `skip` was fixed before the run).
    pub fn stats(&self, d: &Derived, skip: usize) -> ErrorStats {
        self.stats_from(d, skip, 0)
    }

    /// [`stats`](Self::stats) over the records from index `skip` on that left the top at
    /// cycle `from_cycle` or later (`simulate --settle`); streamed statistics have both
    /// fixed before the run.
    pub fn stats_from(&self, d: &Derived, skip: usize, from_cycle: u64) -> ErrorStats {
        if let (true, Some(s)) = (self.records.is_empty(), &self.streamed) {
            return s.stats();
        }
        if self.records.is_empty() {
            return ErrorStats::default();
        }
        let offset = self.offset_lsb(d);
        let mut s = ErrorStats::default();
        let (mut sum, mut sum2) = (0.0, 0.0);
        // With the absolute start only the referenced samples are the encoder's position.
        let counted = |r: &&Record| (d.absolute.is_none() || r.referenced) && r.cycle >= from_cycle;
        for r in self.records.iter().skip(skip).filter(counted) {
            let e = Self::error_lsb(d, r, offset);
            s.samples += 1;
            s.max_lsb = s.max_lsb.max(e.abs());
            sum += e;
            sum2 += e * e;
            s.errors += r.error as usize;
            s.warnings += r.warning as usize;
        }
        if s.samples > 0 {
            s.mean_lsb = sum / s.samples as f64;
            s.rms_lsb = (sum2 / s.samples as f64).sqrt();
        }
        s
    }
}

/// Velocity figures of a run (`[velocity] enabled`): the estimate `par_velocity` / 2^frac_bits
/// against [`VelRecord::truth`], in position LSB per update period and in rpm.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct VelStats {
    /// Updates counted (after the estimator's warm-up).
    pub updates: usize,
    /// Updates left out at the start: those before the first decoded sample, then
    /// [`crate::blocks::velocity::VelocityParams::warmup_updates`].
    pub warmup: usize,
    /// rpm of one position LSB per update period.
    pub rpm_per_lsb: f64,
    /// Mean of estimate - truth, LSB per period.
    pub mean_err: f64,
    /// Standard deviation of estimate - truth, LSB per period.
    pub std_err: f64,
    /// Largest |estimate - truth|, LSB per period.
    pub max_err: f64,
    /// The last update's estimate, LSB per period.
    pub last: f64,
    /// The last update's true speed, LSB per period.
    pub last_truth: f64,
}

impl SimResult {
    /// Velocity figures over the updates after the warm-up; None without `[velocity]`
    /// enabled or when no update passed the warm-up. The warm-up counts from the first
    /// update after the first decoded sample: before it the estimator sees position 0, and
    /// the first sample is a step to the encoder's position.
    pub fn velocity_stats(&self, d: &Derived) -> Option<VelStats> {
        let v = d.velocity.as_ref()?;
        // The first decoded sample: the kept records' or, without them, the streamed one.
        let first = match (self.records.first(), &self.streamed) {
            (Some(r), _) => r.cycle,
            (None, Some(s)) => s.first?.cycle,
            (None, None) => return None,
        };
        let before = self
            .velocity
            .iter()
            .take_while(|r| r.cycle <= first)
            .count();
        let warmup = before + v.warmup_updates() as usize;
        let scale = (1u64 << v.spec.frac_bits) as f64;
        let errs: Vec<f64> = self
            .velocity
            .iter()
            .skip(warmup)
            .map(|r| r.raw as f64 / scale - r.truth)
            .collect();
        let last = self.velocity.last()?;
        if errs.is_empty() {
            return None;
        }
        let n = errs.len() as f64;
        let mean = errs.iter().sum::<f64>() / n;
        let var = errs.iter().map(|e| (e - mean) * (e - mean)).sum::<f64>() / n;
        let rate = d.clock_hz / v.period_clocks as f64;
        let lsb_per_turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
        Some(VelStats {
            updates: errs.len(),
            warmup,
            rpm_per_lsb: rate * 60.0 / lsb_per_turn,
            mean_err: mean,
            std_err: var.sqrt(),
            max_err: errs.iter().fold(0.0, |m, e| m.max(e.abs())),
            last: last.raw as f64 / scale,
            last_truth: last.truth,
        })
    }
}

/// The ADC chip model of the configured preset ([`crate::sim::adc_chip`]), converting the
/// encoder's voltages: through the LTC6912-1's gains on the kit, else with the encoder's
/// swing about 1.65 V at the ADC's full scale.
fn adc_chip(d: &Derived, encoder: EncoderModel) -> AdcChipModel {
    let mut enc = encoder;
    let w = d.adc_width;
    let gains = d
        .preamp
        .as_ref()
        .map(|p| [p.gain_a as f64, p.gain_b as f64]);
    adc_chip_model(
        d,
        7,
        Box::new(move |_k, t| {
            let (s, c) = enc.voltages(t);
            match gains {
                Some(g) => [
                    Ltc1407a::code_from_voltage(s, g[0]) as i32,
                    Ltc1407a::code_from_voltage(c, g[1]) as i32,
                ],
                None => [full_scale_code(s, w), full_scale_code(c, w)],
            }
        }),
    )
}

/// The code of a W-bit ADC for an encoder voltage `v`: the encoder's signals swing about
/// 1.65 V, and 1.25 V from there is the ADC's full scale (as on the kit at gain -1).
fn full_scale_code(v: f64, w: u32) -> i32 {
    let half = (1i64 << (w - 1)) as f64;
    let d = ((v - 1.65) / 1.25 * half).round();
    if d.is_nan() {
        return 0;
    }
    d.clamp(-half, half - 1.0) as i32
}

/// The closed loop.
pub struct System {
    d: Derived,
    top: Dut<TopRtl>,
    adc: AdcChipModel,
    /// The LTC6912-1 pre-amplifier (with `[preamp]`).
    amp: Option<Ltc6912>,
    truth: EncoderModel,
    conv_times: HashMap<u64, f64>,
    cycle: u64,
    latency: u64,
    clock_hz: f64,
    result: SimResult,
    rst_cycles: u64,
    record_inputs: bool,
    ma: Option<Box<dyn crate::sim::serial_line::LineMaster>>,
    ssi: Option<Box<dyn crate::sim::serial_line::LineMaster>>,
    spi: Option<std::rc::Rc<std::cell::RefCell<crate::sim::spi_master::SpiMaster>>>,
    qep_b_stuck: Option<(f64, f64)>,
    /// A missing index: `qep_z` held low from `.0` to `.1` seconds.
    no_index: Option<(f64, f64)>,
    /// A stuck ADC data line: the pads read `.2` from `.0` to `.1` seconds.
    sdo_stuck: Option<(f64, f64, bool)>,
    /// The stuck level now applied to the chip model's pads.
    sdo_now: Option<bool>,
    /// The live flags of the previous cycle (`flags`, with the register map).
    flags_prev: u64,
    /// `preset` high from `.0` to `.1` seconds (`[reference] enabled`).
    preset: Option<(f64, f64)>,
    /// `capture` high in each of these (from, to) seconds (`[capture] enabled`), in order.
    capture: Vec<(f64, f64)>,
    /// The first of `capture` that has not ended yet.
    capture_next: usize,
    /// STATUS poll period in cycles ([`System::poll_status`]), the last poll's cycle, and
    /// the bits to clear in the next cycle.
    status_poll: Option<u64>,
    last_poll: u64,
    status_clear: u64,
    /// The capture pin was high in the last cycle.
    capture_high: bool,
    /// (cycle, seconds) at which `capture` rose, not yet answered by `cap_valid`: the first
    /// cycle whose input has it high, and the pulse's own start.
    capture_pending: std::collections::VecDeque<(u64, f64)>,
    /// The quadrature counter on the ABZ outputs (`[abz] enabled`).
    abz: Option<AbzCounter>,
    /// The BiSS-C master whose frames [`BissCheck`] checks.
    biss: Option<std::rc::Rc<std::cell::RefCell<crate::sim::biss_master::BissMaster>>>,
    /// The SSI master whose frames [`WordCheck`] checks.
    ssi_mon: Option<std::rc::Rc<std::cell::RefCell<crate::sim::ssi_master::SsiMaster>>>,
    /// The encoder's SSI digital channel on `abs_clk`/`abs_data` (`[reference] absolute`).
    abs_enc: Option<crate::sim::ssi_encoder::SsiEncoder>,
    /// The cycle of the first referenced sample.
    first_referenced: Option<u64>,
    /// (cycle, BiSS position word, turns) of the latest parallel-bus positions.
    par_history: std::collections::VecDeque<(u64, u64, u64)>,
    trace: Option<crate::sim::vcd::TopTrace>,
    trace_error: Option<std::io::Error>,
}

impl System {
    /// A system for the derived parameters and an encoder (the voltages go through the
    /// LTC6912-1 gains configured for the preamp).
    pub fn new(d: &Derived, encoder: EncoderModel) -> crate::error::Result<System> {
        Self::on(d, encoder, EngineKind::RustHdl)
    }

    /// [`new`](Self::new) with the top simulated by `engine` (the compiled engine builds
    /// it with Yosys and rustc, or loads it from its cache).
    pub fn on(
        d: &Derived,
        encoder: EncoderModel,
        engine: EngineKind,
    ) -> crate::error::Result<System> {
        let top = Dut::new(d, engine, &IN_PINS, &OUT_PINS)?;
        let truth = encoder.clone();
        // The encoder's digital channel, as its data sheet and the config's word give it,
        // behind the pins of the line timing's one derivation (`SsiTiming`) and a 5 m cable.
        let abs_enc = d.absolute.as_ref().map(|a| {
            crate::sim::ssi_encoder::SsiEncoder::new(
                a.word(),
                encoder.clone(),
                d.clock_hz,
                crate::sim::adc_pins::PinTiming::from_io(&a.timing().io),
                5.0 * crate::sim::ssi_encoder::CABLE_NS_PER_M,
                11,
            )
        });
        let adc = adc_chip(d, encoder);
        Ok(System {
            d: d.clone(),
            top,
            adc,
            amp: d.preamp.as_ref().map(|_| Ltc6912::new(d.clock_hz)),
            result: SimResult::default(),
            abz: d.abz.as_ref().map(AbzCounter::new),
            truth,
            conv_times: HashMap::new(),
            cycle: 0,
            latency: crate::blocks::top::hdl::conv_to_position_cycles(d) as u64,
            clock_hz: d.clock_hz,
            rst_cycles: 2,
            record_inputs: false,
            ma: None,
            ssi: None,
            spi: None,
            qep_b_stuck: None,
            no_index: None,
            sdo_stuck: None,
            sdo_now: None,
            flags_prev: 0,
            preset: None,
            capture: Vec::new(),
            capture_next: 0,
            status_poll: None,
            last_poll: 0,
            status_clear: 0,
            capture_high: false,
            capture_pending: std::collections::VecDeque::new(),
            biss: None,
            ssi_mon: None,
            abs_enc,
            first_referenced: None,
            par_history: std::collections::VecDeque::new(),
            trace: None,
            trace_error: None,
        })
    }

    /// Streams every cycle's pins into `t` from now on (see [`crate::sim::vcd`]).
    pub fn trace_to(&mut self, t: crate::sim::vcd::TopTrace) {
        self.trace = Some(t);
    }

    /// Ends the trace: flushes it and returns the first write error, if any.
    pub fn finish_trace(&mut self) -> std::io::Result<()> {
        if let Some(e) = self.trace_error.take() {
            return Err(e);
        }
        match self.trace.take() {
            Some(t) => t.finish(),
            None => Ok(()),
        }
    }

    /// A comparator fault: QEP B held low from `from` to `to` seconds.
    pub fn qep_b_stuck_low(&mut self, from: f64, to: f64) {
        self.qep_b_stuck = Some((from, to));
    }

    /// A missing index: `qep_z` held low from `from` to `to` seconds (the index track lost,
    /// or its comparator dead).
    pub fn no_index(&mut self, from: f64, to: f64) {
        self.no_index = Some((from, to));
    }

    /// A stuck ADC data line: from `from` to `to` seconds every data line of the chip model
    /// reads `level` at the FPGA's pad (`crate::sim::adc_chip::AdcChipModel::set_sdo_stuck`).
    pub fn sdo_stuck(&mut self, from: f64, to: f64, level: bool) {
        self.sdo_stuck = Some((from, to, level));
    }

    /// Drives `preset` (`[reference] enabled`) high from `from` to `to` seconds.
    pub fn preset_pulse(&mut self, from: f64, to: f64) {
        self.preset = Some((from, to));
    }

    /// The encoder's SSI digital channel (`[reference] absolute`), to set its alignment
    /// error, cable or timing before the run; None without the absolute start.
    pub fn absolute_encoder_mut(&mut self) -> Option<&mut crate::sim::ssi_encoder::SsiEncoder> {
        self.abs_enc.as_mut()
    }

    /// Drives `capture` (`[capture] enabled`) high in each (from, to) interval, in seconds
    /// (sorted here by their start).
    pub fn capture_pulses(&mut self, pulses: &[(f64, f64)]) {
        self.capture = pulses.to_vec();
        self.capture.sort_by(|a, b| a.0.total_cmp(&b.0));
        self.capture_next = 0;
    }

    /// Reads STATUS (`[registers] enabled`) through the AXI4-Lite slave every `period`
    /// cycles and clears the faults it found, recording each in [`SimResult::faults`].
    pub fn poll_status(&mut self, period: u64) {
        self.status_poll = Some(period.max(8));
    }

    /// Keeps no records: the statistics are gathered as the samples come, leaving out the
    /// first `skip` (memory stays bounded however long the run; [`SimResult::records`]
    /// stays empty).
    pub fn stream_stats(&mut self, skip: usize) {
        self.stream_stats_from(skip, 0);
    }

    /// [`stream_stats`](Self::stream_stats), also leaving out the samples that leave the
    /// top before cycle `from_cycle` (`simulate --settle`).
    pub fn stream_stats_from(&mut self, skip: usize, from_cycle: u64) {
        self.result.streamed = Some(StreamStats {
            skip,
            from_cycle,
            ..Default::default()
        });
    }

    /// Records the design's inputs of every cycle (see [`SimResult::inputs`]).
    pub fn record_inputs(&mut self) {
        self.record_inputs = true;
    }

    /// Connects a BiSS (or SSI) master model to `biss_ma`/`biss_slo` (MA idles high
    /// without one).
    pub fn attach_master(&mut self, m: Box<dyn crate::sim::serial_line::LineMaster>) {
        self.ma = Some(m);
    }

    /// The line every serial master model sees: the system clock and one board trace.
    fn line_timing(&self) -> crate::sim::serial_line::LineTiming {
        crate::sim::serial_line::LineTiming {
            clock_hz: self.clock_hz,
            line_delay_ns: self.d.io_timing.trace_ns,
        }
    }

    /// Connects a BiSS-C master that reads frames back to back at `ma_hz` for `seconds`, and
    /// checks each against the parallel bus ([`SimResult::biss`]).
    pub fn monitor_biss(&mut self, ma_hz: f64, seconds: f64) {
        let p = &self.d.biss;
        let gap_ns = 1000.0;
        let frame_s =
            (p.frame_rising_edges() + 1) as f64 / ma_hz + p.timeout_us() * 1e-6 + gap_ns * 1e-9;
        let n = (seconds / frame_s).ceil() as usize + 1;
        let reqs = vec![crate::sim::serial_line::FrameRequest::new(ma_hz).gap(gap_ns); n];
        let m = self.biss_master(reqs);
        self.biss = Some(m);
        self.result.biss = Some(BissCheck {
            ma_hz: ma_hz.round() as u64,
            ..BissCheck::default()
        });
    }

    /// A BiSS-C master for this design's frames, connected to `biss_ma`/`biss_slo`, that
    /// clocks the frames `reqs` (1 us apart after the slave is ready).
    fn biss_master(
        &mut self,
        reqs: Vec<crate::sim::serial_line::FrameRequest>,
    ) -> std::rc::Rc<std::cell::RefCell<crate::sim::biss_master::BissMaster>> {
        use crate::sim::biss_master::{BissMaster, BissMasterConfig};
        let p = &self.d.biss;
        let mut c = BissMasterConfig::new(self.line_timing(), p.data_bits(), p.multiturn_bits);
        c.word.gray = p.gray;
        c.word = c.word.with_velocity(p.velocity_bits);
        let m = std::rc::Rc::new(std::cell::RefCell::new(BissMaster::new(c, reqs, 500.0)));
        self.ma = Some(Box::new(m.clone()));
        m
    }

    /// Connects a BiSS-C master that clocks one frame per CDM bit of `cdm` at `ma_hz` (a
    /// control session, `crate::sim::biss_control::Session`); its frames carry the CDS
    /// answers.
    pub fn biss_session(
        &mut self,
        ma_hz: f64,
        cdm: &[bool],
    ) -> std::rc::Rc<std::cell::RefCell<crate::sim::biss_master::BissMaster>> {
        let reqs = cdm
            .iter()
            .map(|&cdm| crate::sim::serial_line::FrameRequest {
                cdm,
                ..crate::sim::serial_line::FrameRequest::new(ma_hz).gap(1000.0)
            })
            .collect();
        self.biss_master(reqs)
    }

    /// Checks the BiSS-C master's frames finished since the last call against the
    /// parallel bus's history.
    fn check_biss_frames(&mut self) {
        let (Some(m), Some(c)) = (&self.biss, self.result.biss.as_mut()) else {
            return;
        };
        let m = m.borrow();
        let p = &self.d.biss;
        let (pw, pb) = (self.d.position_width, p.position_bits);
        for f in m.frames().iter().skip(c.frames as usize) {
            c.frames += 1;
            let data = match &f.outcome {
                crate::sim::biss_master::Outcome::Data(data) => data,
                _ => {
                    c.failed += 1;
                    continue;
                }
            };
            if !data.crc_ok() {
                c.crc_errors += 1;
                continue;
            }
            c.good += 1;
            // The slave latches at its first MA edge, a line delay and the synchronizer
            // after the master's.
            let latch = latch_cycle(&self.d, f.t_start_ns, p.latch_latency());
            let widths = (pw, pb, p.multiturn_bits);
            if !par_match(
                &self.par_history,
                latch,
                widths,
                (data.position, data.turns),
            ) {
                c.position_mismatches += 1;
            }
        }
    }

    /// Connects an SSI master that reads frames back to back at `clock_hz` for `seconds`,
    /// and checks each against the parallel bus ([`SimResult::ssi`]). Needs `[ssi] enabled`.
    pub fn monitor_ssi(&mut self, clock_hz: f64, seconds: f64) {
        use crate::sim::ssi_master::{SsiMaster, SsiMasterConfig};
        let Some(p) = self.d.ssi.clone() else {
            return;
        };
        let t = self.line_timing();
        let mut c = SsiMasterConfig::new(t, p.data_bits(), p.multiturn_bits);
        c.word.gray = p.gray;
        c.word = c.word.with_velocity(p.velocity_bits);
        c.error_bit = p.error_bit;
        let gap_ns = 1000.0;
        let frame_s =
            (p.frame_bits() + 2) as f64 / clock_hz + p.timeout_us() * 1e-6 + gap_ns * 1e-9;
        let n = (seconds / frame_s).ceil() as usize + 1;
        let reqs = vec![crate::sim::serial_line::FrameRequest::new(clock_hz).gap(gap_ns); n];
        let m = std::rc::Rc::new(std::cell::RefCell::new(SsiMaster::new(c, reqs, 500.0)));
        self.ssi = Some(Box::new(m.clone()));
        self.ssi_mon = Some(m);
        self.result.ssi = Some(WordCheck {
            clock_hz: clock_hz.round() as u64,
            ..WordCheck::default()
        });
    }

    /// Checks the SSI master's frames finished since the last call.
    fn check_ssi_frames(&mut self) {
        let (Some(m), Some(c), Some(p)) = (&self.ssi_mon, self.result.ssi.as_mut(), &self.d.ssi)
        else {
            return;
        };
        let m = m.borrow();
        for f in m.frames().iter().skip(c.frames as usize) {
            c.frames += 1;
            let crate::sim::ssi_master::SsiOutcome::Data(data) = &f.outcome else {
                c.failed += 1;
                continue;
            };
            c.good += 1;
            // The slave latches at its first clock edge, a line delay and the synchronizer
            // after the master's.
            let latch = latch_cycle(&self.d, f.t_start_ns, p.latch_latency());
            let widths = (self.d.position_width, p.position_bits, p.multiturn_bits);
            if !par_match(
                &self.par_history,
                latch,
                widths,
                (data.position, data.turns),
            ) {
                c.position_mismatches += 1;
            }
        }
    }

    /// Connects an SPI master (mode 0) that reads one word per transaction at `sck_hz` for
    /// `seconds`, and checks each against the parallel bus ([`SimResult::spi`]). Needs
    /// `[spi] enabled`.
    pub fn monitor_spi(&mut self, sck_hz: f64, seconds: f64) {
        use crate::sim::spi_master::{SpiMaster, SpiTxn};
        let Some(p) = &self.d.spi else {
            return;
        };
        let t = self.line_timing();
        let gap_ns = 1000.0;
        let txn_s = (p.word_bits() + 2) as f64 / sck_hz + gap_ns * 1e-9;
        let n = (seconds / txn_s).ceil() as usize + 1;
        let txn = SpiTxn {
            mode: 0,
            sck_hz,
            clocks: p.word_bits(),
            gap_ns,
        };
        let m = std::rc::Rc::new(std::cell::RefCell::new(SpiMaster::new(
            t,
            &vec![txn; n],
            500.0,
        )));
        self.spi = Some(m);
        self.result.spi = Some(WordCheck {
            clock_hz: sck_hz.round() as u64,
            ..WordCheck::default()
        });
    }

    /// Checks the SPI transactions whose last bit the master has read (its sampling
    /// instant a round trip and a clock behind the simulated time).
    fn check_spi_words(&mut self) {
        let (Some(m), Some(c), Some(p)) = (&self.spi, self.result.spi.as_mut(), &self.d.spi) else {
            return;
        };
        let m = m.borrow();
        let now_ns = self.cycle as f64 * 1e9 / self.clock_hz;
        let settled_ns = now_ns - 2.0 * self.d.io_timing.trace_ns - 2e9 / self.clock_hz;
        while let Some(x) = m.txns().get(c.frames as usize) {
            if x.samples.last().is_none_or(|&ts| ts > settled_ns) {
                break;
            }
            let fmt = crate::sim::serial_line::WordFormat {
                gray: p.gray,
                ..crate::sim::serial_line::WordFormat::new(p.data_bits(), p.multiturn_bits)
                    .with_velocity(p.velocity_bits)
            };
            let bits = m.word(c.frames as usize);
            c.frames += 1;
            let Some(w) = crate::sim::spi_master::decode_word(&bits, &fmt) else {
                c.failed += 1;
                continue;
            };
            c.good += 1;
            // Chip select latches the word (cs_n reaches the slave a line delay later).
            let latch = latch_cycle(&self.d, x.t_cs_ns, p.latch_latency());
            let widths = (self.d.position_width, p.position_bits, p.multiturn_bits);
            if !par_match(&self.par_history, latch, widths, (w.position, w.turns)) {
                c.position_mismatches += 1;
            }
        }
    }

    /// Connects an SSI master model to `ssi_clk`/`ssi_data` (the clock idles high without
    /// one).
    pub fn attach_ssi_master(&mut self, m: Box<dyn crate::sim::serial_line::LineMaster>) {
        self.ssi = Some(m);
    }

    /// Connects an SPI master model to `enc_sck`/`enc_cs_n`/`enc_miso` (chip select high
    /// without one); the caller keeps the handle to read its words.
    pub fn attach_spi_master(
        &mut self,
        m: std::rc::Rc<std::cell::RefCell<crate::sim::spi_master::SpiMaster>>,
    ) {
        self.spi = Some(m);
    }

    /// The rust-hdl design (to read its outputs after a cycle); None on the compiled engine.
    pub fn top(&self) -> Option<&TopRtl> {
        self.top.rtl()
    }

    /// The engine that runs the top (after any fallback, see [`Dut::note`]).
    pub fn engine(&self) -> EngineKind {
        self.top.engine()
    }

    /// Why the engine that runs is not the one asked for, if it is not.
    pub fn engine_note(&self) -> Option<&str> {
        self.top.note()
    }

    /// The design's outputs in co-simulation order (either engine).
    pub fn sample(&self) -> Vec<u64> {
        self.top.sample()
    }

    /// Connects the design; call once.
    pub fn start(&mut self) -> Result<(), NoConvergence> {
        self.top.start()
    }

    /// Simulates `cycles` clock cycles.
    pub fn run(&mut self, cycles: u64) -> Result<(), NoConvergence> {
        let fine = self.d.fine_bits;
        let lsb_per_rad = (1u64 << fine) as f64 / FRAC_PI_2;
        let qturn = self.d.quadrants_per_turn as i64;
        for _ in 0..cycles {
            // Pins are read before the edge: the chip models see the levels the design
            // drove during the previous cycle, as real chips do.
            let conv = self.top.get(O_CONV) != 0;
            let sck = self.top.get(O_SCK) != 0;
            let now = self.cycle as f64 / self.clock_hz;
            if let Some((a, b, level)) = self.sdo_stuck {
                let stuck = (now >= a && now < b).then_some(level);
                if stuck != self.sdo_now {
                    self.adc.set_sdo_stuck(stuck);
                    self.sdo_now = stuck;
                }
            }
            // Conversions are counted here and forgotten: a long run keeps no per-sample
            // history.
            let [miso, miso_b] = self.adc.step(conv, sck);
            if self.adc.take_conversion() {
                self.conv_times
                    .insert(self.cycle, self.cycle as f64 / self.clock_hz);
            }
            if let Some(amp) = self.amp.as_mut() {
                amp.step(
                    self.top.get(O_AMP_CS) != 0,
                    sck,
                    self.top.get(O_AMP_MOSI) != 0,
                    self.top.get(O_AMP_SHDN) != 0,
                );
            }
            let rst = self.cycle < self.rst_cycles;
            self.top.set(I_RST, rst as u64);
            self.top.set(I_MISO, miso as u64);
            self.top.set(I_MISO_B, miso_b as u64);
            let ma = match self.ma.as_mut() {
                Some(m) => m.ma_for_cycle(self.cycle as usize),
                None => true,
            };
            self.top.set(I_MA, ma as u64);
            // Comparators on the noise-free tracks: A = cos > 0, B = sin > 0 (forward = the
            // angle increasing), Z = index in the first quadrant of every turn; on the
            // scale's angle, as the tracks (the eccentricity moves them alike).
            let th = self.truth.scale_angle(self.cycle as f64 / self.clock_hz);
            let (qa, mut qb) = (th.cos() >= 0.0, th.sin() >= 0.0);
            if let Some((a, b)) = self.qep_b_stuck {
                if now >= a && now < b {
                    qb = false;
                }
            }
            let turn = std::f64::consts::TAU * self.d.quadrants_per_turn as f64 / 4.0;
            let qz = th.rem_euclid(turn) < std::f64::consts::FRAC_PI_2
                && !self.no_index.is_some_and(|(a, b)| now >= a && now < b);
            self.top.set(I_QEP_A, qa as u64);
            self.top.set(I_QEP_B, qb as u64);
            self.top.set(I_QEP_Z, qz as u64);
            let preset = self.preset.is_some_and(|(a, b)| now >= a && now < b);
            self.top.set(I_PRESET, preset as u64);
            while self
                .capture
                .get(self.capture_next)
                .is_some_and(|&(_, b)| now >= b)
            {
                self.capture_next += 1;
            }
            let pulse = self
                .capture
                .get(self.capture_next)
                .filter(|&&(a, b)| now >= a && now < b);
            let capture = pulse.is_some();
            if let (Some(&(a, _)), false) = (pulse, self.capture_high) {
                self.capture_pending.push_back((self.cycle, a));
            }
            self.capture_high = capture;
            self.top.set(I_CAPTURE, capture as u64);
            // The encoder's digital channel answers the SSI clock the design drove.
            if let Some(e) = self.abs_enc.as_mut() {
                let data = e.step(self.top.get(O_ABS_CLK) != 0);
                self.top.set(I_ABS_DATA, data as u64);
            }
            // The STATUS poll: a one-clock read request every period (the slave is idle then:
            // nothing else drives it), the data taken at once, and a one-clock write of the
            // bits found (write 1 to clear) in the clock after.
            if let Some(period) = self.status_poll {
                let status = crate::blocks::regmap::STATUS_WORD as u64 * 4;
                let read = self.cycle > 0 && self.cycle.is_multiple_of(period);
                let clear = self.status_clear != 0;
                self.top.set(I_ARADDR, status);
                self.top.set(I_ARVALID, read as u64);
                self.top.set(I_RREADY, 1);
                self.top.set(I_BREADY, 1);
                self.top.set(I_AWADDR, status);
                self.top.set(I_WDATA, self.status_clear);
                self.top.set(I_WSTRB, 0xf);
                self.top.set(I_AWVALID, clear as u64);
                self.top.set(I_WVALID, clear as u64);
                self.status_clear = 0;
            }
            let ssi_clk = match self.ssi.as_mut() {
                Some(m) => m.ma_for_cycle(self.cycle as usize),
                None => true,
            };
            self.top.set(I_SSI_CLK, ssi_clk as u64);
            let (sck, cs_n) = match &self.spi {
                Some(m) => m.borrow_mut().lines_for_cycle(self.cycle as usize),
                None => (false, true),
            };
            self.top.set(I_ENC_SCK, sck as u64);
            self.top.set(I_ENC_CS_N, cs_n as u64);
            self.top.tick()?;
            // The inputs just applied, read back by name in the port table's order.
            let row = (self.record_inputs || self.trace.is_some()).then(|| self.top.input_row());
            if let (Some(t), Some(r)) = (self.trace.as_mut(), row.as_ref()) {
                let outs = self.top.sample();
                if let Err(e) = t.cycle(r, &outs) {
                    self.trace_error = Some(e);
                    self.trace = None;
                }
            }
            if self.record_inputs {
                if let Some(r) = row {
                    self.result.inputs.push(r);
                }
            }
            if let Some(m) = self.ma.as_mut() {
                m.push_slo(self.top.get(O_SLO) != 0);
            }
            self.check_biss_frames();
            if let Some(m) = self.ssi.as_mut() {
                m.push_slo(self.top.get(O_SSI_DATA) != 0);
            }
            self.check_ssi_frames();
            if let Some(m) = &self.spi {
                m.borrow_mut().push_miso(self.top.get(O_ENC_MISO) != 0);
            }
            self.check_spi_words();
            if self.record_inputs {
                self.result.outputs.push(self.top.sample());
            }
            self.cycle += 1;
            if self.abz.is_some() {
                let g = |k| self.top.get(k) != 0;
                let pins = (g(O_ABZ_A), g(O_ABZ_B), g(O_ABZ_Z));
                let qmask = crate::blocks::mask(self.d.position_width - fine);
                let sample = g(O_VALID)
                    .then(|| ((self.top.get(O_QC) & qmask) << fine) | self.top.get(O_FINE));
                if let Some(c) = self.abz.as_mut() {
                    c.step(self.cycle, pins, sample);
                }
            }
            if self.top.get(O_VALID) != 0 {
                let qc = self.top.get(O_QC);
                let pos = (qc << fine) | self.top.get(O_FINE);
                let turns = if self.d.multiturn_bits == 0 {
                    0
                } else {
                    sext(self.top.get(O_TURNS), self.d.multiturn_bits)
                };
                let conv_cycle = self.cycle.saturating_sub(self.latency + 1);
                let t = match self.conv_times.remove(&conv_cycle) {
                    Some(t) => t,
                    None => {
                        self.result.latency_mismatches += 1;
                        conv_cycle as f64 / self.clock_hz
                    }
                };
                let rec = Record {
                    cycle: self.cycle,
                    conv_cycle,
                    position: pos,
                    turns,
                    error: self.top.get(O_ERROR) != 0,
                    warning: self.top.get(O_WARNING) != 0,
                    referenced: self.top.get(O_REFERENCED) != 0,
                    unwrapped: turns * qturn * (1i64 << fine) + pos as i64,
                    truth: self.truth.electrical_angle(t) * lsb_per_rad,
                };
                if self.biss.is_some() || self.ssi_mon.is_some() || self.result.spi.is_some() {
                    if self.par_history.len() == PAR_HISTORY {
                        self.par_history.pop_front();
                    }
                    self.par_history
                        .push_back((self.cycle, pos, self.top.get(O_TURNS)));
                }
                if rec.referenced && self.first_referenced.is_none() {
                    self.first_referenced = Some(self.cycle);
                }
                self.result.decoded += 1;
                match self.result.streamed.as_mut() {
                    Some(s) => s.add(&self.d, &rec),
                    None => self.result.records.push(rec),
                }
            }
            if self.status_poll.is_some() {
                self.watch_faults();
            }
            if self.top.get(O_CAP_VALID) != 0 {
                let (pin_cycle, rise) = self.capture_pending.pop_front().unwrap_or_default();
                let qc = self.top.get(O_CAP_QC);
                let pos = (qc << fine) | self.top.get(O_CAP_FINE);
                let turns = if self.d.multiturn_bits == 0 {
                    0
                } else {
                    sext(self.top.get(O_CAP_TURNS), self.d.multiturn_bits)
                };
                let velocity = match &self.d.velocity {
                    Some(v) => sext(self.top.get(O_CAP_VELOCITY), v.spec.width),
                    None => 0,
                };
                self.result.captures.push(CaptureRecord {
                    cycle: self.cycle,
                    pin_cycle,
                    position: pos,
                    turns,
                    unwrapped: turns * qturn * (1i64 << fine) + pos as i64,
                    age: self.top.get(O_CAP_AGE),
                    velocity,
                    truth: self.truth.electrical_angle(rise) * lsb_per_rad,
                });
            }
            if let Some(v) = &self.d.velocity {
                if self.top.get(O_VELOCITY_VALID) != 0 {
                    let raw = sext(self.top.get(O_VELOCITY), v.spec.width);
                    // The strobe's edge, back by the estimator's latency and the
                    // CONV-to-position latency.
                    let tick = self.cycle as f64 - 1.0 - v.latency() as f64 - self.latency as f64;
                    let t1 = tick / self.clock_hz;
                    let t0 = (tick - v.period_clocks as f64) / self.clock_hz;
                    let truth = (self.truth.electrical_angle(t1) - self.truth.electrical_angle(t0))
                        * lsb_per_rad;
                    self.result.velocity.push(VelRecord {
                        cycle: self.cycle,
                        raw,
                        truth,
                    });
                }
            }
        }
        self.result.cycles = self.cycle;
        Ok(())
    }

    /// The faults of this cycle (with the register map): the live `flags` port every cycle
    /// (the exact clock a fault is raised), and the data of a STATUS read, whose bits the
    /// next cycle clears (write 1).
    fn watch_faults(&mut self) {
        use crate::blocks::regmap::{FAULTS, STATUS_MASK};
        let record = |faults: &mut Vec<FaultRecord>, name: &'static str| -> usize {
            match faults.iter().position(|r| r.name == name) {
                Some(k) => k,
                None => {
                    faults.push(FaultRecord::new(name));
                    faults.len() - 1
                }
            }
        };
        let flags = self.top.get(O_FLAGS);
        for f in FAULTS {
            if flags >> f.lsb & 1 == 0 {
                continue;
            }
            let k = record(&mut self.result.faults, f.name);
            let r = &mut self.result.faults[k];
            r.raised.get_or_insert(self.cycle);
            r.last = self.cycle;
            if self.flags_prev >> f.lsb & 1 == 0 {
                r.rises += 1;
            }
        }
        self.flags_prev = flags;
        if self.top.get(O_RVALID) == 0 {
            return;
        }
        let bits = self.top.get(O_RDATA) & STATUS_MASK as u64;
        self.result.status_polls += 1;
        for f in FAULTS {
            let set = bits >> f.lsb & 1 == 1;
            let found = self.result.faults.iter().position(|r| r.name == f.name);
            if !set {
                if let Some(k) = found {
                    let r = &mut self.result.faults[k];
                    r.cleared = r.polls > 0;
                }
                continue;
            }
            let k = record(&mut self.result.faults, f.name);
            let r = &mut self.result.faults[k];
            if r.polls == 0 {
                r.after = self.last_poll;
                r.by = self.cycle;
            }
            r.polls += 1;
            r.cleared = false;
        }
        self.last_poll = self.cycle;
        self.status_clear = bits;
    }

    /// Finishes the run and returns its result.
    pub fn finish(mut self) -> SimResult {
        self.result.adc_violations = self.adc.violation_messages();
        self.result.absolute = self.abs_enc.as_ref().map(|e| AbsoluteCheck {
            latches: e.latches().to_vec(),
            violations: e.violations().to_vec(),
            referenced_cycle: self.first_referenced,
            line_delay_ns: e.line_delay_ns(),
        });
        self.result.abz = self.abz.as_ref().map(|c| c.figures);
        if let Some(amp) = &self.amp {
            self.result.amp_violations =
                amp.violations().iter().map(|v| format!("{v:?}")).collect();
            self.result.amp_gains = amp.gains();
        }
        self.result
    }
}

/// A shared master: the system drives it while the caller keeps a handle to read its
/// frame reports.
impl<M: crate::sim::serial_line::LineMaster> crate::sim::serial_line::LineMaster
    for std::rc::Rc<std::cell::RefCell<M>>
{
    fn ma_for_cycle(&mut self, k: usize) -> bool {
        self.borrow_mut().ma_for_cycle(k)
    }
    fn push_slo(&mut self, slo: bool) {
        self.borrow_mut().push_slo(slo)
    }
}

#[cfg(test)]
mod tests {
    use super::par_match;
    use std::collections::VecDeque;

    /// A word matches one of the two latest positions at or before the latch (+1 clock),
    /// cut to the interface's bits, and the reset value before the first position; any
    /// other word is a mismatch.
    #[test]
    fn par_match_takes_the_two_latest_positions_at_the_latch() {
        // (cycle, 20-bit position, turns)
        let h: VecDeque<(u64, u64, u64)> =
            [(100, 0x12345, 3), (200, 0x23456, 3), (300, 0x34567, 4)].into();
        let w = (20, 16, 4); // 16 position bits, 4 turn bits
        assert!(par_match(&h, 250, w, (0x2345, 3)));
        assert!(par_match(&h, 250, w, (0x1234, 3)));
        assert!(par_match(&h, 299, w, (0x3456, 4)), "latch + 1");
        assert!(!par_match(&h, 250, w, (0x3456, 4)), "after the latch");
        assert!(!par_match(&h, 350, w, (0x1234, 3)), "three back");
        assert!(!par_match(&h, 250, w, (0x2346, 3)), "one LSB off");
        assert!(!par_match(&h, 250, w, (0x2345, 2)), "turns off");
        assert!(par_match(&h, 50, w, (0, 0)), "reset value before the first");
        assert!(!par_match(&h, 50, w, (0x1234, 3)));
        assert!(par_match(&VecDeque::new(), 50, w, (0, 0)));
    }
}
