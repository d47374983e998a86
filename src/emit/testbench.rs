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
//! `-g2012` works as well: no identifier is a SystemVerilog keyword (`tests/testbench.rs`).
//!
//! Timing per cycle (the co-simulation harness's semantics): inputs change while `clk` is
//! low, `clk` rises, outputs are compared 1 ns after the edge.
use crate::blocks::core::model::{CoreIn, CoreModel};
use crate::blocks::mask;
use crate::config::Loaded;
use crate::emit::{core_input_ports, core_name, core_output_ports};
use crate::sim::stimulus;

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

/// Verilog text of `<name>_core_tb`.
pub fn core_testbench(loaded: &Loaded) -> String {
    let d = &loaded.derived;
    let stim = testbench_stimulus(loaded);
    let mut model = CoreModel::new(d);
    let ins = core_input_ports(d);
    let outs = core_output_ports(d);
    let in_bits: u32 = ins.iter().map(|p| p.width).sum();
    let out_bits: u32 = outs.iter().map(|p| p.width).sum();
    let name = core_name(loaded);
    let am = mask(d.adc_width);
    let mut vectors = String::new();
    for (k, i) in stim.iter().enumerate() {
        let o = model.step(*i);
        let iv = [
            i.rst as u64,
            i.valid as u64,
            i.sin as u64 & am,
            i.cos as u64 & am,
        ];
        let ov = o.row();
        vectors.push_str(&format!(
            "        stim[{k}] = {in_bits}'b{}; expected[{k}] = {out_bits}'b{};\n",
            bits(&iv, &ins),
            bits(&ov, &outs)
        ));
    }
    let n = stim.len();
    let in_list = ins
        .iter()
        .map(|p| p.name.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let out_list = outs
        .iter()
        .map(|p| p.name.as_str())
        .collect::<Vec<_>>()
        .join(", ");
    let decl = |ports: &[crate::sim::cosim::Port], kind: &str| {
        ports
            .iter()
            .map(|p| {
                if p.width == 1 {
                    format!("    {kind} {};\n", p.name)
                } else {
                    format!("    {kind} [{}:0] {};\n", p.width - 1, p.name)
                }
            })
            .collect::<String>()
    };
    let conns = ins
        .iter()
        .chain(outs.iter())
        .map(|p| format!(".{0}({0})", p.name))
        .collect::<Vec<_>>()
        .join(", ");
    format!(
        r#"// {name}_tb: self-checking testbench, {n} cycles; prints PASS or FAIL and the first
// mismatches. Stimulus and expected outputs from sinedec's bit-accurate model.
module {name}_tb;
    reg clk = 1'b0;
{in_decl}{out_decl}    reg [{im}:0] stim [0:{nm}];   // {{{in_list}}} per cycle
    reg [{om}:0] expected [0:{nm}]; // {{{out_list}}} per cycle
    integer k;
    // Initialized here, not by the stimulus process: Verilator 5.006 propagates a 0 assigned
    // there into the final check and reports PASS however many cycles mismatched.
    integer errors = 0;
    {name} dut(.clk(clk), {conns}, .in_ready());
    initial begin
{vectors}    end
    // Checker: 1 ns after each rising edge, the outputs of cycle k against expected[k].
    always @(posedge clk) begin
        #1 if ({{{out_list}}} !== expected[k]) begin
            errors = errors + 1;
            if (errors <= 10)
                $display("cycle %0d: got %b expected %b", k, {{{out_list}}}, expected[k]);
        end
    end
    // Stimulus: inputs change while clk is low, then clk rises.
    initial begin
        {{{in_list}}} = {in_bits}'d0;
        for (k = 0; k <= {nm}; k = k + 1) begin
            {{{in_list}}} = stim[k];
            #5 clk = 1'b1;
            #5 clk = 1'b0;
        end
        if (errors == 0) begin
            $display("PASS: %0d cycles", {n});
            $finish;
        end else begin
            $display("FAIL: %0d mismatching cycles", errors);
            // Non-zero exit status: vvp exits 1, a Verilator binary aborts.
            $fatal(1, "{name}_tb: %0d mismatching cycles", errors);
        end
    end
endmodule // {name}_tb
"#,
        in_decl = decl(&ins, "reg"),
        out_decl = decl(&outs, "wire"),
        im = in_bits - 1,
        om = out_bits - 1,
        nm = n - 1,
    )
}

fn bits(values: &[u64], ports: &[crate::sim::cosim::Port]) -> String {
    values
        .iter()
        .zip(ports)
        .map(|(v, p)| format!("{:0w$b}", v & mask(p.width), w = p.width as usize))
        .collect::<Vec<_>>()
        .join("_")
}
