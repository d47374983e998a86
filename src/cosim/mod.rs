//! Co-simulation harness: drives the exported Verilog of a synchronous design in
//! Icarus Verilog, in Verilator and in sinedec's compiled engine (`engine.rs`) with one
//! stimulus and returns the output traces,
//! so that they can be compared bit-for-bit with a rust-hdl simulation of the same design.
//!
//! # Cycle semantics
//!
//! Both simulators follow exactly the same protocol. Initially the clock is 0 and every
//! input is 0 (registers start from their Verilog `initial` blocks). Then, for each
//! stimulus row `k` (`k = 0..stimulus.len()`):
//!
//! 1. the inputs are driven with row `k` while the clock is low, and combinational logic settles;
//! 2. the clock rises (the `k`-th rising edge) and everything settles;
//! 3. every output is sampled, giving output row `k`;
//! 4. the clock falls.
//!
//! ```text
//!                 row 0             row 1             row 2
//!             |<--------------->|<--------------->|<--------------->|
//! clock  _____________/‾‾‾‾‾‾‾‾\________/‾‾‾‾‾‾‾‾\________/‾‾‾‾‾‾‾‾\__
//! inputs ==X==< in[0]           >< in[1]           >< in[2]           >
//!                 ^      ^    ^
//!                 |      |    +-- sample outputs -> out[0]
//!                 |      +------- rising edge #0 (registers load from in[0])
//!                 +-------------- inputs of row 0 applied, clock low
//! ```
//!
//! So output row `k` shows the state after the `k`-th rising edge, with the inputs of row `k`
//! applied before that edge; purely combinational outputs reflect row `k`'s inputs and the
//! register state after the edge.
//!
//! In Icarus the cycle is 10 time units long: inputs at `t+2`, rising edge at `t+5`, sampling
//! at `t+8`, falling edge at `t+10`. In Verilator the model is evaluated after each of the
//! three changes (inputs, rising edge, falling edge) and sampled after the rising-edge `eval()`.
//!
//! # Values
//!
//! Every value is a `u64` holding the port's bits (ports are 1..=64 bits wide); signed ports
//! are given and returned as raw two's complement bits within the width. Stimulus values are
//! masked to the input width before they are applied; output values wider than their port,
//! or containing `x`/`z` bits (Icarus), are reported as [`CosimError::Parse`].
//!
//! # Files
//!
//! Everything is written into the caller-given work directory (which must exist and whose path
//! must not contain spaces, a GNU make restriction that matters for Verilator). Each simulator
//! has its own file names, so one directory can serve both simulators and successive designs:
//!
//! * `cosim_design.v`: the design source (shared, rewritten by each run);
//! * `cosim_stimulus.hex`: one line per cycle, input values in hex separated by spaces (shared);
//! * Icarus: `cosim_tb.v`, `cosim_icarus.vvp`, `cosim_icarus_out.hex`, `cosim_icarus_*.log`;
//! * Verilator: `cosim_main.cpp`, `cosim_verilator_obj/` (with the `cosim_sim` executable),
//!   `cosim_verilator_out.hex`, `cosim_verilator_*.log`.
//!
//! Every tool invocation is bounded by a time limit of [`TOOL_TIMEOUT`]; a tool that exceeds it
//! is killed and reported as [`CosimError::ToolFailed`].
use std::fmt::Write as _;
use std::fs;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};

mod block;
mod cache;
mod engine;
mod icarus;
pub mod step;
pub mod stimulus;
mod tool;
mod verilator;

pub(crate) use block::cosim_block;
pub use block::{CosimBlock, RowValue};
pub use cache::{passed_once, Verdict, COSIM_CACHE_ENV};
pub use engine::{cosim_engine_kind, run_engine, run_engine_expecting, BlockEngine, ENGINE_ENV};
pub use icarus::{run_icarus, run_icarus_expecting};
pub(crate) use tool::run_checked;
pub use tool::{check_tool_named, require_tool, tool_version_of, CosimError, TOOL_TIMEOUT};
use tool::{io_err, read_file, trim_message, write_file, ToolOutput};
pub use verilator::{run_verilator, run_verilator_expecting};

/// One port of the design under test: its Verilog name and width in bits (1..=64).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Port {
    /// The port's name in the Verilog top module (a plain identifier: `[A-Za-z_][A-Za-z0-9_]*`).
    pub name: String,
    /// The port's width in bits, 1..=64.
    pub width: u32,
}

