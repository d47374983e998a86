//! Constant-coefficient multiplier as a pipelined shift-add tree: the product a * c of a
//! 16-bit register a and a 16-bit constant code c, without a hard multiplier. Used for the
//! gain and phase products of static mode when a code is not a power of two
//! ([`super::CorrectionParams::shift_add`]; maths in [`crate::blocks::correction`]).
//!
//! ```text
//!  a (reg) ─► pp_i = (a << i) if bit i of c, else 0      (wires: c is a constant)
//!      level 1 (reg): l1_k = pp_2k + pp_2k+1              k = 0..7
//!      level 2 (reg): l2_k = l1_2k + l1_2k+1              k = 0..3
//!      level 3 (reg): l3_k = l2_2k + l2_2k+1              k = 0..1 ──► out_x, out_y
//!  neg, v ──► three registers (v cleared by rst) ─────────────────────► out_neg, out_v
//!  the caller's product register takes out_x + out_y (the fourth level)
//! ```
//!
//! Bit growth: a < 2^16, so every partial sum is at most a * c < 2^32 and the 32-bit words
//! are exact. Each level is one adder between registers (one carry chain per path). A
//! constant code drives the gates, so Yosys removes every adder with a zero operand and
//! every register that holds a constant 0: a code with n one bits costs n - 1 adders.
use crate::blocks::{c32, mask};
use rust_hdl::prelude::*;

/// Levels of the tree inside this block; the caller's register is one more. The extra
/// latency over a one-stage multiplier is this number.
pub const TREE_LEVELS: u32 = 3;

/// Shift-add tree for the constant `code` (16 bits): three register levels.
#[derive(LogicBlock)]
pub struct MulTree {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: clears the valid bits.
    pub rst: Signal<In, Bit>,
    /// Multiplicand a (a register of the caller), unsigned.
    pub a: Signal<In, Bits<16>>,
    /// Sign bit travelling with a.
    pub neg: Signal<In, Bit>,
    /// Valid bit travelling with a.
    pub v: Signal<In, Bit>,
    /// First half of a * code (out_x + out_y = a * code, three clocks after a).
    pub out_x: Signal<Out, Bits<32>>,
    /// Second half of a * code.
    pub out_y: Signal<Out, Bits<32>>,
    /// `neg` three clocks later.
    pub out_neg: Signal<Out, Bit>,
    /// `v` three clocks later (cleared by rst on each clock).
    pub out_v: Signal<Out, Bit>,
    l1_0: DFF<Bits<32>>,
    l1_1: DFF<Bits<32>>,
    l1_2: DFF<Bits<32>>,
    l1_3: DFF<Bits<32>>,
    l1_4: DFF<Bits<32>>,
    l1_5: DFF<Bits<32>>,
    l1_6: DFF<Bits<32>>,
    l1_7: DFF<Bits<32>>,
    l2_0: DFF<Bits<32>>,
    l2_1: DFF<Bits<32>>,
    l2_2: DFF<Bits<32>>,
    l2_3: DFF<Bits<32>>,
    l3_0: DFF<Bits<32>>,
    l3_1: DFF<Bits<32>>,
    n1: DFF<Bit>,
    n2: DFF<Bit>,
    n3: DFF<Bit>,
    v1: DFF<Bit>,
    v2: DFF<Bit>,
    v3: DFF<Bit>,
    /// a on 32 bits.
    ax: Signal<Local, Bits<32>>,
    /// All ones when bit i of the code is set, else 0.
    g0: Constant<Bits<32>>,
    g1: Constant<Bits<32>>,
    g2: Constant<Bits<32>>,
    g3: Constant<Bits<32>>,
    g4: Constant<Bits<32>>,
    g5: Constant<Bits<32>>,
    g6: Constant<Bits<32>>,
    g7: Constant<Bits<32>>,
    g8: Constant<Bits<32>>,
    g9: Constant<Bits<32>>,
    g10: Constant<Bits<32>>,
    g11: Constant<Bits<32>>,
    g12: Constant<Bits<32>>,
    g13: Constant<Bits<32>>,
    g14: Constant<Bits<32>>,
    g15: Constant<Bits<32>>,
    /// Shift amounts 1..15.
    s1: Constant<Bits<32>>,
    s2: Constant<Bits<32>>,
    s3: Constant<Bits<32>>,
    s4: Constant<Bits<32>>,
    s5: Constant<Bits<32>>,
    s6: Constant<Bits<32>>,
    s7: Constant<Bits<32>>,
    s8: Constant<Bits<32>>,
    s9: Constant<Bits<32>>,
    s10: Constant<Bits<32>>,
    s11: Constant<Bits<32>>,
    s12: Constant<Bits<32>>,
    s13: Constant<Bits<32>>,
    s14: Constant<Bits<32>>,
    s15: Constant<Bits<32>>,
}

