//! Four-way check of the core: the rust-hdl simulation, the bit-accurate model, Icarus
//! Verilog and Verilator on the exported Verilog, all driven by one stimulus; and the same
//! check of any block without the model. Whenever a Verilog simulator runs, sinedec's own
//! engine of the same Verilog runs too (`crate::cosim::run_engine_expecting`: the compiled engine, or
//! its interpreter with `SINEDEC_COSIM_ENGINE=interpreter`) and must give the same trace.
use crate::blocks::core::hdl::simulate_rtl;
use crate::blocks::core::model::{CoreIn, CoreModel};
use crate::blocks::mask;
use crate::config::Loaded;
use crate::cosim::{
    cosim_engine_kind, first_mismatch, run_engine_expecting, run_icarus_expecting,
    run_verilator_expecting, CosimSpec, Trace,
};
use crate::emit::{core_input_ports, core_name, core_output_ports, core_verilog};
use crate::error::{Error, Result};
use std::path::Path;

/// Which simulators to run besides rust-hdl and the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Simulators {
    /// Run Icarus Verilog.
    pub icarus: bool,
    /// Run Verilator.
    pub verilator: bool,
}

impl Simulators {
    /// Both Verilog simulators.
    pub const ALL: Simulators = Simulators {
        icarus: true,
        verilator: true,
    };
}

/// The traces of one run, all in `<name>_core` port order.
#[derive(Clone, Debug)]
pub struct CoreTraces {
    /// rust-hdl simulation, stepped by hand.
    pub rust_hdl: Trace,
    /// Bit-accurate model.
    pub model: Trace,
    /// Icarus Verilog, when run.
    pub icarus: Option<Trace>,
    /// Verilator, when run.
    pub verilator: Option<Trace>,
    /// sinedec's engine of the exported Verilog, run with either Verilog simulator.
    pub engine: Option<Trace>,
}

impl CoreTraces {
    /// None when every trace equals the rust-hdl one; otherwise the first difference.
    pub fn mismatch(&self, loaded: &Loaded) -> Option<String> {
        let outs = core_output_ports(&loaded.derived);
        let mut others: Vec<(&str, &Trace)> = vec![("model", &self.model)];
        if let Some(t) = &self.icarus {
            others.push(("icarus", t));
        }
        if let Some(t) = &self.verilator {
            others.push(("verilator", t));
        }
        if let Some(t) = &self.engine {
            others.push(("engine", t));
        }
        others
            .into_iter()
            .find_map(|(name, t)| first_mismatch("rust-hdl", &self.rust_hdl, name, t, &outs))
    }
}

/// Stimulus rows for the Verilog simulators (`core_input_ports` order).
pub fn stimulus_rows(loaded: &Loaded, inputs: &[CoreIn]) -> Vec<Vec<u64>> {
    let am = mask(loaded.derived.adc_width);
    inputs
        .iter()
        .map(|i| {
            vec![
                i.rst as u64,
                i.valid as u64,
                i.sin as u64 & am,
                i.cos as u64 & am,
            ]
        })
        .collect()
}

/// Runs every simulator on `inputs`; `workdir` holds the Verilog runs' files.
pub fn core_traces(
    loaded: &Loaded,
    inputs: &[CoreIn],
    sims: Simulators,
    workdir: &Path,
) -> Result<CoreTraces> {
    let d = &loaded.derived;
    let rust_hdl = simulate_rtl(d, inputs)
        .map_err(|e| Error::HdlCheck {
            block: "core".into(),
            message: e.to_string(),
        })?
        .iter()
        .map(|o| o.row())
        .collect();
    let mut m = CoreModel::new(d);
    let model = inputs.iter().map(|i| m.step(*i).row()).collect();
    let verilog = core_verilog(loaded)?;
    let top = core_name(loaded);
    let ins = core_input_ports(d);
    let outs = core_output_ports(d);
    let spec = CosimSpec {
        verilog: &verilog,
        top: &top,
        clock: "clk",
        inputs: &ins,
        outputs: &outs,
    };
    let rows = stimulus_rows(loaded, inputs);
    let icarus = if sims.icarus {
        Some(run_icarus_expecting(&spec, &rows, workdir, &rust_hdl)?)
    } else {
        None
    };
    let verilator = if sims.verilator {
        Some(run_verilator_expecting(&spec, &rows, workdir, &rust_hdl)?)
    } else {
        None
    };
    let engine = engine_trace(&spec, &rows, sims, &rust_hdl)?;
    Ok(CoreTraces {
        rust_hdl,
        model,
        icarus,
        verilator,
        engine,
    })
}

