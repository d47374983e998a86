//! Absolute start block (SSI master and merge): rust-hdl == model cycle for cycle, rust-hdl
//! == Icarus == Verilator == engine, and its behaviour against expectations written from the
//! SSI protocol and the encoder's true position (not from the block): the clock waveform
//! (quiescent high, the first falling edge at the CONV assertion, N + 1 pulses of 2H
//! clocks, high afterwards), the word read MSB first in Gray or binary, the sample of the
//! latch's conversion as B, and a target T that is the encoder's true quadrant count (turns
//! included) whenever the channels' alignment error is within the tolerance.
use crate::common;
use sinedec::blocks::absolute::hdl::AbsoluteStart;
use sinedec::blocks::absolute::model::{AbsoluteIn, AbsoluteModel, AbsoluteOut};
use sinedec::blocks::absolute::{AbsoluteParams, SsiTiming, SsiWord};
use sinedec::blocks::mask;
use sinedec::board::IoTiming;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::synth::{synthesize, Family};
use sinedec::verify::{block_traces, Simulators};
use std::collections::VecDeque;

const RUST_ONLY: Simulators = Simulators {
    icarus: false,
    verilator: false,
};

/// 100 MHz, an SSI clock of 12.5 MHz (H = 4), t1 = 20 ns, t_m = 0.3 us (W = 30).
fn timing() -> SsiTiming {
    SsiTiming::new(100e6, 12.5e6, 20.0, 0.3, IoTiming::DEFAULT).expect("timing")
}

/// qb = 13 (2048 lines), F = 14, M = 12 turn bits; `s` single-turn and `mt` multi-turn bits;
/// L = `l` clocks from CONV to the core's sample, P = `period`.
#[allow(clippy::too_many_arguments)]
fn params(
    s: u32,
    mt: u32,
    gray: bool,
    inverted: bool,
    l: u32,
    period: u32,
    conv_active_high: bool,
) -> AbsoluteParams {
    let word = SsiWord {
        single_turn_bits: s,
        multiturn_bits: mt,
        gray,
    };
    AbsoluteParams::new(
        word,
        13,
        14,
        12,
        inverted,
        l,
        period,
        conv_active_high,
        timing(),
    )
    .expect("params")
}

/// An SSI slave written from the protocol (not from the block): quiescent high; a falling
/// clock edge from quiescence stores a word; rising edge n puts bit N - n (MSB first) on
/// the line `delay` clocks later, rising edge N + 1 a 0, later ones repeat the word; the
/// line returns high `tm` clocks after the last clock edge. Optionally stuck at a level.
struct Slave {
    bits: u32,
    gray: bool,
    delay: usize,
    tm: usize,
    stuck: Option<bool>,
    prev: bool,
    sent: Option<(u64, u32)>,
    last_edge: usize,
    /// (row from which, level) changes still to come.
    pending: VecDeque<(usize, bool)>,
    level: bool,
    /// (row of the falling edge, binary word) of every stored word.
    stored: Vec<(usize, u64)>,
}

impl Slave {
    fn new(bits: u32, gray: bool, delay: usize, tm: usize) -> Self {
        Slave {
            bits,
            gray,
            delay,
            tm,
            stuck: None,
            prev: true,
            sent: None,
            last_edge: 0,
            pending: VecDeque::new(),
            level: true,
            stored: Vec::new(),
        }
    }

    /// The level on the data line in row `r`.
    fn data(&mut self, r: usize) -> bool {
        if let Some(v) = self.stuck {
            return v;
        }
        if self.sent.is_some() && r >= self.last_edge + self.tm {
            self.sent = None;
            self.pending.push_back((r, true));
        }
        while self.pending.front().is_some_and(|(from, _)| *from <= r) {
            self.level = self.pending.pop_front().unwrap().1;
        }
        self.level
    }

