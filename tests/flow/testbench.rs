//! The emitted self-checking testbench passes in Icarus (as Verilog-2005 and as
//! SystemVerilog-2012) and in Verilator against the emitted core; when the core is changed it
//! reports FAIL and the simulator process exits non-zero in both simulators. It uses no
//! SystemVerilog keyword as an identifier. The commands are the ones docs/verification.md documents.
use crate::common;
use std::path::Path;
use std::process::{Command, Output};

/// Exit status and stdout of one simulator run.
struct Run {
    ok: bool,
    code: Option<i32>,
    stdout: String,
}

fn tool(cmd: &mut Command, what: &str) -> Output {
    cmd.output()
        .unwrap_or_else(|e| panic!("{what} does not start: {e}"))
}

/// `iverilog -g<generation> -o tb.vvp core.v tb.v && vvp -n tb.vvp`.
fn icarus(core: &str, tb: &str, dir: &Path, generation: &str) -> Run {
    sinedec::cosim::require_tool("iverilog").expect("iverilog installed");
    std::fs::write(dir.join("core.v"), core).expect("write");
    std::fs::write(dir.join("tb.v"), tb).expect("write");
    let c = tool(
        Command::new("iverilog")
            .arg(format!("-g{generation}"))
            .arg("-o")
            .arg(dir.join("tb.vvp"))
            .arg(dir.join("core.v"))
            .arg(dir.join("tb.v")),
        "iverilog",
    );
    assert!(
        c.status.success(),
        "iverilog -g{generation}: {}",
        String::from_utf8_lossy(&c.stderr)
    );
    let r = tool(Command::new("vvp").arg("-n").arg(dir.join("tb.vvp")), "vvp");
    Run {
        ok: r.status.success(),
        code: r.status.code(),
        stdout: String::from_utf8_lossy(&r.stdout).to_string(),
    }
}

/// `verilator --binary --timing --top-module sd_core_tb core.v tb.v &&
/// obj_dir/Vsd_core_tb`; no warning may concern the testbench itself.
fn verilator(core: &str, tb: &str, dir: &Path) -> Run {
    verilator_top(core, tb, dir, "sd_core_tb")
}

/// [`verilator`] with the testbench module `top`.
fn verilator_top(core: &str, tb: &str, dir: &Path, top: &str) -> Run {
    sinedec::cosim::require_tool("verilator").expect("verilator installed");
    let _ = std::fs::remove_dir_all(dir.join("obj_dir"));
    std::fs::write(dir.join("core.v"), core).expect("write");
    std::fs::write(dir.join("tb.v"), tb).expect("write");
    let c = tool(
        Command::new("verilator")
            .args(["--binary", "--timing", "-j", "1"])
            .args(["--top-module", top])
            .arg("core.v")
            .arg("tb.v")
            .current_dir(dir),
        "verilator",
    );
    assert!(
        c.status.success(),
        "verilator: {}",
        String::from_utf8_lossy(&c.stderr)
    );
    let log = String::from_utf8_lossy(&c.stderr);
    assert!(
        !log.lines()
            .any(|l| l.starts_with('%') && l.contains("tb.v:")),
        "warnings about the testbench:\n{log}"
    );
    let bin = format!("V{top}");
    let r = tool(&mut Command::new(dir.join("obj_dir").join(&bin)), &bin);
    Run {
        ok: r.status.success(),
        code: r.status.code(),
        stdout: String::from_utf8_lossy(&r.stdout).to_string(),
    }
}

/// Runs `check` unless it passed before for these files (the commit in their header aside),
/// these simulators' versions and this file's text (`sinedec::cosim::passed_once`, the verdict cache that scripts/test.sh
/// points at tests/data/cosim-cache): a change to any of them runs the simulators again.
fn once(name: &str, tools: &[&str], files: &[&str], check: impl FnOnce()) {
    let files: Vec<String> = files.iter().map(|f| common::without_commit(f)).collect();
    let mut parts = vec![include_str!("testbench.rs")];
    parts.extend(files.iter().map(String::as_str));
    sinedec::cosim::passed_once(name, tools, &parts, check).expect("simulators installed");
}

/// The core and testbench of a small config, and the core broken (fine LSB dropped).
fn files() -> (String, String, String) {
    let l = common::cfg(6, 12, 14, 5, 3);
    let g = sinedec::emit::generate(&l, "test").expect("generate");
    let get = |n: &str| {
        g.files
            .iter()
            .find(|f| f.name == n)
            .unwrap_or_else(|| panic!("{n} missing"))
            .text
            .clone()
    };
    let core = get("sd_core.v");
    let tb = get("sd_core_tb.v");
    let broken = core.replacen(
        "assign out_fine = fine[11:0];",
        "assign out_fine = fine[11:0] & 12'hffe;",
        1,
    );
    assert_ne!(broken, core);
    (core, tb, broken)
}

