//! Worst register-to-register path of a Yosys-mapped netlist (xc3sa or cycloneive), as LUT
//! levels plus carry bits, and an estimated Fmax from the delay model of `docs/timing.md`.
//!
//! The netlist is the flattened module of `write_json`. Every net bit gets an arrival time:
//!
//! ```text
//!   FF Q / RAM DO ............ clock-to-out (start of a path)
//!   comb cell output ......... max over its inputs of (arrival + routing + cell arc)
//!   FF D/CE/R/S, RAM inputs .. arrival + routing + setup (end of a path)
//! ```
//!
//! Cell arcs ([`Arc`]): a LUT (LUT1..4, INV; a `cycloneive_lcell_comb` data input to
//! `combout`) is one LUT level; a carry step (MUXCY `CI -> O`, lcell `cin -> cout`) is one
//! carry bit; entering a chain (MUXCY `S`/`DI -> O`, lcell data input to `cout`) starts a
//! carry chain and is one carry bit (and, on Cyclone, one LUT level: the LE's LUT computes
//! the carry); the sum (XORCY, lcell `cin -> combout`) is neither; MUXF5..8 are wide-function
//! multiplexers; a combinational multiplier (MULT18X18) is one multiplier. Routing: every
//! net into a general-purpose input adds [`DelayModel::route_ps`]; the slice-internal
//! connections (LUT to carry, carry to carry, LUT to MUXF5, LUT/XORCY to the FF beside it)
//! add nothing. Paths from or to ports are not register-to-register and are ignored.
//!
//! The result is the path with the largest modelled delay, with its LUT levels, carry bits,
//! carry chains, multiplexers, multipliers and routed nets, and its start and end registers.
use crate::synth::Family;
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::HashMap;

/// Cell and routing delays of one family and speed grade, in picoseconds (sources and
/// calibration in `docs/timing.md`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct DelayModel {
    /// Family, speed grade and data sheet.
    pub name: &'static str,
    /// Flip-flop clock to output.
    pub tcko_ps: u64,
    /// Flip-flop setup (data input, LUT already counted).
    pub tsu_ps: u64,
    /// One LUT.
    pub lut_ps: u64,
    /// Entering a carry chain (MUXCY select/data to out; Cyclone: the LUT's carry out).
    pub carry_entry_ps: u64,
    /// One carry bit along the chain.
    pub carry_bit_ps: u64,
    /// Carry to sum output (XORCY, lcell `cin -> combout`).
    pub carry_sum_ps: u64,
    /// One wide-function multiplexer (MUXF5..8).
    pub mux_ps: u64,
    /// A combinational hard multiplier, input to output.
    pub mult_ps: u64,
    /// Block RAM clock to output.
    pub ram_tco_ps: u64,
    /// Routing per net (calibrated against nextpnr-ecp5, `docs/timing.md`).
    pub route_ps: u64,
}

/// Spartan-3A/3AN, speed grade -4 (DS529 / DS557 switching characteristics).
pub const XC3SA_4: DelayModel = DelayModel {
    name: "Spartan-3A/3AN -4",
    tcko_ps: 630,
    tsu_ps: 400,
    lut_ps: 710,
    carry_entry_ps: 430,
    carry_bit_ps: 80,
    carry_sum_ps: 560,
    mux_ps: 450,
    mult_ps: 4880,
    ram_tco_ps: 2400,
    route_ps: 810,
};

/// Cyclone III (the EP3C40F324C8 of the capacitive preset). The Cyclone III handbook's data
/// sheet publishes no LE-level delays; these are the Quartus II 11.1 (Chip Planner) figures
/// of FloPoCo's Cyclone III target (`src/Targets/CycloneIII.hpp`), which states no speed
/// grade: LUT 0.436 ns, carry 0.058 ns per bit, carry-in to sum 0.455 ns, clock to Q
/// 0.352 ns (marked TODO there), 18x18 multiplier 2.860 ns with its 0.265 ns output
/// register (2.595 ns combinational), M9K 2.792 ns. Setup is not in that source: 0.20 ns is
/// an estimate. MUXF cells do not occur in the cycloneive mapping. See `docs/timing.md`.
pub const CYCLONE3_C8: DelayModel = DelayModel {
    name: "Cyclone III (Quartus II 11.1 figures)",
    tcko_ps: 352,
    tsu_ps: 200,
    lut_ps: 436,
    carry_entry_ps: 0,
    carry_bit_ps: 58,
    carry_sum_ps: 455,
    mux_ps: 450,
    mult_ps: 2595,
    ram_tco_ps: 2792,
    route_ps: 497,
};

