//! The word-level netlist the engine runs: Yosys's flattened cells (src/engine/yosys.rs)
//! regrouped from bits into words, the combinational cells put in evaluation order, the
//! registers and memories as the state.
//!
//! ```text
//!  inputs ──┐                         ┌──► next-state cone ──► registers, memory writes
//!           ├──► combinational cells ─┤        (evaluated before the rising edge)
//!  state ───┘    (topological order)  └──► output cone ──► outputs
//!                                              (evaluated after it)
//! ```
//!
//! Every signal is one word of 1..=64 bits: an input port, a register's output or a
//! combinational cell's output. A cell's operand is assembled from slices of signals and
//! constant bits ([`Operand`]). Only one clock is supported (every flip-flop and memory
//! write on its rising edge, no asynchronous reset): rust-hdl designs have one clock.
use super::cells::comb_op;
use super::yosys::{Bit, JCell, JModule};
use crate::error::{Error, Result};
use std::collections::{BTreeMap, HashMap};

/// Index of a signal in [`Netlist::signals`].
pub type SigId = usize;

/// What drives a signal.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SigKind {
    /// Input port number `k` (clock left out).
    Input(usize),
    /// Register number `k`.
    Reg(usize),
    /// Combinational cell number `k` (in [`Netlist::cells`]).
    Comb(usize),
}

/// One word.
#[derive(Clone, Debug)]
pub struct Signal {
    /// Width in bits, 1..=64.
    pub width: u32,
    /// Its driver.
    pub kind: SigKind,
}

/// `width` bits of signal `sig` from bit `lo`, placed at bit `at` of an operand.
#[derive(Clone, Copy, Debug)]
pub struct Chunk {
    /// The signal.
    pub sig: SigId,
    /// Its first bit taken.
    pub lo: u32,
    /// Bits taken.
    pub width: u32,
    /// Where they go in the operand.
    pub at: u32,
}

/// A cell input: slices of signals OR-ed with constant bits.
#[derive(Clone, Debug, Default)]
pub struct Operand {
    /// Width in bits (at most 64).
    pub width: u32,
    /// The slices.
    pub chunks: Vec<Chunk>,
    /// The constant bits (0 where a chunk is).
    pub konst: u64,
}

/// The operation of a combinational cell; the number is the `op` of src/engine/ops.rs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Op {
    /// `ops::unary`.
    Unary(u8),
    /// `ops::arith`.
    Arith(u8),
    /// `ops::compare`.
    Compare(u8),
    /// `ops::logic`.
    Logic(u8),
    /// `ops::shift`.
    Shift(u8),
    /// `s ? b : a`.
    Mux,
    /// `ops::pmux` over `words`.
    Pmux,
    /// Asynchronous read of memory `k` at address `a`.
    MemRead(usize),
}

/// A combinational cell.
#[derive(Clone, Debug)]
pub struct Cell {
    /// Operation.
    pub op: Op,
    /// Operand A (and its signedness).
    pub a: Operand,
    /// A is signed.
    pub a_signed: bool,
    /// Operand B.
    pub b: Operand,
    /// B is signed.
    pub b_signed: bool,
    /// The select of `$mux`/`$pmux`.
    pub s: Operand,
    /// The words of `$pmux`'s B, one per select bit.
    pub words: Vec<Operand>,
    /// The output signal.
    pub out: SigId,
    /// Output width.
    pub y_width: u32,
    /// Yosys cell name (for messages).
    pub name: String,
}

/// A register: `q` loads `d` on the rising edge, with an optional enable and synchronous
/// reset.
#[derive(Clone, Debug)]
pub struct Reg {
    /// Its output signal.
    pub q: SigId,
    /// Data.
    pub d: Operand,
    /// Enable and its active level.
    pub en: Option<(Operand, bool)>,
    /// Synchronous reset, its active level and value.
    pub srst: Option<(Operand, bool, u64)>,
    /// The reset acts only when enabled (`$sdffce`).
    pub ce_over_srst: bool,
    /// Initial value.
    pub init: u64,
}

