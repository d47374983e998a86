//! The table's online learner as the RTL will run it (docs/correction.md, "Learning the
//! table online"): the method of [`super::learn`] in integers, as a sequencer of table steps
//! with one [`Sequencer::step`] per clock, for the RTL to follow register for register. No
//! RTL yet; no float in the state or the arithmetic.
//!
//! ```text
//!  strobe, angle m, delta ──► Collect ──(N samples)──► Line ──► Residual[0..P) ──► Mean
//!         (one sample per strobe:          (b by a      (per bin: products, one    (sum r /
//!          bin RAM read-modify-write)       division,    division, r_i into the     bins with
//!               ▲                           a by shift)  bin's word)                samples)
//!               │                                                                     │
//!             Apply ◄──────────── Update[0..P): c'_i = c_i + clip(2^-g (r_i - r), ±step) ◄┘
//!   (flip the bank: the new        into the other bank, one table write per clock;
//!    table from the next sample)   bin i's sums cleared
//! ```
//!
//! Units and formats. F fine bits: the period is 2^(F+2) LSB. P = 2^p entries, a window of
//! N = 2^w samples, T = [`TABLE_FRAC`] fraction bits (the "q unit", 2^-T LSB), the line's
//! B = w + [`LINE_GUARD`] fraction bits below the q unit. Each register holds an integer of
//! the stated width (two's complement when signed) and the model wraps it there
//! ([`wrap`]), as the RTL does; the widths are large enough that nothing wraps for an input
//! within the conditions (|delta| < 2^(F+1) LSB per sample, the counter's unwrap limit).
//!
//! | register | meaning | units | bits (signed) | F = 14, p = 7, w = 12, T = 8 |
//! |---|---|---|---|---|
//! | c_i (two banks of P) | table entry, \|c_i\| <= 2^(F-4) LSB (saturated) | q | F - 4 + T + 1 | 19 |
//! | pos | raw position since the window's first sample, \|pos\| < 2^(w+F+1) | LSB | w + F + 2 | 28 |
//! | q | pos 2^T - c(m): the corrected position | q | w + F + T + 3 | 37 |
//! | k | sample of the window, 0..N | 1 | w + 1 (unsigned) | 13 |
//! | n_i | samples of bin i, <= N | 1 | w + 1 (unsigned) | 13 |
//! | sk_i | sum of k in bin i, < N^2 / 2 | 1 | 2w - 1 (unsigned) | 23 |
//! | sp_i | sum of q in bin i, < N 2^(w+F+T+2) | q | 2w + F + T + 3 | 49 |
//! | Sp, Skp | sum of q, sum of k q (the window's) | q | 2w + F + T + 3, 3w + F + T + 2 | 49, 60 |
//! | b | the line's slope, \|b\| < 2^(F+1) LSB per sample | 2^-B q | F + T + B + 2 | 40 |
//! | a | the line's value at k = 0, \|a\| < max\|q\| + \|b\| N / 2 | 2^-B q | w + F + T + B + 4 | 54 |
//! | r_i (in sp_i's word) | bin i's mean residual, saturated to \|r\| < 2^(F-2) LSB | q | F - 2 + T + 1 | 21 |
//! | sum r, r | the residuals' sum over <= P bins, their mean | q | F - 2 + T + 1 + p, F - 2 + T + 1 | 28, 21 |
//!
//! Bit growth: a sum of N = 2^w terms grows by w bits (sp_i, Sp), a sum of k q by 2w (k < 2^w),
//! a product by the sum of the factors' widths. The window's S0 = N, S1 = N (N - 1) / 2 and
//! S2 = (N - 1) N (2N - 1) / 6 are constants (every sample of the window falls in a bin), so
//! the line needs only Sp and Skp:
//!
//! ```text
//! det = N S2 - S1^2 = N^2 (N^2 - 1) / 12                       (constant, 4w bits)
//! b   = round((N Skp - S1 Sp) 2^B / det)                       (numerator 4w + F + T + B + 3 bits)
//! a   = (Sp 2^B - b S1) >> w                                   (floor)
//! r_i = sat(round((sp_i 2^B - a n_i - b sk_i) / (n_i 2^B)))    (numerator 3w + F + T + B + 4 bits)
//! r   = round(sum_i r_i / bins with samples)
//! c'_i = sat(c_i + clip(round((r_i - r) 2^-g), ±step))         (only bins with samples)
//! ```
//!
//! round(x / d) is a restoring division of |x| + d/2 by d (one quotient bit per clock) with
//! x's sign; the products are shift-add (one multiplier bit per clock). The model computes
//! each result whole at its step's last clock, which is what the bit-serial unit holds
//! then, and counts the clocks: [`LearnParams::line_clocks`], [`LearnParams::residual_clocks`]
//! per bin, [`LearnParams::mean_clocks`], P clocks of Update and one of Apply
//! ([`LearnParams::solve_clocks`]: 6229 at F = 14, p = 7, w = 12, T = 8, i.e. 61 samples at
//! 102 clocks per sample). Samples that arrive outside Collect still move `pos` but are not
//! collected: the next window starts at the first sample after Apply.
//!
//! The table's correction at the raw fine angle m (LSB, 0..2^(F+2)), s = F + 2 - p:
//! i = m >> s, f = m mod 2^s, c(m) = (c_i 2^s + (c_(i+1 mod P) - c_i) f) >> s (floor, q
//! units); the sample's bin is round(((m 2^T - c(m)) mod 2^(F+2+T)) / 2^(s+T)) mod P, the
//! entry nearest the corrected angle.
//!
//! Error against the floating-point model ([`super::learn::Learner`]) on the same samples,
//! in q units per window: c(m) floors (<= 1, which enters every q and so r_i by <= 1), a and
//! b round (b's error 2^-B times k < 2^w: 2^-[`LINE_GUARD`]), r_i and r round (1/2 each),
//! so r_i - r is within 1 + 1/16 + 1/2 + (1 + 1/16 + 1/2 + 1/2) = 3.63 and the update,
//! 2^-g of it rounded, within delta = 3.63 / 2 + 1/2 = 2.3 q units at g = 1 (0.009 LSB at
//! T = 8). Without credit for the update's contraction (a pattern of entries that the bins'
//! residuals see weakly keeps its error) the tables drift apart by at most delta per
//! window: 0.27 LSB after 30 windows. At T = 4 the measured drift reached 0.6 LSB in 23
//! windows, so T = 8. A constant in the table is a constant in the position, which neither
//! model observes (the residuals lose their mean), so the comparison leaves it out; the
//! update rounds halves away from zero so that the table's mean walks without a bias.
//!
//! The position never jumps by more than `step`: the block's correction is a convex
//! combination of two entries, each of which moves by at most `step` at an Apply, and no
//! entry changes at any other clock.
//!
//! Conditions (docs/correction.md): the speed at most the counter's unwrap limit (|delta| <
//! 2^(F+1) LSB per sample) and at least one period per window (|b| N >= 2^(F+2) LSB: at
//! 1.307 Msps, N = 4096 and the default 2048 lines, 9.3 rpm), else the window writes every
//! entry back unchanged (at zero speed all samples fall in one or two bins, whose residuals
//! are noise); a steady speed: an acceleration of alpha LSB per sample^2 bends the window's
//! positions from their line by up to alpha N^2 / 8 LSB, which must stay below 1 LSB
//! (alpha < 8 / N^2 = 4.8e-7 LSB per sample^2 at N = 4096); an unsteady window still moves
//! no entry by more than `step`.

