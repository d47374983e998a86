//! Constraint and project files of the board tops: the Xilinx UCF, ISE script and BitGen
//! options, the Quartus QSF, SDC and QPF, and the board-clock wrapper files.
use super::{clock, header, templates, top_name, OutFile};
use crate::config::Loaded;
use crate::error::Result;

/// UCF (pins, clock, I/O timing), ISE project script and, for the kit, BitGen options of the
/// sinewave board top `b`.
pub(super) fn xilinx_files(
    loaded: &Loaded,
    command: &str,
    b: &crate::config::BoardConfig,
) -> Result<Vec<OutFile>> {
    let name = &loaded.config.name;
    let mut files = Vec::new();
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
            capture => capture_comment(loaded),
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
    Ok(files)
}

/// Quartus QSF (device, sources, pins, I/O standard), SDC (clock) and QPF (the project) of
/// the capacitive top.
pub(super) fn cap_constraints(
    loaded: &Loaded,
    command: &str,
) -> Result<Option<(String, String, String)>> {
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
            capture => capture_comment(loaded),
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

/// The capture distance and the round trip it leaves, for the UCF/SDC comments (the
/// figures `check` prints; see `crate::board`).
fn capture_comment(loaded: &Loaded) -> String {
    let adc = &loaded.derived.adc;
    let c = adc.capture_distance_clocks();
    let (available, needed) = crate::board::adc_round_trip(
        &loaded.derived.io_timing,
        adc.timing.data_valid_ns,
        c,
        adc.clock_hz,
    );
    format!(
        "# adc_miso is sampled {c} system clocks ({available:.2} ns) after the clock edge that\n\
         # moves adc_sck to shift the bit out (AdcParams::capture_distance_clocks); the round\n\
         # trip through the chip needs {needed:.2} ns: slack {:.2} ns (`sinedec check`).\n",
        available - needed
    )
}

/// The Verilog files a synthesis project needs and its top module: `<name>_top.v`, plus
/// `<name>_board.v` and `<name>_clock.v` (then the top) when the board clock goes through
/// a synthesizer.
pub(super) fn synthesis_sources(loaded: &Loaded) -> (Vec<String>, String) {
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
pub(super) fn board_files(loaded: &Loaded, command: &str, top: &str) -> Result<Vec<OutFile>> {
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

/// How the SDC and XDC of a top without `[board]` constrain one of its ports (see
/// [`port_timing`] and docs/interfaces.md, "I/O timing of a top without `[board]`").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PortTiming {
    /// The system clock: `create_clock` with the configured period.
    Clock,
    /// An ADC data line: sampled C system clocks after the edge that moves the ADC's
    /// clock ([`crate::blocks::adc::AdcParams::capture_distance_clocks`]), so an input
    /// delay of the round trip ([`crate::board::adc_data_arrival`]) and a multicycle of C.
    AdcData,
    /// An output launched by `clk`: output delay that leaves the clock-to-out budget.
    Out,
    /// An input sampled by `clk` without a synchronizer: input delay that leaves the pad
    /// set-up budget.
    SyncIn,
    /// An asynchronous input that enters through a synchronizer: a false path from it.
    Synchronized,
    /// An output held at a constant level: a false path to it.
    Static,
}

/// One port of a top as its constraints see it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ConstrainedPort {
    /// The port's name.
    pub name: String,
    /// A bus (`name[*]` in `get_ports`).
    pub bus: bool,
    /// An input (else an output).
    pub input: bool,
    /// How it is constrained.
    pub timing: PortTiming,
    /// The interface it belongs to (a comment heading of the files).
    pub interface: &'static str,
}

/// The constraint of the port `name` of a sinewave top (`input`: its direction; `comment`:
/// its one-line comment, which says whether `rst` is asynchronous), and the interface it
/// belongs to; None for a port this table does not know (a port added to the top needs a
/// line here: `tests/flow/flow.rs` checks every port of the port table).
pub fn port_timing(name: &str, input: bool, comment: &str) -> Option<(PortTiming, &'static str)> {
    use PortTiming::*;
    let by_prefix = |p: &str| name.starts_with(p);
    Some(match (name, input) {
        ("clk", true) => (Clock, "System clock"),
        ("rst", true) if comment.to_ascii_lowercase().contains("asynchronous") => {
            (Synchronized, "Reset")
        }
        ("rst", true) => (SyncIn, "Reset"),
        (_, true) if by_prefix("adc_") => (AdcData, "ADC data"),
        (_, false) if by_prefix("adc_") => (Out, "ADC control"),
        (_, false) if by_prefix("amp_") => (Out, "Pre-amplifier set-up"),
        ("biss_ma", true) => (Synchronized, "BiSS-C"),
        ("biss_slo", false) => (Out, "BiSS-C"),
        ("ssi_clk", true) => (Synchronized, "SSI"),
        ("ssi_data", false) => (Out, "SSI"),
        ("enc_sck" | "enc_cs_n", true) => (Synchronized, "SPI slave"),
        ("enc_miso" | "enc_miso_oe", false) => (Out, "SPI slave"),
        (_, true) if by_prefix("qep_") => (Synchronized, "QEP comparator"),
        (_, false) if by_prefix("par_") => (Out, "Parallel bus"),
        // The capture's results (`[capture] enabled`), registered in the block.
        (_, false) if by_prefix("cap_") => (Out, "Synchronous capture"),
        // The register map's AXI4-Lite slave (`[registers] enabled`): synchronous to `clk`,
        // its outputs registered.
        (_, true) if by_prefix("s_axi_") => (SyncIn, "AXI4-Lite register map"),
        (_, false) if by_prefix("s_axi_") => (Out, "AXI4-Lite register map"),
        // Its live flags (an OR of the blocks' flag registers, as FLAGS reads them).
        ("flags", false) => (Out, "AXI4-Lite register map"),
        (_, false) if crate::config::DESELECT_PINS.contains(&name) => (Static, "Deselect lines"),
        // A registered block's port (`crate::blocks::registry`): its outputs are registered,
        // its inputs enter through a synchronizer.
        _ => match crate::blocks::registry::port_owner(name) {
            Some(b) if input => (Synchronized, b.io_group),
            Some(b) => (Out, b.io_group),
            None => return None,
        },
    })
}

/// The ports of the top Verilog `top` (as `generate` writes it) with their constraints;
/// an error names a port [`port_timing`] does not know.
pub fn constrained_ports(top: &str) -> Result<Vec<ConstrainedPort>> {
    crate::board::wrapper_ports(top)
        .into_iter()
        .map(|p| {
            let input = p.dir.trim() == "input";
            let (timing, interface) = port_timing(&p.name, input, &p.comment).ok_or_else(|| {
                crate::error::Error::block_params(
                    "top",
                    format!(
                        "port `{}` has no I/O constraint (src/emit/constraints.rs, port_timing)",
                        p.name
                    ),
                )
            })?;
            Ok(ConstrainedPort {
                bus: !p.range.is_empty(),
                name: p.name,
                input,
                timing,
                interface,
            })
        })
        .collect()
}

/// The numbers of the SDC/XDC of a top without `[board]`, ns (clock cycles for the
/// capture distance), all from the one derivation `check` prints: [`crate::board::IoTiming`]
/// and [`crate::board::adc_data_arrival`] with the capture distance of the ADC controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IoBudget {
    /// The system clock period.
    pub period_ns: f64,
    /// `set_output_delay -max`: the period less the clock-to-out budget.
    pub out_max_ns: f64,
    /// `set_output_delay -min`.
    pub out_min_ns: f64,
    /// `set_input_delay -max` of a synchronous input: the period less the set-up budget.
    pub in_max_ns: f64,
    /// `set_input_delay -min` of a synchronous input.
    pub in_min_ns: f64,
    /// `set_input_delay -max` of an ADC data line: the latest arrival after the edge that
    /// moved the ADC's clock.
    pub adc_max_ns: f64,
    /// `set_input_delay -min` of an ADC data line: the earliest arrival.
    pub adc_min_ns: f64,
    /// The multicycle of the ADC data lines: the capture distance C.
    pub capture_clocks: u32,
}

