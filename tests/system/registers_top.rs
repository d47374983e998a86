//! The register map in `<name>_top` (`[registers] enabled`): a closed-loop run's inputs
//! with AXI4-Lite requests added are replayed in rust-hdl, Icarus, Verilator and the engine
//! (all equal), and the registers' effect on the decoder is read off the replay: POSITION
//! equals the parallel bus, STATUS latched the loss of signal of the start and clears,
//! a PRESET write references the position as the `preset` pin does, GAIN_SIN and GAIN_COS
//! read the configured gain and, halved, halve AMPLITUDE.
use sinedec::blocks::regmap::{flag_bit, ID, REGISTERS, STATUS_MASK};
use sinedec::blocks::top::hdl::TopRtl;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::cosim::CosimBlock;
use sinedec::sim::encoder::{EncoderModel, Profile};
use sinedec::sim::system::System;
use sinedec::verify::{block_traces, Simulators};

fn addr(name: &str) -> u64 {
    REGISTERS
        .iter()
        .find(|r| r.name == name)
        .map(|r| r.address as u64)
        .expect("register")
}

#[test]
fn registers_read_the_decoder_and_preset_it_in_four_simulators() {
    let text =
        format!("{DEFAULT_CONFIG}\n[reference]\nenabled = true\n\n[registers]\nenabled = true\n");
    let l = Loaded::parse(&text, "registers_top.toml").expect("config");
    let d = &l.derived;
    // Far from the index (period 20), so only the preset references.
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = 20.0 / 2048.0;
    enc.profile = Profile::Constant { rpm: 1000.0 };
    let mut s = System::new(d, enc).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    let cycles = 4000;
    s.run(cycles).expect("runs");
    let mut rows = s.finish().inputs;
    let top = TopRtl::new(d).expect("top");
    let ins = top.input_ports();
    let outs = top.output_ports();
    let col = |ports: &[sinedec::cosim::Port], n: &str| {
        ports
            .iter()
            .position(|p| p.name == n)
            .unwrap_or_else(|| panic!("no port {n}"))
    };
    let i = |n: &str| col(&ins, n);
    // The master: responses always taken; each request a one-clock valid while the slave
    // is idle (its ready is up then), at least 8 clocks apart.
    for r in rows.iter_mut() {
        r[i("s_axi_bready_0")] = 1;
        r[i("s_axi_rready_0")] = 1;
        r[i("s_axi_wstrb_0")] = 0xf;
    }
    let mut reads: Vec<(usize, &str)> = vec![];
    let mut read = |rows: &mut Vec<Vec<u64>>, at: usize, name: &'static str| {
        rows[at][i("s_axi_araddr_0")] = addr(name);
        rows[at][i("s_axi_arvalid_0")] = 1;
        reads.push((at, name));
    };
    let write = |rows: &mut Vec<Vec<u64>>, at: usize, name: &str, v: u64| {
        rows[at][i("s_axi_awaddr_0")] = addr(name);
        rows[at][i("s_axi_awvalid_0")] = 1;
        rows[at][i("s_axi_wdata_0")] = v;
        rows[at][i("s_axi_wvalid_0")] = 1;
    };
    read(&mut rows, 100, "ID");
    read(&mut rows, 120, "STATUS");
    for k in 0..10 {
        read(&mut rows, 1500 + 211 * k, "POSITION");
    }
    write(&mut rows, 2000, "STATUS", STATUS_MASK as u64);
    read(&mut rows, 2020, "STATUS");
    read(&mut rows, 2030, "FLAGS");
    write(&mut rows, 2500, "PRESET", 1);
    // The correction's gains: the configured 1.0 (2^GF), then both halved.
    let one = 1u64 << d.correction.gain_frac_bits();
    read(&mut rows, 2800, "AMPLITUDE");
    read(&mut rows, 2810, "GAIN_SIN");
    write(&mut rows, 2900, "GAIN_SIN", one / 2);
    write(&mut rows, 2910, "GAIN_COS", one / 2);
    read(&mut rows, 2920, "GAIN_COS");
    read(&mut rows, 3500, "FLAGS");
    read(&mut rows, 3900, "AMPLITUDE");
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("registers_top");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let t = block_traces(top, "sd_top_rtl", "clk", &rows, Simulators::ALL, &dir)
        .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    let o = |n: &str| col(&outs, n);
    let tr = &t.rust_hdl;
    // Each read's data: the first clock with rvalid after its request.
    let data = |at: usize| -> u64 {
        let k = (at..tr.len())
            .find(|&k| tr[k][o("s_axi_rvalid_0")] == 1)
            .expect("a response");
        assert!(k <= at + 3, "the read answered within 3 clocks");
        tr[k][o("s_axi_rdata_0")]
    };
    let f = d.fine_bits;
    for &(at, name) in &reads {
        let v = data(at);
        match name {
            "ID" => assert_eq!(v, ID as u64),
            "POSITION" => {
                // The parallel bus's position in the clock the data was taken (or the one
                // after, if a sample arrived just then).
                let par = |k: usize| (tr[k][o("par_qc")] << f) | tr[k][o("par_fine")];
                assert!(
                    v == par(at) || v == par(at + 1),
                    "POSITION {v} at {at}: par {} / {}",
                    par(at),
                    par(at + 1)
                );
            }
            _ => {}
        }
    }
    let by = |at: usize| data(at);
    // Loss of signal until the monitor's window of good samples passed: latched at 120.
    assert_eq!(by(120) & 1, 1, "STATUS.LOS latched at the start");
    let not_ref = flag_bit("NOT_REFERENCED") as u64;
    assert_eq!(
        by(2020) & STATUS_MASK as u64,
        not_ref,
        "STATUS cleared, no fault since but NOT_REFERENCED, set again (not homed)"
    );
    let refd = flag_bit("REFERENCED") as u64;
    assert_eq!(by(2030) & refd, 0, "not referenced before the preset");
    assert_eq!(
        by(2030) & not_ref,
        not_ref,
        "FLAGS.NOT_REFERENCED before it"
    );
    assert_eq!(by(3500) & refd, refd, "referenced after the PRESET write");
    assert_eq!(by(2810), one, "GAIN_SIN: the configured gain 1.0");
    assert_eq!(by(2920), one / 2, "GAIN_COS as written");
    let ratio = by(3900) as f64 / by(2800) as f64;
    assert!(
        (0.47..0.53).contains(&ratio),
        "AMPLITUDE x {ratio} after halving both gains"
    );
    assert_eq!(by(3500) & not_ref, 0, "FLAGS.NOT_REFERENCED clear");
    let pin = o("referenced_0");
    assert!(tr[..2500].iter().all(|r| r[pin] == 0));
    assert!(tr[3000..].iter().all(|r| r[pin] == 1));
    // The live flags port is FLAGS.
    let fl = o("flags_0");
    assert!(tr[..2500].iter().all(|r| r[fl] & refd == 0));
    assert!(tr[3000..].iter().all(|r| r[fl] & (refd | not_ref) == refd));
}

