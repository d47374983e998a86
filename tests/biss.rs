//! BiSS-C slave: CRC6 against hand-worked frames, the master model reading the rust-hdl
//! slave in a closed loop (positions, flags, timeout, corrupted bits, glitches, reset and
//! protocol violations), the closed-loop MA sequences replayed in rust-hdl, Icarus and
//! Verilator, and the measured maximum MA rate.
use sinedec::blocks::biss::crc::{biss_crc, crc6, crc6_bits, POLY};
use sinedec::blocks::biss::hdl::BissSlave;
use sinedec::blocks::biss::BissParams;
use sinedec::blocks::serial::data_word;
use sinedec::blocks::mask;
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::cosim::CosimBlock;
use sinedec::sim::biss_master::{
    expected_crc, BissFrame, BissMaster, BissMasterConfig, Outcome,
};
use sinedec::sim::serial_line::{FrameRequest, LineMaster, LineTiming};
use sinedec::verify::{block_traces, Simulators};
mod common;

// ---------------------------------------------------------------------------------------
// CRC6
// ---------------------------------------------------------------------------------------

/// Three frames worked by hand: the CRC is the remainder of message(x) * x^6 modulo
/// g(x) = x^6 + x + 1, found with x^6 = x + 1 (mod g), then inverted (6 bits).
#[test]
fn crc_hand_worked_examples() {
    assert_eq!(POLY, 0x43);

    // Example 1: one data bit 1, nE = 1, nW = 1: message 111.
    //   111 000000 (message * x^6)
    //   100 0011     g aligned under the leading 1
    //   --------
    //    11 001100 -> 1100 1100
    //    10 000110   g aligned
    //    ---------
    //     1 001010
    //     1 000011   g aligned
    //     --------
    //       001001   remainder 0x09; sent inverted: 110110 = 0x36.
    assert_eq!(crc6_bits([true, true, true]), 0x09);
    assert_eq!(biss_crc(0b1, 1, true, true), 0x36);
    assert_eq!(expected_crc(0b111, 3), 0x36);

    // Example 2: the thesis's 19-bit position 0x40000 (only the MSB set), nE = 1, nW = 1:
    // message x^20 + x + 1, times x^6 = x^26 + x^7 + x^6. Powers of x mod g (x^6 = x + 1):
    //   x^6 = 000011, x^7 = 000110, x^12 = x^2 + 1 (x^6 squared: x^2 + 1),
    //   x^24 = (x^12)^2 = x^4 + 1, x^26 = x^24 * x^2 = x^6 + x^2 = x^2 + x + 1 = 000111.
    //   000111 ^ 000110 ^ 000011 = 000010: remainder 0x02; sent inverted 111101 = 0x3d.
    let m2 = (0x40000u64 << 2) | 0b11;
    assert_eq!(crc6(m2, 21), 0x02);
    assert_eq!(biss_crc(0x40000, 19, true, true), 0x3d);
    assert_eq!(expected_crc(m2, 21), 0x3d);

    // Example 3: 2 multi-turn bits (turns = 2) ahead of 3 position bits (pos = 5):
    // data 10 101, nE = 0 (error), nW = 1: message 1010101 = x^6 + x^4 + x^2 + 1.
    // Times x^6: x^12 + x^10 + x^8 + x^6 with
    //   x^8 = x^2 * x^6 = x^3 + x^2 = 001100, x^10 = x^4 * x^6 = x^5 + x^4 = 110000,
    //   x^12 = 000101, x^6 = 000011:
    //   000101 ^ 110000 ^ 001100 ^ 000011 = 111010: remainder 0x3a; inverted 000101 = 0x05.
    let d3 = data_word(5, 2, 3, 2, false);
    assert_eq!(d3, 0b10101);
    assert_eq!(crc6(0b1010101, 7), 0x3a);
    assert_eq!(biss_crc(d3, 5, false, true), 0x05);
    assert_eq!(expected_crc(0b1010101, 7), 0x05);
}

