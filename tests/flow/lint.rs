//! Every emitted Verilog file passes `verilator --lint-only` with its default warnings and no
//! waiver (WIDTH, UNOPTFLAT and UNSIGNED included), and `-Wall` with the emitted
//! `<name>_lint.vlt`, whose waivers each state their reason: the core, the top and the
//! self-checking testbench of the shipped sinewave config, of its iterative-CORDIC variant
//! and of the capacitive config, and the kit preset's board wrapper with the clock
//! simulation model and the DCM_SP clock module; and the same files and the board wrapper
//! for every option combination the shipped tests use (velocity, ABZ, BiSS control, auto
//! correction, phase correction, and those together). (`<name>_inst.v` holds instantiation
//! templates, not a module; the other emitted files are not Verilog.)
use crate::common;
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
/// A clean run is recorded in the verdict cache (`sinedec::cosim::Verdict`, keyed by the
/// Verilator version, the arguments, the files' text without the commit in their header,
/// and this file's text), and a run
/// recorded clean is not repeated; a run with findings always runs.
fn verilator(
    dir: &std::path::Path,
    args: &[&str],
    files: &[&str],
    top: &str,
) -> (bool, Vec<String>) {
    let texts: Vec<String> = files
        .iter()
        .map(|f| std::fs::read_to_string(dir.join(f)).unwrap_or_else(|e| panic!("{f}: {e}")))
        .map(|t| common::without_commit(&t))
        .collect();
    let mut parts = vec![include_str!("lint.rs"), top];
    parts.extend_from_slice(args);
    parts.extend(files.iter().copied());
    parts.extend(texts.iter().map(String::as_str));
    let verdict = sinedec::cosim::Verdict::of("verilator --lint-only", &["verilator"], &parts)
        .unwrap_or_else(|e| panic!("verilator is needed for the lint test: {e}"));
    if verdict.passed() {
        return (true, Vec::new());
    }
    let r = run_verilator(dir, args, files, top);
    if r.0 && r.1.is_empty() {
        verdict.record_pass();
    }
    r
}

