//! The table learner's RTL (`sinedec::blocks::harmonics::learner`, issue 46): rust-hdl ==
//! its integer model ([`Sequencer`]) clock by clock == Icarus == Verilator == engine on
//! every output, over whole windows at a steady speed, a reversal, zero speed, update off,
//! reset in mid-solve, loads in Collect and while busy; the RTL's 64-bit arithmetic
//! (`line_b_serial`, `residual_serial`) against the model's i128 one; and the synthesis
//! figures (no multiplier).
use crate::common;
use sinedec::blocks::harmonics::learner::HarmonicLearner;
use sinedec::blocks::harmonics::sequencer::{
    div_round, line_b, line_b_serial, residual, residual_serial, restoring, wrap, LearnIn,
    LearnParams, Sequencer, State,
};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::synth::SynthStats;
use sinedec::verify::Simulators;
use std::f64::consts::PI;

/// F of the default config.
const F: u32 = 14;
/// A period, LSB.
const PERIOD: i64 = 1 << (F + 2);

/// The test's small learner: 16 entries, windows of 256 samples, 32 LSB a step.
fn small() -> LearnParams {
    LearnParams::new(F, 16, 256, 32).expect("a small learner")
}

/// The decoded position of a sample: x plus 2 % H3 and 1 % H5 and +-1 LSB of noise.
fn decoded(x: f64, r: &mut SplitMix64) -> i64 {
    let lsb = (1u64 << F) as f64 / (PI / 2.0);
    let e = |t: f64| {
        let re = 1.0 - 0.02 * (4.0 * t).cos() + 0.01 * (4.0 * t).cos();
        let im = 0.02 * (4.0 * t).sin() + 0.01 * (4.0 * t).sin();
        im.atan2(re)
    };
    (x + e(x / lsb) * lsb + (r.unit() * 2.0 - 1.0)).round() as i64
}

/// Builds the stimulus clock by clock beside the model, so that events can be placed at
/// the model's states (reset in mid-solve, loads in Collect).
struct Plan {
    seq: Sequencer,
    rows: Vec<Vec<u64>>,
    model: Vec<Vec<u64>>,
    rng: SplitMix64,
    /// The true position, LSB, and its speed, LSB per sample.
    x: f64,
    v: f64,
    update: bool,
    /// Table writes, strobes lost, windows applied, the largest change at an Apply.
    writes: usize,
    lost: usize,
    applied: u64,
    moved: i64,
}

impl Plan {
    fn new(p: LearnParams, start: &[i64], seed: u64) -> Self {
        Plan {
            seq: Sequencer::with_table(p, start).expect("start table"),
            rows: Vec::new(),
            model: Vec::new(),
            rng: SplitMix64(seed),
            x: 1234.0,
            v: 0.0,
            update: true,
            writes: 0,
            lost: 0,
            applied: 0,
            moved: 0,
        }
    }

    fn clock(&mut self, i: LearnIn) {
        let i = LearnIn {
            update: self.update,
            ..i
        };
        if i.strobe && !self.seq.takes_sample() {
            self.lost += 1;
        }
        let before = self.seq.windows;
        let o = self.seq.step(i);
        self.writes += o.tw as usize;
        if self.seq.windows > before {
            self.applied += 1;
            self.moved = self.moved.max(self.seq.last_change);
        }
        self.rows.push(i.row());
        self.model.push(o.row());
    }

    fn idle(&mut self, n: usize) {
        for _ in 0..n {
            self.clock(LearnIn::default());
        }
    }

    /// One sample (the position advances by v, with acceleration `acc` on v), then
    /// `gap - 1` idle clocks.
    fn sample(&mut self, gap: usize, acc: f64) {
        self.x += self.v;
        self.v += acc;
        let p = decoded(self.x, &mut self.rng);
        self.clock(LearnIn {
            strobe: true,
            angle: p.rem_euclid(PERIOD) as u32,
            ..LearnIn::default()
        });
        self.idle(gap - 1);
    }