/// The slave's shift register and the master's long division agree on random messages.
#[test]
fn crc_register_equals_long_division() {
    let mut r = SplitMix64(43);
    for _ in 0..20_000 {
        let n = 1 + (r.next_u64() % 32) as u32;
        let d = r.next_u64() & mask(n);
        let (e, w) = (r.next_u64() & 1 == 1, r.next_u64() & 1 == 1);
        let msg = (d << 2) | ((e as u64) << 1) | w as u64;
        assert_eq!(
            biss_crc(d, n, e, w),
            expected_crc(msg, n + 2),
            "n={n} d={d:#x}"
        );
    }
    // Any single flipped message or CRC bit changes the check (distance >= 2 for CRC6 on
    // up to 57 message bits): verified here for every bit of 34-bit messages.
    for _ in 0..200 {
        let d = r.next_u64() & mask(32);
        let msg = (d << 2) | (r.next_u64() & 3);
        let c = expected_crc(msg, 34);
        for b in 0..34 {
            assert_ne!(expected_crc(msg ^ (1 << b), 34), c);
        }
    }
}

#[test]
fn params_are_validated() {
    assert!(BissParams::new(19, 0, 50e6).is_ok());
    let e = BissParams::new(0, 0, 50e6).unwrap_err().to_string();
    assert!(e.contains("position_bits"), "{e}");
    let e = BissParams::new(20, 13, 50e6).unwrap_err().to_string();
    assert!(e.contains("exceeds"), "{e}");
    let e = BissParams::new(19, 0, 0.0).unwrap_err().to_string();
    assert!(e.contains("clock_hz"), "{e}");
    let mut p = BissParams::new(19, 0, 50e6).unwrap();
    assert_eq!(p.timeout_clocks, 1000);
    assert!(p
        .set_timeout_us(0.01)
        .unwrap_err()
        .to_string()
        .contains("timeout"));
    assert!(p.set_timeout_us(-1.0).is_err());
    p.ack_periods = 0;
    assert!(p
        .validate()
        .unwrap_err()
        .to_string()
        .contains("ack_periods"));
    p.ack_periods = 65;
    assert!(BissSlave::new(&p).is_err());
    let p = BissParams::new(19, 0, 133.33e6).unwrap();
    assert_eq!(p.timeout_clocks, 2667);
    assert!((p.max_ma_hz() - 33.33e6).abs() < 0.01e6);
}

// ---------------------------------------------------------------------------------------
// Closed loop: master model <-> rust-hdl slave
// ---------------------------------------------------------------------------------------

/// Position stream: random 32-bit words every cycle (bits above the configured widths must
/// be ignored), valid every `every` cycles, error / warning in the listed cycles.
#[derive(Clone, Debug, Default)]
struct Stream {
    every: usize,
    errors: Vec<usize>,
    warnings: Vec<usize>,
}

impl Stream {
    fn pos(&self, k: usize) -> u64 {
        SplitMix64(k as u64 * 2 + 1).next_u64() & mask(32)
    }
    fn turns(&self, k: usize) -> u64 {
        SplitMix64(k as u64 * 2 + 0x5555).next_u64() & mask(32)
    }
    fn valid(&self, k: usize) -> bool {
        k.is_multiple_of(self.every.max(1))
    }
}

/// Per-cycle test controls.
#[derive(Clone, Copy, Debug, Default)]
struct Ctl {
    /// Reset this cycle.
    rst: bool,
    /// Invert MA at the slave's pin this cycle (a one-sample glitch).
    ma_flip: bool,
    /// Invert SLO on the wire to the master this cycle.
    slo_flip: bool,
}

/// One closed-loop run: the stimulus rows (slave port order), the slave's SLO per cycle and
/// the master's frames.
struct Run {
    rows: Vec<Vec<u64>>,
    slo: Vec<u64>,
    frames: Vec<BissFrame>,
    timing: LineTiming,
}

