//! `[board]`: the UCF of `<name>_top` lists every pin with its I/O standard and the clock
//! period; a missing pin is rejected with the port's name and nothing is written. The
//! wrapper declares only the ports the configuration uses (QEP, SSI, SPI slave, pinned
//! deselect lines), each with a LOC; the kit preset adds the BitGen option file.
mod common;

use sinedec::config::{Loaded, DEFAULT_CONFIG, QEP_PINS, TOP_PINS};
use sinedec::emit::Generation;

/// The pins of the default config's top (QEP enabled there, SSI and SPI off).
fn default_pins() -> Vec<&'static str> {
    TOP_PINS.iter().chain(QEP_PINS).copied().collect()
}

fn with_board(skip: Option<&str>) -> String {
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
fn in_section(text: &str, section: &str, from: &str, to: &str) -> String {
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

fn file<'a>(g: &'a Generation, name: &str) -> &'a str {
    &g.files
        .iter()
        .find(|f| f.name == name)
        .unwrap_or_else(|| panic!("{name} not generated"))
        .text
}

/// The ports of `module sd_top (...)`: (direction, name), read from the declarations.
fn wrapper_ports(v: &str) -> Vec<(String, String)> {
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
fn pinned_ports(v: &str) -> Vec<String> {
    let mut p: Vec<String> = wrapper_ports(v)
        .into_iter()
        .map(|(_, n)| n)
        .filter(|n| !n.starts_with("par_"))
        .collect();
    p.sort();
    p
}

/// (net, loc) of every LOC line of a UCF, sorted by net.
fn ucf_locs(ucf: &str) -> Vec<(String, String)> {
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
fn ucf_tigs(ucf: &str) -> Vec<String> {
    ucf.lines()
        .filter(|l| l.starts_with("NET ") && l.ends_with(" TIG;"))
        .map(|l| l.split('"').nth(1).unwrap_or("").to_string())
        .collect()
}

fn sorted(v: &[&str]) -> Vec<String> {
    let mut v: Vec<String> = v.iter().map(|s| s.to_string()).collect();
    v.sort();
    v
}

#[test]
fn ucf_lists_every_pin_and_the_clock() {
    let l = Loaded::parse(&with_board(None), "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let ucf = &g
        .files
        .iter()
        .find(|f| f.name == "sd_top.ucf")
        .expect("ucf")
        .text;
    for (i, p) in default_pins().iter().enumerate() {
        let line = format!("NET \"{p}\" LOC = \"P{}\" | IOSTANDARD = LVCMOS33;", 10 + i);
        assert!(ucf.contains(&line), "{line} missing:\n{ucf}");
    }
    // 133.33 MHz -> 7.500 ns.
    assert!(ucf.contains("PERIOD \"clk\" 7.500 ns"), "{ucf}");
    // The pinned ports are exactly the top's non-par ports, each with one LOC line.
    let top = file(&g, "sd_top.v");
    assert_eq!(pinned_ports(top), sorted(&default_pins()));
    let locs: Vec<String> = ucf_locs(ucf).into_iter().map(|(n, _)| n).collect();
    assert_eq!(locs, sorted(&default_pins()));
    // Without the kit preset there is no BitGen option file.
    assert!(!g.files.iter().any(|f| f.name.ends_with(".ut")));
}

#[test]
fn a_missing_pin_is_rejected_by_name_and_nothing_is_written() {
    let text = with_board(Some("biss_slo"));
    let dir = tempfile::tempdir().expect("tmp");
    let cfg = dir.path().join("b.toml");
    std::fs::write(&cfg, &text).expect("write");
    let out = dir.path().join("out");
    let r = std::process::Command::new(env!("CARGO_BIN_EXE_sinedec"))
        .arg("generate")
        .arg(&cfg)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("runs");
    assert!(!r.status.success());
    let msg = String::from_utf8_lossy(&r.stderr);
    assert!(
        msg.contains("pins missing for the board: biss_slo"),
        "{msg}"
    );
    assert!(msg.contains("board.pins"), "{msg}");
    assert!(!out.exists());
}

#[test]
fn an_unknown_pin_name_is_rejected() {
    let text = with_board(None).replace("[board.pins]\n", "[board.pins]\nled7 = \"A1\"\n");
    let e = Loaded::parse(&text, "b.toml").expect_err("unknown port");
    assert!(e.to_string().contains("led7"), "{e}");
}

/// The Starter Kit's pins as the board's user guides give them (UG334 chapter 9 for the SPI
/// bus of the analog capture circuit; the 50 MHz oscillator CLK_50M on E12 and BTN_SOUTH on
/// T15), written here from those sources, not from the code's table.
const KIT: &[(&str, &str)] = &[
    ("clk", "E12"),
    ("rst", "T15"),
    ("adc_sck", "AA20"),
    ("adc_conv", "Y6"),
    ("adc_miso", "D16"),
    ("amp_mosi", "AB14"),
    ("amp_cs", "W6"),
    ("amp_shdn", "W15"),
];

fn with_preset(extra: &[(&str, &str)]) -> String {
    let mut t = DEFAULT_CONFIG.to_string();
    t.push_str("\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\n");
    for (k, v) in extra {
        t.push_str(&format!("{k} = \"{v}\"\n"));
    }
    t
}

/// The pins the preset does not know (board wiring the user decides).
fn user_pins() -> Vec<(&'static str, String)> {
    default_pins()
        .into_iter()
        .filter(|p| !KIT.iter().any(|(k, _)| k == p))
        .enumerate()
        .map(|(i, p)| (p, format!("H{}", i + 1)))
        .collect()
}

/// The deselect lines of the kit's other SPI-bus devices (DAC_CS, DAC_CLR, SPI_SS_B,
/// SF_CE0), optional since their kit pins are not known.
const DESELECT: &[&str] = &["dac_cs", "dac_clr", "spi_ss_b", "sf_ce0"];

#[test]
fn the_starter_kit_preset_fills_in_the_known_pins() {
    let user = user_pins();
    let extra: Vec<(&str, &str)> = user.iter().map(|(k, v)| (*k, v.as_str())).collect();
    let l = Loaded::parse(&with_preset(&extra), "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let ucf = &g
        .files
        .iter()
        .find(|f| f.name == "sd_top.ucf")
        .expect("ucf")
        .text;
    for (p, loc) in KIT
        .iter()
        .map(|(k, v)| (*k, *v))
        .chain(extra.iter().copied())
    {
        let line = format!("NET \"{p}\" LOC = \"{loc}\" | IOSTANDARD = LVCMOS33;");
        assert!(ucf.contains(&line), "{line} missing:\n{ucf}");
    }
    // A pin given in [board.pins] wins over the preset's.
    let mut over = extra.clone();
    over.push(("clk", "AA12"));
    let l = Loaded::parse(&with_preset(&over), "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let ucf = &g
        .files
        .iter()
        .find(|f| f.name == "sd_top.ucf")
        .expect("ucf")
        .text;
    assert!(ucf.contains("NET \"clk\" LOC = \"AA12\""), "{ucf}");
    assert!(!ucf.contains("\"E12\""), "{ucf}");
}

#[test]
fn the_preset_alone_names_exactly_the_pins_still_missing() {
    let e = Loaded::parse(&with_preset(&[]), "b.toml").expect_err("pins missing");
    let msg = e.to_string();
    // With QEP enabled (the default config), the header wiring: comparators and BiSS.
    assert!(
        msg.contains(
            "pins missing for the board: qep_a, qep_b, qep_z, biss_ma, biss_slo (every port"
        ),
        "{msg}"
    );
    assert!(msg.contains("wiring on the kit's headers"), "{msg}");
    for k in KIT.iter().map(|(k, _)| *k).chain(DESELECT.iter().copied()) {
        assert!(!msg.contains(k), "{k} should not be required: {msg}");
    }
    // Without QEP only the BiSS pins are missing.
    let no_qep = in_section(
        &with_preset(&[]),
        "[qep]",
        "enabled = true",
        "enabled = false",
    );
    let e = Loaded::parse(&no_qep, "b.toml").expect_err("pins missing");
    assert!(
        e.to_string()
            .contains("pins missing for the board: biss_ma, biss_slo (every port"),
        "{e}"
    );
}

/// The preset plus the header wiring generates: no deselect line is a port or has a LOC,
/// and the BitGen option file pulls the unused pins up; same config, same bytes.
#[test]
fn the_preset_leaves_the_deselect_lines_to_pull_ups() {
    let wiring = [
        ("qep_a", "H1"),
        ("qep_b", "H2"),
        ("qep_z", "H3"),
        ("biss_ma", "H4"),
        ("biss_slo", "H5"),
    ];
    let text = with_preset(&wiring);
    let l = Loaded::parse(&text, "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let top = file(&g, "sd_top.v");
    let ucf = file(&g, "sd_top.ucf");
    let expected: Vec<&str> = KIT.iter().chain(wiring.iter()).map(|(k, _)| *k).collect();
    assert_eq!(pinned_ports(top), sorted(&expected));
    let mut locs: Vec<(String, String)> = KIT
        .iter()
        .chain(wiring.iter())
        .map(|(k, v)| (k.to_string(), v.to_string()))
        .collect();
    locs.sort();
    assert_eq!(ucf_locs(ucf), locs);
    for p in DESELECT {
        assert!(
            !ucf.contains(&format!("NET \"{p}\"")),
            "{p} in the UCF:\n{ucf}"
        );
        assert!(
            !wrapper_ports(top).iter().any(|(_, n)| n == p),
            "{p} is a port"
        );
    }
    let ut = file(&g, "sd_top.ut");
    let lines: Vec<&str> = ut.lines().collect();
    // Options only (no comment lines: BitGen's -f syntax for comments is not documented in
    // our sources); the explanation is in the UCF header.
    assert_eq!(lines, ["-w", "-g UnusedPin:PullUp"], "{ut}");
    assert!(ucf.contains("sd_top.ut"), "{ucf}");
    assert!(
        ucf.contains("DAC_CS") && ucf.contains("SPI_SS_B") && ucf.contains("SF_CE0"),
        "{ucf}"
    );
    // Deterministic: the same config gives the same bytes.
    let again = sinedec::emit::generate(&Loaded::parse(&text, "b.toml").expect("parses"), "test")
        .expect("generates");
    assert_eq!(g.files, again.files);
}

/// A pinned deselect line becomes a port (an output, driven 1 by the rtl) with its LOC; it
/// is validated like any pin.
#[test]
fn a_pinned_deselect_line_is_a_port_with_a_loc() {
    let wiring = [
        ("qep_a", "H1"),
        ("qep_b", "H2"),
        ("qep_z", "H3"),
        ("biss_ma", "H4"),
        ("biss_slo", "H5"),
        ("dac_cs", "H6"),
    ];
    let l = Loaded::parse(&with_preset(&wiring), "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let top = file(&g, "sd_top.v");
    let ports = wrapper_ports(top);
    assert!(
        ports.contains(&("output".to_string(), "dac_cs".to_string())),
        "{ports:?}"
    );
    for p in ["dac_clr", "spi_ss_b", "sf_ce0"] {
        assert!(!ports.iter().any(|(_, n)| n == p), "{p} is a port");
    }
    assert!(top.contains(".dac_cs(dac_cs)"), "dac_cs not connected");
    let ucf = file(&g, "sd_top.ucf");
    assert!(
        ucf.contains("NET \"dac_cs\" LOC = \"H6\" | IOSTANDARD = LVCMOS33;"),
        "{ucf}"
    );
    assert_eq!(ucf_locs(ucf).len(), KIT.len() + wiring.len());
    // A bad pin for a deselect line is rejected like any other.
    let bad = with_preset(&[("sf_ce0", "H-7")]);
    let e = Loaded::parse(&bad, "b.toml").expect_err("bad pin");
    assert!(e.to_string().contains("sf_ce0"), "{e}");
}

/// Ports follow the configuration: without QEP the comparator inputs are neither required
/// nor ports nor in the UCF; with SSI (and the SPI slave) their pins are required and present.
#[test]
fn ports_follow_the_enabled_blocks() {
    let base = in_section(DEFAULT_CONFIG, "[qep]", "enabled = true", "enabled = false");
    let board = |cfg: &str, pins: &[&str]| {
        let mut t = cfg.to_string();
        t.push_str("\n[board]\niostandard = \"LVCMOS33\"\n[board.pins]\n");
        // Balls P1, P2, ... R1, R2, ...: the FG484 rows have 22 columns.
        for (i, p) in pins.iter().enumerate() {
            let row = ["P", "R"][i / 22];
            t.push_str(&format!("{p} = \"{row}{}\"\n", i % 22 + 1));
        }
        t
    };
    let l = Loaded::parse(&board(&base, TOP_PINS), "b.toml").expect("no QEP pins needed");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let (top, ucf) = (file(&g, "sd_top.v"), file(&g, "sd_top.ucf"));
    assert_eq!(pinned_ports(top), sorted(TOP_PINS));
    for p in QEP_PINS {
        assert!(!ucf.contains(p), "{p} in the UCF:\n{ucf}");
        assert!(top.contains(&format!(".{p}(1'b0)")), "{p} not tied low");
    }
    assert_eq!(ucf_tigs(ucf), vec!["biss_ma".to_string()]);
    // A QEP pin is then not a port of the top.
    let mut with_qep: Vec<&str> = TOP_PINS.to_vec();
    with_qep.push("qep_a");
    let e = Loaded::parse(&board(&base, &with_qep), "b.toml").expect_err("qep_a not a port");
    assert!(e.to_string().contains("qep_a"), "{e}");

    // SSI and the SPI slave: their pins are required, named when missing, and present.
    let ssi = in_section(&base, "[ssi]", "enabled = false", "enabled = true");
    let both = in_section(&ssi, "[spi]", "enabled = false", "enabled = true");
    let e = Loaded::parse(&board(&ssi, TOP_PINS), "b.toml").expect_err("ssi pins missing");
    assert!(
        e.to_string()
            .contains("pins missing for the board: ssi_clk, ssi_data (every port"),
        "{e}"
    );
    let spi = ["enc_sck", "enc_cs_n", "enc_miso", "enc_miso_oe"];
    let mut all: Vec<&str> = TOP_PINS.to_vec();
    all.extend(["ssi_clk", "ssi_data"]);
    let e = Loaded::parse(&board(&both, &all), "b.toml").expect_err("spi pins missing");
    assert!(
        e.to_string().contains(&format!(
            "pins missing for the board: {} (every port",
            spi.join(", ")
        )),
        "{e}"
    );
    all.extend(spi);
    let l = Loaded::parse(&board(&both, &all), "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let (top, ucf) = (file(&g, "sd_top.v"), file(&g, "sd_top.ucf"));
    assert_eq!(pinned_ports(top), sorted(&all));
    let locs: Vec<String> = ucf_locs(ucf).into_iter().map(|(n, _)| n).collect();
    assert_eq!(locs, sorted(&all));
    for p in ["ssi_clk", "ssi_data", "enc_sck", "enc_cs_n"] {
        assert!(top.contains(&format!(".{p}({p})")), "{p} not connected");
    }
}

/// Runs the emitted top through Icarus and a Verilator lint; the wrapper itself (the lines
/// up to `endmodule // sd_top`) must draw no Verilator warning.
fn compiles(g: &Generation, tag: &str) {
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

#[test]
fn the_emitted_top_compiles_in_icarus_and_verilator() {
    let wiring = [
        ("qep_a", "H1"),
        ("qep_b", "H2"),
        ("qep_z", "H3"),
        ("biss_ma", "H4"),
        ("biss_slo", "H5"),
    ];
    let l = Loaded::parse(&with_preset(&wiring), "b.toml").expect("parses");
    compiles(
        &sinedec::emit::generate(&l, "test").expect("generates"),
        "board_preset",
    );
    // Ties and open outputs: QEP off, SSI and SPI on, one deselect line pinned.
    let mut t = in_section(DEFAULT_CONFIG, "[qep]", "enabled = true", "enabled = false");
    t = in_section(&t, "[ssi]", "enabled = false", "enabled = true");
    t = in_section(&t, "[spi]", "enabled = false", "enabled = true");
    t.push_str("\n[board]\npreset = \"spartan3an-starter-kit\"\n[board.pins]\n");
    for (i, p) in [
        "biss_ma",
        "biss_slo",
        "ssi_clk",
        "ssi_data",
        "enc_sck",
        "enc_cs_n",
        "enc_miso",
        "enc_miso_oe",
        "spi_ss_b",
    ]
    .iter()
    .enumerate()
    {
        t.push_str(&format!("{p} = \"J{}\"\n", i + 1));
    }
    let l = Loaded::parse(&t, "b.toml").expect("parses");
    compiles(
        &sinedec::emit::generate(&l, "test").expect("generates"),
        "board_ties",
    );
}

#[test]
fn an_unknown_preset_and_a_missing_iostandard_are_rejected() {
    let e = Loaded::parse(
        &with_preset(&[]).replace("spartan3an-starter-kit", "de0-nano"),
        "b.toml",
    )
    .expect_err("unknown preset");
    let msg = e.to_string();
    assert!(
        msg.contains("de0-nano") && msg.contains("spartan3an-starter-kit"),
        "{msg}"
    );
    let no_std = with_board(None).replace("iostandard = \"LVCMOS33\"\n", "");
    let e = Loaded::parse(&no_std, "b.toml").expect_err("iostandard missing");
    assert!(e.to_string().contains("iostandard"), "{e}");
}

/// The header wiring that, with the kit preset, completes the default config's pins.
const WIRING: &[(&str, &str)] = &[
    ("qep_a", "H1"),
    ("qep_b", "H2"),
    ("qep_z", "H3"),
    ("biss_ma", "H4"),
    ("biss_slo", "H5"),
];

#[test]
fn the_kit_clock_is_the_50_mhz_oscillator_and_a_dcm_makes_133_mhz() {
    let l = Loaded::parse(&with_preset(WIRING), "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let ucf = file(&g, "sd_top.ucf");
    // The kit's CLK_50M on E12 (UG334): 20 ns, not the 7.5 ns of the system clock.
    assert!(ucf.contains("PERIOD \"clk\" 20.000 ns"), "{ucf}");
    assert!(!ucf.contains("7.500 ns HIGH"), "{ucf}");
    assert!(ucf.contains("# Top module: sd_board."), "{ucf}");
    // 133.33 MHz = 50 MHz x 8 / 3 (the thesis's clock from the kit's oscillator).
    let clock = file(&g, "sd_clock.v");
    for want in [
        "DCM_SP #(",
        ".CLKFX_MULTIPLY(8)",
        ".CLKFX_DIVIDE(3)",
        ".CLKIN_PERIOD(20.000)",
        "BUFG",
    ] {
        assert!(clock.contains(want), "{want} missing:\n{clock}");
    }
    let board = file(&g, "sd_board.v");
    assert!(board.contains("module sd_board ("), "{board}");
    assert!(board.contains("rst | ~locked"), "{board}");
    assert!(board.contains(".clk(clk_sys)"), "{board}");
    // The board wrapper has the top's ports, so the UCF's LOCs apply to it unchanged.
    let board_ports: Vec<String> = sinedec::board::wrapper_ports(board)
        .into_iter()
        .map(|p| p.name)
        .collect();
    let top_ports: Vec<String> = sinedec::board::wrapper_ports(file(&g, "sd_top.v"))
        .into_iter()
        .map(|p| p.name)
        .collect();
    assert_eq!(board_ports, top_ports);
    assert!(g.files.iter().any(|f| f.name == "sd_clock_sim.v"));
    // `check` shows it.
    let d = l.derived.describe();
    assert!(d.contains("DCM_SP CLKFX x 8 / 3 = 133.333 MHz"), "{d}");
}

#[test]
fn a_system_clock_equal_to_the_oscillator_needs_no_dcm() {
    let t = with_preset(WIRING).replace(
        "frequency_hz = 133_330_000.0",
        "frequency_hz = 50_000_000.0",
    );
    assert!(
        t.contains("50_000_000.0"),
        "the default config's clock line moved"
    );
    let l = Loaded::parse(&t, "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let ucf = file(&g, "sd_top.ucf");
    assert!(ucf.contains("PERIOD \"clk\" 20.000 ns"), "{ucf}");
    assert!(ucf.contains("# Top module: sd_top."), "{ucf}");
    for f in ["sd_board.v", "sd_clock.v", "sd_clock_sim.v"] {
        assert!(!g.files.iter().any(|x| x.name == f), "{f} written");
    }
}

#[test]
fn an_unreachable_board_clock_is_rejected_with_the_numbers() {
    // 27 MHz x M / D (M <= 32, D <= 32) comes no closer than 0.04 % to 133.33 MHz.
    let t = with_preset(WIRING).replace(
        "[board]\npreset = \"spartan3an-starter-kit\"\n",
        "[board]\npreset = \"spartan3an-starter-kit\"\nclock_hz = 27e6\n",
    );
    let e = Loaded::parse(&t, "b.toml").expect_err("unreachable");
    let m = e.to_string();
    assert!(m.contains("board.clock_hz") && m.contains("DCM_SP"), "{m}");
    assert!(
        m.contains("133.330000 MHz") && m.contains("27.000000 MHz"),
        "{m}"
    );
    assert!(m.starts_with("b.toml:"), "no location: {m}");
}

/// Simulates `sd_board` with the behavioural clock model in Icarus: a 50 MHz oscillator
/// gives a 7.5 ns system clock, and the top's reset stays high until the model locks.
#[test]
fn the_board_wrapper_runs_in_icarus_with_the_clock_model() {
    if let Err(e) = sinedec::cosim::require_tool("iverilog") {
        panic!("iverilog is needed to simulate sd_board.v: {e}");
    }
    let l = Loaded::parse(&with_preset(WIRING), "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let dir = common::workdir("board_clock_sim");
    for f in ["sd_board.v", "sd_clock_sim.v", "sd_top.v"] {
        std::fs::write(dir.join(f), file(&g, f)).expect("write");
    }
    let tb = r#"`timescale 1ns / 1ps
module tb;
    reg clk = 1'b0;
    reg rst = 1'b0;
    always #10 clk = ~clk; // 50 MHz oscillator
    wire adc_sck, adc_conv, amp_cs, amp_mosi, amp_shdn, biss_slo, par_valid, par_error, par_warning;
    wire [31:0] par_position, par_turns, par_fine;
    sd_board uut (.clk(clk), .rst(rst), .adc_miso(1'b0), .adc_sck(adc_sck), .adc_conv(adc_conv),
        .amp_cs(amp_cs), .amp_mosi(amp_mosi), .amp_shdn(amp_shdn), .qep_a(1'b0), .qep_b(1'b0),
        .qep_z(1'b0), .biss_ma(1'b1), .biss_slo(biss_slo), .par_valid(par_valid),
        .par_position(par_position), .par_turns(par_turns), .par_fine(par_fine),
        .par_error(par_error), .par_warning(par_warning));
    realtime t0, t1;
    integer fails = 0;
    integer k;
    initial begin
        // Before lock: reset held.
        #200;
        if (uut.locked !== 1'b0) begin $display("FAIL locked too early"); fails = fails + 1; end
        wait (uut.locked === 1'b1);
        if (uut.top.rst !== 1'b1) begin $display("FAIL reset released before lock"); fails = fails + 1; end
        @(posedge uut.clk_sys); t0 = $realtime;
        for (k = 0; k < 30; k = k + 1) @(posedge uut.clk_sys);
        t1 = $realtime;
        $display("period %f", (t1 - t0) / 30.0);
        if ((t1 - t0) / 30.0 < 7.49 || (t1 - t0) / 30.0 > 7.51) begin $display("FAIL period"); fails = fails + 1; end
        if (uut.top.rst !== 1'b0) begin $display("FAIL reset not released after lock"); fails = fails + 1; end
        if (fails == 0) $display("PASS");
        $finish;
    end
endmodule
"#;
    std::fs::write(dir.join("tb.v"), tb).expect("write tb");
    let out = std::process::Command::new("iverilog")
        .args([
            "-g2005",
            "-o",
            "tb.vvp",
            "tb.v",
            "sd_board.v",
            "sd_clock_sim.v",
            "sd_top.v",
        ])
        .current_dir(&dir)
        .output()
        .expect("iverilog runs");
    assert!(
        out.status.success(),
        "iverilog: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = std::process::Command::new("vvp")
        .arg("tb.vvp")
        .current_dir(&dir)
        .output()
        .expect("vvp runs");
    let log = String::from_utf8_lossy(&out.stdout);
    assert!(log.contains("PASS") && !log.contains("FAIL"), "{log}");
}

/// Yosys maps `sd_board` with the vendor clock module for xc3sa: the DCM_SP, IBUFG and BUFG
/// instances use ports and parameters the Xilinx cell library knows.
#[test]
fn the_board_wrapper_synthesizes_with_the_dcm_for_xc3sa() {
    if let Err(e) = sinedec::cosim::require_tool("yosys") {
        panic!("yosys is needed to synthesize sd_board.v: {e}");
    }
    let l = Loaded::parse(&with_preset(WIRING), "b.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let dir = common::workdir("board_clock_synth");
    for f in ["sd_board.v", "sd_clock.v"] {
        std::fs::write(dir.join(f), file(&g, f)).expect("write");
    }
    // The top is a black box here: this checks the wrapper and the primitives only.
    let ports: Vec<String> = sinedec::board::wrapper_ports(file(&g, "sd_top.v"))
        .into_iter()
        .map(|p| format!("{} {}{}", p.dir.trim(), p.range, p.name))
        .collect();
    let stub = format!(
        "(* blackbox *) module sd_top({}); endmodule\n",
        ports.join(", ")
    );
    std::fs::write(dir.join("stub.v"), stub).expect("write stub");
    let out = std::process::Command::new("yosys")
        .args([
            "-p",
            "read_verilog sd_board.v sd_clock.v stub.v; synth_xilinx -family xc3sa -top sd_board; stat",
        ])
        .current_dir(&dir)
        .output()
        .expect("yosys runs");
    let log =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{log}");
    assert!(log.contains("DCM_SP"), "{log}");
}

#[test]
fn pins_must_be_balls_of_the_package_used_once() {
    // Two ports on one ball.
    let mut w: Vec<(&str, &str)> = WIRING.to_vec();
    w[1] = ("qep_b", "H1");
    let e = Loaded::parse(&with_preset(&w), "b.toml")
        .expect_err("twice")
        .to_string();
    assert!(
        e.contains("H1") && e.contains("qep_a") && e.contains("qep_b"),
        "{e}"
    );
    assert!(e.starts_with("b.toml:"), "no location: {e}");
    // A header pin on the preset's oscillator ball.
    let mut w: Vec<(&str, &str)> = WIRING.to_vec();
    w[0] = ("qep_a", "E12");
    let e = Loaded::parse(&with_preset(&w), "b.toml")
        .expect_err("preset pin")
        .to_string();
    assert!(
        e.contains("E12") && e.contains("preset's pin for `clk`"),
        "{e}"
    );
    assert!(e.contains("key `board.pins.qep_a`"), "{e}");
    // A ball the FG484 package does not have (rows stop at AB, columns at 22).
    for bad in ["ZZ99", "AC1", "A23", "I5", "h1"] {
        let mut w: Vec<(&str, &str)> = WIRING.to_vec();
        w[4] = ("biss_slo", bad);
        let e = Loaded::parse(&with_preset(&w), "b.toml")
            .expect_err(bad)
            .to_string();
        assert!(e.contains(bad) && e.contains("XC3S700AN FGG484"), "{e}");
        assert!(!e.contains("One("), "Debug text: {e}");
        // Line and column of the key: `biss_slo = ...` is the last line of the config.
        let line = with_preset(&w).lines().count();
        assert!(e.starts_with(&format!("b.toml:{line}:1: ")), "{e}");
    }
    // An unknown I/O standard, and one of the other family.
    for bad in ["LVCMOS99", "3.3-V LVTTL"] {
        let t = with_preset(WIRING).replace(
            "[board]\npreset = \"spartan3an-starter-kit\"\n",
            &format!("[board]\npreset = \"spartan3an-starter-kit\"\niostandard = \"{bad}\"\n"),
        );
        let e = Loaded::parse(&t, "b.toml").expect_err(bad).to_string();
        assert!(e.contains(bad) && e.contains("LVCMOS33"), "{e}");
    }
}

#[test]
fn the_adc_round_trip_is_checked_and_constrained() {
    // 3 SCK clocks at 133.33 MHz = 22.50 ns; 9 + 2 x 1 + 8 + 3 = 22 ns fits ...
    let ok = with_preset(WIRING).replace(
        "[board]\npreset = \"spartan3an-starter-kit\"\n",
        "[board]\npreset = \"spartan3an-starter-kit\"\nfpga_clock_to_out_ns = 9.0\n",
    );
    let l = Loaded::parse(&ok, "b.toml").expect("fits");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let ucf = file(&g, "sd_top.ucf");
    assert!(
        ucf.contains("NET \"adc_sck\" OFFSET = OUT 9.00 ns AFTER \"clk\";"),
        "{ucf}"
    );
    assert!(
        ucf.contains("NET \"adc_miso\" OFFSET = IN 3.00 ns VALID 3.00 ns BEFORE \"clk\";"),
        "{ucf}"
    );
    // ... 10 + 2 + 8 + 3 = 23 ns does not: at least 4 clocks (30 ns).
    let bad = ok.replace("fpga_clock_to_out_ns = 9.0", "fpga_clock_to_out_ns = 10.0");
    let e = Loaded::parse(&bad, "b.toml")
        .expect_err("too tight")
        .to_string();
    assert!(e.contains("key `board.fpga_clock_to_out_ns`"), "{e}");
    assert!(e.starts_with("b.toml:"), "no location: {e}");
    assert!(e.contains("22.50 ns") && e.contains("23.00 ns"), "{e}");
    assert!(e.contains("at least 4 clocks"), "{e}");
    // A longer trace fails the same way and is blamed with its numbers.
    let bad = with_preset(WIRING).replace(
        "[board]\npreset = \"spartan3an-starter-kit\"\n",
        "[board]\npreset = \"spartan3an-starter-kit\"\ntrace_delay_ns = 3.0\n",
    );
    let e = Loaded::parse(&bad, "b.toml")
        .expect_err("trace")
        .to_string();
    assert!(
        e.contains("2 x board trace 3.00") && e.contains("23.00 ns"),
        "{e}"
    );
}

#[test]
fn the_cyclone_board_uses_its_package_and_a_pll_when_the_clock_differs() {
    // 50 MHz system clock from a 25 MHz oscillator: ALTPLL x 2 / 1.
    let l = Loaded::parse(&common::cap_board(Some("25e6"), "A1"), "c.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let qsf = file(&g, "cap_top.qsf");
    assert!(qsf.contains("TOP_LEVEL_ENTITY cap_board"), "{qsf}");
    assert!(
        qsf.contains("set_location_assignment PIN_A1 -to clk"),
        "{qsf}"
    );
    let sdc = file(&g, "cap_top.sdc");
    assert!(
        sdc.contains("create_clock -name clk -period 40.000 [get_ports clk]"),
        "{sdc}"
    );
    assert!(sdc.contains("derive_pll_clocks"), "{sdc}");
    let pll = file(&g, "cap_clock.v");
    for want in [
        "altpll #(",
        ".clk0_multiply_by(2)",
        ".clk0_divide_by(1)",
        ".inclk0_input_frequency(40000)",
    ] {
        assert!(pll.contains(want), "{want} missing:\n{pll}");
    }
    // The same oscillator as the system clock: no PLL, the SDC clock is the system clock.
    let l = Loaded::parse(&common::cap_board(None, "A1"), "c.toml").expect("parses");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    assert!(file(&g, "cap_top.qsf").contains("TOP_LEVEL_ENTITY cap_top"));
    let sdc = file(&g, "cap_top.sdc");
    assert!(sdc.contains("-period 20.000 [get_ports clk]"), "{sdc}");
    assert!(
        sdc.contains("set_input_delay -clock [get_clocks clk] -max 17.000 [get_ports adc_miso]"),
        "{sdc}"
    );
    assert!(!g.files.iter().any(|f| f.name == "cap_clock.v"));
    // W1 is a ball of the FG484 but not of the F324 (its rows end at V).
    let e = Loaded::parse(&common::cap_board(None, "W1"), "c.toml")
        .expect_err("W1")
        .to_string();
    assert!(e.contains("W1") && e.contains("EP3C40F324"), "{e}");
}
