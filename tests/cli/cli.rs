//! Command-line happy paths: `generate` (files, determinism, headers, module names, atomic
//! replacement), `check` (derived parameters) and `init` (writes an accepted config, refuses to
//! overwrite without `--force`).
use sinedec::config::DEFAULT_CONFIG;
use std::path::Path;
use std::process::{Command, Output};

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");
const VERSION: &str = env!("CARGO_PKG_VERSION");
const MANIFEST: &str = ".sinedec-manifest";

fn run(dir: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run sinedec")
}

/// Runs and asserts success; returns stdout.
fn ok(dir: &Path, args: &[&str]) -> String {
    let o = run(dir, args);
    assert!(
        o.status.success(),
        "sinedec {args:?} failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8(o.stdout).expect("utf-8 stdout")
}

fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Asserts the files `generate` must write for config name `name` are in `dir`, and that every
/// file there belongs to this generation (named `<name>_...`, besides the manifest of what
/// sinedec wrote). More files may be added over time (e.g. a testbench), so the listing is
/// not fixed.
fn assert_generated(dir: &Path, name: &str) -> Vec<String> {
    let mut files = listing(dir);
    assert!(
        files.contains(&MANIFEST.to_string()),
        "no manifest in {files:?}"
    );
    files.retain(|f| f != MANIFEST);
    for want in [format!("{name}_core.v"), format!("{name}_params.md")] {
        assert!(files.contains(&want), "{want} missing from {files:?}");
    }
    for f in &files {
        assert!(
            f.starts_with(&format!("{name}_")),
            "unexpected file {f:?} in {files:?}"
        );
        assert!(dir.join(f).is_file(), "{f} is not a file");
    }
    files
}

/// The file listing of a fresh `generate` with `args` (plus `-o ref`) in a new directory.
fn fresh_listing(config: Option<(&str, &str)>) -> Vec<String> {
    let tmp = tempfile::tempdir().unwrap();
    let mut args = vec!["generate"];
    if let Some((file, text)) = config {
        std::fs::write(tmp.path().join(file), text).unwrap();
        args.push(file);
    }
    args.extend(["-o", "ref"]);
    ok(tmp.path(), &args);
    listing(&tmp.path().join("ref"))
}

fn read(p: impl AsRef<Path>) -> String {
    std::fs::read_to_string(p.as_ref()).unwrap_or_else(|e| panic!("{}: {e}", p.as_ref().display()))
}

/// FNV-1a 64 of the bytes, written out here independently of the crate.
fn fnv1a64(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf29ce484222325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x100000001b3);
    }
    format!("{h:016x}")
}

/// Every `module NAME` declared in Verilog text, with the count of `endmodule`.
fn modules(v: &str) -> (Vec<String>, usize) {
    let mut names = Vec::new();
    let mut ends = 0;
    for line in v.lines() {
        let t = line.trim_start();
        if let Some(rest) = t.strip_prefix("module ") {
            let name: String = rest
                .trim_start()
                .chars()
                .take_while(|c| !c.is_whitespace() && *c != '(' && *c != ';' && *c != '#')
                .collect();
            names.push(name);
        }
        if t.starts_with("endmodule") {
            ends += 1;
        }
    }
    (names, ends)
}

fn assert_modules_prefixed(v: &str, name: &str) {
    let (mods, ends) = modules(v);
    assert!(
        mods.len() > 1,
        "expected the core and its submodules, got {mods:?}"
    );
    assert_eq!(mods.len(), ends, "module/endmodule count");
    let core = format!("{name}_core");
    assert_eq!(
        mods.iter().filter(|m| **m == core).count(),
        1,
        "{core} declared once"
    );
    let prefix = format!("{name}_");
    for m in &mods {
        assert!(
            m.starts_with(&prefix),
            "module {m:?} lacks prefix {prefix:?}"
        );
        assert!(
            m.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'),
            "module {m:?} has characters outside [A-Za-z0-9_]"
        );
    }
    let unique: std::collections::BTreeSet<_> = mods.iter().collect();
    assert_eq!(unique.len(), mods.len(), "duplicate module names");
}

