//! rust-hdl description of the whole core.
use crate::blocks::c32;
use crate::blocks::cordic::hdl::{CordicStage, QuadrantMapper};
use crate::blocks::cordic::iterative::IterativeCordic;
use crate::blocks::counter::hdl::{z_start, Combiner, QuadrantCounter};
use crate::blocks::harmonics::hdl::HarmonicCorrection;
use crate::blocks::harmonics::learned::LearnedHarmonics;
use crate::blocks::params::{Architecture, Derived};
use rust_hdl::prelude::*;

/// The core as simulated in rust-hdl and exported (inside the `<name>_core` wrapper).
#[derive(LogicBlock)]
pub struct CoreRtl {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// Sample strobe.
    pub in_valid: Signal<In, Bit>,
    /// Sine sample (A-bit two's complement in the low bits).
    pub in_sin: Signal<In, Bits<16>>,
    /// Cosine sample (A-bit two's complement in the low bits).
    pub in_cos: Signal<In, Bits<16>>,
    /// Resynchronise the coarse count at the next accepted sample (see the counter).
    pub load: Signal<In, Bit>,
    /// Coarse count to resynchronise to.
    pub load_qc: Signal<In, Bits<32>>,
    /// Turn count to resynchronise to.
    pub load_turns: Signal<In, Bits<32>>,
    /// Output strobe.
    pub out_valid: Signal<Out, Bit>,
    /// Coarse quadrant count (upper part of out_position).
    pub out_qc: Signal<Out, Bits<32>>,
    /// Fine part (lower F bits of out_position).
    pub out_fine: Signal<Out, Bits<32>>,
    /// Turn count (M bits).
    pub out_turns: Signal<Out, Bits<32>>,
    /// Error flag.
    pub out_error: Signal<Out, Bit>,
    /// Warning flag.
    pub out_warning: Signal<Out, Bit>,
    /// CORDIC magnitude K_N |v| 2^G of the sample leaving the last stage (W bits).
    pub out_mag: Signal<Out, Bits<32>>,
    /// `out_mag` holds a sample (two cycles before that sample's `out_valid`).
    pub out_mag_valid: Signal<Out, Bit>,
    /// A sample offered in this cycle is accepted (always high for the unrolled CORDIC;
    /// see `crate::blocks::cordic::iterative` for the iterative one).
    pub in_ready: Signal<Out, Bit>,
    /// The learned harmonic table (`[harmonics] mode = "learn"`; one each, else none): 1
    /// freezes the table (the register map's LEARN cleared).
    pub h_freeze: Vec<Signal<In, Bit>>,
    /// A request to set entry `h_ld_addr` of the learned table to `h_ld_data` (q units).
    pub h_ld: Vec<Signal<In, Bit>>,
    /// The entry of the request.
    pub h_ld_addr: Vec<Signal<In, Bits<32>>>,
    /// Its value, q units (2^-8 LSB), two's complement in the learner's entry width.
    pub h_ld_data: Vec<Signal<In, Bits<32>>>,
    /// The learner writes an entry this clock (for the register map's copy).
    pub h_tw: Vec<Signal<Out, Bit>>,
    /// Its address: bank P + i.
    pub h_tw_addr: Vec<Signal<Out, Bits<32>>>,
    /// Its value, q units.
    pub h_tw_data: Vec<Signal<Out, Bits<32>>>,
    /// The bank of the table in use.
    pub h_bank: Vec<Signal<Out, Bit>>,
    /// A load request is pending.
    pub h_ld_busy: Vec<Signal<Out, Bit>>,
    mapper: QuadrantMapper,
    /// The N unrolled stages (empty for the iterative architecture).
    stages: Vec<CordicStage>,
    /// The iterative engine (one for the iterative architecture, else none).
    iter: Vec<IterativeCordic>,
    /// The harmonic table between the last stage and the combiner (`[harmonics]`: one,
    /// else none).
    harm: Vec<HarmonicCorrection>,
    /// The learned table between the last stage and the combiner (`[harmonics] mode =
    /// "learn"`: one, else none).
    harm_l: Vec<LearnedHarmonics>,
    combiner: Combiner,
    counter: QuadrantCounter,
    /// 2^(Gz-1): the rounding half in the initial angle.
    zhalf: Constant<Bits<32>>,
    /// F + Gz: the shift of the quadrant in the initial angle.
    zqshift: Constant<Bits<32>>,
}

