//! End to end in the Rust simulation: encoder model -> LTC1407A-1 model -> `<name>_top`
//! (preamp set-up, ADC controller, core) -> decoded position against the true angle.
use crate::common;
use sinedec::config::Loaded;
use sinedec::sim::dut::EngineKind;
use sinedec::sim::encoder::EncoderModel;
use sinedec::sim::system::System;

#[test]
fn constant_speed_closed_loop() {
    let l = Loaded::default_config().expect("default");
    let d = &l.derived;
    let enc = EncoderModel::ideal(2048, 1.0, 300.0);
    let mut s = System::new(d, enc).expect("system");
    s.start().expect("settles");
    s.run(20_000).expect("runs");
    let r = s.finish();
    let st = r.stats(d, 2);
    eprintln!(
        "{} samples, {:?}, gains {:?}",
        r.records.len(),
        st,
        r.amp_gains
    );
    assert_eq!(r.latency_mismatches, 0);
    assert!(r.adc_violations.is_empty(), "{:?}", r.adc_violations);
    assert!(r.amp_violations.is_empty(), "{:?}", r.amp_violations);
    assert_eq!(r.amp_gains, Some((-1, -1)));
    assert!(r.records.len() > 180);
    assert!(st.max_lsb < 4.0, "{st:?}");
}

/// The closed-loop run's inputs replayed through the exported top in Icarus and Verilator
/// give the same pin and position trace as the rust-hdl simulation. 20,000 rpm: above the
/// unwrap limit, so the QEP fallback resynchronises the counter at every sample.
#[test]
fn closed_loop_replayed_in_icarus_and_verilator() {
    let l = Loaded::default_config().expect("default");
    common::replay_top_in_simulators(&l, 20_000.0, 8000, "system_replay");
}

