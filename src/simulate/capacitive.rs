//! `simulate` on the capacitive path: the capacitive `<name>_top` against the
//! capacitive-encoder model.

use super::*;

/// `simulate` for a configuration with `[capacitive]`: the capacitive top against the
/// capacitive-encoder model (16-bit ADC of 1 V full scale; `amplitude` is the received
/// amplitude as a fraction of the ADC's range, `noise_lsb` its noise in ADC LSB RMS;
/// offsets, gain mismatch, phase error and harmonics do not apply and are rejected).
/// Returns the summary and a CSV of every decoded position ([`CSV_COLUMNS`]).
pub fn run_capacitive(
    loaded: &Loaded,
    o: &SimOptions,
    progress: impl FnMut(u64, u64),
) -> Result<(String, String)> {
    run_capacitive_traced(loaded, o, progress, None)
}

/// [`run_capacitive`], streaming the capacitive `<name>_top`'s pins as VCD into `vcd`.
pub fn run_capacitive_traced(
    loaded: &Loaded,
    o: &SimOptions,
    progress: impl FnMut(u64, u64),
    vcd: Option<Box<dyn std::io::Write>>,
) -> Result<(String, String)> {
    let r = run_capacitive_report(loaded, o, progress, vcd)?;
    Ok((r.summary, r.csv))
}

/// A finished capacitive simulation.
pub struct CapReport {
    /// Human-readable summary.
    pub summary: String,
    /// CSV of every decoded position ([`CSV_COLUMNS`]; only the header when
    /// [`SimOptions::keep_records`] is off).
    pub csv: String,
    /// The engine that ran the top (after any fallback).
    pub engine: crate::sim::dut::EngineKind,
    /// Why that is not the engine asked for, if it is not (one line).
    pub engine_note: Option<String>,
    /// The error statistics after the settling window (what the summary prints).
    pub stats: crate::sim::cap_system::CapStats,
    /// Every decoded position (empty when [`SimOptions::keep_records`] is off).
    pub records: Vec<crate::sim::cap_system::CapRecord>,
}

