//! The core every clocked serial master model shares (BiSS-C in
//! [`crate::sim::biss_master`], SSI in [`crate::sim::ssi_master`]): the phase loop that
//! waits for the slave, clocks a frame, samples the answers and measures the timeout, on the
//! line model of [`crate::sim::serial_line`]. A protocol ([`FrameProtocol`]) says only which
//! answers it samples, when, and what they mean.
//!
//! ```text
//!            ┌──────── SL high (or no wait), not before the gap ────────┐
//!            v                                                          │
//!   Ready ──────> Frame: MA burst, low first; samples the answers ──> Timeout: wait for SL
//!     │  ^           │  (protocol: wanted? when? meaning? stop?)          │   high after the
//!     │  │           │  burst stopped, no sample pending:                 │   answer to the
//!     │  │           │    complete and the next request waits -> Timeout  │   last pulse;
//!     │  └───────────┴─── otherwise: report, next request ───────────────┘   report
//!     └── slave not ready for giveup_ns, or no more requests ──> Done
//! ```
//!
//! Per frame the core gives the burst ([`Burst`]): it stops after the protocol's frame
//! length (if known at the start), after the request's abort count, or when the protocol
//! stops it. Answers are sampled in order, one per rising edge n (from
//! [`FrameProtocol::first_sample`]), each at the protocol's time for n, and never for an
//! edge the burst will not give. Edges and samples are processed in time order up to the
//! instant the slave's next clock edge needs the clock line.
use crate::sim::serial_line::{Burst, FrameRequest, LineMaster, LineTiming, MaLine, SlaveLine};
use std::fmt::Debug;

/// Settings every master has: the line, and how long it waits for the slave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MasterLine {
    /// Line timing.
    pub timing: LineTiming,
    /// After a failed or aborted frame: wait this long, then for the line high.
    pub recover_ns: f64,
    /// Give up when the slave is not ready for this long.
    pub giveup_ns: f64,
}

impl MasterLine {
    /// The line with the default patience: 60 us of recovery, give up after 2 ms.
    pub fn new(timing: LineTiming) -> Self {
        Self {
            timing,
            recover_ns: 60_000.0,
            giveup_ns: 2e6,
        }
    }
}

/// What one serial protocol decides in the master core.
pub trait FrameProtocol: Clone + Debug {
    /// The protocol's per-frame state (what it has read so far).
    type Run: Clone + Debug;
    /// How a frame ended.
    type Outcome: Clone + Debug + PartialEq;
    /// The line and the master's patience.
    fn line(&self) -> &MasterLine;
    /// Rising edges of a complete frame, when known at its start (None: the protocol stops
    /// the burst itself).
    fn frame_rises(&self) -> Option<u32>;
    /// A new frame's state.
    fn new_run(&self) -> Self::Run;
    /// The first rising edge whose answer is sampled.
    fn first_sample(&self) -> u32 {
        1
    }
    /// Called before every step of the frame with the line known up to `t` (e.g. to
    /// measure the line delay).
    fn observe(&self, _run: &mut Self::Run, _burst: &mut Burst, _sl: &SlaveLine, _t: f64) {}
    /// Whether the answer to rising edge `n` is wanted.
    fn wants_sample(&self, run: &Self::Run, n: u32) -> bool;
    /// When the answer to rising edge `n` is sampled, if known yet.
    fn sample_time(&self, run: &Self::Run, burst: &Burst, n: u32) -> Option<f64>;
    /// The answer `v` to rising edge `n`; may stop the burst.
    fn on_sample(&self, run: &mut Self::Run, burst: &mut Burst, n: u32, v: bool);
    /// The frame was read to its end, so the master measures the slave's timeout.
    fn complete(&self, run: &Self::Run) -> bool;
    /// The outcome of a frame whose clocking has ended.
    fn outcome(&self, run: &Self::Run) -> Self::Outcome;
    /// The outcome reported when the slave never becomes ready.
    fn not_ready(&self) -> Self::Outcome;
    /// The line delay the frame measured, if the protocol measures one.
    fn delay_ns(&self, _run: &Self::Run) -> Option<f64> {
        None
    }
}

