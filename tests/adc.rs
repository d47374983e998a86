//! SPI ADC controller: parameters and limits, closed loop with the LTC1407A-1 chip model in
//! the rust-hdl simulation (every delivered sample equals the code the chip sampled, at the
//! predicted latency, back to back, across resets, no protocol violation), a generic SPI
//! ADC in closed loop with an independent slave model, and rust-hdl == Icarus == Verilator
//! (the MISO sequence of the closed loop replayed as stimulus) for both presets.
use sinedec::blocks::adc::hdl::AdcController;
use sinedec::blocks::adc::model::{AdcIn, AdcModel};
use sinedec::blocks::adc::{AdcFrame, AdcParams, AdcTiming, SignFormat};
use sinedec::blocks::sext;
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::sim::ltc1407a::{Ltc1407a, ViolationKind};
use sinedec::sim::spi_adc::SpiAdc;
use sinedec::verify::{block_traces, Simulators};
mod common;

const F133: f64 = 133.33e6;
const F50: f64 = 50e6;

/// The pins a slave model sees each clock and answers with the MISO level of the next edge.
trait Slave {
    fn step(&mut self, conv: bool, sck: bool) -> bool;
}

impl Slave for Ltc1407a {
    fn step(&mut self, conv: bool, sck: bool) -> bool {
        Ltc1407a::step(self, conv, sck)
    }
}

/// Inputs of each clock: (rst, enable).
type Schedule<'a> = dyn Fn(usize) -> (bool, bool) + 'a;

/// A closed-loop run: stimulus rows [rst, enable, miso] and output rows of the controller.
struct Run {
    rows: Vec<Vec<u64>>,
    outs: Vec<Vec<u64>>,
}

impl Run {
    /// (row, ch0, ch1) of every out_valid strobe, sign-extended from `w` bits.
    fn samples(&self, w: u32) -> Vec<(usize, i64, i64)> {
        self.outs
            .iter()
            .enumerate()
            .filter(|(_, o)| o[2] == 1)
            .map(|(k, o)| (k, sext(o[3], w), sext(o[4], w)))
            .collect()
    }
    /// Rows where CONV rises.
    fn conv_rises(&self) -> Vec<usize> {
        (0..self.outs.len())
            .filter(|&k| self.outs[k][1] == 1 && (k == 0 || self.outs[k - 1][1] == 0))
            .collect()
    }
}

/// Steps the rust-hdl controller by hand, feeding MISO from `chip` (which sees the pins of
/// each clock), and checks every clock against the plain-Rust model of the controller.
fn closed_loop(p: &AdcParams, chip: &mut dyn Slave, sched: &Schedule<'_>, cycles: usize) -> Run {
    let mut uut = AdcController::new(p);
    prepare(&mut uut).expect("settles");
    let mut model = AdcModel::new(p);
    let mut miso = false;
    let mut run = Run {
        rows: Vec::with_capacity(cycles),
        outs: Vec::with_capacity(cycles),
    };
    for k in 0..cycles {
        let (rst, en) = sched(k);
        uut.rst.next = rst;
        uut.enable.next = en;
        uut.adc_miso.next = miso;
        tick(&mut uut).expect("settles");
        let o = vec![
            uut.adc_sck.val() as u64,
            uut.adc_conv.val() as u64,
            uut.out_valid.val() as u64,
            uut.out_ch0.val().to_u64(),
            uut.out_ch1.val().to_u64(),
        ];
        let m = model.step(AdcIn {
            rst,
            enable: en,
            miso,
        });
        assert_eq!(o, m.row(), "rust-hdl vs model at clock {k}");
        run.rows.push(vec![rst as u64, en as u64, miso as u64]);
        miso = chip.step(o[1] == 1, o[0] == 1);
        run.outs.push(o);
    }
    run
}

/// Random 14-bit codes, starting with the extremes and the values around zero.
fn code_list(n: usize, seed: u64) -> Vec<[i16; 2]> {
    let mut v = vec![
        [-8192, 8191],
        [8191, -8192],
        [0, -1],
        [-1, 0],
        [-8192, -8192],
        [8191, 8191],
        [1, -8191],
        [0x1555, -0x1556],
    ];
    let mut r = SplitMix64(seed);
    while v.len() < n {
        v.push([r.range(-8192, 8191) as i16, r.range(-8192, 8191) as i16]);
    }
    v
}

