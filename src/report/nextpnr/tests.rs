use super::*;

/// A log in nextpnr-ecp5 0.11's format (abridged by hand): a placement-time estimate,
/// then the post-route report. The path: 0.52 clk-to-q, 1.18 routing, 0.45 + 0.07 + 0.40
/// logic (two carry steps and a sum), 0.00 dedicated carry net, 0.41 routing, 0.24 LUT,
/// 0.53 routing: logic 1.68, routing 2.12 over 3 routed nets.
const LOG: &str = "Info: Max frequency for clock 'clk': 140.00 MHz (PASS at 133.33 MHz)
Info: Critical path report for clock 'clk' (posedge -> posedge):
Info:       type curr  total name
Info:   clk-to-q  0.52  0.52 Source early_TRELLIS_FF_Q.Q
Info:      setup  0.00  0.52 Source late_TRELLIS_FF_Q.DI
Info: 0.52 ns logic, 0.00 ns routing

Info: Critical path report for clock 'clk' (posedge -> posedge):
Info:       type curr  total name
Info:   clk-to-q  0.52  0.52 Source rtl.combiner.p_reg.q_TRELLIS_FF_Q_1.Q
Info:    routing  1.18  1.70 Net rtl.combiner.p_reg.q[0] (46,16) -> (47,15)
Info:                          Sink rtl.counter.x_CCU2C_S1$CCU2_COMB0.A
Info:                          Defined in:
Info:                               sd_core.v:870.24-870.25
Info:      logic  0.45  2.15 Source rtl.counter.x_CCU2C_S1$CCU2_COMB0.FCO
Info:    routing  0.00  2.15 Net rtl.counter.x_CCU2C_S1$CCU2_FCI_INT (47,15) -> (47,15)
Info:                          Sink rtl.counter.x_CCU2C_S1$CCU2_COMB1.FCI
Info:      logic  0.07  2.22 Source rtl.counter.x_CCU2C_S1$CCU2_COMB1.FCO
Info:      logic  0.40  2.62 Source rtl.counter.y_CCU2C_S0$CCU2_COMB1.F
Info:    routing  0.41  3.03 Net rtl.counter.y_S1[1] (47,14) -> (49,14)
Info:                          Sink rtl.counter.usum_TRELLIS_FF_Q_CE_LUT4_Z.D
Info:      logic  0.24  3.27 Source rtl.counter.usum_TRELLIS_FF_Q_CE_LUT4_Z.F
Info:    routing  0.53  3.80 Net rtl.counter.usum_TRELLIS_FF_Q_CE (49,14) -> (51,14)
Info:                          Sink rtl.counter.usum_TRELLIS_FF_Q_9.CE
Info:      setup  0.00  3.80 Source rtl.counter.usum_TRELLIS_FF_Q_9.CE
Info: 1.68 ns logic, 2.12 ns routing

Info: Critical path report for cross-domain path '<async>' -> 'posedge clk':
Info:       type curr  total name
Info:   routing  9.00  9.00 Net in_sin[3] (0,0) -> (1,1)
Info:      setup  0.00  9.00 Source port_TRELLIS_FF_Q.DI
Info: 0.00 ns logic, 9.00 ns routing

Warning: Max frequency for clock 'clk': 263.16 MHz (FAIL at 300.00 MHz)
";

#[test]
fn log_gives_the_post_route_figures() {
    let t = parse_log(LOG, 300.0).expect("parsed");
    // The last Max frequency line is the post-route one.
    assert_eq!(t.fmax_mhz, Some(263.16));
    assert_eq!(t.from_cell, "rtl.combiner.p_reg.q_TRELLIS_FF_Q_1");
    assert_eq!(t.to_cell, "rtl.counter.usum_TRELLIS_FF_Q_9");
    assert_eq!(t.logic_ns, 1.68);
    assert_eq!(t.routing_ns, 2.12);
    // 1.18, 0.41, 0.53: the 0.00 carry net is dedicated.
    assert_eq!(t.routed_nets, 3);
    // 1000/300 - 1000/263.16 = 3.3333 - 3.8000 = -0.4667 ns.
    let s = t.slack_ns().unwrap();
    assert!((s - (-0.46667)).abs() < 1e-3, "{s}");
    assert!((t.routing_per_net_ns().unwrap() - 2.12 / 3.0).abs() < 1e-12);
    assert_eq!(t.from_register(), "rtl.combiner.p_reg.q");
    assert_eq!(t.to_register(), "rtl.counter.usum");
}

