//! The constructors of the per-block report rows ([`super::blocks::BLOCKS`]): each builds one
//! block's rust-hdl description from the configuration and states its timing.
use super::blocks::{job, BlockJob, BlockTiming};
use crate::blocks::adc::hdl::AdcController;
use crate::blocks::biss::hdl::BissSlave;
use crate::blocks::core::hdl::CoreRtl;
use crate::blocks::correction::hdl::Correction;
use crate::blocks::fallback::hdl::Fallback;
use crate::blocks::monitor::hdl::Monitor;
use crate::blocks::parallel::hdl::ParallelBus;
use crate::blocks::parallel::ParallelParams;
use crate::blocks::preamp::hdl::PreampSetup;
use crate::blocks::qep::hdl::QepDecoder;
use crate::blocks::spi_slave::hdl::SpiSlave;
use crate::blocks::spi_slave::SpiSlaveParams;
use crate::blocks::ssi::hdl::SsiSlave;
use crate::blocks::ssi::SsiParams;
use crate::config::Loaded;
use crate::error::Result;

const NO_PREAMP: &str = "not in this config: needs the LTC1407A-1 preset";
const DISABLED: &str = "disabled in this config";

fn ssi_params(l: &Loaded) -> Result<(SsiParams, bool)> {
    let d = &l.derived;
    if let Some(p) = &d.ssi {
        return Ok((p.clone(), true));
    }
    let mut p = SsiParams::new(d.biss.position_bits, d.biss.multiturn_bits, d.clock_hz)?;
    p.gray = l.config.ssi.gray;
    if let Some(t) = l.config.ssi.timeout_us {
        p.set_timeout_us(t)?;
    }
    p.validate()?;
    Ok((p, false))
}

fn spi_params(l: &Loaded) -> Result<(SpiSlaveParams, bool)> {
    let d = &l.derived;
    if let Some(p) = &d.spi {
        return Ok((p.clone(), true));
    }
    let mut p = SpiSlaveParams::new(d.biss.position_bits, d.biss.multiturn_bits, d.clock_hz)?;
    p.gray = l.config.spi.gray;
    p.validate()?;
    Ok((p, false))
}

pub(crate) fn adc_job(l: &Loaded) -> Result<BlockJob> {
    let a = &l.derived.adc;
    let t = BlockTiming {
        latency_cycles: Some(a.conv_to_valid_clocks()),
        clocks_per_sample: Some(a.period_clocks),
        rate_sps: Some(a.sample_rate_hz()),
        text: format!(
            "conversion frame of P clocks per sample pair; latency = {} to out_valid",
            a.frame.start_edge()
        ),
    };
    job(l, "adc", AdcController::new(a), t)
}

pub(crate) fn preamp_job(l: &Loaded) -> Result<BlockJob> {
    match &l.derived.preamp {
        Some(p) => job(
            l,
            "preamp",
            PreampSetup::new(p),
            BlockTiming::none(&format!(
                "one-shot after reset: done after {} clocks",
                p.done_clocks()
            )),
        ),
        None => Ok(BlockJob::absent("preamp", NO_PREAMP)),
    }
}

pub(crate) fn correction_job(l: &Loaded) -> Result<BlockJob> {
    job(
        l,
        "correction",
        Correction::new(&l.derived.correction),
        BlockTiming::latency(
            l.derived.correction.latency_cycles(),
            "in_valid to out_valid",
        ),
    )
}

pub(crate) fn monitor_job(l: &Loaded) -> Result<BlockJob> {
    job(
        l,
        "monitor",
        Monitor::new(&l.derived.monitor),
        BlockTiming::latency(1, "flags one clock after the input"),
    )
}

pub(crate) fn core_job(l: &Loaded) -> Result<BlockJob> {
    let d = &l.derived;
    let t = BlockTiming {
        latency_cycles: Some(d.latency_cycles),
        clocks_per_sample: Some(d.cycles_per_sample),
        rate_sps: Some(d.clock_hz / d.cycles_per_sample.max(1) as f64),
        text: format!(
            "N + 2 cycles in_valid to out_valid ({} CORDIC; rate = throughput)",
            match d.architecture {
                crate::config::Architecture::Unrolled => "unrolled",
                crate::config::Architecture::Iterative => "iterative",
            }
        ),
    };
    job(l, "core", CoreRtl::new(d), t)
}

pub(crate) fn qep_job(l: &Loaded) -> Result<BlockJob> {
    let p = &l.derived.qep;
    job(
        l,
        "qep",
        QepDecoder::new(p),
        BlockTiming::latency(
            p.filter() + 3,
            "input level change to count: filter + 3 rising edges",
        ),
    )
}

pub(crate) fn fallback_job(l: &Loaded) -> Result<BlockJob> {
    let j = job(
        l,
        "fallback",
        Fallback::new(&l.derived),
        BlockTiming::none("works per sample beside the core"),
    )?;
    Ok(if l.derived.qep_enabled {
        j
    } else {
        j.with_note(DISABLED)
    })
}

pub(crate) fn biss_job(l: &Loaded) -> Result<BlockJob> {
    let uut = BissSlave::new(&l.derived.biss)?;
    let j = job(
        l,
        "biss",
        uut,
        BlockTiming::none("serial: clocked by the master's MA"),
    )?;
    // The row includes the control channel and its 128-byte register file when it is on.
    Ok(if l.derived.biss.control.is_some() {
        j.with_note("with the control channel (register file, docs/biss_control.md)")
    } else {
        j
    })
}

