//! The position reference as a block of the top: its config section `[reference]`, the
//! parameters derived from it, its `check` lines, its report job and its registry entry
//! ([`super::BLOCK`]).
use super::ReferenceParams;
use crate::blocks::mask;
use crate::blocks::registry::{BlockDef, BlockPort};
use crate::blocks::top::ports::Dir;
use crate::config::{Config, ErrFn, Loaded};
use crate::error::Result;
use crate::report::blocks::{job, BlockJob, BlockTiming};
use serde::Deserialize;

/// `[reference]`: homing on the index Z, the index latch and the position preset.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferenceConfig {
    /// Include the block (default false: no logic, no ports).
    #[serde(default)]
    pub enabled: bool,
    /// Comparator levels "AB" of the quadrant that qualifies Z (A = cos > 0, B = sin > 0):
    /// "11" (default), "01", "00" or "10".
    #[serde(default = "default_gate")]
    pub gate: String,
    /// Quadrant count the reference quadrant reads after homing (0..4PPR-1, default 0).
    #[serde(default)]
    pub quadrant: i64,
    /// Turn count the reference quadrant reads after homing (default 0).
    #[serde(default)]
    pub turn: i64,
    /// Quadrant count a preset loads (0..4PPR-1, default 0).
    #[serde(default)]
    pub preset_quadrant: i64,
    /// Turn count a preset loads (default 0).
    #[serde(default)]
    pub preset_turn: i64,
    /// Raise the warning flag (parallel bus, BiSS-C, SSI, SPI) until the position is
    /// referenced (default true).
    #[serde(default = "default_true")]
    pub warn_until_referenced: bool,
    /// Absolute start from the encoder's digital channel: "none" (default) or "ssi" (an SSI
    /// master reads the absolute word once after reset; `crate::blocks::absolute`).
    #[serde(default = "default_absolute")]
    pub absolute: String,
    /// `[reference.ssi]`: the encoder's SSI channel, with `absolute = "ssi"`.
    #[serde(default)]
    pub ssi: crate::blocks::absolute::AbsoluteSsiConfig,
}

impl Default for ReferenceConfig {
    fn default() -> Self {
        Self {
            enabled: false,
            gate: default_gate(),
            quadrant: 0,
            turn: 0,
            preset_quadrant: 0,
            preset_turn: 0,
            warn_until_referenced: true,
            absolute: default_absolute(),
            ssi: Default::default(),
        }
    }
}

fn default_absolute() -> String {
    "none".into()
}

fn default_gate() -> String {
    "11".into()
}

fn default_true() -> bool {
    true
}

/// The comparator levels "AB" of each quadrant, quadrant 0 first (A = cos > 0, B = sin > 0).
pub const GATES: [&str; 4] = ["11", "01", "00", "10"];

/// The registry entry: `[reference] enabled = true` adds the pins `preset` and `referenced`.
pub const BLOCK: BlockDef = BlockDef {
    key: "reference",
    label: "position reference",
    section: "[reference] enabled = true",
    enabled: |c| c.reference.enabled && c.capacitive.is_none(),
    ports: &[
        BlockPort {
            name: "preset",
            dir: Dir::In,
            comment: "position preset (`[reference]`): a rising edge loads the preset count at the next sample",
        },
        BlockPort {
            name: "referenced",
            dir: Dir::Out,
            comment: "position referenced (`[reference]`): 1 once homed on Z or preset",
        },
    ],
    io_group: "position reference",
    describe: |d| d.reference.as_ref().map(|r| describe(r, d.sample_rate_hz)),
    build: report_job,
    timing_case: Some("[reference]\nenabled = true\n"),
};

