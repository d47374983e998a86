//! SPI ADC controller: parameters and limits, closed loop with the LTC1407A-1 chip model in
//! the rust-hdl simulation (every delivered sample equals the code the chip sampled, at the
//! predicted latency, back to back, across resets, no protocol violation), a generic SPI
//! ADC in closed loop with an independent slave model, and rust-hdl == Icarus == Verilator
//! (the MISO sequence of the closed loop replayed as stimulus) for both presets.
//!
//! (More tests in `tests/blocks/adc_closed_loop.rs`; the helpers are in `tests/blocks/adc_util/`.)
use crate::adc_util;
use adc_util::*;
use sinedec::blocks::adc::{AdcFrame, AdcParams, AdcTiming};
use sinedec::sim::ltc1407a::Ltc1407a;

#[test]
fn ltc1407a_rates_and_latencies_at_the_kit_clocks() {
    let fast = AdcParams::ltc1407a_fastest(F133).expect("feasible");
    assert_eq!(fast.sck_period_clocks, 3, "44.4 MHz SCK at 133.33 MHz");
    assert_eq!(fast.period_clocks, 34 * 3, "continuous 34-SCK frames");
    // Rate from clock counts: 133.33e6 / 102.
    assert!(fast.sample_rate_hz() >= 1.2e6, "{}", fast.sample_rate_hz());
    assert!(fast.sample_rate_hz() <= 1.5e6);
    assert_eq!(fast.conv_to_valid_clocks(), 102 + 32 * 3 + 2);
    let slow = AdcParams::ltc1407a_fastest(F50).expect("feasible");
    assert_eq!(slow.sck_period_clocks, 2);
    assert_eq!(slow.period_clocks, 68);
    assert_eq!(slow.conv_to_valid_clocks(), 68 + 32 * 2 + 1);
    println!(
        "--- 133.33 MHz\n{}--- 50 MHz\n{}",
        fast.describe(),
        slow.describe()
    );
}

#[test]
fn infeasible_settings_are_rejected_with_the_reason() {
    let e = AdcParams::ltc1407a(F133, 2, None)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("limit") && e.contains("at least 3 clocks"),
        "{e}"
    );
    let e = AdcParams::ltc1407a(F133, 3, Some(100))
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("shorter than the frame"), "{e}");
    let e = AdcParams::ltc1407a(F133, 1, None)
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("2..=255"), "{e}");
    // 300 MHz: one clock of CONV is 3.3 ns < 4 ns; force it.
    let mut p = AdcParams::ltc1407a(300e6, 6, None);
    p.conv_clocks = 1;
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("CONV pulse"), "{e}");
    // A conversion period that leaves too little acquisition time.
    let mut p = AdcParams::ltc1407a(F133, 3, None);
    p.frame.frame_sck = 33; // 32nd rise to CONV only 7 clocks... still a legal frame
    p.period_clocks = 33 * 3;
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("acquisition"), "{e}");
    // Above the chip's per-channel rate.
    let mut t = AdcTiming::LTC1407A_1;
    t.max_sample_rate_hz = 1.0e6;
    let p = AdcParams::generic(F133, AdcFrame::LTC1407A_1, t, 3, Some(102));
    let e = p.validate().unwrap_err().to_string();
    assert!(e.contains("above the ADC limit"), "{e}");
    // Frame format errors.
    let mut f = AdcFrame::LTC1407A_1;
    f.width = 17;
    assert!(AdcParams::generic(F133, f, AdcTiming::LTC1407A_1, 3, None)
        .validate()
        .unwrap_err()
        .to_string()
        .contains("10..=16"));
    let mut f = AdcFrame::LTC1407A_1;
    f.offsets = [2, 10];
    assert!(AdcParams::generic(F133, f, AdcTiming::LTC1407A_1, 3, None)
        .validate()
        .unwrap_err()
        .to_string()
        .contains("overlap"));
    let mut f = AdcFrame::LTC1407A_1;
    f.offsets = [2, 25];
    assert!(AdcParams::generic(F133, f, AdcTiming::LTC1407A_1, 3, None)
        .validate()
        .unwrap_err()
        .to_string()
        .contains("do not fit"));
    // Too low a rate for the 16-bit period counter.
    let e = AdcParams::ltc1407a(F133, 3, Some(70_000))
        .validate()
        .unwrap_err()
        .to_string();
    assert!(e.contains("65535"), "{e}");
}

#[test]
fn closed_loop_fastest_divider_133mhz() {
    closed_loop_ltc(F133, 60, 11);
}

#[test]
fn closed_loop_fastest_divider_50mhz() {
    closed_loop_ltc(F50, 40, 12);
}

