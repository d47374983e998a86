//! Helpers shared by `tests/cli/board.rs` and `tests/cli/board_clock_pins.rs` (moved out of `tests/cli/board.rs` so that
//! no test file is longer than about 600 lines).
#![allow(dead_code)]
use crate::common;
use sinedec::config::{DEFAULT_CONFIG, PREAMP_PINS, QEP_PINS, TOP_PINS};
use sinedec::emit::Generation;

/// The pins of the default config's top (QEP enabled there, SSI and SPI off).
pub fn default_pins() -> Vec<&'static str> {
    kit_pins()
        .into_iter()
        .chain(QEP_PINS.iter().copied())
        .collect()
}

/// The pins every top of the LTC1407A-1 kit has: the top's own and the pre-amplifier's.
pub fn kit_pins() -> Vec<&'static str> {
    TOP_PINS.iter().chain(PREAMP_PINS).copied().collect()
}

pub fn with_board(skip: Option<&str>) -> String {
    let mut t = DEFAULT_CONFIG.to_string();
    t.push_str("\n[board]\niostandard = \"LVCMOS33\"\n[board.pins]\n");
    for (i, p) in default_pins().iter().enumerate() {
        if Some(*p) != skip {
            t.push_str(&format!("{p} = \"P{}\"\n", 10 + i));
        }
    }
    t
}

/// `text` with `from` replaced by `to` in the first line after the section header `section`
/// that holds it (panics when there is none, so a changed default config fails loudly).
pub fn in_section(text: &str, section: &str, from: &str, to: &str) -> String {
    let at = text
        .find(&format!("\n{section}\n"))
        .unwrap_or_else(|| panic!("{section} not in the config"));
    let rel = text[at..]
        .find(from)
        .unwrap_or_else(|| panic!("{from} not in {section}"));
    format!(
        "{}{to}{}",
        &text[..at + rel],
        &text[at + rel + from.len()..]
    )
}

pub fn file<'a>(g: &'a Generation, name: &str) -> &'a str {
    &g.files
        .iter()
        .find(|f| f.name == name)
        .unwrap_or_else(|| panic!("{name} not generated"))
        .text
}

/// The ports of `module sd_top (...)`: (direction, name), read from the declarations.
pub fn wrapper_ports(v: &str) -> Vec<(String, String)> {
    let start = v.find("module sd_top (").expect("module sd_top");
    let end = start + v[start..].find(");").expect("end of the port list");
    v[start..end]
        .lines()
        .skip(1)
        .filter_map(|l| {
            let code = l.split("//").next().unwrap_or("").replace(',', " ");
            let words: Vec<&str> = code.split_whitespace().collect();
            match (words.first(), words.last()) {
                (Some(d), Some(n)) if *d == "input" || *d == "output" => {
                    Some((d.to_string(), n.to_string()))
                }
                _ => None,
            }
        })
        .collect()
}

/// The non-`par_*` port names of `sd_top`, sorted.
pub fn pinned_ports(v: &str) -> Vec<String> {
    let mut p: Vec<String> = wrapper_ports(v)
        .into_iter()
        .map(|(_, n)| n)
        .filter(|n| !n.starts_with("par_"))
        .collect();
    p.sort();
    p
}

/// (net, loc) of every LOC line of a UCF, sorted by net.
pub fn ucf_locs(ucf: &str) -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = ucf
        .lines()
        .filter(|l| l.starts_with("NET ") && l.contains(" LOC = "))
        .map(|l| {
            let q: Vec<&str> = l.split('"').collect();
            (q[1].to_string(), q[3].to_string())
        })
        .collect();
    v.sort();
    v
}

/// Nets with a TIG line.
pub fn ucf_tigs(ucf: &str) -> Vec<String> {
    ucf.lines()
        .filter(|l| l.starts_with("NET ") && l.ends_with(" TIG;"))
        .map(|l| l.split('"').nth(1).unwrap_or("").to_string())
        .collect()
}

pub fn sorted(v: &[&str]) -> Vec<String> {
    let mut v: Vec<String> = v.iter().map(|s| s.to_string()).collect();
    v.sort();
    v
}

/// The Starter Kit's pins as the board's user guides give them (UG334 chapter 9 for the SPI
/// bus of the analog capture circuit; the 50 MHz oscillator CLK_50M on E12 and BTN_SOUTH on
/// T15), written here from those sources, not from the code's table.
pub const KIT: &[(&str, &str)] = &[
    ("clk", "E12"),
    ("rst", "T15"),
    ("adc_sck", "AA20"),
    ("adc_conv", "Y6"),
    ("adc_miso", "D16"),
    ("amp_mosi", "AB14"),
    ("amp_cs", "W6"),
    ("amp_shdn", "W15"),
];

pub fn with_preset(extra: &[(&str, &str)]) -> String {
    let mut t = DEFAULT_CONFIG.to_string();
    t.push_str("\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\n");
    for (k, v) in extra {
        t.push_str(&format!("{k} = \"{v}\"\n"));
    }
    t
}

/// The pins the preset does not know (board wiring the user decides).
pub fn user_pins() -> Vec<(&'static str, String)> {
    default_pins()
        .into_iter()
        .filter(|p| !KIT.iter().any(|(k, _)| k == p))
        .enumerate()
        .map(|(i, p)| (p, format!("H{}", i + 1)))
        .collect()
}

/// The deselect lines of the kit's other SPI-bus devices (DAC_CS, DAC_CLR, SPI_SS_B,
/// SF_CE0), optional since their kit pins are not known.
pub const DESELECT: &[&str] = &["dac_cs", "dac_clr", "spi_ss_b", "sf_ce0"];

/// Runs the emitted top through Icarus and a Verilator lint; the wrapper itself (the lines
/// up to `endmodule // sd_top`) must draw no Verilator warning.
pub fn compiles(g: &Generation, tag: &str) {
    for tool in ["iverilog", "verilator"] {
        if let Err(e) = sinedec::cosim::require_tool(tool) {
            panic!("{tool} is needed to check the emitted sd_top.v: {e}");
        }
    }
    let dir = common::workdir(tag);
    let top = file(g, "sd_top.v");
    let path = dir.join("sd_top.v");
    std::fs::write(&path, top).expect("write sd_top.v");
    let out = std::process::Command::new("iverilog")
        .args(["-g2005", "-o", "/dev/null"])
        .arg(&path)
        .output()
        .expect("iverilog runs");
    assert!(
        out.status.success(),
        "iverilog rejects sd_top.v ({}):\n{}",
        path.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let out = std::process::Command::new("verilator")
        .args(["--lint-only", "-Wno-fatal"])
        .arg(&path)
        .args(["--top-module", "sd_top"])
        .output()
        .expect("verilator runs");
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "verilator rejects sd_top.v ({}):\n{log}",
        path.display()
    );
    let end = top
        .lines()
        .position(|l| l == "endmodule // sd_top")
        .expect("end of the wrapper")
        + 1;
    for l in log.lines().filter(|l| l.starts_with("%Warning")) {
        let line: usize = l
            .split("sd_top.v:")
            .nth(1)
            .and_then(|r| r.split(':').next())
            .and_then(|n| n.parse().ok())
            .unwrap_or(usize::MAX);
        assert!(line > end, "warning in the wrapper: {l}");
    }
}

/// The header wiring that, with the kit preset, completes the default config's pins.
pub const WIRING: &[(&str, &str)] = &[
    ("qep_a", "H1"),
    ("qep_b", "H2"),
    ("qep_z", "H3"),
    ("biss_ma", "H4"),
    ("biss_slo", "H5"),
];