    /// The clock after the edge that ends row `r`; `word` gives the binary word stored.
    fn clock(&mut self, r: usize, clk: bool, word: impl Fn() -> u64) {
        if clk == self.prev {
            return;
        }
        self.prev = clk;
        self.last_edge = r + 1;
        if !clk {
            if self.sent.is_none() {
                let w = word() & mask(self.bits);
                self.stored.push((r, w));
                let g = if self.gray { w ^ (w >> 1) } else { w };
                self.sent = Some((g, 0));
            }
            return;
        }
        if let Some((g, n)) = self.sent.as_mut() {
            *n += 1;
            let m = (*n - 1) % (self.bits + 1);
            let v = m < self.bits && (*g >> (self.bits - 1 - m)) & 1 == 1;
            self.pending.push_back((r + 1 + self.delay, v));
        }
    }
}

/// A decoder's view of an encoder at `angle(row)` quadrants (true, unwrapped): CONV pulses
/// of 4 rows every `period` rows, each sample leaving the core `l` rows after its CONV with
/// the decoder's count: the true quadrant less `s` (the front end's turn) plus `offset`
/// whole periods, its fine part and turns. The slave stores the true position plus the
/// alignment error `e` (quadrants) at 2^-k quadrant per code. Returns the rows, the model's
/// outputs and the slave.
#[allow(clippy::too_many_arguments)]
fn closed_loop(
    p: &AbsoluteParams,
    rows: usize,
    period: usize,
    l: usize,
    angle: impl Fn(usize) -> f64,
    offset: i64,
    e: f64,
    delay: usize,
) -> (Vec<AbsoluteIn>, Vec<AbsoluteOut>, Slave) {
    let w = p.word();
    let k = p.sub_quadrant_bits();
    let q = p.quadrants_per_turn() as i64;
    let shift = p.quadrant_shift() as i64;
    let mut slave = Slave::new(w.bits(), w.gray, delay, p.timing().wait_clocks as usize / 2);
    let mut m = AbsoluteModel::new(p);
    let (mut ins, mut outs) = (vec![], vec![]);
    let act = p.conv_active_high();
    for r in 0..rows {
        let conv_on = r % period < 4 && r >= period;
        let from = r.checked_sub(l).filter(|c| c % period == 0 && *c >= period);
        let (valid, qc, fine, turns) = match from.map(&angle) {
            Some(a) => {
                let count = a.floor() as i64 - shift + 4 * offset;
                (
                    true,
                    count.rem_euclid(q) as u64,
                    (a.fract().rem_euclid(1.0) * 16384.0) as u64,
                    count.div_euclid(q) as u64 & mask(12),
                )
            }
            None => (false, 0, 0, 0),
        };
        let i = AbsoluteIn {
            rst: r < 2,
            conv: conv_on == act,
            valid,
            qc,
            fine,
            turns,
            data: slave.data(r),
        };
        let o = m.step(i);
        let code = ((angle(r) + e) * (1u64 << k) as f64).floor() as i64;
        slave.clock(r, o.clk, || code.rem_euclid(1 << 40) as u64);
        ins.push(i);
        outs.push(o);
    }
    (ins, outs, slave)
}

/// Runs the block on `ins` in the chosen simulators; asserts rust-hdl == model row by row
/// and the Verilog simulators == rust-hdl; returns the model's outputs.
fn run(p: &AbsoluteParams, ins: &[AbsoluteIn], tag: &str, sims: Simulators) -> Vec<AbsoluteOut> {
    let rows: Vec<Vec<u64>> = ins.iter().map(|i| i.row()).collect();
    let mut m = AbsoluteModel::new(p);
    let model: Vec<AbsoluteOut> = ins.iter().map(|i| m.step(*i)).collect();
    let dir = common::workdir(tag);
    let t =
        block_traces(AbsoluteStart::new(p), tag, "clk", &rows, sims, &dir).expect("simulators ran");
    for (k, (r, m)) in t.rust_hdl.iter().zip(&model).enumerate() {
        assert_eq!(
            r,
            &m.row(),
            "{tag} row {k}: rust-hdl vs model (inputs {:?})",
            rows[k]
        );
    }
    if let Some(m) = t.mismatch() {
        panic!("{tag}: {m}");
    }
    model
}