/// Every module in every emitted `.v` file (core, testbench, ...) carries the prefix.
fn assert_all_verilog_prefixed(dir: &Path, name: &str) {
    let prefix = format!("{name}_");
    for f in listing(dir).iter().filter(|f| f.ends_with(".v")) {
        let (mods, ends) = modules(&read(dir.join(f)));
        assert_eq!(mods.len(), ends, "{f}: module/endmodule count");
        for m in mods {
            assert!(
                m.starts_with(&prefix) && m.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'),
                "{f}: module {m:?} lacks prefix {prefix:?} or has characters outside [A-Za-z0-9_]"
            );
        }
    }
}

/// A line of `check` output starting with `label`.
fn line_of<'a>(out: &'a str, label: &str) -> &'a str {
    out.lines()
        .find(|l| l.starts_with(label))
        .unwrap_or_else(|| panic!("no {label:?} line in:\n{out}"))
}

// ---------------------------------------------------------------------------------------
// generate

#[test]
fn generate_default_writes_core_and_params() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let out = ok(dir, &["generate", "-o", "out"]);
    for f in assert_generated(&dir.join("out"), "sd") {
        assert!(
            out.contains(&format!("wrote {}", Path::new("out").join(&f).display())),
            "{out}"
        );
    }
    // Nothing else beside the output directory (no temporary leftovers).
    assert_eq!(listing(dir), vec!["out"]);
    let v = read(dir.join("out/sd_core.v"));
    assert!(v.contains("module sd_core ("), "core module missing");
    let md = read(dir.join("out/sd_params.md"));
    assert!(md.contains("16 cycles"), "{md}");
}

#[test]
fn generate_into_nested_new_directory() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(dir, &["generate", "-o", "a/b/out"]);
    assert_generated(&dir.join("a/b/out"), "sd");
    assert_eq!(listing(&dir.join("a/b")), vec!["out"]);
}

#[test]
fn generate_is_deterministic() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("c.toml"),
        DEFAULT_CONFIG.replace("ppr = 2048", "ppr = 1000"),
    )
    .unwrap();
    for args in [
        &["generate", "-o", "out"][..],
        &["generate", "c.toml", "-o", "out"][..],
    ] {
        ok(dir, args);
        let first: Vec<(String, Vec<u8>)> = listing(&dir.join("out"))
            .into_iter()
            .map(|f| {
                let b = std::fs::read(dir.join("out").join(&f)).unwrap();
                (f, b)
            })
            .collect();
        assert!(first.len() >= 2);
        ok(dir, args);
        let second: Vec<(String, Vec<u8>)> = listing(&dir.join("out"))
            .into_iter()
            .map(|f| {
                let b = std::fs::read(dir.join("out").join(&f)).unwrap();
                (f, b)
            })
            .collect();
        assert!(
            first == second,
            "{args:?}: second run differs from the first"
        );
    }
}