/// Fraction bits T of a table entry and of the corrected position below the LSB.
pub const TABLE_FRAC: u32 = 8;

/// Fraction bits of the line's a and b beyond the window's w (B = w + LINE_GUARD).
pub const LINE_GUARD: u32 = 4;

/// The learner's formats and settings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LearnParams {
    /// F: fine bits of the position (the period is 2^(F+2) LSB).
    pub fine_bits: u32,
    /// p: log2 of the entries P.
    pub points_log2: u32,
    /// w: log2 of the samples per window N.
    pub window_log2: u32,
    /// g: the update takes 2^-g of a bin's residual.
    pub gain_shift: u32,
    /// The largest change of an entry per update, q units (2^-T LSB).
    pub step: i64,
}

impl LearnParams {
    /// The design's learner (docs/correction.md): `points` entries, windows of `window`
    /// samples, gain 1/2, at most `step_lsb` per update; the message says what is allowed.
    pub fn new(fine_bits: u32, points: u32, window: u32, step_lsb: u32) -> Result<Self, String> {
        if !(super::POINTS_RANGE.contains(&points) && points.is_power_of_two()) {
            return Err(format!(
                "{points} entries: allowed a power of two from {} to {}",
                super::POINTS_RANGE.start(),
                super::POINTS_RANGE.end()
            ));
        }
        if !((256..=65536).contains(&window) && window.is_power_of_two()) {
            return Err(format!(
                "a window of {window} samples: allowed a power of two from 256 to 65536"
            ));
        }
        if !(8..=20).contains(&fine_bits) {
            return Err(format!("{fine_bits} fine bits: allowed 8 to 20"));
        }
        let p = LearnParams {
            fine_bits,
            points_log2: points.trailing_zeros(),
            window_log2: window.trailing_zeros(),
            gain_shift: 1,
            step: i64::from(step_lsb) << TABLE_FRAC,
        };
        if p.step > p.entry_max() {
            return Err(format!(
                "a step of {step_lsb} LSB: allowed up to the largest entry, 2^(F-4) = {} LSB",
                1u64 << (fine_bits - 4)
            ));
        }
        Ok(p)
    }

