//! The harmonic-correction block in the core: its config section `[harmonics]`, the
//! parameters derived from it, its `check` lines, its report job and its registry entry
//! ([`super::BLOCK`]).
use super::sequencer::LearnParams;
use super::{HarmonicParams, POINTS_RANGE};
use crate::blocks::params::Architecture;
use crate::blocks::registry::BlockDef;
use crate::config::{Config, ErrFn, Loaded};
use crate::error::Result;
use crate::report::blocks::{job, BlockJob, BlockTiming};
use crate::report::nextpnr::{median_mhz, MEDIAN_MARGIN, SEED_MARGIN};
use serde::Deserialize;

/// How the table is had (`[harmonics] mode`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum HarmonicsMode {
    /// Learned online from the signal (the learner of `super::sequencer`), from zeros.
    #[default]
    Learn,
    /// The config's `table`, fixed.
    Static,
}

/// `[harmonics]`: a table of angle corrections against the angle within the signal period,
/// between the CORDIC and the combiner (docs/correction.md, "Harmonic distortion").
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct HarmonicsConfig {
    /// Include the block (default false: no logic).
    pub enabled: bool,
    /// `"learn"` (default): the table is learned online from zeros; `"static"`: `table`,
    /// fixed.
    pub mode: HarmonicsMode,
    /// Entries over one signal period: a power of two, 16..=256 (default 64).
    pub points: u32,
    /// `mode = "static"`: the corrections, position LSB (2^-F quadrant), `points` of them
    /// from angle 0 in steps of one period / points: the decoded angle's error there,
    /// subtracted. A learned table starts from zeros.
    pub table: Option<Vec<f64>>,
    /// `mode = "learn"`: samples per learning window, a power of two 256..=65536 (default
    /// 4096).
    pub window: u32,
    /// `mode = "learn"`: the largest change of an entry per window, LSB (default 32).
    pub step: u32,
}

impl Default for HarmonicsConfig {
    fn default() -> Self {
        HarmonicsConfig {
            enabled: false,
            mode: HarmonicsMode::Learn,
            points: 64,
            table: None,
            window: 4096,
            step: 32,
        }
    }
}

/// A top with a learned table measured on the ECP5 flow at 133.33 MHz (scripts/ecp5_fmax.sh,
/// docs/timing.md).
#[derive(Clone, Copy, Debug)]
pub struct LearnedTop {
    /// The design, as `check` names it.
    pub design: &'static str,
    /// Post-route Fmax in MHz at seeds 1, 2 and 3.
    pub seeds_mhz: [f64; 3],
}

/// The learned-table tops measured by hand at 133.33 MHz, which miss the timing rule there:
/// the default one (64 points) and the largest (128 points and the register map). The
/// clock at which both meet it ([`learned_clock_mhz`]) is the highest a learned table is
/// built for; `check` prints them for every learned-table design, and `tests/timing.rs`
/// holds the default one at 100 MHz ([`learned_case`]).
pub const LEARNED_TOPS: [LearnedTop; 2] = [
    LearnedTop {
        design: "the default top with 64 points",
        seeds_mhz: [158.63, 137.27, 152.95],
    },
    LearnedTop {
        design: "with 128 points and [registers]",
        seeds_mhz: [143.00, 151.03, 156.89],
    },
];

/// The clock the learned tops were measured at, MHz (the default config's).
pub const LEARNED_TOPS_CLOCK_MHZ: f64 = 133.33;

/// The median of three seeds' figures (the timing rule's, `report::nextpnr::median_mhz`).
pub fn learned_median_mhz(seeds: [f64; 3]) -> f64 {
    median_mhz(&seeds.map(Some)).unwrap_or(0.0)
}

