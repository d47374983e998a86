//! The absolute start in `<name>_top` (`[reference] absolute = "ssi"`), in the closed loop
//! with the encoder's sin/cos tracks, its SSI digital channel (`sim::ssi_encoder`, from the
//! data sheets), the ADC and the comparators.
//!
//! The expectations come from the encoder model, not from the block: once referenced, the
//! position on the parallel bus must be the encoder's true absolute position, turns
//! included (modulo the 2^12 turns both the word and the decoder count), to within the
//! decoder's own error, from every start: at and one LSB around a period boundary and a
//! quadrant boundary, inside periods, at rest and moving slowly both ways, with the
//! channel's alignment error up to the documented tolerance (docs/absolute.md). Beyond the
//! tolerance the period is off by one: the test can fail.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::encoder::{EncoderModel, Profile};
use sinedec::sim::system::{Record, SimResult, System};

/// The default config with the absolute start: a 25-bit Gray word (12 + 13 bits, one code
/// per quadrant at 2048 lines) at 1 MHz (unless `extra` names the clock), plus `extra` in
/// `[reference.ssi]`.
fn config(extra: &str) -> Loaded {
    let clock = if extra.contains("clock_hz") {
        ""
    } else {
        "clock_hz = 1e6\n"
    };
    let text = format!(
        "{DEFAULT_CONFIG}\n[reference]\nenabled = true\nabsolute = \"ssi\"\n\n[reference.ssi]\nmultiturn_bits = 12\n{clock}{extra}\n"
    );
    Loaded::parse(&text, "absolute_top.toml").expect("config")
}

/// Runs an ideal 2048-line encoder from `start` turns at `rpm` for `seconds` (rust-hdl),
/// with the digital channel's alignment error `e` quadrants.
fn run(l: &Loaded, start: f64, rpm: f64, e: f64, seconds: f64) -> SimResult {
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = start;
    enc.profile = Profile::Constant { rpm };
    let mut s = System::new(d, enc).expect("system");
    s.absolute_encoder_mut()
        .expect("the channel")
        .set_alignment_quadrants(e);
    s.start().expect("settles");
    s.run((seconds * d.clock_hz) as u64).expect("runs");
    s.finish()
}

/// |decoded - true| in fine LSB of a record, modulo 2^12 turns.
fn error_lsb(l: &Loaded, r: &Record) -> f64 {
    let d = &l.derived;
    let range = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64 * 4096.0;
    let e = r.unwrapped as f64 - r.truth;
    (e - range * (e / range).round()).abs()
}

/// Quadrants per turn (2048 lines) and fine LSB per quadrant (F = 14).
const Q: f64 = 8192.0;
const LSB: f64 = 1.0 / 16384.0;

/// What one run showed: the largest error of the referenced samples and the raw
/// (unreferenced) error of the first sample in periods.
struct Outcome {
    max_lsb: f64,
    raw_periods: f64,
}

/// Runs `case` and checks what every run must show: one read, no timing violation, the
/// warning until referenced and none after, and the word tied to the sample of the
/// conversion one clock before the latch's edge.
fn outcome(l: &Loaded, start: f64, rpm: f64, e: f64, what: &str) -> Outcome {
    let d = &l.derived;
    let r = run(l, start, rpm, e, 62e-6);
    let a = r.absolute.as_ref().expect("the channel's record");
    assert_eq!(a.latches.len(), 1, "{what}: one read");
    assert!(a.violations.is_empty(), "{what}: {:?}", a.violations);
    let k = r
        .records
        .iter()
        .position(|x| x.referenced)
        .unwrap_or_else(|| panic!("{what}: never referenced"));
    assert!(k > 0, "{what}: referenced from the first sample");
    assert!(
        r.records[..k].iter().all(|x| x.warning && !x.referenced),
        "{what}"
    );
    assert!(
        r.records[k..].iter().all(|x| x.referenced && !x.warning),
        "{what}"
    );
    // The latch's edge left one clock after a conversion's CONV edge (the one derivation).
    let lag = sinedec::blocks::absolute::SsiTiming::LATCH_LAG_CLOCKS as u64;
    let launched = (a.latches[0].launched_ns * d.clock_hz / 1e9).round() as u64;
    assert!(
        r.records.iter().any(|x| x.conv_cycle + lag == launched),
        "{what}: the latch at cycle {launched} follows no conversion by {lag} clock"
    );
    // Referenced by the word, not by homing on the index (Z is high in the first quadrant
    // of every turn in the loop): not before the frame after the latch has ended.
    let t = d.absolute.as_ref().expect("absolute").timing();
    let frame = t.frame_clocks(d.absolute.as_ref().unwrap().word().bits()) as u64;
    assert!(
        r.records[k].cycle > launched + frame,
        "{what}: referenced before the word came"
    );
    let max_lsb = r.records[k..]
        .iter()
        .map(|x| error_lsb(l, x))
        .fold(0.0, f64::max);
    let period = 4.0 * (1u64 << d.fine_bits) as f64;
    Outcome {
        max_lsb,
        raw_periods: ((r.records[0].unwrapped as f64 - r.records[0].truth) / period).round(),
    }
}

