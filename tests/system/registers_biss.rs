//! The register map through the BiSS C control channel (`[registers]` with `[biss] control
//! = true`; docs/registers.md, "Through BiSS C"): a control master in the closed loop reads
//! every byte of bank 0 and checks each register against the table (ID, VERSION, the
//! latched loss of signal of the start, the live flags, POSITION / TURNS from a decoded
//! sample at the read, nothing indexed or captured, the configured threshold), reads
//! LOS_RELEASE from bank 1 and 0 from bank 4, finds the standard registers 0x40..0x7F
//! unchanged, clears STATUS, presets the position and raises the loss-of-signal threshold
//! by byte writes, reads the correction's codes from bank 1 and halves both gains (the
//! amplitude halves). A one-byte read is then replayed in rust-hdl, Verilator and the engine
//! (all equal).
use sinedec::blocks::regmap::{ID, REGISTERS, VERSION};
use sinedec::blocks::top::hdl::TopRtl;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::cosim::CosimBlock;
use sinedec::sim::biss_control::{Command, Outcome, Session};
use sinedec::sim::dut::EngineKind;
use sinedec::sim::encoder::{EncoderModel, Profile};
use sinedec::sim::system::{SimResult, System};
use sinedec::verify::{block_traces, Simulators};

/// MA clock of the control master.
const MA_HZ: f64 = 10e6;

fn config() -> Loaded {
    // The first `timeout_us` is [biss]'s.
    let text = DEFAULT_CONFIG.replacen(
        "timeout_us = 20.0\n",
        "timeout_us = 1.0\ncontrol = true\ndevice_id = \"SINDEC\"\n",
        1,
    );
    assert_ne!(text, DEFAULT_CONFIG);
    let text = format!("{text}\n[reference]\nenabled = true\n\n[registers]\nenabled = true\n");
    Loaded::parse(&text, "registers_biss.toml").expect("config")
}

fn word(name: &str) -> usize {
    REGISTERS
        .iter()
        .position(|r| r.name == name)
        .expect("register")
}

/// Runs `s` in the closed loop (1000 rpm, far from the index); returns the outcomes, the
/// clock at which each frame started, and the run.
fn run(l: &Loaded, s: &mut Session, record: bool) -> (Vec<Outcome>, Vec<u64>, SimResult) {
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = 20.0 / 2048.0;
    enc.profile = Profile::Constant { rpm: 1000.0 };
    let mut sys = System::on(d, enc, EngineKind::Compiled).expect("system");
    if record {
        sys.record_inputs();
    }
    // One frame per CDM bit, and one more for the last answer.
    let frames = s.frames();
    let mut cdm = s.cdm.clone();
    cdm.resize(frames, false);
    let m = sys.biss_session(MA_HZ, &cdm);
    sys.start().expect("settles");
    let mut k = 0;
    while m.borrow().frames().len() < frames {
        sys.run(20_000).expect("runs");
        k += 1;
        assert!(
            k < 1000,
            "the master stopped at frame {}",
            m.borrow().frames().len()
        );
    }
    let fr = m.borrow();
    let cds: Vec<bool> = fr
        .frames()
        .iter()
        .map(|f| f.good().expect("a good frame").cds)
        .collect();
    let starts = fr
        .frames()
        .iter()
        .map(|f| (f.t_start_ns * d.clock_hz * 1e-9) as u64)
        .collect();
    drop(fr);
    (s.outcomes(&cds), starts, sys.finish())
}

fn bytes(o: &Outcome) -> Vec<u8> {
    match o {
        Outcome::Read(b) => b.clone(),
        other => panic!("not read: {other:?}"),
    }
}

fn le(b: &[u8], w: usize) -> u32 {
    u32::from_le_bytes([b[4 * w], b[4 * w + 1], b[4 * w + 2], b[4 * w + 3]])
}

