//! rust-hdl description of the capacitive front end (see the module docs).
use super::CapFrontParams;
use crate::blocks::biquad::hdl::{BiquadMul, BiquadRtl};
use crate::blocks::nco::hdl::Nco;
use crate::blocks::{c32, mask};
use crate::cosim::Port;
use rust_hdl::prelude::*;

/// NCO + biquad engine + demodulator.
#[derive(LogicBlock)]
pub struct CapFront {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high.
    pub rst: Signal<In, Bit>,
    /// ADC sample strobe.
    pub in_valid: Signal<In, Bit>,
    /// ADC sample, A-bit two's complement in the low bits.
    pub in_sample: Signal<In, Bits<32>>,
    /// Excitation word A sin(wt), W-bit two's complement.
    pub exc_sin: Signal<Out, Bits<32>>,
    /// Excitation word A cos(wt), W-bit two's complement.
    pub exc_cos: Signal<Out, Bits<32>>,
    /// One clock when new excitation words are out.
    pub exc_strobe: Signal<Out, Bit>,
    /// One clock: new out_i / out_q.
    pub out_valid: Signal<Out, Bit>,
    /// Low-passed I (~cos theta), D-bit two's complement.
    pub out_i: Signal<Out, Bits<32>>,
    /// Low-passed Q (~sin theta), D-bit two's complement.
    pub out_q: Signal<Out, Bits<32>>,
    /// With out_valid: a filter section or the demodulator saturated for this sample.
    pub overflow: Signal<Out, Bit>,
    /// One clock: a sample arrived while the engine was busy and was lost.
    pub dropped: Signal<Out, Bit>,
    nco: Nco,
    engine: BiquadRtl,
    demod: BiquadMul,
    ref_s: DFF<Bits<32>>,
    ref_c: DFF<Bits<32>>,
    i_reg: DFF<Bits<32>>,
    q_reg: DFF<Bits<32>>,
    dm1: DFF<Bit>,
    dm2: DFF<Bit>,
    dovf: DFF<Bit>,
    xs: Signal<Local, Bits<32>>,
    sat: Signal<Local, Bits<32>>,
    sat_hit: Signal<Local, Bit>,
    /// Sign bit of an A-bit sample.
    asign: Constant<Bits<32>>,
    /// Mask of A bits.
    amask: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
    /// Bits A..D-1: sign extension of a negative sample to D bits.
    afill: Constant<Bits<32>>,
    /// Bit 31 (sign of the 32-bit product word).
    psign: Constant<Bits<32>>,
    /// Largest D-bit value.
    dmax: Constant<Bits<32>>,
    /// Smallest D-bit value as a 32-bit word.
    dmin32: Constant<Bits<32>>,
    /// Smallest D-bit value, D bits.
    dmin: Constant<Bits<32>>,
    /// Mask of D bits.
    dmask: Constant<Bits<32>>,
}

impl CapFront {
    /// The front end for validated parameters.
    pub fn new(p: &CapFrontParams) -> Self {
        let a = p.adc_width;
        let d = p.data_width();
        let w = p.nco.width();
        Self {
            clk: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_sample: Default::default(),
            exc_sin: Default::default(),
            exc_cos: Default::default(),
            exc_strobe: Default::default(),
            out_valid: Default::default(),
            out_i: Default::default(),
            out_q: Default::default(),
            overflow: Default::default(),
            dropped: Default::default(),
            nco: Nco::new(&p.nco),
            engine: BiquadRtl::new(&p.engine),
            demod: BiquadMul::new(d, w, w - 1),
            ref_s: Default::default(),
            ref_c: Default::default(),
            i_reg: Default::default(),
            q_reg: Default::default(),
            dm1: Default::default(),
            dm2: Default::default(),
            dovf: Default::default(),
            xs: Default::default(),
            sat: Default::default(),
            sat_hit: Default::default(),
            asign: c32(1 << (a - 1)),
            amask: c32(mask(a)),
            zero: c32(0),
            afill: c32(mask(d) & !mask(a)),
            psign: c32(1 << 31),
            dmax: c32(mask(d - 1)),
            dmin32: c32(mask(32) & !mask(d - 1)),
            dmin: c32(1 << (d - 1)),
            dmask: c32(mask(d)),
        }
    }
}

