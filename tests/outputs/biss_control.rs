//! BiSS C control channel (docs/biss_control.md): the CRC4 worked by hand, the protocol
//! model against the control master, and the slave (compiled engine) in the closed loop
//! with the master model (register reads and writes, a refused write, a corrupted CRC, a
//! restart mid-command), its CDS stream equal to the model's, replayed in rust-hdl, Icarus
//! and Verilator; the single-cycle data unchanged with the channel on.
use crate::biss_loop;
use crate::common;
use biss_loop::*;
use sinedec::blocks::biss::control_model::{ControlModel, Phase};
use sinedec::blocks::biss::hdl::BissSlave;
use sinedec::blocks::biss::regs::{crc4, writable, BissIdent};
use sinedec::blocks::biss::BissParams;
use sinedec::sim::biss_control::{sent_crc4, Command, Outcome, Session};
use sinedec::sim::biss_master::{BissMaster, FrameData};
use sinedec::sim::serial_line::FrameRequest;

/// The identification registers of these tests.
fn ident() -> BissIdent {
    BissIdent {
        device_id: *b"ENC123",
        manufacturer_id: *b"XY",
        profile_id: 0x1234,
        serial_number: 0xDEAD_BEEF,
        eds_bank: 5,
    }
}

/// 0x40..0x47 and 0x78..0x7F as the register map of docs/biss_control.md places the values
/// of [`ident`] (written out by hand: low bytes first for the profile ID and serial number).
const ID_40: [u8; 8] = [0x00, 0x05, 0x34, 0x12, 0xEF, 0xBE, 0xAD, 0xDE];
const ID_78: [u8; 8] = [b'E', b'N', b'C', b'1', b'2', b'3', b'X', b'Y'];

/// CTS = 1, ID = 0, address 0: message x^10. With x^4 = x + 1 (mod x^4 + x + 1):
/// x^8 = x^2 + 1, x^12 = x^8 x^4 = x^3 + x^2 + x + 1, x^14 = x^12 x^2 = x^3 + 1: remainder
/// 1001, sent inverted 0110. Address 0x42: message x^10 + x^6 + x, times x^4:
/// x^14 + x^10 + x^5 = (x^3 + 1) + (x^2 + x + 1) + (x^2 + x) = x^3: 1000, sent 0111.
/// Data 0x00: remainder 0, sent 1111 (so no control frame holds 14 zeros in a row).
#[test]
fn crc4_hand_worked() {
    assert_eq!(crc4(1 << 10, 11), 0b1001);
    assert_eq!(sent_crc4(1 << 10, 11), 0b0110);
    assert_eq!(sent_crc4((1 << 10) | 0x42, 11), 0b0111);
    assert_eq!(sent_crc4(0, 8), 0xf);
    // The slave's shift register and the master's long division agree everywhere.
    for m in 0..(1u64 << 11) {
        assert_eq!(!crc4(m, 11) & 0xf, sent_crc4(m, 11), "{m:#x}");
    }
    assert!(writable(0x00) && writable(0x3f) && writable(0x40));
    assert!(!writable(0x41) && !writable(0x7f));
}

/// The session every closed-loop test runs: all ID registers, a write and its read-back,
/// a refused write to a read-only register, a corrupted address CRC, a command abandoned
/// mid-address followed by a good one.
fn session() -> Session {
    let mut s = Session::new();
    s.command(Command::read(0x40, 8))
        .command(Command::read(0x78, 8))
        .command(Command::write(0x10, &[0xA5]))
        .command(Command::read(0x10, 1))
        .command(Command::write(0x41, &[0x77]))
        .command(Command::read(0x41, 1))
        .command(Command {
            corrupt_crc: true,
            ..Command::read(0x78, 1)
        })
        .command(Command {
            truncate: Some(9),
            ..Command::write(0x20, &[0x11])
        })
        .command(Command::read(0x7e, 2));
    s
}

