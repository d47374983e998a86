//! End to end in the Rust simulation: encoder model -> LTC1407A-1 model -> `<name>_top`
//! (preamp set-up, ADC controller, core) -> decoded position against the true angle.
use sinedec::config::Loaded;
use sinedec::sim::encoder::EncoderModel;
use sinedec::sim::system::System;

#[test]
fn constant_speed_closed_loop() {
    let l = Loaded::default_config().expect("default");
    let d = &l.derived;
    let enc = EncoderModel::ideal(2048, 1.0, 300.0);
    let mut s = System::new(d, enc).expect("system");
    s.start().expect("settles");
    s.run(20_000).expect("runs");
    let r = s.finish();
    let st = r.stats(d, 2);
    eprintln!(
        "{} samples, {:?}, gains {:?}",
        r.records.len(),
        st,
        r.amp_gains
    );
    assert_eq!(r.latency_mismatches, 0);
    assert!(r.adc_violations.is_empty(), "{:?}", r.adc_violations);
    assert!(r.amp_violations.is_empty(), "{:?}", r.amp_violations);
    assert_eq!(r.amp_gains, Some((-1, -1)));
    assert!(r.records.len() > 180);
    assert!(st.max_lsb < 4.0, "{st:?}");
}

/// The closed-loop run's inputs replayed through the exported top in Icarus and Verilator
/// give the same pin and position trace as the rust-hdl simulation.
#[test]
fn closed_loop_replayed_in_icarus_and_verilator() {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::verify::{block_traces, CosimBlock, Simulators};
    let l = Loaded::default_config().expect("default");
    let d = &l.derived;
    let enc = EncoderModel::ideal(2048, 1.0, 3000.0).with_seed(3);
    let mut s = System::new(d, enc).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    let mut rust = vec![];
    for _ in 0..6000 {
        s.run(1).expect("runs");
        rust.push(s.top().sample());
    }
    let r = s.finish();
    assert!(r.records.len() > 50);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("system_replay");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let top = TopRtl::new(d).expect("top");
    let t = block_traces(top, "sd_top_rtl", "clk", &r.inputs, Simulators::ALL, &dir)
        .expect("simulators ran");
    assert_eq!(
        t.rust_hdl, rust,
        "block_traces' own rust-hdl run equals the closed loop"
    );
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
}
