//! `[biss]`: the BiSS-C slave's keys (schema and defaults) and its parameters built from the
//! config, the control channel's identification registers included (docs/biss_control.md).
//! Errors name the key to change.

use super::params::ErrFn;
use super::*;
use crate::blocks::biss::regs::BissIdent;

/// `[biss]`: the BiSS-C slave of `<name>_top` (pins `biss_ma`, `biss_slo`).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BissConfig {
    /// Single-turn data bits: the most significant bits of `out_position` (default: all of
    /// them, at most 32).
    pub position_bits: Option<u32>,
    /// Multi-turn bits sent ahead of the position (default 0; at most encoder.multiturn_bits
    /// and position_bits + multiturn_bits <= 32).
    pub multiturn_bits: Option<u32>,
    /// Gray-code the data word (default false).
    pub gray: Option<bool>,
    /// MA periods of Ack before Start (1..=64, default 1).
    pub ack_periods: Option<u32>,
    /// Timeout in microseconds (default 20).
    pub timeout_us: Option<f64>,
    /// BiSS C control channel: register access over CDM/CDS (default false).
    pub control: Option<bool>,
    /// Device ID, registers 0x78..0x7D: up to 6 printable ASCII characters (default
    /// "SINDEC"; needs control = true, as do the four keys below).
    pub device_id: Option<String>,
    /// Manufacturer ID, registers 0x7E..0x7F: up to 2 printable ASCII characters (default "SD").
    pub manufacturer_id: Option<String>,
    /// Profile ID, registers 0x42..0x43, 0..=0xFFFF (default 0).
    pub profile_id: Option<u32>,
    /// Serial number, registers 0x44..0x47, 0..=0xFFFFFFFF (default 0).
    pub serial_number: Option<u64>,
    /// First EDS bank, register 0x41, 0..=255 (default 0: no EDS).
    pub eds_bank: Option<u32>,
}

/// BiSS-C parameters: data bits default to the whole single-turn position (at most 32).
pub(super) fn biss_params(c: &Config, position_width: u32, err: &ErrFn) -> Result<BissParams> {
    let b = &c.biss;
    let pb = b.position_bits.unwrap_or(position_width.min(32));
    if pb == 0 || pb > position_width.min(32) {
        return Err(err(
            "biss",
            "position_bits",
            format!(
                "{pb} bits: allowed 1..={} (out_position has {position_width} bits; BiSS words hold 32)",
                position_width.min(32)
            ),
        ));
    }
    let mb = b.multiturn_bits.unwrap_or(0);
    if mb > c.encoder.multiturn_bits {
        return Err(err(
            "biss",
            "multiturn_bits",
            format!(
                "{mb} bits: at most encoder.multiturn_bits ({}), the turns the decoder counts",
                c.encoder.multiturn_bits
            ),
        ));
    }
    if pb + mb > 32 {
        let pos = if b.position_bits.is_some() {
            format!("position_bits = {pb}")
        } else {
            format!("position_bits (default {pb}: all of out_position)")
        };
        return Err(err(
            "biss",
            if b.multiturn_bits.is_some() {
                "multiturn_bits"
            } else {
                "position_bits"
            },
            format!(
                "the data word would be {mb} + {pb} = {} bits (multiturn_bits = {mb}, {pos}), more than the 32 a BiSS word holds; use at most {} multi-turn bits, or set position_bits to at most {}",
                mb + pb,
                32u32.saturating_sub(pb),
                32 - mb
            ),
        ));
    }
    let mut p = BissParams::new(pb, mb, c.clock.frequency_hz)
        .map_err(|m| err("biss", "position_bits", m.to_string()))?;
    p.gray = b.gray.unwrap_or(false);
    p.ack_periods = b.ack_periods.unwrap_or(1);
    if let Some(t) = b.timeout_us {
        p.set_timeout_us(t)
            .map_err(|m| err("biss", "timeout_us", m.to_string()))?;
    }
    p.validate()
        .map_err(|m| err("biss", "ack_periods", m.to_string()))?;
    p.control = control_ident(b, err)?;
    Ok(p)
}

/// The control channel's identification registers with `control = true` (None otherwise;
/// the ID keys without the channel are an error, since they would have no effect).
fn control_ident(b: &BissConfig, err: &ErrFn) -> Result<Option<BissIdent>> {
    let id_keys = [
        ("device_id", b.device_id.is_some()),
        ("manufacturer_id", b.manufacturer_id.is_some()),
        ("profile_id", b.profile_id.is_some()),
        ("serial_number", b.serial_number.is_some()),
        ("eds_bank", b.eds_bank.is_some()),
    ];
    if !b.control.unwrap_or(false) {
        if let Some((k, _)) = id_keys.iter().find(|(_, set)| *set) {
            return Err(err(
                "biss",
                k,
                format!(
                    "{k} is a register of the control channel: set control = true or remove {k}"
                ),
            ));
        }
        return Ok(None);
    }
    let mut id = BissIdent::default();
    if let Some(s) = &b.device_id {
        id.device_id = BissIdent::ascii_id::<6>(s).ok_or_else(|| {
            err(
                "biss",
                "device_id",
                format!("{s:?}: allowed up to 6 printable ASCII characters"),
            )
        })?;
    }
    if let Some(s) = &b.manufacturer_id {
        id.manufacturer_id = BissIdent::ascii_id::<2>(s).ok_or_else(|| {
            err(
                "biss",
                "manufacturer_id",
                format!("{s:?}: allowed up to 2 printable ASCII characters"),
            )
        })?;
    }
    if let Some(v) = b.profile_id {
        id.profile_id = u16::try_from(v).map_err(|_| {
            err(
                "biss",
                "profile_id",
                format!("{v}: allowed 0..=65535 (0xFFFF)"),
            )
        })?;
    }
    if let Some(v) = b.serial_number {
        id.serial_number = u32::try_from(v).map_err(|_| {
            err(
                "biss",
                "serial_number",
                format!("{v}: allowed 0..=4294967295 (0xFFFFFFFF)"),
            )
        })?;
    }
    if let Some(v) = b.eds_bank {
        id.eds_bank = u8::try_from(v)
            .map_err(|_| err("biss", "eds_bank", format!("{v}: allowed 0..=255")))?;
    }
    Ok(Some(id))
}
