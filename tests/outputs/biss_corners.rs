//! BiSS-C slave, protocol corners: the closed loop of `tests/biss_loop` with frames started
//! during the timeout, aborted frames, resets and glitches, replayed in rust-hdl, Icarus and
//! Verilator; one-sample MA glitches at every cycle of a frame; the measured maximum MA rate;
//! synthesis for both families.
use crate::biss_loop;
use crate::common;
use biss_loop::*;
use sinedec::blocks::biss::hdl::BissSlave;
use sinedec::blocks::biss::BissParams;
use sinedec::sim::biss_master::{BissMaster, BissMasterConfig, Outcome};
use sinedec::sim::serial_line::{FrameRequest, LineTiming};

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
    // SLO is the slave's only output: the recorded trace is one column.
    let slo: Vec<Vec<u64>> = run.slo.iter().map(|&s| vec![s]).collect();
    common::replay_in_all_simulators(
        BissSlave::new(p).unwrap(),
        "biss_slave",
        &run.rows,
        &slo,
        tag,
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
    c.line.recover_ns = 2.0 * p.timeout_us() * 1e3;
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
// Line delay
// ---------------------------------------------------------------------------------------

/// How the frames of one run ended: read with a good CRC and the latched position, failed
/// loudly (bad CRC, no Ack or Start, not ready), or read with a good CRC and a wrong
/// position (silently wrong: only beyond the supported round trip).
#[derive(Debug, Default, PartialEq)]
struct Tally {
    right: usize,
    loud: usize,
    silent: usize,
}

/// Frames at `hz` over a line whose round trip, pads included, is `rt_ns`, at many
/// MA/clock phases (a gap of 7.3 ns more before each frame).
fn tally(p: &BissParams, rt_ns: f64, hz: f64, compensate: bool, frames: usize) -> Tally {
    let t = timing(p.clock_hz, rt_ns / 2.0);
    let reqs: Vec<_> = (0..frames)
        .map(|i| FrameRequest::new(hz).gap(7.3 * i as f64))
        .collect();
    let mut c = BissMasterConfig::new(t, p.data_bits(), p.multiturn_bits);
    c.compensate = compensate;
    c.max_ack_bits = 40;
    c.line.recover_ns = 2.0 * p.timeout_us() * 1e3 + rt_ns;
    let mut m = BissMaster::new(c, reqs.clone(), 300.0);
    let stream = Stream {
        every: 1,
        ..Default::default()
    };
    let n = cycles_for(
        p,
        &reqs,
        frames as f64 * (rt_ns + 3.0 * p.timeout_us() * 1e3),
    );
    let run = closed_loop(p, &mut m, &stream, n, |_, _| Ctl::default(), t);
    assert_eq!(run.frames.len(), frames, "{:#?}", run.frames);
    let mut out = Tally::default();
    for f in &run.frames {
        match f.good() {
            None => out.loud += 1,
            Some(d) => {
                let l = run.latch_row(f.t_start_ns, p);
                if d.position == run.expect(p, l, 0).0 {
                    out.right += 1;
                } else {
                    out.silent += 1;
                }
            }
        }
    }
    out
}

/// The supported line round trip (cable and transceivers, both ways) at each MA rate, the
/// figure `check` prints (`sinedec::blocks::serial::max_round_trip_ns`, docs/interfaces.md):
/// with the `[board]` default pad budgets (set-up 3 ns, clock-to-out 6 ns) added to the
/// model's line, a master that reads each answer at the next MA rising edge reads every
/// frame right at that round trip; up to two clock periods beyond it frames are read right
/// one bit late (BiSS's Ack/Start search allows it) or fail the CRC, and a few slip with a
/// good CRC (the table counts them: the limit must be kept); a compensating master reads
/// every frame right at ten times the limit (and 1 us).
#[test]
fn supported_round_trip_at_each_ma_rate() {
    use sinedec::blocks::serial::{answer_window, max_round_trip_ns};
    let io = sinedec::board::IoTiming::DEFAULT;
    let pads = io.input_setup_ns + io.clock_to_out_ns;
    let mut table = String::new();
    for clock in [50e6, 133.33e6] {
        let mut p = BissParams::new(19, 0, clock).unwrap();
        p.set_timeout_us(2.0).unwrap();
        let a = answer_window(clock, p.glitch_filter, &io);
        let tclk = 1e9 / clock;
        for hz in [1e6, 4e6, 10e6] {
            let limit = max_round_trip_ns(1e9 / hz, &a);
            assert!(limit > 0.0, "{clock} Hz, {hz} Hz: limit {limit}");
            let at = tally(&p, limit + pads - 0.05, hz, false, 16);
            assert_eq!(
                at.right, 16,
                "{clock} Hz clock, MA {hz} Hz at the limit: {at:?}"
            );
            let mut beyond = Tally::default();
            for k in 1..=8 {
                let t = tally(&p, limit + pads + k as f64 * tclk / 4.0, hz, false, 8);
                beyond.right += t.right;
                beyond.loud += t.loud;
                beyond.silent += t.silent;
            }
            // Beyond the limit CRC6 flags most slipped frames, not all (docs/interfaces.md):
            // the figures go to the table; the limit is what a master must keep.
            assert!(beyond.loud + beyond.right > 0, "{beyond:?}");
            let far = (10.0 * limit).max(1000.0);
            let comp = tally(&p, far + pads, hz, true, 8);
            assert_eq!(comp.right, 8, "compensated at {far} ns: {comp:?}");
            table += &format!(
                "| {:>7.2} MHz | {:>5.1} MHz | {:>7.1} ns | {:>3} right, {:>3} loud, {:>3} silent |\n",
                clock / 1e6,
                hz / 1e6,
                limit,
                beyond.right,
                beyond.loud,
                beyond.silent
            );
        }
    }
    println!(
        "| clock | MA | max round trip | beyond (up to +2 T_clk) |\n|---|---|---|---|\n{table}"
    );
}

/// `sinedec check` prints each serial slave's answer window and its supported round trip at
/// each rate up to the synchronizer's limit, the same figures as the functions the sweeps
/// above and `tests/outputs/ssi.rs`, `tests/outputs/spi_slave.rs` hold the slaves to; a `[board]` budget
/// moves them.
#[test]
fn check_prints_the_supported_round_trip() {
    use sinedec::blocks::serial::{answer_window, max_round_trip_ns, LINE_RATES_HZ};
    let text = sinedec::config::DEFAULT_CONFIG
        .replace(
            "[ssi]\n# SSI slave on ssi_clk/ssi_data, sending the BiSS data word (binary or Gray).\nenabled = false",
            "[ssi]\nenabled = true",
        )
        .replace(
            "enc_miso: the BiSS data word, then E and W.\nenabled = false",
            "enc_miso: the BiSS data word, then E and W.\nenabled = true",
        );
    // The kit preset with the header pins, and budgets of 4.5 ns and 1 ns.
    let board = format!(
        "{}\n[board]\npreset = \"spartan3an-starter-kit\"\nfpga_clock_to_out_ns = 4.5\nfpga_input_setup_ns = 1.0\n[board.pins]\nqep_a = \"H1\"\nqep_b = \"H2\"\nqep_z = \"H3\"\nbiss_ma = \"H4\"\nbiss_slo = \"H5\"\n",
        sinedec::config::DEFAULT_CONFIG
    );
    for (text, co, su) in [(text, 6.0, 3.0), (board, 4.5, 1.0)] {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("c.toml"), &text).unwrap();
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_sinedec"))
            .args(["check", "c.toml"])
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let out = String::from_utf8_lossy(&o.stdout).to_string();
        let l = sinedec::config::Loaded::parse(&text, "c.toml").unwrap();
        let d = &l.derived;
        let io = sinedec::board::IoTiming {
            clock_to_out_ns: co,
            input_setup_ns: su,
            ..sinedec::board::IoTiming::DEFAULT
        };
        let a = answer_window(d.clock_hz, d.biss.glitch_filter, &io);
        let mut lines = vec![("biss line timing", 1.0, d.biss.max_ma_hz())];
        if let Some(x) = &d.spi {
            lines.push(("ssi line timing", 1.0, d.biss.max_ma_hz()));
            lines.push(("spi line timing", 0.5, x.max_sck_hz(0.0)));
        }
        for (label, window, max_hz) in lines {
            let line = out
                .lines()
                .find(|x| x.starts_with(label))
                .unwrap_or_else(|| panic!("no `{label}` in:\n{out}"));
            assert!(
                line.contains(&format!("{:.2}..{:.2} ns", a.min_ns, a.max_ns)),
                "{line}"
            );
            for f in LINE_RATES_HZ.iter().filter(|&&f| f <= max_hz) {
                let r = max_round_trip_ns(window * 1e9 / f, &a);
                let at = if *f >= 1e6 {
                    format!("{:.0} MHz", f / 1e6)
                } else {
                    format!("{:.0} kHz", f / 1e3)
                };
                assert!(
                    line.contains(&format!("{r:.1} ns at {at}")),
                    "{r:.1} at {at}: {line}"
                );
            }
        }
    }
    // The shipped figures: 133.33 MHz, filter on, default pads: 4 clocks + 9 ns = 39.00 ns;
    // 10 MHz MA leaves 100 - 39.00 = 61.0 ns of round trip.
    let io = sinedec::board::IoTiming::DEFAULT;
    let a = answer_window(133.33e6, true, &io);
    assert!((a.max_ns - (4e9 / 133.33e6 + 9.0)).abs() < 1e-9);
    assert!((max_round_trip_ns(100.0, &a) - (100.0 - 4e9 / 133.33e6 - 9.0)).abs() < 1e-9);
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
        // sync 4 (3 without the filter), position hold S + M + 3, one-hot state 11 (Timeout,
        // Idle, First, Second, Ack, Start, Cds, Data, nE, nW, Crc), SLO, shift N, CRC 6, bit
        // counter 7, timeout counter, latched flags 2, the registered counter compares 4 (bit
        // counter = A, N, 6; timeout counter one before its end), the registered timeout gate
        // 1 (not Idle and the timeout counter at its end), the shift register's registered
        // state decode 1 (Cds or Data before the last bit), the next rise's actions 6 (CRC
        // step and feedback, count up, load 1, SLO enable and value), the synchronizer's
        // registered edge pulses 2 (rise, fall).
        let want = 3 + filter as u64 + n + 3 + 11 + 1 + n + 6 + 7 + tbits + 2 + 4 + 1 + 1 + 6 + 2;
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