/// The highest whole-MHz clock f that three seeds' figures meet the timing rule at: the
/// median at least `MEDIAN_MARGIN` f and every seed at least `SEED_MARGIN` f
/// (docs/timing.md).
pub fn rule_clock_mhz(seeds: [f64; 3]) -> f64 {
    let slowest = seeds[0].min(seeds[1]).min(seeds[2]);
    (learned_median_mhz(seeds) / MEDIAN_MARGIN)
        .min(slowest / SEED_MARGIN)
        .floor()
}

/// The highest clock, whole MHz, at which a learned table is built: the lowest at which
/// each of [`LEARNED_TOPS`] meets the timing rule ([`rule_clock_mhz`]; 119 MHz).
pub fn learned_clock_mhz() -> f64 {
    LEARNED_TOPS
        .iter()
        .map(|t| rule_clock_mhz(t.seeds_mhz))
        .fold(f64::INFINITY, f64::min)
}

/// The held learned-table top of the timing rule (`tests/timing.rs`): `config` (the
/// default's text) at 100 MHz, below [`learned_clock_mhz`], with a 64-point table learned
/// online.
pub fn learned_case(config: &str) -> String {
    format!(
        "{}\n[harmonics]\nenabled = true\n",
        with_clock(config, LEARNED_CLOCK_TOML)
    )
}

/// `config` (the default's text) with its clock written as `clock_toml` (TOML, Hz).
pub fn with_clock(config: &str, clock_toml: &str) -> String {
    config.replace(
        &format!("frequency_hz = {DEFAULT_CLOCK_TOML}"),
        &format!("frequency_hz = {clock_toml}"),
    )
}

/// The default config's clock as its text writes it.
pub const DEFAULT_CLOCK_TOML: &str = "133_330_000.0";

/// The held learned-table top's clock, TOML: 100 MHz.
pub const LEARNED_CLOCK_TOML: &str = "100_000_000.0";

/// The registry entry: no pins (the block sits inside the core).
pub const BLOCK: BlockDef = BlockDef {
    key: "harmonics",
    label: "harmonic correction (table)",
    section: "[harmonics] enabled = true",
    enabled: |c| c.harmonics.enabled && c.capacitive.is_none(),
    ports: &[],
    io_group: "",
    describe: |d| d.harmonics.as_ref().map(|h| describe(h, d)),
    build: report_job,
    timing_case: Some(HELD_CASE),
};

/// The held design of the timing rule: the default config with a 64-point table of a
/// 2 % third harmonic's error (208.6 sin 4x LSB, the peak asin 0.02 at F = 14).
pub const HELD_CASE: &str = "[harmonics]\nenabled = true\nmode = \"static\"\npoints = 64\ntable = [0.0, 79.8, 147.5, 192.7, 208.6, 192.7, 147.5, 79.8, 0.0, -79.8, -147.5, -192.7, -208.6, -192.7, -147.5, -79.8, 0.0, 79.8, 147.5, 192.7, 208.6, 192.7, 147.5, 79.8, 0.0, -79.8, -147.5, -192.7, -208.6, -192.7, -147.5, -79.8, 0.0, 79.8, 147.5, 192.7, 208.6, 192.7, 147.5, 79.8, 0.0, -79.8, -147.5, -192.7, -208.6, -192.7, -147.5, -79.8, 0.0, 79.8, 147.5, 192.7, 208.6, 192.7, 147.5, 79.8, 0.0, -79.8, -147.5, -192.7, -208.6, -192.7, -147.5, -79.8]\n";