/// Report of one frame.
#[derive(Clone, Debug, PartialEq)]
pub struct MasterFrame<O> {
    /// First clock edge (falling) at the master, ns.
    pub t_start_ns: f64,
    /// Last clock edge at the master, ns.
    pub t_last_edge_ns: f64,
    /// Clock frequency.
    pub ma_hz: f64,
    /// Measured line delay D (a compensating BiSS master: rising edge 2 to the Ack).
    pub delay_ns: Option<f64>,
    /// From the last clock edge to the line high (the slave's timeout seen by the master).
    pub timeout_ns: Option<f64>,
    /// Result.
    pub outcome: O,
}

#[derive(Clone, Debug)]
struct Run<R> {
    req: FrameRequest,
    burst: Burst,
    /// The next rising edge whose answer is sampled.
    next_sample: u32,
    /// When the last answer was sampled (for a complete frame, the answer to the final
    /// pulse: the line is low from then until the timeout).
    t_last_sample: f64,
    proto: R,
}

#[derive(Clone, Debug)]
enum Phase<R> {
    /// Waiting to start the next frame: not before `not_before`, and (if the request says
    /// so) only with the line high.
    Ready { not_before: f64, scan: usize },
    /// Clocking a frame.
    Frame(Box<Run<R>>),
    /// Frame read; waiting for the line to return high after the last edge.
    Timeout { run: Box<Run<R>>, scan: usize },
    /// No more requests (or the slave is dead).
    Done,
}

/// A serial master model: protocol `P` on the shared phase loop.
#[derive(Clone, Debug)]
pub struct SerialMaster<P: FrameProtocol> {
    cfg: P,
    requests: Vec<FrameRequest>,
    next_req: usize,
    phase: Phase<P::Run>,
    ma: MaLine,
    sl: SlaveLine,
    frames: Vec<MasterFrame<P::Outcome>>,
}

