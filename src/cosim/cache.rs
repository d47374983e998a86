//! Verdict cache of the Verilog simulators: Icarus and Verilator give the same trace for the
//! same design, driver, stimulus and tool version, so a trace once produced need not be
//! produced again to know it. The cache keeps, per run, only the SHA-256 of the trace the
//! simulator printed, keyed by everything the run depends on:
//!
//! ```text
//!  key = SHA-256(CACHE_VERSION, simulator, tool version, build arguments,
//!                driver (testbench / C++ main), design Verilog, stimulus file)
//!
//!  run_*_expecting(spec, rows, expected) ─► key ─► <dir>/<key> holds SHA-256(trace)?
//!     ├─ equals SHA-256(expected) ──► Ok(expected): the simulator printed exactly it
//!     └─ absent or different ──► run the simulator ──► write SHA-256(its trace) ──► its trace
//! ```
//!
//! A hit therefore proves that the simulator's trace equals `expected` bit for bit; any other
//! case runs the tool, so a difference is always reported from a real run with its first
//! mismatching cycle. The tool must still be installed (its version is part of the key):
//! a missing simulator fails with its install hint, cached or not.
//!
//! The cache is off unless [`COSIM_CACHE_ENV`] names a directory. `scripts/test.sh` points it
//! at `tests/data/cosim-cache`, committed, so that CI on a fresh clone runs Icarus and
//! Verilator only for the designs whose Verilog changed (`scripts/tool_caches.sh` refreshes
//! it). Written by hand: the key must cover this harness's own files, which no generic
//! memoizing crate knows.
use super::tool::{install_hint, tool_version_named};
use super::{CosimError, CosimSpec, Trace};
use sha2::{Digest, Sha256};
use std::path::PathBuf;
use std::sync::OnceLock;

/// The environment variable naming the cache directory (unset or empty: no cache).
pub const COSIM_CACHE_ENV: &str = "SINEDEC_COSIM_CACHE";

/// Changes whenever the meaning of a key or an entry changes.
const CACHE_VERSION: &str = "sinedec-cosim-verdict-1";

/// The cache directory, when one is configured.
fn cache_dir() -> Option<PathBuf> {
    std::env::var_os(COSIM_CACHE_ENV)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
}

