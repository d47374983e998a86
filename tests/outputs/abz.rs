//! ABZ emulator: rust-hdl == model cycle for cycle, rust-hdl == Icarus == Verilator, and
//! behaviour against an independent quadrature counter written from the A/B/Z definition
//! (A leads B going forward: 00 -> 10 -> 11 -> 01; Z high in the quarter period of count 0):
//! its count equals floor(position x 4 lines / positions per turn) at every sample through
//! reversals and up to the maximum speed, Z comes at every zero crossing, edges are never
//! closer than the configured spacing, and a catch-up after jumps loses no count.
use crate::common;
use sinedec::blocks::abz::hdl::AbzEmulator;
use sinedec::blocks::abz::model::{AbzIn, AbzModel};
use sinedec::blocks::abz::AbzParams;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::synth::{synthesize, Family};
use sinedec::verify::{block_traces, Simulators};

const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

/// Runs the emulator on `ins` in the chosen simulators; asserts rust-hdl == model row by
/// row and the Verilog simulators == rust-hdl; returns the rust-hdl trace (a, b, z, warning).
fn run(p: &AbzParams, ins: &[AbzIn], tag: &str, sims: Simulators) -> Vec<Vec<u64>> {
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = AbzModel::new(p);
    let model: Vec<Vec<u64>> = ins.iter().map(|i| m.step(*i).row()).collect();
    let dir = common::workdir(tag);
    let t =
        block_traces(AbzEmulator::new(p), tag, "clk", &rows, sims, &dir).expect("simulators ran");
    for (k, (r, m)) in t.rust_hdl.iter().zip(&model).enumerate() {
        assert_eq!(
            r, m,
            "{tag} row {k}: rust-hdl vs model (inputs {:?})",
            rows[k]
        );
    }
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    t.rust_hdl
}

/// Exact count of position `pos` (0..P), written from the definition with 128-bit integers:
/// floor(pos * 4 lines / P).
fn exact_count(p: &AbzParams, pos: u64) -> i64 {
    let e = 4 * p.lines() as u128;
    let pp = (p.quadrants_per_turn() as u128) << p.fine_bits();
    ((pos as u128 * e) / pp) as i64
}

/// An independent quadrature counter: decodes A/B transitions (x4), counts, records the
/// smallest spacing between two edges and any double transition.
struct QuadCounter {
    state: u8,
    count: i64,
    last_edge: Option<usize>,
    min_gap: usize,
    illegal: usize,
    edges: usize,
}

impl QuadCounter {
    /// Gray index of (A, B): 00 -> 0, 10 -> 1, 11 -> 2, 01 -> 3.
    fn index(a: bool, b: bool) -> u8 {
        match (a, b) {
            (false, false) => 0,
            (true, false) => 1,
            (true, true) => 2,
            (false, true) => 3,
        }
    }
    fn new(a: bool, b: bool, count: i64) -> Self {
        Self {
            state: Self::index(a, b),
            count,
            last_edge: None,
            min_gap: usize::MAX,
            illegal: 0,
            edges: 0,
        }
    }
    /// The levels at clock `k`.
    fn observe(&mut self, k: usize, a: bool, b: bool) {
        let s = Self::index(a, b);
        let step = (s + 4 - self.state) % 4;
        if step == 0 {
            return;
        }
        match step {
            1 => self.count += 1,
            3 => self.count -= 1,
            _ => self.illegal += 1,
        }
        if let Some(l) = self.last_edge {
            self.min_gap = self.min_gap.min(k - l);
        }
        self.last_edge = Some(k);
        self.edges += 1;
        self.state = s;
    }
}