#[test]
fn header_has_version_hash_and_command_line() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(dir, &["generate", "-o", "out"]);
    let default_hash = fnv1a64(DEFAULT_CONFIG.as_bytes());
    let v = read(dir.join("out/sd_core.v"));
    let head: Vec<&str> = v.lines().take(4).collect();
    assert!(
        head[0].starts_with("// ") && head[0].contains(&format!("sinedec {VERSION}")),
        "{head:?}"
    );
    // The commit the binary was built from, checked against git itself: the hash in
    // "(commit <hash>)" is a prefix of HEAD's full hash (the tests run in a git checkout).
    let full = std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("git (the tests run in a git checkout)");
    let full = String::from_utf8_lossy(&full.stdout).trim().to_string();
    let named = head[0]
        .split("(commit ")
        .nth(1)
        .and_then(|r| r.split(')').next())
        .unwrap_or("");
    assert!(
        named.len() >= 7 && full.starts_with(named),
        "header commit {named:?} is not HEAD {full:?}: {head:?}"
    );
    assert!(
        head.iter()
            .any(|l| l.starts_with("//") && l.contains(&default_hash)),
        "hash {default_hash} not in {head:?}"
    );
    assert!(
        head.contains(&"// Command: sinedec generate -o out"),
        "{head:?}"
    );
    let md = read(dir.join("out/sd_params.md"));
    assert!(
        md.contains(&format!("sinedec {VERSION}")) && md.contains(&default_hash),
        "{md}"
    );
    assert!(md.contains("Command: sinedec generate -o out"), "{md}");
    // Every emitted file carries the same header in its first lines.
    for f in listing(&dir.join("out"))
        .into_iter()
        .filter(|f| f != MANIFEST)
    {
        let text = read(dir.join("out").join(&f));
        let head: Vec<&str> = text.lines().take(5).collect();
        let has = |s: &str| head.iter().any(|l| l.contains(s));
        // JSON has no comments: the same facts are its first keys.
        let command = if f.ends_with(".json") {
            "\"command\": \"sinedec generate -o out\""
        } else {
            "Command: sinedec generate -o out"
        };
        assert!(
            has(&format!("sinedec {VERSION}")) && has(&default_hash) && has(command),
            "{f}: header {head:?}"
        );
    }

    // A config file: its own hash, and the command line as typed.
    let text = DEFAULT_CONFIG.replace("multiturn_bits = 12", "multiturn_bits = 8");
    std::fs::write(dir.join("mt8.toml"), &text).unwrap();
    ok(dir, &["generate", "mt8.toml", "-o", "out8"]);
    let hash = fnv1a64(text.as_bytes());
    assert_ne!(hash, default_hash);
    let v = read(dir.join("out8/sd_core.v"));
    let head: Vec<&str> = v.lines().take(4).collect();
    assert!(
        head.iter()
            .any(|l| l.contains(&hash) && l.contains("mt8.toml")),
        "{head:?}"
    );
    assert!(
        head.contains(&"// Command: sinedec generate mt8.toml -o out8"),
        "{head:?}"
    );
}

#[test]
fn module_names_default_prefix() {
    let tmp = tempfile::tempdir().unwrap();
    ok(tmp.path(), &["generate", "-o", "out"]);
    assert_modules_prefixed(&read(tmp.path().join("out/sd_core.v")), "sd");
    assert_all_verilog_prefixed(&tmp.path().join("out"), "sd");
}

#[test]
fn module_names_follow_config_name() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("enc2.toml"),
        DEFAULT_CONFIG.replace("name = \"sd\"", "name = \"enc2\""),
    )
    .unwrap();
    ok(dir, &["generate", "enc2.toml", "-o", "out"]);
    assert_generated(&dir.join("out"), "enc2");
    let v = read(dir.join("out/enc2_core.v"));
    assert_modules_prefixed(&v, "enc2");
    assert_all_verilog_prefixed(&dir.join("out"), "enc2");
    assert!(
        !v.contains("sd_core"),
        "default name leaked into enc2 output"
    );
}

/// Regenerating into a directory sinedec wrote replaces its files and removes the ones it no
/// longer produces; files it did not write stay (the rule: docs/cli.md "Output directory"; a
/// directory sinedec did not write is refused, see tests/cli/output_safety.rs). Until issue 13
/// this test asked for the whole directory to be replaced, which deleted the user's files.
#[test]
fn generate_replaces_its_previous_generation() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let out = dir.join("out");
    ok(dir, &["generate", "-o", "out"]);
    std::fs::write(out.join("sd_core.v"), "// old core\n").unwrap();
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    ok(dir, &["generate", "-o", "out"]);
    let mut want = fresh_listing(None);
    want.push("notes.txt".into());
    want.sort();
    assert_eq!(
        listing(&out),
        want,
        "old files survived or new ones are missing"
    );
    assert_eq!(read(out.join("notes.txt")), "mine");
    let v = read(out.join("sd_core.v"));
    assert!(
        v.starts_with(&format!("// Generated by sinedec {VERSION}")),
        "core not rewritten"
    );
    assert!(v.contains("module sd_core ("));
    // No temporary or backup files left beside it or in it.
    assert_eq!(listing(dir), vec!["out"]);

    // Regenerating with another name replaces the previous generation completely.
    let enc2 = DEFAULT_CONFIG.replace("name = \"sd\"", "name = \"enc2\"");
    std::fs::write(dir.join("enc2.toml"), &enc2).unwrap();
    ok(dir, &["generate", "enc2.toml", "-o", "out"]);
    let mut want = fresh_listing(Some(("enc2.toml", &enc2)));
    want.push("notes.txt".into());
    want.sort();
    assert_eq!(listing(&out), want);
    assert_eq!(listing(dir), vec!["enc2.toml", "out"]);
}

