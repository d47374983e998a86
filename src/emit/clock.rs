//! The board-level files written when the board's oscillator is not the system clock (see
//! [`crate::board`]): `<name>_board.v` (the synthesizer, reset held until it locks, then
//! `<name>_top`), `<name>_clock.v` (DCM_SP on Spartan-3AN, ALTPLL on Cyclone III) and
//! `<name>_clock_sim.v` (a behavioural model with the same ports). Their text is in
//! `rtl-templates/board/`; this module computes the values.
use super::templates::render;
use crate::board::{BoardClock, SynthKind, WrapperPort, SIM_LOCK_PERIODS};
use crate::error::{Error, Result};
use minijinja::{context, Value};

/// The synthesizer of `clock`, which the board files need.
fn synth_of(clock: &BoardClock) -> Result<crate::board::ClockSynth> {
    clock.synth.ok_or_else(|| {
        Error::Export(
            "the board files need a clock synthesizer (the board clock is the system clock)".into(),
        )
    })
}

/// Values every board template uses.
fn common(name: &str, clock: &BoardClock, synth: &crate::board::ClockSynth) -> Value {
    context! {
        name => name,
        kind => synth.kind.label(),
        m => synth.multiply,
        d => synth.divide,
        out_mhz => format!("{:.3}", synth.out_hz / 1e6),
        osc_mhz => format!("{:.3}", clock.osc_hz / 1e6),
    }
}

/// `<name>_board`: the board clock feeds `<name>_clock`, whose output clocks `top`; reset
/// is held until the synthesizer locks. `ports` are the top's (see
/// [`crate::board::wrapper_ports`]).
pub fn board_verilog(
    name: &str,
    top: &str,
    clock: &BoardClock,
    ports: &[WrapperPort],
) -> Result<String> {
    let synth = synth_of(clock)?;
    let decl: Vec<Value> = ports
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let sep = if i + 1 < ports.len() { "," } else { " " };
            let comment = if p.name == "clk" {
                format!("board oscillator, {:.3} MHz", clock.osc_hz / 1e6)
            } else if p.name == "rst" {
                format!(
                    "reset, active high, held while the clock is not locked; released through 2 flops here, then {top}'s reset synchronizer"
                )
            } else {
                p.comment.clone()
            };
            context! {
                decl => format!(
                    "{} wire {:<7}{:<14}",
                    p.dir,
                    p.range,
                    format!("{}{sep}", p.name)
                ),
                comment => comment,
            }
        })
        .collect();
    let conns: Vec<String> = ports
        .iter()
        .map(|p| match p.name.as_str() {
            "clk" => ".clk(clk_sys)".to_string(),
            "rst" => ".rst(rst_sync[1])".to_string(),
            n => format!(".{n}({n})"),
        })
        .collect();
    // Four connections per line, a comma after every line but the last.
    let chunks: Vec<&[String]> = conns.chunks(4).collect();
    let lines: Vec<String> = chunks
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let end = if i + 1 < chunks.len() { "," } else { "" };
            format!("{}{end}", c.join(", "))
        })
        .collect();
    render(
        "board/board.v.j2",
        context! { top => top, ports => decl, connections => lines, ..common(name, clock, &synth) },
    )
}

/// `<name>_clock` for synthesis: DCM_SP (IBUFG -> CLKFX -> BUFG) or ALTPLL (c0).
pub fn clock_verilog(name: &str, clock: &BoardClock) -> Result<String> {
    let synth = synth_of(clock)?;
    let base = common(name, clock, &synth);
    match synth.kind {
        SynthKind::DcmSp => render(
            "board/clock_dcm_sp.v.j2",
            context! { period_ns => format!("{:.3}", 1e9 / clock.osc_hz), ..base },
        ),
        SynthKind::Altpll => render(
            "board/clock_altpll.v.j2",
            context! { period_ps => (1e12 / clock.osc_hz).round() as u64, ..base },
        ),
    }
}

/// `<name>_clock` for simulation (Icarus; Verilator with --timing): measures the
/// oscillator period and, after [`SIM_LOCK_PERIODS`] periods, toggles clk_sys with the
/// period x D / M and raises locked.
pub fn clock_sim_verilog(name: &str, clock: &BoardClock) -> Result<String> {
    let synth = synth_of(clock)?;
    render(
        "board/clock_sim.v.j2",
        context! { lock => SIM_LOCK_PERIODS, ..common(name, clock, &synth) },
    )
}