fn closed_loop(
    p: &BissParams,
    master: &mut BissMaster,
    stream: &Stream,
    cycles: usize,
    mut ctl: impl FnMut(usize, &BissMaster) -> Ctl,
    timing: LineTiming,
) -> Run {
    let mut uut = BissSlave::new(p).expect("params");
    rust_hdl::prelude::Block::connect_all(&mut uut);
    prepare(&mut uut).expect("settles");
    let mut rows = Vec::with_capacity(cycles);
    let mut slo = Vec::with_capacity(cycles);
    for k in 0..cycles {
        let c = ctl(k, master);
        let ma = master.ma_for_cycle(k) ^ c.ma_flip;
        let row = vec![
            (k < 3 || c.rst) as u64,
            ma as u64,
            stream.pos(k),
            stream.turns(k),
            stream.valid(k) as u64,
            stream.errors.contains(&k) as u64,
            stream.warnings.contains(&k) as u64,
        ];
        uut.apply(&row);
        tick(&mut uut).expect("settles");
        let s = uut.sample()[0];
        slo.push(s);
        rows.push(row);
        master.push_slo((s != 0) ^ c.slo_flip);
    }
    Run {
        rows,
        slo,
        frames: master.frames().to_vec(),
        timing,
    }
}

impl Run {
    /// Row at which the slave latched the frame that the master started at `t0`: its first
    /// MA-low row (with the glitch filter: the first of two consecutive low rows, so that a
    /// one-row glitch next to the start counts as the slave sees it) plus the latency.
    fn latch_row(&self, t0: f64, p: &BissParams) -> usize {
        let need = if p.glitch_filter { 2 } else { 1 };
        let k0 = ((t0 + self.timing.line_delay_ns) / self.timing.tclk_ns()).floor() as usize;
        let mut k = k0.saturating_sub(3);
        while !(0..need).all(|i| self.rows[k + i][1] == 0) {
            k += 1;
        }
        k + p.latch_latency() as usize
    }
    /// Last valid row at or before `k`.
    fn last_valid(&self, k: usize) -> Option<usize> {
        (0..=k)
            .rev()
            .find(|&j| self.rows[j][4] != 0 && self.rows[j][0] == 0)
    }
    /// What the slave must send for a frame latched at row `l`, the previous take (or
    /// reset) at row `prev`: (position, turns, nE, nW).
    fn expect(&self, p: &BissParams, l: usize, prev: usize) -> (u64, u64, bool, bool) {
        let last_rst = (0..=l).rev().find(|&j| self.rows[j][0] != 0).unwrap_or(0);
        let from = prev.max(last_rst) + 1;
        let err = (from..=l).any(|j| self.rows[j][5] != 0);
        let warn = (from..=l).any(|j| self.rows[j][6] != 0);
        match self.last_valid(l).filter(|&v| v > last_rst) {
            Some(v) => {
                let pos = self.rows[v][2] & mask(p.position_bits);
                let turns = self.rows[v][3] & mask(p.multiturn_bits);
                (pos, turns, !err, !warn)
            }
            None => (0, 0, false, !warn),
        }
    }
}

fn timing(clock_hz: f64, d: f64) -> LineTiming {
    LineTiming {
        clock_hz,
        line_delay_ns: d,
    }
}

fn master_for(p: &BissParams, t: LineTiming, reqs: Vec<FrameRequest>) -> BissMaster {
    let mut c = BissMasterConfig::new(t, p.data_bits(), p.multiturn_bits);
    c.gray = p.gray;
    BissMaster::new(c, reqs, 500.0)
}

/// Cycles for a list of requests: frame time + timeout + margin, each.
fn cycles_for(p: &BissParams, reqs: &[FrameRequest], extra_ns: f64) -> usize {
    let ns: f64 = reqs
        .iter()
        .map(|r| {
            (p.frame_rising_edges() + 1) as f64 * 1e9 / r.ma_hz
                + r.gap_ns
                + p.timeout_us() * 1e3
                + 1000.0
        })
        .sum::<f64>()
        + extra_ns
        + 2000.0;
    (ns * p.clock_hz / 1e9) as usize + p.timeout_clocks as usize + 100
}