// ---------------------------------------------------------------------------------------
// check

#[test]
fn check_default_prints_derived_parameters() {
    let tmp = tempfile::tempdir().unwrap();
    let out = ok(tmp.path(), &["check"]);
    assert!(out.lines().next().unwrap().ends_with(": ok"), "{out}");
    // Default: N = 14, latency = N + 2.
    assert!(
        line_of(&out, "cordic iterations N")
            .split_whitespace()
            .last()
            == Some("14"),
        "{out}"
    );
    let lat = line_of(&out, "core latency");
    assert!(lat.contains(" 16 cycles"), "{lat}");
    // 16 cycles at 133.33 MHz.
    assert!(
        lat.contains(&format!("{:.1} ns", 16.0 * 1e9 / 133.33e6)),
        "{lat}"
    );
    // Highest speed with steps below 1.75 quadrants (minus one fine LSB) per sample:
    // 2048 PPR = 8192 quadrants per turn, F = 14, and the LTC1407A-1's fastest rate at
    // 133.33 MHz: a 34-SCK frame of 3-clock SCK periods = 102 clocks per sample.
    let q_per_sample = 1.75 - 1.0 / 16384.0;
    let rpm = q_per_sample * (133.33e6 / 102.0) / 8192.0 * 60.0;
    let speed = line_of(&out, "max speed");
    assert!(
        speed.contains(&format!("{rpm:.0} rpm")),
        "{speed} (want {rpm:.0} rpm)"
    );
}

/// Runs `sinedec check c.toml` in `dir` with the Yosys caches `synth` (SINEDEC_SYNTH_CACHE)
/// and `xdg`/sinedec/yosys (report's default) and no Yosys on PATH: `check` must not need
/// it. Returns its resource line.
fn check_resource_line(dir: &Path, synth: &Path, xdg: &Path) -> String {
    let o = Command::new(BIN)
        .args(["check", "c.toml"])
        .current_dir(dir)
        .env("SINEDEC_SYNTH_CACHE", synth)
        .env("XDG_CACHE_HOME", xdg)
        .env("PATH", dir.join("no-tools"))
        .output()
        .expect("run sinedec");
    let out = String::from_utf8_lossy(&o.stdout).into_owned();
    assert!(
        o.status.success(),
        "{out}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    line_of(&out, "resources (top)").to_string()
}

#[test]
fn check_prints_the_tops_resources_from_the_report_cache_or_how_to_get_them() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(dir.join("c.toml"), DEFAULT_CONFIG).unwrap();
    let (empty, cache, xdg) = (dir.join("empty"), dir.join("cache"), dir.join("xdg"));
    for d in [&empty, &cache, &xdg] {
        std::fs::create_dir_all(d).unwrap();
    }
    // Nothing cached: one line that says how to get the figures.
    let line = check_resource_line(dir, &empty, &xdg);
    assert!(
        line.contains("not synthesized") && line.contains("`sinedec report c.toml`"),
        "{line}"
    );
    // The top synthesized as `sinedec report` does (its Yosys runner, seeded from the
    // suite's Yosys cache so that a known design does not run again): `check` prints the
    // same figures.
    if let Some(seed) = std::env::var_os("SINEDEC_SYNTH_CACHE").filter(|v| !v.is_empty()) {
        for e in std::fs::read_dir(seed).into_iter().flatten().flatten() {
            let _ = std::fs::copy(e.path(), cache.join(e.file_name()));
        }
    }
    let l = sinedec::config::Loaded::parse(DEFAULT_CONFIG, "c.toml").unwrap();
    let top = sinedec::emit::top_verilog(&l).unwrap().expect("a top");
    let ys = sinedec::report::yosys::Yosys::new(Some(cache.clone()), dir.join("work"))
        .expect("yosys (apt-get install -y yosys)");
    let (s, _) = ys
        .family_indexed(&top, "sd_top", sinedec::synth::Family::Xc3sa, "top")
        .expect("synthesis");
    // Keep a new run in the suite's cache, as `sinedec::synth::synthesize` does.
    if let Some(seed) = std::env::var_os("SINEDEC_SYNTH_CACHE").filter(|v| !v.is_empty()) {
        let seed = std::path::PathBuf::from(seed);
        for e in std::fs::read_dir(&cache).unwrap().flatten() {
            if !seed.join(e.file_name()).exists() {
                let _ = std::fs::copy(e.path(), seed.join(e.file_name()));
            }
        }
    }
    let line = check_resource_line(dir, &cache, &xdg);
    let want = format!(
        "xc3sa: {} LUTs, {} FFs, {} block RAMs, {} multipliers",
        s.luts, s.ffs, s.brams, s.multipliers
    );
    assert!(
        line.contains(&want) && line.contains(ys.version()),
        "{line}\nwant {want}"
    );
    assert!(s.luts > 0 && s.ffs > 0, "{s:?}");
    // Report's default cache directory is read as well.
    let home = xdg.join("sinedec/yosys");
    std::fs::create_dir_all(&home).unwrap();
    for e in std::fs::read_dir(&cache).unwrap().flatten() {
        std::fs::copy(e.path(), home.join(e.file_name())).unwrap();
    }
    assert!(check_resource_line(dir, &empty, &xdg).contains(&want));
    // Another design (one more CORDIC iteration) is not answered by the cached figures.
    std::fs::write(
        dir.join("c.toml"),
        DEFAULT_CONFIG.replace("iterations = 14", "iterations = 15"),
    )
    .unwrap();
    assert!(check_resource_line(dir, &cache, &xdg).contains("not synthesized"));
}