/// Position samples: `valid` every `period` clocks, position from `pos_at(sample index)`
/// (any integer, taken modulo P), after a reset of 3 clocks.
fn samples(p: &AbzParams, n: usize, period: usize, pos_at: impl Fn(usize) -> i64) -> Vec<AbzIn> {
    let pp = p.positions() as i64;
    let f = p.fine_bits();
    let mut ins = vec![
        AbzIn {
            rst: true,
            ..AbzIn::default()
        };
        3
    ];
    for s in 0..n {
        let pos = pos_at(s).rem_euclid(pp) as u64;
        ins.push(AbzIn {
            valid: true,
            qc: pos >> f,
            fine: pos & ((1 << f) - 1),
            ..AbzIn::default()
        });
        for _ in 1..period {
            ins.push(AbzIn::default());
        }
    }
    ins
}

/// The facts the independent counter checks on a trace. Sample s is at row 3 + s * period.
/// Returns (counter, rows with warning, largest |count - exact| at the sample checks).
fn check_against_counter(
    p: &AbzParams,
    ins: &[AbzIn],
    out: &[Vec<u64>],
    period: usize,
    tag: &str,
    exact_at_samples: bool,
) -> (QuadCounter, usize, i64) {
    let lat = p.latency() as usize;
    let e = p.edges() as i64;
    let rows: Vec<usize> = (0..ins.len()).filter(|&k| ins[k].valid).collect();
    let pos = |k: usize| (ins[k].qc << p.fine_bits()) | ins[k].fine;
    // The first sample sets the state without counting: start the counter there.
    let k0 = rows[0] + lat - 1;
    let t0 = exact_count(p, pos(rows[0]));
    let (a, b) = (out[k0][0] == 1, out[k0][1] == 1);
    assert_eq!(
        QuadCounter::index(a, b) as i64,
        t0.rem_euclid(4),
        "{tag}: initial A/B state"
    );
    let mut qc = QuadCounter::new(a, b, t0);
    let mut worst = 0i64;
    let mut next = 1;
    let mut warned = 0;
    for (k, o) in out.iter().enumerate().skip(k0) {
        qc.observe(k, o[0] == 1, o[1] == 1);
        // Z exactly in the count-0 state of each turn.
        assert_eq!(
            o[2] == 1,
            qc.count.rem_euclid(e) == 0,
            "{tag}: Z at row {k} (count {})",
            qc.count
        );
        warned += o[3] as usize;
        // Just before sample `next` can move the output: the count is sample next-1's.
        if next < rows.len() && k == rows[next] + lat - 1 {
            let want = exact_count(p, pos(rows[next - 1]));
            let got = qc.count.rem_euclid(e);
            let mut diff = (got - want).rem_euclid(e);
            if diff > e / 2 {
                diff -= e;
            }
            worst = worst.max(diff.abs());
            if exact_at_samples {
                assert_eq!(diff, 0, "{tag}: count at sample {next} (row {k})");
            }
            next += 1;
        }
    }
    assert_eq!(qc.illegal, 0, "{tag}: double transitions");
    assert!(
        qc.edges < 2 || qc.min_gap >= p.spacing() as usize,
        "{tag}: edges {} clocks apart, minimum {}",
        qc.min_gap,
        p.spacing()
    );
    let _ = period;
    (qc, warned, worst)
}

/// Default-like parameters: PPR 2048, F 14, 16 x PPR lines, 12.5 MHz at 133.33 MHz (S = 11).
fn default_params() -> AbzParams {
    AbzParams::new(4 * 2048, 14, 16 * 2048, 11).unwrap()
}

/// Non-power-of-two ratio: PPR 5, F 6, 37 lines (E/P = 148/1280 = 37/320), S = 3.
fn odd_params() -> AbzParams {
    AbzParams::new(20, 6, 37, 3).unwrap()
}

#[test]
fn rounding_rule_is_exact_and_a_turn_is_e_counts() {
    for p in [
        default_params(),
        odd_params(),
        AbzParams::new(4 * 2048, 14, 1000, 2).unwrap(),
        AbzParams::new(4 * 3, 2, 3, 2).unwrap(),
    ] {
        let pp = p.positions();
        assert_eq!(p.count_of(0), 0);
        assert_eq!(p.count_of(pp - 1), p.edges() - 1);
        for pos in (0..pp).step_by((pp / 5000).max(1) as usize) {
            assert_eq!(p.count_of(pos) as i64, exact_count(&p, pos));
        }
    }
}

