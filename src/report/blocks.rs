//! Per-block rows of the report: every block of the sinewave top synthesized alone, and the
//! whole `<name>_top`.
//!
//! Each row comes from a [`BlockDef`] of the block registry ([`BLOCKS`],
//! `crate::blocks::registry`): a key, a label and a constructor that
//! builds the block's rust-hdl description from the configuration, exports it with
//! [`crate::emit::verilog::export`] under the module name `<name>_blk_<key>` ([`export_block`])
//! and states its timing ([`BlockTiming`]). The report synthesizes every [`BlockJob`] for
//! xc3sa and cycloneive in the same parallel pool and Yosys cache as the per-N designs, and
//! turns the results into [`BlockRow`]s (Markdown table "Blocks of `<name>_top`", the `blocks`
//! array of the JSON and `<name>_report_blocks.csv`).
//!
//! A block's row is its registry entry (`pub const BLOCK` in its folder, e.g.
//! `blocks/abz/mod.rs`, listed in [`BLOCKS`] before the `top` row):
//!
//! ```text
//! BlockDef::report_only("nco", "NCO", |l| job(l, "nco", Nco::new(&l.derived.nco), BlockTiming::latency(2, "phase to output")))
//! ```
//!
//! (a non-capturing closure is a [`BlockCtor`]; [`job`] exports the block as
//! `<name>_blk_nco`). A block whose constructor can fail
//! maps its error into [`crate::error::Error`] (see `biss_job` in `jobs.rs`).
//!
//! A constructor that returns a job without Verilog ([`BlockJob::absent`]) gives a row with
//! empty cells and its reason (e.g. the pre-amplifier of a config without the LTC1407A-1
//! preset); blocks that exist but are disabled in the config are built with their
//! parameters anyway and marked in their note.
use crate::config::Loaded;
use crate::error::Result;
use crate::synth::SynthStats;
use rust_hdl::prelude::Block;

/// Timing of a block, where it has one (all `None` and an explanatory text otherwise).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct BlockTiming {
    /// Cycles from input to output (as defined in `text`).
    pub latency_cycles: Option<u32>,
    /// Clocks per sample (conversion frame, or clocks per accepted sample).
    pub clocks_per_sample: Option<u32>,
    /// Samples per second at the configured clock.
    pub rate_sps: Option<f64>,
    /// What the figures mean (no `|` and no `,`: it is a Markdown and CSV cell).
    pub text: String,
}

impl BlockTiming {
    /// No timing of its own; `text` says why.
    pub fn none(text: &str) -> Self {
        BlockTiming {
            text: text.to_string(),
            ..Default::default()
        }
    }

    /// A latency in cycles.
    pub fn latency(cycles: u32, text: &str) -> Self {
        BlockTiming {
            latency_cycles: Some(cycles),
            text: text.to_string(),
            ..Default::default()
        }
    }
}

/// A block to synthesize alone.
#[derive(Clone, Debug)]
pub struct BlockJob {
    /// Key (CSV/JSON, scratch directory names).
    pub key: String,
    /// Row label.
    pub label: String,
    /// Top module of `verilog`.
    pub module: String,
    /// Verilog of the block (None: the block is not part of this config; `note` says why).
    pub verilog: Option<String>,
    /// Timing.
    pub timing: BlockTiming,
    /// Remark shown after the label (e.g. "disabled in this config"); "" for none.
    pub note: String,
}

impl BlockJob {
    /// A row without synthesis: the block does not exist for this config (`why`).
    pub fn absent(key: &str, why: &str) -> BlockJob {
        BlockJob {
            key: key.to_string(),
            label: String::new(),
            module: String::new(),
            verilog: None,
            timing: BlockTiming::none(""),
            note: why.to_string(),
        }
    }

    /// The same job with a note.
    pub fn with_note(mut self, note: &str) -> BlockJob {
        self.note = note.to_string();
        self
    }
}

pub use crate::blocks::registry::{BlockCtor, BlockDef};

/// Synthesis figures of one block.
#[derive(Clone, Debug)]
pub struct BlockRow {
    /// Key.
    pub key: String,
    /// Label (with the note in parentheses when there is one).
    pub label: String,
    /// Top module synthesized ("" when absent).
    pub module: String,
    /// Timing.
    pub timing: BlockTiming,
    /// xc3sa figures (None when the block is absent from this config).
    pub xc3sa: Option<SynthStats>,
    /// cycloneive figures.
    pub cyclone: Option<SynthStats>,
    /// Post-route ECP5 timing.
    pub ecp5: Option<super::nextpnr::PnrTiming>,
}

/// Module name of a block: `<name>_blk_<key>`.
pub fn block_module(loaded: &Loaded, key: &str) -> String {
    format!("{}_blk_{key}", loaded.config.name)
}

/// Connects `uut` and exports it as `<name>_blk_<key>`: (module name, Verilog).
pub fn export_block<B: Block>(loaded: &Loaded, key: &str, mut uut: B) -> Result<(String, String)> {
    uut.connect_all();
    let module = block_module(loaded, key);
    let v = crate::emit::verilog::export(&uut, key, &module)?;
    Ok((module, v))
}

/// A job for a rust-hdl block with its timing.
pub fn job<B: Block>(loaded: &Loaded, key: &str, uut: B, timing: BlockTiming) -> Result<BlockJob> {
    let (module, verilog) = export_block(loaded, key, uut)?;
    Ok(BlockJob {
        key: key.to_string(),
        label: String::new(),
        module,
        verilog: Some(verilog),
        timing,
        note: String::new(),
    })
}

