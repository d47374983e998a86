//! Co-simulation harness: drives the exported Verilog of a synchronous design in
//! Icarus Verilog and in Verilator with one stimulus and returns the output traces,
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
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

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

/// Everything that can go wrong while co-simulating.
#[derive(Debug, thiserror::Error)]
pub enum CosimError {
    /// A required external tool could not be launched.
    #[error("{tool} is not installed or not on PATH; install it with `{install}` (the co-simulation tests need it)")]
    ToolMissing {
        /// Name of the program that could not be launched.
        tool: String,
        /// Command that installs it (e.g. `apt-get install -y iverilog`).
        install: String,
    },
    /// A tool ran but failed (non-zero exit status, error marker in its output, or time-out).
    #[error("{tool} failed ({stage}): {message}")]
    ToolFailed {
        /// Name of the program that failed.
        tool: String,
        /// `"compile"` or `"run"`.
        stage: String,
        /// The tool's stderr (and stdout when relevant), trimmed to a few KB.
        message: String,
    },
    /// Reading or writing a file (or creating a directory) failed.
    #[error("I/O error in {path}: {source}")]
    Io {
        /// The path involved.
        path: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// Malformed output from the simulator (wrong row/column count, `x`/`z` bits, value wider
    /// than its port, ...) or an invalid specification/stimulus (bad port name or width, row
    /// of the wrong length).
    #[error("{0}")]
    Parse(String),
}

/// Time limit for every external tool invocation (compilation or simulation run).
pub const TOOL_TIMEOUT: Duration = Duration::from_secs(900);

/// Maximum number of characters of tool output kept in [`CosimError::ToolFailed`] messages.
const MAX_MESSAGE_CHARS: usize = 6000;

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

/// Package-manager command that installs `tool` (Debian/Ubuntu package names).
fn install_hint(tool: &str) -> String {
    let package = match tool {
        "iverilog" | "vvp" => "iverilog",
        "verilator" => "verilator",
        "yosys" => "yosys",
        "make" => "make",
        "g++" | "c++" => "g++",
        other => other,
    };
    format!("apt-get install -y {package}")
}

/// Flag that makes `tool` print its version and exit successfully.
fn version_flag(tool: &str) -> &'static str {
    match tool {
        "iverilog" | "vvp" | "yosys" => "-V",
        _ => "--version",
    }
}

/// Checks that `tool` (e.g. "iverilog", "verilator", "yosys") runs; returns ToolMissing with
/// the apt-get package name otherwise.
pub fn require_tool(tool: &str) -> Result<(), CosimError> {
    check_tool_named(tool, &install_hint(tool))
}

/// Checks that the program `bin` can be launched (it is run with its version flag, e.g.
/// `--version`, through the same launcher the simulations use). A program that cannot be
/// found or executed yields [`CosimError::ToolMissing`] carrying `install` as the install
/// command; a program that starts but exits with a failure status yields
/// [`CosimError::ToolFailed`].
pub fn check_tool_named(bin: &str, install: &str) -> Result<(), CosimError> {
    let mut cmd = Command::new(bin);
    cmd.arg(version_flag(bin));
    let out = launch(&mut cmd, bin, install, "run", None)?;
    if out.status.success() {
        Ok(())
    } else {
        Err(CosimError::ToolFailed {
            tool: bin.to_string(),
            stage: "run".to_string(),
            message: format!(
                "`{bin} {}` exited with {}: {}",
                version_flag(bin),
                out.status,
                trim_message(&out.combined())
            ),
        })
    }
}

/// Result of one tool invocation: exit status and captured output.
struct ToolOutput {
    status: ExitStatus,
    stdout: String,
    stderr: String,
}

impl ToolOutput {
    /// stderr followed by stdout (whichever are non-empty).
    fn combined(&self) -> String {
        let mut s = self.stderr.trim_end().to_string();
        let so = self.stdout.trim_end();
        if !so.is_empty() {
            if !s.is_empty() {
                s.push_str("\n--- stdout ---\n");
            }
            s.push_str(so);
        }
        s
    }
}