    /// Samples at spacings drawn from `gaps` until the model has applied `windows` more.
    fn windows(&mut self, windows: u64, gaps: &[usize], acc: f64) {
        let end = self.seq.windows + windows;
        while self.seq.windows < end {
            let g = gaps[(self.rng.next_u64() % gaps.len() as u64) as usize];
            self.sample(g, acc);
        }
    }

    /// Samples until the model is in `state`.
    fn until(&mut self, state: State, gap: usize) {
        while self.seq.state != state {
            self.x += self.v;
            let p = decoded(self.x, &mut self.rng);
            self.clock(LearnIn {
                strobe: true,
                angle: p.rem_euclid(PERIOD) as u32,
                ..LearnIn::default()
            });
            for _ in 1..gap {
                if self.seq.state == state {
                    return;
                }
                self.clock(LearnIn::default());
            }
        }
    }

    fn load(&mut self, addr: u32, data: i64, strobe: bool) {
        let ew = self.seq.params.entry_width();
        self.x += if strobe { self.v } else { 0.0 };
        let p = decoded(self.x, &mut self.rng);
        self.clock(LearnIn {
            ld: true,
            ld_addr: addr,
            ld_data: (data as u64 & ((1 << ew) - 1)) as u32,
            strobe,
            angle: p.rem_euclid(PERIOD) as u32,
            ..LearnIn::default()
        });
    }
}

fn four_ways(p: &LearnParams, start: &[i64], plan: &Plan, tag: &str) {
    common::check_against_model(
        HarmonicLearner::new(p, start),
        tag,
        &plan.rows,
        &plan.model,
        Simulators::ALL,
    );
}

/// The stimulus of the small learner's four-way test: a random start table; a reset;
/// three windows at a steady 700 LSB per sample (2.7 periods a window) at spacings from
/// the shortest allowed up; loads in Collect (alone, with a strobe the same clock, a
/// second while busy, during Clear); a reversal within a window; zero speed; update off;
/// a reset in mid-solve (Residual) and one in Update; strobes too close together.
fn small_plan(start: &[i64]) -> Plan {
    let p = small();
    let min = p.min_sample_clocks() as usize;
    let gaps = [min, min + 1, min + 7, 31, 40];
    let mut pl = Plan::new(p, start, 17);
    // Power-up is Clear; a reset a few clocks in restarts it.
    pl.idle(5);
    pl.clock(LearnIn {
        rst: true,
        ..LearnIn::default()
    });
    // A load during Clear waits for Collect.
    pl.load(3, 1000, false);
    pl.idle(p.clear_clocks() as usize);
    pl.v = 700.0;
    pl.windows(1, &gaps, 0.0);
    // Loads in Collect: alone, then with a strobe on the same clock, then one while busy
    // (dropped), then one whose value saturates.
    pl.sample(min, 0.0);
    pl.load(5, -777, false);
    pl.idle(1);
    pl.load(6, 4321, false);
    pl.sample(min, 0.0);
    pl.load(7, 12, true);
    pl.load(8, 99, false);
    pl.idle(min);
    pl.load(9, -(1 << 22), false);
    pl.idle(min);
    pl.windows(2, &gaps, 0.0);
    // A reversal within a window: 700 to -700 LSB per sample over 300 samples.
    pl.windows(2, &gaps, -1400.0 / 300.0);
    pl.v = -700.0;
    pl.windows(1, &gaps, 0.0);
    // Zero speed, then update off.
    pl.v = 0.0;
    pl.windows(1, &gaps, 0.0);
    pl.v = 900.0;
    pl.update = false;
    pl.windows(1, &gaps, 0.0);
    pl.update = true;
    // Reset in mid-solve (Residual), then in Update; strobes too close (lost).
    pl.until(State::ResMul, 30);
    pl.clock(LearnIn {
        rst: true,
        ..LearnIn::default()
    });
    pl.idle(p.clear_clocks() as usize + 3);
    pl.windows(1, &gaps, 0.0);
    pl.until(State::UpdAbs, 30);
    pl.clock(LearnIn {
        rst: true,
        ..LearnIn::default()
    });
    pl.idle(p.clear_clocks() as usize + 3);
    for _ in 0..20 {
        pl.sample(3, 0.0);
    }
    pl.windows(1, &gaps, 0.0);
    pl
}

