//! The design a closed loop drives: a board top's rust-hdl rtl stepped by hand (the
//! reference) or the compiled engine built from the Verilog that same rtl exports
//! (`crate::engine`; tests/system/engine.rs and tests/system/engine_loop.rs prove them equal cycle for
//! cycle). The loop reads and writes pins by fixed indices into its own pin lists
//! ([`IN_PINS`]/[`OUT_PINS`] for the sinewave top, [`CAP_IN_PINS`]/[`CAP_OUT_PINS`] for the
//! capacitive one), so every engine looks the same to it.
//!
//! The compiled engine needs Yosys (netlist) and rustc (build); a cached library needs
//! neither Yosys nor a build. [`EngineKind::Auto`] (the default) falls back: when rustc is
//! missing the same netlist is interpreted; when Yosys is missing the loop runs on rust-hdl.
//! An engine asked for by name runs or fails. Either way [`Dut::note`] says what ran and
//! why (a fallback, or an engine cache that could not be used), for the command line to
//! print.
use crate::blocks::captop::hdl::CapTopRtl;
use crate::blocks::top::hdl::TopRtl;
use crate::cosim::step::{prepare, tick, NoConvergence};
use crate::cosim::{CosimBlock, CosimError};
use crate::engine::{Engine, Kind};
use crate::error::{Error, Result};

/// Inputs the sinewave loop drives, in index order ([`Dut::set`]).
pub const IN_PINS: [&str; 22] = [
    "rst",
    "adc_miso",
    "biss_ma",
    "qep_a",
    "qep_b",
    "qep_z",
    "ssi_clk",
    "enc_sck",
    "enc_cs_n",
    "adc_miso_b",
    "preset_0",
    "capture_0",
    "s_axi_awaddr_0",
    "s_axi_awvalid_0",
    "s_axi_wdata_0",
    "s_axi_wstrb_0",
    "s_axi_wvalid_0",
    "s_axi_bready_0",
    "s_axi_araddr_0",
    "s_axi_arvalid_0",
    "s_axi_rready_0",
    "abs_data_0",
];
/// How many of the last [`IN_PINS`] are optional (the position reference's `preset`, with
/// `[reference] enabled`, the capture's `capture`, with `[capture] enabled`, the
/// register map's AXI4-Lite inputs, with `[registers] enabled`, and the absolute start's
/// `abs_data`, with `[reference] absolute`; driving a missing one does nothing).
pub const OPTIONAL_IN_PINS: usize = 12;
/// Outputs the closed loop reads, in index order ([`Dut::get`]); the last
/// [`OPTIONAL_OUT_PINS`] exist only in some configurations (the velocity estimator's, with
/// `[velocity] enabled`, the ABZ emulator's, with `[abz] enabled`, and the position
/// reference's, with `[reference] enabled`, the capture's, with `[capture] enabled`, the
/// register map's, with `[registers] enabled`, and the absolute start's, with `[reference]
/// absolute`) and read 0 without them.
pub const OUT_PINS: [&str; 34] = [
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
    "abz_a_0",
    "abz_b_0",
    "abz_z_0",
    "referenced_0",
    "cap_valid_0",
    "cap_qc_0",
    "cap_fine_0",
    "cap_turns_0",
    "cap_age_0",
    "cap_velocity_0",
    "s_axi_awready_0",
    "s_axi_wready_0",
    "s_axi_bvalid_0",
    "s_axi_arready_0",
    "s_axi_rdata_0",
    "s_axi_rvalid_0",
    "flags_0",
    "abs_clk_0",
];
/// Inputs the capacitive loop drives, in index order.
pub const CAP_IN_PINS: [&str; 3] = ["rst", "adc_miso", "biss_ma"];
/// Outputs the capacitive loop reads, in index order.
pub const CAP_OUT_PINS: [&str; 11] = [
    "adc_conv",
    "adc_sck",
    "exc_strobe",
    "exc_sin",
    "exc_cos",
    "par_valid",
    "par_qc",
    "par_fine",
    "par_turns",
    "par_error",
    "par_warning",
];
/// How many of the last [`OUT_PINS`] are optional (read 0 when the top lacks them).
pub const OPTIONAL_OUT_PINS: usize = 20;

