//! STATUS in the closed loop, one test per latched fault bit: `simulate` with a `--fault`
//! (`sinedec::simulate::FaultSpec`) on the default top with `[reference]` and
//! `[registers]`. The loop reads STATUS through the AXI4-Lite slave every 10 us and writes
//! back 1 to each bit it found (`System::poll_status`), and watches the top's live `flags`
//! port for the exact cycle. For each fault: its bit is raised after the fault starts (at
//! the exact cycle the flags show, within the monitor's reaction), every poll while the
//! fault lasts finds it set again (it stays set while it persists), and the poll after it
//! ends finds it clear (cleared by the write of 1). Each test names the other bits the
//! fault may raise with it. A clean run raises nothing after the start (LOS until the
//! monitor's window of good samples has passed, NOT_REFERENCED until the first index).
//! The ADC frame error, whose RTL is new, is also replayed in rust-hdl, Icarus, Verilator
//! and the engine.
use sinedec::blocks::regmap::{FAULTS, REGISTERS, STATUS_MASK};
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::dut::EngineKind;
use sinedec::sim::system::{FaultRecord, SimResult};
use sinedec::simulate::{parse_fault, status_poll_cycles, SimOptions};

/// The default top with the position reference and the register map.
fn loaded() -> Loaded {
    let text =
        format!("{DEFAULT_CONFIG}\n[reference]\nenabled = true\n\n[registers]\nenabled = true\n");
    Loaded::parse(&text, "status_faults.toml").expect("config")
}

/// Fault windows: from 200 us to 300 us in a 500 us run at 300 rpm.
const FROM: f64 = 200e-6;
const TO: f64 = 300e-6;
const RUN: f64 = 500e-6;

/// `simulate` with `faults` (the `--fault` strings) on the compiled engine.
fn simulate(l: &Loaded, faults: &[&str]) -> SimResult {
    let o = SimOptions {
        duration_s: RUN,
        engine: EngineKind::Compiled,
        keep_records: false,
        faults: faults
            .iter()
            .map(|f| parse_fault(f).expect("fault"))
            .collect(),
        ..Default::default()
    };
    sinedec::simulate::run(l, &o, |_, _| {})
        .expect("simulates")
        .result
}

fn cycle(l: &Loaded, t: f64) -> u64 {
    (t * l.derived.clock_hz).round() as u64
}

/// The record of `name`, which must exist.
fn record<'a>(r: &'a SimResult, name: &str) -> &'a FaultRecord {
    r.faults
        .iter()
        .find(|f| f.name == name)
        .unwrap_or_else(|| panic!("{name} not latched: {:#?}", r.faults))
}

/// The start-up faults: LOS (the monitor's window after reset) and NOT_REFERENCED (until
/// the first index), each raised at the start and cleared within the first 20 us.
fn assert_startup(l: &Loaded, r: &SimResult) {
    for name in ["LOS", "NOT_REFERENCED"] {
        let f = record(r, name);
        assert!(f.raised.is_some_and(|c| c <= 3), "{f:?}");
        assert!(f.after == 0 && f.polls >= 1, "{f:?}");
    }
    let nr = record(r, "NOT_REFERENCED");
    assert!(
        nr.last < cycle(l, 20e-6) && nr.rises == 1 && nr.cleared,
        "{nr:?}"
    );
}

/// `name` was raised within `react` seconds after the fault started (the exact cycle of
/// its live flag), found set by every poll while the fault lasted, and cleared by the poll
/// after it ended. `rises` is its count of rises of the live flag before the fault (the
/// start-up LOS).
fn assert_raised_and_cleared(l: &Loaded, r: &SimResult, name: &str, react: f64, before: u64) {
    let f = record(r, name);
    let period = status_poll_cycles(&l.derived);
    assert!(f.rises > before, "{name}: not raised by the fault: {f:?}");
    if before == 0 {
        let c = f.raised.expect("a live flag");
        assert!(
            c >= cycle(l, FROM) && c <= cycle(l, FROM + react),
            "{name}: raised at cycle {c}, the fault starts at {}: {f:?}",
            cycle(l, FROM)
        );
        assert!(
            f.by >= c && f.by - f.after <= period + 1 && f.after <= c,
            "{name}: the first poll's window holds the raise: {f:?}"
        );
    }
    // Set again at every poll while the fault lasted (each poll clears it).
    let lasted = ((TO - FROM - react) * l.derived.clock_hz) as u64 / period;
    assert!(
        f.polls >= lasted,
        "{name}: {} polls found it, {lasted} polls fell in the fault",
        f.polls
    );
    assert!(f.cleared, "{name}: still set after the fault: {f:?}");
    assert!(
        f.last < cycle(l, TO + 20e-6),
        "{name}: live until cycle {}",
        f.last
    );
}

