//! 64-bit sums over two clocks, in two 32-bit carry chains: the learner's wide words
//! (super::harmonics::learner). A 64-bit chain alone is about 3.6 ns of logic on the ECP5 of
//! the timing rule, which with its routing misses the rule's clock (docs/timing.md); a
//! 32-bit chain leaves room for the routing.
//!
//! [`SplitAdd`], a free-running sum of two operands that hold still for two clocks:
//!
//! ```text
//!   a, b ─┬─ {0, a_lo, 0} +- {0, b_lo, 0} ──reg──► lo (bit 33: carry, or borrow)
//!   (held)└─ {a_hi, 1} + {b_hi, carry}    ──reg──► hi          s = {hi, lo}
//!            {a_hi, 0} - {b_hi, borrow}   (subtracting)
//! ```
//!
//! The low half is right a clock after a and b settle, the whole sum two clocks after. The
//! carry (borrow) enters the high chain as its bit 0's second operand, so each half is one
//! carry chain from registers to a register: {x, 1} + {y, c} = 2 (x + y + c) + 1 - c and
//! {x, 0} - {y, c} = 2 (x - y - c) + c, whose bits 32..1 are x + y + c and x - y - c.
//!
//! [`SplitAcc`], an accumulator s += x, one add a clock at most:
//!
//! ```text
//!   x (add) ──► {0, lo, 0} + {0, x_lo, 0} ──reg──► lo (bit 33: carry)
//!               {hi, 1} + {xh, carry}      ──reg──► hi;   x_hi ──reg──► xh
//! ```
//!
//! Each add's high half and carry enter the high chain a clock after its low half, so `s`
//! is the sum a clock after the last add. `clear` zeroes it.
//!
//! Bit growth: none; both are 64-bit two's complement words that wrap as a 64-bit sum does,
//! and the learner's words never wrap (super::harmonics::sequencer's bounds). Written here
//! because no crate builds rust-hdl arithmetic.
use rust_hdl::prelude::*;

fn k34(v: u64) -> Constant<Bits<34>> {
    Constant::new(Bits::<34>::from(v))
}

fn k33(v: u64) -> Constant<Bits<33>> {
    Constant::new(Bits::<33>::from(v))
}

fn k64(v: u64) -> Constant<Bits<64>> {
    Constant::new(Bits::<64>::from(v))
}

/// s = a + b or a - b over two clocks (module doc).
#[derive(LogicBlock)]
pub struct SplitAdd {
    /// The clock.
    pub clock: Signal<In, Clock>,
    /// The first operand (held for two clocks before `s` is read).
    pub a: Signal<In, Bits<64>>,
    /// The second operand, added or subtracted.
    pub b: Signal<In, Bits<64>>,
    /// The sum (difference) of `a` and `b` two clocks ago.
    pub s: Signal<Out, Bits<64>>,
    /// The low half: {carry or borrow, 32 sum bits, 0}.
    lo: DFF<Bits<34>>,
    /// The high half: {32 sum bits, the carry trick's bit}.
    hi: DFF<Bits<33>>,
    /// Subtract.
    sub: Constant<Bit>,
    /// 1 (34- and 33-bit), 33, 32, the low 32 bits.
    one34: Constant<Bits<34>>,
    one33: Constant<Bits<33>>,
    k33: Constant<Bits<34>>,
    k32: Constant<Bits<64>>,
    m32: Constant<Bits<64>>,
    /// The low halves, shifted a bit up; the high halves, shifted a bit up; the carry.
    al: Signal<Local, Bits<34>>,
    bl: Signal<Local, Bits<34>>,
    ah: Signal<Local, Bits<33>>,
    bh: Signal<Local, Bits<33>>,
    cy: Signal<Local, Bits<33>>,
}

impl SplitAdd {
    fn with(sub: bool) -> Self {
        SplitAdd {
            clock: Default::default(),
            a: Default::default(),
            b: Default::default(),
            s: Default::default(),
            lo: Default::default(),
            hi: Default::default(),
            sub: Constant::new(sub),
            one34: k34(1),
            one33: k33(1),
            k33: k34(33),
            k32: k64(32),
            m32: k64(0xffff_ffff),
            al: Default::default(),
            bl: Default::default(),
            ah: Default::default(),
            bh: Default::default(),
            cy: Default::default(),
        }
    }

    /// s = a + b.
    pub fn add() -> Self {
        Self::with(false)
    }

    /// s = a - b.
    pub fn sub() -> Self {
        Self::with(true)
    }
}

