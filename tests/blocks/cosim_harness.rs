//! Tests of the co-simulation harness (`sinedec::cosim`): a small hand-written design is
//! simulated in Icarus Verilog and Verilator and compared with an independent Rust reference
//! model; trace comparison, X detection and missing-tool reporting are checked too.

use sinedec::cosim::{
    check_tool_named, first_mismatch, require_tool, run_icarus, run_verilator, CosimError,
    CosimSpec, Port, Trace,
};
use std::path::Path;

/// Unwraps a harness result, panicking with the error's human-readable message.
fn ok<T>(r: Result<T, CosimError>) -> T {
    r.unwrap_or_else(|e| panic!("{e}"))
}

fn workdir() -> tempfile::TempDir {
    tempfile::tempdir().unwrap_or_else(|e| panic!("cannot create a temporary directory: {e}"))
}

/// Demo design spread over several modules:
/// * `count`: 8-bit counter with synchronous reset (priority) and enable;
/// * `sum`/`carry`: 40-bit registered adder of `a` and `b` with carry out;
/// * `mix`: purely combinational `count ^ sel` (current register state, current input);
/// * `diff`: purely combinational 20-bit `a[19:0] - b[19:0]` (an IData port);
/// * `wide`: 64-bit register loading `d` rotated left by one bit (a full-width QData port);
/// * `nib`: 13-bit register loading `{sel[4:0], count}` (an SData port).
const DEMO_VERILOG: &str = r#"
module demo_counter(input clock, input reset, input enable, output reg [7:0] count);
  initial count = 8'd0;
  always @(posedge clock) begin
    if (reset) count <= 8'd0;
    else if (enable) count <= count + 8'd1;
  end
endmodule

module demo_adder(input clock, input [39:0] a, input [39:0] b,
                  output reg [39:0] sum, output reg carry);
  initial begin sum = 40'd0; carry = 1'b0; end
  always @(posedge clock) {carry, sum} <= {1'b0, a} + {1'b0, b};
endmodule

module demo_rot(input clock, input [63:0] d, output reg [63:0] q);
  initial q = 64'd0;
  always @(posedge clock) q <= {d[62:0], d[63]};
endmodule

module demo_top(
  input clock,
  input reset,
  input enable,
  input [39:0] a,
  input [39:0] b,
  input [7:0] sel,
  input [63:0] d,
  output [7:0] count,
  output [39:0] sum,
  output carry,
  output [7:0] mix,
  output [19:0] diff,
  output [63:0] wide,
  output reg [12:0] nib
);
  demo_counter u_counter(.clock(clock), .reset(reset), .enable(enable), .count(count));
  demo_adder u_adder(.clock(clock), .a(a), .b(b), .sum(sum), .carry(carry));
  demo_rot u_rot(.clock(clock), .d(d), .q(wide));
  initial nib = 13'd0;
  always @(posedge clock) nib <= {sel[4:0], count};
  assign mix = count ^ sel;
  assign diff = a[19:0] - b[19:0];
endmodule
"#;

fn demo_inputs() -> Vec<Port> {
    vec![
        Port::new("reset", 1),
        Port::new("enable", 1),
        Port::new("a", 40),
        Port::new("b", 40),
        Port::new("sel", 8),
        Port::new("d", 64),
    ]
}

fn demo_outputs() -> Vec<Port> {
    vec![
        Port::new("count", 8),
        Port::new("sum", 40),
        Port::new("carry", 1),
        Port::new("mix", 8),
        Port::new("diff", 20),
        Port::new("wide", 64),
        Port::new("nib", 13),
    ]
}

/// Deterministic xorshift64* generator for the stimulus.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

const MASK40: u64 = (1 << 40) - 1;

