//! The biquad engine's three leaves, each with a hand-written Verilog body and a rust-hdl
//! `update()` that computes the same: the single multiplier [`BiquadMul`], the program ROM
//! [`BiquadProgram`] and the state RAM [`BiquadStateRam`] (used by [`super::hdl::BiquadRtl`]).
use super::BiquadParams;
use crate::blocks::{mask, sext};
use rust_hdl::prelude::*;

/// The engine's only multiplier: p = (a * b) >> shift (arithmetic), a and b signed in the
/// low `a_width` / `b_width` bits, p sign-extended to / truncated at 32 bits.
#[derive(LogicBlock)]
pub struct BiquadMul {
    /// Data operand: `a_width`-bit two's complement in the low bits.
    pub a: Signal<In, Bits<32>>,
    /// Coefficient operand: `b_width`-bit two's complement in the low bits.
    pub b: Signal<In, Bits<32>>,
    /// Shifted product, 32-bit two's complement.
    pub p: Signal<Out, Bits<32>>,
    _a_width: u32,
    _b_width: u32,
    _shift: u32,
}

impl BiquadMul {
    /// A `a_width` x `b_width` signed multiplier followed by `>> shift`.
    pub fn new(a_width: u32, b_width: u32, shift: u32) -> Self {
        BiquadMul {
            a: Default::default(),
            b: Default::default(),
            p: Default::default(),
            _a_width: a_width,
            _b_width: b_width,
            _shift: shift,
        }
    }

    /// The product the block computes, as i64.
    pub fn compute(&self, a: u64, b: u64) -> i64 {
        let x = sext(a, self._a_width) as i128 * sext(b, self._b_width) as i128;
        (x >> self._shift) as i64
    }
}

impl Logic for BiquadMul {
    fn update(&mut self) {
        let v = self.compute(self.a.val().to_u64(), self.b.val().to_u64());
        self.p.next = Bits::<32>::from(v as u64 & 0xffff_ffff);
    }
    fn connect(&mut self) {
        self.p.connect();
    }
    fn hdl(&self) -> Verilog {
        let (aw, bw, f) = (self._a_width, self._b_width, self._shift);
        let pw = aw + bw;
        // Significant bits after the shift; sign-extend to 32 (or truncate).
        let sw = pw - f;
        let out = if sw >= 32 {
            "m_shr[31:0]".to_string()
        } else {
            format!(
                "{{{{{ext}{{m_shr[{top}]}}}}, m_shr[{top}:0]}}",
                ext = 32 - sw,
                top = sw - 1
            )
        };
        Verilog::Custom(format!(
            "\
wire signed [{am}:0] m_opa = a[{am}:0];
wire signed [{bm}:0] m_opb = b[{bm}:0];
wire signed [{pm}:0] m_prod = m_opa * m_opb;
wire signed [{pm}:0] m_shr = m_prod >>> {f};
always @(*) p = {out};
",
            am = aw - 1,
            bm = bw - 1,
            pm = pw - 1,
        ))
    }
}

/// The program ROM: for address `pc`, the coefficient and the control word of that clock
/// (combinational; a case table in Verilog).
#[derive(LogicBlock)]
pub struct BiquadProgram {
    /// Program counter.
    pub pc: Signal<In, Bits<32>>,
    /// Coefficient, C-bit two's complement in the low bits.
    pub coef: Signal<Out, Bits<32>>,
    /// Control word (`ctrl` bits).
    pub ctrl: Signal<Out, Bits<32>>,
    _words: Vec<(u32, u32)>,
    _pc_width: u32,
}

impl BiquadProgram {
    /// The ROM of `p.program()`.
    pub fn new(p: &BiquadParams) -> Self {
        let cm = mask(p.coef_width);
        BiquadProgram {
            pc: Default::default(),
            coef: Default::default(),
            ctrl: Default::default(),
            _words: p
                .program()
                .iter()
                .map(|o| ((o.coef as u64 & cm) as u32, o.ctrl))
                .collect(),
            _pc_width: p.pc_width(),
        }
    }
}

