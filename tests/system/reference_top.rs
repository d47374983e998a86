//! The position reference in `<name>_top` (`[reference] enabled`), in the closed loop with
//! the encoder, ADC and comparator models: homing on Z gives the same absolute position
//! from any start angle in both directions, a preset loads its count without moving the
//! fine part, and nothing homes while the encoder stays away from the index.
//!
//! The expectations come from the encoder model, not from the block: the loop's comparator
//! Z is high in the first quadrant (A = B = 1) of the first signal period of every turn, so
//! with the default `[reference]` (gate "11", quadrant 0, turn 0) the referenced position
//! must equal the encoder's true angle, turns included, to within the decoder's error.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::encoder::{EncoderModel, Profile};
use sinedec::sim::system::{Record, System};

fn config(extra: &str) -> Loaded {
    let text = format!("{DEFAULT_CONFIG}\n[reference]\nenabled = true\n{extra}\n");
    Loaded::parse(&text, "reference_top.toml").expect("config")
}

/// Runs an ideal 2048-line encoder from `periods` signal periods into the turn at `rpm` for
/// `seconds` in the loop (rust-hdl), pulsing `preset` over `preset` seconds if given.
fn run(
    l: &Loaded,
    periods: f64,
    rpm: f64,
    seconds: f64,
    preset: Option<(f64, f64)>,
) -> Vec<Record> {
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = periods / 2048.0;
    enc.profile = Profile::Constant { rpm };
    let mut s = System::new(d, enc).expect("system");
    if let Some((a, b)) = preset {
        s.preset_pulse(a, b);
    }
    s.start().expect("settles");
    s.run((seconds * d.clock_hz) as u64).expect("runs");
    s.finish().records
}

/// Largest |decoded - true| in position LSB over the referenced records.
fn referenced_error(recs: &[Record]) -> f64 {
    recs.iter()
        .filter(|r| r.referenced)
        .map(|r| (r.unwrapped as f64 - r.truth).abs())
        .fold(0.0, f64::max)
}

#[test]
fn homing_gives_the_true_position_from_every_start_both_ways() {
    let l = config("");
    let d = &l.derived;
    let period_lsb = 4.0 * (1u64 << d.fine_bits) as f64;
    // Starts before the index going forward and after it going backward, inside the
    // reference quadrant (slowly: the first sample leaves the decoder 3.5 us after the start,
    // once the LTC6912-1 is set up), in the quadrant just before it, and several periods
    // away. At 3000 rpm a signal period takes 9.8 us (0.3 quadrants per sample).
    let cases = [
        (-3.45, 3000.0),
        (-1.7, 3000.0),
        (-0.1, 3000.0),
        (0.1, 300.0),
        (0.1, -300.0),
        (0.3, -3000.0),
        (1.7, -3000.0),
        (3.45, -3000.0),
    ];
    let mut raw_offsets = vec![];
    for (start, rpm) in cases {
        let recs = run(&l, start, rpm, 60e-6, None);
        let first = recs.iter().position(|r| r.referenced);
        let Some(k) = first else {
            panic!("start {start} periods at {rpm} rpm: never referenced");
        };
        // Before homing: the warning (warn_until_referenced) and the decoder's own zero.
        assert!(k > 0, "start {start}: referenced from the first sample");
        assert!(recs[..k].iter().all(|r| r.warning && !r.referenced));
        assert!(recs[k..].iter().all(|r| r.referenced && !r.warning));
        raw_offsets.push(((recs[0].unwrapped as f64 - recs[0].truth) / period_lsb).round());
        let e = referenced_error(&recs);
        assert!(
            e <= 8.0,
            "start {start} periods at {rpm} rpm: referenced position {e} LSB from the truth"
        );
        // It homed where the index is: within the quadrant before or at the reference.
        let at = recs[k].truth / period_lsb;
        assert!(
            (-0.5..0.75).contains(&at),
            "start {start}: homed at {at} periods"
        );
    }
    // Without homing the position would be off by whole periods: the test can fail.
    assert!(
        raw_offsets.iter().any(|o| *o != 0.0),
        "raw offsets {raw_offsets:?}"
    );
}