    /// P.
    pub fn points(&self) -> usize {
        1 << self.points_log2
    }

    /// N.
    pub fn window(&self) -> u64 {
        1 << self.window_log2
    }

    /// B: fraction bits of a and b below the q unit.
    pub fn line_frac(&self) -> u32 {
        self.window_log2 + LINE_GUARD
    }

    /// The largest entry, q units: 2^(F-4) LSB (the block's bound, [`super::HarmonicParams`]).
    pub fn entry_max(&self) -> i64 {
        1 << (self.fine_bits - 4 + TABLE_FRAC)
    }

    /// The largest residual, q units: 2^(F-2) LSB less one q unit.
    pub fn residual_max(&self) -> i64 {
        (1 << (self.fine_bits - 2 + TABLE_FRAC)) - 1
    }

    /// Bits of an entry (signed).
    pub fn entry_width(&self) -> u32 {
        self.fine_bits - 4 + TABLE_FRAC + 1
    }

    /// Bits of `pos` (signed).
    pub fn pos_width(&self) -> u32 {
        self.window_log2 + self.fine_bits + 2
    }

    /// Bits of q (signed).
    pub fn q_width(&self) -> u32 {
        self.window_log2 + self.fine_bits + TABLE_FRAC + 3
    }

    /// Bits of sp_i and Sp (signed).
    pub fn sum_p_width(&self) -> u32 {
        2 * self.window_log2 + self.fine_bits + TABLE_FRAC + 3
    }

    /// Bits of Skp (signed).
    pub fn sum_kp_width(&self) -> u32 {
        3 * self.window_log2 + self.fine_bits + TABLE_FRAC + 2
    }

    /// Bits of b (signed).
    pub fn b_width(&self) -> u32 {
        self.fine_bits + TABLE_FRAC + self.line_frac() + 2
    }

    /// Bits of a (signed).
    pub fn a_width(&self) -> u32 {
        self.window_log2 + self.fine_bits + TABLE_FRAC + self.line_frac() + 4
    }

