//! The absolute start as a block of the top: its config keys (`[reference] absolute` and
//! the table `[reference.ssi]`), the parameters derived from them, its `check` lines, its
//! report job and its registry entry ([`super::BLOCK`]).
use super::{AbsoluteParams, SsiTiming, SsiWord};
use crate::blocks::registry::{BlockDef, BlockPort};
use crate::blocks::top::ports::Dir;
use crate::config::{Config, Derived, ErrFn, Loaded};
use crate::error::Result;
use crate::report::blocks::{job, BlockJob, BlockTiming};
use serde::Deserialize;

/// `[reference.ssi]`: the encoder's SSI channel that `[reference] absolute = "ssi"` reads
/// (its data sheet gives every value).
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct AbsoluteSsiConfig {
    /// S: single-turn bits of the absolute word; 2^S must be 4 x PPR x 2^k (k >= 0). Default
    /// log2(4 x PPR): one code per quadrant (13 bits at 2048 lines).
    pub single_turn_bits: Option<u32>,
    /// Multi-turn bits ahead of the single-turn bits (0..=24, default 0: a single-turn
    /// encoder).
    pub multiturn_bits: u32,
    /// Gray code over the whole word (default true, as SSI encoders send it).
    pub gray: bool,
    /// SSI clock in Hz, at most the system clock / 8 (default 500 kHz).
    pub clock_hz: f64,
    /// t1: the encoder's clock edge to valid data, ns, without the cable (default 400:
    /// Heidenhain's t1 <= 0.4 us).
    pub data_valid_ns: f64,
    /// t_m: the encoder's monoflop time, us; the master keeps the clock high this long after
    /// reset and before reading again (default 20: Heidenhain's t2 <= 20 us).
    pub monoflop_us: f64,
}

impl Default for AbsoluteSsiConfig {
    fn default() -> Self {
        Self {
            single_turn_bits: None,
            multiturn_bits: 0,
            gray: true,
            clock_hz: 500e3,
            data_valid_ns: 400.0,
            monoflop_us: 20.0,
        }
    }
}

/// The values `[reference] absolute` takes.
pub const PROTOCOLS: [&str; 2] = ["none", "ssi"];

/// The registry entry: `[reference] absolute = "ssi"` adds the pins `abs_clk` and
/// `abs_data`.
pub const BLOCK: BlockDef = BlockDef {
    key: "absolute",
    label: "absolute start (SSI master)",
    section: "[reference] absolute = \"ssi\"",
    enabled: |c| c.reference.enabled && c.reference.absolute == "ssi" && c.capacitive.is_none(),
    ports: &[
        BlockPort {
            name: "abs_clk",
            dir: Dir::Out,
            comment: "SSI clock to the encoder's digital channel (`[reference] absolute`): idle high, N + 1 pulses once after reset",
        },
        BlockPort {
            name: "abs_data",
            dir: Dir::In,
            comment: "SSI data from the encoder's digital channel (`[reference] absolute`): the absolute word, MSB first",
        },
    ],
    io_group: IO_GROUP,
    describe: |d| d.absolute.as_ref().map(|a| describe(a, d.sample_rate_hz)),
    build: report_job,
    timing_case: Some("[reference]\nenabled = true\nabsolute = \"ssi\"\n"),
};

/// The constraints' interface name of the absolute start's pins.
pub const IO_GROUP: &str = "absolute encoder (SSI)";

