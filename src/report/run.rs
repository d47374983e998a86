//! The report's runs: every design (per-N cores of both architectures, blocks, the top)
//! is generated, synthesized with Yosys and routed with nextpnr-ecp5 in one parallel pool,
//! and the accuracy is swept; [`build`] assembles the [`Report`].

use super::*;

pub(super) fn progress_bar(show: bool, total: u64) -> indicatif::ProgressBar {
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
    // Entered before it exists: a signal removes it with its content.
    let _work_entry = crate::cleanup::temp_dir(&work);
    let result = (|| {
        let ys = Yosys::new(opts.cache_dir.clone(), work.clone())?;
        // The same cache directory: the entries' names are hashes with distinct prefixes.
        let pnr = Ecp5::new(opts.cache_dir.clone(), work.join("ecp5"))?;
        build_inner(loaded, opts, &designs, angle_design, angle_n, &ys, &pnr)
    })();
    let _ = std::fs::remove_dir_all(&work);
    result
}

/// One Verilog design to synthesize (a per-N core, the other architecture's core, or a
/// block); identical designs are synthesized once.
pub(super) struct Unit {
    verilog: String,
    top: String,
    tag: String,
    generic: bool,
    weight: u32,
}

#[derive(Clone, Copy)]
pub(super) enum Job {
    Family(usize, Family),
    Generic(usize),
    Pnr(usize),
}

pub(super) enum JobOut {
    Family(SynthStats, bool),
    Generic(GateStats, bool),
    Pnr(PnrTiming, bool),
}

pub(super) fn add_unit(units: &mut Vec<Unit>, u: Unit) -> usize {
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

pub(super) fn arch_name(a: Architecture) -> &'static str {
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

pub(super) fn build_inner(
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
    let jobs = jobs_for(&units);
    bar.set_length(jobs.len() as u64 + sweep::rows(plan));
    bar.set_message("synthesizing, placing, routing");
    let outs = run_jobs(&jobs, &units, ys, pnr, clock_mhz, &bar)?;
    let Figures {
        xc,
        cy,
        ge,
        pn,
        hits,
        runs,
        pnr_hits,
        pnr_runs,
    } = figures(&jobs, outs, units.len())?;
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
                (Ok(o), Some(k)) => OtherArch::Figures(Box::new(ArchFigures {
                    architecture: other_arch,
                    latency_cycles: o.derived.latency_cycles,
                    cycles_per_sample: o.derived.cycles_per_sample,
                    xc3sa: xc[k].clone(),
                    cyclone: cy[k].clone(),
                    ecp5: pn[k].clone(),
                })),
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

/// The tool runs per unit: ECP5 place and route, the two families' synthesis, and the
/// generic gate count for the units that ask for it.
fn jobs_for(units: &[Unit]) -> Vec<Job> {
    units
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
        .collect()
}

/// Runs every job in one parallel pool, the longest first; each result with its job's
/// index.
fn run_jobs(
    jobs: &[Job],
    units: &[Unit],
    ys: &Yosys,
    pnr: &Ecp5,
    clock_mhz: f64,
    bar: &indicatif::ProgressBar,
) -> Result<Vec<(usize, JobOut)>> {
    // Longest runs first (the whole top, large N, generic) so the two cores stay busy.
    let weight = |j: &Job| match *j {
        Job::Generic(i) => units[i].weight * 3 / 2 + 2,
        Job::Pnr(i) => units[i].weight * 2 + 3,
        Job::Family(i, _) => units[i].weight,
    };
    let mut order: Vec<usize> = (0..jobs.len()).collect();
    order.sort_by_key(|&j| std::cmp::Reverse(weight(&jobs[j])));
    order
        .par_iter()
        .map(|&j| {
            let r = match jobs[j] {
                Job::Family(i, fam) => {
                    let u = &units[i];
                    let tag = format!("{}_{}", u.tag, fam.name());
                    ys.family_indexed(&u.verilog, &u.top, fam, &tag)
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
        .collect::<Result<_>>()
}

/// The tools' figures per unit, and how many runs the caches answered.
struct Figures {
    /// Spartan-3A synthesis, per unit.
    xc: Vec<SynthStats>,
    /// Cyclone IV E synthesis, per unit.
    cy: Vec<SynthStats>,
    /// Generic gate counts, per unit (default where not asked for).
    ge: Vec<GateStats>,
    /// ECP5 post-route timing, per unit.
    pn: Vec<PnrTiming>,
    /// Yosys runs the cache answered.
    hits: usize,
    /// Yosys runs made.
    runs: usize,
    /// Place-and-route runs the cache answered.
    pnr_hits: usize,
    /// Place-and-route runs made.
    pnr_runs: usize,
}

/// Sorts the jobs' results into [`Figures`] by unit.
fn figures(jobs: &[Job], outs: Vec<(usize, JobOut)>, n_units: usize) -> Result<Figures> {
    let mut xc = vec![SynthStats::default(); n_units];
    let mut cy = vec![SynthStats::default(); n_units];
    let mut ge = vec![GateStats::default(); n_units];
    let mut pn = vec![PnrTiming::default(); n_units];
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
    Ok(Figures {
        xc,
        cy,
        ge,
        pn,
        hits,
        runs,
        pnr_hits,
        pnr_runs,
    })
}
