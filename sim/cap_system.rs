//! Closed loop of the capacitive path in the Rust simulation: the capacitive `<name>_top`
//! (rust-hdl, or the engine of its Verilog: `crate::sim::dut`) drives the excitation DACs; the capacitive-encoder model couples them through
//! the rotor into the receiver signal; the generic SPI ADC model converts it at each CONV;
//! the decoded position is compared with the model's true angle.
use crate::blocks::captop::hdl::CapTopRtl;
use crate::blocks::sext;
use crate::config::Derived;
use crate::cosim::step::NoConvergence;
use crate::sim::capacitive::{CapEncoder, CapParams};
use crate::sim::dut::{Dut, EngineKind, CAP_IN_PINS, CAP_OUT_PINS};
use crate::sim::spi_adc::SpiAdc;
use std::cell::RefCell;
use std::f64::consts::TAU;
use std::rc::Rc;

/// One decoded position.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CapRecord {
    /// Clock cycle of par_valid.
    pub cycle: u64,
    /// Single-turn position (2^-F quadrant units).
    pub position: u64,
    /// Signed turn count.
    pub turns: i64,
    /// Unwrapped decoded position in LSB (turns * 4 PPR 2^F + position).
    pub decoded: i64,
    /// True mechanical position at par_valid, same units.
    pub truth: f64,
    /// Error flag.
    pub error: bool,
    /// Warning flag.
    pub warning: bool,
}

/// Error figures after removing the mean (the filters' group delay is a constant lag at
/// constant speed, and the band-pass's phase at the carrier a constant offset).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CapStats {
    /// Records used.
    pub samples: usize,
    /// Mean error (the constant lag/offset), mechanical degrees.
    pub mean_deg: f64,
    /// Max |error - mean|, mechanical degrees.
    pub max_deg: f64,
    /// Mean |error - mean|, mechanical degrees.
    pub mean_abs_deg: f64,
    /// RMS of error - mean, mechanical degrees.
    pub rms_deg: f64,
    /// Peak-to-peak of the error, mechanical degrees.
    pub pp_deg: f64,
    /// Records with the error or warning flag.
    pub flagged: usize,
}

// Pin indices of [`CAP_IN_PINS`] / [`CAP_OUT_PINS`].
const I_RST: usize = 0;
const I_MISO: usize = 1;
const I_MA: usize = 2;
const O_CONV: usize = 0;
const O_SCK: usize = 1;
const O_STROBE: usize = 2;
const O_SIN: usize = 3;
const O_COS: usize = 4;
const O_VALID: usize = 5;
const O_QC: usize = 6;
const O_FINE: usize = 7;
const O_TURNS: usize = 8;
const O_ERROR: usize = 9;
const O_WARNING: usize = 10;

/// The closed loop.
pub struct CapSystem {
    top: Dut<CapTopRtl>,
    adc: SpiAdc,
    dac: Rc<RefCell<(i64, i64)>>,
    enc: Rc<RefCell<CapEncoder>>,
    clock_hz: f64,
    dac_width: u32,
    lsb_per_turn: f64,
    f: u32,
    turns_width: u32,
    cycle: u64,
    /// Decoded positions (kept unless [`CapSystem::keep_records`] turned them off).
    pub records: Vec<CapRecord>,
    /// Per-cycle input rows (`CapTopRtl`'s port-table input order), when recording.
    pub inputs: Option<Vec<Vec<u64>>>,
    keep: bool,
    /// Every decoded position reduced to (cycle, decoded - truth, flagged): what the
    /// statistics need, 24 bytes a position, when the records are not kept.
    errors: Vec<(u64, f64, bool)>,
    decoded: usize,
    trace: Option<crate::sim::vcd::TopTrace>,
    trace_error: Option<std::io::Error>,
}

impl CapSystem {
    /// A loop for the derived parameters (needs `[capacitive]`) and an encoder model, with
    /// the top on rust-hdl.
    pub fn new(d: &Derived, p: CapParams) -> crate::error::Result<CapSystem> {
        Self::on(d, p, EngineKind::RustHdl)
    }

