//! The capture block of the top: its config section `[capture]`, the parameters derived
//! from it, its `check` lines, its report job and its registry entry ([`super::BLOCK`]).
use super::CaptureParams;
use crate::blocks::registry::{BlockDef, BlockPort};
use crate::blocks::top::ports::Dir;
use crate::config::{Config, ErrFn, Loaded};
use crate::error::Result;
use crate::report::blocks::{job, BlockJob, BlockTiming};
use serde::Deserialize;

/// `[capture]`: a `capture` input latches the position, the velocity and their age.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaptureConfig {
    /// Include the block (default false: no logic, no ports).
    #[serde(default)]
    pub enabled: bool,
    /// Carry the captured position to the capture instant by velocity x age (default
    /// false; needs `[velocity] enabled`).
    #[serde(default)]
    pub extrapolate: bool,
}

/// The registry entry: `[capture] enabled = true` adds the pin `capture` (the wrapper's
/// `cap_*` outputs are fabric ports, like the parallel bus).
pub const BLOCK: BlockDef = BlockDef {
    key: "capture",
    label: "synchronous capture",
    section: "[capture] enabled = true",
    enabled: |c| c.capture.enabled && c.capacitive.is_none(),
    ports: &[BlockPort {
        name: "capture",
        dir: Dir::In,
        comment: "capture (`[capture]`): a rising edge latches the position, the velocity and their age on cap_*",
    }],
    io_group: "synchronous capture",
    describe: |d| d.capture.as_ref().map(|c| describe(c, d.clock_hz)),
    build: report_job,
    timing_case: Some(
        "[velocity]\nenabled = true\n\n[capture]\nenabled = true\nextrapolate = true\n",
    ),
};

/// `[capture]`: the block's parameters when enabled (None otherwise). `latency` is L,
/// clocks from a conversion start to the position every output takes (the top's
/// `conv_to_position_cycles`).
pub fn params(
    c: &Config,
    adc: &crate::blocks::adc::AdcParams,
    latency: u32,
    velocity: Option<&crate::blocks::velocity::VelocityParams>,
    err: &ErrFn,
) -> Result<Option<CaptureParams>> {
    let k = &c.capture;
    if !k.enabled {
        return Ok(None);
    }
    if c.capacitive.is_some() {
        return Err(err(
            "capture",
            "enabled",
            "the capture input is built into the sinewave board top only; remove [capture] or set enabled = false with [capacitive]".into(),
        ));
    }
    if k.extrapolate && velocity.is_none() {
        return Err(err(
            "capture",
            "extrapolate",
            "extrapolation multiplies the velocity estimate by the age: set [velocity] enabled = true, or extrapolate = false".into(),
        ));
    }
    CaptureParams::new(
        latency,
        adc.period_clocks,
        4 * c.encoder.ppr as u64,
        c.cordic.fine_bits,
        c.encoder.multiturn_bits,
        velocity,
        k.extrapolate,
    )
    .map(Some)
    .map_err(|e| {
        let key = if k.extrapolate {
            "extrapolate"
        } else {
            "enabled"
        };
        err("capture", key, e.detail())
    })
}

/// The `[capture]` lines of `check`.
fn describe(p: &CaptureParams, clock_hz: f64) -> String {
    let ns = |c: u32| c as f64 * 1e9 / clock_hz;
    let what = if p.velocity() {
        "position, velocity and age"
    } else {
        "position and age"
    };
    let mut s = format!(
        "capture                     a rising edge of `capture` latches the {what} on cap_* ({} clocks = {:.0} ns later, cap_valid)\n\
         capture age                 clocks from the sample's CONV edge to the capture: {} to {} while the ADC runs ({:.0} to {:.0} ns); saturates at 2^{} - 1\n",
        p.capture_latency(),
        ns(p.capture_latency()),
        p.latency() - 1,
        p.latency() + p.adc_period() - 2,
        ns(p.latency() - 1),
        ns(p.latency() + p.adc_period() - 2),
        p.age_bits(),
    );
    if let Some(e) = p.extrapolation() {
        s.push_str(&format!(
            "capture extrapolation       position + velocity x (age + 1/2 clock), within 3/4 LSB of the estimate's own motion up to {} clocks (R = {}, B = {}); at most {} LSB\n",
            e.horizon, e.recip, e.recip_bits, e.max_step
        ));
    }
    s
}

/// The report's row: the block synthesized alone.
fn report_job(l: &Loaded) -> Result<BlockJob> {
    let Some(p) = &l.derived.capture else {
        return Ok(BlockJob::absent("capture", "needs [capture] enabled"));
    };
    job(
        l,
        "capture",
        super::hdl::Capture::new(p),
        BlockTiming::latency(
            p.capture_latency(),
            "synchronizer, latch (and the extrapolation's multiply)",
        ),
    )
}
