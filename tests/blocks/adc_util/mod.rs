//! Helpers shared by `tests/blocks/adc.rs` and `tests/blocks/adc_closed_loop.rs` (moved out of `tests/blocks/adc.rs` so that
//! no test file is longer than about 600 lines).
#![allow(dead_code)]
use crate::common;
use sinedec::blocks::adc::hdl::AdcController;
use sinedec::blocks::adc::model::{AdcIn, AdcModel};
use sinedec::blocks::adc::{AdcFrame, AdcParams, AdcTiming, SignFormat};
use sinedec::blocks::sext;
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::stimulus::SplitMix64;
use sinedec::sim::adc_pins::PinTiming;
use sinedec::sim::ltc1407a::Ltc1407a;
use sinedec::sim::spi_adc::SpiAdc;
use sinedec::verify::{block_traces, Simulators};

pub const F133: f64 = 133.33e6;
pub const F50: f64 = 50e6;

/// The pins a slave model sees each clock and answers with the MISO level of the next edge.
pub trait Slave {
    fn step(&mut self, conv: bool, sck: bool) -> bool;
    /// Both data lines (A, B) of a two-line chip; line B is low on a one-line chip.
    fn step_lines(&mut self, conv: bool, sck: bool) -> [bool; 2] {
        [self.step(conv, sck), false]
    }
}

impl Slave for Ltc1407a {
    fn step(&mut self, conv: bool, sck: bool) -> bool {
        Ltc1407a::step(self, conv, sck)
    }
}

/// Inputs of each clock: (rst, enable).
pub type Schedule<'a> = dyn Fn(usize) -> (bool, bool) + 'a;

/// A closed-loop run: stimulus rows [rst, enable, miso] and output rows of the controller.
pub struct Run {
    pub rows: Vec<Vec<u64>>,
    pub outs: Vec<Vec<u64>>,
}

impl Run {
    /// (row, ch0, ch1) of every out_valid strobe, sign-extended from `w` bits.
    pub fn samples(&self, w: u32) -> Vec<(usize, i64, i64)> {
        self.outs
            .iter()
            .enumerate()
            .filter(|(_, o)| o[2] == 1)
            .map(|(k, o)| (k, sext(o[3], w), sext(o[4], w)))
            .collect()
    }
    /// Rows where CONV rises.
    pub fn conv_rises(&self) -> Vec<usize> {
        (0..self.outs.len())
            .filter(|&k| self.outs[k][1] == 1 && (k == 0 || self.outs[k - 1][1] == 0))
            .collect()
    }
}

/// Steps the rust-hdl controller by hand, feeding MISO from `chip` (which sees the pins of
/// each clock), and checks every clock against the plain-Rust model of the controller.
pub fn closed_loop(
    p: &AdcParams,
    chip: &mut dyn Slave,
    sched: &Schedule<'_>,
    cycles: usize,
) -> Run {
    let mut uut = AdcController::new(p);
    prepare(&mut uut).expect("settles");
    let mut model = AdcModel::new(p);
    let mut miso = [false; 2];
    let two = p.frame.lines >= 2;
    let mut run = Run {
        rows: Vec::with_capacity(cycles),
        outs: Vec::with_capacity(cycles),
    };
    for k in 0..cycles {
        let (rst, en) = sched(k);
        uut.rst.next = rst;
        uut.enable.next = en;
        uut.adc_miso.next = miso[0];
        for b in uut.adc_miso_b.iter_mut() {
            b.next = miso[1];
        }
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
            miso: miso[0],
            miso_b: miso[1],
        });
        assert_eq!(o, m.row(), "rust-hdl vs model at clock {k}");
        let mut row = vec![rst as u64, en as u64, miso[0] as u64];
        if two {
            row.push(miso[1] as u64);
        }
        run.rows.push(row);
        miso = chip.step_lines(o[1] == 1, o[0] == 1);
        run.outs.push(o);
    }
    run
}

