//! `sinedec simulate` runs on the compiled engine by default, and `--engine rust-hdl` (the
//! reference) prints the same report and writes the same CSV on both paths (sinewave and
//! capacitive); without rustc the engine's interpreter runs, without Yosys rust-hdl runs,
//! each said in one line on stderr. Only the speed line may differ: it names the engine.
use crate::common;
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const CAP: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/configs/cyclone3_capacitive.toml"
);

fn simulate(args: &[&str], csv: &Path, env: &[(&str, OsString)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_sinedec"));
    c.arg("simulate").args(args).arg("--csv").arg(csv);
    for (k, v) in env {
        c.env(k, v);
    }
    let out = c.output().expect("sinedec runs");
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The report without its speed line, and the speed line (the only one naming the engine).
fn split(out: &Output) -> (String, String) {
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    // Sinewave path: "simulation speed ..."; capacitive: "simulated N cycles in T s (...)".
    let speed = |l: &str| {
        l.starts_with("simulation speed") || (l.starts_with("simulated ") && l.contains(" in "))
    };
    let rest: Vec<&str> = text
        .lines()
        .filter(|l| !speed(l) && !l.starts_with("wrote "))
        .collect();
    let line = text.lines().find(|l| speed(l)).unwrap_or("").to_string();
    (rest.join("\n"), line)
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).to_string()
}

/// One config: the default run, then `--engine rust-hdl`; both reports and CSVs equal.
fn default_equals_rust_hdl(tag: &str, args: &[&str], rows: usize) {
    let dir = common::workdir(tag);
    let (a_csv, b_csv) = (dir.join("compiled.csv"), dir.join("rust_hdl.csv"));
    let a = simulate(args, &a_csv, &[]);
    let mut ref_args = args.to_vec();
    ref_args.extend(["--engine", "rust-hdl"]);
    let b = simulate(&ref_args, &b_csv, &[]);
    let ((ra, sa), (rb, sb)) = (split(&a), split(&b));
    assert!(sa.contains("compiled engine"), "default: {sa}");
    assert!(sb.contains("rust-hdl engine"), "reference: {sb}");
    assert!(!stderr(&a).contains("instead"), "{}", stderr(&a));
    assert_eq!(ra, rb, "{tag}: the reports differ");
    let (ta, tb) = (
        std::fs::read_to_string(&a_csv).expect("csv"),
        std::fs::read_to_string(&b_csv).expect("csv"),
    );
    assert!(
        ta.lines().count() > rows,
        "{tag}: {} rows",
        ta.lines().count()
    );
    assert_eq!(ta, tb, "{tag}: the CSVs differ");
}

#[test]
fn sinewave_default_is_the_compiled_engine_and_equals_rust_hdl() {
    let args = [
        "--duration",
        "0.0005",
        "--profile",
        "reversal:3000:0.0002:0.0001",
    ];
    default_equals_rust_hdl("simeng_sine", &args, 500);
}

#[test]
fn capacitive_default_is_the_compiled_engine_and_equals_rust_hdl() {
    // The first 1.5 ms are the filters' settling, not measured: 1 ms of rows after them.
    let args = [CAP, "--duration", "0.0025", "--profile", "constant:800"];
    default_equals_rust_hdl("simeng_cap", &args, 150);
}

/// The `rustc` that cargo's PATH finds, as an absolute path.
fn rustc_path() -> PathBuf {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .map(|d| d.join("rustc"))
        .find(|p| p.is_file())
        .expect("rustc on PATH")
}

#[test]
fn without_rustc_the_interpreter_runs_and_says_so() {
    let dir = common::workdir("simeng_norustc");
    let args = ["--duration", "0.0005", "--profile", "constant:3000"];
    let reference = split(&simulate(&args, &dir.join("a.csv"), &[]));
    let env = [
        ("RUSTC", OsString::from("/nonexistent/rustc")),
        ("SINEDEC_ENGINE_CACHE", dir.join("cache").into_os_string()),
    ];
    let out = simulate(&args, &dir.join("b.csv"), &env);
    let err = stderr(&out);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("instead")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].contains("interpreter") && lines[0].contains("rustc"),
        "{err}"
    );
    let (report, speed) = split(&out);
    assert!(speed.contains("interpreter engine"), "{speed}");
    assert_eq!(report, reference.0);
}

