//! SSI slave: the SSI master model reads the rust-hdl slave in a closed loop (binary and
//! Gray, error bit, monoflop time, glitches, reset, early and aborted frames), and the
//! recorded clock sequences replayed in rust-hdl, Icarus and Verilator give identical traces.
use crate::common;
use sinedec::blocks::mask;
use sinedec::blocks::serial::data_word;
use sinedec::blocks::ssi::hdl::SsiSlave;
use sinedec::blocks::ssi::SsiParams;
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::cosim::CosimBlock;
use sinedec::sim::serial_line::{FrameRequest, LineMaster, LineTiming};
use sinedec::sim::ssi_master::{SsiFrame, SsiMaster, SsiMasterConfig, SsiOutcome};

fn pos(k: usize) -> u64 {
    SplitMix64(k as u64 * 2 + 1).next_u64() & mask(32)
}
fn turns(k: usize) -> u64 {
    SplitMix64(k as u64 * 2 + 0x5555).next_u64() & mask(32)
}

#[derive(Clone, Copy, Debug, Default)]
struct Ctl {
    rst: bool,
    ma_flip: bool,
}

struct Run {
    rows: Vec<Vec<u64>>,
    slo: Vec<u64>,
    frames: Vec<SsiFrame>,
    timing: LineTiming,
}

/// Closed loop; the position is valid every `every` cycles, errors in `errors`.
fn closed_loop(
    p: &SsiParams,
    m: &mut SsiMaster,
    every: usize,
    errors: &[usize],
    cycles: usize,
    mut ctl: impl FnMut(usize, &SsiMaster) -> Ctl,
    timing: LineTiming,
) -> Run {
    let mut uut = SsiSlave::new(p).expect("params");
    rust_hdl::prelude::Block::connect_all(&mut uut);
    prepare(&mut uut).expect("settles");
    let (mut rows, mut slo) = (Vec::new(), Vec::new());
    for k in 0..cycles {
        let c = ctl(k, m);
        let ma = m.ma_for_cycle(k) ^ c.ma_flip;
        let row = vec![
            (k < 3 || c.rst) as u64,
            ma as u64,
            pos(k),
            turns(k),
            (k % every == 0) as u64,
            errors.contains(&k) as u64,
        ];
        uut.apply(&row);
        tick(&mut uut).expect("settles");
        let s = uut.sample()[0];
        m.push_slo(s != 0);
        slo.push(s);
        rows.push(row);
    }
    Run {
        rows,
        slo,
        frames: m.frames().to_vec(),
        timing,
    }
}

impl Run {
    fn latch_row(&self, t0: f64, p: &SsiParams) -> usize {
        let need = if p.glitch_filter { 2 } else { 1 };
        let k0 = ((t0 + self.timing.line_delay_ns) / self.timing.tclk_ns()).floor() as usize;
        let mut k = k0.saturating_sub(3);
        while !(0..need).all(|i| self.rows[k + i][1] == 0) {
            k += 1;
        }
        k + p.latch_latency() as usize
    }
    /// (position, turns, error) the slave latched at row `l`, previous take at `prev`.
    fn expect(&self, p: &SsiParams, l: usize, prev: usize) -> (u64, u64, bool) {
        let last_rst = (0..=l).rev().find(|&j| self.rows[j][0] != 0).unwrap_or(0);
        let from = prev.max(last_rst) + 1;
        let err = (from..=l).any(|j| self.rows[j][5] != 0);
        match (0..=l)
            .rev()
            .find(|&j| self.rows[j][4] != 0 && j > last_rst)
        {
            Some(v) => (
                self.rows[v][2] & mask(p.position_bits),
                self.rows[v][3] & mask(p.multiturn_bits),
                err,
            ),
            None => (0, 0, true),
        }
    }
}

fn master(p: &SsiParams, t: LineTiming, reqs: Vec<FrameRequest>) -> SsiMaster {
    let mut c = SsiMasterConfig::new(t, p.data_bits(), p.multiturn_bits);
    c.word.gray = p.gray;
    c.error_bit = p.error_bit;
    SsiMaster::new(c, reqs, 400.0)
}

