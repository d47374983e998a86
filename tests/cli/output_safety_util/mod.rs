//! Helpers shared by `tests/cli/output_safety.rs`, `tests/cli/output_robustness.rs` and
//! `tests/cli/signals.rs` (moved out of `tests/cli/output_safety.rs` so that
//! no test file is longer than about 600 lines).
#![allow(dead_code)]
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

// ---------------------------------------------------------------------------------------
// A. The rule at the library level (emit::output)

use sinedec::emit::output::OutputOptions;

pub const BIN: &str = env!("CARGO_BIN_EXE_sinedec");
pub const MANIFEST: &str = ".sinedec-manifest";

pub fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("run sinedec")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Runs and asserts success; returns stdout.
pub fn ok(dir: &Path, args: &[&str]) -> String {
    let o = run(dir, args);
    assert!(
        o.status.success(),
        "sinedec {args:?} failed ({:?}): {}",
        o.status,
        stderr(&o)
    );
    stdout(&o)
}

/// Runs and asserts exit status 1 (a refusal, not a panic); returns stderr.
pub fn refused(dir: &Path, args: &[&str]) -> String {
    let o = run(dir, args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "sinedec {args:?}: {e}");
    assert!(!e.contains("panicked"), "{e}");
    e
}

/// Every entry under `dir` (recursively) with its bytes (directories as None).
pub fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
    let mut m = BTreeMap::new();
    fn walk(base: &Path, d: &Path, m: &mut BTreeMap<PathBuf, Option<Vec<u8>>>) {
        for e in std::fs::read_dir(d).unwrap() {
            let p = e.unwrap().path();
            let rel = p.strip_prefix(base).unwrap().to_path_buf();
            if p.is_dir() {
                m.insert(rel, None);
                walk(base, &p, m);
            } else {
                m.insert(rel, Some(std::fs::read(&p).unwrap()));
            }
        }
    }
    walk(dir, dir, &mut m);
    m
}

pub fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The names the manifest lists for `command` (lines "<command> <file>").
pub fn manifest(dir: &Path, command: &str) -> Vec<String> {
    let text = std::fs::read_to_string(dir.join(MANIFEST)).expect("manifest written");
    let mut v: Vec<String> = text
        .lines()
        .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
        .filter_map(|l| l.strip_prefix(&format!("{command} ")))
        .map(String::from)
        .collect();
    v.sort();
    v
}

/// The argument lists the stdout tests run: every subcommand (report stops at an argument
/// error after its first output would be due; it has no output before).
pub fn each_command() -> Vec<Vec<&'static str>> {
    vec![
        vec!["check"],
        vec!["generate", "-o", "out"],
        vec!["init", "new.toml"],
        vec!["simulate", "--duration", "0.0001"],
    ]
}

/// Rust Debug spellings that must not reach a user.
pub fn assert_no_debug_text(what: &str, text: &str) {
    for bad in [
        "Some(",
        "None",
        "Ok(",
        "Err(",
        "Ltc1407a1",
        "Unrolled",
        "Iterative",
        "Generic",
        "Static",
        "Auto",
    ] {
        assert!(
            !text.contains(bad),
            "{what}: Debug text {bad:?} in:\n{text}"
        );
    }
}

pub fn opts(command: &str) -> OutputOptions {
    OutputOptions::new(command)
}

// ---------------------------------------------------------------------------------------
// F. Header text never breaks the file it sits in

/// The comment marker a header line of `file` starts with (None: no header).
pub fn marker(file: &str) -> Option<&'static str> {
    match file.rsplit('.').next() {
        Some("v") => Some("//"),
        Some("ucf" | "qsf" | "sdc") => Some("#"),
        Some("md") => Some("<!--"),
        _ => None,
    }
}

/// Temporary names sinedec makes, found in `dir`.
pub fn temporaries(dir: &std::path::Path) -> Vec<String> {
    listing(dir)
        .into_iter()
        .filter(|f| {
            (f.starts_with(".sinedec-") && f.ends_with(".tmp"))
                || f.starts_with("sinedec-")
                || f.starts_with(".tmp")
        })
        .collect()
}