/// Every frame of a run is good and carries what the slave latched at its first MA edge.
fn check_frames(run: &Run, p: &BissParams, expect_frames: usize) {
    assert_eq!(run.frames.len(), expect_frames, "frames: {:#?}", run.frames);
    let mut prev = 0;
    for (i, f) in run.frames.iter().enumerate() {
        let d = f
            .good()
            .unwrap_or_else(|| panic!("frame {i} at {} MHz not good: {f:#?}", f.ma_hz / 1e6));
        let l = run.latch_row(f.t_start_ns, p);
        let (pos, turns, n_e, n_w) = run.expect(p, l, prev);
        prev = l;
        assert_eq!(d.position, pos, "frame {i} position (latched at row {l})");
        assert_eq!(d.turns, turns, "frame {i} turns");
        assert_eq!((d.n_e, d.n_w), (n_e, n_w), "frame {i} flags");
        assert_eq!(d.ack_bits, p.ack_periods, "frame {i} ack length");
        assert!(!d.cds && d.stop_low, "frame {i}: CDS 0 and the timeout low");
        let to = f.timeout_ns.expect("timeout measured");
        // Round trip, 3-4 clocks of synchronizer, up to 2 more when a glitch moves the edge.
        let nominal = p.timeout_us() * 1e3;
        assert!(
            to >= nominal
                && to <= nominal + 2.0 * run.timing.line_delay_ns + 7.0 * 1e9 / p.clock_hz,
            "frame {i}: timeout {to} ns, nominal {nominal} ns"
        );
    }
}

/// The 19-bit thesis frame and a 12+13-bit Gray multi-turn frame with a 3-period Ack, at
/// 50 MHz and 133.33 MHz, read back to back at 100 kHz .. 10 MHz over a 5 m cable (25 ns).
#[test]
fn master_reads_every_frame_at_100khz_to_10mhz() {
    for clock in [50e6, 133.33e6] {
        let single = BissParams::new(19, 0, clock).unwrap();
        let mut multi = BissParams::new(13, 12, clock).unwrap();
        multi.gray = true;
        multi.ack_periods = 3;
        for p in [single, multi] {
            let t = timing(clock, 25.0);
            let mut reqs = Vec::new();
            for hz in [100e3, 1e6, 2.5e6, 4e6, 7.3e6, 10e6] {
                reqs.push(FrameRequest::new(hz));
                reqs.push(FrameRequest::new(hz).gap(130.0));
            }
            let stream = Stream {
                every: 3,
                ..Default::default()
            };
            let mut m = master_for(&p, t, reqs.clone());
            let run = closed_loop(
                &p,
                &mut m,
                &stream,
                cycles_for(&p, &reqs, 0.0),
                |_, _| Ctl::default(),
                t,
            );
            check_frames(&run, &p, reqs.len());
        }
    }
}

/// An error or warning flag, even for a single cycle between frames, shows as nE = 0 /
/// nW = 0 in the next frame only.
#[test]
fn flags_show_in_the_next_frame() {
    let p = BissParams::new(19, 0, 50e6).unwrap();
    let t = timing(50e6, 10.0);
    let reqs: Vec<_> = (0..6).map(|_| FrameRequest::new(5e6).gap(2000.0)).collect();
    // Find the frame starts of a clean run, then put flags between them.
    let quiet = Stream {
        every: 1,
        ..Default::default()
    };
    let n = cycles_for(&p, &reqs, 12_000.0);
    let run = closed_loop(
        &p,
        &mut master_for(&p, t, reqs.clone()),
        &quiet,
        n,
        |_, _| Ctl::default(),
        t,
    );
    let starts: Vec<usize> = run
        .frames
        .iter()
        .map(|f| run.latch_row(f.t_start_ns, &p))
        .collect();
    let stream = Stream {
        every: 1,
        // error one cycle after frame 1's latch (during frame 1) -> frame 2;
        // error exactly at frame 3's latch row -> frame 3; warning between 3 and 4 -> 4.
        errors: vec![starts[1] + 1, starts[3]],
        warnings: vec![(starts[3] + starts[4]) / 2],
    };
    let run = closed_loop(
        &p,
        &mut master_for(&p, t, reqs.clone()),
        &stream,
        n,
        |_, _| Ctl::default(),
        t,
    );
    check_frames(&run, &p, 6);
    let flags: Vec<(bool, bool)> = run
        .frames
        .iter()
        .map(|f| {
            let d = f.good().expect("good frame");
            (d.n_e, d.n_w)
        })
        .collect();
    assert_eq!(
        flags,
        vec![
            (true, true),
            (true, true),
            (false, true),
            (false, true),
            (true, false),
            (true, true)
        ]
    );
}