#[test]
fn closed_loop_slower_dividers_and_odd_periods() {
    for (d, extra) in [(4u32, 0u32), (5, 7), (7, 1)] {
        let mut p = AdcParams::ltc1407a(F133, d, None);
        p.period_clocks += extra;
        p.validate().expect("feasible");
        let codes = code_list(24, d as u64);
        let mut chip = ltc_with_list(F133, codes.clone(), 5);
        let cycles = 2 + p.startup_clocks() as usize + 19 * p.period_clocks as usize + 1;
        let run = closed_loop(&p, &mut chip, &|k| (k < 2, true), cycles);
        assert!(
            chip.violations().is_empty(),
            "D={d}: {:?}",
            chip.violations()
        );
        let s = run.samples(14);
        assert_eq!(s.len(), 20, "D={d}");
        for (j, &(_, a, b)) in s.iter().enumerate() {
            assert_eq!(
                [a, b],
                [codes[j][0] as i64, codes[j][1] as i64],
                "D={d} sample {j}"
            );
        }
    }
}

#[test]
fn reset_and_enable_mid_frame() {
    for clock in [F133, F50] {
        let p = AdcParams::ltc1407a_fastest(clock).expect("feasible");
        let (resets, drop_at, end) = reset_schedule(&p);
        let r2 = resets.clone();
        let sched = move |k: usize| {
            let rst = k < 3 || r2.iter().any(|&(a, n)| k >= a && k < a + n);
            let en = !(k >= drop_at && k < drop_at + 20);
            (rst, en)
        };
        let mut chip = ltc_with_list(clock, code_list(500, 3), 9);
        let run = closed_loop(&p, &mut chip, &sched, end);
        assert!(
            chip.violations().is_empty(),
            "{:.0} MHz: {:?}",
            clock / 1e6,
            chip.violations()
        );
        let n = check_against_chip(&p, &run, &chip);
        assert!(n >= 30, "{n} samples checked");
        // After the last disturbance the stream resumes at the predicted time.
        let s = run.samples(14);
        let resume = drop_at + 20 + p.startup_clocks() as usize;
        assert!(
            s.iter().any(|&(r, _, _)| r == resume),
            "resumes at row {resume}"
        );
        // No sample is delivered from a frame disturbed by a reset.
        for &(row, _, _) in &s {
            for &(a, len) in &resets {
                assert!(
                    !(row >= a && row < a + len + p.startup_clocks() as usize),
                    "sample at {row} too soon after the reset at {a}"
                );
            }
        }
    }
}

#[test]
fn voltages_through_the_preamp_gain() {
    assert_eq!(Ltc1407a::code_from_voltage(1.65, -1.0), 0);
    assert_eq!(Ltc1407a::code_from_voltage(2.9, -1.0), -8192);
    assert_eq!(Ltc1407a::code_from_voltage(0.4, -1.0), 8191, "clamped");
    assert_eq!(Ltc1407a::code_from_voltage(1.65 + 1.25 / 8192.0, -1.0), -1);
    assert_eq!(Ltc1407a::code_from_voltage(1.66, -100.0), -6554);
    assert_eq!(Ltc1407a::code_from_voltage(1.40, 1.0), -1638);
    let p = AdcParams::ltc1407a_fastest(F133).expect("feasible");
    let gain = [-2.0, -5.0];
    let mut chip = Ltc1407a::new(F133, 1).with_voltages(gain, |_, t| {
        let w = 2.0 * std::f64::consts::PI * 20e3 * t;
        [1.65 + 0.3 * w.sin(), 1.65 + 0.12 * w.cos()]
    });
    let cycles = 2 + p.startup_clocks() as usize + 30 * p.period_clocks as usize;
    let run = closed_loop(&p, &mut chip, &|k| (k < 2, true), cycles);
    assert!(chip.violations().is_empty());
    assert!(check_against_chip(&p, &run, &chip) >= 25);
    // The sampled codes follow the voltage formula at the CONV instants.
    for c in chip.conversions() {
        let t = c.clock as f64 / F133;
        let w = 2.0 * std::f64::consts::PI * 20e3 * t;
        let e = [
            Ltc1407a::code_from_voltage(1.65 + 0.3 * w.sin(), gain[0]),
            Ltc1407a::code_from_voltage(1.65 + 0.12 * w.cos(), gain[1]),
        ];
        for ch in 0..2 {
            assert!(
                (c.codes[ch] as i32 - e[ch] as i32).abs() <= 1,
                "{c:?} vs {e:?}"
            );
        }
    }
    assert!(
        run.samples(14).iter().any(|s| s.1.abs() > 1500),
        "a real swing is seen"
    );
}
