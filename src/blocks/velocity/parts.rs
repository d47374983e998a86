//! The velocity block's two leaves, each with a hand-written Verilog body and a rust-hdl
//! `update()` that computes the same: the single multiplier [`VelMul`] (operands up to 64
//! bits, a product up to 127 bits: wider than rust-hdl's `Bits` arithmetic goes) and the
//! coefficient ROM [`VelCoefRom`] (used by [`super::hdl::Velocity`]).
use crate::blocks::{mask, sext};
use rust_hdl::prelude::*;

/// The block's only multiplier: p = q(a b / 2^k), round half up (q of the module docs of
/// `velocity`), with k = `shift0` or `shift1` as `sel` says; a and b are two's complement
/// in their low `a_width` / `b_width` bits, p the result's low `out_width` bits (upper bits
/// zero). Pipelined: p shows the operands of [`VelMul::stages`] clock edges earlier.
///
/// ```text
///  a ─┬ split: 17-bit unsigned low chunks, a signed top chunk of <= 18 bits
///  b ─┘   │ (every chunk product fits an 18 x 18 signed multiplier)
///         ▼
///  [pp_ij := a_i b_j]  [h := 2^(k-1)]  [sel]      stage 1 (registers)
///         ▼ sum of pairs, shifted to their weights, modulo 2^SW
///  [s := t0 + t1] ...                  [sel]      stage 2 .. L (one pair level each)
///         ▼
///  p = (sel ? s >>> k1 : s >>> k0), low out_width bits      (combinational)
/// ```
/// SW = min(Wa + Wb + 1, max(k0, k1) + out_width): the result's bits of a b + h lie below
/// max(k) + out_width, and a sum modulo 2^SW keeps every bit below SW exact.
#[derive(LogicBlock)]
pub struct VelMul {
    /// System clock (the pipeline registers; no reset, zero at power-up in simulation).
    pub clk: Signal<In, Clock>,
    /// Operand a, `a_width`-bit two's complement in the low bits.
    pub a: Signal<In, Bits<64>>,
    /// Operand b (the coefficient), `b_width`-bit two's complement in the low bits.
    pub b: Signal<In, Bits<64>>,
    /// Shift select: `shift1` when high, `shift0` when low.
    pub sel: Signal<In, Bit>,
    /// q(a b / 2^k) of the operands `stages` edges ago, `out_width`-bit two's complement
    /// in the low bits.
    pub p: Signal<Out, Bits<64>>,
    _a_width: u32,
    _b_width: u32,
    _out_width: u32,
    _shift0: u32,
    _shift1: u32,
    /// The operands in flight (a, b, sel), newest first, one per stage.
    _pipe: Vec<(u64, u64, bool)>,
}

/// Chunks of a `w`-bit signed operand, low first: (offset, width, signed).
fn chunks(w: u32) -> Vec<(u32, u32, bool)> {
    let mut v = Vec::new();
    let mut off = 0;
    while w - off > 18 {
        v.push((off, 17, false));
        off += 17;
    }
    v.push((off, w - off, true));
    v
}

impl VelMul {
    /// An `a_width` x `b_width` signed multiplier (each 2..=64 bits) with rounding shifts
    /// `shift0` / `shift1` (below `a_width + b_width`) and an `out_width`-bit result.
    pub fn new(a_width: u32, b_width: u32, out_width: u32, shift0: u32, shift1: u32) -> Self {
        let n = Self::stages(a_width, b_width, shift0, shift1) as usize;
        VelMul {
            clk: Default::default(),
            a: Default::default(),
            b: Default::default(),
            sel: Default::default(),
            p: Default::default(),
            _a_width: a_width,
            _b_width: b_width,
            _out_width: out_width,
            _shift0: shift0,
            _shift1: shift1,
            _pipe: vec![(0, 0, false); n],
        }
    }

    /// Register stages from the operands to p: one for the chunk products, one per level
    /// of the pairwise sum of the products and the rounding constant.
    pub fn stages(a_width: u32, b_width: u32, shift0: u32, shift1: u32) -> u32 {
        let mut terms = chunks(a_width.max(2)).len() * chunks(b_width.max(2)).len();
        if shift0.max(shift1) > 0 {
            terms += 1;
        }
        let mut levels = 0;
        while terms > 1 {
            terms = terms.div_ceil(2);
            levels += 1;
        }
        1 + levels
    }

    /// The result the block computes for raw operand bits (low `out_width` bits).
    pub fn compute(&self, a: u64, b: u64, sel: bool) -> u64 {
        let x = sext(a, self._a_width) as i128 * sext(b, self._b_width) as i128;
        let k = if sel { self._shift1 } else { self._shift0 };
        (super::qround(x, k) as u64) & mask(self._out_width)
    }
}

