//! `sinedec datasheet`: the configured `<name>_top` characterized in its closed loop over a
//! grid of operating points ([`grid`], in parallel) and drawn as one data-sheet page,
//! `index.html` (inline SVG figures, tables, print CSS, no external asset), with the
//! tables' numbers in `datasheet.json`. The files go through the output-directory rule of
//! `generate` (`crate::emit::output`). Same config and command, same bytes: no time or
//! path enters the page.
//!
//! Two pages, by the config's path:
//!
//! ```text
//!   sinewave    grid.rs, tables.rs, samples.rs, figures.rs -> page::html
//!   capacitive  capacitive.rs (grid, tables, figures)      -> page::cap_html
//! ```
//!
//! A `[capacitive]` config gets its own page ([`capacitive`]): error in mechanical degrees
//! against angle and speed through the filters, processing time, resources; the sinewave
//! page's correction, Lissajous figure, QEP fallback and velocity do not apply there, and
//! the page says so in one line.
use crate::config::Loaded;
use crate::emit::{Generation, OutFile};
use crate::error::{Error, Result};
use serde::Serialize;

pub mod capacitive;
mod figures;
pub mod grid;
mod page;
pub mod resources;
pub mod samples;
mod tables;

pub use grid::Plan;
pub use tables::*;

/// What to run and how the page names its origin.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// The reduced grid (CI): fewer speeds, shorter runs.
    pub quick: bool,
    /// The command line, quoted on the page.
    pub command: String,
    /// The config argument as the user gave it (None: the embedded default), for commands
    /// the page suggests.
    pub config_arg: Option<String>,
}

/// One figure of the page.
#[derive(Clone, Debug)]
pub struct Figure {
    /// Anchor id (`fig-accuracy`).
    pub id: String,
    /// Caption.
    pub caption: String,
    /// The SVG document.
    pub svg: String,
}

/// The tables of either page (`datasheet.json` is the inner value as it is: no tag).
#[derive(Clone, Debug, Serialize)]
#[serde(untagged)]
pub enum AnySheet {
    /// The sinewave path's page.
    Sinewave(Box<Sheet>),
    /// The capacitive path's page.
    Capacitive(Box<capacitive::CapSheet>),
}

/// A characterized decoder: the tables (also the JSON) and the figures.
#[derive(Clone, Debug)]
pub struct Datasheet {
    /// Every number of the page's tables.
    pub sheet: AnySheet,
    /// The figures, in page order.
    pub figures: Vec<Figure>,
    /// The engine's fallback, if the compiled engine did not run (for stderr).
    pub engine_note: Option<String>,
}

/// Clock cycles of every run of the grid of `loaded` (the progress bar's length).
pub fn total_cycles(loaded: &Loaded, quick: bool) -> u64 {
    if loaded.derived.capacitive.is_some() {
        capacitive::CapPlan::new(loaded, quick).total_cycles(loaded)
    } else {
        Plan::new(loaded, quick).total_cycles(loaded)
    }
}

/// Runs the grid of `opts` (`progress(cycles)` as the runs advance, from any thread) and
/// builds the page's tables and figures: the capacitive page for a `[capacitive]` config,
/// else the sinewave page.
pub fn build(
    loaded: &Loaded,
    opts: &Options,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<Datasheet> {
    if loaded.derived.capacitive.is_some() {
        let (sheet, figures, engine_note) = capacitive::build(loaded, opts, progress)?;
        return Ok(Datasheet {
            sheet: AnySheet::Capacitive(Box::new(sheet)),
            figures,
            engine_note,
        });
    }
    let plan = Plan::new(loaded, opts.quick);
    let runs = plan.run(loaded, progress)?;
    let analysis = tables::analyse(loaded, &plan, &runs);
    let sheet = tables::sheet(loaded, opts, &plan, &runs, &analysis)?;
    let figures = figures::figures(&plan, &analysis, &sheet)?;
    Ok(Datasheet {
        sheet: AnySheet::Sinewave(Box::new(sheet)),
        figures,
        engine_note: runs.engine_note,
    })
}

impl Datasheet {
    /// `index.html` and `datasheet.json`, for [`crate::emit::write_output_with`].
    pub fn render(&self, loaded: &Loaded) -> Result<Generation> {
        let json = serde_json::to_string_pretty(&self.sheet).map_err(|e| Error::Json {
            what: "datasheet".into(),
            source: e,
        })? + "\n";
        Ok(Generation {
            files: vec![
                OutFile {
                    name: "index.html".into(),
                    text: match &self.sheet {
                        AnySheet::Sinewave(s) => page::html(loaded, self, s),
                        AnySheet::Capacitive(s) => page::cap_html(loaded, self, s),
                    },
                },
                OutFile {
                    name: "datasheet.json".into(),
                    text: json,
                },
            ],
        })
    }
}

/// Every number of the page's tables, as `datasheet.json` holds them.
#[derive(Clone, Debug, Serialize)]
pub struct Sheet {
    /// `sinedec 0.1.0 (commit abc1234)`.
    pub generator: String,
    /// The config's name (`<default spartan3an.toml>` or its path as given).
    pub config_name: String,
    /// The config's hash (as in the generated files' headers).
    pub config_hash: String,
    /// The command that wrote the page.
    pub command: String,
    /// Whether the reduced grid ran.
    pub quick: bool,
    /// Key figures.
    pub overview: Overview,
    /// The imperfections of the runs "with imperfections".
    pub conditions: Conditions,
    /// Error at the three accuracy speeds.
    pub accuracy: Vec<AccuracyRow>,
    /// Error (and velocity noise) against speed.
    pub sweep: Vec<SweepRow>,
    /// Latency from CONV to each output.
    pub latency: Vec<LatencyRow>,
    /// The correction and, when automatic, its convergence.
    pub correction: CorrectionSheet,
    /// The velocity estimator (None: `[velocity]` off).
    pub velocity: Option<VelocitySheet>,
    /// Resources and Fmax.
    pub resources: resources::Resources,
    /// The config's text, so that the page can be reproduced.
    pub config_text: String,
}
