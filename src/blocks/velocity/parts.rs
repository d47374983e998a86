//! The velocity block's two leaves, each with a hand-written Verilog body and a rust-hdl
//! `update()` that computes the same: the single multiplier [`VelMul`] (operands up to 64
//! bits, a product up to 127 bits: wider than rust-hdl's `Bits` arithmetic goes) and the
//! coefficient ROM [`VelCoefRom`] (used by [`super::hdl::Velocity`]).
use crate::blocks::{mask, sext};
use rust_hdl::prelude::*;

/// The block's only multiplier: p = q(a b / 2^k), round half up (q of the module docs of
/// `velocity`), with a fixed rounding shift k = `shift`; a and b are two's complement
/// in their low `a_width` / `b_width` bits, p the result's low `out_width` bits (upper bits
/// zero). Sequential, radix-4 Booth, built from adds only (no `*`, so no hard multiplier is
/// inferred, and every register-to-register path holds one carry chain):
///
/// ```text
///  start: win := {sext(b, 2n), 0}   x := 0, c := 0   R := 2^(k+1) 2^(2n)
///  every other clock (n = ceil(Wb / 2) digits, digit t = -2 w2 + w1 + w0 of win[2:0]):
///   win[2:0] ─► one, two, neg ─┐
///   a ── sext to H bits ───────┴► [x := (two ? 2a : one ? a : 0) ^ neg..neg]  [c := neg]
///   R = {hi (H bits), lo (2n bits)}:  hi + x + c  (one carry chain, c its carry-in)
///   [R := {hi + x + c, lo} >>> 2]     [win := win >>> 2]
///  p = (R >>> k) low Wo bits (wiring: R's bits from k up)
/// ```
/// The product of digit t enters R at edge start + 2 + t and is shifted n - t more times,
/// so it lands at 4^t; the start value, shifted n + 1 times, lands at 2^(k-1) (the rounding
/// constant; 0 for k = 0). After edge start + n + 1, R = a b + 2^(k-1) exactly, and p is
/// valid until the next edge ([`VelMul::steps`] = n). H = max(Wa, k + 1) + 3: the high part
/// before a shift is below 2^(k+1) + (4/3 + 1/4) 2^Wa + 1 < 2^(H-1) in magnitude (|digit| <=
/// 2, |a| <= 2^(Wa-1)), so it never wraps, and R's H + 2n bits hold a b + 2^(k-1).
#[derive(LogicBlock)]
pub struct VelMul {
    /// System clock (the registers; no reset, zero at power-up in simulation).
    pub clk: Signal<In, Clock>,
    /// Operand a, `a_width`-bit two's complement in the low bits; held from the clock after
    /// `start` until p is taken.
    pub a: Signal<In, Bits<64>>,
    /// Operand b (the coefficient), `b_width`-bit two's complement in the low bits; read
    /// on the `start` clock only.
    pub b: Signal<In, Bits<64>>,
    /// Start a multiply this clock.
    pub start: Signal<In, Bit>,
    /// q(a b / 2^k), `out_width`-bit two's complement in the low bits, in the clock after
    /// edge start + n + 1 (n = `steps`).
    pub p: Signal<Out, Bits<64>>,
    _a_width: u32,
    _b_width: u32,
    _out_width: u32,
    _shift: u32,
    /// The registers as in the Verilog body: R's high part (H bits) and low part (2n bits),
    /// the Booth window (2n + 1 bits), x (H bits) and c.
    _hi: u128,
    _lo: u128,
    _win: u128,
    _x: u128,
    _c: bool,
}

/// Low `w` bits set (w <= 128).
fn mask128(w: u32) -> u128 {
    if w >= 128 {
        u128::MAX
    } else {
        (1u128 << w) - 1
    }
}

/// The low `w` bits of `v`, sign-extended (w in 1..=128).
fn sext128(v: u128, w: u32) -> i128 {
    let s = 128 - w;
    ((v << s) as i128) >> s
}

impl VelMul {
    /// An `a_width` x `b_width` signed multiplier (each 2..=64 bits) with the rounding
    /// shift `shift` (below `a_width + b_width`) and an `out_width`-bit result.
    pub fn new(a_width: u32, b_width: u32, out_width: u32, shift: u32) -> Self {
        VelMul {
            clk: Default::default(),
            a: Default::default(),
            b: Default::default(),
            start: Default::default(),
            p: Default::default(),
            _a_width: a_width.max(2),
            _b_width: b_width.max(2),
            _out_width: out_width,
            _shift: shift,
            _hi: 0,
            _lo: 0,
            _win: 0,
            _x: 0,
            _c: false,
        }
    }