/// The internal launcher: runs `cmd` to completion with a time limit, capturing its stdout and
/// stderr. If `logs` is given, the output goes to `<workdir>/<stem>.stdout.log` and
/// `.stderr.log` (kept for debugging), otherwise to files in the system temp directory that
/// are removed afterwards. A program that cannot be launched (not found, not executable)
/// becomes [`CosimError::ToolMissing`] for `tool`/`install`; a time-out becomes
/// [`CosimError::ToolFailed`] for `stage`. The exit status is *not* checked here.
fn launch(
    cmd: &mut Command,
    tool: &str,
    install: &str,
    stage: &str,
    logs: Option<(&Path, &str)>,
) -> Result<ToolOutput, CosimError> {
    let (out_path, err_path, keep) = match logs {
        Some((dir, stem)) => (
            dir.join(format!("{stem}.stdout.log")),
            dir.join(format!("{stem}.stderr.log")),
            true,
        ),
        None => {
            let base = std::env::temp_dir().join(format!(
                "sinedec-cosim-{}-{}",
                std::process::id(),
                unique_counter()
            ));
            (
                base.with_extension("stdout.log"),
                base.with_extension("stderr.log"),
                false,
            )
        }
    };
    let out_file = fs::File::create(&out_path).map_err(|e| io_err(&out_path, e))?;
    let err_file = fs::File::create(&err_path).map_err(|e| io_err(&err_path, e))?;
    cmd.stdin(Stdio::null())
        .stdout(Stdio::from(out_file))
        .stderr(Stdio::from(err_file));
    let result = match cmd.spawn() {
        Ok(child) => wait_with_timeout(child, tool),
        Err(e) => return Err(spawn_error(e, tool, install)),
    };
    let stdout = fs::read(&out_path)
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .unwrap_or_default();
    let stderr = fs::read(&err_path)
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .unwrap_or_default();
    if !keep {
        let _ = fs::remove_file(&out_path);
        let _ = fs::remove_file(&err_path);
    }
    let status = match result {
        Ok(status) => status,
        Err(problem) => {
            // Time-out or wait failure: add whatever the tool printed before it stopped.
            let mut message = problem;
            for (label, text) in [("stderr", &stderr), ("stdout", &stdout)] {
                if !text.trim().is_empty() {
                    let _ = write!(message, "\n--- {label} ---\n{}", trim_message(text));
                }
            }
            return Err(CosimError::ToolFailed {
                tool: tool.to_string(),
                stage: stage.to_string(),
                message,
            });
        }
    };
    Ok(ToolOutput {
        status,
        stdout,
        stderr,
    })
}

/// A process-wide counter used to make temporary file names unique.
fn unique_counter() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    COUNTER.fetch_add(1, Ordering::Relaxed)
}

/// Maps a failure to start a program to the right error.
fn spawn_error(e: std::io::Error, tool: &str, install: &str) -> CosimError {
    match e.kind() {
        ErrorKind::NotFound | ErrorKind::PermissionDenied => CosimError::ToolMissing {
            tool: tool.to_string(),
            install: install.to_string(),
        },
        _ => CosimError::ToolFailed {
            tool: tool.to_string(),
            stage: "launch".to_string(),
            message: format!("could not start {tool}: {e}"),
        },
    }
}

/// Waits for `child`, killing it if it runs longer than [`TOOL_TIMEOUT`]. The error is a
/// description of what went wrong (time-out or failure to wait).
fn wait_with_timeout(mut child: Child, tool: &str) -> Result<ExitStatus, String> {
    let start = Instant::now();
    let mut sleep = Duration::from_millis(2);
    loop {
        match child.try_wait() {
            Ok(Some(status)) => return Ok(status),
            Ok(None) => {}
            Err(e) => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(format!("waiting for {tool} failed: {e}"));
            }
        }
        if start.elapsed() > TOOL_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "timed out after {} s and was killed",
                TOOL_TIMEOUT.as_secs()
            ));
        }
        std::thread::sleep(sleep);
        sleep = (sleep * 2).min(Duration::from_millis(50));
    }
}

/// Runs a tool and turns a non-zero exit status into [`CosimError::ToolFailed`].
fn run_checked(
    cmd: &mut Command,
    tool: &str,
    stage: &str,
    workdir: &Path,
    log_stem: &str,
) -> Result<ToolOutput, CosimError> {
    let out = launch(
        cmd,
        tool,
        &install_hint(tool),
        stage,
        Some((workdir, log_stem)),
    )?;
    if !out.status.success() {
        return Err(CosimError::ToolFailed {
            tool: tool.to_string(),
            stage: stage.to_string(),
            message: format!(
                "exit status {}:\n{}",
                out.status,
                trim_message(&out.combined())
            ),
        });
    }
    Ok(out)
}