fn cycles_for(p: &SsiParams, reqs: &[FrameRequest], extra_ns: f64) -> usize {
    let ns: f64 = reqs
        .iter()
        .map(|r| {
            (p.frame_bits() + 3) as f64 * 1e9 / r.ma_hz + r.gap_ns + p.timeout_us() * 1e3 + 1000.0
        })
        .sum::<f64>()
        + extra_ns
        + 2000.0;
    (ns * p.clock_hz / 1e9) as usize + p.timeout_clocks as usize + 100
}

fn check_good(run: &Run, p: &SsiParams, i: usize, prev: usize) -> usize {
    let f = &run.frames[i];
    let SsiOutcome::Data(d) = &f.outcome else {
        panic!("frame {i}: {f:#?}")
    };
    let l = run.latch_row(f.t_start_ns, p);
    let (pos, turns, err) = run.expect(p, l, prev);
    assert_eq!(
        (d.position, d.turns),
        (pos, turns),
        "frame {i} at {} Hz",
        f.ma_hz
    );
    assert_eq!(
        d.data,
        data_word(pos, turns, p.position_bits, p.multiturn_bits, p.gray),
        "frame {i} word"
    );
    if p.error_bit {
        assert_eq!(d.error, Some(err), "frame {i} error bit");
    }
    assert!(d.tail_low, "frame {i}: line low after the last bit");
    l
}

#[test]
fn params_are_validated() {
    assert!(SsiParams::new(25, 0, 50e6).is_ok());
    assert!(SsiParams::new(0, 0, 50e6)
        .unwrap_err()
        .to_string()
        .contains("position_bits"));
    assert!(SsiParams::new(13, 20, 50e6)
        .unwrap_err()
        .to_string()
        .contains("exceeds"));
    let mut p = SsiParams::new(13, 12, 50e6).unwrap();
    assert!(p.set_timeout_us(0.05).is_err());
    p.set_timeout_us(30.0).unwrap();
    assert_eq!(p.timeout_clocks, 1500);
    p.timeout_clocks = 1;
    assert!(SsiSlave::new(&p).is_err());
}

/// Binary and Gray, with and without the error bit, 100 kHz .. 2 MHz (a next-edge master
/// over 25 ns of line: the answer must come within one period), 50 and 133.33 MHz.
#[test]
fn master_reads_every_frame() {
    for clock in [50e6, 133.33e6] {
        let mut a = SsiParams::new(13, 12, clock).unwrap();
        a.gray = true;
        a.error_bit = true;
        let b = SsiParams::new(24, 0, clock).unwrap();
        for p in [a, b] {
            let t = LineTiming {
                clock_hz: clock,
                line_delay_ns: 25.0,
            };
            let reqs: Vec<_> = [100e3, 500e3, 1e6, 1.5e6, 2e6]
                .iter()
                .flat_map(|&hz| [FrameRequest::new(hz), FrameRequest::new(hz).gap(77.0)])
                .collect();
            let errors = [30_000, 31_000];
            let n = cycles_for(&p, &reqs, 0.0);
            let run = closed_loop(
                &p,
                &mut master(&p, t, reqs.clone()),
                3,
                &errors,
                n,
                |_, _| Ctl::default(),
                t,
            );
            assert_eq!(run.frames.len(), reqs.len());
            let mut prev = 0;
            for i in 0..reqs.len() {
                prev = check_good(&run, &p, i, prev);
                let to = run.frames[i].timeout_ns.expect("monoflop measured");
                let nominal = p.timeout_us() * 1e3;
                assert!(
                    to >= nominal && to < nominal + 50.0 + 5e9 / clock,
                    "frame {i}: {to}"
                );
            }
            if p.error_bit {
                let flagged = run
                    .frames
                    .iter()
                    .filter(|f| matches!(&f.outcome, SsiOutcome::Data(d) if d.error == Some(true)))
                    .count();
                assert_eq!(flagged, 1, "one frame carries the error");
            }
        }
    }
}

