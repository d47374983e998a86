//! Yosys runs of the report, cached by design hash.
//!
//! Two kinds of run per design:
//!
//! * the project's FPGA synthesis ([`crate::synth::synthesize`], with its design rules) for
//!   xc3sa and cycloneive;
//! * a generic gate-level synthesis for a technology-independent gate count and the logic
//!   depth ([`GENERIC_SCRIPT`]).
//!
//! Each result is stored as JSON under the cache directory, named by the SHA-256 of the
//! Verilog text, the run kind (family), the script (for FPGA runs: the source text of
//! `src/synth.rs`, which holds the script and the counting rules) and the Yosys version, so
//! any change to any of them misses the cache.
use crate::cosim::{require_tool, CosimError};
use crate::error::{Error, Result};
use crate::synth::{parse_stat_json, synthesize_cached, Family, SynthStats};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Gate set of the generic count (Yosys `abc -g`).
pub const GATE_SET: &str = "AND,NAND,OR,NOR,XOR,XNOR,ANDNOT,ORNOT,MUX";

/// The generic synthesis script; `{v}`, `{top}`, `{stat}`, `{ltp}` are substituted.
pub const GENERIC_SCRIPT: &str = "read_verilog {v}
hierarchy -check -top {top}
synth -flatten -top {top}
abc -g AND,NAND,OR,NOR,XOR,XNOR,ANDNOT,ORNOT,MUX
opt_clean
tee -q -o {stat} stat -json
tee -q -o {ltp} ltp -noff
";

/// Version of the cache entry layout.
const CACHE_VERSION: &str = "sinedec-report-cache-2";

/// Result of the generic synthesis.
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct GateStats {
    /// Every cell type after `abc -g` and its count.
    pub cells: BTreeMap<String, u64>,
    /// Two-input gates of the gate set, a 2:1 MUX counted as one gate.
    pub gates: u64,
    /// Of which 2:1 multiplexers.
    pub muxes: u64,
    /// Inverters (not in `gates`).
    pub inverters: u64,
    /// Flip-flops (not in `gates`).
    pub ffs: u64,
    /// Other cells (none expected).
    pub other: u64,
    /// Gates on the longest path between flip-flops or ports (`ltp -noff`).
    pub depth: u64,
    /// Where that path starts.
    pub path_from: String,
    /// Where it ends.
    pub path_to: String,
}

/// Serializable copy of [`SynthStats`].
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct CachedSynth {
    cells: BTreeMap<String, u64>,
    luts: u64,
    ffs: u64,
    carry: u64,
    multipliers: u64,
    brams: u64,
    #[serde(default)]
    path: Option<super::levels::PathLevels>,
    #[serde(default)]
    chain_path: Option<super::levels::PathLevels>,
}

impl From<&SynthStats> for CachedSynth {
    fn from(s: &SynthStats) -> Self {
        CachedSynth {
            cells: s.cells.clone(),
            luts: s.luts,
            ffs: s.ffs,
            carry: s.carry,
            multipliers: s.multipliers,
            brams: s.brams,
            path: s.path.clone(),
            chain_path: s.chain_path.clone(),
        }
    }
}

impl From<CachedSynth> for SynthStats {
    fn from(c: CachedSynth) -> Self {
        SynthStats {
            cells: c.cells,
            luts: c.luts,
            ffs: c.ffs,
            carry: c.carry,
            multipliers: c.multipliers,
            brams: c.brams,
            path: c.path,
            chain_path: c.chain_path,
        }
    }
}

/// The cache entry `key` in `dir` (None: no cache, no entry or an unreadable one).
pub(crate) fn cache_load<T: for<'de> Deserialize<'de>>(dir: Option<&Path>, key: &str) -> Option<T> {
    let dir = dir?;
    let text = std::fs::read_to_string(dir.join(format!("{key}.json"))).ok()?;
    serde_json::from_str(&text).ok()
}

