//! The ADC controller's frame check (`AdcController::with_frame_check`, STATUS.ADC_FRAME):
//! against the chip models of every preset with their data lines stuck for a while
//! (`DataLine::stick`), clock for clock against the model, and replayed in rust-hdl,
//! Icarus, Verilator and the engine. The expectation is the chip's: a frame delivered while
//! the pads were stuck is in error, any other is not (the codes never put every line at
//! one level: the rule of `sinedec::blocks::adc::frame_check`).
use crate::common;
use sinedec::blocks::adc::hdl::AdcController;
use sinedec::blocks::adc::model::{AdcIn, AdcModel};
use sinedec::blocks::adc::{AdcParams, FrameCheck};
use sinedec::cosim::step::{prepare, tick};
use sinedec::cosim::CosimBlock;
use sinedec::verify::Simulators;

const F133: f64 = 133.33e6;
const F100: f64 = 100e6;

/// A chip model behind the pads, with its data lines stuck on demand.
trait Chip {
    fn step(&mut self, conv: bool, sck: bool) -> [bool; 2];
    fn stick(&mut self, level: Option<bool>);
}

impl Chip for sinedec::sim::ltc1407a::Ltc1407a {
    fn step(&mut self, conv: bool, sck: bool) -> [bool; 2] {
        [
            sinedec::sim::ltc1407a::Ltc1407a::step(self, conv, sck),
            false,
        ]
    }
    fn stick(&mut self, level: Option<bool>) {
        self.set_sdo_stuck(level);
    }
}

impl Chip for sinedec::sim::cs_adc::CsAdc {
    fn step(&mut self, conv: bool, sck: bool) -> [bool; 2] {
        sinedec::sim::cs_adc::CsAdc::step(self, conv, sck)
    }
    fn stick(&mut self, level: Option<bool>) {
        self.set_sdo_stuck(level);
    }
}

/// Codes that never put a frame's lines all at one level: no channel at 0, -1 or a
/// full-scale code (so neither word is all zeros or all ones in either coding).
fn codes(k: u64, w: u32) -> [i32; 2] {
    let top = (1i64 << (w - 1)) - 2;
    let a = ((k * 7919 + 3) as i64 % top) + 1;
    let b = -(((k * 104_729 + 11) as i64 % top) + 2);
    [a as i32, b as i32]
}

struct Run {
    rows: Vec<Vec<u64>>,
    outs: Vec<Vec<u64>>,
    /// (row of out_valid, frame_error, the pads were stuck while the frame's data bits
    /// were read)
    frames: Vec<(usize, bool, bool)>,
}

/// The controller with the check against `chip`, the model checked every clock; the pads
/// stuck at `level` from clock `from` to `to`.
fn run(p: &AdcParams, chip: &mut dyn Chip, cycles: usize, stuck: (usize, usize, bool)) -> Run {
    let mut uut = AdcController::with_frame_check(p);
    prepare(&mut uut).expect("settles");
    let mut model = AdcModel::with_frame_check(p);
    let two = p.frame.lines >= 2;
    let (from, to, level) = stuck;
    // The data bits of a frame are read within the clocks from its first capture to its
    // last: a frame "read while stuck" has every one of those inside the window.
    let (first, last) = p.data_slots();
    let span = (p.capture_clock(last) - p.capture_clock(first)) as usize + 2;
    let mut miso = [false; 2];
    let mut r = Run {
        rows: vec![],
        outs: vec![],
        frames: vec![],
    };
    for k in 0..cycles {
        let rst = k < 3;
        uut.rst.next = rst;
        uut.enable.next = true;
        uut.adc_miso.next = miso[0];
        for b in uut.adc_miso_b.iter_mut() {
            b.next = miso[1];
        }
        tick(&mut uut).expect("settles");
        let o = uut.sample();
        let m = model.step(AdcIn {
            rst,
            enable: true,
            miso: miso[0],
            miso_b: miso[1],
        });
        assert_eq!(o, m.row(), "rust-hdl vs model at clock {k}");
        let mut row = vec![rst as u64, 1, miso[0] as u64];
        if two {
            row.push(miso[1] as u64);
        }
        r.rows.push(row);
        if o[2] == 1 {
            // A frame straddling an end of the window may go either way: left out.
            let inside = k >= from + span + 3 && k <= to;
            let outside = k + 1 < from || k > to + span + 3;
            if inside || outside {
                r.frames.push((k, o[5] == 1, inside));
            }
        }
        chip.stick((k + 1 >= from && k + 1 < to).then_some(level));
        miso = chip.step(o[1] == 1, o[0] == 1);
        r.outs.push(o);
    }
    r
}

