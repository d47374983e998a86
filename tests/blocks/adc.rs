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
use sinedec::sim::adc_pins::PinTiming;
use sinedec::sim::ltc1407a::Ltc1407a;

#[test]
fn ltc1407a_rates_and_latencies_at_the_kit_clocks() {
    let fast = AdcParams::ltc1407a_fastest(F133).expect("feasible");
    assert_eq!(fast.sck_period_clocks, 3, "44.4 MHz SCK at 133.33 MHz");
    assert_eq!(fast.period_clocks, 34 * 3, "continuous 34-SCK frames");
    // Rate from clock counts: 133.33e6 / 102.
    assert!(fast.sample_rate_hz() >= 1.2e6, "{}", fast.sample_rate_hz());
    assert!(fast.sample_rate_hz() <= 1.5e6);
    // Last capture state at pc = 32 x 3 + 2; the bit is sampled one clock later and
    // shifted in (with the strobe) one clock after that: + 1 against CONV on its pin.
    assert_eq!(fast.conv_to_valid_clocks(), 102 + 32 * 3 + 2 + 1);
    let slow = AdcParams::ltc1407a_fastest(F50).expect("feasible");
    assert_eq!(slow.sck_period_clocks, 2);
    assert_eq!(slow.period_clocks, 68);
    assert_eq!(slow.conv_to_valid_clocks(), 68 + 32 * 2 + 1 + 1);
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
        // No sample is delivered from a frame disturbed by a reset. The outputs of row a
        // leave the edge that registers the reset (rst_d), so a sample there belongs to a
        // frame completed before it (and check_against_chip proved it right).
        for &(row, _, _) in &s {
            for &(a, len) in &resets {
                assert!(
                    !(row > a && row < a + len + p.startup_clocks() as usize),
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

/// Measures the capture distance in the rust-hdl simulation: the controller is fed a
/// pseudo-random `adc_miso` level at every edge, and for every bit of every delivered
/// sample the test finds the pin edge of `adc_sck` that shifted that slot out (counted on
/// the pin trace from the CONV / chip-select edge that opens the frame) and the offset
/// `delta` such that the level applied at edge `pin edge + delta` is the bit delivered.
/// Exactly one offset must explain every bit; it is returned.
fn measured_capture_distance(p: &AdcParams) -> usize {
    use sinedec::blocks::adc::hdl::AdcController;
    use sinedec::cosim::step::{prepare, tick};
    use sinedec::cosim::stimulus::SplitMix64;
    let f = p.frame;
    let per = p.period_clocks as usize;
    let cycles = 3 + p.startup_clocks() as usize + 6 * per;
    let mut r = SplitMix64(p.sck_period_clocks as u64 * 7919 + f.width as u64);
    let miso: Vec<bool> = (0..cycles).map(|_| r.next_u64() & 1 == 1).collect();
    let mut uut = AdcController::new(p);
    prepare(&mut uut).expect("settles");
    // Pins and outputs after edge k: (sck, conv, valid, ch0, ch1).
    let mut outs = Vec::with_capacity(cycles);
    for (k, &m) in miso.iter().enumerate() {
        uut.rst.next = k < 3;
        uut.enable.next = true;
        uut.adc_miso.next = m;
        tick(&mut uut).expect("settles");
        outs.push((
            uut.adc_sck.val(),
            uut.adc_conv.val(),
            uut.out_valid.val(),
            uut.out_ch0.val().to_u64(),
            uut.out_ch1.val().to_u64(),
        ));
    }
    let active = |k: usize| outs[k].1 == f.conv_active_high;
    let mut candidates: Vec<usize> = (0..3 * p.sck_period_clocks as usize + 4).collect();
    let mut checked = 0;
    for v in (1..cycles).filter(|&k| outs[k].2) {
        // The frame: the last CONV / CS assertion on the pin before the strobe.
        let Some(start) = (1..v).rev().find(|&k| active(k) && !active(k - 1)) else {
            continue;
        };
        // Pin edges after the frame start: leading (leaving CPOL) and trailing.
        let (mut leading, mut trailing) = (vec![], vec![]);
        for k in start..v {
            if outs[k].0 != outs[k - 1].0 {
                if outs[k].0 != f.cpol {
                    leading.push(k);
                } else {
                    trailing.push(k);
                }
            }
        }
        for c in 0..f.channels as usize {
            let word = if c == 0 { outs[v].3 } else { outs[v].4 };
            let raw = if p.frame.sign == sinedec::blocks::adc::SignFormat::OffsetBinary {
                word ^ (1 << (f.width - 1))
            } else {
                word
            };
            for i in 0..f.width {
                let slot = (f.offsets[c] + i) as usize;
                // CPHA = 1: slot s leaves on the leading edge of cycle s; CPHA = 0: on the
                // trailing edge of cycle s - 1 (slot 0 at the CS edge: not an SCK edge).
                let edge = match (f.cpha, slot) {
                    (true, s) => leading[s],
                    (false, 0) => continue,
                    (false, s) => trailing[s - 1],
                };
                let bit = (raw >> (f.width - 1 - i)) & 1 == 1;
                candidates.retain(|&d| edge + d < cycles && miso[edge + d] == bit);
                checked += 1;
            }
        }
    }
    assert!(checked >= 40, "only {checked} bits delivered");
    assert_eq!(
        candidates.len(),
        1,
        "offsets explaining every bit: {candidates:?}"
    );
    candidates[0]
}

#[test]
fn capture_distance_measured_in_the_rtl_is_the_derived_one() {
    let mut cases = vec![];
    for d in [3, 4, 5, 7, 8] {
        cases.push(AdcParams::ltc1407a(F133, d, None));
    }
    cases.push(AdcParams::ltc1407a(F50, 2, None));
    for d in [3, 5, 6, 7] {
        let mut p = generic_two_channels();
        p.sck_period_clocks = d;
        p.sck_high_clocks = d / 2;
        p.period_clocks = p.min_period_clocks() + 3;
        cases.push(p);
        let mut p = generic_one_channel();
        p.sck_period_clocks = d;
        p.sck_high_clocks = d.div_ceil(2);
        p.frame.conv_clocks = p.frame.lead_clocks + p.frame.frame_sck * d + 1;
        p.conv_clocks = p.frame.conv_clocks;
        p.period_clocks = p.min_period_clocks();
        cases.push(p);
    }
    for p in &cases {
        let want = p.capture_distance_clocks() as usize;
        assert_eq!(
            want, p.sck_period_clocks as usize,
            "the documented window is D"
        );
        let got = measured_capture_distance(p);
        assert_eq!(
            got, want,
            "{} at D = {} (cpha {}): adc_sck pin edge to the miso sample",
            p.chip, p.sck_period_clocks, p.frame.cpha
        );
    }
}

/// Sweeps the chip's SCK-to-data valid delay across the capture window with the chip
/// models behind the board pins of a shipped config: every sample exact up to the limit
/// `check` prints (its slack added to the delay it assumes), every sample wrong from just
/// beyond it to one clock period beyond.
fn sweep_data_valid(
    name: &str,
    text: &str,
    run: &dyn Fn(&AdcParams, PinTiming, f64) -> (usize, usize),
) {
    let l = sinedec::config::Loaded::parse(text, "w.toml").expect("config");
    let p = l.derived.adc.clone();
    let pins = PinTiming::from_io(&l.derived.io_timing);
    let (c, slack) = check_round_trip(text);
    assert_eq!(
        c,
        p.capture_distance_clocks(),
        "{name}: check prints the distance"
    );
    let limit = p.timing.data_valid_ns + slack;
    let t = 1e9 / p.clock_hz;
    println!(
        "{name}: capture distance {c} clocks, slack {slack:.2} ns, data valid up to {limit:.2} ns"
    );
    // `check` prints the slack to 10 ps: the sweep steps around the limit by 20 ps.
    for v in [0.5 * limit, limit - 0.02] {
        let (wrong, n) = run(&p, pins, v);
        assert_eq!(
            wrong, 0,
            "{name}: data valid {v:.2} ns <= {limit:.2} ns: {wrong} of {n} wrong"
        );
    }
    for v in [limit + 0.02, limit + 0.5 * t, limit + t - 0.02] {
        let (wrong, n) = run(&p, pins, v);
        assert!(
            wrong * 4 >= n * 3,
            "{name}: data valid {v:.2} ns > {limit:.2} ns: only {wrong} of {n} wrong"
        );
    }
}

#[test]
fn the_decoder_is_exact_up_to_the_window_check_prints() {
    sweep_data_valid(
        "spartan3an (LTC1407A-1)",
        include_str!("../../configs/spartan3an.toml"),
        &|p, pins, v| ltc_wrong_samples(p, pins, v, 6),
    );
    sweep_data_valid(
        "cyclone3_capacitive (generic)",
        include_str!("../../configs/cyclone3_capacitive.toml"),
        &|p, pins, v| generic_wrong_samples(p, pins, v, 6),
    );
}

/// The chip presets from a config: the fastest SCK the chip allows, and `check` states the rate reached and what binds it.
#[test]
fn chip_presets_from_a_config_state_what_binds_the_rate() {
    use sinedec::config::{Loaded, DEFAULT_CONFIG};
    let text = |preset: &str, clock: &str, rate: Option<&str>| {
        let i = DEFAULT_CONFIG.find("\n[preamp]\n").expect("preamp table");
        let j = DEFAULT_CONFIG.find("\n[cordic]\n").expect("cordic table");
        let rate = rate
            .map(|r| format!("\nsample_rate_hz = {r}"))
            .unwrap_or_default();
        format!("{}{}", &DEFAULT_CONFIG[..i], &DEFAULT_CONFIG[j..])
            .replacen(
                "preset = \"ltc1407a-1\"",
                &format!("preset = \"{preset}\"{rate}"),
                1,
            )
            .replacen("width = 14", "width = 16", 1)
            .replacen(
                "frequency_hz = 133_330_000.0",
                &format!("frequency_hz = {clock}"),
                1,
            )
    };
    // At its fastest frame the AD7380's sample arrives with the next conversion start, too
    // late for the QEP fallback (3 clocks): refused at the preset, with the way out.
    let e = Loaded::parse(&text("ad7380", "100e6", None), "w.toml")
        .expect_err("the fastest AD7380 frame at 100 MHz is refused")
        .to_string();
    assert!(
        e.contains("key `adc.preset`")
            && e.contains("at least 3")
            && e.contains("adc.sample_rate_hz"),
        "{e}"
    );
    for (preset, clock, rate, want_d, bound) in [
        ("ads8354", "100e6", None, 5, "the clock binds"),
        (
            "ad7380",
            "100e6",
            Some("2.5e6"),
            2,
            "the configured adc.sample_rate_hz",
        ),
        // SCLK <= 20 MHz: 32 SCLK take 1.6 us > 1 / 700 ksps whatever the clock.
        ("ads8354", "400e6", None, 20, "the clock binds"),
    ] {
        let l = Loaded::parse(&text(preset, clock, rate), "w.toml")
            .unwrap_or_else(|e| panic!("{preset} {clock}: {e}"));
        let p = &l.derived.adc;
        assert_eq!(p.sck_period_clocks, want_d, "{preset} at {clock}");
        assert!(l.derived.preamp.is_none());
        let d = l.derived.describe();
        let line = d
            .lines()
            .find(|x| x.starts_with("ADC sample rate"))
            .expect("rate line");
        println!("{preset} at {clock}: {line}");
        assert!(line.contains(bound), "{line}");
        assert!(p.sample_rate_hz() <= p.timing.max_sample_rate_hz);
    }
}

/// From power-up (before the first clock edge) and through reset, the ADC pins rest at
/// their idle levels: SCK at CPOL and CONV/CS inactive. An active-low CS that powered up
/// low would select a CS-framed chip (ADS8354, AD7380) for a clock and start a frame the
/// controller never reads.
#[test]
fn adc_pins_rest_idle_from_power_up() {
    use sinedec::blocks::adc::hdl::AdcController;
    use sinedec::cosim::step::{prepare, tick};
    for p in [
        AdcParams::ltc1407a(F133, 3, None),
        AdcParams::ads8354(100e6, 5, None),
        AdcParams::ad7380(100e6, 2, None),
    ] {
        let f = p.frame;
        let mut uut = AdcController::new(&p);
        uut.rst.next = true;
        uut.enable.next = true;
        prepare(&mut uut).expect("settles");
        let idle = (f.cpol, !f.conv_active_high);
        assert_eq!(
            (uut.adc_sck.val(), uut.adc_conv.val()),
            idle,
            "{}: (sck, conv) at power-up",
            p.describe()
        );
        for k in 0..4 {
            tick(&mut uut).expect("settles");
            assert_eq!(
                (uut.adc_sck.val(), uut.adc_conv.val()),
                idle,
                "{}: (sck, conv) after reset edge {k}",
                p.describe()
            );
        }
    }
}

/// Without `adc.sck_period_clocks` the divider is the smallest that both the chip's SCK
/// limit and the ADC round trip allow: a generic 16-bit ADC (SCK-to-data 10 ns) at 100 MHz
/// gets 3 clocks (2 would capture 20 ns after the shifting edge, short of the 21 ns round
/// trip), and `check` accepts it. Setting 2 clocks is refused at that key.
#[test]
fn the_default_sck_divider_covers_the_round_trip() {
    use sinedec::config::{Loaded, DEFAULT_CONFIG};
    let i = DEFAULT_CONFIG.find("\n[preamp]\n").expect("preamp table");
    let j = DEFAULT_CONFIG.find("\n[cordic]\n").expect("cordic table");
    let text = |extra: &str| {
        format!("{}{}", &DEFAULT_CONFIG[..i], &DEFAULT_CONFIG[j..])
            .replacen(
                "preset = \"ltc1407a-1\"",
                &format!("preset = \"generic\"\nmax_sample_rate_hz = 1e6{extra}"),
                1,
            )
            .replacen("width = 14", "width = 16", 1)
            .replacen("frequency_hz = 133_330_000.0", "frequency_hz = 100e6", 1)
    };
    let l = Loaded::parse(&text(""), "g.toml").unwrap_or_else(|e| panic!("{e}"));
    let p = &l.derived.adc;
    assert_eq!(
        p.timing.data_valid_ns, 10.0,
        "the generic default's SCK-to-data"
    );
    assert_eq!(p.sck_period_clocks, 3);
    assert_eq!(p.capture_distance_clocks(), 3);
    let e = Loaded::parse(&text("\nsck_period_clocks = 2"), "g.toml")
        .expect_err("2 clocks are short of the round trip")
        .to_string();
    assert!(
        e.contains("key `adc.sck_period_clocks`") && e.contains("at least 3 clocks"),
        "{e}"
    );
}
