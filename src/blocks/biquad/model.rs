//! Bit-accurate model of the biquad engine: [`BiquadModel`] computes one sample of every
//! branch (the arithmetic of the module docs, written directly from the difference
//! equation, not from the hardware program), [`BiquadCycleModel`] adds the clock-level
//! interface (busy, out_valid, dropped, reset sweep) in the co-simulation row format of
//! [`super::hdl::BiquadRtl`].
use super::BiquadParams;
use crate::blocks::{mask, sext};

/// Sample-level model: per branch, the history (x[n-1], x[n-2]) of every cascade node
/// (node 0 = branch input, node k = output of section k-1) in the S-bit state format.
#[derive(Clone, Debug)]
pub struct BiquadModel {
    p: BiquadParams,
    /// hist[branch][node] = (z^-1, z^-2).
    hist: Vec<Vec<(i64, i64)>>,
}

impl BiquadModel {
    /// Zero state.
    pub fn new(p: &BiquadParams) -> Self {
        let hist = p
            .branches
            .iter()
            .map(|s| vec![(0, 0); s.len() + 1])
            .collect();
        BiquadModel { p: p.clone(), hist }
    }

    /// Clears the state (as after reset).
    pub fn reset(&mut self) {
        for b in &mut self.hist {
            for h in b.iter_mut() {
                *h = (0, 0);
            }
        }
    }

    /// One sample: `inputs[k]` is branch k's D-bit input (values outside the D-bit range
    /// are wrapped to D bits like the hardware's port). Returns the D-bit outputs and
    /// whether any used section result was saturated.
    pub fn step(&mut self, inputs: &[i64]) -> (Vec<i64>, bool) {
        let d = self.p.data_width;
        let g = self.p.guard_frac;
        let s_w = self.p.state_width();
        let f = self.p.coef_frac;
        let smax = (1i64 << (s_w - 1)) - 1;
        let smin = -(1i64 << (s_w - 1));
        let mut outs = Vec::with_capacity(self.hist.len());
        let mut overflow = false;
        for (b, secs) in self.p.branches.iter().enumerate() {
            let raw = inputs.get(b).copied().unwrap_or(0);
            let mut x = sext(raw as u64 & mask(d), d) << g;
            let h = &mut self.hist[b];
            for (s, c) in secs.iter().enumerate() {
                let terms = [
                    c[0] * x,
                    c[1] * h[s].0,
                    c[2] * h[s].1,
                    -c[3] * h[s + 1].0,
                    -c[4] * h[s + 1].1,
                ];
                // Each product is floored (arithmetic shift) before the sum.
                let acc: i64 = terms.iter().map(|t| t >> f).sum();
                let y = acc.clamp(smin, smax);
                overflow |= y != acc;
                h[s] = (x, h[s].0);
                x = y;
            }
            let n = secs.len();
            h[n] = (x, h[n].0);
            outs.push(x >> g);
        }
        (outs, overflow)
    }
}

/// Inputs of one clock in [`super::hdl::BiquadRtl`]'s stimulus-row order.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct BiquadIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Start strobe.
    pub in_valid: bool,
    /// Branch inputs (D-bit values).
    pub data: Vec<i64>,
}

impl BiquadIn {
    /// The stimulus row: rst, in_valid, in_data_0.. (D-bit two's complement).
    pub fn row(&self, p: &BiquadParams) -> Vec<u64> {
        let mut r = vec![self.rst as u64, self.in_valid as u64];
        r.extend(
            (0..p.branch_count())
                .map(|k| self.data.get(k).copied().unwrap_or(0) as u64 & mask(p.data_width)),
        );
        r
    }
}

/// Clock-level model: the interface timing of the module docs around [`BiquadModel`].
#[derive(Clone, Debug)]
pub struct BiquadCycleModel {
    m: BiquadModel,
    p: BiquadParams,
    clearing: u32,
    busy_left: u32,
    pending: (Vec<i64>, bool),
    out_valid: bool,
    out_data: Vec<i64>,
    overflow: bool,
    dropped: bool,
}

impl BiquadCycleModel {
    /// Power-up state (state RAM zero, idle; outputs 0).
    pub fn new(p: &BiquadParams) -> Self {
        BiquadCycleModel {
            m: BiquadModel::new(p),
            p: p.clone(),
            clearing: 0,
            busy_left: 0,
            pending: (vec![], false),
            out_valid: false,
            out_data: vec![0; p.branch_count()],
            overflow: false,
            dropped: false,
        }
    }

    /// One clock edge with the inputs `i`; returns the output row after it.
    pub fn tick(&mut self, i: &BiquadIn) -> Vec<u64> {
        self.out_valid = false;
        self.overflow = false;
        self.dropped = false;
        if i.rst {
            self.m.reset();
            self.clearing = self.p.state_words();
            self.busy_left = 0;
            self.out_data.iter_mut().for_each(|v| *v = 0);
        } else if self.clearing > 0 {
            self.clearing -= 1;
            self.dropped = i.in_valid;
        } else if self.busy_left == 0 {
            if i.in_valid {
                self.pending = self.m.step(&i.data);
                self.busy_left = self.p.latency();
            }
        } else {
            self.dropped = i.in_valid;
            self.busy_left -= 1;
            if self.busy_left == 0 {
                self.out_valid = true;
                self.out_data = self.pending.0.clone();
                self.overflow = self.pending.1;
            }
        }
        self.row()
    }

    /// Output row: out_valid, out_data_0.., overflow, busy, dropped.
    pub fn row(&self) -> Vec<u64> {
        let dm = mask(self.p.data_width);
        let mut r = vec![self.out_valid as u64];
        r.extend(self.out_data.iter().map(|&v| v as u64 & dm));
        r.push(self.overflow as u64);
        r.push((self.clearing > 0 || self.busy_left > 0) as u64);
        r.push(self.dropped as u64);
        r
    }
}
