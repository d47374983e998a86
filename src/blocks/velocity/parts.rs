//! The velocity block's two leaves, each with a hand-written Verilog body and a rust-hdl
//! `update()` that computes the same: the single multiplier [`VelMul`] (operands up to 64
//! bits, a product up to 127 bits: wider than rust-hdl's `Bits` arithmetic goes) and the
//! coefficient ROM [`VelCoefRom`] (used by [`super::hdl::Velocity`]).
use crate::blocks::{mask, sext};
use rust_hdl::prelude::*;

/// The block's only multiplier: p = q(a b / 2^k), round half up (q of the module docs of
/// `velocity`), with k = `shift0` or `shift1` as `sel` says; a and b are two's complement
/// in their low `a_width` / `b_width` bits, p the result's low `out_width` bits (upper bits
/// zero). Combinational: the registers around it are the block's.
#[derive(LogicBlock)]
pub struct VelMul {
    /// Operand a, `a_width`-bit two's complement in the low bits.
    pub a: Signal<In, Bits<64>>,
    /// Operand b (the coefficient), `b_width`-bit two's complement in the low bits.
    pub b: Signal<In, Bits<64>>,
    /// Shift select: `shift1` when high, `shift0` when low.
    pub sel: Signal<In, Bit>,
    /// q(a b / 2^k), `out_width`-bit two's complement in the low bits.
    pub p: Signal<Out, Bits<64>>,
    _a_width: u32,
    _b_width: u32,
    _out_width: u32,
    _shift0: u32,
    _shift1: u32,
}

impl VelMul {
    /// An `a_width` x `b_width` signed multiplier (each 2..=64 bits) with rounding shifts
    /// `shift0` / `shift1` (below `a_width + b_width`) and an `out_width`-bit result.
    pub fn new(a_width: u32, b_width: u32, out_width: u32, shift0: u32, shift1: u32) -> Self {
        VelMul {
            a: Default::default(),
            b: Default::default(),
            sel: Default::default(),
            p: Default::default(),
            _a_width: a_width,
            _b_width: b_width,
            _out_width: out_width,
            _shift0: shift0,
            _shift1: shift1,
        }
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
        let v = self.compute(self.a.val().to_u64(), self.b.val().to_u64(), self.sel.val());
        self.p.next = Bits::<64>::from(v);
    }
    fn connect(&mut self) {
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        let (aw, bw, ow) = (self._a_width, self._b_width, self._out_width);
        // Product PW bits, one more for the rounding add; XW holds both the rounded
        // product and the output word.
        let pw = aw + bw;
        let xw = (pw + 1).max(ow);
        let shifted = |k: u32, n: u32| -> String {
            if k == 0 {
                format!("wire signed [{pw}:0] m_s{n} = m_p;\n")
            } else {
                format!(
                    "wire signed [{pw}:0] m_r{n} = m_p + {w}'sh{h:x};\n\
                     wire signed [{pw}:0] m_s{n} = m_r{n} >>> {k};\n",
                    w = pw + 1,
                    h = 1u128 << (k - 1),
                )
            }
        };
        let pad = if ow >= 64 {
            format!("m_x[{}:0]", ow - 1)
        } else {
            format!("{{{}'d0, m_x[{}:0]}}", 64 - ow, ow - 1)
        };
        Verilog::Custom(format!(
            "\
wire signed [{am}:0] m_a = a[{am}:0];
wire signed [{bm}:0] m_b = b[{bm}:0];
wire signed [{pm}:0] m_p = m_a * m_b;
{s0}{s1}wire signed [{xm}:0] m_x = sel ? m_s1 : m_s0;
always @(*) p = {pad};
",
            am = aw - 1,
            bm = bw - 1,
            pm = pw - 1,
            xm = xw - 1,
            s0 = shifted(self._shift0, 0),
            s1 = shifted(self._shift1, 1),
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