fn expected_outcomes() -> Vec<Outcome> {
    vec![
        Outcome::Read(ID_40.to_vec()),
        Outcome::Read(ID_78.to_vec()),
        Outcome::Written(1),
        Outcome::Read(vec![0xA5]),
        Outcome::Refused,
        Outcome::Read(vec![0x05]),
        Outcome::Refused,
        Outcome::Truncated,
        Outcome::Read(vec![b'X', b'Y']),
    ]
}

/// The CDS per frame the model gives for a session's CDM bits (frame 0: 0).
fn model_cds(s: &mut Session) -> Vec<bool> {
    let frames = s.frames();
    let mut m = ControlModel::new(&ident());
    let mut cds = vec![false];
    for &b in &s.cdm[..frames - 1] {
        cds.push(m.step(b));
    }
    assert_eq!(m.phase(), Phase::Idle);
    cds
}

/// The protocol model answers the control master as the protocol says.
#[test]
fn model_answers_the_master() {
    let mut s = session();
    let cds = model_cds(&mut s);
    assert_eq!(s.outcomes(&cds), expected_outcomes());
    // A start bit after fewer than 14 zeros is no start; a wrong slave ID is refused.
    let mut m = ControlModel::new(&ident());
    for _ in 0..13 {
        assert!(!m.step(false));
    }
    assert!(!m.step(true), "start after 13 zeros");
    let mut s = Session::new();
    s.command(Command {
        id: 3,
        ..Command::read(0x78, 1)
    });
    let cds = model_cds(&mut s);
    assert_eq!(s.outcomes(&cds), vec![Outcome::Refused]);
}

fn params(clock: f64, control: bool) -> BissParams {
    let mut p = BissParams::new(19, 0, clock).unwrap();
    p.set_timeout_us(1.0).unwrap();
    if control {
        p.control = Some(ident());
    }
    p
}

/// Runs a session through the slave (compiled engine): every frame must be good; returns the run and
/// the frames' data.
fn run_session(p: &BissParams, s: &mut Session, ma_hz: f64) -> (Run, Vec<FrameData>) {
    run_session_with_resets(p, s, ma_hz, &[])
}

/// Clocks of the reset pulse, and how long after the master has seen the slave ready again
/// (its CDM bit taken) it starts.
const RESET_AFTER: usize = 20;
const RESET_CLOCKS: usize = 10;

/// As [`run_session`], with `rst` pulsed after each frame `r` of `resets` (in order): the
/// frame after r waits 4 us after the slave is ready, and rst is high for [`RESET_CLOCKS`]
/// clocks from [`RESET_AFTER`] clocks after the master has reported frame r (seen SL high
/// at the end of its timeout, so the slave has taken its CDM bit), well inside that pause.
fn run_session_with_resets(
    p: &BissParams,
    s: &mut Session,
    ma_hz: f64,
    resets: &[usize],
) -> (Run, Vec<FrameData>) {
    let frames = s.frames();
    let t = timing(p.clock_hz, 25.0);
    let reqs: Vec<FrameRequest> = (0..frames)
        .map(|j| {
            let r = FrameRequest {
                cdm: s.cdm.get(j).copied().unwrap_or(false),
                ..FrameRequest::new(ma_hz)
            };
            if j > 0 && resets.contains(&(j - 1)) {
                r.gap(4000.0)
            } else {
                r
            }
        })
        .collect();
    // (frame, clock at which the master had reported it) of the next reset.
    let mut pending = resets.iter().copied().peekable();
    let mut seen: Option<usize> = None;
    let ctl = move |k: usize, m: &BissMaster| {
        let mut c = Ctl::default();
        if let Some(&r) = pending.peek() {
            if m.frames().len() > r {
                let k0 = *seen.get_or_insert(k);
                c.rst = (k0 + RESET_AFTER..k0 + RESET_AFTER + RESET_CLOCKS).contains(&k);
                if k >= k0 + RESET_AFTER + RESET_CLOCKS {
                    pending.next();
                    seen = None;
                }
            }
        }
        c
    };
    let stream = Stream {
        every: 3,
        ..Default::default()
    };
    let mut m = master_for(p, t, reqs.clone());
    let run = closed_loop(p, &mut m, &stream, cycles_for(p, &reqs, 0.0), ctl, t);
    assert_eq!(run.frames.len(), frames);
    let data = run
        .frames
        .iter()
        .enumerate()
        .map(|(i, f)| {
            f.good()
                .unwrap_or_else(|| panic!("frame {i}: {f:#?}"))
                .clone()
        })
        .collect();
    (run, data)
}

