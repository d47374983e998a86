//! Data safety and robustness of the command line (issue 13, sections A, B and D):
//! the output-directory rule (docs/cli.md "Output directory"), refusal of `-o` at a regular file,
//! no fixed temporary names, up-front `--csv`/`--vcd` checks, `init` parents, non-UTF-8
//! paths, a closed or full stdout, OS errors printed once, no Rust Debug text in user output,
//! long echoed values clipped, negative option values.
//!
//! (More tests in `tests/cli/output_robustness.rs`, the signals in `tests/cli/signals.rs`; the
//! helpers are in `tests/cli/output_safety_util/`.)
use sinedec::config::DEFAULT_CONFIG;
use std::process::{Command, Stdio};

// ---------------------------------------------------------------------------------------
// A. The rule at the library level (emit::output)

use crate::output_safety_util;
use output_safety_util::*;

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

/// The example: the config in the output directory survives.
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
    // With a board (the kit preset and header pins as in tests/cli/board.rs) it has one.
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

// ---------------------------------------------------------------------------------------
// E. Special files, outputs that are inputs, the directory lock, plain messages (issue 42)

/// A node of `special_nodes` and the listener that keeps a socket bound.
type Node = (std::path::PathBuf, std::os::unix::net::UnixListener);

/// A FIFO and a Unix socket made in `dir` (never under /dev).
fn special_nodes(dir: &std::path::Path) -> Vec<Node> {
    let fifo = dir.join("fifo");
    let st = Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(st.success());
    let sock = dir.join("sock");
    let l = std::os::unix::net::UnixListener::bind(&sock).expect("socket");
    let l2 = l.try_clone().expect("clone");
    vec![(fifo, l), (sock, l2)]
}

fn is_special(p: &std::path::Path) -> bool {
    use std::os::unix::fs::FileTypeExt;
    let t = std::fs::symlink_metadata(p)
        .expect("still there")
        .file_type();
    t.is_fifo() || t.is_socket()
}

/// H1: `--csv`, `--vcd` and `init --force` refuse a FIFO or a socket (docs/cli.md "Output
/// directory": sinedec writes only regular files) and leave it in place.
#[test]
fn special_files_are_refused_and_kept() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let nodes = special_nodes(dir);
    for (node, _keep) in &nodes {
        let name = node.file_name().unwrap().to_str().unwrap();
        for args in [
            vec!["simulate", "--duration", "0.0005", "--csv", name],
            vec!["simulate", "--duration", "0.0005", "--vcd", name],
            vec!["init", name, "--force"],
        ] {
            let e = refused(dir, &args);
            assert!(
                e.contains(name) && e.contains("regular file"),
                "{args:?}: {e}"
            );
            assert!(is_special(node), "{args:?} replaced {name}");
        }
    }
    let mut left = listing(dir);
    left.sort();
    assert_eq!(left, vec!["fifo", "sock"], "temporaries left");
}

/// M4: an output that is the config, or both outputs at one path, is refused before the
/// run; the config keeps its bytes.
#[test]
fn outputs_that_overwrite_inputs_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("cfg.toml"), DEFAULT_CONFIG).unwrap();
    for args in [
        &[
            "simulate",
            "cfg.toml",
            "--duration",
            "0.0005",
            "--csv",
            "cfg.toml",
        ][..],
        &[
            "simulate",
            "cfg.toml",
            "--duration",
            "0.0005",
            "--vcd",
            "./cfg.toml",
        ][..],
        &[
            "simulate",
            "--duration",
            "0.0005",
            "--csv",
            "x",
            "--vcd",
            "x",
        ][..],
    ] {
        let e = refused(dir, args);
        assert!(
            e.contains("configuration file") || e.contains("its own path"),
            "{args:?}: {e}"
        );
        assert_eq!(
            std::fs::read_to_string(dir.join("cfg.toml")).unwrap(),
            DEFAULT_CONFIG
        );
        assert_eq!(listing(dir), vec!["cfg.toml"], "{args:?}");
    }
}

/// L1: while another sinedec holds the output directory's lock (`flock` on the directory,
/// docs/cli.md "Output directory"), `generate -o d` says so and writes nothing.
#[test]
fn a_locked_output_directory_is_named_as_busy() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::create_dir(dir.join("d")).unwrap();
    let held = std::fs::File::open(dir.join("d")).unwrap();
    held.try_lock().expect("lock");
    let e = refused(dir, &["generate", "-o", "d"]);
    assert!(e.contains("another sinedec is writing d"), "{e}");
    assert!(listing(&dir.join("d")).is_empty());
    drop(held);
    ok(dir, &["generate", "-o", "d"]);
}

/// L1: two `generate -o d` at once: each succeeds, or one says the other is writing; never
/// "sinedec did not write it".
#[test]
fn concurrent_generates_into_one_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    for round in 0..4 {
        let d = format!("d{round}");
        let spawn = || {
            Command::new(BIN)
                .args(["generate", "-o", &d])
                .current_dir(dir)
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (a, b) = (spawn(), spawn());
        for c in [a, b] {
            let o = c.wait_with_output().unwrap();
            let e = stderr(&o);
            assert!(
                o.status.success() || e.contains("another sinedec is writing"),
                "{e}"
            );
        }
        assert!(!listing(&dir.join(&d)).iter().any(|f| f.ends_with(".tmp")));
    }
}

/// L2: a path through a regular file gets one sentence naming that file, not an OS error
/// number or a Debug-quoted temporary path.
#[test]
fn io_errors_are_one_plain_sentence() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("notes.txt"), "mine").unwrap();
    for args in [
        &["generate", "-o", "notes.txt/out"][..],
        &["init", "notes.txt/a/b.toml"][..],
        &[
            "simulate",
            "--duration",
            "0.0005",
            "--csv",
            "notes.txt/run.csv",
        ][..],
    ] {
        let e = refused(dir, args);
        assert!(
            e.contains("notes.txt") && e.contains("not a directory"),
            "{args:?}: {e}"
        );
        assert!(
            !e.contains("os error") && !e.contains("at path"),
            "{args:?}: {e}"
        );
    }
    assert_eq!(
        std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
        "mine"
    );
}
