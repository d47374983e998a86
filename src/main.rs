//! sinedec command line: a thin layer over the library.
//!
//! Standard output goes through [`out`]: a reader that went away (`sinedec check | head -1`)
//! ends the program quietly with status 141, the status a shell shows for `cat` killed by
//! SIGPIPE; any other write error (`> /dev/full`) is reported with status 1. Errors are
//! printed once each (see [`message`]), long echoed values clipped.
use anyhow::{bail, Result};
use clap::Parser;
use sinedec::config::Loaded;
use sinedec::emit::output::{check_output_dir, same_file, OutputOptions, PendingFile};
use std::io::Write;
use std::path::PathBuf;

mod cli;
use cli::{Cli, Command, EngineArg, SimulateArgs};

/// Largest configuration file read, bytes: a config is a few kB; a larger file (or a
/// device such as /dev/zero) is not one.
const MAX_CONFIG_BYTES: u64 = 1 << 20;

fn load(config: &Option<PathBuf>) -> Result<Loaded> {
    Ok(match config {
        Some(p) => {
            // A missing file is reported by the loader, with its own words.
            if let Ok(m) = std::fs::metadata(p) {
                if !m.is_file() {
                    let what = if m.is_dir() {
                        "a directory"
                    } else {
                        "not a regular file (a device, FIFO or socket)"
                    };
                    bail!(
                        "{}: is {what}; give the path of a TOML configuration file",
                        p.display()
                    );
                }
                if m.len() > MAX_CONFIG_BYTES {
                    bail!(
                        "{}: is {} bytes; a configuration file is at most 1 MB ({MAX_CONFIG_BYTES} bytes)",
                        p.display(),
                        m.len()
                    );
                }
            }
            Loaded::from_file(p)?
        }
        None => Loaded::default_config()?,
    })
}

/// Refuses an output path that names the configuration or another output (`--csv cfg.toml`,
/// `--csv x --vcd x`): one file cannot be both.
fn distinct_outputs(config: &Option<PathBuf>, outputs: &[(&str, Option<&PathBuf>)]) -> Result<()> {
    for (i, (opt, path)) in outputs.iter().enumerate() {
        let Some(path) = path else { continue };
        if let Some(c) = config.as_ref().filter(|c| same_file(c, path)) {
            bail!(
                "{opt} {}: is the configuration file {}, which this run reads; give the output another path",
                path.display(),
                c.display()
            );
        }
        for (other, q) in &outputs[..i] {
            if q.is_some_and(|q| same_file(q, path)) {
                bail!(
                    "{opt} {}: is also the path of {other}; give each output its own path",
                    path.display()
                );
            }
        }
    }
    Ok(())
}

/// The command line as quoted in file headers (program name normalized so the bytes do not
/// depend on where the binary lives). An argument that is not UTF-8 is quoted lossily (U+FFFD
/// for each bad byte); the header escapes control characters (`emit::comment_text`).
fn command_line() -> String {
    let args: Vec<String> = std::env::args_os()
        .skip(1)
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    format!("sinedec {}", args.join(" "))
}

/// A failed write to standard output.
#[derive(Debug)]
struct StdoutError(std::io::Error);

impl std::fmt::Display for StdoutError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "writing to standard output: {}", self.0)
    }
}

impl std::error::Error for StdoutError {}

/// Writes `text` to standard output and flushes it, so a full disk is seen here.
fn out(text: &str) -> Result<()> {
    let mut o = std::io::stdout().lock();
    o.write_all(text.as_bytes())
        .and_then(|_| o.flush())
        .map_err(|e| anyhow::Error::new(StdoutError(e)))
}

/// `println!` through [`out`].
macro_rules! say {
    ($($t:tt)*) => { out(&format!("{}\n", format_args!($($t)*))) };
}

