//! The operating points of the data sheet ([`Plan`]) and their closed-loop runs: every point
//! is one run of `simulate`'s closed loop ([`crate::simulate::run`]: the configured
//! `<name>_top` on the compiled engine against the encoder and ADC chip models), all of them
//! in parallel on rayon's pool (one thread per core). Results come back in the plan's order,
//! so the page does not depend on the schedule.
use crate::config::Loaded;
use crate::error::Result;
use crate::sim::encoder::Profile;
use crate::sim::system::SimResult;
use crate::simulate::SimOptions;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// The imperfections of the "with imperfections" runs, in `simulate`'s options (a typical
/// uncalibrated optical encoder at 80 % of the ADC's range).
pub fn imperfect_options() -> SimOptions {
    SimOptions {
        amplitude: 0.8,
        noise_lsb: 1.0,
        offset: (0.01, -0.01),
        gain_mismatch: 0.01,
        phase_error_deg: 0.5,
        third_harmonic: 0.005,
        seed: 7,
        ..SimOptions::default()
    }
}

/// `x` rounded to two significant digits (speeds people read).
pub fn nice(x: f64) -> f64 {
    if x <= 0.0 || !x.is_finite() {
        return 0.0;
    }
    let p = 10f64.powf(x.log10().floor() - 1.0);
    (x / p).round() * p
}

/// What runs: speeds, durations, and the velocity runs when `[velocity]` is on.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The unwrap limit (`check`'s max speed), rpm.
    pub limit_rpm: f64,
    /// The accuracy runs' speeds (slow, middle, near the limit), rpm.
    pub accuracy_rpm: Vec<f64>,
    /// Their simulated time, seconds.
    pub accuracy_s: f64,
    /// The sweep's speeds, standstill to 1.5 x the limit, rpm.
    pub sweep_rpm: Vec<f64>,
    /// Simulated time of an ideal-encoder sweep run, seconds.
    pub sweep_s: f64,
    /// Simulated time of a sweep run with imperfections (long enough for the velocity
    /// estimator's warm-up when it is on), seconds.
    pub sweep_imperfect_s: f64,
    /// Velocity step and ramp: (speed before, time of the change, ramp time, duration).
    pub velocity: Option<VelocityPlan>,
}

/// The velocity estimator's step and ramp runs: the speed reverses from `rpm` to `-rpm`
/// at `at`, within one ADC sample (step) or within `ramp_s` (ramp).
#[derive(Clone, Copy, Debug)]
pub struct VelocityPlan {
    /// Speed before the change, rpm.
    pub rpm: f64,
    /// Start of the change, seconds.
    pub at: f64,
    /// Duration of the ramp, seconds.
    pub ramp_s: f64,
    /// Duration of the step run, seconds.
    pub step_run_s: f64,
    /// Duration of the ramp run, seconds.
    pub ramp_run_s: f64,
}

impl Plan {
    /// The default grid, or the reduced one of `--quick` (CI).
    pub fn new(loaded: &Loaded, quick: bool) -> Plan {
        let d = &loaded.derived;
        let limit = crate::simulate::followable_rpm(loaded);
        let n = if quick { 9 } else { 31 };
        let sweep_rpm = (0..n)
            .map(|i| (1.5 * limit * i as f64 / (n - 1) as f64).round())
            .collect();
        let sweep_s: f64 = if quick { 0.6e-3 } else { 2e-3 };
        // Reset, ADC start-up and the position's latency, before any statistics.
        let start_s = (d.adc.startup_clocks() as f64
            + crate::blocks::top::hdl::conv_to_position_cycles(d) as f64
            + 20.0 * d.adc.period_clocks as f64)
            / d.clock_hz;
        let velocity = d.velocity.as_ref().map(|v| {
            let update = 1.0 / v.spec.rate_hz;
            let warm = start_s + (v.warmup_updates() + 2) as f64 * update;
            let at = warm + 10.0 * update;
            let ramp_s = (if quick { 30.0 } else { 80.0 }) * update;
            let tail = (if quick { 30.0 } else { 60.0 }) * update;
            VelocityPlan {
                rpm: nice(0.2 * limit),
                at,
                ramp_s,
                step_run_s: at + tail,
                ramp_run_s: at + ramp_s + tail / 2.0,
            }
        });
        let sweep_imperfect_s = match &d.velocity {
            Some(v) => {
                let update = 1.0 / v.spec.rate_hz;
                let warm = start_s + (v.warmup_updates() + 2) as f64 * update;
                sweep_s.max(warm + (if quick { 8.0 } else { 24.0 }) * update)
            }
            None => sweep_s,
        };
        Plan {
            limit_rpm: limit,
            accuracy_rpm: vec![nice(0.02 * limit), nice(0.3 * limit), nice(0.9 * limit)],
            accuracy_s: if quick { 1.5e-3 } else { 8e-3 },
            sweep_rpm,
            sweep_s,
            sweep_imperfect_s,
            velocity,
        }
    }

