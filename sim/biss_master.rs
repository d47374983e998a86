//! BiSS-C master model, written from the protocol (the iC-Haus BiSS C description as
//! summarised in [`crate::blocks::biss`]'s frame table), not from the slave's code. It runs
//! on the shared master core ([`crate::sim::serial_master`]) and its line model
//! ([`crate::sim::serial_line`]: continuous-time master, line delay d both ways, slave
//! stepped one system clock at a time).
//!
//! The master gives MA as a free-running square wave during a frame (low first: the frame
//! begins with a falling edge), then:
//!
//! * samples SL once per rising edge n: with line-delay compensation (the default, as BiSS
//!   masters do) it measures D, from rising edge 2 to the falling SL edge of the Ack, and
//!   samples the answer to edge n at r_n + D + T/2, the middle of its bit cell; without
//!   compensation it samples the answer to edge n at the next rising edge r_(n+1), which only
//!   works while the round trip plus the slave's response time stays below one MA period;
//! * finds Ack (first 0) and Start (next 1), reads CDS, the data word, nE, nW and the CRC,
//!   checks the CRC with its own polynomial division, gives one more clock pulse (the slave
//!   answers 0: the timeout), stops with MA high, and measures the time until SL returns high
//!   (the slave's timeout, round trip included);
//! * starts the next frame when SL is high (or, on request, without waiting).
//!
//! Every frame is reported ([`BissFrame`]): data, decoded position and turns, flags, received
//! and expected CRC, or what went wrong (no Ack, no Start, aborted on request, slave never
//! ready).
use crate::sim::serial_line::{word_of, Burst, LineTiming, SlaveLine, WordFormat};
use crate::sim::serial_master::{FrameProtocol, MasterFrame, MasterLine, SerialMaster};

/// Master settings.
#[derive(Clone, Debug, PartialEq)]
pub struct BissMasterConfig {
    /// Line timing, recovery and give-up times.
    pub line: MasterLine,
    /// The data word: N bits, M of them multi-turn, binary or Gray.
    pub word: WordFormat,
    /// Line-delay compensation (sample at r_n + D + T/2) instead of sampling at r_(n+1).
    pub compensate: bool,
    /// Ack bits accepted before the Start bit (processing time) before giving up.
    pub max_ack_bits: u32,
}

impl BissMasterConfig {
    /// Compensating master for N data bits of which M are multi-turn, binary.
    pub fn new(timing: LineTiming, data_bits: u32, multiturn_bits: u32) -> Self {
        Self {
            line: MasterLine::new(timing),
            word: WordFormat::new(data_bits, multiturn_bits),
            compensate: true,
            max_ack_bits: 80,
        }
    }
}

/// A frame's content as the master read it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FrameData {
    /// Zeros read before the Start bit (Ack length in MA periods).
    pub ack_bits: u32,
    /// The CDS bit.
    pub cds: bool,
    /// The data word as received (Gray or binary), MSB first.
    pub data: u64,
    /// Single-turn position (binary, after Gray decoding).
    pub position: u64,
    /// Turn count (binary, after Gray decoding).
    pub turns: u64,
    /// nE as received (false = error).
    pub n_e: bool,
    /// The velocity word after the data, sign-extended (`[velocity] in_frames`; None without
    /// one in the word format).
    pub velocity: Option<i64>,
    /// nW as received (false = warning).
    pub n_w: bool,
    /// The six CRC bits as received.
    pub crc_received: u8,
    /// The six CRC bits the master expects (inverted CRC6 of data, nE, nW).
    pub crc_expected: u8,
    /// SL was low in answer to the final clock pulse (the timeout).
    pub stop_low: bool,
}

impl FrameData {
    /// The CRC matches.
    pub fn crc_ok(&self) -> bool {
        self.crc_received == self.crc_expected
    }
}

/// How a frame ended.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Read completely (check [`FrameData::crc_ok`]).
    Data(FrameData),
    /// SL never went low after rising edge 1.
    NoAck,
    /// No Start bit within `max_ack_bits`.
    NoStart,
    /// The request stopped the clock before the frame was complete.
    Aborted,
    /// SL never returned high.
    NotReady,
}

/// Report of one frame.
pub type BissFrame = MasterFrame<Outcome>;

impl BissFrame {
    /// Frame data with a good CRC, if so.
    pub fn good(&self) -> Option<&FrameData> {
        match &self.outcome {
            Outcome::Data(d) if d.crc_ok() => Some(d),
            _ => None,
        }
    }
}

/// CRC6 0x43 as the master computes it: the remainder of message(x) * x^6 divided by
/// x^6 + x + 1, by long division, then inverted as BiSS sends it.
pub fn expected_crc(message: u64, bits: u32) -> u8 {
    expected_crc_wide(message as u128, bits)
}