/// Frames read while stuck are in error, the others not; and some of each were seen.
fn check(r: &Run, what: &str) {
    let stuck = r.frames.iter().filter(|f| f.2).count();
    let clean = r.frames.iter().filter(|f| !f.2).count();
    assert!(
        stuck >= 3 && clean >= 6,
        "{what}: {stuck} stuck, {clean} clean frames"
    );
    for &(row, err, inside) in &r.frames {
        assert_eq!(err, inside, "{what}: frame at row {row}");
    }
}

fn replay(p: &AdcParams, r: &Run, tag: &str) {
    let t = common::simulators_agree(
        AdcController::with_frame_check(p),
        tag,
        tag,
        &r.rows,
        Simulators::ALL,
    );
    assert_eq!(t, r.outs, "{tag}: replay differs from the closed loop");
}

#[test]
fn the_rule_is_every_line_at_one_level() {
    let (a1, a0, mix) = ([true; 14], [false; 14], [true, false, true]);
    assert!(FrameCheck::stuck(&[&a1]));
    assert!(FrameCheck::stuck(&[&a0, &a1]));
    assert!(!FrameCheck::stuck(&[&mix]));
    assert!(
        !FrameCheck::stuck(&[&a1, &mix]),
        "one stuck line of two is not"
    );
    let p = AdcParams::ltc1407a_fastest(F133).expect("feasible");
    assert_eq!(
        p.frame_check(),
        FrameCheck {
            lines: 1,
            bits_per_line: 28
        }
    );
    let p = AdcParams::ad7380(F100, 4, None);
    assert_eq!(
        p.frame_check(),
        FrameCheck {
            lines: 2,
            bits_per_line: 16
        }
    );
}

#[test]
fn ltc1407a_sdo_stuck_high_and_low_raise_frame_errors() {
    let p = AdcParams::ltc1407a_fastest(F133).expect("feasible");
    let per = p.period_clocks as usize;
    for (level, seed) in [(true, 3), (false, 4)] {
        let mut chip = sinedec::sim::ltc1407a::Ltc1407a::new(F133, seed).with_codes(|k, _| {
            let c = codes(k, 14);
            [c[0] as i16, c[1] as i16]
        });
        let start = p.startup_clocks() as usize + 6 * per;
        let r = run(
            &p,
            &mut chip,
            start + 20 * per,
            (start, start + 6 * per, level),
        );
        check(&r, &format!("LTC1407A-1 stuck at {level}"));
        if level {
            replay(&p, &r, "adc_frame_ltc");
        }
    }
}

#[test]
fn cs_chips_with_both_lines_stuck_raise_frame_errors() {
    for (name, p) in [
        ("ads8354", AdcParams::ads8354(F100, 6, None)),
        ("ad7380", AdcParams::ad7380(F100, 4, None)),
    ] {
        p.validate().expect("feasible");
        let per = p.period_clocks as usize;
        let spec = if name == "ads8354" {
            sinedec::sim::ads8354::ADS8354
        } else {
            sinedec::sim::ad7380::AD7380
        };
        let mut chip =
            sinedec::sim::cs_adc::CsAdc::new(spec, F100, 5).with_codes(move |k, _| codes(k, 16));
        let start = p.startup_clocks() as usize + 6 * per;
        let r = run(
            &p,
            &mut chip,
            start + 20 * per,
            (start, start + 6 * per, name == "ad7380"),
        );
        check(&r, name);
        assert!(
            chip.violations().is_empty(),
            "{name}: {:?}",
            chip.violations()
        );
        replay(&p, &r, &format!("adc_frame_{name}"));
    }
}

/// One stuck line of a two-line chip is not a frame error (a live channel crosses zero):
/// the check needs every line stuck.
#[test]
fn one_stuck_line_of_two_is_not_a_frame_error() {
    let p = AdcParams::ad7380(F100, 4, None);
    let mut model = AdcModel::with_frame_check(&p);
    let mut chip = sinedec::sim::cs_adc::CsAdc::new(sinedec::sim::ad7380::AD7380, F100, 6)
        .with_codes(|k, _| codes(k, 16));
    let mut out = model.step(AdcIn::default());
    let mut seen = 0;
    for k in 0..(p.startup_clocks() + 30 * p.period_clocks) as usize {
        let [_, b] = chip.step(out.conv, out.sck);
        // Line A stuck low: channel 0 reads 0; line B live.
        out = model.step(AdcIn {
            rst: k < 3,
            enable: true,
            miso: false,
            miso_b: b,
        });
        if out.valid {
            assert_eq!(out.ch0, 0);
            assert_eq!(out.frame_error, Some(false), "clock {k}");
            seen += 1;
        }
    }
    assert!(seen >= 25, "{seen} samples");
}