impl Logic for SplitAdd {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, lo, hi);
        self.al.next = bit_cast::<34, 64>(self.a.val() & self.m32.val()) << self.one34.val();
        self.bl.next = bit_cast::<34, 64>(self.b.val() & self.m32.val()) << self.one34.val();
        self.ah.next = bit_cast::<33, 64>(self.a.val() >> self.k32.val()) << self.one33.val();
        self.bh.next = bit_cast::<33, 64>(self.b.val() >> self.k32.val()) << self.one33.val();
        self.cy.next = bit_cast::<33, 34>(self.lo.q.val() >> self.k33.val());
        if self.sub.val() {
            self.lo.d.next = self.al.val() - self.bl.val();
            self.hi.d.next = self.ah.val() - (self.bh.val() | self.cy.val());
        } else {
            self.lo.d.next = self.al.val() + self.bl.val();
            self.hi.d.next = (self.ah.val() | self.one33.val()) + (self.bh.val() | self.cy.val());
        }
        self.s.next = (bit_cast::<64, 33>(self.hi.q.val() >> self.one33.val()) << self.k32.val())
            | (bit_cast::<64, 34>(self.lo.q.val() >> self.one34.val()) & self.m32.val());
    }
}

/// s += x when `add`, zeroed by `clear`; `s` is the sum a clock after the last add (module
/// doc).
#[derive(LogicBlock)]
pub struct SplitAcc {
    /// The clock.
    pub clock: Signal<In, Clock>,
    /// Zero the sum (an add of the same clock is dropped).
    pub clear: Signal<In, Bit>,
    /// Add `x` this clock.
    pub add: Signal<In, Bit>,
    /// The addend.
    pub x: Signal<In, Bits<64>>,
    /// The sum, a clock after the last add.
    pub s: Signal<Out, Bits<64>>,
    /// The low half: {carry, 32 sum bits, 0}.
    lo: DFF<Bits<34>>,
    /// The high half.
    hi: DFF<Bits<32>>,
    /// The last add's high half (0 without an add), added a clock after its low half.
    xh: DFF<Bits<32>>,
    /// 1 (34-bit), 33, 32, the low 32 bits (34-bit, shifted a bit up: the low sum's
    /// place), zero.
    one34: Constant<Bits<34>>,
    k33: Constant<Bits<34>>,
    k32: Constant<Bits<64>>,
    m32: Constant<Bits<64>>,
    ml: Constant<Bits<34>>,
    z34: Constant<Bits<34>>,
    z32: Constant<Bits<32>>,
    /// The addend's low half, shifted a bit up (zero without an add); the high chain's
    /// operands {hi, 1}, {xh, carry}.
    xl: Signal<Local, Bits<34>>,
    hh: Signal<Local, Bits<33>>,
    xc: Signal<Local, Bits<33>>,
    one33: Constant<Bits<33>>,
}

impl Default for SplitAcc {
    fn default() -> Self {
        SplitAcc {
            clock: Default::default(),
            clear: Default::default(),
            add: Default::default(),
            x: Default::default(),
            s: Default::default(),
            lo: Default::default(),
            hi: Default::default(),
            xh: Default::default(),
            one34: k34(1),
            k33: k34(33),
            k32: k64(32),
            m32: k64(0xffff_ffff),
            ml: k34(0x1_ffff_fffe),
            z34: k34(0),
            z32: Constant::new(Bits::<32>::from(0u64)),
            xl: Default::default(),
            hh: Default::default(),
            xc: Default::default(),
            one33: k33(1),
        }
    }
}

impl Logic for SplitAcc {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clock, lo, hi, xh);
        self.xl.next = self.z34.val();
        self.xh.d.next = self.z32.val();
        if self.add.val() {
            self.xl.next = bit_cast::<34, 64>(self.x.val() & self.m32.val()) << self.one34.val();
            self.xh.d.next = bit_cast::<32, 64>(self.x.val() >> self.k32.val());
        }
        self.lo.d.next = (self.lo.q.val() & self.ml.val()) + self.xl.val();
        self.hh.next = (bit_cast::<33, 32>(self.hi.q.val()) << self.one33.val()) | self.one33.val();
        self.xc.next = (bit_cast::<33, 32>(self.xh.q.val()) << self.one33.val())
            | bit_cast::<33, 34>(self.lo.q.val() >> self.k33.val());
        self.hi.d.next = bit_cast::<32, 33>((self.hh.val() + self.xc.val()) >> self.one33.val());
        if self.clear.val() {
            self.lo.d.next = self.z34.val();
            self.hi.d.next = self.z32.val();
            self.xh.d.next = self.z32.val();
        }
        self.s.next = (bit_cast::<64, 32>(self.hi.q.val()) << self.k32.val())
            | (bit_cast::<64, 34>(self.lo.q.val() >> self.one34.val()) & self.m32.val());
    }
}