/// Shortens a tool's output to at most about [`MAX_MESSAGE_CHARS`] characters, keeping the
/// beginning and the end (errors are usually at the end, the first diagnostics at the start).
fn trim_message(s: &str) -> String {
    let s = s.trim();
    let chars: Vec<char> = s.chars().collect();
    if chars.len() <= MAX_MESSAGE_CHARS {
        return s.to_string();
    }
    let head = MAX_MESSAGE_CHARS / 3;
    let tail = MAX_MESSAGE_CHARS - head;
    let first: String = chars[..head].iter().collect();
    let last: String = chars[chars.len() - tail..].iter().collect();
    format!(
        "{first}\n[... {} characters omitted ...]\n{last}",
        chars.len() - head - tail
    )
}

fn io_err(path: &Path, source: std::io::Error) -> CosimError {
    CosimError::Io {
        path: path.display().to_string(),
        source,
    }
}

fn write_file(path: &Path, contents: &str) -> Result<(), CosimError> {
    fs::write(path, contents).map_err(|e| io_err(path, e))
}

fn read_file(path: &Path) -> Result<String, CosimError> {
    fs::read_to_string(path).map_err(|e| io_err(path, e))
}

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
    write_file(&workdir.join(STIMULUS_FILE), &text)
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

/// Generates the Icarus testbench module `cosim_tb` (see the module documentation for timing).
fn icarus_testbench(spec: &CosimSpec, cycles: usize) -> String {
    let mut tb = String::new();
    let _ = writeln!(tb, "// Generated by sinedec::sim::cosim; do not edit.");
    let _ = writeln!(tb, "`timescale 1ns/1ns");
    let _ = writeln!(tb, "module {TB_MODULE};");
    let _ = writeln!(tb, "  reg cosim_clk = 1'b0;");
    for p in spec.inputs {
        let _ = writeln!(
            tb,
            "  reg [{}:0] cosim_in_{} = {}'d0;",
            p.width - 1,
            p.name,
            p.width
        );
    }
    for p in spec.outputs {
        let _ = writeln!(tb, "  wire [{}:0] cosim_out_{};", p.width - 1, p.name);
    }
    let _ = writeln!(tb, "  integer cosim_fin, cosim_fout, cosim_r, cosim_k;");
    let _ = writeln!(tb, "  reg [63:0] cosim_v;");
    let mut conns = vec![format!("    .{}(cosim_clk)", spec.clock)];
    conns.extend(
        spec.inputs
            .iter()
            .map(|p| format!("    .{0}(cosim_in_{0})", p.name)),
    );
    conns.extend(
        spec.outputs
            .iter()
            .map(|p| format!("    .{0}(cosim_out_{0})", p.name)),
    );
    let _ = writeln!(
        tb,
        "  {} cosim_dut (\n{}\n  );",
        spec.top,
        conns.join(",\n")
    );
    let _ = writeln!(tb, "  initial begin");
    let _ = writeln!(tb, "    cosim_fin = $fopen(\"{STIMULUS_FILE}\", \"r\");");
    let _ = writeln!(tb, "    if (cosim_fin == 0) begin");
    let _ = writeln!(
        tb,
        "      $display(\"{ERROR_MARKER}: cannot open {STIMULUS_FILE}\");"
    );
    let _ = writeln!(tb, "      $finish;");
    let _ = writeln!(tb, "    end");
    let _ = writeln!(tb, "    cosim_fout = $fopen(\"{ICARUS_OUT_FILE}\", \"w\");");
    let _ = writeln!(tb, "    if (cosim_fout == 0) begin");
    let _ = writeln!(
        tb,
        "      $display(\"{ERROR_MARKER}: cannot open {ICARUS_OUT_FILE}\");"
    );
    let _ = writeln!(tb, "      $finish;");
    let _ = writeln!(tb, "    end");
    let _ = writeln!(
        tb,
        "    for (cosim_k = 0; cosim_k < {cycles}; cosim_k = cosim_k + 1) begin"
    );
    let _ = writeln!(tb, "      #2; // clock low: apply row k");
    for p in spec.inputs {
        let _ = writeln!(tb, "      cosim_r = $fscanf(cosim_fin, \"%h\", cosim_v);");
        let _ = writeln!(tb, "      if (cosim_r != 1) begin");
        let _ = writeln!(
            tb,
            "        $display(\"{ERROR_MARKER}: cannot read input {} of cycle %0d\", cosim_k);",
            p.name
        );
        let _ = writeln!(tb, "        $finish;");
        let _ = writeln!(tb, "      end");
        let _ = writeln!(
            tb,
            "      cosim_in_{} = cosim_v[{}:0];",
            p.name,
            p.width - 1
        );
    }
    let _ = writeln!(tb, "      #3 cosim_clk = 1'b1; // rising edge k");
    let fmt: Vec<&str> = spec.outputs.iter().map(|_| "%h").collect();
    let mut args = String::new();
    for p in spec.outputs {
        let _ = write!(args, ", cosim_out_{}", p.name);
    }
    let _ = writeln!(
        tb,
        "      #3 $fwrite(cosim_fout, \"{}\\n\"{args}); // sample row k",
        fmt.join(" ")
    );
    let _ = writeln!(tb, "      #2 cosim_clk = 1'b0;");
    let _ = writeln!(tb, "    end");
    let _ = writeln!(tb, "    $fclose(cosim_fout);");
    let _ = writeln!(tb, "    $fclose(cosim_fin);");
    let _ = writeln!(tb, "    $finish;");
    let _ = writeln!(tb, "  end");
    let _ = writeln!(tb, "endmodule");
    tb
}

