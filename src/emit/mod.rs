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
pub mod templates;
pub mod testbench;
pub mod verilog;

use crate::blocks::core::hdl::CoreRtl;
use crate::blocks::top::hdl::SD_TOP_PORTS;
use crate::blocks::top::ports::{Dir, Pin, TopPort};
use crate::config::{Derived, Loaded};
use crate::cosim::Port;
use crate::error::{Error, Result};
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

/// The wrapper that gives `<name>_core` its exact port widths
/// (`rtl-templates/core/core_wrapper.v.j2`).
fn core_wrapper(loaded: &Loaded, rtl: &str) -> Result<String> {
    let d = &loaded.derived;
    let a = d.adc_width;
    let pad = |s: &str| {
        if a < 16 {
            format!("{{{}'d0, {s}}}", 16 - a)
        } else {
            s.to_string()
        }
    };
    let f = d.fine_bits;
    templates::render(
        "core/core_wrapper.v.j2",
        minijinja::context! {
            name => core_name(loaded),
            rtl => rtl,
            f => f,
            turns => turns_expr(d),
            n => d.iterations,
            ppr => loaded.config.encoder.ppr,
            lat => d.latency_cycles,
            thr => if d.cycles_per_sample == 1 {
                "one sample per clock".to_string()
            } else {
                format!(
                    "one sample per {} clocks (iterative CORDIC; hold samples off while in_ready is low)",
                    d.cycles_per_sample
                )
            },
            am => a - 1,
            pm => d.position_width - 1,
            tm => d.turns_width - 1,
            fm => f - 1,
            mt => d.multiturn_bits,
            qmax => d.quadrants_per_turn - 1,
            qb => d.quadrant_bits - 1,
            sin => pad("in_sin"),
            cos => pad("in_cos"),
        },
    )
}

/// Verilog of `<name>_core` (wrapper first, then the rust-hdl modules), without header.
pub fn core_verilog(loaded: &Loaded) -> Result<String> {
    let rtl_name = format!("{}_rtl", core_name(loaded));
    let mut uut = CoreRtl::new(&loaded.derived);
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let body = verilog::export(&uut, "core", &rtl_name)?;
    Ok(format!("{}\n{body}", core_wrapper(loaded, &rtl_name)?))
}

/// Verilog expression of the turn count from the 32-bit `turns` word (M bits, or 0).
fn turns_expr(d: &crate::config::Derived) -> String {
    if d.multiturn_bits == 0 {
        "1'b0".to_string()
    } else {
        format!("turns[{}:0]", d.multiturn_bits - 1)
    }
}

fn has_top(loaded: &Loaded) -> bool {
    loaded.derived.preamp.is_some() && loaded.config.target == crate::config::Target::Spartan3an
}

/// Name of the board top module.
pub fn top_name(loaded: &Loaded) -> String {
    format!("{}_top", loaded.config.name)
}

/// Ports of `<name>_top` in declaration order as (name, width): the sinewave top's pins
/// ([`crate::config::board_ports`] in the wrapper's order) or the capacitive top's, then the
/// parallel bus; empty when the configuration has no board top. The VCD of `simulate` uses
/// these names and widths.
pub fn top_ports(loaded: &Loaded) -> Vec<(String, u32)> {
    let d = &loaded.derived;
    let one = |p: &str| (p.to_string(), 1u32);
    let mut v: Vec<(String, u32)> = if let Some(k) = &d.capacitive {
        let w = k.config.dac_width;
        crate::blocks::captop::hdl::CAP_TOP_PORTS
            .iter()
            .filter(|p| p.pin != Pin::Parallel)
            .map(|p| match p.pin {
                Pin::DacBus => (p.name.to_string(), w),
                _ => one(p.name),
            })
            .collect()
    } else if has_top(loaded) {
        let used: Vec<&str> = crate::config::board_ports(&loaded.config)
            .iter()
            .map(|p| p.0)
            .collect();
        SD_TOP_PORTS
            .iter()
            .filter(|t| used.contains(&t.name))
            .map(|t| one(t.name))
            .collect()
    } else {
        return Vec::new();
    };
    v.extend([
        one("par_valid"),
        ("par_position".into(), d.position_width),
        ("par_turns".into(), d.turns_width),
        ("par_fine".into(), d.fine_bits),
        one("par_error"),
        one("par_warning"),
    ]);
    v
}