impl Logic for CapFront {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, ref_s, ref_c, i_reg, q_reg, dm1, dm2, dovf);
        self.nco.clk.next = self.clk.val();
        self.nco.rst.next = self.rst.val();
        self.nco.tick.next = self.in_valid.val();
        self.engine.clk.next = self.clk.val();
        self.engine.rst.next = self.rst.val();
        // Sample, sign-extended from A to D bits.
        self.xs.next = self.in_sample.val() & self.amask.val();
        if (self.in_sample.val() & self.asign.val()).any() {
            self.xs.next = self.xs.val() | self.afill.val();
        }
        self.engine.in_valid.next = self.in_valid.val();
        self.engine.in_data[0].next = self.xs.val();
        self.engine.in_data[1].next = self.i_reg.q.val();
        self.engine.in_data[2].next = self.q_reg.q.val();
        // The words on the DACs while this sample converted: the NCO's before its tick.
        if self.in_valid.val() {
            self.ref_s.d.next = self.nco.out_sin.val();
            self.ref_c.d.next = self.nco.out_cos.val();
        }
        // Demodulation of the band-passed sample, one product per clock.
        self.demod.a.next = self.engine.out_data[0].val();
        self.demod.b.next = self.ref_s.q.val();
        if self.dm2.q.val() {
            self.demod.b.next = self.ref_c.q.val();
        }
        // Saturate the 32-bit product word to D bits.
        self.sat.next = self.demod.p.val() & self.dmask.val();
        self.sat_hit.next = false;
        if (self.demod.p.val() & self.psign.val()).any() {
            if self.demod.p.val() < self.dmin32.val() {
                self.sat.next = self.dmin.val();
                self.sat_hit.next = true;
            }
        } else if self.demod.p.val() > self.dmax.val() {
            self.sat.next = self.dmax.val();
            self.sat_hit.next = true;
        }
        self.dm1.d.next = self.engine.out_valid.val();
        self.dm2.d.next = self.dm1.q.val();
        if self.dm1.q.val() {
            self.i_reg.d.next = self.sat.val();
        }
        if self.dm2.q.val() {
            self.q_reg.d.next = self.sat.val();
        }
        // A demodulator saturation is reported with the next sample's out_valid.
        if (self.dm1.q.val() | self.dm2.q.val()) & self.sat_hit.val() {
            self.dovf.d.next = true;
        }
        if self.engine.out_valid.val() {
            self.dovf.d.next = false;
        }
        if self.rst.val() {
            self.ref_s.d.next = self.zero.val();
            self.ref_c.d.next = self.zero.val();
            self.i_reg.d.next = self.zero.val();
            self.q_reg.d.next = self.zero.val();
            self.dm1.d.next = false;
            self.dm2.d.next = false;
            self.dovf.d.next = false;
        }
        self.exc_sin.next = self.nco.out_sin.val();
        self.exc_cos.next = self.nco.out_cos.val();
        self.exc_strobe.next = self.nco.out_valid.val();
        self.out_valid.next = self.engine.out_valid.val();
        self.out_i.next = self.engine.out_data[1].val();
        self.out_q.next = self.engine.out_data[2].val();
        self.overflow.next =
            self.engine.out_valid.val() & (self.engine.overflow.val() | self.dovf.q.val());
        self.dropped.next = self.engine.dropped.val();
    }
}

impl crate::cosim::step::Clocked for CapFront {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for CapFront {
    fn input_ports(&self) -> Vec<Port> {
        vec![
            Port::new("rst", 1),
            Port::new("in_valid", 1),
            Port::new("in_sample", 32),
        ]
    }
    fn output_ports(&self) -> Vec<Port> {
        vec![
            Port::new("exc_sin", 32),
            Port::new("exc_cos", 32),
            Port::new("exc_strobe", 1),
            Port::new("out_valid", 1),
            Port::new("out_i", 32),
            Port::new("out_q", 32),
            Port::new("overflow", 1),
            Port::new("dropped", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.in_valid.next = r[1] != 0;
        self.in_sample.next = Bits::<32>::from(r[2] & 0xffff_ffff);
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.exc_sin.val().to_u64(),
            self.exc_cos.val().to_u64(),
            self.exc_strobe.val() as u64,
            self.out_valid.val() as u64,
            self.out_i.val().to_u64(),
            self.out_q.val().to_u64(),
            self.overflow.val() as u64,
            self.dropped.val() as u64,
        ]
    }
}
