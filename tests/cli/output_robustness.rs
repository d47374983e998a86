//! Data safety and robustness of the command line (issue 13, sections A, B and D):
//! the output-directory rule (docs/cli.md "Output directory"), refusal of `-o` at a regular file,
//! no fixed temporary names, up-front `--csv`/`--vcd` checks, `init` parents, non-UTF-8
//! paths, a closed or full stdout, OS errors printed once, no Rust Debug text in user output,
//! long echoed values clipped, negative option values.
//!
//! (Second half of the tests of `tests/cli/output_safety.rs`; helpers in `tests/cli/output_safety_util/`.)
use sinedec::config::DEFAULT_CONFIG;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

// ---------------------------------------------------------------------------------------
// A. The rule at the library level (emit::output)

use crate::output_safety_util;
use output_safety_util::*;
use sinedec::emit::output::write_files;

/// A full stdout (`> /dev/full`): exit status 1 and a message, no panic.
#[cfg(target_os = "linux")]
#[test]
fn full_stdout_is_an_error() {
    for args in each_command() {
        let tmp = tempfile::tempdir().unwrap();
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = Command::new(BIN)
            .args(&args)
            .current_dir(tmp.path())
            .stdin(Stdio::null())
            .stdout(full)
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {:?} {e}", o.status);
        assert!(
            e.contains("standard output") && e.contains("No space left"),
            "{args:?}: {e}"
        );
        assert!(!e.contains("panicked"), "{args:?}: {e}");
    }
}

// ---------------------------------------------------------------------------------------
// D. Messages

#[test]
fn os_errors_are_printed_once() {
    let tmp = tempfile::tempdir().unwrap();
    let e = refused(tmp.path(), &["check", "missing.toml"]);
    assert!(e.contains("missing.toml"), "{e}");
    // One plain sentence (L2 of the reliability rules): the problem said once, and the
    // OS's own wording not repeated after it.
    assert_eq!(e.matches("does not exist").count(), 1, "{e}");
    assert!(!e.contains("No such file or directory"), "{e}");
}

#[test]
fn no_debug_text_in_user_output() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let out = ok(dir, &["check"]);
    assert_no_debug_text("check", &out);
    assert!(
        out.contains("LTC1407A-1") && out.contains("unrolled"),
        "{out}"
    );
    let iter = DEFAULT_CONFIG.replace(
        "architecture = \"unrolled\"",
        "architecture = \"iterative\"",
    );
    std::fs::write(dir.join("it.toml"), iter).unwrap();
    let out = ok(dir, &["check", "it.toml"]);
    assert_no_debug_text("check it.toml", &out);
    assert!(out.contains("iterative"), "{out}");
    let out = ok(dir, &["simulate", "--duration", "0.0001"]);
    assert_no_debug_text("simulate", &out);
    assert!(out.contains("preamp gains read back"), "{out}");
    ok(dir, &["generate", "-o", "out"]);
    let md = std::fs::read_to_string(dir.join("out/sd_params.md")).unwrap();
    assert_no_debug_text("sd_params.md", &md);
}

/// A 100,000-character value is not echoed whole.
#[test]
fn long_echoed_values_are_clipped() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let long = "x".repeat(100_000);
    std::fs::write(
        dir.join("long.toml"),
        DEFAULT_CONFIG.replace("name = \"sd\"", &format!("name = \"{long}\"")),
    )
    .unwrap();
    let e = refused(dir, &["check", "long.toml"]);
    assert!(e.contains("name"), "{}", &e[..e.len().min(500)]);
    assert!(e.len() < 1000, "{} bytes: {}", e.len(), &e[..500]);
    let profile = format!("constant:{long}");
    let e = refused(dir, &["simulate", "--profile", &profile]);
    assert!(e.len() < 1000, "{} bytes: {}", e.len(), &e[..500]);
}

