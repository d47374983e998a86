//! Board level: package pins, I/O standards, the board clock (DCM_SP on Spartan-3AN, ALTPLL
//! on Cyclone III) and the SPI ADC's I/O timing budget.
//!
//! `<name>_top` stays vendor-neutral and runs on the system clock. When the oscillator on
//! the board's `clk` pin (`board.clock_hz`; 50 MHz with the Starter Kit preset) differs from
//! `clock.frequency_hz`, `generate` also writes `<name>_board.v`, the module the UCF/QSF
//! belong to:
//!
//! ```text
//!            <name>_board
//!   clk ──► <name>_clock ──clk_sys──┬──────────────► <name>_top.clk
//!  (osc)    (DCM_SP CLKFX       locked                     ▲
//!            or ALTPLL c0)        │    ┌─────────┐         │
//!   rst ─────────────────────────(OR)─►│ 2 flops │─ rst ───┘ (held until locked)
//!                                      └─────────┘ clk_sys
//! ```
//!
//! `<name>_clock.v` instantiates the vendor primitive (for ISE / Quartus) and
//! `<name>_clock_sim.v` is a behavioural model with the same module name and ports for
//! Icarus and Verilator: it measures the oscillator period and, after
//! [`SIM_LOCK_PERIODS`] periods, toggles `clk_sys` at `clk x M / D` and raises `locked`.
//!
//! # Clock synthesis
//!
//! DCM_SP CLKFX = CLKIN x M / D with CLKFX_MULTIPLY M in 2..=32 and CLKFX_DIVIDE D in
//! 1..=32 (the DCM_SP attribute ranges). The ratio with the smallest frequency error is
//! taken (the smallest M on a tie); the result must be within [`MAX_CLOCK_PPM`] of
//! `clock.frequency_hz`: 50 MHz x 8 / 3 = 133.333 MHz for the configured 133.33 MHz is
//! +25 ppm. The ALTPLL's clk0_multiply_by / clk0_divide_by are searched over 1..=64 each.
//!
//! # ADC round trip (LTC1407A-1 or generic SPI ADC)
//!
//! The controller moves the `adc_sck` pin with the edge that shifts a bit out at system
//! clock edge k, and its input register samples `adc_miso` for that bit at edge k + C, with
//! C the capture distance `AdcParams::capture_distance_clocks` (C = D =
//! `adc.sck_period_clocks`: the sample is taken at the edge that launches the next shifting
//! SCK edge). The bit reaches the FPGA's input pin at most `t_co + t_trace + t_sdo + t_trace`
//! after edge k (t_co: the FPGA's clock to output pad; t_trace: one board trace; t_sdo: the
//! chip's SCK-to-SDO delay, LTC1407A-1 t8 = 8 ns) and must be there `t_su` (pad set-up)
//! before edge k + C:
//!
//! ```text
//! C x T  >=  t_co + 2 t_trace + t_sdo + t_su        (T = 1 / clock.frequency_hz)
//! ```
//!
//! At the shipped config: 3 x 7.5 = 22.5 ns >= 6 + 2 x 1 + 8 + 3 = 19 ns (3.5 ns slack).
//! The hold side: the next SCK edge leaves the FPGA at edge k + C, so the sampled bit stays
//! at the pin for t_co + 2 t_trace + the chip's hold (LTC1407A-1 t10 = 2 ns) after the
//! sampling edge. t_co and t_su are budgets ([`IoTiming`], `[board]` keys
//! `fpga_clock_to_out_ns` and `fpga_input_setup_ns`), and the UCF/SDC make the vendor tool
//! verify them: OFFSET OUT (`set_output_delay`) bounds the FPGA's clock-to-out of the ADC
//! outputs by t_co, OFFSET IN (`set_input_delay`) bounds the set-up the FPGA needs at
//! `adc_miso` by t_su. The chip models of `simulate` (`sim::ltc1407a`, `sim::spi_adc`)
//! put the same delays on their pins.
use crate::config::Target;
use crate::error::Error;

/// Largest accepted difference between the synthesized and the configured system clock.
pub const MAX_CLOCK_PPM: f64 = 100.0;
/// Oscillator periods the simulation model of `<name>_clock` waits before `locked`.
pub const SIM_LOCK_PERIODS: u32 = 16;
/// The Spartan-3AN Starter Kit's oscillator on E12 (CLK_50M, UG334).
pub const STARTER_KIT_CLOCK_HZ: f64 = 50.0e6;

