//! The ABZ emulator as a block of the top: its config section `[abz]`, the parameters
//! derived from it, its `check` lines, its report job and its registry entry
//! ([`super::BLOCK`]).
use super::AbzParams;
use crate::blocks::registry::{BlockDef, BlockPort};
use crate::blocks::top::ports::Dir;
use crate::config::{Config, ErrFn, Loaded};
use crate::error::Result;
use crate::report::blocks::{job, BlockJob, BlockTiming};
use serde::Deserialize;

/// `[abz]`: A/B/Z incremental encoder emulation of the decoded position.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AbzConfig {
    /// Include the emulator (default false: no logic).
    #[serde(default)]
    pub enabled: bool,
    /// A/B periods per turn (default 16 x PPR, at most a quarter of the positions per turn).
    pub lines: Option<u64>,
    /// Highest edge rate on A and B together, edges per second (the minimum edge spacing;
    /// default 12.5 MHz, at most clock / 2).
    pub max_edge_hz: Option<f64>,
}

/// Default `abz.max_edge_hz`: 12.5 M edges per second (or clock / 2 if that is lower).
pub const ABZ_DEFAULT_EDGE_HZ: f64 = 12.5e6;

/// The registry entry: `[abz] enabled = true` adds the pins `abz_a`, `abz_b` and `abz_z`.
pub const BLOCK: BlockDef = BlockDef {
    key: "abz",
    label: "ABZ emulation",
    section: "[abz] enabled = true",
    enabled: |c| c.abz.enabled && c.capacitive.is_none(),
    ports: &[
        BlockPort {
            name: "abz_a",
            dir: Dir::Out,
            comment: "ABZ emulation: channel A (leads B when the position increases)",
        },
        BlockPort {
            name: "abz_b",
            dir: Dir::Out,
            comment: "ABZ emulation: channel B",
        },
        BlockPort {
            name: "abz_z",
            dir: Dir::Out,
            comment: "ABZ emulation: index, one quarter A/B period at position 0",
        },
    ],
    io_group: "ABZ",
    describe: |d| d.abz.as_ref().map(|a| describe(a, d.clock_hz)),
    build: report_job,
    timing_case: Some("[abz]\nenabled = true\n"),
};

/// `[abz]`: the emulator's parameters when enabled (None otherwise). `lines` defaults to
/// 16 x PPR (at most a quarter of the positions per turn); `max_edge_hz` to
/// [`ABZ_DEFAULT_EDGE_HZ`], at most clock / 2 and at least clock / 2^24; the edge spacing is
/// ceil(clock / max_edge_hz) clocks. The keys are checked only when enabled.
pub fn params(
    c: &Config,
    quadrants_per_turn: u64,
    fine_bits: u32,
    err: &ErrFn,
) -> Result<Option<AbzParams>> {
    let a = &c.abz;
    // Off: the keys have no effect and are not checked (the rule for every section with an
    // `enabled` key).
    if !a.enabled {
        return Ok(None);
    }
    let clock = c.clock.frequency_hz;
    let positions = quadrants_per_turn << fine_bits;
    let lines = a
        .lines
        .unwrap_or((4 * quadrants_per_turn).min(positions / 4));
    if lines == 0 || 4 * lines > positions || 4 * lines > 1 << 30 {
        return Err(err(
            "abz",
            "lines",
            format!(
                "{lines}: allowed 1..={} A/B periods per turn (4 edges each, at most one edge per position LSB: {positions} positions per turn{})",
                (positions / 4).min(1 << 28),
                if positions / 4 > 1 << 28 { "; at most 2^28" } else { "" }
            ),
        ));
    }
    let hz = a
        .max_edge_hz
        .unwrap_or(ABZ_DEFAULT_EDGE_HZ.min(clock / 2.0));
    let lo = clock / (1u64 << 24) as f64;
    if !hz.is_finite() || hz < lo || hz > clock / 2.0 {
        return Err(err(
            "abz",
            "max_edge_hz",
            format!(
                "{hz} Hz: allowed {lo:.3}..={:.0} Hz (at {clock:.0} Hz the emulator needs 2 to 2^24 clocks between two edges)",
                clock / 2.0
            ),
        ));
    }
    if c.capacitive.is_some() {
        return Err(err(
            "abz",
            "enabled",
            "ABZ emulation is built into the sinewave board top only; remove [abz] or set enabled = false with [capacitive]".into(),
        ));
    }
    // Spacing in clocks: the smallest S with clock / S <= max_edge_hz.
    let mut spacing = (clock / hz).ceil().max(2.0) as u32;
    if clock / ((spacing - 1) as f64) <= hz && spacing > 2 {
        spacing -= 1;
    }
    AbzParams::new(quadrants_per_turn, fine_bits, lines, spacing)
        .map(Some)
        .map_err(|m| err("abz", "lines", m.detail()))
}

/// The `[abz]` lines of `check`: resolution, rounding rule, maximum edge rate and speed.
fn describe(a: &AbzParams, clock_hz: f64) -> String {
    let rate = clock_hz / a.spacing() as f64;
    let (ea, eb) = a.ratio();
    format!(
        "abz lines                   {} A/B periods per turn = {} edges; count = floor(position x {ea} / {eb}) (exact, no drift over a turn)\n\
         abz max edge rate           {:.3} M edges/s (edges at least {} clocks apart; A/B at most {:.3} MHz)\n\
         abz max speed               {:.0} rpm at that rate (faster: the output lags, catches up and raises the warning)\n\
         abz latency                 {} cycles from the position to its first edge\n",
        a.lines(),
        a.edges(),
        rate / 1e6,
        a.spacing(),
        rate / 4e6,
        rate / a.edges() as f64 * 60.0,
        a.latency()
    )
}

/// The report's row: the emulator synthesized alone.
fn report_job(l: &Loaded) -> Result<BlockJob> {
    let Some(p) = &l.derived.abz else {
        return Ok(BlockJob::absent("abz", "needs [abz] enabled"));
    };
    let note = format!(
        "position to first edge; edges at least {} clocks apart",
        p.spacing()
    );
    job(
        l,
        "abz",
        super::hdl::AbzEmulator::new(p),
        BlockTiming::latency(p.latency(), &note),
    )
}