/// One port with a learned harmonic table, none without.
fn learned_ports<T: Default>(d: &Derived) -> Vec<T> {
    let n = d.harmonics.iter().filter(|h| h.learn.is_some()).count();
    (0..n).map(|_| T::default()).collect()
}

impl CoreRtl {
    /// Core for the derived parameters (N = `d.iterations` stages).
    pub fn new(d: &Derived) -> Self {
        let zs = z_start(d);
        Self {
            clk: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_sin: Default::default(),
            in_cos: Default::default(),
            load: Default::default(),
            load_qc: Default::default(),
            load_turns: Default::default(),
            out_valid: Default::default(),
            out_qc: Default::default(),
            out_fine: Default::default(),
            out_turns: Default::default(),
            out_error: Default::default(),
            out_warning: Default::default(),
            out_mag: Default::default(),
            out_mag_valid: Default::default(),
            in_ready: Default::default(),
            h_freeze: learned_ports(d),
            h_ld: learned_ports(d),
            h_ld_addr: learned_ports(d),
            h_ld_data: learned_ports(d),
            h_tw: learned_ports(d),
            h_tw_addr: learned_ports(d),
            h_tw_data: learned_ports(d),
            h_bank: learned_ports(d),
            h_ld_busy: learned_ports(d),
            mapper: QuadrantMapper::new(d),
            stages: if d.architecture == Architecture::Unrolled {
                (0..d.iterations).map(|i| CordicStage::new(d, i)).collect()
            } else {
                Vec::new()
            },
            iter: if d.architecture == Architecture::Iterative {
                vec![IterativeCordic::new(d)]
            } else {
                Vec::new()
            },
            harm: d
                .harmonics
                .iter()
                .filter(|h| h.learn.is_none())
                .map(HarmonicCorrection::new)
                .collect(),
            harm_l: d
                .harmonics
                .iter()
                .filter(|h| h.learn.is_some())
                .map(LearnedHarmonics::new)
                .collect(),
            combiner: Combiner::new(d),
            counter: QuadrantCounter::new(d),
            zhalf: c32(zs.0),
            zqshift: c32(zs.1),
        }
    }
}