/// `sinedec simulate`: checks the options and outputs, runs the closed loop with a progress
/// bar, then writes the CSV and VCD and prints the summary.
fn simulate(args: SimulateArgs) -> Result<()> {
    let SimulateArgs {
        config,
        profile,
        duration,
        amplitude,
        noise_lsb,
        offset_sin,
        offset_cos,
        gain_mismatch,
        phase_error,
        harmonic2,
        harmonic2_phase,
        harmonic3,
        harmonic3_phase,
        harmonic5,
        harmonic5_phase,
        eccentricity,
        settle,
        seed,
        capture_hz,
        fault,
        csv,
        vcd,
        engine,
    } = args;
    let loaded = load(&config)?;
    if !(duration > 0.0 && duration <= 10.0) {
        bail!("--duration {duration}: allowed 0 < seconds <= 10");
    }
    distinct_outputs(&config, &[("--csv", csv.as_ref()), ("--vcd", vcd.as_ref())])?;
    // The output files are checked (and their temporary files created beside them)
    // before the simulation runs.
    let mut csv_out = csv.as_deref().map(PendingFile::new).transpose()?;
    let mut vcd_out = vcd.as_deref().map(PendingFile::new).transpose()?;
    let o = sinedec::simulate::SimOptions {
        profile: sinedec::simulate::parse_profile(&profile)?,
        duration_s: duration,
        amplitude,
        noise_lsb,
        offset: (offset_sin, offset_cos),
        gain_mismatch,
        phase_error_deg: phase_error,
        second_harmonic: harmonic2,
        third_harmonic: harmonic3,
        fifth_harmonic: harmonic5,
        harmonic_phase_deg: [harmonic2_phase, harmonic3_phase, harmonic5_phase],
        eccentricity_arcsec: eccentricity,
        settle_s: settle,
        seed,
        engine: match engine {
            None => sinedec::sim::dut::EngineKind::Auto,
            Some(EngineArg::RustHdl) => sinedec::sim::dut::EngineKind::RustHdl,
            Some(EngineArg::Compiled) => sinedec::sim::dut::EngineKind::Compiled,
            Some(EngineArg::Interpreter) => sinedec::sim::dut::EngineKind::Interpreted,
        },
        // Without --csv no sample is kept: memory stays bounded on long runs.
        keep_records: csv.is_some(),
        capture_hz,
        faults: fault
            .iter()
            .map(|f| sinedec::simulate::parse_fault(f))
            .collect::<std::result::Result<Vec<_>, _>>()?,
        ..Default::default()
    };
    if let Some(w) = sinedec::simulate::speed_warning(&loaded, &o) {
        let _ = writeln!(std::io::stderr(), "{w}");
    }
    // The VCD streams during the run into its temporary file (checked above, renamed
    // onto the path when the run is complete).
    let trace: Option<Box<dyn std::io::Write>> = match vcd_out.as_mut() {
        Some(f) => Some(Box::new(std::io::BufWriter::new(
            f.file()
                .try_clone()
                .map_err(|e| anyhow::anyhow!("opening the VCD's temporary file: {e}"))?,
        ))),
        None => None,
    };
    let total = (duration * loaded.derived.clock_hz).ceil() as u64;
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} cycles {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    // Files first, then standard output: a closed stdout cannot lose them.
    let mut wrote = vec![];
    let summary = if loaded.derived.capacitive.is_some() {
        let r = sinedec::simulate::run_capacitive_report(
            &loaded,
            &o,
            |done, _| bar.set_position(done),
            trace,
        )?;
        bar.finish_and_clear();
        if let Some(n) = &r.engine_note {
            let _ = writeln!(std::io::stderr(), "{n}");
        }
        if let Some(mut f) = csv_out.take() {
            f.write_all(r.csv.as_bytes())?;
            wrote.push(f.commit()?);
        }
        r.summary
    } else {
        let report =
            sinedec::simulate::run_traced(&loaded, &o, |done, _| bar.set_position(done), trace)?;
        bar.finish_and_clear();
        if let Some(n) = &report.engine_note {
            let _ = writeln!(std::io::stderr(), "{n}");
        }
        if let Some(mut f) = csv_out.take() {
            f.write_all(report.csv(&loaded, o.skip).as_bytes())?;
            wrote.push(f.commit()?);
        }
        report.summary(&loaded)
    };
    if let Some(f) = vcd_out.take() {
        wrote.push(f.commit()?);
    }
    out(&summary)?;
    for p in wrote {
        say!("wrote {}", p.display())?;
    }
    Ok(())
}

