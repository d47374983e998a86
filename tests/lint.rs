//! Every emitted design passes `verilator --lint-only` with its default warnings and no
//! waiver (WIDTH, UNOPTFLAT and UNSIGNED included), and `-Wall` with the emitted
//! `<name>_lint.vlt`, whose waivers each state their reason: the shipped sinewave config,
//! its iterative-CORDIC variant, the capacitive config and the kit preset's board wrapper.
use sinedec::config::{Loaded, DEFAULT_CONFIG};

fn generated(text: &str, tag: &str) -> (std::path::PathBuf, Vec<String>) {
    let l = Loaded::parse(text, &format!("{tag}.toml")).expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let dir = std::env::temp_dir().join(format!("sinedec_lint_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    for f in &g.files {
        std::fs::write(dir.join(&f.name), &f.text).expect("write");
    }
    (dir, g.files.iter().map(|f| f.name.clone()).collect())
}

/// Runs Verilator on `files` with `top`; returns (exit ok, every %Warning/%Error line).
fn verilator(
    dir: &std::path::Path,
    args: &[&str],
    files: &[&str],
    top: &str,
) -> (bool, Vec<String>) {
    if let Err(e) = sinedec::cosim::require_tool("verilator") {
        panic!("verilator is needed for the lint test: {e}");
    }
    let out = std::process::Command::new("verilator")
        .arg("--lint-only")
        .args(args)
        .args(files)
        .args(["--top-module", top])
        .current_dir(dir)
        .output()
        .expect("verilator runs");
    let log = String::from_utf8_lossy(&out.stderr).to_string();
    let findings = log
        .lines()
        .filter(|l| l.starts_with("%Warning") || l.starts_with("%Error"))
        .map(String::from)
        .collect();
    (out.status.success(), findings)
}

fn lint_clean(text: &str, tag: &str, name: &str) {
    let (dir, files) = generated(text, tag);
    let vlt = format!("{name}_lint.vlt");
    assert!(files.contains(&vlt), "{vlt} not generated: {files:?}");
    for m in ["core", "top"] {
        let top = format!("{name}_{m}");
        let file = format!("{top}.v");
        assert!(files.contains(&file), "{file} not generated");
        let (ok, f) = verilator(&dir, &[], &[&file], &top);
        assert!(
            ok && f.is_empty(),
            "{tag} {file}, default warnings:\n{}",
            f.join("\n")
        );
        let (ok, f) = verilator(&dir, &["-Wall"], &[&vlt, &file], &top);
        assert!(
            ok && f.is_empty(),
            "{tag} {file}, -Wall with {vlt}:\n{}",
            f.join("\n")
        );
    }
}

#[test]
fn the_default_design_is_lint_clean() {
    lint_clean(DEFAULT_CONFIG, "default", "sd");
}

#[test]
fn the_iterative_design_is_lint_clean() {
    let t = DEFAULT_CONFIG.replace(
        "architecture = \"unrolled\"",
        "architecture = \"iterative\"",
    );
    assert_ne!(
        t, DEFAULT_CONFIG,
        "the default config's architecture line moved"
    );
    lint_clean(&t, "iterative", "sd");
}

#[test]
fn the_capacitive_design_is_lint_clean() {
    let t = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/configs/cyclone3_capacitive.toml"
    ))
    .expect("config");
    lint_clean(&t, "capacitive", "cap");
}

#[test]
fn the_board_wrapper_is_lint_clean_with_the_clock_model() {
    let t = format!(
        "{DEFAULT_CONFIG}\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\nqep_a = \"H1\"\nqep_b = \"H2\"\nqep_z = \"H3\"\nbiss_ma = \"H4\"\nbiss_slo = \"H5\"\n"
    );
    let (dir, _) = generated(&t, "board");
    let files = ["sd_board.v", "sd_clock_sim.v", "sd_top.v"];
    let (ok, f) = verilator(&dir, &["--timing"], &files, "sd_board");
    assert!(
        ok && f.is_empty(),
        "sd_board, default warnings:\n{}",
        f.join("\n")
    );
    let mut all = vec!["sd_lint.vlt"];
    all.extend(files);
    let (ok, f) = verilator(&dir, &["--timing", "-Wall"], &all, "sd_board");
    assert!(ok && f.is_empty(), "sd_board, -Wall:\n{}", f.join("\n"));
}