    /// [`new`](Self::new) with the top simulated by `engine` (see [`crate::sim::dut`]).
    pub fn on(d: &Derived, p: CapParams, engine: EngineKind) -> crate::error::Result<CapSystem> {
        let k = d
            .capacitive
            .as_ref()
            .ok_or_else(|| crate::error::Error::ModelParams {
                model: "capacitive system".into(),
                message: "needs [capacitive]".into(),
            })?;
        let top = Dut::new(d, engine, &CAP_IN_PINS, &CAP_OUT_PINS)?;
        let enc = Rc::new(RefCell::new(CapEncoder::new(p)?));
        let dac = Rc::new(RefCell::new((0i64, 0i64)));
        let clock_hz = d.clock_hz;
        let (e2, d2) = (enc.clone(), dac.clone());
        let adc = SpiAdc::new(
            &d.adc,
            crate::sim::adc_pins::PinTiming::from_io(&d.io_timing),
            Box::new(move |clock| {
                let (s, c) = *d2.borrow();
                let code = e2.borrow_mut().sample(clock as f64 / clock_hz, s, c);
                [code as i32, 0]
            }),
        );
        Ok(CapSystem {
            top,
            adc,
            dac,
            enc,
            clock_hz,
            dac_width: k.config.dac_width,
            lsb_per_turn: d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64,
            f: d.fine_bits,
            turns_width: d.turns_width,
            cycle: 0,
            records: Vec::new(),
            inputs: None,
            keep: true,
            errors: Vec::new(),
            decoded: 0,
            trace: None,
            trace_error: None,
        })
    }

    /// The engine that runs the top (after any fallback).
    pub fn engine(&self) -> EngineKind {
        self.top.engine()
    }

    /// Why the engine that runs is not the one asked for, if it is not.
    pub fn engine_note(&self) -> Option<&str> {
        self.top.note()
    }

    /// Keep every decoded record (the default) or only what the statistics need.
    pub fn keep_records(&mut self, keep: bool) {
        self.keep = keep;
    }

    /// Decoded positions so far (kept or not).
    pub fn decoded(&self) -> usize {
        self.decoded
    }

    /// Streams every cycle's pins into `t` from now on (see [`crate::sim::vcd`]).
    pub fn trace_to(&mut self, t: crate::sim::vcd::TopTrace) {
        self.trace = Some(t);
    }

    /// Ends the trace: flushes it and returns the first write error, if any.
    pub fn finish_trace(&mut self) -> std::io::Result<()> {
        if let Some(e) = self.trace_error.take() {
            return Err(e);
        }
        match self.trace.take() {
            Some(t) => t.finish(),
            None => Ok(()),
        }
    }

    /// Records every cycle's inputs from now on (a stimulus that replays the run in a
    /// Verilog simulator).
    pub fn record_inputs(&mut self) {
        self.inputs = Some(Vec::new());
    }

    /// Resets the design (4 cycles) and settles it.
    pub fn start(&mut self) -> Result<(), NoConvergence> {
        self.top.start()
    }

    /// Runs `cycles` clocks.
    pub fn run(&mut self, cycles: u64) -> Result<(), NoConvergence> {
        for _ in 0..cycles {
            let t = &mut self.top;
            t.set(I_RST, (self.cycle < 4) as u64);
            t.set(I_MA, 1);
            let miso = self.adc.step(t.get(O_CONV) != 0, t.get(O_SCK) != 0);
            t.set(I_MISO, miso as u64);
            t.tick()?;
            if self.inputs.is_some() || self.trace.is_some() {
                // The inputs just applied, read back by name in the port table's order.
                let row = t.input_row();
                if let Some(tr) = self.trace.as_mut() {
                    let outs = t.sample();
                    if let Err(e) = tr.cycle(&row, &outs) {
                        self.trace_error = Some(e);
                        self.trace = None;
                    }
                }
                if let Some(v) = &mut self.inputs {
                    v.push(row);
                }
            }
            self.cycle += 1;
            let t = &self.top;
            if t.get(O_STROBE) != 0 {
                *self.dac.borrow_mut() = (
                    sext(t.get(O_SIN), self.dac_width),
                    sext(t.get(O_COS), self.dac_width),
                );
            }
            if t.get(O_VALID) != 0 {
                let pos = (t.get(O_QC) << self.f) | t.get(O_FINE);
                let turns = sext(t.get(O_TURNS), self.turns_width);
                let decoded = turns * self.lsb_per_turn as i64 + pos as i64;
                let ts = self.cycle as f64 / self.clock_hz;
                let truth = self.enc.borrow().mech_angle(ts) / TAU * self.lsb_per_turn;
                let r = CapRecord {
                    cycle: self.cycle,
                    position: pos,
                    turns,
                    decoded,
                    truth,
                    error: t.get(O_ERROR) != 0,
                    warning: t.get(O_WARNING) != 0,
                };
                self.decoded += 1;
                if self.keep {
                    self.records.push(r);
                } else {
                    self.errors
                        .push((r.cycle, r.decoded as f64 - r.truth, r.error || r.warning));
                }
                // The ADC model needs only its latest conversion.
                self.adc.forget_old();
            }
        }
        Ok(())
    }

    /// Clock cycles run.
    pub fn cycles(&self) -> u64 {
        self.cycle
    }

