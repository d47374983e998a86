//! BiSS-C slave: CRC6 against hand-worked frames, the parameter checks, and the master model
//! reading the slave (compiled engine) in the closed loop of `tests/biss_loop` (positions at 100 kHz
//! to 10 MHz, flags, every single-bit error detected). Protocol corners, glitches, the
//! maximum MA rate and synthesis: `tests/outputs/biss_corners.rs`.
use crate::biss_loop;
use biss_loop::*;
use sinedec::blocks::biss::crc::{biss_crc, crc6, crc6_bits, POLY};
use sinedec::blocks::biss::hdl::BissSlave;
use sinedec::blocks::biss::BissParams;
use sinedec::blocks::mask;
use sinedec::blocks::serial::data_word;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::sim::biss_master::{expected_crc, Outcome};
use sinedec::sim::serial_line::FrameRequest;

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
// Closed loop: master model <-> slave (compiled engine; replays check rust-hdl)
// ---------------------------------------------------------------------------------------
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