/// The block table, in row order: the registry ([`crate::blocks::registry::BLOCKS`]).
pub use crate::blocks::registry::BLOCKS;

/// Builds every job of [`BLOCKS`] for the configuration (in order); the label of each is
/// the table's, `whole top` becoming `<name>_top`.
pub fn block_jobs(loaded: &Loaded) -> Result<Vec<BlockJob>> {
    use rayon::prelude::*;
    BLOCKS
        .par_iter()
        .map(|b| {
            let mut j = (b.build)(loaded)?;
            // On the capacitive path the sinewave-only blocks are built for comparison but
            // are not part of its top.
            if loaded.derived.capacitive.is_some()
                && ["correction", "monitor", "qep", "fallback", "ssi", "spi"].contains(&b.key)
                && j.verilog.is_some()
                && j.note.is_empty()
            {
                j = j.with_note("not in the capacitive top");
            }
            j.key = b.key.to_string();
            j.label = if b.key == "top" {
                crate::emit::top_name(loaded)
            } else {
                b.label.to_string()
            };
            Ok(j)
        })
        .collect()
}

/// The row of a job, given its synthesis results.
pub fn block_row(
    j: &BlockJob,
    xc3sa: Option<SynthStats>,
    cyclone: Option<SynthStats>,
    ecp5: Option<super::nextpnr::PnrTiming>,
) -> BlockRow {
    let label = if j.note.is_empty() {
        j.label.clone()
    } else {
        format!("{} ({})", j.label, j.note)
    };
    BlockRow {
        key: j.key.clone(),
        label,
        module: j.module.clone(),
        timing: j.timing.clone(),
        xc3sa,
        cyclone,
        ecp5,
    }
}

/// Columns of the block table: (key used in CSV and JSON, title used in Markdown).
pub const BLOCK_COLUMNS: &[(&str, &str)] = &[
    ("block", "block"),
    ("module", "module"),
    ("xc3sa_lut", "xc3sa LUT4 (incl. INV)"),
    ("xc3sa_ff", "xc3sa FF"),
    ("xc3sa_carry", "xc3sa MUXCY"),
    ("xc3sa_mult", "xc3sa MULT18X18"),
    ("cycloneive_lut", "cycloneive LE"),
    ("cycloneive_ff", "cycloneive FF"),
    ("cycloneive_mult", "cycloneive mult"),
    ("latency_cycles", "latency (cycles)"),
    ("clocks_per_sample", "clocks per sample"),
    ("rate_sps", "rate (samples/s)"),
    ("timing", "timing"),
    (
        "ecp5_fmax_mhz",
        "ECP5-6 post-route Fmax, median of seeds 1-3 (MHz)",
    ),
    ("ecp5_seeds_mhz", "ECP5-6 Fmax at seeds 1 / 2 / 3 (MHz)"),
    ("ecp5_slack_ns", "ECP5-6 slack at the median (ns)"),
    ("ecp5_path", "ECP5 critical path"),
    ("xc3sa_lut_levels", "xc3sa LUT levels"),
    ("xc3sa_carry_bits", "xc3sa carry bits"),
    ("xc3sa_carry_chains", "xc3sa carry chains"),
    ("xc3sa_est_fmax_mhz", "xc3sa -4 est. Fmax (MHz)"),
    ("cycloneive_lut_levels", "cycloneive LUT levels"),
    ("cycloneive_est_fmax_mhz", "Cyclone III C8 est. Fmax (MHz)"),
];

/// Cells of a row in [`BLOCK_COLUMNS`] order ("" = empty).
pub fn block_cells(r: &BlockRow) -> Vec<String> {
    let int = |v: Option<u64>| v.map(|v| v.to_string()).unwrap_or_default();
    let x = r.xc3sa.as_ref();
    let c = r.cyclone.as_ref();
    let t = &r.timing;
    let clean = |s: &str| s.replace(['|', ','], ";");
    let e = r.ecp5.as_ref();
    let lv = |s: Option<&SynthStats>, f: fn(&super::levels::PathLevels) -> u32| {
        s.and_then(|s| s.path.as_ref())
            .map(|p| f(p).to_string())
            .unwrap_or_default()
    };
    vec![
        clean(&r.label),
        r.module.clone(),
        int(x.map(|s| s.luts)),
        int(x.map(|s| s.ffs)),
        int(x.map(|s| s.carry)),
        int(x.map(|s| s.multipliers)),
        int(c.map(|s| s.luts)),
        int(c.map(|s| s.ffs)),
        int(c.map(|s| s.multipliers)),
        int(t.latency_cycles.map(u64::from)),
        int(t.clocks_per_sample.map(u64::from)),
        t.rate_sps.map(|v| format!("{v:.0}")).unwrap_or_default(),
        clean(&t.text),
        e.map(|e| super::fmax_cell(e.fmax_mhz)).unwrap_or_default(),
        e.map(|e| super::nextpnr::seeds_text(&e.seeds_mhz))
            .unwrap_or_default(),
        e.and_then(|e| e.slack_ns())
            .map(|v| format!("{v:.2}"))
            .unwrap_or_default(),
        e.filter(|e| !e.from_cell.is_empty())
            .map(|e| {
                clean(&format!(
                    "{} -> {}",
                    super::path_block(&e.from_cell, true),
                    super::path_block(&e.to_cell, true)
                ))
            })
            .unwrap_or_default(),
        lv(x, |p| p.lut_levels),
        lv(x, |p| p.carry_bits),
        lv(x, |p| p.carry_chains),
        x.map(super::est_cell).unwrap_or_default(),
        lv(c, |p| p.lut_levels),
        c.map(super::est_cell).unwrap_or_default(),
    ]
}