/// `[harmonics]`: the block's parameters when enabled (None otherwise), for the angle word
/// of `z_width` bits with `z_guard` guard bits below the `fine_bits` LSB.
pub fn params(
    c: &Config,
    z_width: u32,
    z_guard: u32,
    fine_bits: u32,
    err: &ErrFn,
) -> Result<Option<HarmonicParams>> {
    let h = &c.harmonics;
    // A section that is off is not checked beyond its types (docs/cli.md).
    if !h.enabled {
        return Ok(None);
    }
    if !(POINTS_RANGE.contains(&h.points) && h.points.is_power_of_two()) {
        return Err(err(
            "harmonics",
            "points",
            format!(
                "{}: allowed a power of two from {} to {}",
                h.points,
                POINTS_RANGE.start(),
                POINTS_RANGE.end()
            ),
        ));
    }
    if c.capacitive.is_some() {
        return Err(err(
            "harmonics",
            "enabled",
            "the harmonic table is built into the sinewave core only; remove [harmonics] or set enabled = false with [capacitive]".into(),
        ));
    }
    if c.cordic.architecture != Architecture::Unrolled {
        return Err(err(
            "harmonics",
            "enabled",
            "the harmonic table is built for the unrolled CORDIC only; set cordic.architecture = \"unrolled\" or enabled = false".into(),
        ));
    }
    let table = match (&h.table, h.mode) {
        (Some(t), HarmonicsMode::Static) => t.clone(),
        (None, HarmonicsMode::Learn) => vec![0.0; h.points as usize],
        (Some(_), HarmonicsMode::Learn) => {
            return Err(err(
                "harmonics",
                "table",
                "a learned table starts from zeros: remove `table`, or set mode = \"static\" to use it fixed".into(),
            ))
        }
        (None, HarmonicsMode::Static) => {
            return Err(err(
                "harmonics",
                "mode",
                format!(
                    "\"static\" needs `table`, {} corrections in position LSB (docs/correction.md, \"Harmonic distortion\"); or mode = \"learn\" to learn it online",
                    h.points
                ),
            ))
        }
    };
    if table.len() != h.points as usize {
        return Err(err(
            "harmonics",
            "table",
            format!(
                "{} entries: allowed exactly `points` = {} (one per 1/{} of the signal period, from angle 0)",
                table.len(),
                h.points,
                h.points
            ),
        ));
    }
    match h.mode {
        HarmonicsMode::Static => HarmonicParams::new(z_width, z_guard, fine_bits, &table)
            .map(Some)
            .map_err(|m| err("harmonics", "table", m)),
        HarmonicsMode::Learn => {
            if h.points > super::hdl_ram::MAX_POINTS {
                return Err(err(
                    "harmonics",
                    "points",
                    format!(
                        "{}: a learned table has at most {} points (its two banks share one 256-word block RAM); use mode = \"static\" for 256",
                        h.points,
                        super::hdl_ram::MAX_POINTS
                    ),
                ));
            }
            if !((256..=65536).contains(&h.window) && h.window.is_power_of_two()) {
                return Err(err(
                    "harmonics",
                    "window",
                    format!(
                        "{}: allowed a power of two from 256 to 65536 samples",
                        h.window
                    ),
                ));
            }
            if !(1..=1u32 << fine_bits.saturating_sub(4)).contains(&h.step) {
                return Err(err(
                    "harmonics",
                    "step",
                    format!(
                        "{} LSB: allowed 1 to 2^(F-4) = {} LSB",
                        h.step,
                        1u32 << fine_bits.saturating_sub(4)
                    ),
                ));
            }
            let lp = LearnParams::new(fine_bits, h.points, h.window, h.step)
                .map_err(|m| err("harmonics", "enabled", m))?;
            // Every emitted design meets its configured clock (docs/timing.md): a learned
            // table only up to the clock its measured tops meet the rule at.
            let mhz = c.clock.frequency_hz / 1e6;
            let most = learned_clock_mhz();
            if mhz > most {
                return Err(err(
                    "harmonics",
                    "enabled",
                    format!(
                        "a learned table meets the timing rule up to {most:.0} MHz (docs/timing.md; its tops miss it at {LEARNED_TOPS_CLOCK_MHZ:.2} MHz), and clock.frequency_hz is {mhz:.2} MHz; allowed: clock.frequency_hz at most {most:.0} MHz (100 MHz: the Starter Kit's DCM makes it as 50 MHz x 2), or mode = \"static\""
                    ),
                ));
            }
            HarmonicParams::learned(z_width, z_guard, fine_bits, h.points, lp)
                .map(Some)
                .map_err(|m| err("harmonics", "enabled", m))
        }
    }
}

