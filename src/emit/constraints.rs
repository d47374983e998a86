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