const FG484: &str = include_str!("../data/packages/xc3s700an_fg484.txt");
const F324: &str = include_str!("../data/packages/ep3c40_f324.txt");

/// The package of the target: (name, ball list file in the repo, ball names).
pub fn package(target: Target) -> (&'static str, &'static str, Vec<&'static str>) {
    let (name, file, text) = match target {
        Target::Spartan3an => (
            "XC3S700AN FGG484",
            "data/packages/xc3s700an_fg484.txt",
            FG484,
        ),
        Target::Cyclone3 => ("EP3C40F324", "data/packages/ep3c40_f324.txt", F324),
    };
    let balls = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .collect();
    (name, file, balls)
}

/// Single-ended I/O standards accepted in `board.iostandard`, by target: the UCF
/// IOSTANDARD names of Spartan-3A/3AN (UG331, SelectIO chapter) and the Quartus
/// IO_STANDARD names of Cyclone III (Cyclone III Device Handbook, I/O features chapter).
pub fn iostandards(target: Target) -> &'static [&'static str] {
    match target {
        Target::Spartan3an => &[
            "LVTTL",
            "LVCMOS33",
            "LVCMOS25",
            "LVCMOS18",
            "LVCMOS15",
            "LVCMOS12",
            "PCI33_3",
            "PCI66_3",
            "HSTL_I",
            "HSTL_III",
            "HSTL_I_18",
            "HSTL_II_18",
            "HSTL_III_18",
            "SSTL18_I",
            "SSTL18_II",
            "SSTL2_I",
            "SSTL2_II",
            "SSTL3_I",
            "SSTL3_II",
        ],
        Target::Cyclone3 => &[
            "3.3-V LVTTL",
            "3.3-V LVCMOS",
            "3.0-V LVTTL",
            "3.0-V LVCMOS",
            "2.5 V",
            "1.8 V",
            "1.5 V",
            "1.2 V",
            "3.0-V PCI",
            "3.0-V PCI-X",
            "SSTL-2 Class I",
            "SSTL-2 Class II",
            "SSTL-18 Class I",
            "SSTL-18 Class II",
            "1.8-V HSTL Class I",
            "1.8-V HSTL Class II",
            "1.5-V HSTL Class I",
            "1.5-V HSTL Class II",
            "1.2-V HSTL Class I",
            "1.2-V HSTL Class II",
        ],
    }
}

/// Which clock synthesizer `<name>_clock` instantiates.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum SynthKind {
    /// Xilinx DCM_SP, CLKFX output (Spartan-3A/3AN).
    DcmSp,
    /// Altera ALTPLL, c0 output (Cyclone III).
    Altpll,
}

impl SynthKind {
    /// Name used in comments and messages.
    pub fn label(self) -> &'static str {
        match self {
            SynthKind::DcmSp => "DCM_SP CLKFX",
            SynthKind::Altpll => "ALTPLL c0",
        }
    }
}

/// The board clock: the oscillator and, when it differs from the system clock, the
/// synthesizer that makes the system clock from it.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct BoardClock {
    /// Oscillator frequency on the board's `clk` pin, Hz.
    pub osc_hz: f64,
    /// The clock synthesizer; None when the oscillator is the system clock.
    pub synth: Option<ClockSynth>,
}

/// A clock synthesizer setting: out = osc x multiply / divide.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct ClockSynth {
    /// DCM_SP or ALTPLL.
    pub kind: SynthKind,
    /// CLKFX_MULTIPLY / clk0_multiply_by.
    pub multiply: u32,
    /// CLKFX_DIVIDE / clk0_divide_by.
    pub divide: u32,
    /// The synthesized system clock, Hz.
    pub out_hz: f64,
    /// Its difference from `clock.frequency_hz`, ppm.
    pub error_ppm: f64,
}