/// Simulates `spec` in Icarus Verilog (`iverilog -g2005` + `vvp`) with `stimulus` (one row per
/// cycle, values in `spec.inputs` order) and returns the output trace (one row per cycle,
/// values in `spec.outputs` order). All files are written into `workdir` (see the module
/// documentation). Any `x`/`z` bit in a recorded output is a [`CosimError::Parse`] error naming
/// the cycle and port.
pub fn run_icarus(
    spec: &CosimSpec,
    stimulus: &[Vec<u64>],
    workdir: &Path,
) -> Result<Trace, CosimError> {
    validate(spec, stimulus)?;
    check_workdir(workdir)?;
    write_common_files(spec, stimulus, workdir)?;
    write_file(
        &workdir.join(ICARUS_TB_FILE),
        &icarus_testbench(spec, stimulus.len()),
    )?;
    let out_path = workdir.join(ICARUS_OUT_FILE);
    remove_if_exists(&out_path)?;

    let mut compile = Command::new("iverilog");
    compile.current_dir(workdir).args([
        "-g2005",
        "-o",
        ICARUS_VVP_FILE,
        "-s",
        TB_MODULE,
        ICARUS_TB_FILE,
        DESIGN_FILE,
    ]);
    run_checked(
        &mut compile,
        "iverilog",
        "compile",
        workdir,
        "cosim_icarus_compile",
    )?;

    let mut run = Command::new("vvp");
    run.current_dir(workdir).args(["-n", ICARUS_VVP_FILE]);
    let out = run_checked(&mut run, "vvp", "run", workdir, "cosim_icarus_run")?;
    check_error_marker(&out, "vvp")?;

    let text = read_file(&out_path)?;
    parse_output("icarus", &text, spec.outputs, stimulus.len())
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

/// C++ type Verilator uses for a port of `width` bits (1..=64).
fn verilator_ctype(width: u32) -> &'static str {
    match width {
        0..=8 => "CData",
        9..=16 => "SData",
        17..=32 => "IData",
        _ => "QData",
    }
}

