//! BiSS-C master model, written from the protocol (the iC-Haus BiSS C description as
//! summarised in [`crate::blocks::biss`]'s frame table), not from the slave's code.
//!
//! The master lives in continuous time (f64 nanoseconds); the slave is a synchronous design
//! simulated one system clock at a time. Rising system clock edge k is at t_k = k T_clk. The
//! line adds the same delay d in both directions:
//!
//! * the slave's MA input for edge k is MA as the master drove it at t_k - d (edges exactly
//!   at that instant not yet seen), so MA edges land between slave clock edges at whatever
//!   phase the master's frequency and start time give;
//! * SLO after edge k (registered, so constant until edge k+1) reaches the master at
//!   t_k + d: SL at the master at time t is SLO after the last edge k with t_k < t - d.
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

/// Timing shared by the master and the simulated slave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineTiming {
    /// The slave's system clock in Hz.
    pub clock_hz: f64,
    /// One-way line delay in ns (cable and transceivers), the same in both directions.
    pub line_delay_ns: f64,
}

impl LineTiming {
    /// System clock period in ns.
    pub fn tclk_ns(&self) -> f64 {
        1e9 / self.clock_hz
    }
    /// Time of rising system clock edge k in ns.
    pub fn edge_ns(&self, k: usize) -> f64 {
        k as f64 * self.tclk_ns()
    }
}

/// A master model that drives a clock line into a slave simulated one clock at a time.
pub trait LineMaster {
    /// The clock line (MA) at the slave's pin as the slave's clock edge k samples it.
    /// Called once per cycle, k = 0, 1, 2, ...
    fn ma_for_cycle(&mut self, k: usize) -> bool;
    /// The slave's output after clock edge k (called after `ma_for_cycle(k)`).
    fn push_slo(&mut self, slo: bool);
}

/// The slave's output line as seen at the master, from the slave's per-cycle outputs.
#[derive(Clone, Debug)]
pub struct SlaveLine {
    tclk: f64,
    delay: f64,
    initial: bool,
    slo: Vec<bool>,
}

impl SlaveLine {
    /// Empty history; `initial` is the line before the first clock edge.
    pub fn new(t: &LineTiming, initial: bool) -> Self {
        Self {
            tclk: t.tclk_ns(),
            delay: t.line_delay_ns,
            initial,
            slo: Vec::new(),
        }
    }
    /// Appends the slave's output after the next clock edge.
    pub fn push(&mut self, v: bool) {
        self.slo.push(v);
    }
    /// SL at the master at time `t` (must be known: `t <= known_until()`).
    pub fn at(&self, t: f64) -> bool {
        let u = t - self.delay;
        if u <= 0.0 {
            return self.initial;
        }
        let j = (u / self.tclk).ceil() as usize - 1;
        assert!(j < self.slo.len(), "SL at {t} ns is not known yet");
        self.slo[j]
    }
    /// Index of the first slave cycle whose output reaches the master at or after `t`.
    pub fn index_at(&self, t: f64) -> usize {
        ((t - self.delay) / self.tclk).ceil().max(0.0) as usize
    }
    /// First change of SL to `to` at a time before `until`, searching from cycle `*j` on
    /// (`*j` advances past cycles without that change, so repeated calls are cheap).
    pub fn find_change(&self, j: &mut usize, to: bool, until: f64) -> Option<f64> {
        while *j < self.slo.len() {
            let tj = *j as f64 * self.tclk + self.delay;
            if tj >= until {
                return None;
            }
            let prev = if *j == 0 {
                self.initial
            } else {
                self.slo[*j - 1]
            };
            if self.slo[*j] == to && prev != to {
                return Some(tj);
            }
            *j += 1;
        }
        None
    }
}

/// The master's clock output: its transitions in time (starting high).
#[derive(Clone, Debug, Default)]
pub struct MaLine {
    edges: Vec<(f64, bool)>,
    cursor: usize,
    level: Option<bool>,
}