/// Stimulus: reset at the start and twice mid-stream, random enable (mostly on) so the counter
/// wraps, random 40-bit operands with some all-ones/carry corner cases, and random 64-bit `d`.
/// Values are deliberately given with bits above the port widths set: the harness must mask.
fn demo_stimulus(cycles: usize) -> Vec<Vec<u64>> {
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    (0..cycles)
        .map(|k| {
            let r = rng.next();
            let reset = u64::from(k < 2 || (300..303).contains(&k) || k == 700);
            let enable = u64::from(!r.is_multiple_of(8)) | 0b10; // bit 1 must be masked away
            let (a, b) = match k % 50 {
                7 => (MASK40, 1),
                8 => (MASK40, MASK40),
                9 => (0, 0),
                _ => (rng.next() | (1 << 45), rng.next()), // bit 45 must be masked away
            };
            let sel = rng.next() & 0x3FF; // bits 8..9 must be masked away
            let d = match k % 97 {
                3 => u64::MAX,
                4 => 1 << 63,
                _ => rng.next(),
            };
            vec![reset, enable, a, b, sel, d]
        })
        .collect()
}

/// Independent reference model of `demo_top` following the harness's cycle semantics: row `k`
/// of the result is the state after the `k`-th rising edge (inputs of row `k` applied before
/// it), with combinational outputs computed from row `k`'s inputs.
fn demo_reference(stimulus: &[Vec<u64>]) -> Trace {
    let mut count = 0u8;
    let mut trace = Vec::new();
    for row in stimulus {
        let reset = row[0] & 1 == 1;
        let enable = row[1] & 1 == 1;
        let a = row[2] & MASK40;
        let b = row[3] & MASK40;
        let sel = (row[4] & 0xFF) as u8;
        let d = row[5];
        // Rising edge: every register loads from the values before the edge.
        let full = a + b;
        let next_nib = (u64::from(sel & 0x1F) << 8) | u64::from(count);
        count = if reset {
            0
        } else if enable {
            count.wrapping_add(1)
        } else {
            count
        };
        let sum = full & MASK40;
        let carry = full >> 40;
        let wide = d.rotate_left(1);
        let nib = next_nib;
        // Outputs after the edge.
        let mix = count ^ sel;
        let diff = (a & 0xFFFFF).wrapping_sub(b & 0xFFFFF) & 0xFFFFF;
        trace.push(vec![
            u64::from(count),
            sum,
            carry,
            u64::from(mix),
            diff,
            wide,
            nib,
        ]);
    }
    trace
}

fn demo_spec<'a>(inputs: &'a [Port], outputs: &'a [Port]) -> CosimSpec<'a> {
    CosimSpec {
        verilog: DEMO_VERILOG,
        top: "demo_top",
        clock: "clock",
        inputs,
        outputs,
    }
}

fn assert_same(name: &str, got: &Trace, expected: &Trace, outputs: &[Port]) {
    if let Some(m) = first_mismatch(name, got, "reference", expected, outputs) {
        panic!("{name} disagrees with the Rust reference: {m}");
    }
}

/// Sanity checks on the reference model itself, so that a broken reference cannot make the
/// simulator comparisons meaningless (e.g. a counter stuck at 0 would hide edge errors).
#[test]
fn reference_model_sanity() {
    let stim = demo_stimulus(1000);
    let r = demo_reference(&stim);
    assert_eq!(r.len(), 1000);
    assert_eq!(r[0][0], 0, "reset in row 0 clears the counter");
    assert_eq!(r[2][0], stim[2][1] & 1, "first increment after reset");
    assert_eq!(r[301][0], 0, "mid-stream reset");
    assert!(r.iter().any(|row| row[0] == 255), "the counter reaches 255");
    assert!(r.iter().any(|row| row[2] == 1), "the adder carries");
    assert_eq!(r[8][1], MASK40 - 1);
    assert_eq!(r[8][2], 1);
    assert_eq!(r[4][5], 1, "wide rotates 1<<63 into bit 0");
}

