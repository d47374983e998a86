//! The table's online learner in integers (docs/correction.md, "Learning the table
//! online"): the method of [`super::learn`] as a sequencer of table steps with one
//! [`Sequencer::step`] per clock, the specification that the RTL,
//! [`super::learner::HarmonicLearner`], follows register for register and state for state
//! (rust-hdl == this model == Icarus == Verilator == engine, tests/blocks/harmonics_learner.rs).
//! No float in the state or the arithmetic.
//!
//! ```text
//!  rst / power-up ─► Clear: the start table into both banks (2P writes), the bins' sums 0
//!                      │
//!  strobe, angle m ──► Collect ──(N samples)──► Line ──► Residual[0..P) ──► Mean
//!   (delta = m - m_prev,  Wait ─► ReadI, ReadJ,  (U, b by a      (per bin: four      (sum r /
//!    F+2 bits, moves      LatJ, Diff, Mult x s,  division, a by  products, one       bins with
//!    pos on every         Corr, Bin, ReadBin,    shifts and      division, r_i into  samples)
//!    strobe)              LatBin, Acc, Sum       adds)           the bin's word)        │
//!                         Wait ─► LoadA, LoadB                                          │
//!               ▲          (ld: both banks)                                             │
//!             Apply ◄──────────── Update[0..P): c'_i = c_i + clip(2^-g (r_i - r), ±step) ◄┘
//!   (flip the bank: the new        into the other bank, one table write per entry;
//!    table from the next sample)   bin i's sums cleared
//! ```
//!
//! Ports ([`LearnIn`], [`LearnOut`]): `rst`, `strobe` (a sample), `angle` (its raw fine
//! angle m within the period, F + 2 bits), `update` (0: every entry written back
//! unchanged), `ld`, `ld_addr`, `ld_data` (set an entry); out `tw`, `tw_addr`, `tw_data`
//! (every table write, a clock after it: address bank P + i, the entry in q units in
//! [`LearnParams::entry_width`] bits), `bank` (the bank the correction reads) and `ld_busy`.
//!
//! - delta = (m - m_prev) wrapped to F + 2 bits (two's complement): the raw position's
//!   increment while |delta| < 2^(F+1) (the counter's unwrap limit, a condition anyway).
//!   Every strobe moves `pos` by it; the first sample a window collects sets `pos` = 0.
//! - Clear ([`LearnParams::clear_clocks`]) writes the start table (the config's `[harmonics]
//!   table` in q units, or zeros; [`Sequencer::with_table`]) into bank 0 and bank 1 through
//!   the write port, one entry a clock, and clears the bins; power-up is Clear, as after
//!   `rst`.
//! - A load (`ld`) is held (`ld_busy`) until a clock of Wait without a strobe, then written
//!   into entry `ld_addr` of both banks (LoadA, LoadB: two writes) so that the next Update
//!   starts from it; an `ld` while one is pending is dropped. `ld_data` is saturated to
//!   +-2^(F-4) LSB. A strobe during LoadA or LoadB is latched and processed after them.
//! - A sample takes [`LearnParams::collect_clocks`] (s + 11: 20 at F = 14, p = 7) from its
//!   strobe in Wait; with a load's two writes [`LearnParams::min_sample_clocks`] (22) is the
//!   shortest sample spacing at which no sample of a window is lost, and the core refuses a
//!   config whose sample period is shorter. A strobe that comes while a sample is in
//!   process (or in Line .. Apply, or Clear) moves `pos` but is not collected; inside a
//!   window that would bend its line, hence the refusal.
//!
//! Units and formats. F fine bits: the period is 2^(F+2) LSB. P = 2^p entries, a window of
//! N = 2^w samples, T = [`TABLE_FRAC`] fraction bits (the "q unit", 2^-T LSB), the line's
//! B = w + [`LINE_GUARD`] fraction bits below the q unit. Each register holds an integer of
//! the stated width (two's complement when signed) and the model wraps it there
//! ([`wrap`]), as the RTL does; the widths are large enough that nothing wraps for an input
//! within the conditions (|delta| < 2^(F+1) LSB per sample, the counter's unwrap limit).
//! No word of the RTL is wider than 64 bits ([`WORD_MAX`], the compiled engine's limit):
//! [`LearnParams::new`] refuses 3w + F + T + 3 > 64 (at F = 14: N <= 8192).
//!
//! | register | meaning | units | bits (signed) | F = 14, p = 7, w = 12, T = 8 |
//! |---|---|---|---|---|
//! | c_i (two banks of P) | table entry, \|c_i\| <= 2^(F-4) LSB (saturated) | q | F - 4 + T + 2 | 20 |
//! | pos | raw position since the window's first sample, \|pos\| < 2^(w+F+1) | LSB | w + F + 2 | 28 |
//! | q | pos 2^T - c(m): the corrected position | q | w + F + T + 3 | 37 |
//! | k | sample of the window, 0..N | 1 | w + 1 (unsigned) | 13 |
//! | n_i | samples of bin i, <= N | 1 | w + 1 (unsigned) | 13 |
//! | sk_i | sum of k in bin i, < N^2 / 2 | 1 | 2w - 1 (unsigned) | 23 |
//! | sp_i | sum of q in bin i, < N 2^(w+F+T+2) | q | 2w + F + T + 3 | 49 |
//! | Sp | sum of q (the window's) | q | 2w + F + T + 3 | 49 |
//! | PS | sum over the window of Sp's running value, < N^2 2^(w+F+T+2) | q | 3w + F + T + 3 | 61 |
//! | U | (N + 1) Sp - 2 PS = sum (2k - N + 1) q, \|U\| < N^2 2^(w+F+T+2) | q | 3w + F + T + 3 | 61 |
//! | b | the line's slope, \|b\| < 2^(F+1) LSB per sample | 2^-B q | F + T + B + 2 | 40 |
//! | a | the line's value at k = 0, \|a\| < max\|q\| + \|b\| N / 2 | 2^-B q | w + F + T + B + 4 | 54 |
//! | r_i (in sp_i's word) | bin i's mean residual, saturated to \|r\| < 2^(F-2) LSB | q | F - 2 + T + 1 | 21 |
//! | sum r, r | the residuals' sum over <= P bins, their mean | q | F - 2 + T + 1 + p, F - 2 + T + 1 | 28, 21 |
//!
//! Bit growth: a sum of N = 2^w terms grows by w bits (sp_i, Sp), a sum of N running sums
//! by 2w (PS), a product by the sum of the factors' widths. The window's S0 = N,
//! S1 = N (N - 1) / 2 and S2 = (N - 1) N (2N - 1) / 6 are constants (every sample of the
//! window falls in a bin). The line of the least-squares fit, b = round((N Skp - S1 Sp) 2^B / det) with
//! det = N S2 - S1^2 = N^2 (N^2 - 1) / 12, needs an 89-bit numerator and Skp = sum k q a
//! product per sample; neither is built. Instead, with PS = sum_j (sum_(k<=j) q_k) = sum_k
//! (N - k) q_k, Skp = N Sp - PS, and N Skp - S1 Sp = (N / 2) U with U = 2 Skp - (N - 1) Sp =
//! (N + 1) Sp - 2 PS (one adder per sample, no product):
//!
//! ```text
//! D    = (N^2 - 1) / 3                                       (constant, 2w - 1 bits)
//! b    = round((N/2) U 2^B / det) = round(U 2^5 / D)         (= the formula above exactly)
//!      = ±((floor(|U| 2^6 / D) + 1) >> 1)                    (Kb = 3w+F+T+10-2w quotient bits)
//! a    = (Sp 2^B - b S1) >> w = (Sp 2^5 + b - b 2^w) >> 1    (floor; no product)
//! r_i  = sat(round((sp_i 2^B - a n_i - b sk_i) / (n_i 2^B)))  (numerator 3w + F + T + B + 4 bits)
//! r    = round(sum_i r_i / bins with samples)
//! c'_i = sat(c_i + clip(round((r_i - r) 2^-g), ±step))        (only bins with samples)
//! ```
//!
//! round(x / d), d > 0, is |x| / d rounded half up with x's sign ([`div_round`]); the RTL
//! takes it as (floor(2 |x| / d) + 1) >> 1: one quotient bit more instead of adding d/2 to
//! a wide dividend. Its restoring division ([`restoring`]: t = 2 rem + next dividend bit;
//! t >= d ? (rem = t - d, bit 1) : (rem = t, bit 0)) starts with rem = dividend >> K and
//! shifts the dividend's low bits, then its low zero bits, into the remainder, one quotient
//! bit a clock, so the dividend's appended zeros (2^6 for b) need no wider word; rem < 2d.
//! b's division never overflows: |U| 2^6 / D < 2^(3w+F+T+9) / 2^(2w-2) = 2^Kb.
//!
//! r_i in 64-bit words ([`residual_serial`], checked against the i128 formula
//! [`residual`]): a = a_h 2^B + a_l and b = b_h 2^B + b_l (arithmetic shift; 0 <= a_l, b_l <
//! 2^B); Z1 = sp_i - a_h n_i - b_h sk_i (exact: < 2^(2w+F+T+4)), Z2 = a_l n_i + b_l sk_i (0
//! <= Z2 < 2^B (n_i + sk_i)), so x = sp_i 2^B - a n_i - b sk_i = Z1 2^B - Z2. With H =
//! 2^(62-B): if -H <= Z1 < H, |x| <= 2^62 + 2^(B+2w) < 2^63 fits and r_i =
//! ±((floor((|x| >> (B-1)) / n_i) + 1) >> 1), saturated (floor(floor(y / 2^(B-1)) / n) = floor(y / (n
//! 2^(B-1))); Kr = F - 1 + T quotient bits, an overflow of them saturates); if Z1 >= H, x /
//! (n_i 2^B) > H / n_i - 1 - sk_i / n_i >= 2^(58-2w) - 2^w > 2^(F-2+T), so r_i saturates
//! (likewise Z1 < -H), which holds whenever 3w + F + T + 3 <= 64; at Z1 = -H the division
//! overflows (|x| >> (Kr + B - 1) >= 2^(60-F-T-w) >= N), so r_i saturates there too, and
//! the test is Z1 + H outside [0, 2H): a sum and a test of its top bits. The four products a_h
//! n_i, b_h sk_i, a_l n_i, b_l sk_i are shift-add side by side, 2w clocks (sk_i's 2w - 1
//! bits, and one for the last add to settle); c(m)'s (c_j - c_i) f likewise, s clocks (f's
//! bits, from the LSB).
//!
//! Clocks (the model counts them state by state, the RTL's named states): Collect
//! [`LearnParams::collect_clocks`] per sample; [`LearnParams::line_clocks`] (Kb + 12 = 56),
//! [`LearnParams::residual_clocks`] per bin (2w + Kr + 14 = 59),
//! [`LearnParams::mean_clocks`] (Kr + 5 = 26), [`LearnParams::update_clocks`] per bin (7),
//! Apply 1: [`LearnParams::solve_clocks`] = 8531 at F = 14, p = 7, w = 12, T = 8, i.e. 84
//! samples at 102 clocks per sample. Every register-to-register path of the RTL holds at
//! most one carry chain, and a 64-bit sum takes two clocks (its 32-bit halves,
//! src/blocks/splitadd.rs), so the states of Line, Residual and Mean include the clocks in
//! which these sums settle, and a RAM's output is latched before an adder. Samples that arrive
//! outside Collect still move `pos` but are not collected: the next window starts at the
//! first sample after Apply.
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

