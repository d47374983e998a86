//! sinedec command line: a thin layer over the library.
use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use sinedec::config::Loaded;
use std::path::{Path, PathBuf};

#[derive(Parser)]
#[command(
    name = "sinedec",
    version,
    about = "Generates verified Verilog for an FPGA sine/cosine encoder decoder"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Writes Verilog and the parameter report for a configuration.
    Generate {
        /// Configuration file (TOML); the embedded Spartan-3AN default when omitted.
        config: Option<PathBuf>,
        /// Output directory (replaced atomically).
        #[arg(short, long, default_value = "out")]
        output: PathBuf,
    },
    /// Simulates the board top cycle by cycle against encoder, ADC and amplifier models.
    Simulate {
        /// Configuration file (TOML); the embedded default when omitted.
        config: Option<PathBuf>,
        /// Speed profile: constant:RPM, ramp:FROM:TO:SECONDS, reversal:RPM:AT_S:OVER_S, creep.
        #[arg(long, default_value = "constant:300")]
        profile: String,
        /// Simulated time in seconds.
        #[arg(long, default_value_t = 0.002)]
        duration: f64,
        /// Track amplitude as a fraction of the ADC input range.
        #[arg(long, default_value_t = 0.8)]
        amplitude: f64,
        /// Gaussian noise, RMS in ADC LSB.
        #[arg(long, default_value_t = 0.0)]
        noise_lsb: f64,
        /// Offset of the sin track, fraction of the amplitude.
        #[arg(long, default_value_t = 0.0)]
        offset_sin: f64,
        /// Offset of the cos track, fraction of the amplitude.
        #[arg(long, default_value_t = 0.0)]
        offset_cos: f64,
        /// Relative gain mismatch of the tracks.
        #[arg(long, default_value_t = 0.0)]
        gain_mismatch: f64,
        /// Quadrature phase error in degrees.
        #[arg(long, default_value_t = 0.0)]
        phase_error: f64,
        /// Third-harmonic ratio.
        #[arg(long, default_value_t = 0.0)]
        harmonic3: f64,
        /// Noise seed.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Write every decoded sample as CSV.
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Write the top's pins, cycle by cycle, as VCD.
        #[arg(long)]
        vcd: Option<PathBuf>,
    },
    /// Validates a configuration and prints its derived parameters.
    Check {
        /// Configuration file (TOML); the embedded default when omitted.
        config: Option<PathBuf>,
    },
    /// Writes a commented example configuration.
    Init {
        /// Where to write it.
        #[arg(default_value = "sinedec.toml")]
        path: PathBuf,
        /// Overwrite an existing file.
        #[arg(long)]
        force: bool,
    },
    /// Gates, LUTs, flip-flops, latency and accuracy per CORDIC iteration count (both
    /// architectures), and every block of the top synthesized alone.
    Report {
        /// Configuration file (TOML); the embedded default when omitted.
        config: Option<PathBuf>,
        /// Iteration counts: A..=B, A..B, A-B, N or a comma-separated list (1..=20).
        #[arg(long, default_value = "2..=20")]
        iterations: String,
        /// Output directory (replaced atomically).
        #[arg(short, long, default_value = "report")]
        output: PathBuf,
        /// Files to write: comma-separated md, csv (per N and per block), json, svg.
        #[arg(long, default_value = "md,csv,json,svg")]
        format: String,
        /// N of the error-against-angle plot (default: the config's N).
        #[arg(long)]
        angle_n: Option<u32>,
        /// Yosys result cache (default: $XDG_CACHE_HOME/sinedec/yosys or ~/.cache/sinedec/yosys).
        #[arg(long)]
        cache_dir: Option<PathBuf>,
        /// Run every Yosys synthesis again instead of using the cache.
        #[arg(long)]
        no_cache: bool,
    },
}

fn load(config: &Option<PathBuf>) -> Result<Loaded> {
    Ok(match config {
        Some(p) => Loaded::from_file(p)?,
        None => Loaded::default_config()?,
    })
}

/// The command line as quoted in file headers (program name normalized so the bytes do not
/// depend on where the binary lives).
fn command_line() -> String {
    let args: Vec<String> = std::env::args().skip(1).collect();
    format!("sinedec {}", args.join(" "))
}

fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Generate { config, output } => {
            let loaded = load(&config)?;
            let generation = sinedec::emit::generate(&loaded, &command_line())?;
            sinedec::emit::write_output(&generation, &output)?;
            for f in &generation.files {
                println!("wrote {}", output.join(&f.name).display());
            }
        }
        Command::Simulate {
            config,
            profile,
            duration,
            amplitude,
            noise_lsb,
            offset_sin,
            offset_cos,
            gain_mismatch,
            phase_error,
            harmonic3,
            seed,
            csv,
            vcd,
        } => {
            let loaded = load(&config)?;
            if !(duration > 0.0 && duration <= 10.0) {
                bail!("--duration {duration}: allowed 0 < seconds <= 10");
            }
            let o = sinedec::simulate::SimOptions {
                profile: sinedec::simulate::parse_profile(&profile).map_err(anyhow::Error::msg)?,
                duration_s: duration,
                amplitude,
                noise_lsb,
                offset: (offset_sin, offset_cos),
                gain_mismatch,
                phase_error_deg: phase_error,
                third_harmonic: harmonic3,
                seed,
                ..Default::default()
            };
            // The VCD streams to disk during the run.
            let trace: Option<Box<dyn std::io::Write>> = match &vcd {
                Some(p) => Some(Box::new(std::io::BufWriter::new(
                    std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?,
                ))),
                None => None,
            };
            let total = (duration * loaded.derived.clock_hz).ceil() as u64;
            let bar = indicatif::ProgressBar::new(total);
            bar.set_style(
                indicatif::ProgressStyle::with_template("{bar:40} {pos}/{len} cycles {eta}")
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            if loaded.derived.capacitive.is_some() {
                let (s, table) = sinedec::simulate::run_capacitive_traced(
                    &loaded,
                    &o,
                    |done, _| bar.set_position(done),
                    trace,
                )?;
                bar.finish_and_clear();
                print!("{s}");
                if let Some(p) = csv {
                    write_new(&p, &table)?;
                    println!("wrote {}", p.display());
                }
                if let Some(p) = vcd {
                    println!("wrote {}", p.display());
                }
                return Ok(());
            }
            let report =
                sinedec::simulate::run_traced(&loaded, &o, |done, _| bar.set_position(done), trace)?;
            bar.finish_and_clear();
            print!("{}", report.summary(&loaded));
            if let Some(p) = csv {
                write_new(&p, &report.csv(&loaded, o.skip))?;
                println!("wrote {}", p.display());
            }
            if let Some(p) = vcd {
                println!("wrote {}", p.display());
            }
        }
        Command::Check { config } => {
            let loaded = load(&config)?;
            println!("{}: ok", loaded.source_name);
            print!("{}", loaded.derived.describe());
            print!("{}", loaded.derived.adc.describe());
            if let Some(k) = &loaded.derived.capacitive {
                println!("\nband-pass (quantized {}):", k.config.coef.width);
                print!("{}", k.bandpass.to_markdown());
                println!("\nlow-pass (both branches):");
                print!("{}", k.lowpass.to_markdown());
            }
            if let Some(p) = &loaded.derived.preamp {
                println!(
                    "preamp                      LTC6912-1 gains A {} B {}, word 0x{:02x}, set-up {} clocks",
                    p.gain_a,
                    p.gain_b,
                    p.word(),
                    p.done_clocks()
                );
            }
        }
        Command::Report {
            config,
            iterations,
            output,
            format,
            angle_n,
            cache_dir,
            no_cache,
        } => {
            let loaded = load(&config)?;
            let mut o = sinedec::report::Options::new(&command_line());
            o.iterations =
                sinedec::report::parse_iterations(&iterations).map_err(anyhow::Error::msg)?;
            o.formats = sinedec::report::Formats::parse(&format).map_err(anyhow::Error::msg)?;
            o.angle_n = angle_n;
            o.cache_dir = (!no_cache).then(|| {
                cache_dir.unwrap_or_else(|| sinedec::report::yosys::default_cache_dir(&output))
            });
            o.progress = true;
            let (generation, report) = sinedec::report::run(&loaded, &o, &output)?;
            for f in &generation.files {
                println!("wrote {}", output.join(&f.name).display());
            }
            eprintln!(
                "yosys: {} runs, {} answered from the cache",
                report.yosys_runs, report.cache_hits
            );
        }
        Command::Init { path, force } => {
            if path.exists() && !force {
                bail!("{} exists; pass --force to overwrite it", path.display());
            }
            write_new(&path, sinedec::config::DEFAULT_CONFIG)?;
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}

fn write_new(path: &Path, text: &str) -> Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    std::fs::write(&tmp, text).with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("renaming onto {}", path.display()))?;
    Ok(())
}

fn main() {
    let cli = Cli::parse();
    if let Err(e) = run(cli) {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}
