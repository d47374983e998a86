//! `[board]`: the UCF of `<name>_top` lists every pin with its I/O standard and the clock
//! period; a missing pin is rejected with the port's name and nothing is written.
use sinedec::config::{Loaded, DEFAULT_CONFIG, TOP_PINS};

fn with_board(skip: Option<&str>) -> String {
    let mut t = DEFAULT_CONFIG.to_string();
    t.push_str("\n[board]\niostandard = \"LVCMOS33\"\n[board.pins]\n");
    for (i, p) in TOP_PINS.iter().enumerate() {
        if Some(*p) != skip {
            t.push_str(&format!("{p} = \"P{}\"\n", 10 + i));
        }
    }
    t
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
    for (i, p) in TOP_PINS.iter().enumerate() {
        let line = format!("NET \"{p}\" LOC = \"P{}\" | IOSTANDARD = LVCMOS33;", 10 + i);
        assert!(ucf.contains(&line), "{line} missing:\n{ucf}");
    }
    // 133.33 MHz -> 7.500 ns.
    assert!(ucf.contains("PERIOD \"clk\" 7.500 ns"), "{ucf}");
    // Every top port with a pin exists in the emitted top.
    let top = &g
        .files
        .iter()
        .find(|f| f.name == "sd_top.v")
        .expect("top")
        .text;
    for p in TOP_PINS {
        assert!(
            top.contains(&format!(" {p},")) || top.contains(&format!(" {p} ")),
            "{p} not a port"
        );
    }
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
    TOP_PINS
        .iter()
        .filter(|p| !KIT.iter().any(|(k, _)| k == *p))
        .enumerate()
        .map(|(i, p)| (*p, format!("H{}", i + 1)))
        .collect()
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
    let expected: Vec<&str> = user_pins().iter().map(|(k, _)| *k).collect();
    assert!(
        msg.contains(&format!(
            "pins missing for the board: {}",
            expected.join(", ")
        )),
        "{msg}"
    );
    for (k, _) in KIT {
        assert!(
            !msg.contains(&format!(" {k},")),
            "{k} is the preset's: {msg}"
        );
    }
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
