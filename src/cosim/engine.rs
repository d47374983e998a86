//! The compiled engine (`crate::engine`) as the co-simulation's third simulator of the
//! emitted Verilog, next to Icarus and Verilator: the same [`CosimSpec`], the same stimulus
//! rows and the same cycle (inputs with the clock low, rising edge, outputs read), so its
//! trace compares with rust-hdl's bit for bit. `crate::verify` runs it whenever it runs a
//! Verilog simulator, so every block co-simulation checks it without a test of its own.
//!
//! Which engine: `SINEDEC_COSIM_ENGINE` = `compiled` (the default, what `simulate` runs;
//! built once per design and cached by its hash, see docs/benchmarks.md) or `interpreter`
//! (the same netlist interpreted: no rustc build, slower per cycle).
use super::{validate, CosimSpec, Trace};
use crate::engine::{Engine, Kind};
use crate::error::{Error, Result};

/// The environment variable that picks the co-simulation's engine.
pub const ENGINE_ENV: &str = "SINEDEC_COSIM_ENGINE";

/// The engine co-simulation runs ([`ENGINE_ENV`]; compiled when unset).
pub fn cosim_engine_kind() -> Result<Kind> {
    match std::env::var(ENGINE_ENV).as_deref() {
        Err(_) | Ok("") | Ok("compiled") => Ok(Kind::Compiled),
        Ok("interpreter") => Ok(Kind::Interpreted),
        Ok(other) => Err(Error::Simulation(format!(
            "{ENGINE_ENV}={other:?}: allowed compiled or interpreter"
        ))),
    }
}

/// Runs `stimulus` through the engine `kind` built from `spec`'s Verilog: one output row
/// per stimulus row, in `spec.outputs` order (the trace of `run_icarus`/`run_verilator`).
pub fn run_engine(spec: &CosimSpec, stimulus: &[Vec<u64>], kind: Kind) -> Result<Trace> {
    validate(spec, stimulus)?;
    let mut e = Engine::new(spec.verilog, spec.top, spec.clock, kind)?;
    e.trace(spec.inputs, spec.outputs, stimulus)
}

/// [`run_engine`] behind the verdict cache (`cache.rs`), as `run_icarus_expecting`: when
/// the cache holds `expected` for exactly this run (design, stimulus and
/// [`crate::engine::version`]), returns it without building the engine; otherwise runs it
/// and records the trace. Either way the result is the trace the engine gives.
pub fn run_engine_expecting(
    spec: &CosimSpec,
    stimulus: &[Vec<u64>],
    kind: Kind,
    expected: &Trace,
) -> Result<Trace> {
    validate(spec, stimulus)?;
    let version = crate::engine::version(kind)?;
    let stim = super::stimulus_text(spec, stimulus);
    super::cache::cached_as("engine", &version, spec, &[&stim], expected, || {
        run_engine(spec, stimulus, kind)
    })
}

/// A block's exported Verilog on the engine, stepped row by row like the rust-hdl block
/// (`CosimBlock::apply`, `step::tick`, `CosimBlock::sample`): closed loops whose subject is
/// the hardware's behaviour, not rust-hdl's simulation, run on it (the co-simulation tests
/// prove the engine equal to rust-hdl on every block).
pub struct BlockEngine {
    e: Engine,
    ins: Vec<usize>,
    outs: Vec<usize>,
}

impl BlockEngine {
    /// Exports `uut` as module `top` (every module prefixed with it) and builds `kind` of it.
    pub fn new<B: super::CosimBlock>(mut uut: B, top: &str, kind: Kind) -> Result<BlockEngine> {
        rust_hdl::prelude::Block::connect_all(&mut uut);
        let verilog = crate::emit::verilog::export(&uut, top, top)?;
        let e = Engine::new(&verilog, top, "clk", kind)?;
        let find = |p: &super::Port, list: &[super::Port], what: &str| {
            list.iter().position(|q| q.name == p.name).ok_or_else(|| {
                Error::Simulation(format!("the engine's `{top}` has no {what} `{}`", p.name))
            })
        };
        let ins = uut
            .input_ports()
            .iter()
            .map(|p| find(p, e.inputs(), "input"))
            .collect::<Result<Vec<_>>>()?;
        let outs = uut
            .output_ports()
            .iter()
            .map(|p| find(p, e.outputs(), "output"))
            .collect::<Result<Vec<_>>>()?;
        Ok(BlockEngine { e, ins, outs })
    }

    /// Drives the inputs from one row (the block's input-port order) for the next edge.
    pub fn apply(&mut self, row: &[u64]) {
        for (v, &k) in row.iter().zip(&self.ins) {
            self.e.set(k, *v);
        }
    }

    /// One rising edge.
    pub fn tick(&mut self) {
        self.e.tick();
    }

    /// Back to the power-up state ([`Engine::restart`]).
    pub fn restart(&mut self) {
        self.e.restart();
    }

    /// The outputs in the block's output-port order.
    pub fn sample(&self) -> Vec<u64> {
        self.outs.iter().map(|&k| self.e.get(k)).collect()
    }

    /// Output `k` of the block's output-port order.
    pub fn output(&self, k: usize) -> u64 {
        self.e.get(self.outs[k])
    }
}