impl Logic for CoreRtl {
    #[hdl_gen]
    fn update(&mut self) {
        self.mapper.clk.next = self.clk.val();
        self.mapper.rst.next = self.rst.val();
        self.mapper.in_valid.next = self.in_valid.val();
        self.in_ready.next = true;
        // Iterative architecture: the mapper only takes samples the engine can accept.
        for i in 0..self.iter.len() {
            self.iter[i].clk.next = self.clk.val();
            self.iter[i].rst.next = self.rst.val();
            self.iter[i].in_valid.next = self.in_valid.val();
            self.iter[i].x_in.next = self.mapper.x.val();
            self.iter[i].y_in.next = self.mapper.y.val();
            self.iter[i].q_in.next = self.mapper.q.val();
            self.iter[i].v_in.next = self.mapper.v.val();
            self.mapper.in_valid.next = self.in_valid.val() & self.iter[i].in_ready.val();
            self.in_ready.next = self.iter[i].in_ready.val();
        }
        self.mapper.in_sin.next = self.in_sin.val();
        self.mapper.in_cos.next = self.in_cos.val();
        // Every stage first takes the mapper's output; stages 1.. are then rewired to
        // their predecessor (the last assignment wins, in rust-hdl and in Verilog alike).
        for i in 0..self.stages.len() {
            self.stages[i].clk.next = self.clk.val();
            self.stages[i].rst.next = self.rst.val();
            self.stages[i].x_in.next = self.mapper.x.val();
            self.stages[i].y_in.next = self.mapper.y.val();
            // The angle starts at the rounding half plus the quadrant (see `Combiner`).
            self.stages[i].z_in.next =
                self.zhalf.val() | (bit_cast::<32, 2>(self.mapper.q.val()) << self.zqshift.val());
            self.stages[i].q_in.next = self.mapper.q.val();
            self.stages[i].v_in.next = self.mapper.v.val();
        }
        for i in 1..self.stages.len() {
            self.stages[i].x_in.next = self.stages[i - 1].x_out.val();
            self.stages[i].y_in.next = self.stages[i - 1].y_out.val();
            self.stages[i].z_in.next = self.stages[i - 1].z_out.val();
            self.stages[i].q_in.next = self.stages[i - 1].q_out.val();
            self.stages[i].v_in.next = self.stages[i - 1].v_out.val();
        }
        // The combiner takes the last stage's output (last assignment wins).
        self.combiner.clk.next = self.clk.val();
        self.combiner.rst.next = self.rst.val();
        for i in 0..self.stages.len() {
            self.combiner.z_in.next = self.stages[i].z_out.val();
            self.combiner.x_in.next = self.stages[i].x_out.val();
            self.combiner.v_in.next = self.stages[i].v_out.val();
            self.out_mag.next = self.stages[i].x_out.val();
            self.out_mag_valid.next = self.stages[i].v_out.val();
        }
        // With `[harmonics]` the table takes the last stage's output and the combiner (and
        // the magnitude, which keeps its two clocks ahead of out_valid) the table's.
        for j in 0..self.harm.len() {
            self.harm[j].clk.next = self.clk.val();
            self.harm[j].rst.next = self.rst.val();
            for i in 0..self.stages.len() {
                self.harm[j].z_in.next = self.stages[i].z_out.val();
                self.harm[j].x_in.next = self.stages[i].x_out.val();
                self.harm[j].v_in.next = self.stages[i].v_out.val();
            }
            self.combiner.z_in.next = self.harm[j].z_out.val();
            self.combiner.x_in.next = self.harm[j].x_out.val();
            self.combiner.v_in.next = self.harm[j].v_out.val();
            self.out_mag.next = self.harm[j].x_out.val();
            self.out_mag_valid.next = self.harm[j].v_out.val();
        }
        for j in 0..self.harm_l.len() {
            self.harm_l[j].clk.next = self.clk.val();
            self.harm_l[j].rst.next = self.rst.val();
            for i in 0..self.stages.len() {
                self.harm_l[j].z_in.next = self.stages[i].z_out.val();
                self.harm_l[j].x_in.next = self.stages[i].x_out.val();
                self.harm_l[j].v_in.next = self.stages[i].v_out.val();
            }
            self.harm_l[j].update.next = !self.h_freeze[j].val();
            self.harm_l[j].ld.next = self.h_ld[j].val();
            self.harm_l[j].ld_addr.next = self.h_ld_addr[j].val();
            self.harm_l[j].ld_data.next = self.h_ld_data[j].val();
            self.h_tw[j].next = self.harm_l[j].tw.val();
            self.h_tw_addr[j].next = self.harm_l[j].tw_addr.val();
            self.h_tw_data[j].next = self.harm_l[j].tw_data.val();
            self.h_bank[j].next = self.harm_l[j].bank.val();
            self.h_ld_busy[j].next = self.harm_l[j].ld_busy.val();
            self.combiner.z_in.next = self.harm_l[j].z_out.val();
            self.combiner.x_in.next = self.harm_l[j].x_out.val();
            self.combiner.v_in.next = self.harm_l[j].v_out.val();
            self.out_mag.next = self.harm_l[j].x_out.val();
            self.out_mag_valid.next = self.harm_l[j].v_out.val();
        }
        for i in 0..self.iter.len() {
            self.combiner.z_in.next = self.iter[i].z_out.val();
            self.combiner.x_in.next = self.iter[i].x_out.val();
            self.combiner.v_in.next = self.iter[i].v_out.val();
            self.out_mag.next = self.iter[i].x_out.val();
            self.out_mag_valid.next = self.iter[i].v_out.val();
        }
        self.counter.clk.next = self.clk.val();
        self.counter.rst.next = self.rst.val();
        self.counter.p_in.next = self.combiner.p.val();
        self.counter.q_next.next = self.combiner.q_next.val();
        self.counter.acc_in.next = self.combiner.acc.val();
        self.counter.ok_in.next = self.combiner.mag_ok.val();
        self.counter.v_in.next = self.combiner.v.val();
        self.counter.up_in.next = self.combiner.up.val();
        self.counter.down_in.next = self.combiner.down.val();
        self.counter.step_in.next = self.combiner.step.val();
        self.counter.wq_in.next = self.combiner.wq.val();
        self.counter.wz_in.next = self.combiner.wz.val();
        self.counter.load.next = self.load.val();
        self.counter.load_qc.next = self.load_qc.val();
        self.counter.load_turns.next = self.load_turns.val();
        self.out_valid.next = self.counter.valid.val();
        self.out_qc.next = self.counter.qc.val();
        self.out_fine.next = self.counter.fine.val();
        self.out_turns.next = self.counter.turns.val();
        self.out_error.next = self.counter.error.val();
        self.out_warning.next = self.counter.warning.val();
        // A dropped sample (iterative only) raises the warning of the next one.
        for i in 0..self.iter.len() {
            self.out_warning.next = self.counter.warning.val() | self.iter[i].lost.val();
        }
    }
}