    /// Every run, in the order of the results.
    fn jobs(&self) -> Vec<Job> {
        let mut j: Vec<Job> = self
            .accuracy_rpm
            .iter()
            .map(|&r| Job::Accuracy(r))
            .collect();
        for imperfect in [false, true] {
            j.extend(
                self.sweep_rpm
                    .iter()
                    .map(|&rpm| Job::Sweep { rpm, imperfect }),
            );
        }
        if self.velocity.is_some() {
            j.push(Job::VelocityStep);
            j.push(Job::VelocityRamp);
        }
        j
    }

    /// The options of run `j`.
    fn options(&self, j: &Job) -> SimOptions {
        let base = |imperfect: bool| {
            if imperfect {
                imperfect_options()
            } else {
                SimOptions::default()
            }
        };
        let v = self.velocity.unwrap_or(VelocityPlan {
            rpm: 0.0,
            at: 0.0,
            ramp_s: 1e-6,
            step_run_s: 1e-3,
            ramp_run_s: 1e-3,
        });
        let (profile, duration_s, keep, imperfect) = match *j {
            Job::Accuracy(rpm) => (Profile::Constant { rpm }, self.accuracy_s, true, true),
            Job::Sweep { rpm, imperfect } => (
                Profile::Constant { rpm },
                if imperfect {
                    self.sweep_imperfect_s
                } else {
                    self.sweep_s
                },
                false,
                imperfect,
            ),
            Job::VelocityStep => (
                Profile::Reversal {
                    rpm: v.rpm,
                    at: v.at,
                    over: 1e-7,
                },
                v.step_run_s,
                true,
                false,
            ),
            Job::VelocityRamp => (
                Profile::Reversal {
                    rpm: v.rpm,
                    at: v.at,
                    over: v.ramp_s,
                },
                v.ramp_run_s,
                true,
                false,
            ),
        };
        SimOptions {
            profile,
            duration_s,
            keep_records: keep,
            ..base(imperfect)
        }
    }

    /// Clock cycles of every run together (the progress bar's length).
    pub fn total_cycles(&self, loaded: &Loaded) -> u64 {
        self.jobs()
            .iter()
            .map(|j| (self.options(j).duration_s * loaded.derived.clock_hz).ceil() as u64)
            .sum()
    }

    /// Runs every point in parallel; `progress(cycles)` gets the cycles simulated since its
    /// last call, from any thread.
    pub fn run(&self, loaded: &Loaded, progress: &(dyn Fn(u64) + Sync)) -> Result<Runs> {
        let jobs = self.jobs();
        let outs: Vec<Out> = jobs
            .par_iter()
            .map(|j| {
                let o = self.options(j);
                let last = AtomicU64::new(0);
                let r = crate::simulate::run(loaded, &o, |done, _| {
                    progress(done - last.swap(done, Ordering::Relaxed));
                })?;
                Ok(Out {
                    options: o,
                    result: r.result,
                    stats: r.stats,
                    engine_note: r.engine_note,
                })
            })
            .collect::<Result<_>>()?;
        let mut it = outs.into_iter();
        let mut take = |n: usize| it.by_ref().take(n).collect::<Vec<Out>>();
        let accuracy = take(self.accuracy_rpm.len());
        let sweep_ideal = take(self.sweep_rpm.len());
        let sweep_imperfect = take(self.sweep_rpm.len());
        let velocity = take(2);
        let engine_note = accuracy.iter().find_map(|o| o.engine_note.clone());
        let (step, ramp) = match <[Out; 2]>::try_from(velocity) {
            Ok([s, r]) => (Some(s), Some(r)),
            Err(_) => (None, None),
        };
        Ok(Runs {
            accuracy,
            sweep_ideal,
            sweep_imperfect,
            step,
            ramp,
            engine_note,
        })
    }
}

/// One run.
#[derive(Clone, Copy, Debug)]
enum Job {
    Accuracy(f64),
    Sweep { rpm: f64, imperfect: bool },
    VelocityStep,
    VelocityRamp,
}

/// A finished run.
pub struct Out {
    /// Its options.
    pub options: SimOptions,
    /// The closed loop's records.
    pub result: SimResult,
    /// Its error statistics.
    pub stats: crate::sim::system::ErrorStats,
    /// Why the engine is not the one asked for, if it is not.
    pub engine_note: Option<String>,
}

/// Every run of a [`Plan`], by purpose.
pub struct Runs {
    /// At [`Plan::accuracy_rpm`], with imperfections, records kept.
    pub accuracy: Vec<Out>,
    /// At [`Plan::sweep_rpm`], ideal encoder.
    pub sweep_ideal: Vec<Out>,
    /// At [`Plan::sweep_rpm`], with imperfections.
    pub sweep_imperfect: Vec<Out>,
    /// Velocity step (with `[velocity]`).
    pub step: Option<Out>,
    /// Velocity ramp (with `[velocity]`).
    pub ramp: Option<Out>,
    /// The engine's fallback, if any (said once).
    pub engine_note: Option<String>,
}