#[test]
fn every_register_reads_and_writes_through_the_biss_control_channel() {
    let l = config();
    let d = &l.derived;
    // The default config's gains are 1.0: code 2^GF; half of it as GAIN_SIN's two low bytes.
    let gf = d.correction.gain_frac_bits();
    let half = (1u16 << (gf - 1)).to_le_bytes();
    let half = u16::from_le_bytes(half);
    let mut s = Session::new();
    s.command(Command::read(0x00, 64))
        .command(Command::write(0x40, &[1]))
        .command(Command::read(0x00, 4))
        .command(Command::write(0x40, &[4]))
        .command(Command::read(0x3c, 4))
        .command(Command::write(0x40, &[0]))
        .command(Command::read(0x78, 8))
        .command(Command::write(0x08, &[0xff]))
        .command(Command::read(0x08, 4))
        .command(Command::write(0x28, &[0x01]))
        .command(Command::read(0x0c, 4))
        // LOS_THRESHOLD far above the amplitude: the monitor reports a loss of signal.
        .command(Command::write(0x3c, &[0xff, 0xff, 0xff, 0x7f]))
        .command(Command::write(0x08, &[0xff]))
        .command(Command::read(0x08, 1))
        // Bank 1: the correction's codes (map 0x48..0x5B), then both gains halved.
        .command(Command::write(0x40, &[1]))
        .command(Command::read(0x08, 20))
        .command(Command::write(0x10, &half.to_le_bytes()))
        .command(Command::write(0x14, &half.to_le_bytes()))
        .command(Command::write(0x40, &[0]))
        .command(Command::read(0x10, 4));
    assert!(
        d.describe().contains(
            "control channel 0x00..0x3F = the map's bytes 64 x bank (bank select 0x40; banks 0..=3)"
        ),
        "check prints the banks"
    );
    let first_read = s.commands[0].0;
    let (out, starts, res) = run(&l, &mut s, false);
    println!("{out:?}");
    let b0 = bytes(&out[0]);
    assert_eq!(b0.len(), 64);
    let f = d.fine_bits;
    let reg = |name: &str| le(&b0, word(name));
    assert_eq!(reg("ID"), ID);
    assert_eq!(&b0[0..4], b"CEDS", "ID low byte first");
    assert_eq!(reg("VERSION"), VERSION);
    assert_eq!(
        reg("STATUS") & 1,
        1,
        "the start's loss of signal is latched"
    );
    assert_eq!(
        reg("FLAGS") & 0b111_1111,
        0,
        "no fault, not referenced, no fallback"
    );
    assert!(
        reg("AMPLITUDE") > 1000,
        "the CORDIC magnitude: {}",
        reg("AMPLITUDE")
    );
    // POSITION and TURNS: one decoded sample, from around the frame whose start bit began
    // the read of byte 0x14 (frame 18 + 14 * 0x14 of the command).
    let at = starts[first_read + 18 + 14 * 0x14];
    let (pos, turns) = (reg("POSITION") as u64, reg("TURNS") as i32 as i64);
    let near: Vec<_> = res
        .records
        .iter()
        .filter(|r| r.cycle + 2000 >= at && r.cycle <= at + 2000)
        .collect();
    assert!(!near.is_empty());
    assert!(
        near.iter().any(|r| r.position == pos && r.turns == turns),
        "POSITION 0x{pos:x} / TURNS {turns} is no sample near clock {at}: {:?}",
        near.iter()
            .map(|r| (r.position, r.turns))
            .collect::<Vec<_>>()
    );
    assert_eq!(reg("VELOCITY"), 0, "no [velocity]");
    for name in [
        "INDEX_POSITION",
        "INDEX_TURNS",
        "PRESET",
        "CAPTURE_POSITION",
        "CAPTURE_TURNS",
        "CAPTURE_VELOCITY",
        "CAPTURE_AGE",
    ] {
        assert_eq!(
            reg(name),
            0,
            "{name}: nothing indexed or captured, PRESET reads 0"
        );
    }
    assert_eq!(
        reg("LOS_THRESHOLD") as u64,
        d.monitor.los_threshold(),
        "the configured loss-of-signal threshold"
    );
    // Bank 1 starts with LOS_RELEASE (map 0x40); bank 4 is beyond the map.
    assert_eq!(out[1], Outcome::Written(1));
    assert_eq!(
        le(&bytes(&out[2]), 0) as u64,
        d.monitor.los_release(),
        "bank 1, address 0: LOS_RELEASE"
    );
    assert_eq!(bytes(&out[4]), vec![0; 4], "bank 4 (beyond the map)");
    // The standard registers stay: device ID "SINDEC", manufacturer "SD".
    assert_eq!(bytes(&out[6]), b"SINDECSD".to_vec());
    // STATUS cleared by a byte write (the loss of signal is gone); PRESET references.
    assert_eq!(out[7], Outcome::Written(1));
    // Only NOT_REFERENCED (bit 10, byte 1) remains: still present before the preset.
    assert_eq!(
        le(&bytes(&out[8]), 0),
        1 << 10,
        "STATUS after writing 0xff to its byte 0"
    );
    assert_eq!(out[9], Outcome::Written(1));
    assert_eq!(out[11], Outcome::Written(4));
    assert_eq!(
        bytes(&out[13])[0] & 1,
        1,
        "LOS after LOS_THRESHOLD was raised (and STATUS cleared)"
    );
    // The correction's codes: the configured offsets 0, gains 2^GF, phase 0; halving both
    // gains halves the CORDIC magnitude.
    let codes = bytes(&out[15]);
    assert_eq!(
        (0..5).map(|w| le(&codes, w)).collect::<Vec<_>>(),
        vec![0, 0, 1 << gf, 1 << gf, 0],
        "OFFSET_SIN, OFFSET_COS, GAIN_SIN, GAIN_COS, PHASE through bank 1"
    );
    let (before, after) = (reg("AMPLITUDE") as f64, le(&bytes(&out[19]), 0) as f64);
    assert!(
        (0.47..0.53).contains(&(after / before)),
        "AMPLITUDE {before} -> {after} with both gains halved"
    );
    let flags = le(&bytes(&out[10]), 0);
    assert_eq!(
        flags >> 6 & 1,
        1,
        "REFERENCED after the PRESET write: 0x{flags:x}"
    );
    let (pq, pt) = d.reference.as_ref().expect("reference").preset();
    let first = res
        .records
        .iter()
        .find(|r| r.referenced)
        .expect("a referenced sample");
    assert_eq!(
        (first.position >> f, first.turns),
        (pq, pt as i64),
        "the first referenced sample reads the preset count"
    );
}

/// The top with the channel in the map replayed: one read of POSITION's byte 0 (the bank
/// address, the snapshot and the byte's way back), about 40,000 clocks, in rust-hdl,
/// Verilator and the engine. Not in Icarus: it runs this top at about 50 clocks a second
/// on the 2-core machine (a 900 s time-out at 40,000 clocks); the map's byte port is
/// co-simulated four ways, Icarus included, by `tests/blocks/regmap.rs`.
#[test]
fn biss_register_access_is_equal_in_rust_hdl_verilator_and_the_engine() {
    let l = config();
    let d = &l.derived;
    let mut s = Session::new();
    s.command(Command::read(0x14, 1));
    let (out, _, res) = run(&l, &mut s, true);
    assert!(matches!(out[0], Outcome::Read(_)), "{out:?}");
    let rows = res.inputs;
    println!("{} clocks", rows.len());
    let top = TopRtl::new(d).expect("top");
    assert!(top.input_ports().iter().any(|p| p.name == "biss_ma"));
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("registers_biss");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let sims = Simulators {
        icarus: false,
        ..Simulators::ALL
    };
    let t = block_traces(top, "sd_top_rtl", "clk", &rows, sims, &dir).expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
}
