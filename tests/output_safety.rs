//! Data safety and robustness of the command line (issue 13, sections A, B and D):
//! the output-directory rule (README "Output directory"), refusal of `-o` at a regular file,
//! no fixed temporary names, up-front `--csv`/`--vcd` checks, `init` parents, non-UTF-8
//! paths, a closed or full stdout, OS errors printed once, no Rust Debug text in user output,
//! long echoed values clipped, negative option values.
use sinedec::config::DEFAULT_CONFIG;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");
const MANIFEST: &str = ".sinedec-manifest";

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .output()
        .expect("run sinedec")
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// Runs and asserts success; returns stdout.
fn ok(dir: &Path, args: &[&str]) -> String {
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
fn refused(dir: &Path, args: &[&str]) -> String {
    let o = run(dir, args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "sinedec {args:?}: {e}");
    assert!(!e.contains("panicked"), "{e}");
    e
}

/// Every entry under `dir` (recursively) with its bytes (directories as None).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Option<Vec<u8>>> {
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

fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The names the manifest lists for `command` (lines "<command> <file>").
fn manifest(dir: &Path, command: &str) -> Vec<String> {
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

// ---------------------------------------------------------------------------------------
// A. The output-directory rule

#[test]
fn new_directory_is_created_with_parents_and_a_manifest() {
    let tmp = tempfile::tempdir().unwrap();
    ok(tmp.path(), &["generate", "-o", "a/b/out"]);
    let out = tmp.path().join("a/b/out");
    let mut files = listing(&out);
    files.retain(|f| f != MANIFEST);
    assert!(files.contains(&"sd_core.v".to_string()), "{files:?}");
    assert_eq!(
        manifest(&out, "generate"),
        files,
        "manifest lists every file"
    );
    assert_eq!(listing(&tmp.path().join("a/b")), vec!["out"]);
}

#[test]
fn existing_empty_directory_is_filled() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir(tmp.path().join("out")).unwrap();
    ok(tmp.path(), &["generate", "-o", "out"]);
    assert!(tmp.path().join("out/sd_core.v").is_file());
}

#[test]
fn non_empty_directory_without_manifest_is_refused_and_left_alone() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    std::fs::create_dir_all(out.join("sub")).unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    std::fs::write(out.join("sub/deeper.v"), "mine").unwrap();
    let before = snapshot(tmp.path());
    let e = refused(tmp.path(), &["generate", "-o", "out"]);
    assert!(e.contains("--force") && e.contains("out"), "{e}");
    assert_eq!(snapshot(tmp.path()), before, "something changed");
}

/// The issue's example: the config in the output directory survives.
#[test]
fn config_inside_the_output_directory_is_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(dir, &["init", "fpga/sinedec.toml"]);
    let cfg = std::fs::read(dir.join("fpga/sinedec.toml")).unwrap();
    let e = refused(dir, &["generate", "fpga/sinedec.toml", "-o", "fpga"]);
    assert!(e.contains("--force"), "{e}");
    assert_eq!(listing(&dir.join("fpga")), vec!["sinedec.toml"]);
    ok(
        dir,
        &["generate", "fpga/sinedec.toml", "-o", "fpga", "--force"],
    );
    assert_eq!(std::fs::read(dir.join("fpga/sinedec.toml")).unwrap(), cfg);
    assert!(dir.join("fpga/sd_core.v").is_file());
    assert!(!manifest(&dir.join("fpga"), "generate").contains(&"sinedec.toml".to_string()));
    // Regenerating needs no --force (the manifest names sinedec's files) and keeps the config.
    ok(dir, &["generate", "fpga/sinedec.toml", "-o", "fpga"]);
    assert_eq!(std::fs::read(dir.join("fpga/sinedec.toml")).unwrap(), cfg);
}

/// `--force` adds files next to foreign ones but never overwrites a file sinedec did not
/// write.
#[test]
fn force_never_overwrites_a_foreign_file() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    std::fs::create_dir(&out).unwrap();
    std::fs::write(out.join("sd_core.v"), "// my own core\n").unwrap();
    let before = snapshot(tmp.path());
    let e = refused(tmp.path(), &["generate", "-o", "out", "--force"]);
    assert!(e.contains("sd_core.v"), "{e}");
    assert_eq!(snapshot(tmp.path()), before, "something changed");
}

