//! [`build`]: the netlist from Yosys's flattened module, in two passes (every signal and
//! its driver bits first, then every cell's operands), with the memories' and registers'
//! initial values.

use super::*;
use crate::engine::cells::comb_op;
use crate::engine::yosys::{Bit, JCell, JModule};
use crate::error::{Error, Result};
use std::collections::{BTreeMap, HashMap};

fn bad(message: String) -> Error {
    Error::ToolOutput {
        tool: "yosys (engine)".into(),
        message,
    }
}

/// Bits of port `p` of cell `c`.
fn conn<'a>(name: &str, c: &'a JCell, p: &str) -> Result<&'a [Bit]> {
    c.connections
        .get(p)
        .map(|v| v.as_slice())
        .ok_or_else(|| bad(format!("cell {name} ({}) has no port {p}", c.ty)))
}

fn param(name: &str, c: &JCell, p: &str) -> Result<u64> {
    c.parameters
        .get(p)
        .and_then(|v| v.value())
        .ok_or_else(|| bad(format!("cell {name} ({}) lacks parameter {p}", c.ty)))
}

fn param_or(c: &JCell, p: &str, default: u64) -> u64 {
    c.parameters
        .get(p)
        .and_then(|v| v.value())
        .unwrap_or(default)
}

/// Builds operands from bits once every driver is known.
struct Drivers {
    map: HashMap<u64, (SigId, u32)>,
    clock: Vec<u64>,
}

impl Drivers {
    /// Records `sig` as the driver of `bits` (bit i of the signal drives `bits[i]`).
    fn add(&mut self, bits: &[Bit], sig: SigId, what: &str) -> Result<()> {
        for (i, b) in bits.iter().enumerate() {
            if let Bit::Net(n) = b {
                if self.map.insert(*n, (sig, i as u32)).is_some() {
                    return Err(bad(format!("net bit {n} of {what} has two drivers")));
                }
            }
        }
        Ok(())
    }

    fn operand(&self, bits: &[Bit], what: &str) -> Result<Operand> {
        if bits.len() > 64 {
            return Err(bad(format!(
                "{what} is {} bits wide; the engine handles words of up to 64 bits",
                bits.len()
            )));
        }
        let mut o = Operand {
            width: bits.len() as u32,
            ..Default::default()
        };
        for (i, b) in bits.iter().enumerate() {
            let i = i as u32;
            match b {
                Bit::Const(v) => o.konst |= (*v as u64) << i,
                Bit::Net(n) => {
                    if self.clock.contains(n) {
                        return Err(bad(format!(
                            "{what} uses the clock as data; the engine supports the clock \
                             only on flip-flop and memory clock pins"
                        )));
                    }
                    // An undriven bit reads as 0 (x).
                    let Some(&(sig, bit)) = self.map.get(n) else {
                        continue;
                    };
                    match o.chunks.last_mut() {
                        Some(c) if c.sig == sig && c.lo + c.width == bit && c.at + c.width == i => {
                            c.width += 1
                        }
                        _ => o.chunks.push(Chunk {
                            sig,
                            lo: bit,
                            width: 1,
                            at: i,
                        }),
                    }
                }
            }
        }
        Ok(o)
    }
}

