//! `simulate --engine compiled`: the closed loop (encoder model -> LTC1407A-1 model -> the
//! sinewave top -> BiSS master model) on the compiled engine equals the same loop on
//! rust-hdl's simulation, cycle for cycle: every output pin of every cycle, every decoded
//! record and every frame the master read.
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use sinedec::sim::dut::EngineKind;
use sinedec::sim::encoder::{EncoderModel, Profile};
use sinedec::sim::system::System;

fn run(
    l: &Loaded,
    engine: EngineKind,
    cycles: u64,
) -> (Vec<Vec<u64>>, sinedec::sim::system::SimResult) {
    let d = &l.derived;
    let mut enc = EncoderModel::ideal(2048, 1.0, 0.0);
    enc.start_turns = 0.3 / 2048.0;
    // Backward through a reversal: the counter moves both ways within the run.
    enc.profile = Profile::Reversal {
        rpm: -2000.0,
        at: 100e-6,
        over: 80e-6,
    };
    let mut s = System::on(d, enc, engine).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    let mut outs = Vec::new();
    for _ in 0..cycles {
        s.run(1).expect("runs");
        outs.push(s.sample());
    }
    (outs, s.finish())
}

#[test]
fn compiled_closed_loop_equals_rust_hdl() {
    // The default with the BiSS slave's multi-turn bits on, so the turn count reaches a pin.
    let text = DEFAULT_CONFIG.replace("multiturn_bits = 0", "multiturn_bits = 4");
    assert_ne!(text, DEFAULT_CONFIG);
    let l = Loaded::parse(&text, "engine_loop.toml").expect("config");
    let n = (300e-6 * l.derived.clock_hz) as u64;
    let (ref_outs, ref_r) = run(&l, EngineKind::RustHdl, n);
    let (outs, r) = run(&l, EngineKind::Compiled, n);
    assert!(ref_r.records.len() > 300, "{} records", ref_r.records.len());
    // The position moved both ways.
    let first = ref_r.records[0].unwrapped;
    let min = ref_r
        .records
        .iter()
        .map(|x| x.unwrapped)
        .min()
        .expect("records");
    assert!(min < first - 1000, "moved backward: {first} -> {min}");
    for (k, (a, b)) in ref_outs.iter().zip(&outs).enumerate() {
        assert_eq!(a, b, "outputs at cycle {k}");
    }
    assert_eq!(ref_outs.len(), outs.len());
    assert_eq!(ref_r.records, r.records, "decoded records");
    assert_eq!(ref_r.inputs, r.inputs, "recorded inputs");
    assert_eq!(ref_r.latency_mismatches, 0);
    assert_eq!(r.latency_mismatches, 0);
}

/// The capacitive loop (capacitive-encoder model -> SPI ADC model -> `cap_top`) on the
/// compiled engine equals the same loop on rust-hdl: every recorded input row (the ADC's
/// MISO answers the pins the top drove) and every decoded position.
#[test]
fn compiled_capacitive_loop_equals_rust_hdl() {
    use sinedec::sim::cap_system::CapSystem;
    use sinedec::sim::capacitive::CapParams;
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/configs/cyclone3_capacitive.toml"
    ))
    .expect("config file");
    let l = Loaded::parse(&text, "cyclone3_capacitive.toml").expect("config");
    let d = &l.derived;
    let run = |engine| {
        let mut s = CapSystem::on(d, CapParams::paper(), engine).expect("system");
        assert_eq!(s.engine(), engine);
        s.record_inputs();
        s.start().expect("settles");
        s.run(40_000).expect("runs");
        s
    };
    let (a, b) = (run(EngineKind::RustHdl), run(EngineKind::Compiled));
    assert!(a.records.len() > 100, "{} positions", a.records.len());
    assert_eq!(a.inputs, b.inputs, "recorded inputs");
    assert_eq!(a.records, b.records, "decoded positions");
}