/// The delay model of a family.
pub fn model(family: Family) -> &'static DelayModel {
    match family {
        Family::Xc3sa => &XC3SA_4,
        Family::CycloneIve => &CYCLONE3_C8,
    }
}

/// The worst register-to-register path.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct PathLevels {
    /// LUT levels.
    pub lut_levels: u32,
    /// Carry bits (every carry cell the path passes, the entry included).
    pub carry_bits: u32,
    /// Carry chains entered.
    pub carry_chains: u32,
    /// Wide-function multiplexers (MUXF5..8).
    pub muxes: u32,
    /// Combinational multipliers.
    pub multipliers: u32,
    /// Routed nets.
    pub routed_nets: u32,
    /// Modelled delay, clock-to-out and setup included (ps).
    pub delay_ps: u64,
    /// Start register (net name of its output, with the bit).
    pub from: String,
    /// End register.
    pub to: String,
}

impl PathLevels {
    /// Estimated Fmax from the modelled delay.
    pub fn fmax_mhz(&self) -> f64 {
        if self.delay_ps == 0 {
            0.0
        } else {
            1.0e6 / self.delay_ps as f64
        }
    }
}

/// Kind of a cell arc.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arc {
    /// Through a LUT.
    Lut,
    /// Into a carry chain (Cyclone: through the LUT into the chain).
    CarryEntry {
        /// The arc passes the LE's LUT too (Cyclone).
        through_lut: bool,
    },
    /// Along the carry chain.
    CarryBit,
    /// Carry to sum.
    CarrySum,
    /// Wide-function multiplexer.
    Mux,
    /// Combinational multiplier.
    Mult,
    /// No delay, no level (an inverter Yosys left for the LUT to absorb).
    Wire,
}

/// What a cell is for the analysis.
enum Role {
    /// Flip-flop or synchronous RAM: outputs start paths, these inputs end them.
    Seq {
        tco_ps: u64,
        ends: &'static [&'static str],
    },
    /// Combinational cell.
    Comb,
    /// Not timed (I/O buffers, clock buffers, constants).
    None,
}

fn role(t: &str, m: &DelayModel) -> Role {
    match t {
        _ if t.starts_with("FD") => Role::Seq {
            tco_ps: m.tcko_ps,
            ends: &["D", "CE", "R", "S"],
        },
        "dffeas" => Role::Seq {
            tco_ps: m.tcko_ps,
            ends: &["d", "ena", "sclr", "sload", "asdata"],
        },
        _ if t.starts_with("RAMB16") => Role::Seq {
            tco_ps: m.ram_tco_ps,
            ends: &[
                "ADDR", "DI", "DIP", "EN", "SSR", "WE", "ADDRA", "ADDRB", "DIA", "DIB", "DIPA",
                "DIPB", "ENA", "ENB", "SSRA", "SSRB", "WEA", "WEB",
            ],
        },
        _ if t.starts_with("cycloneive_ram_block") || t == "altsyncram" => Role::Seq {
            tco_ps: m.ram_tco_ps,
            ends: &[
                "portadatain",
                "portaaddr",
                "portawe",
                "portbdatain",
                "portbaddr",
                "portbwe",
                "portare",
                "portbre",
                "data_a",
                "address_a",
                "wren_a",
                "data_b",
                "address_b",
                "wren_b",
                "rden_a",
                "rden_b",
            ],
        },
        _ if t.starts_with("LUT")
            || t == "INV"
            || t == "MUXCY"
            || t == "XORCY"
            || t.starts_with("MUXF")
            || t == "MULT18X18"
            || t == "cycloneive_lcell_comb"
            || t == "$not"
            || t == "$_NOT_" =>
        {
            Role::Comb
        }
        _ => Role::None,
    }
}