impl<P: FrameProtocol> SerialMaster<P> {
    /// Master that clocks `requests` in order, the first not before `start_ns`.
    pub fn new(cfg: P, requests: Vec<FrameRequest>, start_ns: f64) -> Self {
        let sl = SlaveLine::new(&cfg.line().timing, false);
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
    pub fn frames(&self) -> &[MasterFrame<P::Outcome>] {
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

    fn report(&mut self, run: &Run<P::Run>, timeout_ns: Option<f64>) {
        self.frames.push(MasterFrame {
            t_start_ns: run.burst.t0,
            t_last_edge_ns: run.burst.last_edge(),
            ma_hz: run.req.ma_hz,
            delay_ns: self.cfg.delay_ns(&run.proto),
            timeout_ns,
            outcome: self.cfg.outcome(&run.proto),
        });
    }

    /// Reports a slave that never became ready (at `t`) and stops.
    fn not_ready(&mut self, t: f64, ma_hz: f64) {
        self.frames.push(MasterFrame {
            t_start_ns: t,
            t_last_edge_ns: t,
            ma_hz,
            delay_ns: None,
            timeout_ns: None,
            outcome: self.cfg.not_ready(),
        });
        self.phase = Phase::Done;
    }

    /// Moves to the next request after a frame whose last edge was at `last`.
    fn next_frame(&mut self, last: f64, after_failure: bool, ready_at: Option<f64>) {
        if self.next_req >= self.requests.len() {
            self.phase = Phase::Done;
            return;
        }
        let req = self.requests[self.next_req];
        let not_before = if !req.wait_ready {
            last + req.gap_ns
        } else if let Some(t) = ready_at {
            t + req.gap_ns
        } else if after_failure {
            last + self.cfg.line().recover_ns.max(req.gap_ns)
        } else {
            last + req.gap_ns
        };
        let scan = self.sl.index_at(not_before);
        self.phase = Phase::Ready { not_before, scan };
    }

    /// Starts the next frame at `s`.
    fn start_frame(&mut self, req: FrameRequest, s: f64) {
        self.next_req += 1;
        let mut burst = Burst::new(s, req.ma_hz, req.duty);
        burst.end_low = req.cdm && req.abort_after_rises.is_none();
        burst.stop_after = self.cfg.frame_rises();
        if let Some(k) = req.abort_after_rises {
            burst.stop_after_rise(k);
        }
        self.phase = Phase::Frame(Box::new(Run {
            req,
            burst,
            next_sample: self.cfg.first_sample(),
            t_last_sample: 0.0,
            proto: self.cfg.new_run(),
        }));
    }

    /// Processes every event up to time `t` (the line must be known up to `t`).
    fn advance(&mut self, t: f64) {
        loop {
            match std::mem::replace(&mut self.phase, Phase::Done) {
                Phase::Done => return,
                Phase::Ready { not_before, scan } => {
                    if !self.ready(t, not_before, scan) {
                        return;
                    }
                }
                Phase::Frame(run) => {
                    if !self.frame_step(t, run) {
                        return;
                    }
                }
                Phase::Timeout { run, mut scan } => match self.sl.find_change(&mut scan, true, t) {
                    Some(tau) => {
                        let last = run.burst.last_edge();
                        self.report(&run, Some(tau - last));
                        // A CDM = 1 frame: MA returns high as the slave is seen ready, and
                        // stays high for one period before the next frame.
                        let ready = if run.burst.ended_low() {
                            self.ma.push(tau, true);
                            tau + run.burst.period
                        } else {
                            tau
                        };
                        self.next_frame(last, false, Some(ready));
                    }
                    None => {
                        if t - run.burst.last_edge() > self.cfg.line().giveup_ns {
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

    /// The Ready phase up to `t`; true if a frame has started (go on processing).
    fn ready(&mut self, t: f64, not_before: f64, mut scan: usize) -> bool {
        if self.next_req >= self.requests.len() {
            return false;
        }
        let req = self.requests[self.next_req];
        if not_before > t {
            self.phase = Phase::Ready { not_before, scan };
            return false;
        }
        let start = if !req.wait_ready || self.sl.at(not_before) {
            Some(not_before)
        } else {
            self.sl.find_change(&mut scan, true, t)
        };
        match start {
            Some(s) if s <= t => {
                self.start_frame(req, s);
                true
            }
            _ => {
                if t - not_before > self.cfg.line().giveup_ns {
                    self.not_ready(not_before, req.ma_hz);
                } else {
                    self.phase = Phase::Ready { not_before, scan };
                }
                false
            }
        }
    }

    /// One event of the frame (an edge or a sample) if one is due by `t`; true to go on.
    fn frame_step(&mut self, t: f64, mut run: Box<Run<P::Run>>) -> bool {
        self.cfg
            .observe(&mut run.proto, &mut run.burst, &self.sl, t);
        let edge = run.burst.next_edge();
        let n = run.next_sample;
        // Never beyond the clock the burst will give.
        let given = run.burst.stop_after.is_none_or(|k| n <= k);
        let sample = if given && self.cfg.wants_sample(&run.proto, n) {
            self.cfg.sample_time(&run.proto, &run.burst, n)
        } else {
            None
        };
        let te = edge.map_or(f64::INFINITY, |e| e.0);
        let ts = sample.unwrap_or(f64::INFINITY);
        if te.min(ts) > t {
            // Nothing more before t. The frame is over once the clock has stopped and no
            // sample is pending (none wanted, or one whose time is never known).
            if edge.is_none() && sample.is_none() {
                self.finish_frame(run, t);
                return true;
            }
            self.phase = Phase::Frame(run);
            return false;
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
            run.next_sample += 1;
            run.t_last_sample = ts;
            self.cfg.on_sample(&mut run.proto, &mut run.burst, n, v);
        }
        self.phase = Phase::Frame(run);
        true
    }

    /// Clocking has stopped and no sample is pending (at `t`): report, or wait for the
    /// timeout.
    fn finish_frame(&mut self, run: Box<Run<P::Run>>, t: f64) {
        let last = run.burst.last_edge();
        let complete = self.cfg.complete(&run.proto);
        let next_waits = self
            .requests
            .get(self.next_req)
            .is_none_or(|r| r.wait_ready);
        if complete && next_waits {
            // The answers to earlier edges may still be arriving after the last edge (a
            // compensating master allows more than one period of delay): the timeout is the
            // first rise of the line after the (low) answer to the final pulse.
            let scan = self.sl.index_at(run.t_last_sample);
            self.phase = Phase::Timeout { run, scan };
        } else {
            let mut last = last;
            if run.burst.ended_low() {
                // MA held low for CDM, but the frame is not followed by a timeout wait.
                self.ma.push(t, true);
                last = t;
            }
            self.report(&run, None);
            self.next_frame(last, !complete, None);
        }
    }
}

impl<P: FrameProtocol> LineMaster for SerialMaster<P> {
    fn ma_for_cycle(&mut self, k: usize) -> bool {
        let timing = self.cfg.line().timing;
        let t = timing.edge_ns(k) - timing.line_delay_ns;
        self.advance(t);
        self.ma.before(t)
    }
    fn push_slo(&mut self, slo: bool) {
        self.sl.push(slo);
    }
}
