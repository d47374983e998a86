//! Tool-flow files written next to the Verilog: a FuseSoC CAPI2 core
//! (`<name>_sinedec.core`), instantiation templates (`<name>_inst.v`) and a machine-readable
//! list of every derived parameter and port (`<name>_params.json`). Their text is in
//! `rtl-templates/flow/`.
//!
//! The ports are read back from the wrappers sinedec writes (the first module of the core
//! and top texts: one `input|output wire [signed] [h:0] name, // comment` line per port), so
//! these files cannot disagree with the Verilog.
use super::templates::render;
use crate::config::Loaded;
use crate::error::{Error, Result};
use minijinja::{context, Value};
use serde::Serialize;

/// One port of a wrapper module.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct PortDecl {
    /// Port name.
    pub name: String,
    /// `input` or `output`.
    pub direction: String,
    /// Width in bits.
    pub width: u32,
    /// Declared `signed` (two's complement).
    pub signed: bool,
    /// The port's one-line comment.
    pub comment: String,
}

/// The ports of the first module in `text` (a wrapper sinedec writes).
pub fn ports_of(text: &str) -> Result<Vec<PortDecl>> {
    let mut out = Vec::new();
    let mut inside = false;
    for line in text.lines() {
        let t = line.trim();
        if !inside {
            inside = t.starts_with("module ");
            continue;
        }
        if t.starts_with(");") {
            return Ok(out);
        }
        let (decl, comment) = t.split_once("//").unwrap_or((t, ""));
        let words: Vec<&str> = decl
            .trim()
            .trim_end_matches(',')
            .split_whitespace()
            .filter(|w| *w != "wire")
            .collect();
        let Some((&direction, rest)) = words.split_first() else {
            continue;
        };
        if direction != "input" && direction != "output" {
            continue;
        }
        let signed = rest.first() == Some(&"signed");
        let rest = if signed { &rest[1..] } else { rest };
        let (width, name) = match rest {
            [n] => (1, *n),
            [r, n] => {
                let hi = r
                    .strip_prefix('[')
                    .and_then(|r| r.strip_suffix(":0]"))
                    .and_then(|h| h.parse::<u32>().ok())
                    .ok_or_else(|| Error::Export(format!("port range {r} of {n}")))?;
                (hi + 1, *n)
            }
            _ => return Err(Error::Export(format!("unexpected port line `{t}`"))),
        };
        out.push(PortDecl {
            name: name.to_string(),
            direction: direction.to_string(),
            width,
            signed,
            comment: comment.trim().to_string(),
        });
    }
    Err(Error::Export("no end of the port list".into()))
}

/// One module for the instantiation templates and the JSON: name, what it is, ports.
pub struct Module<'a> {
    /// Module name.
    pub name: String,
    /// One-line description.
    pub what: &'a str,
    /// Its ports.
    pub ports: Vec<PortDecl>,
}

/// `<name>_lint.vlt`: the Verilator configuration that waives `-Wall`'s style findings on
/// the generated files, each rule with its reason; `top` is the module its usage line
/// names. The default warnings need no waiver: the emitted Verilog passes
/// `verilator --lint-only` as it is (see [`super::lint`]).
pub fn lint_config(header: String, name: &str, top: &str) -> Result<String> {
    render(
        "flow/lint.vlt.j2",
        context! {
            header => header,
            name => name,
            top => top,
            files => format!("*{name}_*.v"),
        },
    )
}