    /// Clocks of Line: b's division (one clock per quotient bit and one to load), then a's
    /// product b S1 (one per bit of S1, 2w - 1 bits).
    pub fn line_clocks(&self) -> u32 {
        (self.b_width() - 1 + 1) + (2 * self.window_log2 - 1)
    }

    /// Clocks of Residual per bin: the read, the products a n_i and b sk_i side by side (2w -
    /// 1 clocks, sk_i's bits), the subtract, r_i's division (F - 2 + T quotient bits and one
    /// to load) and the write.
    pub fn residual_clocks(&self) -> u32 {
        1 + (2 * self.window_log2 - 1) + 1 + (self.fine_bits - 2 + TABLE_FRAC + 1) + 1
    }

    /// Clocks of Mean: the division of sum r by the bins with samples.
    pub fn mean_clocks(&self) -> u32 {
        self.fine_bits - 2 + TABLE_FRAC + 1
    }

    /// Clocks from the window's last sample to the first clock of the next Collect.
    pub fn solve_clocks(&self) -> u32 {
        self.line_clocks()
            + self.residual_clocks() * self.points() as u32
            + self.mean_clocks()
            + self.points() as u32
            + 1
    }
}

/// The sequencer's states (the RTL's state enum).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum State {
    /// Take one sample per strobe into its bin's sums and the window's.
    Collect,
    /// The line's b and a; `left` clocks to go.
    Line {
        /// Clocks left.
        left: u32,
    },
    /// Bin `bin`'s mean residual; `left` clocks to go.
    Residual {
        /// The bin.
        bin: usize,
        /// Clocks left.
        left: u32,
    },
    /// The residuals' mean; `left` clocks to go.
    Mean {
        /// Clocks left.
        left: u32,
    },
    /// Entry `bin` of the other bank (one table write), bin `bin`'s sums cleared.
    Update {
        /// The bin.
        bin: usize,
    },
    /// Take the other bank as the table.
    Apply,
}

/// One clock's inputs (what the RTL's ports will carry).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LearnIn {
    /// Synchronous reset: zero table, empty sums, Collect.
    pub rst: bool,
    /// A decoded sample this clock.
    pub strobe: bool,
    /// Its raw fine angle within the period (before the table), LSB, 0..2^(F+2).
    pub angle: u32,
    /// Its raw position less the previous sample's, LSB (|delta| < 2^(F+1)).
    pub delta: i32,
    /// Update the table (0: the learner collects and solves but writes each entry back
    /// unchanged).
    pub update: bool,
}

/// The integer learner: registers and RAMs of the RTL to come.
#[derive(Clone, Debug)]
pub struct Sequencer {
    /// Formats and settings.
    pub params: LearnParams,
    /// The state.
    pub state: State,
    /// The two banks of the table, q units.
    banks: [Vec<i64>; 2],
    /// The bank the block reads.
    active: usize,
    /// Per bin: n_i, sk_i, sp_i (r_i after Residual).
    n: Vec<i64>,
    sk: Vec<i64>,
    sp: Vec<i64>,
    /// The window's sample count k, raw position, Sp, Skp.
    k: u64,
    pos: i64,
    sum_p: i128,
    sum_kp: i128,
    /// The line (2^-B q units).
    a: i128,
    b: i128,
    /// The window travelled at least one period (|b| N >= 2^(F+2) LSB): else no update.
    moving: bool,
    /// The residuals' sum, the bins with samples, their mean.
    sum_r: i64,
    bins: i64,
    mean: i64,
    /// Windows applied.
    pub windows: u64,
    /// The largest change of an entry at the last Apply, q units.
    pub last_change: i64,
    /// The largest change of an entry at any Apply since reset, q units.
    pub max_change: i64,
    change: i64,
}