/// Random 14-bit codes, starting with the extremes and the values around zero.
pub fn code_list(n: usize, seed: u64) -> Vec<[i16; 2]> {
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

pub fn ltc_with_list(clock_hz: f64, codes: Vec<[i16; 2]>, seed: u64) -> Ltc1407a {
    Ltc1407a::new(clock_hz, seed).with_codes(move |k, _| codes[k as usize % codes.len()])
}

/// Every delivered sample equals the conversion whose CONV rise lies exactly the predicted
/// latency earlier; returns how many were checked.
pub fn check_against_chip(p: &AdcParams, run: &Run, chip: &Ltc1407a) -> usize {
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

pub fn closed_loop_ltc(clock_hz: f64, n: usize, seed: u64) {
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

/// Resets at many points of the flush period, the discarded frame and running frames, and
/// an enable drop: after each, the flush restarts the chip cleanly and every sample still
/// matches its conversion.
pub fn reset_schedule(p: &AdcParams) -> (Vec<(usize, usize)>, usize, usize) {
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

// ---------------------------------------------------------------------------------------
// Generic SPI ADC.

impl Slave for SpiAdc {
    fn step(&mut self, conv: bool, sck: bool) -> bool {
        SpiAdc::step(self, conv, sck)
    }
    fn step_lines(&mut self, conv: bool, sck: bool) -> [bool; 2] {
        SpiAdc::step_lines(self, conv, sck)
    }
}

pub fn generic_timing() -> AdcTiming {
    AdcTiming {
        sck_min_period_ns: 25.0,
        sck_max_period_ns: 0.0,
        sck_min_pulse_ns: 10.0,
        data_valid_ns: 15.0,
        conv_min_pulse_ns: 20.0,
        conv_min_low_ns: 30.0,
        conv_to_sck_ns: 10.0,
        acquisition_ns: 0.0,
        conversion_ns: 0.0,
        conversion_edges: 0,
        max_sample_rate_hz: 1.0e6,
    }
}

/// One channel, 16-bit offset binary, SCK idle high, data on trailing edges, active-low
/// chip select framing the whole transfer, D = 5 (2 high), lead 2.
pub fn generic_one_channel() -> AdcParams {
    let mut f = AdcFrame {
        frame_sck: 18,
        channels: 1,
        lines: 1,
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
pub fn generic_two_channels() -> AdcParams {
    let f = AdcFrame {
        frame_sck: 30,
        channels: 2,
        lines: 1,
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

/// Two channels on two data lines (SDO-A, SDO-B), 16-bit two's complement, MSB in slot 1
/// of each line, SCK idle high, data on leading (falling) edges, active-low chip select
/// framing the whole 18-SCK transfer, D = 4 (30 ns: the 26 ns round trip with the 15 ns
/// data-valid delay of `generic_timing`), lead 1.
pub fn generic_two_lines() -> AdcParams {
    let mut f = AdcFrame {
        frame_sck: 18,
        channels: 2,
        lines: 2,
        offsets: [1, 1],
        width: 16,
        sign: SignFormat::TwosComplement,
        cpol: true,
        cpha: true,
        conv_active_high: false,
        conv_clocks: 0,
        lead_clocks: 1,
        pipeline: 0,
    };
    f.conv_clocks = f.lead_clocks + f.frame_sck * 4 + 1;
    let mut t = generic_timing();
    t.sck_min_period_ns = 20.0;
    t.sck_min_pulse_ns = 5.0;
    AdcParams::generic(F133, f, t, 4, None)
}

pub fn generic_codes(w: u32, n: usize, seed: u64) -> Vec<[i32; 2]> {
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

pub fn generic_closed_loop(p: &AdcParams, n: usize) -> Run {
    p.validate().expect("feasible");
    let w = p.frame.width;
    let codes = generic_codes(w, n + 4, w as u64);
    let mut slave = SpiAdc::with_codes(p, PinTiming::board_default(), codes.clone());
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

// ---------------------------------------------------------------------------------------
// Co-simulation: the closed-loop MISO sequence replayed in Icarus and Verilator.

pub fn cosim(p: &AdcParams, run: &Run, top: &str) {
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

// ---------------------------------------------------------------------------------------
// The capture window against chip models that keep real time.

/// The capture distance and the round-trip slack `check` prints for a config (parsed from
/// the `ADC round trip` line of its describe text).
pub fn check_round_trip(text: &str) -> (u32, f64) {
    let l = sinedec::config::Loaded::parse(text, "w.toml").expect("config");
    let d = l.derived.describe();
    let line = d
        .lines()
        .find(|l| l.starts_with("ADC round trip"))
        .expect("round-trip line");
    let after = |key: &str| -> &str {
        let i = line.find(key).unwrap_or_else(|| panic!("{key} in {line}")) + key.len();
        line[i..].split_whitespace().next().unwrap_or("")
    };
    let c = after("capture distance ").parse().expect("distance");
    let slack = after("slack ").parse().expect("slack");
    (c, slack)
}

/// Runs the LTC1407A-1 controller against the chip with SCK-to-data valid `t8_ns` behind
/// `pins`; returns (wrong samples, samples).
pub fn ltc_wrong_samples(p: &AdcParams, pins: PinTiming, t8_ns: f64, n: usize) -> (usize, usize) {
    use sinedec::sim::ltc1407a::Ltc1407aTiming;
    let codes = code_list(n + 4, 11);
    let mut chip = ltc_with_list(p.clock_hz, codes.clone(), 5)
        .with_pins(pins)
        .with_timing(Ltc1407aTiming {
            sdo_valid_ns: t8_ns,
            ..Ltc1407aTiming::DATASHEET
        });
    let cycles = 3 + p.startup_clocks() as usize + (n - 1) * p.period_clocks as usize + 1;
    let run = closed_loop(p, &mut chip, &|k| (k < 3, true), cycles);
    let s = run.samples(14);
    assert_eq!(s.len(), n);
    let wrong = s
        .iter()
        .enumerate()
        .filter(|(j, &(_, a, b))| [a, b] != [codes[*j][0] as i64, codes[*j][1] as i64])
        .count();
    (wrong, s.len())
}

/// The same with the generic SPI ADC model (data valid `valid_ns`, no hold).
pub fn generic_wrong_samples(
    p: &AdcParams,
    pins: PinTiming,
    valid_ns: f64,
    n: usize,
) -> (usize, usize) {
    let w = p.frame.width;
    let codes = generic_codes(w, n + 4, 3);
    let mut slave = SpiAdc::with_codes(p, pins, codes).with_delays(valid_ns, 0.0);
    let cycles = 3 + p.startup_clocks() as usize + (n - 1) * p.period_clocks as usize + 1;
    let run = closed_loop(p, &mut slave, &|k| (k < 3, true), cycles);
    let s = run.samples(w);
    assert_eq!(s.len(), n);
    let wrong = s
        .iter()
        .enumerate()
        .filter(|(j, &(_, a, b))| {
            let c = slave.taken()[*j].1;
            let b_expect = if p.frame.channels == 2 {
                c[1] as i64
            } else {
                0
            };
            [a, b] != [c[0] as i64, b_expect]
        })
        .count();
    (wrong, s.len())
}

// ---------------------------------------------------------------------------------------
// CS-framed dual-SDO chips (ADS8354, AD7380).

impl Slave for sinedec::sim::cs_adc::CsAdc {
    fn step(&mut self, conv: bool, sck: bool) -> bool {
        sinedec::sim::cs_adc::CsAdc::step(self, conv, sck)[0]
    }
    fn step_lines(&mut self, conv: bool, sck: bool) -> [bool; 2] {
        sinedec::sim::cs_adc::CsAdc::step(self, conv, sck)
    }
}

/// Every delivered sample equals the conversion whose CS falling edge lies exactly the
/// predicted latency earlier; returns how many were checked.
pub fn check_against_cs_chip(
    p: &AdcParams,
    run: &Run,
    chip: &sinedec::sim::cs_adc::CsAdc,
) -> usize {
    let lat = p.conv_to_valid_clocks() as usize;
    let s = run.samples(p.frame.width);
    for &(row, a, b) in &s {
        let c = chip
            .conversions()
            .iter()
            .find(|c| c.clock as usize + lat == row)
            .unwrap_or_else(|| {
                panic!("no CS falling edge {lat} clocks before the sample at row {row}")
            });
        assert_eq!(
            [a, b],
            [c.codes[0] as i64, c.codes[1] as i64],
            "sample at row {row}"
        );
    }
    s.len()
}

/// The controller of `p` against `chip` for `n` samples after a reset; returns the run,
/// the samples that differ from the codes the chip sampled, and the samples delivered.
pub fn cs_closed_loop(
    p: &AdcParams,
    chip: &mut sinedec::sim::cs_adc::CsAdc,
    n: usize,
) -> (Run, usize, usize) {
    let cycles = 3 + p.startup_clocks() as usize + (n - 1) * p.period_clocks as usize + 1;
    let run = closed_loop(p, chip, &|k| (k < 3, true), cycles);
    let lat = p.conv_to_valid_clocks() as usize;
    let s = run.samples(p.frame.width);
    let wrong = s
        .iter()
        .filter(|&&(row, a, b)| {
            !chip.conversions().iter().any(|c| {
                c.clock as usize + lat == row && [a, b] == [c.codes[0] as i64, c.codes[1] as i64]
            })
        })
        .count();
    (run, wrong, s.len())
}