#[test]
fn icarus_matches_reference() {
    ok(require_tool("iverilog"));
    ok(require_tool("vvp"));
    let (inputs, outputs) = (demo_inputs(), demo_outputs());
    let spec = demo_spec(&inputs, &outputs);
    let stim = demo_stimulus(2000);
    let dir = workdir();
    let got = ok(run_icarus(&spec, &stim, dir.path()));
    assert_eq!(got.len(), stim.len());
    assert_same("icarus", &got, &demo_reference(&stim), &outputs);
}

#[test]
fn verilator_matches_reference() {
    ok(require_tool("verilator"));
    let (inputs, outputs) = (demo_inputs(), demo_outputs());
    let spec = demo_spec(&inputs, &outputs);
    let stim = demo_stimulus(2000);
    let dir = workdir();
    let got = ok(run_verilator(&spec, &stim, dir.path()));
    assert_eq!(got.len(), stim.len());
    assert_same("verilator", &got, &demo_reference(&stim), &outputs);
}

/// One work directory serves both simulators and successive designs: a second, different
/// design (different ports, fewer modules) simulated in the same directory must not pick up
/// anything stale from the first.
#[test]
fn workdir_is_reused_across_designs_and_simulators() {
    let (inputs, outputs) = (demo_inputs(), demo_outputs());
    let spec = demo_spec(&inputs, &outputs);
    let stim = demo_stimulus(64);
    let dir = workdir();
    let expected = demo_reference(&stim);
    assert_same(
        "verilator",
        &ok(run_verilator(&spec, &stim, dir.path())),
        &expected,
        &outputs,
    );
    assert_same(
        "icarus",
        &ok(run_icarus(&spec, &stim, dir.path())),
        &expected,
        &outputs,
    );

    // Second design: an accumulator with a single input and the clock named differently.
    let verilog = r#"
module acc(input clk, input [15:0] x, output reg [15:0] total, output [15:0] next);
  initial total = 16'd0;
  assign next = total + x;
  always @(posedge clk) total <= next;
endmodule
"#;
    let inputs2 = [Port::new("x", 16)];
    let outputs2 = [Port::new("total", 16), Port::new("next", 16)];
    let spec2 = CosimSpec {
        verilog,
        top: "acc",
        clock: "clk",
        inputs: &inputs2,
        outputs: &outputs2,
    };
    let stim2: Vec<Vec<u64>> = (0..50u64).map(|k| vec![k * 1000 + 7]).collect();
    let mut total = 0u16;
    let expected2: Trace = stim2
        .iter()
        .map(|row| {
            total = total.wrapping_add(row[0] as u16);
            vec![
                u64::from(total),
                u64::from(total.wrapping_add(row[0] as u16)),
            ]
        })
        .collect();
    assert_same(
        "verilator",
        &ok(run_verilator(&spec2, &stim2, dir.path())),
        &expected2,
        &outputs2,
    );
    assert_same(
        "icarus",
        &ok(run_icarus(&spec2, &stim2, dir.path())),
        &expected2,
        &outputs2,
    );
}