    /// Bits of the register R = {hi, lo} for these operand widths and shift: H + 2n with
    /// H = max(a_width, shift + 1) + 3 (the widest register of the multiplier).
    pub fn register_bits(a_width: u32, b_width: u32, shift: u32) -> u32 {
        a_width.max(2).max(shift + 1) + 3 + 2 * Self::steps(b_width)
    }

    /// Booth digits n = ceil(b_width / 2): p is valid after edge start + n + 1.
    pub fn steps(b_width: u32) -> u32 {
        b_width.max(2).div_ceil(2)
    }

    /// n of this instance.
    fn n(&self) -> u32 {
        Self::steps(self._b_width)
    }

    /// Width H of R's high part, the adder and x.
    fn hi_width(&self) -> u32 {
        self._a_width.max(self._shift + 1) + 3
    }

    /// R's start value's high part: 2^(k+1) (0 for k = 0).
    fn start_hi(&self) -> u128 {
        if self._shift == 0 {
            0
        } else {
            1u128 << (self._shift + 1)
        }
    }

    /// The exact result for raw operand bits (low `out_width` bits): what p shows once a
    /// multiply has run (the reference of the tests).
    #[cfg(test)]
    fn compute(&self, a: u64, b: u64) -> u64 {
        let x = sext(a, self._a_width) as i128 * sext(b, self._b_width) as i128;
        (super::qround(x, self._shift) as u64) & mask(self._out_width)
    }

    /// One clock edge of the registers (`start`, `a`, `b`: the inputs before it).
    fn edge(&mut self, start: bool, a: u64, b: u64) {
        let (h, n2) = (self.hi_width(), 2 * self.n());
        if start {
            let bs = sext(b, self._b_width) as i128 as u128;
            self._win = (bs << 1) & mask128(n2 + 1);
            self._x = 0;
            self._c = false;
            self._hi = self.start_hi();
            self._lo = 0;
            return;
        }
        let sum = self._hi.wrapping_add(self._x).wrapping_add(self._c as u128) & mask128(h);
        let (w2, w1, w0) = (self._win >> 2 & 1, self._win >> 1 & 1, self._win & 1);
        let one = w1 ^ w0 == 1;
        let two = (w2, w1, w0) == (1, 0, 0) || (w2, w1, w0) == (0, 1, 1);
        let ae = sext(a, self._a_width) as i128 as u128 & mask128(h);
        let mag = if two {
            (ae << 1) & mask128(h)
        } else if one {
            ae
        } else {
            0
        };
        self._x = if w2 == 1 { !mag & mask128(h) } else { mag };
        self._c = w2 == 1;
        self._win = (sext128(self._win, n2 + 1) >> 2) as u128 & mask128(n2 + 1);
        self._lo = (self._lo >> 2) | ((sum & 3) << (n2 - 2));
        self._hi = (sext128(sum, h) >> 2) as u128 & mask128(h);
    }

    /// p from the registers: bits k .. k + out_width of R (sign-extended).
    fn result(&self) -> u64 {
        let k = self._shift;
        let n2 = 2 * self.n();
        let hi = sext128(self._hi, self.hi_width());
        let v = if k >= n2 {
            (hi >> (k - n2).min(127)) as u128
        } else {
            (hi.wrapping_shl(n2 - k) as u128) | (self._lo >> k)
        };
        v as u64 & mask(self._out_width)
    }
}

