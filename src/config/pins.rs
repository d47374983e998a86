//! The board top's pinned ports and the Spartan-3A/3AN Starter Kit's known pins
//! (`[board]`, `[board.pins]`).

use super::params::ErrFn;
use super::*;

pub use crate::blocks::captop::hdl::{CAP_TOP_BUSES, CAP_TOP_PINS};

/// The board top's pinned ports for this configuration: (name, None) for a pin,
/// (name, Some(width)) for a bus. These are exactly the ports of `<name>_top` but the
/// parallel bus: on the sinewave top [`TOP_PINS`], the [`QEP_PINS`] with `[qep] enabled`,
/// [`SSI_PINS`] / [`SPI_PINS`] when those slaves are enabled, the ports of the enabled
/// blocks of the registry (`crate::blocks::registry::enabled_ports`, e.g. `abz_*` with
/// `[abz] enabled`; after the rtl's ports: the wrapper declares them) and each of the
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
                    Pin::Preamp => c.adc.preset == AdcPreset::Ltc1407a1,
                    Pin::AdcB => adc_data_lines(c) == 2,
                    Pin::Deselect => pins.contains_key(p.name),
                    Pin::Qep => c.qep.enabled,
                    Pin::Ssi => c.ssi.enabled,
                    Pin::Spi => c.spi.enabled,
                    Pin::DacBus | Pin::Parallel => false,
                })
                .map(|p| (p.name, None))
                .chain(crate::blocks::registry::enabled_ports(c).map(|p| (p.name, None)))
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

/// Data lines of the configured ADC: 2 when channel 1 has a line of its own (`adc_miso_b`).
/// A chip preset's come from its frame (the one `adc_params` derives from); the board pins
/// are checked before the derivation, so a generic frame's key is read here.
pub fn adc_data_lines(c: &Config) -> u32 {
    match c.adc.preset {
        AdcPreset::Ads8354 => AdcFrame::ADS8354.lines,
        AdcPreset::Ad7380 => AdcFrame::AD7380.lines,
        AdcPreset::Ltc1407a1 => AdcFrame::LTC1407A_1.lines,
        AdcPreset::Generic => c.adc.frame.as_ref().and_then(|f| f.lines).unwrap_or(1),
    }
}

pub use crate::blocks::top::hdl::{
    ADC_B_PINS, DESELECT_PINS, PREAMP_PINS, QEP_PINS, SPI_PINS, SSI_PINS, TOP_PINS,
};

/// The section that makes `port` a port of `<name>_top`, for a port this configuration's
/// top does not have; None for a name that is no port of either top.
fn section_of_port(c: &Config, port: &str) -> Option<&'static str> {
    let sine = "the sinewave board top (a config without [capacitive])";
    let on = |pins: &[&str], section: &'static str| pins.contains(&port).then_some(section);
    if c.capacitive.is_some() {
        if TOP_PINS.contains(&port)
            || PREAMP_PINS.contains(&port)
            || ADC_B_PINS.contains(&port)
            || QEP_PINS.contains(&port)
            || SSI_PINS.contains(&port)
            || SPI_PINS.contains(&port)
            || crate::blocks::registry::port_owner(port).is_some()
            || DESELECT_PINS.contains(&port)
        {
            return Some(sine);
        }
        return None;
    }
    if CAP_TOP_PINS.contains(&port) || CAP_TOP_BUSES.contains(&port) {
        return Some("the capacitive top ([capacitive])");
    }
    on(QEP_PINS, "[qep] enabled = true")
        .or_else(|| on(SSI_PINS, "[ssi] enabled = true"))
        .or_else(|| on(SPI_PINS, "[spi] enabled = true"))
        .or_else(|| crate::blocks::registry::port_owner(port).map(|b| b.section))
}

/// What is wrong with `[board.pins] key = value`, if anything, in one sentence: the port is
/// not in this configuration's top (and which section adds it) or in no top at all; the
/// value's shape does not fit the port (one ball for a pin, `width` balls LSB first for a
/// bus); or a ball is not in the package.
pub(super) fn pin_problem(
    c: &Config,
    ports: &[(&str, Option<u32>)],
    key: &str,
    value: &PinValue,
    balls: &[&str],
    package: &str,
    file: &str,
) -> Option<String> {
    let example = balls.get(balls.len() / 2).copied().unwrap_or("A1");
    let not_a_ball = |p: &str| -> Option<String> {
        (!balls.contains(&p)).then(|| {
            format!(
                "{} is not a ball of the {package} package (its balls are listed in {file}, e.g. \"{example}\")",
                Quoted(&clip(p))
            )
        })
    };
    let key = clip(key);
    match ports.iter().find(|p| p.0 == key) {
        None if key.starts_with("par_") => Some(format!(
            "`{key}` belongs to the parallel bus, which is not pinned (it is meant for logic in the same FPGA)"
        )),
        None => Some(match section_of_port(c, &key) {
            Some(section) => format!(
                "`{key}` is not a port of this configuration's top: it is one with {section}"
            ),
            None => {
                let mut names: Vec<String> = ports
                    .iter()
                    .filter(|(p, _)| !DESELECT_PINS.contains(p))
                    .map(|(p, w)| match w {
                        Some(w) => format!("{p} ({w} pins)"),
                        None => p.to_string(),
                    })
                    .collect();
                if c.capacitive.is_none() {
                    names.extend(DESELECT_PINS.iter().map(|p| format!("{p} (optional)")));
                }
                format!(
                    "the top has no port `{key}`; its ports: {}",
                    names.join(", ")
                )
            }
        }),
        Some((_, None)) => match value {
            PinValue::One(p) => not_a_ball(p),
            PinValue::Bus(ps) => Some(format!(
                "`{key}` is one pin: give one ball such as \"{example}\", not a list ({} given)",
                ps.len()
            )),
        },
        Some((_, Some(w))) => match value {
            PinValue::Bus(ps) if ps.len() == *w as usize => ps.iter().find_map(|p| not_a_ball(p)),
            PinValue::Bus(ps) => Some(format!(
                "`{key}` is a {w}-bit bus: give a list of {w} balls, LSB first ({} given)",
                ps.len()
            )),
            PinValue::One(_) => Some(format!(
                "`{key}` is a {w}-bit bus: give a list of {w} balls, LSB first, not one ball"
            )),
        },
    }
}