/// The [`IoBudget`] of the configuration.
pub fn io_budget(loaded: &Loaded) -> IoBudget {
    let io = &loaded.derived.io_timing;
    let adc = &loaded.derived.adc;
    let period_ns = 1e9 / loaded.derived.clock_hz;
    let (adc_min_ns, adc_max_ns) = crate::board::adc_data_arrival(io, adc.timing.data_valid_ns);
    IoBudget {
        period_ns,
        out_max_ns: period_ns - io.clock_to_out_ns,
        out_min_ns: 0.0,
        in_max_ns: period_ns - io.input_setup_ns,
        in_min_ns: 0.0,
        adc_max_ns,
        adc_min_ns,
        capture_clocks: adc.capture_distance_clocks(),
    }
}

/// `<name>_top.sdc` (Quartus, Synopsys) and `<name>_top.xdc` (Vivado) of a top without
/// `[board]`: the clock and the I/O timing of every port of `top` (its Verilog).
pub(super) fn io_files(loaded: &Loaded, command: &str, top: &str) -> Result<Vec<OutFile>> {
    let name = &loaded.config.name;
    let ports = constrained_ports(top)?;
    let b = io_budget(loaded);
    let io = &loaded.derived.io_timing;
    let adc = &loaded.derived.adc;
    let (available, needed) =
        crate::board::adc_round_trip(io, adc.timing.data_valid_ns, b.capture_clocks, adc.clock_hz);
    // Groups of ports with one constraint, in the order of the top's port list.
    let mut groups: Vec<(PortTiming, &'static str, Vec<&ConstrainedPort>)> = Vec::new();
    for p in ports.iter().filter(|p| p.timing != PortTiming::Clock) {
        match groups
            .iter_mut()
            .find(|g| g.0 == p.timing && g.1 == p.interface)
        {
            Some(g) => g.2.push(p),
            None => groups.push((p.timing, p.interface, vec![p])),
        }
    }
    let why = |t: PortTiming, interface: &str| -> String {
        match t {
            PortTiming::AdcData => format!(
                "Sampled {c} system clocks ({available:.2} ns) after the clock edge that moves the\n\
                 # ADC's clock to shift the bit out (AdcParams::capture_distance_clocks): the bit arrives\n\
                 # {min:.2}..{max:.2} ns after that edge (clock-to-out {tco:.2} + 2 x trace {tr:.2} + SCK-to-data\n\
                 # {sdo:.2}), hence the multicycle of {c}; the round trip needs {needed:.2} ns with the\n\
                 # set-up: slack {slack:.2} ns (`sinedec check`, \"ADC round trip\").",
                c = b.capture_clocks,
                min = b.adc_min_ns,
                max = b.adc_max_ns,
                tco = io.clock_to_out_ns,
                tr = io.trace_ns,
                sdo = adc.timing.data_valid_ns,
                slack = available - needed,
            ),
            PortTiming::Out => format!(
                "Launched by clk: the output delay leaves the clock-to-out budget of {:.2} ns.",
                io.clock_to_out_ns
            ),
            PortTiming::SyncIn => format!(
                "Sampled by clk without a synchronizer: the input delay leaves the set-up budget of {:.2} ns.",
                io.input_setup_ns
            ),
            PortTiming::Synchronized if interface == "Reset" => {
                "Asynchronous: asserts at once and releases through the reset synchronizer, so no\n\
                 # path from the pin is timed."
                    .to_string()
            }
            PortTiming::Synchronized => match (&loaded.derived.absolute, interface) {
                // The absolute start's data line: sampled at a fixed distance after the
                // clock edge it answers (the one derivation, `SsiTiming`).
                (Some(a), crate::blocks::absolute::block::IO_GROUP) => {
                    let t = a.timing();
                    format!(
                        "Asynchronous to clk (the encoder answers over its cable): it enters through a\n\
                         # synchronizer (two flops), so no path from the pin is timed. Each bit is sampled\n\
                         # 2H = {} clocks after the abs_clk edge it answers, which needs\n\
                         # {}:\n\
                         # the line's round trip (cable + transceivers, both ways) may take up to {:.1} ns\n\
                         # (`sinedec check`, \"absolute line timing\").",
                        t.capture_clocks(),
                        t.budget_text(),
                        t.max_round_trip_ns()
                    )
                }
                _ => "Asynchronous to clk: it enters through a synchronizer (two flops), so no path from\n\
                      # the pin is timed; `sinedec check` counts the synchronizer in the line timing."
                    .to_string(),
            },
            PortTiming::Static => "Held at a constant level: no path to the pin is timed.".into(),
            PortTiming::Clock => String::new(),
        }
    };
    let kind = |t: PortTiming| match t {
        PortTiming::AdcData => "adc_data",
        PortTiming::Out => "out",
        PortTiming::SyncIn => "sync_in",
        PortTiming::Synchronized => "synchronized",
        PortTiming::Static => "static",
        PortTiming::Clock => "clock",
    };
    let groups: Vec<_> = groups
        .iter()
        .map(|(t, interface, ps)| {
            let names: Vec<String> = ps
                .iter()
                .map(|p| {
                    if p.bus {
                        format!("{}[*]", p.name)
                    } else {
                        p.name.clone()
                    }
                })
                .collect();
            // One Tcl word: braced (no command substitution of `[*]`) unless a plain name.
            let list = match names.as_slice() {
                [one] if !one.contains('[') => one.clone(),
                _ => format!("{{{}}}", names.join(" ")),
            };
            let what = match t {
                PortTiming::Out if *interface != "Parallel bus" => format!("{interface} outputs"),
                PortTiming::Synchronized | PortTiming::SyncIn | PortTiming::AdcData
                    if *interface != "Reset" =>
                {
                    format!("{interface} inputs")
                }
                _ => interface.to_string(),
            };
            minijinja::context! {
                kind => kind(*t),
                what => what,
                why => why(*t, interface),
                ports => ps.iter().map(|p| p.name.clone()).collect::<Vec<_>>(),
                list => list,
            }
        })
        .collect();
    let clock = board_clock(loaded);
    let mut files = Vec::new();
    for (ext, tool, purpose) in [
        (
            "sdc",
            "Quartus TimeQuest, Synopsys",
            "SDC: clock and I/O timing of the top for a board of your own (Quartus, Synopsys).",
        ),
        (
            "xdc",
            "Vivado",
            "XDC: clock and I/O timing of the top for a board of your own (Vivado).",
        ),
    ] {
        let text = templates::render(
            "constraints/top_io.j2",
            minijinja::context! {
                header => header(loaded, command, purpose, "#"),
                top => top_name(loaded),
                tool => tool,
                sdc => ext == "sdc",
                clock_comment => clock_comment(&clock, "#"),
                period_ns => format!("{:.3}", b.period_ns),
                tco_ns => format!("{:.2}", io.clock_to_out_ns),
                tsu_ns => format!("{:.2}", io.input_setup_ns),
                trace_ns => format!("{:.2}", io.trace_ns),
                out_max_ns => format!("{:.3}", b.out_max_ns),
                out_min_ns => format!("{:.3}", b.out_min_ns),
                in_max_ns => format!("{:.3}", b.in_max_ns),
                in_min_ns => format!("{:.3}", b.in_min_ns),
                adc_max_ns => format!("{:.3}", b.adc_max_ns),
                adc_min_ns => format!("{:.3}", b.adc_min_ns),
                capture_clocks => b.capture_clocks,
                groups => groups.clone(),
            },
        )?;
        files.push(OutFile {
            name: format!("{name}_top.{ext}"),
            text,
        });
    }
    Ok(files)
}