/// The widest word the RTL may hold (the compiled engine's limit, src/engine).
pub const WORD_MAX: u32 = 64;

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
        if p.ps_width() > WORD_MAX {
            let w_max = (WORD_MAX - fine_bits - TABLE_FRAC - 3) / 3;
            return Err(format!(
                "a window of {window} samples at F = {fine_bits}: the learner's widest word, 3 log2(window) + F + {} bits, must fit in {WORD_MAX}; allowed up to {} samples",
                TABLE_FRAC + 3,
                1u64 << w_max
            ));
        }
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

    /// s = F + 2 - p: bits of the place f within a segment of the table.
    pub fn seg_bits(&self) -> u32 {
        self.fine_bits + 2 - self.points_log2
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

    /// Bits of an entry (signed; +-2^(F-4) LSB both fit).
    pub fn entry_width(&self) -> u32 {
        self.fine_bits - 4 + TABLE_FRAC + 2
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

    /// Bits of PS (the sum of Sp's running values) and of U = (N + 1) Sp - 2 PS (signed):
    /// the learner's widest word.
    pub fn ps_width(&self) -> u32 {
        3 * self.window_log2 + self.fine_bits + TABLE_FRAC + 3
    }

    /// Bits of b (signed).
    pub fn b_width(&self) -> u32 {
        self.fine_bits + TABLE_FRAC + self.line_frac() + 2
    }

    /// Bits of a (signed).
    pub fn a_width(&self) -> u32 {
        self.window_log2 + self.fine_bits + TABLE_FRAC + self.line_frac() + 4
    }

    /// One period per window in b's units: |b| >= 2^(F + 2 + T + B - w) moves the table.
    pub fn one_period(&self) -> i64 {
        1 << (self.fine_bits + 2 + TABLE_FRAC + LINE_GUARD)
    }

    /// D = (N^2 - 1) / 3, b's divisor (b = round(32 U / D)).
    pub fn line_divisor(&self) -> u64 {
        ((1u64 << (2 * self.window_log2)) - 1) / 3
    }

    /// Quotient bits of b's division, floor(2 |U| 2^5 / D) < 2^(ps_width + 7 - 2w): never
    /// overflows.
    pub fn line_div_bits(&self) -> u32 {
        self.ps_width() + 7 - 2 * self.window_log2
    }

    /// Quotient bits of r_i's and r's divisions: floor(2 |x| / d) < 2^(F - 1 + T) unless
    /// the result saturates.
    pub fn res_div_bits(&self) -> u32 {
        self.fine_bits - 1 + TABLE_FRAC
    }

    /// H = 2^(62 - B): Z1 >= H or Z1 < -H saturates r_i (module doc), else |x| < 2^63.
    pub fn big_limit(&self) -> i64 {
        1 << (62 - self.line_frac())
    }

    /// Clocks of Clear: P + P table writes, each a clock after its start entry's read.
    pub fn clear_clocks(&self) -> u32 {
        2 * self.points() as u32 + 1
    }

    /// Clocks of one sample in Collect, from its strobe to the next clock that takes one:
    /// Wait, ReadI, ReadJ, LatJ, Diff, s of Mult, Corr, Bin, ReadBin, LatBin, Acc, Sum.
    pub fn collect_clocks(&self) -> u32 {
        self.seg_bits() + 11
    }

    /// The shortest sample spacing, clocks, at which every sample of a window is collected:
    /// a sample's clocks and a load's two writes (a strobe during LoadA or LoadB waits for
    /// them). The core refuses a config whose sample period is shorter.
    pub fn min_sample_clocks(&self) -> u32 {
        self.collect_clocks() + 2
    }

    /// Clocks of Line: Sp and PS settle, (N + 1) Sp and U (two-clock sums, five clocks),
    /// the load, b's quotient bits, the rounding (two), the sign, a (three).
    pub fn line_clocks(&self) -> u32 {
        self.line_div_bits() + 12
    }

    /// Clocks of Residual per bin: the read, the latch, the products (2w clocks: sk_i's
    /// 2w - 1 bits and one for the last sum to settle), Z1 and x (two-clock sums, six
    /// clocks), |x|, the load, r_i's quotient bits, the rounding (two), the write, the sum.
    pub fn residual_clocks(&self) -> u32 {
        2 * self.window_log2 + self.res_div_bits() + 14
    }

    /// Clocks of Mean: |sum r|, the load, the quotient bits, the rounding (two), the sign.
    pub fn mean_clocks(&self) -> u32 {
        self.res_div_bits() + 5
    }

    /// Clocks of Update per bin: the read, the latch, r_i - r, its magnitude, the step, the
    /// sum, the write.
    pub fn update_clocks(&self) -> u32 {
        7
    }

    /// Clocks from the window's last sample's Sum to the first clock of the next Collect.
    pub fn solve_clocks(&self) -> u32 {
        self.line_clocks()
            + self.residual_clocks() * self.points() as u32
            + self.mean_clocks()
            + self.update_clocks() * self.points() as u32
            + 1
    }
}

/// The sequencer's states: the RTL's own state enum ([`super::learner::LearnState`]), so
/// that the model and the RTL name the same states.
pub use super::learner::LearnState as State;

/// One clock's inputs (the RTL's input ports).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LearnIn {
    /// Synchronous reset: the start table back (Clear), empty sums, no load pending.
    pub rst: bool,
    /// A decoded sample this clock.
    pub strobe: bool,
    /// Its raw fine angle within the period (before the table), LSB, 0..2^(F+2).
    pub angle: u32,
    /// Update the table (0: the learner collects and solves but writes each entry back
    /// unchanged).
    pub update: bool,
    /// A request to set entry `ld_addr` to `ld_data` (dropped while one is pending).
    pub ld: bool,
    /// The entry (low p bits).
    pub ld_addr: u32,
    /// Its value, q units, two's complement in [`LearnParams::entry_width`] bits
    /// (saturated to +-2^(F-4) LSB).
    pub ld_data: u32,
}