/// Stores `value` as the cache entry `key` in `dir` (written to a temporary file, then
/// renamed, so a parallel reader never sees half an entry); nothing without a cache.
pub(crate) fn cache_store<T: Serialize>(dir: Option<&Path>, key: &str, value: &T) -> Result<()> {
    let Some(dir) = dir else {
        return Ok(());
    };
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    let text = serde_json::to_string_pretty(value).map_err(|source| Error::Json {
        what: format!("cache entry {key}"),
        source,
    })?;
    let tmp = dir.join(format!(
        ".{key}.{}.{:?}.tmp",
        std::process::id(),
        std::thread::current().id()
    ));
    let path = dir.join(format!("{key}.json"));
    std::fs::write(&tmp, text).map_err(|e| Error::io(&tmp, e))?;
    std::fs::rename(&tmp, &path).map_err(|e| Error::io(&path, e))?;
    Ok(())
}

/// The latest FPGA synthesis of a design in the cache, whatever the Yosys version: the
/// entry `check` reads for its resource line ([`cached_synthesis`]), which cannot compute the
/// key of [`synthesize_cached`] since that holds the version of Yosys, and `check` never
/// runs Yosys.
#[derive(Clone, Debug, Serialize, Deserialize)]
struct LatestSynth {
    /// `yosys -V` of the run.
    yosys: String,
    /// Its figures.
    stats: CachedSynth,
}

/// The key of a design's [`LatestSynth`] entry: the family, the top, the synthesis script
/// and the Verilog, without the Yosys version.
fn latest_key(verilog: &str, top: &str, family: Family) -> String {
    let kind = format!("latest family {} top {top}", family.name());
    cache_key(&kind, "", crate::synth::SYNTH_SOURCE, verilog)
}

/// The figures of the latest synthesis of `verilog` (top `top`) for `family` that `sinedec
/// report` stored in one of the cache directories `dirs`, with the Yosys version that ran
/// it; None when none holds it. Reads files only: no Yosys run.
pub fn cached_synthesis(
    dirs: &[PathBuf],
    verilog: &str,
    top: &str,
    family: Family,
) -> Option<(SynthStats, String)> {
    let key = latest_key(verilog, top, family);
    dirs.iter()
        .find_map(|d| cache_load::<LatestSynth>(Some(d), &key))
        .map(|e| (e.stats.into(), e.yosys))
}

/// The name of a cache entry: the SHA-256 of the entry layout's version, the run kind
/// (family and top), the Yosys version, the script (for FPGA runs, the source of
/// `src/synth.rs` and of the path analysis) and the Verilog, each framed by its length.
pub(crate) fn cache_key(kind: &str, version: &str, script: &str, verilog: &str) -> String {
    let mut h = Sha256::new();
    for part in [CACHE_VERSION, kind, version, script, verilog] {
        h.update((part.len() as u64).to_le_bytes());
        h.update(part.as_bytes());
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// `yosys -V`'s output, trimmed; a missing Yosys is an error with its install hint.
pub fn yosys_version() -> Result<String> {
    match require_tool("yosys") {
        Ok(()) => {}
        Err(CosimError::ToolMissing { install, .. }) => return Err(missing(&install)),
        Err(e) => return Err(e.into()),
    }
    let out = crate::cleanup::output(Command::new("yosys").arg("-V")).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            missing("apt-get install -y yosys")
        } else {
            Error::Tool(CosimError::ToolFailed {
                tool: "yosys".into(),
                stage: "version".into(),
                message: e.to_string(),
            })
        }
    })?;
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_string())
}

/// Runs Yosys with a cache.
#[derive(Clone, Debug)]
pub struct Yosys {
    version: String,
    cache: Option<PathBuf>,
    work: PathBuf,
}

/// The error for a missing Yosys: names the tool and how to install it.
fn missing(install: &str) -> Error {
    Error::Tool(CosimError::ToolFailed {
        tool: "yosys".into(),
        stage: "not found".into(),
        message: format!(
            "`sinedec report` synthesizes every design with Yosys, which is not installed or not on PATH; install it with `{install}` (Debian/Ubuntu; elsewhere YosysHQ's OSS CAD Suite) and run the report again. Nothing was written."
        ),
    })
}