/// The template context of one wrapper port declaration: direction, range (8 columns;
/// `width` for a bus narrowed from the rtl's word), the name with its comma in 14 columns,
/// and the comment.
fn wrapper_port(t: &TopPort, width: Option<u32>) -> minijinja::Value {
    let dir = if t.dir == Dir::Out {
        "output"
    } else {
        "input "
    };
    let range = match width {
        Some(w) => format!("[{}:0]  ", w - 1),
        None => " ".repeat(8),
    };
    minijinja::context! {
        dir => dir,
        range => range,
        name => format!("{:<14}", format!("{},", t.name)),
        comment => t.comment,
    }
}

/// `items` separated by ", " and closed by `end`, on lines that start with `prefix` and
/// stay within 95 columns (an item longer than a line gets a line of its own).
fn wrap_list(items: &[impl AsRef<str>], prefix: &str, end: &str) -> String {
    let mut out = String::new();
    let mut line = String::from(prefix);
    for (i, item) in items.iter().enumerate() {
        let sep = if i + 1 < items.len() { "," } else { end };
        let word = format!(" {}{sep}", item.as_ref());
        if line.len() > prefix.len() && line.len() + word.len() > 95 {
            out.push_str(&line);
            out.push('\n');
            line = String::from(prefix);
        }
        line.push_str(&word);
    }
    out.push_str(&line);
    out
}

/// Verilog of `<name>_top` (sinewave path, LTC1407A-1 preset), without header; None when
/// the configuration has no board top yet (other presets and targets).
///
/// The wrapper declares only the ports the configuration uses (see
/// [`crate::config::board_ports`]): `qep_a/b/z` with `[qep] enabled`, `ssi_*` and `enc_*`
/// with the SSI / SPI slave, and each deselect line (`dac_cs`, `dac_clr`, `spi_ss_b`,
/// `sf_ce0`) only when `[board.pins]` pins it. The rtl's inputs of the ports left out are
/// tied to their idle level (`qep_*` 0, `ssi_clk` 1, `enc_cs_n` 1, `enc_sck` 0) and its
/// outputs left unconnected, so no output without a LOC reaches a package pin.
pub fn top_verilog(loaded: &Loaded) -> Result<Option<String>> {
    let d = &loaded.derived;
    if d.preamp.is_none() || loaded.config.target != crate::config::Target::Spartan3an {
        return Ok(None);
    }
    let name = top_name(loaded);
    let rtl_name = format!("{name}_rtl");
    let mut uut = crate::blocks::top::hdl::TopRtl::new(d)?;
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let body = verilog::export(&uut, "top", &rtl_name)?;
    let f = d.fine_bits;
    let turns = turns_expr(d);
    let used: Vec<&str> = crate::config::board_ports(&loaded.config)
        .iter()
        .map(|p| p.0)
        .collect();
    if let Some(p) = used
        .iter()
        .find(|p| !SD_TOP_PORTS.iter().any(|t| t.name == **p))
    {
        return Err(Error::Export(format!(
            "{name}: the pinned port {p} has no place in the wrapper"
        )));
    }
    // The wrapper's ports and the rtl's connections, from the top's port table: a port the
    // configuration uses is a wrapper port; a left-out input is tied to its idle level, a
    // left-out output left open; the parallel bus goes to the wrapper's wires.
    let mut decl = Vec::new();
    let mut conns: Vec<String> = vec![];
    let mut left_out: Vec<&str> = vec![];
    for t in SD_TOP_PORTS {
        let p = t.name;
        let input = t.dir != Dir::Out;
        if t.pin == Pin::Parallel {
            conns.push(format!(".{p}({})", t.net));
        } else if used.contains(&p) {
            decl.push(wrapper_port(t, None));
            conns.push(format!(".{p}({})", t.net));
        } else if input {
            if t.pin == Pin::Always {
                return Err(Error::Export(format!(
                    "{name}: the required input {p} is not a port of the wrapper"
                )));
            }
            conns.push(format!(".{p}(1'b{})", t.idle));
            left_out.push(p);
        } else {
            conns.push(format!(".{p}()"));
            left_out.push(p);
        }
    }
    let inst = wrap_list(&conns, "       ", "");
    // The ports left out, as comment lines of at most 95 characters (empty: none).
    let left_out_lines = if left_out.is_empty() {
        String::new()
    } else {
        wrap_list(&left_out, "//", ".")
    };
    let wrapper = templates::render(
        "top/sinewave_top.v.j2",
        minijinja::context! {
            name => name,
            left_out => left_out_lines,
            ports => decl,
            rtl_name => rtl_name,
            inst => inst,
            turns => turns,
            f => f,
            rate => format!("{:.0}", d.sample_rate_hz),
            pm => d.position_width - 1,
            tm => d.turns_width - 1,
            fm => f - 1,
            qb => d.quadrant_bits - 1,
        },
    )?;
    Ok(Some(format!(
        "{wrapper}
{body}"
    )))
}