#[test]
fn emitted_testbench_passes_and_catches_a_change() {
    let (core, tb, broken) = files();
    once(
        "testbench icarus",
        &["iverilog"],
        &[&core, &tb, &broken],
        || {
            let dir = common::workdir("testbench");
            for generation in ["2005", "2012"] {
                let r = icarus(&core, &tb, &dir, generation);
                assert!(
                    r.stdout.contains("PASS") && r.ok,
                    "-g{generation}: {}",
                    r.stdout
                );
                let r = icarus(&broken, &tb, &dir, generation);
                assert!(r.stdout.contains("FAIL"), "-g{generation}: {}", r.stdout);
                assert!(
                    !r.ok,
                    "-g{generation}: vvp exited {:?} after a mismatch",
                    r.code
                );
            }
        },
    );
}

#[test]
fn emitted_testbench_runs_in_verilator_and_fails_on_a_change() {
    let (core, tb, broken) = files();
    once(
        "testbench verilator",
        &["verilator"],
        &[&core, &tb, &broken],
        || {
            let dir = common::workdir("testbench_verilator");
            let r = verilator(&core, &tb, &dir);
            assert!(
                r.stdout.contains("PASS") && r.ok,
                "{:?} {}",
                r.code,
                r.stdout
            );
            let r = verilator(&broken, &tb, &dir);
            assert!(r.stdout.contains("FAIL"), "{}", r.stdout);
            assert!(!r.ok, "the simulation exited {:?} after a mismatch", r.code);
        },
    );
}

/// A velocity configuration (tracking estimator at 20 kHz, 6667 clocks per update): its
/// core and testbench, and the testbench with the lowest velocity bit of one expected
/// update flipped.
fn velocity_files() -> (String, String, String) {
    let text = format!(
        "{}\n[velocity]\nenabled = true\nrate_hz = 20e3\nbandwidth_hz = 2000.0\n",
        sinedec::config::DEFAULT_CONFIG
    );
    let l = sinedec::config::Loaded::parse(&text, "v.toml").expect("config");
    let g = sinedec::emit::generate(&l, "test").expect("generate");
    let get = |n: &str| {
        g.files
            .iter()
            .find(|f| f.name == n)
            .unwrap_or_else(|| panic!("{n} missing"))
            .text
            .clone()
    };
    let (core, tb) = (get("sd_core.v"), get("sd_core_tb.v"));
    // An expected value whose last two fields are a non-zero velocity and its strobe:
    // flip the velocity's lowest bit.
    let line = tb
        .lines()
        .find(|l| {
            l.contains("expected[") && l.trim_end().ends_with("_1;") && {
                let f: Vec<&str> = l.rsplit('_').collect();
                f[1].contains('1')
            }
        })
        .expect("an expected velocity update");
    let cut = line.len() - "_1;".len() - 1;
    let flipped_bit = if &line[cut..cut + 1] == "0" { "1" } else { "0" };
    let flipped = format!("{}{flipped_bit}{}", &line[..cut], &line[cut + 1..]);
    let broken = tb.replacen(line, &flipped, 1);
    assert_ne!(broken, tb);
    (core, tb, broken)
}

/// With `[velocity] enabled` the testbench connects `out_velocity` / `out_velocity_valid`,
/// checks them over several updates of both signs, passes in Icarus and Verilator, and
/// fails in both when one velocity bit of the expected data is wrong.
#[test]
fn velocity_testbench_checks_the_velocity_in_icarus_and_verilator() {
    let (core, tb, broken) = velocity_files();
    for port in ["out_velocity", "out_velocity_valid"] {
        assert!(
            tb.contains(&format!(".{port}({port})")),
            "{port} not connected"
        );
    }
    once(
        "velocity testbench",
        &["iverilog", "verilator"],
        &[&core, &tb, &broken],
        || {
            let dir = common::workdir("testbench_velocity");
            let r = icarus(&core, &tb, &dir, "2005");
            assert!(r.stdout.contains("PASS") && r.ok, "{}", r.stdout);
            let r = icarus(&core, &broken, &dir, "2005");
            assert!(r.stdout.contains("FAIL") && !r.ok, "{}", r.stdout);
            let dir = common::workdir("testbench_velocity_verilator");
            let r = verilator(&core, &tb, &dir);
            assert!(
                r.stdout.contains("PASS") && r.ok,
                "{:?} {}",
                r.code,
                r.stdout
            );
            let r = verilator(&core, &broken, &dir);
            assert!(
                r.stdout.contains("FAIL") && !r.ok,
                "{:?} {}",
                r.code,
                r.stdout
            );
        },
    );
}