impl Logic for BiquadProgram {
    fn update(&mut self) {
        let a = self.pc.val().to_u64() & mask(self._pc_width);
        let (c, k) = self._words.get(a as usize).copied().unwrap_or((0, 0));
        self.coef.next = Bits::<32>::from(c as u64);
        self.ctrl.next = Bits::<32>::from(k as u64);
    }
    fn connect(&mut self) {
        self.coef.connect();
        self.ctrl.connect();
    }
    fn hdl(&self) -> Verilog {
        let w = self._pc_width;
        // One `if` per word, not a `case`: Yosys would turn a case table into a ROM and,
        // with the engine's register after it, into an initialized block RAM, which its
        // Cyclone III mapping rejects; as logic it is a 6-input function per bit.
        let m = w - 1;
        let cases: String = self
            ._words
            .iter()
            .enumerate()
            .map(|(i, (c, k))| {
                format!(
                    "  if (pc[{m}:0] == {w}'d{i}) begin coef = 32'h{c:08x}; ctrl = 32'h{k:08x}; end\n"
                )
            })
            .collect();
        Verilog::Custom(format!(
            "\
always @(*) begin
  coef = 32'h00000000;
  ctrl = 32'h00000000;
{cases}end
"
        ))
    }
}

/// The state RAM: `words` x `width` bits, one port, synchronous read (old data on a write).
/// Zero at power-up in simulation (rust-hdl, and an `ifndef SYNTHESIS` initial block for
/// Icarus/Verilator); in hardware its contents are defined by the clearing sweep after
/// reset (Yosys 0.23's Cyclone III M9K mapping rejects initialized memories), so the
/// engine needs one reset after configuration.
#[derive(LogicBlock)]
pub struct BiquadStateRam {
    /// Clock.
    pub clk: Signal<In, Clock>,
    /// Word address (low `addr_width` bits used).
    pub addr: Signal<In, Bits<32>>,
    /// Write enable.
    pub we: Signal<In, Bit>,
    /// Write data (low `width` bits stored).
    pub wd: Signal<In, Bits<32>>,
    /// Read data of the address of the previous clock (zero-extended).
    pub q: Signal<Out, Bits<32>>,
    _mem: Vec<u32>,
    _width: u32,
    _addr_width: u32,
}

impl BiquadStateRam {
    /// A zeroed RAM.
    pub fn new(words: u32, width: u32, addr_width: u32) -> Self {
        BiquadStateRam {
            clk: Default::default(),
            addr: Default::default(),
            we: Default::default(),
            wd: Default::default(),
            q: Default::default(),
            _mem: vec![0; words as usize],
            _width: width,
            _addr_width: addr_width,
        }
    }
}

impl Logic for BiquadStateRam {
    fn update(&mut self) {
        if self.clk.pos_edge() {
            let a = (self.addr.val().to_u64() & mask(self._addr_width)) as usize;
            let old = self._mem.get(a).copied().unwrap_or(0);
            self.q.next = Bits::<32>::from(old as u64);
            if self.we.val() {
                if let Some(m) = self._mem.get_mut(a) {
                    *m = (self.wd.val().to_u64() & mask(self._width)) as u32;
                }
            }
        }
    }
    fn connect(&mut self) {
        self.q.connect();
    }
    fn hdl(&self) -> Verilog {
        let (w, aw, n) = (self._width, self._addr_width, self._mem.len());
        let init: String = (0..n)
            .map(|i| format!("  sr_mem[{i}] = {w}'d0;\n"))
            .collect();
        let rd = if w >= 32 {
            format!("sr_mem[addr[{}:0]]", aw - 1)
        } else {
            format!("{{{}'d0, sr_mem[addr[{}:0]]}}", 32 - w, aw - 1)
        };
        Verilog::Custom(format!(
            "\
reg [{wm}:0] sr_mem [0:{nm}];
`ifndef SYNTHESIS
initial begin
{init}  q = 32'h00000000;
end
`endif
always @(posedge clk) begin
  if (we) sr_mem[addr[{am}:0]] <= wd[{wm}:0];
  q <= {rd};
end
",
            wm = w - 1,
            nm = n - 1,
            am = aw - 1,
        ))
    }
}
