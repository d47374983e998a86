//! Checks across blocks: the board clock and the ADC's I/O timing budget, the CORDIC's
//! throughput against the sample rate, and the target against the design. Errors name
//! the config key to change.

use super::params::ErrFn;
use super::*;

/// The I/O timing budget as configured (`[board]` `fpga_clock_to_out_ns`,
/// `fpga_input_setup_ns`, `trace_delay_ns`), the defaults for the keys not given; the
/// ranges are checked by [`board_timing`].
pub(super) fn io_timing(c: &Config) -> crate::board::IoTiming {
    let mut io = crate::board::IoTiming::DEFAULT;
    if let Some(b) = &c.board {
        io.clock_to_out_ns = b.fpga_clock_to_out_ns.unwrap_or(io.clock_to_out_ns);
        io.input_setup_ns = b.fpga_input_setup_ns.unwrap_or(io.input_setup_ns);
        io.trace_ns = b.trace_delay_ns.unwrap_or(io.trace_ns);
    }
    io
}

/// The board clock and the ADC's I/O timing budget, checked: the synthesizer must reach
/// `clock.frequency_hz` from `board.clock_hz`, and the SCK period must leave room for the
/// ADC round trip (see `crate::board`).
pub(super) fn board_timing(
    c: &Config,
    adc: &AdcParams,
    err: &dyn Fn(&str, &str, String) -> Error,
) -> Result<(Option<crate::board::BoardClock>, crate::board::IoTiming)> {
    use crate::board::STARTER_KIT_CLOCK_HZ;
    let io = io_timing(c);
    let mut board_clock = None;
    if let Some(b) = &c.board {
        for (key, v) in [
            ("fpga_clock_to_out_ns", b.fpga_clock_to_out_ns),
            ("fpga_input_setup_ns", b.fpga_input_setup_ns),
            ("trace_delay_ns", b.trace_delay_ns),
        ] {
            if let Some(v) = v {
                if !(0.0..=100.0).contains(&v) {
                    return Err(err(
                        "board",
                        key,
                        format!("`{key}` = {v} is out of range: allowed 0..=100 ns"),
                    ));
                }
            }
        }
        let kit = b.preset.as_deref() == Some("spartan3an-starter-kit");
        let osc = match (b.clock_hz, kit) {
            (Some(f), _) => {
                if !(1.0e6..=500.0e6).contains(&f) {
                    return Err(err(
                        "board",
                        "clock_hz",
                        format!("`clock_hz` = {f} is out of range: allowed 1e6..=500e6 Hz"),
                    ));
                }
                f
            }
            (None, true) => STARTER_KIT_CLOCK_HZ,
            (None, false) => c.clock.frequency_hz,
        };
        let key = if b.clock_hz.is_some() {
            "clock_hz"
        } else {
            "preset"
        };
        board_clock = Some(
            crate::board::board_clock(c.target, osc, c.clock.frequency_hz)
                .map_err(|m| err("board", key, m.to_string()))?,
        );
    }
    let d = adc.sck_period_clocks;
    let (available, needed) = crate::board::adc_round_trip(
        &io,
        adc.timing.data_valid_ns,
        adc.capture_distance_clocks(),
        adc.clock_hz,
    );
    if available + 1e-9 < needed {
        let t = 1e9 / adc.clock_hz;
        let min_d = ((needed / t) - 1e-9).ceil() as u32;
        // Blame the SCK period when the config sets it, else the board budget or the
        // ADC's data-valid delay it sets (no divider up to 64 clocks past the chip's fits).
        let b = c.board.as_ref();
        let (table, key) = if c.adc.sck_period_clocks.is_some() {
            ("adc", "sck_period_clocks")
        } else if b.is_some_and(|b| b.trace_delay_ns.is_some()) {
            ("board", "trace_delay_ns")
        } else if b.is_some_and(|b| b.fpga_clock_to_out_ns.is_some()) {
            ("board", "fpga_clock_to_out_ns")
        } else if b.is_some_and(|b| b.fpga_input_setup_ns.is_some()) {
            ("board", "fpga_input_setup_ns")
        } else if c
            .adc
            .timing
            .as_ref()
            .is_some_and(|t| t.data_valid_ns.is_some())
        {
            ("adc.timing", "data_valid_ns")
        } else {
            ("adc", "sck_period_clocks")
        };
        return Err(err(
            table,
            key,
            format!(
                "an SCK period of {d} clocks (capture {available:.2} ns after the shifting edge at {:.3} MHz, `clock.frequency_hz`) is shorter than the ADC round trip of {needed:.2} ns: FPGA clock-to-out {:.2} + 2 x board trace {:.2} + the ADC's SCK-to-data delay {:.2} + FPGA input set-up {:.2} ns (board.fpga_clock_to_out_ns, board.trace_delay_ns, board.fpga_input_setup_ns); use an SCK period of at least {min_d} clocks",
                adc.clock_hz / 1e6,
                io.clock_to_out_ns,
                io.trace_ns,
                adc.timing.data_valid_ns,
                io.input_setup_ns,
            ),
        ));
    }
    Ok((board_clock, io))
}