#[test]
fn signed_options_take_negative_values() {
    let tmp = tempfile::tempdir().unwrap();
    let out = ok(
        tmp.path(),
        &[
            "simulate",
            "--duration",
            "0.0001",
            "--offset-sin",
            "-0.05",
            "--offset-cos",
            "-0.02",
            "--gain-mismatch",
            "-0.01",
            "--phase-error",
            "-1",
            "--harmonic3",
            "-0.01",
        ],
    );
    assert!(out.contains("max |error|"), "{out}");
}

/// A failure after some new files are complete, before any rename: the old files are intact,
/// no temporary file is left, and a directory created for the output is removed again.
#[test]
fn a_failure_before_the_renames_leaves_the_old_files_and_no_temporaries() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let old: &[(&str, &[u8])] = &[("a.v", b"old a"), ("b.v", b"old b"), ("c.v", b"old c")];
    write_files(&out, old, &opts("generate")).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let before = snapshot(tmp.path());
    let new: &[(&str, &[u8])] = &[("a.v", b"new a"), ("b.v", b"new b"), ("d.v", b"new d")];
    for k in 0..new.len() {
        let mut o = opts("generate");
        o.fail_after_temps = Some(k);
        assert!(write_files(&out, new, &o).is_err());
        assert_eq!(snapshot(tmp.path()), before, "after {k} temporary files");
    }
    // Into a new nested directory: nothing is left, not even the directories.
    let mut o = opts("generate");
    o.fail_after_temps = Some(1);
    assert!(write_files(&tmp.path().join("x/y/z"), new, &o).is_err());
    assert!(!tmp.path().join("x").exists());
    // Without the injected failure the new set replaces the old one.
    write_files(&out, new, &opts("generate")).unwrap();
    assert_eq!(std::fs::read(out.join("a.v")).unwrap(), b"new a");
    assert!(!out.join("c.v").exists(), "stale file kept");
    assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), b"mine");
}

/// `generate` and `report` can share a directory: each removes only its own stale files.
#[test]
fn two_commands_share_a_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    write_files(&out, &[("g1", b"1"), ("g2", b"2")], &opts("generate")).unwrap();
    write_files(&out, &[("r1", b"1")], &opts("report")).unwrap();
    assert_eq!(listing(&out), vec![MANIFEST, "g1", "g2", "r1"]);
    write_files(&out, &[("g1", b"1")], &opts("generate")).unwrap();
    assert_eq!(listing(&out), vec![MANIFEST, "g1", "r1"]);
    assert_eq!(manifest(&out, "generate"), vec!["g1"]);
    assert_eq!(manifest(&out, "report"), vec!["r1"]);
}

/// A manifest line that is not `<command> <plain file name>` (here one that would reach
/// outside the directory) stops everything; so does a listed name that is now a symbolic
/// link or a directory.
#[cfg(unix)]
#[test]
fn a_bad_manifest_or_a_replaced_file_stops_the_write() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(tmp.path().join("precious"), "mine").unwrap();
    std::fs::write(out.join(MANIFEST), "generate ../precious\n").unwrap();
    let before = snapshot(tmp.path());
    let e = write_files(&out, &[("a.v", b"a")], &opts("generate")).unwrap_err();
    assert!(e.to_string().contains("line 1"), "{e}");
    assert_eq!(snapshot(tmp.path()), before);

    std::fs::write(out.join(MANIFEST), "generate a.v\ngenerate b.v\n").unwrap();
    std::os::unix::fs::symlink(tmp.path().join("precious"), out.join("a.v")).unwrap();
    std::fs::create_dir(out.join("b.v")).unwrap();
    let before = snapshot(tmp.path());
    for name in ["a.v", "b.v"] {
        let e = write_files(&out, &[(name, b"new")], &opts("generate")).unwrap_err();
        assert!(e.to_string().contains("regular file"), "{e}");
        assert_eq!(snapshot(tmp.path()), before);
    }
    // Removing stale entries leaves a link or directory alone as well.
    write_files(&out, &[("c.v", b"c")], &opts("generate")).unwrap();
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("precious")).unwrap(),
        "mine"
    );
    assert!(out.join("a.v").is_symlink() && out.join("b.v").is_dir());
}

