//! The compiled engine (src/engine) and its interpreter fallback against rust-hdl, stepped
//! by hand, and Verilator, cycle for cycle and bit for bit, on the emitted `<name>_core`
//! (the directed, random and rotation stimulus of tests/blocks/cosim_core.rs) and on the
//! `<name>_top` rtl of the default config and the capacitive config, driven by the inputs
//! their closed loops (encoder, ADC and amplifier models) recorded; restarted after a run,
//! each engine replays the same trace.
use crate::common;
use sinedec::config::Loaded;
use sinedec::cosim::{first_mismatch, stimulus, Port, Trace};
use sinedec::engine::{Engine, Kind};
use sinedec::verify::{block_traces, core_traces, stimulus_rows, Simulators};

const VERILATOR: Simulators = Simulators {
    icarus: false,
    verilator: true,
};

/// Both engines on `verilog`: each trace must equal `reference` (rust-hdl's).
fn check_engines(
    verilog: &str,
    top: &str,
    ins: &[Port],
    outs: &[Port],
    rows: &[Vec<u64>],
    reference: &Trace,
) {
    for kind in [Kind::Compiled, Kind::Interpreted] {
        let mut e = Engine::new(verilog, top, "clk", kind)
            .unwrap_or_else(|err| panic!("{top}: {kind:?} engine: {err}"));
        let t = e.trace(ins, outs, rows).expect("engine runs");
        if let Some(m) = first_mismatch("rust-hdl", reference, &format!("{kind:?}"), &t, outs) {
            panic!("{top}: {m}");
        }
        // Restarted after the run, the model is back at power-up, as one built anew: on
        // rows with no reset in them (the run's last 2000) it gives the new model's trace,
        // which the model left where the run ended does not.
        let n = rows.len().min(2000);
        let tail = &rows[rows.len() - n..];
        let mut fresh = Engine::new(verilog, top, "clk", kind).expect("engine builds");
        let want = fresh.trace(ins, outs, tail).expect("engine runs");
        let carried = e.trace(ins, outs, tail).expect("engine runs");
        assert_ne!(
            carried, want,
            "{top}: the run must leave a state to restart from"
        );
        e.restart();
        let got = e.trace(ins, outs, tail).expect("engine runs");
        if let Some(m) = first_mismatch(
            "new model",
            &want,
            &format!("{kind:?} restarted"),
            &got,
            outs,
        ) {
            panic!("{top}: {m}");
        }
    }
}

/// Number of rows in which output column `k` is nonzero.
fn active(t: &Trace, k: usize) -> usize {
    t.iter().filter(|r| r[k] != 0).count()
}

#[test]
fn core_engine_equals_rust_hdl_and_verilator() {
    use sinedec::emit::{core_input_ports, core_name, core_output_ports, core_verilog};
    let l = Loaded::default_config().expect("default config");
    let d = &l.derived;
    let a = d.adc_width;
    let mut s = stimulus::directed(a);
    s.extend(stimulus::random(a, 3000, 0.25, 7));
    let step = std::f64::consts::FRAC_PI_2 * 0.9;
    s.extend(stimulus::rotation(a, 0.7, 0.0, step, 400));
    s.extend(stimulus::rotation(a, 0.7, 0.0, -step, 600));
    let dir = common::workdir("engine_core");
    let t = core_traces(&l, &s, VERILATOR, &dir).expect("rust-hdl and Verilator ran");
    if let Some(m) = t.mismatch(&l) {
        panic!("core: {m}");
    }
    // out_valid (column 0) pulses often and the positions move: a trace worth comparing.
    assert!(
        active(&t.rust_hdl, 0) > 2000,
        "{} valid rows",
        active(&t.rust_hdl, 0)
    );
    assert!(active(&t.rust_hdl, 1) > 1000);
    let verilog = core_verilog(&l).expect("core Verilog");
    let (ins, outs) = (core_input_ports(d), core_output_ports(d));
    let rows = stimulus_rows(&l, &s);
    check_engines(&verilog, &core_name(&l), &ins, &outs, &rows, &t.rust_hdl);
    // The comparison can fail: with one sample's sine changed the engine's trace differs.
    let mut bad = rows.clone();
    let k = (200..bad.len())
        .find(|&i| bad[i][1] == 1)
        .expect("a valid sample");
    bad[k][2] ^= 1 << (a - 2);
    let mut e = Engine::new(&verilog, &core_name(&l), "clk", Kind::Compiled).expect("engine");
    let t2 = e.trace(&ins, &outs, &bad).expect("engine runs");
    assert!(first_mismatch("rust-hdl", &t.rust_hdl, "changed", &t2, &outs).is_some());
}