impl Logic for VelMul {
    fn update(&mut self) {
        if self.clk.pos_edge() {
            self._pipe.pop();
            let now = (self.a.val().to_u64(), self.b.val().to_u64(), self.sel.val());
            self._pipe.insert(0, now);
        }
        let (a, b, sel) = self._pipe.last().copied().unwrap_or((0, 0, false));
        self.p.next = Bits::<64>::from(self.compute(a, b, sel));
    }
    fn connect(&mut self) {
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        let (aw, bw, ow) = (self._a_width, self._b_width, self._out_width);
        let (k0, k1) = (self._shift0, self._shift1);
        let pw = aw + bw;
        let sw = (pw + 1).min(k0.max(k1) + ow);
        let xw = sw.max(ow);
        let fw = pw + 1;
        let mut v = String::new();
        let mut init = String::new();
        let mut terms: Vec<String> = Vec::new();
        // Stage 1: the chunk products, each widened to FW bits and moved to its weight.
        for (i, &(ao, aw_, asg)) in chunks(aw).iter().enumerate() {
            for (j, &(bo, bw_, bsg)) in chunks(bw).iter().enumerate() {
                let opnd = |n: &str, o: u32, w: u32, sg: bool| {
                    if sg {
                        format!("$signed({n}[{}:{o}])", o + w - 1)
                    } else {
                        format!("$signed({{1'b0, {n}[{}:{o}]}})", o + w - 1)
                    }
                };
                let ppw = aw_ + bw_ + 2;
                v += &format!(
                    "reg signed [{m}:0] m_pp{i}_{j};\n\
                     always @(posedge clk) m_pp{i}_{j} <= {x} * {y};\n\
                     wire signed [{fm}:0] m_w{i}_{j} = m_pp{i}_{j};\n\
                     wire signed [{fm}:0] m_t{i}_{j} = m_w{i}_{j} <<< {o};\n",
                    m = ppw - 1,
                    x = opnd("a", ao, aw_, asg),
                    y = opnd("b", bo, bw_, bsg),
                    fm = fw - 1,
                    o = ao + bo,
                );
                init += &format!(
                    "  m_pp{i}_{j} = {ppw}'d0;
"
                );
                terms.push(format!("m_t{i}_{j}[{}:0]", sw - 1));
            }
        }
        let half = |k: u32| if k == 0 { 0u128 } else { 1u128 << (k - 1) };
        if k0.max(k1) > 0 {
            v += &format!(
                "reg [{sm}:0] m_h;
always @(posedge clk) m_h <= sel ? {sw}'h{h1:x} : {sw}'h{h0:x};
",
                sm = sw - 1,
                h0 = half(k0),
                h1 = half(k1),
            );
            init += &format!(
                "  m_h = {sw}'d0;
"
            );
            terms.push("m_h".into());
        }
        // Stages 2 ..: pairwise sums, modulo 2^SW; an odd term out is registered as is.
        let mut level = 0;
        while terms.len() > 1 {
            level += 1;
            let mut next = Vec::new();
            for (n, pair) in terms.chunks(2).enumerate() {
                let name = format!("m_s{level}_{n}");
                let rhs = if pair.len() == 2 {
                    format!("{} + {}", pair[0], pair[1])
                } else {
                    pair[0].clone()
                };
                v += &format!(
                    "reg [{sm}:0] {name};
always @(posedge clk) {name} <= {rhs};
",
                    sm = sw - 1
                );
                init += &format!(
                    "  {name} = {sw}'d0;
"
                );
                next.push(name);
            }
            terms = next;
        }
        // The shift select, delayed along.
        let stages = level + 1;
        for s in 1..=stages {
            let src = if s == 1 {
                "sel".to_string()
            } else {
                format!("m_sel{}", s - 1)
            };
            v += &format!(
                "reg m_sel{s};
always @(posedge clk) m_sel{s} <= {src};
"
            );
            init += &format!(
                "  m_sel{s} = 1'b0;
"
            );
        }
        let pad = if ow >= 64 {
            format!("m_x[{}:0]", ow - 1)
        } else {
            format!("{{{}'d0, m_x[{}:0]}}", 64 - ow, ow - 1)
        };
        Verilog::Custom(format!(
            "\
{v}`ifndef SYNTHESIS
initial begin
{init}end
`endif
wire signed [{sm}:0] m_root = {root};
wire signed [{xm}:0] m_r0 = m_root >>> {k0};
wire signed [{xm}:0] m_r1 = m_root >>> {k1};
wire signed [{xm}:0] m_x = m_sel{stages} ? m_r1 : m_r0;
always @(*) p = {pad};
",
            sm = sw - 1,
            xm = xw - 1,
            root = terms[0],
        ))
    }
}

/// The coefficient ROM: word `addr` of a list of constants (combinational; 0 past the end).
#[derive(LogicBlock)]
pub struct VelCoefRom {
    /// Word address (low `addr_width` bits used).
    pub addr: Signal<In, Bits<32>>,
    /// The word, `width`-bit two's complement in the low bits.
    pub coef: Signal<Out, Bits<64>>,
    _words: Vec<u64>,
    _addr_width: u32,
}

impl VelCoefRom {
    /// A ROM of `words` (signed), each stored as its low `width` bits.
    pub fn new(words: &[i64], width: u32) -> Self {
        let n = words.len().max(2) as u64;
        let addr_width = 64 - (n - 1).leading_zeros();
        VelCoefRom {
            addr: Default::default(),
            coef: Default::default(),
            _words: words.iter().map(|&w| w as u64 & mask(width)).collect(),
            _addr_width: addr_width,
        }
    }
}

impl Logic for VelCoefRom {
    fn update(&mut self) {
        let a = self.addr.val().to_u64() & mask(self._addr_width);
        let c = self._words.get(a as usize).copied().unwrap_or(0);
        self.coef.next = Bits::<64>::from(c);
    }
    fn connect(&mut self) {
        self.coef.connect();
    }
    fn hdl(&self) -> Verilog {
        let w = self._addr_width;
        let m = w - 1;
        // One conditional expression per word, as a single assignment: no `case` (which
        // Yosys may turn into a block RAM, see the biquad engine's program ROM) and no
        // default-then-override (a momentary value on `coef` re-triggers the block that
        // drives `addr`, and Icarus loops at one time step).
        let words: String = self
            ._words
            .iter()
            .enumerate()
            .map(|(i, c)| format!("  (addr[{m}:0] == {w}'d{i}) ? 64'h{c:016x} :\n"))
            .collect();
        Verilog::Custom(format!(
            "\
always @(*) coef =
{words}  64'h0000000000000000;
"
        ))
    }
}