/// The velocity testbench's expected data hold several updates at the default update rate
/// (7.5 kHz: 17777 clocks per update), not just the warm-up: the stimulus runs
/// `VELOCITY_TB_UPDATES` update periods each way, and the estimate rises, then falls.
#[test]
fn velocity_testbench_spans_several_updates_at_the_default_rate() {
    use sinedec::emit::testbench::{
        testbench_expected, testbench_output_ports, testbench_stimulus, VELOCITY_TB_UPDATES,
    };
    let text = format!(
        "{}\n[velocity]\nenabled = true\n",
        sinedec::config::DEFAULT_CONFIG
    );
    let l = sinedec::config::Loaded::parse(&text, "v.toml").expect("config");
    let w = l.derived.velocity.as_ref().expect("enabled").spec.width;
    let stim = testbench_stimulus(&l);
    let rows = testbench_expected(&l, &stim);
    let n = testbench_output_ports(&l).len();
    let updates: Vec<i64> = rows
        .iter()
        .filter(|r| r[n - 1] == 1)
        .map(|r| ((r[n - 2] << (64 - w)) as i64) >> (64 - w))
        .collect();
    assert!(
        updates.len() as u64 >= 2 * VELOCITY_TB_UPDATES - 1,
        "{} updates",
        updates.len()
    );
    // Not just the warm-up's zeros: the estimate rises through the forward rotation and
    // falls after the reversal.
    let peak = (0..updates.len())
        .max_by_key(|&i| updates[i])
        .expect("updates");
    assert!(
        updates[peak] > 0 && peak > 1 && peak + 1 < updates.len(),
        "{updates:?}"
    );
    assert!(
        updates[peak + 1..].windows(2).all(|w| w[1] < w[0]),
        "{updates:?}"
    );
}

/// The configs whose `sd_top_tb.v` runs: the default (LTC1407A-1 behind the LTC6912-1),
/// the default with `[abz] enabled`, and a `generic` SPI ADC without the pre-amplifier
/// (as `tests/cli/config_errors_util` makes one: `GENERIC`, `NO_PREAMP`).
fn top_configs() -> Vec<(&'static str, String)> {
    let d = sinedec::config::DEFAULT_CONFIG;
    let preamp = "[preamp]\n# LTC6912-1 gains (inverting): -1, -2, -5, -10, -20, -50 or -100. A feeds sin, B cos.\ngain_a = -1\ngain_b = -1\n";
    assert!(d.contains(preamp) && d.contains("preset = \"ltc1407a-1\""));
    let generic = d
        .replace(
            "preset = \"ltc1407a-1\"",
            "preset = \"generic\"\nmax_sample_rate_hz = 2e6",
        )
        .replace(preamp, "");
    let shipped = |file: &str| {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("configs")
            .join(file);
        std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{file}: {e}"))
    };
    vec![
        ("default", d.to_string()),
        ("abz", format!("{d}\n[abz]\nenabled = true\n")),
        ("generic", generic),
        ("ads8354", shipped("ads8354_100mhz.toml")),
        ("ad7380", shipped("ad7380_100mhz.toml")),
    ]
}

/// `<name>_top.v` and `<name>_top_tb.v` of a config.
fn top_files(text: &str) -> (String, String) {
    let l = sinedec::config::Loaded::parse(text, "t.toml").expect("config");
    let name = l.config.name.clone();
    let g = sinedec::emit::generate(&l, "test").expect("generate");
    let get = |n: &str| {
        g.files
            .iter()
            .find(|f| f.name == n)
            .unwrap_or_else(|| panic!("{n} missing"))
            .text
            .clone()
    };
    (
        get(&format!("{name}_top.v")),
        get(&format!("{name}_top_tb.v")),
    )
}

/// The PASS line of a run, asserted with exit status 0.
fn passed(r: &Run, what: &str) {
    assert!(
        r.ok && r.code == Some(0) && r.stdout.contains("PASS:") && !r.stdout.contains("FAIL"),
        "{what}: exit {:?}\n{}",
        r.code,
        r.stdout
    );
}