/// The closed loop's recorded inputs of `top`, replayed in rust-hdl (and Verilator), then
/// in both engines.
fn top_case<B: sinedec::cosim::CosimBlock>(uut: B, name: &str, rows: &[Vec<u64>], valid: &str) {
    let dir = common::workdir(&format!("engine_{name}"));
    let outs = uut.output_ports();
    let ins = uut.input_ports();
    let mut uut = uut;
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let verilog = sinedec::emit::verilog::export(&uut, name, name).expect("export");
    let bt = block_traces(uut, name, "clk", rows, VERILATOR, &dir).expect("simulators ran");
    if let Some(m) = bt.mismatch() {
        panic!("{name}: {m}");
    }
    let v = outs
        .iter()
        .position(|p| p.name == valid)
        .expect("valid port");
    assert!(
        active(&bt.rust_hdl, v) > 20,
        "{name}: {} positions",
        active(&bt.rust_hdl, v)
    );
    check_engines(&verilog, name, &ins, &outs, rows, &bt.rust_hdl);
}

#[test]
fn top_engine_equals_rust_hdl_and_verilator() {
    use sinedec::blocks::top::hdl::TopRtl;
    use sinedec::sim::encoder::EncoderModel;
    use sinedec::sim::system::System;
    let l = Loaded::default_config().expect("default config");
    let d = &l.derived;
    let enc = EncoderModel::ideal(2048, 1.0, 3000.0).with_seed(5);
    let mut s = System::new(d, enc).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    s.run(30_000).expect("runs");
    let r = s.finish();
    let name = format!("{}_top_rtl", l.config.name);
    top_case(TopRtl::new(d).expect("top"), &name, &r.inputs, "par_valid");
}

#[test]
fn capacitive_top_engine_equals_rust_hdl_and_verilator() {
    use sinedec::blocks::captop::hdl::CapTopRtl;
    use sinedec::sim::cap_system::CapSystem;
    use sinedec::sim::capacitive::CapParams;
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/configs/cyclone3_capacitive.toml"
    ))
    .expect("config file");
    let l = Loaded::parse(&text, "cyclone3_capacitive.toml").expect("config");
    let d = &l.derived;
    let mut s = CapSystem::new(d, CapParams::paper()).expect("system");
    s.record_inputs();
    s.start().expect("settles");
    s.run(30_000).expect("runs");
    let rows = s.inputs.take().expect("recorded");
    let name = format!("{}_top_rtl", l.config.name);
    top_case(CapTopRtl::new(d).expect("top"), &name, &rows, "par_valid");
}

/// A hand-written module with what the sinedec designs use little or not at all (signed
/// compare, arithmetic shift, a written memory, an initial value, enable and reset) against
/// a model written from the Verilog semantics.
#[test]
fn small_module_matches_its_verilog_semantics() {
    const V: &str = "module t(input clk, input rst, input en, input [7:0] a, input [7:0] b,
        output reg [7:0] cnt, output [8:0] sum, output lt_s, output [7:0] sra, output [7:0] rd);
      reg [7:0] mem [0:15];
      initial cnt = 8'd5;
      always @(posedge clk) begin
        if (rst) cnt <= 8'd0; else if (en) cnt <= cnt + 8'd1;
        if (en) mem[a[3:0]] <= b;
      end
      assign sum = a + b;
      assign lt_s = $signed(a) < $signed(b);
      assign sra = $signed(a) >>> b[2:0];
      assign rd = mem[b[3:0]];
    endmodule";
    let ins: Vec<Port> = [("rst", 1), ("en", 1), ("a", 8), ("b", 8)]
        .iter()
        .map(|(n, w)| Port::new(n, *w))
        .collect();
    let outs: Vec<Port> = [("cnt", 8), ("sum", 9), ("lt_s", 1), ("sra", 8), ("rd", 8)]
        .iter()
        .map(|(n, w)| Port::new(n, *w))
        .collect();
    let mut x = 12345u64;
    let mut rnd = || {
        x = x
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        x >> 33
    };
    let rows: Vec<Vec<u64>> = (0..3000)
        .map(|k| {
            vec![
                (k % 700 == 699) as u64,
                rnd() & 1,
                rnd() & 0xff,
                rnd() & 0xff,
            ]
        })
        .collect();
    let (mut cnt, mut mem) = (5u64, [0u64; 16]);
    let want: Trace = rows
        .iter()
        .map(|r| {
            let (rst, en, a, b) = (r[0], r[1], r[2], r[3]);
            cnt = if rst == 1 {
                0
            } else if en == 1 {
                (cnt + 1) & 0xff
            } else {
                cnt
            };
            if en == 1 {
                mem[(a & 15) as usize] = b;
            }
            let sa = a as u8 as i8 as i64;
            let sb = b as u8 as i8 as i64;
            vec![
                cnt,
                a + b,
                (sa < sb) as u64,
                ((sa >> (b & 7)) as u64) & 0xff,
                mem[(b & 15) as usize],
            ]
        })
        .collect();
    assert!(want.iter().filter(|r| r[2] == 1).count() > 1000);
    check_engines(V, "t", &ins, &outs, &rows, &want);
}
