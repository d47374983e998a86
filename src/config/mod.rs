//! Configuration: the TOML schema, its validation, and the parameters derived from it.
//!
//! Parameters flow one way: TOML text -> [`Config`] (parsed, ranges checked while
//! deserializing so errors carry line and column) -> [`Derived`] (cross-field checks,
//! widths, tables and figures computed once) -> the rust-hdl blocks and the Rust model.
//!
//! Supported ranges (enforced here, stated in the README):
//!
//! | key | range |
//! |---|---|
//! | `adc.width` | 10..=16 bits |
//! | `cordic.iterations` | 1..=20 |
//! | `cordic.fine_bits` | 2..=16 |
//! | `cordic.guard_bits` | 0..=19 and `adc.width` + 2 + guard <= 31 (default: derived) |
//! | `cordic.architecture` | `"unrolled"` (default) or `"iterative"` |
//! | `encoder.ppr` | 1..=65535 |
//! | `encoder.multiturn_bits` | 0..=16 |
//! | `clock.frequency_hz` | 1 MHz..=500 MHz |
//! | `adc.sample_rate_hz` | up to the ADC's limit and the clock |
//! | `correction.periods` | 1..=256 |
//! | `correction.gain_frac_bits` | 8..=15 |
//! | `correction.phase_deg` | -15..=15 degrees (static mode) |
//! | `correction.min_samples` | 1..=2^24 samples (auto mode: also more than 2041 clocks) |
//! | `monitor.los_window`, `monitor.clip_hold` | 1..=65535 samples |
//!
//! `check`, `generate`, `simulate` and `report` all validate through [`Loaded::parse`]
//! (`Derived::compute`), which also builds the capacitive front end's parameters, so a
//! configuration one command accepts is accepted by all of them.
//!
//! The files: `schema` (the TOML tables as serde structs, ranges and defaults), `pins` (the
//! board top's pinned ports and the Starter Kit's known pins), `derived` ([`Derived`] and
//! its description), `params` (each block's parameters built and checked from the config),
//! `spans` (line and column of a key in the text, echoed values).

use crate::blocks::adc::{AdcFrame, AdcParams, AdcTiming, SignFormat};
use crate::blocks::biss::BissParams;
use crate::blocks::correction::{gain_code, phase_codes, CorrectionParams};
use crate::blocks::monitor::MonitorParams;
use crate::blocks::preamp::PreampParams;
use crate::blocks::qep::QepParams;
use crate::blocks::spi_slave::SpiSlaveParams;
use crate::blocks::ssi::SsiParams;
use crate::blocks::velocity::VelocityParams;
use crate::error::{Error, Quoted, Result};
use crate::exact;
use serde::{Deserialize, Deserializer};

mod adc;
mod biss;
mod checks;
mod derived;
mod describe;
mod params;
mod pins;
mod schema;
mod spans;
mod velocity;

pub use crate::blocks::params::{Architecture, CapDerived, CapacitiveConfig, Derived};
use adc::adc_params;
use biss::biss_params;
pub use biss::BissConfig;
pub use checks::*;
pub use params::*;
pub use pins::*;
pub use schema::*;
pub use spans::*;
use velocity::{velocity_frame_bits, velocity_params};

/// The default configuration (the thesis's Spartan-3AN Starter Kit design), embedded.
pub const DEFAULT_CONFIG: &str = include_str!("../../configs/spartan3an.toml");

/// Name used in messages for the embedded default.
pub const DEFAULT_NAME: &str = "<default spartan3an.toml>";

/// A parsed configuration together with the text it came from.
#[derive(Clone, Debug)]
pub struct Loaded {
    /// The validated config.
    pub config: Config,
    /// Derived parameters.
    pub derived: Derived,
    /// The exact TOML text (hashed into file headers).
    pub text: String,
    /// Name of the source for messages.
    pub source_name: String,
}

impl Loaded {
    /// Parses and validates `text`; `source_name` is used in error messages.
    pub fn parse(text: &str, source_name: &str) -> Result<Loaded> {
        Loaded::parse_unescaped(text, source_name).map_err(|e| match e {
            // Text from the config (a key, a value) never reaches the terminal raw.
            Error::ConfigSyntax {
                source_name,
                line,
                column,
                message,
            } => Error::ConfigSyntax {
                source_name: escape_controls(&source_name),
                line,
                column,
                message: escape_controls(&message),
            },
            Error::ConfigValue {
                source_name,
                location,
                key,
                message,
            } => Error::ConfigValue {
                source_name: escape_controls(&source_name),
                location,
                key: escape_controls(&key),
                message: escape_controls(&message),
            },
            e => e,
        })
    }

    fn parse_unescaped(text: &str, source_name: &str) -> Result<Loaded> {
        let config: Config = toml::from_str(text).map_err(|e| {
            let (line, column) = e.span().map(|s| line_col(text, s.start)).unwrap_or((1, 1));
            Error::ConfigSyntax {
                source_name: source_name.to_string(),
                line,
                column,
                message: syntax_message(&e, text),
            }
        })?;
        let derived = Derived::compute(&config, text, source_name)?;
        Ok(Loaded {
            config,
            derived,
            text: text.to_string(),
            source_name: source_name.to_string(),
        })
    }

    /// What `generate` writes as the board top and whether `simulate` runs, two lines that
    /// `check` prints before the derived parameters.
    pub fn scope(&self) -> String {
        let c = &self.config;
        let name = &c.name;
        let (top, sim) = if c.capacitive.is_some() {
            (
                format!("{name}_top.v: the capacitive top (excitation NCO, filters, demodulation, CORDIC, BiSS-C){}", if c.board.is_some() { ", with its QSF and SDC" } else { "" }),
                format!("available: runs {name}_top against the capacitive encoder and ADC models"),
            )
        } else {
            let d = &self.derived;
            let chip = d.adc.chip.to_string();
            let pre = if d.preamp.is_some() {
                ", LTC6912-1"
            } else {
                ""
            };
            let constraints = match (&c.board, c.target) {
                (Some(_), Target::Spartan3an) => ", with its UCF",
                _ => "",
            };
            (
                format!("{name}_top.v: the sinewave board top ({chip}{pre}, correction, core, BiSS-C){constraints}"),
                match d.preamp {
                    Some(_) => format!("available: runs {name}_top against the encoder, {chip} and LTC6912-1 models"),
                    None => format!("available: runs {name}_top against the encoder and {chip} models"),
                },
            )
        };
        format!(
            "board top                   {top}
simulate                    {sim}
"
        )
    }

    /// The embedded default configuration.
    pub fn default_config() -> Result<Loaded> {
        Loaded::parse(DEFAULT_CONFIG, DEFAULT_NAME)
    }

    /// Reads and parses a file.
    pub fn from_file(path: &std::path::Path) -> Result<Loaded> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
        Loaded::parse(&text, &path.display().to_string())
    }

    /// FNV-1a 64-bit hash of the config text, printed in every file header. Written out
    /// here (five lines) rather than taken from a hashing crate: the value is part of every
    /// emitted file, so it must never move with a dependency's version.
    pub fn hash(&self) -> String {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        for b in self.text.bytes() {
            h ^= b as u64;
            h = h.wrapping_mul(0x0000_0100_0000_01b3);
        }
        format!("{h:016x}")
    }
}