impl crate::cosim::step::Clocked for CoreRtl {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

/// Runs the rust-hdl simulation of the core, stepped by hand, on a stimulus; returns the
/// outputs after every clock edge with the widths of `<name>_core`.
pub fn simulate_rtl(
    d: &Derived,
    inputs: &[super::model::CoreIn],
) -> Result<Vec<super::model::CoreOut>, crate::cosim::step::NoConvergence> {
    Ok(simulate_rtl_ready(d, inputs)?
        .into_iter()
        .map(|(o, _)| o)
        .collect())
}

/// As [`simulate_rtl`], with `in_ready` after every edge (the value for the next cycle).
pub fn simulate_rtl_ready(
    d: &Derived,
    inputs: &[super::model::CoreIn],
) -> Result<Vec<(super::model::CoreOut, bool)>, crate::cosim::step::NoConvergence> {
    use crate::blocks::mask;
    use crate::cosim::step::{prepare, tick};
    let mut uut = Box::new(CoreRtl::new(d));
    prepare(uut.as_mut())?;
    let am = mask(d.adc_width);
    let mut out = Vec::with_capacity(inputs.len());
    for i in inputs {
        uut.rst.next = i.rst;
        uut.in_valid.next = i.valid;
        uut.in_sin.next = Bits::<16>::from(i.sin as u64 & am);
        uut.in_cos.next = Bits::<16>::from(i.cos as u64 & am);
        let l = i.load.unwrap_or_default();
        uut.load.next = i.load.is_some();
        uut.load_qc.next = Bits::<32>::from(l.qc & mask(32));
        uut.load_turns.next = Bits::<32>::from(l.turns & mask(32));
        tick(uut.as_mut())?;
        let qc = uut.out_qc.val().to_u64();
        let fine = uut.out_fine.val().to_u64();
        out.push((
            super::model::CoreOut {
                valid: uut.out_valid.val(),
                position: (qc << d.fine_bits) | fine,
                turns: uut.out_turns.val().to_u64() & mask(d.turns_width),
                fine,
                error: uut.out_error.val(),
                warning: uut.out_warning.val(),
            },
            uut.in_ready.val(),
        ));
    }
    Ok(out)
}

impl crate::cosim::CosimBlock for CoreRtl {
    fn input_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("rst", 1),
            Port::new("in_valid", 1),
            Port::new("in_sin", 16),
            Port::new("in_cos", 16),
            Port::new("load", 1),
            Port::new("load_qc", 32),
            Port::new("load_turns", 32),
        ]
    }
    fn output_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("out_valid", 1),
            Port::new("out_qc", 32),
            Port::new("out_fine", 32),
            Port::new("out_turns", 32),
            Port::new("out_error", 1),
            Port::new("out_warning", 1),
            Port::new("out_mag", 32),
            Port::new("out_mag_valid", 1),
            Port::new("in_ready", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.in_valid.next = r[1] != 0;
        self.in_sin.next = Bits::<16>::from(r[2]);
        self.in_cos.next = Bits::<16>::from(r[3]);
        self.load.next = r[4] != 0;
        self.load_qc.next = Bits::<32>::from(r[5]);
        self.load_turns.next = Bits::<32>::from(r[6]);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.out_valid.val() as u64,
            self.out_qc.val().to_u64(),
            self.out_fine.val().to_u64(),
            self.out_turns.val().to_u64(),
            self.out_error.val() as u64,
            self.out_warning.val() as u64,
            self.out_mag.val().to_u64(),
            self.out_mag_valid.val() as u64,
            self.in_ready.val() as u64,
        ]
    }
}
