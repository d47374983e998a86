//! Emitted files: Verilog with headers, written safely.
//!
//! `generate` returns every file as a string (library first); only [`write_output`] touches
//! the file system, under the output-directory rule of [`output`]: it never overwrites or
//! removes a file sinedec did not write, and replaces a file only once every new file is
//! complete.
pub mod clock;
pub mod flow;
pub mod lint;
pub mod output;
pub mod regmap;
pub mod templates;
pub mod testbench;
pub mod verilog;

mod constraints;
mod wrappers;

pub use wrappers::{cap_top_verilog, core_verilog, top_ports, top_verilog};

use crate::config::{Derived, Loaded};
use crate::cosim::Port;
use crate::error::Result;
use constraints::{board_files, cap_constraints, io_files, synthesis_sources, xilinx_files};
pub use constraints::{
    constrained_ports, io_budget, port_timing, ConstrainedPort, IoBudget, PortTiming,
};
use std::path::Path;

/// Tool version printed in headers.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// The git commit sinedec was built from (short hash, see `build.rs`), or `unknown`.
pub fn commit() -> &'static str {
    match option_env!("VERGEN_GIT_SHA") {
        Some(sha) if !sha.is_empty() && sha.chars().all(|c| c.is_ascii_hexdigit()) => sha,
        _ => "unknown",
    }
}

/// One generated file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OutFile {
    /// File name (no directory).
    pub name: String,
    /// Contents.
    pub text: String,
}

/// Everything `generate` produces for one configuration.
#[derive(Clone, Debug)]
pub struct Generation {
    /// The files, in a fixed order.
    pub files: Vec<OutFile>,
}

/// File header: tool version, config hash, command line, purpose.
///
/// The config name and the command line come from the user and are passed through
/// [`comment_text`], so no character in them can end the comment or the line.
pub fn header(loaded: &Loaded, command: &str, purpose: &str, comment: &str) -> String {
    // The template is compiled in and its variables are all given here, so rendering cannot
    // fail on any input (`templates::tests` renders every template).
    templates::render(
        "header.j2",
        minijinja::context! {
            c => comment,
            version => VERSION,
            commit => commit(),
            config_name => comment_text(&loaded.source_name, comment),
            config_hash => loaded.hash(),
            command => comment_text(command, comment),
            purpose => purpose,
        },
    )
    .expect("rtl-templates/header.j2 renders")
}

/// `text` made safe inside a one-line comment that starts with `comment` (`//`, `#` or
/// `<!--`): a backslash is doubled and a control character (newline, carriage return, tab,
/// escape, ...) or a Unicode line or paragraph separator becomes `\n`, `\r`, `\t` or
/// `\u{..}`, so the comment stays on its line and no line ends in a single backslash (a Tcl
/// comment in a QSF or SDC would continue onto the next line). Inside an HTML comment
/// (`<!--`) the sequences that would end or nest it (`-->`, `--!>`, `<!--`) get `&gt;` or
/// `&lt;` for their angle bracket.
pub fn comment_text(text: &str, comment: &str) -> String {
    let html = comment == "<!--";
    let mut s = String::with_capacity(text.len());
    for ch in text.chars() {
        match ch {
            '\\' => s.push_str("\\\\"),
            '\n' => s.push_str("\\n"),
            '\r' => s.push_str("\\r"),
            '\t' => s.push_str("\\t"),
            c if c.is_control() || c == '\u{2028}' || c == '\u{2029}' => {
                s.push_str(&format!("\\u{{{:x}}}", c as u32))
            }
            c => s.push(c),
        }
    }
    if html {
        s = s
            .replace("-->", "--&gt;")
            .replace("--!>", "--!&gt;")
            .replace("<!--", "&lt;!--");
    }
    s
}

/// Name of the core's top module.
pub fn core_name(loaded: &Loaded) -> String {
    format!("{}_core", loaded.config.name)
}

/// Input ports of `<name>_core` besides `clk`, in stimulus order.
pub fn core_input_ports(d: &Derived) -> Vec<Port> {
    vec![
        Port::new("rst", 1),
        Port::new("in_valid", 1),
        Port::new("in_sin", d.adc_width),
        Port::new("in_cos", d.adc_width),
    ]
}

/// Output ports of `<name>_core`, in trace order (see `CoreOut::row`).
pub fn core_output_ports(d: &Derived) -> Vec<Port> {
    vec![
        Port::new("out_valid", 1),
        Port::new("out_position", d.position_width),
        Port::new("out_turns", d.turns_width),
        Port::new("out_fine", d.fine_bits),
        Port::new("out_error", 1),
        Port::new("out_warning", 1),
    ]
}