#[test]
fn rule_takes_the_median_and_every_seed() {
    // 133.33 MHz: the median must reach 166.66 MHz and every seed 153.33 MHz.
    let c = 133.33;
    assert_eq!(
        median_mhz(&[Some(170.0), Some(160.0), Some(180.0)]),
        Some(170.0)
    );
    assert_eq!(median_mhz(&[None, Some(160.0), Some(180.0)]), Some(160.0));
    assert_eq!(median_mhz(&[None, None, None]), None);
    assert!(check_rule(&[Some(170.0), Some(160.0), Some(180.0)], c).is_ok());
    // Median 165 < 166.66: fails although two seeds pass.
    let e = check_rule(&[Some(165.0), Some(160.0), Some(180.0)], c).unwrap_err();
    assert!(e.contains("median 165.00"), "{e}");
    // One seed at 150 < 153.33 fails although the median passes.
    let e = check_rule(&[Some(170.0), Some(150.0), Some(180.0)], c).unwrap_err();
    assert!(e.contains("seed 2 150.00"), "{e}");
    assert!(check_rule(&[Some(170.0), None, Some(180.0)], c).is_err());
    assert_eq!(
        seeds_text(&[Some(170.0), None, Some(180.25)]),
        "170.00 / no / 180.25"
    );
}

#[test]
fn log_without_timing_is_none() {
    assert_eq!(parse_log("Info: Routing complete.\n", 100.0), None);
}

#[test]
fn registers_are_named_by_block() {
    assert_eq!(
        register_name("rtl.counter.usum_TRELLIS_FF_Q_3"),
        "rtl.counter.usum"
    );
    assert_eq!(register_name("q_TRELLIS_FF_Q_14_DI_MULT18X18D_P15"), "q");
    assert_eq!(register_name("rtl.a.b[7]"), "rtl.a.b");
    assert_eq!(register_name("x$CCU2_COMB0"), "x");
    assert_eq!(block_of("rtl.counter.usum"), "counter");
    assert_eq!(block_of("rtl.combiner.p_reg.q"), "combiner");
    assert_eq!(block_of("rtl.core.counter.turns_reg.q"), "core.counter");
    assert_eq!(block_of("out_turns"), "(top level)");
    assert_eq!(block_of("rtl.q"), "(top level)");
    assert_eq!(block_of("$auto$ff.cc:266:slice$2200"), "(top level)");
}

#[test]
fn tools_are_found_in_the_configured_order() {
    let root = std::env::temp_dir().join(format!("sinedec-locate-{}", std::process::id()));
    let a = root.join("a");
    let venv = root.join("cache").join("sinedec").join("venv").join("bin");
    let p = root.join("p");
    for d in [&a, &venv, &p] {
        std::fs::create_dir_all(d).unwrap();
        std::fs::write(d.join(NEXTPNR), "").unwrap();
    }
    let path = std::env::join_paths([&p]).unwrap();
    let env = Some(a.clone().into_os_string());
    let cache = Some(root.join("cache"));
    assert_eq!(
        locate(NEXTPNR, env.clone(), cache.clone(), Some(path.clone())),
        Some(a.join(NEXTPNR))
    );
    assert_eq!(
        locate(NEXTPNR, None, cache.clone(), Some(path.clone())),
        Some(venv.join(NEXTPNR))
    );
    assert_eq!(
        locate(NEXTPNR, None, None, Some(path.clone())),
        Some(p.join(NEXTPNR))
    );
    assert_eq!(locate(YOSYS, env, cache, Some(path)), None);
    let _ = std::fs::remove_dir_all(&root);
}
