//! Launching external tools (Icarus, Verilator, Yosys, make, ...): lookup with an install
//! hint, a time limit for every run, captured output, and the error type of every tool run.
use std::fmt::Write as _;
use std::fs;
use std::io::ErrorKind;
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

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
/// Package-manager command that installs `tool` (Debian/Ubuntu package names).
pub(crate) fn install_hint(tool: &str) -> String {
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

/// The version line `tool` prints (e.g. "yosys", "iverilog", "verilator"), or
/// [`CosimError::ToolMissing`] with its install hint.
pub fn tool_version_of(tool: &str) -> Result<String, CosimError> {
    tool_version_named(tool, &install_hint(tool))
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
    tool_version_named(bin, install).map(|_| ())
}

/// As [`check_tool_named`], returning the first line the version flag printed
/// (`Icarus Verilog version 12.0 (stable) ()`, `Verilator 5.032 2025-01-01 rev ...`).
pub(crate) fn tool_version_named(bin: &str, install: &str) -> Result<String, CosimError> {
    let mut cmd = Command::new(bin);
    cmd.arg(version_flag(bin));
    let out = launch(&mut cmd, bin, install, "run", None)?;
    if out.status.success() {
        let text = if out.stdout.trim().is_empty() {
            &out.stderr
        } else {
            &out.stdout
        };
        Ok(text.lines().next().unwrap_or("").trim().to_string())
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
pub(crate) struct ToolOutput {
    pub(crate) status: ExitStatus,
    pub(crate) stdout: String,
    pub(crate) stderr: String,
}

impl ToolOutput {
    /// stderr followed by stdout (whichever are non-empty).
    pub(crate) fn combined(&self) -> String {
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
pub(crate) fn launch(
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
    // Unique names of sinedec's own, entered before they exist: a signal removes them.
    let _entries = (!keep).then(|| {
        (
            crate::cleanup::temp_file(&out_path),
            crate::cleanup::temp_file(&err_path),
        )
    });
    let out_file = fs::File::create(&out_path).map_err(|e| io_err(&out_path, e))?;
    let err_file = fs::File::create(&err_path).map_err(|e| io_err(&err_path, e))?;
    cmd.stdin(Stdio::null())
        .stdout(Stdio::from(out_file))
        .stderr(Stdio::from(err_file));
    let result = match crate::cleanup::spawn(cmd) {
        Ok((child, _entry)) => wait_with_timeout(child, tool),
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
            let mut message = problem.to_string();
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

/// Waits for `child`, killing it if it runs longer than [`TOOL_TIMEOUT`]. The error says
/// what went wrong (time-out, kind `TimedOut`, or failure to wait).
fn wait_with_timeout(mut child: Child, tool: &str) -> std::io::Result<ExitStatus> {
    let start = Instant::now();
    let mut sleep = Duration::from_millis(2);
    loop {
        match child.try_wait() {
            Ok(Some(status)) => return Ok(status),
            Ok(None) => {}
            Err(e) => {
                let _ = child.kill();
                let _ = child.wait();
                return Err(std::io::Error::new(
                    e.kind(),
                    format!("waiting for {tool} failed: {e}"),
                ));
            }
        }
        if start.elapsed() > TOOL_TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(std::io::Error::new(
                ErrorKind::TimedOut,
                format!(
                    "timed out after {} s and was killed",
                    TOOL_TIMEOUT.as_secs()
                ),
            ));
        }
        std::thread::sleep(sleep);
        sleep = (sleep * 2).min(Duration::from_millis(50));
    }
}

/// Runs a tool and turns a non-zero exit status into [`CosimError::ToolFailed`].
pub(crate) fn run_checked(
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
pub(crate) fn trim_message(s: &str) -> String {
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

pub(crate) fn io_err(path: &Path, source: std::io::Error) -> CosimError {
    CosimError::Io {
        path: path.display().to_string(),
        source,
    }
}

pub(crate) fn write_file(path: &Path, contents: &str) -> Result<(), CosimError> {
    fs::write(path, contents).map_err(|e| io_err(path, e))
}

pub(crate) fn read_file(path: &Path) -> Result<String, CosimError> {
    fs::read_to_string(path).map_err(|e| io_err(path, e))
}
