//! rust-hdl description of the quadrant mapper and one vectoring CORDIC stage.
use crate::blocks::params::Derived;
use crate::blocks::{c32, fill, mask};
use rust_hdl::prelude::*;

/// Registers the mapped first-quadrant vector, the quadrant and the valid bit.
///
/// Table 2-3 as two absolute values and a swap: every row negates only a negative input,
/// so x' = |cos|, y' = |sin|, swapped when the signs differ (q1: x' = sin, y' = -cos; q3:
/// x' = -sin, y' = cos). Each absolute value is (a ^ m) + c with m all ones and c one when
/// a < 0, a single carry chain whose inversion and carry-in come from the input's own sign
/// bit; the swap is one LUT per bit after the adders (before them it put the swap, the
/// inversion and the carry-in of the other input's sign in front of the chain).
///
/// Both outputs are never negative: every row of Table 2-3 negates only a negative input,
/// so x', y' lie in 0..=2^(A-1) before the G-bit guard shift. The registers keep the low
/// A + G bits and the top two of the W-bit word are constant 0. Synthesis sees that stage
/// 0's direction (the sign of y') is constant and folds its sign logic (stage 0 always
/// rotates by -atan(1) on y, +atan(1) on z), as the model's arithmetic implies anyway.
#[derive(LogicBlock)]
pub struct QuadrantMapper {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high (clears the valid bit).
    pub rst: Signal<In, Bit>,
    /// Sample strobe.
    pub in_valid: Signal<In, Bit>,
    /// Sine sample, A-bit two's complement in the low bits.
    pub in_sin: Signal<In, Bits<16>>,
    /// Cosine sample, A-bit two's complement in the low bits.
    pub in_cos: Signal<In, Bits<16>>,
    /// Mapped x' (W-bit, G guard bits).
    pub x: Signal<Out, Bits<32>>,
    /// Mapped y' (W-bit, G guard bits).
    pub y: Signal<Out, Bits<32>>,
    /// Quadrant of the sample, 0..3.
    pub q: Signal<Out, Bits<2>>,
    /// Valid bit travelling with the sample.
    pub v: Signal<Out, Bit>,
    x_reg: DFF<Bits<32>>,
    y_reg: DFF<Bits<32>>,
    q_reg: DFF<Bits<2>>,
    v_reg: DFF<Bit>,
    /// cos sign-extended to 32 bits.
    sx: Signal<Local, Bits<32>>,
    /// sin sign-extended to 32 bits.
    sy: Signal<Local, Bits<32>>,
    /// cos < 0.
    cneg: Signal<Local, Bit>,
    /// sin < 0.
    sneg: Signal<Local, Bit>,
    /// |cos| (32-bit).
    ax: Signal<Local, Bits<32>>,
    /// |sin| (32-bit).
    ay: Signal<Local, Bits<32>>,
    /// Inversion mask of |cos| (all ones when cos < 0).
    mx: Signal<Local, Bits<32>>,
    /// Carry-in of |cos| (one when cos < 0).
    cx: Signal<Local, Bits<32>>,
    /// Inversion mask of |sin| (all ones when sin < 0).
    my: Signal<Local, Bits<32>>,
    /// Carry-in of |sin| (one when sin < 0).
    cy: Signal<Local, Bits<32>>,
    /// Mask of the A input bits.
    amask: Constant<Bits<32>>,
    /// Sign bit of an A-bit input.
    asign: Constant<Bits<32>>,
    /// Bits A..31: sign extension of a negative input.
    asext: Constant<Bits<32>>,
    /// Guard-bit shift G.
    gshift: Constant<Bits<32>>,
    /// Mask of the low A + G bits: x', y' are in 0..=2^(A-1+G), so bits A+G..W-1 are 0.
    vmask: Constant<Bits<32>>,
    /// All ones: inversion mask of a negation.
    ones: Constant<Bits<32>>,
    /// One: carry-in of a negation.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
}