/// Verilog of the capacitive `<name>_top` (with `[capacitive]`), without header.
pub fn cap_top_verilog(loaded: &Loaded) -> Result<Option<String>> {
    let d = &loaded.derived;
    let Some(k) = &d.capacitive else {
        return Ok(None);
    };
    let name = top_name(loaded);
    let rtl_name = format!("{name}_rtl");
    let mut uut = crate::blocks::captop::hdl::CapTopRtl::new(d)?;
    rust_hdl::prelude::Block::connect_all(&mut uut);
    let body = verilog::export(&uut, "top", &rtl_name)?;
    let f = d.fine_bits;
    let turns = turns_expr(d);
    let w = k.config.dac_width;
    let table = crate::blocks::captop::hdl::CAP_TOP_PORTS;
    let decl: Vec<minijinja::Value> = table
        .iter()
        .filter(|t| t.pin != Pin::Parallel)
        .map(|t| wrapper_port(t, (t.pin == Pin::DacBus).then_some(w)))
        .collect();
    let conns: Vec<String> = table
        .iter()
        .map(|t| format!(".{}({})", t.name, t.net))
        .collect();
    let wrapper = templates::render(
        "top/capacitive_top.v.j2",
        minijinja::context! {
            name => name,
            ports => decl,
            inst => wrap_list(&conns, "       ", ""),
            rtl_name => rtl_name,
            turns => turns,
            f => f,
            carrier => format!("{:.0}", k.config.carrier_hz),
            rate => format!("{:.0}", k.sample_rate_hz),
            wm => k.config.dac_width - 1,
            pm => d.position_width - 1,
            tm => d.turns_width - 1,
            fm => f - 1,
            qb => d.quadrant_bits - 1,
        },
    )?;
    Ok(Some(format!("{wrapper}\n{body}")))
}