impl LearnIn {
    /// The row of input port values (rst, strobe, angle, update, ld, ld_addr, ld_data).
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.rst as u64,
            self.strobe as u64,
            u64::from(self.angle),
            self.update as u64,
            self.ld as u64,
            u64::from(self.ld_addr),
            u64::from(self.ld_data),
        ]
    }
}

/// One clock's outputs, after the edge (the RTL's output ports).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct LearnOut {
    /// A table write was made at the edge.
    pub tw: bool,
    /// Its address, bank * P + i.
    pub tw_addr: u32,
    /// Its entry, q units, two's complement in [`LearnParams::entry_width`] bits.
    pub tw_data: u32,
    /// The bank the correction reads.
    pub bank: bool,
    /// A load is pending.
    pub ld_busy: bool,
    /// The state was Clear in the clock before the edge: with `tw`, it marks the Clear's
    /// writes (the correction reads zeros meanwhile).
    pub clearing: bool,
}

impl LearnOut {
    /// The row of output port values (tw, tw_addr, tw_data, bank, ld_busy, clearing).
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.tw as u64,
            u64::from(self.tw_addr),
            u64::from(self.tw_data),
            self.bank as u64,
            self.ld_busy as u64,
            self.clearing as u64,
        ]
    }
}

/// The integer learner: registers and RAMs of the RTL ([`super::learner::HarmonicLearner`]).
#[derive(Clone, Debug)]
pub struct Sequencer {
    /// Formats and settings.
    pub params: LearnParams,
    /// The state.
    pub state: State,
    /// The state was Clear before the last edge ([`LearnOut::clearing`]).
    was_clear: bool,
    /// The clock of a multi-clock state (Clear, Mult, the divisions).
    cnt: u32,
    /// The bin of Residual and Update.
    idx: usize,
    /// The start table, q units.
    start: Vec<i64>,
    /// The two banks of the table, q units.
    banks: [Vec<i64>; 2],
    /// The bank the block reads.
    active: usize,
    /// The load: pending, its entry and value.
    pend: bool,
    ld_i: usize,
    ld_v: i64,
    /// A sample latched during a load's writes.
    got: bool,
    /// The sample in process: its angle and raw position.
    m_s: u32,
    ps: i64,
    /// The previous sample's angle, the raw position since the window's first sample.
    prev: u32,
    pos: i64,
    /// The sample's correction c(m), bin and q.
    c: i64,
    bin: usize,
    q: i64,
    /// Per bin: n_i, sk_i, sp_i (r_i after Residual).
    n: Vec<i64>,
    sk: Vec<i64>,
    sp: Vec<i64>,
    /// The window's sample count k, Sp, PS, U.
    k: u64,
    sum_p: i128,
    sum_ps: i128,
    u: i128,
    /// The line (2^-B q units).
    a: i128,
    b: i128,
    /// The window travelled at least one period (|b| N >= 2^(F+2) LSB): else no update.
    moving: bool,
    /// The residual of the bin in Residual.
    r: i64,
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

/// round(x / d), halves away from zero, d > 0: the rational |x| / d rounded half up, with
/// x's sign. The RTL takes it as (floor(2 |x| / d) + 1) >> 1, one quotient bit more.
pub fn div_round(x: i128, d: i128) -> i128 {
    let q = (x.abs() + d / 2) / d;
    if x < 0 {
        -q
    } else {
        q
    }
}

/// b of the window's U = (N + 1) Sp - 2 PS: round(32 U / D) in b's width (the model's
/// i128 arithmetic; the RTL's division is [`line_b_serial`]).
pub fn line_b(p: &LearnParams, u: i128) -> i128 {
    wrap(div_round(u << 5, i128::from(p.line_divisor())), p.b_width())
}

/// b as the RTL computes it: a restoring division of |U| 2^6 by D, [`LearnParams::line_div_bits`]
/// quotient bits, the dividend's low zeros shifted into the remainder, 64-bit words.
pub fn line_b_serial(p: &LearnParams, u: i64) -> i64 {
    let d = p.line_divisor();
    let kb = p.line_div_bits();
    let mag = u.unsigned_abs();
    let q = restoring(mag, kb - 6, kb, d);
    let r = ((q + 1) >> 1) as i64;
    wrap(i128::from(if u < 0 { -r } else { r }), p.b_width()) as i64
}

/// floor(x 2^(k - lead) / d) over `k` quotient bits: the remainder starts at x >> lead,
/// then x's `lead` low bits and k - lead zeros enter it, one a clock (64-bit words).
pub fn restoring(x: u64, lead: u32, k: u32, d: u64) -> u64 {
    let mut rem = x >> lead;
    let mut dvd = if lead == 0 { 0 } else { x << (64 - lead) };
    let mut q = 0u64;
    for _ in 0..k {
        let t = (rem << 1) | (dvd >> 63);
        dvd <<= 1;
        if t >= d {
            rem = t.wrapping_sub(d);
            q = (q << 1) | 1;
        } else {
            rem = t;
            q <<= 1;
        }
    }
    q
}

/// r_i = sat(round((sp_i 2^B - a n_i - b sk_i) / (n_i 2^B))), n_i > 0 (the model's i128
/// arithmetic).
pub fn residual(p: &LearnParams, sp: i64, n: i64, sk: i64, a: i128, b: i128) -> i64 {
    let bf = p.line_frac();
    let ni = i128::from(n);
    let num = (i128::from(sp) << bf) - a * ni - b * i128::from(sk);
    let lim = i128::from(p.residual_max());
    div_round(num, ni << bf).clamp(-lim, lim) as i64
}

/// r_i as the RTL computes it in 64-bit words: a = a_h 2^B + a_l, b = b_h 2^B + b_l (0 <=
/// a_l, b_l < 2^B), Z1 = sp_i - a_h n_i - b_h sk_i, Z2 = a_l n_i + b_l sk_i, x = Z1 2^B - Z2;
/// |Z1| >= H saturates, else x fits 64 bits and r_i = (floor((|x| >> (B - 1)) / n_i) + 1)
/// >> 1 with x's sign, saturated.
pub fn residual_serial(p: &LearnParams, sp: i64, n: i64, sk: i64, a: i64, b: i64) -> i64 {
    let bf = p.line_frac();
    let lo = (1i64 << bf) - 1;
    let (ah, al, bh, bl) = (a >> bf, a & lo, b >> bf, b & lo);
    let z1 = sp
        .wrapping_sub(ah.wrapping_mul(n))
        .wrapping_sub(bh.wrapping_mul(sk));
    let z2 = al.wrapping_mul(n).wrapping_add(bl.wrapping_mul(sk));
    let lim = p.residual_max();
    let h = p.big_limit();
    if z1 >= h || z1 < -h {
        return if z1 < 0 { -lim } else { lim };
    }
    let x = (z1 << bf).wrapping_sub(z2);
    let mag = x.unsigned_abs();
    let kr = p.res_div_bits();
    let lead = kr + bf - 1;
    let ovf = (mag >> lead) >= n as u64;
    let q = restoring(mag, lead, kr, n as u64);
    let over = ovf || q > 2 * lim as u64;
    let r = if over { lim } else { ((q + 1) >> 1) as i64 };
    if x < 0 {
        -r
    } else {
        r
    }
}

impl Sequencer {
    /// At power-up: a zero start table, Clear.
    pub fn new(params: LearnParams) -> Self {
        Self::with_table(params, &vec![0; params.points()]).expect("a zero table")
    }