    /// Error statistics over the records after `skip_s` seconds (filter settling). The
    /// decoded position has an arbitrary zero (an incremental position), so the error is
    /// taken modulo one turn around its first value before the mean is removed.
    pub fn stats(&self, skip_s: f64) -> CapStats {
        let skip = (skip_s * self.clock_hz) as u64;
        if self.keep {
            stats_of(&self.records, self.lsb_per_turn, skip)
        } else {
            stats_of_errors(&self.errors, self.lsb_per_turn, skip)
        }
    }
}

/// The same loop on the bit-accurate models (sample-level front end, cycle-level core) for
/// long runs: a whole turn at 800 rpm is 30,000 samples. Sample n is converted at n / fs
/// with the DAC words the NCO holds then; the result's records use sample indices as
/// cycles. Proven equal to the RTL by tests/capacitive/capacitive.rs (front end and top replays).
pub fn model_run(
    d: &Derived,
    p: CapParams,
    samples: usize,
) -> crate::error::Result<Vec<CapRecord>> {
    use crate::blocks::capacitive::model::CapFrontModel;
    use crate::blocks::capacitive::CapFrontParams;
    use crate::blocks::core::model::{CoreIn, CoreModel};
    let fp = CapFrontParams::new(d)?;
    let mut front = CapFrontModel::new(&fp);
    let mut core = CoreModel::new(d);
    let mut enc = CapEncoder::new(p)?;
    let fs = fp.nco.update_hz();
    let lsb_per_turn = d.quadrants_per_turn as f64 * (1u64 << d.fine_bits) as f64;
    let mut out = Vec::with_capacity(samples);
    let mut t_of: std::collections::VecDeque<f64> = Default::default();
    for n in 0..samples + d.latency_cycles as usize + 1 {
        let step = if n < samples {
            let t = n as f64 / fs;
            let (s, c) = front.dac_words();
            let code = enc.sample(t, s, c);
            let o = front.step(code as i64);
            t_of.push_back(t);
            CoreIn {
                rst: false,
                valid: true,
                sin: o.q as i32,
                cos: o.i as i32,
                load: None,
            }
        } else {
            CoreIn {
                rst: false,
                valid: false,
                sin: 0,
                cos: 0,
                load: None,
            }
        };
        let r = core.step(step);
        if r.valid {
            let t = t_of.pop_front().unwrap_or(0.0);
            out.push(CapRecord {
                cycle: (t * d.clock_hz) as u64,
                position: r.position,
                turns: r.turns_signed(d),
                decoded: r.turns_signed(d) * lsb_per_turn as i64 + r.position as i64,
                truth: enc.mech_angle(t) / TAU * lsb_per_turn,
                error: r.error,
                warning: r.warning,
            });
        }
    }
    Ok(out)
}

/// [`CapSystem::stats`] for records of any source.
pub fn stats_of(records: &[CapRecord], lsb_per_turn: f64, skip_cycles: u64) -> CapStats {
    let errs: Vec<(u64, f64, bool)> = records
        .iter()
        .map(|r| (r.cycle, r.decoded as f64 - r.truth, r.error || r.warning))
        .collect();
    stats_of_errors(&errs, lsb_per_turn, skip_cycles)
}

/// [`stats_of`] on (cycle, decoded - truth, flagged) per position.
fn stats_of_errors(errors: &[(u64, f64, bool)], lsb_per_turn: f64, skip_cycles: u64) -> CapStats {
    let recs: Vec<&(u64, f64, bool)> = errors.iter().filter(|r| r.0 >= skip_cycles).collect();
    if recs.is_empty() {
        return CapStats::default();
    }
    let turn = lsb_per_turn;
    let raw: Vec<f64> = recs.iter().map(|r| r.1).collect();
    let e0 = raw[0];
    let errs: Vec<f64> = raw
        .iter()
        .map(|e| e0 + (e - e0 + turn / 2.0).rem_euclid(turn) - turn / 2.0)
        .collect();
    let n = errs.len() as f64;
    let mean = errs.iter().sum::<f64>() / n;
    let to_deg = 360.0 / turn;
    let dev: Vec<f64> = errs.iter().map(|e| e - mean).collect();
    let max = dev.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    let lo = dev.iter().cloned().fold(f64::MAX, f64::min);
    let hi = dev.iter().cloned().fold(f64::MIN, f64::max);
    CapStats {
        samples: recs.len(),
        mean_deg: mean.rem_euclid(turn) * to_deg,
        max_deg: max * to_deg,
        mean_abs_deg: dev.iter().map(|e| e.abs()).sum::<f64>() / n * to_deg,
        rms_deg: (dev.iter().map(|e| e * e).sum::<f64>() / n).sqrt() * to_deg,
        pp_deg: (hi - lo) * to_deg,
        flagged: recs.iter().filter(|r| r.2).count(),
    }
}