impl MaLine {
    /// Adds a transition at `t` (times must not decrease).
    pub fn push(&mut self, t: f64, level: bool) {
        self.edges.push((t, level));
    }
    /// The line just before time `t` (transitions at `t` not yet seen). Queries must not go
    /// back in time.
    pub fn before(&mut self, t: f64) -> bool {
        while self.cursor < self.edges.len() && self.edges[self.cursor].0 < t {
            self.level = Some(self.edges[self.cursor].1);
            self.cursor += 1;
        }
        self.level.unwrap_or(true)
    }
    /// Every transition so far.
    pub fn edges(&self) -> &[(f64, bool)] {
        &self.edges
    }
}

/// A free-running clock burst: falling edge n at t0 + (n-1) T, rising edge n a low time later.
#[derive(Clone, Copy, Debug)]
pub struct Burst {
    /// First falling edge.
    pub t0: f64,
    /// Period in ns.
    pub period: f64,
    /// Low time in ns.
    pub tlow: f64,
    /// Falling edges given.
    pub falls: u32,
    /// Rising edges given.
    pub rises: u32,
    /// Stop (MA high) after this rising edge.
    pub stop_after: Option<u32>,
}

impl Burst {
    /// Burst at `hz` with high fraction `duty`, starting at `t0`.
    pub fn new(t0: f64, hz: f64, duty: f64) -> Self {
        let period = 1e9 / hz;
        Self {
            t0,
            period,
            tlow: period * (1.0 - duty),
            falls: 0,
            rises: 0,
            stop_after: None,
        }
    }
    /// Time of rising edge n (1-based).
    pub fn rise(&self, n: u32) -> f64 {
        self.t0 + (n as f64 - 1.0) * self.period + self.tlow
    }
    /// Time of falling edge n (1-based).
    pub fn fall(&self, n: u32) -> f64 {
        self.t0 + (n as f64 - 1.0) * self.period
    }
    /// Whether the burst has stopped (MA high for good).
    pub fn stopped(&self) -> bool {
        self.stop_after
            .is_some_and(|k| self.rises >= k && self.falls == self.rises)
    }
    /// The next edge (time, new level), if any.
    pub fn next_edge(&self) -> Option<(f64, bool)> {
        if self.stopped() {
            None
        } else if self.falls == self.rises {
            Some((self.fall(self.falls + 1), false))
        } else {
            Some((self.rise(self.rises + 1), true))
        }
    }
    /// Stops as soon as possible: after the current rising edge, or the next one if MA is low.
    pub fn stop_now(&mut self) {
        let k = self.rises + (self.falls > self.rises) as u32;
        self.stop_after = Some(self.stop_after.map_or(k, |s| s.min(k)));
    }
    /// Stops after rising edge k at the latest.
    pub fn stop_after_rise(&mut self, k: u32) {
        let k = k.max(self.rises + (self.falls > self.rises) as u32);
        self.stop_after = Some(self.stop_after.map_or(k, |s| s.min(k)));
    }
    /// Time of the last edge given.
    pub fn last_edge(&self) -> f64 {
        if self.falls > self.rises {
            self.fall(self.falls)
        } else if self.rises > 0 {
            self.rise(self.rises)
        } else {
            self.t0
        }
    }
}

/// One frame to clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameRequest {
    /// MA frequency in Hz.
    pub ma_hz: f64,
    /// MA high fraction of the period (0.5 = 50 % duty).
    pub duty: f64,
    /// Pause in ns before the frame: after SL is seen high again (or, without `wait_ready`,
    /// after the previous frame's last MA edge).
    pub gap_ns: f64,
    /// Wait for SL high (slave ready) before starting; false starts the frame regardless,
    /// e.g. during the slave's timeout.
    pub wait_ready: bool,
    /// Stop clocking after this many rising edges (a master that gives up mid-frame).
    pub abort_after_rises: Option<u32>,
}

impl FrameRequest {
    /// A well-behaved frame at `ma_hz`: 50 % duty, started as soon as the slave is ready.
    pub fn new(ma_hz: f64) -> Self {
        Self {
            ma_hz,
            duty: 0.5,
            gap_ns: 0.0,
            wait_ready: true,
            abort_after_rises: None,
        }
    }
    /// With a pause before the frame.
    pub fn gap(mut self, ns: f64) -> Self {
        self.gap_ns = ns;
        self
    }
}