impl Port {
    /// Creates a port description from its Verilog name and its width in bits (1..=64).
    pub fn new(name: &str, width: u32) -> Port {
        Port {
            name: name.to_string(),
            width,
        }
    }

    /// Bit mask covering the port's width (all ones for 64 bits).
    fn mask(&self) -> u64 {
        mask_for(self.width)
    }

    /// Number of hexadecimal digits needed to print a value of this port.
    fn hex_digits(&self) -> usize {
        self.width.div_ceil(4) as usize
    }
}

/// What to simulate: Verilog source text (may contain many modules), the top module's name,
/// its clock input's name (driven by the harness), its other inputs and the outputs to record.
pub struct CosimSpec<'a> {
    /// Verilog source text of the design; may contain many modules.
    pub verilog: &'a str,
    /// Name of the top module to simulate.
    pub top: &'a str,
    /// Name of the top module's clock input; the harness drives it (it must not be in `inputs`).
    pub clock: &'a str,
    /// The other inputs of the top module, in the column order of the stimulus rows.
    pub inputs: &'a [Port],
    /// The outputs to record, in the column order of the returned trace rows.
    pub outputs: &'a [Port],
}

/// One row per clock cycle; values in `inputs`/`outputs` order, each masked to the port width
/// (signed values are given and returned as raw two's complement bits within the width).
pub type Trace = Vec<Vec<u64>>;

/// Name of the generated Icarus testbench module.
const TB_MODULE: &str = "cosim_tb";
const DESIGN_FILE: &str = "cosim_design.v";
const STIMULUS_FILE: &str = "cosim_stimulus.hex";
const ICARUS_TB_FILE: &str = "cosim_tb.v";
const ICARUS_VVP_FILE: &str = "cosim_icarus.vvp";
const ICARUS_OUT_FILE: &str = "cosim_icarus_out.hex";
const VERILATOR_MAIN_FILE: &str = "cosim_main.cpp";
const VERILATOR_OBJ_DIR: &str = "cosim_verilator_obj";
const VERILATOR_EXE: &str = "cosim_sim";
const VERILATOR_OUT_FILE: &str = "cosim_verilator_out.hex";
/// Marker printed by the generated testbenches on fatal errors (bad stimulus file, ...).
const ERROR_MARKER: &str = "COSIM_ERROR";

fn mask_for(width: u32) -> u64 {
    if width >= 64 {
        u64::MAX
    } else {
        (1u64 << width) - 1
    }
}

/// Whether `name` is a plain identifier usable unescaped in Verilog and in C++.
fn is_plain_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    match chars.next() {
        Some(c) if c.is_ascii_alphabetic() || c == '_' => {}
        _ => return false,
    }
    chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

/// Checks port names and widths, the clock and top names, and the stimulus shape.
fn validate(spec: &CosimSpec, stimulus: &[Vec<u64>]) -> Result<(), CosimError> {
    for (what, name) in [("top module", spec.top), ("clock", spec.clock)] {
        if !is_plain_identifier(name) {
            return Err(CosimError::Parse(format!(
                "invalid {what} name {name:?}: must match [A-Za-z_][A-Za-z0-9_]*"
            )));
        }
    }
    let mut seen = std::collections::HashSet::new();
    seen.insert(spec.clock);
    for (kind, ports) in [("input", spec.inputs), ("output", spec.outputs)] {
        for p in ports {
            if !is_plain_identifier(&p.name) {
                return Err(CosimError::Parse(format!(
                    "invalid {kind} port name {:?}: must match [A-Za-z_][A-Za-z0-9_]*",
                    p.name
                )));
            }
            if !(1..=64).contains(&p.width) {
                return Err(CosimError::Parse(format!(
                    "{kind} port `{}` has width {}; supported widths are 1..=64",
                    p.name, p.width
                )));
            }
            if !seen.insert(p.name.as_str()) {
                return Err(CosimError::Parse(format!(
                    "port `{}` is listed more than once (or is the clock)",
                    p.name
                )));
            }
        }
    }
    for (k, row) in stimulus.iter().enumerate() {
        if row.len() != spec.inputs.len() {
            return Err(CosimError::Parse(format!(
                "stimulus row {k} has {} values but the design has {} inputs",
                row.len(),
                spec.inputs.len()
            )));
        }
    }
    Ok(())
}

/// Checks that `workdir` is an existing directory.
fn check_workdir(workdir: &Path) -> Result<(), CosimError> {
    match fs::metadata(workdir) {
        Ok(m) if m.is_dir() => Ok(()),
        Ok(_) => Err(io_err(
            workdir,
            std::io::Error::other("work directory is not a directory"),
        )),
        Err(e) => Err(io_err(workdir, e)),
    }
}