/// `sd_top_tb.v` passes against `sd_top.v` in Icarus and Verilator, exit status 0, for the
/// default config, with ABZ, and for a generic SPI ADC; its PASS line gives the figures.
#[test]
fn top_testbench_passes_in_icarus_and_verilator() {
    for (what, text) in top_configs() {
        let (top, tb) = top_files(&text);
        let module = tb
            .lines()
            .find_map(|l| l.strip_prefix("module ")?.strip_suffix(';'))
            .unwrap_or_else(|| panic!("{what}: no testbench module"))
            .to_string();
        assert!(module.ends_with("_top_tb"), "{what}: {module}");
        if what == "abz" {
            assert!(tb.contains(".abz_a(abz_a)"), "abz_a not connected");
        }
        if what == "generic" {
            assert!(!tb.contains("amp_cs") && tb.contains("generic SPI ADC"));
        }
        once(
            &format!("top testbench {what}"),
            &["iverilog", "verilator"],
            &[&top, &tb],
            || {
                let dir = common::workdir(&format!("top_tb_{what}"));
                passed(&icarus(&top, &tb, &dir, "2005"), what);
                passed(&verilator_top(&top, &tb, &dir, &module), what);
            },
        );
    }
}

/// One-bit changes of the default `sd_top.v`: the BiSS slave's CRC taps 0x03 -> 0x01 (one
/// bit of the polynomial), and the parallel bus's position LSB inverted.
fn top_mutants(top: &str) -> Vec<(&'static str, String)> {
    let mutate = |from: &str, to: &str| {
        assert_eq!(top.matches(from).count(), 1, "{from}");
        top.replacen(from, to, 1)
    };
    vec![
        (
            "crc",
            mutate("localparam  taps = 32'h3;", "localparam  taps = 32'h1;"),
        ),
        (
            "position",
            mutate(
                "assign par_position = {qc[12:0], fine[13:0]};",
                "assign par_position = {qc[12:0], fine[13:0]} ^ 27'd1;",
            ),
        ),
    ]
}

/// The failing run of a mutant: no PASS, `what_failed` reported, a non-zero exit.
fn failed(r: &Run, what: &str, what_failed: &str) {
    assert!(
        !r.ok && !r.stdout.contains("PASS") && r.stdout.contains(what_failed),
        "{what}: exit {:?}\n{}",
        r.code,
        r.stdout
    );
}

/// The top testbench fails, exits non-zero and says why in Icarus and Verilator when one
/// bit of the design changes: the BiSS CRC (a CRC6 mismatch) or par_position's LSB (the
/// BiSS-C word differs from the parallel bus).
#[test]
fn top_testbench_fails_on_a_one_bit_change() {
    let (top, tb) = top_files(sinedec::config::DEFAULT_CONFIG);
    let mutants = top_mutants(&top);
    let texts: Vec<&str> = [tb.as_str()]
        .into_iter()
        .chain(mutants.iter().map(|m| m.1.as_str()))
        .collect();
    once(
        "top testbench mutants",
        &["iverilog", "verilator"],
        &texts,
        || {
            for (what, broken) in &mutants {
                let expect = match *what {
                    "crc" => "CRC6 mismatch",
                    _ => "word differs from the parallel bus",
                };
                let dir = common::workdir(&format!("top_tb_{what}"));
                failed(&icarus(broken, &tb, &dir, "2005"), what, expect);
                failed(&verilator_top(broken, &tb, &dir, "sd_top_tb"), what, expect);
            }
        },
    );
}

