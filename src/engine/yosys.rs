//! Yosys's half of the engine: the emitted Verilog is elaborated, flattened and optimised
//! into one module of word-level cells (`read_verilog; hierarchy -top X; proc; flatten;
//! opt; wreduce; opt_clean; write_json`), and the JSON is read into plain structs.
//!
//! In the JSON every net bit has a number (2, 3, ...) and a constant bit is the string
//! `"0"`, `"1"`, `"x"` or `"z"`; a cell's connections and a port's bits are lists of these.
//! Parameters are bit strings (MSB first) or, for strings, text.
use crate::cosim::{CosimError, TOOL_TIMEOUT};
use crate::error::{Error, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;

/// The Yosys script: `{top}` is the top module.
pub const SCRIPT: &str = "read_verilog design.v; hierarchy -check -top {top}; proc; flatten; \
    opt; wreduce; opt_clean; write_json netlist.json";

/// One bit of a connection: a net number or a constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Bit {
    /// Net bit number.
    Net(u64),
    /// Constant 0 or 1 (`x` and `z` read as 0).
    Const(bool),
}

impl<'de> Deserialize<'de> for Bit {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Bit, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum Raw {
            N(u64),
            S(String),
        }
        match Raw::deserialize(d)? {
            Raw::N(n) => Ok(Bit::Net(n)),
            Raw::S(s) => Ok(Bit::Const(s == "1")),
        }
    }
}

/// A port of the top module.
#[derive(Clone, Debug, Deserialize)]
pub struct JPort {
    /// `input`, `output` or `inout`.
    pub direction: String,
    /// Its bits, LSB first.
    pub bits: Vec<Bit>,
}

/// A parameter value: a bit string, a number or text.
#[derive(Clone, Debug, Deserialize)]
#[serde(untagged)]
pub enum Param {
    /// A JSON number.
    Num(u64),
    /// A bit string (MSB first) or text.
    Text(String),
}

impl Param {
    /// The bits, LSB first (`x`/`z` as 0); text that is not a bit string gives None.
    pub fn bits(&self) -> Option<Vec<bool>> {
        match self {
            Param::Num(n) => Some((0..64).map(|i| (n >> i) & 1 == 1).collect()),
            Param::Text(t) => {
                if t.is_empty() {
                    return Some(vec![]);
                }
                t.chars()
                    .rev()
                    .map(|c| match c {
                        '0' | 'x' | 'z' => Some(false),
                        '1' => Some(true),
                        _ => None,
                    })
                    .collect()
            }
        }
    }

    /// The value as an unsigned number (up to 64 bits).
    pub fn value(&self) -> Option<u64> {
        let b = self.bits()?;
        if b.iter().skip(64).any(|&x| x) {
            return None;
        }
        Some(
            b.iter()
                .take(64)
                .enumerate()
                .fold(0, |acc, (i, &x)| acc | ((x as u64) << i)),
        )
    }
}

/// A cell.
#[derive(Clone, Debug, Deserialize)]
pub struct JCell {
    /// Cell type, e.g. `$add`.
    #[serde(rename = "type")]
    pub ty: String,
    /// Parameters.
    #[serde(default)]
    pub parameters: BTreeMap<String, Param>,
    /// Connections by port name.
    #[serde(default)]
    pub connections: BTreeMap<String, Vec<Bit>>,
}

/// A named net (for initial values).
#[derive(Clone, Debug, Deserialize)]
pub struct JNet {
    /// Its bits.
    pub bits: Vec<Bit>,
    /// Attributes; `init` holds the initial value of register bits.
    #[serde(default)]
    pub attributes: BTreeMap<String, Param>,
}

/// A memory's declaration.
#[derive(Clone, Debug, Deserialize)]
pub struct JMemory {
    /// Word width.
    pub width: u32,
    /// Address of the first word.
    #[serde(default)]
    pub start_offset: i64,
    /// Number of words.
    pub size: u64,
}

/// The flattened top module.
#[derive(Clone, Debug, Deserialize)]
pub struct JModule {
    /// Ports by name.
    #[serde(default)]
    pub ports: BTreeMap<String, JPort>,
    /// Cells by name.
    #[serde(default)]
    pub cells: BTreeMap<String, JCell>,
    /// Named nets.
    #[serde(default)]
    pub netnames: BTreeMap<String, JNet>,
    /// Memories by id.
    #[serde(default)]
    pub memories: BTreeMap<String, JMemory>,
}

#[derive(Deserialize)]
struct JDesign {
    modules: BTreeMap<String, JModule>,
}

/// Parses Yosys's JSON and returns the module `top`.
pub fn parse(json: &str, top: &str) -> Result<JModule> {
    let mut d: JDesign = serde_json::from_str(json).map_err(|e| Error::Json {
        what: "Yosys netlist".into(),
        source: e,
    })?;
    d.modules.remove(top).ok_or_else(|| Error::ToolOutput {
        tool: "yosys".into(),
        message: format!("the netlist has no module `{top}` after flattening"),
    })
}

/// Runs Yosys on `verilog` (top module `top`) in `workdir` and returns the JSON text.
pub fn run(verilog: &str, top: &str, workdir: &Path) -> Result<String> {
    if !top.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') || top.is_empty() {
        return Err(Error::Export(format!("bad top module name {top:?}")));
    }
    let design = workdir.join("design.v");
    std::fs::write(&design, verilog).map_err(|e| Error::io(&design, e))?;
    let mut cmd = Command::new("yosys");
    cmd.current_dir(workdir)
        .args(["-q", "-p", &SCRIPT.replace("{top}", top)]);
    crate::cosim::run_checked(&mut cmd, "yosys", "engine netlist", workdir, "engine_yosys")?;
    let out = workdir.join("netlist.json");
    std::fs::read_to_string(&out).map_err(|e| {
        Error::Tool(CosimError::ToolFailed {
            tool: "yosys".into(),
            stage: "engine netlist".into(),
            message: format!(
                "no netlist at {} ({e}); time limit {} s",
                out.display(),
                TOOL_TIMEOUT.as_secs()
            ),
        })
    })
}