/// A compensating master (sampling a fixed delay after each rising edge) reads 10 MHz.
#[test]
fn compensating_master_at_10mhz() {
    for clock in [50e6, 133.33e6] {
        let p = SsiParams::new(19, 0, clock).unwrap();
        let t = LineTiming {
            clock_hz: clock,
            line_delay_ns: 25.0,
        };
        let mut c = SsiMasterConfig::new(t, 19, 0);
        // The answer to edge n is on the line from 2d + 4 T_clk to T + 2d + 3 T_clk after
        // it (round trip, 3..4 clocks of synchronizer): sample in the middle.
        c.sample_delay_ns = Some(50.0 + 3.5e9 / clock + 50.0);
        let reqs: Vec<_> = (0..6)
            .map(|i| FrameRequest::new(10e6).gap(3.3 * i as f64))
            .collect();
        let mut m = SsiMaster::new(c, reqs.clone(), 400.0);
        let n = cycles_for(&p, &reqs, 0.0);
        let run = closed_loop(&p, &mut m, 1, &[], n, |_, _| Ctl::default(), t);
        let mut prev = 0;
        for i in 0..reqs.len() {
            prev = check_good(&run, &p, i, prev);
        }
    }
}

/// The supported line round trip (cable and transceivers, both ways) at each clock rate,
/// the figure `check` prints (`sinedec::blocks::serial::max_round_trip_ns`,
/// docs/interfaces.md), with the `[board]` default pad budgets added to the model's line:
/// a master reading each bit at the next rising edge reads every frame right at the limit;
/// one clock period beyond it every answer is late and the master reads the word one bit
/// late, a wrong position that SSI, without a check sum, cannot flag (why the limit must
/// be kept; BiSS-C's CRC and Ack/Start search catch or absorb it).
#[test]
fn supported_round_trip_at_each_clock_rate() {
    use sinedec::blocks::serial::{answer_window, max_round_trip_ns};
    let io = sinedec::board::IoTiming::DEFAULT;
    let pads = io.input_setup_ns + io.clock_to_out_ns;
    let clock = 50e6;
    let mut p = SsiParams::new(19, 0, clock).unwrap();
    p.set_timeout_us(2.0).unwrap();
    let a = answer_window(clock, p.glitch_filter, &io);
    for hz in [1e6, 4e6] {
        let limit = max_round_trip_ns(1e9 / hz, &a);
        for (rt, right) in [(limit - 0.05, true), (limit + 1e9 / clock + 0.05, false)] {
            let t = LineTiming {
                clock_hz: clock,
                line_delay_ns: (rt + pads) / 2.0,
            };
            let reqs: Vec<_> = (0..6)
                .map(|i| FrameRequest::new(hz).gap(7.3 * i as f64))
                .collect();
            let mut m = master(&p, t, reqs.clone());
            let n = cycles_for(&p, &reqs, 6.0 * rt);
            let run = closed_loop(&p, &mut m, 1, &[], n, |_, _| Ctl::default(), t);
            assert_eq!(run.frames.len(), reqs.len());
            for (i, f) in run.frames.iter().enumerate() {
                let SsiOutcome::Data(d) = &f.outcome else {
                    panic!("frame {i}: {f:#?}")
                };
                let l = run.latch_row(f.t_start_ns, &p);
                let want = run.expect(&p, l, 0).0;
                assert_eq!(
                    d.position == want,
                    right,
                    "{hz} Hz, round trip {rt:.2} ns (limit {limit:.2}): frame {i} read {:#x}, latched {want:#x}",
                    d.position
                );
            }
        }
    }
}