#[test]
fn the_learner_equals_its_model_four_ways() {
    let p = small();
    let mut r = SplitMix64(99);
    let start: Vec<i64> = (0..p.points())
        .map(|_| r.range(-p.entry_max(), p.entry_max()))
        .collect();
    let pl = small_plan(&start);
    // The stimulus reaches what it is meant to: windows applied, writes of every kind,
    // lost strobes, the table moved, and some update clipped at the step (Update's clip
    // flags, cpos / cneg).
    assert!(pl.applied >= 10, "{}", pl.applied);
    assert!(pl.writes > 12 * p.points(), "{} writes", pl.writes);
    assert!(pl.lost > 0);
    assert_eq!(pl.moved, p.step);
    eprintln!(
        "harmonics_learner: {} clocks, {} table writes, {} strobes lost, largest change {} (step {})",
        pl.rows.len(),
        pl.writes,
        pl.lost,
        pl.moved,
        p.step
    );
    four_ways(&p, &start, &pl, "harmonics_learner");
}

/// The design's learner (128 entries, windows of 4096 samples) over a window at the
/// default config's 102 clocks a sample and into the next.
#[test]
fn the_design_learner_equals_its_model_four_ways() {
    let p = LearnParams::new(F, 128, 4096, 32).expect("the design's learner");
    let start = vec![0; p.points()];
    let mut pl = Plan::new(p, &start, 5);
    pl.idle(p.clear_clocks() as usize + 2);
    pl.v = 3000.0;
    pl.windows(1, &[102], 0.0);
    for _ in 0..200 {
        pl.sample(102, 0.0);
    }
    assert!(pl.moved > 0);
    four_ways(&p, &start, &pl, "harmonics_learner_design");
}

/// The RTL's b (a restoring division of |U| 2^6 by D = (N^2 - 1) / 3 in 64-bit words)
/// equals the model's round(32 U / D), and that equals the old closed form round((N Skp -
/// S1 Sp) 2^B / det) with U = (N + 1) Sp - 2 PS = 2 Skp - (N - 1) Sp, on random windows of
/// q values and at U's extremes.
#[test]
fn the_line_in_64_bit_words_equals_the_i128_line() {
    let mut r = SplitMix64(3);
    for w in [8u32, 10, 12] {
        let p = LearnParams::new(F, 64, 1 << w, 32).expect("params");
        let n = 1i128 << w;
        for trial in 0..20 {
            // q of a line with noise, or random within q's width.
            let qmax = 1i64 << (p.q_width() - 2);
            let (q0, dq) = (r.range(-qmax / 2, qmax / 2), r.range(-(1 << 24), 1 << 24));
            let qs: Vec<i128> = (0..n)
                .map(|k| {
                    i128::from(if trial % 2 == 0 {
                        q0 + dq * k as i64 / 7 + r.range(-300, 300)
                    } else {
                        r.range(-qmax, qmax)
                    })
                })
                .collect();
            let (mut sp, mut ps, mut skp) = (0i128, 0i128, 0i128);
            for (k, &q) in qs.iter().enumerate() {
                sp += q;
                ps += sp;
                skp += k as i128 * q;
            }
            let u = (n + 1) * sp - 2 * ps;
            assert_eq!(u, 2 * skp - (n - 1) * sp);
            let s1 = n * (n - 1) / 2;
            let det = n * n * (n * n - 1) / 12;
            let old = wrap(
                div_round((n * skp - s1 * sp) << p.line_frac(), det),
                p.b_width(),
            );
            assert_eq!(line_b(&p, u), old, "w = {w}, trial {trial}");
            assert_eq!(i128::from(line_b_serial(&p, u as i64)), old);
        }
        let top = (1i64 << (p.ps_width() - 1)) - 1;
        for u in [top, -top - 1, 0, 1, -1, 12345, -98765] {
            assert_eq!(
                i128::from(line_b_serial(&p, u)),
                line_b(&p, i128::from(u)),
                "U = {u}"
            );
        }
    }
}