/// The names latched besides the start-up ones, which must all be `allowed`.
fn assert_only(r: &SimResult, allowed: &[&str]) {
    for f in &r.faults {
        assert!(
            ["LOS", "NOT_REFERENCED"].contains(&f.name) || allowed.contains(&f.name),
            "{} latched: {:#?}",
            f.name,
            r.faults
        );
    }
}

#[test]
fn a_clean_run_latches_only_the_start() {
    let l = loaded();
    let r = simulate(&l, &[]);
    assert!(r.status_polls >= 49, "{} polls", r.status_polls);
    assert_startup(&l, &r);
    assert_only(&r, &[]);
    let los = record(&r, "LOS");
    assert!(
        los.rises == 1 && los.last < cycle(&l, 20e-6) && los.cleared,
        "{los:?}"
    );
}

#[test]
fn los_is_latched_while_the_tracks_are_weak() {
    let l = loaded();
    let r = simulate(&l, &["los@200e-6..300e-6"]);
    assert_startup(&l, &r);
    // The monitor's window of low samples (10 us at the default) before it rises.
    assert_raised_and_cleared(&l, &r, "LOS", 20e-6, 1);
    let los = record(&r, "LOS");
    assert_eq!(los.rises, 2, "{los:?}");
    // Back from the loss, the QEP cross-check may disagree for a moment.
    assert_only(&r, &["QEP_MISMATCH"]);
}

#[test]
fn clip_and_full_scale_are_latched_while_the_tracks_clip() {
    let l = loaded();
    let r = simulate(&l, &["clip@200e-6..300e-6"]);
    assert_startup(&l, &r);
    assert_raised_and_cleared(&l, &r, "FULL_SCALE", 5e-6, 0);
    assert_raised_and_cleared(&l, &r, "CLIP", 5e-6, 0);
    assert_only(&r, &["FULL_SCALE", "CLIP"]);
}

#[test]
fn a_broken_wire_latches_full_scale() {
    let l = loaded();
    let r = simulate(&l, &["broken-wire@200e-6..300e-6"]);
    assert_startup(&l, &r);
    // The sin track at 0 V is beyond the ADC's range (gain -1 about 1.65 V): full scale,
    // and the magnitude over the clip threshold.
    assert_raised_and_cleared(&l, &r, "FULL_SCALE", 5e-6, 0);
    assert_raised_and_cleared(&l, &r, "CLIP", 5e-6, 0);
    // The angle is wrong meanwhile: the QEP cross-check may disagree.
    assert_only(&r, &["FULL_SCALE", "CLIP", "QEP_MISMATCH"]);
}

#[test]
fn overspeed_is_latched_above_the_unwrap_limit() {
    let l = loaded();
    let r = simulate(&l, &["overspeed@200e-6..300e-6"]);
    assert_startup(&l, &r);
    let f = record(&r, "OVERSPEED");
    let c = f.raised.expect("a live flag");
    // The first sample taken at 1.1 x the limit steps 1.925 quadrants (one sample period
    // plus the latency after the start).
    assert!(
        c > cycle(&l, FROM) && c < cycle(&l, FROM + 5e-6),
        "raised at {c}: {f:?}"
    );
    assert!(f.polls >= 1 && f.cleared, "{f:?}");
    assert!(f.last < cycle(&l, TO + 20e-6), "{f:?}");
    assert_only(&r, &["OVERSPEED", "QEP_MISMATCH"]);
}

#[test]
fn qep_mismatch_is_latched_with_a_dead_comparator() {
    let l = loaded();
    let r = simulate(&l, &["qep-b-stuck@200e-6..300e-6"]);
    assert_startup(&l, &r);
    let f = record(&r, "QEP_MISMATCH");
    let c = f.raised.expect("a live flag");
    assert!(
        c > cycle(&l, FROM) && c < cycle(&l, TO),
        "raised at {c}: {f:?}"
    );
    assert!(f.polls >= 1 && f.cleared, "{f:?}");
    assert_only(&r, &["QEP_MISMATCH"]);
}

#[test]
fn adc_frame_is_latched_while_the_data_line_is_stuck() {
    let l = loaded();
    let r = simulate(&l, &["adc-frame@200e-6..300e-6"]);
    assert_startup(&l, &r);
    // The first frame read wholly while stuck: one sample period and the frame's latency.
    assert_raised_and_cleared(&l, &r, "ADC_FRAME", 3e-6, 0);
    // Both words read -1: the magnitude is gone, so the monitor also sees a loss of signal,
    // and the QEP cross-check may disagree on the way back.
    assert_only(&r, &["ADC_FRAME", "QEP_MISMATCH"]);
    assert_eq!(record(&r, "LOS").rises, 2);
}