/// The rows at which the clock changes to `level`.
fn edges(outs: &[AbsoluteOut], level: bool) -> Vec<usize> {
    (1..outs.len())
        .filter(|&r| outs[r].clk == level && outs[r - 1].clk != level)
        .collect()
}

#[test]
fn the_clock_follows_the_ssi_protocol() {
    // 17-bit word, H = 4, W = 30; P = 40, L = 70.
    let p = params(13, 4, true, false, 70, 40, true);
    let (ins, outs, slave) = closed_loop(&p, 1200, 40, 70, |_| 123.4, 0, 0.0, 3);
    let run_outs = run(&p, &ins, "abs_protocol", RUST_ONLY);
    assert_eq!(run_outs, outs);
    let falls = edges(&outs, false);
    let rises = edges(&outs, true);
    // Quiescent high through reset (rows 0, 1) and the wait W = 30 clocks (rows 2..31); the
    // first falling edge comes with the first CONV assertion after it (rows 40, 80, ...), at
    // the edge that ends the assertion's row.
    assert!(outs[..40].iter().all(|o| o.clk), "high until the start");
    assert_eq!(falls[0], 40);
    // N + 1 = 18 pulses, low and high H = 4 clocks each, then high for good.
    assert_eq!(falls.len(), 18, "{falls:?}");
    assert_eq!(rises.len(), 18);
    for n in 0..18 {
        assert_eq!(falls[n], 40 + 8 * n);
        assert_eq!(rises[n], 44 + 8 * n);
    }
    assert!(outs[rises[17]..].iter().all(|o| o.clk));
    // The slave stored once, at the first falling edge.
    assert_eq!(slave.stored.len(), 1);
    assert_eq!(slave.stored[0].0, 40);
    // One request, in a row without a sample, and no fault.
    let req: Vec<usize> = (0..outs.len()).filter(|&r| outs[r].req).collect();
    assert_eq!(req.len(), 1);
    assert!(!ins[req[0]].valid);
    assert!(outs.iter().all(|o| !o.fault));
}

/// The expected T: the encoder's true quadrant count at the latch (turns modulo 2^12).
fn true_count(a: f64, q: i64) -> (u64, u64) {
    let c = a.floor() as i64;
    (c.rem_euclid(q) as u64, c.div_euclid(q) as u64 & mask(12))
}

#[test]
fn the_target_is_the_true_count_at_and_around_boundaries() {
    let q = 8192i64;
    let lsb = 1.0 / 16384.0;
    // (single-turn bits, gray, inverted front end, start quadrants, speed in quadrants per
    // row, decoder's period offset, alignment error in quadrants)
    let mut cases = vec![];
    for (s, tol) in [(13u32, 1.5), (15, 1.875)] {
        for &start in &[
            4.0 * 77.0,
            4.0 * 77.0 - lsb,
            4.0 * 77.0 + lsb,
            4.0 * 77.0 + 1.0,
            4.0 * 77.0 + 1.0 - lsb,
            4.0 * 77.0 + 3.0 + lsb,
            0.0,
            -lsb,
            (q * 5 - 2) as f64 + 0.3,
            (q * -3) as f64 + 2.7,
        ] {
            for (e, speed) in [
                (0.0, 0.0),
                (tol - 0.01, 0.0),
                (-(tol - 0.01), 1e-4),
                (0.6, -1e-4),
            ] {
                cases.push((s, start, e, speed));
            }
        }
    }
    for (n, &(s, start, e, speed)) in cases.iter().enumerate() {
        let gray = n % 2 == 0;
        let inverted = n % 3 == 0;
        let offset = (n as i64 % 5) * 311 - 700;
        let p = params(s, 12, gray, inverted, 70, 40, n % 4 != 1);
        let angle = |r: usize| start + speed * r as f64;
        let (ins, outs, slave) = closed_loop(&p, 900, 40, 70, angle, offset, e, 7);
        assert_eq!(run(&p, &ins, &format!("abs_target_{n}"), RUST_ONLY), outs);
        let r = (0..outs.len())
            .find(|&r| outs[r].req)
            .unwrap_or_else(|| panic!("case {n}: no request"));
        let latch = slave.stored[0].0;
        // B: the sample of the latch's conversion (the assertion at the latch's row).
        let b = latch + 70;
        assert!(ins[b].valid, "case {n}");
        assert_eq!(
            (outs[r].bq, outs[r].bt),
            (ins[b].qc, ins[b].turns),
            "case {n}"
        );
        let want = true_count(angle(latch), q);
        assert_eq!(
            (outs[r].tq, outs[r].tt),
            want,
            "case {n}: {s} bits, start {start}, e {e}, speed {speed}"
        );
        // The neighbours the reference's offset path takes.
        let o = outs[r];
        assert_eq!(o.tqm, (o.tq as i64 - q) as u64 & mask(14));
        assert_eq!(o.tqp, o.tq + q as u64);
        assert_eq!(o.ttm, o.tt.wrapping_sub(1) & mask(12));
        assert_eq!(o.ttp, (o.tt + 1) & mask(12));
    }
}