/// The board clock for an oscillator of `osc_hz` and a system clock of `sys_hz`; an error
/// (a sentence with the numbers) when no synthesizer ratio reaches the system clock.
pub fn board_clock(target: Target, osc_hz: f64, sys_hz: f64) -> crate::error::Result<BoardClock> {
    if ((osc_hz - sys_hz) / sys_hz).abs() * 1e6 <= MAX_CLOCK_PPM {
        return Ok(BoardClock {
            osc_hz,
            synth: None,
        });
    }
    let (kind, m_range, d_range) = match target {
        Target::Spartan3an => (SynthKind::DcmSp, 2..=32u32, 1..=32u32),
        Target::Cyclone3 => (SynthKind::Altpll, 1..=64u32, 1..=64u32),
    };
    let mut best: Option<ClockSynth> = None;
    for m in m_range.clone() {
        for d in d_range.clone() {
            let out = osc_hz * m as f64 / d as f64;
            let ppm = (out - sys_hz) / sys_hz * 1e6;
            if best.is_none_or(|b| ppm.abs() < b.error_ppm.abs() - 1e-9) {
                best = Some(ClockSynth {
                    kind,
                    multiply: m,
                    divide: d,
                    out_hz: out,
                    error_ppm: ppm,
                });
            }
        }
    }
    match best {
        Some(b) if b.error_ppm.abs() <= MAX_CLOCK_PPM => Ok(BoardClock {
            osc_hz,
            synth: Some(b),
        }),
        Some(b) => Err(Error::BoardClock { message: format!(
            "no {} ratio M/D (M {}..={}, D {}..={}) makes clock.frequency_hz = {:.6} MHz from the {:.6} MHz oscillator within {MAX_CLOCK_PPM} ppm (nearest: x {}/{} = {:.6} MHz, {:+.0} ppm); choose a reachable clock.frequency_hz or set board.clock_hz to the oscillator",
            kind.label(),
            m_range.start(),
            m_range.end(),
            d_range.start(),
            d_range.end(),
            sys_hz / 1e6,
            osc_hz / 1e6,
            b.multiply,
            b.divide,
            b.out_hz / 1e6,
            b.error_ppm
        ) }),
        None => Err(Error::BoardClock {
            message: "no clock synthesizer ratio".into(),
        }),
    }
}

/// I/O timing budget of the ADC interface, ns (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct IoTiming {
    /// FPGA clock to output pad (SCK, CONV): the budget the UCF/SDC make the tool verify.
    pub clock_to_out_ns: f64,
    /// FPGA pad set-up before the capturing clock edge (`adc_miso`), likewise verified.
    pub input_setup_ns: f64,
    /// One board trace between the FPGA and the ADC.
    pub trace_ns: f64,
}

impl IoTiming {
    /// Defaults: 6 ns clock-to-out and 3 ns set-up are budgets that the emitted OFFSET /
    /// set_output_delay / set_input_delay constraints hand to ISE or Quartus to verify on
    /// the placed design; 1 ns of trace is about 15 cm of FR-4 stripline.
    pub const DEFAULT: IoTiming = IoTiming {
        clock_to_out_ns: 6.0,
        input_setup_ns: 3.0,
        trace_ns: 1.0,
    };
}

/// The ADC round trip at capture distance C (`AdcParams::capture_distance_clocks`) and
/// `clock_hz`: (available C x T, needed t_co + 2 t_trace + t_sdo + t_su), ns.
pub fn adc_round_trip(
    io: &IoTiming,
    sdo_delay_ns: f64,
    capture_distance_clocks: u32,
    clock_hz: f64,
) -> (f64, f64) {
    let available = capture_distance_clocks as f64 * 1e9 / clock_hz;
    let needed = adc_data_arrival(io, sdo_delay_ns).1 + io.input_setup_ns;
    (available, needed)
}

/// When an ADC data bit reaches the FPGA's input pin after the system clock edge that moves
/// `adc_sck` to shift it out, ns: (earliest, latest). Latest t_co + 2 t_trace + t_sdo (the
/// round trip of [`adc_round_trip`] without the pad set-up); earliest 2 t_trace, taking the
/// FPGA's clock-to-out and the chip's data hold as at least 0. The SDC/XDC of a top without
/// `[board]` give these as the data inputs' `set_input_delay -max` / `-min`.
pub fn adc_data_arrival(io: &IoTiming, sdo_delay_ns: f64) -> (f64, f64) {
    (
        2.0 * io.trace_ns,
        io.clock_to_out_ns + 2.0 * io.trace_ns + sdo_delay_ns,
    )
}

