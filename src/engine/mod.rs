//! A compiled cycle-accurate simulation engine for the Verilog sinedec emits: the Rust
//! counterpart of Verilator, so that long closed-loop simulations of `<name>_top` need not
//! step rust-hdl's many small modules (about 12 settle passes per cycle).
//!
//! ```text
//!  emitted Verilog ──► Yosys: proc; flatten; opt; wreduce ──► JSON (word-level cells)
//!        (yosys.rs)                                                 │
//!  netlist/:   bits regrouped into words, registers, memories ◄─────┘
//!  order.rs:   combinational cells in topological order, next-state and output cones
//!        ├──► codegen.rs: straight-line Rust ──► rustc -O ──► cdylib ──► compiled.rs
//!        │    (cached by a hash of its inputs)                      (libloading, C ABI)
//!        └──► interp.rs: the same cells interpreted (fallback, no rustc needed)
//! ```
//!
//! Both paths use one definition of every cell's arithmetic, ops.rs (pasted into the
//! generated code), and the co-simulation cycle of src/cosim/mod.rs: inputs applied with the
//! clock low, the rising edge (every register and memory write loads what the inputs and
//! the old state give), outputs read after it. Registers start at their Verilog `initial`
//! values, inputs at 0, `x` bits read as 0. Words are `u64`: a signal, operand or memory
//! word wider than 64 bits, a second clock, an asynchronous reset or a latch is reported as
//! an error naming the cell. Measurements: docs/benchmarks.md.
mod cells;
mod codegen;
mod compiled;
mod interp;
mod netlist;
pub mod ops;
mod order;
mod yosys;

use crate::cosim::{Port, Trace};
use crate::error::{Error, Result};
use sha2::{Digest, Sha256};
use std::path::PathBuf;
use std::time::Instant;

/// What a model can do; the compiled library and the interpreter implement it.
trait Sim: Send {
    fn set(&mut self, input: usize, v: u64);
    fn get(&self, output: usize) -> u64;
    fn eval(&mut self);
    fn tick(&mut self);
    /// `rows.len() / n_in` cycles of set-all-inputs, tick, read-all-outputs.
    fn run(&mut self, rows: &[u64], outs: &mut Vec<u64>);
    /// Back to the power-up state (registers and memories at their initial values, inputs
    /// 0), as a model built anew would be.
    fn restart(&mut self);
}

/// Which engine runs the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Generated Rust compiled by rustc (cached).
    Compiled,
    /// The levelized netlist interpreted.
    Interpreted,
}

/// How a model was built, for benchmarks.
#[derive(Clone, Debug, Default)]
pub struct BuildInfo {
    /// Seconds Yosys took (0 when the library came from the cache).
    pub yosys_s: f64,
    /// Seconds rustc took (0 from the cache or for the interpreter).
    pub rustc_s: f64,
    /// The library came from the cache.
    pub cached: bool,
    /// Combinational cells, registers, memories.
    pub cells: usize,
    /// Registers.
    pub regs: usize,
    /// The cache directory of the compiled library.
    pub dir: Option<PathBuf>,
    /// Why the engine cache could not be used, naming its path (one line), when the
    /// library was built in a temporary directory instead.
    pub cache_note: Option<String>,
}

/// A model of one Verilog top module, stepped cycle by cycle.
pub struct Engine {
    sim: Box<dyn Sim>,
    inputs: Vec<Port>,
    outputs: Vec<Port>,
    info: BuildInfo,
}

/// The ports' names and widths, kept next to a cached library.
#[derive(serde::Serialize, serde::Deserialize)]
pub(crate) struct Shape {
    inputs: Vec<(String, u32)>,
    outputs: Vec<(String, u32)>,
    cells: usize,
    regs: usize,
}

fn ports(v: &[(String, u32)]) -> Vec<Port> {
    v.iter().map(|(n, w)| Port::new(n, *w)).collect()
}

/// A scratch directory `sinedec-engine-XXXXXX` in the temporary directory, entered in
/// [`crate::cleanup`] (a signal removes it); an error names `TMPDIR`.
struct Scratch {
    dir: tempfile::TempDir,
    _entry: crate::cleanup::Entry,
}

fn scratch() -> Result<Scratch> {
    let base = std::env::temp_dir();
    let (dir, _entry) = crate::cleanup::create_dir(
        || {
            tempfile::Builder::new()
                .prefix("sinedec-engine-")
                .tempdir_in(&base)
        },
        |d: &tempfile::TempDir| d.path().to_path_buf(),
    )
    .map_err(|e| Error::TempDir {
        path: base.clone(),
        reason: crate::error::io_text(&e),
    })?;
    Ok(Scratch { dir, _entry })
}