#[test]
fn the_reference_count_and_turn_are_taken_from_the_config() {
    let l = config("quadrant = 100\nturn = -2\n");
    let d = &l.derived;
    let q = d.quadrants_per_turn as f64;
    let lsb = (1u64 << d.fine_bits) as f64;
    let recs = run(&l, -0.6, 3000.0, 30e-6, None);
    let k = recs.iter().position(|r| r.referenced).expect("homed");
    // The reference quadrant (truth 0..1 quadrant) reads quadrant count 100 of turn -2.
    let want = (-2.0 * q + 100.0) * lsb;
    for r in &recs[k..] {
        let e = r.unwrapped as f64 - r.truth - want;
        assert!(e.abs() <= 8.0, "{e} LSB off at cycle {}", r.cycle);
    }
}

#[test]
fn a_preset_loads_its_count_and_keeps_the_fine_part() {
    let l = config("preset_quadrant = 3000\npreset_turn = 1\n");
    let d = &l.derived;
    let q = d.quadrants_per_turn as i64;
    let f = d.fine_bits;
    // Far from the index (periods 20..): only the preset can reference.
    let recs = run(&l, 20.0, 1000.0, 40e-6, Some((15e-6, 16e-6)));
    let k = recs
        .iter()
        .position(|r| r.referenced)
        .expect("preset taken");
    let b = &recs[k - 1];
    // The preset sample reads (3000, 1) with its own fine part: every later sample keeps
    // that offset from the truth.
    let fine_b = b.position & ((1 << f) - 1);
    let c = ((q + 3000) << f) as f64 + fine_b as f64 - b.truth;
    for r in &recs[k..] {
        let e = r.unwrapped as f64 - r.truth - c;
        assert!(e.abs() <= 8.0, "{e} LSB off at cycle {}", r.cycle);
    }
    // Taken at the first sample after the synchronized edge (one sample period is 102
    // clocks at 133.33 MHz; the pulse rises at 15 us).
    let rise = (15e-6 * d.clock_hz) as u64;
    let lat = sinedec::blocks::top::hdl::conv_to_position_cycles(d) as u64;
    assert!(b.cycle >= rise && b.cycle <= rise + lat + 2 * d.adc.period_clocks as u64);
    assert!(recs[..k].iter().all(|r| !r.referenced));
}

#[test]
fn nothing_homes_away_from_the_index() {
    let l = config("");
    let recs = run(&l, 5.0, 3000.0, 40e-6, None);
    assert!(recs.len() > 40);
    assert!(recs.iter().all(|r| !r.referenced && r.warning));
}

#[test]
fn top_with_the_reference_replays_in_icarus_verilator_and_the_engine() {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::cosim::CosimBlock;
    use sinedec::verify::{block_traces, Simulators};
    let l = config("");
    let d = &l.derived;
    // Homes at the first sample (inside the index quadrant), then a preset at 15 us.
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = -0.3 / 2048.0;
    enc.profile = Profile::Constant { rpm: 3000.0 };
    let mut s = System::new(d, enc).expect("system");
    s.preset_pulse(15e-6, 16e-6);
    s.record_inputs();
    s.start().expect("settles");
    s.run(3500).expect("runs");
    let r = s.finish();
    let top = TopRtl::new(d).expect("top");
    let outs = top.output_ports();
    assert!(top.input_ports().iter().any(|p| p.name == "preset_0"));
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("reference_top");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let t = block_traces(top, "sd_top_rtl", "clk", &r.inputs, Simulators::ALL, &dir)
        .expect("simulators ran");
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    // The replay saw the homing and the preset: referenced_0 rises, and the parallel
    // position jumps at the preset.
    let col = |n: &str| outs.iter().position(|p| p.name == n).expect("port");
    let refd = col("referenced_0");
    assert!(t.rust_hdl.iter().any(|row| row[refd] == 1));
    assert!(t.rust_hdl[..400].iter().all(|row| row[refd] == 0));
}