    /// At power-up with the start table `start` (q units, P entries within +-2^(F-4) LSB),
    /// Clear; the message says what is allowed.
    pub fn with_table(params: LearnParams, start: &[i64]) -> Result<Self, String> {
        let pp = params.points();
        if start.len() != pp {
            return Err(format!("{} entries: allowed exactly {pp}", start.len()));
        }
        let max = params.entry_max();
        if let Some((i, c)) = start.iter().enumerate().find(|(_, c)| c.abs() > max) {
            return Err(format!(
                "entry {i} = {c} q units: allowed -{max}..={max} (2^(F-4) LSB)"
            ));
        }
        Ok(Sequencer {
            params,
            state: State::Clear,
            was_clear: false,
            cnt: 0,
            idx: 0,
            start: start.to_vec(),
            banks: [start.to_vec(), start.to_vec()],
            active: 0,
            pend: false,
            ld_i: 0,
            ld_v: 0,
            got: false,
            m_s: 0,
            ps: 0,
            prev: 0,
            pos: 0,
            c: 0,
            bin: 0,
            q: 0,
            n: vec![0; pp],
            sk: vec![0; pp],
            sp: vec![0; pp],
            k: 0,
            sum_p: 0,
            sum_ps: 0,
            u: 0,
            a: 0,
            b: 0,
            moving: false,
            r: 0,
            sum_r: 0,
            bins: 0,
            mean: 0,
            windows: 0,
            last_change: 0,
            max_change: 0,
            change: 0,
        })
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

    /// A strobe this clock would be collected: Collect with no sample in process.
    pub fn takes_sample(&self) -> bool {
        matches!(self.state, State::Wait | State::LoadA | State::LoadB)
    }

    /// The table's correction at the raw fine angle `m` (LSB), q units.
    pub fn correction(&self, m: u32) -> i64 {
        let s = self.params.seg_bits();
        let t = self.table();
        let i = (m >> s) as usize % t.len();
        let j = (i + 1) % t.len();
        let f = i64::from(m & ((1 << s) - 1));
        ((t[i] << s) + (t[j] - t[i]) * f) >> s
    }

    /// One clock: inputs before the edge, outputs after it.
    pub fn step(&mut self, x: LearnIn) -> LearnOut {
        let mut out = LearnOut::default();
        let was_clear = self.state == State::Clear;
        self.was_clear = was_clear;
        if x.rst {
            let mut fresh = Sequencer::with_table(self.params, &self.start).expect("checked");
            fresh.banks = std::mem::take(&mut self.banks);
            *self = fresh;
            self.was_clear = was_clear;
            return self.out(out);
        }
        let pr = self.params;
        let pp = pr.points();
        let ew = pr.entry_width();
        // The load request, held while one is pending.
        let load = x.ld && !self.pend;
        if load {
            let v = wrap(i128::from(x.ld_data), ew) as i64;
            self.ld_v = v.clamp(-pr.entry_max(), pr.entry_max());
            self.ld_i = x.ld_addr as usize & (pp - 1);
        }
        // Every strobe moves the raw position (delta: the angle's change, F + 2 bits); a
        // strobe Collect takes at k = 0 starts the window's.
        let accept = x.strobe && self.takes_sample();
        if x.strobe {
            let delta = wrap(
                i128::from(x.angle) - i128::from(self.prev),
                pr.fine_bits + 2,
            );
            self.prev = x.angle;
            self.pos = if accept && self.k == 0 {
                0
            } else {
                wrap(i128::from(self.pos) + delta, pr.pos_width()) as i64
            };
            if accept {
                self.m_s = x.angle;
                self.ps = self.pos;
            }
        }
        let write = |out: &mut LearnOut, banks: &mut [Vec<i64>; 2], bank: usize, i, v| {
            banks[bank][i] = v;
            out.tw = true;
            out.tw_addr = (bank * pp + i) as u32;
            out.tw_data = (v as u64 & crate::blocks::mask(ew)) as u32;
        };
        let mut next = self.state;
        match self.state {
            State::Clear => {
                let c = self.cnt as usize;
                if c >= 1 {
                    let a = c - 1;
                    let v = self.start[a % pp];
                    write(&mut out, &mut self.banks, a / pp, a % pp, v);
                }
                let i = c % pp;
                self.n[i] = 0;
                self.sk[i] = 0;
                self.sp[i] = 0;
                self.cnt += 1;
                if c == 2 * pp {
                    self.cnt = 0;
                    next = State::Wait;
                }
            }
            State::Wait => {
                if x.strobe {
                    next = State::ReadI;
                } else if self.pend {
                    next = State::LoadA;
                }
            }
            State::LoadA => {
                // The active bank first, then the other.
                let (i, v) = (self.ld_i, self.ld_v);
                write(&mut out, &mut self.banks, self.active, i, v);
                self.got |= x.strobe;
                next = State::LoadB;
            }
            State::LoadB => {
                let (i, v) = (self.ld_i, self.ld_v);
                write(&mut out, &mut self.banks, self.active ^ 1, i, v);
                self.pend = false;
                next = if self.got || x.strobe {
                    State::ReadI
                } else {
                    State::Wait
                };
                self.got = false;
            }
            State::ReadI => next = State::ReadJ,
            State::ReadJ => next = State::LatJ,
            State::LatJ => next = State::Diff,
            State::Diff => {
                self.cnt = 0;
                next = State::Mult;
            }
            State::Mult => {
                self.cnt += 1;
                if self.cnt == pr.seg_bits() {
                    self.cnt = 0;
                    next = State::Corr;
                }
            }
            State::Corr => {
                self.c = self.correction(self.m_s);
                next = State::Bin;
            }
            State::Bin => {
                let s = pr.seg_bits() + TABLE_FRAC;
                let mc = (i64::from(self.m_s) << TABLE_FRAC) - self.c;
                self.bin = (((mc + (1 << (s - 1))) >> s) & (pp as i64 - 1)) as usize;
                self.q = wrap(
                    (i128::from(self.ps) << TABLE_FRAC) - i128::from(self.c),
                    pr.q_width(),
                ) as i64;
                next = State::ReadBin;
            }
            State::ReadBin => next = State::LatBin,
            State::LatBin => next = State::Acc,
            State::Acc => {
                let (i, q) = (self.bin, i128::from(self.q));
                self.n[i] += 1;
                self.sk[i] += self.k as i64;
                self.sp[i] = wrap(i128::from(self.sp[i]) + q, pr.sum_p_width()) as i64;
                self.sum_p = wrap(self.sum_p + q, pr.sum_p_width());
                next = State::Sum;
            }
            State::Sum => {
                self.sum_ps = wrap(self.sum_ps + self.sum_p, pr.ps_width());
                self.k += 1;
                next = if self.k == pr.window() {
                    State::LineN1
                } else {
                    State::Wait
                };
            }
            State::LineN1 => next = State::LineU,
            State::LineU => {
                let n = i128::from(pr.window() as u32);
                self.u = wrap((n + 1) * self.sum_p - 2 * self.sum_ps, pr.ps_width());
                next = State::LineW1;
            }
            State::LineW1 => next = State::LineW2,
            State::LineW2 => next = State::LineW3,
            State::LineW3 => next = State::LineLoad,
            State::LineLoad => {
                self.cnt = 0;
                next = State::LineDiv;
            }
            State::LineDiv => {
                self.cnt += 1;
                if self.cnt == pr.line_div_bits() {
                    self.cnt = 0;
                    next = State::LineRnd;
                }
            }
            State::LineRnd => next = State::LineRnd2,
            State::LineRnd2 => next = State::LineB,
            State::LineB => {
                self.b = line_b(&pr, self.u);
                next = State::LineA1;
            }
            State::LineA1 => {
                // One period per window: |b| 2^w >= 2^(F+2+T+B), a compare of |b| with a
                // constant.
                self.moving = self.b.abs() >= i128::from(pr.one_period());
                next = State::LineA2;
            }
            State::LineA2 => {
                let w = pr.window_log2;
                self.a = wrap(
                    ((self.sum_p << 5) - (self.b << w) + self.b) >> 1,
                    pr.a_width(),
                );
                next = State::LineA3;
            }
            State::LineA3 => {
                self.idx = 0;
                next = State::ResRead;
            }
            State::ResRead => next = State::ResLatch,
            State::ResLatch => {
                self.cnt = 0;
                next = State::ResMul;
            }
            State::ResMul => {
                self.cnt += 1;
                if self.cnt == 2 * pr.window_log2 {
                    self.cnt = 0;
                    next = State::ResZa;
                }
            }
            State::ResZa => next = State::ResZb,
            State::ResZb => next = State::ResX,
            State::ResX => next = State::ResW1,
            State::ResW1 => next = State::ResW2,
            State::ResW2 => next = State::ResW3,
            State::ResW3 => next = State::ResAbs,
            State::ResAbs => next = State::ResLoad,
            State::ResLoad => next = State::ResDiv,
            State::ResDiv => {
                self.cnt += 1;
                if self.cnt == pr.res_div_bits() {
                    self.cnt = 0;
                    next = State::ResEnd;
                }
            }
            State::ResEnd => next = State::ResEnd2,
            State::ResEnd2 => next = State::ResWrite,
            State::ResWrite => {
                let i = self.idx;
                if self.n[i] > 0 {
                    self.r = residual(&pr, self.sp[i], self.n[i], self.sk[i], self.a, self.b);
                    self.sp[i] = self.r;
                }
                next = State::ResSum;
            }
            State::ResSum => {
                if self.n[self.idx] > 0 {
                    self.sum_r += self.r;
                    self.bins += 1;
                }
                self.idx += 1;
                next = if self.idx < pp {
                    State::ResRead
                } else {
                    self.idx = 0;
                    State::MeanAbs
                };
            }
            State::MeanAbs => next = State::MeanLoad,
            State::MeanLoad => {
                self.cnt = 0;
                next = State::MeanDiv;
            }
            State::MeanDiv => {
                self.cnt += 1;
                if self.cnt == pr.res_div_bits() {
                    self.cnt = 0;
                    next = State::MeanEnd;
                }
            }
            State::MeanEnd => next = State::MeanEnd2,
            State::MeanEnd2 => next = State::MeanSign,
            State::MeanSign => {
                self.mean = if self.bins > 0 {
                    div_round(i128::from(self.sum_r), i128::from(self.bins)) as i64
                } else {
                    0
                };
                self.change = 0;
                next = State::UpdRead;
            }
            State::UpdRead => next = State::UpdLat,
            State::UpdLat => next = State::UpdDiff,
            State::UpdDiff => next = State::UpdAbs,
            State::UpdAbs => next = State::UpdStep,
            State::UpdStep => next = State::UpdAdd,
            State::UpdAdd => next = State::UpdWrite,
            State::UpdWrite => {
                let i = self.idx;
                let old = self.banks[self.active][i];
                let new = if x.update && self.moving && self.n[i] > 0 {
                    let g = pr.gain_shift;
                    // 2^-g (r_i - r) rounded, halves away from zero (no bias to the table's
                    // mean).
                    let d = self.sp[i] - self.mean;
                    let d = d.signum() * ((d.abs() + (1 << (g - 1))) >> g);
                    let d = d.clamp(-pr.step, pr.step);
                    (old + d).clamp(-pr.entry_max(), pr.entry_max())
                } else {
                    old
                };
                self.change = self.change.max((new - old).abs());
                write(&mut out, &mut self.banks, self.active ^ 1, i, new);
                self.n[i] = 0;
                self.sk[i] = 0;
                self.sp[i] = 0;
                self.idx += 1;
                next = if self.idx < pp {
                    State::UpdRead
                } else {
                    self.idx = 0;
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
                self.sum_ps = 0;
                self.sum_r = 0;
                self.bins = 0;
                next = State::Wait;
            }
        }
        self.state = next;
        if load {
            self.pend = true;
        }
        self.out(out)
    }

    /// The outputs after the edge: the write `w` made, the bank, the load pending.
    fn out(&self, w: LearnOut) -> LearnOut {
        LearnOut {
            bank: self.active == 1,
            ld_busy: self.pend,
            clearing: self.was_clear,
            ..w
        }
    }
}
