//! The design a closed loop drives: the rust-hdl `<name>_top` rtl stepped by hand (the
//! reference) or the compiled engine built from the Verilog that same rtl exports
//! (`crate::engine`, tests/engine.rs proves them equal cycle for cycle). The loop reads and
//! writes pins by the fixed indices below, so both look the same to it.
use crate::blocks::top::hdl::TopRtl;
use crate::cosim::step::{prepare, tick, NoConvergence};
use crate::cosim::CosimBlock;
use crate::engine::{Engine, Kind};
use crate::error::{Error, Result};

/// Inputs the closed loop drives, in index order ([`Dut::set`]).
pub const IN_PINS: [&str; 9] = [
    "rst", "adc_miso", "biss_ma", "qep_a", "qep_b", "qep_z", "ssi_clk", "enc_sck", "enc_cs_n",
];
/// Outputs the closed loop reads, in index order ([`Dut::get`]); the last
/// [`OPTIONAL_OUT_PINS`] exist only in some configurations (the velocity estimator's, with
/// `[velocity] enabled`) and read 0 without them.
pub const OUT_PINS: [&str; 16] = [
    "adc_conv",
    "adc_sck",
    "amp_cs",
    "amp_mosi",
    "amp_shdn",
    "biss_slo",
    "ssi_data",
    "par_valid",
    "par_qc",
    "par_fine",
    "par_turns",
    "par_error",
    "par_warning",
    "enc_miso",
    "par_velocity_0",
    "par_velocity_valid_0",
];
/// How many of the last [`OUT_PINS`] are optional.
pub const OPTIONAL_OUT_PINS: usize = 2;

/// Which engine simulates the top (`simulate --engine`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EngineKind {
    /// rust-hdl's own simulation (the reference).
    #[default]
    RustHdl,
    /// The compiled engine (Yosys + rustc, cached).
    Compiled,
}

/// The compiled top and the index maps of its ports.
pub struct CompiledTop {
    e: Box<Engine>,
    /// Engine input index of each [`IN_PINS`] entry.
    ins: [usize; 9],
    /// Engine output index of each [`OUT_PINS`] entry (None: an optional pin the
    /// configuration lacks).
    outs: [Option<usize>; 16],
    /// Present value of every engine input (the engine has no read-back).
    shadow: Vec<u64>,
    /// Engine input index of each of the rtl's co-simulation inputs (port-table order).
    row_ins: Vec<Option<usize>>,
    /// Engine output index of each of the rtl's co-simulation outputs.
    row_outs: Vec<Option<usize>>,
    /// The rtl's co-simulation inputs (idle levels for ports the engine lacks).
    idle: Vec<u64>,
}

/// The design under the closed loop.
pub enum Dut {
    /// rust-hdl's simulation of the top.
    Rtl(Box<TopRtl>),
    /// The compiled engine.
    Compiled(Box<CompiledTop>),
}

impl Dut {
    /// The top for `d` on `kind`.
    pub fn new(d: &crate::config::Derived, kind: EngineKind) -> Result<Dut> {
        let mut rtl = Box::new(TopRtl::new(d)?);
        if kind == EngineKind::RustHdl {
            return Ok(Dut::Rtl(rtl));
        }
        // The same instance gives the Verilog and the co-simulation port lists.
        rust_hdl::prelude::Block::connect_all(rtl.as_mut());
        let name = "sinedec_top_rtl";
        let verilog = crate::emit::verilog::export(rtl.as_ref(), "top", name)?;
        let e = Engine::new(&verilog, name, "clk", Kind::Compiled)?;
        let missing = |what: &str, p: &str| {
            Error::Simulation(format!("the compiled top has no {what} `{p}`"))
        };
        let mut ins = [0; 9];
        for (k, p) in IN_PINS.iter().enumerate() {
            ins[k] = e.input_index(p).ok_or_else(|| missing("input", p))?;
        }
        let mut outs = [None; 16];
        for (k, p) in OUT_PINS.iter().enumerate() {
            outs[k] = e.output_index(p);
            if outs[k].is_none() && k < OUT_PINS.len() - OPTIONAL_OUT_PINS {
                return Err(missing("output", p));
            }
        }
        let row_ins = rtl
            .input_ports()
            .iter()
            .map(|p| e.input_index(&p.name))
            .collect();
        let row_outs = rtl
            .output_ports()
            .iter()
            .map(|p| e.output_index(&p.name))
            .collect();
        let idle = rtl.input_row();
        let shadow = vec![0; e.inputs().len()];
        Ok(Dut::Compiled(Box::new(CompiledTop {
            e: Box::new(e),
            ins,
            outs,
            shadow,
            row_ins,
            row_outs,
            idle,
        })))
    }

    /// Connects the design and settles its outputs; call once.
    pub fn start(&mut self) -> std::result::Result<(), NoConvergence> {
        match self {
            Dut::Rtl(t) => prepare(t.as_mut()),
            Dut::Compiled(c) => {
                c.e.eval();
                Ok(())
            }
        }
    }

    /// Drives input [`IN_PINS`]`[k]` for the next edge.
    pub fn set(&mut self, k: usize, v: bool) {
        match self {
            Dut::Rtl(t) => {
                t.set_input(IN_PINS[k], v as u64);
            }
            Dut::Compiled(c) => {
                let i = c.ins[k];
                c.shadow[i] = v as u64;
                c.e.set(i, v as u64);
            }
        }
    }

    /// Output [`OUT_PINS`]`[k]` (as of the last edge).
    pub fn get(&self, k: usize) -> u64 {
        match self {
            Dut::Rtl(t) => t.output(OUT_PINS[k]).unwrap_or(0),
            Dut::Compiled(c) => c.outs[k].map_or(0, |i| c.e.get(i)),
        }
    }

    /// One clock edge.
    pub fn tick(&mut self) -> std::result::Result<(), NoConvergence> {
        match self {
            Dut::Rtl(t) => tick(t.as_mut()),
            Dut::Compiled(c) => {
                c.e.tick();
                Ok(())
            }
        }
    }

    /// The inputs applied at the last edge, in the rtl's co-simulation order.
    pub fn input_row(&self) -> Vec<u64> {
        match self {
            Dut::Rtl(t) => t.input_row(),
            Dut::Compiled(c) => c
                .row_ins
                .iter()
                .zip(&c.idle)
                .map(|(i, idle)| i.map_or(*idle, |i| c.shadow[i]))
                .collect(),
        }
    }

    /// The outputs in the rtl's co-simulation order.
    pub fn sample(&self) -> Vec<u64> {
        match self {
            Dut::Rtl(t) => t.sample(),
            Dut::Compiled(c) => c
                .row_outs
                .iter()
                .map(|i| i.map_or(0, |i| c.e.get(i)))
                .collect(),
        }
    }

    /// The rust-hdl top, when that is the engine.
    pub fn rtl(&self) -> Option<&TopRtl> {
        match self {
            Dut::Rtl(t) => Some(t),
            Dut::Compiled(_) => None,
        }
    }
}
