//! Sample-level bit-accurate model of the capacitive front end: what reaches the core for
//! each ADC sample (the RTL's out_i / out_q at each out_valid).
use super::CapFrontParams;
use crate::blocks::biquad::model::BiquadModel;
use crate::blocks::nco::model::{NcoIn, NcoModel};

/// Model state.
#[derive(Clone, Debug)]
pub struct CapFrontModel {
    p: CapFrontParams,
    nco: NcoModel,
    engine: BiquadModel,
    /// NCO words currently on the DACs.
    cur: (i64, i64),
    i: i64,
    q: i64,
    demod_ovf: bool,
}

/// One processed sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CapFrontOut {
    /// Low-passed I (~cos theta).
    pub i: i64,
    /// Low-passed Q (~sin theta).
    pub q: i64,
    /// Some section (or the previous demodulation) saturated.
    pub overflow: bool,
    /// Band-passed sample.
    pub y: i64,
}

impl CapFrontModel {
    /// Power-up (= reset) state.
    pub fn new(p: &CapFrontParams) -> Self {
        CapFrontModel {
            p: p.clone(),
            nco: NcoModel::new(&p.nco),
            engine: BiquadModel::new(&p.engine),
            cur: (0, 0),
            i: 0,
            q: 0,
            demod_ovf: false,
        }
    }

    /// The DAC words the next sample is converted with.
    pub fn dac_words(&self) -> (i64, i64) {
        self.cur
    }

    /// One ADC sample (A-bit signed value): ticks the NCO, runs the filters, demodulates.
    pub fn step(&mut self, x: i64) -> CapFrontOut {
        let (rs, rc) = self.cur;
        let o = self.nco.step(NcoIn {
            rst: false,
            tick: true,
        });
        self.cur = (o.sin, o.cos);
        let (outs, ovf) = self.engine.step(&[x, self.i, self.q]);
        let out = CapFrontOut {
            i: outs[1],
            q: outs[2],
            overflow: ovf | self.demod_ovf,
            y: outs[0],
        };
        let d = self.p.data_width();
        let sh = self.p.nco.width() - 1;
        let (lo, hi) = (-(1i64 << (d - 1)), (1i64 << (d - 1)) - 1);
        let dm = |r: i64| {
            let v = ((outs[0] as i128 * r as i128) >> sh) as i64;
            (v.clamp(lo, hi), v < lo || v > hi)
        };
        let (i, oi) = dm(rs);
        let (q, oq) = dm(rc);
        self.i = i;
        self.q = q;
        self.demod_ovf = oi || oq;
        out
    }
}
