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
        Command::Check { config } => {
            let loaded = load(&config)?;
            println!("{}: ok", loaded.source_name);
            print!("{}", loaded.derived.describe());
            print!("{}", loaded.derived.adc.describe());
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
    let tmp = path.with_extension("toml.tmp");
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