#[test]
fn not_referenced_stays_latched_while_the_index_is_missing() {
    let l = loaded();
    // Out of the index at 300 rpm, back over it after a reversal: the angle leaves period
    // 0's first quadrant (where Z is high) at 24 us, turns at 150 us and is in that quadrant
    // again from 276 us to 300 us. Without the index until 250 us the first pass is lost:
    // the position homes on the way back.
    let o = SimOptions {
        duration_s: RUN,
        engine: EngineKind::Compiled,
        keep_records: false,
        profile: sinedec::sim::encoder::Profile::Reversal {
            rpm: 300.0,
            at: 100e-6,
            over: 100e-6,
        },
        faults: vec![parse_fault("no-index@0..250e-6").expect("fault")],
        ..Default::default()
    };
    let r = sinedec::simulate::run(&l, &o, |_, _| {})
        .expect("simulates")
        .result;
    let f = record(&r, "NOT_REFERENCED");
    let period = status_poll_cycles(&l.derived);
    assert!(f.raised.is_some_and(|c| c <= 3) && f.rises == 1, "{f:?}");
    // Set at every poll up to the homing (27 polls by 276 us), then cleared.
    assert!(f.polls >= cycle(&l, 270e-6) / period, "{f:?}");
    assert!(
        f.last >= cycle(&l, 276e-6) && f.last < cycle(&l, 300e-6),
        "{f:?}"
    );
    assert!(f.cleared, "{f:?}");
    assert_only(&r, &[]);
}

/// The ADC frame error replayed in four simulators: a closed loop's inputs (the chip
/// model's data line stuck high from clock 2500 to 3400, STATUS read and cleared through
/// AXI4-Lite every 300 clocks) in rust-hdl, Icarus, Verilator and the engine, all equal;
/// then the reads of STATUS in that replay: ADC_FRAME set by every read from the first
/// frame read wholly while stuck to the last one, clear before and after, and `flags_0`
/// high exactly then.
#[test]
fn adc_frame_replays_in_four_simulators() {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::cosim::CosimBlock;
    use sinedec::sim::encoder::EncoderModel;
    use sinedec::sim::system::System;
    use sinedec::verify::{block_traces, Simulators};
    let l = loaded();
    let d = &l.derived;
    let enc = EncoderModel::ideal(2048, 1.0, 300.0);
    let mut s = System::new(d, enc).expect("system");
    s.record_inputs();
    s.poll_status(300);
    let t = |c: u64| c as f64 / d.clock_hz;
    s.sdo_stuck(t(2500), t(3400), true);
    s.start().expect("settles");
    s.run(4400).expect("runs");
    let r = s.finish();
    let top = TopRtl::new(d).expect("top");
    let (ins, outs) = (top.input_ports(), top.output_ports());
    let col = |ports: &[sinedec::cosim::Port], n: &str| {
        ports
            .iter()
            .position(|p| p.name == n)
            .unwrap_or_else(|| panic!("no port {n}"))
    };
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("status_faults_adc_frame");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let tr = block_traces(top, "sd_top_rtl", "clk", &r.inputs, Simulators::ALL, &dir)
        .expect("simulators ran");
    if let Some(m) = tr.mismatch() {
        panic!("{m}");
    }
    assert_eq!(tr.rust_hdl, r.outputs, "the replay is the closed loop");
    let bit = FAULTS
        .iter()
        .find(|f| f.name == "ADC_FRAME")
        .map(|f| f.lsb)
        .expect("field");
    let status = REGISTERS
        .iter()
        .find(|r| r.name == "STATUS")
        .map(|r| r.address as u64)
        .expect("STATUS");
    let (rv, rd, fl) = (
        col(&outs, "s_axi_rvalid_0"),
        col(&outs, "s_axi_rdata_0"),
        col(&outs, "flags_0"),
    );
    let (ar, arv) = (col(&ins, "s_axi_araddr_0"), col(&ins, "s_axi_arvalid_0"));
    let reads: Vec<(usize, u64)> = (0..tr.rust_hdl.len())
        .filter(|&k| tr.rust_hdl[k][rv] == 1)
        .map(|k| (k, tr.rust_hdl[k][rd] & STATUS_MASK as u64))
        .collect();
    assert!(reads.len() >= 14, "{} reads", reads.len());
    assert!(r.inputs.iter().any(|i| i[arv] == 1 && i[ar] == status));
    // The live flag: high from the first frame read wholly while stuck (its out_valid,
    // within one period and the frame's length after 2500) to the last one.
    let live: Vec<usize> = (0..tr.rust_hdl.len())
        .filter(|&k| tr.rust_hdl[k][fl] >> bit & 1 == 1)
        .collect();
    let per = d.adc.period_clocks as usize;
    let (first, last) = (live[0], *live.last().expect("raised"));
    assert!(
        first > 2500 && first <= 2500 + 2 * per + 40,
        "first {first}"
    );
    assert!(
        last >= 3400 - per && last <= 3400 + 2 * per + 40,
        "last {last}"
    );
    assert_eq!(live.len(), last - first + 1, "high throughout");
    for &(k, v) in &reads {
        let set = v >> bit & 1 == 1;
        if k < first {
            assert!(!set, "read at {k}: {v:#x}");
        } else if k > first + 1 && k <= last {
            assert!(set, "read at {k}: set while the fault lasts: {v:#x}");
        } else if k > last + 300 + 2 {
            assert!(!set, "read at {k}: cleared after: {v:#x}");
        }
    }
}