/// `[reference]`: the block's parameters when enabled (None otherwise). `latency` is L,
/// clocks from a conversion start to the core's `out_valid` of its sample; `inverted`: the
/// analog front end inverts both channels (the LTC6912-1 of `[preamp]` has only inverting
/// gains), so the decoded angle is the comparators' plus 180 degrees and the gate's
/// decoded quadrant is two on from the comparators' (the Z and A/B comparators see the
/// encoder's own tracks).
pub fn params(
    c: &Config,
    adc: &crate::blocks::adc::AdcParams,
    latency: u32,
    inverted: bool,
    err: &ErrFn,
) -> Result<Option<ReferenceParams>> {
    let r = &c.reference;
    if !r.enabled {
        return Ok(None);
    }
    if c.capacitive.is_some() {
        return Err(err(
            "reference",
            "enabled",
            "the position reference is built into the sinewave board top only; remove [reference] or set enabled = false with [capacitive]".into(),
        ));
    }
    // Homing needs the index; an absolute start references without it (no Z: no homing).
    let absolute = r.absolute == "ssi";
    if !c.qep.enabled && !absolute {
        return Err(err(
            "reference",
            "enabled",
            "homing needs the index Z, a comparator input: set [qep] enabled = true, or take the position from the encoder's digital channel (absolute = \"ssi\")".into(),
        ));
    }
    let gate = GATES.iter().position(|g| *g == r.gate).ok_or_else(|| {
        err(
            "reference",
            "gate",
            format!(
                "\"{}\": allowed \"11\", \"01\", \"00\" or \"10\" (the levels of A = cos > 0 and B = sin > 0 in the quadrant that qualifies Z)",
                r.gate
            ),
        )
    })?;
    let q = 4 * c.encoder.ppr as u64;
    let m = c.encoder.multiturn_bits;
    let quadrant = |key: &str, v: i64| {
        u64::try_from(v).ok().filter(|v| *v < q).ok_or_else(|| {
            err(
                "reference",
                key,
                format!("{v}: allowed 0..={} (4 x PPR quadrants per turn)", q - 1),
            )
        })
    };
    let (lo, hi) = if m == 0 {
        (0, 0)
    } else {
        (-(1i64 << (m - 1)), (1i64 << (m - 1)) - 1)
    };
    let turn = |key: &str, v: i64| {
        if (lo..=hi).contains(&v) {
            Ok(v as u64 & mask(m))
        } else {
            Err(err(
                "reference",
                key,
                format!("{v}: allowed {lo}..={hi} (encoder.multiturn_bits = {m})"),
            ))
        }
    };
    let index = (quadrant("quadrant", r.quadrant)?, turn("turn", r.turn)?);
    let preset = (
        quadrant("preset_quadrant", r.preset_quadrant)?,
        turn("preset_turn", r.preset_turn)?,
    );
    ReferenceParams::new(
        q,
        m,
        (gate as u32 + if inverted { 2 } else { 0 }) % 4,
        index,
        preset,
        latency,
        adc.period_clocks,
        adc.frame.conv_active_high,
        r.warn_until_referenced,
    )
    .map(|p| Some(p.with_gate_levels(GATES[gate]).with_absolute(absolute)))
    .map_err(|e| err("reference", "enabled", e.detail()))
}

/// The `[reference]` lines of `check`.
fn describe(r: &ReferenceParams, sample_rate_hz: f64) -> String {
    // A turn word of M bits as a signed count (M = 0: the word is 0).
    let signed = |t: u64| crate::blocks::sext(t, r.turns_bits().max(1));
    format!(
        "reference index             Z in the quadrant with A/B = {} (decoded quadrant {} of its period) reads quadrant count {}, turn {}; latched at every index\n\
         reference homing            below {:.0} rpm (one quadrant per sample); warning until referenced: {}\n\
         reference preset            a rising edge of `preset` loads quadrant count {}, turn {} at the next sample\n\
         reference latency           {} clock on every position output\n",
        r.gate_levels(),
        r.gate(),
        r.index().0,
        signed(r.index().1),
        r.homing_rpm(sample_rate_hz),
        if r.warn_until_referenced() { "yes" } else { "no" },
        r.preset().0,
        signed(r.preset().1),
        ReferenceParams::LATENCY,
    )
}

/// The report's row: the block synthesized alone.
fn report_job(l: &Loaded) -> Result<BlockJob> {
    let Some(p) = &l.derived.reference else {
        return Ok(BlockJob::absent("reference", "needs [reference] enabled"));
    };
    job(
        l,
        "reference",
        super::hdl::PositionReference::new(p),
        BlockTiming::latency(ReferenceParams::LATENCY, "one register stage"),
    )
}