/// The position in turns whose quadrant count is `quadrants` (unwrapped).
fn at(quadrants: f64) -> f64 {
    quadrants / Q
}

#[test]
fn the_position_is_absolute_from_every_start() {
    let l = config("");
    // The latch instant, the same in every run (reset, the wait, the CONV schedule): a
    // moving encoder is started so that it sits on the named position when latched.
    let t_latch = run(&l, 0.25, 0.0, 0.0, 62e-6)
        .absolute
        .expect("read")
        .latches[0]
        .at_ns
        * 1e-9;
    let m = 4.0 * (3.0 * Q / 4.0 + 25.0); // a period boundary in turn 3
                                          // (quadrant count at the latch, rpm, alignment error in quadrants, what)
    let cases: [(f64, f64, f64, &str); 20] = [
        (m, 0.0, 0.0, "period boundary"),
        (m + LSB, 0.0, 1.45, "1 LSB after a period boundary"),
        (m - LSB, 0.0, -1.45, "1 LSB before a period boundary"),
        (
            m - LSB,
            0.0,
            1.45,
            "1 LSB before a period boundary, channel ahead",
        ),
        (m + 1.0, 0.0, 1.45, "quadrant boundary"),
        (m + 1.0 + LSB, 0.0, -1.45, "1 LSB after a quadrant boundary"),
        (m + 1.0 - LSB, 0.0, 1.0, "1 LSB before a quadrant boundary"),
        (m + 2.0 - LSB, 0.0, -1.0, "1 LSB before the third quadrant"),
        (m + 3.0 + LSB, 0.0, 0.5, "1 LSB into the last quadrant"),
        (0.0, 0.0, -1.45, "turn boundary (code 8191 of turn -1 read)"),
        (
            -LSB,
            0.0,
            1.45,
            "1 LSB before the turn (code 0 of turn 0 read)",
        ),
        (17.0 * Q + 2.5, 60.0, 0.0, "60 rpm forward"),
        (m, -60.0, 1.0, "60 rpm backward on a period boundary"),
        (
            m + 1.0,
            600.0,
            -1.0,
            "600 rpm forward on a quadrant boundary",
        ),
        (m + 2.5, -600.0, 1.45, "600 rpm backward mid-quadrant"),
        (
            m + 4.0 - LSB,
            300.0,
            -1.45,
            "300 rpm forward 1 LSB before a period",
        ),
        (
            m + LSB,
            -300.0,
            1.45,
            "300 rpm backward 1 LSB after a period",
        ),
        (-3.0 * Q + 5000.7, 0.0, -0.5, "turn -3"),
        (
            4095.0 * Q + 8191.9,
            0.0,
            1.2,
            "the last quadrant of turn 4095 (wraps)",
        ),
        (1234.0 * Q + 0.5, 0.0, -1.2, "turn 1234"),
    ];
    let mut raw = vec![];
    for (x, rpm, e, what) in cases {
        let start = at(x) - rpm / 60.0 * t_latch;
        let o = outcome(&l, start, rpm, e, what);
        assert!(
            o.max_lsb <= 8.0,
            "{what} (e = {e} quadrants, {rpm} rpm): {} LSB from the true absolute position",
            o.max_lsb
        );
        raw.push(o.raw_periods);
    }
    // Without the absolute start the position would be off by whole periods.
    assert!(raw.iter().any(|p| *p != 0.0), "{raw:?}");
}

#[test]
fn beyond_the_tolerance_the_period_is_wrong() {
    // One code per quadrant: +-1.5 quadrants. At 0.48 quadrants into a period an error of
    // 1.6 quadrants puts the word's code centre 2.08 quadrants ahead, and the merge takes the
    // next period; 1.4 still takes the right one.
    let l = config("");
    let x = at(4.0 * 1000.0 + 0.48);
    let d = &l.derived;
    let period = 4.0 * (1u64 << d.fine_bits) as f64;
    let bad = outcome(&l, x, 0.0, 1.6, "1.6 quadrants");
    assert!(
        (bad.max_lsb - period).abs() <= 8.0,
        "one period off: {} LSB",
        bad.max_lsb
    );
    let good = outcome(&l, x, 0.0, 1.4, "1.4 quadrants");
    assert!(good.max_lsb <= 8.0, "{} LSB", good.max_lsb);
}