/// `x` taken modulo 2^bits as a two's complement number.
pub fn wrap(x: i128, bits: u32) -> i128 {
    let m = 1i128 << bits;
    let y = x.rem_euclid(m);
    if y >= m / 2 {
        y - m
    } else {
        y
    }
}

/// round(x / d), halves away from zero, d > 0: a restoring division of |x| + d/2 by d.
fn div_round(x: i128, d: i128) -> i128 {
    let q = (x.abs() + d / 2) / d;
    if x < 0 {
        -q
    } else {
        q
    }
}

impl Sequencer {
    /// Out of reset: a zero table, Collect.
    pub fn new(params: LearnParams) -> Self {
        let pp = params.points();
        Sequencer {
            params,
            state: State::Collect,
            banks: [vec![0; pp], vec![0; pp]],
            active: 0,
            n: vec![0; pp],
            sk: vec![0; pp],
            sp: vec![0; pp],
            k: 0,
            pos: 0,
            sum_p: 0,
            sum_kp: 0,
            a: 0,
            b: 0,
            moving: false,
            sum_r: 0,
            bins: 0,
            mean: 0,
            windows: 0,
            last_change: 0,
            max_change: 0,
            change: 0,
        }
    }

    /// The table the block reads, q units.
    pub fn table(&self) -> &[i64] {
        &self.banks[self.active]
    }

    /// The table the block reads, LSB (for `[harmonics] table` in tests).
    pub fn table_lsb(&self) -> Vec<f64> {
        let unit = f64::from(1u32 << TABLE_FRAC);
        self.table().iter().map(|&c| c as f64 / unit).collect()
    }

    /// The table's correction at the raw fine angle `m` (LSB), q units.
    pub fn correction(&self, m: u32) -> i64 {
        let s = self.params.fine_bits + 2 - self.params.points_log2;
        let t = self.table();
        let i = (m >> s) as usize % t.len();
        let j = (i + 1) % t.len();
        let f = i64::from(m & ((1 << s) - 1));
        ((t[i] << s) + (t[j] - t[i]) * f) >> s
    }

    /// One clock.
    pub fn step(&mut self, x: LearnIn) {
        if x.rst {
            *self = Sequencer::new(self.params);
            return;
        }
        let pr = self.params;
        let pp = pr.points();
        if x.strobe {
            // The raw position since the window's first sample; restarted by it.
            let start = self.state == State::Collect && self.k == 0;
            let pos = if start {
                0
            } else {
                i128::from(self.pos) + i128::from(x.delta)
            };
            self.pos = wrap(pos, pr.pos_width()) as i64;
        }
        match self.state {
            State::Collect => {
                if x.strobe {
                    self.collect(x.angle);
                    if self.k == pr.window() {
                        self.state = State::Line {
                            left: pr.line_clocks() - 1,
                        };
                    }
                }
            }
            State::Line { left: 0 } => {
                self.line();
                self.state = State::Residual {
                    bin: 0,
                    left: pr.residual_clocks() - 1,
                };
            }
            State::Line { left } => self.state = State::Line { left: left - 1 },
            State::Residual { bin, left: 0 } => {
                self.residual(bin);
                self.state = if bin + 1 < pp {
                    State::Residual {
                        bin: bin + 1,
                        left: pr.residual_clocks() - 1,
                    }
                } else {
                    State::Mean {
                        left: pr.mean_clocks() - 1,
                    }
                };
            }
            State::Residual { bin, left } => {
                self.state = State::Residual {
                    bin,
                    left: left - 1,
                }
            }
            State::Mean { left: 0 } => {
                self.mean = if self.bins > 0 {
                    div_round(i128::from(self.sum_r), i128::from(self.bins)) as i64
                } else {
                    0
                };
                self.change = 0;
                self.state = State::Update { bin: 0 };
            }
            State::Mean { left } => self.state = State::Mean { left: left - 1 },
            State::Update { bin } => {
                self.update(bin, x.update);
                self.state = if bin + 1 < pp {
                    State::Update { bin: bin + 1 }
                } else {
                    State::Apply
                };
            }
            State::Apply => {
                self.active ^= 1;
                self.windows += 1;
                self.last_change = self.change;
                self.max_change = self.max_change.max(self.change);
                self.k = 0;
                self.sum_p = 0;
                self.sum_kp = 0;
                self.sum_r = 0;
                self.bins = 0;
                self.state = State::Collect;
            }
        }
    }