/// The chip-select tops (ADS8354: no pipeline, the fallback's capture straight into c2;
/// AD7380: one frame) replayed the same way, at speeds where the QEP fallback is active
/// (2.3 and 4.5 quadrants per sample of the replay's 2048-line encoder): the fallback's
/// conversion start, the inverse of the chip select, and its capture depth
/// (src/blocks/fallback/hdl.rs, `conv_inverted`, `capture_depth`) give the same trace in
/// rust-hdl, Icarus, Verilator and the engine.
#[test]
fn chip_select_tops_in_the_fallback_replayed_in_icarus_and_verilator() {
    for (file, rpm, cycles) in [
        ("ads8354_100mhz.toml", 10_000.0, 12_000),
        ("ad7380_100mhz.toml", 80_000.0, 6_000),
    ] {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("configs")
            .join(file);
        let l = Loaded::from_file(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        let r = common::replay_top_in_simulators(&l, rpm, cycles, &format!("cs_replay_{file}"));
        let warned = r.records.iter().filter(|x| x.warning).count();
        assert!(
            warned > r.records.len() / 2,
            "{file}: {warned} of {} samples in the fallback",
            r.records.len()
        );
    }
}

/// BiSS-C end to end: encoder -> ADC -> top -> BiSS master model. Every frame's CRC checks,
/// the position read is the one on the parallel bus when the frame's first MA edge reached
/// the slave, and a loss of signal shows as nE = 0.
#[test]
fn biss_frames_end_to_end() {
    use sinedec::sim::biss_master::{BissMaster, BissMasterConfig};
    use sinedec::sim::serial_line::{FrameRequest, LineTiming};
    use std::cell::RefCell;
    use std::rc::Rc;
    // A 2 us BiSS timeout, so that many frames fit in a short simulation.
    let text = sinedec::config::DEFAULT_CONFIG.replace("timeout_us = 20.0", "timeout_us = 2.0");
    let l = Loaded::parse(&text, "t").expect("config");
    let d = &l.derived;
    let clock = d.clock_hz;
    let mut enc = EncoderModel::ideal(2048, 1.0, 300.0);
    // Signal lost from 60 us to 90 us. The master starts at 15 us: until the monitor has
    // seen its window of good samples after reset (about 9 us) nE is 0 by design.
    enc.fault = Some((60e-6, 90e-6, 0.02));
    let mut s = System::new(d, enc).expect("system");
    let timing = LineTiming {
        clock_hz: clock,
        line_delay_ns: 25.0,
    };
    let cfg = BissMasterConfig::new(timing, d.biss.position_bits, 0);
    let reqs: Vec<FrameRequest> = (0..40)
        .map(|k| FrameRequest::new(if k % 2 == 0 { 5e6 } else { 10e6 }).gap(300.0))
        .collect();
    let master = Rc::new(RefCell::new(BissMaster::new(cfg, reqs, 15_000.0)));
    s.attach_master(Box::new(master.clone()));
    s.start().expect("settles");
    let drop = d.position_width - d.biss.position_bits;
    let mut words = vec![];
    let cycles = (150e-6 * clock) as u64;
    for _ in 0..cycles {
        s.run(1).expect("runs");
        let t = s.top().expect("rust-hdl top");
        let pos = (t.par_qc.val().to_u64() << d.fine_bits) | t.par_fine.val().to_u64();
        words.push((pos >> drop, t.par_error.val()));
    }
    let frames = master.borrow().frames().to_vec();
    assert!(frames.len() >= 15, "{} frames", frames.len());
    let mut lost_seen = false;
    // Flags are sticky until a frame reads them: the first frame reports the start-up
    // loss of signal (the monitor's window after reset), so it may carry nE = 0.
    for (i, f) in frames.iter().enumerate() {
        let g = f.good().unwrap_or_else(|| panic!("bad frame {f:?}"));
        // The first MA edge leaves the master at t_start and reaches the slave one line
        // delay later; the slave latches within its synchronizer and filter delay.
        let c0 = ((f.t_start_ns + 25.0) * clock / 1e9) as usize;
        let window = &words[c0.saturating_sub(1)..(c0 + 6).min(words.len())];
        assert!(
            window.iter().any(|(w, _)| *w == g.position),
            "frame at {} ns: position {} not among {:?}",
            f.t_start_ns,
            g.position,
            window
        );
        if !g.n_e && i > 0 {
            lost_seen = true;
            assert!(
                f.t_start_ns > 60_000.0 && f.t_start_ns < 100_000.0,
                "nE=0 outside the fault: {f:?}"
            );
        }
    }
    assert!(
        lost_seen,
        "the loss of signal showed as nE = 0 in some frame"
    );
}

/// QEP cross-check: a comparator fault (B stuck low for 0.5 ms at 300 rpm: the QEP count
/// then dithers instead of following the encoder) makes the two counts disagree by more
/// than one quadrant between samples: the warning rises. The cross-check compares each
/// sample with the offset of the sample before (it re-aligns every good sample), so it
/// catches jumps, not a slow drift. The position keeps the CORDIC's count (good signals,
/// low speed): its error stays as small as without the fault, and the warning clears after
/// the fault ends.
#[test]
fn qep_fault_raises_the_warning_and_does_not_move_the_position() {
    let l = Loaded::default_config().expect("default");
    let d = &l.derived;
    let enc = EncoderModel::ideal(2048, 1.0, 300.0);
    // The top's Verilog on the compiled engine (tests/system/engine.rs and engine_loop.rs
    // prove it equal to rust-hdl): 1.6 ms is 213 k clocks.
    let mut s = System::on(d, enc, EngineKind::Compiled).expect("system");
    s.qep_b_stuck_low(0.4e-3, 0.9e-3);
    s.start().expect("settles");
    s.run((1.6e-3 * d.clock_hz) as u64).expect("runs");
    let r = s.finish();
    let st = r.stats(d, 8);
    let t = |rec: &sinedec::sim::system::Record| rec.cycle as f64 / d.clock_hz;
    let warned_during = r
        .records
        .iter()
        .filter(|x| (0.45e-3..0.9e-3).contains(&t(x)) && x.warning)
        .count();
    let warned_after = r
        .records
        .iter()
        .filter(|x| t(x) > 1.1e-3 && x.warning)
        .count();
    let errors = r
        .records
        .iter()
        .filter(|x| t(x) > 0.1e-3 && x.error)
        .count();
    eprintln!(
        "{} samples, {st:?}, warned during the fault {warned_during}, after {warned_after}",
        r.records.len()
    );
    assert!(warned_during > 0, "the mismatch must raise the warning");
    assert_eq!(warned_after, 0, "the warning clears when the QEP recovers");
    assert_eq!(errors, 0);
    assert!(st.max_lsb < 4.0, "position moved: {st:?}");
}

/// The default config with ABZ on, its LTC1407A-1 kit swapped for a generic 16-bit SPI ADC
/// when `generic` (no pre-amplifier; the generic frame's defaults).
fn interfaces_config(generic: bool) -> Loaded {
    let mut text = format!(
        "{}\n[abz]\nenabled = true\n",
        sinedec::config::DEFAULT_CONFIG
    );
    if generic {
        text = text
            .replace(
                "preset = \"ltc1407a-1\"",
                "preset = \"generic\"\nmax_sample_rate_hz = 2e6",
            )
            .replace("width = 14", "width = 16")
            .replace("[preamp]\n", "[unused_preamp]\n");
        let start = text.find("[unused_preamp]").expect("preamp section");
        let end = start + text[start..].find("\n[").expect("next section") + 1;
        text.replace_range(start..end, "");
    }
    // The SSI (Gray-coded) and SPI slaves on too.
    for (section, extra) in [("[ssi]\n", "\ngray = true"), ("[spi]\n", "")] {
        let at = text.find(section).expect("section") + section.len();
        let off = at + text[at..].find("enabled = false").expect("enabled key");
        text.replace_range(off..off + "enabled = false".len(), "enabled = true");
        if !extra.is_empty() {
            let end = off + "enabled = true".len();
            let line_end = end + text[end..].find('\n').expect("line");
            let next = line_end + 1 + text[line_end + 1..].find('\n').expect("gray line");
            // Drop the section's own `gray = false` line and set Gray.
            assert!(
                text[line_end + 1..next].starts_with("gray = "),
                "gray key follows"
            );
            text.replace_range(line_end..next, extra);
        }
    }
    Loaded::parse(&text, "interfaces.toml").expect("config")
}

/// `simulate` reads every output it drives: its BiSS-C master's frames carry a good CRC and
/// the parallel bus's position at the slave's latch, so do the SSI master's frames (Gray)
/// and the SPI master's words, and a quadrature counter on ABZ equals
/// floor(position x E / P) of every sample before the next one shows, through a reversal at
/// 3000 rpm, with no illegal A/B step. The same holds with a generic SPI ADC in place of the kit's LTC1407A-1: its top
/// is the same composition without the pre-amplifier.
#[test]
fn simulate_reads_biss_and_abz_against_the_parallel_bus() {
    for generic in [false, true] {
        let l = interfaces_config(generic);
        let o = sinedec::simulate::SimOptions {
            profile: sinedec::sim::encoder::Profile::Reversal {
                rpm: 3000.0,
                at: 0.001,
                over: 0.001,
            },
            duration_s: 0.003,
            ..Default::default()
        };
        let r = sinedec::simulate::run(&l, &o, |_, _| {}).expect("simulates");
        let res = &r.result;
        let b = res.biss.expect("BiSS-C master attached");
        assert!(b.frames >= 50, "{generic}: {b:?}");
        assert_eq!(
            (b.good, b.crc_errors, b.failed, b.position_mismatches),
            (b.frames, 0, 0, 0),
            "{generic}: {b:?}"
        );
        for (name, c) in [("SSI", res.ssi), ("SPI", res.spi)] {
            let c = c.unwrap_or_else(|| panic!("{name} master attached"));
            assert!(c.frames >= 50, "{generic} {name}: {c:?}");
            assert_eq!(
                (c.good, c.failed, c.position_mismatches),
                (c.frames, 0, 0),
                "{generic} {name}: {c:?}"
            );
        }
        let a = res.abz.expect("ABZ counter");
        assert_eq!(a.illegal, 0, "{generic}: {a:?}");
        assert!(a.edges > 1000, "{generic}: {a:?}");
        assert!(a.checked > 3000, "{generic}: {a:?}");
        assert_eq!((a.max_lag, a.last_lag), (0, 0), "{generic}: {a:?}");
        assert_eq!(res.latency_mismatches, 0, "{generic}");
        assert!(
            res.adc_violations.is_empty(),
            "{generic}: {:?}",
            res.adc_violations
        );
        assert!(r.stats.max_lsb < 4.0, "{generic}: {:?}", r.stats);
        assert_eq!(res.amp_gains.is_some(), !generic, "{generic}");
        let summary = r.summary(&l);
        for line in ["BiSS-C frames", "SSI frames", "SPI words", "ABZ quadrature"] {
            assert!(summary.contains(line), "{line}:\n{summary}");
        }
    }
}
