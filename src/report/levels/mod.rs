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
mod delay;

use crate::error::{Error, Result};
use crate::synth::Family;
pub use delay::{arc, model, routed, Arc, DelayModel, CYCLONE3_C8, XC3SA_4};
use delay::{arc_ps, role, Role};
use serde::{Deserialize, Serialize};
use serde_json::Value;
use std::collections::HashMap;
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

/// [`Error::ToolOutput`] for a netlist the analysis cannot use.
fn bad_netlist(message: String) -> Error {
    Error::ToolOutput {
        tool: "yosys".into(),
        message,
    }
}

/// Analyzes module `top` of a Yosys JSON netlist mapped for `family`. Ok(None): no
/// register-to-register path.
pub fn analyze(json: &str, top: &str, family: Family) -> Result<Option<PathLevels>> {
    analyze_with(json, top, model(family))
}

/// [`analyze`] with an explicit delay model.
pub fn analyze_with(json: &str, top: &str, m: &DelayModel) -> Result<Option<PathLevels>> {
    let v: Value =
        serde_json::from_str(json).map_err(|e| bad_netlist(format!("netlist JSON: {e}")))?;
    let module = v
        .get("modules")
        .and_then(|ms| ms.get(top))
        .ok_or_else(|| bad_netlist(format!("netlist has no module `{top}`")))?;
    let names = net_names(module);
    let cells = read_cells(module);
    let driver = drivers(&cells);
    let mut memo: HashMap<u64, Option<Arr>> = HashMap::new();
    // Iterative depth-first evaluation of arrival times (paths can be hundreds of cells).
    let mut visiting: std::collections::HashSet<u64> = std::collections::HashSet::new();
    let mut arrival = |start: u64, memo: &mut HashMap<u64, Option<Arr>>| -> Result<Option<Arr>> {
        let mut stack: Vec<(u64, bool)> = vec![(start, false)];
        while let Some((b, expanded)) = stack.pop() {
            if memo.contains_key(&b) && !expanded {
                continue;
            }
            if !expanded && visiting.contains(&b) {
                return Err(bad_netlist(format!(
                    "combinational loop through net bit {b}"
                )));
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
    trace_back(&mut p, &memo, &names, &cells, end_bit);
    p.carry_chains = chain_runs(&memo, end_bit);
    Ok(Some(p))
}

/// Net bit -> a readable name (prefer names without `$`, then the shortest).
fn net_names(module: &Value) -> HashMap<u64, String> {
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
    names
}

/// The module's cells with their ports' directions and bits.
fn read_cells(module: &Value) -> Vec<Cell<'_>> {
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
    cells
}

/// Net bit -> (driving cell, output port).
fn drivers(cells: &[Cell]) -> HashMap<u64, (usize, usize)> {
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
    driver
}

/// Walks the worst path back from its end bit to its start, counting its levels into `p`
/// and naming its start.
fn trace_back(
    p: &mut PathLevels,
    memo: &HashMap<u64, Option<Arr>>,
    names: &HashMap<u64, String>,
    cells: &[Cell],
    end_bit: u64,
) {
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
mod tests;