/// With a manifest: files of the previous generation are replaced or removed, a foreign file
/// that a new output would overwrite is refused before anything is written, other foreign
/// files stay.
#[test]
fn manifest_bounds_what_is_replaced_and_removed() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let out = dir.join("out");
    // The default config has no [board]: no UCF in the first generation.
    ok(dir, &["generate", "-o", "out"]);
    let first = manifest(&out, "generate");
    assert!(!first.contains(&"sd_top.ucf".to_string()), "{first:?}");
    // With a board (the kit preset and header pins as in tests/board.rs) it has one.
    let mut board = DEFAULT_CONFIG.to_string();
    board.push_str("\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\n");
    for (i, p) in ["qep_a", "qep_b", "qep_z", "biss_ma", "biss_slo"]
        .iter()
        .enumerate()
    {
        board.push_str(&format!("{p} = \"H{}\"\n", i + 1));
    }
    std::fs::write(dir.join("b.toml"), board).unwrap();
    // The user adds files, one with a name the next generation produces.
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    std::fs::write(out.join("sd_top.ucf"), "# my pins\n").unwrap();
    let before = snapshot(dir);
    let e = refused(dir, &["generate", "b.toml", "-o", "out"]);
    assert!(e.contains("sd_top.ucf"), "{e}");
    assert_eq!(snapshot(dir), before, "something changed");
    let e = refused(dir, &["generate", "b.toml", "-o", "out", "--force"]);
    assert!(e.contains("sd_top.ucf"), "{e}");
    assert_eq!(snapshot(dir), before, "something changed");
    // Without the clash the board config replaces the old files and adds its own.
    std::fs::remove_file(out.join("sd_top.ucf")).unwrap();
    ok(dir, &["generate", "b.toml", "-o", "out"]);
    assert!(std::fs::read_to_string(out.join("sd_top.ucf"))
        .unwrap()
        .contains("NET \"clk\""));
    assert_eq!(
        std::fs::read_to_string(out.join("notes.txt")).unwrap(),
        "mine"
    );
    // Back to the default config: the UCF and .ut it no longer produces are removed.
    ok(dir, &["generate", "-o", "out"]);
    assert!(!out.join("sd_top.ucf").exists() && !out.join("sd_top.ut").exists());
    assert_eq!(manifest(&out, "generate"), first);
    // Another name: the previous generation's files are removed, the user's file stays.
    let enc2 = DEFAULT_CONFIG.replace("name = \"sd\"", "name = \"enc2\"");
    std::fs::write(dir.join("enc2.toml"), enc2).unwrap();
    ok(dir, &["generate", "enc2.toml", "-o", "out"]);
    let files = listing(&out);
    assert!(
        files.iter().all(|f| !f.starts_with("sd_")),
        "stale files of the previous generation: {files:?}"
    );
    assert!(files.contains(&"notes.txt".to_string()), "{files:?}");
    assert!(files.contains(&"enc2_core.v".to_string()), "{files:?}");
    let mut expect: Vec<String> = files
        .into_iter()
        .filter(|f| f != MANIFEST && f != "notes.txt")
        .collect();
    expect.sort();
    assert_eq!(manifest(&out, "generate"), expect);
}

#[test]
fn output_at_a_regular_file_is_refused_before_touching_anything() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("target"), "mine").unwrap();
    let before = snapshot(dir);
    let e = refused(dir, &["generate", "-o", "target"]);
    assert!(e.contains("target") && e.contains("not a directory"), "{e}");
    assert_eq!(snapshot(dir), before, "something changed");
    // report: refused up front, before any synthesis (no Yosys summary line).
    let e = refused(dir, &["report", "-o", "target", "--iterations", "2"]);
    assert!(
        e.contains("not a directory") && !e.contains("yosys:"),
        "{e}"
    );
    assert_eq!(snapshot(dir), before, "something changed");
    // report into a foreign non-empty directory: refused up front too.
    std::fs::create_dir(dir.join("rep")).unwrap();
    std::fs::write(dir.join("rep/notes.txt"), "mine").unwrap();
    let before = snapshot(dir);
    let e = refused(dir, &["report", "-o", "rep", "--iterations", "2"]);
    assert!(e.contains("--force") && !e.contains("yosys:"), "{e}");
    assert_eq!(snapshot(dir), before, "something changed");
}

/// No fixed `<path>.tmp` names: a user's file with that name survives.
#[test]
fn no_fixed_temporary_names() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("my.toml.tmp"), "mine").unwrap();
    std::fs::write(dir.join("run.csv.tmp"), "mine").unwrap();
    ok(dir, &["init", "my.toml"]);
    ok(
        dir,
        &["simulate", "--duration", "0.0001", "--csv", "run.csv"],
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("my.toml.tmp")).unwrap(),
        "mine"
    );
    assert_eq!(
        std::fs::read_to_string(dir.join("run.csv.tmp")).unwrap(),
        "mine"
    );
    assert_eq!(
        listing(dir),
        vec!["my.toml", "my.toml.tmp", "run.csv", "run.csv.tmp"]
    );
}

