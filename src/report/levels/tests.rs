//! Tests of the path timing: hand-built netlists with round-number delays.
use super::*;

/// A model with round numbers so the expected delays are easy to check by hand.
const M: DelayModel = DelayModel {
    name: "test",
    tcko_ps: 1000,
    tsu_ps: 100,
    lut_ps: 10_000,
    carry_entry_ps: 200,
    carry_bit_ps: 20,
    carry_sum_ps: 300,
    mux_ps: 400,
    mult_ps: 50_000,
    ram_tco_ps: 2000,
    route_ps: 1,
};

fn cell(ty: &str, conns: &[(&str, bool, &[u64])]) -> Value {
    let mut dirs = serde_json::Map::new();
    let mut c = serde_json::Map::new();
    for (p, out, bs) in conns {
        dirs.insert(
            p.to_string(),
            Value::from(if *out { "output" } else { "input" }),
        );
        c.insert(p.to_string(), Value::from(bs.to_vec()));
    }
    serde_json::json!({"type": ty, "port_directions": dirs, "connections": c})
}

fn netlist(cells: Vec<(&str, Value)>, nets: &[(&str, &[u64])]) -> String {
    let mut cs = serde_json::Map::new();
    for (n, c) in cells {
        cs.insert(n.to_string(), c);
    }
    let mut nn = serde_json::Map::new();
    for (n, b) in nets {
        nn.insert(n.to_string(), serde_json::json!({"bits": b.to_vec()}));
    }
    serde_json::json!({"modules": {"t": {"cells": cs, "netnames": nn}}}).to_string()
}

/// Two registers a, b -> LUT2 -> LUT2 -> FD q: two LUT levels, three routed nets
/// (a -> LUT, LUT -> LUT; the last LUT sits beside the FF). A shorter path b -> FD r
/// through one LUT loses.
#[test]
fn two_lut_levels() {
    let j = netlist(
        vec![
            (
                "fa",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[90]), ("Q", true, &[10])],
                ),
            ),
            (
                "fb",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[91]), ("Q", true, &[11])],
                ),
            ),
            (
                "l1",
                cell(
                    "LUT2",
                    &[
                        ("I0", false, &[10]),
                        ("I1", false, &[11]),
                        ("O", true, &[12]),
                    ],
                ),
            ),
            (
                "l2",
                cell(
                    "LUT2",
                    &[
                        ("I0", false, &[12]),
                        ("I1", false, &[11]),
                        ("O", true, &[13]),
                    ],
                ),
            ),
            (
                "fq",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[13]), ("Q", true, &[14])],
                ),
            ),
            (
                "l3",
                cell("LUT1", &[("I0", false, &[11]), ("O", true, &[15])]),
            ),
            (
                "fr",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[15]), ("Q", true, &[16])],
                ),
            ),
        ],
        &[
            ("a", &[10]),
            ("b", &[11]),
            ("q", &[14]),
            ("r", &[16]),
            ("$auto$x", &[10]),
        ],
    );
    let p = analyze_with(&j, "t", &M).unwrap().unwrap();
    assert_eq!(p.lut_levels, 2);
    assert_eq!(p.carry_bits, 0);
    // tcko + route + lut + route + lut + (no route: LUT beside FF) + tsu
    assert_eq!(p.delay_ps, 1000 + 1 + 10_000 + 1 + 10_000 + 100);
    assert_eq!(p.routed_nets, 2);
    assert_eq!(p.from, "a");
    assert_eq!(p.to, "q");
}

/// A 3-bit ripple adder on MUXCY/XORCY from register x to register s2: LUT (S) ->
/// MUXCY (entry) -> MUXCY (bit) -> MUXCY (bit) -> XORCY -> FD: one LUT level, three carry
/// bits, one chain.
#[test]
fn carry_chain_bits() {
    let j = netlist(
        vec![
            (
                "fx",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[90]), ("Q", true, &[10])],
                ),
            ),
            (
                "l0",
                cell(
                    "LUT2",
                    &[
                        ("I0", false, &[10]),
                        ("I1", false, &[10]),
                        ("O", true, &[20]),
                    ],
                ),
            ),
            (
                "m0",
                cell(
                    "MUXCY",
                    &[
                        ("CI", false, &[]),
                        ("DI", false, &[10]),
                        ("S", false, &[20]),
                        ("O", true, &[21]),
                    ],
                ),
            ),
            (
                "m1",
                cell(
                    "MUXCY",
                    &[
                        ("CI", false, &[21]),
                        ("DI", false, &[10]),
                        ("S", false, &[20]),
                        ("O", true, &[22]),
                    ],
                ),
            ),
            (
                "m2",
                cell(
                    "MUXCY",
                    &[
                        ("CI", false, &[22]),
                        ("DI", false, &[10]),
                        ("S", false, &[20]),
                        ("O", true, &[23]),
                    ],
                ),
            ),
            (
                "x3",
                cell(
                    "XORCY",
                    &[
                        ("CI", false, &[23]),
                        ("LI", false, &[20]),
                        ("O", true, &[24]),
                    ],
                ),
            ),
            (
                "fs",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[24]), ("Q", true, &[25])],
                ),
            ),
        ],
        &[("x", &[10]), ("s", &[99, 98, 25])],
    );
    let p = analyze_with(&j, "t", &M).unwrap().unwrap();
    assert_eq!((p.lut_levels, p.carry_bits, p.carry_chains), (1, 3, 1));
    // tcko + route + LUT + entry + 2 bits + sum + tsu (LUT->S, carry, XORCY->FF dedicated)
    assert_eq!(p.delay_ps, 1000 + 1 + 10_000 + 200 + 40 + 300 + 100);
    assert_eq!(p.routed_nets, 1);
    assert_eq!(p.to, "s[2]");
    assert_eq!(p.from, "x");
}