#[test]
fn first_mismatch_finds_first_difference() {
    let outputs = demo_outputs();
    let stim = demo_stimulus(40);
    let a = demo_reference(&stim);
    assert_eq!(
        first_mismatch("icarus", &a, "rust-hdl", &a.clone(), &outputs),
        None
    );

    let mut b = a.clone();
    b[17][1] ^= 0x10_0000_0000; // `sum`, cycle 17
    b[30][0] ^= 1; // a later difference must not be the one reported
    let m = first_mismatch("icarus", &a, "rust-hdl", &b, &outputs)
        .unwrap_or_else(|| panic!("altered trace reported as equal"));
    assert!(m.contains("cycle 17"), "{m}");
    assert!(m.contains("`sum`"), "{m}");
    assert!(m.contains(&format!("icarus=0x{:010x}", a[17][1])), "{m}");
    assert!(m.contains(&format!("rust-hdl=0x{:010x}", b[17][1])), "{m}");

    // Row-count difference with an equal common prefix.
    let short: Trace = a[..35].to_vec();
    let m = first_mismatch("verilator", &a, "icarus", &short, &outputs)
        .unwrap_or_else(|| panic!("shorter trace reported as equal"));
    assert!(m.contains("verilator has 40 cycles"), "{m}");
    assert!(m.contains("icarus has 35 cycles"), "{m}");

    // Value difference before the end of a shorter trace is reported first, with a note.
    let mut short2 = short.clone();
    short2[3][6] ^= 1;
    let m = first_mismatch("verilator", &a, "icarus", &short2, &outputs)
        .unwrap_or_else(|| panic!("altered trace reported as equal"));
    assert!(
        m.contains("cycle 3") && m.contains("`nib`") && m.contains("row counts"),
        "{m}"
    );

    // A row with a missing column.
    let mut c = a.clone();
    c[5].pop();
    let m = first_mismatch("a", &a, "b", &c, &outputs)
        .unwrap_or_else(|| panic!("short row reported as equal"));
    assert!(
        m.contains("cycle 5") && m.contains("7 values") && m.contains("6 values"),
        "{m}"
    );
}

/// An output driven by a register that is never initialised nor assigned is X in Icarus; the
/// harness must report it as a Parse error naming the port and cycle.
#[test]
fn icarus_reports_x_outputs() {
    let verilog = r#"
module xdesign(input clock, input d, output reg q, output [3:0] y);
  reg [3:0] never_set;
  initial q = 1'b0;
  always @(posedge clock) q <= d;
  assign y = never_set;
endmodule
"#;
    let inputs = [Port::new("d", 1)];
    let outputs = [Port::new("q", 1), Port::new("y", 4)];
    let spec = CosimSpec {
        verilog,
        top: "xdesign",
        clock: "clock",
        inputs: &inputs,
        outputs: &outputs,
    };
    let stim = vec![vec![1], vec![0], vec![1]];
    let dir = workdir();
    match run_icarus(&spec, &stim, dir.path()) {
        Err(CosimError::Parse(m)) => {
            assert!(m.contains("`y`") && m.contains("cycle 0"), "{m}");
            assert!(m.contains("unknown"), "{m}");
        }
        other => panic!("expected a Parse error for an X output, got {other:?}"),
    }
}

/// Syntax errors are reported as compile failures of the right tool, with the tool's message.
#[test]
fn compile_errors_are_reported() {
    let verilog = "module broken(input clock, output y);\n  assign y = ;\nendmodule\n";
    let outputs = [Port::new("y", 1)];
    let spec = CosimSpec {
        verilog,
        top: "broken",
        clock: "clock",
        inputs: &[],
        outputs: &outputs,
    };
    let dir = workdir();
    let stim = vec![vec![]; 3];
    for (sim, result) in [
        ("iverilog", run_icarus(&spec, &stim, dir.path())),
        ("verilator", run_verilator(&spec, &stim, dir.path())),
    ] {
        match result {
            Err(CosimError::ToolFailed {
                tool,
                stage,
                message,
            }) => {
                assert_eq!(tool, sim);
                assert_eq!(stage, "compile");
                assert!(message.contains("cosim_design.v"), "{sim}: {message}");
            }
            other => panic!("{sim}: expected a compile failure, got {other:?}"),
        }
    }
}

/// Invalid specifications and stimuli are rejected before any tool runs.
#[test]
fn invalid_specs_are_rejected() {
    let inputs = [Port::new("a", 8)];
    let outputs = [Port::new("y", 65)];
    let spec = CosimSpec {
        verilog: "",
        top: "t",
        clock: "clock",
        inputs: &inputs,
        outputs: &outputs,
    };
    let dir = workdir();
    assert!(
        matches!(run_icarus(&spec, &[vec![1]], dir.path()), Err(CosimError::Parse(m)) if m.contains("65"))
    );
    let outputs = [Port::new("y", 8)];
    let spec = CosimSpec {
        outputs: &outputs,
        ..spec
    };
    assert!(
        matches!(run_verilator(&spec, &[vec![1, 2]], dir.path()), Err(CosimError::Parse(m)) if m.contains("row 0"))
    );
    let missing = Path::new("/nonexistent/cosim/dir");
    assert!(matches!(
        run_icarus(&spec, &[vec![1]], missing),
        Err(CosimError::Io { .. })
    ));
}

