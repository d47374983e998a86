//! Building and loading the generated code: `rustc` compiles it into a `cdylib` in a cache
//! directory keyed by a hash of everything the library depends on (the Verilog, the top and
//! clock names, the Yosys script, the engine's own sources, the `rustc` version), as
//! Verilator builds its C++ once per model; `libloading` opens it.
use super::codegen::ABI_VERSION;
use super::Sim;
use crate::cosim::CosimError;
use crate::error::{Error, Result};
use std::ffi::c_void;
use std::path::{Path, PathBuf};
use std::process::Command;

/// `rustc` options of the generated library.
pub const RUSTC_FLAGS: &[&str] = &[
    "--edition",
    "2021",
    "--crate-type",
    "cdylib",
    "-C",
    "opt-level=3",
    "-C",
    "codegen-units=1",
    "-C",
    "panic=abort",
    "-C",
    "debuginfo=0",
];

/// The `rustc` to use: `$RUSTC` (as cargo sets it) or `rustc` on PATH.
pub fn rustc() -> String {
    std::env::var("RUSTC").unwrap_or_else(|_| "rustc".to_string())
}

/// `rustc --version`, for the cache key; asked once per process and `rustc` path (a closed
/// loop that builds an engine per run would otherwise start rustc, through rustup's proxy,
/// at every run).
pub fn rustc_version() -> Result<String> {
    use std::collections::HashMap;
    use std::sync::Mutex;
    static KNOWN: Mutex<Option<HashMap<String, String>>> = Mutex::new(None);
    let bin = rustc();
    if let Some(v) = KNOWN
        .lock()
        .ok()
        .and_then(|m| m.as_ref().and_then(|m| m.get(&bin).cloned()))
    {
        return Ok(v);
    }
    let v = ask_rustc_version(&bin)?;
    if let Ok(mut m) = KNOWN.lock() {
        m.get_or_insert_with(HashMap::new).insert(bin, v.clone());
    }
    Ok(v)
}

