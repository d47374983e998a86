//! Helpers shared by the integration tests.
#![allow(dead_code)]
use sinedec::config::{Loaded, DEFAULT_CONFIG};

/// The default config with the given core parameters (A != 14 switches to the generic ADC).
pub fn cfg(n: u32, f: u32, a: u32, ppr: u32, mt: u32) -> Loaded {
    cfg_named("sd", n, f, a, ppr, mt)
}

/// As [`cfg`] with a module-name prefix.
pub fn cfg_named(name: &str, n: u32, f: u32, a: u32, ppr: u32, mt: u32) -> Loaded {
    let mut text = DEFAULT_CONFIG
        .replace("name = \"sd\"", &format!("name = \"{name}\""))
        .replace("iterations = 14", &format!("iterations = {n}"))
        .replace("fine_bits = 14", &format!("fine_bits = {f}"))
        .replace("width = 14", &format!("width = {a}"))
        .replace("ppr = 2048", &format!("ppr = {ppr}"))
        .replace("multiturn_bits = 12", &format!("multiturn_bits = {mt}"));
    if a != 14 {
        text = text.replace(
            "preset = \"ltc1407a-1\"",
            "preset = \"generic\"\nmax_sample_rate_hz = 2e6",
        )
        .replace("[preamp]\n# LTC6912-1 gains (inverting): -1, -2, -5, -10, -20, -50 or -100. A feeds sin, B cos.\ngain_a = -1\ngain_b = -1\n", "");
    }
    Loaded::parse(&text, "test").expect("test config parses")
}

/// A fresh work directory for tool runs (kept under target/ for inspection).
pub fn workdir(tag: &str) -> std::path::PathBuf {
    let p = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(tag);
    let _ = std::fs::remove_dir_all(&p);
    std::fs::create_dir_all(&p).expect("create work dir");
    p
}

/// The closed loop (encoder -> LTC1407A-1 model -> `<name>_top`) at a constant `rpm` for
/// `cycles` clocks, its recorded inputs replayed through the exported top in Icarus and
/// Verilator: panics unless all three give the same pin and position trace. Returns the
/// closed loop's result.
pub fn replay_top_in_simulators(
    l: &Loaded,
    rpm: f64,
    cycles: usize,
    tag: &str,
) -> sinedec::sim::system::SimResult {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::sim::encoder::EncoderModel;
    use sinedec::sim::system::System;
    use sinedec::verify::{block_traces, CosimBlock, Simulators};
    let d = &l.derived;
    let enc = EncoderModel::ideal(2048, 1.0, rpm).with_seed(3);
    let mut s = System::new(d, enc).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    let mut rust = vec![];
    for _ in 0..cycles {
        s.run(1).expect("runs");
        rust.push(s.top().sample());
    }
    let r = s.finish();
    assert!(r.records.len() > 50, "{} records", r.records.len());
    let dir = workdir(tag);
    let top = TopRtl::new(d).expect("top");
    let name = format!("{}_top_rtl", l.config.name);
    let t =
        block_traces(top, &name, "clk", &r.inputs, Simulators::ALL, &dir).expect("simulators ran");
    assert_eq!(
        t.rust_hdl, rust,
        "block_traces' own rust-hdl run equals the closed loop"
    );
    if let Some(m) = t.mismatch() {
        panic!("{m}");
    }
    r
}
