//! Cycle-accurate, bit-accurate model of `<name>_core`.
use crate::blocks::cordic::model::cordic;
use crate::blocks::cordic::model::IterTiming;
use crate::blocks::counter::model::{combine, Combined, Counter, Load};
use crate::blocks::mask;
use crate::blocks::params::{Architecture, Derived};
use std::collections::VecDeque;

/// Inputs of one clock cycle.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoreIn {
    /// Synchronous reset.
    pub rst: bool,
    /// Sample strobe.
    pub valid: bool,
    /// Sine sample (A-bit signed value).
    pub sin: i32,
    /// Cosine sample (A-bit signed value).
    pub cos: i32,
    /// Resynchronisation request for the counter.
    pub load: Option<Load>,
}

/// Outputs after one clock edge, with the port widths of `<name>_core`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoreOut {
    /// out_valid.
    pub valid: bool,
    /// out_position = qc * 2^F + fine.
    pub position: u64,
    /// out_turns (raw M bits).
    pub turns: u64,
    /// out_fine.
    pub fine: u64,
    /// out_error.
    pub error: bool,
    /// out_warning.
    pub warning: bool,
}

impl CoreOut {
    /// Signed turn count.
    pub fn turns_signed(&self, d: &Derived) -> i64 {
        if d.multiturn_bits == 0 {
            0
        } else {
            crate::blocks::sext(self.turns, d.multiturn_bits)
        }
    }

    /// Row of port values in the order of [`core_ports`](crate::emit::core_output_ports).
    pub fn row(&self) -> Vec<u64> {
        vec![
            self.valid as u64,
            self.position,
            self.turns,
            self.fine,
            self.error as u64,
            self.warning as u64,
        ]
    }
}

/// The sample-level function of the datapath (no timing): what the combiner registers.
#[inline]
pub fn sample(d: &Derived, sin: i32, cos: i32) -> Combined {
    let c = cordic(d, sin, cos);
    match &d.harmonics {
        None => combine(d, &c),
        Some(h) => crate::blocks::harmonics::model::combine_corrected(d, h, &c),
    }
}

/// Cycle-level model: the pipeline as a delay line of N + 2 stages, then the counter
/// (unrolled CORDIC), or the iterative engine's timing, then the counter (iterative).
#[derive(Clone, Debug)]
pub struct CoreModel {
    d: Derived,
    line: VecDeque<Option<Combined>>,
    counter: Counter,
    /// Iterative architecture: mapper/engine/combiner timing and the drop marks.
    iter: Option<IterTiming<Combined>>,
}

impl CoreModel {
    /// A model in its power-up state.
    pub fn new(d: &Derived) -> Self {
        CoreModel {
            d: d.clone(),
            line: (0..d.latency_cycles).map(|_| None).collect(),
            counter: Counter::default(),
            iter: (d.architecture == Architecture::Iterative).then(IterTiming::new),
        }
    }

    /// `in_ready` for the coming cycle (always true for the unrolled CORDIC).
    pub fn in_ready(&self) -> bool {
        self.iter
            .as_ref()
            .is_none_or(|t| t.ready(self.d.cycles_per_sample))
    }

    /// One clock cycle: inputs applied before the edge, outputs after it.
    pub fn step(&mut self, i: CoreIn) -> CoreOut {
        if let Some(t) = self.iter.as_mut() {
            let d = &self.d;
            let head = t.clock(d.cycles_per_sample, i.rst, i.valid, || {
                let a = d.adc_width;
                let sin = crate::blocks::sext(i.sin as u64 & mask(a), a) as i32;
                let cos = crate::blocks::sext(i.cos as u64 & mask(a), a) as i32;
                sample(d, sin, cos)
            });
            self.counter.clock(d, i.rst, head, i.load);
            let c = &self.counter;
            return CoreOut {
                valid: c.valid,
                position: (c.qc << d.fine_bits) | c.fine,
                turns: c.turns,
                fine: c.fine,
                error: c.error,
                warning: c.warning | t.hold,
            };
        }
        let head = self.line.pop_back().flatten();
        self.counter.clock(&self.d, i.rst, head, i.load);
        if i.rst {
            self.line.iter_mut().for_each(|s| *s = None);
        }
        let s = if i.valid && !i.rst {
            let a = self.d.adc_width;
            let sin = crate::blocks::sext(i.sin as u64 & mask(a), a) as i32;
            let cos = crate::blocks::sext(i.cos as u64 & mask(a), a) as i32;
            Some(sample(&self.d, sin, cos))
        } else {
            None
        };
        self.line.push_front(s);
        let c = &self.counter;
        CoreOut {
            valid: c.valid,
            position: (c.qc << self.d.fine_bits) | c.fine,
            turns: c.turns,
            fine: c.fine,
            error: c.error,
            warning: c.warning,
        }
    }
}