/// The arc of a combinational cell from input `i` to output `o` (None: no arc).
pub fn arc(t: &str, i: &str, o: &str) -> Option<Arc> {
    match t {
        _ if t.starts_with("LUT") || t == "INV" => Some(Arc::Lut),
        "MUXCY" => Some(if i == "CI" {
            Arc::CarryBit
        } else {
            Arc::CarryEntry { through_lut: false }
        }),
        "XORCY" => Some(Arc::CarrySum),
        _ if t.starts_with("MUXF") => Some(Arc::Mux),
        "MULT18X18" => Some(Arc::Mult),
        "$not" | "$_NOT_" => Some(Arc::Wire),
        "cycloneive_lcell_comb" => match (i, o) {
            ("cin", "cout") => Some(Arc::CarryBit),
            ("cin", "combout") => Some(Arc::CarrySum),
            (_, "cout") => Some(Arc::CarryEntry { through_lut: true }),
            (_, "combout") => Some(Arc::Lut),
            _ => None,
        },
        _ => None,
    }
}

fn arc_ps(a: Arc, m: &DelayModel) -> u64 {
    match a {
        Arc::Lut => m.lut_ps,
        Arc::CarryEntry { through_lut } => {
            m.carry_entry_ps + if through_lut { m.lut_ps } else { 0 }
        }
        Arc::CarryBit => m.carry_bit_ps,
        Arc::CarrySum => m.carry_sum_ps,
        Arc::Mux => m.mux_ps,
        Arc::Mult => m.mult_ps,
        Arc::Wire => 0,
    }
}

/// Whether the connection from a cell of type `driver` into input `pin` of a `sink` cell
/// uses general routing (false: a dedicated connection inside the slice or LE).
pub fn routed(driver: &str, sink: &str, pin: &str) -> bool {
    let lutlike = |t: &str| {
        t.starts_with("LUT")
            || t == "INV"
            || t == "XORCY"
            || t.starts_with("MUXF")
            || t == "cycloneive_lcell_comb"
    };
    match (sink, pin) {
        ("MUXCY", "CI") | ("XORCY", "CI") | ("MUXCY", "S") | ("XORCY", "LI") => false,
        (s, "I0") | (s, "I1") if s.starts_with("MUXF") => false,
        ("cycloneive_lcell_comb", "cin") => false,
        ("$not", _) | ("$_NOT_", _) => false,
        (s, "D") if s.starts_with("FD") => !lutlike(driver),
        ("dffeas", "d") => !lutlike(driver),
        _ => true,
    }
}

struct Cell<'a> {
    name: &'a str,
    ty: &'a str,
    /// (port, direction is output, bits).
    ports: Vec<(&'a str, bool, Vec<Option<u64>>)>,
}

/// Best arrival at a net bit: (time ps, predecessor).
#[derive(Clone, Copy)]
struct Arr {
    t: u64,
    /// (input bit, arc, routed) of the chosen input; None at a path start.
    prev: Option<(u64, Arc, bool)>,
    /// Cell that drives the bit.
    cell: usize,
}

fn bits(v: &Value) -> Vec<Option<u64>> {
    v.as_array()
        .map(|a| a.iter().map(|b| b.as_u64()).collect())
        .unwrap_or_default()
}

/// Analyzes module `top` of a Yosys JSON netlist mapped for `family`. Ok(None): no
/// register-to-register path.
pub fn analyze(json: &str, top: &str, family: Family) -> Result<Option<PathLevels>, String> {
    analyze_with(json, top, model(family))
}