fn ltc_with_list(clock_hz: f64, codes: Vec<[i16; 2]>, seed: u64) -> Ltc1407a {
    Ltc1407a::new(clock_hz, seed).with_codes(move |k, _| codes[k as usize % codes.len()])
}

/// Every delivered sample equals the conversion whose CONV rise lies exactly the predicted
/// latency earlier; returns how many were checked.
fn check_against_chip(p: &AdcParams, run: &Run, chip: &Ltc1407a) -> usize {
    let lat = p.conv_to_valid_clocks() as usize;
    let s = run.samples(14);
    for &(row, a, b) in &s {
        let c = chip
            .conversions()
            .iter()
            .find(|c| c.clock as usize + lat == row)
            .unwrap_or_else(|| panic!("no CONV {lat} clocks before the sample at row {row}"));
        assert_eq!(
            [a, b],
            [c.codes[0] as i64, c.codes[1] as i64],
            "sample at row {row}"
        );
    }
    s.len()
}

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

fn closed_loop_ltc(clock_hz: f64, n: usize, seed: u64) {
    let p = AdcParams::ltc1407a_fastest(clock_hz).expect("feasible");
    let codes = code_list(n + 4, seed);
    let mut chip = ltc_with_list(clock_hz, codes.clone(), seed);
    let release = 3;
    let cycles = release + p.startup_clocks() as usize + (n - 1) * p.period_clocks as usize + 1;
    let run = closed_loop(&p, &mut chip, &|k| (k < release, true), cycles);
    assert!(
        chip.violations().is_empty(),
        "{:?}",
        &chip.violations()[..1]
    );
    let s = run.samples(14);
    assert_eq!(s.len(), n, "one sample per period");
    // First sample after reset: flush period, one discarded frame, latency.
    assert_eq!(s[0].0, release + p.startup_clocks() as usize);
    // Back to back: exactly one period apart.
    for w in s.windows(2) {
        assert_eq!(w[1].0 - w[0].0, p.period_clocks as usize);
    }
    // Sample j is conversion j, whose codes are codes[j] (the extremes come first).
    for (j, &(_, a, b)) in s.iter().enumerate() {
        assert_eq!(
            [a, b],
            [codes[j][0] as i64, codes[j][1] as i64],
            "sample {j}"
        );
    }
    assert_eq!(check_against_chip(&p, &run, &chip), n);
    // CONV: none in the flush period, then one per period, each accepted by the chip. The
    // pins are registered one clock after the state that drives them, so the first rise is
    // one clock after the flush period.
    let rises = run.conv_rises();
    assert_eq!(rises[0], release + p.period_clocks as usize + 1);
    assert_eq!(rises.len(), chip.conversions().len());
    assert!(rises
        .windows(2)
        .all(|w| w[1] - w[0] == p.period_clocks as usize));
    let rate = clock_hz / (s[1].0 - s[0].0) as f64;
    println!(
        "{:.2} MHz: SCK {} clocks, {} clocks per sample = {:.0} samples/s per channel, latency {} clocks",
        clock_hz / 1e6,
        p.sck_period_clocks,
        s[1].0 - s[0].0,
        rate,
        p.conv_to_valid_clocks()
    );
    if clock_hz == F133 {
        assert!(rate >= 1.2e6, "{rate}");
    }
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

/// Resets at many points of the flush period, the discarded frame and running frames, and
/// an enable drop: after each, the flush restarts the chip cleanly and every sample still
/// matches its conversion.
fn reset_schedule(p: &AdcParams) -> (Vec<(usize, usize)>, usize, usize) {
    let per = p.period_clocks as usize;
    let start = 3 + per * 4;
    // (first row, length) of each reset; the positions sweep the frame.
    let mut resets = vec![(start + 1, 2), (start + per * 3 + 40, 1)];
    let mut at = resets[1].0 + per * 5;
    for off in [0, 1, 2, 5, 17, 50, 97, 98, 99, 101] {
        resets.push((at + off % per, 3));
        at += per * 6 + 13;
    }
    // A reset, another during the flush period after it, a third during the discarded
    // frame after that.
    resets.push((at + 10, 1));
    resets.push((at + 16, 1));
    resets.push((at + 17 + per + 5, 2));
    let enable_drop = at + 17 + per * 8;
    (resets, enable_drop, enable_drop + per * 6)
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

// ---------------------------------------------------------------------------------------
// Generic SPI ADC.

impl Slave for SpiAdc {
    fn step(&mut self, conv: bool, sck: bool) -> bool {
        SpiAdc::step(self, conv, sck)
    }
}

fn generic_timing() -> AdcTiming {
    AdcTiming {
        sck_min_period_ns: 25.0,
        sck_max_period_ns: 0.0,
        sck_min_pulse_ns: 10.0,
        data_valid_ns: 15.0,
        conv_min_pulse_ns: 20.0,
        conv_min_low_ns: 30.0,
        conv_to_sck_ns: 10.0,
        acquisition_ns: 0.0,
        conversion_edges: 0,
        max_sample_rate_hz: 1.0e6,
    }
}

/// One channel, 16-bit offset binary, SCK idle high, data on trailing edges, active-low
/// chip select framing the whole transfer, D = 5 (2 high), lead 2.
fn generic_one_channel() -> AdcParams {
    let mut f = AdcFrame {
        frame_sck: 18,
        channels: 1,
        offsets: [1, 0],
        width: 16,
        sign: SignFormat::OffsetBinary,
        cpol: true,
        cpha: false,
        conv_active_high: false,
        conv_clocks: 0,
        lead_clocks: 2,
        pipeline: 0,
    };
    f.conv_clocks = f.lead_clocks + f.frame_sck * 5 + 1;
    AdcParams::generic(F133, f, generic_timing(), 5, None)
}

/// Two channels, 12-bit two's complement, SCK idle low, data on leading edges, CONV pulse
/// active high, D = 4 with one high clock, lead 1, slots 3 and 16.
fn generic_two_channels() -> AdcParams {
    let f = AdcFrame {
        frame_sck: 30,
        channels: 2,
        offsets: [3, 16],
        width: 12,
        sign: SignFormat::TwosComplement,
        cpol: false,
        cpha: true,
        conv_active_high: true,
        conv_clocks: 0,
        lead_clocks: 1,
        pipeline: 0,
    };
    let mut p = AdcParams::generic(F50, f, generic_timing(), 4, None);
    p.sck_high_clocks = 1;
    p.period_clocks = p.min_period_clocks() + 3;
    p
}

fn generic_codes(w: u32, n: usize, seed: u64) -> Vec<[i32; 2]> {
    let lo = -(1i32 << (w - 1));
    let hi = (1i32 << (w - 1)) - 1;
    let mut v = vec![[lo, hi], [hi, lo], [0, -1], [-1, 0]];
    let mut r = SplitMix64(seed);
    while v.len() < n {
        v.push([
            r.range(lo as i64, hi as i64) as i32,
            r.range(lo as i64, hi as i64) as i32,
        ]);
    }
    v
}

fn generic_closed_loop(p: &AdcParams, n: usize) -> Run {
    p.validate().expect("feasible");
    let w = p.frame.width;
    let codes = generic_codes(w, n + 4, w as u64);
    let mut slave = SpiAdc::with_codes(p.frame, codes.clone());
    let per = p.period_clocks as usize;
    let cycles = 2 + p.startup_clocks() as usize + (n - 1) * per + 1;
    let run = closed_loop(p, &mut slave, &|k| (k < 2, true), cycles);
    let s = run.samples(w);
    assert_eq!(s.len(), n);
    assert_eq!(s[0].0, 2 + p.startup_clocks() as usize);
    for (j, &(row, a, b)) in s.iter().enumerate() {
        let (conv_row, c) = slave.taken()[j];
        assert_eq!(
            row - conv_row,
            p.conv_to_valid_clocks() as usize,
            "latency {j}"
        );
        let b_expect = if p.frame.channels == 2 {
            c[1] as i64
        } else {
            0
        };
        assert_eq!([a, b], [c[0] as i64, b_expect], "sample {j}");
        if j > 0 {
            assert_eq!(row - s[j - 1].0, per);
        }
    }
    run
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

// ---------------------------------------------------------------------------------------
// Co-simulation: the closed-loop MISO sequence replayed in Icarus and Verilator.

fn cosim(p: &AdcParams, run: &Run, top: &str) {
    let dir = common::workdir(top);
    let t = block_traces(
        AdcController::new(p),
        top,
        "clk",
        &run.rows,
        Simulators::ALL,
        &dir,
    )
    .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{top}: {m}");
    }
    assert_eq!(
        t.rust_hdl, run.outs,
        "{top}: replay differs from the closed loop"
    );
    assert!(t.icarus.is_some() && t.verilator.is_some());
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
                row[2] = r.next_u64() & 1;
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