impl MulTree {
    /// Tree for the constant `code` (the low 16 bits are used).
    pub fn new(code: u64) -> Self {
        let g = |i: u32| c32(if code >> i & 1 == 1 { mask(32) } else { 0 });
        Self {
            clk: Default::default(),
            rst: Default::default(),
            a: Default::default(),
            neg: Default::default(),
            v: Default::default(),
            out_x: Default::default(),
            out_y: Default::default(),
            out_neg: Default::default(),
            out_v: Default::default(),
            l1_0: Default::default(),
            l1_1: Default::default(),
            l1_2: Default::default(),
            l1_3: Default::default(),
            l1_4: Default::default(),
            l1_5: Default::default(),
            l1_6: Default::default(),
            l1_7: Default::default(),
            l2_0: Default::default(),
            l2_1: Default::default(),
            l2_2: Default::default(),
            l2_3: Default::default(),
            l3_0: Default::default(),
            l3_1: Default::default(),
            n1: Default::default(),
            n2: Default::default(),
            n3: Default::default(),
            v1: Default::default(),
            v2: Default::default(),
            v3: Default::default(),
            ax: Default::default(),
            g0: g(0),
            g1: g(1),
            g2: g(2),
            g3: g(3),
            g4: g(4),
            g5: g(5),
            g6: g(6),
            g7: g(7),
            g8: g(8),
            g9: g(9),
            g10: g(10),
            g11: g(11),
            g12: g(12),
            g13: g(13),
            g14: g(14),
            g15: g(15),
            s1: c32(1),
            s2: c32(2),
            s3: c32(3),
            s4: c32(4),
            s5: c32(5),
            s6: c32(6),
            s7: c32(7),
            s8: c32(8),
            s9: c32(9),
            s10: c32(10),
            s11: c32(11),
            s12: c32(12),
            s13: c32(13),
            s14: c32(14),
            s15: c32(15),
        }
    }
}

impl Logic for MulTree {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clk, l1_0, l1_1, l1_2, l1_3, l1_4, l1_5, l1_6, l1_7, l2_0, l2_1, l2_2, l2_3,
            l3_0, l3_1, n1, n2, n3, v1, v2, v3
        );
        self.ax.next = bit_cast::<32, 16>(self.a.val());
        // Level 1: pairs of gated partial products.
        self.l1_0.d.next =
            (self.ax.val() & self.g0.val()) + ((self.ax.val() << self.s1.val()) & self.g1.val());
        self.l1_1.d.next = ((self.ax.val() << self.s2.val()) & self.g2.val())
            + ((self.ax.val() << self.s3.val()) & self.g3.val());
        self.l1_2.d.next = ((self.ax.val() << self.s4.val()) & self.g4.val())
            + ((self.ax.val() << self.s5.val()) & self.g5.val());
        self.l1_3.d.next = ((self.ax.val() << self.s6.val()) & self.g6.val())
            + ((self.ax.val() << self.s7.val()) & self.g7.val());
        self.l1_4.d.next = ((self.ax.val() << self.s8.val()) & self.g8.val())
            + ((self.ax.val() << self.s9.val()) & self.g9.val());
        self.l1_5.d.next = ((self.ax.val() << self.s10.val()) & self.g10.val())
            + ((self.ax.val() << self.s11.val()) & self.g11.val());
        self.l1_6.d.next = ((self.ax.val() << self.s12.val()) & self.g12.val())
            + ((self.ax.val() << self.s13.val()) & self.g13.val());
        self.l1_7.d.next = ((self.ax.val() << self.s14.val()) & self.g14.val())
            + ((self.ax.val() << self.s15.val()) & self.g15.val());
        // Levels 2 and 3.
        self.l2_0.d.next = self.l1_0.q.val() + self.l1_1.q.val();
        self.l2_1.d.next = self.l1_2.q.val() + self.l1_3.q.val();
        self.l2_2.d.next = self.l1_4.q.val() + self.l1_5.q.val();
        self.l2_3.d.next = self.l1_6.q.val() + self.l1_7.q.val();
        self.l3_0.d.next = self.l2_0.q.val() + self.l2_1.q.val();
        self.l3_1.d.next = self.l2_2.q.val() + self.l2_3.q.val();
        // The sign and valid bits keep pace.
        self.n1.d.next = self.neg.val();
        self.n2.d.next = self.n1.q.val();
        self.n3.d.next = self.n2.q.val();
        self.v1.d.next = self.v.val() & !self.rst.val();
        self.v2.d.next = self.v1.q.val() & !self.rst.val();
        self.v3.d.next = self.v2.q.val() & !self.rst.val();
        self.out_x.next = self.l3_0.q.val();
        self.out_y.next = self.l3_1.q.val();
        self.out_neg.next = self.n3.q.val();
        self.out_v.next = self.v3.q.val();
    }
}