/// Writes the design source and the stimulus file (values masked to the input widths).
fn write_common_files(
    spec: &CosimSpec,
    stimulus: &[Vec<u64>],
    workdir: &Path,
) -> Result<(), CosimError> {
    write_file(&workdir.join(DESIGN_FILE), spec.verilog)?;
    write_file(&workdir.join(STIMULUS_FILE), &stimulus_text(spec, stimulus))
}

/// The stimulus file: one line per cycle, the input values in hex separated by spaces.
fn stimulus_text(spec: &CosimSpec, stimulus: &[Vec<u64>]) -> String {
    let mut text = String::with_capacity(stimulus.len() * (spec.inputs.len() * 6 + 1));
    for row in stimulus {
        for (i, (v, p)) in row.iter().zip(spec.inputs).enumerate() {
            if i > 0 {
                text.push(' ');
            }
            let _ = write!(text, "{:x}", v & p.mask());
        }
        text.push('\n');
    }
    text
}

/// What both runners do before building their simulator: check `spec` and `stimulus`, write
/// the design, the stimulus and the simulator's driver (`driver_file`, the text `driver()`
/// returns: a testbench or a C++ main), and remove an output file `out_file` left by an
/// earlier run. Returns the output file's path.
fn prepare_run(
    spec: &CosimSpec,
    stimulus: &[Vec<u64>],
    workdir: &Path,
    driver_file: &str,
    driver: impl FnOnce() -> String,
    out_file: &str,
) -> Result<PathBuf, CosimError> {
    validate(spec, stimulus)?;
    check_workdir(workdir)?;
    write_common_files(spec, stimulus, workdir)?;
    write_file(&workdir.join(driver_file), &driver())?;
    let out_path = workdir.join(out_file);
    remove_if_exists(&out_path)?;
    Ok(out_path)
}

/// What both runners do after their simulator ran (its output `out`): fail if the testbench
/// reported an error, then read and parse the output trace at `out_path`.
fn finish_run(
    tool: &str,
    out: &ToolOutput,
    out_path: &Path,
    spec: &CosimSpec,
    cycles: usize,
) -> Result<Trace, CosimError> {
    check_error_marker(out, tool)?;
    let text = read_file(out_path)?;
    parse_output(tool, &text, spec.outputs, cycles)
}

/// Parses an output file written by a generated testbench: one line per cycle, one hex value
/// per output. `x`/`z` digits, values wider than the port and wrong row/column counts are
/// [`CosimError::Parse`] errors naming the simulator, cycle and port.
fn parse_output(
    sim: &str,
    text: &str,
    outputs: &[Port],
    cycles: usize,
) -> Result<Trace, CosimError> {
    let mut trace = Vec::with_capacity(cycles);
    for (k, line) in text.lines().enumerate() {
        if k >= cycles {
            return Err(CosimError::Parse(format!(
                "{sim}: output has more rows than the {cycles} stimulus cycles (extra row {k}: {line:?})"
            )));
        }
        let fields: Vec<&str> = line.split_whitespace().collect();
        if fields.len() != outputs.len() {
            return Err(CosimError::Parse(format!(
                "{sim}: cycle {k}: expected {} output values, found {} in line {line:?}",
                outputs.len(),
                fields.len()
            )));
        }
        let mut row = Vec::with_capacity(outputs.len());
        for (field, port) in fields.iter().zip(outputs) {
            if field.chars().any(|c| matches!(c, 'x' | 'X' | 'z' | 'Z')) {
                return Err(CosimError::Parse(format!(
                    "{sim}: cycle {k}: output `{}` has unknown/high-impedance bits: {field} \
                     (x = unknown, z = undriven)",
                    port.name
                )));
            }
            let v = u64::from_str_radix(field, 16).map_err(|e| {
                CosimError::Parse(format!(
                    "{sim}: cycle {k}: output `{}`: cannot parse {field:?} as hex: {e}",
                    port.name
                ))
            })?;
            if v & !port.mask() != 0 {
                return Err(CosimError::Parse(format!(
                    "{sim}: cycle {k}: output `{}` value {v:#x} does not fit in {} bits",
                    port.name, port.width
                )));
            }
            row.push(v);
        }
        trace.push(row);
    }
    if trace.len() != cycles {
        return Err(CosimError::Parse(format!(
            "{sim}: output has {} rows but the stimulus has {cycles} cycles",
            trace.len()
        )));
    }
    Ok(trace)
}