impl Logic for VelMul {
    fn update(&mut self) {
        if self.clk.pos_edge() {
            let (a, b) = (self.a.val().to_u64(), self.b.val().to_u64());
            self.edge(self.start.val(), a, b);
        }
        self.p.next = Bits::<64>::from(self.result());
    }
    fn connect(&mut self) {
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        let (aw, bw, ow) = (self._a_width, self._b_width, self._out_width);
        let k = self._shift;
        let h = self.hi_width();
        let n2 = 2 * self.n();
        let w = h + n2;
        let xw = w.max(ow);
        // sext(b) to 2n bits, sext(a) to H bits (no zero-width replications).
        let bext = if n2 > bw {
            format!("{{{{{}{{b[{}]}}}}, b[{}:0]}}", n2 - bw, bw - 1, bw - 1)
        } else {
            format!("b[{}:0]", bw - 1)
        };
        let start = format!("{w}'h{:x} << {n2}", self.start_hi());
        let pad = if ow >= 64 {
            format!("m_y[{}:0]", ow - 1)
        } else {
            format!("{{{}'d0, m_y[{}:0]}}", 64 - ow, ow - 1)
        };
        Verilog::Custom(format!(
            "\
// Radix-4 Booth, one digit per clock: R = {{hi ({h} bits), lo ({n2} bits)}}.
reg [{wm}:0] m_r;
reg [{n2}:0] m_win;
reg [{hm}:0] m_x;
reg m_c;
wire m_one = m_win[1] ^ m_win[0];
wire m_two = (m_win[2] & ~m_win[1] & ~m_win[0]) | (~m_win[2] & m_win[1] & m_win[0]);
wire [{hm}:0] m_ae = {{{{{ah}{{a[{am}]}}}}, a[{am}:0]}};
wire [{hm}:0] m_mag = m_two ? {{m_ae[{hm1}:0], 1'b0}} : (m_one ? m_ae : {h}'d0);
wire [{hm}:0] m_sum = m_r[{wm}:{n2}] + m_x + {{{hm}'d0, m_c}};
always @(posedge clk) begin
  if (start) begin
    m_win <= {{{bext}, 1'b0}};
    m_x <= {h}'d0;
    m_c <= 1'b0;
    m_r <= {start};
  end else begin
    m_win <= {{m_win[{n2}], m_win[{n2}], m_win[{n2}:2]}};
    m_x <= m_mag ^ {{{h}{{m_win[2]}}}};
    m_c <= m_win[2];
    m_r <= {{m_sum[{hm}], m_sum[{hm}], m_sum, m_r[{n2m}:2]}};
  end
end
`ifndef SYNTHESIS
initial begin
  m_r = {w}'d0;
  m_win = {n21}'d0;
  m_x = {h}'d0;
  m_c = 1'b0;
end
`endif
wire signed [{wm}:0] m_rs = m_r;
wire signed [{xm}:0] m_y = m_rs >>> {k};
always @(*) p = {pad};
",
            wm = w - 1,
            hm = h - 1,
            hm1 = h - 2,
            n2m = n2 - 1,
            n21 = n2 + 1,
            ah = h - aw,
            am = aw - 1,
            xm = xw - 1,
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

#[cfg(test)]
mod tests {
    use super::VelMul;
    use crate::blocks::mask;

    /// Runs one multiply on the register model: start, then n + 1 edges with `a` held.
    fn run(m: &mut VelMul, a: u64, b: u64) -> u64 {
        m.edge(true, a, b);
        for _ in 0..=VelMul::steps(m._b_width) {
            // b is read on the start clock only: anything else here must not matter.
            m.edge(false, a, !b);
        }
        m.result()
    }

    #[test]
    fn booth_multiplier_is_the_rounded_product() {
        // (Wa, Wb, Wout, k): the four methods' shapes at the defaults (lsq: k = B), odd and
        // even Wb, the widest operands, no shift, a result wider than R's bits above k.
        let shapes = [
            (36, 18, 36, 18),
            (36, 19, 36, 18),
            (28, 33, 33, 27),
            (41, 17, 41, 18),
            (64, 64, 64, 63),
            (64, 64, 64, 0),
            (2, 2, 8, 1),
            (20, 5, 62, 3),
        ];
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut rnd = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        for (aw, bw, ow, k) in shapes {
            let mut m = VelMul::new(aw, bw, ow, k);
            let edges = |w: u32| {
                [
                    0,
                    1,
                    mask(w),
                    mask(w) >> 1,
                    1 << (w - 1),
                    (1 << (w - 1)) + 1,
                ]
            };
            let mut cases = vec![];
            for a in edges(aw) {
                for b in edges(bw) {
                    cases.push((a, b));
                }
            }
            for _ in 0..2000 {
                cases.push((rnd() & mask(aw), rnd() & mask(bw)));
            }
            for &(a, b) in &cases {
                let got = run(&mut m, a, b);
                let want = m.compute(a, b);
                assert_eq!(got, want, "{aw}x{bw} k {k}: a {a:#x} b {b:#x}");
            }
        }
    }
}