fn netlist_of(verilog: &str, top: &str, clock: &str) -> Result<(netlist::Netlist, f64)> {
    let t0 = Instant::now();
    let dir = scratch()?;
    let json = yosys::run(verilog, top, dir.dir.path())?;
    let m = yosys::parse(&json, top)?;
    let nl = netlist::build(&m, clock)?;
    Ok((nl, t0.elapsed().as_secs_f64()))
}

fn shape_of(nl: &netlist::Netlist) -> Shape {
    let w = |s: usize| nl.signals[s].width;
    Shape {
        inputs: nl.inputs.iter().map(|(n, s)| (n.clone(), w(*s))).collect(),
        outputs: nl
            .outputs
            .iter()
            .map(|(n, o)| (n.clone(), o.width))
            .collect(),
        cells: nl.cells.len(),
        regs: nl.regs.len(),
    }
}

/// What a trace of the engine `kind` depends on besides the design and its stimulus, as one
/// digest: the engine's own sources, its Yosys script and the Yosys version (its front end),
/// and for the compiled kind the rustc version and flags. The co-simulation's verdict cache
/// (`crate::cosim::run_engine_expecting`) keys the engine's traces with it.
pub fn version(kind: Kind) -> Result<String> {
    let yosys_version = crate::cosim::tool_version_of("yosys")?;
    let mut h = Sha256::new();
    let compiled = match kind {
        Kind::Compiled => format!(
            "compiled\n{}\n{}",
            compiled::rustc_version()?,
            compiled::RUSTC_FLAGS.join(" ")
        ),
        Kind::Interpreted => "interpreted".to_string(),
    };
    for part in [
        compiled.as_str(),
        &yosys_version,
        yosys::SCRIPT,
        include_str!("mod.rs"),
        include_str!("ops.rs"),
        include_str!("yosys.rs"),
        include_str!("cells.rs"),
        include_str!("netlist/mod.rs"),
        include_str!("netlist/build.rs"),
        include_str!("order.rs"),
        include_str!("codegen.rs"),
        include_str!("compiled.rs"),
        include_str!("interp.rs"),
    ] {
        h.update((part.len() as u64).to_le_bytes());
        h.update(part.as_bytes());
    }
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

impl Engine {
    /// Builds the model of module `top` of `verilog` (clock input `clock`) with `kind`.
    pub fn new(verilog: &str, top: &str, clock: &str, kind: Kind) -> Result<Engine> {
        match kind {
            Kind::Compiled => Engine::compiled(verilog, top, clock),
            Kind::Interpreted => {
                let (nl, yosys_s) = netlist_of(verilog, top, clock)?;
                let sh = shape_of(&nl);
                Ok(Engine {
                    sim: Box::new(interp::Interp::new(nl)),
                    inputs: ports(&sh.inputs),
                    outputs: ports(&sh.outputs),
                    info: BuildInfo {
                        yosys_s,
                        cells: sh.cells,
                        regs: sh.regs,
                        ..Default::default()
                    },
                })
            }
        }
    }

    fn compiled(verilog: &str, top: &str, clock: &str) -> Result<Engine> {
        let mut h = Sha256::new();
        for part in [
            verilog,
            top,
            clock,
            yosys::SCRIPT,
            include_str!("ops.rs"),
            include_str!("yosys.rs"),
            include_str!("cells.rs"),
            include_str!("netlist/mod.rs"),
            include_str!("netlist/build.rs"),
            include_str!("order.rs"),
            include_str!("codegen.rs"),
            &compiled::rustc_version()?,
            &compiled::RUSTC_FLAGS.join(" "),
        ] {
            h.update((part.len() as u64).to_le_bytes());
            h.update(part.as_bytes());
        }
        let key: String = h
            .finalize()
            .iter()
            .take(12)
            .map(|b| format!("{b:02x}"))
            .collect();
        let (root, var) = compiled::cache_root();
        let dir = root.join(format!("{top}-{key}"));
        let mut info = BuildInfo {
            dir: Some(dir.clone()),
            ..Default::default()
        };
        // 1. A cached library whose content matches the hash stored beside it.
        if let Some(shape) = compiled::cached_shape(&dir) {
            if let Ok(sim) = compiled::Compiled::load(
                &dir.join(compiled::LIB),
                shape.inputs.len(),
                shape.outputs.len(),
            ) {
                info.cached = true;
                return Ok(Engine::of_compiled(sim, shape, info));
            }
        }
        // 2. Built into the cache (a damaged entry is rebuilt over), or, when the cache
        // cannot be written, into a scratch directory, said in one line.
        let (nl, yosys_s) = netlist_of(verilog, top, clock)?;
        info.yosys_s = yosys_s;
        let source = codegen::generate(&nl);
        let shape = shape_of(&nl);
        let t0 = Instant::now();
        let (sim, scratch_dir) = match compiled::build_entry(&source, &shape, &dir) {
            Ok(()) => (
                compiled::Compiled::load(
                    &dir.join(compiled::LIB),
                    shape.inputs.len(),
                    shape.outputs.len(),
                )?,
                None,
            ),
            Err(compiled::EntryError::Cache(why)) => {
                let from = var.map_or(String::new(), |v| format!(" (from {v})"));
                info.cache_note = Some(format!(
                    "engine: the cache {}{from} cannot be used ({why}); the model was built in a temporary directory and is not cached",
                    root.display()
                ));
                info.dir = None;
                let s = scratch()?;
                let d = s.dir.path().join("entry");
                compiled::build_entry(&source, &shape, &d).map_err(|e| e.into_error(&d))?;
                let sim = compiled::Compiled::load(
                    &d.join(compiled::LIB),
                    shape.inputs.len(),
                    shape.outputs.len(),
                )?;
                (sim, Some(s))
            }
            Err(e) => return Err(e.into_error(&dir)),
        };
        // The library stays mapped after its scratch directory goes.
        drop(scratch_dir);
        info.rustc_s = t0.elapsed().as_secs_f64();
        Ok(Engine::of_compiled(sim, shape, info))
    }

    fn of_compiled(sim: compiled::Compiled, shape: Shape, mut info: BuildInfo) -> Engine {
        info.cells = shape.cells;
        info.regs = shape.regs;
        Engine {
            sim: Box::new(sim),
            inputs: ports(&shape.inputs),
            outputs: ports(&shape.outputs),
            info,
        }
    }

    /// The input ports (clock left out), in index order.
    pub fn inputs(&self) -> &[Port] {
        &self.inputs
    }

    /// The output ports, in index order.
    pub fn outputs(&self) -> &[Port] {
        &self.outputs
    }

    /// How the model was built.
    pub fn info(&self) -> &BuildInfo {
        &self.info
    }

    /// Index of input `name`.
    pub fn input_index(&self, name: &str) -> Option<usize> {
        self.inputs.iter().position(|p| p.name == name)
    }

    /// Index of output `name`.
    pub fn output_index(&self, name: &str) -> Option<usize> {
        self.outputs.iter().position(|p| p.name == name)
    }

    /// Drives input `k` (masked to its width) for the next edge.
    pub fn set(&mut self, k: usize, v: u64) {
        self.sim.set(k, v)
    }

    /// Output `k` as of the last [`tick`](Self::tick) or [`eval`](Self::eval).
    pub fn get(&self, k: usize) -> u64 {
        self.sim.get(k)
    }

    /// Re-evaluates the outputs after inputs changed, without a clock edge.
    pub fn eval(&mut self) {
        self.sim.eval()
    }

    /// One rising edge of the clock, then the outputs settle.
    pub fn tick(&mut self) {
        self.sim.tick()
    }

    /// Back to the power-up state, as [`Engine::new`] leaves it, without building or
    /// loading the model again (closed loops that run many short scenarios on one design).
    pub fn restart(&mut self) {
        self.sim.restart();
    }

    /// Runs `rows` (values in the order of `inputs`, which name ports of the model) one row
    /// a cycle, returning the `outputs` after each edge: the co-simulation harness's trace.
    pub fn trace(&mut self, inputs: &[Port], outputs: &[Port], rows: &[Vec<u64>]) -> Result<Trace> {
        let find = |list: &[Port], p: &Port, what: &str| {
            list.iter().position(|q| q.name == p.name).ok_or_else(|| {
                Error::Simulation(format!("the engine's model has no {what} `{}`", p.name))
            })
        };
        let in_map = inputs
            .iter()
            .map(|p| find(&self.inputs, p, "input"))
            .collect::<Result<Vec<_>>>()?;
        let out_map = outputs
            .iter()
            .map(|p| find(&self.outputs, p, "output"))
            .collect::<Result<Vec<_>>>()?;
        let ni = self.inputs.len();
        let mut flat = vec![0u64; rows.len() * ni];
        for (r, row) in rows.iter().enumerate() {
            if row.len() != inputs.len() {
                return Err(Error::Simulation(format!(
                    "stimulus row {r} has {} values for {} inputs",
                    row.len(),
                    inputs.len()
                )));
            }
            for (v, &k) in row.iter().zip(&in_map) {
                flat[r * ni + k] = *v;
            }
        }
        let no = self.outputs.len();
        if ni == 0 {
            let mut t = Vec::with_capacity(rows.len());
            for _ in rows {
                self.tick();
                t.push(out_map.iter().map(|&k| self.get(k)).collect());
            }
            return Ok(t);
        }
        let mut outs = Vec::new();
        self.sim.run(&flat, &mut outs);
        Ok(outs
            .chunks(no.max(1))
            .take(rows.len())
            .map(|row| out_map.iter().map(|&k| row[k]).collect())
            .collect())
    }
}