/// Generates the C++ main for the Verilator model (class `Vcosim`).
fn verilator_main(spec: &CosimSpec, cycles: usize) -> String {
    let mut c = String::new();
    let _ = writeln!(c, "// Generated by sinedec::sim::cosim; do not edit.");
    let _ = writeln!(c, "#include \"Vcosim.h\"");
    let _ = writeln!(c, "#include \"verilated.h\"");
    let _ = writeln!(c, "#include <cstdio>");
    let _ = writeln!(c, "#include <memory>");
    let _ = writeln!(c);
    let _ = writeln!(c, "int main(int argc, char** argv) {{");
    let _ = writeln!(
        c,
        "    const std::unique_ptr<VerilatedContext> ctx{{new VerilatedContext}};"
    );
    let _ = writeln!(c, "    ctx->commandArgs(argc, argv);");
    let _ = writeln!(
        c,
        "    const std::unique_ptr<Vcosim> top{{new Vcosim{{ctx.get(), \"TOP\"}}}};"
    );
    let _ = writeln!(
        c,
        "    std::FILE* fin = std::fopen(\"{STIMULUS_FILE}\", \"r\");"
    );
    let _ = writeln!(c, "    if (!fin) {{ std::fprintf(stderr, \"{ERROR_MARKER}: cannot open {STIMULUS_FILE}\\n\"); return 2; }}");
    let _ = writeln!(
        c,
        "    std::FILE* fout = std::fopen(\"{VERILATOR_OUT_FILE}\", \"w\");"
    );
    let _ = writeln!(c, "    if (!fout) {{ std::fprintf(stderr, \"{ERROR_MARKER}: cannot open {VERILATOR_OUT_FILE}\\n\"); return 2; }}");
    let _ = writeln!(c, "    // Initial state: clock low, all inputs 0.");
    let _ = writeln!(c, "    top->{} = 0;", spec.clock);
    for p in spec.inputs {
        let _ = writeln!(c, "    top->{} = 0;", p.name);
    }
    let _ = writeln!(c, "    top->eval();");
    let _ = writeln!(c, "    unsigned long long v = 0;");
    let _ = writeln!(c, "    for (long long k = 0; k < {cycles}LL; ++k) {{");
    let _ = writeln!(c, "        // 1. clock low: apply row k and settle.");
    for p in spec.inputs {
        let _ = writeln!(c, "        if (std::fscanf(fin, \"%llx\", &v) != 1) {{");
        let _ = writeln!(
            c,
            "            std::fprintf(stderr, \"{ERROR_MARKER}: cannot read input {} of cycle %lld\\n\", k);",
            p.name
        );
        let _ = writeln!(c, "            return 2;");
        let _ = writeln!(c, "        }}");
        let _ = writeln!(
            c,
            "        top->{} = static_cast<{}>(v & {:#x}ULL);",
            p.name,
            verilator_ctype(p.width),
            p.mask()
        );
    }
    let _ = writeln!(c, "        ctx->timeInc(1);");
    let _ = writeln!(c, "        top->eval();");
    let _ = writeln!(c, "        // 2. rising edge k, settle.");
    let _ = writeln!(c, "        ctx->timeInc(1);");
    let _ = writeln!(c, "        top->{} = 1;", spec.clock);
    let _ = writeln!(c, "        top->eval();");
    let _ = writeln!(c, "        // 3. sample row k.");
    let fmt: Vec<&str> = spec.outputs.iter().map(|_| "%llx").collect();
    let mut args = String::new();
    for p in spec.outputs {
        let _ = write!(
            args,
            ", static_cast<unsigned long long>(top->{}) & {:#x}ULL",
            p.name,
            p.mask()
        );
    }
    let _ = writeln!(
        c,
        "        std::fprintf(fout, \"{}\\n\"{args});",
        fmt.join(" ")
    );
    let _ = writeln!(c, "        // 4. falling edge.");
    let _ = writeln!(c, "        ctx->timeInc(1);");
    let _ = writeln!(c, "        top->{} = 0;", spec.clock);
    let _ = writeln!(c, "        top->eval();");
    let _ = writeln!(c, "    }}");
    let _ = writeln!(c, "    top->final();");
    let _ = writeln!(c, "    std::fclose(fin);");
    let _ = writeln!(c, "    if (std::fclose(fout) != 0) {{ std::fprintf(stderr, \"{ERROR_MARKER}: cannot write {VERILATOR_OUT_FILE}\\n\"); return 2; }}");
    let _ = writeln!(c, "    return 0;");
    let _ = writeln!(c, "}}");
    c
}

/// Environment variables removed for the Verilator build (GNU make would honour them).
const MAKE_ENV_VARS: [&str; 12] = [
    "MAKEFLAGS",
    "MFLAGS",
    "MAKELEVEL",
    "MAKEFILES",
    "CXXFLAGS",
    "CPPFLAGS",
    "LDFLAGS",
    "LDLIBS",
    "OPT",
    "OPT_FAST",
    "OPT_SLOW",
    "OPT_GLOBAL",
];