/// [`expected_crc`] of a message of up to 122 bits (data, velocity word, nE, nW).
pub fn expected_crc_wide(message: u128, bits: u32) -> u8 {
    let mut r = message << 6;
    for i in (6..bits + 6).rev() {
        if r >> i & 1 == 1 {
            r ^= 0x43u128 << (i - 6);
        }
    }
    !(r as u8) & 0x3f
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Seek {
    Ack,
    Start,
    Read,
    Stop,
    Done,
}

/// What a BiSS frame has read so far.
#[derive(Clone, Debug)]
pub struct BissRun {
    delay: Option<f64>,
    ack_scan: usize,
    seek: Seek,
    ack_bits: u32,
    bits: Vec<bool>,
    stop_low: bool,
    failure: Option<Outcome>,
}

/// The BiSS-C master model.
pub type BissMaster = SerialMaster<BissMasterConfig>;

impl BissMasterConfig {
    /// The frame as read: data, flags and CRC from the bits after Start.
    fn decode(&self, run: &BissRun) -> FrameData {
        let nb = self.word.data_bits;
        let nv = self.word.velocity_bits;
        let n = nb as usize;
        // After CDS: N data bits, V velocity bits, nE, nW, six CRC bits.
        let e = n + nv as usize;
        let b = &run.bits;
        let data = word_of(&b[1..1 + n]);
        let velocity = self.word.velocity(&b[1 + n..1 + e]);
        let (n_e, n_w) = (b[1 + e], b[2 + e]);
        let crc_received = word_of(&b[3 + e..9 + e]) as u8;
        // The CRC covers every bit from the data's MSB to nW.
        let message = b[1..3 + e].iter().fold(0u128, |a, &v| (a << 1) | v as u128);
        let (position, turns) = self.word.split(data);
        FrameData {
            ack_bits: run.ack_bits,
            cds: b[0],
            data,
            position,
            turns,
            velocity,
            n_e,
            n_w,
            crc_received,
            crc_expected: expected_crc_wide(message, nb + nv + 2),
            stop_low: run.stop_low,
        }
    }

    /// Gives up on the frame: `outcome`, no more samples, the clock stops.
    fn fail(run: &mut BissRun, burst: &mut Burst, outcome: Outcome) {
        run.failure = Some(outcome);
        run.seek = Seek::Done;
        burst.end_low = false;
        burst.stop_now();
    }
}

impl FrameProtocol for BissMasterConfig {
    type Run = BissRun;
    type Outcome = Outcome;

    fn line(&self) -> &MasterLine {
        &self.line
    }
    /// Unknown until the Start bit: the burst is stopped from [`Self::on_sample`].
    fn frame_rises(&self) -> Option<u32> {
        None
    }
    fn new_run(&self) -> BissRun {
        BissRun {
            delay: None,
            ack_scan: 0,
            seek: Seek::Ack,
            ack_bits: 0,
            bits: Vec::new(),
            stop_low: false,
            failure: None,
        }
    }
    /// A compensating master samples from edge 2 (edge 1's answer comes before D is known).
    fn first_sample(&self) -> u32 {
        if self.compensate {
            2
        } else {
            1
        }
    }
    /// Line-delay measurement: the first falling SL edge after rising edge 1.
    fn observe(&self, run: &mut BissRun, burst: &mut Burst, sl: &SlaveLine, t: f64) {
        if !self.compensate || run.delay.is_some() || burst.rises < 1 {
            return;
        }
        if run.ack_scan == 0 {
            run.ack_scan = sl.index_at(burst.rise(1));
        }
        if let Some(tau) = sl.find_change(&mut run.ack_scan, false, t) {
            run.delay = Some(tau - burst.rise(2));
        } else if run.seek == Seek::Ack
            && burst.rises >= 3 + self.max_ack_bits
            && burst.rise(3 + self.max_ack_bits) + 2.0 * burst.period < t
        {
            Self::fail(run, burst, Outcome::NoAck);
        }
    }
    /// Samples wanted: up to the stop pulse once Start is known, or until the search ends.
    fn wants_sample(&self, run: &BissRun, _n: u32) -> bool {
        run.seek != Seek::Done
    }
    fn sample_time(&self, run: &BissRun, burst: &Burst, n: u32) -> Option<f64> {
        if self.compensate {
            run.delay.map(|d| burst.rise(n) + d + burst.period / 2.0)
        } else {
            Some(burst.rise(n + 1))
        }
    }
    fn on_sample(&self, run: &mut BissRun, burst: &mut Burst, n: u32, v: bool) {
        let nb = self.word.data_bits + self.word.velocity_bits;
        match run.seek {
            Seek::Ack => {
                if !v {
                    run.seek = Seek::Start;
                    run.ack_bits = 1;
                } else if n >= 3 + self.max_ack_bits {
                    Self::fail(run, burst, Outcome::NoAck);
                }
            }
            Seek::Start => {
                if v {
                    run.seek = Seek::Read;
                    // CDS, N data (+ V velocity), nE, nW, 6 CRC, then one pulse for the timeout.
                    burst.stop_after_rise(n + nb + 10);
                } else {
                    run.ack_bits += 1;
                    if run.ack_bits > self.max_ack_bits {
                        Self::fail(run, burst, Outcome::NoStart);
                    }
                }
            }
            Seek::Read => {
                run.bits.push(v);
                if run.bits.len() as u32 == nb + 9 {
                    run.seek = Seek::Stop;
                }
            }
            Seek::Stop => {
                run.stop_low = !v;
                run.seek = Seek::Done;
            }
            Seek::Done => {}
        }
    }
    fn complete(&self, run: &BissRun) -> bool {
        run.failure.is_none() && run.seek == Seek::Done
    }
    fn outcome(&self, run: &BissRun) -> Outcome {
        if let Some(f) = &run.failure {
            f.clone()
        } else if run.seek == Seek::Done {
            Outcome::Data(self.decode(run))
        } else {
            Outcome::Aborted
        }
    }
    fn not_ready(&self) -> Outcome {
        Outcome::NotReady
    }
    fn delay_ns(&self, run: &BissRun) -> Option<f64> {
        run.delay
    }
}