#[test]
fn model_equals_rtl_on_random_positions() {
    for (p, tag, seed) in [
        (default_params(), "abz_rand_def", 1u64),
        (odd_params(), "abz_rand_odd", 2),
        (
            AbzParams::new(4 * 2048, 14, 1000, 2).unwrap(),
            "abz_rand_1000",
            3,
        ),
    ] {
        let mut r = SplitMix64(seed);
        let pp = p.positions() as i64;
        let mut pos = 0i64;
        let mut ins = vec![];
        for k in 0..6000 {
            let valid = r.unit() < 0.05;
            if valid {
                // Mostly small moves, sometimes a jump of up to a third of a turn.
                pos += if r.unit() < 0.9 {
                    r.range(-pp / 200, pp / 200)
                } else {
                    r.range(-pp / 3, pp / 3)
                };
            }
            let pv = pos.rem_euclid(pp) as u64;
            ins.push(AbzIn {
                rst: k < 2 || r.unit() < 0.001,
                valid,
                qc: (pv >> p.fine_bits()) | (r.next_u64() << 20 & 0xfff0_0000),
                fine: pv & ((1 << p.fine_bits()) - 1),
            });
        }
        let out = run(&p, &ins, tag, RUST_ONLY);
        assert!(out.iter().any(|o| o[3] == 1), "{tag}: catch-up exercised");
        assert!(
            p.edges() > 1000 || out.iter().any(|o| o[2] == 1),
            "{tag}: index exercised"
        );
    }
}

#[test]
fn four_way_cosimulation() {
    for (p, tag, seed) in [
        (odd_params(), "abz_cosim_odd", 7u64),
        (default_params(), "abz_cosim_def", 8),
    ] {
        let mut r = SplitMix64(seed);
        let pp = p.positions() as i64;
        let mut pos = 0i64;
        let mut ins = vec![];
        for k in 0..5000 {
            let valid = r.unit() < 0.04 || (k / 1000 == 2 && r.unit() < 0.5);
            if valid {
                pos += if r.unit() < 0.9 {
                    r.range(-pp / 100, pp / 100)
                } else {
                    r.range(-pp / 3, pp / 3)
                };
            }
            let pv = pos.rem_euclid(pp) as u64;
            ins.push(AbzIn {
                rst: k < 2 || r.unit() < 0.0005,
                valid,
                qc: pv >> p.fine_bits(),
                fine: pv & ((1 << p.fine_bits()) - 1),
            });
        }
        let out = run(&p, &ins, tag, Simulators::ALL);
        assert!(out.iter().any(|o| o[3] == 1));
        assert!(p.edges() > 1000 || out.iter().any(|o| o[2] == 1));
    }
}

#[test]
fn latency_of_a_first_edge_is_as_documented() {
    let p = default_params();
    let lsb = (p.positions() / p.edges()) as i64;
    // Sample 0 at position 10 counts; sample 1 one count further on.
    let ins = samples(&p, 2, 200, |s| (10 + s as i64) * lsb);
    let out = run(&p, &ins, "abz_lat", RUST_ONLY);
    let s1 = 3 + 200;
    let first = (s1..out.len())
        .find(|&k| out[k][..2] != out[k - 1][..2])
        .expect("an edge");
    assert_eq!(first - s1, p.latency() as usize);
}

/// Counts per sample at speed `frac` x the maximum (f_clk / S edges per second).
fn speed(p: &AbzParams, period: usize, frac: f64) -> f64 {
    frac * period as f64 / p.spacing() as f64 * (p.positions() as f64 / p.edges() as f64)
}