pub(crate) fn ssi_job(l: &Loaded) -> Result<BlockJob> {
    let (p, enabled) = ssi_params(l)?;
    let uut = SsiSlave::new(&p)?;
    let j = job(
        l,
        "ssi",
        uut,
        BlockTiming::none("serial: clocked by the master"),
    )?;
    Ok(if enabled { j } else { j.with_note(DISABLED) })
}

pub(crate) fn spi_job(l: &Loaded) -> Result<BlockJob> {
    let (p, enabled) = spi_params(l)?;
    let uut = SpiSlave::new(&p)?;
    let j = job(
        l,
        "spi",
        uut,
        BlockTiming::none("serial: clocked by the master"),
    )?;
    Ok(if enabled { j } else { j.with_note(DISABLED) })
}

pub(crate) fn parallel_job(l: &Loaded) -> Result<BlockJob> {
    let d = &l.derived;
    let p = ParallelParams::new(d.position_width.min(32), d.multiturn_bits)?;
    let uut = ParallelBus::new(&p)?;
    job(
        l,
        "parallel",
        uut,
        BlockTiming::latency(1, "registered outputs"),
    )
}

pub(crate) fn velocity_job(l: &Loaded) -> Result<BlockJob> {
    let Some(p) = &l.derived.velocity else {
        return Ok(BlockJob::absent("velocity", "needs [velocity] enabled"));
    };
    let note = format!(
        "{}: tick to out_velocity_valid; one update every {} clocks",
        p.spec.method, p.period_clocks
    );
    let mut t = BlockTiming::latency(p.latency() as u32, &note);
    t.clocks_per_sample = Some(p.period_clocks as u32);
    t.rate_sps = Some(p.spec.clock_hz / p.period_clocks as f64);
    job(
        l,
        "velocity",
        crate::blocks::velocity::hdl::Velocity::new(p)?,
        t,
    )
}

const CAP_ONLY: &str = "capacitive path only: needs [capacitive]";

pub(crate) fn nco_job(l: &Loaded) -> Result<BlockJob> {
    if l.derived.capacitive.is_none() {
        return Ok(BlockJob::absent("nco", CAP_ONLY));
    }
    let p = crate::blocks::capacitive::CapFrontParams::new(&l.derived)?;
    job(
        l,
        "nco",
        crate::blocks::nco::hdl::Nco::new(&p.nco),
        BlockTiming::latency(1, "one update per ADC sample (tick)"),
    )
}

pub(crate) fn biquad_job(l: &Loaded) -> Result<BlockJob> {
    if l.derived.capacitive.is_none() {
        return Ok(BlockJob::absent("biquad", CAP_ONLY));
    }
    let d = &l.derived;
    let p = crate::blocks::capacitive::CapFrontParams::new(d)?;
    let note = format!(
        "band-pass + 2 low-pass branches on one multiplier: {} clocks per section",
        crate::blocks::biquad::CYCLES_PER_SECTION
    );
    let mut t = BlockTiming::latency(p.engine.latency(), &note);
    t.clocks_per_sample = Some(p.engine.cycles_per_sample());
    t.rate_sps = Some(d.clock_hz / p.engine.cycles_per_sample() as f64);
    job(
        l,
        "biquad",
        crate::blocks::biquad::hdl::BiquadRtl::new(&p.engine),
        t,
    )
}

pub(crate) fn capfront_job(l: &Loaded) -> Result<BlockJob> {
    if l.derived.capacitive.is_none() {
        return Ok(BlockJob::absent("capfront", CAP_ONLY));
    }
    let d = &l.derived;
    let p = crate::blocks::capacitive::CapFrontParams::new(d)?;
    let mut t = BlockTiming::latency(
        p.latency(),
        "NCO + biquad engine + demodulator (2 clocks on its own multiplier)",
    );
    t.clocks_per_sample = Some(p.cycles_per_sample());
    job(
        l,
        "capfront",
        crate::blocks::capacitive::hdl::CapFront::new(&p),
        t,
    )
}

pub(crate) fn top_job(l: &Loaded) -> Result<BlockJob> {
    let d = &l.derived;
    if let Some(k) = &d.capacitive {
        let p = crate::blocks::capacitive::CapFrontParams::new(d)?;
        return match crate::emit::cap_top_verilog(l)? {
            Some(v) => Ok(BlockJob {
                key: "top".into(),
                label: String::new(),
                module: crate::emit::top_name(l),
                verilog: Some(v),
                timing: BlockTiming {
                    latency_cycles: Some(d.adc.conv_to_valid_clocks() + p.latency() + d.latency_cycles),
                    clocks_per_sample: Some(d.adc.period_clocks),
                    rate_sps: Some(k.sample_rate_hz),
                    text: format!("latency = {} to par_valid (plus one sample in the demodulator and the filters' group delay)", d.adc.frame.start_edge()),
                },
                note: String::new(),
            }),
            None => Ok(BlockJob::absent("top", CAP_ONLY)),
        };
    }
    match crate::emit::top_verilog(l)? {
        Some(v) => Ok(BlockJob {
            key: "top".into(),
            label: String::new(),
            module: crate::emit::top_name(l),
            verilog: Some(v),
            timing: BlockTiming {
                latency_cycles: Some(crate::blocks::top::hdl::conv_to_position_cycles(d)),
                clocks_per_sample: Some(d.adc.period_clocks),
                rate_sps: Some(d.sample_rate_hz),
                text: format!(
                    "latency = {} to par_valid; one position per ADC frame",
                    d.adc.frame.start_edge()
                ),
            },
            note: String::new(),
        }),
        None => Ok(BlockJob::absent(
            "top",
            "no board top for this config: needs the LTC1407A-1 preset and target spartan3an",
        )),
    }
}