/// `[reference] absolute = "ssi"`: the block's parameters (None with `absolute = "none"`).
/// `latency` is L, clocks from a conversion start to the core's `out_valid` of its sample;
/// `d` gives the decoder's widths, the ADC and the board's I/O budget.
pub fn params(
    c: &Config,
    d: &Derived,
    latency: u32,
    err: &ErrFn,
) -> Result<Option<AbsoluteParams>> {
    let r = &c.reference;
    if !PROTOCOLS.contains(&r.absolute.as_str()) {
        return Err(err(
            "reference",
            "absolute",
            format!(
                "\"{}\": allowed \"none\" or \"ssi\" (an SSI master reads the encoder's absolute word at start-up)",
                crate::config::clip(&r.absolute)
            ),
        ));
    }
    if r.absolute == "none" {
        return Ok(None);
    }
    if !r.enabled {
        return Err(err(
            "reference",
            "absolute",
            "the absolute start is a source of the position reference: set [reference] enabled = true".into(),
        ));
    }
    if c.capacitive.is_some() {
        return Err(err(
            "reference",
            "absolute",
            "the absolute start is built into the sinewave board top only".into(),
        ));
    }
    let ppr = c.encoder.ppr;
    if !ppr.is_power_of_two() {
        return Err(err(
            "reference",
            "absolute",
            format!(
                "`encoder.ppr` = {ppr}: the absolute word's 2^S codes per turn must be 4 x PPR x 2^k, so PPR must be a power of two"
            ),
        ));
    }
    let x = &r.ssi;
    let qb = d.quadrant_bits;
    let s = x.single_turn_bits.unwrap_or(qb);
    let word = SsiWord {
        single_turn_bits: s,
        multiturn_bits: x.multiturn_bits,
        gray: x.gray,
    };
    if s < qb || s > 29 || s + 1 - qb > d.fine_bits {
        return Err(err(
            "reference.ssi",
            "single_turn_bits",
            format!(
                "{s}: allowed {qb}..={} (at least log2(4 x PPR) = {qb} for one code per quadrant; at most 29, and k + 1 = S - {qb} + 1 <= `cordic.fine_bits` = {})",
                (qb + d.fine_bits - 1).min(29),
                d.fine_bits
            ),
        ));
    }
    if x.multiturn_bits > 24 || s + x.multiturn_bits > 32 {
        return Err(err(
            "reference.ssi",
            "multiturn_bits",
            format!(
                "{}: allowed 0..={} (at most 24, and 32 bits in the word with the {s} single-turn bits)",
                x.multiturn_bits,
                (32 - s).min(24)
            ),
        ));
    }
    let clock_hz = c.clock.frequency_hz;
    if !(x.clock_hz.is_finite() && (10e3..=10e6).contains(&x.clock_hz)) {
        return Err(err(
            "reference.ssi",
            "clock_hz",
            format!(
                "{}: allowed 10e3..=10e6 Hz (SSI encoders: about 100 kHz to 2 MHz)",
                x.clock_hz
            ),
        ));
    }
    if !(x.data_valid_ns.is_finite() && (0.0..=10_000.0).contains(&x.data_valid_ns)) {
        return Err(err(
            "reference.ssi",
            "data_valid_ns",
            format!("{}: allowed 0..=10000 ns", x.data_valid_ns),
        ));
    }
    if !(x.monoflop_us.is_finite() && x.monoflop_us > 0.0 && x.monoflop_us <= 10_000.0) {
        return Err(err(
            "reference.ssi",
            "monoflop_us",
            format!("{}: allowed > 0 and <= 10000 us", x.monoflop_us),
        ));
    }
    let timing = SsiTiming::new(
        clock_hz,
        x.clock_hz,
        x.data_valid_ns,
        x.monoflop_us,
        d.io_timing,
    )
    .map_err(|e| {
        let m = e.detail();
        let key = if m.contains("monoflop") {
            "monoflop_us"
        } else {
            "clock_hz"
        };
        err(
            "reference.ssi",
            key,
            m.replace(
                "lower the SSI clock",
                "lower `reference.ssi.clock_hz` or `reference.ssi.data_valid_ns`",
            ),
        )
    })?;
    AbsoluteParams::new(
        word,
        qb,
        d.fine_bits,
        c.encoder.multiturn_bits,
        d.preamp.is_some(),
        latency,
        d.adc.period_clocks,
        d.adc.frame.conv_active_high,
        timing,
    )
    .map(Some)
    .map_err(|e| err("reference", "absolute", e.detail()))
}

/// The `[reference] absolute` lines of `check`.
fn describe(a: &AbsoluteParams, sample_rate_hz: f64) -> String {
    let t = a.timing();
    let w = a.word();
    let us = |c: f64| c * 1e6 / t.clock_hz;
    let read = t.wait_clocks as f64
        + t.clock_hz / sample_rate_hz
        + t.frame_clocks(w.bits()) as f64
        + MERGE_CLOCKS as f64;
    format!(
        "absolute start              SSI master on abs_clk/abs_data reads the encoder's {}-bit {} word ({} multi-turn + {} single-turn bits: {} code(s) per quadrant) once after reset; within {:.1} us\n\
         absolute SSI clock          {:.3} kHz ({} clocks per half period); {} pulses per read = {:.1} us; the clock stays high {:.1} us (monoflop t_m) after reset and before a retry\n\
         absolute line timing        each bit read 2H = {} clocks after the rising edge it answers: {}; round trip (cable + transceivers, both ways) up to {:.1} ns ({:.0} m at 6 ns/m)\n\
         absolute latch              the first falling edge leaves {} clock ({:.1} ns) after the ADC's sampling edge: the sample of that conversion takes the word\n\
         absolute merge              {} synchronization bits (quadrant, {} code bits, half a code); the period is right within +-{:.3} quadrants ({:.1} degrees electrical) of alignment error between the channels\n",
        w.bits(),
        if w.gray { "Gray" } else { "binary" },
        w.multiturn_bits,
        w.single_turn_bits,
        1u32 << a.sub_quadrant_bits(),
        us(read),
        t.rate_hz() / 1e3,
        t.half_clocks,
        w.bits() + 1,
        us(((w.bits() + 1) * 2 * t.half_clocks) as f64),
        t.monoflop_us,
        t.capture_clocks(),
        t.budget_text(),
        t.max_round_trip_ns(),
        t.max_round_trip_ns() / 2.0 / 6.0,
        SsiTiming::LATCH_LAG_CLOCKS,
        SsiTiming::LATCH_LAG_CLOCKS as f64 * t.tclk_ns(),
        a.sync_bits(),
        a.sub_quadrant_bits(),
        a.tolerance_quadrants(),
        a.tolerance_quadrants() * 90.0,
    )
}

/// Clocks of the merge after the tail: Sync, Place, Split, Target and at least one of
/// Request.
pub const MERGE_CLOCKS: u32 = 5;

/// The report's row: the block synthesized alone.
fn report_job(l: &Loaded) -> Result<BlockJob> {
    let Some(p) = &l.derived.absolute else {
        return Ok(BlockJob::absent("absolute", "needs [reference] absolute"));
    };
    job(
        l,
        "absolute",
        super::hdl::AbsoluteStart::new(p),
        BlockTiming::latency(
            p.timing().frame_clocks(p.word().bits()) + MERGE_CLOCKS,
            "one SSI frame and the merge",
        ),
    )
}
