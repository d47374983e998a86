//! The register map as a block of the top: its config section `[registers]`, the
//! parameters derived from it, its `check` lines, its report job and its registry entry
//! ([`super::BLOCK`]).
use super::{RegmapParams, ADDR_BITS, REGISTERS};
use crate::blocks::registry::BlockDef;
use crate::config::{Config, ErrFn, Loaded};
use crate::error::Result;
use crate::report::blocks::{job, BlockJob, BlockTiming};
use serde::Deserialize;

/// `[registers]`: an AXI4-Lite slave with the register map on `<name>_top`.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RegistersConfig {
    /// Include the slave (default false: no logic, no ports).
    #[serde(default)]
    pub enabled: bool,
}

/// The registry entry: `[registers] enabled = true` adds the `s_axi_*` ports (fabric ports,
/// like the parallel bus: no pins).
pub const BLOCK: BlockDef = BlockDef {
    key: "registers",
    label: "register map (AXI4-Lite)",
    section: "[registers] enabled = true",
    enabled: |c| c.registers.enabled && c.capacitive.is_none(),
    ports: &[],
    io_group: "register map",
    describe: |d| {
        d.registers
            .as_ref()
            .map(|p| describe(p) + &d.adc.frame_check().describe())
    },
    build: report_job,
    timing_case: Some(
        "[velocity]\nenabled = true\n\n[reference]\nenabled = true\n\n[capture]\nenabled = true\n\n[registers]\nenabled = true\n",
    ),
};

/// `[registers]`: the block's parameters when enabled (None otherwise).
pub fn params(c: &Config, d: &crate::config::Derived, err: &ErrFn) -> Result<Option<RegmapParams>> {
    if !c.registers.enabled {
        return Ok(None);
    }
    if c.capacitive.is_some() {
        return Err(err(
            "registers",
            "enabled",
            "the register map is built into the sinewave board top only; remove [registers] or set enabled = false with [capacitive]".into(),
        ));
    }
    RegmapParams::new(
        d.position_width,
        d.fine_bits,
        d.multiturn_bits,
        d.velocity.as_ref().map_or(0, |v| v.spec.width),
        d.reference.is_none(),
    )
    .and_then(|p| {
        let m = &d.monitor;
        // Each fits the magnitude's W <= 32 bits (MonitorParams checks it).
        let t = |v: u64| v.min(u32::MAX as u64) as u32;
        let p = p
            .with_thresholds([
                t(m.los_threshold()),
                t(m.los_release()),
                t(m.clip_threshold()),
            ])
            .with_codes(d.correction.reset_words());
        // The learned harmonic table: HARM_CONTROL, HARM_INDEX, HARM_ENTRY.
        match d.harmonics.as_ref().and_then(|h| h.learn) {
            Some(l) => p.with_harmonics(l.points() as u32, l.entry_width()),
            None => Ok(p),
        }
        .map(Some)
    })
    .map_err(|e| err("registers", "enabled", e.detail()))
}

/// The `[registers]` lines of `check`.
fn describe(p: &RegmapParams) -> String {
    let names: Vec<&str> = REGISTERS.iter().map(|r| r.name).collect();
    let [los, rel, clip] = p.thresholds();
    let c = p.codes();
    let mut s = format!(
        "registers                   AXI4-Lite slave s_axi_* ({ADDR_BITS}-bit byte addresses, 32-bit data): {} registers from 0x00 to 0x{:02x}: {}\n\
         register thresholds         LOS_THRESHOLD {los}, LOS_RELEASE {rel}, CLIP_THRESHOLD {clip} after reset (monitor units)\n\
         register correction codes   OFFSET_SIN {}, OFFSET_COS {}, GAIN_SIN {}, GAIN_COS {}, PHASE k = {} after reset (run-time codes: written in static mode, start values in auto and peak)\n",
        REGISTERS.len(),
        REGISTERS.last().map_or(0, |r| r.address),
        names.join(", "),
        c[0] as i32,
        c[1] as i32,
        c[2],
        c[3],
        crate::blocks::correction::codes::phase_of(c[4]),
    );
    if let Some((points, e)) = p.harmonics() {
        s.push_str(&format!(
            "register harmonic table     HARM_CONTROL, HARM_INDEX, HARM_ENTRY: the learned table's {points} entries ({e}-bit, 2^-8 LSB) of the bank in use, LEARN 1 after reset; a HARM_ENTRY write of byte 3 loads entry HARM_INDEX of both banks\n"
        ));
    }
    if p.biss_port() {
        s.push_str(&format!(
            "register map over BiSS C    control channel 0x00..0x3F = the map's bytes 64 x bank (bank select 0x40; banks 0..={}), low byte first\n",
            (1u32 << ADDR_BITS) / super::BISS_BANK_BYTES - 1
        ));
    }
    s
}

/// The report's row: the block synthesized alone.
fn report_job(l: &Loaded) -> Result<BlockJob> {
    let Some(p) = &l.derived.registers else {
        return Ok(BlockJob::absent("registers", "needs [registers] enabled"));
    };
    job(
        l,
        "registers",
        super::hdl::RegisterMap::new(p),
        BlockTiming::latency(2, "address held, then read data"),
    )
}