#[test]
fn finer_words_take_a_larger_error() {
    // 512 lines and a 13-bit word: four codes per quadrant (k = 2), a tolerance of
    // 2 - 1/8 = 1.875 quadrants.
    let text = format!(
        "{DEFAULT_CONFIG}\n[reference]\nenabled = true\nabsolute = \"ssi\"\n\n[reference.ssi]\nsingle_turn_bits = 13\nmultiturn_bits = 12\nclock_hz = 1e6\n"
    )
    .replace("ppr = 2048", "ppr = 512");
    let l = Loaded::parse(&text, "fine.toml").expect("config");
    let a = l.derived.absolute.as_ref().expect("absolute");
    assert_eq!(a.sub_quadrant_bits(), 2);
    assert_eq!(a.tolerance_quadrants(), 1.875);
    for (x, e) in [
        (4.0 * 300.0, 1.85),
        (4.0 * 300.0 + 1.0 - LSB, -1.85),
        (7.3, 0.9),
    ] {
        let mut enc = EncoderModel::ideal(512, 1.0, 0.0);
        enc.start_turns = x / 2048.0;
        let d = &l.derived;
        let mut s = System::new(d, enc).expect("system");
        s.absolute_encoder_mut()
            .expect("channel")
            .set_alignment_quadrants(e);
        s.start().expect("settles");
        s.run((62e-6 * d.clock_hz) as u64).expect("runs");
        let r = s.finish();
        let k = r
            .records
            .iter()
            .position(|x| x.referenced)
            .expect("referenced");
        let range = 2048.0 * (1u64 << d.fine_bits) as f64 * 4096.0;
        for rec in &r.records[k..] {
            let err = rec.unwrapped as f64 - rec.truth;
            let err = (err - range * (err / range).round()).abs();
            assert!(err <= 8.0, "x {x}, e {e}: {err} LSB");
        }
    }
}

/// The data-valid boundary sits where `check` puts it: a cable whose round trip is two
/// system clocks inside `check`'s longest round trip (594 ns at 1 MHz) reads the position,
/// one two clocks beyond it samples the bits before they arrive and reads garbage.
#[test]
fn the_cable_boundary_is_where_check_puts_it() {
    let l = config("");
    let d = &l.derived;
    let t = d.absolute.as_ref().expect("absolute").timing();
    let rt = t.max_round_trip_ns();
    assert!(
        d.describe().contains(&format!("{rt:.0}")),
        "check prints {rt:.0} ns"
    );
    let x = at(4.0 * 777.0 + 1.3);
    for (round_trip, ok) in [
        (rt - 2.0 * t.tclk_ns(), true),
        (rt + 2.0 * t.tclk_ns(), false),
    ] {
        let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
        enc.start_turns = x;
        let mut s = System::new(d, enc).expect("system");
        s.absolute_encoder_mut()
            .expect("channel")
            .set_line_delay_ns(round_trip / 2.0);
        s.start().expect("settles");
        s.run((62e-6 * d.clock_hz) as u64).expect("runs");
        let r = s.finish();
        let k = r.records.iter().position(|x| x.referenced);
        let good = k.is_some_and(|k| r.records[k..].iter().all(|x| error_lsb(&l, x) <= 8.0));
        assert_eq!(
            good, ok,
            "a {round_trip:.1} ns round trip against check's {rt:.1} ns"
        );
    }
}

#[test]
fn simulate_reports_the_absolute_start() {
    use sinedec::simulate::{run, SimOptions};
    let l = config("");
    let o = SimOptions {
        profile: Profile::Constant { rpm: 120.0 },
        duration_s: 150e-6,
        skip: 0,
        ..Default::default()
    };
    let rep = run(&l, &o, |_, _| {}).expect("simulate runs");
    // The statistics are over the referenced samples, against the absolute truth.
    assert!(rep.stats.samples > 50, "{}", rep.stats.samples);
    assert!(rep.stats.max_lsb <= 8.0, "{} LSB", rep.stats.max_lsb);
    let text = rep.summary(&l);
    assert!(text.contains("absolute start"), "{text}");
}

#[test]
fn top_with_the_absolute_start_replays_in_icarus_verilator_and_the_engine() {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::cosim::CosimBlock;
    use sinedec::verify::{block_traces, Simulators};
    // A faster read to keep the replay short: 2 MHz and a 2 us monoflop (a faster encoder).
    let l = config("monoflop_us = 2.0\nclock_hz = 2e6\n");
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = 5.0 + 0.3 / 2048.0;
    enc.profile = Profile::Constant { rpm: -300.0 };
    let mut s = System::new(d, enc).expect("system");
    let ch = s.absolute_encoder_mut().expect("channel");
    let mut t = ch.timing();
    t.min_period_ns = 400.0;
    t.monoflop_ns = 2000.0;
    ch.set_timing(t);
    s.record_inputs();
    s.start().expect("settles");
    s.run(3600).expect("runs");
    let r = s.finish();
    let k = r
        .records
        .iter()
        .position(|x| x.referenced)
        .expect("referenced in the replay");
    assert!(r.records[k..].iter().all(|x| error_lsb(&l, x) <= 8.0));
    let top = TopRtl::new(d).expect("top");
    let outs = top.output_ports();
    assert!(top.input_ports().iter().any(|p| p.name == "abs_data_0"));
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("absolute_top");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let t = block_traces(top, "sd_top_rtl", "clk", &r.inputs, Simulators::ALL, &dir)
        .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    let col = |n: &str| outs.iter().position(|p| p.name == n).expect("port");
    let refd = col("referenced_0");
    assert!(t.rust_hdl.iter().any(|row| row[refd] == 1));
    let clk = col("abs_clk_0");
    assert!(
        t.rust_hdl.iter().any(|row| row[clk] == 0),
        "the SSI clock ran"
    );
}
