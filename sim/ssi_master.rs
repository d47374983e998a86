//! SSI master model, written from the protocol (see [`crate::blocks::ssi`]'s table), with
//! the time model of [`crate::sim::biss_master`] (continuous-time master, line delay d both
//! ways, slave stepped one system clock at a time).
//!
//! Per frame the master gives B + 1 clock pulses (B = data bits, plus the error bit when
//! configured) starting with a falling edge, reads the answer to rising edge n (n = 1..B) at
//! the next rising edge (or at a fixed delay after edge n), checks that the line answers the
//! last pulse with 0, stops with the clock high and measures the time until the line returns
//! high (the slave's monoflop time, round trip included). The next frame starts when the
//! line is high again (or, on request, without waiting).
use crate::sim::biss_master::{
    from_gray, Burst, FrameRequest, LineMaster, LineTiming, MaLine, SlaveLine,
};

/// Master settings.
#[derive(Clone, Debug, PartialEq)]
pub struct SsiMasterConfig {
    /// Line timing.
    pub timing: LineTiming,
    /// Data bits N (multi-turn + single-turn).
    pub data_bits: u32,
    /// Multi-turn bits at the head of the data.
    pub multiturn_bits: u32,
    /// The data word is Gray-coded.
    pub gray: bool,
    /// One error bit follows the data.
    pub error_bit: bool,
    /// Sample the answer to rising edge n this long after it; None = at rising edge n+1.
    pub sample_delay_ns: Option<f64>,
    /// After an aborted frame: wait this long, then for the line high.
    pub recover_ns: f64,
    /// Give up when the slave is not ready for this long.
    pub giveup_ns: f64,
}

impl SsiMasterConfig {
    /// Master sampling at the next rising edge, binary, no error bit.
    pub fn new(timing: LineTiming, data_bits: u32, multiturn_bits: u32) -> Self {
        Self {
            timing,
            data_bits,
            multiturn_bits,
            gray: false,
            error_bit: false,
            sample_delay_ns: None,
            recover_ns: 60_000.0,
            giveup_ns: 2e6,
        }
    }
    fn frame_bits(&self) -> u32 {
        self.data_bits + self.error_bit as u32
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

/// Report of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct SsiFrame {
    /// First clock edge (falling) at the master, ns.
    pub t_start_ns: f64,
    /// Last clock edge, ns.
    pub t_last_edge_ns: f64,
    /// Clock frequency.
    pub ma_hz: f64,
    /// From the last clock edge to the line high.
    pub timeout_ns: Option<f64>,
    /// Result.
    pub outcome: SsiOutcome,
}

#[derive(Clone, Debug)]
struct Run {
    req: FrameRequest,
    burst: Burst,
    bits: Vec<bool>,
    tail_low: Option<bool>,
    t_tail: f64,
}

#[derive(Clone, Debug)]
enum Phase {
    Ready { not_before: f64, scan: usize },
    Frame(Box<Run>),
    Timeout { run: Box<Run>, scan: usize },
    Done,
}

/// The SSI master model.
#[derive(Clone, Debug)]
pub struct SsiMaster {
    cfg: SsiMasterConfig,
    requests: Vec<FrameRequest>,
    next_req: usize,
    phase: Phase,
    ma: MaLine,
    sl: SlaveLine,
    frames: Vec<SsiFrame>,
}

impl SsiMaster {
    /// Master that clocks `requests` in order, the first not before `start_ns`.
    pub fn new(cfg: SsiMasterConfig, requests: Vec<FrameRequest>, start_ns: f64) -> Self {
        let sl = SlaveLine::new(&cfg.timing, false);
        Self {
            cfg,
            requests,
            next_req: 0,
            phase: Phase::Ready {
                not_before: start_ns,
                scan: 0,
            },
            ma: MaLine::default(),
            sl,
            frames: Vec::new(),
        }
    }

    /// Frames reported so far.
    pub fn frames(&self) -> &[SsiFrame] {
        &self.frames
    }

    /// Whether every request has been served.
    pub fn done(&self) -> bool {
        matches!(self.phase, Phase::Done)
    }

    /// Rising edges given so far in the frame being clocked, if one is.
    pub fn rises_in_frame(&self) -> Option<u32> {
        match &self.phase {
            Phase::Frame(run) => Some(run.burst.rises),
            _ => None,
        }
    }

    fn sample_time(&self, run: &Run, n: u32) -> f64 {
        match self.cfg.sample_delay_ns {
            Some(d) => run.burst.rise(n) + d,
            None => run.burst.rise(n + 1),
        }
    }

    fn report(&mut self, run: &Run, timeout_ns: Option<f64>) {
        let b = self.cfg.frame_bits() as usize;
        let outcome = match run.tail_low {
            Some(tail_low) if run.bits.len() == b => {
                let n = self.cfg.data_bits as usize;
                let data = run.bits[..n].iter().fold(0u64, |a, &v| (a << 1) | v as u64);
                let bin = if self.cfg.gray { from_gray(data) } else { data };
                let st = self.cfg.data_bits - self.cfg.multiturn_bits;
                SsiOutcome::Data(SsiData {
                    data,
                    position: bin & ((1u64 << st) - 1),
                    turns: bin >> st,
                    error: self.cfg.error_bit.then(|| run.bits[n]),
                    tail_low,
                })
            }
            _ => SsiOutcome::Aborted,
        };
        self.frames.push(SsiFrame {
            t_start_ns: run.burst.t0,
            t_last_edge_ns: run.burst.last_edge(),
            ma_hz: run.req.ma_hz,
            timeout_ns,
            outcome,
        });
    }