fn ask_rustc_version(bin: &str) -> Result<String> {
    let out = crate::cleanup::output(Command::new(bin).arg("--version")).map_err(|e| {
        Error::Tool(CosimError::ToolMissing {
            tool: format!("rustc ({e})"),
            install: "curl https://sh.rustup.rs -sSf | sh".into(),
        })
    })?;
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// The library's file name in a cache entry.
pub const LIB: &str = "libsdengine.so";
/// The file beside the library holding the SHA-256 of its bytes (hex): a library is loaded
/// from the cache only when its bytes still give that hash.
pub const LIB_HASH: &str = "libsdengine.so.sha256";
/// The ports' shape beside the library.
pub const SHAPE: &str = "shape.json";

/// An absolute path from environment variable `var`; an empty or relative value is
/// ignored, as the XDG Base Directory specification asks.
fn absolute_var(var: &str) -> Option<PathBuf> {
    std::env::var_os(var)
        .map(PathBuf::from)
        .filter(|p| p.is_absolute())
}

/// The cache directory and the environment variable it comes from:
/// `$SINEDEC_ENGINE_CACHE`, else `$XDG_CACHE_HOME/sinedec/engine`, else
/// `$HOME/.cache/sinedec/engine`, else the temporary directory's `sinedec-engine` (empty
/// or relative values skipped).
pub fn cache_root() -> (PathBuf, Option<&'static str>) {
    if let Some(p) = absolute_var("SINEDEC_ENGINE_CACHE") {
        return (p, Some("SINEDEC_ENGINE_CACHE"));
    }
    if let Some(p) = absolute_var("XDG_CACHE_HOME") {
        return (p.join("sinedec").join("engine"), Some("XDG_CACHE_HOME"));
    }
    if let Some(p) = absolute_var("HOME") {
        return (
            p.join(".cache").join("sinedec").join("engine"),
            Some("HOME"),
        );
    }
    (std::env::temp_dir().join("sinedec-engine"), Some("TMPDIR"))
}

fn sha256_hex(bytes: &[u8]) -> String {
    use sha2::{Digest, Sha256};
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The shape of the cache entry `dir` when the entry is whole: its shape file parses and
/// its library's bytes give the hash stored beside it. None for a missing, partial or
/// damaged entry (truncated or scrambled library, a file where the directory should be).
pub(crate) fn cached_shape(dir: &Path) -> Option<super::Shape> {
    let shape = std::fs::read_to_string(dir.join(SHAPE)).ok()?;
    let shape: super::Shape = serde_json::from_str(&shape).ok()?;
    let want = std::fs::read_to_string(dir.join(LIB_HASH)).ok()?;
    let lib = std::fs::read(dir.join(LIB)).ok()?;
    (sha256_hex(&lib) == want.trim()).then_some(shape)
}

/// Why a cache entry could not be built.
pub(crate) enum EntryError {
    /// The entry's directory cannot be created or written (the reason, with the path).
    Cache(String),
    /// rustc is missing or failed.
    Other(Error),
}

impl EntryError {
    /// As a library error about `dir`.
    pub(crate) fn into_error(self, dir: &Path) -> Error {
        match self {
            EntryError::Cache(why) => {
                Error::Simulation(format!("engine library in {}: {why}", dir.display()))
            }
            EntryError::Other(e) => e,
        }
    }
}

fn cache_error(path: &Path, e: std::io::Error) -> EntryError {
    EntryError::Cache(format!("{}: {}", path.display(), crate::error::io_text(&e)))
}

/// Writes `bytes` to `path` through a temporary file in `dir` renamed into place.
fn write_atomic(dir: &Path, path: &Path, bytes: &[u8]) -> std::result::Result<(), EntryError> {
    use std::io::Write;
    let mut t = tempfile::Builder::new()
        .prefix(".write")
        .tempfile_in(dir)
        .map_err(|e| cache_error(dir, e))?;
    t.write_all(bytes).map_err(|e| cache_error(path, e))?;
    t.persist(path).map_err(|e| cache_error(path, e.error))?;
    Ok(())
}

/// Builds the cache entry `dir` for `source`: the library compiled by rustc, its shape,
/// and last the hash of its bytes (an entry interrupted before that is rebuilt).
pub(crate) fn build_entry(
    source: &str,
    shape: &super::Shape,
    dir: &Path,
) -> std::result::Result<(), EntryError> {
    std::fs::create_dir_all(dir).map_err(|e| cache_error(dir, e))?;
    let lib = dir.join(LIB);
    build(source, dir, &lib)?;
    let bytes = std::fs::read(&lib).map_err(|e| cache_error(&lib, e))?;
    let text = serde_json::to_string(shape).map_err(|e| {
        EntryError::Other(Error::Json {
            what: "engine shape".into(),
            source: e,
        })
    })?;
    write_atomic(dir, &dir.join(SHAPE), text.as_bytes())?;
    write_atomic(dir, &dir.join(LIB_HASH), sha256_hex(&bytes).as_bytes())
}

/// Compiles `source` into `lib` (through a temporary directory in the same directory,
/// renamed into place, so concurrent builds of one key do not see half a library).
fn build(source: &str, dir: &Path, lib: &Path) -> std::result::Result<(), EntryError> {
    let src = dir.join("engine.rs");
    std::fs::write(&src, source).map_err(|e| cache_error(&src, e))?;
    let (tmp, _entry) = crate::cleanup::create_dir(
        || {
            tempfile::Builder::new()
                .prefix(".tmp-build")
                .tempdir_in(dir)
        },
        |d: &tempfile::TempDir| d.path().to_path_buf(),
    )
    .map_err(|e| cache_error(dir, e))?;
    let out = tmp.path().join(LIB);
    let mut cmd = Command::new(rustc());
    cmd.current_dir(dir)
        .args(RUSTC_FLAGS)
        .arg("--crate-name")
        .arg("sdengine")
        .arg("-o")
        .arg(&out)
        .arg(&src);
    crate::cosim::run_checked(&mut cmd, "rustc", "engine build", dir, "engine_rustc")
        .map_err(|e| EntryError::Other(e.into()))?;
    std::fs::rename(&out, lib).map_err(|e| cache_error(lib, e))
}

type NewFn = unsafe extern "C" fn() -> *mut c_void;
type FreeFn = unsafe extern "C" fn(*mut c_void);
type SetFn = unsafe extern "C" fn(*mut c_void, u32, u64);
type GetFn = unsafe extern "C" fn(*const c_void, u32) -> u64;
type StepFn = unsafe extern "C" fn(*mut c_void);
type RunFn = unsafe extern "C" fn(*mut c_void, *const u64, u64, *mut u64);
type InfoFn = unsafe extern "C" fn() -> u64;

/// A loaded library and one state of its model.
pub struct Compiled {
    st: *mut c_void,
    new: NewFn,
    free: FreeFn,
    set: SetFn,
    get: GetFn,
    tick: StepFn,
    eval: StepFn,
    run: RunFn,
    n_in: usize,
    n_out: usize,
    // Kept last: dropped after the state is freed.
    _lib: libloading::Library,
}

// SAFETY: the state is owned by this value alone and the library keeps no global state.
unsafe impl Send for Compiled {}

fn sym<T: Copy>(lib: &libloading::Library, name: &str, path: &Path) -> Result<T> {
    // SAFETY: the symbol types are those codegen.rs generates (checked by sdeng_abi).
    unsafe { lib.get::<T>(name.as_bytes()) }
        .map(|s| *s)
        .map_err(|e| Error::Simulation(format!("engine library {}: {name}: {e}", path.display())))
}

impl Compiled {
    /// Opens the library at `path` for a model of `n_in` inputs and `n_out` outputs.
    pub fn load(path: &Path, n_in: usize, n_out: usize) -> Result<Compiled> {
        // SAFETY: the library is one sinedec generated; its initialisers do nothing.
        let lib = unsafe { libloading::Library::new(path) }
            .map_err(|e| Error::Simulation(format!("engine library {}: {e}", path.display())))?;
        let abi: InfoFn = sym(&lib, "sdeng_abi", path)?;
        let shape: InfoFn = sym(&lib, "sdeng_shape", path)?;
        // SAFETY: plain functions without arguments.
        let (a, s) = unsafe { (abi(), shape()) };
        if a != ABI_VERSION || s != ((n_in as u64) << 32 | n_out as u64) {
            return Err(Error::Simulation(format!(
                "engine library {} does not match the netlist (abi {a}, shape {s:#x})",
                path.display()
            )));
        }
        let new: NewFn = sym(&lib, "sdeng_new", path)?;
        // SAFETY: sdeng_new returns a fresh boxed state.
        let st = unsafe { new() };
        Ok(Compiled {
            st,
            new,
            free: sym(&lib, "sdeng_free", path)?,
            set: sym(&lib, "sdeng_set", path)?,
            get: sym(&lib, "sdeng_get", path)?,
            tick: sym(&lib, "sdeng_tick", path)?,
            eval: sym(&lib, "sdeng_eval", path)?,
            run: sym(&lib, "sdeng_run", path)?,
            n_in,
            n_out,
            _lib: lib,
        })
    }
}

impl Drop for Compiled {
    fn drop(&mut self) {
        // SAFETY: st came from sdeng_new of this library, which is still loaded.
        unsafe { (self.free)(self.st) }
    }
}

impl Sim for Compiled {
    fn restart(&mut self) {
        // SAFETY: st came from sdeng_new of this library and is not used after the free;
        // sdeng_new returns a fresh boxed state.
        unsafe {
            (self.free)(self.st);
            self.st = (self.new)();
        }
    }

    fn set(&mut self, input: usize, v: u64) {
        // SAFETY: the callee ignores an index out of range.
        unsafe { (self.set)(self.st, input as u32, v) }
    }
    fn get(&self, output: usize) -> u64 {
        // SAFETY: as above.
        unsafe { (self.get)(self.st, output as u32) }
    }
    fn eval(&mut self) {
        // SAFETY: a valid state.
        unsafe { (self.eval)(self.st) }
    }
    fn tick(&mut self) {
        // SAFETY: a valid state.
        unsafe { (self.tick)(self.st) }
    }
    fn run(&mut self, rows: &[u64], outs: &mut Vec<u64>) {
        let n = rows.len() / self.n_in.max(1);
        let n = if self.n_in == 0 { 0 } else { n };
        outs.resize(n * self.n_out, 0);
        // SAFETY: rows holds n * n_in values and outs n * n_out.
        unsafe { (self.run)(self.st, rows.as_ptr(), n as u64, outs.as_mut_ptr()) }
    }
}
