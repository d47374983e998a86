//! `[registers]`: off by default (no ports, no files), and when on the emitted SystemRDL
//! compiles with PeakRDL into a C header whose offsets and resets (read back by gcc) equal
//! `<name>_regs.json`, which equals the register table the RTL decodes; the Markdown table,
//! `check`'s line, the wrapper's AXI4-Lite ports and the errors.
use crate::common;
use sinedec::blocks::regmap::REGISTERS;
use sinedec::config::{Loaded, DEFAULT_CONFIG};
use std::path::{Path, PathBuf};
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_sinedec");
/// The `peakrdl` executable of the tools' venv (`common::venv_tool`).
fn peakrdl() -> PathBuf {
    common::venv_tool("peakrdl", "peakrdl==1.5.0")
}

fn with_registers() -> String {
    format!(
        "{DEFAULT_CONFIG}\n[velocity]\nenabled = true\n\n[capture]\nenabled = true\n\n[registers]\nenabled = true\n"
    )
}

/// `sinedec generate` of `text` into `dir/out`.
fn generate(text: &str, dir: &Path) {
    std::fs::write(dir.join("c.toml"), text).expect("write");
    let o = Command::new(BIN)
        .args(["generate", "c.toml", "-o", "out"])
        .current_dir(dir)
        .output()
        .expect("runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

#[test]
fn off_by_default() {
    let l = Loaded::parse(DEFAULT_CONFIG, "d.toml").expect("default");
    assert!(l.derived.registers.is_none());
    let dir = tempfile::tempdir().expect("dir");
    generate(DEFAULT_CONFIG, dir.path());
    let out = dir.path().join("out");
    assert!(!out.join("sd_regs.rdl").exists() && !out.join("sd_regs.json").exists());
    let top = std::fs::read_to_string(out.join("sd_top.v")).expect("top");
    assert!(!top.contains("s_axi_"));
}

#[test]
fn the_systemrdl_compiles_and_agrees_with_the_json_and_the_table() {
    let dir = tempfile::tempdir().expect("dir");
    generate(&with_registers(), dir.path());
    let out = dir.path().join("out");
    // PeakRDL: the SystemRDL into a C header.
    let o = Command::new(peakrdl())
        .args(["c-header", "sd_regs.rdl", "-o", "sd_regs.h"])
        .current_dir(&out)
        .output()
        .expect("peakrdl runs");
    assert!(
        o.status.success(),
        "peakrdl: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    // gcc reads the header back: each register's offset in the struct and each field's
    // reset macro (constant and latched fields have one; live ones none).
    let mut c = String::from(
        "#include <stdio.h>\n#include <stddef.h>\n#include \"sd_regs.h\"\nint main(void) {\n",
    );
    for r in REGISTERS {
        c.push_str(&format!(
            "  printf(\"{0} %zu\\n\", offsetof(sd_regs_t, {0}));\n",
            r.name
        ));
    }
    c.push_str("  return 0;\n}\n");
    std::fs::write(out.join("offsets.c"), c).expect("write");
    let o = Command::new("gcc")
        .args(["-std=c11", "-o", "offsets", "offsets.c"])
        .current_dir(&out)
        .output()
        .expect("gcc runs (apt-get install gcc)");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = Command::new(out.join("offsets")).output().expect("runs");
    let offsets: Vec<(String, u32)> = String::from_utf8_lossy(&o.stdout)
        .lines()
        .map(|l| {
            let (n, v) = l.split_once(' ').expect("name offset");
            (n.to_string(), v.parse().expect("number"))
        })
        .collect();
    let header = std::fs::read_to_string(out.join("sd_regs.h")).expect("header");
    // The JSON.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sd_regs.json")).expect("json"))
            .expect("JSON parses");
    // Every reset is the table's, but the monitor thresholds' and the correction codes' are
    // the config's: the default's offsets 0, gains 1.0 (2^GF) and no phase error.
    let l = sinedec::config::Loaded::parse(&with_registers(), "r.toml").expect("config");
    let m = &l.derived.monitor;
    let one = 1u64 << l.derived.correction.gain_frac_bits();
    let want_reset = |r: &sinedec::blocks::regmap::RegDef| -> u64 {
        match r.name {
            "LOS_THRESHOLD" => m.los_threshold(),
            "LOS_RELEASE" => m.los_release(),
            "CLIP_THRESHOLD" => m.clip_threshold(),
            "GAIN_SIN" | "GAIN_COS" => one,
            // No learned harmonic table here: its words are not decoded.
            "HARM_CONTROL" => 0,
            _ => r.reset as u64,
        }
    };
    assert!(m.los_threshold() > 0 && m.los_release() >= m.los_threshold());
    let regs = json.as_array().expect("a list");
    assert_eq!(regs.len(), REGISTERS.len());
    assert_eq!(offsets.len(), REGISTERS.len());
    for ((j, (name, off)), r) in regs.iter().zip(&offsets).zip(REGISTERS) {
        assert_eq!(j["name"], r.name);
        assert_eq!(name, r.name);
        assert_eq!(j["address"].as_u64(), Some(r.address as u64), "{name}");
        assert_eq!(*off, r.address, "{name}: the C struct's offset");
        assert_eq!(j["width"].as_u64(), Some(32));
        assert_eq!(j["access"], r.access.as_str());
        assert_eq!(j["reset"].as_u64(), Some(want_reset(r)), "{name}");
        assert!(j["description"].as_str().is_some_and(|d| !d.is_empty()));
        // The header's reset of each field with one equals the JSON's word.
        for f in r.fields {
            let mac = format!("SD_REGS__{}__{}_reset ", r.name, f.name);
            if let Some(line) = header.lines().find(|l| l.contains(&mac)) {
                let v = line.rsplit(' ').next().expect("value");
                let v = u64::from_str_radix(v.trim_start_matches("0x"), 16).expect("hex");
                assert_eq!(
                    v,
                    (want_reset(r) >> f.lsb) & ((1u64 << f.width) - 1),
                    "{mac}"
                );
            }
        }
    }
    // The constant registers have their reset in the header; STATUS's fields too.
    assert!(
        header.contains("SD_REGS__ID__ID_reset 0x53444543"),
        "{header}"
    );
    assert!(header.contains("SD_REGS__STATUS__LOS_reset 0x0"));
    assert!(header.contains("SD_REGS__HARM_CONTROL__LEARN_reset 0x0"));
    // The Markdown table in the parameters.
    let md = std::fs::read_to_string(out.join("sd_params.md")).expect("md");
    for r in REGISTERS {
        let row = format!(
            "| 0x{:02x} | {} | {} |",
            r.address,
            r.name,
            r.access.as_str()
        );
        assert!(md.contains(&row), "{row}");
    }
    // The wrapper's AXI4-Lite ports.
    let top = std::fs::read_to_string(out.join("sd_top.v")).expect("top");
    for p in [
        "input  wire [7:0]   s_axi_awaddr,",
        "input  wire [3:0]   s_axi_wstrb,",
        "output wire [31:0]  s_axi_rdata,",
        "output wire [1:0]   s_axi_bresp,",
        "input  wire         s_axi_rready,",
    ] {
        assert!(top.contains(p), "{p}");
    }
}

#[test]
fn check_lists_the_map_and_bad_values_are_rejected() {
    let dir = tempfile::tempdir().expect("dir");
    std::fs::write(dir.path().join("c.toml"), with_registers()).expect("write");
    let o = Command::new(BIN)
        .args(["check", "c.toml"])
        .current_dir(dir.path())
        .output()
        .expect("runs");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.contains("AXI4-Lite slave s_axi_*")
            && out.contains(&format!("{} registers", REGISTERS.len())),
        "{out}"
    );
    // The thresholds' reset values are the monitor's, as the check prints them itself.
    let l = Loaded::parse(&with_registers(), "c.toml").expect("config");
    let m = &l.derived.monitor;
    assert!(
        out.contains(&format!(
            "LOS_THRESHOLD {}, LOS_RELEASE {}, CLIP_THRESHOLD {}",
            m.los_threshold(),
            m.los_release(),
            m.clip_threshold()
        )),
        "{out}"
    );
    assert!(
        !out.contains("register map over BiSS C"),
        "no control channel"
    );
    // The kit's one data line carries both 14-bit words.
    assert!(
        out.contains("adc frame check             every data line stuck over a frame (1 line, 28 data bits each) -> STATUS.ADC_FRAME"),
        "{out}"
    );
    // A wrong type points at the value.
    let text = common::with_section("registers", "enabled = 2");
    let (line, col) = common::line_col(&text, "enabled = 2");
    let e = Loaded::parse(&text, "bad.toml").unwrap_err().to_string();
    let at = format!("bad.toml:{line}:{}: ", col + "enabled = ".len());
    assert!(
        e.starts_with(&at) && e.contains("`registers.enabled`"),
        "{e}"
    );
    let e = Loaded::parse(
        &common::with_section("registers", "enable = true"),
        "bad.toml",
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("enable") && e.contains("enabled"), "{e}");
}

/// With a learned harmonic table (`RegmapParams::with_harmonics`): the SystemRDL compiles
/// with PeakRDL, HARM_CONTROL.LEARN resets to 1 there and in the JSON and the Markdown,
/// LOAD_BUSY is a read-only field (no reset) of the read-write HARM_CONTROL.
#[test]
fn a_learned_table_resets_learn_to_one_in_every_output() {
    let l = Loaded::parse(&with_registers(), "r.toml").expect("config");
    let p = l
        .derived
        .registers
        .expect("registers")
        .with_harmonics(64, 20)
        .expect("harmonics");
    let dir = tempfile::tempdir().expect("dir");
    let rdl = sinedec::emit::regmap::rdl(&p, "sd", "// test\n");
    assert!(rdl.contains("sw = r; hw = w; desc = "), "{rdl}");
    assert!(rdl.contains("LOAD_BUSY[1:1];"), "{rdl}");
    std::fs::write(dir.path().join("sd_regs.rdl"), &rdl).expect("write");
    let o = Command::new(peakrdl())
        .args(["c-header", "sd_regs.rdl", "-o", "sd_regs.h"])
        .current_dir(dir.path())
        .output()
        .expect("peakrdl runs");
    assert!(
        o.status.success(),
        "peakrdl: {}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    let header = std::fs::read_to_string(dir.path().join("sd_regs.h")).expect("header");
    assert!(
        header.contains("SD_REGS__HARM_CONTROL__LEARN_reset 0x1"),
        "{header}"
    );
    assert!(!header.contains("SD_REGS__HARM_CONTROL__LOAD_BUSY_reset"));
    assert!(header.contains("SD_REGS__HARM_ENTRY__HARM_ENTRY_reset 0x0"));
    let json: serde_json::Value =
        serde_json::from_str(&sinedec::emit::regmap::json(&p).expect("json")).expect("parses");
    let ctl = json
        .as_array()
        .expect("a list")
        .iter()
        .find(|r| r["name"] == "HARM_CONTROL")
        .expect("HARM_CONTROL");
    assert_eq!(ctl["address"].as_u64(), Some(0x5c));
    assert_eq!(ctl["reset"].as_u64(), Some(1));
    let md = sinedec::emit::regmap::markdown(&p);
    assert!(
        md.contains("| 0x5c | HARM_CONTROL | rw | 0x00000001 |"),
        "{md}"
    );
    assert!(
        md.contains("| 0x64 | HARM_ENTRY | rw | 0x00000000 |"),
        "{md}"
    );
}