/// [`run_capacitive_traced`] with the engine that ran.
pub fn run_capacitive_report(
    loaded: &Loaded,
    o: &SimOptions,
    mut progress: impl FnMut(u64, u64),
    vcd: Option<Box<dyn std::io::Write>>,
) -> Result<CapReport> {
    use crate::sim::cap_system::CapSystem;
    use crate::sim::capacitive::CapParams;
    o.validate(true)?;
    let d = &loaded.derived;
    let k = d.capacitive.as_ref().ok_or_else(|| {
        Error::Simulation("run_capacitive needs a configuration with [capacitive]".into())
    })?;
    // The settling window is fixed (a shorter run would measure the filters' transient);
    // `--settle` may lengthen it.
    let skip = CAP_SETTLE_S.max(o.settle_s);
    // Ten decoded positions past the settling window at least.
    let need = CAP_SETTLE_S + 10.0 / k.sample_rate_hz;
    if o.duration_s < need {
        return Err(Error::option(
            "--duration",
            format!(
                "{} s: the capacitive path's filters settle for the first {:.1} ms, which are not measured; use at least {need:.6} s",
                o.duration_s,
                CAP_SETTLE_S * 1e3
            ),
        ));
    }
    let mut p = CapParams::ideal(loaded.config.encoder.ppr, 0.0);
    p.profile = o.profile.clone();
    p.dac_bits = k.config.dac_width;
    p.coupling = o.amplitude / k.config.amplitude;
    p.noise_rms_v = o.noise_lsb * p.adc_full_scale_v / (1u64 << (d.adc.frame.width - 1)) as f64;
    p.seed = o.seed;
    let mut sys = CapSystem::on(d, p, o.engine)?;
    sys.keep_records(o.keep_records);
    let engine = sys.engine();
    let engine_note = sys.engine_note().map(str::to_string);
    if let Some(out) = vcd {
        let top = crate::blocks::captop::hdl::CapTopRtl::new(d)?;
        let t = top_trace(loaded, out, &top)?;
        sys.trace_to(t);
    }
    let settle = |e: crate::cosim::step::NoConvergence| Error::HdlCheck {
        block: "top".into(),
        message: e.to_string(),
    };
    sys.start().map_err(settle)?;
    let total = (o.duration_s * d.clock_hz).ceil() as u64;
    let t0 = std::time::Instant::now();
    let mut done = 0;
    while done < total {
        let n = (1u64 << 14).min(total - done);
        sys.run(n).map_err(settle)?;
        done += n;
        progress(done, total);
    }
    let wall = t0.elapsed().as_secs_f64();
    sys.finish_trace().map_err(|e| Error::io("VCD output", e))?;
    let s = sys.stats(skip);
    if s.samples == 0 && o.settle_s > CAP_SETTLE_S {
        return Err(Error::option(
            "--settle",
            format!(
                "{} s: leaves no sample: the {} positions decoded in the {} s run all came before it; use a shorter --settle or a longer --duration",
                o.settle_s,
                sys.decoded(),
                o.duration_s
            ),
        ));
    }
    if s.samples == 0 {
        return Err(no_sample(
            o.duration_s,
            sys.decoded(),
            format!("those of the first {:.3} ms are settling", skip * 1e3),
            need,
        ));
    }
    let front = crate::blocks::capacitive::CapFrontParams::new(d)?;
    let us = |c: u32| c as f64 / d.clock_hz * 1e6;
    // error_lsb: decoded - truth minus the constant lag/offset the summary removes (the
    // mean over the statistics window), taken modulo one turn like the statistics.
    let turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
    let mean_lsb = s.mean_deg / 360.0 * turn;
    let skip_cycles = (skip * d.clock_hz) as u64;
    let mut t = CsvText::new(CSV_COLUMNS);
    for r in &sys.records {
        let e = r.decoded as f64 - r.truth - mean_lsb;
        t.row(&[
            &r.cycle,
            &r.cycle,
            &r.position,
            &r.turns,
            &r.decoded,
            &format_args!("{:.3}", r.truth),
            &format_args!("{:.3}", e - turn * (e / turn).round()),
            &(r.error as u8),
            &(r.warning as u8),
            &((r.cycle < skip_cycles) as u8),
        ]);
    }
    let csv = t.finish();
    let summary = format!(
        "capacitive path: {} periods per turn, carrier {:.0} Hz, {:.0} samples/s\n\
         positions after {:.1} ms of settling: {} ({} flagged)\n\
         error after removing the constant lag/offset ({:.4} deg): max {:.5} deg, mean |e| {:.5} deg, RMS {:.5} deg, p-p {:.5} deg (mechanical)\n\
         per sample: ADC conv->sample {} clocks ({:.2} us), filters+demod {} clocks ({:.2} us), CORDIC core {} clocks ({:.2} us), period {} clocks ({:.2} us)\n\
         simulated {} cycles in {:.2} s ({:.0} cycles/s, {} engine)\n",
        loaded.config.encoder.ppr,
        k.config.carrier_hz,
        k.sample_rate_hz,
        skip * 1e3,
        s.samples,
        s.flagged,
        s.mean_deg,
        s.max_deg,
        s.mean_abs_deg,
        s.rms_deg,
        s.pp_deg,
        d.adc.conv_to_valid_clocks(),
        us(d.adc.conv_to_valid_clocks()),
        front.cycles_per_sample(),
        us(front.cycles_per_sample()),
        d.latency_cycles,
        us(d.latency_cycles),
        d.adc.period_clocks,
        us(d.adc.period_clocks),
        sys.cycles(),
        wall,
        sys.cycles() as f64 / wall.max(1e-9),
        engine.name(),
    );
    Ok(CapReport {
        summary,
        csv,
        engine,
        engine_note,
        stats: s,
        records: std::mem::take(&mut sys.records),
    })
}