/// `--csv`/`--vcd` paths that cannot be written are rejected before the simulation runs
/// (no summary printed), and leave nothing behind.
#[test]
fn csv_and_vcd_paths_are_checked_up_front() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("adir")).unwrap();
    for args in [
        &["--csv", "missing/run.csv"][..],
        &["--vcd", "missing/run.vcd"][..],
        &["--csv", "adir"][..],
        &["--vcd", "adir"][..],
    ] {
        let mut all = vec!["simulate", "--duration", "0.0001"];
        all.extend(args);
        let o = run(dir, &all);
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {e}");
        assert!(e.contains(args[1]), "{args:?}: {e}");
        assert!(
            !stdout(&o).contains("max |error|"),
            "{args:?}: the simulation ran before the check:\n{}",
            stdout(&o)
        );
        assert_eq!(listing(dir), vec!["adir"]);
        assert!(listing(&dir.join("adir")).is_empty());
    }
}

#[test]
fn init_creates_parent_directories() {
    let tmp = tempfile::tempdir().unwrap();
    ok(tmp.path(), &["init", "a/b/c.toml"]);
    assert_eq!(
        std::fs::read_to_string(tmp.path().join("a/b/c.toml")).unwrap(),
        DEFAULT_CONFIG
    );
    assert_eq!(listing(&tmp.path().join("a/b")), vec!["c.toml"]);
}

// ---------------------------------------------------------------------------------------
// B. No panics

#[cfg(unix)]
#[test]
fn non_utf8_paths_do_not_panic() {
    use std::ffi::OsStr;
    use std::os::unix::ffi::OsStrExt;
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let cfg = OsStr::from_bytes(b"cfg\xff.toml");
    let out = OsStr::from_bytes(b"out\xfe");
    std::fs::write(dir.join(cfg), DEFAULT_CONFIG).unwrap();
    let o = Command::new(BIN)
        .arg("generate")
        .arg(cfg)
        .arg("-o")
        .arg(out)
        .current_dir(dir)
        .output()
        .unwrap();
    assert!(o.status.success(), "{:?}: {}", o.status, stderr(&o));
    let v = std::fs::read_to_string(dir.join(out).join("sd_core.v")).unwrap();
    assert!(v.contains("module sd_core ("));
    // report: an argument error after the config is read, no panic on the way.
    for args in [&["check"][..], &["report", "--iterations", "99"][..]] {
        let o = Command::new(BIN)
            .args(args)
            .arg(cfg)
            .arg("-o")
            .arg(out)
            .current_dir(dir)
            .output()
            .unwrap();
        let e = stderr(&o);
        assert!(!e.contains("panicked"), "{args:?}: {e}");
        assert_ne!(o.status.code(), Some(101), "{args:?}: {e}");
    }
    let o = Command::new(BIN)
        .args(["report", "--iterations", "99"])
        .arg(cfg)
        .arg("-o")
        .arg(out)
        .current_dir(dir)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
}

/// The argument lists the stdout tests run: every subcommand (report stops at an argument
/// error after its first output would be due; it has no output before).
fn each_command() -> Vec<Vec<&'static str>> {
    vec![
        vec!["check"],
        vec!["generate", "-o", "out"],
        vec!["init", "new.toml"],
        vec!["simulate", "--duration", "0.0001"],
    ]
}

/// A closed pipe (`sinedec check | true`): no panic, no message, the status a shell shows
/// for a tool killed by SIGPIPE (141), as `cat` or `seq` give.
#[cfg(unix)]
#[test]
fn closed_stdout_exits_quietly() {
    for args in each_command() {
        let tmp = tempfile::tempdir().unwrap();
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = Command::new(BIN)
            .args(&args)
            .current_dir(tmp.path())
            .stdin(Stdio::null())
            .stdout(writer)
            .stderr(Stdio::piped())
            .output()
            .unwrap();
        let e = stderr(&o);
        assert_eq!(o.status.code(), Some(141), "{args:?}: {:?} {e}", o.status);
        assert!(e.trim().is_empty(), "{args:?}: {e}");
    }
}

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
    assert_eq!(e.matches("No such file or directory").count(), 1, "{e}");
}

/// Rust Debug spellings that must not reach a user.
fn assert_no_debug_text(what: &str, text: &str) {
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

// ---------------------------------------------------------------------------------------
// A. The rule at the library level (emit::output)

use sinedec::emit::output::{write_files, OutputOptions};

fn opts(command: &str) -> OutputOptions {
    OutputOptions::new(command)
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

// ---------------------------------------------------------------------------------------
// F. Header text never breaks the file it sits in

/// The comment marker a header line of `file` starts with (None: no header).
fn marker(file: &str) -> Option<&'static str> {
    match file.rsplit('.').next() {
        Some("v") => Some("//"),
        Some("ucf" | "qsf" | "sdc") => Some("#"),
        Some("md") => Some("<!--"),
        _ => None,
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