/// SHA-256 of a trace: every value as 8 little-endian bytes, rows framed by their length.
pub(super) fn trace_digest(trace: &Trace) -> String {
    let mut h = Sha256::new();
    h.update((trace.len() as u64).to_le_bytes());
    for row in trace {
        h.update((row.len() as u64).to_le_bytes());
        for v in row {
            h.update(v.to_le_bytes());
        }
    }
    hex(&h.finalize())
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// The version line of `tool` (`iverilog -V`'s first line, `verilator --version`), read once
/// per process; a missing tool is [`CosimError::ToolMissing`] with its install hint.
fn tool_version(tool: &'static str) -> Result<String, CosimError> {
    static ICARUS: OnceLock<String> = OnceLock::new();
    static VERILATOR: OnceLock<String> = OnceLock::new();
    let cell = if tool == "verilator" {
        &VERILATOR
    } else {
        &ICARUS
    };
    if let Some(v) = cell.get() {
        return Ok(v.clone());
    }
    let v = tool_version_named(tool, &install_hint(tool))?;
    Ok(cell.get_or_init(|| v).clone())
}

/// One run's place in the cache.
pub(super) struct Entry {
    path: PathBuf,
}

impl Entry {
    /// The entry in `dir` of a run of `tool` (`iverilog` or `verilator`) whose inputs are
    /// `parts`.
    fn of(
        dir: PathBuf,
        tool: &'static str,
        version: &str,
        spec: &CosimSpec,
        parts: &[&str],
    ) -> Result<Entry, CosimError> {
        let mut h = Sha256::new();
        for part in [
            CACHE_VERSION,
            tool,
            version,
            spec.top,
            spec.clock,
            spec.verilog,
        ]
        .into_iter()
        .chain(parts.iter().copied())
        {
            h.update((part.len() as u64).to_le_bytes());
            h.update(part.as_bytes());
        }
        Ok(Entry {
            path: dir.join(hex(&h.finalize())),
        })
    }

    /// True when the cached trace of this run is `expected`.
    pub(super) fn holds(&self, expected: &Trace) -> bool {
        std::fs::read_to_string(&self.path).is_ok_and(|s| s.trim() == trace_digest(expected))
    }

    /// Records the trace a real run printed (best effort: a cache that cannot be written
    /// only costs the next run its time).
    pub(super) fn store(&self, trace: &Trace) {
        let Some(dir) = self.path.parent() else {
            return;
        };
        if std::fs::create_dir_all(dir).is_err() {
            return;
        }
        // Written beside and renamed over: parallel tests never read half an entry.
        if let Ok(mut tmp) = tempfile::NamedTempFile::new_in(dir) {
            use std::io::Write;
            if writeln!(tmp, "{}", trace_digest(trace)).is_ok() {
                let _ = tmp.persist(&self.path);
            }
        }
    }
}

/// Runs `run` unless the cache of [`COSIM_CACHE_ENV`] holds `expected` for this run (see
/// the module doc).
pub(super) fn cached(
    tool: &'static str,
    spec: &CosimSpec,
    parts: &[&str],
    expected: &Trace,
    run: impl FnOnce() -> Result<Trace, CosimError>,
) -> Result<Trace, CosimError> {
    let version = match cache_dir() {
        Some(_) => tool_version(tool)?,
        None => String::new(),
    };
    cached_in(cache_dir(), tool, &version, spec, parts, expected, run)
}

/// [`cached`] for a simulator whose version the caller gives (the compiled engine: a digest
/// of its own sources and of the tools it builds with).
pub(super) fn cached_as<E: From<CosimError>>(
    tool: &'static str,
    version: &str,
    spec: &CosimSpec,
    parts: &[&str],
    expected: &Trace,
    run: impl FnOnce() -> Result<Trace, E>,
) -> Result<Trace, E> {
    cached_in(cache_dir(), tool, version, spec, parts, expected, run)
}

/// [`cached`] with the cache directory given (None: no cache, `run` runs).
fn cached_in<E: From<CosimError>>(
    dir: Option<PathBuf>,
    tool: &'static str,
    version: &str,
    spec: &CosimSpec,
    parts: &[&str],
    expected: &Trace,
    run: impl FnOnce() -> Result<Trace, E>,
) -> Result<Trace, E> {
    let Some(dir) = dir else {
        return run();
    };
    let entry = Entry::of(dir, tool, version, spec, parts)?;
    if entry.holds(expected) {
        return Ok(expected.clone());
    }
    let trace = run()?;
    entry.store(&trace);
    Ok(trace)
}

/// A check that passed once for exactly these inputs need not run again: `check` runs
/// (and may panic, as a test's assertions do) unless the cache holds a pass for the key of
/// `name`, the versions of `tools` and `parts`; when it returns, the pass is recorded.
///
/// ```text
///  key = SHA-256(CACHE_VERSION, "check", name, version of each tool, parts...)
///  <dir>/<key> holds "pass" ─► skip;  otherwise ─► check() ─► returns ─► write "pass"
/// ```
///
/// For runs whose verdict is not one trace: an emitted testbench's PASS and FAIL, a lint
/// run, a long sweep. `parts` must hold everything the verdict depends on (the design, the
/// stimulus, the source text of the check itself, the models' source text), so that any
/// change to them runs the check. A failure is never recorded: it reruns every time. The
/// tools must be installed whatever the cache holds (their versions are in the key).
pub fn passed_once(
    name: &str,
    tools: &[&str],
    parts: &[&str],
    check: impl FnOnce(),
) -> Result<(), CosimError> {
    passed_once_in(cache_dir(), name, tools, parts, check)
}

/// [`passed_once`] with the cache directory given (None: no cache, `check` runs).
fn passed_once_in(
    dir: Option<PathBuf>,
    name: &str,
    tools: &[&str],
    parts: &[&str],
    check: impl FnOnce(),
) -> Result<(), CosimError> {
    let verdict = Verdict::in_dir(dir, name, tools, parts)?;
    if !verdict.passed() {
        check();
        verdict.record_pass();
    }
    Ok(())
}

/// The cached verdict of one check (see [`passed_once`]), for a caller that decides itself
/// whether its run passed.
pub struct Verdict {
    /// The entry's path; None without a cache.
    path: Option<PathBuf>,
}

impl Verdict {
    /// The verdict of check `name` on `parts` with the installed versions of `tools`.
    pub fn of(name: &str, tools: &[&str], parts: &[&str]) -> Result<Verdict, CosimError> {
        Verdict::in_dir(cache_dir(), name, tools, parts)
    }

    fn in_dir(
        dir: Option<PathBuf>,
        name: &str,
        tools: &[&str],
        parts: &[&str],
    ) -> Result<Verdict, CosimError> {
        let mut h = Sha256::new();
        let mut put = |part: &str| {
            h.update((part.len() as u64).to_le_bytes());
            h.update(part.as_bytes());
        };
        put(CACHE_VERSION);
        put("check");
        put(name);
        for tool in tools {
            put(&tool_version_named(tool, &install_hint(tool))?);
        }
        for part in parts {
            put(part);
        }
        let key = hex(&h.finalize());
        Ok(Verdict {
            path: dir.map(|d| d.join(key)),
        })
    }

    /// True when this check passed before on the same inputs.
    pub fn passed(&self) -> bool {
        self.path
            .as_ref()
            .is_some_and(|p| std::fs::read_to_string(p).is_ok_and(|s| s.trim() == "pass"))
    }

    /// Records that the check passed (best effort, written beside and renamed over).
    pub fn record_pass(&self) {
        let Some(dir) = self.path.as_ref().and_then(|p| p.parent()) else {
            return;
        };
        if std::fs::create_dir_all(dir).is_err() {
            return;
        }
        if let (Some(path), Ok(mut tmp)) = (&self.path, tempfile::NamedTempFile::new_in(dir)) {
            use std::io::Write;
            if writeln!(tmp, "pass").is_ok() {
                let _ = tmp.persist(path);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digest_frames_rows() {
        // [[1, 2]] and [[1], [2]] hold the same values; the framing keeps them apart.
        assert_ne!(
            trace_digest(&vec![vec![1, 2]]),
            trace_digest(&vec![vec![1], vec![2]])
        );
        assert_eq!(trace_digest(&vec![vec![7]]), trace_digest(&vec![vec![7]]));
    }

    /// A pass is recorded and skips the next run of the same check; other parts, another
    /// name or no cache run it; a check that panics records nothing. (Needs iverilog for
    /// the version in the key.)
    #[test]
    fn a_check_is_skipped_only_after_it_passed_for_the_same_inputs() {
        use std::cell::Cell;
        let dir = tempfile::tempdir().expect("tempdir");
        let d = || Some(dir.path().to_path_buf());
        let runs = Cell::new(0);
        let count = || runs.set(runs.get() + 1);
        let t = ["iverilog"];
        passed_once_in(d(), "a", &t, &["x"], count).expect("ran");
        passed_once_in(d(), "a", &t, &["x"], count).expect("hit");
        assert_eq!(runs.get(), 1);
        passed_once_in(d(), "a", &t, &["y"], count).expect("other part");
        passed_once_in(d(), "b", &t, &["x"], count).expect("other name");
        passed_once_in(None, "a", &t, &["x"], count).expect("no cache");
        assert_eq!(runs.get(), 4);
        let failed = std::panic::catch_unwind(|| {
            let _ = passed_once_in(d(), "c", &t, &["x"], || panic!("check failed"));
        });
        assert!(failed.is_err());
        passed_once_in(d(), "c", &t, &["x"], count).expect("reran");
        assert_eq!(runs.get(), 5, "a failure is not recorded");
        assert!(matches!(
            passed_once_in(d(), "a", &["no-such-tool-sinedec"], &["x"], count),
            Err(CosimError::ToolMissing { .. })
        ));
    }

    #[test]
    fn an_entry_holds_only_its_own_trace() {
        let dir = tempfile::tempdir().expect("tempdir");
        let e = Entry {
            path: dir.path().join("k"),
        };
        assert!(!e.holds(&vec![vec![1]]));
        e.store(&vec![vec![1]]);
        assert!(e.holds(&vec![vec![1]]));
        assert!(!e.holds(&vec![vec![2]]));
    }

    /// A hit skips the run; a miss, a different expectation or a different design runs it.
    /// (Needs iverilog for the version in the key, as every co-simulation does.)
    #[test]
    fn a_run_is_skipped_only_when_its_entry_holds_the_expected_trace() {
        let dir = tempfile::tempdir().expect("tempdir");
        let ports = [super::super::Port::new("a", 1)];
        fn spec<'a>(verilog: &'a str, ports: &'a [super::super::Port]) -> CosimSpec<'a> {
            CosimSpec {
                verilog,
                top: "t",
                clock: "clk",
                inputs: ports,
                outputs: ports,
            }
        }
        let runs = std::cell::Cell::new(0);
        let go = |verilog: &str, stim: &str, expected: Trace, printed: Trace| {
            cached_in(
                Some(dir.path().to_path_buf()),
                "iverilog",
                "v",
                &spec(verilog, &ports),
                &[stim],
                &expected,
                || -> Result<Trace, CosimError> {
                    runs.set(runs.get() + 1);
                    Ok(printed)
                },
            )
            .expect("cached run")
        };
        let t1 = vec![vec![1]];
        let t0 = vec![vec![0]];
        assert_eq!(go("v1", "s", t1.clone(), t1.clone()), t1); // miss: runs, stores
        assert_eq!(runs.get(), 1);
        assert_eq!(go("v1", "s", t1.clone(), t0.clone()), t1); // hit: the stored verdict
        assert_eq!(runs.get(), 1);
        // Expecting something else than the simulator printed: it runs and tells the truth.
        assert_eq!(go("v1", "s", t0.clone(), t1.clone()), t1);
        assert_eq!(runs.get(), 2);
        // Another design or stimulus is another key.
        go("v2", "s", t1.clone(), t1.clone());
        go("v1", "s2", t1.clone(), t1.clone());
        assert_eq!(runs.get(), 4);
        // No cache: always runs.
        cached_in(
            None,
            "iverilog",
            "v",
            &spec("v1", &ports),
            &["s"],
            &t1,
            || {
                runs.set(runs.get() + 1);
                Ok::<_, CosimError>(t1.clone())
            },
        )
        .expect("uncached run");
        assert_eq!(runs.get(), 5);
    }
}