/// The slave in the closed loop (compiled engine): the control master's commands give the register
/// contents, the CDS stream equals the model's, and rust-hdl, Icarus, Verilator replay the same SLO.
#[test]
fn closed_loop_register_access_four_way() {
    let p = params(50e6, true);
    let mut s = session();
    let (run, data) = run_session(&p, &mut s, 10e6);
    let cds: Vec<bool> = data.iter().map(|d| d.cds).collect();
    let first = s.commands[1].0;
    println!(
        "read of 0x78..0x7F (its first 32 frames):\n{}",
        s.transcript(&cds, first, first + 32)
    );
    assert_eq!(s.outcomes(&cds), expected_outcomes());
    assert_eq!(cds, model_cds(&mut s), "slave CDS vs model");
    let slo: Vec<Vec<u64>> = run.slo.iter().map(|&v| vec![v]).collect();
    common::replay_in_all_simulators(
        BissSlave::new(&p).unwrap(),
        "biss_slave",
        &run.rows,
        &slo,
        "biss_control",
    );
}

/// The model's CDS per frame with the slave reset after the CDM bit of each frame in
/// `resets` was taken: the reset clears the answer already registered for the next frame
/// (CDS 0) and returns the channel to idle (registers kept).
fn model_cds_with_resets(s: &mut Session, resets: &[usize]) -> Vec<bool> {
    let frames = s.frames();
    let mut m = ControlModel::new(&ident());
    let mut cds = vec![false];
    for (j, &b) in s.cdm[..frames - 1].iter().enumerate() {
        let mut c = m.step(b);
        if resets.contains(&j) {
            m.reset();
            c = false;
        }
        cds.push(c);
    }
    assert_eq!(m.phase(), Phase::Idle);
    cds
}

/// Reset in the middle of control commands, and a master that restarts during a read's
/// answer: nothing partial is performed and the next command works.
/// * rst during the data bits of a write to 0x20 (after D3's frame): the write is not
///   confirmed and not performed (0x20 still reads the 0x5A written before);
/// * rst during the answer of a read of 0x78 (after D5's frame): the master sees D7..D5 of
///   'E' (0x45: 010), then zeros: byte 0x40 with CRC 0000, a CRC error; the next read of
///   0x7E..0x7F is answered in full;
/// * the master abandons a read after 24 bits (in the slave's data answer) and, after the
///   14 zeros, reads 0x41.
///
/// The CDS stream equals the model's with the same resets, and Icarus and Verilator replay
/// the run (rst included) with the same SLO.
#[test]
fn reset_and_restart_mid_command() {
    let p = params(50e6, true);
    let mut s = Session::new();
    s.command(Command::write(0x20, &[0x5A]))
        .command(Command::write(0x20, &[0x11]))
        .command(Command::read(0x20, 1))
        .command(Command::read(0x78, 2))
        .command(Command::read(0x7e, 2))
        .command(Command {
            truncate: Some(24),
            ..Command::read(0x78, 1)
        })
        .command(Command::read(0x41, 1));
    // S 0, CTS 1, ID 2..4, A 5..11, C 12..15, R 16, W 17, data start 18, D7..D0 19..26:
    // frame j0 + 22 carries D3 of a write and is answered with D4 of a read (its answer
    // arrives in the next frame, which the reset clears).
    let resets = [s.commands[1].0 + 22, s.commands[3].0 + 22];
    let (run, data) = run_session_with_resets(&p, &mut s, 10e6, &resets);
    assert!(
        run.rows.iter().filter(|r| r[0] != 0).count() >= 3 + 2 * RESET_CLOCKS,
        "the resets were applied"
    );
    let cds: Vec<bool> = data.iter().map(|d| d.cds).collect();
    assert_eq!(
        s.outcomes(&cds),
        vec![
            Outcome::Written(1),
            Outcome::WriteUnconfirmed { index: 0 },
            Outcome::Read(vec![0x5A]),
            Outcome::ReadCrc {
                index: 0,
                got: (0x40, 0, sent_crc4(0x40, 8)),
            },
            Outcome::Read(vec![b'X', b'Y']),
            Outcome::Truncated,
            Outcome::Read(vec![0x05]),
        ]
    );
    assert_eq!(
        cds,
        model_cds_with_resets(&mut s, &resets),
        "rust-hdl CDS vs model"
    );
    let slo: Vec<Vec<u64>> = run.slo.iter().map(|&v| vec![v]).collect();
    common::replay_in_all_simulators(
        BissSlave::new(&p).unwrap(),
        "biss_slave",
        &run.rows,
        &slo,
        "biss_control_reset",
    );
}

