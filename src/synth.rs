//! Yosys synthesis for Spartan-3A (`synth_xilinx -family xc3sa`) and Cyclone III
//! (`synth_intel -family cycloneive`: the Cyclone IV E logic element is the Cyclone III
//! one), with the design rules of the project:
//!
//! * no latch after `proc` (`select -assert-none` on every latch cell type);
//! * `check -assert` before and after synthesis: no undriven or multiply driven nets, no
//!   combinational loops;
//! * no Yosys warning outside a short list of known, result-neutral ones.
//!
//! Counts come from `stat -json` on the flattened netlist; the worst register-to-register path (LUT
//! levels, carry bits and an estimated delay) from the mapped netlist written with
//! `write_json` ([`crate::report::levels`]).
use crate::cosim::{require_tool, CosimError};
use crate::error::{Error, Result};
use crate::report::yosys::{cache_key, cache_load, cache_store, CachedSynth};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

/// The environment variable naming a directory of synthesis results (unset or empty: none).
/// [`synthesize`] answers a design whose Verilog, top, family, Yosys version and counting
/// rules match an entry from it, and stores what it runs. `scripts/test.sh` points it at
/// `tests/data/yosys-cache`, committed, so CI runs Yosys only for the designs that changed.
pub const SYNTH_CACHE_ENV: &str = "SINEDEC_SYNTH_CACHE";

/// Source of the FPGA synthesis (this file: script and counting rules) and of the path
/// analysis, hashed into cache keys so that a change to either misses the cache.
pub(crate) const SYNTH_SOURCE: &str = concat!(
    include_str!("synth.rs"),
    include_str!("report/levels/mod.rs"),
    include_str!("report/levels/delay.rs")
);

/// FPGA family to synthesize for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Family {
    /// Spartan-3A / 3AN.
    Xc3sa,
    /// Cyclone IV E (= Cyclone III logic element).
    CycloneIve,
}

impl Family {
    /// Yosys family name.
    pub fn name(self) -> &'static str {
        match self {
            Family::Xc3sa => "xc3sa",
            Family::CycloneIve => "cycloneive",
        }
    }
    fn synth_command(self, top: &str) -> String {
        match self {
            Family::Xc3sa => format!("synth_xilinx -family xc3sa -top {top} -flatten"),
            Family::CycloneIve => format!("synth_intel -family cycloneive -top {top}"),
        }
    }
}

/// Cell counts of a synthesized design.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SynthStats {
    /// Every cell type and its count.
    pub cells: BTreeMap<String, u64>,
    /// LUTs (LUT1..LUT4 and INV on xc3sa; logic cells on cycloneive).
    pub luts: u64,
    /// Flip-flops.
    pub ffs: u64,
    /// Carry cells (MUXCY on xc3sa; cycloneive carries inside its logic cells: 0).
    pub carry: u64,
    /// Hard multipliers.
    pub multipliers: u64,
    /// Block RAMs.
    pub brams: u64,
    /// Worst register-to-register path of the mapped netlist (None: no such path).
    pub path: Option<crate::report::levels::PathLevels>,
    /// The register-to-register path that enters the most carry chains
    /// ([`crate::report::levels::most_carry_chains`]; None: no such path).
    pub chain_path: Option<crate::report::levels::PathLevels>,
}

/// Yosys warnings that do not change results.
const HARMLESS: &[&str] = &[
    "Shift register inference not yet supported for family xc3sa",
    "Feature 'synth_intel' is experimental",
];

/// Block-RAM ports Yosys's `memory_bram` mapping may resize (the RAM primitive's data and
/// parity ports are wider than the inferred memory; the extra bits are unused): Spartan-3A
/// RAMB16 and Cyclone M9K (`data_a` .. `q_b`, 36 bits wide in its 256-word mode).
const BRAM_PORTS: &[&str] = &[
    "DI", "DO", "DIP", "DOP", "DIA", "DIB", "DOA", "DOB", "DIPA", "DIPB", "DOPA", "DOPB", "data_a",
    "data_b", "q_a", "q_b",
];

/// A warning that does not change results: one of [`HARMLESS`], or the resizing of a data
/// port of a block RAM tile that `memory_bram` made of an inferred memory (cell names end in
/// `.<row>.<column>.<port>`).
pub fn harmless_warning(line: &str) -> bool {
    if HARMLESS.iter().any(|h| line.contains(h)) {
        return true;
    }
    let Some(rest) = line.split("Resizing cell port ").nth(1) else {
        return false;
    };
    let cell = rest.split(' ').next().unwrap_or("");
    let parts: Vec<&str> = cell.rsplitn(4, '.').collect();
    parts.len() == 4
        && BRAM_PORTS.contains(&parts[0])
        && parts[1].parse::<u32>().is_ok()
        && parts[2].parse::<u32>().is_ok()
}