impl QuadrantMapper {
    /// Mapper for the derived parameters.
    pub fn new(d: &Derived) -> Self {
        let a = d.adc_width;
        Self {
            clk: Default::default(),
            rst: Default::default(),
            in_valid: Default::default(),
            in_sin: Default::default(),
            in_cos: Default::default(),
            x: Default::default(),
            y: Default::default(),
            q: Default::default(),
            v: Default::default(),
            x_reg: Default::default(),
            y_reg: Default::default(),
            q_reg: Default::default(),
            v_reg: Default::default(),
            sx: Default::default(),
            sy: Default::default(),
            cneg: Default::default(),
            sneg: Default::default(),
            ax: Default::default(),
            ay: Default::default(),
            mx: Default::default(),
            cx: Default::default(),
            my: Default::default(),
            cy: Default::default(),
            amask: c32(mask(a)),
            asign: c32(1 << (a - 1)),
            asext: c32(fill(32, 32 - a)),
            gshift: c32(d.xy_guard as u64),
            vmask: c32(mask(a + d.xy_guard)),
            ones: c32(mask(32)),
            one: c32(1),
            zero: c32(0),
        }
    }
}

impl Logic for QuadrantMapper {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, x_reg, y_reg, q_reg, v_reg);
        // Sign-extend the A-bit inputs to 32 bits.
        self.sx.next = bit_cast::<32, 16>(self.in_cos.val()) & self.amask.val();
        self.cneg.next = (self.sx.val() & self.asign.val()).any();
        if self.cneg.val() {
            self.sx.next = self.sx.val() | self.asext.val();
        }
        self.sy.next = bit_cast::<32, 16>(self.in_sin.val()) & self.amask.val();
        self.sneg.next = (self.sy.val() & self.asign.val()).any();
        if self.sneg.val() {
            self.sy.next = self.sy.val() | self.asext.val();
        }
        // Table 2-3: q0 (x, y), q1 (y, -x), q2 (-x, -y), q3 (-y, x): the absolute values,
        // swapped when the signs differ.
        self.mx.next = self.zero.val();
        self.cx.next = self.zero.val();
        if self.cneg.val() {
            self.mx.next = self.ones.val();
            self.cx.next = self.one.val();
        }
        self.my.next = self.zero.val();
        self.cy.next = self.zero.val();
        if self.sneg.val() {
            self.my.next = self.ones.val();
            self.cy.next = self.one.val();
        }
        self.ax.next = (self.sx.val() ^ self.mx.val()) + self.cx.val();
        self.ay.next = (self.sy.val() ^ self.my.val()) + self.cy.val();
        self.q_reg.d.next = 0.into();
        if self.sneg.val() {
            if self.cneg.val() {
                self.q_reg.d.next = 2.into();
            } else {
                self.q_reg.d.next = 3.into();
            }
        } else if self.cneg.val() {
            self.q_reg.d.next = 1.into();
        }
        self.x_reg.d.next = (self.ax.val() << self.gshift.val()) & self.vmask.val();
        self.y_reg.d.next = (self.ay.val() << self.gshift.val()) & self.vmask.val();
        if self.cneg.val() ^ self.sneg.val() {
            self.x_reg.d.next = (self.ay.val() << self.gshift.val()) & self.vmask.val();
            self.y_reg.d.next = (self.ax.val() << self.gshift.val()) & self.vmask.val();
        }
        self.v_reg.d.next = self.in_valid.val() & !self.rst.val();
        self.x.next = self.x_reg.q.val();
        self.y.next = self.y_reg.q.val();
        self.q.next = self.q_reg.q.val();
        self.v.next = self.v_reg.q.val();
    }
}