/// `sinedec datasheet`: checks the config and the output directory, runs the grid with a
/// progress bar, then writes the page through the output-directory rule.
fn datasheet(config: Option<PathBuf>, output: PathBuf, force: bool, quick: bool) -> Result<()> {
    let mut opts = OutputOptions::new("datasheet");
    opts.force = force;
    let loaded = load(&config)?;
    check_output_dir(&output, &opts)?;
    let o = sinedec::datasheet::Options {
        quick,
        command: command_line(),
        config_arg: config.as_ref().map(|c| c.display().to_string()),
    };
    let total = sinedec::datasheet::total_cycles(&loaded, quick);
    let bar = indicatif::ProgressBar::new(total);
    bar.set_style(
        indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} cycles {eta}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let ds = sinedec::datasheet::build(&loaded, &o, &|n| bar.inc(n))?;
    bar.finish_and_clear();
    if let Some(n) = &ds.engine_note {
        let _ = writeln!(std::io::stderr(), "{n}");
    }
    let generation = ds.render(&loaded)?;
    sinedec::emit::write_output_with(&generation, &output, &opts)?;
    for f in &generation.files {
        say!("wrote {}", output.join(&f.name).display())?;
    }
    Ok(())
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Generate {
            config,
            output,
            force,
        } => {
            let mut opts = OutputOptions::new("generate");
            opts.force = force;
            let loaded = load(&config)?;
            check_output_dir(&output, &opts)?;
            let generation = sinedec::emit::generate(&loaded, &command_line())?;
            sinedec::emit::write_output_with(&generation, &output, &opts)?;
            for f in &generation.files {
                say!("wrote {}", output.join(&f.name).display())?;
            }
        }
        Command::Simulate(args) => simulate(args)?,
        Command::Check { config } => {
            let loaded = load(&config)?;
            say!("{}: ok", loaded.source_name)?;
            out(&loaded.scope())?;
            out(&loaded.derived.describe())?;
            out(&loaded.derived.adc.describe())?;
            if let Some(k) = &loaded.derived.capacitive {
                say!("\nband-pass (quantized {}):", k.config.coef.width)?;
                out(&k.bandpass.to_markdown())?;
                say!("\nlow-pass (both branches):")?;
                out(&k.lowpass.to_markdown())?;
            }
            if let Some(p) = &loaded.derived.preamp {
                say!(
                    "preamp                      LTC6912-1 gains A {} B {}, word 0x{:02x}, set-up {} clocks",
                    p.gain_a,
                    p.gain_b,
                    p.word(),
                    p.done_clocks()
                )?;
            }
            let arg = config.as_ref().map(|c| c.display().to_string());
            // The harmonic table's own figures (`[harmonics]`), then the whole top's.
            if let Some(line) =
                sinedec::report::block_resource_line(&loaded, "harmonics", arg.as_deref())?
            {
                say!("{line}")?;
            }
            if let Some(line) = sinedec::report::top_resource_line(&loaded, arg.as_deref())? {
                say!("{line}")?;
            }
        }
        Command::Report {
            config,
            iterations,
            output,
            force,
            format,
            angle_n,
            cache_dir,
            no_cache,
        } => {
            let mut opts = OutputOptions::new("report");
            opts.force = force;
            let loaded = load(&config)?;
            check_output_dir(&output, &opts)?;
            let mut o = sinedec::report::Options::new(&command_line());
            o.iterations = sinedec::report::parse_iterations(&iterations)?;
            o.formats = sinedec::report::Formats::parse(&format)?;
            o.angle_n = angle_n;
            o.cache_dir = (!no_cache).then(|| {
                cache_dir.unwrap_or_else(|| sinedec::report::yosys::default_cache_dir(&output))
            });
            o.progress = true;
            let report = sinedec::report::build(&loaded, &o)?;
            let generation = report.render(&loaded, &o)?;
            sinedec::emit::write_output_with(&generation, &output, &opts)?;
            let _ = writeln!(
                std::io::stderr(),
                "yosys: {} runs, {} answered from the cache",
                report.yosys_runs,
                report.cache_hits
            );
            for f in &generation.files {
                say!("wrote {}", output.join(&f.name).display())?;
            }
        }
        Command::Datasheet {
            config,
            output,
            force,
            quick,
        } => datasheet(config, output, force, quick)?,
        Command::Init { path, force } => {
            if path.is_dir() {
                bail!(
                    "{}: is a directory; give the path of the file to write",
                    path.display()
                );
            }
            sinedec::emit::output::check_target(&path)?;
            if path.exists() && !force {
                bail!("{}: exists; pass --force to overwrite it", path.display());
            }
            if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
                std::fs::create_dir_all(parent)
                    .map_err(|e| sinedec::error::Error::io(parent, e))?;
            }
            let mut f = PendingFile::new(&path)?;
            f.write_all(sinedec::config::DEFAULT_CONFIG.as_bytes())?;
            if force {
                f.commit()?;
            } else {
                f.commit_new()?;
            }
            say!("wrote {}", path.display())?;
        }
    }
    Ok(())
}

/// The error and its causes, each said once (a cause whose text the message already holds,
/// such as the OS error inside `path: No such file or directory`, is not repeated), with
/// every long word clipped (a 100,000-character value is not echoed whole).
fn message(e: &anyhow::Error) -> String {
    let mut msg = String::new();
    for cause in e.chain() {
        let t = cause.to_string();
        if msg.contains(&t) {
            continue;
        }
        if !msg.is_empty() {
            msg.push_str(": ");
        }
        msg.push_str(&t);
    }
    let clipped: Vec<String> = msg
        .split(' ')
        .map(|w| {
            if w.chars().count() > 300 {
                sinedec::error::clip(w, 200)
            } else {
                w.to_string()
            }
        })
        .collect();
    sinedec::error::clip(&clipped.join(" "), 4000)
}

fn main() {
    let cli = Cli::parse();
    // SIGINT, SIGTERM, SIGHUP: temporaries removed, children killed, exit 130/143/129.
    if let Err(e) = sinedec::cleanup::install() {
        let _ = writeln!(
            std::io::stderr(),
            "warning: cannot handle SIGINT/SIGTERM/SIGHUP ({e}); a stop by a signal may leave temporary files"
        );
    }
    if let Err(e) = run(cli) {
        let broken_pipe = e.chain().any(|c| {
            c.downcast_ref::<StdoutError>()
                .is_some_and(|s| s.0.kind() == std::io::ErrorKind::BrokenPipe)
        });
        if broken_pipe {
            // As a Unix tool killed by SIGPIPE looks to its shell: status 128 + 13, no message.
            std::process::exit(141);
        }
        let _ = writeln!(std::io::stderr(), "error: {}", message(&e));
        std::process::exit(1);
    }
}