/// Master settings.
#[derive(Clone, Debug, PartialEq)]
pub struct BissMasterConfig {
    /// Line timing.
    pub timing: LineTiming,
    /// Data bits N in the frame (multi-turn + single-turn).
    pub data_bits: u32,
    /// Multi-turn bits at the head of the data.
    pub multiturn_bits: u32,
    /// The data word is Gray-coded.
    pub gray: bool,
    /// Line-delay compensation (sample at r_n + D + T/2) instead of sampling at r_(n+1).
    pub compensate: bool,
    /// Ack bits accepted before the Start bit (processing time) before giving up.
    pub max_ack_bits: u32,
    /// After a failed or aborted frame: wait this long, then for SL high.
    pub recover_ns: f64,
    /// Give up when the slave is not ready for this long.
    pub giveup_ns: f64,
}

impl BissMasterConfig {
    /// Compensating master for N data bits of which M are multi-turn, binary.
    pub fn new(timing: LineTiming, data_bits: u32, multiturn_bits: u32) -> Self {
        Self {
            timing,
            data_bits,
            multiturn_bits,
            gray: false,
            compensate: true,
            max_ack_bits: 80,
            recover_ns: 60_000.0,
            giveup_ns: 2e6,
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
#[derive(Clone, Debug, PartialEq)]
pub struct BissFrame {
    /// First MA edge (falling) at the master, ns.
    pub t_start_ns: f64,
    /// Last MA edge at the master, ns.
    pub t_last_edge_ns: f64,
    /// MA frequency.
    pub ma_hz: f64,
    /// Measured delay D from rising edge 2 to the Ack (compensating master).
    pub delay_ns: Option<f64>,
    /// From the last MA edge to SL high (slave timeout seen by the master).
    pub timeout_ns: Option<f64>,
    /// Result.
    pub outcome: Outcome,
}

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
    let mut r = (message as u128) << 6;
    for i in (6..bits + 6).rev() {
        if r >> i & 1 == 1 {
            r ^= 0x43u128 << (i - 6);
        }
    }
    !(r as u8) & 0x3f
}

/// Binary value of a Gray-coded word.
pub fn from_gray(g: u64) -> u64 {
    let mut b = g;
    let mut s = 1;
    while s < 64 {
        b ^= b >> s;
        s <<= 1;
    }
    b
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Seek {
    Ack,
    Start,
    Read,
    Stop,
    Done,
}

#[derive(Clone, Debug)]
struct FrameRun {
    req: FrameRequest,
    burst: Burst,
    delay: Option<f64>,
    ack_scan: usize,
    next_sample: u32,
    seek: Seek,
    ack_bits: u32,
    start_n: u32,
    bits: Vec<bool>,
    stop_low: bool,
    /// When the answer to the final pulse was sampled (SL low from then until the timeout).
    t_stop_sample: f64,
    failure: Option<Outcome>,
}

#[derive(Clone, Debug)]
enum Phase {
    /// Waiting to start the next frame: not before `not_before`, and (if the request says
    /// so) only with SL high.
    Ready { not_before: f64, scan: usize },
    /// Clocking a frame.
    Frame(Box<FrameRun>),
    /// Frame read; waiting for SL to return high after the last edge.
    Timeout { run: Box<FrameRun>, scan: usize },
    /// No more requests (or the slave is dead).
    Done,
}

/// The BiSS-C master model.
#[derive(Clone, Debug)]
pub struct BissMaster {
    cfg: BissMasterConfig,
    requests: Vec<FrameRequest>,
    next_req: usize,
    phase: Phase,
    ma: MaLine,
    sl: SlaveLine,
    frames: Vec<BissFrame>,
}

impl BissMaster {
    /// Master that clocks `requests` in order, the first not before `start_ns`.
    pub fn new(cfg: BissMasterConfig, requests: Vec<FrameRequest>, start_ns: f64) -> Self {
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
    pub fn frames(&self) -> &[BissFrame] {
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

    fn data_bits(&self) -> u32 {
        self.cfg.data_bits
    }

    /// Time at which the answer to rising edge n is sampled, when known.
    fn sample_time(&self, run: &FrameRun, n: u32) -> Option<f64> {
        if self.cfg.compensate {
            run.delay
                .map(|d| run.burst.rise(n) + d + run.burst.period / 2.0)
        } else {
            Some(run.burst.rise(n + 1))
        }
    }

    /// Samples wanted: up to the stop pulse once Start is known, or until the search ends.
    fn wants_sample(&self, run: &FrameRun, n: u32) -> bool {
        if run.seek == Seek::Done {
            return false;
        }
        // Never beyond the clock the burst will give.
        match run.burst.stop_after {
            Some(k) => n <= k,
            None => true,
        }
    }

    fn on_sample(&mut self, run: &mut FrameRun, n: u32, v: bool) {
        let nb = self.data_bits();
        match run.seek {
            Seek::Ack => {
                if !v {
                    run.seek = Seek::Start;
                    run.ack_bits = 1;
                } else if n >= 3 + self.cfg.max_ack_bits {
                    run.failure = Some(Outcome::NoAck);
                    run.seek = Seek::Done;
                    run.burst.stop_now();
                }
            }
            Seek::Start => {
                if v {
                    run.start_n = n;
                    run.seek = Seek::Read;
                    // CDS, N data, nE, nW, 6 CRC, then one pulse for the timeout.
                    run.burst.stop_after_rise(n + nb + 10);
                } else {
                    run.ack_bits += 1;
                    if run.ack_bits > self.cfg.max_ack_bits {
                        run.failure = Some(Outcome::NoStart);
                        run.seek = Seek::Done;
                        run.burst.stop_now();
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

    fn decode(&self, run: &FrameRun) -> FrameData {
        let nb = self.data_bits();
        let b = &run.bits;
        let word = |r: std::ops::Range<usize>| r.fold(0u64, |a, i| (a << 1) | b[i] as u64);
        let data = word(1..1 + nb as usize);
        let n_e = b[1 + nb as usize];
        let n_w = b[2 + nb as usize];
        let crc_received = word(3 + nb as usize..9 + nb as usize) as u8;
        let message = (data << 2) | ((n_e as u64) << 1) | n_w as u64;
        let bin = if self.cfg.gray { from_gray(data) } else { data };
        let st = nb - self.cfg.multiturn_bits;
        let st_mask = if st >= 64 { u64::MAX } else { (1u64 << st) - 1 };
        FrameData {
            ack_bits: run.ack_bits,
            cds: b[0],
            data,
            position: bin & st_mask,
            turns: if st >= 64 { 0 } else { bin >> st },
            n_e,
            n_w,
            crc_received,
            crc_expected: expected_crc(message, nb + 2),
            stop_low: run.stop_low,
        }
    }

    fn report(&mut self, run: &FrameRun, timeout_ns: Option<f64>) {
        let outcome = if let Some(f) = &run.failure {
            f.clone()
        } else if run.seek == Seek::Done {
            Outcome::Data(self.decode(run))
        } else {
            Outcome::Aborted
        };
        self.frames.push(BissFrame {
            t_start_ns: run.burst.t0,
            t_last_edge_ns: run.burst.last_edge(),
            ma_hz: run.req.ma_hz,
            delay_ns: run.delay,
            timeout_ns,
            outcome,
        });
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
            last + self.cfg.recover_ns.max(req.gap_ns)
        } else {
            last + req.gap_ns
        };
        let scan = self.sl.index_at(not_before);
        self.phase = Phase::Ready { not_before, scan };
    }

    /// Processes every event up to time `t` (SL must be known up to `t`).
    fn advance(&mut self, t: f64) {
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
                            if let Some(k) = req.abort_after_rises {
                                burst.stop_after = Some(k);
                            }
                            self.phase = Phase::Frame(Box::new(FrameRun {
                                req,
                                burst,
                                delay: None,
                                ack_scan: 0,
                                next_sample: if self.cfg.compensate { 2 } else { 1 },
                                seek: Seek::Ack,
                                ack_bits: 0,
                                start_n: 0,
                                bits: Vec::new(),
                                stop_low: false,
                                t_stop_sample: 0.0,
                                failure: None,
                            }));
                        }
                        _ => {
                            if t - not_before > self.cfg.giveup_ns {
                                self.frames.push(BissFrame {
                                    t_start_ns: not_before,
                                    t_last_edge_ns: not_before,
                                    ma_hz: req.ma_hz,
                                    delay_ns: None,
                                    timeout_ns: None,
                                    outcome: Outcome::NotReady,
                                });
                                self.phase = Phase::Done;
                            } else {
                                self.phase = Phase::Ready { not_before, scan };
                            }
                            return;
                        }
                    }
                }
                Phase::Frame(mut run) => {
                    // Line-delay measurement: the first falling SL edge after rising edge 1.
                    if self.cfg.compensate && run.delay.is_none() && run.burst.rises >= 1 {
                        if run.ack_scan == 0 {
                            run.ack_scan = self.sl.index_at(run.burst.rise(1));
                        }
                        if let Some(tau) = self.sl.find_change(&mut run.ack_scan, false, t) {
                            run.delay = Some(tau - run.burst.rise(2));
                        } else if run.seek == Seek::Ack
                            && run.burst.rises >= 3 + self.cfg.max_ack_bits
                            && run.burst.rise(3 + self.cfg.max_ack_bits) + 2.0 * run.burst.period
                                < t
                        {
                            run.failure = Some(Outcome::NoAck);
                            run.seek = Seek::Done;
                            run.burst.stop_now();
                        }
                    }
                    let edge = run.burst.next_edge();
                    let n = run.next_sample;
                    let sample = if self.wants_sample(&run, n) {
                        self.sample_time(&run, n)
                    } else {
                        None
                    };
                    let te = edge.map_or(f64::INFINITY, |e| e.0);
                    let ts = sample.unwrap_or(f64::INFINITY);
                    if te.min(ts) > t {
                        // Nothing more before t. The frame is over once the clock has
                        // stopped and no sample is pending (none wanted, or a compensating
                        // master that never saw the Ack).
                        if edge.is_none() && sample.is_none() {
                            self.finish_frame(run);
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
                        run.next_sample += 1;
                        run.t_stop_sample = ts;
                        self.on_sample(&mut run, n, v);
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
                            self.frames.push(BissFrame {
                                t_start_ns: t,
                                t_last_edge_ns: t,
                                ma_hz: run.req.ma_hz,
                                delay_ns: None,
                                timeout_ns: None,
                                outcome: Outcome::NotReady,
                            });
                            self.phase = Phase::Done;
                        } else {
                            self.phase = Phase::Timeout { run, scan };
                        }
                        return;
                    }
                },
            }
        }
    }

    /// Clocking has stopped and no sample is pending: report, or wait for the timeout.
    fn finish_frame(&mut self, run: Box<FrameRun>) {
        let last = run.burst.last_edge();
        let complete = run.failure.is_none() && run.seek == Seek::Done;
        let next_waits = self
            .requests
            .get(self.next_req)
            .is_none_or(|r| r.wait_ready);
        if complete && next_waits {
            // The answers to earlier edges may still be arriving after the last edge (a
            // compensating master allows more than one period of delay): the timeout is the
            // first rise of SL after the (low) answer to the final pulse.
            let scan = self.sl.index_at(run.t_stop_sample);
            self.phase = Phase::Timeout { run, scan };
        } else {
            self.report(&run, None);
            self.next_frame(last, !complete, None);
        }
    }
}

impl LineMaster for BissMaster {
    fn ma_for_cycle(&mut self, k: usize) -> bool {
        let t = self.cfg.timing.edge_ns(k) - self.cfg.timing.line_delay_ns;
        self.advance(t);
        self.ma.before(t)
    }
    fn push_slo(&mut self, slo: bool) {
        self.sl.push(slo);
    }
}