/// `simulate`'s STATUS poll: the loop reads STATUS through the slave every 10 us and
/// clears it. A comparator fault (B stuck low from 150 to 350 us at 1000 rpm) makes the QEP
/// fallback disagree with the CORDIC: QEP_MISMATCH is found in a poll window that starts
/// after the fault does. The loss of signal of the start (the monitor's window after reset)
/// is found by the first poll; nothing else is latched at this speed.
#[test]
fn simulate_polls_status_and_reports_each_latched_fault() {
    use sinedec::simulate::status_poll_cycles;
    let text = format!("{DEFAULT_CONFIG}\n[registers]\nenabled = true\n");
    let l = Loaded::parse(&text, "registers_top.toml").expect("config");
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.profile = Profile::Constant { rpm: 1000.0 };
    let mut s = System::new(d, enc).expect("system");
    let period = status_poll_cycles(d);
    s.poll_status(period);
    s.qep_b_stuck_low(150e-6, 350e-6);
    s.start().expect("settles");
    s.run((500e-6 * d.clock_hz) as u64).expect("runs");
    let r = s.finish();
    let cycle = |t: f64| (t * d.clock_hz) as u64;
    assert!(r.status_polls >= 45, "{} polls", r.status_polls);
    let names: Vec<&str> = r.faults.iter().map(|f| f.name).collect();
    assert_eq!(names, ["LOS", "QEP_MISMATCH"], "{:?}", r.faults);
    let los = &r.faults[0];
    assert!(los.after == 0 && los.by <= period + 3, "{los:?}");
    let qep = &r.faults[1];
    assert!(
        qep.by > cycle(150e-6) && qep.after < cycle(350e-6) && qep.by - qep.after <= period + 1,
        "{qep:?}"
    );
}
