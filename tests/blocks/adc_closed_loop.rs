//! SPI ADC controller: parameters and limits, closed loop with the LTC1407A-1 chip model in
//! the rust-hdl simulation (every delivered sample equals the code the chip sampled, at the
//! predicted latency, back to back, across resets, no protocol violation), a generic SPI
//! ADC in closed loop with an independent slave model, and rust-hdl == Icarus == Verilator
//! (the MISO sequence of the closed loop replayed as stimulus) for both presets.
//!
//! (Second half of the tests of `tests/blocks/adc.rs`; helpers in `tests/blocks/adc_util/`.)
use crate::adc_util;
use crate::common;
use adc_util::*;
use sinedec::blocks::adc::hdl::AdcController;
use sinedec::blocks::adc::AdcParams;
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::sim::ltc1407a::{Ltc1407a, ViolationKind};
use sinedec::verify::{block_traces, Simulators};

#[test]
fn chip_model_flags_a_controller_that_breaks_the_timing() {
    // SCK of 2 clocks at 133.33 MHz (66.7 MHz) bypassing validate(): the model must report
    // it and the data read 15 ns after the shifting edge (t8 = 8 ns is met, but the SCK is
    // too fast) still decode; then a period one SCK short of the acquisition time.
    let p = AdcParams::ltc1407a(F133, 2, None);
    assert!(p.validate().is_err());
    let mut chip = ltc_with_list(F133, code_list(20, 1), 2);
    let cycles = 2 + p.startup_clocks() as usize + 5 * p.period_clocks as usize;
    closed_loop(&p, &mut chip, &|k| (k < 2, true), cycles);
    assert!(chip
        .violations()
        .iter()
        .any(|v| v.kind == ViolationKind::SckTooFast));
    // Period of 33 SCK: CONV comes 30 ns after the 32nd rise, and the second CONV of a
    // too-short period is ignored when it arrives before the 32nd edge.
    let mut p = AdcParams::ltc1407a(F133, 3, None);
    p.frame.frame_sck = 33;
    p.period_clocks = 33 * 3;
    let mut chip = ltc_with_list(F133, code_list(20, 1), 2);
    let cycles = 2 + p.startup_clocks() as usize + 5 * p.period_clocks as usize;
    closed_loop(&p, &mut chip, &|k| (k < 2, true), cycles);
    assert!(chip
        .violations()
        .iter()
        .any(|v| v.kind == ViolationKind::AcquisitionTooShort));
    let mut p = AdcParams::ltc1407a(F133, 3, None);
    p.period_clocks = 31 * 3;
    p.frame.frame_sck = 31;
    p.frame.offsets = [2, 16];
    let mut chip = ltc_with_list(F133, code_list(20, 1), 2);
    let cycles = 2 + p.startup_clocks() as usize + 5 * p.period_clocks as usize;
    closed_loop(&p, &mut chip, &|k| (k < 2, true), cycles);
    assert!(chip
        .violations()
        .iter()
        .any(|v| v.kind == ViolationKind::ConvBeforeConversionDone));
}

#[test]
fn reading_too_early_gives_wrong_data() {
    // A controller that captures one clock after the shifting edge (7.5 ns < t8 = 8 ns)
    // reads undefined bits: emulate it by shifting the chip's answer one clock earlier.
    struct Early(Ltc1407a, std::collections::VecDeque<bool>);
    impl Slave for Early {
        fn step(&mut self, conv: bool, sck: bool) -> bool {
            // Delay the chip's answers by two clocks: the controller, capturing three
            // clocks after the shifting edge, then sees the level one clock (7.5 ns) after
            // it, inside the t8 window.
            self.1.push_back(self.0.step(conv, sck));
            if self.1.len() > 2 {
                self.1.pop_front().unwrap_or(false)
            } else {
                false
            }
        }
    }
    let p = AdcParams::ltc1407a_fastest(F133).expect("feasible");
    let codes = code_list(30, 4);
    let mut chip = Early(ltc_with_list(F133, codes.clone(), 4), Default::default());
    let cycles = 2 + p.startup_clocks() as usize + 20 * p.period_clocks as usize;
    let run = closed_loop(&p, &mut chip, &|k| (k < 2, true), cycles);
    let s = run.samples(14);
    let wrong = s
        .iter()
        .enumerate()
        .filter(|(j, &(_, a, b))| [a, b] != [codes[*j][0] as i64, codes[*j][1] as i64])
        .count();
    assert!(wrong > s.len() / 2, "only {wrong} of {} wrong", s.len());
}