/// Clocks the block adds to the core (0 without it).
pub fn latency_cycles(p: Option<&HarmonicParams>) -> u32 {
    p.map_or(0, HarmonicParams::latency)
}

/// What the block's clocks do, for `check` and the report.
fn stages(p: &HarmonicParams) -> &'static str {
    if p.learn.is_some() {
        "table RAM read over two clocks, its words registered, slope, partial products, two adder levels, subtract"
    } else {
        "table lookup, partial products, two adder levels, subtract"
    }
}

/// The `[harmonics]` lines of `check`.
fn describe(p: &HarmonicParams, d: &crate::blocks::params::Derived) -> String {
    let max = p.table.iter().map(|c| c.unsigned_abs()).max().unwrap_or(0) as f64
        / (1u64 << p.z_guard) as f64;
    let how = match &p.learn {
        None => format!(
            "{} points over the signal period, fixed, linear interpolation ({} fraction bits), entries in 2^-{} LSB, largest {:.2} LSB; within {:.3} LSB of the table's line",
            p.points(),
            super::INTERP_BITS,
            p.z_guard,
            max,
            p.bound_lsb()
        ),
        Some(l) => {
            // A window's samples at the sample rate, then the solve, during which samples
            // are not collected (super::sequencer::LearnParams::solve_clocks).
            let solve_s = f64::from(l.solve_clocks()) / d.clock_hz;
            format!(
                "{} points over the signal period, learned online from zeros (windows of {} samples = {:.2} ms, each followed by a solve of {} clocks = {:.1} us in which up to {} samples are not collected; at most {} LSB per entry per window; docs/correction.md), linear interpolation ({} fraction bits), entries in 2^-{} LSB",
                p.points(),
                l.window(),
                l.window() as f64 / d.sample_rate_hz * 1e3,
                l.solve_clocks(),
                solve_s * 1e6,
                (solve_s * d.sample_rate_hz).ceil(),
                l.step >> super::sequencer::TABLE_FRAC,
                super::INTERP_BITS,
                p.z_guard
            )
        }
    };
    // The learned tops' timing (docs/timing.md): said where the design is shown.
    let timing = if p.learn.is_some() {
        let tops: Vec<String> = LEARNED_TOPS
            .iter()
            .map(|t| {
                let [a, b, c] = t.seeds_mhz;
                let m = learned_median_mhz(t.seeds_mhz);
                format!(
                    "{}: {a:.2} / {b:.2} / {c:.2} MHz (median {m:.2} MHz, {:.3} x)",
                    t.design,
                    m / LEARNED_TOPS_CLOCK_MHZ
                )
            })
            .collect();
        format!(
            "harmonic correction timing  a learned table is built up to {:.0} MHz, where it meets the timing rule on the ECP5 flow (docs/timing.md; tests/timing.rs holds the default top at 100 MHz); at {LEARNED_TOPS_CLOCK_MHZ:.2} MHz it misses it: {}\n",
            learned_clock_mhz(),
            tops.join(", ")
        )
    } else {
        String::new()
    };
    format!(
        "harmonic correction         {how}\n\
         harmonic correction latency {} clocks (in the core's latency: {})\n{timing}",
        p.latency(),
        stages(p)
    )
}

/// The report's row: the block synthesized alone.
fn report_job(l: &Loaded) -> Result<BlockJob> {
    let Some(p) = &l.derived.harmonics else {
        return Ok(BlockJob::absent("harmonics", "needs [harmonics] enabled"));
    };
    let timing = BlockTiming::latency(p.latency(), stages(p));
    match &p.learn {
        None => job(
            l,
            "harmonics",
            super::hdl::HarmonicCorrection::new(p),
            timing,
        ),
        Some(lp) => job(
            l,
            "harmonics",
            super::hdl_ram::HarmonicCorrectionRam::new(p, lp.entry_width()),
            timing,
        ),
    }
}