/// Which engine simulates the top (`simulate --engine`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EngineKind {
    /// The default: the compiled engine, else the interpreter (no rustc), else rust-hdl (no
    /// Yosys), the fallback said in [`Dut::note`].
    #[default]
    Auto,
    /// rust-hdl's own simulation (the reference).
    RustHdl,
    /// The compiled engine (Yosys + rustc, cached), asked for by name: no fallback.
    Compiled,
    /// The engine's interpreter of the same netlist (Yosys only; the fallback without rustc).
    Interpreted,
}

impl EngineKind {
    /// The name `simulate` prints.
    pub fn name(self) -> &'static str {
        match self {
            EngineKind::RustHdl => "rust-hdl",
            EngineKind::Compiled | EngineKind::Auto => "compiled",
            EngineKind::Interpreted => "interpreter",
        }
    }
}

/// A board top rtl a closed loop can drive by pin name.
pub trait BoardTop: CosimBlock {
    /// The rtl for the derived parameters.
    fn build(d: &crate::config::Derived) -> Result<Self>;
    /// Top module name of its Verilog for the engine (also the engine cache's prefix).
    const MODULE: &'static str;
    /// Drives input `name` (`.next`).
    fn set_pin(&mut self, name: &str, v: u64);
    /// Port `name`'s value.
    fn pin(&self, name: &str) -> u64;
    /// The inputs' present values in co-simulation order.
    fn inputs_now(&self) -> Vec<u64>;
}

macro_rules! board_top_impl {
    ($ty:ty, $module:literal) => {
        impl BoardTop for $ty {
            fn build(d: &crate::config::Derived) -> Result<Self> {
                <$ty>::new(d)
            }
            const MODULE: &'static str = $module;
            fn set_pin(&mut self, name: &str, v: u64) {
                self.set_input(name, v);
            }
            fn pin(&self, name: &str) -> u64 {
                self.output(name).unwrap_or(0)
            }
            fn inputs_now(&self) -> Vec<u64> {
                self.input_row()
            }
        }
    };
}
board_top_impl!(TopRtl, "sinedec_top_rtl");
board_top_impl!(CapTopRtl, "sinedec_cap_top_rtl");

/// The engine's model of the top and the index maps of its ports.
pub struct EngineTop {
    e: Box<Engine>,
    /// Engine input index of each loop input pin (None: an optional pin the configuration
    /// lacks).
    ins: Vec<Option<usize>>,
    /// Engine output index of each loop output pin (None: an optional pin the
    /// configuration lacks).
    outs: Vec<Option<usize>>,
    /// Present value of every engine input (the engine has no read-back).
    shadow: Vec<u64>,
    /// Engine input index of each of the rtl's co-simulation inputs (port-table order).
    row_ins: Vec<Option<usize>>,
    /// Engine output index of each of the rtl's co-simulation outputs.
    row_outs: Vec<Option<usize>>,
    /// The rtl's co-simulation inputs (idle levels for ports the engine lacks).
    idle: Vec<u64>,
}

enum Imp<B> {
    Rtl(Box<B>),
    Engine(Box<EngineTop>),
}

/// The design under a closed loop: the rtl `B` on rust-hdl or on the engine.
pub struct Dut<B> {
    imp: Imp<B>,
    in_pins: &'static [&'static str],
    out_pins: &'static [&'static str],
    used: EngineKind,
    note: Option<String>,
}

/// `Some(tool)` when `e` says that program could not be launched.
fn missing_tool(e: &Error) -> Option<&str> {
    match e {
        Error::Tool(CosimError::ToolMissing { tool, .. }) => Some(tool.as_str()),
        _ => None,
    }
}