#[test]
fn an_alignment_error_beyond_the_tolerance_takes_the_wrong_period() {
    // One code per quadrant: the tolerance is 1.5 quadrants. At 0.48 quadrants into a
    // period an error of 1.6 quadrants points the word's half-code centre 2.1 quadrants
    // ahead: the merge then lands a period too far.
    let p = params(13, 12, true, false, 70, 40, true);
    let start = 4.0 * 100.0 + 0.48;
    let (_, outs, _) = closed_loop(&p, 900, 40, 70, |_| start, 3, 1.6, 2);
    let o = outs.iter().find(|o| o.req).expect("request");
    assert_eq!(o.tq, 404, "one period (four quadrants) off");
    let (_, outs, _) = closed_loop(&p, 900, 40, 70, |_| start, 3, 1.4, 2);
    assert_eq!(outs.iter().find(|o| o.req).expect("request").tq, 400);
}

#[test]
fn a_line_that_does_not_answer_is_a_fault_and_read_again() {
    let p = params(13, 4, false, false, 70, 40, true);
    // Held high: the tail reads 1, the frame fails and a new one starts after W.
    let ins: Vec<AbsoluteIn> = (0..800)
        .map(|r| AbsoluteIn {
            rst: r < 2,
            conv: r % 40 < 4,
            data: true,
            valid: r % 40 == 10,
            ..Default::default()
        })
        .collect();
    let outs = run(&p, &ins, "abs_stuck_high", RUST_ONLY);
    let falls = edges(&outs, false);
    assert!(
        falls.len() > 18,
        "read again: {} falling edges",
        falls.len()
    );
    assert!(outs.iter().any(|o| o.fault));
    assert!(outs.iter().all(|o| !o.req));
    // Held low: never quiescent, never started.
    let mut m = AbsoluteModel::new(&p);
    let outs: Vec<AbsoluteOut> = (0..800)
        .map(|r| {
            m.step(AbsoluteIn {
                rst: r < 2,
                conv: r % 40 < 4,
                ..Default::default()
            })
        })
        .collect();
    assert!(outs.iter().all(|o| o.clk && !o.req));
}

#[test]
fn four_way_cosimulation() {
    // Random samples, CONV edges, resets, a slave answering random words with random
    // delays, data glitches and stuck lines.
    for (tag, seed, s, gray, inv, act) in [
        ("abs_cosim_a", 5u64, 13u32, true, false, true),
        ("abs_cosim_b", 6, 15, false, true, false),
    ] {
        let p = params(s, 12, gray, inv, 30, 12, act);
        let mut r = SplitMix64(seed);
        let mut m = AbsoluteModel::new(&p);
        let mut slave = Slave::new(p.word().bits(), gray, 2, 12);
        let mut ins = vec![];
        let mut word = 0u64;
        for k in 0..8000usize {
            if k % 1500 == 700 {
                slave.delay = r.range(0, 7) as usize;
            }
            slave.stuck = match k % 2600 {
                2000..=2300 => Some(true),
                2301..=2400 => Some(false),
                _ => None,
            };
            let mut data = slave.data(k);
            if r.unit() < 0.002 {
                data = !data;
            }
            let i = AbsoluteIn {
                rst: k < 2 || r.unit() < 0.0008 || k % 1100 == 0,
                conv: (k % 12 < 3) == act || r.unit() < 0.01,
                valid: r.unit() < 0.1,
                qc: r.range(0, 8191) as u64,
                fine: r.range(0, 16383) as u64,
                turns: r.range(0, 4095) as u64,
                data,
            };
            let o = m.step(i);
            if r.unit() < 0.01 {
                word = r.next_u64();
            }
            slave.clock(k, o.clk, || word);
            ins.push(i);
        }
        let out = run(&p, &ins, tag, Simulators::ALL);
        assert!(out.iter().any(|o| o.req), "{tag}: a merge");
        assert!(out.iter().any(|o| o.fault), "{tag}: a failed frame");
    }
}