/// Verilator options besides the file names, chosen to minimise compile + run time for small
/// designs: build time is dominated by compiling the Verilator runtime (`verilated.cpp` takes
/// ~1.9 s at `-O0` vs ~3.0 s at the default `-Os`), while simulating 20 000 cycles of a
/// 20-module design takes ~15 ms even unoptimised, so all C++ is compiled at `-O0`, in parallel.
/// Measured on 2 cores, 20 modules, 20 000 cycles: ~1.8-2.1 s total (defaults: ~2.7-2.9 s;
/// `-j 1`: ~3.2-3.8 s). Initial values and explicit X assignments are deterministic (zero).
/// Warnings never fail the build (`-Wno-fatal`) but are kept in the log and error message;
/// the noisiest ones for generated code are silenced.
fn verilator_args(spec: &CosimSpec) -> Vec<String> {
    let mut args: Vec<String> = [
        "--cc",
        "--exe",
        "--build",
        "--no-timing",
        "--x-assign",
        "0",
        "--x-initial",
        "0",
        "-Wno-fatal",
        "-Wno-WIDTH",
        "-Wno-UNOPTFLAT",
        "-Wno-CASEINCOMPLETE",
        "-Wno-UNUSED",
        "--prefix",
        "Vcosim",
        "--Mdir",
        VERILATOR_OBJ_DIR,
        "-o",
        VERILATOR_EXE,
        "-MAKEFLAGS",
        "OPT_FAST=-O0 OPT_SLOW=-O0 OPT_GLOBAL=-O0",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    // One job per core, at most 4: a small design yields only ~4 C++ files to compile.
    let jobs = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    args.push("-j".to_string());
    args.push(jobs.to_string());
    args.push("--top-module".to_string());
    args.push(spec.top.to_string());
    args
}

/// Simulates `spec` in Verilator (`--cc --exe --build` with a generated C++ main) with
/// `stimulus` (one row per cycle, values in `spec.inputs` order) and returns the output trace
/// (one row per cycle, values in `spec.outputs` order). All files, including the Verilator
/// object directory, are written into `workdir`; an object directory left there by an earlier
/// run is reused (make rebuilds what changed). Verilator warnings do not fail the build, but
/// they are included in the message of a failed build. Registers without `initial` blocks
/// start at 0 (`--x-initial 0`), so X bugs are only caught by [`run_icarus`].
pub fn run_verilator(
    spec: &CosimSpec,
    stimulus: &[Vec<u64>],
    workdir: &Path,
) -> Result<Trace, CosimError> {
    validate(spec, stimulus)?;
    check_workdir(workdir)?;
    write_common_files(spec, stimulus, workdir)?;
    write_file(
        &workdir.join(VERILATOR_MAIN_FILE),
        &verilator_main(spec, stimulus.len()),
    )?;
    let out_path = workdir.join(VERILATOR_OUT_FILE);
    remove_if_exists(&out_path)?;
    let exe: PathBuf = workdir.join(VERILATOR_OBJ_DIR).join(VERILATOR_EXE);
    remove_if_exists(&exe)?;

    let mut build = Command::new("verilator");
    // Make would pick these up from the environment (jobserver state of an enclosing make,
    // CXXFLAGS=-O2 of a CI job, ...) and change or slow down the build.
    for var in MAKE_ENV_VARS {
        build.env_remove(var);
    }
    build
        .current_dir(workdir)
        .args(verilator_args(spec))
        .args([DESIGN_FILE, VERILATOR_MAIN_FILE]);
    run_checked(
        &mut build,
        "verilator",
        "compile",
        workdir,
        "cosim_verilator_compile",
    )?;
    if !exe.is_file() {
        return Err(CosimError::ToolFailed {
            tool: "verilator".to_string(),
            stage: "compile".to_string(),
            message: format!("the build succeeded but {} was not produced", exe.display()),
        });
    }

    // The executable is run by absolute path so that PATH lookup plays no part.
    let exe_abs = fs::canonicalize(&exe).map_err(|e| io_err(&exe, e))?;
    let mut run = Command::new(&exe_abs);
    run.current_dir(workdir);
    let out = run_checked(&mut run, "verilator", "run", workdir, "cosim_verilator_run")?;
    check_error_marker(&out, "verilator")?;

    let text = read_file(&out_path)?;
    parse_output("verilator", &text, spec.outputs, stimulus.len())
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