/// Traces of one block run: rust-hdl, and the Verilog simulators that were asked for.
#[derive(Clone, Debug)]
pub struct BlockTraces {
    /// rust-hdl simulation, stepped by hand.
    pub rust_hdl: Trace,
    /// Icarus Verilog, when run.
    pub icarus: Option<Trace>,
    /// Verilator, when run.
    pub verilator: Option<Trace>,
    /// sinedec's engine of the exported Verilog, run with either Verilog simulator.
    pub engine: Option<Trace>,
    /// The output ports (for messages).
    pub outputs: Vec<crate::cosim::Port>,
}

impl BlockTraces {
    /// None when Icarus, Verilator and the engine equal rust-hdl; otherwise the first
    /// difference.
    pub fn mismatch(&self) -> Option<String> {
        [
            ("icarus", &self.icarus),
            ("verilator", &self.verilator),
            ("engine", &self.engine),
        ]
        .into_iter()
        .filter_map(|(n, t)| t.as_ref().map(|t| (n, t)))
        .find_map(|(n, t)| first_mismatch("rust-hdl", &self.rust_hdl, n, t, &self.outputs))
    }
}

/// Exports `uut` as Verilog (top module `top_name`, every module prefixed with it), runs
/// the rust-hdl simulation of it on `rows`, and the chosen Verilog simulators in `workdir`.
/// The clock input must be named `clk` (or `clock`: give its name in `clock`).
pub fn block_traces<B: crate::cosim::CosimBlock>(
    mut uut: B,
    top_name: &str,
    clock: &str,
    rows: &[Vec<u64>],
    sims: Simulators,
    workdir: &Path,
) -> Result<BlockTraces> {
    use crate::cosim::step::{prepare, tick};
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let verilog = crate::emit::verilog::export(&uut, top_name, top_name)?;
    let ins = uut.input_ports();
    let outs = uut.output_ports();
    let settle = |e: crate::cosim::step::NoConvergence| Error::HdlCheck {
        block: top_name.to_string(),
        message: e.to_string(),
    };
    prepare(&mut uut).map_err(settle)?;
    let mut rust_hdl = Vec::with_capacity(rows.len());
    for r in rows {
        uut.apply(r);
        tick(&mut uut).map_err(settle)?;
        rust_hdl.push(uut.sample());
    }
    let spec = CosimSpec {
        verilog: &verilog,
        top: top_name,
        clock,
        inputs: &ins,
        outputs: &outs,
    };
    let icarus = if sims.icarus {
        Some(run_icarus_expecting(&spec, rows, workdir, &rust_hdl)?)
    } else {
        None
    };
    let verilator = if sims.verilator {
        Some(run_verilator_expecting(&spec, rows, workdir, &rust_hdl)?)
    } else {
        None
    };
    let engine = engine_trace(&spec, rows, sims, &rust_hdl)?;
    Ok(BlockTraces {
        rust_hdl,
        icarus,
        verilator,
        engine,
        outputs: outs,
    })
}

/// The engine's trace of `spec` on `rows` when a Verilog simulator is asked for, through
/// the verdict cache as the simulators' (`expected`: rust-hdl's trace).
fn engine_trace(
    spec: &CosimSpec,
    rows: &[Vec<u64>],
    sims: Simulators,
    expected: &Trace,
) -> Result<Option<Trace>> {
    if !(sims.icarus || sims.verilator) {
        return Ok(None);
    }
    run_engine_expecting(spec, rows, cosim_engine_kind()?, expected).map(Some)
}