/// A memory: `size` words of `width` bits; address `offset` is word 0.
#[derive(Clone, Debug)]
pub struct Memory {
    /// Word width (1..=64).
    pub width: u32,
    /// Address of word 0.
    pub offset: i64,
    /// Initial contents.
    pub init: Vec<u64>,
}

/// A synchronous memory write: on the rising edge the bits of `en` of word `addr` take
/// `data`'s.
#[derive(Clone, Debug)]
pub struct MemWrite {
    /// The memory.
    pub mem: usize,
    /// Address.
    pub addr: Operand,
    /// Data.
    pub data: Operand,
    /// Per-bit enable.
    pub en: Operand,
    /// Priority (higher writes last).
    pub priority: u64,
}

/// The whole design.
#[derive(Clone, Debug)]
pub struct Netlist {
    /// Every word.
    pub signals: Vec<Signal>,
    /// Input ports (clock left out): name and signal.
    pub inputs: Vec<(String, SigId)>,
    /// Output ports: name and operand.
    pub outputs: Vec<(String, Operand)>,
    /// Combinational cells in evaluation order.
    pub cells: Vec<Cell>,
    /// Registers.
    pub regs: Vec<Reg>,
    /// Memories.
    pub mems: Vec<Memory>,
    /// Memory writes in priority order.
    pub writes: Vec<MemWrite>,
    /// Cells (indices in `cells`, in order) the registers' and writes' operands need.
    pub next_cone: Vec<usize>,
    /// Cells the outputs need.
    pub out_cone: Vec<usize>,
}

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
    let add_driver = |drv: &mut Drivers, bits: &[Bit], sig: SigId, what: &str| -> Result<()> {
        for (i, b) in bits.iter().enumerate() {
            if let Bit::Net(n) = b {
                if drv.map.insert(*n, (sig, i as u32)).is_some() {
                    return Err(bad(format!("net bit {n} of {what} has two drivers")));
                }
            }
        }
        Ok(())
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
                add_driver(&mut drv, &p.bits, id, name)?;
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
    let memid = |name: &str, c: &JCell| -> Result<usize> {
        let id = match c.parameters.get("MEMID") {
            Some(super::yosys::Param::Text(t)) => t.trim_end().to_string(),
            _ => return Err(bad(format!("memory cell {name} has no MEMID"))),
        };
        let key = id.strip_prefix('\\').unwrap_or(&id);
        mem_index
            .get(key)
            .or_else(|| mem_index.get(id.as_str()))
            .copied()
            .ok_or_else(|| bad(format!("memory cell {name} names an unknown memory {id}")))
    };
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
    struct Pending<'a> {
        name: &'a str,
        c: &'a JCell,
        sig: SigId,
    }
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
        add_driver(&mut drv, bits, sig, name)?;
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
        regs.push(Reg {
            q: p.sig,
            d,
            en,
            srst,
            ce_over_srst: c.ty == "$sdffce",
            init: 0,
        });
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
        let (name, c) = (p.name, p.c);
        let ty = c.ty.as_str();
        let y_width = signals[p.sig].width;
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
            cell.op = Op::MemRead(memid(name, c)?);
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
        cells.push(cell);
    }
    let mut writes = Vec::new();
    for (name, c) in writes_p {
        writes.push(MemWrite {
            mem: memid(name, c)?,
            addr: drv.operand(conn(name, c, "ADDR")?, name)?,
            data: drv.operand(conn(name, c, "DATA")?, name)?,
            en: drv.operand(conn(name, c, "EN")?, name)?,
            priority: param_or(c, "PORTID", param_or(c, "PRIORITY", 0)),
        });
    }
    writes.sort_by_key(|w| w.priority);
    for (name, c) in inits {
        let k = memid(name, c)?;
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
    // Initial register values from the `init` attributes.
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
    super::order::levelize(&mut nl)?;
    Ok(nl)
}

impl Operand {
    /// The signals it reads.
    pub fn sources(&self) -> impl Iterator<Item = SigId> + '_ {
        self.chunks.iter().map(|c| c.sig)
    }
}

impl Cell {
    /// Every operand.
    pub fn operands(&self) -> impl Iterator<Item = &Operand> {
        [&self.a, &self.b, &self.s]
            .into_iter()
            .chain(self.words.iter())
    }
}