/// At 133.33 MHz with a 12+13-bit Gray word and 3 Ack periods, and MA at 5 MHz.
#[test]
fn closed_loop_multiturn_gray_133mhz() {
    let mut p = BissParams::new(13, 12, 133.33e6).unwrap();
    p.gray = true;
    p.ack_periods = 3;
    p.set_timeout_us(1.5).unwrap();
    p.control = Some(ident());
    let mut s = Session::new();
    s.command(Command::write(0x3f, &[0x5A, 0xC3]))
        .command(Command::read(0x3e, 4));
    let (_, data) = run_session(&p, &mut s, 5e6);
    let cds: Vec<bool> = data.iter().map(|d| d.cds).collect();
    assert_eq!(
        s.outcomes(&cds),
        vec![
            // 0x40 (bank select) is writable, so both bytes go in.
            Outcome::Written(2),
            Outcome::Read(vec![0x00, 0x5A, 0xC3, 0x05]),
        ]
    );
}

/// With the channel on, every frame carries the same data, flags and CRC6 as without it:
/// only the CDS slot differs.
#[test]
fn single_cycle_data_unchanged() {
    let mut s = session();
    let (_, off) = run_session(&params(50e6, false), &mut s, 10e6);
    let mut s = session();
    let (_, on) = run_session(&params(50e6, true), &mut s, 10e6);
    assert_eq!(off.len(), on.len());
    assert!(off.iter().all(|d| !d.cds), "without the channel CDS is 0");
    assert!(on.iter().any(|d| d.cds));
    for (i, (a, b)) in off.iter().zip(&on).enumerate() {
        assert_eq!(
            (a.data, a.n_e, a.n_w, a.crc_received, a.ack_bits),
            (b.data, b.n_e, b.n_w, b.crc_received, b.ack_bits),
            "frame {i}"
        );
    }
}

// ---------------------------------------------------------------------------------------
// Config keys
// ---------------------------------------------------------------------------------------

/// The default config with `lines` added at the top of its `[biss]` table.
fn with_biss(lines: &str) -> String {
    let d = sinedec::config::DEFAULT_CONFIG;
    assert_eq!(d.matches("[biss]\n").count(), 1);
    d.replace("[biss]\n", &format!("[biss]\n{lines}\n"))
}

#[test]
fn config_keys_fill_the_registers() {
    use sinedec::config::Loaded;
    let l = Loaded::parse(&with_biss("control = true"), "ok.toml").expect("parses");
    assert_eq!(l.derived.biss.control, Some(BissIdent::default()));
    let text = with_biss(
        "control = true\ndevice_id = \"ENC123\"\nmanufacturer_id = \"XY\"\nprofile_id = 0x1234\nserial_number = 0xDEADBEEF\neds_bank = 5",
    );
    let l = Loaded::parse(&text, "ok.toml").expect("parses");
    assert_eq!(l.derived.biss.control, Some(ident()));
    let l = Loaded::parse(sinedec::config::DEFAULT_CONFIG, "ok.toml").expect("parses");
    assert_eq!(l.derived.biss.control, None, "off by default");
}