/// Reads the flattened module; `clock` is the clock input's name.
pub fn build(m: &JModule, clock: &str) -> Result<Netlist> {
    let mut signals = Vec::new();
    let mut drv = Drivers {
        map: HashMap::new(),
        clock: vec![],
    };
    let mut inputs = Vec::new();
    let mut out_ports = Vec::new();
    for (name, p) in &m.ports {
        match p.direction.as_str() {
            "input" if name == clock => {
                drv.clock = p
                    .bits
                    .iter()
                    .filter_map(|b| if let Bit::Net(n) = b { Some(*n) } else { None })
                    .collect();
            }
            "input" => {
                if p.bits.len() > 64 {
                    return Err(bad(format!("input `{name}` is wider than 64 bits")));
                }
                let id = signals.len();
                signals.push(Signal {
                    width: p.bits.len() as u32,
                    kind: SigKind::Input(inputs.len()),
                });
                drv.add(&p.bits, id, name)?;
                inputs.push((name.clone(), id));
            }
            "output" => out_ports.push((name.clone(), p.bits.clone())),
            d => return Err(bad(format!("port `{name}` has direction {d}"))),
        }
    }
    if drv.clock.len() != 1 {
        return Err(bad(format!("the top has no 1-bit clock input `{clock}`")));
    }
    let clk = drv.clock[0];
    let mem_index: BTreeMap<&str, usize> = m
        .memories
        .keys()
        .enumerate()
        .map(|(i, k)| (k.as_str(), i))
        .collect();
    let check_clock = |name: &str, c: &JCell, enable: bool| -> Result<()> {
        let cb = conn(name, c, "CLK")?;
        if enable && (cb != [Bit::Net(clk)] || param_or(c, "CLK_POLARITY", 1) != 1) {
            return Err(bad(format!(
                "{name} ({}) is not clocked by the rising edge of `{clock}`; the engine \
                 supports one clock",
                c.ty
            )));
        }
        Ok(())
    };
    // Pass 1: create every signal and register its driver bits.
    let (mut combs, mut regs_p, mut writes_p, mut inits) = (vec![], vec![], vec![], vec![]);
    let mut ncomb = 0;
    for (name, c) in &m.cells {
        let ty = c.ty.as_str();
        let out_port = match ty {
            "$dff" | "$dffe" | "$sdff" | "$sdffe" | "$sdffce" => Some("Q"),
            "$memrd" | "$memrd_v2" => Some("DATA"),
            "$memwr" | "$memwr_v2" => {
                check_clock(name, c, true)?;
                writes_p.push((name.as_str(), c));
                None
            }
            "$meminit" | "$meminit_v2" => {
                inits.push((name.as_str(), c));
                None
            }
            _ if comb_op(ty).is_some() => Some("Y"),
            _ => {
                return Err(bad(format!(
                    "cell {name} has type {ty}, which the engine does not support"
                )))
            }
        };
        let Some(port) = out_port else { continue };
        let bits = conn(name, c, port)?;
        if bits.is_empty() || bits.len() > 64 {
            return Err(bad(format!(
                "cell {name} ({ty}) has a {}-bit output; the engine handles 1..=64 bits",
                bits.len()
            )));
        }
        let sig = signals.len();
        let is_reg = port == "Q";
        if is_reg {
            check_clock(name, c, true)?;
        } else if ty.starts_with("$memrd") && param_or(c, "CLK_ENABLE", 0) != 0 {
            return Err(bad(format!(
                "memory read {name} is clocked; only asynchronous reads are supported"
            )));
        }
        signals.push(Signal {
            width: bits.len() as u32,
            kind: if is_reg {
                SigKind::Reg(regs_p.len())
            } else {
                SigKind::Comb(usize::MAX)
            },
        });
        drv.add(bits, sig, name)?;
        let p = Pending { name, c, sig };
        if is_reg {
            regs_p.push(p);
        } else {
            combs.push(p);
            ncomb += 1;
        }
    }
    // Pass 2: operands.
    let mut regs = Vec::with_capacity(regs_p.len());
    for p in &regs_p {
        regs.push(register(&drv, p)?);
    }
    let mut mems: Vec<Memory> = m
        .memories
        .values()
        .map(|jm| Memory {
            width: jm.width,
            offset: jm.start_offset,
            init: vec![0; jm.size as usize],
        })
        .collect();
    if let Some(w) = mems.iter().find(|x| x.width == 0 || x.width > 64) {
        return Err(bad(format!(
            "a memory has {}-bit words; the engine handles 1..=64",
            w.width
        )));
    }
    let mut cells = Vec::with_capacity(ncomb);
    for p in &combs {
        cells.push(comb_cell(&drv, &mem_index, p, signals[p.sig].width)?);
    }
    let mut writes = Vec::new();
    for (name, c) in writes_p {
        writes.push(MemWrite {
            mem: memid(&mem_index, name, c)?,
            addr: drv.operand(conn(name, c, "ADDR")?, name)?,
            data: drv.operand(conn(name, c, "DATA")?, name)?,
            en: drv.operand(conn(name, c, "EN")?, name)?,
            priority: param_or(c, "PORTID", param_or(c, "PRIORITY", 0)),
        });
    }
    writes.sort_by_key(|w| w.priority);
    init_memories(&mut mems, &inits, &mem_index)?;
    init_registers(m, &drv, &signals, &mut regs);
    let outputs = out_ports
        .iter()
        .map(|(n, b)| Ok((n.clone(), drv.operand(b, n)?)))
        .collect::<Result<Vec<_>>>()?;
    let mut nl = Netlist {
        signals,
        inputs,
        outputs,
        cells,
        regs,
        mems,
        writes,
        next_cone: vec![],
        out_cone: vec![],
    };
    crate::engine::order::levelize(&mut nl)?;
    Ok(nl)
}

/// The index (in the module's memories) of the memory a memory cell names by `MEMID`.
fn memid(mem_index: &BTreeMap<&str, usize>, name: &str, c: &JCell) -> Result<usize> {
    let id = match c.parameters.get("MEMID") {
        Some(crate::engine::yosys::Param::Text(t)) => t.trim_end().to_string(),
        _ => return Err(bad(format!("memory cell {name} has no MEMID"))),
    };
    let key = id.strip_prefix('\\').unwrap_or(&id);
    mem_index
        .get(key)
        .or_else(|| mem_index.get(id.as_str()))
        .copied()
        .ok_or_else(|| bad(format!("memory cell {name} names an unknown memory {id}")))
}

