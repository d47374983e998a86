//! The register map's files (`[registers] enabled`), all from the one table
//! [`crate::blocks::regmap::REGISTERS`] the RTL's decode comes from: `<name>_regs.rdl`
//! (SystemRDL, for PeakRDL and the field's other tools), `<name>_regs.json` and the Markdown
//! table appended to `<name>_params.md`. Written here because no crate writes SystemRDL.
use crate::blocks::regmap::{Access, Field, RegDef, RegmapParams, ADDR_BITS, REGISTERS, RO_FIELDS};
use std::fmt::Write as _;

/// A SystemRDL string literal of `s` (quotes and backslashes escaped).
fn rdl_str(s: &str) -> String {
    format!("\"{}\"", s.replace('\\', "\\\\").replace('"', "\\\""))
}

/// Whether field `f` of `r` is read-only inside a read-write register ([`RO_FIELDS`]).
fn ro_field(r: &RegDef, f: &Field) -> bool {
    RO_FIELDS.contains(&(r.name, f.name))
}

/// The SystemRDL field properties of a register's access: constant read-only (ID,
/// VERSION), live read-only (also a read-only field of a read-write register),
/// write-1-to-clear latched by hardware, a write pulse.
fn field_props(r: &RegDef, f: &Field) -> &'static str {
    if ro_field(r, f) {
        return "sw = r; hw = w;";
    }
    match (r.access, r.name) {
        (Access::Ro, "ID" | "VERSION") => "sw = r; hw = na;",
        (Access::Ro, _) => "sw = r; hw = w;",
        (Access::W1c, _) => "sw = rw; onwrite = woclr; hw = w; hwset;",
        (Access::Wo, _) => "sw = w; hw = r; singlepulse;",
        (Access::Rw, _) => "sw = rw; hw = r;",
    }
}

/// Whether a register's fields carry a reset value in SystemRDL (not the live ones).
fn has_reset(r: &RegDef) -> bool {
    r.access != Access::Ro || matches!(r.name, "ID" | "VERSION")
}

/// `<name>_regs.rdl` for the map `p` (its configured resets): one `addrmap` named `<name>_regs`, after the comment `header`.
pub fn rdl(p: &RegmapParams, name: &str, header: &str) -> String {
    let mut o = String::from(header);
    let _ = writeln!(o, "addrmap {name}_regs {{");
    let _ = writeln!(
        o,
        "    name = {};",
        rdl_str(&format!("{name} register map"))
    );
    let _ = writeln!(
        o,
        "    desc = {};",
        rdl_str(&format!(
            "AXI4-Lite slave of {name}_top ({ADDR_BITS}-bit byte addresses, 32-bit data); docs/registers.md"
        ))
    );
    o.push_str("    default regwidth = 32;\n    default accesswidth = 32;\n");
    for r in REGISTERS {
        let _ = writeln!(o, "    reg {{");
        let _ = writeln!(o, "        name = {};", rdl_str(r.name));
        let _ = writeln!(o, "        desc = {};", rdl_str(r.description));
        for f in r.fields {
            let reset = if has_reset(r) && !ro_field(r, f) {
                let v = (p.reset(r) as u64 >> f.lsb) & crate::blocks::mask(f.width);
                format!(" = 0x{v:x}")
            } else {
                String::new()
            };
            let _ = writeln!(
                o,
                "        field {{ {} desc = {}; }} {}[{}:{}]{reset};",
                field_props(r, f),
                rdl_str(f.description),
                f.name,
                f.lsb + f.width - 1,
                f.lsb
            );
        }
        let _ = writeln!(o, "    }} {} @ 0x{:02x};", r.name, r.address);
    }
    o.push_str("};\n");
    o
}

/// One object of `<name>_regs.json`.
#[derive(serde::Serialize)]
struct JsonReg {
    name: &'static str,
    address: u32,
    width: u32,
    access: &'static str,
    reset: u32,
    description: &'static str,
}

/// `<name>_regs.json`: the registers in address order, each with `name`, `address`,
/// `width`, `access` (`ro`, `rw`, `w1c`, `wo`), `reset` and `description`.
pub fn json(p: &RegmapParams) -> crate::error::Result<String> {
    let v: Vec<JsonReg> = REGISTERS
        .iter()
        .map(|r| JsonReg {
            name: r.name,
            address: r.address,
            width: r.width,
            access: r.access.as_str(),
            reset: p.reset(r),
            description: r.description,
        })
        .collect();
    serde_json::to_string_pretty(&v)
        .map(|s| s + "\n")
        .map_err(|e| crate::error::Error::Export(format!("register map JSON: {e}")))
}

/// The Markdown table of the registers (appended to `<name>_params.md`).
pub fn markdown(p: &RegmapParams) -> String {
    let mut o = String::from(
        "\n## Register map (AXI4-Lite, docs/registers.md)\n\n| address | name | access | reset | description |\n|---|---|---|---|---|\n",
    );
    for r in REGISTERS {
        let _ = writeln!(
            o,
            "| 0x{:02x} | {} | {} | 0x{:08x} | {} |",
            r.address,
            r.name,
            r.access.as_str(),
            p.reset(r),
            r.description.replace('|', "\\|")
        );
    }
    o
}
