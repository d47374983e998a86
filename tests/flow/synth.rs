//! Yosys synthesis of `<name>_core` for xc3sa and cycloneive: completes, no latch, no
//! undriven net, no unexpected warning; and the rules themselves catch bad designs.
use crate::common;
use sinedec::emit::{core_name, core_verilog};
use sinedec::synth::{synthesize, Family};

#[test]
fn default_core_synthesizes_for_both_families() {
    let l = sinedec::config::Loaded::default_config().expect("default config");
    let v = core_verilog(&l).expect("export");
    let top = core_name(&l);
    let dir = common::workdir("synth_default");
    let x = synthesize(&v, &top, Family::Xc3sa, &dir).expect("xc3sa synthesis");
    let c = synthesize(&v, &top, Family::CycloneIve, &dir).expect("cycloneive synthesis");
    eprintln!("xc3sa: {} LUT, {} FF, {} carry", x.luts, x.ffs, x.carry);
    eprintln!("cycloneive: {} LE, {} FF", c.luts, c.ffs);
    // Register count from the widths: per stage x, y (W bits), z (ZW bits), q (2), valid;
    // Yosys may drop constant bits (e.g. low z bits of early stages) but never adds any.
    let d = &l.derived;
    let upper = d.iterations as u64 * (2 * d.xy_width + d.z_width + 3) as u64
        + (2 * d.xy_width + 3) as u64
        + 200;
    for (name, s) in [("xc3sa", &x), ("cycloneive", &c)] {
        assert!(
            s.ffs > upper / 2 && s.ffs <= upper,
            "{name}: {} FF vs bound {upper}",
            s.ffs
        );
        assert!(s.luts > 500, "{name}: {} LUT", s.luts);
    }
    assert!(x.carry > 0, "Spartan-3A adders use the carry chain");
}

#[test]
fn a_latch_is_rejected() {
    let v = "module latchy(input wire en, input wire d, output reg q);\n\
             always @(*) if (en) q = d;\nendmodule\n";
    let dir = common::workdir("synth_latch");
    let e = synthesize(v, "latchy", Family::Xc3sa, &dir).expect_err("latch must fail");
    assert!(e.to_string().contains("latch inferred"), "{e}");
}

#[test]
fn an_undriven_net_is_rejected() {
    let v = "module undriven(input wire clk, output reg q);\n wire w;\n\
             always @(posedge clk) q <= w;\nendmodule\n";
    let dir = common::workdir("synth_undriven");
    let e = synthesize(v, "undriven", Family::CycloneIve, &dir).expect_err("must fail");
    assert!(e.to_string().contains("undriven"), "{e}");
}

#[test]
fn the_synthesis_cache_answers_only_the_same_run() {
    use sinedec::synth::synthesize_cached;
    let v = "module acc(input wire clk, input wire [3:0] d, output reg [3:0] q);\n\
             always @(posedge clk) q <= q + d;\nendmodule\n";
    let dir = common::workdir("synth_cache");
    let cache = dir.join("cache");
    let version = sinedec::report::yosys::yosys_version().expect("yosys -V");
    let run = |v: &str, fam: Family, version: &str| {
        synthesize_cached(v, "acc", fam, &dir.join("work"), Some(&cache), version)
            .expect("synthesis")
    };
    let entries = || std::fs::read_dir(&cache).map_or(0, |d| d.count());
    let (first, hit) = run(v, Family::Xc3sa, &version);
    assert!(!hit, "an empty cache cannot answer");
    assert_eq!(entries(), 1);
    assert!(first.ffs == 4 && first.luts > 0, "{first:?}");
    let (again, hit) = run(v, Family::Xc3sa, &version);
    assert!(hit, "the same run is answered from the cache");
    assert_eq!(again, first);
    // The answer is the entry's: an edited entry is what comes back.
    let entry = std::fs::read_dir(&cache)
        .unwrap()
        .next()
        .unwrap()
        .unwrap()
        .path();
    let text = std::fs::read_to_string(&entry).unwrap();
    let edited = text.replacen("\"ffs\": 4", "\"ffs\": 40", 1);
    assert_ne!(edited, text, "entry holds the flip-flop count: {text}");
    std::fs::write(&entry, edited).unwrap();
    assert_eq!(run(v, Family::Xc3sa, &version).0.ffs, 40);
    // A different design, family or Yosys version is a miss and a new entry.
    let wider = v.replace("[3:0] d", "[4:0] d");
    assert!(!run(&wider, Family::Xc3sa, &version).1);
    assert!(!run(v, Family::CycloneIve, &version).1);
    assert!(!run(v, Family::Xc3sa, "Yosys 0.0 (another build)").1);
    assert_eq!(entries(), 4);
    // A failed run stores nothing: the error comes from Yosys every time.
    let latchy = "module acc(input wire en, input wire d, output reg q);\n\
                  always @(*) if (en) q = d;\nendmodule\n";
    for _ in 0..2 {
        let e = synthesize_cached(
            latchy,
            "acc",
            Family::Xc3sa,
            &dir.join("w"),
            Some(&cache),
            &version,
        )
        .expect_err("latch must fail");
        assert!(e.to_string().contains("latch inferred"), "{e}");
    }
    assert_eq!(entries(), 4);
}
