//! `[board]`: the UCF of `<name>_top` lists every pin with its I/O standard and the clock
//! period; a missing pin is rejected with the port's name and nothing is written. The
//! wrapper declares only the ports the configuration uses (QEP, SSI, SPI slave, pinned
//! deselect lines), each with a LOC; the kit preset adds the BitGen option file.
//!
//! (Second half of the tests of `tests/cli/board.rs`; helpers in `tests/cli/board_util/`.)

use crate::board_util;
use crate::common;
use board_util::*;
use sinedec::config::Loaded;

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
    let log = common::icarus_output(
        &dir,
        "tb",
        &["tb.v", "sd_board.v", "sd_clock_sim.v", "sd_top.v"],
    );
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
    assert_eq!(l.derived.adc.sck_period_clocks, 3);
    // ... 10 + 2 + 8 + 3 = 23 ns does not: without adc.sck_period_clocks the divider that
    // covers it, 4 clocks (30 ns), is chosen; set to 3 clocks the config is refused there.
    let slow = ok.replace("fpga_clock_to_out_ns = 9.0", "fpga_clock_to_out_ns = 10.0");
    let l = Loaded::parse(&slow, "b.toml").expect("a 4-clock SCK fits");
    assert_eq!(l.derived.adc.sck_period_clocks, 4);
    let three = |t: &str| t.replacen("# sck_period_clocks = 3", "sck_period_clocks = 3", 1);
    let bad = three(&slow);
    let e = Loaded::parse(&bad, "b.toml")
        .expect_err("too tight")
        .to_string();
    assert!(e.contains("key `adc.sck_period_clocks`"), "{e}");
    assert!(e.starts_with("b.toml:"), "no location: {e}");
    assert!(e.contains("22.50 ns") && e.contains("23.00 ns"), "{e}");
    assert!(e.contains("at least 4 clocks"), "{e}");
    // A longer trace fails the same way and is blamed with its numbers.
    let bad = three(&with_preset(WIRING).replace(
        "[board]\npreset = \"spartan3an-starter-kit\"\n",
        "[board]\npreset = \"spartan3an-starter-kit\"\ntrace_delay_ns = 3.0\n",
    ));
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