/// `<name>_inst.v`: an instantiation template of each module.
pub fn inst_verilog(header: String, modules: &[Module]) -> Result<String> {
    let ms: Vec<Value> = modules
        .iter()
        .map(|m| {
            let w = m.ports.iter().map(|p| p.name.len()).max().unwrap_or(0);
            let ports: Vec<Value> = m
                .ports
                .iter()
                .map(|p| {
                    let kind = match (p.width, p.signed) {
                        (1, _) => "1 bit".to_string(),
                        (n, false) => format!("[{}:0]", n - 1),
                        (n, true) => format!("[{}:0] signed", n - 1),
                    };
                    context! {
                        pad_name => format!("{:<w$}", p.name),
                        pad_conn => p.name.as_str(),
                        gap => " ".repeat(w - p.name.len()),
                        dir => p.direction.as_str(),
                        kind => kind,
                        comment => p.comment.as_str(),
                    }
                })
                .collect();
            context! { name => m.name.as_str(), what => m.what, ports => ports }
        })
        .collect();
    render(
        "flow/inst.v.j2",
        context! { header => header, modules => ms },
    )
}

/// `<name>_params.json`: what a header says (generator, config, hash, command line), the
/// modules' ports and every derived parameter.
pub fn params_json(loaded: &Loaded, command: &str, modules: &[Module]) -> Result<String> {
    #[derive(Serialize)]
    struct Ports<'a> {
        module: &'a str,
        ports: &'a [PortDecl],
    }
    #[derive(Serialize)]
    struct Doc<'a> {
        generator: String,
        config: &'a str,
        config_hash: String,
        command: &'a str,
        modules: Vec<Ports<'a>>,
        derived: &'a crate::config::Derived,
    }
    let doc = Doc {
        generator: format!("sinedec {} (commit {})", super::VERSION, super::commit()),
        config: &loaded.source_name,
        config_hash: loaded.hash(),
        command,
        modules: modules
            .iter()
            .map(|m| Ports {
                module: &m.name,
                ports: &m.ports,
            })
            .collect(),
        derived: &loaded.derived,
    };
    let mut s = serde_json::to_string_pretty(&doc).map_err(|source| Error::Json {
        what: "parameter file".into(),
        source,
    })?;
    s.push('\n');
    Ok(s)
}

/// The synthesis target of the FuseSoC core: tool, part, top, files.
pub struct Synth {
    /// edalize tool: `ise` or `quartus`.
    pub tool: &'static str,
    /// Vendor tool name for the comments.
    pub tool_name: &'static str,
    /// The part, for the comments.
    pub part: &'static str,
    /// Top module (`<name>_board` with a clock synthesizer, else `<name>_top`).
    pub top: String,
    /// Verilog files of the synthesis target.
    pub rtl: Vec<String>,
    /// Constraint files with their FuseSoC file types.
    pub constraints: Vec<(String, &'static str)>,
}

/// `<name>_sinedec.core`: FuseSoC CAPI2 core with `sim` (Icarus, Verilator), `sim_top`
/// when `top_tb` names the top whose testbench `<top>_tb.v` is written, and, when there is
/// a board top, `synth` (ISE or Quartus) targets; `io_constraints` (the SDC and XDC of a
/// top without `[board]`, with their FuseSoC file types) become the `top_constraints`
/// fileset.
pub fn fusesoc_core(
    loaded: &Loaded,
    header: String,
    core: &str,
    top_tb: Option<&str>,
    synth: Option<Synth>,
    io_constraints: &[(String, &'static str)],
) -> Result<String> {
    let name = &loaded.config.name;
    let synth = synth.map(|s| {
        let constraints: Vec<Value> = s
            .constraints
            .iter()
            .map(|(n, k)| context! { name => n, kind => *k })
            .collect();
        context! {
            tool => s.tool,
            tool_name => s.tool_name,
            part => s.part,
            top => s.top,
            rtl => s.rtl,
            constraints => constraints,
        }
    });
    render(
        "flow/sinedec.core.j2",
        context! {
            header => header,
            vlnv => format!("sinedec:generated:{name}:{}", super::VERSION),
            description => format!("{name}: sinewave encoder decoder generated by sinedec"),
            core => core,
            top => top_tb,
            synth => synth,
            io_constraints => io_constraints
                .iter()
                .map(|(n, k)| context! { name => n, kind => *k })
                .collect::<Vec<Value>>(),
        },
    )
}