#[test]
fn generic_one_channel_offset_binary_cs_framed() {
    let p = generic_one_channel();
    generic_closed_loop(&p, 30);
    println!("{}", p.describe());
}

#[test]
fn generic_two_channels_cpha1_asymmetric_sck() {
    let p = generic_two_channels();
    generic_closed_loop(&p, 30);
    println!("{}", p.describe());
}

#[test]
fn generic_two_lines_cs_framed_mode3() {
    let p = generic_two_lines();
    // The Verilog of a one-line frame has no adc_miso_b; a two-line one has it.
    assert_eq!(AdcController::new(&p).adc_miso_b.len(), 1);
    assert!(AdcController::new(&generic_two_channels())
        .adc_miso_b
        .is_empty());
    generic_closed_loop(&p, 30);
    println!("{}", p.describe());
}

#[test]
fn cosim_ltc1407a_fastest_divider_with_resets() {
    let p = AdcParams::ltc1407a_fastest(F133).expect("feasible");
    let per = p.period_clocks as usize;
    let resets = [(3 + per * 4 + 40, 2usize), (3 + per * 9 + 97, 1)];
    let drop_at = 3 + per * 14 + 20;
    let sched = move |k: usize| {
        let rst = k < 3 || resets.iter().any(|&(a, n)| k >= a && k < a + n);
        (rst, !(k >= drop_at && k < drop_at + 9))
    };
    let mut chip = ltc_with_list(F133, code_list(100, 21), 21);
    let run = closed_loop(&p, &mut chip, &sched, 3 + per * 20);
    assert!(chip.violations().is_empty());
    assert!(check_against_chip(&p, &run, &chip) >= 8);
    cosim(&p, &run, "adc_ltc133");
}

#[test]
fn cosim_ltc1407a_50mhz() {
    let p = AdcParams::ltc1407a_fastest(F50).expect("feasible");
    let per = p.period_clocks as usize;
    let mut chip = ltc_with_list(F50, code_list(100, 22), 22);
    let run = closed_loop(
        &p,
        &mut chip,
        &|k| (k < 2 || k == 2 + per * 5 + 33, true),
        per * 16,
    );
    assert!(chip.violations().is_empty());
    assert!(check_against_chip(&p, &run, &chip) >= 8);
    cosim(&p, &run, "adc_ltc50");
}

#[test]
fn cosim_generic_presets() {
    for (p, top) in [
        (generic_one_channel(), "adc_gen1"),
        (generic_two_channels(), "adc_gen2"),
        (generic_two_lines(), "adc_gen2l"),
    ] {
        let run = generic_closed_loop(&p, 12);
        // Add a reset in the middle of a frame and random MISO afterwards.
        let mut rows = run.rows.clone();
        let mut r = SplitMix64(5);
        let at = rows.len() / 2 + 7;
        for (k, row) in rows.iter_mut().enumerate() {
            if k >= at && k < at + 2 {
                row[0] = 1;
            }
            if k >= at {
                for bit in row.iter_mut().skip(2) {
                    *bit = r.next_u64() & 1;
                }
            }
        }
        let dir = common::workdir(top);
        let t = block_traces(
            AdcController::new(&p),
            top,
            "clk",
            &rows,
            Simulators::ALL,
            &dir,
        )
        .expect("simulators ran");
        if let Some(m) = t.mismatch() {
            panic!("{top}: {m}");
        }
        assert_eq!(t.rust_hdl[..at], run.outs[..at], "{top}");
        assert!(
            t.rust_hdl.iter().skip(at).any(|o| o[2] == 1),
            "{top}: restarts"
        );
    }
}

/// 16-bit codes for the CS-framed chips: the extremes first, then pseudo-random.
fn codes16(seed: u64) -> impl FnMut(u64, f64) -> [i32; 2] {
    let mut r = SplitMix64(seed);
    move |k, _| match k {
        0 => [-32768, 32767],
        1 => [32767, -32768],
        2 => [0, -1],
        _ => [r.range(-32768, 32767) as i32, r.range(-32768, 32767) as i32],
    }
}

/// The fastest SCK divider the chip allows at `clock_hz`.
fn fastest(clock_hz: f64, min_period_ns: f64) -> u32 {
    ((min_period_ns * clock_hz / 1e9) - 1e-9).ceil().max(2.0) as u32
}

