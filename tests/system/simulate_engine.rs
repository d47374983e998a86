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
    let args = [CAP, "--duration", "0.0035", "--profile", "constant:800"];
    default_equals_rust_hdl("simeng_cap", &args, 400);
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
