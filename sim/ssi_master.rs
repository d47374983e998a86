//! SSI master model, written from the protocol (see [`crate::blocks::ssi`]'s table), on the
//! shared master core ([`crate::sim::serial_master`]) and its line model
//! ([`crate::sim::serial_line`]: continuous-time master, line delay d both ways, slave
//! stepped one system clock at a time).
//!
//! Per frame the master gives B + 1 clock pulses (B = data bits, plus the error bit when
//! configured) starting with a falling edge, reads the answer to rising edge n (n = 1..B) at
//! the next rising edge (or at a fixed delay after edge n), checks that the line answers the
//! last pulse with 0, stops with the clock high and measures the time until the line returns
//! high (the slave's monoflop time, round trip included). The next frame starts when the
//! line is high again (or, on request, without waiting).
use crate::sim::serial_line::{word_of, Burst, LineTiming, WordFormat};
use crate::sim::serial_master::{FrameProtocol, MasterFrame, MasterLine, SerialMaster};

/// Master settings.
#[derive(Clone, Debug, PartialEq)]
pub struct SsiMasterConfig {
    /// Line timing, recovery and give-up times.
    pub line: MasterLine,
    /// The data word: N bits, M of them multi-turn, binary or Gray.
    pub word: WordFormat,
    /// One error bit follows the data.
    pub error_bit: bool,
    /// Sample the answer to rising edge n this long after it; None = at rising edge n+1.
    pub sample_delay_ns: Option<f64>,
}

impl SsiMasterConfig {
    /// Master sampling at the next rising edge, binary, no error bit.
    pub fn new(timing: LineTiming, data_bits: u32, multiturn_bits: u32) -> Self {
        Self {
            line: MasterLine::new(timing),
            word: WordFormat::new(data_bits, multiturn_bits),
            error_bit: false,
            sample_delay_ns: None,
        }
    }
    fn frame_bits(&self) -> u32 {
        self.word.data_bits + self.word.velocity_bits + self.error_bit as u32
    }
}

/// A frame's content as the master read it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SsiData {
    /// The data word as received.
    pub data: u64,
    /// Single-turn position (binary).
    pub position: u64,
    /// Turn count (binary).
    pub turns: u64,
    /// The velocity word after the data, sign-extended (`[velocity] in_frames`).
    pub velocity: Option<i64>,
    /// The error bit, when configured.
    pub error: Option<bool>,
    /// The line answered the last clock pulse with 0.
    pub tail_low: bool,
}

/// How a frame ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SsiOutcome {
    /// Read completely.
    Data(SsiData),
    /// The request stopped the clock early.
    Aborted,
    /// The line never returned high.
    NotReady,
}
/// Report of one frame (`delay_ns` is always None: the SSI master measures no delay).
pub type SsiFrame = MasterFrame<SsiOutcome>;

/// What an SSI frame has read so far.
#[derive(Clone, Debug, Default)]
pub struct SsiRun {
    bits: Vec<bool>,
    tail_low: Option<bool>,
}

/// The SSI master model.
pub type SsiMaster = SerialMaster<SsiMasterConfig>;

impl FrameProtocol for SsiMasterConfig {
    type Run = SsiRun;
    type Outcome = SsiOutcome;

    fn line(&self) -> &MasterLine {
        &self.line
    }
    /// B + 1: the frame's bits and the tail pulse.
    fn frame_rises(&self) -> Option<u32> {
        Some(self.frame_bits() + 1)
    }
    fn new_run(&self) -> SsiRun {
        SsiRun::default()
    }
    /// Answers to rising edges 1..=B are data; B + 1 is the tail.
    fn wants_sample(&self, _run: &SsiRun, n: u32) -> bool {
        n <= self.frame_bits() + 1
    }
    fn sample_time(&self, _run: &SsiRun, burst: &Burst, n: u32) -> Option<f64> {
        Some(match self.sample_delay_ns {
            Some(d) => burst.rise(n) + d,
            None => burst.rise(n + 1),
        })
    }
    fn on_sample(&self, run: &mut SsiRun, _burst: &mut Burst, n: u32, v: bool) {
        if n <= self.frame_bits() {
            run.bits.push(v);
        } else {
            run.tail_low = Some(!v);
        }
    }
    /// The monoflop ends with the first rise after the (low) answer to the last pulse.
    fn complete(&self, run: &SsiRun) -> bool {
        run.tail_low.is_some()
    }
    fn outcome(&self, run: &SsiRun) -> SsiOutcome {
        match run.tail_low {
            Some(tail_low) if run.bits.len() == self.frame_bits() as usize => {
                // N data bits, V velocity bits, the error bit.
                let n = self.word.data_bits as usize;
                let e = n + self.word.velocity_bits as usize;
                let data = word_of(&run.bits[..n]);
                let (position, turns) = self.word.split(data);
                SsiOutcome::Data(SsiData {
                    data,
                    position,
                    turns,
                    velocity: self.word.velocity(&run.bits[n..e]),
                    error: self.error_bit.then(|| run.bits[e]),
                    tail_low,
                })
            }
            _ => SsiOutcome::Aborted,
        }
    }
    fn not_ready(&self) -> SsiOutcome {
        SsiOutcome::NotReady
    }
}