/// Bad `--fault` values are rejected before the run, naming `--fault` and what is allowed,
/// by the library and by the command line (no panic); a good one is listed in the summary
/// with each latched fault's cycle.
#[test]
fn bad_faults_are_rejected_and_good_ones_reported() {
    let err = |s: &str| parse_fault(s).expect_err(s).to_string();
    for (s, says) in [
        ("melt", "unknown fault `melt`"),
        ("clip@soon", "start `soon`"),
        ("clip@1e-4..later", "end `later`"),
    ] {
        let e = err(s);
        assert!(e.contains("--fault") && e.contains(says), "{e}");
        assert!(e.contains("broken-wire") || e.contains("seconds"), "{e}");
    }
    let l = loaded();
    for (faults, says) in [
        (vec!["clip@-1e-4"], "allowed a start of 0 <= seconds"),
        (vec!["clip@1"], "allowed a start of 0 <= seconds"),
        (vec!["clip@2e-4..1e-4"], "an end after the start"),
        (vec!["clip@1e-4", "clip@2e-4"], "clip given twice"),
    ] {
        let o = SimOptions {
            duration_s: RUN,
            faults: faults
                .iter()
                .map(|f| parse_fault(f).expect("parses"))
                .collect(),
            ..Default::default()
        };
        let e = match sinedec::simulate::run(&l, &o, |_, _| {}) {
            Ok(_) => panic!("{faults:?} accepted"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains("--fault") && e.contains(says), "{e}");
    }
    let cap = Loaded::parse(
        include_str!("../../configs/cyclone3_capacitive.toml"),
        "cap.toml",
    )
    .expect("config");
    let o = SimOptions {
        duration_s: 3e-3,
        faults: vec![parse_fault("los").expect("parses")],
        ..Default::default()
    };
    let e = match sinedec::simulate::run_capacitive(&cap, &o, |_, _| {}) {
        Ok(_) => panic!("accepted on the capacitive path"),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("--fault") && e.contains("capacitive"), "{e}");
    // The command line.
    let bin = env!("CARGO_BIN_EXE_sinedec");
    let out = std::process::Command::new(bin)
        .args(["simulate", "--duration", "1e-4", "--fault", "melt@1e-5"])
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains("--fault") && stderr.contains("no-index") && !stderr.contains("panicked"),
        "{stderr}"
    );
    let dir = tempfile::tempdir().expect("dir");
    let cfg = dir.path().join("regs.toml");
    std::fs::write(
        &cfg,
        format!("{DEFAULT_CONFIG}\n[reference]\nenabled = true\n\n[registers]\nenabled = true\n"),
    )
    .expect("write");
    let out = std::process::Command::new(bin)
        .arg("simulate")
        .arg(&cfg)
        .args(["--duration", "2e-4", "--fault", "adc-frame@100e-6..150e-6"])
        .output()
        .expect("runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("faults injected             adc-frame from 100.0 us to 150.0 us"),
        "{stdout}"
    );
    let line = stdout
        .lines()
        .find(|l| l.starts_with("latched fault ADC_FRAME"))
        .unwrap_or_else(|| panic!("{stdout}"));
    // Raised at the first frame read wholly while stuck: 100 us plus at most a period and
    // the frame's latency, in cycles and microseconds.
    let c: u64 = line
        .split("raised at cycle ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("{line}"));
    assert!(c > cycle(&l, 100e-6) && c < cycle(&l, 103e-6), "{line}");
    assert!(
        line.contains(" us), live last at ") && line.contains("cleared"),
        "{line}"
    );
}
