//! The line model every serial master model shares ([`crate::sim::serial_master`]): time,
//! the master's clock line, the slave's answer line, the clock burst of one frame, and the
//! frame request.
//!
//! The master lives in continuous time (f64 nanoseconds); the slave is a synchronous design
//! simulated one system clock at a time. Rising system clock edge k is at t_k = k T_clk. The
//! line adds the same delay d in both directions:
//!
//! * the slave's clock input for edge k is the clock as the master drove it at t_k - d
//!   (edges exactly at that instant not yet seen), so clock edges land between slave clock
//!   edges at whatever phase the master's frequency and start time give;
//! * the slave's output after edge k (registered, so constant until edge k+1) reaches the
//!   master at t_k + d: the line at the master at time t is the output after the last edge k
//!   with t_k < t - d.
//!
//! ```text
//!  master (continuous time)           line (delay d)          slave (clocked, T_clk)
//!  MaLine: transitions (t, level) ──── t_k - d ──────────────> sampled at edge k
//!  SlaveLine::at(t)  <──────────────── + d ───────────────────── output after edge k
//! ```

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
    /// Stop after this rising edge.
    pub stop_after: Option<u32>,
    /// After the last rising edge, one more falling edge: MA stays low (a BiSS master's
    /// CDM = 1 during the timeout) until the master raises it.
    pub end_low: bool,
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
            end_low: false,
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
    /// Whether the burst has stopped (MA high for good, or low with `end_low`).
    pub fn stopped(&self) -> bool {
        self.stop_after
            .is_some_and(|k| self.rises >= k && self.falls == self.rises + self.end_low as u32)
    }
    /// Whether the burst has stopped with MA low (`end_low`).
    pub fn ended_low(&self) -> bool {
        self.stopped() && self.falls > self.rises
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
    /// BiSS C control bit CDM sent in this frame's timeout: true holds MA low after the
    /// frame's last rising edge until the slave is ready again (complete frames only).
    pub cdm: bool,
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
            cdm: false,
        }
    }
    /// With a pause before the frame.
    pub fn gap(mut self, ns: f64) -> Self {
        self.gap_ns = ns;
        self
    }
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

/// The data word a master reads: N bits, MSB first, the top M of them the turn count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WordFormat {
    /// Data bits N (multi-turn + single-turn), 1..=32.
    pub data_bits: u32,
    /// Multi-turn bits M at the head of the data.
    pub multiturn_bits: u32,
    /// The data word is Gray-coded.
    pub gray: bool,
    /// Bits of the velocity word after the data word (0: none): two's complement, MSB first,
    /// never Gray-coded (`[velocity] in_frames`).
    pub velocity_bits: u32,
}

impl WordFormat {
    /// Binary word of N data bits of which M are multi-turn.
    pub fn new(data_bits: u32, multiturn_bits: u32) -> Self {
        Self {
            data_bits,
            multiturn_bits,
            gray: false,
            velocity_bits: 0,
        }
    }

    /// The same word followed by a `bits`-bit velocity word.
    pub fn with_velocity(mut self, bits: u32) -> Self {
        self.velocity_bits = bits;
        self
    }

    /// The velocity of the velocity word's bits (MSB first), sign-extended; None without
    /// one.
    pub fn velocity(&self, bits: &[bool]) -> Option<i64> {
        let v = self.velocity_bits;
        (v > 0).then(|| {
            let w = word_of(bits);
            ((w << (64 - v)) as i64) >> (64 - v)
        })
    }
    /// Single-turn position and turn count (binary, after Gray decoding) of a data word.
    pub fn split(&self, data: u64) -> (u64, u64) {
        let bin = if self.gray { from_gray(data) } else { data };
        let st = self.data_bits - self.multiturn_bits;
        if st >= 64 {
            (bin, 0)
        } else {
            (bin & ((1u64 << st) - 1), bin >> st)
        }
    }
}

/// The word of `bits`, MSB first.
pub fn word_of(bits: &[bool]) -> u64 {
    bits.iter().fold(0u64, |a, &v| (a << 1) | v as u64)
}