/// 25 frames of a CS-framed chip read by the controller at `p` (validated): no timing
/// violation, every frame read, every sample the chip's code at the derived latency.
fn reads_on_time(p: &AdcParams, chip: &mut sinedec::sim::cs_adc::CsAdc) -> Run {
    p.validate().expect("feasible");
    println!("{}", p.describe());
    let (run, wrong, n) = cs_closed_loop(p, chip, 25);
    assert!(
        chip.violations().is_empty(),
        "{:?}",
        &chip.violations()[..1]
    );
    assert_eq!((n, wrong), (25, 0));
    assert_eq!(check_against_cs_chip(p, &run, chip), 25);
    run
}

#[test]
fn ads8354_closed_loop_at_100mhz() {
    use sinedec::sim::ads8354::ads8354;
    let d = fastest(
        100e6,
        sinedec::blocks::adc::AdcTiming::ADS8354.sck_min_period_ns,
    );
    let p = AdcParams::ads8354(100e6, d, None);
    let run = reads_on_time(&p, &mut ads8354(100e6, 5).with_codes(codes16(31)));
    // The extremes reach the outputs.
    let s = run.samples(16);
    assert!(s.iter().any(|x| (x.1, x.2) == (-32768, 32767)));
    // The SCK one clock faster than the data sheet allows: the chip records it (and the
    // conversion is not over when the MSB leaves), so the loop above would fail.
    let p = AdcParams::ads8354(100e6, d - 1, None);
    assert!(p.validate().is_err(), "validate refuses it too");
    let mut chip = ads8354(100e6, 5).with_codes(codes16(31));
    let (_, wrong, n) = cs_closed_loop(&p, &mut chip, 10);
    let kinds: Vec<_> = chip.violations().iter().map(|v| v.kind).collect();
    use sinedec::sim::cs_adc::CsViolationKind as K;
    assert!(kinds.contains(&K::SclkTooFast), "{kinds:?}");
    assert!(wrong * 2 >= n, "only {wrong} of {n} wrong");
}

#[test]
fn ad7380_closed_loop_at_100mhz() {
    use sinedec::sim::ad7380::ad7380;
    let d = fastest(
        100e6,
        sinedec::blocks::adc::AdcTiming::AD7380.sck_min_period_ns,
    );
    let p = AdcParams::ad7380(100e6, d, None);
    reads_on_time(&p, &mut ad7380(100e6, 6).with_codes(codes16(32)));
    // The capture one system clock early (the chip's answers seen one clock later, so
    // the controller samples D - 1 clocks after the shifting edge): wrong data.
    struct Early(sinedec::sim::cs_adc::CsAdc, [bool; 2]);
    impl Slave for Early {
        fn step(&mut self, conv: bool, sck: bool) -> bool {
            self.step_lines(conv, sck)[0]
        }
        fn step_lines(&mut self, conv: bool, sck: bool) -> [bool; 2] {
            let now = self.0.step(conv, sck);
            std::mem::replace(&mut self.1, now)
        }
    }
    let mut early = Early(ad7380(100e6, 6).with_codes(codes16(32)), [false; 2]);
    let cycles = 3 + p.startup_clocks() as usize + 24 * p.period_clocks as usize + 1;
    let run = closed_loop(&p, &mut early, &|k| (k < 3, true), cycles);
    let lat = p.conv_to_valid_clocks() as usize;
    let s = run.samples(16);
    let wrong = s
        .iter()
        .filter(|&&(row, a, b)| {
            !early.0.conversions().iter().any(|c| {
                c.clock as usize + 1 + lat == row
                    || (c.clock as usize + lat == row
                        && [a, b] == [c.codes[0] as i64, c.codes[1] as i64])
            })
        })
        .count();
    assert!(wrong * 2 >= s.len(), "only {wrong} of {} wrong", s.len());
}

#[test]
fn cosim_ads8354_and_ad7380() {
    use sinedec::sim::{ad7380::ad7380, ads8354::ads8354};
    let p = AdcParams::ads8354(100e6, 5, None);
    let mut chip = ads8354(100e6, 5).with_codes(codes16(41));
    let (run, wrong, _) = cs_closed_loop(&p, &mut chip, 8);
    assert_eq!(wrong, 0);
    cosim(&p, &run, "adc_ads8354");
    let p = AdcParams::ad7380(100e6, 2, None);
    let mut chip = ad7380(100e6, 6).with_codes(codes16(42));
    let (run, wrong, _) = cs_closed_loop(&p, &mut chip, 8);
    assert_eq!(wrong, 0);
    cosim(&p, &run, "adc_ad7380");
}