#[test]
fn check_latency_follows_iterations() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    std::fs::write(
        dir.join("n10.toml"),
        DEFAULT_CONFIG.replace("iterations = 14", "iterations = 10"),
    )
    .unwrap();
    let out = ok(dir, &["check", "n10.toml"]);
    assert!(out.starts_with("n10.toml: ok"), "{out}");
    assert!(
        line_of(&out, "core latency").contains(" 12 cycles"),
        "{out}"
    );
}

// ---------------------------------------------------------------------------------------
// init

#[test]
fn init_writes_a_config_that_check_accepts() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    ok(dir, &["init", "my.toml"]);
    assert_eq!(listing(dir), vec!["my.toml"], "temporary file left behind");
    let out = ok(dir, &["check", "my.toml"]);
    assert!(out.starts_with("my.toml: ok"), "{out}");
    // Same derived parameters as the embedded default; only the resources hint names
    // the file the user passes to `report`.
    let default = ok(dir, &["check"]);
    let body = |s: &str| {
        s.lines()
            .skip(1)
            .filter(|l| !l.starts_with("resources (top)"))
            .collect::<Vec<_>>()
            .join("\n")
    };
    assert_eq!(body(&out), body(&default));
    // Before `report` has cached the top's synthesis, the hint names the file given.
    let (mine, theirs) = (
        line_of(&out, "resources (top)"),
        line_of(&default, "resources (top)"),
    );
    if mine.contains("not synthesized") {
        assert!(mine.contains("`sinedec report my.toml`"), "{out}");
        assert!(theirs.contains("`sinedec report` synthesizes"), "{default}");
    } else {
        assert_eq!(mine, theirs);
    }
    // And it generates.
    ok(dir, &["generate", "my.toml", "-o", "out"]);
    assert_generated(&dir.join("out"), "sd");
}

#[test]
fn init_default_path_is_sinedec_toml() {
    let tmp = tempfile::tempdir().unwrap();
    ok(tmp.path(), &["init"]);
    assert_eq!(listing(tmp.path()), vec!["sinedec.toml"]);
    ok(tmp.path(), &["check", "sinedec.toml"]);
}

#[test]
fn init_refuses_to_overwrite_without_force() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let p = dir.join("my.toml");
    std::fs::write(&p, "# mine\n").unwrap();
    let o = run(dir, &["init", "my.toml"]);
    assert!(!o.status.success(), "init overwrote without --force");
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(e.contains("my.toml") && e.contains("--force"), "{e}");
    assert_eq!(read(&p), "# mine\n", "file changed");
    assert_eq!(listing(dir), vec!["my.toml"]);

    ok(dir, &["init", "my.toml", "--force"]);
    assert_eq!(read(&p), DEFAULT_CONFIG);
    assert_eq!(listing(dir), vec!["my.toml"]);
    ok(dir, &["check", "my.toml"]);
}