/// The RTL's r_i (Z1, Z2 and a division of 64-bit words, module doc of the sequencer)
/// equals the model's i128 r_i for sums near a line (the conditions) and for any values of
/// the registers' widths (saturated), with n_i and sk_i as a bin can hold them.
#[test]
fn the_residual_in_64_bit_words_equals_the_i128_residual() {
    let mut r = SplitMix64(11);
    let mut saturated = 0;
    for w in [8u32, 12, 13] {
        let p = LearnParams::new(F, 128, 1 << w, 32).expect("params");
        let big = |r: &mut SplitMix64, width: u32| {
            let v = r.next_u64() as i64;
            wrap(i128::from(v), width) as i64
        };
        for trial in 0..20_000 {
            let nmax = 1i64 << w;
            let n = 1 + r.range(0, nmax - 1);
            let sk = r.range(0, (n * (2 * nmax - n - 1) / 2).max(1));
            let (a, b, sp) = if trial % 2 == 0 {
                // Near the line: sp = (a n + b sk) 2^-B + n r with r within the residuals.
                let b = big(&mut r, p.b_width() - 2);
                let a = big(&mut r, p.a_width() - 3);
                let res = r.range(-p.residual_max() - 50, p.residual_max() + 50);
                let exact = (i128::from(a) * i128::from(n) + i128::from(b) * i128::from(sk))
                    >> p.line_frac();
                let sp = wrap(
                    exact + i128::from(n) * i128::from(res) + i128::from(r.range(-3, 3)),
                    p.sum_p_width(),
                ) as i64;
                (a, b, sp)
            } else {
                (
                    big(&mut r, p.a_width()),
                    big(&mut r, p.b_width()),
                    big(&mut r, p.sum_p_width()),
                )
            };
            let want = residual(&p, sp, n, sk, i128::from(a), i128::from(b));
            saturated += (want.abs() == p.residual_max()) as usize;
            assert_eq!(
                residual_serial(&p, sp, n, sk, a, b),
                want,
                "w = {w}: sp {sp}, n {n}, sk {sk}, a {a}, b {b}"
            );
        }
    }
    assert!(saturated > 1000, "{saturated}");
}

/// At the edges of the residual's 64-bit path, Z1 = -H - 1, -H, -H + 1, H - 1 and H: Z1 =
/// -H takes the division (x still fits 64 bits), whose quotient overflows, and saturates
/// as the i128 formula does; Z1 = H and -H - 1 saturate without it.
#[test]
fn the_residual_at_the_edges_of_its_64_bit_path_equals_the_i128_residual() {
    let mut r = SplitMix64(12);
    for w in [12u32, 13] {
        let p = LearnParams::new(F, 128, 1 << w, 32).expect("params");
        let (h, bf) = (p.big_limit(), p.line_frac());
        let mut hits = [0usize; 5];
        for _ in 0..4000 {
            let nmax = 1i64 << w;
            let n = 1 + r.range(0, nmax - 1);
            let sk = r.range(0, (n * (2 * nmax - n - 1) / 2).max(1));
            let b = wrap(i128::from(r.next_u64() as i64), p.b_width() - 2) as i64;
            let bh = b >> bf;
            for (j, z) in [-h - 1, -h, -h + 1, h - 1, h].into_iter().enumerate() {
                // a_h n cancels Z1 + b_h sk to within n, so that sp is small.
                let ah = -(z + bh * sk) / n + r.range(-2, 2);
                let a = (ah << bf) | r.range(0, (1 << bf) - 1);
                let sp = z + ah * n + bh * sk;
                let fits = |v: i64, width: u32| wrap(i128::from(v), width) as i64 == v;
                if !(fits(a, p.a_width()) && fits(sp, p.sum_p_width())) {
                    continue;
                }
                hits[j] += 1;
                assert_eq!(
                    residual_serial(&p, sp, n, sk, a, b),
                    residual(&p, sp, n, sk, i128::from(a), i128::from(b)),
                    "w = {w}, Z1 = {z}: sp {sp}, n {n}, sk {sk}, a {a}, b {b}"
                );
            }
        }
        assert!(hits.iter().all(|&k| k > 100), "w = {w}: {hits:?}");
    }
}