/// Corner cases, then the replay in three simulators.
fn scenario(p: &SsiParams, d: f64, tag: &str) {
    let t = LineTiming {
        clock_hz: p.clock_hz,
        line_delay_ns: d,
    };
    let mut reqs = vec![
        FrameRequest::new(100e3),
        FrameRequest::new(1e6),
        FrameRequest::new(1e6),
        // starts during the monoflop time: the slave keeps the line low
        FrameRequest {
            wait_ready: false,
            gap_ns: 800.0,
            ..FrameRequest::new(1.2e6)
        },
        FrameRequest::new(1.2e6),
        FrameRequest {
            abort_after_rises: Some(7),
            ..FrameRequest::new(1.5e6)
        },
        FrameRequest::new(1.5e6),
        FrameRequest::new(5e6), // reset after 9 rising edges
        FrameRequest::new(5e6),
        FrameRequest::new(4e6).gap(2000.0), // glitches
        FrameRequest::new(4e6),
        FrameRequest::new(10e6),
        FrameRequest::new(10e6),
    ];
    reqs.iter_mut().for_each(|r| r.duty = 0.55);
    // A master that samples a fixed delay after each rising edge (in the middle of the
    // answer window at 10 MHz, see `compensating_master_at_10mhz`), so that one master reads
    // 100 kHz to 10 MHz.
    let mut c = SsiMasterConfig::new(t, p.data_bits(), p.multiturn_bits);
    c.word.gray = p.gray;
    c.error_bit = p.error_bit;
    c.sample_delay_ns = Some(2.0 * d + 3.5e9 / p.clock_hz + 50.0);
    let mut m = SsiMaster::new(c, reqs.clone(), 400.0);
    let (mut reset_left, mut reset_done, mut glitched) = (0, false, [false; 2]);
    let n = cycles_for(p, &reqs, 200_000.0);
    let run = closed_loop(
        p,
        &mut m,
        5,
        &[4000, 60_000],
        n,
        |_, m| {
            let f = m.frames().len();
            let mut c = Ctl::default();
            if f == 7 && !reset_done && rises_reached(m, 9) {
                reset_done = true;
                reset_left = 2;
            }
            if reset_left > 0 {
                c.rst = true;
                reset_left -= 1;
            }
            if f == 9 && !glitched[0] {
                glitched[0] = true;
                c.ma_flip = true;
            }
            if f == 9 && rises_reached(m, 6) && !glitched[1] {
                glitched[1] = true;
                c.ma_flip = true;
            }
            c
        },
        t,
    );
    assert_eq!(run.frames.len(), reqs.len(), "{:#?}", run.frames);
    let mut prev = 0;
    for i in 0..reqs.len() {
        let f = &run.frames[i];
        match i {
            // Clocked during the monoflop time: the line stays low, the master reads zeros.
            3 => assert!(
                matches!(&f.outcome, SsiOutcome::Data(d) if d.data == 0),
                "frame 3: {f:?}"
            ),
            5 => assert_eq!(f.outcome, SsiOutcome::Aborted),
            7 => {}
            9 if !p.glitch_filter => {}
            _ => prev = check_good(&run, p, i, prev),
        }
        if i == 5 || i == 7 || i == 9 {
            prev = run.latch_row(f.t_start_ns, p);
        }
    }
    // The data line is the slave's only output: the recorded trace is one column.
    let slo: Vec<Vec<u64>> = run.slo.iter().map(|&s| vec![s]).collect();
    common::replay_in_all_simulators(SsiSlave::new(p).unwrap(), "ssi_slave", &run.rows, &slo, tag);
}

/// Whether the master has given at least `k` rising edges in the frame it is clocking.
fn rises_reached(m: &SsiMaster, k: usize) -> bool {
    m.rises_in_frame().is_some_and(|r| r as usize >= k)
}

#[test]
fn cosim_50mhz_gray_error_bit() {
    let mut p = SsiParams::new(13, 12, 50e6).unwrap();
    p.gray = true;
    p.error_bit = true;
    p.set_timeout_us(16.0).unwrap();
    scenario(&p, 25.0, "ssi_50");
}

#[test]
fn cosim_133mhz_binary() {
    let p = SsiParams::new(22, 0, 133.33e6).unwrap();
    scenario(&p, 25.0, "ssi_133");
}

#[test]
fn synthesizes_for_both_families() {
    use sinedec::synth::{synthesize, Family};
    let mut p = SsiParams::new(13, 12, 50e6).unwrap();
    p.gray = true;
    p.error_bit = true;
    let mut uut = SsiSlave::new(&p).unwrap();
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let v = sinedec::emit::verilog::export(&uut, "ssi", "ssi_slave").expect("export");
    let dir = common::workdir("ssi_synth");
    let n = p.data_bits() as u64;
    let tbits = 32 - (p.timeout_clocks - 1).leading_zeros() as u64;
    // sync 4 and its registered edge pulses 2, hold N + 3, state 3, line, shift N,
    // counter 7, monoflop counter, error 1.
    let want = 4 + 2 + n + 3 + 3 + 1 + n + 7 + tbits + 1;
    for fam in [Family::Xc3sa, Family::CycloneIve] {
        let s = synthesize(&v, "ssi_slave", fam, &dir).expect("synthesis");
        eprintln!(
            "ssi {}: {} LUT, {} FF (bound {want})",
            fam.name(),
            s.luts,
            s.ffs
        );
        assert!(s.ffs <= want && s.ffs + 8 >= want, "{} FF vs {want}", s.ffs);
    }
}