/// [`analyze`] with an explicit delay model.
pub fn analyze_with(json: &str, top: &str, m: &DelayModel) -> Result<Option<PathLevels>, String> {
    let v: Value = serde_json::from_str(json).map_err(|e| format!("netlist JSON: {e}"))?;
    let module = v
        .get("modules")
        .and_then(|ms| ms.get(top))
        .ok_or_else(|| format!("netlist has no module `{top}`"))?;
    // Net bit -> a readable name (prefer names without `$`, then the shortest).
    let mut names: HashMap<u64, String> = HashMap::new();
    if let Some(nn) = module.get("netnames").and_then(Value::as_object) {
        for (name, n) in nn {
            let bs = n.get("bits").map(bits).unwrap_or_default();
            let width = bs.len();
            for (i, b) in bs.into_iter().enumerate() {
                let Some(b) = b else { continue };
                let full = if width == 1 {
                    name.clone()
                } else {
                    format!("{name}[{i}]")
                };
                let better = match names.get(&b) {
                    None => true,
                    Some(old) => {
                        let rank = |s: &str| (s.contains('$'), s.len(), s.to_string());
                        rank(&full) < rank(old)
                    }
                };
                if better {
                    names.insert(b, full);
                }
            }
        }
    }
    let mut cells: Vec<Cell> = Vec::new();
    if let Some(cs) = module.get("cells").and_then(Value::as_object) {
        for (name, c) in cs {
            let ty = c.get("type").and_then(Value::as_str).unwrap_or("");
            let dirs = c.get("port_directions").and_then(Value::as_object);
            let mut ports = Vec::new();
            if let Some(conn) = c.get("connections").and_then(Value::as_object) {
                for (p, b) in conn {
                    let out = dirs
                        .and_then(|d| d.get(p))
                        .and_then(Value::as_str)
                        .map(|d| d == "output")
                        .unwrap_or(false);
                    ports.push((p.as_str(), out, bits(b)));
                }
            }
            cells.push(Cell {
                name: name.as_str(),
                ty,
                ports,
            });
        }
    }
    // Net bit -> (driving cell, output port).
    let mut driver: HashMap<u64, (usize, usize)> = HashMap::new();
    for (ci, c) in cells.iter().enumerate() {
        for (pi, (_, out, bs)) in c.ports.iter().enumerate() {
            if *out {
                for b in bs.iter().flatten() {
                    driver.insert(*b, (ci, pi));
                }
            }
        }
    }
    let mut memo: HashMap<u64, Option<Arr>> = HashMap::new();
    // Iterative depth-first evaluation of arrival times (paths can be hundreds of cells).
    let mut visiting: std::collections::HashSet<u64> = std::collections::HashSet::new();
    let mut arrival =
        |start: u64, memo: &mut HashMap<u64, Option<Arr>>| -> Result<Option<Arr>, String> {
            let mut stack: Vec<(u64, bool)> = vec![(start, false)];
            while let Some((b, expanded)) = stack.pop() {
                if memo.contains_key(&b) && !expanded {
                    continue;
                }
                if !expanded && visiting.contains(&b) {
                    return Err(format!("combinational loop through net bit {b}"));
                }
                let Some(&(ci, pi)) = driver.get(&b) else {
                    memo.insert(b, None);
                    continue;
                };
                let c = &cells[ci];
                match role(c.ty, m) {
                    Role::None => {
                        memo.insert(b, None);
                    }
                    Role::Seq { tco_ps, .. } => {
                        memo.insert(
                            b,
                            Some(Arr {
                                t: tco_ps,
                                prev: None,
                                cell: ci,
                            }),
                        );
                    }
                    Role::Comb => {
                        let o = c.ports[pi].0;
                        let inputs: Vec<(u64, Arc, bool)> = c
                            .ports
                            .iter()
                            .filter(|(_, out, _)| !*out)
                            .filter_map(|(p, _, bs)| arc(c.ty, p, o).map(|a| (p, a, bs)))
                            .flat_map(|(p, a, bs)| bs.iter().flatten().map(move |&ib| (ib, a, *p)))
                            .map(|(ib, a, p)| {
                                let r = match driver.get(&ib) {
                                    Some(&(dci, _)) => routed(cells[dci].ty, c.ty, p),
                                    None => true,
                                };
                                (ib, a, r)
                            })
                            .collect();
                        if !expanded {
                            let pending: Vec<u64> = inputs
                                .iter()
                                .map(|x| x.0)
                                .filter(|ib| !memo.contains_key(ib))
                                .collect();
                            if !pending.is_empty() {
                                visiting.insert(b);
                                stack.push((b, true));
                                for ib in pending {
                                    stack.push((ib, false));
                                }
                                continue;
                            }
                        }
                        let mut best: Option<Arr> = None;
                        for (ib, a, r) in inputs {
                            let Some(Some(ia)) = memo.get(&ib) else {
                                continue;
                            };
                            let t = ia.t + arc_ps(a, m) + if r { m.route_ps } else { 0 };
                            if best.map(|x| t > x.t).unwrap_or(true) {
                                best = Some(Arr {
                                    t,
                                    prev: Some((ib, a, r)),
                                    cell: ci,
                                });
                            }
                        }
                        visiting.remove(&b);
                        memo.insert(b, best);
                    }
                }
            }
            Ok(memo.get(&start).copied().flatten())
        };
    // Endpoints, in cell-name order (the JSON object is sorted): the latest arrival wins.
    let mut worst: Option<(u64, u64, usize, bool)> = None; // (delay, bit, end cell, routed)
    for (ci, c) in cells.iter().enumerate() {
        let Role::Seq { ends, .. } = role(c.ty, m) else {
            continue;
        };
        for (p, out, bs) in &c.ports {
            if *out || !ends.contains(p) {
                continue;
            }
            for b in bs.iter().flatten() {
                let Some(a) = arrival(*b, &mut memo)? else {
                    continue;
                };
                let r = routed(cells[a.cell].ty, c.ty, p);
                let d = a.t + if r { m.route_ps } else { 0 } + m.tsu_ps;
                if worst.map(|w| d > w.0).unwrap_or(true) {
                    worst = Some((d, *b, ci, r));
                }
            }
        }
    }
    let Some((delay, end_bit, end_cell, end_routed)) = worst else {
        return Ok(None);
    };
    let mut p = PathLevels {
        delay_ps: delay,
        routed_nets: end_routed as u32,
        ..Default::default()
    };
    p.to = {
        let c = &cells[end_cell];
        c.ports
            .iter()
            .find(|(_, out, _)| *out)
            .and_then(|(_, _, bs)| bs.iter().flatten().next().copied())
            .and_then(|b| names.get(&b).cloned())
            .unwrap_or_else(|| c.name.to_string())
    };
    let mut b = end_bit;
    while let Some(Some(a)) = memo.get(&b).copied() {
        match a.prev {
            None => {
                p.from = names
                    .get(&b)
                    .cloned()
                    .unwrap_or_else(|| cells[a.cell].name.to_string());
                break;
            }
            Some((ib, arc, r)) => {
                match arc {
                    Arc::Lut => p.lut_levels += 1,
                    Arc::CarryEntry { through_lut } => {
                        p.carry_bits += 1;
                        if through_lut {
                            p.lut_levels += 1;
                        }
                    }
                    Arc::CarryBit => p.carry_bits += 1,
                    Arc::CarrySum => {}
                    Arc::Mux => p.muxes += 1,
                    Arc::Mult => p.multipliers += 1,
                    Arc::Wire => {}
                }
                if r {
                    p.routed_nets += 1;
                }
                b = ib;
            }
        }
    }
    p.carry_chains = chain_runs(&memo, end_bit);
    Ok(Some(p))
}

/// Number of separate runs of carry arcs on the path ending at `end` (walking backwards).
fn chain_runs(memo: &HashMap<u64, Option<Arr>>, end: u64) -> u32 {
    let mut runs = 0;
    let mut in_run = false;
    let mut b = end;
    while let Some(Some(a)) = memo.get(&b).copied() {
        let Some((ib, arc, _)) = a.prev else { break };
        let carry = matches!(arc, Arc::CarryBit | Arc::CarryEntry { .. });
        if carry && !in_run {
            runs += 1;
        }
        // An entry ends the run (walking backwards, the chain starts there).
        in_run = carry && !matches!(arc, Arc::CarryEntry { .. });
        b = ib;
    }
    runs
}

#[cfg(test)]
mod tests {
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
}