impl<B: BoardTop> Dut<B> {
    /// The top for `d` on `kind` (falling back as the module doc says), driven through
    /// `in_pins` and read through `out_pins`.
    pub fn new(
        d: &crate::config::Derived,
        kind: EngineKind,
        in_pins: &'static [&'static str],
        out_pins: &'static [&'static str],
    ) -> Result<Dut<B>> {
        let mut rtl = Box::new(B::build(d)?);
        let rust_hdl = |rtl, note| Dut {
            imp: Imp::Rtl(rtl),
            in_pins,
            out_pins,
            used: EngineKind::RustHdl,
            note,
        };
        if kind == EngineKind::RustHdl {
            return Ok(rust_hdl(rtl, None));
        }
        // The same instance gives the Verilog and the co-simulation port lists.
        rust_hdl::prelude::Block::connect_all(rtl.as_mut());
        let verilog = crate::emit::verilog::export(rtl.as_ref(), "top", B::MODULE)?;
        let mut used = match kind {
            EngineKind::Auto => EngineKind::Compiled,
            k => k,
        };
        let mut note = None;
        let first = match kind {
            EngineKind::Interpreted => Kind::Interpreted,
            _ => Kind::Compiled,
        };
        let mut built = Engine::new(&verilog, B::MODULE, "clk", first);
        let fallback = kind == EngineKind::Auto;
        if let Err(e) = &built {
            if let Some(tool) = missing_tool(e).filter(|t| fallback && t.starts_with("rustc")) {
                note = Some(format!(
                    "engine: interpreter instead of the compiled engine, because {tool} could not be run (install Rust to compile the model; the interpreter gives the same results, slower)"
                ));
                used = EngineKind::Interpreted;
                built = Engine::new(&verilog, B::MODULE, "clk", Kind::Interpreted);
            }
        }
        let e = match built {
            Ok(e) => {
                if let Some(n) = &e.info().cache_note {
                    note.get_or_insert_with(|| n.clone());
                }
                e
            }
            Err(e) => match missing_tool(&e).filter(|t| fallback && t.starts_with("yosys")) {
                Some(_) => {
                    let why = note.map_or(String::new(), |_| " (and rustc)".to_string());
                    let n = format!(
                        "engine: rust-hdl instead of the {} engine, because yosys could not be run{why} (apt-get install yosys for the fast engines; rust-hdl gives the same results, about 100x slower)",
                        kind.name()
                    );
                    return Ok(rust_hdl(rtl, Some(n)));
                }
                None => return Err(e),
            },
        };
        let missing = |what: &str, p: &str| {
            Error::Simulation(format!("the engine's top has no {what} `{p}`"))
        };
        let optional_in = &IN_PINS[IN_PINS.len() - OPTIONAL_IN_PINS..];
        let ins = in_pins
            .iter()
            .map(|p| match e.input_index(p) {
                None if !optional_in.contains(p) => Err(missing("input", p)),
                i => Ok(i),
            })
            .collect::<Result<Vec<_>>>()?;
        let optional = &OUT_PINS[OUT_PINS.len() - OPTIONAL_OUT_PINS..];
        let outs = out_pins
            .iter()
            .map(|p| match e.output_index(p) {
                None if !optional.contains(p) => Err(missing("output", p)),
                i => Ok(i),
            })
            .collect::<Result<Vec<_>>>()?;
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
        let idle = rtl.inputs_now();
        let shadow = vec![0; e.inputs().len()];
        Ok(Dut {
            imp: Imp::Engine(Box::new(EngineTop {
                e: Box::new(e),
                ins,
                outs,
                shadow,
                row_ins,
                row_outs,
                idle,
            })),
            in_pins,
            out_pins,
            used,
            note,
        })
    }

    /// The engine that runs (after any fallback).
    pub fn engine(&self) -> EngineKind {
        self.used
    }

    /// Why the engine that runs is not the one asked for (one line), if it is not.
    pub fn note(&self) -> Option<&str> {
        self.note.as_deref()
    }

    /// Connects the design and settles its outputs; call once.
    pub fn start(&mut self) -> std::result::Result<(), NoConvergence> {
        match &mut self.imp {
            Imp::Rtl(t) => prepare(t.as_mut()),
            Imp::Engine(c) => {
                c.e.eval();
                Ok(())
            }
        }
    }

    /// Drives input pin `k` for the next edge.
    pub fn set(&mut self, k: usize, v: u64) {
        match &mut self.imp {
            Imp::Rtl(t) => t.set_pin(self.in_pins[k], v),
            Imp::Engine(c) => {
                if let Some(i) = c.ins[k] {
                    c.shadow[i] = v;
                    c.e.set(i, v);
                }
            }
        }
    }

    /// Output pin `k` (as of the last edge).
    pub fn get(&self, k: usize) -> u64 {
        match &self.imp {
            Imp::Rtl(t) => t.pin(self.out_pins[k]),
            Imp::Engine(c) => c.outs[k].map_or(0, |i| c.e.get(i)),
        }
    }

    /// One clock edge.
    pub fn tick(&mut self) -> std::result::Result<(), NoConvergence> {
        match &mut self.imp {
            Imp::Rtl(t) => tick(t.as_mut()),
            Imp::Engine(c) => {
                c.e.tick();
                Ok(())
            }
        }
    }

    /// The inputs applied at the last edge, in the rtl's co-simulation order.
    pub fn input_row(&self) -> Vec<u64> {
        match &self.imp {
            Imp::Rtl(t) => t.inputs_now(),
            Imp::Engine(c) => c
                .row_ins
                .iter()
                .zip(&c.idle)
                .map(|(i, idle)| i.map_or(*idle, |i| c.shadow[i]))
                .collect(),
        }
    }

    /// The outputs in the rtl's co-simulation order.
    pub fn sample(&self) -> Vec<u64> {
        match &self.imp {
            Imp::Rtl(t) => t.sample(),
            Imp::Engine(c) => c
                .row_outs
                .iter()
                .map(|i| i.map_or(0, |i| c.e.get(i)))
                .collect(),
        }
    }

    /// The rust-hdl top, when that is the engine.
    pub fn rtl(&self) -> Option<&B> {
        match &self.imp {
            Imp::Rtl(t) => Some(t),
            Imp::Engine(_) => None,
        }
    }
}