/// The restoring division with the dividend's low zeros shifted in: floor(x 2^(k - lead)
/// / d) whenever the quotient fits k bits.
#[test]
fn the_restoring_division_is_floor() {
    let mut r = SplitMix64(5);
    for _ in 0..100_000 {
        let d = 1 + (r.next_u64() >> (1 + r.next_u64() % 62));
        let k = 1 + (r.next_u64() % 60) as u32;
        let lead = (r.next_u64() % u64::from(k + 1)) as u32;
        let x = r.next_u64() >> (r.next_u64() % 64);
        let want = (u128::from(x) << (k - lead)) / u128::from(d);
        if want < 1u128 << k {
            assert_eq!(
                u128::from(restoring(x, lead, k, d)),
                want,
                "{x} {lead} {k} {d}"
            );
        }
    }
}

/// The learner of `points` entries (F = 14, windows of 4096 samples, a zero start table)
/// alone in Yosys for xc3sa and Cyclone; with its xc3sa RAM16X1D cells.
fn synth_learner(points: u32, name: &str) -> (SynthStats, SynthStats, u64) {
    let p = LearnParams::new(F, points, 4096, 32).expect("a learner");
    let (x, c) =
        crate::correction_util::synth(HarmonicLearner::new(&p, &vec![0; p.points()]), name);
    let lutram = x.cells.get("RAM16X1D").copied().unwrap_or(0);
    (x, c, lutram)
}

/// The RAMs' 16 x 1 cells on xc3sa at 128 entries: the table (two banks, 256 words x 20
/// bits) 320, n_i (128 x 13) 104, sk_i (128 x 23) 184 and sp_i (128 x 49, as 32 + 17) 392.
const LUTRAM_128: u64 = 320 + 104 + 184 + 392;

/// The learner alone in Yosys: no hard multiplier (the products are shift-add), its RAMs;
/// the figures are printed for docs/correction.md.
#[test]
fn the_learner_synthesizes_without_a_multiplier() {
    let (x, c, lutram) = synth_learner(128, "harmonics_learner_synth");
    let path = x.path.clone().expect("a register-to-register path");
    // Yosys 0.23 maps Cyclone IV's M9K as `altsyncram` (counted in `brams`).
    let m9k = c.brams;
    eprintln!(
        "harmonics_learner_synth: xc3sa {} LUT ({lutram} RAM16X1D), {} FF, {} MULT18X18, {} BRAM; cycloneive {} LE, {} FF, {} multipliers, {m9k} M9K; worst path {} -> {}: {} carry chains, {} LUT levels",
        x.luts, x.ffs, x.multipliers, x.brams, c.luts, c.ffs, c.multipliers, path.from, path.to, path.carry_chains, path.lut_levels
    );
    assert_eq!(x.multipliers + c.multipliers, 0);
    // The table (both banks in one RAM) and the bins' sums (n_i, sk_i, and sp_i as two RAMs
    // of 32 bits), each read in two clocks from four arrays (`PipedLutRam`), are LUT RAM on
    // xc3sa, and M9K on Cyclone, which ignores the attribute: one per array (at most 36
    // bits wide), 4 x 5.
    assert_eq!(x.brams, 0);
    assert_eq!(lutram, LUTRAM_128);
    assert_eq!(m9k, 20);
    assert!(path.carry_chains <= 1, "{path:?}");
}

/// A 64-entry learner keeps half of each RAM's four arrays: its table's two banks are 128
/// words and its bins 64 (the addresses' top bit is zero), so Yosys drops the arrays that
/// are never written or read: half of [`LUTRAM_128`] on xc3sa, and on Cyclone, where each
/// used array is one M9K, 5 RAMs x 2.
#[test]
fn a_64_entry_learner_keeps_half_of_its_ram() {
    let (x, c, lutram) = synth_learner(64, "harmonics_learner64_synth");
    eprintln!(
        "harmonics_learner64_synth: xc3sa {} LUT ({lutram} RAM16X1D), {} FF; cycloneive {} LE, {} FF, {} M9K",
        x.luts, x.ffs, c.luts, c.ffs, c.brams
    );
    assert_eq!(lutram, LUTRAM_128 / 2);
    assert_eq!(c.brams, 10);
}
