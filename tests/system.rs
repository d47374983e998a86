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