/// IEEE 1800-2017 Annex B reserved keywords (SystemVerilog), which a Verilog-2001 file
/// read as SystemVerilog must not use as identifiers.
const SV_KEYWORDS: &[&str] = &[
    "accept_on",
    "alias",
    "always",
    "always_comb",
    "always_ff",
    "always_latch",
    "and",
    "assert",
    "assign",
    "assume",
    "automatic",
    "before",
    "begin",
    "bind",
    "bins",
    "binsof",
    "bit",
    "break",
    "buf",
    "bufif0",
    "bufif1",
    "byte",
    "case",
    "casex",
    "casez",
    "cell",
    "chandle",
    "checker",
    "class",
    "clocking",
    "cmos",
    "config",
    "const",
    "constraint",
    "context",
    "continue",
    "cover",
    "covergroup",
    "coverpoint",
    "cross",
    "deassign",
    "default",
    "defparam",
    "design",
    "disable",
    "dist",
    "do",
    "edge",
    "else",
    "end",
    "endcase",
    "endchecker",
    "endclass",
    "endclocking",
    "endconfig",
    "endfunction",
    "endgenerate",
    "endgroup",
    "endinterface",
    "endmodule",
    "endpackage",
    "endprimitive",
    "endprogram",
    "endproperty",
    "endspecify",
    "endsequence",
    "endtable",
    "endtask",
    "enum",
    "event",
    "eventually",
    "expect",
    "export",
    "extends",
    "extern",
    "final",
    "first_match",
    "for",
    "force",
    "foreach",
    "forever",
    "fork",
    "forkjoin",
    "function",
    "generate",
    "genvar",
    "global",
    "highz0",
    "highz1",
    "if",
    "iff",
    "ifnone",
    "ignore_bins",
    "illegal_bins",
    "implements",
    "implies",
    "import",
    "incdir",
    "include",
    "initial",
    "inout",
    "input",
    "inside",
    "instance",
    "int",
    "integer",
    "interconnect",
    "interface",
    "intersect",
    "join",
    "join_any",
    "join_none",
    "large",
    "let",
    "liblist",
    "library",
    "local",
    "localparam",
    "logic",
    "longint",
    "macromodule",
    "matches",
    "medium",
    "modport",
    "module",
    "nand",
    "negedge",
    "nettype",
    "new",
    "nexttime",
    "nmos",
    "nor",
    "noshowcancelled",
    "not",
    "notif0",
    "notif1",
    "null",
    "or",
    "output",
    "package",
    "packed",
    "parameter",
    "pmos",
    "posedge",
    "primitive",
    "priority",
    "program",
    "property",
    "protected",
    "pull0",
    "pull1",
    "pulldown",
    "pullup",
    "pulsestyle_ondetect",
    "pulsestyle_onevent",
    "pure",
    "rand",
    "randc",
    "randcase",
    "randsequence",
    "rcmos",
    "real",
    "realtime",
    "ref",
    "reg",
    "reject_on",
    "release",
    "repeat",
    "restrict",
    "return",
    "rnmos",
    "rpmos",
    "rtran",
    "rtranif0",
    "rtranif1",
    "s_always",
    "s_eventually",
    "s_nexttime",
    "s_until",
    "s_until_with",
    "scalared",
    "sequence",
    "shortint",
    "shortreal",
    "showcancelled",
    "signed",
    "small",
    "soft",
    "solve",
    "specify",
    "specparam",
    "static",
    "string",
    "strong",
    "strong0",
    "strong1",
    "struct",
    "super",
    "supply0",
    "supply1",
    "sync_accept_on",
    "sync_reject_on",
    "table",
    "tagged",
    "task",
    "this",
    "throughout",
    "time",
    "timeprecision",
    "timeunit",
    "tran",
    "tranif0",
    "tranif1",
    "tri",
    "tri0",
    "tri1",
    "triand",
    "trior",
    "trireg",
    "type",
    "typedef",
    "union",
    "unique",
    "unique0",
    "unsigned",
    "until",
    "until_with",
    "untyped",
    "use",
    "uwire",
    "var",
    "vectored",
    "virtual",
    "void",
    "wait",
    "wait_order",
    "wand",
    "weak",
    "weak0",
    "weak1",
    "while",
    "wildcard",
    "wire",
    "with",
    "within",
    "wor",
    "xnor",
    "xor",
];

/// Every identifier the testbench declares (reg, wire, integer, module, instance names) is
/// not a SystemVerilog keyword.
#[test]
fn testbench_declares_no_systemverilog_keyword() {
    let (_, tb, _) = files();
    let mut declared = vec![];
    for line in tb.lines().map(str::trim_start) {
        if line.starts_with("//") {
            continue;
        }
        let decl = ["reg ", "wire ", "integer ", "module "]
            .iter()
            .find_map(|k| line.strip_prefix(k));
        if let Some(rest) = decl {
            let rest = rest.trim_start();
            let rest = if rest.starts_with('[') {
                rest.split_once(']').map(|x| x.1).unwrap_or(rest)
            } else {
                rest
            };
            let name: String = rest
                .trim_start()
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect();
            declared.push(name);
        }
        // Instance: "<module> <instance>(".
        if let Some((m, rest)) = line.split_once(' ') {
            if m.ends_with("_core") {
                declared.push(rest.split('(').next().unwrap_or("").trim().to_string());
            }
        }
    }
    assert!(declared.len() >= 8, "{declared:?}");
    for d in &declared {
        assert!(!d.is_empty(), "{declared:?}");
        assert!(
            !SV_KEYWORDS.contains(&d.as_str()),
            "`{d}` is a SystemVerilog keyword: {declared:?}"
        );
    }
    // The memory of expected values in particular (it was named `expect`).
    assert!(!tb.contains("expect ["), "{}", &tb[..tb.len().min(2000)]);
}