impl Yosys {
    /// Checks that Yosys runs and records its version; `cache` is the cache directory
    /// (None: no cache), `work` a scratch directory for the runs (created on demand).
    pub fn new(cache: Option<PathBuf>, work: PathBuf) -> Result<Yosys> {
        let version = yosys_version()?;
        Ok(Yosys {
            version,
            cache,
            work,
        })
    }

    /// `yosys -V` output.
    pub fn version(&self) -> &str {
        &self.version
    }

    fn key(&self, kind: &str, script: &str, verilog: &str) -> String {
        cache_key(kind, &self.version, script, verilog)
    }

    fn load<T: for<'de> Deserialize<'de>>(&self, key: &str) -> Option<T> {
        cache_load(self.cache.as_deref(), key)
    }

    fn store<T: Serialize>(&self, key: &str, value: &T) -> Result<()> {
        cache_store(self.cache.as_deref(), key, value)
    }

    fn scratch(&self, tag: &str) -> Result<PathBuf> {
        let dir = self.work.join(tag);
        if dir.exists() {
            std::fs::remove_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
        }
        std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
        Ok(dir)
    }

    /// FPGA synthesis with the project's design rules; `tag` names the scratch directory.
    /// Returns the figures and whether they came from the cache.
    pub fn family(
        &self,
        verilog: &str,
        top: &str,
        family: Family,
        tag: &str,
    ) -> Result<(SynthStats, bool)> {
        let dir = self.work.join(tag);
        let s = synthesize_cached(
            verilog,
            top,
            family,
            &dir,
            self.cache.as_deref(),
            &self.version,
        );
        let _ = std::fs::remove_dir_all(&dir);
        s
    }

    /// [`family`](Self::family), and the design's [`LatestSynth`] entry written beside
    /// the result (so that `check` finds it without asking Yosys for its version).
    pub fn family_indexed(
        &self,
        verilog: &str,
        top: &str,
        family: Family,
        tag: &str,
    ) -> Result<(SynthStats, bool)> {
        let r = self.family(verilog, top, family, tag)?;
        let key = latest_key(verilog, top, family);
        let entry = LatestSynth {
            yosys: self.version.clone(),
            stats: CachedSynth::from(&r.0),
        };
        let same = self
            .load::<LatestSynth>(&key)
            .is_some_and(|e| e.yosys == entry.yosys);
        if !same {
            self.store(&key, &entry)?;
        }
        Ok(r)
    }