#[test]
fn without_yosys_rust_hdl_runs_and_says_so() {
    let dir = common::workdir("simeng_noyosys");
    let empty = dir.join("empty_path");
    std::fs::create_dir_all(&empty).expect("dir");
    let args = ["--duration", "0.0005", "--profile", "constant:3000"];
    let reference = split(&simulate(&args, &dir.join("a.csv"), &[]));
    let env = [
        ("PATH", empty.into_os_string()),
        ("RUSTC", rustc_path().into_os_string()),
        ("SINEDEC_ENGINE_CACHE", dir.join("cache").into_os_string()),
    ];
    let out = simulate(&args, &dir.join("b.csv"), &env);
    let err = stderr(&out);
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("instead")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(
        lines[0].contains("rust-hdl") && lines[0].contains("yosys"),
        "{err}"
    );
    let (report, speed) = split(&out);
    assert!(speed.contains("rust-hdl engine"), "{speed}");
    assert_eq!(report, reference.0);
}

/// `sinedec simulate ARGS` with `env` (no assertion on the status).
fn simulate_raw(args: &[&str], dir: &Path, env: &[(&str, OsString)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_sinedec"));
    c.arg("simulate").args(args).current_dir(dir);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("sinedec runs")
}

const SHORT: [&str; 4] = ["--duration", "0.0005", "--profile", "constant:3000"];

/// The one cache entry under `cache` (the run built it).
fn entry(cache: &Path) -> PathBuf {
    let v: Vec<PathBuf> = std::fs::read_dir(cache)
        .expect("cache")
        .flatten()
        .map(|e| e.path())
        .collect();
    assert_eq!(v.len(), 1, "{v:?}");
    v[0].clone()
}

/// M6: a truncated or scrambled cached library is not loaded (its bytes no longer give the
/// hash stored beside it): the entry is rebuilt and the report is the same.
#[test]
fn a_damaged_cached_library_is_rebuilt() {
    let dir = common::workdir("simeng_damaged");
    let cache = dir.join("cache");
    let env = [("SINEDEC_ENGINE_CACHE", cache.clone().into_os_string())];
    let reference = split(&simulate(&SHORT, &dir.join("a.csv"), &env)).0;
    let lib = entry(&cache).join("libsdengine.so");
    let good = std::fs::read(&lib).expect("library");
    let mut scrambled = good.clone();
    for b in scrambled.iter_mut().skip(64).step_by(7) {
        *b ^= 0x5a;
    }
    for damaged in [good[..good.len() / 3].to_vec(), scrambled] {
        std::fs::write(&lib, &damaged).expect("damage");
        let out = simulate_raw(&SHORT, &dir, &env);
        assert!(out.status.success(), "{}", stderr(&out));
        assert_eq!(split(&out).0, reference);
        assert_eq!(std::fs::read(&lib).expect("rebuilt").len(), good.len());
    }
}

/// M6: a key directory replaced by a file: the model is built in a temporary directory,
/// one stderr line names the cache, the file stays, the report is the same.
#[test]
fn a_cache_entry_that_is_a_file_falls_back_with_one_line() {
    let dir = common::workdir("simeng_entryfile");
    let cache = dir.join("cache");
    let env = [("SINEDEC_ENGINE_CACHE", cache.clone().into_os_string())];
    let reference = split(&simulate(&SHORT, &dir.join("a.csv"), &env)).0;
    let key = entry(&cache);
    std::fs::remove_dir_all(&key).expect("remove entry");
    std::fs::write(&key, "not a directory").expect("file");
    let out = simulate_raw(&SHORT, &dir, &env);
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    let lines: Vec<&str> = err.lines().filter(|l| l.contains("cache")).collect();
    assert_eq!(lines.len(), 1, "{err}");
    assert!(lines[0].contains(&cache.display().to_string()), "{err}");
    assert_eq!(split(&out).0, reference);
    assert_eq!(std::fs::read_to_string(&key).unwrap(), "not a directory");
}

/// M7: an empty or relative XDG_CACHE_HOME is ignored (XDG Base Directory specification):
/// nothing is created in the working directory.
#[test]
fn empty_or_relative_xdg_cache_home_is_ignored() {
    let dir = common::workdir("simeng_xdg_rel");
    let home = dir.join("home");
    std::fs::create_dir_all(&home).unwrap();
    for value in ["", "rel/cache"] {
        let work = dir.join(format!("work{}", value.len()));
        std::fs::create_dir_all(&work).unwrap();
        // rustup finds its toolchains through HOME unless RUSTUP_HOME says where they are.
        let rustup = std::env::var_os("RUSTUP_HOME").unwrap_or_else(|| {
            let h = PathBuf::from(std::env::var_os("HOME").expect("HOME"));
            h.join(".rustup").into_os_string()
        });
        let env = [
            ("XDG_CACHE_HOME", OsString::from(value)),
            ("HOME", home.clone().into_os_string()),
            ("RUSTUP_HOME", rustup),
        ];
        let mut c = Command::new(env!("CARGO_BIN_EXE_sinedec"));
        c.arg("simulate").args(SHORT).current_dir(&work);
        c.env_remove("SINEDEC_ENGINE_CACHE");
        for (k, v) in &env {
            c.env(k, v);
        }
        let out = c.output().expect("runs");
        let left: Vec<_> = std::fs::read_dir(&work).unwrap().flatten().collect();
        assert!(left.is_empty(), "{value:?}: {left:?}");
        assert!(out.status.success(), "{value:?}: {}", stderr(&out));
        assert!(home.join(".cache/sinedec/engine").is_dir(), "{value:?}");
    }
}

/// M8: XDG_CACHE_HOME at a file: the run goes on, one line names the variable; an unusable
/// TMPDIR is named in the error, with no OS error number.
#[test]
fn bad_cache_or_temporary_locations_name_the_variable() {
    let dir = common::workdir("simeng_xdg_file");
    let file = dir.join("a_file");
    std::fs::write(&file, "x").unwrap();
    let mut c = Command::new(env!("CARGO_BIN_EXE_sinedec"));
    c.arg("simulate").args(SHORT).current_dir(&dir);
    c.env_remove("SINEDEC_ENGINE_CACHE")
        .env("XDG_CACHE_HOME", &file);
    let out = c.output().expect("runs");
    let err = stderr(&out);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("XDG_CACHE_HOME"), "{err}");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "x");
    // TMPDIR at a file: the engine's scratch directory cannot be made.
    let env = [
        ("TMPDIR", file.clone().into_os_string()),
        (
            "SINEDEC_ENGINE_CACHE",
            dir.join("fresh_cache").into_os_string(),
        ),
    ];
    let out = simulate_raw(&SHORT, &dir, &env);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("TMPDIR") && !err.contains("os error"), "{err}");
}

/// L5: `--engine interpreter` without Yosys fails (only the default falls back).
#[test]
fn an_explicit_engine_does_not_fall_back() {
    let dir = common::workdir("simeng_explicit");
    let empty = dir.join("empty_path");
    std::fs::create_dir_all(&empty).unwrap();
    let env = [
        ("PATH", empty.into_os_string()),
        ("RUSTC", rustc_path().into_os_string()),
        ("SINEDEC_ENGINE_CACHE", dir.join("cache").into_os_string()),
    ];
    for engine in ["interpreter", "compiled"] {
        let mut args = SHORT.to_vec();
        args.extend(["--engine", engine]);
        let out = simulate_raw(&args, &dir, &env);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{engine}: {err}");
        assert!(err.contains("yosys"), "{engine}: {err}");
        assert!(!String::from_utf8_lossy(&out.stdout).contains("max |error|"));
    }
}
