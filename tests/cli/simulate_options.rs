//! `simulate`'s encoder-distortion and statistics options on the command line (issue 46):
//! `--harmonic2/3/5`, their phases and `--eccentricity` are checked by name, and `--settle S`
//! leaves out of the statistics (and marks in the CSV's `warmup` column) every sample that
//! leaves the top before S, and is refused when it leaves no sample.
use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run sinedec")
}

/// Runs and asserts failure with exit status 1; returns stderr.
fn refused(dir: &Path, args: &[&str]) -> String {
    let o = run(dir, args);
    let e = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(1), "sinedec {args:?}: {e}");
    e
}

/// The number after `label` on its summary line.
fn figure(out: &str, label: &str) -> f64 {
    let line = out
        .lines()
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("no {label:?} in\n{out}"));
    line[label.len()..]
        .split_whitespace()
        .next()
        .and_then(|w| w.parse().ok())
        .unwrap_or_else(|| panic!("{line}"))
}

#[test]
fn distortion_options_are_checked_by_name() {
    let tmp = tempfile::tempdir().unwrap();
    for (opt, v, allowed) in [
        ("--harmonic2", "0.51", "-0.5..=0.5"),
        ("--harmonic5", "-1", "-0.5..=0.5"),
        ("--harmonic2-phase", "-400", "-360..=360 degrees"),
        ("--harmonic5-phase", "nan", "-360..=360 degrees"),
        ("--eccentricity", "1e4", "-3600..=3600 arc-seconds"),
        ("--settle", "-0.1", "0 <= seconds < --duration"),
    ] {
        let e = refused(tmp.path(), &["simulate", "--duration", "0.001", opt, v]);
        assert!(
            e.contains(&format!("`{opt}`")) && e.contains(allowed),
            "{opt} {v}: {e}"
        );
    }
}

#[test]
fn a_settle_time_past_the_run_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    // At or after the end: refused before the run.
    for s in ["0.001", "5"] {
        let e = refused(
            tmp.path(),
            &["simulate", "--duration", "0.001", "--settle", s],
        );
        assert!(
            e.contains("`--settle`") && e.contains("leaves no sample"),
            "{e}"
        );
    }
    // Within the run's last clock cycle: no sample leaves after it.
    let e = refused(
        tmp.path(),
        &[
            "simulate",
            "--duration",
            "0.0003",
            "--settle",
            "0.000299997",
        ],
    );
    assert!(
        e.contains("`--settle`") && e.contains("leaves no sample"),
        "{e}"
    );
}

/// With `--settle 0.0004` the statistics count the CSV's rows whose `cycle` is at least
/// 0.0004 s x the clock (past the first 12), and only those have `warmup` 0; the max error
/// is theirs.
#[test]
fn settle_leaves_the_early_samples_out() {
    let tmp = tempfile::tempdir().unwrap();
    let args = [
        "simulate",
        "--profile",
        "constant:3000",
        "--duration",
        "0.001",
        "--harmonic3",
        "0.02",
        "--settle",
        "0.0004",
        "--csv",
        "s.csv",
    ];
    let o = run(tmp.path(), &args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    // The shipped default's clock: 133.33 MHz (configs/spartan3an.toml).
    let first = (0.0004f64 * 133.33e6).ceil() as u64;
    assert!(out.contains("statistics from"), "{out}");
    let csv = std::fs::read_to_string(tmp.path().join("s.csv")).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (c_cycle, c_err, c_warm) = (col("cycle"), col("error_lsb"), col("warmup"));
    let (mut counted, mut max, mut early) = (0usize, 0f64, 0usize);
    for (i, l) in lines.enumerate() {
        let f: Vec<&str> = l.split(',').collect();
        let cycle: u64 = f[c_cycle].parse().unwrap();
        let warm = f[c_warm] == "1";
        assert_eq!(warm, i < 12 || cycle < first, "row {i}: {l}");
        if warm {
            early += (i >= 12) as usize;
        } else {
            counted += 1;
            max = max.max(f[c_err].parse::<f64>().unwrap().abs());
        }
    }
    assert!(early > 100, "{early} rows before --settle");
    let stats = out
        .lines()
        .find(|l| l.starts_with("decoded samples"))
        .unwrap();
    assert!(
        stats.contains(&format!("({counted} in the statistics)")),
        "{stats}"
    );
    assert!((figure(&out, "max |error|") - max).abs() < 0.01, "{out}");
}