pub(super) fn ceil_log2(v: u32) -> u32 {
    if v <= 1 {
        0
    } else {
        32 - (v - 1).leading_zeros()
    }
}

/// Checks that the CORDIC keeps up with the ADC: the iterative architecture accepts one
/// sample per `cycles` = N·D clocks (D digit clocks per iteration), so clock / cycles must
/// be at least the sample rate.
pub fn check_throughput(
    architecture: Architecture,
    n: u32,
    cycles: u32,
    clock_hz: f64,
    rate: f64,
) -> Result<()> {
    if architecture == Architecture::Unrolled {
        return Ok(());
    }
    if rate * cycles as f64 > clock_hz * (1.0 + 1e-9) {
        let per_iter = (cycles / n.max(1)).max(1);
        return Err(Error::block_params("cordic", format!(
            "the iterative CORDIC accepts one sample per {cycles} clocks (N = {n} iterations of {per_iter} digit clocks): {:.0} samples/s at {:.3} MHz, below the ADC sample rate of {rate:.0} samples/s; use at most {} iterations, a faster clock, a lower sample rate, or architecture = \"unrolled\"",
            clock_hz / cycles as f64,
            clock_hz / 1e6,
            ((clock_hz / rate + 1e-9).floor() as u64) / per_iter as u64
        )));
    }
    Ok(())
}

/// The target must fit the design: the capacitive top is built for the Cyclone III (QSF and
/// SDC), the LTC1407A-1 / LTC6912-1 board top for the Spartan-3AN Starter Kit (UCF).
pub(super) fn check_target(c: &Config, err: &ErrFn) -> Result<()> {
    match (c.target, c.capacitive.is_some(), c.adc.preset) {
        (Target::Spartan3an, true, _) => Err(err(
            "",
            "target",
            "\"spartan3an\" with [capacitive]: the capacitive path's board top is built for the Cyclone III EP3C40F324C8 (Quartus QSF and SDC); set target = \"cyclone3\"".into(),
        )),
        (Target::Cyclone3, false, AdcPreset::Ltc1407a1) => Err(err(
            "",
            "target",
            "\"cyclone3\" with adc.preset = \"ltc1407a-1\": the LTC1407A-1 / LTC6912-1 board top (<name>_top, UCF) is the Spartan-3AN Starter Kit's; set target = \"spartan3an\" for the kit, or another adc.preset (such as \"generic\") for a Cyclone III board of your own".into(),
        )),
        _ => Ok(()),
    }
}

/// The capacitive top has no QEP inputs and no offset, gain or phase correction: `[qep]
/// enabled = true`, or a `[correction]` value other than its default, would only show in the
/// parameter files. Each is rejected at its key; the defaults written out are accepted.
pub(super) fn check_capacitive_scope(c: &Config, err: &ErrFn) -> Result<()> {
    if c.capacitive.is_none() {
        return Ok(());
    }
    if c.qep.enabled {
        return Err(err(
            "qep",
            "enabled",
            "the capacitive top has no QEP inputs (qep_a/b/z) to cross-check: set enabled = false with [capacitive]".into(),
        ));
    }
    let k = &c.correction;
    for (key, differs) in [
        ("mode", k.mode != "static"),
        ("offset_sin", k.offset_sin != 0),
        ("offset_cos", k.offset_cos != 0),
        ("gain_sin", k.gain_sin != 1.0),
        ("gain_cos", k.gain_cos != 1.0),
        ("phase_deg", k.phase_deg != 0.0),
    ] {
        if differs {
            return Err(err(
                "correction",
                key,
                format!("the capacitive top has no offset, gain or phase correction (the filters take the ADC's samples as they are): remove `{key}` with [capacitive]"),
            ));
        }
    }
    Ok(())
}