#[test]
fn the_line_timing_is_derived_once() {
    // 133.33 MHz, 1 MHz asked: H = ceil(66.665) = 67, 995 kHz; C = 134 clocks = 1005 ns;
    // the budget 6 + 2 x 1 + 400 + 3 = 411 ns leaves a 594 ns round trip.
    let t = SsiTiming::new(133.33e6, 1e6, 400.0, 20.0, IoTiming::DEFAULT).expect("timing");
    assert_eq!(t.half_clocks, 67);
    assert_eq!(t.capture_clocks(), 134);
    assert_eq!(t.wait_clocks, 2667);
    assert!((t.rate_hz() - 995_000.0).abs() < 1.0);
    assert!((t.max_round_trip_ns() - (134.0 * 1e9 / 133.33e6 - 411.0)).abs() < 1e-9);
    // Too fast for the synchronizer, too slow for its counter, and a t1 no rate leaves.
    let err = |r: sinedec::error::Result<SsiTiming>| r.expect_err("rejected").to_string();
    assert!(err(SsiTiming::new(100e6, 20e6, 0.0, 20.0, IoTiming::DEFAULT)).contains("at least 4"));
    assert!(
        err(SsiTiming::new(100e6, 1e6, 990.0, 20.0, IoTiming::DEFAULT))
            .contains("lower the SSI clock")
    );
    assert!(err(SsiTiming::new(100e6, 1e6, 10.0, 1e9, IoTiming::DEFAULT)).contains("monoflop"));
}

#[test]
fn bad_parameters_are_rejected_with_a_message() {
    let word = |s, mt| SsiWord {
        single_turn_bits: s,
        multiturn_bits: mt,
        gray: true,
    };
    let msg = |w: SsiWord, f: u32| {
        AbsoluteParams::new(w, 13, f, 12, false, 70, 40, true, timing())
            .expect_err("rejected")
            .to_string()
    };
    assert!(msg(word(12, 0), 14).contains("fewer than the 8192 quadrants"));
    assert!(msg(word(17, 0), 4).contains("fine bits"));
    assert!(msg(word(30, 0), 16).contains("at most 29"));
    assert!(msg(word(13, 25), 14).contains("at most 24"));
}

#[test]
fn synthesizes_for_both_families() {
    let p = params(13, 12, true, true, 219, 102, true);
    let mut uut = AbsoluteStart::new(&p);
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let name = "absolute_synth";
    let v = sinedec::emit::verilog::export(&uut, name, name).expect("export");
    let dir = common::workdir(name);
    let x = synthesize(&v, name, Family::Xc3sa, &dir).expect("xc3sa synthesis");
    let c = synthesize(&v, name, Family::CycloneIve, &dir).expect("cycloneive synthesis");
    eprintln!(
        "{name}: xc3sa {} LUT, {} FF; cycloneive {} LE, {} FF",
        x.luts, x.ffs, c.luts, c.ffs
    );
    // Registers: the word (25), B and o (13 + 12 + 3), δ and p (3 + 16), the six target
    // words (13 + 14 + 14 + 3 x 12), the counters (6 + 5), the state, the tag and the
    // synchronizers: about 180.
    assert!(x.ffs > 120 && x.ffs < 260, "{} FF", x.ffs);
}
