//! Reading nextpnr-ecp5's log: the post-route Fmax and the critical path ([`parse_log`]).
//!
//! nextpnr names its cells after the nets of the flattened design, which keep the RTL names:
//! `rtl.counter.usum_TRELLIS_FF_Q_3` is a flip-flop of register `usum` of instance `counter`
//! of the `rtl` wrapper. [`register_name`] strips the mapping suffix and [`block_of`] names
//! the instance (the block of `<name>_top`).

use super::*;

/// Suffixes Yosys `synth_ecp5` and nextpnr append to a net name to name a cell.
const CELL_SUFFIXES: &[&str] = &[
    "_TRELLIS_FF",
    "_TRELLIS_",
    "_LUT4",
    "_CCU2C",
    "_PFUMX",
    "_L6MUX21",
    "_MULT18X18D",
    "_ALU54B",
    "_DP16KD",
    "_DPR16X4",
    "$",
];

/// The register (net) name of an ECP5 cell: the cell name up to the first mapping suffix,
/// without a trailing bit index (`rtl.counter.usum_TRELLIS_FF_Q_3` -> `rtl.counter.usum`,
/// `q[3]` -> `q`).
pub fn register_name(cell: &str) -> String {
    let mut end = cell.len();
    for s in CELL_SUFFIXES {
        if let Some(i) = cell.find(s) {
            if i > 0 {
                end = end.min(i);
            }
        }
    }
    let base = &cell[..end];
    let base = match base.rfind('[') {
        Some(i) if base.ends_with(']') => &base[..i],
        _ => base,
    };
    base.trim_start_matches('\\').to_string()
}

/// The block of a register name: its instance path without the `rtl` wrapper and without
/// rust-hdl's flip-flop wrappers (instances named `*_reg`), or `(top level)` for a register
/// named after a port of the top module. `rtl.counter.usum` -> `counter`,
/// `rtl.combiner.p_reg.q` -> `combiner`, `rtl.core.counter.turns_reg.q` -> `core.counter`.
pub fn block_of(register: &str) -> String {
    let parts: Vec<&str> = register.split('.').collect();
    if parts.len() < 2 || register.starts_with('$') {
        return "(top level)".into();
    }
    let inst: Vec<&str> = parts[..parts.len() - 1]
        .iter()
        .copied()
        .enumerate()
        .filter(|&(i, p)| (i != 0 || p != "rtl") && !p.ends_with("_reg"))
        .map(|(_, p)| p)
        .collect();
    if inst.is_empty() {
        "(top level)".into()
    } else {
        inst.join(".")
    }
}

/// Parses a nextpnr-ecp5 log: the last `Max frequency for clock` line (post-route) and the
/// last register-to-register critical path report (`(posedge -> posedge)`) before it.
/// Returns None when the log holds neither (the run did not get to timing analysis).
pub fn parse_log(text: &str, target_mhz: f64) -> Option<PnrTiming> {
    let mut t = PnrTiming {
        target_mhz,
        ..Default::default()
    };
    let mut seen = false;
    let mut in_path = false;
    // The path being read: (from, to, logic, routing, nets).
    let mut cur: Option<(String, String, f64, f64, u32)> = None;
    for line in text.lines() {
        let l = line
            .trim_start_matches("Info:")
            .trim_start_matches("Warning:")
            .trim();
        if l.starts_with("Critical path report for clock") {
            in_path = l.contains("(posedge -> posedge)") || l.contains("(negedge -> negedge)");
            cur = in_path.then(|| (String::new(), String::new(), 0.0, 0.0, 0));
            continue;
        }
        if let Some(rest) = l.strip_prefix("Max frequency for clock") {
            let mhz = rest
                .split(": ")
                .nth(1)
                .and_then(|v| v.split_whitespace().next())
                .and_then(|v| v.parse::<f64>().ok());
            if let Some(m) = mhz {
                t.fmax_mhz = Some(m);
                seen = true;
            }
            in_path = false;
            continue;
        }
        if !in_path {
            continue;
        }
        let Some(c) = cur.as_mut() else { continue };
        let f: Vec<&str> = l.split_whitespace().collect();
        // `<type> <curr> <total> Source|Net <name> ...`
        if f.len() >= 5 && f[1].parse::<f64>().is_ok() && f[2].parse::<f64>().is_ok() {
            let curr: f64 = f[1].parse().unwrap_or(0.0);
            match (f[0], f[3]) {
                ("routing", "Net") => {
                    c.3 += curr;
                    if curr > 0.0 {
                        c.4 += 1;
                    }
                }
                ("setup", "Source") => {
                    c.1 = pin_cell(f[4]);
                }
                (_, "Source") => {
                    if c.0.is_empty() {
                        c.0 = pin_cell(f[4]);
                    }
                    if f[0] == "logic" || f[0] == "clk-to-q" {
                        c.2 += curr;
                    }
                }
                _ => {}
            }
            continue;
        }
        if l.ends_with("ns routing") && l.contains("ns logic") {
            in_path = false;
            if let Some((from, to, logic, routing, nets)) = cur.take() {
                let _ = (logic, routing);
                // The summary line is authoritative for the sums.
                let nums: Vec<f64> = l
                    .split_whitespace()
                    .filter_map(|w| w.parse::<f64>().ok())
                    .collect();
                t.from_cell = from;
                t.to_cell = to;
                t.logic_ns = nums.first().copied().unwrap_or(logic);
                t.routing_ns = nums.get(1).copied().unwrap_or(routing);
                t.routed_nets = nets;
            }
        }
    }
    seen.then_some(t)
}

/// `cell.PIN` -> `cell` (the pin is the part after the last dot).
fn pin_cell(s: &str) -> String {
    match s.rfind('.') {
        Some(i) => s[..i].to_string(),
        None => s.to_string(),
    }
}