/// Verilog port of a wrapper: (declaration text after the direction, name, comment).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct WrapperPort {
    /// "input " or "output".
    pub dir: String,
    /// "", "[7:0] " or "signed [31:0] ".
    pub range: String,
    /// Port name.
    pub name: String,
    /// The one-line comment.
    pub comment: String,
}

/// The ports of the first module in `text` (the wrappers sinedec writes: one
/// `input|output wire [range] name, // comment` line per port).
pub fn wrapper_ports(text: &str) -> Vec<WrapperPort> {
    let mut out = vec![];
    let mut inside = false;
    for line in text.lines() {
        let t = line.trim();
        if t.starts_with("module ") {
            inside = true;
            continue;
        }
        if !inside {
            continue;
        }
        if t.starts_with(");") {
            break;
        }
        let (decl, comment) = match t.split_once("//") {
            Some((a, b)) => (a.trim(), b.trim()),
            None => (t, ""),
        };
        let mut words = decl.trim_end_matches(',').split_whitespace();
        let dir = match words.next() {
            Some("input") => "input ",
            Some("output") => "output",
            _ => continue,
        };
        let rest: Vec<&str> = words.filter(|w| *w != "wire").collect();
        let (range, name) = match rest.as_slice() {
            [n] => (String::new(), n.to_string()),
            [r, n] => (format!("{r} "), n.to_string()),
            ["signed", r, n] => (format!("signed {r} "), n.to_string()),
            _ => continue,
        };
        out.push(WrapperPort {
            dir: dir.into(),
            range,
            name,
            comment: comment.into(),
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kit_dcm_is_8_over_3() {
        let c = board_clock(Target::Spartan3an, 50e6, 133.33e6).unwrap();
        let s = c.synth.unwrap();
        assert_eq!((s.multiply, s.divide), (8, 3));
        // 50 x 8 / 3 = 133.3333 MHz vs 133.33 MHz: +25.0 ppm.
        assert!((s.error_ppm - 25.0).abs() < 0.1, "{}", s.error_ppm);
    }

    #[test]
    fn same_frequency_needs_no_synth() {
        let c = board_clock(Target::Spartan3an, 50e6, 50e6).unwrap();
        assert!(c.synth.is_none());
    }

    #[test]
    fn unreachable_clock_is_an_error_with_numbers() {
        // 50 MHz x M / D with M <= 32, D <= 32 cannot come within 100 ppm of 123.457 MHz
        // (nearest 50 x 42/17 needs M = 42).
        let e = board_clock(Target::Spartan3an, 50e6, 123.457e6)
            .unwrap_err()
            .to_string();
        assert!(e.contains("DCM_SP") && e.contains("123.457"), "{e}");
    }

    #[test]
    fn packages_have_their_ball_count() {
        assert_eq!(package(Target::Spartan3an).2.len(), 484);
        assert_eq!(package(Target::Cyclone3).2.len(), 324);
        let fg = package(Target::Spartan3an).2;
        for p in ["E12", "T15", "AA20", "Y6", "D16", "AB14", "W6", "W15"] {
            assert!(fg.contains(&p), "{p}");
        }
        for p in ["I1", "O5", "AC1", "A23", "ZZ99"] {
            assert!(!fg.contains(&p), "{p}");
        }
    }

    #[test]
    fn round_trip_of_the_shipped_config() {
        let (a, n) = adc_round_trip(&IoTiming::DEFAULT, 8.0, 3, 133.33e6);
        assert!((a - 22.5006).abs() < 1e-3 && (n - 19.0).abs() < 1e-9);
    }

    #[test]
    fn ports_are_read_back() {
        let t = "module x (\n    input  wire         clk,          // system clock\n    output wire [9:0]  par_position, // pos\n    output wire         par_warning   // warn\n);\n";
        let p = wrapper_ports(t);
        assert_eq!(p.len(), 3);
        assert_eq!(p[1].range, "[9:0] ");
        assert_eq!(p[2].name, "par_warning");
        assert_eq!(p[0].dir, "input ");
        // A signed port (par_velocity) is a port too.
        let t = "module x (\n    output wire signed [31:0] par_velocity, // v\n    output wire par_velocity_valid // s\n);\n";
        let p = wrapper_ports(t);
        assert_eq!(p.len(), 2, "{p:?}");
        assert_eq!(
            (p[0].range.as_str(), p[0].name.as_str()),
            ("signed [31:0] ", "par_velocity")
        );
    }
}
