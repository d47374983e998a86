//! Self-checking Verilog testbench for `<name>_core`: stimulus and expected outputs come
//! from the bit-accurate Rust model (which the test suite proves equal to the RTL), so a user
//! can re-run the check in any Verilog simulator:
//!
//! ```text
//! iverilog -g2005 -o tb.vvp <name>_core.v <name>_core_tb.v && vvp -n tb.vvp
//! verilator --binary --timing --top-module <name>_core_tb <name>_core.v <name>_core_tb.v \
//!     && ./obj_dir/V<name>_core_tb
//! ```
//!
//! Both print PASS and exit 0, or print FAIL with the first mismatches and exit non-zero
//! (`$fatal`: vvp exits 1, the Verilator binary aborts), so a CI job can use the exit status.
//! `-g2012` works as well: no identifier is a SystemVerilog keyword (`tests/flow/testbench.rs`).
//!
//! Timing per cycle (the co-simulation harness's semantics): inputs change while `clk` is
//! low, `clk` rises, outputs are compared 1 ns after the edge.
use crate::blocks::core::model::{CoreIn, CoreModel};
use crate::blocks::mask;
use crate::config::Loaded;
use crate::cosim::stimulus;
use crate::cosim::Port;
use crate::emit::templates::render;
use crate::emit::{core_input_ports, core_name, core_output_ports};
use crate::error::Result;

/// The stimulus the emitted testbench uses: directed cases, random samples with gaps and a
/// reset, and a rotation over a turn in each direction.
pub fn testbench_stimulus(loaded: &Loaded) -> Vec<CoreIn> {
    let d = &loaded.derived;
    let a = d.adc_width;
    let mut s = stimulus::directed(a);
    s.extend(stimulus::random(a, 1000, 0.2, 0x5eed));
    let step = std::f64::consts::FRAC_PI_2 * 0.45;
    s.extend(stimulus::rotation(a, 0.7, 0.1, step, 200));
    s.extend(stimulus::rotation(a, 0.7, 0.1, -step, 200));
    s.extend((0..d.latency_cycles + 2).map(|_| stimulus::idle()));
    s
}

/// Verilog text of `<name>_core_tb` (`rtl-templates/tb/core_tb.v.j2`).
pub fn core_testbench(loaded: &Loaded) -> Result<String> {
    let d = &loaded.derived;
    let stim = testbench_stimulus(loaded);
    let mut model = CoreModel::new(d);
    let ins = core_input_ports(d);
    let outs = core_output_ports(d);
    let am = mask(d.adc_width);
    // One (stimulus bits, expected bits) pair per cycle, fields separated by `_`.
    let vectors: Vec<(String, String)> = stim
        .iter()
        .map(|i| {
            let o = model.step(*i);
            let iv = [
                i.rst as u64,
                i.valid as u64,
                i.sin as u64 & am,
                i.cos as u64 & am,
            ];
            (bits(&iv, &ins), bits(&o.row(), &outs))
        })
        .collect();
    let names = |ports: &[Port]| {
        ports
            .iter()
            .map(|p| p.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let list = |ports: &[Port]| -> Vec<minijinja::Value> {
        ports
            .iter()
            .map(|p| minijinja::context! { name => p.name.as_str(), width => p.width })
            .collect()
    };
    let conns = ins
        .iter()
        .chain(outs.iter())
        .map(|p| format!(".{0}({0})", p.name))
        .collect::<Vec<_>>()
        .join(", ");
    render(
        "tb/core_tb.v.j2",
        minijinja::context! {
            name => core_name(loaded),
            n => stim.len(),
            inputs => list(&ins),
            outputs => list(&outs),
            in_bits => ins.iter().map(|p| p.width).sum::<u32>(),
            out_bits => outs.iter().map(|p| p.width).sum::<u32>(),
            in_list => names(&ins),
            out_list => names(&outs),
            conns => conns,
            vectors => vectors,
        },
    )
}

fn bits(values: &[u64], ports: &[Port]) -> String {
    values
        .iter()
        .zip(ports)
        .map(|(v, p)| format!("{:0w$b}", v & mask(p.width), w = p.width as usize))
        .collect::<Vec<_>>()
        .join("_")
}