/// [`verilator`] without the cache.
fn run_verilator(
    dir: &std::path::Path,
    args: &[&str],
    files: &[&str],
    top: &str,
) -> (bool, Vec<String>) {
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

/// Asserts that Verilator ran and found nothing.
fn assert_clean((ok, findings): (bool, Vec<String>), what: &str) {
    assert!(
        ok && findings.is_empty(),
        "{what}:\n{}",
        findings.join("\n")
    );
}

fn lint_clean(text: &str, tag: &str, name: &str) {
    let (dir, files) = generated(text, tag);
    lint_generated(&dir, &files, tag, name);
}

/// [`lint_clean`] of files already generated into `dir`.
fn lint_generated(dir: &std::path::Path, files: &[String], tag: &str, name: &str) {
    let dir = dir.to_path_buf();
    let vlt = format!("{name}_lint.vlt");
    assert!(files.contains(&vlt), "{vlt} not generated: {files:?}");
    for m in ["core", "top"] {
        let top = format!("{name}_{m}");
        let file = format!("{top}.v");
        assert!(files.contains(&file), "{file} not generated");
        let r = verilator(&dir, &[], &[&file], &top);
        assert_clean(r, &format!("{tag} {file}, default warnings"));
        let r = verilator(&dir, &["-Wall"], &[&vlt, &file], &top);
        assert_clean(r, &format!("{tag} {file}, -Wall with {vlt}"));
    }
    // The testbench (delays: --timing) with the core it drives.
    let tb = format!("{name}_core_tb");
    let (core, tb_file) = (format!("{name}_core.v"), format!("{tb}.v"));
    assert!(files.contains(&tb_file), "{tb_file} not generated");
    let r = verilator(&dir, &["--timing"], &[&core, &tb_file], &tb);
    assert_clean(r, &format!("{tag} {tb_file}, default warnings"));
    let r = verilator(&dir, &["--timing", "-Wall"], &[&vlt, &core, &tb_file], &tb);
    assert_clean(r, &format!("{tag} {tb_file}, -Wall with {vlt}"));
    // The top's testbench with the top, when the config has a sinewave top.
    let tb = format!("{name}_top_tb");
    let (top, tb_file) = (format!("{name}_top.v"), format!("{tb}.v"));
    if files.contains(&tb_file) {
        let r = verilator(&dir, &["--timing"], &[&top, &tb_file], &tb);
        assert_clean(r, &format!("{tag} {tb_file}, default warnings"));
        let r = verilator(&dir, &["--timing", "-Wall"], &[&vlt, &top, &tb_file], &tb);
        assert_clean(r, &format!("{tag} {tb_file}, -Wall with {vlt}"));
    }
}

/// The check itself can fail: a width mismatch of the kind rust-hdl writes (a 32-bit
/// constant into a 2-bit variable) is reported, with the default warnings.
#[test]
fn a_width_mismatch_is_found() {
    let dir = std::env::temp_dir().join(format!("sinedec_lint_bad_{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(
        dir.join("bad.v"),
        "module bad(input wire clk, output reg [1:0] q);\n    always @(posedge clk) q <= 32'h2;\nendmodule\n",
    )
    .expect("write");
    let (ok, f) = verilator(&dir, &[], &["bad.v"], "bad");
    assert!(!ok, "verilator accepted a width mismatch");
    assert!(f.iter().any(|l| l.contains("WIDTH")), "{f:?}");
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
    let (dir, files) = generated(&t, "board");
    let board = ["sd_board.v", "sd_clock_sim.v", "sd_top.v"];
    let r = verilator(&dir, &["--timing"], &board, "sd_board");
    assert_clean(r, "sd_board, default warnings");
    let mut all = vec!["sd_lint.vlt"];
    all.extend(board);
    let r = verilator(&dir, &["--timing", "-Wall"], &all, "sd_board");
    assert_clean(r, "sd_board, -Wall with sd_lint.vlt");
    // The synthesis clock module, against black-box stubs of the Xilinx primitives with the
    // ports it connects (the vendor libraries are not on the machine): its own text is lint
    // clean, names and widths as declared in the stubs.
    assert!(files.iter().any(|f| f == "sd_clock.v"), "{files:?}");
    std::fs::write(dir.join("xilinx_stubs.v"), XILINX_STUBS).expect("write");
    let clock = ["sd_clock.v", "xilinx_stubs.v"];
    let r = verilator(&dir, &[], &clock, "sd_clock");
    assert_clean(r, "sd_clock, default warnings");
    let r = verilator(
        &dir,
        &["-Wall"],
        &["sd_lint.vlt", clock[0], clock[1]],
        "sd_clock",
    );
    assert_clean(r, "sd_clock, -Wall with sd_lint.vlt");
}

/// The option combinations the shipped tests use, as (tag, config text): the velocity
/// estimator, ABZ output, the BiSS control channel, auto correction, static phase
/// correction, the position reference with its absolute start, and all of velocity, ABZ,
/// control and auto together. Each on the Starter Kit preset, so that `<name>_board.v` (the
/// DCM wrapper) is written as well.
fn option_combinations() -> Vec<(&'static str, String)> {
    let set = |from: &str, to: &str, text: &str| {
        assert_eq!(
            text.matches(from).count(),
            1,
            "{from:?} moved in the default config"
        );
        text.replacen(from, to, 1)
    };
    let velocity = "\n[velocity]\nenabled = true\nrate_hz = 200e3\nbandwidth_hz = 20000.0\n";
    let abz = "\n[abz]\nenabled = true\n";
    let absolute = "\n[reference]\nenabled = true\nabsolute = \"ssi\"\n";
    let control = |t: &str| set("[biss]\n", "[biss]\ncontrol = true\n", t);
    let auto = |t: &str| set("\nmode = \"static\"\n", "\nmode = \"auto\"\n", t);
    let phase = |t: &str| {
        set(
            "\nmode = \"static\"\n",
            "\nmode = \"static\"\nphase_deg = 3.0\n",
            t,
        )
    };
    let d = DEFAULT_CONFIG;
    let combos = vec![
        ("velocity", format!("{d}{velocity}")),
        ("abz", format!("{d}{abz}")),
        ("control", control(d)),
        ("auto", auto(d)),
        ("phase", phase(d)),
        ("absolute", format!("{d}{absolute}")),
        ("all", format!("{}{velocity}{abz}", auto(&control(d)))),
    ];
    combos
        .into_iter()
        .map(|(tag, t)| {
            let abz_pins = if t.contains("\n[abz]\n") {
                "abz_a = \"J1\"\nabz_b = \"J2\"\nabz_z = \"J3\"\n"
            } else if t.contains("\n[reference]\n") {
                "preset = \"K1\"\nreferenced = \"K2\"\nabs_clk = \"K3\"\nabs_data = \"K4\"\n"
            } else {
                ""
            };
            (
                tag,
                format!(
                    "{t}\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\nqep_a = \"H1\"\nqep_b = \"H2\"\nqep_z = \"H3\"\nbiss_ma = \"H4\"\nbiss_slo = \"H5\"\n{abz_pins}"
                ),
            )
        })
        .collect()
}

/// Every emitted Verilog file of every option combination the shipped tests use is lint
/// clean at the default warnings and with `-Wall` plus the emitted `.vlt`: the core, the top,
/// the core's testbench, and the board wrapper with the clock model (which must carry every
/// port of `<name>_top`, signed and optional ones: a missing one is PINMISSING).
#[test]
fn every_option_combination_is_lint_clean_with_its_board_wrapper() {
    for (tag, text) in option_combinations() {
        let (dir, files) = generated(&text, tag);
        lint_generated(&dir, &files, tag, "sd");
        assert!(files.iter().any(|f| f == "sd_board.v"), "{tag}: {files:?}");
        let board = ["sd_board.v", "sd_clock_sim.v", "sd_top.v"];
        let r = verilator(&dir, &["--timing"], &board, "sd_board");
        assert_clean(r, &format!("{tag} sd_board, default warnings"));
        let mut all = vec!["sd_lint.vlt"];
        all.extend(board);
        let r = verilator(&dir, &["--timing", "-Wall"], &all, "sd_board");
        assert_clean(r, &format!("{tag} sd_board, -Wall with sd_lint.vlt"));
    }
}

/// The capacitive top's board wrapper on Cyclone III (a 25 MHz oscillator: an ALTPLL makes the
/// 50 MHz system clock), with the clock simulation model, and the ALTPLL clock module
/// against a stub of the megafunction.
#[test]
fn the_cyclone3_board_wrapper_is_lint_clean() {
    let t = common::cap_board(Some("25e6"), "A1");
    let (dir, files) = generated(&t, "cap_board");
    let board = ["cap_board.v", "cap_clock_sim.v", "cap_top.v"];
    let r = verilator(&dir, &["--timing"], &board, "cap_board");
    assert_clean(r, "cap_board, default warnings");
    let mut all = vec!["cap_lint.vlt"];
    all.extend(board);
    let r = verilator(&dir, &["--timing", "-Wall"], &all, "cap_board");
    assert_clean(r, "cap_board, -Wall with cap_lint.vlt");
    assert!(files.iter().any(|f| f == "cap_clock.v"), "{files:?}");
    std::fs::write(dir.join("altera_stubs.v"), ALTERA_STUBS).expect("write");
    let clock = ["cap_clock.v", "altera_stubs.v"];
    let r = verilator(&dir, &[], &clock, "cap_clock");
    assert_clean(r, "cap_clock, default warnings");
    let r = verilator(
        &dir,
        &["-Wall"],
        &["cap_lint.vlt", clock[0], clock[1]],
        "cap_clock",
    );
    assert_clean(r, "cap_clock, -Wall with cap_lint.vlt");
}

/// A black box of Altera's `altpll` megafunction with the ports `<name>_clock.v` connects
/// (`inclk[1:0]`, `clk[width_clock-1:0]`; Altera ALTPLL Megafunction User Guide).
const ALTERA_STUBS: &str = "/* verilator lint_off UNUSEDSIGNAL */
/* verilator lint_off UNUSEDPARAM */
/* verilator lint_off UNDRIVEN */
/* verilator lint_off DECLFILENAME */
module altpll #(
    parameter intended_device_family = \"Cyclone III\",
    parameter lpm_type = \"altpll\",
    parameter operation_mode = \"NORMAL\",
    parameter pll_type = \"AUTO\",
    parameter integer inclk0_input_frequency = 0,
    parameter integer clk0_multiply_by = 1,
    parameter integer clk0_divide_by = 1,
    parameter integer clk0_duty_cycle = 50,
    parameter clk0_phase_shift = \"0\",
    parameter compensate_clock = \"CLK0\",
    parameter port_inclk0 = \"PORT_USED\",
    parameter port_clk0 = \"PORT_USED\",
    parameter port_locked = \"PORT_USED\",
    parameter integer width_clock = 5
) (
    input wire [1:0] inclk, input wire areset,
    output wire [width_clock-1:0] clk, output wire locked
);
endmodule
";

/// Black boxes of the Spartan-3A primitives `<name>_clock.v` instantiates, with the ports and
/// parameters it uses (Xilinx UG613, Spartan-3 Libraries Guide for HDL Designs).
const XILINX_STUBS: &str = "/* verilator lint_off UNUSEDSIGNAL */
/* verilator lint_off UNUSEDPARAM */
/* verilator lint_off UNDRIVEN */
/* verilator lint_off DECLFILENAME */
module IBUFG(input wire I, output wire O);
    assign O = I;
endmodule
module BUFG(input wire I, output wire O);
    assign O = I;
endmodule
module DCM_SP #(
    parameter real CLKIN_PERIOD = 10.0,
    parameter integer CLKFX_MULTIPLY = 4,
    parameter integer CLKFX_DIVIDE = 1,
    parameter CLK_FEEDBACK = \"1X\",
    parameter STARTUP_WAIT = \"FALSE\"
) (
    input wire CLKIN, input wire CLKFB, input wire RST,
    input wire PSEN, input wire PSCLK, input wire PSINCDEC, input wire DSSEN,
    output wire CLKFX, output wire LOCKED
);
endmodule
";