/// Fails if a generated testbench reported an error (it prints [`ERROR_MARKER`]).
fn check_error_marker(out: &ToolOutput, tool: &str) -> Result<(), CosimError> {
    if out.stdout.contains(ERROR_MARKER) || out.stderr.contains(ERROR_MARKER) {
        return Err(CosimError::ToolFailed {
            tool: tool.to_string(),
            stage: "run".to_string(),
            message: trim_message(&out.combined()),
        });
    }
    Ok(())
}

fn remove_if_exists(path: &Path) -> Result<(), CosimError> {
    match fs::remove_file(path) {
        Ok(()) => Ok(()),
        Err(e) if e.kind() == ErrorKind::NotFound => Ok(()),
        Err(e) => Err(io_err(path, e)),
    }
}

/// None if equal; otherwise a human-readable description of the first difference:
/// cycle number, port name, both values in hex, and which side is which (names a_name/b_name),
/// also row-count differences.
///
/// Rows are compared cycle by cycle over the cycles both traces have; the first differing
/// value is reported (with a note if the row counts differ too). If the common cycles agree,
/// a row-count difference is reported. A row with the wrong number of values is reported as
/// such. Port names come from `outputs`; a column beyond `outputs` is called `#<index>`.
pub fn first_mismatch(
    a_name: &str,
    a: &Trace,
    b_name: &str,
    b: &Trace,
    outputs: &[Port],
) -> Option<String> {
    let count_note = if a.len() != b.len() {
        format!(
            "row counts differ: {a_name} has {} cycles, {b_name} has {} cycles",
            a.len(),
            b.len()
        )
    } else {
        String::new()
    };
    for (k, (ra, rb)) in a.iter().zip(b.iter()).enumerate() {
        if ra == rb {
            continue;
        }
        if ra.len() != rb.len() {
            let mut msg = format!(
                "cycle {k}: {a_name} has {} values, {b_name} has {} values",
                ra.len(),
                rb.len()
            );
            if let Some(i) = ra.iter().zip(rb.iter()).position(|(x, y)| x != y) {
                let _ = write!(
                    msg,
                    "; first differing value: {}",
                    describe_value_diff(a_name, ra[i], b_name, rb[i], i, outputs)
                );
            }
            if !count_note.is_empty() {
                let _ = write!(msg, " (also {count_note})");
            }
            return Some(msg);
        }
        if let Some(i) = ra.iter().zip(rb.iter()).position(|(x, y)| x != y) {
            let mut msg = format!(
                "cycle {k}: {}",
                describe_value_diff(a_name, ra[i], b_name, rb[i], i, outputs)
            );
            if !count_note.is_empty() {
                let _ = write!(msg, " (also {count_note})");
            }
            return Some(msg);
        }
    }
    if count_note.is_empty() {
        None
    } else {
        Some(count_note)
    }
}

/// "output `name`: a_name=0x.. b_name=0x.." with values zero-padded to the port width.
fn describe_value_diff(
    a_name: &str,
    va: u64,
    b_name: &str,
    vb: u64,
    index: usize,
    outputs: &[Port],
) -> String {
    let (name, digits) = match outputs.get(index) {
        Some(p) => (p.name.clone(), p.hex_digits()),
        None => (format!("#{index}"), 1),
    };
    format!("output `{name}` differs: {a_name}=0x{va:0digits$x}, {b_name}=0x{vb:0digits$x}")
}

#[cfg(test)]
mod tests {
    use super::tool::trim_message;
    use super::*;

    #[test]
    fn trim_keeps_head_and_tail() {
        let long = "a".repeat(5000) + &"b".repeat(5000);
        let t = trim_message(&long);
        assert!(t.len() < 7000);
        assert!(t.starts_with('a') && t.ends_with('b'));
        assert!(t.contains("omitted"));
    }

    #[test]
    fn parse_rejects_x_and_wide_values() {
        let outs = [Port::new("y", 4), Port::new("z", 8)];
        assert_eq!(
            parse_output("t", "a 0f\n", &outs, 1).ok(),
            Some(vec![vec![10, 15]])
        );
        let e = parse_output("t", "a 0f\nb xX\n", &outs, 2)
            .err()
            .map(|e| e.to_string());
        assert!(e.is_some_and(|m| m.contains("cycle 1") && m.contains("`z`")));
        assert!(parse_output("t", "1f 00\n", &outs, 1).is_err());
        assert!(parse_output("t", "1 00\n", &outs, 2).is_err());
        assert!(parse_output("t", "1\n", &outs, 1).is_err());
    }
}