/// Cyclone LEs: reg -> lcell (data -> cout) -> lcell (cin -> cout) -> lcell (cin ->
/// combout) -> lcell (LUT) -> dffeas: 2 LUT levels (the entry LE's LUT and the last),
/// 2 carry bits, one chain.
#[test]
fn cyclone_lcells() {
    let lc = |i: &[(&str, &[u64])], o: &[(&str, &[u64])]| {
        let mut v: Vec<(&str, bool, &[u64])> = i.iter().map(|(p, b)| (*p, false, *b)).collect();
        v.extend(o.iter().map(|(p, b)| (*p, true, *b)));
        cell("cycloneive_lcell_comb", &v)
    };
    let j = netlist(
        vec![
            (
                "f0",
                cell(
                    "dffeas",
                    &[
                        ("clk", false, &[1]),
                        ("d", false, &[90]),
                        ("q", true, &[10]),
                    ],
                ),
            ),
            ("c0", lc(&[("dataa", &[10])], &[("cout", &[20])])),
            (
                "c1",
                lc(&[("dataa", &[10]), ("cin", &[20])], &[("cout", &[21])]),
            ),
            (
                "c2",
                lc(&[("dataa", &[10]), ("cin", &[21])], &[("combout", &[22])]),
            ),
            ("c3", lc(&[("dataa", &[22])], &[("combout", &[23])])),
            (
                "f1",
                cell(
                    "dffeas",
                    &[
                        ("clk", false, &[1]),
                        ("d", false, &[23]),
                        ("q", true, &[24]),
                    ],
                ),
            ),
        ],
        &[("r0", &[10]), ("r1", &[24])],
    );
    let p = analyze_with(&j, "t", &M).unwrap().unwrap();
    assert_eq!((p.lut_levels, p.carry_bits, p.carry_chains), (2, 2, 1));
    // tcko + route + (LUT + entry) + bit + sum + route + LUT + tsu
    assert_eq!(p.delay_ps, 1000 + 1 + 10_200 + 20 + 300 + 1 + 10_000 + 100);
}

/// Two chains in series (as in an add followed by a compare) count as two chains.
#[test]
fn two_chains_in_series() {
    let j = netlist(
        vec![
            (
                "fx",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[90]), ("Q", true, &[10])],
                ),
            ),
            (
                "l0",
                cell(
                    "LUT2",
                    &[
                        ("I0", false, &[10]),
                        ("I1", false, &[10]),
                        ("O", true, &[20]),
                    ],
                ),
            ),
            (
                "m0",
                cell(
                    "MUXCY",
                    &[
                        ("CI", false, &[]),
                        ("DI", false, &[10]),
                        ("S", false, &[20]),
                        ("O", true, &[21]),
                    ],
                ),
            ),
            (
                "x0",
                cell(
                    "XORCY",
                    &[
                        ("CI", false, &[21]),
                        ("LI", false, &[20]),
                        ("O", true, &[22]),
                    ],
                ),
            ),
            (
                "l1",
                cell(
                    "LUT2",
                    &[
                        ("I0", false, &[22]),
                        ("I1", false, &[10]),
                        ("O", true, &[30]),
                    ],
                ),
            ),
            (
                "m1",
                cell(
                    "MUXCY",
                    &[
                        ("CI", false, &[]),
                        ("DI", false, &[10]),
                        ("S", false, &[30]),
                        ("O", true, &[31]),
                    ],
                ),
            ),
            (
                "m2",
                cell(
                    "MUXCY",
                    &[
                        ("CI", false, &[31]),
                        ("DI", false, &[10]),
                        ("S", false, &[30]),
                        ("O", true, &[32]),
                    ],
                ),
            ),
            (
                "fy",
                cell(
                    "FDRE",
                    &[
                        ("C", false, &[1]),
                        ("CE", false, &[32]),
                        ("D", false, &[10]),
                        ("Q", true, &[33]),
                    ],
                ),
            ),
        ],
        &[("x", &[10]), ("y", &[33])],
    );
    let p = analyze_with(&j, "t", &M).unwrap().unwrap();
    assert_eq!((p.lut_levels, p.carry_bits, p.carry_chains), (2, 3, 2));
}

#[test]
fn no_register_path_is_none() {
    let j = netlist(
        vec![("l", cell("LUT1", &[("I0", false, &[2]), ("O", true, &[3])]))],
        &[("a", &[2])],
    );
    assert_eq!(analyze_with(&j, "t", &M).unwrap(), None);
    assert!(analyze_with(&j, "nope", &M).is_err());
}

/// A loop of two LUTs between a register and a register is a typed tool-output error that
/// names the loop, not a hang or a panic.
#[test]
fn combinational_loop_is_a_tool_output_error() {
    let j = netlist(
        vec![
            (
                "fa",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[5]), ("Q", true, &[2])],
                ),
            ),
            (
                "l1",
                cell(
                    "LUT2",
                    &[("I0", false, &[2]), ("I1", false, &[4]), ("O", true, &[3])],
                ),
            ),
            (
                "l2",
                cell("LUT1", &[("I0", false, &[3]), ("O", true, &[4])]),
            ),
            (
                "fb",
                cell(
                    "FDRE",
                    &[("C", false, &[1]), ("D", false, &[4]), ("Q", true, &[5])],
                ),
            ),
        ],
        &[("q", &[2])],
    );
    match analyze_with(&j, "t", &M) {
        Err(Error::ToolOutput { tool, message }) => {
            assert_eq!(tool, "yosys");
            assert!(message.contains("combinational loop"), "{message}");
        }
        other => panic!("expected a tool-output error, got {other:?}"),
    }
}