#[test]
fn counter_follows_through_reversals_up_to_the_maximum_speed() {
    let period = 102;
    for (p, tag) in [
        (default_params(), "abz_rev_def"),
        (odd_params(), "abz_rev_odd"),
    ] {
        let n = 1500;
        // Position (in position LSB) swinging with a peak speed of 0.999 x the maximum:
        // x(s) = A sin(w s), peak speed A w per sample; several reversals and zero crossings.
        let vmax = speed(&p, period, 0.999);
        let w = 2.0 * std::f64::consts::PI * 3.0 / n as f64;
        let amp = vmax / w;
        // Centred just below a turn boundary: the swing crosses position 0 both ways.
        let off = p.positions() as f64 - 0.3 * amp;
        let ins = samples(&p, n, period, |s| {
            (off + amp * (w * s as f64).sin()).floor() as i64
        });
        let out = run(&p, &ins, tag, RUST_ONLY);
        let (qc, warned, worst) = check_against_counter(&p, &ins, &out, period, tag, true);
        assert_eq!(worst, 0);
        assert_eq!(warned, 0, "{tag}: no warning below the maximum speed");
        // Coverage: the swing crossed position 0 (Z) several times, both ways.
        let zs = (1..out.len())
            .filter(|&k| out[k][2] == 1 && out[k - 1][2] == 0)
            .count();
        assert!(zs >= 4, "{tag}: {zs} index pulses");
        assert!(qc.edges > 1000, "{tag}: {} edges", qc.edges);
    }
}

#[test]
fn at_the_maximum_speed_the_count_stays_within_one_count() {
    let period = 102;
    let p = default_params();
    for dir in [1.0, -1.0] {
        let v = dir * speed(&p, period, 1.0);
        let ins = samples(&p, 1200, period, |s| (v * s as f64).floor() as i64 + 12345);
        let tag = if dir > 0.0 {
            "abz_max_fwd"
        } else {
            "abz_max_back"
        };
        let out = run(&p, &ins, tag, RUST_ONLY);
        let (qc, _, worst) = check_against_counter(&p, &ins, &out, period, tag, false);
        assert!(worst <= 1, "{tag}: {worst} counts behind at a sample");
        // The emitted rate reaches f_clk / S: edges over the run.
        // (the last sample's counts are still on their way when the run ends)
        let need = (v.abs() * 1198.0 / (p.positions() as f64 / p.edges() as f64)) as usize;
        assert!(qc.edges + 1 >= need, "{tag}: {} edges of {need}", qc.edges);
    }
}

#[test]
fn catch_up_after_jumps_loses_no_count() {
    let period = 102;
    // (params, speed of the fast phase in x the maximum (under half a turn per sample),
    // the jump in positions (caught up within the still phase), tag)
    for (p, x, jump, tag) in [
        (default_params(), 4.0, 1 << 20, "abz_jump_def"),
        (odd_params(), 2.0, 1280 / 3, "abz_jump_odd"),
    ] {
        let pp = p.positions() as i64;
        let e = p.edges() as i64;
        let f = speed(&p, period, x) as i64;
        // Samples 0..200 still; 200..300 forward at x times the maximum speed; sample 300
        // jumps back; still until 1800; 1800..2000 backward at 3x/4 the maximum; still to
        // the end.
        let pos = move |s: usize| -> i64 {
            let s = s as i64;
            777 + if s < 200 {
                0
            } else if s < 300 {
                (s - 200) * f
            } else if s < 1800 {
                100 * f - jump
            } else if s < 2000 {
                100 * f - jump - (s - 1800) * (f * 3 / 4)
            } else {
                100 * f - jump - 200 * (f * 3 / 4)
            }
        };
        let n = 3000;
        let ins = samples(&p, n, period, pos);
        let out = run(&p, &ins, tag, RUST_ONLY);
        // Checks Z, spacing and double transitions on the whole run.
        let (_, warned, _) = check_against_counter(&p, &ins, &out, period, tag, false);
        assert!(warned > 0, "{tag}: the catch-up raised the warning");
        // Net counts of the profile, sample to sample the shortest way (moves < half a turn).
        let net_to = |last: usize| -> i64 {
            let mut net = 0i64;
            let mut prev = exact_count(&p, pos(0).rem_euclid(pp) as u64);
            for s in 1..=last {
                let t = exact_count(&p, pos(s).rem_euclid(pp) as u64);
                let mut d = (t - prev).rem_euclid(e);
                if d > e / 2 {
                    d -= e;
                }
                net += d;
                prev = t;
            }
            net
        };
        let lat = p.latency() as usize;
        let row = |s: usize| 3 + s * period;
        let k0 = row(0) + lat - 1;
        let mut c = QuadCounter::new(out[k0][0] == 1, out[k0][1] == 1, 0);
        let mut moves: Vec<i64> = vec![];
        for (k, o) in out.iter().enumerate().skip(k0) {
            let before = c.count;
            c.observe(k, o[0] == 1, o[1] == 1);
            if c.count != before {
                moves.push(c.count - before);
            }
            for (s, what) in [(1799usize, "after the jump"), (n - 1, "at the end")] {
                if k == row(s) {
                    assert_eq!(
                        c.count,
                        net_to(s - 1),
                        "{tag}: {what}, every count emitted, none invented"
                    );
                    assert_eq!(o[3], 0, "{tag}: warning falls once caught up ({what})");
                }
            }
        }
        // No back-and-forth: the direction changes only at the two reversals of the profile.
        let turns = moves.windows(2).filter(|w| w[0] != w[1]).count();
        assert!(turns <= 2, "{tag}: {turns} direction changes");
        let up: i64 = moves.iter().filter(|&&m| m > 0).count() as i64;
        let down: i64 = moves.iter().filter(|&&m| m < 0).count() as i64;
        assert_eq!(
            up - down,
            net_to(n - 1),
            "{tag}: net count of the whole run"
        );
        assert!(up > 0 && down > 0);
    }
}