#[cfg(test)]
mod registry_tests {
    /// Every pinned port of a registered block is driven or read by the closed loop as the
    /// rtl's optional input or output `<name>_0` (`IN_PINS`, `OUT_PINS`, by its direction),
    /// and every optional pin there is a velocity output, a capture or register-map port
    /// (wide fabric ports, not pins) or a registered block's port.
    #[test]
    fn the_loop_reads_every_registered_block_port() {
        use crate::blocks::registry::BLOCKS;
        use crate::blocks::top::ports::Dir;
        let optional = &super::OUT_PINS[super::OUT_PINS.len() - super::OPTIONAL_OUT_PINS..];
        let optional_in = &super::IN_PINS[super::IN_PINS.len() - super::OPTIONAL_IN_PINS..];
        for b in BLOCKS {
            for p in b.ports {
                let rtl = format!("{}_0", p.name);
                let list = if p.dir == Dir::In {
                    optional_in
                } else {
                    optional
                };
                assert!(list.contains(&rtl.as_str()), "{}: {rtl}", b.key);
            }
        }
        let pins = optional.iter().chain(optional_in);
        let fabric = |o: &str| {
            ["par_velocity", "cap_", "s_axi_", "flags"]
                .iter()
                .any(|p| o.starts_with(p))
        };
        for o in pins.filter(|o| !fabric(o)) {
            let name = o.trim_end_matches("_0");
            assert!(
                crate::blocks::registry::port_owner(name).is_some(),
                "{o} has no registered block"
            );
        }
    }
}
