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
mod build;

pub use build::build;

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