fn classify(cells: &BTreeMap<String, u64>, family: Family) -> SynthStats {
    let mut s = SynthStats {
        cells: cells.clone(),
        ..Default::default()
    };
    for (name, &n) in cells {
        let is = |p: &str| name.starts_with(p);
        match family {
            Family::Xc3sa => {
                if is("LUT") || name == "INV" {
                    s.luts += n;
                } else if is("FD") {
                    s.ffs += n;
                } else if name == "MUXCY" {
                    s.carry += n;
                } else if is("MULT18X18") {
                    s.multipliers += n;
                } else if is("RAMB16") {
                    s.brams += n;
                }
            }
            Family::CycloneIve => {
                if name == "cycloneive_lcell_comb" {
                    s.luts += n;
                } else if name == "dffeas" {
                    s.ffs += n;
                } else if is("cycloneive_mac_mult") {
                    s.multipliers += n;
                } else if is("cycloneive_ram_block") {
                    s.brams += n;
                }
            }
        }
    }
    s
}

/// The cell counts of module `top` in the output of Yosys `stat -json` (written with
/// `tee -q -o FILE stat -json`): `modules."\\top".num_cells_by_type`. `None` when the text
/// is not such JSON or has no counts for `top`.
pub fn parse_stat_json(json: &str, top: &str) -> Option<BTreeMap<String, u64>> {
    #[derive(serde::Deserialize)]
    struct Stat {
        modules: BTreeMap<String, Module>,
    }
    #[derive(serde::Deserialize)]
    struct Module {
        #[serde(default)]
        num_cells_by_type: BTreeMap<String, u64>,
    }
    let stat: Stat = serde_json::from_str(json).ok()?;
    let m = stat
        .modules
        .get(&format!("\\{top}"))
        .or_else(|| stat.modules.get(top))?;
    Some(m.num_cells_by_type.clone())
}

/// Synthesizes `verilog` (top module `top`) for `family` in `workdir`, answered from the
/// directory [`SYNTH_CACHE_ENV`] names when it holds the same run.
pub fn synthesize(verilog: &str, top: &str, family: Family, workdir: &Path) -> Result<SynthStats> {
    let cache = std::env::var_os(SYNTH_CACHE_ENV)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from);
    if cache.is_none() {
        return synthesize_uncached(verilog, top, family, workdir);
    }
    static VERSION: OnceLock<String> = OnceLock::new();
    let version = match VERSION.get() {
        Some(v) => v.clone(),
        None => VERSION
            .get_or_init(|| crate::report::yosys::yosys_version().unwrap_or_default())
            .clone(),
    };
    if version.is_empty() {
        // No Yosys: the uncached run reports it with its install hint.
        return synthesize_uncached(verilog, top, family, workdir);
    }
    Ok(synthesize_cached(verilog, top, family, workdir, cache.as_deref(), &version)?.0)
}

/// [`synthesize`] through the cache directory `cache` (None: no cache) for Yosys `version`
/// (`yosys -V`): the figures, and whether they came from the cache. A failed run stores
/// nothing, so an error always comes from a real run.
pub fn synthesize_cached(
    verilog: &str,
    top: &str,
    family: Family,
    workdir: &Path,
    cache: Option<&Path>,
    version: &str,
) -> Result<(SynthStats, bool)> {
    let kind = format!("family {} top {top}", family.name());
    let key = cache_key(&kind, version, SYNTH_SOURCE, verilog);
    if let Some(c) = cache_load::<CachedSynth>(cache, &key) {
        return Ok((c.into(), true));
    }
    let s = synthesize_uncached(verilog, top, family, workdir)?;
    cache_store(cache, &key, &CachedSynth::from(&s))?;
    Ok((s, false))
}

