//! Model of learning the table online (docs/correction.md, "Learning the table online"):
//! the method in floating point, sample by sample, for proving its conditions and its
//! convergence on the closed loop's positions before the hardware exists. Not bit-accurate:
//! the integer model the RTL will follow is [`super::sequencer`].
//!
//! Per decoded sample k of a window of N: the corrected position p_k (unwrapped, LSB) and
//! its angle within the signal period give bin i = round(angle P / period) mod P (bin i is
//! centred on entry i). Per bin the learner keeps n_i, sum k and sum p; for the window
//! S0, S1, S2, Sp, Skp. After N samples: the least-squares line p = a + b k, each bin's mean
//! residual r_i = (sum p - a n_i - b sum k) / n_i, their mean r over the bins with samples,
//! and entry i moves by clip(gain (r_i - r), +-step).
//!
//! The learned table is loaded as `[harmonics] table` ([`toml`]) to measure it in the
//! closed loop; the integer model (`super::sequencer`) is checked against this one and
//! measured that way (`tests/blocks/harmonics_learn.rs`).
/// The learner's settings and state.
#[derive(Clone, Debug)]
pub struct Learner {
    /// Entries P.
    points: usize,
    /// Samples per window N.
    window: usize,
    /// Fraction of a bin's residual taken per window.
    gain: f64,
    /// Largest change of an entry per window, LSB.
    step: f64,
    /// Fine bits F (a period is 2^(F+2) LSB).
    fine_bits: u32,
    /// The table, LSB.
    pub table: Vec<f64>,
    /// Per bin: samples, sum of k, sum of p.
    bins: Vec<(f64, f64, f64)>,
    /// Samples so far in this window.
    k: usize,
    /// Sum of k p over the window (the line's Skp).
    skp: f64,
    /// The window's first position: the sums take p less it (f64 keeps them exact).
    p0: f64,
    /// Windows completed.
    pub windows: usize,
    /// The largest change of an entry in the last window, LSB.
    pub last_change: f64,
}

impl Learner {
    /// A learner of `points` entries from a zero table, updating every `window` samples.
    pub fn new(points: usize, window: usize, gain: f64, step: f64, fine_bits: u32) -> Self {
        Learner {
            points,
            window,
            gain,
            step,
            fine_bits,
            table: vec![0.0; points],
            bins: vec![(0.0, 0.0, 0.0); points],
            k: 0,
            skp: 0.0,
            p0: 0.0,
            windows: 0,
            last_change: 0.0,
        }
    }

    /// The period in LSB: 2^(F+2).
    fn period(&self) -> f64 {
        (1u64 << (self.fine_bits + 2)) as f64
    }

    /// The table's correction at the angle `m` (LSB within the period), linearly
    /// interpolated as the block does (in floating point).
    pub fn correction(&self, m: f64) -> f64 {
        let x = m.rem_euclid(self.period()) / self.period() * self.points as f64;
        let i = x.floor() as usize % self.points;
        let u = x - x.floor();
        let j = (i + 1) % self.points;
        self.table[i] + (self.table[j] - self.table[i]) * u
    }

    /// One decoded sample: its position `raw` (unwrapped, LSB) before the table; returns
    /// the position after it (raw less the table's correction at raw's angle).
    pub fn sample(&mut self, raw: f64) -> f64 {
        let p = raw - self.correction(raw);
        let period = self.period();
        let bin =
            (p.rem_euclid(period) / period * self.points as f64).round() as usize % self.points;
        if self.k == 0 {
            self.p0 = p;
        }
        let k = self.k as f64;
        let q = p - self.p0;
        let b = &mut self.bins[bin];
        b.0 += 1.0;
        b.1 += k;
        b.2 += q;
        self.skp += k * q;
        self.k += 1;
        if self.k == self.window {
            self.update();
        }
        p
    }

    /// The window's solve and the table's update.
    fn update(&mut self) {
        let (mut s0, mut s1, mut sp) = (0.0, 0.0, 0.0);
        for &(n, sk, spp) in &self.bins {
            s0 += n;
            s1 += sk;
            sp += spp;
        }
        // S2 over k = 0..N is fixed by the window.
        let n = s0;
        let s2 = (0..self.window).map(|k| (k * k) as f64).sum::<f64>();
        let skp = self.skp;
        let det = n * s2 - s1 * s1;
        let b = (n * skp - s1 * sp) / det;
        let a = (sp - b * s1) / n;
        let mut res = vec![None; self.points];
        for (i, &(ni, ski, spi)) in self.bins.iter().enumerate() {
            if ni > 0.0 {
                res[i] = Some((spi - a * ni - b * ski) / ni);
            }
        }
        let have: Vec<f64> = res.iter().flatten().copied().collect();
        let mean = have.iter().sum::<f64>() / have.len().max(1) as f64;
        self.last_change = 0.0;
        for (c, r) in self.table.iter_mut().zip(&res) {
            if let Some(r) = r {
                let d = (self.gain * (r - mean)).clamp(-self.step, self.step);
                *c += d;
                self.last_change = self.last_change.max(d.abs());
            }
        }
        self.bins.iter_mut().for_each(|b| *b = (0.0, 0.0, 0.0));
        self.k = 0;
        self.skp = 0.0;
        self.windows += 1;
    }
}

/// The learned table as `[harmonics]` TOML (`points` entries, LSB), for a static run.
pub fn toml(table: &[f64]) -> String {
    let e: Vec<String> = table.iter().map(|v| format!("{v:.3}")).collect();
    format!(
        "[harmonics]\nenabled = true\nmode = \"static\"\npoints = {}\ntable = [{}]\n",
        table.len(),
        e.join(", ")
    )
}