    fn next_frame(&mut self, last: f64, aborted: bool, ready_at: Option<f64>) {
        if self.next_req >= self.requests.len() {
            self.phase = Phase::Done;
            return;
        }
        let req = self.requests[self.next_req];
        let not_before = if !req.wait_ready {
            last + req.gap_ns
        } else if let Some(t) = ready_at {
            t + req.gap_ns
        } else if aborted {
            last + self.cfg.recover_ns.max(req.gap_ns)
        } else {
            last + req.gap_ns
        };
        let scan = self.sl.index_at(not_before);
        self.phase = Phase::Ready { not_before, scan };
    }

    fn not_ready(&mut self, t: f64, hz: f64) {
        self.frames.push(SsiFrame {
            t_start_ns: t,
            t_last_edge_ns: t,
            ma_hz: hz,
            timeout_ns: None,
            outcome: SsiOutcome::NotReady,
        });
        self.phase = Phase::Done;
    }

    fn advance(&mut self, t: f64) {
        let b = self.cfg.frame_bits();
        loop {
            match std::mem::replace(&mut self.phase, Phase::Done) {
                Phase::Done => return,
                Phase::Ready {
                    not_before,
                    mut scan,
                } => {
                    if self.next_req >= self.requests.len() {
                        return;
                    }
                    let req = self.requests[self.next_req];
                    if not_before > t {
                        self.phase = Phase::Ready { not_before, scan };
                        return;
                    }
                    let start = if !req.wait_ready || self.sl.at(not_before) {
                        Some(not_before)
                    } else {
                        self.sl.find_change(&mut scan, true, t)
                    };
                    match start {
                        Some(s) if s <= t => {
                            self.next_req += 1;
                            let mut burst = Burst::new(s, req.ma_hz, req.duty);
                            burst.stop_after = Some(b + 1);
                            if let Some(k) = req.abort_after_rises {
                                burst.stop_after_rise(k);
                            }
                            self.phase = Phase::Frame(Box::new(Run {
                                req,
                                burst,
                                bits: Vec::new(),
                                tail_low: None,
                                t_tail: 0.0,
                            }));
                        }
                        _ => {
                            if t - not_before > self.cfg.giveup_ns {
                                self.not_ready(not_before, req.ma_hz);
                            } else {
                                self.phase = Phase::Ready { not_before, scan };
                            }
                            return;
                        }
                    }
                }
                Phase::Frame(mut run) => {
                    let edge = run.burst.next_edge();
                    // Answers to rising edges 1..=b are data; b+1 is the tail.
                    let n = run.bits.len() as u32 + 1 + run.tail_low.is_some() as u32;
                    let given = run.burst.stop_after.unwrap_or(b + 1);
                    let sample = (n <= (b + 1).min(given)).then(|| self.sample_time(&run, n));
                    let te = edge.map_or(f64::INFINITY, |e| e.0);
                    let ts = sample.unwrap_or(f64::INFINITY);
                    if te.min(ts) > t {
                        if edge.is_none() && sample.is_none() {
                            let last = run.burst.last_edge();
                            let complete = run.tail_low.is_some();
                            let next_waits = self
                                .requests
                                .get(self.next_req)
                                .is_none_or(|r| r.wait_ready);
                            if complete && next_waits {
                                // The monoflop ends with the first rise after the (low)
                                // answer to the last pulse.
                                let scan = self.sl.index_at(run.t_tail);
                                self.phase = Phase::Timeout { run, scan };
                            } else {
                                self.report(&run, None);
                                self.next_frame(last, !complete, None);
                            }
                            continue;
                        }
                        self.phase = Phase::Frame(run);
                        return;
                    }
                    if te <= ts {
                        let (time, level) = edge.expect("edge");
                        self.ma.push(time, level);
                        if level {
                            run.burst.rises += 1;
                        } else {
                            run.burst.falls += 1;
                        }
                    } else {
                        let v = self.sl.at(ts);
                        if n <= b {
                            run.bits.push(v);
                        } else {
                            run.tail_low = Some(!v);
                            run.t_tail = ts;
                        }
                    }
                    self.phase = Phase::Frame(run);
                }
                Phase::Timeout { run, mut scan } => match self.sl.find_change(&mut scan, true, t) {
                    Some(tau) => {
                        let last = run.burst.last_edge();
                        self.report(&run, Some(tau - last));
                        self.next_frame(last, false, Some(tau));
                    }
                    None => {
                        if t - run.burst.last_edge() > self.cfg.giveup_ns {
                            self.report(&run, None);
                            self.not_ready(t, run.req.ma_hz);
                        } else {
                            self.phase = Phase::Timeout { run, scan };
                        }
                        return;
                    }
                },
            }
        }
    }
}

impl LineMaster for SsiMaster {
    fn ma_for_cycle(&mut self, k: usize) -> bool {
        let t = self.cfg.timing.edge_ns(k) - self.cfg.timing.line_delay_ns;
        self.advance(t);
        self.ma.before(t)
    }
    fn push_slo(&mut self, slo: bool) {
        self.sl.push(slo);
    }
}