/// `[board]`: a known preset, a single-ended I/O standard of the target, and one ball of
/// the package per port of `<name>_top`, none given twice.
pub(super) fn check_board(c: &Config, err: &ErrFn) -> Result<()> {
    let Some(b) = &c.board else {
        return Ok(());
    };
    if let Some(p) = &b.preset {
        if !BOARD_PRESETS.contains(&p.as_str()) {
            return Err(err(
                "board",
                "preset",
                format!(
                    "unknown board preset {}; allowed: {}",
                    Quoted(p),
                    BOARD_PRESETS.join(", ")
                ),
            ));
        }
    }
    let stds = crate::board::iostandards(c.target);
    match b.effective_iostandard() {
        Some(s) if stds.contains(&s.as_str()) => {}
        Some(s) => {
            return Err(err(
                "board",
                "iostandard",
                format!(
                    "`iostandard` = \"{}\" is not a single-ended I/O standard of {}; allowed: {}",
                    clip(&s),
                    crate::board::package(c.target).0,
                    stds.join(", ")
                ),
            ))
        }
        None => {
            return Err(err(
                "board",
                "iostandard",
                format!(
                    "missing: [board] needs `iostandard` when it has no `preset`; allowed: {}",
                    stds.join(", ")
                ),
            ))
        }
    }
    if b.preset.is_some() && (c.target != Target::Spartan3an || c.capacitive.is_some()) {
        return Err(err(
            "board",
            "preset",
            "the spartan3an-starter-kit preset applies to the sinewave top with target = \"spartan3an\"".into(),
        ));
    }
    let pins = b.effective_pins();
    let (package_name, package_file, balls) = crate::board::package(c.target);
    let ports = board_ports(c);
    for (k, v) in &b.pins {
        if let Some(m) = pin_problem(c, &ports, k, v, &balls, package_name, package_file) {
            return Err(err("board.pins", k, m));
        }
    }
    // One ball, one port: a pin given twice, or on a pin the preset already uses.
    let preset_pins = BoardConfig {
        pins: Default::default(),
        ..b.clone()
    }
    .effective_pins();
    let mut owner: std::collections::BTreeMap<&str, &str> = Default::default();
    let in_use: Vec<&str> = ports.iter().map(|p| p.0).collect();
    for (port, v) in pins.iter().filter(|(p, _)| in_use.contains(&p.as_str())) {
        let balls_of: Vec<&str> = match v {
            PinValue::One(x) => vec![x.as_str()],
            PinValue::Bus(xs) => xs.iter().map(String::as_str).collect(),
        };
        for ball in balls_of {
            if let Some(first) = owner.insert(ball, port.as_str()) {
                // Blame the key the user wrote (the later one when both are theirs).
                let (blamed, other) = if b.pins.contains_key(port) {
                    (port.as_str(), first)
                } else {
                    (first, port.as_str())
                };
                let whose = if preset_pins
                    .get(other)
                    .is_some_and(|p| p.one() == Some(ball))
                    && !b.pins.contains_key(other)
                {
                    format!("the preset's pin for `{other}`")
                } else {
                    format!("already given to `{other}`")
                };
                return Err(err(
                    "board.pins",
                    blamed,
                    format!(
                        "`{blamed}`: pin {ball} is {whose}; every port needs a ball of its own"
                    ),
                ));
            }
        }
    }
    let missing: Vec<&str> = ports
        .iter()
        .map(|p| p.0)
        .filter(|p| !pins.contains_key(*p))
        .collect();
    if !missing.is_empty() {
        let preset = if b.preset.is_some() {
            "; the preset fills in the kit's fixed pins, these are wiring on the kit's headers: give them in [board.pins]"
        } else {
            ""
        };
        return Err(err(
            "board",
            "pins",
            format!("pins missing for the board: {} (every port of <name>_top but the parallel bus needs one{preset})", missing.join(", ")),
        ));
    }
    Ok(())
}
