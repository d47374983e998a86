//! Signals (issue 42, M1-M3): SIGINT, SIGTERM or SIGHUP during `generate`, `simulate` or
//! `report` removes sinedec's temporaries, stops its children and exits 128 + the signal.
//!
//! (The helpers are in `tests/cli/output_safety_util/`.)
use std::process::{Command, Stdio};

use crate::output_safety_util;
use output_safety_util::*;

/// Sends `sig` to `pid`.
fn signal(pid: u32, sig: &str) {
    let st = Command::new("kill")
        .args([&format!("-{sig}"), &pid.to_string()])
        .status()
        .unwrap();
    assert!(st.success());
}

/// Polls `cond` every 10 ms up to `limit_s` seconds (a liveness bound, not a timing
/// assertion).
fn wait_up_to(limit_s: u64, what: &str, mut cond: impl FnMut() -> bool) {
    for _ in 0..limit_s * 100 {
        if cond() {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    panic!("never saw {what}");
}

/// [`wait_up_to`] 300 s: for a stage of a run to begin.
fn wait_for(what: &str, cond: impl FnMut() -> bool) {
    wait_up_to(300, what, cond)
}

/// Children of `pid` (from /proc), with their command names.
fn children(pid: u32) -> Vec<(u32, String)> {
    let mut v = vec![];
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Ok(p) = e.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(format!("/proc/{p}/stat")) else {
            continue;
        };
        let Some(close) = stat.rfind(')') else {
            continue;
        };
        let name = stat[stat.find('(').unwrap() + 1..close].to_string();
        let ppid: u32 = stat[close + 2..]
            .split(' ')
            .nth(1)
            .and_then(|x| x.parse().ok())
            .unwrap_or(0);
        if ppid == pid {
            v.push((p, name));
        }
    }
    v
}

/// Whether process `pid` is gone (or a zombie awaiting its reaper).
fn gone(pid: u32) -> bool {
    match std::fs::read_to_string(format!("/proc/{pid}/stat")) {
        Err(_) => true,
        Ok(s) => s.rfind(')').is_some_and(|i| s[i + 2..].starts_with('Z')),
    }
}

/// M1: SIGTERM while `generate -o new` has its temporary files written leaves no
/// `.sinedec-*.tmp` behind, exits 143, and the next run needs no --force.
#[test]
fn sigterm_during_generate_leaves_no_temporaries() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut c = Command::new(BIN)
        .args(["generate", "-o", "new"])
        .current_dir(dir)
        .env("SINEDEC_TEST_PAUSE", "output-temps")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let out = dir.join("new");
    wait_for("the temporary files", || {
        out.is_dir() && listing(&out).iter().any(|f| f.ends_with(".tmp"))
    });
    signal(c.id(), "TERM");
    let st = c.wait().unwrap();
    let left = if out.exists() { listing(&out) } else { vec![] };
    assert!(left.iter().all(|f| !f.ends_with(".tmp")), "{left:?}");
    assert_eq!(st.code(), Some(143), "{st:?}");
    ok(dir, &["generate", "-o", "new"]);
}

/// M2: SIGHUP during `simulate --csv --vcd` removes both hidden temporaries and exits 129.
#[test]
fn sighup_during_simulate_removes_csv_and_vcd_temporaries() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut c = Command::new(BIN)
        .args([
            "simulate",
            "--engine",
            "rust-hdl",
            "--duration",
            "0.05",
            "--csv",
            "a.csv",
            "--vcd",
            "a.vcd",
        ])
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    wait_for("two temporary files", || {
        listing(dir).iter().filter(|f| f.ends_with(".tmp")).count() == 2
    });
    std::thread::sleep(std::time::Duration::from_millis(300));
    signal(c.id(), "HUP");
    let st = c.wait().unwrap();
    assert_eq!(listing(dir), Vec::<String>::new());
    assert_eq!(st.code(), Some(129), "{st:?}");
}

/// M3: SIGINT during `report` kills its Yosys children (no orphan keeps running), removes
/// the `sinedec-report-*` directory and exits 130.
#[test]
fn sigint_during_report_stops_yosys_and_removes_its_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let tmpdir = dir.join("tmp");
    std::fs::create_dir(&tmpdir).unwrap();
    let mut c = Command::new(BIN)
        .args([
            "report",
            "--iterations",
            "8..=12",
            "--no-cache",
            "-o",
            "rep",
        ])
        .current_dir(dir)
        .env("TMPDIR", &tmpdir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = c.id();
    let mut kids = vec![];
    wait_for("a yosys child", || {
        kids = children(pid);
        kids.iter().any(|(_, n)| n.starts_with("yosys"))
    });
    signal(pid, "INT");
    let st = c.wait().unwrap();
    for (k, name) in &kids {
        // A killed child is gone at once; an orphan would run on for seconds.
        wait_up_to(3, &format!("child {name} ({k}) stopped"), || gone(*k));
    }
    assert_eq!(temporaries(&tmpdir), Vec::<String>::new());
    let rep = dir.join("rep");
    assert!(!rep.exists() || listing(&rep).is_empty());
    assert_eq!(st.code(), Some(130), "{st:?}");
}

/// M3: SIGTERM during the engine build in `simulate` kills rustc (or Yosys), removes the
/// scratch and build directories and exits 143.
#[test]
fn sigterm_during_the_engine_build_stops_the_build() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let tmpdir = dir.join("tmp");
    let cache = dir.join("cache");
    std::fs::create_dir(&tmpdir).unwrap();
    let mut c = Command::new(BIN)
        .args(["simulate", "--duration", "0.0005"])
        .current_dir(dir)
        .env("TMPDIR", &tmpdir)
        .env("SINEDEC_ENGINE_CACHE", &cache)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let pid = c.id();
    let mut kids = vec![];
    // The build itself (`rustc ... engine.rs`), not the `rustc --version` of the cache key.
    wait_for("rustc building the engine", || {
        kids = children(pid);
        kids.iter().any(|(k, n)| {
            n.starts_with("rustc")
                && std::fs::read(format!("/proc/{k}/cmdline"))
                    .is_ok_and(|c| String::from_utf8_lossy(&c).contains("engine.rs"))
        })
    });
    signal(pid, "TERM");
    let st = c.wait().unwrap();
    for (k, name) in &kids {
        // A killed child is gone at once; an orphan would run on for seconds.
        wait_up_to(3, &format!("child {name} ({k}) stopped"), || gone(*k));
    }
    assert_eq!(temporaries(&tmpdir), Vec::<String>::new());
    // The cache entry keeps files only (no half-built library's directory).
    for e in std::fs::read_dir(&cache).unwrap().flatten() {
        for f in std::fs::read_dir(e.path()).unwrap().flatten() {
            assert!(!f.path().is_dir(), "left: {}", f.path().display());
        }
    }
    assert_eq!(st.code(), Some(143), "{st:?}");
}