/// Killed at any moment while replacing a previous generation, every file of it is still
/// there, complete, in its old or its new version (a directory swap would leave a window
/// with no directory at all).
#[cfg(unix)]
#[test]
fn a_kill_never_leaves_a_file_missing_or_partial() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("b.toml"),
        DEFAULT_CONFIG.replace("ppr = 2048", "ppr = 1000"),
    )
    .unwrap();
    // The headers quote the command line, so the references are made with `-o out` too.
    ok(dir, &["generate", "-o", "out"]);
    let old = snapshot(&dir.join("out"));
    ok(dir, &["generate", "b.toml", "-o", "out"]);
    let new = snapshot(&dir.join("out"));
    assert!(
        old.iter().any(|(k, v)| new.get(k) != Some(v)),
        "the versions differ"
    );
    let names: Vec<&PathBuf> = old.keys().filter(|p| !p.ends_with(MANIFEST)).collect();
    for i in 0..16u64 {
        let _ = std::fs::remove_dir_all(dir.join("out"));
        ok(dir, &["generate", "-o", "out"]);
        let mut child = Command::new(BIN)
            .args(["generate", "b.toml", "-o", "out"])
            .current_dir(dir)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_millis(i * i * 4));
        let _ = child.kill();
        let _ = child.wait();
        let now = snapshot(&dir.join("out"));
        for n in &names {
            let got = now
                .get(*n)
                .unwrap_or_else(|| panic!("kill {i}: {n:?} missing"));
            assert!(
                got == &old[*n] || got == &new[*n],
                "kill {i}: {n:?} is neither the old nor the new version"
            );
        }
    }
}

#[test]
fn control_characters_in_the_config_path_stay_inside_the_header_comment() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let cap = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("configs/cyclone3_capacitive.toml"),
    )
    .unwrap();
    let cases = [
        (
            "we\nird\t\u{1b}\r<!-- -->\u{2028}.toml",
            DEFAULT_CONFIG.to_string(),
            "o1",
        ),
        ("cap\nx\\", cap, "o2\\"),
    ];
    for (name, text, out) in cases {
        std::fs::write(dir.join(name), &text).unwrap();
        ok(dir, &["generate", name, "-o", out]);
        let mut seen = 0;
        for f in listing(&dir.join(out)) {
            let Some(m) = marker(&f) else { continue };
            seen += 1;
            let body = std::fs::read_to_string(dir.join(out).join(&f)).unwrap();
            let head: Vec<&str> = body.lines().take(4).collect();
            for l in &head {
                assert!(
                    l.starts_with(m),
                    "{f}: header line {l:?} outside the comment"
                );
                let trailing = l.len() - l.trim_end_matches('\\').len();
                assert!(trailing % 2 == 0, "{f}: {l:?} ends in a line continuation");
                if m == "<!--" {
                    assert!(
                        l.ends_with(" -->") && l.matches("-->").count() == 1,
                        "{f}: {l:?} closes its comment early"
                    );
                    assert_eq!(l.matches("<!--").count(), 1, "{f}: {l:?}");
                }
            }
            assert!(
                head[1].contains("we\\nird\\t\\u{1b}\\r") || head[1].contains("cap\\nx\\\\"),
                "{f}: {head:?}"
            );
            // The line after the header is the file's own first line.
            let next = body.lines().nth(4).unwrap_or("");
            assert!(
                !next.starts_with(m) || m == "#" || m == "<!--",
                "{f}: {next:?}"
            );
        }
        assert!(seen >= 3, "{out}: {seen} files with a header");
    }
    // The Verilog still compiles.
    sinedec::cosim::require_tool("iverilog").expect("iverilog installed");
    let c = Command::new("iverilog")
        .args(["-g2005", "-o", "tb.vvp", "o1/sd_core.v", "o1/sd_core_tb.v"])
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(c.status.success(), "{}", stderr(&c));
}
