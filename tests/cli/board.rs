//! `[board]`: the UCF of `<name>_top` lists every pin with its I/O standard and the clock
//! period; a missing pin is rejected with the port's name and nothing is written. The
//! wrapper declares only the ports the configuration uses (QEP, SSI, SPI slave, pinned
//! deselect lines), each with a LOC; the kit preset adds the BitGen option file.
//!
//! (More tests in `tests/cli/board_clock_pins.rs`; the helpers are in `tests/cli/board_util/`.)

use crate::board_util;
use board_util::*;
use sinedec::config::{Loaded, DEFAULT_CONFIG, QEP_PINS};

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
    let kit = kit_pins();
    let l = Loaded::parse(&board(&base, &kit), "b.toml").expect("no QEP pins needed");
    let g = sinedec::emit::generate(&l, "test").expect("generates");
    let (top, ucf) = (file(&g, "sd_top.v"), file(&g, "sd_top.ucf"));
    assert_eq!(pinned_ports(top), sorted(&kit));
    for p in QEP_PINS {
        assert!(!ucf.contains(p), "{p} in the UCF:\n{ucf}");
        assert!(top.contains(&format!(".{p}(1'b0)")), "{p} not tied low");
    }
    assert_eq!(ucf_tigs(ucf), vec!["biss_ma".to_string()]);
    // A QEP pin is then not a port of the top.
    let mut with_qep: Vec<&str> = kit.clone();
    with_qep.push("qep_a");
    let e = Loaded::parse(&board(&base, &with_qep), "b.toml").expect_err("qep_a not a port");
    assert!(e.to_string().contains("qep_a"), "{e}");

    // SSI and the SPI slave: their pins are required, named when missing, and present.
    let ssi = in_section(&base, "[ssi]", "enabled = false", "enabled = true");
    let both = in_section(&ssi, "[spi]", "enabled = false", "enabled = true");
    let e = Loaded::parse(&board(&ssi, &kit), "b.toml").expect_err("ssi pins missing");
    assert!(
        e.to_string()
            .contains("pins missing for the board: ssi_clk, ssi_data (every port"),
        "{e}"
    );
    let spi = ["enc_sck", "enc_cs_n", "enc_miso", "enc_miso_oe"];
    let mut all: Vec<&str> = kit.clone();
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

/// Pin errors say which part is wrong (they used to give one paragraph for every case): the
/// ball is not in the package; the port is not in this configuration (and which section
/// turns it on); the value is one ball for a bus, or a list of the wrong length. Each names
/// the key at its line.
#[test]
fn pin_errors_say_which_part_is_wrong() {
    let generic = "the key must be one of the top's ports";
    let check = |text: &str, key: &str, needle: &str, says: &[&str]| {
        let e = Loaded::parse(text, "b.toml").expect_err(needle);
        let m = e.to_string();
        let off = text.find(needle).expect("needle");
        assert_eq!(text.matches(needle).count(), 1, "{needle}");
        let line = text[..off].matches('\n').count() + 1;
        assert!(m.starts_with(&format!("b.toml:{line}:")), "{m}");
        assert!(m.contains(&format!("`{key}`")), "{m}");
        for s in says {
            assert!(m.contains(s), "{needle}: {m:?} should say {s:?}");
        }
        assert!(!m.contains(generic), "{m}");
    };
    let sine = |extra: &str| format!("{}{extra}\n", with_board(Some("biss_ma")));
    check(
        &sine("biss_ma = \"ZZ99\""),
        "board.pins.biss_ma",
        "biss_ma = \"ZZ99\"",
        &[
            "\"ZZ99\" is not a ball of the XC3S700AN FGG484",
            "data/packages/xc3s700an_fg484.txt",
        ],
    );
    check(
        &sine("biss_ma = \"A1\"\nssi_clk = \"A2\""),
        "board.pins.ssi_clk",
        "ssi_clk = \"A2\"",
        &["not a port of this configuration", "[ssi] enabled = true"],
    );
    check(
        &sine("biss_ma = \"A1\"\nled7 = \"A2\""),
        "board.pins.led7",
        "led7 = \"A2\"",
        &["no port `led7`", "biss_slo"],
    );
    check(
        &sine("biss_ma = [\"A1\", \"A2\"]"),
        "board.pins.biss_ma",
        "biss_ma = [\"A1\", \"A2\"]",
        &["one ball", "2 given"],
    );
    // The capacitive top's DAC buses: capacitive.dac_width balls each.
    let cap = format!(
        "{}\n[board]\niostandard = \"{}\"\n[board.pins]\n",
        include_str!("../../configs/cyclone3_capacitive.toml"),
        sinedec::board::iostandards(sinedec::config::Target::Cyclone3)[0]
    );
    check(
        &format!("{cap}exc_sin = [\"A1\", \"A2\", \"A3\"]\n"),
        "board.pins.exc_sin",
        "exc_sin = [",
        &["16-bit bus", "16 balls", "3 given"],
    );
    check(
        &format!("{cap}exc_cos = \"A1\"\n"),
        "board.pins.exc_cos",
        "exc_cos = \"A1\"",
        &["16-bit bus", "16 balls"],
    );
}