/// Quartus QSF (device, sources, pins, I/O standard), SDC (clock) and QPF (the project) of
/// the capacitive top.
fn cap_constraints(loaded: &Loaded, command: &str) -> Result<Option<(String, String, String)>> {
    if loaded.derived.capacitive.is_none() {
        return Ok(None);
    }
    let b = loaded.config.board.as_ref();
    let top = top_name(loaded);
    let iostd = b
        .and_then(|b| b.effective_iostandard())
        .unwrap_or_else(|| "3.3-V LVTTL".to_string());
    let clock = board_clock(loaded);
    let qsf_top = match clock.synth {
        Some(_) => format!("{}_board", loaded.config.name),
        None => top.clone(),
    };
    // One entry per pin: a bus gives one per bit, `port[i]`.
    let pins = b.map(|b| b.effective_pins()).unwrap_or_default();
    let mut located = Vec::new();
    for (port, width) in crate::config::board_ports(&loaded.config) {
        match (pins.get(port), width) {
            (Some(crate::config::PinValue::One(p)), None) => {
                located.push(minijinja::context! { port => port, loc => p });
            }
            (Some(crate::config::PinValue::Bus(ps)), Some(_)) => {
                for (i, p) in ps.iter().enumerate() {
                    located.push(minijinja::context! { port => format!("{port}[{i}]"), loc => p });
                }
            }
            _ => {}
        }
    }
    let q = templates::render(
        "constraints/top.qsf.j2",
        minijinja::context! {
            header => header(
                loaded,
                command,
                "QSF: device, top and pins of the board top (Quartus).",
                "#",
            ),
            qsf_top => qsf_top,
            top => top.as_str(),
            rtl => synthesis_sources(loaded).0,
            board => b.is_some(),
            pins => located,
            iostandard => iostd,
        },
    )?;
    // The ADC's I/O delays refer to the clock of the registers that drive and sample it.
    let sys = match clock.synth {
        Some(_) => "[get_clocks {*|clk[0]}]",
        None => "[get_clocks clk]",
    };
    let io = &loaded.derived.io_timing;
    let t_sys = 1e9 / loaded.derived.clock_hz;
    let s = templates::render(
        "constraints/top.sdc.j2",
        minijinja::context! {
            header => header(
                loaded,
                command,
                "SDC: clock of the board top (Quartus TimeQuest).",
                "#",
            ),
            clock_comment => clock_comment(&clock, "#"),
            period_ns => format!("{:.3}", 1e9 / clock.osc_hz),
            synth => clock.synth.is_some(),
            sck_clocks => loaded.derived.adc.sck_period_clocks,
            tco_ns => format!("{:.2}", io.clock_to_out_ns),
            tsu_ns => format!("{:.2}", io.input_setup_ns),
            sys_clock => sys,
            omax_ns => format!("{:.3}", t_sys - io.clock_to_out_ns),
            imax_ns => format!("{:.3}", t_sys - io.input_setup_ns),
        },
    )?;
    let p = templates::render(
        "constraints/top.qpf.j2",
        minijinja::context! {
            header => header(
                loaded,
                command,
                "QPF: the Quartus project (its revision is the QSF).",
                "#",
            ),
            top => top,
        },
    )?;
    Ok(Some((q, s, p)))
}

/// The Verilog files a synthesis project needs and its top module: `<name>_top.v`, plus
/// `<name>_board.v` and `<name>_clock.v` (then the top) when the board clock goes through
/// a synthesizer.
fn synthesis_sources(loaded: &Loaded) -> (Vec<String>, String) {
    let name = &loaded.config.name;
    let top = top_name(loaded);
    let mut rtl = vec![format!("{top}.v")];
    if board_clock(loaded).synth.is_some() && loaded.config.board.is_some() {
        rtl.push(format!("{name}_board.v"));
        rtl.push(format!("{name}_clock.v"));
        return (rtl, format!("{name}_board"));
    }
    (rtl, top)
}

/// The board clock of the configuration (the system clock itself without `[board]`).
fn board_clock(loaded: &Loaded) -> crate::board::BoardClock {
    loaded
        .derived
        .board_clock
        .clone()
        .unwrap_or(crate::board::BoardClock {
            osc_hz: loaded.derived.clock_hz,
            synth: None,
        })
}

/// Comment lines on the clock for a constraint file.
fn clock_comment(clock: &crate::board::BoardClock, c: &str) -> String {
    let synth = clock.synth.as_ref().map(|s| {
        minijinja::context! {
            kind => s.kind.label(),
            multiply => s.multiply,
            divide => s.divide,
            out_mhz => format!("{:.3}", s.out_hz / 1e6),
            out_ns => format!("{:.3}", 1e9 / s.out_hz),
            ppm => format!("{:+.0}", s.error_ppm),
        }
    });
    // Compiled in, every variable given: cannot fail on any input (see `header`).
    templates::render(
        "constraints/clock_comment.j2",
        minijinja::context! {
            c => c,
            osc_mhz => format!("{:.3}", clock.osc_hz / 1e6),
            synth => synth,
        },
    )
    .expect("rtl-templates/constraints/clock_comment.j2 renders")
}