#[test]
fn missing_tool_is_reported() {
    match check_tool_named(
        "sinedec-no-such-simulator-xyz",
        "apt-get install -y nothing",
    ) {
        Err(CosimError::ToolMissing { tool, install }) => {
            assert_eq!(tool, "sinedec-no-such-simulator-xyz");
            assert_eq!(install, "apt-get install -y nothing");
        }
        other => panic!("expected ToolMissing, got {other:?}"),
    }
    let msg = CosimError::ToolMissing {
        tool: "iverilog".into(),
        install: "apt-get install -y iverilog".into(),
    }
    .to_string();
    assert!(msg.contains("apt-get install -y iverilog"), "{msg}");
    // The installed tools are found.
    for tool in ["iverilog", "vvp", "verilator", "yosys"] {
        ok(require_tool(tool));
    }
}

/// Verilog of a 20-module pipeline (distinct stage modules with 16-bit state, a combinational
/// XOR of all stages) used to time the harness on a design of realistic module count.
fn pipeline_verilog(stages: usize) -> String {
    let mut v = String::new();
    for i in 0..stages {
        v.push_str(&format!(
            "module stage{i}(input clock, input [15:0] x, output reg [15:0] y);\n\
             \x20 initial y = 16'd0;\n\
             \x20 always @(posedge clock) y <= (x ^ 16'd{c}) + {{y[14:0], y[15]}} + 16'd{i};\n\
             endmodule\n",
            c = 0x1234 + 97 * i
        ));
    }
    v.push_str("module pipeline(input clock, input [15:0] din, output [15:0] dout, output [15:0] parity);\n");
    for i in 0..stages {
        v.push_str(&format!("  wire [15:0] s{i};\n"));
        let x = if i == 0 {
            "din".to_string()
        } else {
            format!("s{}", i - 1)
        };
        v.push_str(&format!(
            "  stage{i} u{i}(.clock(clock), .x({x}), .y(s{i}));\n"
        ));
    }
    v.push_str(&format!("  assign dout = s{};\n", stages - 1));
    let all: Vec<String> = (0..stages).map(|i| format!("s{i}")).collect();
    v.push_str(&format!(
        "  assign parity = {};\nendmodule\n",
        all.join(" ^ ")
    ));
    v
}

/// Icarus and Verilator agree on a 20-module pipeline over 5 000 cycles, and a second
/// Verilator build in the same work directory gives the same trace.
#[test]
fn icarus_and_verilator_agree_on_a_20_module_pipeline() {
    let verilog = pipeline_verilog(20);
    let inputs = [Port::new("din", 16)];
    let outputs = [Port::new("dout", 16), Port::new("parity", 16)];
    let spec = CosimSpec {
        verilog: &verilog,
        top: "pipeline",
        clock: "clock",
        inputs: &inputs,
        outputs: &outputs,
    };
    let mut rng = Rng(12345);
    let stim: Vec<Vec<u64>> = (0..5_000).map(|_| vec![rng.next() & 0xFFFF]).collect();
    let dir = workdir();
    let iv = ok(run_icarus(&spec, &stim, dir.path()));
    let vl = ok(run_verilator(&spec, &stim, dir.path()));
    if let Some(m) = first_mismatch("icarus", &iv, "verilator", &vl, &outputs) {
        panic!("{m}");
    }
    let vl2 = ok(run_verilator(&spec, &stim, dir.path()));
    assert_eq!(vl, vl2);
}