#[test]
fn bad_parameters_are_rejected_with_a_message() {
    let msg = |r: sinedec::error::Result<AbzParams>| r.unwrap_err().to_string();
    assert!(msg(AbzParams::new(4 * 2048, 14, 0, 11)).contains("lines"));
    // 4 lines > P: more than one edge per position LSB.
    assert!(msg(AbzParams::new(8, 2, 9, 11)).contains("allowed 1..=8"));
    assert!(AbzParams::new(8, 2, 8, 11).is_ok());
    assert!(msg(AbzParams::new(4 * 2048, 14, 1024, 1)).contains("spacing"));
    assert!(msg(AbzParams::new(6, 14, 1024, 3)).contains("4 * PPR"));
    // P / gcd too large for the divider: PPR 65535, F 16, 65535*16+1 lines.
    assert!(msg(AbzParams::new(4 * 65535, 16, 65535 * 16 + 1, 3)).contains("2^30"));
}

#[test]
fn synthesizes_for_both_families() {
    let p = default_params();
    let mut uut = AbzEmulator::new(&p);
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let name = "abz_synth";
    let v = sinedec::emit::verilog::export(&uut, name, name).expect("export");
    let dir = common::workdir(name);
    let x = synthesize(&v, name, Family::Xc3sa, &dir).expect("xc3sa synthesis");
    let c = synthesize(&v, name, Family::CycloneIve, &dir).expect("cycloneive synthesis");
    eprintln!(
        "{name}: xc3sa {} LUT, {} FF; cycloneive {} LE, {} FF",
        x.luts, x.ffs, c.luts, c.ffs
    );
    // The same registers, except that the fold's d, d2 and dd (32 bits, from the difference
    // of two E_w-bit counts) repeat their sign above bit E_w: the cycloneive flow merges
    // those equal flip-flops (18, 18 and 19 kept at E_w = 17), the xc3sa flow keeps all 32.
    let e_w = p.count_bits();
    assert!(
        c.ffs <= x.ffs && x.ffs - c.ffs <= 3 * (31 - e_w as u64),
        "{} FF cycloneive vs {} FF xc3sa",
        c.ffs,
        x.ffs
    );
    assert!(x.ffs > 100 && x.ffs < 400, "{} FF", x.ffs);
}
