//! The board top's pinned ports and the Spartan-3A/3AN Starter Kit's known pins
//! (`[board]`, `[board.pins]`).

use super::*;

pub use crate::blocks::captop::hdl::{CAP_TOP_BUSES, CAP_TOP_PINS};

/// The board top's pinned ports for this configuration: (name, None) for a pin,
/// (name, Some(width)) for a bus. These are exactly the ports of `<name>_top` but the
/// parallel bus: on the sinewave top [`TOP_PINS`], the [`QEP_PINS`] with `[qep] enabled`,
/// [`SSI_PINS`] / [`SPI_PINS`] when those slaves are enabled, the [`ABZ_PINS`] with `[abz]
/// enabled` (after the rtl's ports: the wrapper declares them) and each of the
/// [`DESELECT_PINS`] that `[board.pins]` pins. Every one needs a pin.
pub fn board_ports(c: &Config) -> Vec<(&'static str, Option<u32>)> {
    match &c.capacitive {
        Some(k) => CAP_TOP_PINS
            .iter()
            .map(|p| (*p, None))
            .chain(CAP_TOP_BUSES.iter().map(|b| (*b, Some(k.dac_width))))
            .collect(),
        None => {
            use crate::blocks::top::ports::Pin;
            let pins = c
                .board
                .as_ref()
                .map(|b| b.effective_pins())
                .unwrap_or_default();
            // In the wrapper's port order (the port table's).
            crate::blocks::top::hdl::SD_TOP_PORTS
                .iter()
                .filter(|p| match p.pin {
                    Pin::Always => true,
                    Pin::Deselect => pins.contains_key(p.name),
                    Pin::Qep => c.qep.enabled,
                    Pin::Ssi => c.ssi.enabled,
                    Pin::Spi => c.spi.enabled,
                    Pin::DacBus | Pin::Parallel => false,
                })
                .map(|p| (p.name, None))
                .chain(
                    ABZ_PINS
                        .iter()
                        .filter(|_| c.abz.enabled)
                        .map(|p| (*p, None)),
                )
                .collect()
        }
    }
}

/// The Spartan-3A/3AN Starter Kit's pins that sinedec knows with a source: the SPI bus of
/// the analog capture circuit (UG334 chapter 9: SPI_SCK, AD_CONV, AD_DOUT, SPI_MOSI,
/// AMP_CS, AMP_SHDN), the 50 MHz oscillator CLK_50M (E12) and the BTN_SOUTH push button
/// (T15) as reset.
///
/// The header pins for the comparators (`qep_a/b/z` with `[qep] enabled`), the BiSS
/// transceiver and the SSI / SPI slaves are wiring on the kit's headers: give them in
/// `[board.pins]`. The other devices on the kit's SPI bus (DAC_CS, DAC_CLR, SPI_SS_B,
/// SF_CE0; see [`DESELECT_PINS`]) are not filled in either: their locations are not known
/// here. Each SPI slave on the kit has its own data-out line (UG334 chapter 9: AD_DOUT,
/// AMP_DOUT; chapter 10: DAC_OUT), so they cannot contend with the ADC or the amplifier;
/// with the preset, `generate` writes `<name>_top.ut` (BitGen `-g UnusedPin:PullUp`), whose
/// pull-ups on unused pins hold the active-low selects DAC_CS, SPI_SS_B and SF_CE0
/// deasserted. Pin a deselect line in `[board.pins]` to have the top drive it.
pub const STARTER_KIT_PINS: &[(&str, &str)] = &[
    ("clk", "E12"),
    ("rst", "T15"),
    ("adc_sck", "AA20"),
    ("adc_conv", "Y6"),
    ("adc_miso", "D16"),
    ("amp_mosi", "AB14"),
    ("amp_cs", "W6"),
    ("amp_shdn", "W15"),
];

/// Board presets (`board.preset`).
pub const BOARD_PRESETS: &[&str] = &["spartan3an-starter-kit"];

impl BoardConfig {
    /// The preset's pins overridden by `[board.pins]`.
    pub fn effective_pins(&self) -> std::collections::BTreeMap<String, PinValue> {
        let mut m = std::collections::BTreeMap::new();
        if self.preset.as_deref() == Some("spartan3an-starter-kit") {
            for (k, v) in STARTER_KIT_PINS {
                m.insert(k.to_string(), PinValue::One(v.to_string()));
            }
        }
        for (k, v) in &self.pins {
            m.insert(k.clone(), v.clone());
        }
        m
    }

    /// The I/O standard: the configured one, else the preset's (LVCMOS33 on the kit).
    pub fn effective_iostandard(&self) -> Option<String> {
        self.iostandard
            .clone()
            .or_else(|| self.preset.as_ref().map(|_| "LVCMOS33".to_string()))
    }
}

/// The ABZ emulator's outputs (`[abz] enabled`): ports of the `<name>_top` wrapper, which
/// instantiates the emulator next to the rtl (`rtl-templates/top/sinewave_top.v.j2`).
pub const ABZ_PINS: &[&str] = &["abz_a", "abz_b", "abz_z"];

pub use crate::blocks::top::hdl::{DESELECT_PINS, QEP_PINS, SPI_PINS, SSI_PINS, TOP_PINS};
