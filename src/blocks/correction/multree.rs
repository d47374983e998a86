//! Pipelined shift-add multiplier: the product a * c of a 16-bit register a and a 16-bit
//! code c, without a hard multiplier. The code is either a constant ([`MulTree::new`]:
//! the gain and phase products of static mode when a code is not a power of two) or a
//! run-time operand taken with a ([`MulTree::run_time`]: the gain and phase products of
//! modes `auto` and `peak`, and the fit's sample products); see
//! [`super::CorrectionParams::shift_add`], maths in [`crate::blocks::correction`].
//!
//! ```text
//!  a (reg), c ─► pp_i = (a << i) AND bit i of c     (i = 0..15; wires for a constant c,
//!                                                    one AND per bit for a run-time c)
//!      level 1 (reg): l1_k = pp_2k + pp_2k+1              k = 0..7
//!      level 2 (reg): l2_k = l1_2k + l1_2k+1              k = 0..3
//!      level 3 (reg): l3_k = l2_2k + l2_2k+1              k = 0..1 ──► out_x, out_y
//!  neg, v ──► three registers (v cleared by rst) ─────────────────────► out_neg, out_v
//!  the caller's product register takes out_x + out_y (the fourth level)
//! ```
//!
//! Bit growth: a, c < 2^16, so every partial sum is at most a * c <= (2^16 - 1)^2 < 2^32
//! and the 32-bit words are exact: out_x + out_y = a * c, bit for bit the product of a
//! 16 x 16 -> 32 multiplier, three clocks later. Each level is one adder between
//! registers (one carry chain per path); a run-time code adds one LUT level ahead of
//! level 1's carry chain (each sum bit of level 1 reads two bits of a and two bits of c: a
//! LUT4 into the chain, or two ANDs beside it). A constant code drives the gates, so
//! Yosys removes every adder with a zero operand and every register that holds a
//! constant 0: a code with n one bits costs n - 1 adders. A run-time tree keeps all 15
//! adders (8 + 4 + 2, and the caller's last one). The code is read only by level 1: it
//! must be valid in the same clock as a (both registers of the caller), and a new pair
//! may follow every clock.
use super::CorrectionParams;
use crate::blocks::c32;
use rust_hdl::prelude::*;

/// Levels of the tree inside this block; the caller's register is one more. The extra
/// latency over a one-stage multiplier is this number.
pub const TREE_LEVELS: u32 = 3;