/// A cell whose output signal is created in pass 1, its operands read in pass 2.
struct Pending<'a> {
    name: &'a str,
    c: &'a JCell,
    sig: SigId,
}

/// A flip-flop cell's register: data, enable and synchronous reset operands.
fn register(drv: &Drivers, p: &Pending) -> Result<Reg> {
    let (name, c) = (p.name, p.c);
    let d = drv.operand(conn(name, c, "D")?, name)?;
    let en = if matches!(c.ty.as_str(), "$dffe" | "$sdffe" | "$sdffce") {
        Some((
            drv.operand(conn(name, c, "EN")?, name)?,
            param(name, c, "EN_POLARITY")? == 1,
        ))
    } else {
        None
    };
    let srst = if c.ty.starts_with("$sdff") {
        Some((
            drv.operand(conn(name, c, "SRST")?, name)?,
            param(name, c, "SRST_POLARITY")? == 1,
            param(name, c, "SRST_VALUE")?,
        ))
    } else {
        None
    };
    Ok(Reg {
        q: p.sig,
        d,
        en,
        srst,
        ce_over_srst: c.ty == "$sdffce",
        init: 0,
    })
}

/// A combinational cell (or asynchronous memory read) with its operands; `y_width` is its
/// output's width.
fn comb_cell(
    drv: &Drivers,
    mem_index: &BTreeMap<&str, usize>,
    p: &Pending,
    y_width: u32,
) -> Result<Cell> {
    let (name, c) = (p.name, p.c);
    let ty = c.ty.as_str();
    let mut cell = Cell {
        op: Op::Mux,
        a: Operand::default(),
        a_signed: param_or(c, "A_SIGNED", 0) == 1,
        b: Operand::default(),
        b_signed: param_or(c, "B_SIGNED", 0) == 1,
        s: Operand::default(),
        words: vec![],
        out: p.sig,
        y_width,
        name: name.to_string(),
    };
    if ty.starts_with("$memrd") {
        cell.op = Op::MemRead(memid(mem_index, name, c)?);
        cell.a = drv.operand(conn(name, c, "ADDR")?, name)?;
    } else {
        cell.op = comb_op(ty).ok_or_else(|| bad(format!("cell {name}: {ty}")))?;
        cell.a = drv.operand(conn(name, c, "A")?, name)?;
        if let Some(b) = c.connections.get("B") {
            if cell.op == Op::Pmux {
                let w = y_width as usize;
                cell.words = b
                    .chunks(w)
                    .map(|ch| drv.operand(ch, name))
                    .collect::<Result<_>>()?;
            } else {
                cell.b = drv.operand(b, name)?;
            }
        }
        if let Some(s) = c.connections.get("S") {
            cell.s = drv.operand(s, name)?;
        }
    }
    Ok(cell)
}

/// The memories' initial contents from the `$meminit` cells.
fn init_memories(
    mems: &mut [Memory],
    inits: &[(&str, &JCell)],
    mem_index: &BTreeMap<&str, usize>,
) -> Result<()> {
    for &(name, c) in inits {
        let k = memid(mem_index, name, c)?;
        let mem = &mut mems[k];
        let w = mem.width as usize;
        let addr: Vec<Bit> = conn(name, c, "ADDR")?.to_vec();
        let base = addr
            .iter()
            .enumerate()
            .try_fold(0i64, |acc, (i, b)| match b {
                Bit::Const(v) => Some(acc | ((*v as i64) << i)),
                Bit::Net(_) => None,
            })
            .ok_or_else(|| bad(format!("{name}: memory initialised at a variable address")))?;
        let data = conn(name, c, "DATA")?;
        for (j, word) in data.chunks(w).enumerate() {
            let v = word.iter().enumerate().fold(0u64, |acc, (i, b)| {
                acc | ((matches!(b, Bit::Const(true)) as u64) << i)
            });
            let idx = base - mem.offset + j as i64;
            if let Some(slot) = usize::try_from(idx).ok().and_then(|i| mem.init.get_mut(i)) {
                *slot = v;
            }
        }
    }
    Ok(())
}

/// Initial register values from the `init` attributes.
fn init_registers(m: &JModule, drv: &Drivers, signals: &[Signal], regs: &mut [Reg]) {
    for net in m.netnames.values() {
        let Some(bits) = net.attributes.get("init").and_then(|p| p.bits()) else {
            continue;
        };
        for (b, v) in net.bits.iter().zip(bits) {
            if let (Bit::Net(n), true) = (b, v) {
                if let Some(&(sig, bit)) = drv.map.get(n) {
                    if let SigKind::Reg(r) = signals[sig].kind {
                        regs[r].init |= 1 << bit;
                    }
                }
            }
        }
    }
}