/// One registered vectoring iteration i: rotates (x, y) towards the x axis and accumulates
/// the angle.
#[derive(LogicBlock)]
pub struct CordicStage {
    /// System clock.
    pub clk: Signal<In, Clock>,
    /// Synchronous reset, active high (clears the valid bit).
    pub rst: Signal<In, Bit>,
    /// x from the previous stage (W-bit).
    pub x_in: Signal<In, Bits<32>>,
    /// y from the previous stage (W-bit two's complement).
    pub y_in: Signal<In, Bits<32>>,
    /// Angle so far (ZW-bit two's complement, 2^-(F+Gz) quadrant).
    pub z_in: Signal<In, Bits<32>>,
    /// Quadrant travelling with the sample.
    pub q_in: Signal<In, Bits<2>>,
    /// Valid bit travelling with the sample.
    pub v_in: Signal<In, Bit>,
    /// Registered x.
    pub x_out: Signal<Out, Bits<32>>,
    /// Registered y.
    pub y_out: Signal<Out, Bits<32>>,
    /// Registered z.
    pub z_out: Signal<Out, Bits<32>>,
    /// Registered quadrant.
    pub q_out: Signal<Out, Bits<2>>,
    /// Registered valid bit.
    pub v_out: Signal<Out, Bit>,
    x_reg: DFF<Bits<32>>,
    y_reg: DFF<Bits<32>>,
    z_reg: DFF<Bits<32>>,
    q_reg: DFF<Bits<2>>,
    v_reg: DFF<Bit>,
    xs: Signal<Local, Bits<32>>,
    ys: Signal<Local, Bits<32>>,
    m: Signal<Local, Bits<32>>,
    c: Signal<Local, Bits<32>>,
    nm: Signal<Local, Bits<32>>,
    nc: Signal<Local, Bits<32>>,
    /// z_in + atan(2^-i) (ZW bits): z when y >= 0.
    zp: Signal<Local, Bits<32>>,
    /// z_in - atan(2^-i) (ZW bits): z when y < 0.
    zm: Signal<Local, Bits<32>>,
    /// All ones: operand inversion mask for a subtraction.
    ones: Constant<Bits<32>>,
    /// One: carry-in of a subtraction.
    one: Constant<Bits<32>>,
    /// Zero.
    zero: Constant<Bits<32>>,
    /// Shift amount i.
    shift: Constant<Bits<32>>,
    /// Fill for an arithmetic shift by i of a W-bit word.
    sfill: Constant<Bits<32>>,
    /// Sign bit of a W-bit word.
    xsign: Constant<Bits<32>>,
    /// Mask of W bits.
    xmask: Constant<Bits<32>>,
    /// Mask of ZW bits.
    zmask: Constant<Bits<32>>,
    /// atan(2^-i) in 2^-(F+Gz) quadrant.
    atan: Constant<Bits<32>>,
    /// -atan(2^-i), 32-bit two's complement.
    natan: Constant<Bits<32>>,
}

impl CordicStage {
    /// Stage `i` for the derived parameters.
    pub fn new(d: &Derived, i: u32) -> Self {
        let w = d.xy_width;
        Self {
            clk: Default::default(),
            rst: Default::default(),
            x_in: Default::default(),
            y_in: Default::default(),
            z_in: Default::default(),
            q_in: Default::default(),
            v_in: Default::default(),
            x_out: Default::default(),
            y_out: Default::default(),
            z_out: Default::default(),
            q_out: Default::default(),
            v_out: Default::default(),
            x_reg: Default::default(),
            y_reg: Default::default(),
            z_reg: Default::default(),
            q_reg: Default::default(),
            v_reg: Default::default(),
            xs: Default::default(),
            ys: Default::default(),
            m: Default::default(),
            c: Default::default(),
            nm: Default::default(),
            nc: Default::default(),
            zp: Default::default(),
            zm: Default::default(),
            ones: c32(mask(32)),
            one: c32(1),
            zero: c32(0),
            shift: c32(i as u64),
            sfill: c32(fill(w, i)),
            xsign: c32(1 << (w - 1)),
            xmask: c32(mask(w)),
            zmask: c32(mask(d.z_width)),
            atan: c32(d.atan_table[i as usize]),
            natan: c32(d.atan_table[i as usize].wrapping_neg() & mask(32)),
        }
    }
}