    /// Generic gate count and logic depth ([`GENERIC_SCRIPT`]).
    pub fn generic(&self, verilog: &str, top: &str, tag: &str) -> Result<(GateStats, bool)> {
        let kind = format!("generic top {top}");
        let key = self.key(&kind, GENERIC_SCRIPT, verilog);
        if let Some(g) = self.load::<GateStats>(&key) {
            return Ok((g, true));
        }
        let dir = self.scratch(tag)?;
        let v = dir.join("generic.v");
        let stat = dir.join("generic_stat.json");
        let ltp = dir.join("generic_ltp.txt");
        std::fs::write(&v, verilog).map_err(|e| Error::io(&v, e))?;
        let script = GENERIC_SCRIPT
            .replace("{v}", &v.display().to_string())
            .replace("{top}", top)
            .replace("{stat}", &stat.display().to_string())
            .replace("{ltp}", &ltp.display().to_string());
        let ys = dir.join("generic.ys");
        std::fs::write(&ys, script).map_err(|e| Error::io(&ys, e))?;
        let out = crate::cleanup::output(Command::new("yosys").arg("-q").arg("-s").arg(&ys))
            .map_err(|e| {
                Error::Tool(CosimError::ToolFailed {
                    tool: "yosys".into(),
                    stage: "launch".into(),
                    message: e.to_string(),
                })
            })?;
        if !out.status.success() {
            let log = format!(
                "{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            );
            let lines: Vec<&str> = log.lines().collect();
            return Err(Error::Tool(CosimError::ToolFailed {
                tool: "yosys".into(),
                stage: "generic gate synthesis".into(),
                message: lines[lines.len().saturating_sub(40)..].join("\n"),
            }));
        }
        let stat_text = std::fs::read_to_string(&stat).map_err(|e| Error::io(&stat, e))?;
        let ltp_text = std::fs::read_to_string(&ltp).map_err(|e| Error::io(&ltp, e))?;
        let cells = parse_stat_json(&stat_text, top).unwrap_or_default();
        let g = gate_stats(&cells, &ltp_text).ok_or_else(|| Error::ToolOutput {
            tool: "yosys".into(),
            message: format!(
                "no gate statistics or longest path for `{top}` in {}",
                dir.display()
            ),
        })?;
        self.store(&key, &g)?;
        let _ = std::fs::remove_dir_all(&dir);
        Ok((g, false))
    }
}

/// Classifies the cells of the generic netlist and parses the `ltp -noff` output.
pub fn gate_stats(cells: &BTreeMap<String, u64>, ltp: &str) -> Option<GateStats> {
    if cells.is_empty() {
        return None;
    }
    let mut g = GateStats {
        cells: cells.clone(),
        ..Default::default()
    };
    for (name, &n) in cells {
        match name.as_str() {
            "$_AND_" | "$_NAND_" | "$_OR_" | "$_NOR_" | "$_XOR_" | "$_XNOR_" | "$_ANDNOT_"
            | "$_ORNOT_" => g.gates += n,
            "$_MUX_" => {
                g.gates += n;
                g.muxes += n;
            }
            "$_NOT_" => g.inverters += n,
            s if s.contains("DFF") => g.ffs += n,
            _ => g.other += n,
        }
    }
    let (depth, from, to) = parse_ltp(ltp)?;
    g.depth = depth;
    g.path_from = from;
    g.path_to = to;
    Some(g)
}

/// (length, start, end) of `ltp` output. Parsed from its text by hand: `ltp` has no JSON
/// form (Yosys 0.23 offers only `-noff`), unlike `stat -json`.
pub fn parse_ltp(text: &str) -> Option<(u64, String, String)> {
    let mut length = None;
    let mut from = None;
    let mut to = None;
    for line in text.lines() {
        let t = line.trim();
        if let Some(rest) = t.strip_prefix("Longest topological path in ") {
            let l = rest.split("length=").nth(1)?;
            let digits: String = l.chars().take_while(|c| c.is_ascii_digit()).collect();
            length = digits.parse::<u64>().ok();
            continue;
        }
        if length.is_none() {
            continue;
        }
        let Some((idx, name)) = t.split_once(": ") else {
            continue;
        };
        let name = name.split(" (via ").next().unwrap_or(name);
        let name = name.trim_start_matches('\\').to_string();
        if idx == "0" {
            from = Some(name.clone());
        }
        if idx == "ff" || idx.chars().all(|c| c.is_ascii_digit()) {
            to = Some(name);
        }
    }
    Some((length?, from.unwrap_or_default(), to.unwrap_or_default()))
}

/// Default cache directory: `$XDG_CACHE_HOME/sinedec/yosys`, else `$HOME/.cache/sinedec/yosys`,
/// else `.sinedec-cache/yosys` beside the output directory.
pub fn default_cache_dir(output: &Path) -> PathBuf {
    if let Some(x) = std::env::var_os("XDG_CACHE_HOME").filter(|v| !v.is_empty()) {
        return PathBuf::from(x).join("sinedec").join("yosys");
    }
    if let Some(h) = std::env::var_os("HOME").filter(|v| !v.is_empty()) {
        return PathBuf::from(h)
            .join(".cache")
            .join("sinedec")
            .join("yosys");
    }
    let parent = match output.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    parent.join(".sinedec-cache").join("yosys")
}
