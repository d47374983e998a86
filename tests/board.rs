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