/// Shift-add tree for a 16-bit code (a constant, or the `code` port): three register
/// levels.
#[derive(LogicBlock)]
pub struct MulTree {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high: clears the valid bits.
    pub rst: Signal<In, Bit>,
    /// Multiplicand a (a register of the caller), unsigned.
    pub a: Signal<In, Bits<16>>,
    /// Run-time code c (a register of the caller, valid with a); ignored by a constant tree.
    pub code: Signal<In, Bits<16>>,
    /// Sign bit travelling with a.
    pub neg: Signal<In, Bit>,
    /// Valid bit travelling with a.
    pub v: Signal<In, Bit>,
    /// First half of a * c (out_x + out_y = a * c, three clocks after a).
    pub out_x: Signal<Out, Bits<32>>,
    /// Second half of a * c.
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
    /// The code in use: `kconst`, or the `code` port when `kdyn`.
    kc: Signal<Local, Bits<16>>,
    /// The constant code (a constant tree).
    kconst: Constant<Bits<16>>,
    /// A run-time tree: the code is the `code` port.
    kdyn: Constant<Bit>,
    /// Partial products: pp_i = a << i when bit i of the code is set, else 0.
    pp0: Signal<Local, Bits<32>>,
    pp1: Signal<Local, Bits<32>>,
    pp2: Signal<Local, Bits<32>>,
    pp3: Signal<Local, Bits<32>>,
    pp4: Signal<Local, Bits<32>>,
    pp5: Signal<Local, Bits<32>>,
    pp6: Signal<Local, Bits<32>>,
    pp7: Signal<Local, Bits<32>>,
    pp8: Signal<Local, Bits<32>>,
    pp9: Signal<Local, Bits<32>>,
    pp10: Signal<Local, Bits<32>>,
    pp11: Signal<Local, Bits<32>>,
    pp12: Signal<Local, Bits<32>>,
    pp13: Signal<Local, Bits<32>>,
    pp14: Signal<Local, Bits<32>>,
    pp15: Signal<Local, Bits<32>>,
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
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl MulTree {
    /// Tree for the constant `code` (the low 16 bits are used; the `code` port is ignored).
    pub fn new(code: u64) -> Self {
        Self::build(code, false)
    }

    /// Tree for a run-time code: the `code` port, read with `a`.
    pub fn run_time() -> Self {
        Self::build(0, true)
    }

    /// The tree of a product of `p` whose static code is `code`: none without shift-add
    /// products, a constant tree in static mode, a run-time tree (its `code` port) in auto
    /// and peak modes.
    pub fn of(p: &CorrectionParams, code: u64) -> Vec<Self> {
        match (p.shift_add(), p.run_time_codes()) {
            (false, _) => vec![],
            (true, false) => vec![Self::new(code)],
            (true, true) => vec![Self::run_time()],
        }
    }

    fn build(code: u64, dynamic: bool) -> Self {
        Self {
            clk: Default::default(),
            rst: Default::default(),
            a: Default::default(),
            code: Default::default(),
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
            kc: Default::default(),
            kconst: Constant::new(Bits::<16>::from(code & 0xffff)),
            kdyn: Constant::new(dynamic),
            pp0: Default::default(),
            pp1: Default::default(),
            pp2: Default::default(),
            pp3: Default::default(),
            pp4: Default::default(),
            pp5: Default::default(),
            pp6: Default::default(),
            pp7: Default::default(),
            pp8: Default::default(),
            pp9: Default::default(),
            pp10: Default::default(),
            pp11: Default::default(),
            pp12: Default::default(),
            pp13: Default::default(),
            pp14: Default::default(),
            pp15: Default::default(),
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
            zero: c32(0),
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
        self.kc.next = self.kconst.val();
        if self.kdyn.val() {
            self.kc.next = self.code.val();
        }
        // Partial products, gated by the code's bits.
        self.pp0.next = self.zero.val();
        if self.kc.val().get_bit(0) {
            self.pp0.next = self.ax.val();
        }
        self.pp1.next = self.zero.val();
        if self.kc.val().get_bit(1) {
            self.pp1.next = self.ax.val() << self.s1.val();
        }
        self.pp2.next = self.zero.val();
        if self.kc.val().get_bit(2) {
            self.pp2.next = self.ax.val() << self.s2.val();
        }
        self.pp3.next = self.zero.val();
        if self.kc.val().get_bit(3) {
            self.pp3.next = self.ax.val() << self.s3.val();
        }
        self.pp4.next = self.zero.val();
        if self.kc.val().get_bit(4) {
            self.pp4.next = self.ax.val() << self.s4.val();
        }
        self.pp5.next = self.zero.val();
        if self.kc.val().get_bit(5) {
            self.pp5.next = self.ax.val() << self.s5.val();
        }
        self.pp6.next = self.zero.val();
        if self.kc.val().get_bit(6) {
            self.pp6.next = self.ax.val() << self.s6.val();
        }
        self.pp7.next = self.zero.val();
        if self.kc.val().get_bit(7) {
            self.pp7.next = self.ax.val() << self.s7.val();
        }
        self.pp8.next = self.zero.val();
        if self.kc.val().get_bit(8) {
            self.pp8.next = self.ax.val() << self.s8.val();
        }
        self.pp9.next = self.zero.val();
        if self.kc.val().get_bit(9) {
            self.pp9.next = self.ax.val() << self.s9.val();
        }
        self.pp10.next = self.zero.val();
        if self.kc.val().get_bit(10) {
            self.pp10.next = self.ax.val() << self.s10.val();
        }
        self.pp11.next = self.zero.val();
        if self.kc.val().get_bit(11) {
            self.pp11.next = self.ax.val() << self.s11.val();
        }
        self.pp12.next = self.zero.val();
        if self.kc.val().get_bit(12) {
            self.pp12.next = self.ax.val() << self.s12.val();
        }
        self.pp13.next = self.zero.val();
        if self.kc.val().get_bit(13) {
            self.pp13.next = self.ax.val() << self.s13.val();
        }
        self.pp14.next = self.zero.val();
        if self.kc.val().get_bit(14) {
            self.pp14.next = self.ax.val() << self.s14.val();
        }
        self.pp15.next = self.zero.val();
        if self.kc.val().get_bit(15) {
            self.pp15.next = self.ax.val() << self.s15.val();
        }
        // Level 1: pairs of partial products.
        self.l1_0.d.next = self.pp0.val() + self.pp1.val();
        self.l1_1.d.next = self.pp2.val() + self.pp3.val();
        self.l1_2.d.next = self.pp4.val() + self.pp5.val();
        self.l1_3.d.next = self.pp6.val() + self.pp7.val();
        self.l1_4.d.next = self.pp8.val() + self.pp9.val();
        self.l1_5.d.next = self.pp10.val() + self.pp11.val();
        self.l1_6.d.next = self.pp12.val() + self.pp13.val();
        self.l1_7.d.next = self.pp14.val() + self.pp15.val();
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