/// The Yosys run behind [`synthesize`], without a cache.
fn synthesize_uncached(
    verilog: &str,
    top: &str,
    family: Family,
    workdir: &Path,
) -> Result<SynthStats> {
    require_tool("yosys")?;
    std::fs::create_dir_all(workdir).map_err(|e| Error::io(workdir, e))?;
    let tag = family.name();
    let vfile = workdir.join(format!("synth_{tag}.v"));
    std::fs::write(&vfile, verilog).map_err(|e| Error::io(&vfile, e))?;
    let stat = workdir.join(format!("synth_{tag}_stat.json"));
    let json = workdir.join(format!("synth_{tag}.json"));
    let script = format!(
        "read_verilog {v}\n\
         hierarchy -check -top {top}\n\
         proc\n\
         select -assert-none t:$dlatch t:$adlatch t:$dlatchsr t:$sr\n\
         check -assert\n\
         {synth}\n\
         check -assert\n\
         tee -q -o {stat} stat -json\n\
         write_json {json}\n",
        v = vfile.display(),
        synth = family.synth_command(top),
        stat = stat.display(),
        json = json.display(),
    );
    let ys = workdir.join(format!("synth_{tag}.ys"));
    std::fs::write(&ys, script).map_err(|e| Error::io(&ys, e))?;
    let out = crate::cleanup::output(Command::new("yosys").arg("-q").arg("-s").arg(&ys)).map_err(
        |e| CosimError::ToolFailed {
            tool: "yosys".into(),
            stage: "launch".into(),
            message: e.to_string(),
        },
    )?;
    let log = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    if !out.status.success() {
        let lines: Vec<&str> = log.lines().collect();
        let tail = lines[lines.len().saturating_sub(40)..].join("\n");
        let what = if log.contains("selection is not empty") {
            "latch inferred"
        } else if log.contains("problems in 'check -assert'") {
            "check failed: undriven or multiply driven net, or a logic loop"
        } else {
            "synthesis error"
        };
        return Err(CosimError::ToolFailed {
            tool: "yosys".into(),
            stage: format!("synth {tag}: {what}"),
            message: tail,
        }
        .into());
    }
    let bad: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("Warning:") && !harmless_warning(l))
        .collect();
    if !bad.is_empty() {
        return Err(CosimError::ToolFailed {
            tool: "yosys".into(),
            stage: format!("synth {tag} warnings"),
            message: bad.join("\n"),
        }
        .into());
    }
    let text = std::fs::read_to_string(&stat).map_err(|e| Error::io(&stat, e))?;
    let cells = parse_stat_json(&text, top).unwrap_or_default();
    if cells.is_empty() {
        return Err(Error::ToolOutput {
            tool: "yosys".into(),
            message: format!("no cell statistics for `{top}` in {}", stat.display()),
        });
    }
    let mut s = classify(&cells, family);
    let netlist = std::fs::read_to_string(&json).map_err(|e| Error::io(&json, e))?;
    let named = |e: Error| match e {
        Error::ToolOutput { tool, message } => Error::ToolOutput {
            tool,
            message: format!("path analysis of `{top}` ({tag}): {message}"),
        },
        other => other,
    };
    s.path = crate::report::levels::analyze(&netlist, top, family).map_err(named)?;
    s.chain_path = crate::report::levels::most_carry_chains(&netlist, top).map_err(named)?;
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::{harmless_warning, parse_stat_json};

    #[test]
    fn stat_json_cells_of_the_named_module() {
        // Written by Yosys 0.23 (`tee -q -o s.json stat -json`) for a 4-bit accumulator after
        // `synth -flatten; abc -g ...` (whitespace shortened; the text `stat` of the same run
        // lists the same five counts).
        let json = r#"{
   "creator": "Yosys 0.23 (git sha1 7ce5011c24b)",
   "invocation": "stat -json ",
   "modules": {
      "\\top": {
         "num_wires": 15, "num_wire_bits": 27, "num_pub_wires": 3, "num_pub_wire_bits": 9,
         "num_memories": 0, "num_memory_bits": 0, "num_processes": 0, "num_cells": 18,
         "num_cells_by_type": {
            "$_AND_": 2, "$_DFF_P_": 4, "$_NAND_": 5, "$_XNOR_": 1, "$_XOR_": 6
         }
      }
   },
   "design": { "num_cells": 18 }
}"#;
        let cells = parse_stat_json(json, "top").expect("module top");
        let want: Vec<(&str, u64)> = vec![
            ("$_AND_", 2),
            ("$_DFF_P_", 4),
            ("$_NAND_", 5),
            ("$_XNOR_", 1),
            ("$_XOR_", 6),
        ];
        assert_eq!(
            cells
                .iter()
                .map(|(k, v)| (k.as_str(), *v))
                .collect::<Vec<_>>(),
            want
        );
        assert_eq!(cells.values().sum::<u64>(), 18);
        assert!(parse_stat_json(json, "other").is_none());
        assert!(parse_stat_json("5. Printing statistics.", "top").is_none());
    }

    #[test]
    fn only_block_ram_data_ports_may_be_resized() {
        assert!(harmless_warning(
            "Warning: Resizing cell port cap_top.rtl.front.engine.ram.sr_mem.0.0.DI from 64 bits to 32 bits."
        ));
        assert!(harmless_warning(
            "Warning: Resizing cell port top.m.1.0.DOP from 8 bits to 4 bits."
        ));
        assert!(harmless_warning(
            "Warning: Resizing cell port top.rn.mem.0.0.0.data_a from 32 bits to 36 bits."
        ));
        assert!(!harmless_warning(
            "Warning: Resizing cell port top.tab.mem.0.0.0.address_a from 9 bits to 8 bits."
        ));
        // A width mismatch on an ordinary instance stays an error.
        assert!(!harmless_warning(
            "Warning: Resizing cell port top.rtl.core.in_sin from 32 bits to 16 bits."
        ));
        assert!(!harmless_warning(
            "Warning: Resizing cell port top.rtl.core.0.0.in_sin from 32 bits to 16 bits."
        ));
        assert!(!harmless_warning(
            "Warning: wire foo is used but has no driver."
        ));
    }
}