pub(crate) fn has_top(loaded: &Loaded) -> bool {
    loaded.config.capacitive.is_none()
}

/// Name of the board top module.
pub fn top_name(loaded: &Loaded) -> String {
    format!("{}_top", loaded.config.name)
}

/// All files for one configuration; `command` is the command line quoted in headers.
pub fn generate(loaded: &Loaded, command: &str) -> Result<Generation> {
    let name = &loaded.config.name;
    let core = core_verilog(loaded)?;
    let v = format!(
        "{}`timescale 1ns / 1ps\n\n{core}",
        header(
            loaded,
            command,
            "QEP-CORDIC encoder decoder core (Verilog-2001).",
            "//"
        )
    );
    let report = templates::render(
        "params.md.j2",
        minijinja::context! {
            header => header(
                loaded,
                command,
                "Derived parameters of the configuration.",
                "<!--"
            )
            .lines()
            .map(|l| format!("{l} -->\n"))
            .collect::<String>(),
            name => name,
            parameters => loaded.derived.describe(),
        },
    )?;
    // The register map's table joins the parameters (`[registers] enabled`).
    let report = match &loaded.derived.registers {
        Some(p) => report + &regmap::markdown(p),
        None => report,
    };
    let tb = format!(
        "{}`timescale 1ns / 1ps\n\n{}",
        header(
            loaded,
            command,
            "Self-checking testbench of the core (expected outputs from the Rust model).",
            "//"
        ),
        testbench::core_testbench(loaded)?
    );
    let mut files = vec![
        OutFile {
            name: format!("{name}_core.v"),
            text: v,
        },
        OutFile {
            name: format!("{name}_core_tb.v"),
            text: tb,
        },
        OutFile {
            name: format!("{name}_params.md"),
            text: report,
        },
    ];
    if let Some(p) = &loaded.derived.registers {
        files.push(OutFile {
            name: format!("{name}_regs.rdl"),
            text: regmap::rdl(
                p,
                name,
                &header(
                    loaded,
                    command,
                    "Register map of the AXI4-Lite slave (SystemRDL 2.0; compile with PeakRDL).",
                    "//",
                ),
            ),
        });
        files.push(OutFile {
            name: format!("{name}_regs.json"),
            text: regmap::json(p)?,
        });
    }
    let top_text = top_verilog(loaded)?;
    let cap_text = cap_top_verilog(loaded)?;
    let xilinx = loaded.config.target == crate::config::Target::Spartan3an;
    if let (Some(b), true) = (&loaded.config.board, has_top(loaded) && xilinx) {
        files.extend(xilinx_files(loaded, command, b)?);
    }
    if let Some(top) = &top_text {
        files.extend(board_files(loaded, command, top)?);
        files.push(OutFile {
            name: format!("{name}_top.v"),
            text: format!(
                "{}`timescale 1ns / 1ps\n\n{top}",
                header(
                    loaded,
                    command,
                    "Board top: ADC controller, correction, decoder core and the enabled outputs (Verilog-2001).",
                    "//"
                )
            ),
        });
        if loaded.config.board.is_none() {
            // No board: the clock and I/O timing for the user's own board.
            files.extend(io_files(loaded, command, top)?);
        }
    }
    if let Some(tb) = top_text
        .as_ref()
        .map(|t| testbench::top_testbench(loaded, t))
        .transpose()?
        .flatten()
    {
        files.push(OutFile {
            name: format!("{name}_top_tb.v"),
            text: format!(
                "{}`timescale 1ns / 1ps\n\n{tb}",
                header(
                    loaded,
                    command,
                    "Self-checking testbench of the top: encoder, timed ADC model, BiSS-C master (Verilog-2001).",
                    "//"
                )
            ),
        });
    }
    if let Some(top) = &cap_text {
        files.extend(board_files(loaded, command, top)?);
        files.push(OutFile {
            name: format!("{name}_top.v"),
            text: format!(
                "{}`timescale 1ns / 1ps\n\n{top}",
                header(
                    loaded,
                    command,
                    "Board top (capacitive path): NCO, ADC controller, filters, decoder core (Verilog-2001).",
                    "//"
                )
            ),
        });
        if let Some((qsf, sdc, qpf)) = cap_constraints(loaded, command)? {
            files.push(OutFile {
                name: format!("{name}_top.qpf"),
                text: qpf,
            });
            files.push(OutFile {
                name: format!("{name}_top.qsf"),
                text: qsf,
            });
            files.push(OutFile {
                name: format!("{name}_top.sdc"),
                text: sdc,
            });
        }
    }
    files.extend(flow_files(
        loaded,
        command,
        &core,
        top_text.as_ref().or(cap_text.as_ref()),
        &files,
    )?);
    Ok(Generation { files })
}