/// `<name>_board.v`, `<name>_clock.v` and `<name>_clock_sim.v` when the board clock needs a
/// synthesizer (see [`crate::board`]); `top` is the text of `<name>_top`'s wrapper.
fn board_files(loaded: &Loaded, command: &str, top: &str) -> Result<Vec<OutFile>> {
    let clock = board_clock(loaded);
    if clock.synth.is_none() || loaded.config.board.is_none() {
        return Ok(vec![]);
    }
    let name = &loaded.config.name;
    let ports = crate::board::wrapper_ports(top);
    let v = |purpose: &str, body: String| {
        format!(
            "{}`timescale 1ns / 1ps\n\n{body}",
            header(loaded, command, purpose, "//")
        )
    };
    Ok(vec![
        OutFile {
            name: format!("{name}_board.v"),
            text: v(
                "Board-level wrapper: clock synthesizer, reset held until locked, board top (Verilog-2001).",
                clock::board_verilog(name, &top_name(loaded), &clock, &ports)?,
            ),
        },
        OutFile {
            name: format!("{name}_clock.v"),
            text: v(
                "Clock synthesizer for synthesis (vendor primitive).",
                clock::clock_verilog(name, &clock)?,
            ),
        },
        OutFile {
            name: format!("{name}_clock_sim.v"),
            text: v(
                "Clock synthesizer, simulation model (Icarus; Verilator with --timing).",
                clock::clock_sim_verilog(name, &clock)?,
            ),
        },
    ])
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
    let top_text = top_verilog(loaded)?;
    let cap_text = cap_top_verilog(loaded)?;
    if let (Some(b), true) = (&loaded.config.board, has_top(loaded)) {
        let top = top_name(loaded);
        let kit = b.preset.as_deref() == Some("spartan3an-starter-kit");
        let ports = crate::config::board_ports(&loaded.config);
        let clock = board_clock(loaded);
        let period = 1e9 / clock.osc_hz;
        let ucf_top = match clock.synth {
            Some(_) => format!("{name}_board"),
            None => top.clone(),
        };
        let open: Vec<&str> = crate::config::DESELECT_PINS
            .iter()
            .copied()
            .filter(|p| !ports.iter().any(|q| q.0 == *p))
            .collect();
        let io = &loaded.derived.io_timing;
        let tig: Vec<&str> = ["biss_ma", "qep_a", "qep_b", "qep_z"]
            .into_iter()
            .filter(|p| ports.iter().any(|q| q.0 == *p))
            .collect();
        let pins = b.effective_pins();
        let located: Vec<_> = ports
            .iter()
            .filter_map(|(p, _)| {
                let loc = pins.get(*p).and_then(|v| v.one())?;
                Some(minijinja::context! { port => *p, loc => loc })
            })
            .collect();
        let u = templates::render(
            "constraints/top.ucf.j2",
            minijinja::context! {
                header => header(
                    loaded,
                    command,
                    "UCF: pins and clock of the board top (Xilinx ISE).",
                    "#",
                ),
                ucf_top => ucf_top,
                top => top.as_str(),
                open => open,
                kit => kit,
                clock_comment => clock_comment(&clock, "#"),
                period_ns => format!("{period:.3}"),
                tco_ns => format!("{:.2}", io.clock_to_out_ns),
                tsu_ns => format!("{:.2}", io.input_setup_ns),
                tig => tig,
                pins => located,
                iostandard => b.effective_iostandard().unwrap_or_default(),
            },
        )?;
        files.push(OutFile {
            name: format!("{name}_top.ucf"),
            text: u,
        });
        // ISE project script: the top (and the clock files under the board wrapper), the UCF.
        let (rtl, synth_top) = synthesis_sources(loaded);
        files.push(OutFile {
            name: format!("{name}_ise.tcl"),
            text: templates::render(
                "constraints/top_ise.tcl.j2",
                minijinja::context! {
                    header => header(
                        loaded,
                        command,
                        "ISE project script (xtclsh): part, sources, UCF, top.",
                        "#",
                    ),
                    name => name,
                    top => top.as_str(),
                    project => top.as_str(),
                    synth_top => synth_top,
                    rtl => rtl,
                    ucf => format!("{top}.ucf"),
                },
            )?,
        });
        if kit {
            // Options only: the explanation is in the UCF header (whether BitGen's -f files
            // take comment lines is not documented in the sources we have).
            let t = templates::render("constraints/top.ut.j2", minijinja::context! {})?;
            files.push(OutFile {
                name: format!("{name}_top.ut"),
                text: t,
            });
        }
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
                    "Board top: pre-amplifier set-up, ADC controller, decoder core (Verilog-2001).",
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
                synth,
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