    /// Collect: the sample's bin and sums (one read-modify-write of the bin RAM).
    fn collect(&mut self, m: u32) {
        let pr = self.params;
        let c = self.correction(m);
        let s = pr.fine_bits + 2 - pr.points_log2 + TABLE_FRAC;
        let mc = (i64::from(m) << TABLE_FRAC) - c;
        let bin = (((mc + (1 << (s - 1))) >> s) & (pr.points() as i64 - 1)) as usize;
        let q = wrap(
            (i128::from(self.pos) << TABLE_FRAC) - i128::from(c),
            pr.q_width(),
        );
        let k = self.k as i128;
        self.n[bin] += 1;
        self.sk[bin] += k as i64;
        self.sp[bin] = wrap(i128::from(self.sp[bin]) + q, pr.sum_p_width()) as i64;
        self.sum_p = wrap(self.sum_p + q, pr.sum_p_width());
        self.sum_kp = wrap(self.sum_kp + k * q, pr.sum_kp_width());
        self.k += 1;
    }

    /// Line: b by a division, a by b S1 and a shift.
    fn line(&mut self) {
        let pr = self.params;
        let n = i128::from(pr.window() as u32);
        let s1 = n * (n - 1) / 2;
        let det = n * n * (n * n - 1) / 12;
        let bf = pr.line_frac();
        let num = n * self.sum_kp - s1 * self.sum_p;
        self.b = wrap(div_round(num << bf, det), pr.b_width());
        self.a = wrap(
            ((self.sum_p << bf) - self.b * s1) >> pr.window_log2,
            pr.a_width(),
        );
        // One period per window: |b| 2^w >= 2^(F+2+T+B), a compare of |b| with a constant.
        let one_period = 1i128 << (pr.fine_bits + 2 + TABLE_FRAC + bf - pr.window_log2);
        self.moving = self.b.abs() >= one_period;
    }

    /// Residual: bin i's mean residual into its sp word, summed for the mean.
    fn residual(&mut self, i: usize) {
        let pr = self.params;
        if self.n[i] == 0 {
            return;
        }
        let bf = pr.line_frac();
        let ni = i128::from(self.n[i]);
        let num = (i128::from(self.sp[i]) << bf) - self.a * ni - self.b * i128::from(self.sk[i]);
        let lim = i128::from(pr.residual_max());
        let r = div_round(num, ni << bf).clamp(-lim, lim) as i64;
        self.sp[i] = r;
        self.sum_r += r;
        self.bins += 1;
    }

    /// Update: entry i of the other bank (one table write); bin i's sums cleared.
    fn update(&mut self, i: usize, enable: bool) {
        let pr = self.params;
        let old = self.banks[self.active][i];
        let new = if enable && self.moving && self.n[i] > 0 {
            let g = pr.gain_shift;
            // 2^-g (r_i - r) rounded, halves away from zero (no bias to the table's mean).
            let x = self.sp[i] - self.mean;
            let d = x.signum() * ((x.abs() + (1 << (g - 1))) >> g);
            let d = d.clamp(-pr.step, pr.step);
            (old + d).clamp(-pr.entry_max(), pr.entry_max())
        } else {
            old
        };
        self.change = self.change.max((new - old).abs());
        self.banks[self.active ^ 1][i] = new;
        self.n[i] = 0;
        self.sk[i] = 0;
        self.sp[i] = 0;
    }
}
