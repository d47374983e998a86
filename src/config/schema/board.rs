//! `[board]` and `[board.pins]`: the pins of `<name>_top` and the board's clock and I/O
//! timing budget.

use super::*;

/// `[board]`: pin locations of `<name>_top`'s ports for the UCF.
#[derive(Clone, Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoardConfig {
    /// Board whose fixed pins are filled in: "spartan3an-starter-kit" (see
    /// [`STARTER_KIT_PINS`]; also writes `<name>_top.ut` with `-g UnusedPin:PullUp`).
    #[serde(default)]
    pub preset: Option<String>,
    /// I/O standard of every pin (e.g. "LVCMOS33"); the preset's when omitted.
    #[serde(default)]
    pub iostandard: Option<String>,
    /// Port name -> package pin (e.g. adc_conv = "Y6"), or a list of pins LSB first for a
    /// bus (exc_sin = ["A1", "B1", ...]). Every port of the top except the parallel bus
    /// (`par_*`, meant for logic in the same FPGA) needs one (see [`board_ports`]); the
    /// [`DESELECT_PINS`] are optional and become ports when pinned. These override the
    /// preset's.
    #[serde(default)]
    pub pins: std::collections::BTreeMap<String, PinValue>,
    /// Oscillator on the `clk` pin, Hz: 50 MHz with the Starter Kit preset, else
    /// `clock.frequency_hz`. When it differs from the system clock, `generate` writes
    /// `<name>_board.v` with a DCM_SP (Spartan-3AN) or ALTPLL (Cyclone III) making it.
    #[serde(default)]
    pub clock_hz: Option<f64>,
    /// Budget for the FPGA's clock-to-output of the ADC outputs, ns (default 6; the
    /// UCF/SDC make the vendor tool verify it). See `crate::board`.
    #[serde(default)]
    pub fpga_clock_to_out_ns: Option<f64>,
    /// Budget for the FPGA's pad set-up at `adc_miso`, ns (default 3; verified likewise).
    #[serde(default)]
    pub fpga_input_setup_ns: Option<f64>,
    /// One board trace between the FPGA and the ADC, ns (default 1: about 15 cm).
    #[serde(default)]
    pub trace_delay_ns: Option<f64>,
}

/// A pin (`"Y6"`) or the pins of a bus, LSB first.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(untagged)]
pub enum PinValue {
    /// One package pin.
    One(String),
    /// One package pin per bit, LSB first.
    Bus(Vec<String>),
}

impl PinValue {
    /// The single pin, if this is one.
    pub fn one(&self) -> Option<&str> {
        match self {
            PinValue::One(s) => Some(s),
            PinValue::Bus(_) => None,
        }
    }
}