/// L3: negative option values in scientific notation are numbers, not flags.
#[test]
fn negative_values_in_scientific_notation_are_accepted() {
    let tmp = tempfile::tempdir().unwrap();
    let out = ok(
        tmp.path(),
        &[
            "simulate",
            "--duration",
            "0.0005",
            "--offset-sin",
            "-1e-1",
            "--offset-cos",
            "-2E-2",
            "--phase-error",
            "-1.5e0",
        ],
    );
    assert!(out.contains("max |error|"), "{out}");
}

/// L4: a profile faster than the decoder follows (its unwrap limit, `check`'s max speed)
/// is run with a warning on stderr; a speed within it gets none.
#[test]
fn a_profile_beyond_the_followable_speed_is_warned_about() {
    let tmp = tempfile::tempdir().unwrap();
    let fast = run(
        tmp.path(),
        &[
            "simulate",
            "--duration",
            "0.0005",
            "--profile",
            "constant:600000",
        ],
    );
    let e = String::from_utf8_lossy(&fast.stderr);
    assert!(fast.status.success(), "{e}");
    assert!(e.contains("warning") && e.contains("600000 rpm"), "{e}");
    let slow = run(
        tmp.path(),
        &[
            "simulate",
            "--duration",
            "0.0005",
            "--profile",
            "constant:300",
        ],
    );
    assert!(!String::from_utf8_lossy(&slow.stderr).contains("warning"));
}

/// L11: a config that is not a regular file, or larger than 1 MB, is refused unread.
#[test]
fn a_config_that_is_huge_or_not_a_file_is_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let mut big = DEFAULT_CONFIG.to_string();
    while big.len() <= 1 << 20 {
        big.push_str("# padding padding padding padding padding padding padding padding\n");
    }
    std::fs::write(dir.join("big.toml"), &big).unwrap();
    let _sock = std::os::unix::net::UnixListener::bind(dir.join("sock.toml")).unwrap();
    for (name, says) in [("big.toml", "1 MB"), ("sock.toml", "not a regular file")] {
        let o = run(dir, &["check", name]);
        let e = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {e}");
        assert!(e.contains(name) && e.contains(says), "{name}: {e}");
    }
}

/// Whitespace collapsed to single spaces: clap joins a doc comment's lines and wraps nothing,
/// the Markdown source breaks where it likes.
fn words(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// docs/cli.md's command table names every command with its one-line summary, and each
/// command's section there is what `sinedec <command> --help` prints: the reference has one
/// text in two places, and this keeps them equal.
#[test]
fn long_help_carries_the_command_reference() {
    let doc = include_str!("../../docs/cli.md");
    let dir = tempfile::tempdir().expect("tempdir");
    for cmd in [
        "generate",
        "check",
        "simulate",
        "report",
        "datasheet",
        "init",
    ] {
        let help = words(&ok(dir.path(), &[cmd, "--help"]));
        let row = doc
            .lines()
            .find(|l| l.starts_with(&format!("| `sinedec {cmd}")))
            .unwrap_or_else(|| panic!("docs/cli.md has no table row for `{cmd}`"));
        let summary = row
            .trim_end_matches(" |")
            .rsplit(" | ")
            .next()
            .unwrap_or("");
        assert!(
            help.starts_with(&words(summary)),
            "`{cmd} --help` does not open with the table's summary {summary:?}:\n{help}"
        );
        let head = format!("### `sinedec {cmd}`\n");
        let start = doc
            .find(&head)
            .unwrap_or_else(|| panic!("docs/cli.md has no section {head:?}"))
            + head.len();
        let body = &doc[start..];
        let body = &body[..body.find("\n#").unwrap_or(body.len())];
        let paras: Vec<&str> = body
            .split("\n\n")
            .filter(|p| !p.trim().is_empty())
            .collect();
        assert!(!paras.is_empty(), "docs/cli.md's `{cmd}` section is empty");
        for p in paras {
            let p = words(p);
            assert!(
                help.contains(&p),
                "`{cmd} --help` lacks docs/cli.md's paragraph:\n{p}\n\n--help:\n{help}"
            );
        }
    }
}