#[test]
fn bad_config_keys_are_rejected_with_their_position() {
    use common::assert_config_error;
    assert_config_error(
        &with_biss("control = true\ndevice_id = \"SEVEN77\""),
        "device_id = \"SEVEN77\"",
        &["device_id", "up to 6 printable ASCII"],
    );
    assert_config_error(
        &with_biss("control = true\nmanufacturer_id = \"é\""),
        "manufacturer_id = \"é\"",
        &["manufacturer_id", "up to 2"],
    );
    assert_config_error(
        &with_biss("control = true\nprofile_id = 65536"),
        "profile_id = 65536",
        &["profile_id", "0..=65535"],
    );
    assert_config_error(
        &with_biss("control = true\nserial_number = 0x100000000"),
        "serial_number = 0x100000000",
        &["serial_number", "0..=4294967295"],
    );
    assert_config_error(
        &with_biss("control = true\neds_bank = 256"),
        "eds_bank = 256",
        &["eds_bank", "0..=255"],
    );
    assert_config_error(
        &with_biss("eds_bank = 1"),
        "eds_bank = 1",
        &["control = true"],
    );
    assert_config_error(
        &with_biss("control = true\nregisters = 3"),
        "registers = 3",
        &["registers", "device_id"],
    );
}

/// Yosys for xc3sa and cycloneive with the channel on: no latch, clean checks (as
/// `synthesize` requires), and the flip-flops the control channel adds: armed, stp, bq 3,
/// one-hot state 12, zero run 4, bit count 4, CRC4 4, bad, R, W 3, address 7, shift 8,
/// CDS 1, the registered decodes: address + 1 7, 9 flags, the CRC register's 6 state
/// decodes and the 4 flags of its delayed step, the step's precomputed actions 21 (answer
/// 2, Idle, Start, Read, Write and Stop 10, bad 2, bit count clear and count 4, read
/// shift, write shift, write enable 3), the registered read 9 (load flag, read data 8):
/// 102 (a few fewer if Yosys merges equal flags), plus the register file's eight 8-bit
/// bank output registers (64) and its one-hot bank select (8), and no block RAM. On
/// cycloneive (no LUT RAM in Cyclone III) the 128 x 8 register file becomes 1024 more
/// flip-flops.
#[test]
fn synthesizes_for_both_families_with_control() {
    use sinedec::synth::{synthesize, Family};
    let export = |p: &BissParams| {
        let mut uut = BissSlave::new(p).unwrap();
        rust_hdl::prelude::Block::connect_all(&mut uut);
        sinedec::emit::verilog::export(&uut, "biss", "biss_slave").expect("export")
    };
    let off = export(&params(50e6, false));
    let on = export(&params(50e6, true));
    for fam in [Family::Xc3sa, Family::CycloneIve] {
        let dir = common::workdir(&format!("biss_ctl_synth_{}", fam.name()));
        let a = synthesize(&off, "biss_slave", fam, &dir).expect("synthesis");
        let b = synthesize(&on, "biss_slave", fam, &dir).expect("synthesis");
        eprintln!(
            "biss {}: off {} LUT {} FF, on {} LUT {} FF {} BRAM",
            fam.name(),
            a.luts,
            a.ffs,
            b.luts,
            b.ffs,
            b.brams
        );
        let added = b.ffs - a.ffs;
        let file = if fam == Family::CycloneIve { 1024 } else { 0 };
        assert!(
            (93 + 72 + file..=103 + 72 + file).contains(&added),
            "{added} FF added"
        );
        assert_eq!(b.brams, 0);
    }
}