/// Flipping any one bit of data, nE, nW or CRC on the wire fails the master's CRC check.
#[test]
fn every_single_bit_error_is_detected() {
    for (clock, st, mt) in [(50e6, 19, 0), (133.33e6, 13, 12)] {
        let p = BissParams::new(st, mt, clock).unwrap();
        let t = timing(clock, 25.0);
        let reqs = vec![FrameRequest::new(2e6)];
        let stream = Stream {
            every: 2,
            ..Default::default()
        };
        let n = cycles_for(&p, &reqs, 0.0);
        let clean = closed_loop(
            &p,
            &mut master_for(&p, t, reqs.clone()),
            &stream,
            n,
            |_, _| Ctl::default(),
            t,
        );
        let good = clean.frames[0].good().expect("clean frame is good").clone();
        // The slave's bit for rising edge r occupies the SLO cycles from the row at which it
        // acted on r (first MA-high row of r plus the latency) to the next such row.
        let mut acts = Vec::new();
        for k in 1..clean.rows.len() {
            if clean.rows[k][1] == 1 && clean.rows[k - 1][1] == 0 {
                acts.push(k + p.latch_latency() as usize);
            }
        }
        let a = p.ack_periods as usize;
        let nb = p.data_bits() as usize;
        // Rising edge 4+A carries the data MSB; edges 4+A .. 11+A+N carry data, nE, nW, CRC.
        let positions: Vec<usize> = (4 + a..=11 + a + nb).collect();
        assert_eq!(positions.len(), nb + 8);
        for (bit, &r) in positions.iter().enumerate() {
            let (lo, hi) = (acts[r - 1], acts[r]);
            let run = closed_loop(
                &p,
                &mut master_for(&p, t, reqs.clone()),
                &stream,
                n,
                |k, _| Ctl {
                    slo_flip: (lo..hi).contains(&k),
                    ..Ctl::default()
                },
                t,
            );
            match &run.frames[0].outcome {
                Outcome::Data(d) => {
                    assert!(!d.crc_ok(), "bit {bit} flipped but the CRC checks: {d:?}");
                    // Exactly that bit differs from the clean frame.
                    let flipped = (good.data ^ d.data).count_ones()
                        + (good.n_e != d.n_e) as u32
                        + (good.n_w != d.n_w) as u32
                        + (good.crc_received ^ d.crc_received).count_ones();
                    assert_eq!(flipped, 1, "bit {bit}");
                }
                o => panic!("bit {bit}: {o:?}"),
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Protocol corner cases, each also co-simulated.
// ---------------------------------------------------------------------------------------

/// A closed-loop scenario: frames at several rates, back to back, a frame started during the
/// timeout, a master that stops mid-frame, a reset mid-frame, one-sample MA glitches in idle
/// and in a frame; every good frame is checked, then the recorded MA sequence is replayed in
/// rust-hdl, Icarus and Verilator and the SLO traces must be identical.
fn scenario(p: &BissParams, d: f64, tag: &str) -> Run {
    let clock = p.clock_hz;
    let t = timing(clock, d);
    let mut reqs = vec![
        FrameRequest::new(100e3),
        FrameRequest::new(1e6),
        FrameRequest::new(1e6), // back to back
        // started 1 us after the last edge: the slave is in its timeout
        FrameRequest {
            wait_ready: false,
            gap_ns: 1000.0,
            ..FrameRequest::new(3e6)
        },
        FrameRequest::new(3e6),
        // stops after 12 rising edges
        FrameRequest {
            abort_after_rises: Some(12),
            ..FrameRequest::new(5e6)
        },
        FrameRequest::new(5e6),
        FrameRequest::new(10e6), // reset after 15 rising edges of this one
        FrameRequest::new(10e6),
        // glitches in idle and in this frame; MA levels >= 3 clocks long (see the glitch test)
        FrameRequest::new(4e6).gap(3000.0),
        FrameRequest::new(4e6),
        FrameRequest::new(6.6e6),
    ];
    reqs.iter_mut().for_each(|r| r.duty = 0.45);
    let stream = Stream {
        every: 4,
        errors: vec![5000, 90_000],
        warnings: vec![20_000],
    };
    let mut m = master_for(p, t, reqs.clone());
    let mut reset_left = 0;
    let mut reset_done = false;
    let mut glitched = [false; 3];
    let n = cycles_for(p, &reqs, 250_000.0);
    let run = closed_loop(
        p,
        &mut m,
        &stream,
        n,
        |_, m| {
            let f = m.frames().len();
            let rises = m.rises_in_frame();
            let mut c = Ctl::default();
            // Reset for 3 cycles after 15 rising edges of frame 7.
            if f == 7 && rises == Some(15) && !reset_done {
                reset_done = true;
                reset_left = 3;
            }
            if reset_left > 0 {
                c.rst = true;
                reset_left -= 1;
            }
            // One-sample glitches: in idle before frame 9, then after rising edges 5 and 20.
            if f == 9 && rises.is_none() && !glitched[0] {
                glitched[0] = true;
                c.ma_flip = true;
            }
            if f == 9 && rises == Some(5) && !glitched[1] {
                glitched[1] = true;
                c.ma_flip = true;
            }
            if f == 9 && rises == Some(20) && !glitched[2] {
                glitched[2] = true;
                c.ma_flip = true;
            }
            c
        },
        t,
    );
    assert_eq!(run.frames.len(), reqs.len(), "{:#?}", run.frames);
    // Outcomes: frame 3 (started in the timeout) finds no Ack (SLO stays low), frame 5 is
    // aborted, frame 7 is hit by the reset; every other frame is good.
    for (i, f) in run.frames.iter().enumerate() {
        match i {
            3 => assert_eq!(f.outcome, Outcome::NoAck, "frame 3"),
            5 => assert_eq!(f.outcome, Outcome::Aborted, "frame 5"),
            7 => assert!(f.good().is_none(), "frame 7 was reset: {f:?}"),
            9 if !p.glitch_filter => {}
            _ => assert!(f.good().is_some(), "frame {i}: {f:#?}"),
        }
    }
    if p.glitch_filter {
        assert!(run.frames[9].good().is_some());
    } else {
        assert!(
            run.frames[9].good().is_none(),
            "an unfiltered glitch breaks the frame"
        );
    }
    // Positions and flags of the good frames. The take before frame 9 without the filter
    // is the glitch-started frame in idle, so its flag window is not the oracle's.
    let mut prev = 0;
    for (i, f) in run.frames.iter().enumerate() {
        let l = run.latch_row(f.t_start_ns, p);
        if let Some(d) = f.good() {
            let (pos, turns, n_e, n_w) = run.expect(p, l, prev);
            assert_eq!((d.position, d.turns), (pos, turns), "frame {i} position");
            if p.glitch_filter || i != 10 {
                assert_eq!((d.n_e, d.n_w), (n_e, n_w), "frame {i} flags");
            }
        }
        // Frame 3 never started in the slave (it was clocked during the timeout).
        if i != 3 {
            prev = l;
        }
    }
    let dir = common::workdir(tag);
    let bt = block_traces(
        BissSlave::new(p).unwrap(),
        "biss_slave",
        "clk",
        &run.rows,
        Simulators::ALL,
        &dir,
    )
    .expect("simulators ran");
    if let Some(m) = bt.mismatch() {
        panic!("{tag}: {m}");
    }
    let replay: Vec<u64> = bt.rust_hdl.iter().map(|r| r[0]).collect();
    assert!(
        replay == run.slo,
        "{tag}: the replay differs from the closed loop"
    );
    run
}

#[test]
fn cosim_50mhz() {
    let mut p = BissParams::new(19, 0, 50e6).unwrap();
    p.set_timeout_us(15.0).unwrap();
    scenario(&p, 25.0, "biss_50");
}

#[test]
fn cosim_133mhz_multiturn_gray() {
    let mut p = BissParams::new(17, 12, 133.33e6).unwrap();
    p.gray = true;
    p.ack_periods = 2;
    scenario(&p, 40.0, "biss_133");
}

#[test]
fn cosim_50mhz_without_glitch_filter() {
    let mut p = BissParams::new(32, 0, 50e6).unwrap();
    p.glitch_filter = false;
    p.set_timeout_us(12.0).unwrap();
    scenario(&p, 5.0, "biss_50_nofilter");
}

// ---------------------------------------------------------------------------------------
// Glitches and speed
// ---------------------------------------------------------------------------------------

/// A one-sample MA glitch (the only kind a sub-clock glitch can leave after sampling) at
/// every cycle of a frame and its timeout, one run per position. With the glitch filter and
/// MA levels of at least 3 clock periods, no glitch changes anything. Without the filter a
/// glitch is an edge pair: the frame may be lost, but the next one must be good.
#[test]
fn one_sample_ma_glitch_anywhere() {
    for (filter, clock, hz) in [
        (true, 50e6, 4e6),
        (true, 133.33e6, 10e6),
        (false, 50e6, 4e6),
    ] {
        let mut p = BissParams::new(19, 0, clock).unwrap();
        p.glitch_filter = filter;
        p.set_timeout_us(2.0).unwrap();
        let t = timing(clock, 25.0);
        let reqs = vec![FrameRequest::new(hz), FrameRequest::new(hz)];
        let stream = Stream {
            every: 3,
            ..Default::default()
        };
        let n = cycles_for(&p, &reqs, 0.0);
        let clean = closed_loop(
            &p,
            &mut master_for(&p, t, reqs.clone()),
            &stream,
            n,
            |_, _| Ctl::default(),
            t,
        );
        check_frames(&clean, &p, 2);
        let from = clean.latch_row(clean.frames[0].t_start_ns, &p) - 8;
        let to = clean.latch_row(clean.frames[1].t_start_ns, &p) - 4;
        let mut lost = 0;
        for g in from..to {
            let run = closed_loop(
                &p,
                &mut master_for(&p, t, reqs.clone()),
                &stream,
                n,
                |k, _| Ctl {
                    ma_flip: k == g,
                    ..Ctl::default()
                },
                t,
            );
            if filter {
                check_frames(&run, &p, 2);
            } else {
                assert_eq!(run.frames.len(), 2, "glitch at {g}: {:#?}", run.frames);
                lost += run.frames[0].good().is_none() as u32;
                let f = &run.frames[1];
                let d = f
                    .good()
                    .unwrap_or_else(|| panic!("glitch at {g}: frame 1 {f:#?}"));
                let l = run.latch_row(f.t_start_ns, &p);
                let (pos, _, _, _) = run.expect(&p, l, 0);
                assert_eq!(d.position, pos, "glitch at {g}");
            }
        }
        if !filter {
            assert!(lost > 0, "unfiltered glitches must show");
        }
    }
}

/// Outcome of frames at one MA rate: true when every frame is good and correct.
fn rate_works(p: &BissParams, t: LineTiming, hz: f64, compensate: bool, frames: usize) -> bool {
    let reqs: Vec<_> = (0..frames)
        .map(|i| FrameRequest::new(hz).gap(7.3 * i as f64))
        .collect();
    let mut c = BissMasterConfig::new(t, p.data_bits(), p.multiturn_bits);
    c.compensate = compensate;
    c.max_ack_bits = 4;
    c.recover_ns = 2.0 * p.timeout_us() * 1e3;
    let mut m = BissMaster::new(c, reqs.clone(), 300.0);
    let stream = Stream {
        every: 1,
        ..Default::default()
    };
    let n = cycles_for(p, &reqs, 0.0);
    let run = closed_loop(p, &mut m, &stream, n, |_, _| Ctl::default(), t);
    run.frames.len() == frames
        && run.frames.iter().all(|f| {
            f.good().is_some_and(|d| {
                let l = run.latch_row(f.t_start_ns, p);
                d.position == run.expect(p, l, 0).0
            })
        })
}

/// Highest MA frequency (0.25 MHz steps from 1 MHz) up to which every rate works, over
/// frames at many MA/clock phases, for a one-way line delay of 25 ns (5 m of cable).
#[test]
fn maximum_ma_rate_measured() {
    let d = 25.0;
    let mut table = String::new();
    for clock in [50e6, 133.33e6] {
        for filter in [true, false] {
            for compensate in [true, false] {
                let mut p = BissParams::new(19, 0, clock).unwrap();
                p.glitch_filter = filter;
                p.set_timeout_us(1.0).unwrap();
                let t = timing(clock, d);
                let mut best = 0.0;
                let mut hz: f64 = 1e6;
                while hz < clock / 2.0 {
                    if rate_works(&p, t, hz, compensate, 24) {
                        best = hz;
                    } else {
                        break;
                    }
                    hz += 0.25e6;
                }
                let tclk = 1e9 / clock;
                let lat = p.latch_latency() as f64 + 1.0;
                let theory = if compensate {
                    p.max_ma_hz()
                } else {
                    p.max_ma_hz().min(1e9 / (2.0 * d + lat * tclk))
                };
                table += &format!(
                    "| {:>7.2} MHz | {:<7} | {:<12} | {:>6.2} MHz | {:>6.2} MHz |\n",
                    clock / 1e6,
                    if filter { "on" } else { "off" },
                    if compensate {
                        "compensated"
                    } else {
                        "next edge"
                    },
                    best / 1e6,
                    theory / 1e6
                );
                assert!(best >= 0.9 * theory - 0.25e6, "measured {best} vs {theory}");
                assert!(
                    best <= 1.25 * theory + 0.25e6,
                    "measured {best} vs {theory}"
                );
                if compensate && filter {
                    assert!(best >= 10e6, "10 MHz MA must work at {clock} Hz");
                }
            }
        }
    }
    println!("| clock | filter | master | max MA | bound |\n|---|---|---|---|---|\n{table}");
}

// ---------------------------------------------------------------------------------------
// Synthesis
// ---------------------------------------------------------------------------------------

/// Yosys for xc3sa and cycloneive: no latch, clean checks; the flip-flop count is what the
/// widths ask for (the 32-bit words are trimmed to the configured widths).
#[test]
fn synthesizes_for_both_families() {
    use sinedec::synth::{synthesize, Family};
    for (st, mt, clock, filter) in [
        (19, 0, 50e6, true),
        (17, 12, 133.33e6, true),
        (32, 0, 50e6, false),
    ] {
        let mut p = BissParams::new(st, mt, clock).unwrap();
        p.gray = mt > 0;
        p.glitch_filter = filter;
        let mut uut = BissSlave::new(&p).unwrap();
        rust_hdl::prelude::Block::connect_all(&mut uut);
        let v = sinedec::emit::verilog::export(&uut, "biss", "biss_slave").expect("export");
        let dir = common::workdir(&format!("biss_synth_{st}_{mt}_{filter}"));
        let n = p.data_bits() as u64;
        let tbits = 32 - (p.timeout_clocks - 1).leading_zeros() as u64;
        // sync 4 (3 without the filter), position hold S + M + 3, state 4, SLO, shift N,
        // CRC 6, bit counter 7, timeout counter, latched flags 2, the registered counter
        // compares 4 (bit counter = A, N, 6; timeout counter at its end), the registered
        // state decodes of the shift register 2 (Idle; Cds or Data before the last bit),
        // the synchronizer's registered edge pulses 2 (rise, fall).
        let want = 3 + filter as u64 + n + 3 + 4 + 1 + n + 6 + 7 + tbits + 2 + 4 + 2 + 2;
        for fam in [Family::Xc3sa, Family::CycloneIve] {
            let s = synthesize(&v, "biss_slave", fam, &dir).expect("synthesis");
            eprintln!(
                "biss {st}+{mt} {}: {} LUT, {} FF (bound {want})",
                fam.name(),
                s.luts,
                s.ffs
            );
            assert!(
                s.ffs <= want && s.ffs + 8 >= want,
                "{} FF, expected about {want}",
                s.ffs
            );
        }
    }
}