impl Logic for CordicStage {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(self, clk, x_reg, y_reg, z_reg, q_reg, v_reg);
        self.xs.next = self.x_in.val() >> self.shift.val();
        if (self.x_in.val() & self.xsign.val()).any() {
            self.xs.next = self.xs.val() | self.sfill.val();
        }
        self.ys.next = self.y_in.val() >> self.shift.val();
        // Direction: y < 0 rotates up (x - ys, y + xs, z - atan), else down. x and y are
        // one adder each: a - b = a + (b ^ ones) + 1, with the inversion mask and carry-in
        // chosen by the sign (Yosys maps the carry-in into the chain); z is below.
        self.m.next = self.zero.val();
        self.c.next = self.zero.val();
        self.nm.next = self.ones.val();
        self.nc.next = self.one.val();
        if (self.y_in.val() & self.xsign.val()).any() {
            self.ys.next = self.ys.val() | self.sfill.val();
            self.m.next = self.ones.val();
            self.c.next = self.one.val();
            self.nm.next = self.zero.val();
            self.nc.next = self.zero.val();
        }
        self.x_reg.d.next =
            (self.x_in.val() + (self.ys.val() ^ self.m.val()) + self.c.val()) & self.xmask.val();
        self.y_reg.d.next =
            (self.y_in.val() + (self.xs.val() ^ self.nm.val()) + self.nc.val()) & self.xmask.val();
        // z +- atan: both constants added beside each other and the sign selecting after
        // the chains, so the sign (which also drives the x and y adders) reaches z through
        // one LUT instead of a carry chain.
        self.zp.next = (self.z_in.val() + self.atan.val()) & self.zmask.val();
        self.zm.next = (self.z_in.val() + self.natan.val()) & self.zmask.val();
        self.z_reg.d.next = self.zp.val();
        if (self.y_in.val() & self.xsign.val()).any() {
            self.z_reg.d.next = self.zm.val();
        }
        self.q_reg.d.next = self.q_in.val();
        self.v_reg.d.next = self.v_in.val() & !self.rst.val();
        self.x_out.next = self.x_reg.q.val();
        self.y_out.next = self.y_reg.q.val();
        self.z_out.next = self.z_reg.q.val();
        self.q_out.next = self.q_reg.q.val();
        self.v_out.next = self.v_reg.q.val();
    }
}

impl crate::cosim::step::Clocked for CordicStage {
    fn set_clock(&mut self, high: bool) {
        self.clk.next = Clock::from(high);
    }
}

impl crate::cosim::CosimBlock for CordicStage {
    fn input_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("rst", 1),
            Port::new("x_in", 32),
            Port::new("y_in", 32),
            Port::new("z_in", 32),
            Port::new("q_in", 2),
            Port::new("v_in", 1),
        ]
    }
    fn output_ports(&self) -> Vec<crate::cosim::Port> {
        use crate::cosim::Port;
        vec![
            Port::new("x_out", 32),
            Port::new("y_out", 32),
            Port::new("z_out", 32),
            Port::new("q_out", 2),
            Port::new("v_out", 1),
        ]
    }
    fn apply(&mut self, r: &[u64]) {
        self.rst.next = r[0] != 0;
        self.x_in.next = Bits::<32>::from(r[1]);
        self.y_in.next = Bits::<32>::from(r[2]);
        self.z_in.next = Bits::<32>::from(r[3]);
        self.q_in.next = Bits::<2>::from(r[4]);
        self.v_in.next = r[5] != 0;
    }
    fn sample(&self) -> Vec<u64> {
        vec![
            self.x_out.val().to_u64(),
            self.y_out.val().to_u64(),
            self.z_out.val().to_u64(),
            self.q_out.val().to_u64(),
            self.v_out.val() as u64,
        ]
    }
}