/// The tool-flow files (see [`flow`]): FuseSoC core, instantiation templates, parameters
/// as JSON. `written` are the files generated so far (their names decide the targets).
fn flow_files(
    loaded: &Loaded,
    command: &str,
    core: &str,
    top: Option<&String>,
    written: &[OutFile],
) -> Result<Vec<OutFile>> {
    let name = &loaded.config.name;
    let core_module = core_name(loaded);
    let mut modules = vec![flow::Module {
        name: core_module.clone(),
        what: "decoder core (QEP-CORDIC, quadrant counter)",
        ports: flow::ports_of(core)?,
    }];
    if let Some(t) = top {
        modules.push(flow::Module {
            name: top_name(loaded),
            what: "board top (ADC controller, correction, core, outputs)",
            ports: flow::ports_of(t)?,
        });
    }
    let has = |f: &str| written.iter().any(|o| o.name == f);
    let top_module = top_name(loaded);
    let synth = if has(&format!("{top_module}.ucf")) {
        let (rtl, top) = synthesis_sources(loaded);
        let constraints = vec![(format!("{top_module}.ucf"), "UCF")];
        Some(flow::Synth {
            tool: "ise",
            tool_name: "ISE",
            part: "XC3S700AN-4FGG484",
            top,
            rtl,
            constraints,
        })
    } else if has(&format!("{top_module}.qsf")) {
        let (rtl, top) = synthesis_sources(loaded);
        let constraints = vec![
            (format!("{top_module}.sdc"), "SDC"),
            (format!("{top_module}.qsf"), "tclSource"),
        ];
        Some(flow::Synth {
            tool: "quartus",
            tool_name: "Quartus",
            part: "EP3C40F324C8",
            top,
            rtl,
            constraints,
        })
    } else {
        None
    };
    // A top without [board]: its SDC and XDC for the user's own project.
    let io_constraints: Vec<(String, &'static str)> = [("sdc", "SDC"), ("xdc", "xdc")]
        .into_iter()
        .filter(|(ext, _)| synth.is_none() && has(&format!("{top_module}.{ext}")))
        .map(|(ext, kind)| (format!("{top_module}.{ext}"), kind))
        .collect();
    Ok(vec![
        OutFile {
            name: format!("{name}_sinedec.core"),
            text: flow::fusesoc_core(
                loaded,
                header(
                    loaded,
                    command,
                    "FuseSoC CAPI2 core: simulation and synthesis targets.",
                    "#",
                ),
                &core_module,
                has(&format!("{top_module}_tb.v")).then_some(top_module.as_str()),
                synth,
                &io_constraints,
            )?,
        },
        OutFile {
            name: format!("{name}_inst.v"),
            text: flow::inst_verilog(
                header(
                    loaded,
                    command,
                    "Instantiation templates (not a module: copy from it).",
                    "//",
                ),
                &modules,
            )?,
        },
        OutFile {
            name: format!("{name}_params.json"),
            text: flow::params_json(loaded, command, &modules)?,
        },
        OutFile {
            name: format!("{name}_lint.vlt"),
            text: flow::lint_config(
                header(
                    loaded,
                    command,
                    "Lint configuration for Verilator: the -Wall waivers, each with its reason.",
                    "//",
                ),
                name,
                if top.is_some() {
                    &top_module
                } else {
                    &core_module
                },
            )?,
        },
    ])
}

/// Writes the files into `dir` as `generate` does (see [`output`] and README.md, "Output
/// directory"): never over a file sinedec did not write, each file replaced by a rename only
/// after every new file is complete.
pub fn write_output(generation: &Generation, dir: &Path) -> Result<()> {
    write_output_with(generation, dir, &output::OutputOptions::new("generate"))
}

/// [`write_output`] for another command or with `--force` (see [`output::OutputOptions`]).
pub fn write_output_with(
    generation: &Generation,
    dir: &Path,
    opts: &output::OutputOptions,
) -> Result<()> {
    let files: Vec<(&str, &[u8])> = generation
        .files
        .iter()
        .map(|f| (f.name.as_str(), f.text.as_bytes()))
        .collect();
    output::write_files(dir, &files, opts)
}
